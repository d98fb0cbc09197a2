"""Linkages driven by several actuators (``Mechanism.rates``): a five-bar robot (two
cranks on the frame), a two-link arm (a crank and a motor at its elbow) and a dump body
(one cylinder), built from groups.

References, none of them the library's own statics:

* the links' constraints: every fixed distance as given, and the cylinder's length its
  drawn length plus the travel, to 1e-12 m;
* the motion: velocities and accelerations equal central differences in time of the
  positions along ``q(t) = q + v t + a t**2 / 2`` (step 1e-4 s), to 1e-6 m/s and
  2e-4 m/s2 (the differences' own error, of order step**2 and the rounding);
* the power balance (virtual power): the drivers' power ``sum(E_j * qdot_j)`` with the
  loads' and the weights' equals ``dT/dt = sum(m v.a + J w e)``, to 1e-9 of its terms;
* the assembled ``A x = b`` solved by LU (``method="direct"``) against the groups'
  closed form, every output, to 1e-9.

They are checked at 20 states each with nonzero speeds and accelerations, g 9.81.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkage_fmu.errors import AssemblyError, InputError, InputTypeError, LinkageError
from linkage_fmu.groups import RRR, Crank, Cylinder, LinkPoint
from linkage_fmu.loads import Load
from linkage_fmu.mechanism import Body, Mechanism
from linkage_fmu.outputs import Force
from linkage_fmu.solver import UNASSEMBLED

G = 9.81
H = 1e-4  # s, the step of the central differences
RNG = np.random.default_rng(20261204)


def five_bar(coupler: float = 0.25) -> Mechanism:
    groups = [Crank("1", "A", "B", 0.15), Crank("4", "E", "D", 0.15),
              RRR("2", "3", "B", "C", "D", coupler, coupler, +1)]
    bodies = [Body("1", 0.3, 0.001, "A", along=0.07), Body("2", 0.5, 0.003, "B", along=0.12),
              Body("3", 0.5, 0.003, "D", along=0.12), Body("4", 0.3, 0.001, "E", along=0.07)]
    return Mechanism("five_bar", "0", {"A": (0.0, 0.0), "E": (0.2, 0.0)}, groups, bodies, None,
                     [Force("F12x", "1", "2", "x"), Force("F12y", "1", "2", "y")],
                     [Load("P", "2", "force", at="C", direction=(0.0, -1.0))], G)


def arm() -> Mechanism:
    groups = [Crank("1", "A", "B", 0.4), Crank("2", "B", "C", 0.3, base="1", offset=0.2)]
    bodies = [Body("1", 2.0, 0.03, "A", along=0.2), Body("2", 1.2, 0.01, "B", along=0.15,
                                                        across=0.02)]
    return Mechanism("arm", "0", {"A": (0.0, 0.0)}, groups, bodies, None, [],
                     [Load("F", "2", "force", at="C", direction=(0.6, -0.8)),
                      Load("T", "2", "moment")], G)


def dump_body() -> Mechanism:
    groups = [Cylinder("body", "barrel", "rod", "O", "D", "E", "P", 1.5, 1.2, +1),
              LinkPoint("body", "O", "G", along=2.0, across=0.6)]
    bodies = [Body("body", 900.0, 600.0, "O", along=1.8, across=0.5),
              Body("barrel", 40.0, 2.0, "E", along=0.4), Body("rod", 15.0, 0.8, "D", along=-0.3)]
    return Mechanism("dump_body", "0", {"O": (0.0, 0.0), "E": (1.0, -0.5)}, groups, bodies,
                     None, [Force("FODx", "0", "body", "x")],
                     [Load("W", "body", "force", at="G", direction=(0.0, -1.0))], G)


#: case -> (the linkage, {fixed distance (u, v): m}, each driver's coordinate range)
CASES = {
    "five_bar": (five_bar, {("A", "B"): 0.15, ("E", "D"): 0.15, ("B", "C"): 0.25,
                            ("D", "C"): 0.25}, [(1.6, 2.2), (0.9, 1.5)]),
    "arm": (arm, {("A", "B"): 0.4, ("B", "C"): 0.3}, [(-1.0, 2.0), (-2.0, 2.0)]),
    "dump_body": (dump_body, {("O", "D"): 1.5}, [(-0.1, 0.4)]),
}


def states(ranges, n=20):
    for _ in range(n):
        q = [RNG.uniform(a, b) for a, b in ranges]
        v = [RNG.uniform(-2.0, 2.0) * (b - a) for a, b in ranges]
        acc = [RNG.uniform(-5.0, 5.0) * (b - a) for a, b in ranges]
        yield q, v, acc


def inputs(mech, q, v, a, loads=()):
    values = [x for three in zip(q, v, a) for x in three] + list(loads)
    return dict(zip(mech.input_names, values))


def positions(mech, q):
    st = mech.kinematics(tuple(q), order=0, rates=tuple((0.0, 0.0) for _ in q))
    return st.p, st.u


@pytest.mark.parametrize("name", CASES)
def test_the_links_keep_their_lengths(name):
    build, lengths, ranges = CASES[name]
    mech = build()
    for q, _, _ in states(ranges):
        p, _ = positions(mech, q)
        for (u, w), length in lengths.items():
            assert math.dist(p[u], p[w]) == pytest.approx(length, abs=1e-12)
        if name == "dump_body":  # the cylinder: drawn length + travel
            assert math.dist(p["E"], p["D"]) == pytest.approx(1.2 + q[0], abs=1e-12)


@pytest.mark.parametrize("name", CASES)
def test_velocities_and_accelerations_are_the_positions_differentiated_in_time(name):
    build, _, ranges = CASES[name]
    mech = build()
    for q, v, a in states(ranges):
        st = mech.kinematics(tuple(q), order=2, rates=tuple(zip(v, a)))
        at = [positions(mech, [qi + vi * t + 0.5 * ai * t * t for qi, vi, ai in zip(q, v, a)])
              for t in (-H, 0.0, H)]
        for point in st.p:
            (xm, ym), (x0, y0), (xp, yp) = (s[0][point] for s in at)
            assert st.d1[point] == pytest.approx(((xp - xm) / (2 * H), (yp - ym) / (2 * H)),
                                                 abs=1e-6)
            assert st.d2[point] == pytest.approx(((xp - 2 * x0 + xm) / H**2,
                                                  (yp - 2 * y0 + ym) / H**2), abs=2e-4)


def power_terms(mech, q, v, a, loads):
    """Each term of the power balance: the drivers', the loads', the weights' and
    -dT/dt, from the library's motion (checked above by differences)."""
    sol = mech.solve(**inputs(mech, q, v, a, loads))
    st = mech.kinematics(tuple(q), order=2, rates=tuple(zip(v, a)))
    terms = [sol[e.name] * qd for e, qd in zip(mech.efforts, v)]
    for ld, value in zip(mech.loads, loads):
        if ld.kind == "moment":
            terms.append(value * st.w1[ld.body])
        else:
            vx, vy = st.d1[ld.at]
            terms.append(value * (ld.direction[0] * vx + ld.direction[1] * vy))
    for b in mech.bodies:
        (vx, vy), (ax, ay) = st.d1[b.cg], st.d2[b.cg]
        terms += [-b.mass * G * vy, -(b.mass * (vx * ax + vy * ay)
                                      + b.inertia * st.w1[b.name] * st.w2[b.name])]
    return terms


