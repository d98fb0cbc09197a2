"""Mechanism.simulate: the motion of a linkage under a given crank torque (Eksergian's
equation, alpha = (tau - Mb(theta, omega, 0, loads)) / J(theta)), against conservation of
energy, the closed-form first integral of a scotch yoke, and the kinetostatic solve run
along the motion.

The integrator's tolerance is rtol = 1e-10 (the default) unless a test says otherwise; an
error of the integrated state of some 1e-10 relative per unit of time is its size, so the
tests allow 1e-8 (energy) or 1e-9 (first integrals at rtol = 1e-11), each with the figure
measured.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import IDS as VARIANT_IDS
from conftest import VARIANTS
from linkage_fmu import AssemblyError, SelfLockingError, presets

#: linkages that turn fully, their effort a moment on the crank (the six-bar's other
#: drivers put the effort on another link, which simulate refuses)
FULL = [
    ("four_bar", {}),
    ("slider_crank", {"e": 0.02, "gamma": 0.7, "m1": 0.5, "J1": 1e-3, "l_OS1": 0.02}),
    ("slotted_lever", {"l_AB": 0.55, "l_AC": 0.25, "l_CS3": -0.1}),
    ("crank_shaper", {}),
    ("six_bar", {"driver": "OA"}),
]
T = np.linspace(0.0, 1.0, 21)


def unloaded(name: str, **params):
    """The preset with no gravity, and the loads (over the cycle too) all zero."""
    mech = presets.get(name, **{**params, "g": 0.0})
    return mech, {ld.name: 0.0 for ld in mech.loads}


def potential(mech, theta):
    """V = sum m_i g y_Si, from the positions of the centres of mass."""
    st = mech.kinematics(np.asarray(theta, dtype=float), order=0)
    return sum(b.mass * mech.g * st.p[b.cg][1] for b in mech.bodies if b.mass)


@pytest.mark.parametrize("name,params", FULL)
def test_work_of_a_constant_torque_is_the_kinetic_energy_gained(name, params):
    mech, zero = unloaded(name, **params)
    run = mech.simulate(2.0, T, theta0=0.3, omega0=5.0, **zero)
    work = 2.0 * (run["theta"].iloc[-1] - run["theta"].iloc[0])
    kinetic = 0.5 * run["J_red"] * run["omega"] ** 2
    gained = kinetic - kinetic.iloc[0]
    # at every output time, against the work done up to it; measured <= 1.5e-9 (slider-crank
    # at 470 rad/s)
    done = 2.0 * (run["theta"] - run["theta"].iloc[0])
    assert np.max(np.abs(gained - done)) <= 1e-8 * work
    assert run["theta"].iloc[-1] > 0.3 + math.pi  # it turned half a revolution at least
    assert run["J_red"].iloc[0] == mech.reduced_inertia(0.3)[0]


@pytest.mark.parametrize("name,params", [("four_bar", {}),
                                         ("scotch_yoke", {"m1": 1.5, "J3": 0.2, "g": 9.81})])
def test_kinetic_plus_potential_energy_is_conserved_under_gravity(name, params):
    mech = presets.get(name, **params)
    assert mech.g == 9.81
    run = mech.simulate(0.0, T, theta0=0.3, omega0=10.0, load=0.0)
    V = potential(mech, run["theta"].to_numpy())
    E = 0.5 * run["J_red"].to_numpy() * run["omega"].to_numpy() ** 2 + V
    assert np.ptp(V) > 0.1 * E[0]  # gravity does work worth testing
    assert np.ptp(E) <= 1e-8 * E[0]  # measured 4.0e-10 (four-bar), 5.9e-10 (yoke)


@pytest.mark.parametrize("name,params", FULL)
def test_free_motion_keeps_J_omega_squared(name, params):
    mech, zero = unloaded(name, **params)
    run = mech.simulate(0.0, T, theta0=0.3, omega0=5.0, rtol=1e-11, **zero)
    K = run["J_red"] * run["omega"] ** 2
    assert np.ptp(K) <= 1e-9 * K.iloc[0]  # measured <= 1.4e-10 at rtol = 1e-11
    assert np.ptp(run["omega"]) > 0.05 * 5.0  # the speed does change


def test_scotch_yoke_with_the_yoke_alone_against_its_first_integral():
    """J = m r^2 cos^2(theta), so cos(theta) omega = C: sin(theta) = sin(theta0) + C t."""
    m, r = 10.0, 0.1
    yoke = presets.get("scotch_yoke", m2=0.0, m3=m, g=0.0)
    th0, w0 = 0.2, 1.5
    C = w0 * math.cos(th0)
    t = np.linspace(0.0, 0.5, 11)  # sin(theta) from 0.199 to 0.940: near the dead point
    run = yoke.simulate(0.0, t, theta0=th0, omega0=w0, load=0.0)
    theta = np.arcsin(math.sin(th0) + C * t)
    omega = C / np.cos(theta)
    np.testing.assert_allclose(run["J_red"], m * r**2 * np.cos(run["theta"]) ** 2, rtol=1e-14)
    np.testing.assert_allclose(run["theta"], theta, rtol=1e-9, atol=0)  # measured 1.9e-10
    np.testing.assert_allclose(run["omega"], omega, rtol=1e-9, atol=0)  # measured 8e-11
    # alpha = omega' = C sin(theta) omega / cos^2(theta)
    np.testing.assert_allclose(run["alpha"], C * np.sin(theta) * omega / np.cos(theta) ** 2,
                               rtol=1e-9)  # measured 3.7e-10
    # the first integral itself
    first = m * r**2 * np.cos(run["theta"]) ** 2 * run["omega"] ** 2
    assert np.ptp(first) <= 1e-9 * first.iloc[0]


def tau_of_state(t, theta, omega):
    return 3.0 + math.sin(5.0 * t) - 0.05 * omega


@pytest.mark.parametrize("tau", ["callable", "array", "constant"])
def test_Mb_along_the_motion_is_the_driving_torque(tau):
    mech = presets.get("four_bar")  # gravity, a moment on the rocker
    t = np.linspace(0.0, 2.0, 41)
    given = {"callable": tau_of_state, "array": 3.0 + np.sin(5.0 * t),
             "constant": -1.5}[tau]
    run = mech.simulate(given, t, theta0=1.0, omega0=8.0, load=0.4)
    if tau == "array":
        np.testing.assert_array_equal(run["tau"], given)
    expected = run["tau"].to_numpy()
    if tau == "callable":
        np.testing.assert_array_equal(expected, [tau_of_state(*s) for s in zip(
            t, run["theta"], run["omega"])])
    scale = np.max(np.abs(expected))
    # the solve inside simulate (its outputs in the frame), and the direct method again
    assert np.max(np.abs(run["Mb"] - expected)) <= 1e-9 * scale  # measured <= 5e-13
    direct = mech.solve(run["theta"].to_numpy(), run["omega"].to_numpy(),
                        run["alpha"].to_numpy(), load=0.4, method="direct")
    assert np.max(np.abs(direct["Mb"] - expected)) <= 1e-9 * scale  # measured <= 3e-13
    np.testing.assert_allclose(run["F21x"], direct["F21x"], rtol=1e-9, atol=1e-9 * scale)
    assert run.index.name == "time" and (run.index == t).all()
    assert {"theta", "omega", "alpha", "tau", "J_red", "cond"} <= set(run.columns)
    assert set(mech.output_names) <= set(run.columns)


@pytest.mark.parametrize("name,params", FULL[:2])
def test_a_flywheel_adds_its_inertia_to_the_linkage_s(name, params):
    """With a flywheel I on the crank the work of the torque is the kinetic energy gained
    by the linkage and the flywheel, (J_red + I) omega**2 / 2, and the linkage takes
    Mb = tau - I alpha from the crank; "0.05 kg*m**2" is 0.05."""
    mech, zero = unloaded(name, **params)
    run = mech.simulate(2.0, T, theta0=0.3, omega0=5.0, flywheel="0.05 kg*m**2", **zero)
    kinetic = 0.5 * (run["J_red"] + 0.05) * run["omega"] ** 2
    done = 2.0 * (run["theta"] - run["theta"].iloc[0])
    assert np.max(np.abs(kinetic - kinetic.iloc[0] - done)) <= 1e-8 * done.iloc[-1]
    np.testing.assert_allclose(run["Mb"], 2.0 - 0.05 * run["alpha"], rtol=0, atol=1e-9)
    assert run["J_red"].iloc[0] == mech.reduced_inertia(0.3)[0]  # the linkage's own
    alone = mech.simulate(2.0, T, theta0=0.3, omega0=5.0, **zero)
    assert run["theta"].iloc[-1] < alone["theta"].iloc[-1]  # the flywheel slows the run-up


def test_a_flywheel_drives_a_massless_linkage():
    """The scotch yoke with no mass has J_red = 0: the motion is not defined, unless a
    flywheel gives the crank an inertia: then alpha = tau / I."""
    yoke = presets.get("scotch_yoke", m2=0.0, m3=0.0)
    with pytest.raises(ValueError, match=r"reduced to the crank is 0\.0 at theta = 0\.0 rad; "):
        yoke.simulate(1.0, [0.0, 0.1], theta0=0.0, omega0=1.0, load=0.0)
    run = yoke.simulate(1.0, [0.0, 0.1], theta0=0.0, omega0=1.0, flywheel=0.5, load=0.0)
    np.testing.assert_allclose(run["alpha"], 2.0, rtol=1e-14)
    np.testing.assert_allclose(run["omega"].iloc[-1], 1.2, rtol=1e-12)


def test_the_array_torque_is_interpolated_linearly():
    """A torque ramp given at two times equals the ramp as a callable."""
    mech, zero = unloaded("four_bar")
    t = np.array([0.0, 0.5])
    ramp = mech.simulate([1.0, 3.0], t, theta0=0.0, omega0=2.0, **zero)
    exact = mech.simulate(lambda s, th, w: 1.0 + 4.0 * s, t, theta0=0.0, omega0=2.0, **zero)
    np.testing.assert_allclose(ramp[["theta", "omega"]], exact[["theta", "omega"]],
                               rtol=1e-12)


def test_start_values_default_to_the_linkage_s():
    mech, zero = unloaded("four_bar")  # start: omega 10, theta 0
    run = mech.simulate(0.0, [0.0, 0.01], **zero)
    assert run["theta"].iloc[0] == mech.start["theta"] == 0.0
    assert run["omega"].iloc[0] == mech.start["omega"] == 10.0
    units = mech.simulate(0.0, [0.0, 0.01], theta0="90 deg", omega0="60 rpm", **zero)
    assert units["theta"].iloc[0] == pytest.approx(math.pi / 2, rel=1e-15)
    assert units["omega"].iloc[0] == pytest.approx(2 * math.pi, rel=1e-15)


def test_a_position_that_cannot_be_assembled_is_an_error_naming_time_and_angle():
    rocker = presets.get("four_bar", l_AB=0.3)  # the crank cannot turn fully
    with pytest.raises(AssemblyError, match=r"four_bar cannot be assembled at theta = .*"
                                            r"\(reached at t = 0\.\d+ s\)"):
        rocker.simulate(50.0, np.linspace(0.0, 1.0, 5), theta0=0.0, omega0=0.0, load=0.0)


@pytest.mark.parametrize("kwargs,message", [
    ({"t": [0.0, 0.2, 0.1]}, r"t must be strictly increasing: t\[2\] = 0\.1 <= t\[1\] = 0\.2"),
    ({"t": [0.0, 0.0]}, r"t must be strictly increasing"),
    ({"t": [0.0]}, r"t must be a 1-d array of at least 2 times"),
    ({"t": [0.0, np.nan]}, r"t must be finite"),
    ({"tau": [1.0, 2.0]}, r"tau must be .* one value per time: 3 values .* got shape \(2,\)"),
    ({"tau": np.inf}, r"tau must be a finite number"),
    ({"theta0": np.nan}, r"theta0 must be a finite number, got nan"),
    ({"omega0": np.inf}, r"omega0 must be a finite number, got inf"),
    ({"theta0": "3 m"}, r"theta0"),
    ({"tau": lambda t, th, w: math.nan}, r"tau\(t, theta, omega\) must be a finite number"),
    ({"Mr": 1.0}, r"four_bar has no input 'Mr'"),
    ({"flywheel": -1.0}, r"flywheel must be >= 0 \(a moment of inertia, kg m2\), got -1\.0"),
    ({"flywheel": "2 m"}, r"flywheel = '2 m' must be a moment of inertia"),
    ({"flywheel": np.nan}, r"flywheel must be a finite number"),
])
def test_bad_inputs_are_named(kwargs, message):
    mech = presets.get("four_bar")
    args = {"tau": 1.0, "t": [0.0, 0.1, 0.2], **kwargs}
    with pytest.raises((ValueError, TypeError), match=message):
        mech.simulate(args.pop("tau"), args.pop("t"), **args)


def test_an_effort_off_the_crank_is_refused():
    mech = presets.get("six_bar", driver="KD")
    with pytest.raises(ValueError, match="does not act on the crank"):
        mech.simulate(1.0, [0.0, 0.1])


# -- friction ----------------------------------------------------------------------------------
#: Coulomb friction in every pair, nonzero pin radii: the slider-crank and the four-bar
FRICTION = [
    ("slider_crank", {"mu_O": 0.15, "mu_A": 0.15, "mu_B": 0.15, "mu_guide": 0.15,
                      "r_O": 0.01, "r_A": 0.01, "r_B": 0.008}, {"load": 20.0}),
    ("four_bar", {"mu_A": 0.15, "mu_B": 0.1, "mu_C": 0.1, "mu_D": 0.2, "r_A": 0.005,
                  "r_B": 0.004, "r_C": 0.004, "r_D": 0.005}, {"load": 0.5}),
]
IDS = [name for name, _, _ in FRICTION]


def reference_motion(mech, tau, t, theta0, omega0, flywheel=0.0, **loads):
    """The independent integration: scipy's DOP853 (rtol = atol = 1e-10) on the crank
    acceleration found by Brent's method on the DIRECT solver's Mb with friction, tau -
    flywheel alpha = Mb(theta, omega, alpha): no kernel, no tangent, no Newton of
    simulate's. For a motion in one direction (no stop)."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    def alpha(theta, omega):
        seen = {}

        def g(a):
            if a not in seen:
                seen[a] = tau - flywheel * a - mech.solve(
                    theta, omega, a, outputs=("Mb",), method="direct", **loads)["Mb"]
            return seen[a]

        guess = g(0.0) / (g(0.0) - g(1.0))  # the secant: Mb is nearly affine in alpha
        d = 1e-3 * (abs(guess) + 1.0)
        while g(guess - d) * g(guess + d) > 0.0:
            d *= 10.0
        return brentq(g, guess - d, guess + d, xtol=1e-14 * (abs(guess) + 1.0),
                      rtol=4.0 * np.finfo(float).eps)

    res = solve_ivp(lambda s, y: [y[1], alpha(float(y[0]), float(y[1]))], (t[0], t[-1]),
                    [theta0, omega0], method="DOP853", t_eval=t, rtol=1e-10, atol=1e-10)
    assert res.status == 0
    return res.y


