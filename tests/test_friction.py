"""Coulomb friction in the joints (linkage_fmu.friction): mu = 0 is the frictionless
linkage bit for bit; the power balance and the friction laws hold at random states;
the solution paths agree with each other and with the mpmath reference; a hand-derived
slider-crank and its self-locking angle; an independent fsolve formulation of the
slider-crank with pin and slide friction; the description's checks."""

from __future__ import annotations

import math
import zlib

import mpmath
import numpy as np
import pytest
from scipy.optimize import fsolve

from conftest import IDS, VARIANTS
from linkage_fmu import SelfLockingError, presets, solver
from linkage_fmu.descriptions.description import Description, DescriptionError
from linkage_fmu.kinetostatics import effort_coefficient
from linkage_fmu.pairs import Revolute
from linkage_fmu.precise import MP, reference

NAMES = presets.names()
STATES = [(0.3, 7.0, -20.0, 30.0), (1.7, -4.0, 3.0, 0.0), (4.4, 0.0, 0.0, 50.0),
          (5.9, 12.0, 0.0, -10.0)]

#: per preset: pair -> the outputs holding its reaction ((x, y) of a pin, N of a slide),
#: where the preset reports it
REACTIONS = {
    "scotch_yoke": {"A": ("F41x", "F41y"), "B": ("F12x", "F12y")},
    "four_bar": {"A": ("F14x", "F14y"), "B": ("F21x", "F21y"), "C": ("F32x", "F32y"),
                 "D": ("F43x", "F43y")},
    "six_bar": {"O": ("XO", "YO"), "A": ("XA", "YA"), "B": ("XB", "YB"), "O1": ("XO1", "YO1"),
                "K": ("XK", "YK"), "D": ("XD", "YD"), "guide": ("N4",)},
    "slider_crank": {"O": ("F14x", "F14y"), "A": ("F21x", "F21y"), "B": ("F32x", "F32y"),
                     "guide": ("N43",)},
    "slotted_lever": {"A": ("F01x", "F01y"), "B": ("F12x", "F12y"), "slot": ("N23",),
                      "C": ("F03x", "F03y")},
    "crank_shaper": {"A": ("F01x", "F01y"), "B": ("F12x", "F12y"), "slot": ("N23",),
                     "C": ("F03x", "F03y"), "D": ("F34x", "F34y"), "E": ("F45x", "F45y"),
                     "guide": ("N05",)},
}


def mu_of(name, joint):
    """The preset's parameter of the pair's coefficient (mu_J)."""
    return presets.preset(name).friction[joint]["mu"]


def _friction_params(name, rng, base=None):
    """Random mu in [0, 0.3] on every pair, pin radii in [0, 0.05] of the length scale."""
    mech = presets.get(name, **(base or {}))
    L = mech.length_scale
    p = {}
    for jf in mech.friction.joints:
        j = jf.joint.name
        p[mu_of(name, j)] = float(rng.uniform(0.0, 0.3))
        if isinstance(jf.joint, Revolute):
            p[f"r_{j}"] = float(rng.uniform(0.0, 0.05) * L)
    return p


def _random_states(rng, n):
    th = rng.uniform(0.0, 2 * math.pi, n)
    om = rng.uniform(-15.0, 15.0, n)
    om[:2] = 0.0  # static scenes too (the drive direction decides)
    al = rng.uniform(-50.0, 50.0, n)
    ld = rng.uniform(-100.0, 100.0, n)
    return th, om, al, ld


def _frictionless(name):
    d = presets.preset(name).copy()
    d.friction = {}
    return d


# -- a. mu = 0 is the frictionless linkage ----------------------------------------------------
@pytest.mark.parametrize("name", NAMES)
def test_zero_mu_is_bit_identical_to_no_friction(name):
    """Reference: the same description without [friction.J] tables. Tolerance: exact (==)
    for every common output, scalars by closed_form, interpreted and direct, arrays by
    closed_form; also with mu_X = 0 and a pin radius of 0.01 (X the first pair)."""
    bare = _frictionless(name).build()
    first = presets.get(name).friction.joints[0]
    extra = {mu_of(name, first.joint.name): 0.0}
    if isinstance(first.joint, Revolute):
        extra[f"r_{first.joint.name}"] = 0.01
    common = [n for n in bare.output_names]
    th = np.array([s[0] for s in STATES])
    for mech in (presets.get(name), presets.get(name, **extra)):
        assert not mech.friction.active
        assert set(common) <= set(mech.output_names)
        for state in STATES:
            for method in ("closed_form", "interpreted", "direct"):
                a, b = mech.solve(*state, method=method), bare.solve(*state, method=method)
                for n in common:
                    assert a[n] == b[n] or (math.isnan(a[n]) and math.isnan(b[n])), \
                        (state, method, n)
        for om in (0.0, 9.0):
            a, b = mech.solve(th, om, 2.0, 30.0), bare.solve(th, om, 2.0, 30.0)
            for n in common:
                np.testing.assert_array_equal(a[n], b[n], err_msg=n)