@pytest.mark.parametrize("name", CASES)
def test_the_drivers_efforts_hold_the_power_balance(name):
    build, _, ranges = CASES[name]
    mech = build()
    for q, v, a in states(ranges):
        loads = [RNG.uniform(-50.0, 50.0) for _ in mech.input_loads]
        terms = power_terms(mech, q, v, a, loads)
        assert abs(sum(terms)) <= 1e-9 * max(1.0, max(map(abs, terms)))


@pytest.mark.parametrize("name", CASES)
def test_the_closed_form_is_the_assembled_system(name):
    build, _, ranges = CASES[name]
    mech = build()
    for q, v, a in states(ranges):
        x = inputs(mech, q, v, a, [30.0] * len(mech.input_loads))
        closed, direct = mech.solve(**x), mech.solve(**x, method="direct")
        for k in closed:
            assert closed[k] == pytest.approx(direct[k], abs=1e-9, rel=1e-9), k


def test_the_five_bar_alone_under_gravity_holds_its_weight():
    """At rest, the two cranks' moments balance the weights about A and E: the links'
    total weight moment about the frame is that of the cranks' moments (statics of
    the whole linkage: the frame's reactions, shake_x and shake_y, are the weights)."""
    mech = five_bar()
    sol = mech.solve(theta_A=1.9, theta_E=1.2, P=0.0)
    weight = sum(b.mass for b in mech.bodies) * G
    assert sol["shake_x"] == pytest.approx(0.0, abs=1e-12)
    assert sol["shake_y"] == pytest.approx(-weight, rel=1e-13)


