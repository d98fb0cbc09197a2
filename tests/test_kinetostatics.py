"""Kinetostatics against named references: the table of the scotch yoke worked example (a
Chinese kinetostatics course; MATLAB output printed in the source), the 9x9 matrix of the
hinged four-bar worked example (a Chinese course, kinetostatics without friction) built
literally from its table, virtual power, the equilibrium of every link, virtual work for
the static six-bar of the six-bar coursework (Bertyaev et al.), and a published textbook
slider-crank (Marghitu 2009)."""

from __future__ import annotations

import math
from pathlib import Path

import mpmath
import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st_

from conftest import IDS, MP, VARIANTS, power_residual
from linkage_fmu import presets
from linkage_fmu.kinetostatics import closed_form, equilibrium_system
from linkage_fmu.loads import wrenches
from linkage_fmu.pairs import Prismatic

SCOTCH_YOKE_TABLE = Path(__file__).parent / "reference" / "scotch_yoke_table.csv"
# the worked example's column -> (our output, sign): MECHANISMS.md: F12x and F41x are
# minus the printed
COLUMNS = {"FR23": ("F23y", 1), "FR4p": ("F4p", 1), "FR4": ("F4", 1), "FR12x": ("F12x", -1),
           "FR12y": ("F12y", 1), "FR41x": ("F41x", -1), "FR41y": ("F41y", 1), "Mb": ("Mb", 1)}


@pytest.mark.parametrize("method", ["closed_form", "direct"])
def test_scotch_yoke_worked_example_table(method):
    """All 36 angles x 8 columns of the scotch yoke worked example's table to 1e-3 (printed
    to 4 decimals)."""
    ref = pd.read_csv(SCOTCH_YOKE_TABLE)
    sol = presets.get("scotch_yoke").solve(ref["theta_rad"].to_numpy(), omega=10.0,
                                           load=400.0, method=method)
    for col, (name, sign) in COLUMNS.items():
        np.testing.assert_allclose(sign * sol[name], ref[col], atol=1e-3, rtol=0, err_msg=col)


@pytest.mark.parametrize("method", ["closed_form", "direct"])
@pytest.mark.parametrize("deg, FR23, FR4, FR12x, FR12y, Mb", [
    (60, 313.3975, 195.8734, 20.0000, 278.7564, 15.6699),
    (150, 350.0000, -378.8861, -34.6410, 330.0000, -30.3109),
    (220, 464.2788, -444.5727, -30.6418, 489.9903, -35.5658),
])
def test_scotch_yoke_worked_example_quoted_values(method, deg, FR23, FR4, FR12x, FR12y, Mb):
    """The values the scotch yoke worked example quotes in its text, to the 4 decimals it
    prints."""
    s = presets.get("scotch_yoke").solve(math.radians(deg), omega=10.0, load=400.0, method=method)
    got = (s["F23y"], s["F4"], s["F4p"], -s["F12x"], s["F12y"], -s["F41x"], s["F41y"], s["Mb"])
    want = (FR23, FR4, FR4, FR12x, FR12y, FR12x, FR12y, Mb)
    np.testing.assert_allclose(got, want, atol=6e-5, rtol=0)