# -- b. the power balance and the friction laws ----------------------------------------------
def _relative_motion(mech, st, jf):
    """First-order coefficient of the pair's relative motion, computed here: pins
    w1[b] - w1[a]; slides (v_b(P) - v_a(P)) . t, t = (ny, -nx)."""
    j = jf.joint

    def w(body):
        return 0.0 if body == mech.frame else st.w1[body]

    if isinstance(jf.joint, Revolute):
        return w(j.b) - w(j.a)
    px, py = st.p[j.point]

    def v(body):
        if body == mech.frame:
            return 0.0, 0.0
        cg = mech.cg[body]
        (vx, vy), (sx, sy) = st.d1[cg], st.p[cg]
        return vx - w(body) * (py - sy), vy + w(body) * (px - sx)

    nx, ny = j.normal_at(st)
    (ax, ay), (bx, by) = v(j.a), v(j.b)
    return (bx - ax) * ny + (by - ay) * (-nx)


@pytest.mark.parametrize("method", ["closed_form", "direct"])
@pytest.mark.parametrize("variant", VARIANTS, ids=IDS)
def test_power_balance_and_friction_laws(variant, method):
    """Reference: the virtual power balance (E - E0) q' omega = P_loss (E0 at mu = 0) and
    P_loss = sum |Mf| |w_rel| + sum |Ff| |v_rel| with the relative motions computed here,
    P_loss >= 0; |Mf| = mu r |R|, |Ff| = mu |N| from the reported reactions. 20 seeded
    random states, random mu, radii. Tolerance: 1e-10 relative to the largest term."""
    name, base = variant
    rng = np.random.default_rng(zlib.crc32(str(variant).encode()))
    fp = _friction_params(name, rng, base)
    mech, ideal = presets.get(name, **base, **fp), presets.get(name, **base)
    assert mech.friction.active
    th, om, al, ld = _random_states(rng, 20)
    sol, sol0 = mech.solve(th, om, al, ld, method=method), ideal.solve(th, om, al, ld)
    ok = sol.status == solver.SOLVED
    assert ok.sum() >= 15, sol.status
    st = mech.kinematics(th, 1)
    E, E0 = sol[mech.effort.name], sol0[mech.effort.name]
    q = effort_coefficient(mech, st)
    P = sol["P_loss"]
    assert np.all(P[ok] >= 0.0)
    assert np.all(P[om == 0.0] == 0.0)
    scale = np.abs(E * q * om) + np.abs(E0 * q * om) + P + 1e-300
    np.testing.assert_array_less(np.abs((E - E0) * q * om - P)[ok], 1e-10 * scale[ok] + 1e-12)
    total = np.zeros_like(th)
    for jf in mech.friction.joints:
        f = sol[jf.output]
        total += np.abs(f) * np.abs(_relative_motion(mech, st, jf) * om)
        outs = REACTIONS[name].get(jf.joint.name)
        if outs is None:
            continue
        size = np.hypot(*(sol[o] for o in outs)) if len(outs) == 2 else np.abs(sol[outs[0]])
        law = jf.mu * (jf.radius if isinstance(jf.joint, Revolute) else 1.0) * size
        np.testing.assert_allclose(np.abs(f)[ok], law[ok], rtol=1e-12, atol=1e-12 * (1 + law.max()),
                                   err_msg=jf.output)
    np.testing.assert_allclose(total[ok], P[ok], rtol=1e-10, atol=1e-10 * scale.max())


# -- c. the paths agree --------------------------------------------------------------------
@pytest.mark.parametrize("variant", VARIANTS, ids=IDS)
def test_paths_agree_and_match_the_mpmath_reference(variant):
    """Reference: the direct Newton (method="direct") and the mpmath reference
    (linkage_fmu.precise.reference, 40 digits). Tolerance: 1e-12 of the outputs' scale
    (the largest |output| of the same unit at the state). closed_form and interpreted,
    scalars and arrays, at 6 random states (3 against mpmath)."""
    name, base = variant
    rng = np.random.default_rng(1 + zlib.crc32(str(variant).encode()))
    mech = presets.get(name, **base, **_friction_params(name, rng, base))
    th, om, al, ld = _random_states(rng, 6)
    arrays = {m: mech.solve(th, om, al, ld, method=m) for m in ("closed_form", "direct")}
    units = mech.output_info
    checked = 0
    for i in range(th.size):
        state = (th[i], om[i], al[i], ld[i])
        try:
            ref = mech.solve(*state, method="direct")
        except SelfLockingError:
            assert arrays["closed_form"].status[i] == solver.LOCKED
            continue
        scale = {}
        for n in mech.output_names:
            u = units[n][0]
            scale[u] = max(scale.get(u, 0.0), abs(ref[n]))
        got = [mech.solve(*state, method=m) for m in ("closed_form", "interpreted")]
        got += [{n: a[n][i] for n in mech.output_names} for a in arrays.values()]
        if i < 3:
            got.append({n: float(v) for n, v in reference(mech, *state).items()})
        for g in got:
            for n in mech.output_names:
                tol = 1e-12 * max(scale[units[n][0]], 1e-9)
                if n == "eta":
                    tol = 1e-12
                assert abs(g[n] - ref[n]) <= tol, (i, n, g[n], ref[n])
        checked += 1
    assert checked >= 4


