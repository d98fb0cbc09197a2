"""Description files and the builder: every problem of a bad file reported at once, with
its table and key; the file is the builder's serialisation; expressions are evaluated
safely; group types fail loudly when incomplete; loads are inputs by name."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import linkage_fmu
from conftest import power_residual
from linkage_fmu import Description, DescriptionError, groups, presets
from linkage_fmu.spec import Expression

EXAMPLE = Path(__file__).parents[1] / "examples" / "coupler_four_bar.toml"

BAD = '''
[linkage]
name = "broken"
model = "1nvalid"
colour = "red"

[parameters]
L = { default = -1.0, kind = "length", description = "a length" }
m = { default = 1.0, kind = "weight" }

[points]
A = [0, 0]

[[groups]]
type = "crank"
link = "1"
pivot = "A"
tip = "B"
length = "L"

[[groups]]
type = "RRR"
link1 = "2"
link2 = "3"
end1 = "B"
middle = "C"
end2 = "D"
length1 = "L * 2"
length2 = "__import__('os').system('echo hi')"
branch = 1

[[groups]]
type = "RRRR"

[bodies.1]
mass = "mass_of_crank"
cg = { from = "A" }

[bodies.2]
cg = { from = "B", along = 0.1, distance = 0.2 }

[bodies.9]
cg = { from = "A" }

[[loads]]
name = "omega"
body = "2"
kind = "push"

[effort]
name = "Mb"
body = "7"

[[outputs]]
kind = "force"
name = "F12"
by = "1"
on = "2"

[[outputs]]
kind = "force"
name = "F12"
by = "1"
on = "2"
'''


def test_a_malformed_file_lists_every_problem(tmp_path):
    """Each problem names the file, the table (and entry) and key, and why."""
    path = tmp_path / "broken.toml"
    path.write_text(BAD)
    with pytest.raises(DescriptionError) as info:
        linkage_fmu.load(path)
    err = info.value
    text = str(err)
    assert text.startswith(f"{path}: ")
    expected = [
        "[linkage] colour: unknown key",
        "[linkage] model: '1nvalid' must be a C identifier",
        "[parameters] L: default: L must be > 0 (a length), got -1.0",
        "[parameters] m: kind 'weight' is unknown",
        "[[groups]] #2 (RRR) end2: point 'D' is not placed before this group",
        "[[groups]] #2 (RRR) length2: \"__import__('os').system\" is not a function an "
        "expression may call",
        "[[groups]] #3 type: 'RRRR' is not a group type",
        "[bodies.3]: missing: link '3'",
        "[bodies.1] mass: 'mass_of_crank' uses 'mass_of_crank', which is not a parameter",
        "[bodies.2] cg: give along/across or distance/angle, not both",
        "[bodies.9]: no group adds a link '9': a body without a link",
        "[[loads]] #1 (omega) name: 'omega' is already an input or parameter name",
        "[[loads]] #1 (omega) kind: 'push' must be 'force' or 'moment'",
        "[effort] body: '7' is not a moving link",
        "[[outputs]] #2 (F12): output name 'F12x' is used twice",
    ]
    for line in expected:
        assert any(p.startswith(line) for p in err.problems), (line, err.problems)
    assert len(err.problems) == len(expected) + 1  # and F12y used twice
    assert all(line in text for line in expected)


def test_the_file_is_the_builders_serialisation():
    """The README's coupler four-bar composed with the builder equals the file, and both
    give the same numbers."""
    d = (Description("coupler_four_bar", "Four-bar with a coupler-point force and a rocker "
                     "torque", model="CouplerFourBar", frame="0", gravity="g")
         .parameter("l_AB", 0.10, "length", "crank AB")
         .parameter("l_BC", 0.35, "length", "coupler BC")
         .parameter("l_CD", 0.30, "length", "rocker CD")
         .parameter("l_AD", 0.40, "length", "frame AD, D on the +x axis")
         .parameter("P_along", 0.20, "coordinate", "coupler point P from B along BC")
         .parameter("P_across", 0.05, "coordinate", "coupler point P to the left of BC")
         .parameter("m2", 2.0, "mass", "coupler mass", max=100.0)
         .parameter("J2", 0.02, "inertia", "coupler inertia about its centre of mass")
         .parameter("m3", 1.5, "mass", "rocker mass")
         .parameter("J3", 0.012, "inertia", "rocker inertia about its centre of mass")
         .parameter("g", 9.81, "gravity", "gravity along -y")
         .point("A", 0, 0).point("D", "l_AD", 0)
         .group("crank", link="1", pivot="A", tip="B", length="l_AB")
         .group("RRR", link1="2", link2="3", end1="B", middle="C", end2="D",
                length1="l_BC", length2="l_CD", branch=1)
         .group("point", link="2", **{"from": "B"}, name="P", along="P_along",
                across="P_across")
         .body("1", cg={"from": "A"})
         .body("2", mass="m2", inertia="J2", cg={"from": "B", "along": "l_BC / 2"})
         .body("3", mass="m3", inertia="J3", cg={"from": "D", "along": "l_CD / 2"})
         .load("F_P", body="2", kind="force", at="P", direction=[0, -1],
               description="process force at the coupler point P", start=80.0)
         .load("T4", body="3", kind="moment",
               description="torque on the rocker, counter-clockwise positive", start=120.0)
         .effort("Mb", body="1")
         .output("force", name="F12", by="1", on="2", magnitude="F12_abs")
         .output("force", name="F23", by="2", on="3")
         .output("force", name="F03", by="0", on="3", magnitude=True)
         .output("effort", name="Mb")
         .start(omega=25.0))
    from_file = Description.read(EXAMPLE)
    assert d == from_file
    a = d.build().solve(0.6, 25.0, -40.0, F_P=80.0, T4=120.0)
    b = linkage_fmu.load(EXAMPLE).solve(0.6, 25.0, -40.0, 80.0, 120.0)
    assert dict(a) == dict(b)


def test_loads_are_inputs_by_name_and_balance_the_power():
    """solve(..., F_P=..., T4=...) and positionally; the power balance holds with both
    loads (1e-12 of the largest power term); a magnitude is the hypot of its components."""
    mech = linkage_fmu.load(EXAMPLE)
    assert mech.input_names == ("theta", "omega", "alpha", "F_P", "T4")
    theta, omega, alpha = 0.6, 25.0, -40.0
    sol = mech.solve(theta, omega, alpha, F_P=80.0, T4=120.0)
    res, size = power_residual(mech, sol, theta, omega, alpha, (80.0, 120.0))
    assert abs(res) <= 1e-12 * size
    assert sol["F12_abs"] == pytest.approx(math.hypot(sol["F12x"], sol["F12y"]), rel=1e-15)
    with pytest.raises(TypeError, match="has no input 'F_Q'; its inputs are: theta, omega, "
                                        "alpha, F_P, T4"):
        mech.solve(theta, F_Q=1.0)
    with pytest.raises(ValueError, match="T4 must be a finite number, got nan"):
        mech.solve(theta, T4=math.nan)
    with pytest.raises(ValueError, match="m2 must be <= 100.0"):
        linkage_fmu.load(EXAMPLE, m2=1e3)
    arrays = mech.solve(np.array([0.6, 1.0]), omega, alpha, T4=np.array([120.0, 0.0]))
    assert arrays["Mb"].shape == (2,)


@pytest.mark.parametrize("text", [
    "l.__class__", "(lambda: 1)()", "[x for x in l]", "l if l else 1", "'a' * 3", "l[0]",
    "open('f')", "True", "l < 1",
])
def test_expressions_take_numbers_names_and_arithmetic_only(text):
    with pytest.raises(ValueError):
        Expression(text)


def test_expressions_evaluate_over_parameters():
    assert Expression("-l_AS1 * sin(beta1) + 2 ** 3")({"l_AS1": 2.0, "beta1": math.pi / 2}) == 6.0
    assert Expression(0.25)({}) == 0.25
    with pytest.raises(ValueError, match="unknown name 'q'"):
        Expression("q + 1")({})


def test_a_group_subclass_works_and_an_incomplete_group_fails_loudly():
    """A subclass of RRR with no changes solves like RRR (it used to return Mb = -0.0 and
    then KeyError); a group class that misses a method cannot be instantiated; a
    linkage refuses an object that is not a group."""
    class MyRRR(groups.RRR):
        pass

    base = presets.get("four_bar")
    mine = linkage_fmu.Mechanism(
        "mine", base.frame, base.frame_points,
        [base.groups[0], MyRRR("2", "3", "B", "C", "D", 0.35, 0.30, 1)], base.bodies,
        base.effort, [linkage_fmu.outputs.EffortOutput("Mb")], base.loads, base.g)
    assert mine.solve(0.3, 10.0)["Mb"] == base.solve(0.3, 10.0)["Mb"]

    class Half(groups.Group):
        def position(self, st):
            pass

    with pytest.raises(TypeError, match="abstract"):
        Half()
    with pytest.raises(TypeError, match="is not a group"):
        linkage_fmu.Mechanism("x", "0", {"A": (0, 0)}, [base.groups[0], object()], [],
                              base.effort, [], [], 0.0)