def test_arrays_give_each_state_and_the_scalars_equal_them():
    mech = five_bar()
    qa = np.linspace(1.6, 2.2, 7)
    sol = mech.solve(theta_A=qa, theta_E=1.2, omega_A=1.5, alpha_E=-2.0, P=20.0)
    for k, q in enumerate(qa):
        one = mech.solve(theta_A=float(q), theta_E=1.2, omega_A=1.5, alpha_E=-2.0, P=20.0)
        for name in ("Mb_A", "Mb_E", "F12x", "gamma_C"):
            assert sol[name][k] == pytest.approx(one[name], rel=1e-13, abs=1e-13)


def test_names_follow_the_drivers():
    assert five_bar().input_names == ("theta_A", "omega_A", "alpha_A", "theta_E", "omega_E",
                                      "alpha_E", "P")
    assert dump_body().input_names == ("s_P", "v_P", "a_P", "W")
    assert dump_body().output_names == ("FODx", "Fb_P", "shake_x", "shake_y", "shake_M")
    assert arm().output_info["Mb_B"] == (
        "N.m", "moment the driver applies to link 2 (its reaction on 1), counter-clockwise "
               "positive")


def test_a_travel_the_cylinder_cannot_reach_is_an_error_or_an_invalid_state():
    mech = dump_body()
    with pytest.raises(AssemblyError, match=r"dump_body cannot be assembled at s_P = 2 m: "
                                            r"the cylinder dyad O-D-E cannot close: \|OE\| = "
                                            r"1.11803 m < \|OD - cylinder\| = 1.7 m"):
        mech.solve(2.0)
    sol = mech.solve([0.1, 2.0, -1.3])
    assert sol.valid.tolist() == [True, False, False]
    assert sol.status.tolist()[1:] == [UNASSEMBLED, UNASSEMBLED]
    assert "retracted to no length" in sol.problems[UNASSEMBLED].message or \
        "cannot close" in sol.problems[UNASSEMBLED].message


def test_an_angle_the_five_bar_cannot_reach_is_an_error_naming_both_cranks():
    with pytest.raises(AssemblyError, match=r"five_bar cannot be assembled at theta_A = 3.1 "
                                            r"rad \(177.6 deg\), theta_E = 0 rad \(0 deg\): "
                                            "the dyad B-C-D cannot close"):
        five_bar(coupler=0.15).solve(theta_A=3.1, theta_E=0.0)


def test_bad_calls_are_refused_naming_the_input():
    mech = five_bar()
    with pytest.raises(InputError, match="five_bar: give each driver's coordinate; missing: "
                                         "theta_E"):
        mech.solve(theta_A=1.9)
    with pytest.raises(InputTypeError, match="five_bar has no input 's_P'; its inputs are: "
                                             "theta_A, omega_A"):
        mech.solve(theta_A=1.9, theta_E=1.2, s_P=1.0)
    with pytest.raises(InputTypeError, match="input theta_A is given twice"):
        mech.solve(1.9, theta_A=1.9)



def test_the_traced_kernel_is_the_formulas():
    """The kernel traced from the groups' formulas gives the interpreted formulas'
    outputs, to 1e-12 of each, at 20 states of each linkage."""
    for name, (build, _, ranges) in CASES.items():
        mech = build()
        kernel = mech.kernel()
        loads = [7.0] * len(mech.input_loads)
        for q, v, a in states(ranges):
            values = [x for state in zip(q, v, a) for x in state] + loads
            got = kernel.call(*values)
            want = mech.solve(*values, method="interpreted")
            assert got == pytest.approx([want[n] for n in kernel.index], rel=1e-12,
                                        abs=1e-12), (name, q)


