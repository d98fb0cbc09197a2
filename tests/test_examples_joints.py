"""The joints-and-links examples (examples/jansen.toml, klann.toml, triad_six_bar.toml).

The independent reference (tests/newton_euler.py) checks that each drawn pose is the
published linkage (every drawn distance is its source's length), that the pose carries
through a whole turn of the crank by continuation in 1 deg steps and comes back to
itself (one assembly mode, no lock), and that its forces obey virtual power and the
momentum balance. Then the library, reading the same file, must give the reference's
``Mb`` and shaking force to 1e-9 at angles within 30 deg of the drawn one, with
omega 10 rad/s, alpha 5 rad/s^2 and g 9.81.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

import newton_euler as ne

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
DATA = Path(__file__).resolve().parent / "data"
NAMES = ("jansen", "klann", "triad_six_bar")
OMEGA, ALPHA, G = 10.0, 5.0, 9.81
TOL = 1e-9  # N.m and N
OFFSETS = np.radians(np.linspace(-30.0, 30.0, 13))
#: the example's load and a magnitude to test it with
LOADS = {"jansen": {"F_foot": 60.0}, "klann": {"F_foot": 45.0}, "triad_six_bar": {"T": -8.0}}

HOLY = dict(a=38.0, b=41.5, c=39.3, d=40.1, e=55.8, f=39.4, g=36.7, h=65.7, i=49.0, j=50.0,
            k=61.9, l=7.8, m=15.0)  # cm, strandbeest.com/explains
#: Jansen's lengths between joints (or the foot F), by their letters
JANSEN = {("O", "A"): "m", ("A", "B"): "j", ("Z", "B"): "b", ("Z", "C"): "c", ("Z", "D"): "d",
          ("B", "D"): "e", ("D", "E"): "f", ("C", "E"): "g", ("E", "F"): "h", ("C", "F"): "i",
          ("A", "C"): "k"}
#: boim.com/Walkin8r/Klann.html, units taken as cm
KLANN = {("A", "C"): 17.5, ("B", "H"): 23.7, ("C", "F"): 73.4, ("C", "H"): 38.8,
         ("D", "E"): 34.1, ("E", "F"): 57.7, ("E", "G"): 111.7, ("F", "G"): 59.0,
         ("F", "H"): 35.2}


def read(name: str) -> ne.Linkage:
    return ne.read(EXAMPLES / f"{name}.toml")


def drawn(lk, u, v) -> float:
    p = {**lk.joints, **lk.points}
    return float(np.hypot(*(p[u] - p[v])))


def test_jansen_is_drawn_with_the_holy_numbers():
    lk = read("jansen")
    for (u, v), letter in JANSEN.items():
        assert drawn(lk, u, v) == pytest.approx(HOLY[letter] / 100.0, abs=1e-12), (u, v)
    z = lk.joints["Z"] - lk.joints["O"]
    assert z == pytest.approx([-HOLY["a"] / 100.0, -HOLY["l"] / 100.0], abs=1e-15)
    # one frame pivot Z for the triangle bde and the rocker c, listed by the frame's entry
    assert lk.frame_joints == {"O", "Z"} and lk.on("Z") == ["bde", "c"]
    assert lk.on("A") == ["crank", "j", "k"] and lk.on("C") == ["k", "c", "leg"]


def test_klann_is_drawn_with_the_published_lengths():
    lk = read("klann")
    for (u, v), length in KLANN.items():
        assert drawn(lk, u, v) == pytest.approx(length / 100.0, abs=1e-12), (u, v)
    assert lk.joints["B"] - lk.joints["A"] == pytest.approx([-0.388, -0.125], abs=1e-15)
    assert lk.joints["D"] - lk.joints["A"] == pytest.approx([-0.146, 0.419], abs=1e-15)


def test_triad_is_one_class_three_group():
    """The plate is ternary, each rod binary with one end on it; the other ends are the
    crank pin and two frame pivots, so no dyad (two links, three pins, two of them on
    what is already placed) exists besides the crank."""
    lk = read("triad_six_bar")
    plate = lk.links[lk.index["plate"]]
    assert len(plate.joints) == 3
    placed = {"O", "A", "O2", "O3"}  # frame pivots and the crank's pin
    rods = [link for link in lk.links if link.name.startswith("rod")]
    for a, b in itertools.combinations(rods + [plate], 2):
        shared = set(a.joints) & set(b.joints)
        outer = (set(a.joints) | set(b.joints)) - shared
        assert not (len(shared) == 1 and outer <= placed), (a.name, b.name)
    for rod in rods:
        assert drawn(lk, *rod.joints) == pytest.approx(0.22, abs=1e-15)


@pytest.mark.parametrize("name", NAMES)
def test_whole_turn(name):
    """Continued over a whole turn in 1 deg steps, Newton converges at every step, the
    constraint Jacobian stays well conditioned (no lock, no change of assembly mode),
    every link keeps its drawn distances, and the pose comes back to the drawn one."""
    lk = read(name)
    thetas = lk.theta_drawn + np.radians(np.arange(0.0, 361.0, 1.0))
    poses = ne.sweep(lk, thetas)
    rows = ne._rows(lk)
    assert max(np.linalg.cond(ne._jacobian(lk, rows, q)) for q in poses) < 1e3
    lengths = ne.distances(lk, np.zeros_like(poses[0]))
    for q in poses[::30]:
        for key, value in ne.distances(lk, q).items():
            assert value == pytest.approx(lengths[key], abs=1e-12), key
    back = ne.where(lk, poses[-1])
    for j, p in lk.joints.items():
        assert np.max(np.abs(back[j] - p)) < 1e-12


@pytest.mark.parametrize("name", NAMES)
def test_reference_physics(name):
    """Virtual power and the momentum balance, which use none of the reactions (1e-9)."""
    lk = read(name)
    for offset in OFFSETS[::3]:
        r = ne.solve(lk, lk.theta_drawn + offset, OMEGA, ALPHA, G, LOADS[name])
        assert r["residual"] < 1e-10
        power, kinetic = ne.power_balance(lk, r, G, LOADS[name])
        assert power == pytest.approx(kinetic, abs=1e-9)
        total = ne.momentum_balance(lk, r, G, LOADS[name])
        assert [r["shake_x"], r["shake_y"]] == pytest.approx(list(total), abs=1e-9)


def library(path: Path):
    """The library's Mechanism of the description at ``path``."""
    from linkage_fmu import Description

    return Description.read(path).build()


