"""The shaking force and moment (``linkage_fmu.outputs.Shaking``) against three independent
references: the frame reactions and the balancing effort the solver reports, added up
by hand per preset; the momentum balance of the moving links, their accelerations taken
by finite differences of the positions (not the solver's derivative coefficients); and
the resultant on the frame derived from the joint forces printed in Marghitu & Dupac,
Advanced Dynamics (2012), Example 6.1."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkage_fmu import presets
from test_kinetostatics import EX61, EX61_STATE

STATES = [(0.3, 10.0, 0.0), (2.2, -7.0, 40.0), (4.9, 3.0, -15.0)]


def _frame_sum(name: str, s, mech, theta) -> tuple[float, float, float]:
    """(shake_x, shake_y, shake_M) added up from the named outputs ``s`` of each preset:
    the force of every moving link on the frame at its joint, the guides' normal forces,
    and minus the balancing effort (the frame drives the crank)."""
    p = mech.parameters
    if name == "four_bar":  # F14: crank on frame at A = 0; F43: frame on rocker at D
        fx, fy = s["F14x"] - s["F43x"], s["F14y"] - s["F43y"]
        return fx, fy, p["l_AD"] * -s["F43y"] - s["Mb"]
    if name == "slider_crank":  # e = gamma = 0: the guide's normal is +y, through B
        st = mech.kinematics(theta, order=0)
        xb = st.p["B"][0]
        return s["F14x"], s["F14y"] - s["N43"], xb * -s["N43"] - s["Mb"]
    if name == "slotted_lever":  # frame on crank at A = 0, frame on lever at C = (0, -l_AC)
        fx, fy = -s["F01x"] - s["F03x"], -s["F01y"] - s["F03y"]
        return fx, fy, 0.0 * -s["F03y"] - (-p["l_AC"]) * -s["F03x"] - s["Mb"]
    raise KeyError(name)


@pytest.mark.parametrize("name", ["four_bar", "slider_crank", "slotted_lever"])
@pytest.mark.parametrize("method", ["closed_form", "direct"])
def test_shaking_is_the_sum_of_the_frame_reactions(name, method):
    """To 1e-12 of the largest force: the shaking outputs are the frame reactions of the
    solver's own named outputs and the effort's reaction, added up by hand."""
    mech = presets.get(name)
    for theta, omega, alpha in STATES:
        sol = mech.solve(theta, omega, alpha, 150.0, method=method)
        fx, fy, m = _frame_sum(name, sol, mech, theta)
        scale = max(abs(sol[n]) for n in mech.output_names)
        assert sol["shake_x"] == pytest.approx(fx, abs=1e-12 * scale)
        assert sol["shake_y"] == pytest.approx(fy, abs=1e-12 * scale)
        assert sol["shake_M"] == pytest.approx(m, abs=1e-12 * scale)


def _momentum(mech, theta, omega, alpha, load, h=1e-3):
    """The loads, weights and d'Alembert forces of the moving links, their moment about
    the crank pivot: the centres of mass accelerate by the five-point central difference
    of their positions in time (theta(t) = theta + omega t + alpha t^2 / 2, error
    O(h^4)), the links turn by differences of their angles."""
    def positions(dt):
        th = theta + omega * dt + 0.5 * alpha * dt * dt
        st = mech.kinematics(th, order=0)
        return st, {b.name: st.p[b.cg] for b in mech.bodies}, {
            b.name: math.atan2(st.u[b.name][1], st.u[b.name][0]) if b.name in st.u else 0.0
            for b in mech.bodies}

    def second(values):  # values at -2h, -h, 0, h, 2h
        a, b, c, d, e = values
        return (-a + 16 * b - 30 * c + 16 * d - e) / (12 * h * h)

    states = [positions(k * h) for k in (-2, -1, 0, 1, 2)]
    st, p0, a0 = states[2]
    x0, y0 = st.p[mech.crank.pivot]
    fx = fy = m = 0.0
    for b in mech.bodies:
        ax = second([s[1][b.name][0] for s in states])
        ay = second([s[1][b.name][1] for s in states])
        # the angle's differences from the middle one, across the +-pi cut
        phi2 = second([(s[2][b.name] - a0[b.name] + math.pi) % (2 * math.pi) - math.pi
                       for s in states])
        gx, gy = -b.mass * ax, -b.mass * ay - b.mass * mech.g
        fx, fy = fx + gx, fy + gy
        rx, ry = p0[b.name][0] - x0, p0[b.name][1] - y0
        m += rx * gy - ry * gx - b.inertia * phi2
    for ld in mech.loads:
        if ld.kind == "moment":
            m += load
            continue
        ux, uy = ld.direction
        if ld.fixed_in == "link":
            c, s = st.u[ld.body]
            ux, uy = c * ux - s * uy, s * ux + c * uy
        px, py = st.p[ld.at]
        fx, fy = fx + load * ux, fy + load * uy
        m += (px - x0) * load * uy - (py - y0) * load * ux
    return fx, fy, m


@pytest.mark.parametrize("name, params", [
    ("scotch_yoke", {}), ("four_bar", {}), ("slider_crank", {"e": 0.02, "gamma": 0.3}),
    ("slotted_lever", {}), ("crank_shaper", {}), ("six_bar", {"driver": "D"}),
    ("six_bar", {"driver": "KD"})])
def test_shaking_is_the_momentum_balance_of_the_moving_links(name, params):
    """To 1e-7 of the largest output (the finite differences' error, h = 1e-3): what the
    links put on the frame, the driver's reaction included (a moment, or the six-bar's
    force on its slider), equals their loads, weights and d'Alembert forces."""
    mech = presets.get(name, **params)
    for theta, omega, alpha in STATES:
        sol = mech.solve(theta, omega, alpha, 150.0)
        fx, fy, m = _momentum(mech, theta, omega, alpha, 150.0)
        scale = max(abs(sol[n]) for n in mech.output_names)
        assert sol["shake_x"] == pytest.approx(fx, abs=1e-7 * scale), (theta, "x")
        assert sol["shake_y"] == pytest.approx(fy, abs=1e-7 * scale), (theta, "y")
        assert sol["shake_M"] == pytest.approx(m, abs=1e-7 * scale), (theta, "M")