@pytest.mark.parametrize("name,params,loads", FRICTION, ids=IDS)
def test_friction_motion_follows_an_integration_on_the_direct_solver(name, params, loads):
    mech = presets.get(name, **params)
    t = np.linspace(0.0, 0.1, 3)
    theta, omega = reference_motion(mech, 2.0, t, 0.3, 10.0, flywheel=0.01, **loads)
    run = mech.simulate(2.0, t, theta0=0.3, omega0=10.0, flywheel=0.01, **loads)
    assert theta[-1] - theta[0] > 1.0 and not run["stuck"].any()
    assert run.attrs["switches"] == []  # it moves all along
    # measured 2.4e-11 rad (slider-crank) and 1.5e-14 rad (four-bar)
    np.testing.assert_allclose(run["theta"], theta, rtol=0, atol=1e-6)
    np.testing.assert_allclose(run["omega"], omega, rtol=0, atol=1e-6 * np.abs(omega).max())
    # the linkage takes tau - flywheel alpha: by the direct solver, at the rows' states
    direct = mech.solve(run["theta"].to_numpy(), run["omega"].to_numpy(),
                        run["alpha"].to_numpy(), method="direct", **loads)
    np.testing.assert_allclose(direct["Mb"], 2.0 - 0.01 * run["alpha"], rtol=0,
                               atol=1e-12)  # measured 2.2e-16
    frictionless = presets.get(name).simulate(2.0, t, theta0=0.3, omega0=10.0, flywheel=0.01,
                                              **loads)
    assert run["theta"].iloc[-1] < frictionless["theta"].iloc[-1] - 1e-3  # friction brakes


