"""``linkage_fmu.tables.PeriodicTable`` against scipy's periodic ``CubicSpline`` evaluated
by scipy itself, its nodes (an interpolating spline passes through them), its period,
and the C evaluation compiled and run (the same floats)."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from linkage_fmu.tables import PeriodicTable, read_rows

DEG = [0.0, 40.0, 90.0, 180.0, 300.0, 420.0, 600.0]
VALUES = [30.0, 12.0, 5.0, 1.5, 1.0, 2.5, 9.0]


def _scipy(period=720.0):
    x = np.radians(np.append(DEG, DEG[0] + period))
    return CubicSpline(x, np.append(VALUES, VALUES[0]), bc_type="periodic")


def test_the_spline_is_scipys_periodic_cubic_spline():
    """To 1e-13 relative at 2000 angles over two periods, negative ones included: the
    same spline as scipy's, evaluated by scipy at the angle brought into one period."""
    t = PeriodicTable(DEG, VALUES, 720.0)
    ref = _scipy()
    theta = np.linspace(-4 * math.pi, 8 * math.pi, 2000)
    phase = np.radians(DEG[0]) + np.mod(theta - np.radians(DEG[0]), 4 * math.pi)
    np.testing.assert_allclose(t(theta), ref(phase), rtol=1e-13, atol=1e-13 * 30)
    for th in theta[::97]:
        assert t(float(th)) == pytest.approx(float(ref(np.mod(th, 4 * math.pi))), rel=1e-13)


def test_the_spline_passes_through_its_points_and_repeats_with_its_period():
    t = PeriodicTable(DEG, VALUES, 720.0)
    for d, v in zip(DEG, VALUES):
        assert t(math.radians(d)) == pytest.approx(v, rel=1e-14)
        assert t(math.radians(d + 720.0)) == pytest.approx(v, rel=1e-14)
        assert t(math.radians(d - 1440.0)) == pytest.approx(v, rel=1e-14)
    # 720 deg, not 360: the second revolution is not the first
    assert abs(t(math.radians(40.0)) - t(math.radians(400.0))) > 1.0


def test_mpmath_and_array_evaluations_agree_with_floats():
    t = PeriodicTable(DEG, VALUES, 720.0)
    for th in (0.1, 2.0, 7.5, 11.0):
        assert float(t(mpmath.mpf(th))) == pytest.approx(t(th), rel=1e-15)
        assert t(np.array([th]))[0] == pytest.approx(t(th), rel=1e-15)


@pytest.mark.parametrize("deg, values, period, message", [
    ([0, 90], [1, 2], 360, "three or more points"),
    ([0, 90, 90], [1, 2, 3], 360, "must increase"),
    ([0, 90, 180], [1, math.nan, 3], 360, "finite"),
    ([0, 180, 360], [1, 2, 3], 360, r"span 360.0 deg, not less than the period 360.0 deg"),
    ([0, 90, 180], [1, 2, 3], -1.0, "period_deg = -1.0 must be a number > 0"),
])
def test_a_bad_table_is_refused_with_the_reason(deg, values, period, message):
    with pytest.raises(ValueError, match=message):
        PeriodicTable(deg, values, period)


def test_rows_from_a_csv_file(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text("theta_deg,value,note\n0,1.5,a\n90,2,b\n180,-1e3,c\n")
    assert read_rows(path) == [[0.0, 1.5], [90.0, 2.0], [180.0, -1000.0]]
    (tmp_path / "bad.csv").write_text("angle,value\n0,1\n")
    with pytest.raises(ValueError, match="needs a header with the columns theta_deg and value"):
        read_rows(tmp_path / "bad.csv")
    (tmp_path / "text.csv").write_text("theta_deg,value\n0,1\n90,high\n")
    with pytest.raises(ValueError, match=r"row 3: theta_deg = '90' and value = 'high'"):
        read_rows(tmp_path / "text.csv")
    with pytest.raises(ValueError, match="cannot read it"):
        read_rows(tmp_path / "missing.csv")


def test_the_c_definition_gives_the_same_floats(tmp_path):
    """The generated C function, compiled and run at 500 angles, returns bit for bit what
    the float evaluation does (the same operations in the same order)."""
    import ctypes

    from linkage_fmu.ccompiler import CompilerError, compile_shared

    t = PeriodicTable(DEG, VALUES, 720.0)
    source = tmp_path / "t.c"
    source.write_text("#include <math.h>\n" + t.c_definition()
                      + f"\ndouble call(double x) {{ return {t.name}(x); }}\n")
    try:
        lib = compile_shared([source], tmp_path / "t.so", flags=("-O2", "-ffp-contract=off"),
                             libraries=("m",))
    except CompilerError as err:
        pytest.skip(f"no C compiler: {err}")
    f = ctypes.CDLL(str(lib)).call
    f.restype, f.argtypes = ctypes.c_double, [ctypes.c_double]
    for th in np.linspace(-10.0, 20.0, 500):
        assert f(float(th)) == t(float(th))