def test_what_a_linkage_driven_by_time_cannot_take_is_refused_with_the_reason():
    m = five_bar()
    with pytest.raises(LinkageError, match=r"five_bar: it is driven by time \(Crank at A, "
                                           r"Crank at E\): a load over a crank's cycle \(P\) "
                                           "has no crank angle to follow"):
        Mechanism("five_bar", "0", m.frame_points, m.groups[:3], m.bodies, None, [],
                  [Load("P", "2", "moment", start=0.0, value=_Value())], G)


class _Value:
    """Stands for a load's expression over the cycle (the load is then computed)."""


@pytest.mark.parametrize("job, call", [
    ("the inertia reduced to the crank", lambda m: m.reduced_inertia(1.0)),
    ("a flywheel is sized for a moment on the crank", lambda m: m.flywheel(10.0, 0.05)),
    ("a table over crank angles", lambda m: m.table([1.0, 2.0])),
    ("a plot over crank angles", lambda m: __import__("linkage_fmu.plot").plot.torque(m)),
    ("a plot over crank angles",
     lambda m: __import__("linkage_fmu.plot").plot.transmission(m)),
])
def test_a_job_for_one_crank_is_refused_naming_the_drivers(job, call):
    with pytest.raises(InputError, match=rf"five_bar is driven by time \(theta_A, theta_E\): "
                                         rf"{job} takes a linkage driven by one crank on the "
                                         r"frame, so far; solve \(its kernels, its FMUs\), "
                                         "mass_matrix and simulate take this one"):
        call(five_bar())


EXAMPLES = __import__("pathlib").Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("name, build, state", [
    ("five_bar", five_bar, dict(theta_A=1.9, theta_E=1.2, omega_A=2.0, omega_E=-1.0,
                                alpha_A=3.0, alpha_E=0.5, P=10.0)),
    ("dump_body", dump_body, dict(s_P=0.2, v_P=0.05, a_P=0.01, W=20000.0)),
])
def test_the_example_files_are_the_linkages_built_from_groups(name, build, state):
    """The files examples/five_bar.toml and dump_body.toml, written as joints and links,
    describe the linkages built above from groups: the same efforts and frame forces,
    to 1e-12 relative."""
    import linkage_fmu

    mech, ref = linkage_fmu.load(EXAMPLES / f"{name}.toml"), build()
    assert mech.input_names == ref.input_names
    a, b = mech.solve(**state), ref.solve(**state)
    for e in ref.efforts:
        assert a[e.name] == pytest.approx(b[e.name], rel=1e-12)
    for k in ("shake_x", "shake_y", "shake_M"):
        assert a[k] == pytest.approx(b[k], rel=1e-12, abs=1e-12)


def test_the_command_line_lists_the_drivers_and_refuses_what_takes_one_crank(capsys):
    from linkage_fmu.cli import main

    assert main(["info", str(EXAMPLES / "dump_body.toml")]) == 0
    out = capsys.readouterr().out
    assert "  driver P (travel), effort Fb_P [N]:\n    s_P       [m] travel from the drawn " \
           "length, > 0 extending (start 0.0)\n    v_P       [m/s] speed of travel (start " \
           "0.05)" in out
    assert main(["sweep", str(EXAMPLES / "five_bar.toml")]) == 2
    err = capsys.readouterr().err
    assert "five_bar is driven by time (theta_A, theta_E): " in err
    assert "takes a linkage driven by one crank on the frame, so far" in err


def test_a_sweep_or_an_optimisation_over_crank_angles_is_refused(tmp_path):
    from linkage_fmu.optimize import optimize
    from linkage_fmu.sweep import sweep

    source = EXAMPLES / "dump_body.toml"
    for job, call in [("a sweep over crank angles",
                       lambda: sweep(source, {"m_body": [800.0, 900.0]})),
                      ("an optimisation over crank angles",
                       lambda: optimize(source, {"m_body": (800.0, 900.0)}, "Fb_P_peak"))]:
        with pytest.raises(InputError, match=rf"dump_body is driven by time \(s_P\): {job} "
                                             "takes a linkage driven by one crank"):
            call()