@pytest.mark.parametrize("name,params,loads", FRICTION, ids=IDS)
def test_friction_motion_balances_work_losses_and_kinetic_energy(name, params, loads):
    """work of tau - integral of P_loss - work against the loads and gravity = change of
    (J_red + flywheel) omega**2 / 2. The work against the loads and weights is the
    integral over theta of the static balancing moment WITHOUT friction (the preset with
    every mu 0), by scipy's quad; P_loss is integrated over 8001 output times by
    Simpson's rule."""
    from scipy.integrate import quad, simpson

    mech = presets.get(name, **params)
    plain = presets.get(name, **{k: v for k, v in params.items() if not k.startswith("mu")})
    assert not plain.friction.active and mech.friction.active
    t = np.linspace(0.0, 0.2, 8001)
    run = mech.simulate(2.0, t, theta0=0.3, omega0=10.0, flywheel=0.01, **loads)
    th = run["theta"].to_numpy()
    assert (run["omega"] > 0.0).all()
    work = 2.0 * (th[-1] - th[0])
    lost = simpson(run["P_loss"].to_numpy(), x=t)
    against, _ = quad(lambda x: plain.solve(x, 0.0, 0.0, outputs=("Mb",), **loads)["Mb"],
                      th[0], th[-1], limit=400, epsabs=1e-13, epsrel=1e-13)
    kinetic = 0.5 * (run["J_red"].to_numpy() + 0.01) * run["omega"].to_numpy() ** 2
    assert lost > 0.02 * work  # the friction takes a share worth testing
    # measured 1.4e-7 (slider-crank; 2.4e-8 over 32001 times: Simpson's error at the kinks
    # of P_loss, where a pair's relative motion reverses) and 1.8e-9 (four-bar)
    assert abs(work - lost - against - (kinetic[-1] - kinetic[0])) <= 1e-6 * work


