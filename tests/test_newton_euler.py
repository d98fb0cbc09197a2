"""The independent Newton-Euler reference (tests/newton_euler.py), proved on the presets.

The four_bar, six_bar (with its slider) and slider_crank (e = 0.01) presets and the
coupler four-bar example (a force at a coupler point that is no joint) are written as
joints and links in tests/data (drawn at 60 deg by tests/data/make_drawn_poses.py). The
reference reads them with tomllib and shares no code with the library's groups or
solver; its ``Mb`` and shaking force must equal the group form's to 1e-9 (N.m, N) at
angles within 30 deg of the drawn one, with omega 10 rad/s, alpha 5 rad/s^2 and g 9.81. Its own
physics is checked by virtual power and by the momentum balance, which involve none of the library.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import newton_euler as ne
from linkage_fmu import Description, presets

DATA = Path(__file__).resolve().parent / "data"
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TOL = 1e-9  # N.m and N
OMEGA, ALPHA, G = 10.0, 5.0, 9.81
OFFSETS = np.radians(np.linspace(-30.0, 30.0, 13))
#: case -> (the file, its loads, {(joint, joint): the group form's length})
CASES = {
    "four_bar": ("four_bar_joints.toml", {"load": 3.0},
                 {("A", "B"): 0.10, ("B", "C"): 0.35, ("C", "D"): 0.30, ("A", "D"): 0.40}),
    "six_bar": ("six_bar_joints.toml", {"load": 150.0},
                {("O", "A"): 0.15, ("A", "B"): 0.97, ("O1", "B"): 0.66, ("O1", "K"): 0.25,
                 ("K", "D"): 0.86, ("K", "B"): 0.41}),
    "slider_crank": ("slider_crank_joints.toml", {"load": 300.0}, {("O", "A"): 0.05,
                                                                     ("A", "B"): 0.20}),
    "coupler_four_bar": ("coupler_four_bar_joints.toml", {"F_P": 80.0, "T4": -40.0},
                         {("A", "B"): 0.10, ("B", "C"): 0.35, ("C", "D"): 0.30,
                          ("A", "D"): 0.40, ("B", "P"): math.hypot(0.20, 0.05)}),
}
#: the group form of each case, at the parameters its file is drawn with
GROUP_FORM = {"four_bar": lambda: presets.get("four_bar"),
              "six_bar": lambda: presets.get("six_bar"),
              "slider_crank": lambda: presets.get("slider_crank", e=0.01),
              "coupler_four_bar": lambda: Description.read(EXAMPLES / "coupler_four_bar.toml")
              .build()}
SHAKE = ("shake_x", "shake_y", "shake_M")


def distance(p, u, v) -> float:
    return float(np.hypot(*(np.asarray(p[u]) - np.asarray(p[v]))))


@pytest.mark.parametrize("name", CASES)
def test_drawn_pose_is_the_preset(name):
    """The file's drawn distances are the preset's lengths (so it is that linkage)."""
    path, _, lengths = CASES[name]
    lk = ne.read(DATA / path)
    for (u, v), length in lengths.items():
        assert distance({**lk.joints, **lk.points}, u, v) == pytest.approx(length, abs=1e-15)
    assert math.degrees(lk.theta_drawn) == pytest.approx(60.0, abs=1e-12)


def test_drawn_pose_branches():
    """The assembly modes of the group forms: C left of B->D; B left of A->O1, D above
    K; the piston B on the +x side of A, on the line y = e; P left of B->C."""
    def left(p, a, b, c):
        (ax, ay), (bx, by), (cx, cy) = p[a], p[b], p[c]
        return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax) > 0

    four = ne.read(DATA / "four_bar_joints.toml").joints
    six = ne.read(DATA / "six_bar_joints.toml").joints
    assert left(four, "B", "D", "C")
    assert left(six, "A", "O1", "B")
    assert six["D"][1] > six["K"][1] and six["D"][0] == 0.5
    piston = ne.read(DATA / "slider_crank_joints.toml").joints
    assert piston["B"][0] > piston["A"][0] and piston["B"][1] == 0.01
    coupler = ne.read(DATA / "coupler_four_bar_joints.toml")
    assert left({**coupler.joints, **coupler.points}, "B", "C", "P")


@pytest.mark.parametrize("name", CASES)
def test_reference_equals_presets(name):
    """Mb and the shaking force of the reference equal the group-form preset's to 1e-9."""
    path, loads, _ = CASES[name]
    lk = ne.read(DATA / path)
    mech = GROUP_FORM[name]()
    for offset in OFFSETS:
        theta = lk.theta_drawn + offset
        ref = ne.solve(lk, theta, OMEGA, ALPHA, G, loads)
        sol = mech.solve(theta, omega=OMEGA, alpha=ALPHA, **loads)
        assert ref["residual"] < 1e-10
        for key in ("Mb",) + SHAKE:
            assert ref[key] == pytest.approx(sol[key], abs=TOL), (name, key, offset)


@pytest.mark.parametrize("name", CASES)
def test_virtual_power(name):
    """Mb omega + power of the weights and the load = d/dt of the kinetic energy (1e-9 W)."""
    path, loads, _ = CASES[name]
    lk = ne.read(DATA / path)
    for offset in OFFSETS[::3]:
        r = ne.solve(lk, lk.theta_drawn + offset, OMEGA, ALPHA, G, loads)
        power, kin = ne.power_balance(lk, r, G, loads)
        assert power == pytest.approx(kin, abs=1e-9)