def _hinged_four_bar_solution(p, theta, omega, alpha, Mr):
    """The hinged four-bar worked example's 9x9 system, each entry typed from its table
    (section 6), with kinematics from mpmath positions and mpmath.diff (independent of the
    package)."""
    mpmath.mp.dps = 40

    def angles(t):
        bx, by = p["l_AB"] * mpmath.cos(t), p["l_AB"] * mpmath.sin(t)
        dx, dy = p["l_AD"] - bx, -by
        d = mpmath.sqrt(dx * dx + dy * dy)
        psi = mpmath.atan2(dy, dx)
        gam = mpmath.acos((p["l_BC"] ** 2 + d * d - p["l_CD"] ** 2) / (2 * p["l_BC"] * d))
        phi2 = psi + gam  # branch +1: C left of B->D
        cx, cy = bx + p["l_BC"] * mpmath.cos(phi2), by + p["l_BC"] * mpmath.sin(phi2)
        phi3 = mpmath.atan2(cy, cx - p["l_AD"])
        return bx, by, phi2, phi3

    def s2(t, k):
        bx, by, phi2, _ = angles(t)
        return (bx + p["l_BS2"] * mpmath.cos(phi2), by + p["l_BS2"] * mpmath.sin(phi2))[k]

    def s3(t, k):
        _, _, _, phi3 = angles(t)
        return (p["l_AD"] + p["l_DS3"] * mpmath.cos(phi3), p["l_DS3"] * mpmath.sin(phi3))[k]

    t = mpmath.mpf(theta)
    _, _, phi2, phi3 = angles(t)

    def acc(f, k):
        return float(mpmath.diff(lambda u: f(u, k), t, 2) * omega ** 2
                     + mpmath.diff(lambda u: f(u, k), t, 1) * alpha)

    e2 = float(mpmath.diff(lambda u: angles(u)[2], t, 2) * omega ** 2
               + mpmath.diff(lambda u: angles(u)[2], t, 1) * alpha)
    e3 = float(mpmath.diff(lambda u: angles(u)[3], t, 2) * omega ** 2
               + mpmath.diff(lambda u: angles(u)[3], t, 1) * alpha)
    a2x, a2y, a3x, a3y = acc(s2, 0), acc(s2, 1), acc(s3, 0), acc(s3, 1)
    phi1, phi2, phi3 = theta, float(phi2), float(phi3)
    G1, G2, G3 = -p["m1"] * p["g"], -p["m2"] * p["g"], -p["m3"] * p["g"]
    m2, m3, l1, l2, l3 = p["m2"], p["m3"], p["l_AB"], p["l_BC"], p["l_CD"]
    A = np.array([
        [1, 0, 0, 0, 0, 0, -1, 0, 0],
        [0, 1, 0, 0, 0, 0, 0, -1, 0],
        [-l1 * math.sin(phi1), l1 * math.cos(phi1), 0, 0, 0, 0, 0, 0, 1],
        [-1, 0, 1, 0, 0, 0, 0, 0, 0],
        [0, -1, 0, 1, 0, 0, 0, 0, 0],
        [0, 0, -l2 * math.sin(phi2), l2 * math.cos(phi2), 0, 0, 0, 0, 0],
        [0, 0, -1, 0, 1, 0, 0, 0, 0],
        [0, 0, 0, -1, 0, 1, 0, 0, 0],
        [0, 0, l3 * math.sin(phi3), -l3 * math.cos(phi3), 0, 0, 0, 0, 0],
    ], dtype=float)
    b = np.array([
        0.0, -G1, 0.0,
        m2 * a2x, -G2 + m2 * a2y,
        p["J_S2"] * e2 - p["l_BS2"] * math.cos(phi2) * (G2 - m2 * a2y)
        + p["l_BS2"] * math.sin(phi2) * (-m2 * a2x),
        m3 * a3x, -G3 + m3 * a3y,
        p["l_DS3"] * math.cos(phi3) * (m3 * a3y - G3) + p["l_DS3"] * math.sin(phi3) * (-m3 * a3x)
        + p["J_S3"] * e3 - Mr,
    ])
    return dict(zip(["F21x", "F21y", "F32x", "F32y", "F43x", "F43y", "F14x", "F14y", "Mb"],
                    np.linalg.solve(A, b)))


@pytest.mark.parametrize("method", ["closed_form", "direct"])
@pytest.mark.parametrize("theta, omega, alpha, Mr", [
    (0.3, 10.0, 0.0, 0.0), (1.7, -12.0, 40.0, 5.0), (4.0, 25.0, -300.0, -8.0),
])
def test_four_bar_matches_hinged_four_bar_worked_example(method, theta, omega, alpha, Mr):
    """four_bar == the hinged four-bar worked example's own 9x9 system (crank CG at A as
    there) to 1e-9 relative."""
    mech = presets.get("four_bar")
    ref = _hinged_four_bar_solution(mech.parameters, theta, omega, alpha, Mr)
    sol = mech.solve(theta, omega, alpha, Mr, method=method)
    scale = max(abs(v) for v in ref.values())
    for name, value in ref.items():
        assert abs(sol[name] - value) <= 1e-9 * scale, name