# -- d. the massless slider-crank by hand -----------------------------------------------------
L1, L2 = 0.18, 0.2
P_LOAD = 250.0


def _hand(theta, omega, mu, e=0.0, drive=1.0):
    """Rod force F (compression), crank torque, guide friction on the piston along +x.

    Piston: F cos(phi) - P + f = 0, F sin(phi) + N = 0 (N on the piston along y),
    f = -mu |N| s, s = sign of the piston's velocity (dxB/dtheta * omega, or * drive
    where omega = 0). Hence F = P / (cos(phi) - mu |sin(phi)| s). Crank: Mb = F l1
    sin(phi - theta), the moment about O balancing the rod's push -F u at A."""
    sphi = (e - L1 * math.sin(theta)) / L2
    cphi = math.sqrt(1.0 - sphi * sphi)
    phi = math.atan2(sphi, cphi)
    dxb = L1 * math.sin(phi - theta) / cphi
    s = math.copysign(1.0, dxb * (omega if omega != 0.0 else drive))
    F = P_LOAD / (cphi - mu * abs(sphi) * s)
    return F, F * L1 * math.sin(phi - theta), -mu * F * abs(sphi) * s, -F * sphi


def _massless(mu, **kw):
    return presets.get("slider_crank", m1=0.0, J1=0.0, m2=0.0, J2=0.0, m3=0.0, g=0.0,
                       l_OA=L1, l_AB=L2, mu_guide=mu, **kw)


@pytest.mark.parametrize("e", [0.0, 0.03])
def test_massless_slider_crank_by_hand(e):
    """Reference: the hand solution of _hand (two-force rod), checked first at mu = 0
    against the library. Tolerance: 1e-12 relative, Mb, |rod force|, N43 and Ff_guide,
    omega > 0, < 0 and 0 with drive +1 and -1, several angles."""
    for theta in (0.4, 1.3, 2.2, 3.5, 4.2, 5.6):
        for omega, drive in ((5.0, 1.0), (-5.0, 1.0), (0.0, 1.0), (0.0, -1.0)):
            for mu in (0.0, 0.2):
                mech = _massless(mu, e=e, drive=drive)
                s = mech.solve(theta, omega, 0.0, P_LOAD)
                F, Mb, f, N = _hand(theta, omega, mu, e, drive)
                assert s["Mb"] == pytest.approx(Mb, rel=1e-12, abs=1e-12 * abs(F))
                assert math.hypot(s["F32x"], s["F32y"]) == pytest.approx(abs(F), rel=1e-12)
                assert s["N43"] == pytest.approx(N, rel=1e-12, abs=1e-12 * abs(F))
                # t = (ny, -nx) = (1, 0) for gamma = 0: Ff_guide is the x-force on the piston
                assert s["Ff_guide"] == pytest.approx(f, rel=1e-12, abs=1e-12 * abs(F))


def test_massless_slider_crank_self_locks_where_the_denominator_vanishes():
    """Reference: cos(phi) - mu |sin(phi)| = 0 while the piston moves out against the
    load (theta in (pi, 3 pi / 2) for omega > 0, e = 0), found by bisection to 1e-14.
    Tolerance: SelfLockingError at theta* + 1e-7, a solution at theta* - 1e-7 (its rod
    force by hand to 1e-6 relative, the denominator being ~1e-7 there); arrays: status
    LOCKED past, SOLVED before."""
    mu = 0.6
    mech = _massless(mu)

    def g(theta):
        sphi = -L1 * math.sin(theta) / L2
        return math.sqrt(1.0 - sphi * sphi) - mu * abs(sphi)

    lo, hi = math.pi, 1.5 * math.pi
    assert g(lo) > 0 > g(hi)
    while hi - lo > 1e-14:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) > 0 else (lo, mid)
    star = 0.5 * (lo + hi)
    before = mech.solve(star - 1e-7, 5.0, 0.0, P_LOAD)
    F = _hand(star - 1e-7, 5.0, mu)[0]
    assert math.hypot(before["F32x"], before["F32y"]) == pytest.approx(F, rel=1e-6)
    with pytest.raises(SelfLockingError) as caught:
        mech.solve(star + 1e-7, 5.0, 0.0, P_LOAD)
    # the error names the angle and the pairs whose friction locks
    assert str(caught.value).startswith(
        f"slider_crank locks at theta = {star + 1e-7:.6g} rad ({math.degrees(star + 1e-7):.4g} "
        "deg): friction at A, B, guide locks the group of link 2"), str(caught.value)
    assert caught.value.reason.kind == "locking"
    # omega < 0: the piston moves in, the load drives it: no locking there
    mech.solve(star + 1e-7, -5.0, 0.0, P_LOAD)
    for method in ("closed_form", "interpreted", "direct"):
        arr = mech.solve(np.array([star - 1e-7, star + 1e-7, 0.5]), 5.0, 0.0, P_LOAD,
                         method=method)
        assert list(arr.status) == [solver.SOLVED, solver.LOCKED, solver.SOLVED], method
        assert list(arr.valid) == [True, False, True], method  # no outputs: not valid
        assert np.isnan(arr["Mb"][1]) and np.isfinite(arr["Mb"][0])
        (problem,) = arr.problems.values()
        assert (problem.first, problem.count) == (1, 1)
        assert problem.reason == caught.value.reason, method  # the FMUs' words
        assert problem.reason.text == ("friction locks the linkage: friction at A, B, guide "
                                       "locks the group of link 2")
    # a table has no outputs there, as where the linkage cannot be assembled; the
    # diagnostics of the position (which exists) stay
    table = mech.table([star - 1e-7, star + 1e-7], 5.0, 0.0, P_LOAD)
    assert table.iloc[1][list(mech.output_names)].isna().all()
    assert table.iloc[1][list(mech.diagnostic_names)].notna().all()
    assert table.iloc[0].notna().all()
    # and the one-state call the FMUs make says so in the same words
    assert mech.solver.attempt([star + 1e-7, 5.0, 0.0, P_LOAD]) == caught.value.reason