#: every joints-and-links file with the loads to test it with
FILES = {EXAMPLES / f"{n}.toml": LOADS[n] for n in NAMES} | {
    DATA / "four_bar_joints.toml": {"load": 3.0},
    DATA / "six_bar_joints.toml": {"load": 150.0},
    DATA / "slider_crank_joints.toml": {"load": 300.0},
    DATA / "coupler_four_bar_joints.toml": {"F_P": 80.0, "T4": -40.0},
}


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.stem)
def test_library_equals_reference(path):
    """The library reproduces every drawn joint at the drawn angle (1e-12 m), and its
    Mb and shaking force equal the reference's to 1e-9 within 30 deg of the drawn
    angle, omega 10, alpha 5, g 9.81."""
    mech = library(path)
    lk = ne.read(path)
    st = mech.kinematics(lk.theta_drawn, order=0)
    for j, p in lk.joints.items():
        if j not in lk.slides:
            assert np.max(np.abs(np.array(st.p[j], float) - p)) < 1e-12, j
    loads = FILES[path]
    for offset in OFFSETS:
        theta = lk.theta_drawn + offset
        ref = ne.solve(lk, theta, OMEGA, ALPHA, G, loads)
        sol = mech.solve(theta, omega=OMEGA, alpha=ALPHA, **loads)
        for key in ("Mb", "shake_x", "shake_y", "shake_M"):
            assert sol[key] == pytest.approx(ref[key], abs=TOL), (path.stem, key, offset)


@pytest.mark.parametrize("name", NAMES)
def test_reference_motion_is_the_derivative_of_its_positions(name):
    """Velocities and accelerations from the differentiated constraints equal central
    differences of the positions (step 1e-3 rad: truncation about 1e-7 of the values)
    with q' omega and q'' omega^2 + q' alpha."""
    lk = read(name)
    h = 1e-3
    for offset in OFFSETS[::4]:
        theta = lk.theta_drawn + offset
        q0, qm, qp = (ne.positions(lk, theta + d) for d in (0.0, -h, h))
        qd, qdd = ne.motion(lk, q0, OMEGA, ALPHA)
        d1, d2 = (qp - qm) / (2 * h), (qp - 2 * q0 + qm) / h ** 2
        scale = np.max(np.abs(qdd))
        np.testing.assert_allclose(qd, d1 * OMEGA, atol=1e-6 * np.max(np.abs(qd)))
        np.testing.assert_allclose(qdd, d2 * OMEGA ** 2 + d1 * ALPHA, atol=1e-5 * scale)