def band(name, params, theta, **loads):
    """The friction band at rest by the DIRECT solver: the static Mb with drive -1 and +1."""
    return tuple(presets.get(name, **params, drive=d).solve(
        theta, 0.0, 0.0, outputs=("Mb",), method="direct", **loads)["Mb"] for d in (-1.0, 1.0))


@pytest.mark.parametrize("name,params,loads", FRICTION, ids=IDS)
def test_a_torque_within_the_band_holds_the_crank(name, params, loads):
    mech = presets.get(name, **params)
    lo, hi = band(name, params, 1.0, **loads)
    assert hi - lo > 1e-3 * max(abs(lo), abs(hi))  # a band worth testing
    for tau in (lo + 0.01 * (hi - lo), 0.5 * (lo + hi), hi - 0.01 * (hi - lo)):
        run = mech.simulate(tau, np.linspace(0.0, 0.5, 6), theta0=1.0, omega0=0.0, **loads)
        assert np.max(np.abs(run["theta"] - 1.0)) <= 1e-9  # measured: exactly 0
        assert (run["omega"] == 0.0).all() and (run["alpha"] == 0.0).all()
        assert run["stuck"].all() and run.attrs["switches"] == [(0.0, 1.0, 0)]
        assert (run["Mb"] == tau).all() and (run["P_loss"] == 0.0).all()
        if tau != 0.5 * (lo + hi):  # (the middle itself: either side, to rounding)
            # the holding friction is not determined: the reactions are those at the
            # band's edge on tau's side of its middle, by the DIRECT solver
            edge = presets.get(name, **params, drive=1.0 if tau > 0.5 * (lo + hi) else -1.0)
            ref = edge.solve(1.0, 0.0, 0.0, method="direct", **loads)["F21x"]
            assert np.allclose(run["F21x"], ref, rtol=1e-12, atol=0.0)
    for tau, way in ((hi + 0.01 * (hi - lo), 1), (lo - 0.01 * (hi - lo), -1)):
        run = mech.simulate(tau, np.linspace(0.0, 0.05, 3), theta0=1.0, omega0=0.0, **loads)
        assert run.attrs["switches"][0] == (0.0, 1.0, way)
        assert way * (run["theta"].iloc[-1] - 1.0) > 0.0 and not run["stuck"].any()