# -- e. an independent formulation: fsolve on the slider-crank's equations --------------------
SC = dict(l_OA=0.05, l_AB=0.2, e=0.015, m1=0.5, J1=1e-3, l_OS1=0.02, m2=0.8, J2=0.004,
          l_AS2=0.06, m3=0.6, g=9.81)
MU = dict(mu_O=0.12, r_O=0.01, mu_A=0.2, r_A=0.008, mu_B=0.15, r_B=0.006, mu_guide=0.1)


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _fsolve_slider_crank(theta, omega, alpha, P, mu=MU):
    """Equilibrium of the slider-crank (gamma = 0) written from scratch: unknowns R_O
    (frame on crank), R_A (crank on rod), R_B (rod on piston), N (guide on piston along
    y), M (guide couple on piston), Mb. Pin friction on body b: -mu r |R| sgn(w_b - w_a);
    guide friction on the piston along x: -mu |N| sgn(vB)."""
    p = SC
    l1, l2, e, g = p["l_OA"], p["l_AB"], p["e"], p["g"]
    sphi = (e - l1 * math.sin(theta)) / l2
    cphi = math.sqrt(1 - sphi * sphi)
    phid = -l1 * math.cos(theta) * omega / (l2 * cphi)
    phidd = (l1 * (math.sin(theta) * omega ** 2 - math.cos(theta) * alpha)
             + l2 * sphi * phid ** 2) / (l2 * cphi)
    et = np.array([math.cos(theta), math.sin(theta)])
    en = np.array([-math.sin(theta), math.cos(theta)])
    ep, epn = np.array([cphi, sphi]), np.array([-sphi, cphi])
    A = l1 * et
    S1 = p["l_OS1"] * et
    S2 = A + p["l_AS2"] * ep
    B = A + l2 * ep
    aS1 = p["l_OS1"] * (alpha * en - omega ** 2 * et)
    aA = l1 * (alpha * en - omega ** 2 * et)
    aS2 = aA + p["l_AS2"] * (phidd * epn - phid ** 2 * ep)
    aB = aA + l2 * (phidd * epn - phid ** 2 * ep)
    vB = (l1 * omega * en + l2 * phid * epn)[0]
    grav = np.array([0.0, -g])
    sg = np.sign

    def eqs(x):
        RO, RA, RB = x[0:2], x[2:4], x[4:6]
        N, M, Mb = x[6], x[7], x[8]
        fO = -mu["mu_O"] * mu["r_O"] * np.hypot(*RO) * sg(omega)           # on crank
        fA = -mu["mu_A"] * mu["r_A"] * np.hypot(*RA) * sg(phid - omega)    # on rod
        fB = -mu["mu_B"] * mu["r_B"] * np.hypot(*RB) * sg(0.0 - phid)      # on piston
        fg = -mu["mu_guide"] * abs(N) * sg(vB)                             # on piston, x
        r1 = RO - RA + p["m1"] * (grav - aS1)
        m1 = (_cross(-S1, RO) + _cross(A - S1, -RA) + Mb + fO - fA - p["J1"] * alpha)
        r2 = RA - RB + p["m2"] * (grav - aS2)
        m2 = _cross(A - S2, RA) + _cross(B - S2, -RB) + fA - fB - p["J2"] * phidd
        r3 = RB + np.array([fg, N]) + p["m3"] * (grav - aB) + np.array([-P, 0.0])
        m3 = fB + M
        return np.array([*r1, m1, *r2, m2, *r3, m3])

    x0 = fsolve(eqs, np.ones(9), xtol=1e-14, full_output=True)[0]  # residual checked below
    x = fsolve(eqs, x0, xtol=1e-14, full_output=True)[0]
    assert np.max(np.abs(eqs(x))) < 1e-9 * (1 + np.max(np.abs(x)))
    return x, dict(Mf_O=-mu["mu_O"] * mu["r_O"] * np.hypot(*x[0:2]) * sg(omega),
                   Mf_A=-mu["mu_A"] * mu["r_A"] * np.hypot(*x[2:4]) * sg(phid - omega),
                   Mf_B=-mu["mu_B"] * mu["r_B"] * np.hypot(*x[4:6]) * sg(-phid),
                   Ff_guide=-mu["mu_guide"] * abs(x[6]) * sg(vB))


