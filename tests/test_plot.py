"""linkage_fmu.plot: every figure renders to PNG, and what it draws is the solver's data.

The reference is always ``mech.solve`` (or ``mech.kinematics``) at the same angles and
inputs; the plotted arrays must equal it to 1e-12 relative (they are the same floats,
only passed through matplotlib), the derived marks (mean, peak, minimum) must be the
plain numpy reductions of it, and toggle angles must match the closed-form geometry.
"""

from __future__ import annotations

import itertools
import math
import sys
from pathlib import Path

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.quiver import Quiver  # noqa: E402
from matplotlib.text import Text  # noqa: E402

import linkage_fmu  # noqa: E402
from linkage_fmu import plot, presets  # noqa: E402
from linkage_fmu.descriptions import Description  # noqa: E402
from linkage_fmu.pairs import Revolute  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "coupler_four_bar.toml"
PNG = b"\x89PNG\r\n\x1a\n"
RTOL = 1e-12  # plotted data vs the solver: the same floats
DEG = np.linspace(0.0, 360.0, 721)  # the documented default angles
#: (preset, parameters, inputs): four-bar and slider-crank with speed, acceleration, load
CASES = [
    ("four_bar", {}, dict(omega=12.0, alpha=3.0, load=4.0)),
    ("slider_crank", {"e": 0.01}, dict(omega=150.0, alpha=-20.0, load=300.0)),
]
CASE_IDS = [c[0] for c in CASES]


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def saved_png(fig, path: Path) -> bytes:
    fig.savefig(path)
    data = path.read_bytes()
    assert data[:8] == PNG, f"{path} is not a PNG"
    assert len(data) > 5000, f"{path} is suspiciously small ({len(data)} bytes)"
    return data


def by_gid(ax) -> dict:
    """gid -> list of Line2D."""
    out: dict = {}
    for line in ax.lines:
        out.setdefault(line.get_gid(), []).append(line)
    return out


def solve_deg(mech, deg, **inputs):
    omega, alpha = inputs.pop("omega", 0.0), inputs.pop("alpha", 0.0)
    return mech.solve(np.radians(deg), omega, alpha, **inputs)


# -- torque --------------------------------------------------------------------------------
@pytest.mark.parametrize("name, params, inputs", CASES, ids=CASE_IDS)
def test_torque_is_the_solved_effort_with_its_mean_and_peak(tmp_path, name, params, inputs):
    mech = presets.get(name, **params)
    fig = plot.torque(mech, **inputs)
    saved_png(fig, tmp_path / f"torque_{name}.png")
    ax = fig.axes[0]
    lines = by_gid(ax)
    ref = solve_deg(mech, DEG, **dict(inputs))
    assert ref.valid.all()
    mb = ref[mech.effort.name]

    x, y = lines[mech.effort.name][0].get_data()
    np.testing.assert_array_equal(x, DEG)  # degrees, 0..360 in 0.5 steps
    np.testing.assert_allclose(y, mb, rtol=RTOL, atol=0)

    # the mean over a revolution: the 721st angle is the first again
    (mean_line,) = lines["mean"]
    np.testing.assert_allclose(mean_line.get_ydata(), [np.mean(mb[:-1])] * 2, rtol=1e-9,
                               atol=1e-12 * np.max(np.abs(mb)))
    assert f"{np.mean(mb[:-1]):.4g} N.m" in mean_line.get_label()

    i = int(np.argmax(np.abs(mb)))
    (peak,) = lines["peak"]
    np.testing.assert_array_equal(peak.get_xdata(), [DEG[i]])
    np.testing.assert_allclose(peak.get_ydata(), [mb[i]], rtol=RTOL)
    assert f"at θ = {DEG[i]:.1f}°" in "".join(t.get_text() for t in ax.texts)


def test_torque_mean_is_zero_without_net_work():
    """A slider-crank at constant speed with a constant piston force does no net work
    per revolution (the force is conservative, inertia returns its energy): mean Mb = 0,
    a check of the mean that does not use the solver's numbers."""
    mech = presets.get("slider_crank")
    fig = plot.torque(mech, omega=100.0, load=500.0)
    lines = by_gid(fig.axes[0])
    y = lines["Mb"][0].get_ydata()
    peak = np.max(np.abs(y))
    assert peak > 10.0
    assert abs(lines["mean"][0].get_ydata()[0]) < 1e-12 * peak
    # the peak is of |Mb|: here a negative value (-32.19 N.m; the largest Mb is 32.07)
    i = int(np.argmax(np.abs(y)))
    assert y[i] < 0 < np.max(y) < -y[i]
    np.testing.assert_array_equal(np.ravel(lines["peak"][0].get_data()), [DEG[i], y[i]])


def test_torque_mean_is_printed_against_the_curve_scale():
    """The scotch yoke (crank r, block m2 on its pin, yoke m3 moving y = r sin(theta),
    no gravity, a force F along -y on the yoke) at constant speed: kinetic energy
    T = (m2 + m3 cos(theta)^2) r^2 omega^2 / 2 and Mb omega = dT/dt + F r cos(theta)
    omega, so Mb = F r cos(theta) - m3 r^2 omega^2 sin(2 theta) / 2, whose mean over
    the 720 equal steps of a revolution is exactly 0: the label says 0, not what
    rounding leaves of the sum (about -2e-15 N.m). With alpha as well, Mb gains
    (J1 + m2 r^2 + m3 r^2 cos(theta)^2) alpha, of mean alpha (J1 + m2 r^2 + m3 r^2 / 2),
    printed to 4 digits."""
    r, m2, m3, j1, omega, force = 0.1, 4.2, 10.0, 0.013, 10.0, 400.0
    yoke = presets.get("scotch_yoke", l_AB=r, m2=m2, m3=m3, J1=j1, g=0.0)
    t = np.radians(DEG)
    lines = by_gid(plot.torque(yoke, omega=omega, alpha=0.0, load=force).axes[0])
    mb = force * r * np.cos(t) - m3 * r * r * omega ** 2 * np.sin(2 * t) / 2
    peak = np.max(np.abs(mb))
    np.testing.assert_allclose(lines["Mb"][0].get_ydata(), mb, rtol=0, atol=1e-13 * peak)
    assert abs(lines["mean"][0].get_ydata()[0]) < 1e-12 * peak
    assert lines["mean"][0].get_label() == "mean 0 N.m"

    alpha = 3.0
    lines = by_gid(plot.torque(yoke, omega=omega, alpha=alpha, load=0.0).axes[0])
    mean = alpha * (j1 + m2 * r * r + m3 * r * r / 2)  # 0.315 N.m
    np.testing.assert_allclose(lines["mean"][0].get_ydata(), [mean] * 2, rtol=1e-12)
    assert lines["mean"][0].get_label() == "mean 0.315 N.m"


@pytest.mark.parametrize("name, inputs, side", [
    ("four_bar", {"omega": 10.0, "load": 3.0}, "left"),  # its peak at 312 deg
    ("slider_crank", {"omega": 100.0, "load": 500.0}, "right")])
def test_torque_peak_label_stays_inside_its_axes(name, inputs, side):
    """The peak's label is on the side of the peak with room, towards the middle of the
    axes (to the left of a peak in their right half), and its box inside the axes."""
    fig = plot.torque(presets.get(name), **inputs)
    ax = fig.axes[0]
    (label,) = [t for t in ax.texts if t.get_gid() == "peak label"]
    (peak,) = [line for line in ax.lines if line.get_gid() == "peak"]
    fig.canvas.draw()
    box = label.get_window_extent(fig.canvas.get_renderer())
    x, _ = ax.transData.transform((peak.get_xdata()[0], peak.get_ydata()[0]))
    assert (box.x1 < x) if side == "left" else (box.x0 > x)
    x0, y0, x1, y1 = ax.bbox.extents
    assert x0 <= box.x0 and box.x1 <= x1 and y0 <= box.y0 and box.y1 <= y1


def test_rounded_cuts_below_the_scale_only():
    assert plot.rounded(-3.16e-16, 5.0) == "0"
    assert plot.rounded(4.9e-12, 5.0) == "0"  # 1e-12 of the scale
    assert plot.rounded(5.1e-12, 5.0) == "5.1e-12"
    assert plot.rounded(-1234.5678, 5.0) == "-1235"
    assert plot.rounded(0.0, 0.0) == "0"  # a curve of zeros