@pytest.mark.parametrize("name", CASES)
def test_shaking_is_the_momentum_balance(name):
    """The force the links put on the frame = their weights and loads minus m a (1e-9 N)."""
    path, loads, _ = CASES[name]
    lk = ne.read(DATA / path)
    r = ne.solve(lk, lk.theta_drawn + 0.2, OMEGA, ALPHA, G, loads)
    total = ne.momentum_balance(lk, r, G, loads)
    assert r["shake_x"] == pytest.approx(total[0], abs=1e-9)
    assert r["shake_y"] == pytest.approx(total[1], abs=1e-9)


def compound_six_bar() -> dict:
    """A four-bar A-B-C-D with a second dyad C-E-F on its pin C: links 2, 3 and 4 share
    the compound joint C."""
    b = (0.1 * math.cos(1.0), 0.1 * math.sin(1.0))
    p = ne.assemble({"A": (0.0, 0.0), "B": b, "D": (0.4, 0.0), "F": (0.7, 0.35)},
                    {"C": (0.35, 0.3), "E": (0.55, 0.6)},
                    [("B", "C", 0.35), ("D", "C", 0.30), ("C", "E", 0.32), ("F", "E", 0.25)])
    xy = {k: [float(v[0]), float(v[1])] for k, v in p.items()}

    def rod(name, u, v, m):
        mid = [(xy[u][0] + xy[v][0]) / 2, (xy[u][1] + xy[v][1]) / 2]
        length = math.dist(xy[u], xy[v])
        return {"name": name, "joints": [u, v], "mass": m, "inertia": m * length ** 2 / 12,
                "cg": mid}

    return {"joints": xy,
            "links": [rod("1", "A", "B", 1.0), rod("2", "B", "C", 2.0), rod("3", "C", "D", 1.5),
                      rod("4", "C", "E", 1.2), rod("5", "E", "F", 0.8)],
            "crank": {"link": "1", "pivot": "A"},
            "loads": [{"name": "T", "body": "5", "kind": "moment", "start": 7.0}]}


def test_compound_joint():
    """Three links on one pin are one pin: virtual power and the momentum balance hold
    (1e-9) with the reactions of 2 on 3 and of 2 on 4 at C as the unknowns."""
    lk = ne.from_data(compound_six_bar())
    assert lk.on("C") == ["2", "3", "4"]
    for offset in OFFSETS[::4]:
        r = ne.solve(lk, lk.theta_drawn + offset, OMEGA, ALPHA, G)
        assert r["residual"] < 1e-10
        power, kin = ne.power_balance(lk, r, G)
        assert power == pytest.approx(kin, abs=1e-9)
        total = ne.momentum_balance(lk, r, G)
        assert r["shake_x"] == pytest.approx(total[0], abs=1e-9)
        assert r["shake_y"] == pytest.approx(total[1], abs=1e-9)
        assert {k for k in r["R"] if k[0] == "C"} == {("C", "3"), ("C", "4")}


def test_mobility_not_one_is_refused():
    """A rod from the four-bar's C to a frame pin E locks it: mobility 0, named."""
    data = compound_six_bar()
    data["links"] = data["links"][:4]
    data["joints"].pop("F")
    with pytest.raises(ne.ReferenceError, match="mobility 0: 12 coordinates, 12 constraint"):
        ne.solve(ne.from_data(data), 1.0, 0.0, 0.0, G)


def test_continuation_returns_after_a_turn():
    """The four-bar (a crank-rocker) continued through a whole turn comes back to its
    drawn pose (same assembly mode) to 1e-12 m."""
    lk = ne.read(DATA / "four_bar_joints.toml")
    q = ne.positions(lk, lk.theta_drawn + 2.0 * math.pi)
    p = ne.where(lk, q)
    for j, drawn in lk.joints.items():
        assert np.max(np.abs(p[j] - drawn)) < 1e-12


def test_reference_is_independent_and_its_examples_hold():
    """The reference imports nothing of linkage_fmu, and its docstring examples run."""
    import ast
    import doctest

    tree = ast.parse(Path(ne.__file__).read_text())
    imported = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    imported |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert not any(name and name.startswith("linkage_fmu") for name in imported)
    assert doctest.testmod(ne).failed == 0


def test_frame_listed_as_a_link_and_values_for_expressions():
    """The frame may list its joints as a link of its own name; a coordinate may be a
    parameter's name or an expression resolved in ``values``, or a length with a unit.
    Each gives the same answer as the plain file (1e-12); an unresolved expression is
    refused by name."""
    import tomllib

    data = tomllib.loads((DATA / "four_bar_joints.toml").read_text())
    plain = ne.solve(ne.from_data(data), 1.2, OMEGA, ALPHA, G, {"load": 3.0})
    data["links"].append({"name": "4", "joints": ["A", "D"]})
    data["parameters"]["l_AD"] = {"default": 0.4}
    data["joints"]["D"] = ["l_AD", "0 mm"]
    data["joints"]["B"] = ["l_AB * cos(60 deg)", data["joints"]["B"][1]]
    lk = ne.from_data(data, {"l_AB * cos(60 deg)": 0.1 * math.cos(math.radians(60.0))})
    assert lk.frame_joints == {"A", "D"}
    r = ne.solve(lk, 1.2, OMEGA, ALPHA, G, {"load": 3.0})
    for key in ("Mb",) + SHAKE:
        assert r[key] == pytest.approx(plain[key], abs=1e-12)
    with pytest.raises(ne.ReferenceError, match=r"\[joints\] B: 'l_AB \* cos\(60 deg\)'"):
        ne.from_data(data)