@pytest.mark.parametrize("state", [(0.5, 10.0, 3.0, 200.0), (2.0, -8.0, 40.0, -150.0),
                                   (3.9, 15.0, -20.0, 80.0), (5.5, -3.0, 0.0, 300.0)])
def test_slider_crank_against_an_independent_fsolve_formulation(state):
    """Reference: _fsolve_slider_crank (scipy fsolve, xtol 1e-14) on equations written
    here, with masses, inertia, gravity, pin friction at O, A, B and guide friction.
    Tolerance: 1e-10 relative to the largest force (moments: times l_AB)."""
    mech = presets.get("slider_crank", **SC, **MU)
    s = mech.solve(*state)
    x, fr = _fsolve_slider_crank(*state)
    F = float(np.max(np.abs(x[:7])))
    tol = 1e-10 * F
    assert s["Mb"] == pytest.approx(x[8], abs=tol * SC["l_AB"])
    assert math.hypot(s["F14x"], s["F14y"]) == pytest.approx(math.hypot(*x[0:2]), abs=tol)
    assert math.hypot(s["F21x"], s["F21y"]) == pytest.approx(math.hypot(*x[2:4]), abs=tol)
    # F32 is the force of the piston on the rod: -R_B
    assert (s["F32x"], s["F32y"]) == pytest.approx((-x[4], -x[5]), abs=tol)
    assert s["N43"] == pytest.approx(x[6], abs=tol)
    for n, v in fr.items():
        assert s[n] == pytest.approx(v, abs=tol * (SC["l_AB"] if n.startswith("Mf") else 1))


# -- f. the description's checks ---------------------------------------------------------------
@pytest.mark.parametrize("table, spec, message", [
    ("X", {"mu": "mu_O", "radius": "r_O"}, r"\[friction\.X\].*no pair"),
    ("O", {"mu": "mu_O"}, r"\[friction\.O\] radius: missing"),
    ("guide", {"mu": "mu_guide", "radius": "r_O"}, r"\[friction\.guide\] radius"),
    ("O", {"mu": "mu_O", "radius": "r_O", "grip": 1.0}, r"\[friction\.O\].*unknown key.*grip"),
])
def test_bad_friction_tables_are_description_errors(table, spec, message):
    """Reference: the format's rules (docs/description.md). Tolerance: the error names
    the table."""
    d = presets.preset("slider_crank").copy()
    d.friction[table] = spec
    text = d.to_toml()  # read back: the text's tables are checked
    with pytest.raises(DescriptionError, match=message):
        Description.from_toml(text).build()


def test_bad_friction_values_are_refused():
    """Reference: parameter kinds friction (>= 0) and sign (+1 or -1). Tolerance: a
    ValueError naming the parameter."""
    with pytest.raises(ValueError, match="mu_A"):
        presets.get("slider_crank", mu_A=-0.1)
    with pytest.raises(ValueError, match="drive"):
        presets.get("slider_crank", drive=0.5)
    with pytest.raises(ValueError, match="r_A"):
        presets.get("slider_crank", r_A=-0.01)


@pytest.mark.parametrize("name", ["scotch_yoke", "slider_crank", "four_bar", "slotted_lever",
                                  "crank_shaper"])
def test_every_method_agrees_up_to_the_largest_coefficient_taken(name):
    """Reference: the direct method (Newton on the whole system). With mu = 1e308 the
    methods disagreed: ScotchYoke's guide, whose normal force is 0 up to rounding, locked
    in the closed form and not in the direct method (mu times rounding decides); and the
    direct method locked the slotted lever at mu_slot = 1e5 where the closed form solves
    it. A coefficient above parameters.MU_MAX (1000) is refused, naming it; at MU_MAX,
    each coefficient alone, every method gives the same answer at 5 angles: the same
    error, or the balancing effort within 1e-11 relative."""
    from linkage_fmu.parameters import MU_MAX

    mus = sorted(presets.preset(name).friction_parameters(("mu",)))
    with pytest.raises(ValueError, match=rf"{mus[0]} must be <= 1000.0 .*got 1e\+308"):
        presets.get(name, **{mus[0]: 1e308})
    for mu in mus:
        mech = presets.get(name, **{mu: MU_MAX})
        for theta in (0.3, 1.1, 2.3, 4.0, 5.5):
            answers = {}
            for method in solver.METHODS:
                try:
                    answers[method] = mech.solve(theta, 10.0, method=method)[mech.effort.name]
                except ValueError as err:
                    answers[method] = type(err).__name__
            direct = answers["direct"]
            for answer in answers.values():
                if isinstance(direct, str):
                    assert answer == direct, (mu, theta, answers)
                else:
                    assert answer == pytest.approx(direct, rel=1e-11), (mu, theta, answers)


@pytest.mark.parametrize("variant", [v for v in VARIANTS
                                     if not presets.get(v[0], **v[1]).effort_on_crank],
                         ids=[i for v, i in zip(VARIANTS, IDS)
                              if not presets.get(v[0], **v[1]).effort_on_crank])
