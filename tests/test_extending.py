"""Each extension point is one class in one place: a toy pair kind, a toy group type that
uses it and a toy output kind, each defined in this file alone, build and solve a linkage
(docs/extending.md).

Reference: the four-bar preset, built from the library's own crank, pin and outputs. The
toys compute the same formulas, so the numbers agree to 1e-12 of each output's scale."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from linkage_fmu import presets
from linkage_fmu.descriptions import Description, DescriptionError
from linkage_fmu.groups import FRAME, Field, Group
from linkage_fmu.groups.base import moment_about
from linkage_fmu.outputs import Output
from linkage_fmu.pairs import Pair


@dataclass(frozen=True, slots=True)
class Hinge(Pair):
    """A frictionless pin whose reaction is the force (Hx, Hy) of a on b."""

    components = ("Hx", "Hy")
    friction_prefix = "Mh"
    friction_unit = "N.m"
    draws_pin = True

    def column_scale(self, length_scale):
        return 1.0

    def entries(self, st, row, col, sign, arm):
        # the force's x and y rows, and its moment about the body's centre of mass
        ax, ay = arm
        return [(row, col, sign), (row + 1, col + 1, sign), (row + 2, col, -sign * ay),
                (row + 2, col + 1, sign * ax)]

    def reaction(self, st, first, second):
        return first, second, 0

    def friction_rule(self, radius, length):
        return "a hinge has no friction"

    def friction_formula(self, xp, mu, radius, length, s, first, second):
        raise TypeError("a hinge has no friction")

    def friction_law(self, xp, mu, radius, length, s, reaction, tiny):
        raise TypeError("a hinge has no friction")

    def relative_motion(self, st, omega, velocity):
        raise TypeError("a hinge has no friction")

    def apply_friction(self, st, f, couple, force):
        raise TypeError("a hinge has no friction")

    def friction_description(self):
        return "a hinge has no friction"

    def force_output(self, axis, sign, rubs):
        return lambda R, E, st, name=self.name: sign * R[name][axis]

    def magnitude_output(self):
        def magnitude(R, E, st, name=self.name):
            a, b = R[name]
            return st.xp.sqrt(a * a + b * b)

        return magnitude

    def action(self, R, st, sign, rubs):
        return sign * R[self.name][0], sign * R[self.name][1], self.point, 0.0


@pytest.fixture
def toys(registry):
    """The toy group type (a crank on a hinge) and the toy output kind (the load on a
    pin), defined here; their registries forget them after the test."""
    saved = dict(Output.registry)

    class HingedCrank(Group):
        """A crank ``link`` turning about ``pivot`` on a hinge; its tip is ``tip``."""

        kind = "hinged_crank"
        DRIVER = True
        FIELDS = {
            "link": Field("new link", "the crank"),
            "pivot": Field("point", "the placed point it turns about"),
            "tip": Field("new point", "its end, length from pivot"),
            "length": Field("length", "its length"),
        }

        def __init__(self, link, pivot, tip, length):
            self.link, self.pivot, self.tip, self.length = link, pivot, tip, length
            self.needs, self.places, self.links = (pivot,), (tip,), (link,)
            self.joints = (Hinge(pivot, pivot, FRAME, link),)
            self.owners, self.lengths = {tip: link}, (length,)

        @classmethod
        def from_spec(cls, spec, value):
            return cls(spec["link"], spec["pivot"], spec["tip"], value("length"))

        @classmethod
        def pairs(cls, spec, placed=None):
            return (spec["pivot"],)

        def driver(self, effort, alone=True):
            from linkage_fmu.drivers import Driver

            return Driver.named(self.pivot, "angle", effort, alone)

        @classmethod
        def drives(cls, spec):
            return spec.get("pivot"), "angle", False

        def acts(self):
            return self.link, "", None, FRAME

        def position(self, st):
            c, s = st.xp.cos(st.theta), st.xp.sin(st.theta)
            x0, y0 = st.p[self.pivot]
            st.u[self.link] = (c, s)
            st.p[self.tip] = (x0 + self.length * c, y0 + self.length * s)

        def first(self, st):
            c, s = st.u[self.link]
            st.d1[self.tip] = (-self.length * s, self.length * c)
            st.w1[self.link] = 1.0

        def second(self, st):
            c, s = st.u[self.link]
            st.d2[self.tip] = (-self.length * c, -self.length * s)
            st.w2[self.link] = 0.0

        def statics(self, mech, st, W, R):
            fx, fy, m = moment_about(mech, st, W, self.link, self.pivot)
            R[self.pivot] = (-fx, -fy)
            return -m

        def transmission(self, st, scale):
            return None

    @dataclass(frozen=True)
    class PinLoad(Output):
        """Output: the magnitude of the force a pair transmits, whatever its kind."""

        name: str
        joint: str
        unit = "N"
        kind = "pin_load"
        REPORTS = "magnitude of the force a pair transmits, N"
        KEYS = {"name": "name of the output (required)",
                "joint": "the pair, by its name (required)"}

        @property
        def description(self) -> str:
            return f"load on the pair {self.joint}"

        @classmethod
        def check(cls, checker, where, name, spec):
            if spec.get("joint") not in checker.joints:
                checker.found.append(f"{where} joint: {spec.get('joint')!r} is no pair")
            return [name]

        @classmethod
        def from_spec(cls, spec, d):
            return [cls(spec["name"], spec["joint"])]

        def bind(self, mech):
            (pair,) = [j for j in mech.joints if j.name == self.joint]
            return pair.magnitude_output()

    yield HingedCrank, PinLoad
    Output.registry.clear()
    Output.registry.update(saved)


def hinged_text(ref) -> str:
    """The preset's description file with its crank a hinged crank."""
    text = ref.description.to_toml()
    assert text.count('type = "crank"') == 1
    return text.replace('type = "crank"', 'type = "hinged_crank"')