def test_marghitu_slider_crank():
    """D. B. Marghitu, Mechanisms and Robots Analysis with MATLAB, Springer 2009, ch. 4,
    R-RRT example (eqs. 4.51-4.52): AB = BC = 1 m, centres of mass at mid-links,
    m = 1 kg each, I_C1 = I_C2 = 0.0833417 kg m^2, g = 10, phi1 = 45 deg, omega1 = 1
    rad/s, alpha1 = 0, 100 N on the slider along +x (away from the crank). Published:
    F12 (crank on rod) = (-(400 + 7 sqrt 2)/4, 5 (84 + sqrt 2)/4) = (-102.4749, 106.7678) N.
    Ours: F21 is the rod on the crank, = -F12."""
    mech = presets.get("slider_crank", l_OA=1.0, l_AB=1.0, m1=1.0, J1=0.0833417, l_OS1=0.5,
                       m2=1.0, J2=0.0833417, l_AS2=0.5, m3=1.0, g=10.0)
    for method in ("closed_form", "direct"):
        s = mech.solve(math.pi / 4, omega=1.0, alpha=0.0, load=-100.0, method=method)
        assert s["F21x"] == pytest.approx((400 + 7 * math.sqrt(2)) / 4, rel=1e-12)
        assert s["F21y"] == pytest.approx(-5 * (84 + math.sqrt(2)) / 4, rel=1e-12)


# -- properties at random states ---------------------------------------------------
STATES = st_.tuples(
    st_.floats(0.0, 2 * math.pi),
    st_.floats(-60.0, 60.0).filter(lambda w: abs(w) > 0.1),
    st_.floats(-500.0, 500.0),
    st_.floats(-200.0, 200.0),
)


@pytest.mark.parametrize("variant", VARIANTS, ids=IDS)
@settings(max_examples=40, deadline=None, derandomize=True)
@given(state=STATES)
def test_random_states(variant, state):
    """Virtual power, per-link equilibrium, and direct == closed_form (1e-12 relative)."""
    mech = presets.get(variant[0], **variant[1])
    theta, omega, alpha, load = state
    a = mech.solve(theta, omega, alpha, load, method="closed_form")
    b = mech.solve(theta, omega, alpha, load, method="direct")
    cond = a["cond"]
    # eta is NaN in both where no power enters (a state without load, weight or motion)
    names = [n for n in mech.output_names if not (math.isnan(a[n]) and math.isnan(b[n]))]
    scale = max(abs(a[n]) for n in names)
    for n in names:
        assert abs(a[n] - b[n]) <= 1e-12 * max(1.0, cond / 100) * scale, n
    for sol in (a, b):
        res, size = power_residual(mech, sol, theta, omega, alpha, load)
        assert abs(res) <= 1e-12 * max(1.0, cond / 100) * size
    # equilibrium of every link: A x - b with the closed-form reactions in x
    st = mech.kinematics(theta, order=2)
    W = wrenches(mech, st, omega, alpha, (load,), static=False)
    A, rhs = equilibrium_system(mech, st, W)
    R, effort = closed_form(mech, st, {k: list(v) for k, v in W.items()})
    L = mech.length_scale
    x = []
    for j in mech.joints:
        c0, c1 = R[j.name]
        x += [c0, c1 / L if isinstance(j, Prismatic) else c1]
    x.append(effort / L if mech.effort.direction is None else effort)
    r = A[0] @ np.array(x) - rhs[0]
    assert np.max(np.abs(r)) <= 1e-12 * max(1.0, cond / 100) * np.max(np.abs(x))


def _virtual_work_effort(mech, theta):
    """Static balancing effort from virtual work with derivatives of mpmath positions:
    effort * dq/dtheta = sum m g dy_S/dtheta + load terms (load = 0 here)."""
    def y(t, point):
        return mech.kinematics(t, 0, MP).p[point][1]

    def q(t):
        st = mech.kinematics(t, 0, MP)
        e = mech.effort
        if e.direction is None:
            c, s = st.u[e.body]
            return mpmath.atan2(s, c)
        return st.p[e.point][1]

    t = mpmath.mpf(theta)
    work = sum(b.mass * mech.g * mpmath.diff(lambda u, p=b.cg: y(u, p), t) for b in mech.bodies)
    return float(work / mpmath.diff(q, t))