def test_an_effort_off_the_crank_continues_the_frictionless_solution(variant):
    """Reference: the direct Newton on the whole system from the frictionless solution
    (which follows the solution continuously from mu = 0: checked by hand at the states
    where a fixed-point first step on the effort jumped to another root). Tolerance:
    1e-11 of the effort's magnitude (at least 1); the same states lock. 1000 states over
    5 random friction draws, arrays."""
    name, base = variant
    for draw in range(5):
        rng = np.random.default_rng(100 + draw)
        mech = presets.get(name, **base, **_friction_params(name, rng, base))
        state = _random_states(rng, 200)
        a, b = (mech.solve(*state, method=m) for m in ("closed_form", "direct"))
        np.testing.assert_array_equal(a.status == solver.LOCKED, b.status == solver.LOCKED)
        e = mech.effort.name
        ok = b.status != solver.LOCKED
        assert ok.sum() > 150
        np.testing.assert_allclose(a[e][ok], b[e][ok], rtol=0,
                                   atol=1e-11 * np.maximum(np.abs(b[e][ok]), 1.0).max())


# -- f. the efficiency: eta = 1 - P_loss / P_in -----------------------------------------------
def _rates(mech, th):
    """d/dtheta of every point's position and every moving link's angle at ``th``, by
    central differences of the positions computed in mpmath (40 digits, h = 1e-15:
    truncation ~h^2, rounding ~1e-40 / h, whatever the conditioning), and the positions
    and link directions at ``th`` (floats)."""
    h = mpmath.mpf("1e-15")
    st = mech.kinematics(th, 0)
    points = {p: (np.empty(th.size), np.empty(th.size)) for p in st.p}
    angles = {b.name: np.empty(th.size) for b in mech.bodies}
    with mpmath.workdps(40):
        for i, t in enumerate(th):
            lo, hi = (mech.kinematics(mpmath.mpf(float(t)) + k * h, 0, MP) for k in (-1, 1))
            for p, (dx, dy) in points.items():
                dx[i] = float((hi.p[p][0] - lo.p[p][0]) / (2 * h))
                dy[i] = float((hi.p[p][1] - lo.p[p][1]) / (2 * h))
            for b, dphi in angles.items():
                (c0, s0), (c1, s1) = lo.u[b], hi.u[b]
                dphi[i] = float(mpmath.atan2(c0 * s1 - s0 * c1, c0 * c1 + s0 * s1) / (2 * h))
    return points, angles, st


def _powers_in(mech, sol, th, om, al, ld):
    """Per source its power at each state, computed here from the solution's outputs
    and the positions: the effort's E q' omega, each load's F . v (or M phi' omega),
    gravity's -m g y_S' omega, with every q', v, y', phi' a central difference of the
    positions in mpmath (_rates); the inertia's -dT/dt = -(J_red omega alpha + dJ_red
    omega^3 / 2), T = J_red omega^2 / 2 from the solution's J_red and dJ_red."""
    points, angles, st = _rates(mech, th)
    e = mech.effort
    if e.direction is None:
        q1 = angles[e.body]
    else:
        q1 = e.direction[0] * points[e.point][0] + e.direction[1] * points[e.point][1]
    out = [sol[e.name] * q1 * om,
           -(sol["J_red"] * om * al + 0.5 * sol["dJ_red"] * om ** 3),
           sum(-b.mass * mech.g * points[b.cg][1] for b in mech.bodies) * om]
    assert not mech.computed_loads
    for load, value in zip(mech.loads, [ld]):
        if load.kind == "moment":
            out.append(value * angles[load.body] * om)
            continue
        ux, uy = load.direction
        if load.fixed_in == "link":
            c, s = st.u[load.body]
            ux, uy = c * ux - s * uy, s * ux + c * uy
        vx, vy = points[load.at]
        out.append(value * om * (ux * vx + uy * vy))
    return out


def _reversed_run(variant, seed: int, n: int):
    """The ``variant`` with random friction (seeded by ``seed`` and the variant), ``n``
    :func:`_reversed_states` and their solution."""
    name, base = variant
    rng = np.random.default_rng(seed + zlib.crc32(str(variant).encode()))
    mech = presets.get(name, **base, **_friction_params(name, rng, base))
    states = _reversed_states(rng, n)
    return mech, states, mech.solve(*states)