def test_torque_other_output_theta_in_radians_and_an_axes_given(tmp_path):
    mech = presets.get("four_bar")
    theta = np.linspace(0.5, 2.0, 50)
    fig0, ax = plt.subplots()
    fig = plot.torque(mech, theta, 10.0, 0.0, 2.0, output="F32y", ax=ax)
    assert fig is fig0
    saved_png(fig, tmp_path / "torque_f32y.png")
    x, y = by_gid(ax)["F32y"][0].get_data()
    np.testing.assert_allclose(x, np.degrees(theta), rtol=RTOL)
    np.testing.assert_allclose(y, mech.solve(theta, 10.0, 0.0, 2.0)["F32y"], rtol=RTOL)
    # the mean over a part of a revolution: the trapezoidal mean over the angle
    trapezoid = np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(theta)) / (theta[-1] - theta[0])
    np.testing.assert_allclose(by_gid(ax)["mean"][0].get_ydata()[0], trapezoid, rtol=1e-12)


def test_torque_defaults_are_the_description_start_values():
    mech = linkage_fmu.load(EXAMPLE)  # omega = 25, F_P = 80, T4 = 120 in the file
    fig = plot.torque(mech)
    y = by_gid(fig.axes[0])["Mb"][0].get_ydata()
    ref = mech.solve(np.radians(DEG), 25.0, 0.0, F_P=80.0, T4=120.0)["Mb"]
    np.testing.assert_allclose(y, ref, rtol=RTOL)
    assert not np.allclose(y, mech.solve(np.radians(DEG), 25.0, 0.0, F_P=0.0, T4=0.0)["Mb"])


def test_torque_shows_gaps_where_the_linkage_cannot_be_assembled(tmp_path):
    mech = presets.get("four_bar", l_AB=0.3)  # BD reaches BC + CD: 136..224 deg impossible
    fig = plot.torque(mech, theta_deg=DEG, omega=10.0)
    saved_png(fig, tmp_path / "torque_gaps.png")
    lines = by_gid(fig.axes[0])
    ref = solve_deg(mech, DEG, omega=10.0)
    y = lines["Mb"][0].get_ydata()
    assert 100 < np.count_nonzero(~ref.valid) < 721
    np.testing.assert_array_equal(np.isnan(y), ~ref.valid)  # NaN: matplotlib leaves gaps
    np.testing.assert_allclose(y[ref.valid], ref["Mb"][ref.valid], rtol=RTOL)
    # mean over the angles that can be assembled (intervals with both ends valid)
    total = span = 0.0
    for k in range(720):
        if ref.valid[k] and ref.valid[k + 1]:
            total += 0.5 * (ref["Mb"][k] + ref["Mb"][k + 1]) * 0.5
            span += 0.5
    np.testing.assert_allclose(lines["mean"][0].get_ydata()[0], total / span, rtol=1e-12)
    i = int(np.nanargmax(np.abs(ref["Mb"])))
    np.testing.assert_array_equal(lines["peak"][0].get_xdata(), [DEG[i]])


# -- polar ---------------------------------------------------------------------------------
@pytest.mark.parametrize("name, params, inputs", CASES, ids=CASE_IDS)
def test_polar_is_the_pin_force_hodograph(tmp_path, name, params, inputs):
    mech = presets.get(name, **params)
    fig = plot.polar(mech, "F21", **inputs)
    saved_png(fig, tmp_path / f"polar_{name}.png")
    ax = fig.axes[0]
    lines = by_gid(ax)
    ref = solve_deg(mech, DEG, **dict(inputs))
    fx, fy = ref["F21x"], ref["F21y"]
    x, y = lines["F21"][0].get_data()
    np.testing.assert_allclose(x, fx, rtol=RTOL, atol=0)
    np.testing.assert_allclose(y, fy, rtol=RTOL, atol=0)
    np.testing.assert_array_equal(np.ravel(lines["origin"][0].get_data()), [0.0, 0.0])
    i = int(np.argmax(np.hypot(fx, fy)))
    np.testing.assert_allclose(np.ravel(lines["peak"][0].get_data()), [fx[i], fy[i]],
                               rtol=RTOL)
    text = "".join(t.get_text() for t in ax.texts)
    assert f"{math.hypot(fx[i], fy[i]):.4g} N" in text and f"θ = {DEG[i]:.1f}°" in text
    assert ax.get_aspect() == 1.0


def test_polar_default_pair_and_named_by_component():
    six = presets.get("six_bar")  # the six-bar's forces are XO/YO, XA/YA, ...
    for force in ("A", "XA", "YA"):
        x, y = by_gid(plot.polar(six, force, load=50.0).axes[0])["A"][0].get_data()
        ref = solve_deg(six, DEG, load=50.0)
        np.testing.assert_allclose(x, ref["XA"], rtol=RTOL)
        np.testing.assert_allclose(y, ref["YA"], rtol=RTOL)
    four = presets.get("four_bar")
    assert "F21" in by_gid(plot.polar(four).axes[0])  # the first pair


# -- the linkage ---------------------------------------------------------------------------
def test_force_pairs_sit_at_their_joints():
    assert [(p.name, p.x, p.y, p.point) for p in plot.force_pairs(presets.get("four_bar"))] == [
        ("F21", "F21x", "F21y", "B"), ("F32", "F32x", "F32y", "C"),
        ("F43", "F43x", "F43y", "D"), ("F14", "F14x", "F14y", "A")]
    six = plot.force_pairs(presets.get("six_bar"))  # N4 has one component: not a pair
    assert [(p.x, p.y, p.point) for p in six] == [
        ("XO", "YO", "O"), ("XA", "YA", "A"), ("XB", "YB", "B"), ("XO1", "YO1", "O1"),
        ("XK", "YK", "K"), ("XD", "YD", "D")]
    assert [p.point for p in plot.force_pairs(linkage_fmu.load(EXAMPLE))] == ["B", "C", "D"]


def test_force_pairs_without_a_description_come_from_the_output_names():
    for name in ("four_bar", "slider_crank", "crank_shaper"):
        mech = presets.get(name)
        expected = plot.force_pairs(mech)
        mech.description = None  # as if built in Python from groups and outputs
        assert plot.force_pairs(mech) == expected
    six = presets.get("six_bar")
    six.description = None  # XO/YO: no common stem ending in x/y
    assert plot.force_pairs(six) == ()


def quiver_of(ax) -> Quiver:
    (q,) = [c for c in ax.collections if isinstance(c, Quiver) and c.get_gid() == "forces"]
    return q


LINKAGES = [
    (lambda: presets.get("four_bar"), 0.7, dict(omega=12.0, alpha=3.0, load=4.0)),
    (lambda: presets.get("slider_crank", e=0.01), 2.0, dict(omega=150.0, load=300.0)),
    (lambda: presets.get("six_bar"), 1.2, dict(load=200.0)),
    (lambda: presets.get("six_bar", driver="D"), 4.0, dict(load=200.0)),
    (lambda: linkage_fmu.load(EXAMPLE), 0.6, dict(omega=25.0, alpha=-40.0, F_P=80.0, T4=120.0)),
]


@pytest.mark.parametrize("make, theta, inputs", LINKAGES,
                         ids=["four_bar", "slider_crank", "six_bar", "six_bar-D", "coupler"])