@pytest.fixture
def hinged(toys):
    """The four-bar preset with its crank a hinged crank (a toy group type with a toy
    pair kind), without the friction table of its pivot A (a hinge has none), reporting
    the load on A and on B by the toy output kind; and the preset itself."""
    ref = presets.get("four_bar")
    text = hinged_text(ref)
    text = text.replace('[friction.A]\nmu = "mu_A"\nradius = "r_A"\n', "")
    d = Description.from_toml(text, "four_bar.toml")
    d.output("pin_load", name="P_A", joint="A").output("pin_load", name="P_B", joint="B")
    return d.build(), ref


@pytest.mark.parametrize("method", ["closed_form", "direct", "interpreted"])
def test_a_toy_pair_kind_in_a_toy_group_type_solves_as_the_library_does(hinged, method):
    """Built with the hinge in its crank, the four-bar gives the preset's outputs by
    every method, scalars and arrays, to 1e-12 of each output's largest magnitude."""
    mech, ref = hinged
    assert type(mech.groups[0]).kind == "hinged_crank" and type(mech.joints[0]) is Hinge
    assert mech.drivers[0].inputs == ("theta", "omega", "alpha")
    thetas = [0.0, 0.7, 2.0, 4.5]
    got = mech.solve(thetas, 12.0, -3.0, 40.0, method=method)
    want = ref.solve(thetas, 12.0, -3.0, 40.0, method=method)
    # the hinge reports no friction; the toy outputs come after the file's own
    assert [n for n in got if n not in ("P_A", "P_B")] == [n for n in want if n != "Mf_A"]
    for name in want:
        if name != "Mf_A":
            scale = max(1.0, float(abs(want[name]).max()))
            assert float(abs(got[name] - want[name]).max()) <= 1e-12 * scale, name
    for pin, force in (("A", "F14"), ("B", "F21")):
        load = np.hypot(want[f"{force}x"], want[f"{force}y"])
        assert np.allclose(got[f"P_{pin}"], load, rtol=1e-12, atol=0.0), pin
    one = mech.solve(0.7, 12.0, -3.0, 40.0, method=method)
    assert math.isclose(one["Mb"], float(want["Mb"][1]), rel_tol=1e-12)


def test_a_hinge_refuses_friction_naming_itself(hinged):
    """The pair kind's own rule refuses a friction table, with its reason."""
    from linkage_fmu.friction import Declared, Friction, resolve

    mech, ref = hinged
    with pytest.raises(ValueError, match="friction of A: a hinge has no friction"):
        resolve(mech, Declared((Friction("A", 0.1, 0.01),)))
    d = Description.from_toml(hinged_text(ref), "four_bar.toml").output(
        "pin_load", name="P_X", joint="X")
    with pytest.raises(DescriptionError, match=r"\[\[outputs\]\] #\d+ \(P_X\) joint: 'X' is no "
                                               "pair"):
        d.build()
    d = Description.from_toml(hinged_text(ref), "four_bar.toml")
    with pytest.raises(ValueError, match="four_bar.toml: friction of A: a hinge has no "
                                         "friction"):
        d.build()