@pytest.mark.parametrize("name,params,loads", FRICTION, ids=IDS)
@pytest.mark.parametrize("way", [1, -1])
def test_a_torque_ramp_breaks_away_where_it_crosses_the_band_s_edge(name, params, loads, way):
    """tau = mid + 1.3 way (hi - lo) t from rest at 1 rad: the crank holds until the ramp
    crosses the edge (Brent's method on tau(t) - edge, the edge by the direct solver),
    then moves that way."""
    from scipy.optimize import brentq

    mech = presets.get(name, **params)
    lo, hi = band(name, params, 1.0, **loads)
    mid, rate = 0.5 * (lo + hi), 1.3 * way * (hi - lo)  # crossing at 0.385 s
    edge = hi if way > 0 else lo

    def tau(s, theta, omega):
        return mid + rate * s

    crossing = brentq(lambda s: tau(s, 1.0, 0.0) - edge, 0.0, 1.0, xtol=1e-15, rtol=1e-15)
    t = np.linspace(0.0, 0.8, 17)
    run = mech.simulate(tau, t, theta0=1.0, omega0=0.0, **loads)
    start, breakaway = run.attrs["switches"][:2]
    assert start == (0.0, 1.0, 0) and breakaway.to == way and breakaway.theta == 1.0
    assert abs(breakaway.time - crossing) <= 1e-12  # measured <= 2.2e-15 s
    held = t <= crossing
    assert (run["theta"][held] == 1.0).all() and run["stuck"][held].all()
    assert (way * (run["theta"][~held] - 1.0) > 0.0).all() and not run["stuck"][~held].any()


def test_a_coasting_crank_stops_and_stays_where_the_band_holds_it():
    """The slider-crank coasting (tau = 0) against a constant load on its slider swings
    about dead centre, stops at each swing's end (omega = 0 there, to the integrator's
    tolerance), reverses while the load's moment exceeds the band, and at last sticks:
    from then on theta stays, and tau = 0 lies within the band there (the direct
    solver's)."""
    name, params, _ = FRICTION[0]
    params = {**params, "g": 0.0}
    mech = presets.get(name, **params)
    t = np.linspace(0.0, 3.5, 36)
    run = mech.simulate(0.0, t, theta0=0.3, omega0=10.0, load=5.0)
    switches = run.attrs["switches"]
    assert [s.to for s in switches[-3:]] == [-1, 1, 0]  # reverses, reverses, sticks
    last = switches[-1]
    held = t >= last.time
    assert held.sum() >= 5 and run["stuck"][held].all() and not run["stuck"][~held].any()
    assert (run["theta"][held] == last.theta).all() and (run["omega"][held] == 0.0).all()
    lo, hi = band(name, params, last.theta, load=5.0)
    assert lo <= 0.0 <= hi
    for s in switches[:-1]:  # each reversal: the band did not hold it there
        lo, hi = band(name, params, s.theta, load=5.0)
        assert (0.0 > hi) if s.to > 0 else (0.0 < lo)
    # the stops are where omega passes 0: a run to just past the first one
    first = switches[0]
    stop = mech.simulate(0.0, [0.0, first.time], theta0=0.3, omega0=10.0, load=5.0)
    assert abs(stop["omega"].iloc[-1]) <= 1e-8 * 10.0
    assert stop["theta"].iloc[-1] == pytest.approx(first.theta, abs=1e-9)