def test_linkage_arrows_are_the_joint_forces_to_scale(tmp_path, make, theta, inputs):
    mech = make()
    pairs = plot.force_pairs(mech)
    st = mech.kinematics(theta, order=0)
    omega, alpha = inputs.get("omega", 0.0), inputs.get("alpha", 0.0)
    loads = {k: v for k, v in inputs.items() if k not in ("omega", "alpha")}
    sol = mech.solve(theta, omega, alpha, **loads)
    forces = np.array([(sol[p.x], sol[p.y]) for p in pairs])
    at = np.array([st.p[p.point] for p in pairs], dtype=float)

    # an explicit scale
    fig = plot.linkage(mech, theta, omega, alpha, scale=2e-4, **loads)
    saved_png(fig, tmp_path / f"linkage_{mech.name}.png")
    q = quiver_of(fig.axes[0])
    np.testing.assert_allclose(np.c_[q.X, q.Y], at, rtol=RTOL, atol=1e-15)
    np.testing.assert_allclose(np.c_[q.U, q.V], 2e-4 * forces, rtol=RTOL, atol=0)

    # the default scale: the largest arrow (joint force or load) is 0.4 of the larger
    # side of the bounding box of the linkage's points (the centres of mass lie inside
    # it for these)
    fig = plot.linkage(mech, theta_deg=math.degrees(theta), **inputs)
    q = quiver_of(fig.axes[0])
    points = np.array(list(st.p.values()), dtype=float)
    size = np.max(points.max(axis=0) - points.min(axis=0))
    arrows = np.c_[q.U, q.V]
    loads = [a for a in fig.axes[0].collections if (a.get_gid() or "").startswith("load:")]
    longest = max(np.hypot(arrows[:, 0], arrows[:, 1]).tolist() +
                  [math.hypot(a.U[0], a.V[0]) for a in loads])
    np.testing.assert_allclose(longest, 0.4 * size, rtol=1e-9)
    k = arrows[:, 0] / np.where(forces[:, 0] != 0, forces[:, 0], np.nan)
    assert np.nanmax(k) == pytest.approx(np.nanmin(k), rel=1e-12)  # one scale for all
    # every moving link is drawn, and every revolute joint
    gids = {a.get_gid() for a in fig.axes[0].get_children()}
    assert {f"link:{b.name}" for b in mech.bodies} <= gids
    (joints,) = by_gid(fig.axes[0])["joints"]
    revolute = [st.p[j.point] for j in mech.joints if isinstance(j, Revolute)]
    np.testing.assert_allclose(np.array(joints.get_data(), float).T, np.array(revolute, float),
                               rtol=RTOL, atol=1e-15)


def loaded_coupler():
    """The coupler four-bar (F_P down at P, T4 on the rocker 3) with, besides, a force
    F_R at C along the rocker's own y axis, and over the cycle a moment
    M_c = 3 N.m cos(theta) on the coupler 2 and a force F_c = 40 N sin(theta) at B
    along +x."""
    d = Description.read(EXAMPLE)
    d.load("F_R", body="3", kind="force", at="C", direction=[0, 1], fixed_in="link",
           start=30.0)
    d.load("M_c", body="2", kind="moment", value="3 N*m * cos(theta)")
    d.load("F_c", body="2", kind="force", at="B", direction=[1, 0], value="40 N * sin(theta)")
    return d.build()


def load_artists(ax, name: str):
    """The artists ``load:<name>`` (a quiver, or an arc line) and the label of a load."""
    (drawn,) = [a for a in ax.get_children() if a.get_gid() == f"load:{name}"]
    (label,) = [t for t in ax.texts if t.get_gid() == f"load label:{name}"]
    return drawn, label.get_text()


def arc_sweep(line, centre) -> tuple[np.ndarray, float]:
    """Distances of the line's points from ``centre``, and the angle it turns about
    it from its first point to its last [deg], counter-clockwise positive."""
    x, y = (np.asarray(d, float) for d in line.get_data())
    phi = np.unwrap(np.arctan2(y - centre[1], x - centre[0]))
    assert np.all(np.diff(phi) > 0) or np.all(np.diff(phi) < 0)  # one way round
    return np.hypot(x - centre[0], y - centre[1]), math.degrees(phi[-1] - phi[0])


def test_linkage_draws_the_loads_as_they_act(tmp_path):
    """Each load against its definition: a force arrow ends at its point and points the
    way the force acts (F_P = -80 N along -y: up; F_R along the rocker's y axis, from
    the positions of D and C; F_c at its value over the cycle, 40 N sin(50 deg)), its
    length the value times the scale; a moment is an arc of 270 deg about the middle of
    its link's points, counter-clockwise for a positive value; each label gives the
    name and value with its unit."""
    mech = loaded_coupler()
    th = math.radians(50.0)
    fig = plot.linkage(mech, theta_deg=50.0, F_P=-80.0, scale=1e-3)
    saved_png(fig, tmp_path / "linkage_loads.png")
    ax = fig.axes[0]
    p = {k: np.array(v, dtype=float) for k, v in mech.kinematics(th, order=0).p.items()}
    rocker = (p["C"] - p["D"]) / np.linalg.norm(p["C"] - p["D"])  # link 3's x axis
    expected = {"F_P": (p["P"], -80.0, np.array([0.0, -1.0])),
                "F_R": (p["C"], 30.0, np.array([-rocker[1], rocker[0]])),
                "F_c": (p["B"], 40.0 * math.sin(th), np.array([1.0, 0.0]))}
    for name, (at, value, direction) in expected.items():
        q, text = load_artists(ax, name)
        assert isinstance(q, Quiver) and q.pivot == "tip"
        np.testing.assert_allclose([q.X[0], q.Y[0]], at, rtol=RTOL, atol=1e-15)
        np.testing.assert_allclose([q.U[0], q.V[0]], 1e-3 * value * direction, rtol=1e-12,
                                   atol=1e-15)
        assert text == f"{name} = {value:.4g} N"
    assert load_artists(ax, "F_P")[0].V[0] > 0.0  # -80 N along -y acts upwards
    assert load_artists(ax, "F_c")[1] == "F_c = 30.64 N"

    points = np.array([p[k] for k in "ABCDP"])  # what is drawn: its size sets the arcs
    size = np.max(points.max(axis=0) - points.min(axis=0))
    for name, centre, value in [("T4", (p["C"] + p["D"]) / 2, 120.0),
                                ("M_c", (p["B"] + p["C"] + p["P"]) / 3, 3.0 * math.cos(th))]:
        line, text = load_artists(ax, name)
        radius, sweep = arc_sweep(line, centre)
        np.testing.assert_allclose(radius, plot.MOMENT_FRACTION * size, rtol=1e-12)
        assert sweep == pytest.approx(270.0, rel=1e-12)
        assert text == f"{name} = {value:.4g} N.m"
    assert load_artists(ax, "M_c")[1] == "M_c = 1.928 N.m"

    # negative moments turn clockwise; a load over the cycle given by name is that value
    ax = plot.linkage(mech, theta_deg=50.0, T4=-50.0, M_c=-7.0).axes[0]
    assert arc_sweep(load_artists(ax, "T4")[0], (p["C"] + p["D"]) / 2)[1] == \
        pytest.approx(-270.0, rel=1e-12)
    line, text = load_artists(ax, "M_c")
    assert arc_sweep(line, (p["B"] + p["C"] + p["P"]) / 3)[1] == pytest.approx(-270.0, rel=1e-12)
    assert text == "M_c = -7 N.m"


def test_linkage_default_scale_counts_the_loads():
    """The scotch yoke at 90 deg, 10 rad/s, 400 N on the yoke (m2 = 4 kg, m3 = 10 kg,
    r = 0.1 m): the crank pin carries 400 - (m2 + m3) r omega^2 = 260 N, less than the
    load, so the load's arrow is the 0.4 of the linkage's size (0.1 m: A to B) and the
    pin's 260/400 of it."""
    yoke = presets.get("scotch_yoke")
    ax = plot.linkage(yoke, theta_deg=90.0, omega=10.0, load=400.0).axes[0]
    q, text = load_artists(ax, "load")
    np.testing.assert_allclose([q.U[0], q.V[0]], [0.0, -0.04], rtol=1e-12, atol=1e-15)
    assert text == "load = 400 N"
    forces = quiver_of(ax)
    (i,) = [k for k, p in enumerate(plot.force_pairs(yoke)) if p.name == "F12"]
    np.testing.assert_allclose(math.hypot(forces.U[i], forces.V[i]), 0.04 * 260 / 400,
                               rtol=1e-12)


def test_linkage_draws_a_zero_load_faint_in_its_positive_sense():
    mech = loaded_coupler()
    ax = plot.linkage(mech, theta_deg=50.0, F_R=0.0, T4=0.0).axes[0]
    p = {k: np.array(v, dtype=float) for k, v in mech.kinematics(math.radians(50.0),
                                                                   order=0).p.items()}
    points = np.array([p[k] for k in "ABCDP"])
    size = np.max(points.max(axis=0) - points.min(axis=0))
    q, text = load_artists(ax, "F_R")
    rocker = (p["C"] - p["D"]) / np.linalg.norm(p["C"] - p["D"])
    np.testing.assert_allclose([q.U[0], q.V[0]], 0.15 * size * np.array([-rocker[1],
                                                                          rocker[0]]),
                               rtol=1e-12)
    assert text == "F_R = 0 N" and q.get_alpha() < 1.0
    line, text = load_artists(ax, "T4")
    assert arc_sweep(line, (p["C"] + p["D"]) / 2)[1] == pytest.approx(270.0, rel=1e-12)
    assert text == "T4 = 0 N.m" and line.get_alpha() < 1.0
    assert load_artists(ax, "F_P")[0].get_alpha() in (None, 1.0)  # 80 N: drawn in full


