"""Loads over the cycle (``value = EXPR`` and ``table``) and start values, against
hand-derived numbers.

The reference linkage is the slider-crank with no mass: a force F on the piston, towards
the crank, needs the moment ``Mb = F dx_B/dtheta`` on the crank (virtual power), with
``x_B = r cos(theta) + sqrt(l^2 - r^2 sin(theta)^2)``, and the rod carries
``F / cos(beta)``, ``sin(beta) = r sin(theta) / l``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkage_fmu import presets
from linkage_fmu.descriptions import Description, DescriptionError
from linkage_fmu.interpolation import AngleTable
from linkage_fmu.precise import reference
from linkage_fmu.sweep import sweep

R, L = 0.05, 0.20
MASSLESS = dict(m1=0.0, J1=0.0, m2=0.0, J2=0.0, m3=0.0, g=0.0)
ROWS = [[0.0, 30.0], [40.0, 12.0], [90.0, 5.0], [180.0, 1.5], [300.0, 1.0], [420.0, 2.5],
        [600.0, 9.0]]
AREA = math.pi * 0.086 ** 2 / 4  # m2: a bore of 86 mm


def x_b(theta):
    return R * np.cos(theta) + np.sqrt(L * L - (R * np.sin(theta)) ** 2)


def dx_b(theta):
    s, c = np.sin(theta), np.cos(theta)
    return -R * s - R * R * s * c / np.sqrt(L * L - (R * s) ** 2)


def engine(**load) -> Description:
    """The slider-crank preset, its one load replaced by ``load``."""
    d = presets.preset("slider_crank").copy()
    d.loads.clear()
    return d.load("F_gas", body="3", kind="force", at="B", direction=[-1, 0], **load)


def test_a_table_load_gives_the_hand_derived_torque_at_its_points():
    """At the table's angles the spline is the table's value: 8 bar-table points times
    the bore's area, Mb = F dx_B/dtheta to 1e-12 relative, on both revolutions of the
    720 deg cycle (theta and theta + 360 deg differ)."""
    mech = engine(table=ROWS, period_deg=720.0, table_unit="bar",
                  scale="pi * (86 mm)**2 / 4").build(**MASSLESS)
    assert mech.input_names == ("theta", "omega", "alpha")  # computed: not an input
    theta = np.radians([r[0] for r in ROWS])
    force = np.array([r[1] for r in ROWS]) * 1e5 * AREA
    for method in ("closed_form", "direct"):
        sol = mech.solve(theta, 50.0, 0.0, method=method)
        np.testing.assert_allclose(sol["Mb"], force * dx_b(theta), rtol=1e-12, atol=1e-9)
        beta = np.arcsin(R * np.sin(theta) / L)
        np.testing.assert_allclose(np.hypot(sol["F32x"], sol["F32y"]), force / np.cos(beta),
                                   rtol=1e-12)
    one = [mech.solve(float(t))["Mb"] for t in theta]  # the one-state kernel
    np.testing.assert_allclose(one, force * dx_b(theta), rtol=1e-12, atol=1e-9)
    assert mech.solve(math.radians(40.0))["Mb"] != pytest.approx(
        mech.solve(math.radians(400.0))["Mb"], rel=1e-3)


def test_an_expression_load_of_theta_parameters_and_a_point_position():
    """A spring on the piston, k (x_B - x0), plus a force varying with the angle, given
    with units: ``"2 kN/m * (x_B - l_AB) + 50 N * cos(theta)"``: hand formula to 1e-12
    at 37 angles, on every path (closed form and its kernel, direct, mpmath)."""
    expr = "2 kN/m * (x_B - l_AB) + 50 N * cos(theta)"
    mech = engine(value=expr).build(**MASSLESS)
    theta = np.linspace(0.0, 2 * math.pi, 37)
    force = 2000.0 * (x_b(theta) - L) + 50.0 * np.cos(theta)
    expected = force * dx_b(theta)
    for method in ("closed_form", "direct", "interpreted"):
        np.testing.assert_allclose(mech.solve(theta, 3.0, method=method)["Mb"], expected,
                                   rtol=1e-12, atol=1e-12)
    for k in range(0, 37, 6):
        t = float(theta[k])
        assert mech.solve(t, 3.0)["Mb"] == pytest.approx(expected[k], rel=1e-12, abs=1e-12)
        assert float(reference(mech, t, 3.0)["Mb"]) == pytest.approx(expected[k], rel=1e-12,
                                                                     abs=1e-12)


def test_a_load_over_the_cycle_can_be_overridden_by_name():
    """``solve(..., F_gas=...)`` replaces what the table computes: the same numbers as an
    input load of that value."""
    mech = engine(table=ROWS, period_deg=720.0).build()
    plain = engine(start=0.0).build()
    theta = np.linspace(0.0, 4 * math.pi, 11)
    a = mech.solve(theta, 20.0, 1.0, F_gas=123.0)
    b = plain.solve(theta, 20.0, 1.0, F_gas=123.0)
    for name in plain.output_names:
        np.testing.assert_array_equal(a[name], b[name])
    assert mech.solve(0.3, 20.0, F_gas=123.0)["Mb"] == plain.solve(0.3, 20.0, 0.0, 123.0)["Mb"]


def test_loads_over_the_cycle_in_the_sweep_and_the_angle_table():
    """The sweep's peak and the interpolated table use the computed load: the sweep's
    Mb_peak is the largest |Mb| of the solver; AngleTable is within 1e-6 of the solver
    (size 4096) over two revolutions of a 720 deg table."""
    mech = engine(table=ROWS, period_deg=720.0, table_unit="bar",
                  scale="pi * (86 mm)**2 / 4").build()
    theta = np.linspace(0.0, 4 * math.pi, 720, endpoint=False)
    exact = mech.solve(theta, 100.0)
    table = sweep(mech, {"m2": [mech.parameters["m2"]]}, theta, 100.0)
    assert table["Mb_peak"][0] == pytest.approx(np.max(np.abs(exact["Mb"])), rel=1e-12)
    interpolated = AngleTable(mech, 4096)(theta, 100.0)
    scale = np.max(np.abs(exact["Mb"]))
    assert np.max(np.abs(interpolated["Mb"] - exact["Mb"])) < 1e-6 * scale


def test_start_values_hold_everywhere():
    """A load or speed not given takes the description's start value: solve, table,
    sweep, AngleTable and the mpmath reference all equal an explicit call with the
    start values, and differ from zero loads. The coupler four-bar starts at omega = 25,
    F_P = 80 N, T4 = 120 N m."""
    mech = presets.linkage("examples/coupler_four_bar.toml")
    assert mech.start == {"theta": 0.0, "omega": 25.0, "alpha": 0.0, "F_P": 80.0, "T4": 120.0}
    theta = np.linspace(0.0, 2 * math.pi, 13)
    explicit = mech.solve(theta, 25.0, 0.0, 80.0, 120.0)["Mb"]
    zero = mech.solve(theta, 25.0, 0.0, 0.0, 0.0)["Mb"]
    assert np.max(np.abs(explicit - zero)) > 1.0
    np.testing.assert_array_equal(mech.solve(theta)["Mb"], explicit)
    np.testing.assert_array_equal(mech.table(theta)["Mb"].to_numpy(), explicit)
    assert mech.solve(1.0)["Mb"] == mech.solve(1.0, 25.0, 0.0, 80.0, 120.0)["Mb"]
    assert float(reference(mech, 1.0)["Mb"]) == pytest.approx(
        mech.solve(1.0, 25.0, 0.0, 80.0, 120.0)["Mb"], rel=1e-12)
    assert AngleTable(mech, 4096)(theta)["Mb"] == pytest.approx(explicit, rel=1e-8)
    peak = sweep(mech, {"m2": [2.0]}, theta)["Mb_peak"][0]
    assert peak == pytest.approx(np.max(np.abs(explicit)), rel=1e-12)


def test_start_values_take_units_and_expressions(tmp_path):
    d = presets.preset("scotch_yoke").copy()
    d.start(omega="95.49296585513721 rpm")
    d.loads[0]["start"] = "0.4 kN"
    mech = d.build()
    assert mech.start["omega"] == pytest.approx(10.0, rel=1e-15)
    assert mech.solve(math.radians(60))["Mb"] == pytest.approx(15.6699, abs=5e-5)


@pytest.mark.parametrize("load, message", [
    (dict(value="3 m * theta"), r"value = '3 m \* theta' must be a force \(N\), but it is a "
                                r"length"),
    (dict(value="x_Q * 2"), "'x_Q', which is not a parameter"),
    (dict(value="1", table=ROWS), "give value or table, not both"),
    (dict(table=ROWS, table_unit="kg"), r"table_unit and scale = '1 kg \* \(1.0\)' must be a "
                                        "force"),
    (dict(table=ROWS, period_deg=360.0), "span 600.0 deg, not less than the period 360.0"),
    (dict(table=[[0, 1], [10, "a"]]), "must be a CSV file"),
    (dict(value="10", start=5.0), "a load over the cycle is computed, it has no start"),
    (dict(start="4 kN*m"), r"start = '4 kN\*m' must be a force"),
])
def test_a_bad_load_over_the_cycle_is_named(load, message):
    with pytest.raises(DescriptionError, match=message):
        engine(**load).build()


def test_a_table_file_that_cannot_be_read_is_named(tmp_path):
    with pytest.raises(ValueError, match="load F_gas table: .*no_such.csv: cannot read it"):
        engine(table="no_such.csv")
    path = tmp_path / "engine.toml"
    path.write_text(_with_file(engine(table=ROWS).to_toml()))
    with pytest.raises(DescriptionError, match=r"\(F_gas\) table: .*gas.csv: cannot read it"):
        Description.read(path)


def test_a_table_file_relative_to_the_description(tmp_path):
    """``table = "FILE.csv"`` is read from the description's folder, and the description
    written back (for an FMU's resources) carries the points inline."""
    (tmp_path / "gas.csv").write_text("theta_deg,value\n" + "".join(
        f"{a},{b}\n" for a, b in ROWS))
    text = engine(table=ROWS, period_deg=720.0).to_toml()
    inline = Description.from_toml(text)
    assert inline.loads[0]["table"] == ROWS
    path = tmp_path / "engine.toml"
    path.write_text(_with_file(text))
    d = Description.read(path)
    assert d.loads[0]["table"] == ROWS
    a, b = d.build(), inline.build()
    assert a.solve(1.0)["Mb"] == b.solve(1.0)["Mb"]


def _with_file(text: str) -> str:
    """``text`` with its inline table replaced by ``table = "gas.csv"``."""
    lines = [('table = "gas.csv"' if line.startswith("table = ") else line)
             for line in text.splitlines()]
    return "\n".join(lines) + "\n"


def _four_bar_with(body: str, at: str, point: bool = False) -> Description:
    """The four-bar preset with a force of 100 N straight down on ``body`` at ``at``
    (``point``: first place ``P`` on the coupler, 0.1 m along it from B)."""
    d = presets.preset("four_bar").copy()
    if point:
        d.group("point", link="2", **{"from": "B"}, name="P", along=0.1)
    return d.load("F_c", body=body, kind="force", at=at, direction=[0, -1], start=100.0)


def test_a_force_at_a_point_not_on_its_body_is_refused(tmp_path):
    """A force on the four-bar's coupler (body 2) at the frame pivot D of the rocker was
    taken silently and changed Mb (10.46 to 5.43 N m): D is a point of the rocker and
    the frame, not of the coupler. Refused, naming the load, the point and the body:
    from the Python API (a Load given to a Mechanism), a description, and its file (as a
    problem of the file, named with it)."""
    words = r"load F_c acts on body 2 at point D, which is not a point of body 2"
    with pytest.raises(ValueError, match=words):
        _four_bar_with("2", "D").build()
    path = tmp_path / "off_body.toml"
    path.write_text(_four_bar_with("2", "D").to_toml())
    with pytest.raises(DescriptionError, match=rf"off_body.toml: \[\[loads\]\] "
                                               rf"#2 \(F_c\) at: {words} \(its points: B, C\)"):
        Description.read(path)
    base = presets.get("four_bar")
    from linkage_fmu import Mechanism
    from linkage_fmu.loads import Load

    with pytest.raises(ValueError, match=words):
        Mechanism("mine", base.frame, base.frame_points, base.groups[:2], base.bodies,
                  base.effort, [], [Load("F_c", "2", "force", at="D", direction=(0.0, -1.0))],
                  base.g)


def test_a_force_at_a_point_of_its_body_is_taken():
    """The points of a body: its joints' (C, shared by the coupler and the rocker) and a
    point placed on it by coordinates (P on the coupler). Virtual power is the
    reference: a force F at the pin C needs the same Mb on whichever link of the pin it
    acts, and its share of Mb balances the force's power: Mb omega + F . v_C = 0, so
    with F = (0, -100 N), Mb grows by 100 N dy_C/dtheta (dy_C/dtheta by a central
    difference of the position: 1e-6 relative)."""
    theta, omega = 0.7, 10.0
    on_2, on_3 = (_four_bar_with(b, "C").build(g=0.0) for b in ("2", "3"))
    base = presets.get("four_bar", g=0.0).solve(theta, omega)["Mb"]
    Mb = on_2.solve(theta, omega)["Mb"]
    assert Mb == pytest.approx(on_3.solve(theta, omega)["Mb"], rel=1e-12)
    h = 1e-6
    dy = (on_2.kinematics(theta + h, 0).p["C"][1]
          - on_2.kinematics(theta - h, 0).p["C"][1]) / (2 * h)
    assert Mb - base == pytest.approx(100.0 * dy, rel=1e-6)
    placed = _four_bar_with("2", "P", point=True).build(g=0.0)
    assert math.isfinite(placed.solve(theta, omega)["Mb"])
