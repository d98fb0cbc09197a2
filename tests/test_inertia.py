"""Mechanism.reduced_inertia: J(theta), the inertia of the linkage reduced to the crank
(T = J omega**2 / 2), and dJ/dtheta, against the kinetostatic solve, finite differences,
the mpmath reference and hand-derived closed forms.

With no loads and no gravity, the power balance on the crank (Mb counter-clockwise on
the crank, theta counter-clockwise: MECHANISMS.md, Conventions) is
Mb * omega = dT/dt = J * omega * alpha + dJ/2 * omega**3, so Mb = J * alpha + dJ/2 * omega**2:
Mb(omega=0, alpha=1) = J and Mb(omega=1, alpha=0) = dJ/2. A balancing effort on another
link (the six-bar's drivers) does the same power: effort * q' with q' its link's angular
velocity coefficient, or the velocity coefficient of its point along its direction.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from conftest import VARIANTS
from linkage_fmu import AssemblyError, precise, presets
from linkage_fmu.precise import MP

TH = np.linspace(0.0, 2 * np.pi, 181)[:-1] + 0.013  # 180 angles, off the symmetric ones


def unloaded(name: str, **params):
    """The preset with no gravity, and the named loads that make every load zero."""
    mech = presets.get(name, **{**params, "g": 0.0})
    return mech, {ld.name: 0.0 for ld in mech.loads}


def effort_rate(mech, theta):
    """q': the effort's displacement per unit crank angle (1 for a moment on the crank)."""
    st = mech.kinematics(theta, order=1)
    e = mech.effort
    if e.direction is None:
        return st.w1[e.body]
    vx, vy = st.d1[e.point]
    return e.direction[0] * vx + e.direction[1] * vy


@pytest.mark.parametrize("name,params", VARIANTS)
def test_J_is_the_effort_for_unit_crank_acceleration_from_rest(name, params):
    mech, zero = unloaded(name, **params)
    J, dJ = mech.reduced_inertia(TH)
    assert J.shape == dJ.shape == TH.shape
    sol = mech.solve(TH, 0.0, 1.0, method="interpreted", **zero)
    np.testing.assert_array_equal(np.isnan(J), ~sol.valid)  # NaN exactly where unassembled
    assert sol.valid.sum() > 60
    v = sol.valid
    power = sol[mech.effort.name][v] * effort_rate(mech, TH[v])
    np.testing.assert_allclose(power, J[v], rtol=1e-14, atol=0)  # measured 7e-16
    # scalars: floats, the same numbers, and the scalar solve (its traced kernel)
    for th in TH[v][::30]:
        Js, dJs = mech.reduced_inertia(float(th))
        assert type(Js) is float and type(dJs) is float
        assert Js == pytest.approx(J[TH == th][0], rel=1e-14)
        Mb = mech.solve(float(th), 0.0, 1.0, **zero)[mech.effort.name]
        assert Mb * effort_rate(mech, float(th)) == pytest.approx(Js, rel=1e-12)


def test_J_is_positive_and_broadcasts_to_theta_shape():
    mech = presets.get("four_bar")
    J, dJ = mech.reduced_inertia(TH[:60].reshape(3, 4, 5))
    assert J.shape == dJ.shape == (3, 4, 5) and (J > 0).all()
    # a linkage whose J does not depend on theta still gives arrays of theta's shape
    crank = presets.get("scotch_yoke", m2=0.0, m3=0.0, J1=0.25)
    J, dJ = crank.reduced_inertia(np.zeros((2, 3)))
    assert J.shape == dJ.shape == (2, 3)
    assert (J == 0.25).all() and (dJ == 0.0).all()
    assert crank.reduced_inertia("90 deg") == (0.25, 0.0)


@pytest.mark.parametrize("name,params", VARIANTS)
def test_dJ_against_central_differences_and_the_torque_at_unit_speed(name, params):
    mech, zero = unloaded(name, **params)
    J, dJ = mech.reduced_inertia(TH)
    h = 1e-5
    fd = (mech.reduced_inertia(TH + h)[0] - mech.reduced_inertia(TH - h)[0]) / (2 * h)
    v = np.isfinite(fd) & np.isfinite(dJ)
    assert v.sum() > 60
    # truncation h**2 J'''/6 and rounding 1e-16 J / h, against the size of J
    scale = np.max(np.abs(J[v]))
    assert np.max(np.abs(fd[v] - dJ[v])) <= 1e-7 * scale
    # Mb at omega = 1, alpha = 0 with no loads and no gravity is dJ/2
    sol = mech.solve(TH, 1.0, 0.0, method="interpreted", **zero)
    w = sol.valid
    power = sol[mech.effort.name][w] * effort_rate(mech, TH[w])
    np.testing.assert_allclose(power, 0.5 * dJ[w], rtol=1e-12, atol=1e-12 * scale)


@pytest.mark.parametrize("name,params", VARIANTS[::2])
def test_J_against_the_mpmath_reference(name, params):
    mech, zero = unloaded(name, **params)
    J, dJ = mech.reduced_inertia(TH)
    for th in TH[np.isfinite(J)][::45]:
        ref = precise.reference(mech, float(th), 0.0, 1.0, **zero)  # the direct system, 40 digits
        with mpmath.workdps(40):
            Jmp, dJmp = mech.reduced_inertia(mpmath.mpf(float(th)), xp=MP)
            J_ref = ref[mech.effort.name] * effort_rate_mp(mech, float(th))
            # not 1e-30: the groups keep some constants of their parameters (a link's
            # inverse length) as floats, which each formula uses differently
            assert abs(Jmp - J_ref) <= 1e-15 * abs(J_ref)
            i = np.flatnonzero(TH == th)[0]
            assert abs(J[i] - J_ref) <= 1e-14 * abs(J_ref)  # measured 6e-16
            assert abs(dJ[i] - dJmp) <= 1e-13 * abs(Jmp)


def effort_rate_mp(mech, theta):
    st = mech.kinematics(mpmath.mpf(theta), order=1, xp=MP)
    e = mech.effort
    if e.direction is None:
        return st.w1[e.body]
    vx, vy = st.d1[e.point]
    return e.direction[0] * vx + e.direction[1] * vy


def test_scotch_yoke_with_the_yoke_alone():
    """The yoke translates along y: y3 = r sin(theta), so J = m r**2 cos(theta)**2 and
    dJ = -m r**2 sin(2 theta)."""
    m, r = 7.0, 0.13
    mech = presets.get("scotch_yoke", l_AB=r, m1=0.0, J1=0.0, m2=0.0, m3=m, J3=0.0)
    J, dJ = mech.reduced_inertia(TH)
    np.testing.assert_allclose(J, m * r ** 2 * np.cos(TH) ** 2, rtol=0, atol=1e-15 * m * r ** 2)
    np.testing.assert_allclose(dJ, -m * r ** 2 * np.sin(2 * TH), rtol=0, atol=1e-15 * m * r ** 2)


def test_slider_crank_with_the_piston_alone():
    """x = r cos(theta) + s, s = sqrt(L**2 - r**2 sin(theta)**2): x' = -r sin - f with
    f = r**2 sin cos / s, x'' = -r cos - r**2 cos(2 theta) / s - (r**2 sin cos)**2 / s**3;
    J = m x'**2, dJ = 2 m x' x''."""
    m, r, L = 0.6, 0.05, 0.2
    mech = presets.get("slider_crank", l_OA=r, l_AB=L, m1=0.0, J1=0.0, m2=0.0, J2=0.0, m3=m)
    J, dJ = mech.reduced_inertia(TH)
    s, c = np.sin(TH), np.cos(TH)
    root = np.sqrt(L ** 2 - r ** 2 * s ** 2)
    x1 = -r * s - r ** 2 * s * c / root
    x2 = -r * c - r ** 2 * np.cos(2 * TH) / root - (r ** 2 * s * c) ** 2 / root ** 3
    np.testing.assert_allclose(J, m * x1 ** 2, rtol=0, atol=1e-15 * m * r ** 2)
    np.testing.assert_allclose(dJ, 2 * m * x1 * x2, rtol=0, atol=1e-15 * m * r ** 2)


def test_bad_theta_is_an_error_naming_it():
    mech = presets.get("four_bar")
    for bad in (math.nan, math.inf, np.float64(-np.inf)):
        with pytest.raises(ValueError, match="theta must be a finite number"):
            mech.reduced_inertia(bad)
    with pytest.raises(ValueError, match=r"theta must be finite: entry \(1,\) is nan"):
        mech.reduced_inertia([0.0, math.nan])
    with pytest.raises(ValueError, match="theta"):
        mech.reduced_inertia("3 m")  # a length is not an angle


def test_unassemblable_scalar_raises_as_solve_does():
    mech = presets.get("four_bar", l_AB=0.3)  # a crank too long to turn fully
    with pytest.raises(AssemblyError) as solving:
        mech.solve(3.1)
    with pytest.raises(AssemblyError) as reducing:
        mech.reduced_inertia(3.1)
    assert str(reducing.value) == str(solving.value)
    assert "cannot be assembled at theta = 3.1 rad" in str(reducing.value)
    J, dJ = mech.reduced_inertia([0.0, 3.1])  # arrays: NaN there, as solve's mask
    assert np.isfinite(J[0]) and np.isnan(J[1]) and np.isnan(dJ[1])


@pytest.mark.parametrize("name, params", VARIANTS)
def test_the_diagnostics_J_red_and_dJ_red_are_reduced_inertia_on_every_path(name, params):
    # every path of solve (the traced kernel, compiled once hot, the C array kernel, the
    # interpreted and the direct formulas) gives reduced_inertia's floats, moving or static
    mech = presets.get(name, **params)
    J, dJ = mech.reduced_inertia(TH)
    ok = np.isfinite(J)
    for method in ("closed_form", "interpreted", "direct"):
        for omega in (0.0, 7.0):
            sol = mech.solve(TH, omega, 0.0, method=method)
            np.testing.assert_allclose(sol["J_red"][ok], J[ok], rtol=1e-14, atol=0.0)
            np.testing.assert_allclose(sol["dJ_red"][ok], dJ[ok], rtol=1e-13,
                                       atol=1e-15 * np.max(np.abs(J[ok])))
            assert np.isnan(sol["J_red"][~ok]).all()
    k = mech.solver.kernel()
    theta = float(TH[ok][3])
    k.compile()  # the C kernel where there is a compiler, else the Python one stays
    r = k(theta, 3.0, 1.0, *[1.0] * len(mech.input_loads))
    assert r[k.index["J_red"]] == pytest.approx(mech.reduced_inertia(theta)[0], rel=1e-14)
    assert r[k.index["dJ_red"]] == pytest.approx(mech.reduced_inertia(theta)[1], rel=1e-13,
                                                 abs=1e-15 * J[ok].max())