@pytest.mark.parametrize("driver", ["OA", "AB", "O1B", "KD", "D"])
@pytest.mark.parametrize("theta", [0.2, 1.1, 2.5, 3.6, 5.0])
@pytest.mark.parametrize("method", ["closed_form", "direct"])
def test_static_six_bar_effort_is_virtual_work(driver, theta, method):
    """The six-bar coursework: balancing effort for every driver equals the virtual-work
    value (1e-10)."""
    mech = presets.get("six_bar", driver=driver)
    sol = mech.solve(theta, method=method)
    name = "Pb" if driver == "D" else "Mb"
    other = "Mb" if driver == "D" else "Pb"
    assert sol[name] == pytest.approx(_virtual_work_effort(mech, theta), rel=1e-10)
    assert sol[other] == 0.0


@pytest.mark.parametrize("variant", VARIANTS, ids=IDS)
@settings(max_examples=12, deadline=None, derandomize=True)
@given(state=STATES)
def test_random_states_match_the_mpmath_reference(variant, state):
    """Both methods against the 40-digit mpmath evaluation of the same equations
    (:mod:`linkage_fmu.precise`): normwise relative error <= 16 cond eps."""
    from linkage_fmu.precise import reference

    mech = presets.get(variant[0], **variant[1])
    ref = {n: float(v) for n, v in reference(mech, *state).items()}
    scale = max(abs(v) for v in ref.values())
    for method in ("closed_form", "direct"):
        sol = mech.solve(*state, method=method)
        err = max(abs(sol[n] - ref[n]) for n in ref) / scale
        assert err <= 16 * sol["cond"] * 2.2e-16, (method, err, sol["cond"])


# -- Marghitu & Dupac, Advanced Dynamics (Springer 2012), Example 6.1 ---------------
# The R-RTR-RRT shaper: crank AB = 0.2 m about A; block on B sliding on the lever pivoted
# at D = (0, -0.4) (our C), lever tip C at 0.7 m (our D); rod CE = 0.3 m (our DE) to the
# ram E on the guide y = 0.35; phi = 45 deg, n = 200 rpm counter-clockwise, g = 9.807;
# steel bars and sliders (rho = 8000) with the example's masses and inertias, among them
# its rod inertia 6.00667e-5 kg m2 (computed there with the slider's mass); a 500 N
# force on the ram along +x, against its velocity. The printed results (Fij = force of
# i on j, N and N m, three decimals) are those of the example's program (E6_1.m; E6_2.m,
# the contour method, prints the same). The example puts the crank's centre of mass at
# mid-AB; the preset's is at A, so the crank is massless here, and then F01 = F12 and
# Mb = B x F12, both from the printed F12.
EX61 = dict(l_AB=0.2, l_AC=0.4, l_CD=0.7, l_DE=0.3, h_E=0.35, g=9.807, m1=0.0, J1=0.0,
            m2=8000 * 0.02 * 0.05 * 0.001, J2=8000 * 0.02 * 0.05 * 0.001 * (0.02**2 + 0.05**2) / 12,
            m3=8000 * 0.7 * 0.01 * 0.001, J_S3=8000 * 0.7 * 0.01 * 0.001 * (0.7**2 + 0.01**2) / 12,
            l_CS3=0.35, m4=8000 * 0.3 * 0.01 * 0.001, J_S4=6.00667e-5, l_DS4=0.15,
            m5=8000 * 0.02 * 0.05 * 0.001, branch=-1)
EX61_STATE = (math.radians(45.0), 200 * 2 * math.pi / 60, 0.0)
EX61_PRINTED = {"F12": (-625.610, 162.864), "F32": (625.114, -163.282),
                "F03": (123.647, -38.376), "F34": (-500.685, 124.998),
                "F54": (500.140, -125.037), "F05": (0.0, -124.959), "phi3_deg": 75.361,
                "Min2": -5.871e-5}


