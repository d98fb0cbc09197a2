"""Kinematics: constraints hold, branches are as specified, derivative coefficients equal
the derivatives of the positions (mpmath.diff at 40 digits), and assembly failures are
reported, never clamped."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from conftest import MP
from linkage_fmu import AssemblyError, presets

ANGLES = [0.0, 0.4, 1.3, 2.2, 3.0, 3.9, 4.8, 5.9]


def _mp_positions(mech, theta):
    return mech.kinematics(mpmath.mpf(theta), 0, MP).p


@pytest.mark.parametrize("theta", ANGLES)
def test_derivative_coefficients_match_mpmath_derivatives(mech, theta):
    """d1, d2 of every point equal d/dtheta, d2/dtheta2 of its mpmath position (1e-12)."""
    st = mech.kinematics(theta, order=2)
    for point in st.p:
        for axis in (0, 1):
            def coord(t, point=point, axis=axis):
                return _mp_positions(mech, t)[point][axis]
            d1 = mpmath.diff(coord, mpmath.mpf(theta), 1)
            d2 = mpmath.diff(coord, mpmath.mpf(theta), 2)
            scale = max(mech.length_scale, 1e-300)
            assert abs(st.d1[point][axis] - float(d1)) <= 1e-12 * scale, (point, axis)
            assert abs(st.d2[point][axis] - float(d2)) <= 1e-12 * scale, (point, axis)


def test_four_bar_constraints_and_branch():
    """Link lengths hold to 1e-15 m; C is left of B->D for branch +1, right for -1."""
    for branch in (1, -1):
        mech = presets.get("four_bar", branch=branch)
        p = mech.parameters
        st = mech.kinematics(np.linspace(0, 2 * np.pi, 50), order=0)
        (bx, by), (cx, cy), (dx, dy) = st.p["B"], st.p["C"], st.p["D"]
        np.testing.assert_allclose(np.hypot(cx - bx, cy - by), p["l_BC"], atol=1e-15)
        np.testing.assert_allclose(np.hypot(cx - dx, cy - dy), p["l_CD"], atol=1e-15)
        side = (dx - bx) * (cy - by) - (dy - by) * (cx - bx)
        assert np.all(np.sign(side) == branch)


def test_six_bar_and_slider_crank_guides():
    """Six-bar: D on x = a above K; slider-crank: B on the offset guide, +gamma side."""
    six = presets.get("six_bar")
    st = six.kinematics(np.linspace(0, 2 * np.pi, 40), order=0)
    np.testing.assert_allclose(st.p["D"][0], 0.5, atol=1e-15)
    assert np.all(st.p["D"][1] > st.p["K"][1])
    kx, ky = st.p["K"]
    np.testing.assert_allclose(np.hypot(kx - 0.5, ky - 0.37), 0.25, atol=1e-15)

    sc = presets.get("slider_crank", e=0.02, gamma=0.7)
    st = sc.kinematics(np.linspace(0, 2 * np.pi, 40), order=0)
    t, n = (math.cos(0.7), math.sin(0.7)), (-math.sin(0.7), math.cos(0.7))
    bx, by = st.p["B"]
    ax, ay = st.p["A"]
    np.testing.assert_allclose(bx * n[0] + by * n[1], 0.02, atol=1e-15)
    assert np.all((bx - ax) * t[0] + (by - ay) * t[1] > 0)
    np.testing.assert_allclose(np.hypot(bx - ax, by - ay), 0.2, atol=1e-15)


def test_scotch_yoke_motion_matches_the_worked_example_formulas():
    """y3 = l sin(theta), v3 = l omega cos(theta), a3 = -l omega^2 sin(theta) (the scotch
    yoke worked example)."""
    th = np.linspace(0, 2 * np.pi, 36)
    st = presets.get("scotch_yoke").kinematics(th, order=2)
    np.testing.assert_allclose(st.p["S3"][1], 0.1 * np.sin(th), atol=1e-16)
    np.testing.assert_allclose(st.velocity("S3", 10.0)[1], 0.1 * 10 * np.cos(th), atol=1e-14)
    np.testing.assert_allclose(st.acceleration("S3", 10.0, 0.0)[1], -0.1 * 100 * np.sin(th),
                               atol=1e-13)


def test_assembly_error_names_angle_and_condition():
    mech = presets.get("four_bar", l_AB=0.3)  # |BD| reaches 0.7 > 0.35 + 0.30
    with pytest.raises(AssemblyError,
                       match=r"theta = 3\.14159 rad .*\|BD\| = 0\.7 m > BC \+ CD = 0\.65 m"):
        mech.kinematics(math.pi)
    with pytest.raises(AssemblyError, match="E|guide"):
        presets.get("slider_crank", e=0.3).kinematics(0.0)


def test_arrays_get_nan_exactly_where_not_assemblable():
    """NaN where |BD| > BC + CD (the closed-form Grashof test), finite elsewhere."""
    mech = presets.get("four_bar", l_AB=0.3)
    th = np.linspace(0, 2 * np.pi, 721)
    bd = np.hypot(0.3 * np.cos(th) - 0.4, 0.3 * np.sin(th))
    expected_bad = bd > 0.65
    assert expected_bad.any() and (~expected_bad).any()
    sol = mech.solve(th, omega=5.0)
    np.testing.assert_array_equal(~sol.valid, expected_bad)
    for name in mech.output_names + mech.diagnostic_names:
        assert np.all(np.isnan(sol[name][expected_bad])), name
        assert np.all(np.isfinite(sol[name][~expected_bad])), name
