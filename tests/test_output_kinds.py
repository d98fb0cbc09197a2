"""An output kind is one class: one defined here, with no change to the package, is a kind
of ``[[outputs]]`` table like the shipped ones. The checker refuses its table's problems
naming the table and key, the builder makes its outputs (an output it cannot bind names
its table), every method solves them, in scalars and arrays, with and without friction,
and the reference of the format lists the kind and its keys. A kind that misses one of
its class facts is refused where it is defined."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from linkage_fmu import presets
from linkage_fmu.descriptions import Description, DescriptionError, schema
from linkage_fmu.manual import reference
from linkage_fmu.outputs import Output, has_friction, joint_between

STATES = [(0.3, 10.0, 0.0), (2.2, -7.0, 40.0), (4.9, 3.0, -15.0)]
#: the angles here are those the solver's own force outputs give, through math.atan2
#: against the kernels' atan2 (a vector one, in the compiled closed form): a few ulp
TOLERANCE = 1e-13


@pytest.fixture
def bearing():
    """The kind ``bearing``: the direction of the force one body exerts on another,
    defined in this one class; the registry forgets it after the test."""
    saved = dict(Output.registry)

    @dataclass(frozen=True)
    class Bearing(Output):
        """Output: direction of the force of body ``by`` on body ``on``, counter-clockwise
        from +x."""

        name: str
        by: str
        on: str
        note: str = ""
        unit = "rad"
        kind = "bearing"
        REPORTS = ("direction of the force one body exerts on another through their joint, "
                   "counter-clockwise from x, rad")
        KEYS = {
            "name": "name of the output (required)",
            "by": "the body that exerts the force (required)",
            "on": "the body it acts on, joined to by (required)",
            "description": "what it is",
        }

        @property
        def description(self) -> str:
            return self.note or f"direction of the force of link {self.by} on link {self.on}"

        @classmethod
        def check(cls, checker, where, name, spec):
            for key in ("by", "on"):
                if spec.get(key) not in checker.links and spec.get(key) != checker.d.frame:
                    checker.found.append(f"{where} {key}: {spec.get(key)!r} is not a body")
            if spec.get("by") == spec.get("on"):
                checker.found.append(f"{where} on: a body exerts no force on itself")
            return [name]

        @classmethod
        def from_spec(cls, spec, d):
            return [cls(spec["name"], spec["by"], spec["on"], spec.get("description", ""))]

        def bind(self, mech):
            j, sign = joint_between(mech, self.by, self.on, self.name)
            rubs = has_friction(mech, j.name)
            fx, fy = (j.force_output(axis, sign, rubs) for axis in (0, 1))
            return lambda R, E, st: st.xp.atan2(fy(R, E, st), fx(R, E, st))

    yield Bearing
    Output.registry.clear()
    Output.registry.update(saved)


def four_bar() -> Description:
    """A copy of the shipped four-bar's description (the preset's is shared)."""
    return presets.preset("four_bar").copy()


def with_bearings() -> Description:
    """The shipped four-bar with the directions of the forces in its pin B both ways."""
    return (four_bar().output("bearing", name="phi21", by="2", on="1")
            .output("bearing", name="phi12", by="1", on="2", description="from the crank"))


@pytest.mark.parametrize("friction", [False, True], ids=["frictionless", "friction"])
@pytest.mark.parametrize("method", ["closed_form", "direct", "interpreted"])
def test_a_kind_defined_in_one_class_is_built_and_solved(bearing, method, friction):
    """phi21 is atan2(F21y, F21x) of the force outputs the linkage reports, phi12 the
    same of the opposite force, to TOLERANCE (rad), at each state and for arrays of
    them; every other output is bit for bit what the linkage gives without them."""
    given = {f"mu_{j}": 0.15 for j in "ABCD"} if friction else {}
    mech = with_bearings().build(**given)
    plain = four_bar().build(**given)
    assert mech.output_info["phi21"] == ("rad", "direction of the force of link 2 on link 1")
    assert mech.output_info["phi12"] == ("rad", "from the crank")
    for theta, omega, alpha in STATES:
        sol = mech.solve(theta, omega, alpha, 150.0, method=method)
        fx, fy = sol["F21x"], sol["F21y"]
        assert math.hypot(fx, fy) > 1.0  # a direction well defined
        assert sol["phi21"] == pytest.approx(math.atan2(fy, fx), abs=TOLERANCE)
        assert sol["phi12"] == pytest.approx(math.atan2(-fy, -fx), abs=TOLERANCE)
        base = plain.solve(theta, omega, alpha, 150.0, method=method)
        assert {k: v for k, v in sol.items() if not k.startswith("phi")} == dict(base)
    thetas, omegas, alphas = (np.array(s) for s in zip(*STATES))
    many = mech.solve(thetas, omegas, alphas, 150.0, method=method)
    np.testing.assert_allclose(many["phi21"], np.arctan2(many["F21y"], many["F21x"]),
                               rtol=0.0, atol=TOLERANCE)
    np.testing.assert_allclose(many["phi12"], np.arctan2(-many["F21y"], -many["F21x"]),
                               rtol=0.0, atol=TOLERANCE)


def test_its_tables_are_written_and_read_as_toml(bearing):
    d = with_bearings()
    again = Description.from_toml(d.to_toml(), "bearings.toml")
    assert again.outputs[-2:] == d.outputs[-2:]
    assert again.build().solve(0.4, 10.0)["phi12"] == d.build().solve(0.4, 10.0)["phi12"]


def test_the_checker_asks_the_kind(bearing):
    """The problems its check finds, and the ones every table has (unknown keys, the
    name, a name used twice), each naming the table and key."""
    d = (four_bar()
         .output("bearing", name="phi21", by="2", on="9", offset=0.1)
         .output("bearing", name="phi", by="3", on="3")
         .output("bearing", name="F21x", by="2", on="1")
         .output("bearing", name="2nd", by="2", on="1"))
    with pytest.raises(DescriptionError) as info:
        d.build()
    assert info.value.problems == [
        "[[outputs]] #6 (phi21): unknown key(s) offset",
        "[[outputs]] #6 (phi21) on: '9' is not a body",
        "[[outputs]] #7 (phi) on: a body exerts no force on itself",
        "[[outputs]] #8 (F21x): output name 'F21x' is used twice",
        "[[outputs]] #9 (2nd) name: '2nd' must be an identifier",
    ]
    unknown = four_bar().output("bearings", name="phi21", by="2", on="1")
    with pytest.raises(DescriptionError, match=r"\[\[outputs\]\] #6 \(phi21\) kind: "
                       r"'bearings' is not one of force, normal, couple, effort, "
                       r"expression, bearing$"):
        unknown.build()


def test_an_output_it_cannot_bind_names_its_table(bearing):
    d = four_bar().output("bearing", name="phi31", by="3", on="1")
    with pytest.raises(ValueError, match=r"^four_bar: \[\[outputs\]\] #6 \(phi31\): no joint "
                       r"between bodies '3' and '1'$"):
        d.build()


def test_the_reference_lists_the_kind_and_its_keys(bearing):
    before = dict(bearing.KEYS)
    assert schema.OUTPUT_KINDS["bearing"] == bearing.REPORTS
    assert dict(schema.OUTPUT_KEYS["bearing"]) == before
    text = reference.markdown()
    part = text.split("## `[[outputs]]`")[1].split("\n## ")[0]
    assert f"| `bearing` | {bearing.REPORTS} |" in part
    own = part.split('### `kind = "bearing"`')[1].split("\n### ")[0]
    assert "| `by` | the body that exerts the force (required) |" in own
    Output.registry.pop("bearing")
    assert 'kind = "bearing"' not in reference.markdown()


def test_a_kind_without_its_class_facts_is_refused_where_it_is_defined(bearing):
    keys = {"name": "name of the output (required)"}

    def define(**facts):
        type(Output)("Speed", (Output,), {"kind": "speed", "check": classmethod(
            lambda cls, checker, where, name, spec: [name]), "from_spec": classmethod(
            lambda cls, spec, d: []), "bind": lambda self, mech: None, **facts})

    cases = {
        "must declare REPORTS, what its outputs report, for the reference of the format; "
        "it has none": dict(KEYS=keys),
        "must declare KEYS, a dict of key -> what it is; it has none of its own (KEYS = "
        "Parent.KEYS keeps its parent's)": dict(REPORTS="speed of a point, m/s"),
        "KEYS has no 'name': every output's table names it": dict(
            REPORTS="speed of a point, m/s", KEYS={"point": "the point"}),
        "KEYS has 'kind', which names the output's kind in a description file": dict(
            REPORTS="speed of a point, m/s", KEYS={**keys, "kind": "its kind"}),
        "implements no check: the description's checker asks it": dict(
            REPORTS="speed of a point, m/s", KEYS=keys, check=Output.__dict__["check"]),
        "implements no from_spec: the description's builder asks it": dict(
            REPORTS="speed of a point, m/s", KEYS=keys, from_spec=Output.__dict__["from_spec"]),
    }
    for problem, facts in cases.items():
        with pytest.raises(TypeError) as info:
            define(**facts)
        assert str(info.value) == f"output kind Speed (kind 'speed') {problem}"
    with pytest.raises(TypeError, match=r"^output kind 'bearing' is defined twice: "
                                        r"bearing.<locals>.Bearing and Speed$"):
        type(Output)("Speed", (bearing,), {"kind": "bearing", "REPORTS": "again",
                                           "KEYS": keys})
    assert "speed" not in Output.registry
    assert Output.registry["bearing"] is bearing