def test_friction_that_locks_the_motion_is_an_error_naming_time_and_angle():
    mech = presets.get("slider_crank", mu_guide=5.0)
    with pytest.raises(SelfLockingError, match=r"slider_crank locks at theta = 1\.2 rad "
                                                r"\(68\.75 deg\): .*\(reached at t = 0 s\)"):
        mech.simulate(0.0, [0.0, 0.1], theta0=1.2, omega0=10.0, load=-50.0)


def test_moment_and_slope_is_the_kernel_s_Mb_and_a_derivative_by_alpha():
    """The slope against a central difference of the direct solver's Mb (h = 1e-4:
    Mb is smooth in alpha away from a reaction's zero, so 1e-7 relative holds)."""
    from linkage_fmu.motion import moment_and_slope

    name, params, loads = FRICTION[0]
    mech = presets.get(name, **params)
    f = moment_and_slope(mech, **loads)
    for theta, omega, alpha in [(0.7, 12.0, 3.0), (2.9, -4.0, 0.0), (4.4, 0.0, 50.0)]:
        Mb, slope = f(theta, omega, alpha)

        def direct(a, theta=theta, omega=omega):
            return mech.solve(theta, omega, a, outputs=("Mb",), method="direct", **loads)["Mb"]

        assert Mb == pytest.approx(direct(alpha), rel=1e-12, abs=1e-13)
        h = 1e-4
        assert slope == pytest.approx((direct(alpha + h) - direct(alpha - h)) / (2 * h),
                                      rel=1e-7)


def test_without_a_compiler_the_slope_is_the_tangent_and_the_motion_the_same(monkeypatch,
                                                                           tmp_path):
    """No C compiler: moment_and_slope gives solve's Mb and the slope of the Python
    forward mode, the compiled tangent's floats, and the motion is the one with the
    compiled tangent (the same floats of Mb and slope: the same Newton steps)."""
    import warnings

    from linkage_fmu.kernels import compiled
    from linkage_fmu.motion import moment_and_slope

    name, params, loads = FRICTION[0]
    t = np.linspace(0.0, 0.05, 3)
    mech = presets.get(name, **params)
    with_tangent = mech.simulate(2.0, t, theta0=0.3, omega0=10.0, **loads)
    exact = moment_and_slope(mech, **loads)(0.7, 12.0, 3.0)
    monkeypatch.setenv("CC", "no-such-compiler")
    monkeypatch.setenv("LINKAGE_FMU_CACHE", str(tmp_path))
    compiled._no_compiler_warning.cache_clear()
    mech = presets.get(name, **params)  # no kernel made yet
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # "no C compiler found"
        Mb, slope = moment_and_slope(mech, **loads)(0.7, 12.0, 3.0)
        run = mech.simulate(2.0, t, theta0=0.3, omega0=10.0, **loads)
    assert Mb == mech.solve(0.7, 12.0, 3.0, outputs=("Mb",), **loads)["Mb"]
    assert (Mb, slope) == exact
    np.testing.assert_array_equal(run["theta"], with_tangent["theta"])
    assert not list(tmp_path.iterdir())  # nothing compiled