def label_boxes(fig) -> list:
    """(gid, text, display bbox of the text alone, distance [pt] from its anchor) of
    every label of the linkage plot, and the scale key's text, as drawn."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax = fig.axes[0]
    out = []
    for t in ax.texts:
        if (t.get_gid() or "").split(":")[0] in ("point", "force", "load label"):
            box = Text.get_window_extent(t, renderer)  # without a leader line
            x, y = ax.transData.transform(t.xy)
            dx, dy = max(box.x0 - x, 0.0, x - box.x1), max(box.y0 - y, 0.0, y - box.y1)
            out.append((t.get_gid(), t.get_text(), box, math.hypot(dx, dy) * 72 / fig.dpi))
    (key,) = [a for a in ax.get_children() if a.get_gid() == "scale"]
    out.append(("scale", key.text.get_text(), key.text.get_window_extent(renderer), 0.0))
    return out


def overlaps(boxes) -> list:
    return [(a[:2], b[:2]) for a, b in itertools.combinations(boxes, 2)
            if a[2].x0 < b[2].x1 and b[2].x0 < a[2].x1 and a[2].y0 < b[2].y1 and
            b[2].y0 < a[2].y1]


LABELLED = [(name, lambda name=name: presets.get(name)) for name in presets.names()] + [
    ("six_bar-D", lambda: presets.get("six_bar", driver="D")),
    ("coupler", lambda: linkage_fmu.load(EXAMPLE))]


def arrows_and_arcs(fig) -> list:
    """(gid, path in display pixels, filled, half the line's width [px]) of every
    arrow and arc of the linkage plot as drawn: each arrow of the force and load
    quivers (its polygon: the quiver's paths by its transform, at its offsets), each
    moment's arc (its line) and the arc's head (its patch's path); and each fixed
    guide's dashed line, which next to a load arrow reads as part of it."""
    from matplotlib.path import Path

    fig.canvas.draw()
    ax = fig.axes[0]
    px = fig.dpi / 72.0
    out = []
    for q in ax.collections:
        gid = q.get_gid() or ""
        if isinstance(q, Quiver) and (gid == "forces" or gid.startswith("load:")):
            t, at = q.get_transform(), q.get_offset_transform().transform(q.get_offsets())
            out += [(f"{gid}[{k}]", Path(t.transform(path.vertices) + o), True, 0.0)
                    for k, (path, o) in enumerate(zip(q.get_paths(), at))]
    for line in ax.lines:
        if (line.get_gid() or "").startswith(("load:", "guide:")):
            xy = line.get_transform().transform(line.get_xydata())
            out.append((line.get_gid(), Path(xy), False, 0.5 * line.get_linewidth() * px))
    for patch in ax.patches:
        if (patch.get_gid() or "").startswith("load head:"):
            path = patch.get_transform().transform_path(patch.get_path())
            # its polygons: the vertex a CLOSEPOLY code carries is not a point of it
            out += [(patch.get_gid(), Path(poly), True, 0.5 * patch.get_linewidth() * px)
                    for poly in path.to_polygons(closed_only=False)]
    return out


def link_lines(fig) -> list:
    """(gid, path in display pixels, False, half the line's width [px]) of every link's
    line as drawn: a bar's line, a plate's outline (its edges: a label may lie on its
    light fill); as :func:`arrows_and_arcs` gives the arrows, for :func:`covered`."""
    from matplotlib.patches import Polygon
    from matplotlib.path import Path

    fig.canvas.draw()
    ax = fig.axes[0]
    px = fig.dpi / 72.0
    out = []
    for a in [*ax.lines, *ax.patches]:
        if not (a.get_gid() or "").startswith("link:"):
            continue
        if isinstance(a, Polygon):
            xy = a.get_transform().transform(np.r_[a.get_xy()[:-1], a.get_xy()[:1]])
        elif hasattr(a, "get_xydata"):
            xy = a.get_transform().transform(a.get_xydata())
        else:
            continue  # a slider's square: a block, not a line
        out.append((a.get_gid(), Path(xy), False, 0.5 * a.get_linewidth() * px))
    return out


def outside(boxes, fig) -> list:
    """The labels (gid) whose box is not wholly inside the linkage's axes."""
    x0, y0, x1, y1 = fig.axes[0].bbox.extents
    return [gid for gid, _, box, _ in boxes
            if box.x0 < x0 or box.y0 < y0 or box.x1 > x1 or box.y1 > y1]


def covered(boxes, marks) -> list:
    """(label, arrow or arc) pairs where the label's box meets the drawn shape."""
    from matplotlib.transforms import Bbox

    out = []
    for gid, _, box, _ in boxes:
        for name, path, filled, pad in marks:
            grown = Bbox.from_extents(box.x0 - pad, box.y0 - pad, box.x1 + pad, box.y1 + pad)
            if path.intersects_bbox(grown, filled=filled):
                out.append((gid, name))
    return out


@pytest.mark.parametrize("make", [m for _, m in LABELLED], ids=[n for n, _ in LABELLED])
def test_linkage_labels_do_not_overlap(make):
    """At a few angles of every preset (the six-bar's labels at 60 deg used to lie on
    top of each other): no two labels' boxes overlap as drawn, nor the scale's key, nor
    does a label's box meet an arrow, an arc or a link's line as matplotlib draws them
    (:func:`link_lines`), each lies inside the axes (at the figure's own size), and each stays
    within 50 pt of its point or arrow tip (the sixth ring, 48 pt: kept off the links'
    lines, a label may need one more ring than the five within 33 pt); the same figure
    again puts them in the same
    places; after a resize, and at the 120 dpi the command line writes, they are placed
    again."""
    mech = make()
    angles = [a for a in (30.0, 60.0, 200.0, 300.0) if mech.solve(math.radians(a)).valid]
    assert angles
    for deg in angles:
        fig = plot.linkage(mech, theta_deg=deg)
        boxes = label_boxes(fig)
        assert len(boxes) >= len(plot.force_pairs(mech)) + 3
        assert not overlaps(boxes), (deg, overlaps(boxes))
        assert not covered(boxes, arrows_and_arcs(fig)), (deg, covered(boxes,
                                                                       arrows_and_arcs(fig)))
        assert not covered(boxes, link_lines(fig)), (deg, covered(boxes, link_lines(fig)))
        assert not outside(boxes, fig), (deg, outside(boxes, fig))
        assert max(b[3] for b in boxes) < 50.0, (deg, [(b[0], b[3]) for b in boxes])
        again = label_boxes(plot.linkage(mech, theta_deg=deg))  # the same places again
        np.testing.assert_allclose([b[2].extents for b in again],
                                   [b[2].extents for b in boxes], rtol=0, atol=1e-9)
        for size, dpi in (((4.0, 3.5), 100), ((8.0, 6.5), 120)):
            fig.set_size_inches(*size)
            fig.set_dpi(dpi)
            boxes = label_boxes(fig)
            assert not overlaps(boxes), (deg, size, dpi)
            assert not covered(boxes, arrows_and_arcs(fig)), (deg, size, dpi)
            assert not covered(boxes, link_lines(fig)), (deg, size, dpi)
            if size == (8.0, 6.5):  # shrunk to 4 inches, not every label fits inside
                assert not outside(boxes, fig), (deg, size, dpi, outside(boxes, fig))
        plt.close(fig)


@pytest.mark.parametrize("make, cases", [
    (lambda: presets.get("four_bar"), [(60.0, {"load": 2.0}), (60.0, {"load": 0.0}),
                                       (60.0, {"load": -2.0, "omega": 30.0})]),
    (lambda: presets.get("crank_shaper"), [(60.0, {})]),
    (loaded_coupler, [(0.0, {}), (50.0, {}), (130.0, {}), (250.0, {})]),
], ids=["four_bar-60", "crank_shaper-60", "coupler-loaded"])
def test_linkage_labels_keep_off_the_arrows_and_arcs(make, cases):
    """The cases found: the four-bar at 60 deg with a moment on its rocker (its F43
    label, the load's label and the load's arc lay on each other), the crank shaper at
    60 deg (the README's picture: its load arrow crossed the F45 label), and the
    coupler four-bar with forces and moments on several links. Every label's box (the
    text as drawn) stays off every arrow and arc as matplotlib draws them (the
    quivers' polygons, the arcs' lines with their width, the heads' patches, in
    display pixels) and off every other label, at the default size and dpi, at 4 x 3.5
    inches, and at the 120 dpi the command line writes."""
    mech = make()
    for deg, inputs in cases:
        fig = plot.linkage(mech, theta_deg=deg, **inputs)
        for size, dpi in (((8.0, 6.5), 100), ((4.0, 3.5), 100), ((8.0, 6.5), 120)):
            fig.set_size_inches(*size)
            fig.set_dpi(dpi)
            boxes = label_boxes(fig)
            marks = arrows_and_arcs(fig)
            assert len(marks) >= len(plot.force_pairs(mech)) + len(mech.loads), (deg, size)
            assert not covered(boxes, marks), (deg, inputs, size, dpi, covered(boxes, marks))
            assert not overlaps(boxes), (deg, inputs, size, dpi, overlaps(boxes))
            lines = link_lines(fig)
            assert not covered(boxes, lines), (deg, inputs, size, dpi, covered(boxes, lines))
            if size == (8.0, 6.5):  # shrunk to 4 inches, not every label fits inside
                assert not outside(boxes, fig), (deg, inputs, size, dpi, outside(boxes, fig))
        plt.close(fig)


def test_boxes_along_a_thick_line_cover_it():
    """The boxes the labels keep off an arrow or arc by: every point within the half
    width of the polyline (by its distance to the nearest segment, computed here
    directly) lies in one of them; and none reaches farther than the half width plus
    the step."""
    from linkage_fmu.plot.placement import line_boxes

    rng = np.random.default_rng(3)
    line = np.array([[0.0, 0.0], [37.0, 11.0], [40.0, -25.0], [40.5, -25.2]])
    half, step = 2.5, 1.4
    boxes = line_boxes(line, half, step)
    a, b = line[:-1], line[1:]
    points = rng.uniform([-5.0, -30.0], [45.0, 15.0], (20000, 2))
    d = b - a
    t = np.clip(np.einsum("pkj,kj->pk", points[:, None, :] - a, d) / np.sum(d * d, axis=1),
                0.0, 1.0)
    off = points[:, None, :] - (a + t[..., None] * d)
    near = np.hypot(off[..., 0], off[..., 1]).min(axis=1)
    x, y = points[:, None, 0], points[:, None, 1]
    inside = ((x >= boxes[:, 0]) & (x <= boxes[:, 2]) & (y >= boxes[:, 1]) &
              (y <= boxes[:, 3])).any(axis=1)
    assert (near <= half).sum() > 1000
    assert inside[near <= half].all()
    assert not inside[near > math.sqrt(2.0) * (half + step / 2)].any()
    # a line of more than 10,000 steps gets 10,000 boxes, each larger to cover it
    boxes = line_boxes([(0.0, 0.0), (1e5, 0.0)], 1.0, 1.0)
    assert len(boxes) == 10_001
    assert np.all(boxes[:, 1] <= -1.0) and np.all(boxes[:, 3] >= 1.0)
    assert boxes[0, 0] <= 0.0 and boxes[-1, 2] >= 1e5  # from end to end, no gap in x:
    assert np.all(boxes[1:, 0] <= boxes[:-1, 2]) and np.all(np.diff(boxes[:, 0]) > 0)


def test_place_boxes_keeps_boxes_apart_near_and_inside():
    """40 boxes about two anchors close by, a box taken between them: every two boxes
    (the taken one too) are at least the gap apart along x or y, each lies inside the
    frame and within its distance of its anchor, the distances are on the rings, and
    the first box, with nothing in its way, lies one gap from its anchor straight in
    the direction it wants."""
    rng = np.random.default_rng(7)
    n, gap = 40, 0.5
    sizes = rng.uniform(2.0, 9.0, (n, 2))
    anchors = np.repeat([[-20.0, 0.0], [3.0, 1.0]], n // 2, axis=0)
    toward = rng.uniform(-4.0, 4.0, n)
    taken = [[-1.0, -1.0, 1.0, 1.0]]
    frame = (-60.0, -40.0, 50.0, 45.0)
    centres, distances = plot.place_boxes(anchors, sizes, toward, taken, frame, gap=gap)
    boxes = np.r_[np.c_[centres - sizes / 2, centres + sizes / 2], taken]
    for i, j in itertools.combinations(range(n + 1), 2):
        a, b = boxes[i], boxes[j]
        assert max(a[0] - b[2], b[0] - a[2], a[1] - b[3], b[1] - a[3]) >= gap - 1e-12, (i, j)
    assert np.all((boxes[:n, :2] >= frame[:2]) & (boxes[:n, 2:] <= frame[2:]))
    dx = np.maximum.reduce([boxes[:n, 0] - anchors[:, 0], anchors[:, 0] - boxes[:n, 2],
                            np.zeros(n)])
    dy = np.maximum.reduce([boxes[:n, 1] - anchors[:, 1], anchors[:, 1] - boxes[:n, 3],
                            np.zeros(n)])
    assert np.all(np.hypot(dx, dy) <= distances + 1e-12)
    rings = {gap * (1 + k * (k + 1) // 2) for k in range(30)}
    assert set(distances.tolist()) <= rings
    assert distances[0] == gap
    c, s = math.cos(toward[0]), math.sin(toward[0])
    edge = min(sizes[0, 0] / 2 / abs(c), sizes[0, 1] / 2 / abs(s))  # centre to edge
    np.testing.assert_allclose(centres[0], anchors[0] + (gap + edge) * np.array([c, s]),
                               rtol=1e-12)


def test_place_boxes_avoids_a_line_at_a_cost():
    """A line just right of the anchor: without a cost of covering it the box lies on
    it, to the right; with one it takes the first spot of the same ring clear of the
    line by the gap (turned 157.5 degrees: the box's corner would touch it before)."""
    line = [[0.5, -0.2, 20.0, 0.2]]
    centres, distances = plot.place_boxes([(0, 0)], [(4, 2)], [0.0], avoid=line)
    np.testing.assert_allclose(centres, [[3.0, 0.0]], rtol=1e-15)
    centres, distances = plot.place_boxes([(0, 0)], [(4, 2)], [0.0], avoid=line, cover=50.0)
    (cx, cy), (w, h) = centres[0], (4.0, 2.0)
    assert cx + w / 2 <= 0.5 - 1.0 or cy - h / 2 >= 0.2 + 1.0  # a gap (1) off the line
    assert distances[0] == 1.0
    t = math.radians(157.5)
    edge = min(2.0 / abs(math.cos(t)), 1.0 / abs(math.sin(t)))
    np.testing.assert_allclose(centres[0], (1.0 + edge) * np.array([math.cos(t), math.sin(t)]),
                               rtol=1e-12)


def test_linkage_cannot_be_drawn_where_it_cannot_be_assembled():
    with pytest.raises(linkage_fmu.AssemblyError):
        plot.linkage(presets.get("four_bar", l_AB=0.3), theta_deg=180.0)


# -- transmission angles -------------------------------------------------------------------
@pytest.mark.parametrize("name, params", [("four_bar", {}), ("slider_crank", {"e": 0.01}),
                                          ("six_bar", {})], ids=["four_bar", "slider_crank",
                                                                  "six_bar"])
def test_transmission_lines_are_the_solved_angles(tmp_path, name, params):
    mech = presets.get(name, **params)
    fig = plot.transmission(mech)
    saved_png(fig, tmp_path / f"transmission_{name}.png")
    lines = by_gid(fig.axes[0])
    ref = solve_deg(mech, DEG)
    gammas = [n for n in mech.diagnostic_names if n.startswith("gamma_")]
    assert gammas and all(n in lines for n in gammas)
    for n in gammas:
        x, y = lines[n][0].get_data()
        np.testing.assert_array_equal(x, DEG)
        np.testing.assert_allclose(y, np.degrees(ref[n]), rtol=RTOL, atol=0)
        i = int(np.argmin(ref[n]))
        np.testing.assert_allclose(np.ravel(lines[f"min:{n}"][0].get_data()),
                                   [DEG[i], np.degrees(ref[n][i])], rtol=RTOL)
        assert f"toggle:{n}" not in lines  # these turn fully without a toggle


def _rrr_toggles(l_ab, l_bc, l_cd, l_ad):
    """Crank angles [deg] where |BD| = BC + CD or |BC - CD| (the coupler-rocker dyad
    stretched or folded), 0..360."""
    out = []
    for d in (l_bc + l_cd, abs(l_bc - l_cd)):
        c = (l_ab ** 2 + l_ad ** 2 - d ** 2) / (2 * l_ab * l_ad)
        if -1 <= c <= 1:
            a = math.degrees(math.acos(c))
            out += [a, 360.0 - a]
    return sorted(out)


@pytest.mark.parametrize("make, expected", [
    # BD reaches BC + CD = 0.65 at cos(theta) = (0.3^2 + 0.4^2 - 0.65^2) / (2 0.3 0.4)
    (lambda: presets.get("four_bar", l_AB=0.3), _rrr_toggles(0.3, 0.35, 0.30, 0.40)),
    # the rod (0.15) cannot reach the guide where 0.2 |sin(theta)| > 0.15
    (lambda: presets.get("slider_crank", l_OA=0.2, l_AB=0.15),
     [math.degrees(a) for a in (math.asin(0.75), math.pi - math.asin(0.75),
                                math.pi + math.asin(0.75), 2 * math.pi - math.asin(0.75))]),
    # a change-point four-bar (0.1 + 0.4 = 0.35 + 0.15): stretched at 180 deg, yet it turns
    (lambda: presets.get("four_bar", l_AB=0.1, l_AD=0.4, l_BC=0.35, l_CD=0.15), [180.0]),
], ids=["four_bar-not-grashof", "slider_crank-short-rod", "four_bar-change-point"])
@pytest.mark.parametrize("n", [721, 700])  # on the grid and between its angles
def test_transmission_marks_toggles(tmp_path, make, expected, n):
    mech = make()
    (gamma,) = [d for d in mech.diagnostic_names if d.startswith("gamma_")]
    deg = np.linspace(0.0, 360.0, n)
    fig = plot.transmission(mech, theta_deg=deg)
    saved_png(fig, tmp_path / "toggles.png")
    lines = by_gid(fig.axes[0])
    found = sorted(line.get_xdata()[0] for line in lines[f"toggle:{gamma}"])
    np.testing.assert_allclose(found, expected, atol=1e-4)  # degrees
    for t in found:  # the solver agrees that the dyad is at a toggle there
        m = float(mech.solve(math.radians(t), outputs=(gamma,))[gamma])
        assert min(m, math.pi - m) < 2e-3, (t, m)
    ref = solve_deg(mech, deg)
    y = lines[gamma][0].get_ydata()
    np.testing.assert_array_equal(np.isnan(y), ~ref.valid)


# -- shaking force and moment --------------------------------------------------------------
@pytest.mark.parametrize("name, params, inputs", CASES, ids=CASE_IDS)
def test_shaking_is_the_solved_shaking_force_and_moment(tmp_path, name, params, inputs):
    mech = presets.get(name, **params)
    fig = plot.shaking(mech, **inputs)
    saved_png(fig, tmp_path / f"shaking_{name}.png")
    force_ax, moment_ax = fig.axes
    ref = solve_deg(mech, DEG, **dict(inputs))
    fx, fy, m = ref["shake_x"], ref["shake_y"], ref["shake_M"]

    lines = by_gid(force_ax)
    x, y = lines["shake"][0].get_data()
    np.testing.assert_allclose(x, fx, rtol=RTOL, atol=0)
    np.testing.assert_allclose(y, fy, rtol=RTOL, atol=0)
    np.testing.assert_array_equal(np.ravel(lines["origin"][0].get_data()), [0.0, 0.0])
    np.testing.assert_allclose(np.ravel(lines["start"][0].get_data()), [fx[0], fy[0]],
                               rtol=RTOL)
    i = int(np.argmax(np.hypot(fx, fy)))
    np.testing.assert_allclose(np.ravel(lines["peak"][0].get_data()), [fx[i], fy[i]],
                               rtol=RTOL)
    np.testing.assert_allclose(np.ravel(lines["peak vector"][0].get_data()),
                               [0.0, fx[i], 0.0, fy[i]], rtol=RTOL)
    text = "".join(t.get_text() for t in force_ax.texts)
    assert f"|shake| = {math.hypot(fx[i], fy[i]):.4g} N" in text
    assert f"θ = {DEG[i]:.1f}°" in text
    assert force_ax.get_aspect() == 1.0
    assert (force_ax.get_xlabel(), force_ax.get_ylabel()) == ("shake_x [N]", "shake_y [N]")

    lines = by_gid(moment_ax)
    x, y = lines["shake_M"][0].get_data()
    np.testing.assert_array_equal(x, DEG)
    np.testing.assert_allclose(y, m, rtol=RTOL, atol=0)
    np.testing.assert_allclose(lines["mean"][0].get_ydata(), [np.mean(m[:-1])] * 2, rtol=1e-9,
                               atol=1e-12 * np.max(np.abs(m)))
    i = int(np.argmax(np.abs(m)))
    np.testing.assert_allclose(np.ravel(lines["peak"][0].get_data()), [DEG[i], m[i]],
                               rtol=RTOL)
    assert moment_ax.get_ylabel() == "shake_M [N.m]"


def test_shaking_of_the_scotch_yoke_by_hand():
    """The scotch yoke (crank r with J1, block m2 at its pin B, yoke m3 moving
    y = r sin(theta) along the y axis through A, a force F along -y on it, no gravity)
    puts on the frame the load and the d'Alembert forces of its links:
    shake_x = m2 r (omega^2 cos + alpha sin), shake_y = (m2 + m3) r (omega^2 sin -
    alpha cos) - F: an ellipse about (0, -F); about A only the block's tangential
    inertia and the crank's have a moment, shake_M = -(J1 + m2 r^2) alpha."""
    r, m2, m3, j1, omega, alpha, force = 0.1, 4.0, 10.0, 0.02, 10.0, 3.0, 400.0
    yoke = presets.get("scotch_yoke", l_AB=r, m2=m2, m3=m3, J1=j1, g=0.0)
    fig = plot.shaking(yoke, omega=omega, alpha=alpha, load=force)
    force_ax, moment_ax = fig.axes
    t = np.radians(DEG)
    sx = m2 * r * (omega ** 2 * np.cos(t) + alpha * np.sin(t))
    sy = (m2 + m3) * r * (omega ** 2 * np.sin(t) - alpha * np.cos(t)) - force
    x, y = by_gid(force_ax)["shake"][0].get_data()
    np.testing.assert_allclose(x, sx, rtol=0, atol=1e-12 * force)
    np.testing.assert_allclose(y, sy, rtol=0, atol=1e-12 * force)
    moment = -(j1 + m2 * r * r) * alpha  # -0.18 N.m at every angle
    lines = by_gid(moment_ax)
    np.testing.assert_allclose(lines["shake_M"][0].get_ydata(), moment, rtol=1e-12)
    assert lines["mean"][0].get_label() == "mean -0.18 N.m"


def test_shaking_draws_into_the_axes_given_over_the_angles_given():
    mech = presets.get("slider_crank")
    theta = np.linspace(0.2, 2.5, 40)
    fig0, axes = plt.subplots(1, 2)
    fig = plot.shaking(mech, theta, 80.0, 0.0, 150.0, ax=axes)
    assert fig is fig0
    ref = mech.solve(theta, 80.0, 0.0, 150.0)
    x, y = by_gid(axes[0])["shake"][0].get_data()
    np.testing.assert_allclose(x, ref["shake_x"], rtol=RTOL)
    np.testing.assert_allclose(y, ref["shake_y"], rtol=RTOL)
    x, y = by_gid(axes[1])["shake_M"][0].get_data()
    np.testing.assert_allclose(x, np.degrees(theta), rtol=RTOL)
    np.testing.assert_allclose(y, ref["shake_M"], rtol=RTOL)
    with pytest.raises(TypeError, match="pair of Axes"):
        plot.shaking(mech, ax=axes[0])


# -- speed over a cycle --------------------------------------------------------------------
@pytest.mark.parametrize("name, omega, loads", [("four_bar", 10.0, {"load": 3.0}),
                                                ("slider_crank", 100.0, {"load": 200.0})])
def test_speed_is_the_motion_with_the_sized_flywheel(tmp_path, name, omega, loads):
    """--what speed with Cs: the curve is the flywheel sizing's integrated motion (angle in
    degrees, speed), the mean line its mean speed, the max and min points its refined
    extremes, the band the width Cs omega about the middle of the swing."""
    mech = presets.get(name)
    fig = plot.speed(mech, omega, Cs=0.05, **loads)
    saved_png(fig, tmp_path / f"speed_{name}.png")
    ax = fig.axes[0]
    lines = by_gid(ax)
    ref = mech.flywheel(omega, 0.05, **loads)
    x, y = lines["omega"][0].get_data()
    np.testing.assert_allclose(x, np.degrees(ref.motion["theta"]), rtol=RTOL, atol=0)
    np.testing.assert_allclose(y, ref.motion["omega"], rtol=RTOL, atol=0)
    assert x[0] == 0.0 and abs(x[-1] - 360.0) < 1e-6
    np.testing.assert_array_equal(lines["mean"][0].get_ydata(), [omega] * 2)
    for gid, w, th in (("max", ref.omega_max, ref.run.theta_omega_max),
                       ("min", ref.omega_min, ref.run.theta_omega_min)):
        np.testing.assert_allclose(np.ravel(lines[gid][0].get_data()), [np.degrees(th), w],
                                   rtol=RTOL)
        assert f"{w:.5g} rad/s" in lines[gid][0].get_label()
    middle = 0.5 * (ref.omega_max + ref.omega_min)
    band = sorted(line.get_ydata()[0] for line in lines["band"])
    np.testing.assert_allclose(band, [middle - 0.025 * omega, middle + 0.025 * omega],
                               rtol=RTOL)
    # the swing overshoots the band by what the first-order sizing leaves (0.2 %)
    assert abs((ref.omega_max - ref.omega_min) / (band[1] - band[0]) - 1) < 0.01
    assert f"Cs = (ω_max - ω_min) / ω_mean = {ref.Cs_simulated:.4g}" in ax.get_title()
    assert f"flywheel {ref.flywheel:.4g} kg·m²" in ax.get_title()
    assert ax.get_ylabel() == "crank speed ω [rad/s]"
    (rpm,) = ax.child_axes  # the secondary axis, in rpm
    assert rpm.get_ylabel() == "[rpm]"


def test_speed_of_the_free_scotch_yoke_without_a_flywheel():
    """No Cs, no flywheel: the linkage alone. The scotch yoke with no load turns freely
    (tau = 0), J omega**2 constant: the speed swings between sqrt(0.14 / 0.04) times its
    lowest, highest at 90 and 270 degrees; with a flywheel of 1 kg m2 the ratio is
    sqrt(1.14 / 1.04)."""
    yoke = presets.get("scotch_yoke")
    for flywheel, ratio in ((None, math.sqrt(0.14 / 0.04)), ("1 kg*m**2", math.sqrt(1.14 / 1.04))):
        fig = plot.speed(yoke, "60 rpm", load=0.0, flywheel=flywheel)
        lines = by_gid(fig.axes[0])
        assert "band" not in lines
        top, bottom = lines["max"][0].get_ydata()[0], lines["min"][0].get_ydata()[0]
        assert top / bottom == pytest.approx(ratio, rel=1e-12)
        assert lines["max"][0].get_xdata()[0] % 180.0 == pytest.approx(90.0, abs=1e-6)
        np.testing.assert_allclose(lines["mean"][0].get_ydata(), 2 * math.pi, rtol=1e-15)
    assert "no flywheel" in plot.speed(yoke, 1.0, load=0.0).axes[0].get_title()


def test_a_zero_left_by_rounding_prints_as_0_in_the_picture_and_the_shaking_plot():
    """The scotch yoke (no gravity, 10 rad/s, 400 N on the yoke): Mb = F r cos(theta) -
    m3 r^2 omega^2 sin(2 theta) / 2 is 0 at 90 deg, and the solve leaves 1.8e-15 N m
    (cos of the float nearest pi/2), which the picture's title printed. Its shaking
    moment is zero to the 40-digit reference's 2.5e-15 N m (the binary inputs'
    rounding), and the shaking plot printed its peak as 1.066e-14 N m. Both print 0:
    within 1e-12 of the forces times the linkage's size (260 N on the 0.1 m crank; the
    540 N shaking force times 0.1 m). A real value beside them keeps its figures."""
    from linkage_fmu.precise import reference

    yoke = presets.get("scotch_yoke")
    assert yoke.parameters["g"] == 0.0
    sol = yoke.solve(math.pi / 2, 10.0, 0.0, 400.0)
    assert 0.0 < abs(sol["Mb"]) < 1e-14  # the case
    title = plot.linkage(yoke, theta_deg=90.0, omega=10.0, load=400.0).axes[0].get_title()
    assert "Mb = 0 N.m;" in title
    title = plot.linkage(yoke, theta_deg=60.0, omega=10.0, load=400.0).axes[0].get_title()
    mb = 400.0 * 0.1 * 0.5 - 10.0 * 0.01 * 100.0 * math.sin(math.radians(120.0)) / 2
    assert f"Mb = {mb:.4g} N.m;" in title  # 15.67 N m

    assert abs(float(reference(yoke, math.radians(30.0), 10.0, 0.0, 400.0)["shake_M"])) < 3e-15
    moment = plot.shaking(yoke, omega=10.0, load=400.0).axes[1]
    lines = by_gid(moment)
    assert 1e-15 < np.max(np.abs(lines["shake_M"][0].get_ydata())) < 1e-13  # the case
    assert lines["peak"][0].get_label() == "peak |shake_M| 0 N.m"
    assert lines["mean"][0].get_label() == "mean 0 N.m"
    (peak,) = [t for t in moment.texts if t.get_gid() == "peak label"]
    assert peak.get_text().startswith("0 N.m\nat θ = ")


def test_speed_title_prints_a_zero_torque_as_0():
    """The four-bar at 10 rad/s with no load: its loads (gravity, inertia) are
    conservative, so the cycle mean of Mb at constant speed, the torque tau, is 0
    (energy: the work of Mb over a revolution at constant speed is zero). The sum
    leaves -2.3e-17 N m of rounding, which the title used to print; it prints 0. A real
    torque is printed to 4 figures: the engine's at 3000 rpm, the mean of Mb over its
    720 degree cycle in 1440 equal steps (within 1e-9 of the sizing's quadrature)."""
    title = plot.speed(presets.get("four_bar"), 10.0, load=0.0).axes[0].get_title()
    assert "τ = 0 N·m," in title and "e-" not in title
    engine = linkage_fmu.load(EXAMPLE.parent / "engine.toml")
    mean = float(engine.solve(np.radians(np.arange(0.0, 720.0, 0.5)), 100 * np.pi)["Mb"].mean())
    title = plot.speed(engine, "3000 rpm").axes[0].get_title()
    assert f"τ = {mean:.4g} N·m," in title and mean < -1.0


# -- bad input -----------------------------------------------------------------------------
def test_bad_input_is_refused_with_the_choices():
    four = presets.get("four_bar")
    with pytest.raises(ValueError, match=r"no force pair 'F12'.*F21 \(F21x, F21y\), F32"):
        plot.polar(four, "F12")
    with pytest.raises(ValueError, match=r"no force pair 'N43'.*F21 \(F21x, F21y\)"):
        plot.polar(presets.get("slider_crank"), "N43")  # one component: not a pair
    with pytest.raises(ValueError, match=r"no output 'Mx'.*F21x, .*Mb, Mf_A, .*P_loss, eta, "
                                         r"shake_x, shake_y, shake_M, gamma_C, cond"):
        plot.torque(four, output="Mx")
    with pytest.raises(TypeError, match="not both"):
        plot.torque(four, theta=[0.0, 1.0], theta_deg=[0.0, 1.0])
    with pytest.raises(TypeError, match="inputs are: theta, omega, alpha, load"):
        plot.torque(four, weight=3.0)
    with pytest.raises(ValueError, match="one number"):
        plot.linkage(four, [0.1, 0.2])
    with pytest.raises(TypeError, match="give the crank angle"):
        plot.linkage(four)
    with pytest.raises(ValueError, match="scale must be"):
        plot.linkage(four, 0.3, scale=-1.0)
    with pytest.raises(ValueError, match="cannot be assembled at any"):
        plot.torque(presets.get("four_bar", l_AB=0.3), theta_deg=[170.0, 180.0, 190.0])
    # angles friction locks (test_friction's massless slider-crank, mu 0.6 at its guide)
    locks = presets.get("slider_crank", m1=0.0, J1=0.0, m2=0.0, J2=0.0, m3=0.0, g=0.0,
                        l_OA=0.18, l_AB=0.2, mu_guide=0.6)
    with pytest.raises(ValueError, match=r"slider_crank has no outputs at any of the 3 crank "
                                         r"angles 260\.\.270 deg: slider_crank locks at "):
        plot.torque(locks, theta_deg=[260.0, 265.0, 270.0], omega=5.0, load=250.0)
    with pytest.raises(TypeError, match="give Cs .* or flywheel .*, not both"):
        plot.speed(four, Cs=0.02, flywheel=1.0)
    with pytest.raises(ValueError, match="Cs must be between 0 and 1"):
        plot.speed(four, Cs=2.0)
    with pytest.raises(ValueError, match="does not act on the crank"):
        plot.speed(presets.get("six_bar", driver="KD"), 1.0)


def test_missing_matplotlib_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)  # import fails
    with pytest.raises(ImportError, match=r'pip install "linkage_fmu\[plot\]"'):
        plot.torque(presets.get("four_bar"))


def test_convergence_is_the_optimisations_history(tmp_path):
    """plot.convergence draws the history of ``optimize``: the step line is the best
    feasible objective of each generation of the search (its values exactly), the
    polish a point one generation later, the optimum the value returned."""
    from linkage_fmu.optimize import optimize

    res = optimize("four_bar", {"l_AB": (0.05, 0.15), "l_BC": (0.3, 0.4)}, "Mb_peak",
                   ["gamma_C_min_deg >= 40", "valid"], theta=np.radians(np.arange(0, 360, 10)),
                   omega=10.0, maxiter=4, seed=2)
    fig = plot.convergence(res)
    ax = fig.axes[0]
    lines = {line.get_gid(): line for line in ax.lines}
    assert list(lines) == ["best", "polish", "optimum"]
    search = res.history[res.history["stage"] == "global"]
    x, y = lines["best"].get_data()
    np.testing.assert_array_equal(x, search["generation"].to_numpy())
    np.testing.assert_array_equal(y, search["best"].to_numpy())
    x, y = lines["polish"].get_data()
    assert list(x) == [len(search) - 1, len(search)] and y[1] == res.history["best"].iloc[-1]
    assert list(lines["optimum"].get_data()[1]) == [res.value]
    assert "minimise Mb_peak subject to gamma_C_min_deg >= 40, valid" in ax.get_title()
    fig.savefig(tmp_path / "c.png")
    assert (tmp_path / "c.png").read_bytes()[:8] == PNG
    plt.close(fig)


def test_hull_of_a_links_points():
    """The convex hull by hand: a square's corners counter-clockwise from the lowest
    (its centre and a point on an edge left out); points on one line give its ends."""
    pos = {"a": (0.0, 0.0), "b": (1.0, 0.0), "c": (1.0, 1.0), "d": (0.0, 1.0),
           "m": (0.5, 0.5), "e": (1.0, 0.5)}
    assert plot.hull(["m", "c", "a", "e", "d", "b"], pos) == ["a", "b", "c", "d"]
    line = {"p": (0.0, 0.0), "q": (0.3, 0.6), "r": (0.1, 0.2)}
    assert plot.hull(["r", "q", "p"], line) == ["p", "q"]
    assert plot.hull(["q", "p"], line) == ["p", "q"]


def link_artist(ax, name: str):
    (artist,) = [a for a in ax.get_children() if a.get_gid() == f"link:{name}"]
    return artist


def test_linkage_draws_a_ternary_link_as_a_plate():
    """The coupler of the coupler four-bar carries B, C and its point P (off the line
    BC): it is a Polygon whose corners are those three points where the solver puts
    them, counter-clockwise (its signed area is the triangle's, by the cross product),
    lightly filled with an opaque outline; the crank and the rocker stay bars from one
    joint to the other."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Polygon

    mech = Description.read(EXAMPLE).build()
    theta = math.radians(40.0)
    st = mech.kinematics(theta, order=0)
    ax = plot.linkage(mech, theta).axes[0]
    plate = link_artist(ax, "2")
    assert isinstance(plate, Polygon)
    corners = np.array(plate.get_xy(), float)[:-1]  # the last closes the ring
    points = np.array([st.p[p] for p in ("B", "C", "P")], float)
    assert len(corners) == 3
    for p in points:
        assert np.min(np.hypot(*(corners - p).T)) < 1e-12
    (bx, by), (cx, cy), (px, py) = points
    area = abs((cx - bx) * (py - by) - (cy - by) * (px - bx)) / 2
    x, y = corners.T
    signed = (np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) / 2
    assert signed == pytest.approx(area, rel=1e-12)
    assert plate.get_facecolor()[3] == pytest.approx(0.2)
    assert plate.get_edgecolor()[3] == 1.0
    for link, ends in (("1", ("A", "B")), ("3", ("C", "D"))):
        bar = link_artist(ax, link)
        assert isinstance(bar, Line2D)
        np.testing.assert_allclose(np.array(bar.get_xydata(), float),
                                   np.array([st.p[p] for p in ends], float), atol=1e-15)


@pytest.mark.parametrize("name, link, ends, inner", [
    ("six_bar", "O1B", ("O1", "B"), "K"),       # K on the rocker, between O1 and B
    ("crank_shaper", "3", ("C", "D"), "B"),     # the block's B on the lever C-D
])
def test_linkage_draws_points_on_one_line_as_a_bar(name, link, ends, inner):
    """A link whose points lie on one line is a bar between the two ends (the inner
    point lies on it, between them), not a plate."""
    from matplotlib.lines import Line2D

    mech = presets.get(name)
    theta = math.radians(60.0)
    st = mech.kinematics(theta, order=0)
    bar = link_artist(plot.linkage(mech, theta).axes[0], link)
    assert isinstance(bar, Line2D)
    xy = np.array(bar.get_xydata(), float)
    got = sorted(map(tuple, xy))
    want = sorted(tuple(float(v) for v in st.p[p]) for p in ends)
    np.testing.assert_allclose(got, want, atol=1e-12)
    (ax_, ay), (bx, by), (kx, ky) = (np.array(st.p[p], float) for p in (*ends, inner))
    t = ((kx - ax_) * (bx - ax_) + (ky - ay) * (by - ay)) / ((bx - ax_) ** 2 + (by - ay) ** 2)
    assert 0.0 < t < 1.0


@pytest.mark.parametrize("name, state", [
    ("excavator", dict(s_cyl1=0.2, s_cyl2=0.1, s_cyl3=0.1, v_cyl1=0.05, F_T=15000.0)),
    ("five_bar", dict(theta_A=1.9, theta_E=1.2, omega_A=2.0, P=10.0)),
])
def test_a_linkage_driven_by_time_is_drawn_at_its_drivers_state(tmp_path, name, state):
    """The arrows are the joint forces of ``solve`` at the drivers' state, to scale,
    from the joints' points there; the title gives each driver's coordinate, its
    nonzero speeds and every effort."""
    mech = linkage_fmu.load(Path(__file__).resolve().parents[1] / "examples" / f"{name}.toml")
    pairs = plot.force_pairs(mech)
    q = tuple(state[d.inputs[0]] for d in mech.drivers)
    st = mech.kinematics(q, order=0, rates=tuple((0.0, 0.0) for _ in q))
    sol = mech.solve(**state)
    fig = plot.linkage(mech, scale=1e-5, **state)
    saved_png(fig, tmp_path / f"{name}.png")
    arrows = quiver_of(fig.axes[0])
    drawn = [p for p in pairs if p.point is not None]
    np.testing.assert_allclose(np.c_[arrows.X, arrows.Y],
                               np.array([st.p[p.point] for p in drawn], float), atol=1e-12)
    np.testing.assert_allclose(np.c_[arrows.U, arrows.V],
                               1e-5 * np.array([(sol[p.x], sol[p.y]) for p in drawn]),
                               rtol=1e-12, atol=0)
    title = fig.axes[0].get_title()
    for d in mech.drivers:
        assert f"{d.inputs[0]} = " in title and f"{d.effort} = " in title, title
    assert f"{mech.drivers[0].inputs[1]} = " in title  # a nonzero speed
    assert f"{mech.drivers[1].inputs[2]} = " not in title  # a zero acceleration is not
    with pytest.raises(linkage_fmu.errors.InputTypeError, match="driven by time: give its "
                                                                "inputs by name"):
        plot.linkage(mech, 0.5, **state)