def _reversed_states(rng, n):
    """Random states where power flows every way: the load driving or resisting (either
    sign, up to large), the crank turning either way, accelerating or decelerating."""
    th = rng.uniform(0.0, 2 * math.pi, n)
    om = rng.choice([-1.0, 1.0], n) * rng.uniform(0.5, 30.0, n)
    al = -np.sign(om) * rng.uniform(0.0, 400.0, n)  # decelerating
    al[: n // 3] *= -1.0  # and accelerating
    ld = rng.uniform(-500.0, 500.0, n)
    return th, om, al, ld


@pytest.mark.parametrize("variant", VARIANTS, ids=IDS)
def test_eta_is_one_minus_the_loss_over_the_power_that_enters(variant):
    """Reference: P_in = sum of max(0, P_i) over the sources' powers P_i computed here
    (_powers_in: the effort, the load, gravity from central differences of the
    positions, -dT/dt from J_red and dJ_red), eta_ref = 1 - P_loss / P_in. 300
    seeded random states with reversed power (loads driving, negative omega,
    decelerating), random mu and radii, arrays and one scalar path. Tolerance: every
    finite eta in [0, 1] exactly; |eta - eta_ref| <= 1e-10, and P_loss / (1 - eta) =
    P_in to 1e-10 relative where the loss is > 1e-3 of P_in; the power balance sum P_i
    = P_loss to 1e-9 of the largest |P_i|; P_in > 0 and eta finite at these states."""
    mech, (th, om, al, ld), sol = _reversed_run(variant, 7, 300)
    ok = sol.valid
    assert ok.sum() >= 200
    eta, loss = sol["eta"][ok], sol["P_loss"][ok]
    assert np.all((eta >= 0.0) & (eta <= 1.0)), eta[~((eta >= 0.0) & (eta <= 1.0))]
    powers = [p[ok] for p in _powers_in(mech, sol, th, om, al, ld)]
    size = np.max(np.abs(powers), axis=0)
    np.testing.assert_array_less(np.abs(np.sum(powers, axis=0) - loss), 1e-9 * size + 1e-300)
    p_in = np.sum([np.maximum(p, 0.0) for p in powers], axis=0)
    assert np.all(p_in > 0.0)
    assert np.all(np.isfinite(eta))
    np.testing.assert_allclose(eta, 1.0 - loss / p_in, rtol=0, atol=1e-10)
    lossy = loss > 1e-3 * p_in
    assert lossy.sum() >= 20
    np.testing.assert_allclose(loss[lossy] / (1.0 - eta[lossy]), p_in[lossy], rtol=1e-10)
    assert (eta < 1.0 - 1e-3).sum() >= 20  # reversed power: real losses
    i = int(np.flatnonzero(ok)[0])
    one = mech.solve(th[i], om[i], al[i], ld[i])  # the one-state kernel
    assert one["eta"] == pytest.approx(sol["eta"][i], abs=1e-12)


@pytest.mark.parametrize("name", NAMES)
def test_eta_is_one_without_friction_and_nan_where_no_power_enters(name):
    """Reference: P_loss = 0 exactly where every mu is 0 (declared, or active with mu
    0), so eta = 1 exactly where P_in > 0 (_powers_in); a static scene with no load and
    no gravity has no power at all: NaN, and the state is still solved. Tolerance:
    exact."""
    rng = np.random.default_rng(3)
    th, om, al, ld = _reversed_states(rng, 50)
    for mech in (presets.get(name), presets.preset(name).fmu_build()):
        sol = mech.solve(th, om, al, ld)
        ok = sol.valid
        p_in = np.sum([np.maximum(p, 0.0) for p in _powers_in(mech, sol, th, om, al, ld)],
                      axis=0)
        assert np.all(sol["eta"][ok & (p_in > 0.0)] == 1.0)
        assert (ok & (p_in > 0.0)).sum() >= 40
    still = presets.get(name, g=0.0) if "g" in presets.get(name).parameters else presets.get(name)
    if still.g == 0.0:
        s = still.solve(1.0, 0.0, 0.0, 0.0)
        assert math.isnan(s["eta"]) and math.isfinite(s["P_loss"])
        a = still.solve(np.array([1.0, 2.0]), 0.0, 0.0, 0.0)
        assert a.valid.all() and np.isnan(a["eta"]).all()
        assert list(a.status) == [solver.SOLVED, solver.SOLVED]


@pytest.mark.parametrize("variant", VARIANTS[:8], ids=IDS[:8])
def test_eta_at_rest_is_the_limit_as_the_crank_starts(variant):
    """Reference: eta at omega = 1e-9 (drive +1) and -1e-9 (drive -1), alpha = 0: the
    efficiency of the motion friction opposes at rest. Tolerance: 1e-10."""
    name, base = variant
    rng = np.random.default_rng(11)
    p = _friction_params(name, rng, base)
    th = rng.uniform(0.0, 2 * math.pi, 40)
    ld = rng.uniform(-300.0, 300.0, 40)
    for drive in (1.0, -1.0):
        mech = presets.get(name, **base, **p, drive=drive)
        rest, moving = mech.solve(th, 0.0, 0.0, ld), mech.solve(th, 1e-9 * drive, 0.0, ld)
        ok = rest.valid & moving.valid & np.isfinite(moving["eta"])
        assert ok.sum() >= 30
        np.testing.assert_allclose(rest["eta"][ok], moving["eta"][ok], rtol=0, atol=1e-10)


@pytest.mark.parametrize("variant", VARIANTS, ids=IDS)
def test_each_friction_value_is_the_action_its_description_names(variant):
    """Reference: the description of Mf_J / Ff_J names the pair's links a and b (its
    joint's, as declared) and says the value acts on b, opposing b's motion relative to
    a; the relative motion computed here (_relative_motion: w_b - w_a, or the sliding of
    b on a along t = (n_y, -n_x)) times omega has the opposite sign of the value, at
    every state where both are not 0. 40 random states, random mu and radii; exact
    signs."""
    mech, (th, om, al, ld), sol = _reversed_run(variant, 5, 40)
    ok = sol.valid
    st = mech.kinematics(th, 1)
    for jf in mech.friction.joints:
        j = jf.joint
        text = mech.output_info[jf.output][1]
        kind = ("friction moment in the pin" if isinstance(jf.joint, Revolute) else
                "friction force in the prismatic pair")
        assert text.startswith(f"{kind} {j.name} of link {j.a} on link {j.b}, "), text
        assert f"link {j.b} acts on link {j.a} with its opposite" in text
        motion = _relative_motion(mech, st, jf) * om
        f = sol[jf.output]
        both = ok & (f != 0.0) & (np.abs(motion) > 1e-12 * np.abs(om))
        assert both.sum() >= 10 or jf.mu == 0.0, jf.output
        assert np.all(np.sign(f[both]) == -np.sign(motion[both])), jf.output


# -- the kernels' loops ------------------------------------------------------------------------
def _refused_and_worst(mech, states):
    """Over ``states``: the states the one-state kernel (Solver.attempt) refuses where the
    direct solver solves, and its worst error relative to each output's largest
    magnitude at the state (per unit), against the direct solver."""
    solver_, units = mech.solver, mech.output_info
    refused, worst, solved = [], 0.0, 0
    for state in states:
        try:
            ref = mech.solve(*state, method="direct")
        except SelfLockingError:
            continue
        got = solver_.attempt(list(state))
        if type(got) is not tuple:
            refused.append(state)
            continue
        solved += 1
        scale = {}
        for n in mech.output_names:
            scale[units[n][0]] = max(scale.get(units[n][0], 0.0), abs(ref[n]))
        for n, v in zip(solver_.wanted(None), got):
            if n in mech.output_names and n != "eta":
                worst = max(worst, abs(v - ref[n]) / max(scale[units[n][0]], 1e-300))
    return refused, worst, solved


def test_the_six_bar_driven_at_KD_solves_every_state_the_direct_solver_does(monkeypatch):
    """Reference: the direct Newton on the whole system (method="direct"). Tolerance:
    1e-11 of the largest output of the same unit at the state. Over 300 random states
    with random friction, the compiled one-state kernel (whose iterations are loops)
    refuses none that the direct solver solves; a kernel stopped after ITERATIONS steps (what the
    unrolled kernels took) refuses some: the loops run beyond it there."""
    from linkage_fmu import friction

    rng = np.random.default_rng(29)
    params = _friction_params("six_bar", rng, {"driver": "KD"})
    params = {k: 2.0 * v for k, v in params.items()}  # mu up to 0.6, radii to 0.1 L
    th, om, al, ld = _random_states(rng, 300)
    states = list(zip(th, om, al, ld))
    mech = presets.get("six_bar", driver="KD", **params)
    if not mech.solver.kernel(None, False).compile():  # the C kernel, as native FMUs run it
        pytest.skip("no C compiler")
    refused, worst, solved = _refused_and_worst(mech, states)
    assert refused == [] and solved > 250 and worst <= 1e-11, (refused[:3], worst)
    monkeypatch.setattr(friction, "MAX_ITERATIONS", friction.ITERATIONS)
    short = presets.get("six_bar", driver="KD", **params)
    assert len(_refused_and_worst(short, states)[0]) > 0


def test_a_kernel_traced_without_friction_solves_with_large_friction():
    """Reference: the direct solver. Tolerance: 1e-11 of the largest output of the same
    unit at the state. The slider-crank's kernel with friction traced at its defaults
    (every mu 0, as a native FMU built with them traces it) run with mu 0.6 on every
    pair and 0.1 m pins (its parameters are the kernel's arguments): it solves every
    state the direct solver solves (150 random states), the signs of motion and the
    friction law decided at run time."""
    rng = np.random.default_rng(78)
    mech = presets.preset("slider_crank").fmu_build()
    kernel = mech.solver.kernel(None, False)
    big = {"mu_O": 0.6, "r_O": 0.1, "mu_A": 0.6, "r_A": 0.1, "mu_B": 0.6, "r_B": 0.1,
           "mu_guide": 0.6}
    rubbing = presets.get("slider_crank", **big)
    frozen = kernel.prepare(*(rubbing.parameters[n] for n in kernel.parameters))
    run = kernel.make(*frozen)
    th, om, al, ld = _random_states(rng, 150)
    solved = 0
    for state in zip(th, om, al, ld):
        try:
            ref = rubbing.solve(*state, method="direct")
        except SelfLockingError:
            continue
        got = run(*state)
        assert type(got) is tuple, (state, kernel.reasons[got - 1].text)
        scale = max(abs(ref[n]) for n in rubbing.output_names if n.startswith("F"))
        for n, v in zip(kernel.outputs, got):
            if n.startswith(("F", "M", "P_")):
                assert abs(v - ref[n]) <= 1e-11 * scale, (state, n, v, ref[n])
        solved += 1
    assert solved > 100