def test_friction_energy_balance_through_stops_reversals_and_sticking():
    """The coasting slider-crank of the test above, through its 8 reversals and its
    sticking: -integral of P_loss - the work against the load = the change of kinetic
    energy, to 1e-6 of the energy dissipated (measured 1.8e-8). P_loss has kinks at the
    stops, so it is integrated by Simpson's rule between them: a first run (output
    times 0 and 3.5 s only: most segments hold no output time) gives the switch times,
    a second one on 2001 times between each two of them gives the same switches (the
    output times do not steer the integrator)."""
    from scipy.integrate import quad, simpson

    name, params, _ = FRICTION[0]
    params = {**params, "g": 0.0}
    mech = presets.get(name, **params)
    plain = presets.get(name, **{k: v for k, v in params.items() if not k.startswith("mu")})
    first = mech.simulate(0.0, [0.0, 3.5], theta0=0.3, omega0=10.0, load=5.0)
    switches = first.attrs["switches"]
    assert len(switches) >= 5 and switches[-1].to == 0 and first["stuck"].iloc[-1]
    cuts = [0.0] + [s.time for s in switches] + [3.5]
    t = np.unique(np.concatenate([np.linspace(a, b, 2001) for a, b in zip(cuts, cuts[1:])]))
    run = mech.simulate(0.0, t, theta0=0.3, omega0=10.0, load=5.0)
    assert run.attrs["switches"] == switches
    P = run["P_loss"].to_numpy()
    lost = sum(simpson(P[(t >= a) & (t <= b)], x=t[(t >= a) & (t <= b)])
               for a, b in zip(cuts, cuts[1:]))
    th = run["theta"].to_numpy()
    against, _ = quad(lambda x: plain.solve(x, 0.0, 0.0, outputs=("Mb",), load=5.0)["Mb"],
                      th[0], th[-1], limit=400, epsabs=1e-13, epsrel=1e-13)
    kinetic = 0.5 * run["J_red"].to_numpy() * run["omega"].to_numpy() ** 2
    assert lost > 0.5 * kinetic[0]
    assert abs(-lost - against - (kinetic[-1] - kinetic[0])) <= 1e-6 * lost


def test_a_massless_linkage_with_friction_needs_a_flywheel():
    """The scotch yoke without mass, friction in every pair: no inertia on the crank, so
    no acceleration is defined (the error says so, as without friction); a flywheel
    defines it: alpha = (tau - Mb(alpha)) / I, Mb then independent of alpha (no inertia
    forces), so Mb = tau - I alpha to rounding."""
    d = presets.preset("scotch_yoke")
    params = {spec["mu"]: 0.1 for spec in d.friction.values()}
    params.update({spec["radius"]: 0.01 for spec in d.friction.values() if "radius" in spec})
    yoke = presets.get("scotch_yoke", m2=0.0, m3=0.0, **params)
    with pytest.raises(ValueError, match=r"reduced to the crank is 0\.0 at theta = 0\.3 rad; "
                                         r"the motion is not defined \(reached at t = 0 s\)"):
        yoke.simulate(1.0, [0.0, 0.1], theta0=0.3, omega0=1.0, load=100.0)
    run = yoke.simulate(1.0, [0.0, 0.05], theta0=0.3, omega0=1.0, load=100.0, flywheel=0.5)
    np.testing.assert_allclose(run["Mb"], 1.0 - 0.5 * run["alpha"], rtol=0, atol=1e-12)
    moving = run[~run["stuck"]]
    alone = yoke.solve(moving["theta"].to_numpy(), moving["omega"].to_numpy(), 0.0,
                       load=100.0, method="direct")["Mb"]  # Mb does not depend on alpha
    np.testing.assert_allclose(moving["alpha"], (1.0 - alone) / 0.5, rtol=1e-12)


def test_friction_newton_meets_rounding_where_torque_and_Mb_are_near_0():
    """The four-bar with friction in every pin (mu 0.05, pins of 10 mm) swinging under
    gravity, tau = 0, from theta0 = 4.190620850853655 rad at omega0 = -13.006511562027953
    rad/s, at rtol = atol = 1e-12: the first state's acceleration is -1.68e-3 rad/s2,
    where Mb's terms cancel and Newton's steps stop at 4e-14 rad/s2 (before, a
    SelfLockingError "Newton's method ... does not converge"). Reference: the root of the
    direct solver's Mb with drive -1 (brentq), to 1e-9 rad/s2."""
    from scipy.optimize import brentq

    friction = {f"{k}_{p}": (0.05 if k == "mu" else 0.01) for p in "ABCD" for k in ("mu", "r")}
    th, w = 4.190620850853655, -13.006511562027953
    run = presets.get("four_bar", **friction).simulate(0.0, [0.0, 1e-3], theta0=th, omega0=w,
                                                       rtol=1e-12, atol=1e-12)
    back = presets.get("four_bar", drive=-1.0, **friction)
    root = brentq(lambda a: float(back.solve(th, w, a, method="direct")["Mb"]), -1.0, 1.0,
                  xtol=1e-15)
    assert abs(float(run["alpha"].iloc[0]) - root) <= 1e-9, (run["alpha"].iloc[0], root)
    assert abs(root + 1.68e-3) <= 1e-5


def _with_friction_everywhere(name: str, params: dict) -> dict:
    """``params`` with Coulomb friction in every pair of the preset (mu 0.15, pins of
    0.02 of its length scale)."""
    d = presets.preset(name)
    scale = presets.get(name, **params).length_scale
    out = {**params, **{spec["mu"]: 0.15 for spec in d.friction.values()}}
    out.update({spec["radius"]: 0.02 * scale for spec in d.friction.values()
                if "radius" in spec})
    return out