def test_shaking_of_the_shaper_of_marghitu_dupac_example_6_1():
    """The example prints the frame's forces on the ram (F05), the lever (F03) and the
    crank (the crank pin's F12, for a massless crank): the resultant on the frame is
    -(F05 + F03 + F12) = (501.963, 0.471) N, and its moment about A, with the motor's
    reaction -Mb = -(B x F12), is -175.2293 N m; printed to three decimals (2e-3 N)."""
    mech = presets.get("crank_shaper", **EX61)
    F05, F03, F12 = (0.0, -124.959), (123.647, -38.376), (-625.610, 162.864)
    B = (0.2 * math.cos(EX61_STATE[0]), 0.2 * math.sin(EX61_STATE[0]))
    E = (mech.kinematics(EX61_STATE[0], order=0).p["E"][0], 0.35)
    fx = -(F05[0] + F03[0] + F12[0])
    fy = -(F05[1] + F03[1] + F12[1])
    mb = B[0] * F12[1] - B[1] * F12[0]
    # moments about A of -F05 at E and -F03 at D = (0, -0.4); -F12 acts at A
    m = (E[0] * -F05[1] - E[1] * -F05[0]) + (0.0 * -F03[1] - (-0.4) * -F03[0]) - mb
    for method in ("closed_form", "direct"):
        sol = mech.solve(*EX61_STATE, -500.0, method=method)
        assert sol["shake_x"] == pytest.approx(fx, abs=3e-3)
        assert sol["shake_y"] == pytest.approx(fy, abs=3e-3)
        assert sol["shake_M"] == pytest.approx(m, abs=3e-3)
    assert (fx, fy, m) == pytest.approx((501.963, 0.471, -175.2293), abs=1e-3)


def test_shaking_on_arrays_equals_one_state_at_a_time():
    """The array path and the one-state kernel agree to 1e-13 (one formula)."""
    mech = presets.get("six_bar", driver="D")
    theta = np.linspace(0.0, 2 * np.pi, 25)
    arr = mech.solve(theta, 2.0, 1.0, 50.0)
    for k, t in enumerate(theta):
        one = mech.solve(float(t), 2.0, 1.0, 50.0)
        for n in ("shake_x", "shake_y", "shake_M"):
            assert arr[n][k] == pytest.approx(one[n], abs=1e-13 * max(1.0, abs(one[n])))
