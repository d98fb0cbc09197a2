"""The examples driven by several actuators, written as joints and links: the five-bar
robot (two cranks), the excavator arm (three cylinders) and the dump body (one
cylinder), and a five-bar driven by a crank and a motor at its elbow, against the
independent constrained Newton-Euler reference (tests/multibody.py), which reads the
same files and shares nothing with the library.

At 20 states each, across the drivers' ranges, with nonzero speeds and accelerations,
g 9.81 and the example's load: every effort and every pin's force equal the
reference's to 1e-9 N.m or N (the excavator's forces reach 2.6e5 N: the largest
difference, 5.8e-10 N, is 4e-15 of them); and so with Coulomb friction in every pair (mu
0.1, each pin's radius :data:`RADIUS`), the cylinders' guides included.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

import multibody
from linkage_fmu.descriptions import Description

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TOL = 1e-9  # N.m and N
#: example -> (each driver's coordinate range, its load and a magnitude to test it with)
CASES = {
    "five_bar": ([(1.6, 2.2), (0.9, 1.5)], {"P": 12.0}),
    "dump_body": ([(-0.1, 0.4)], {"W": 20000.0}),
    "excavator": ([(-0.3, 0.5), (-0.4, 0.6), (-0.15, 0.4)], {"F_T": 15000.0}),
    "elbow": ([(0.0, 0.3), (-2.8, -2.4)], {"F": 20.0}),
}
#: a five-bar with a crank at A and a motor at B, between the crank and the link BC
ELBOW = """
[linkage]
name = "elbow"
gravity = 9.81

[joints]
A = [0, 0]
B = [0.15, 0.05]
C = [0.3, 0.3]
D = [0.45, 0.2]
E = [0.4, 0]

[[links]]
name = "1"
joints = ["A", "B"]
mass = 0.4
inertia = 0.002
cg = [0.07, 0.02]

[[links]]
name = "2"
joints = ["B", "C"]
mass = 0.6
inertia = 0.004
cg = [0.2, 0.2]

[[links]]
name = "3"
joints = ["C", "D"]
mass = 0.5
inertia = 0.003
cg = [0.38, 0.26]

[[links]]
name = "4"
joints = ["D", "E"]
mass = 0.3
inertia = 0.001
cg = [0.43, 0.1]

[[drivers]]
joint = "A"

[[drivers]]
joint = "B"