def _states(kernel, n_loads: int, rng) -> list:
    """States of the kernel (theta, omega, alpha, loads): random ones (omega and alpha
    0 or tiny among them: friction's direction decided by drive, or by rounding), and
    states within 1e-3 .. 1e-12 rad of the edges of the angles where it assembles (near
    singular: the reactions grow without bound there)."""
    loads = [float(v) for v in rng.normal(0.0, 30.0, n_loads)]
    out = []
    for _ in range(40):
        omega = float(rng.choice([0.0, 1e-12, -3e-9, rng.normal(0.0, 20.0)]))
        alpha = float(rng.choice([0.0, rng.normal(0.0, 300.0)]))
        out.append([float(rng.uniform(-7.0, 7.0)), omega, alpha, *loads])
    def takes(theta):
        try:
            return kernel(theta, 4.0, 10.0, *loads) is not None
        except ArithmeticError:  # Python's division by 0 at the edge: C's inf
            return False

    grid = np.linspace(0.0, 2 * math.pi, 721)
    ok = [takes(th) for th in grid]
    for a, b, oa, ob in zip(grid, grid[1:], ok, ok[1:]):
        if oa == ob:
            continue
        inside, outside = (a, b) if oa else (b, a)
        for _ in range(60):
            mid = 0.5 * (inside + outside)
            if not takes(mid):
                outside = mid
            else:
                inside = mid
        side = 1.0 if inside > outside else -1.0
        out += [[inside + side * h, w, 10.0, *loads] for h in (0.0, 1e-12, 1e-9, 1e-6, 1e-3)
                for w in (4.0, 0.0)]
    return out


#: every variant of the presets, and a four-bar whose crank is too long to turn (the
#: edges of its range: near singular)
EDGES = [*VARIANTS, ("four_bar", {"l_AB": 0.3})]


@pytest.mark.parametrize("name,params", EDGES, ids=[*VARIANT_IDS, "four_bar-l_AB=0.3"])
def test_without_a_compiler_moment_and_slope_is_the_compiled_tangent(monkeypatch, tmp_path,
                                                                     name, params):
    """Friction in every pair: without a C compiler, moment_and_slope gives the compiled
    kernel's Mb and slope (the Python forward mode of the same tape, the same operations
    in the same order), to 1e-14 relative (absolute of the slopes' scale where a slope
    is near 0; measured: the same floats), at random states and at states near the
    edges of the linkage's range; and the Python tangent kernel is the compiled one
    along random directions of every input, failing the same states."""
    import warnings

    from linkage_fmu.kernels import compiled
    from linkage_fmu.motion import moment_and_slope

    mech = presets.get(name, **_with_friction_everywhere(name, params))
    if not mech.effort_on_crank:
        pytest.skip(f"{name}: the effort does not act on the crank")
    values, given = mech.inputs(0.0, 0.0, (), {})
    kernel = mech.solver.kernel((mech.effort.name,), False, given)
    exact = kernel.tangent()
    if exact is None:
        pytest.skip("no C compiler")
    loads = {ld.name: 7.0 for ld in mech.input_loads}
    with_compiler = moment_and_slope(mech, **loads)
    monkeypatch.setenv("CC", "no-such-compiler")
    monkeypatch.setenv("LINKAGE_FMU_CACHE", str(tmp_path))
    compiled._no_compiler_warning.cache_clear()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # "no C compiler found"
        without = moment_and_slope(mech, **loads)
    python = kernel.python_tangent()
    rng = np.random.default_rng(38)
    states = _states(kernel, kernel.n_inputs - 3, rng)
    pairs = []
    for x in states:
        try:
            pairs.append((with_compiler(*x[:3]), without(*x[:3])))
        except (AssemblyError, SelfLockingError, ValueError):
            with pytest.raises((AssemblyError, SelfLockingError, ValueError)):
                without(*x[:3])
        dx = rng.normal(size=len(x))
        c = exact(x, dx)
        try:
            p = python(x, dx)
        except ArithmeticError:  # Python's division by 0 (C's inf): a state failed
            assert type(c) is not tuple or not np.isfinite(c[0]).all(), x
            continue
        if type(c) is not tuple:
            assert p == c, x
            continue
        np.testing.assert_array_equal(p[0], c[0])
        scale = 1e-14 * max(1e-300, float(np.max(np.abs(c[1]))))
        np.testing.assert_allclose(p[1], c[1], rtol=1e-14, atol=scale, err_msg=str(x))
    assert len(pairs) >= 20
    slopes = 1e-14 * max(abs(s) for (_, s), _ in pairs)
    for (m, s), (mp, sp) in pairs:
        assert mp == m
        assert sp == pytest.approx(s, rel=1e-14, abs=slopes)
    assert not list(tmp_path.iterdir())  # nothing compiled