def _ex61_crank_terms():
    B = (0.2 * math.cos(EX61_STATE[0]), 0.2 * math.sin(EX61_STATE[0]))
    fx, fy = EX61_PRINTED["F12"]
    return B, B[0] * fy - B[1] * fx  # Mb of a massless crank: B x F12


def test_crank_shaper_reproduces_marghitu_dupac_example_6_1():
    """Every printed joint force of the example to its three printed decimals (1.5e-3 N),
    the block's couple on the lever to 1e-8 N m, and the driving moment of a massless
    crank, with both methods."""
    mech = presets.get("crank_shaper", **EX61)
    p = EX61_PRINTED
    n3 = (-math.sin(math.radians(p["phi3_deg"])), math.cos(math.radians(p["phi3_deg"])))
    _, Mb = _ex61_crank_terms()
    expect = {"F12x": p["F12"][0], "F12y": p["F12"][1], "F01x": p["F12"][0],
              "F01y": p["F12"][1], "F03x": p["F03"][0], "F03y": p["F03"][1],
              "F34x": p["F34"][0], "F34y": p["F34"][1], "F45x": -p["F54"][0],
              "F45y": -p["F54"][1], "N05": p["F05"][1],
              # the block's force on the lever, -F32, along the lever's left normal
              "N23": -p["F32"][0] * n3[0] - p["F32"][1] * n3[1]}
    for method in ("closed_form", "direct"):
        sol = mech.solve(*EX61_STATE, -500.0, method=method)  # 500 N along +x
        for name, value in expect.items():
            tol = 0.02 if name == "N23" else 1.5e-3  # N23 also carries the printed angle
            assert sol[name] == pytest.approx(value, abs=tol), (method, name)
        assert sol["M23"] == pytest.approx(p["Min2"], abs=1e-8)
        assert sol["Mb"] == pytest.approx(Mb, abs=1e-3)
    st = mech.kinematics(EX61_STATE[0], order=0)
    assert math.degrees(math.atan2(st.u["3"][1], st.u["3"][0])) == pytest.approx(
        p["phi3_deg"], abs=1e-3)
    assert st.p["E"][0] == pytest.approx(-0.114, abs=1e-3)


def test_slotted_lever_reproduces_the_lever_of_marghitu_dupac_example_6_1():
    """The crank and slotted lever of the same example, with the rod replaced by what
    the example prints for it: the moment about the pivot of the rod's force on the
    lever (-F34 at the lever's tip). The crank pin, block and driving moment are then
    those printed; the pivot carries the printed F03 plus the rod's force, F03 - F34."""
    params = {k: EX61[k] for k in ("l_AB", "l_AC", "g", "m1", "J1", "m2", "J2", "m3", "J_S3",
                                   "l_CS3")}
    mech = presets.get("slotted_lever", **params)
    p = EX61_PRINTED
    B, Mb = _ex61_crank_terms()
    C = (0.0, -0.4)
    s = math.hypot(B[0] - C[0], B[1] - C[1])
    D = (C[0] + 0.7 * (B[0] - C[0]) / s, C[1] + 0.7 * (B[1] - C[1]) / s)
    fx, fy = -p["F34"][0], -p["F34"][1]  # the rod on the lever, at D
    moment = (D[0] - C[0]) * fy - (D[1] - C[1]) * fx
    n3 = (-math.sin(math.radians(p["phi3_deg"])), math.cos(math.radians(p["phi3_deg"])))
    for method in ("closed_form", "direct"):
        sol = mech.solve(*EX61_STATE, moment, method=method)
        assert sol["F12x"] == pytest.approx(p["F12"][0], abs=2e-3)
        assert sol["F12y"] == pytest.approx(p["F12"][1], abs=2e-3)
        assert sol["N23"] == pytest.approx(-p["F32"][0] * n3[0] - p["F32"][1] * n3[1], abs=0.02)
        assert sol["M23"] == pytest.approx(p["Min2"], abs=1e-8)
        assert sol["F03x"] == pytest.approx(p["F03"][0] - p["F34"][0], abs=3e-3)
        assert sol["F03y"] == pytest.approx(p["F03"][1] - p["F34"][1], abs=3e-3)
        assert sol["Mb"] == pytest.approx(Mb, abs=2e-3)