[[loads]]
name = "F"
body = "3"
kind = "force"
at = "D"
direction = [0.6, -0.8]
"""


#: the pin radius of each example with friction, m
RADIUS = {"five_bar": 0.005, "dump_body": 0.03, "excavator": 0.04, "elbow": 0.005}


def linkage(name: str, friction: bool = False):
    """The library's linkage and the reference's, from one file; with ``friction``,
    mu 0.1 in every pair and each pin of radius :data:`RADIUS`."""
    text = ELBOW if name == "elbow" else (EXAMPLES / f"{name}.toml").read_text()
    if friction:
        for joint, at in tomllib.loads(text)["joints"].items():
            pin = "" if isinstance(at, dict) else f"\nradius = {RADIUS[name]}"
            text += f"\n[friction.{joint}]\nmu = 0.1{pin}\n"
    return (Description.from_toml(text, f"{name}.toml").build(),
            multibody.Model(tomllib.loads(text)))


def states(ranges, n=20, seed=7):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        q = [rng.uniform(a, b) for a, b in ranges]
        v = [rng.choice([-1.0, 1.0]) * rng.uniform(0.2, 1.0) * (b - a) for a, b in ranges]
        a = [rng.choice([-1.0, 1.0]) * rng.uniform(0.2, 2.0) * (b - a) for a, b in ranges]
        yield q, v, a


def named(mech, q, v, a) -> dict:
    out = {}
    for d, values in zip(mech.drivers, zip(q, v, a)):
        out.update(zip(d.inputs, values))
    return out


@pytest.mark.parametrize("friction", [False, True], ids=["", "friction"])
@pytest.mark.parametrize("name", CASES)
def test_every_effort_and_pin_force_is_the_reference_s(name, friction):
    ranges, loads = CASES[name]
    mech, ref = linkage(name, friction)
    assert bool(ref.friction) == friction and mech.friction.active == friction
    forces = {(o["by"], o["on"]): o["name"] for o in mech.description.outputs
              if o["kind"] == "force"}
    checked = 0
    for q, v, a in states(ranges):
        got = mech.solve(**named(mech, q, v, a), **loads)
        want = ref.solve(q, v, a, loads)
        scale = max(abs(e) for e in want["efforts"])
        if friction:  # it dissipates: the friction is there
            assert got["P_loss"] > 1e-6 * scale and 0.0 < got["eta"] < 1.0, q
        for d, e in zip(mech.drivers, want["efforts"]):
            assert got[d.effort] == pytest.approx(e, abs=TOL), (d.effort, q)
        for (by, on, joint), f in want["pins"].items():
            stem, sign = forces.get((by, on)), 1.0
            if stem is None:
                stem, sign = forces[(on, by)], -1.0
            assert sign * got[stem + "x"] == pytest.approx(f[0], abs=TOL), (joint, q)
            assert sign * got[stem + "y"] == pytest.approx(f[1], abs=TOL), (joint, q)
            checked += 1
    assert checked >= 20 * 3  # every pin of every state


def test_the_examples_are_drawn_as_their_comments_say():
    """The drawn distances the files' parameters name (the reference's reading)."""
    five, dump = multibody.read(EXAMPLES / "five_bar.toml"), multibody.read(
        EXAMPLES / "dump_body.toml")

    def far(model, u, v):
        return float(np.hypot(*(model.drawn(u) - model.drawn(v))))

    for (u, v), length in {("A", "B"): 0.15, ("E", "D"): 0.15, ("B", "C"): 0.25,
                           ("D", "C"): 0.25, ("A", "E"): 0.2}.items():
        assert far(five, u, v) == pytest.approx(length, abs=1e-15), (u, v)
    assert far(dump, "O", "D") == pytest.approx(1.5, abs=1e-15)
    assert far(dump, "E", "D") == pytest.approx(1.2, abs=1e-15)
    assert [d.drawn for d in five.drivers] == pytest.approx([1.9, 1.2], abs=1e-15)


@pytest.mark.parametrize("name", CASES)
def test_the_mass_matrix_is_the_hessian_of_the_kinetic_energy(name):
    """``M(q)`` against the Hessian of the reference's kinetic energy by the drivers'
    speeds, to 1e-10 of its largest entry, at 5 states."""
    ranges, _ = CASES[name]
    mech, ref = linkage(name)
    for q, v, a in list(states(ranges))[:5]:
        M, H = mech.mass_matrix(q), ref.solve(q, v, a)["hessian"]
        assert M == pytest.approx(H, abs=1e-10 * np.max(np.abs(H))), q
        assert np.array_equal(M, M.T)


def test_friction_that_locks_is_an_error_naming_the_drivers_or_a_locked_state():
    """The elbow five-bar with mu 0.9 and pins of 0.2 m (as large as its links): friction
    locks the dyad CDE. One state raises SelfLockingError naming both drivers'
    coordinates, by the closed form and the direct solver alike; arrays give the status
    LOCKED and NaN."""
    from linkage_fmu.errors import SelfLockingError
    from linkage_fmu.solver import LOCKED

    text = ELBOW + "".join(f"\n[friction.{j}]\nmu = 0.9\nradius = 0.2\n" for j in "ABCDE")
    mech = Description.from_toml(text, "elbow.toml").build()
    state = dict(theta_A=0.1, theta_B=-2.6, omega_A=1.0, omega_B=-0.5, F=20.0)
    for method, what in (("closed_form", "friction at C, D, E locks the group of link 3"),
                         ("direct", "friction locks the linkage")):
        with pytest.raises(SelfLockingError, match=r"elbow locks at theta_A = 0.1 rad "
                                                   r"\(5.73 deg\), theta_B = -2.6 rad "
                                                   rf"\(-149 deg\): {what}"):
            mech.solve(**state, method=method)
    sol = mech.solve(**{**state, "theta_A": np.array([0.0, 0.1, 0.2])})
    assert (np.asarray(sol.status) == LOCKED).all() and np.isnan(sol["Mb_A"]).all()
