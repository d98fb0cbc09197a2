"""The labelled equilibrium equations A x = b (linkage_fmu.equations) against the scotch
yoke worked example's MATLAB function F(x), whose values at 60, 150 and 220 deg it
quotes to four decimals (lAB 0.1 m, h2 0.08 m, 10 rad/s, G2 40 N, G3 100 N, Fr 400 N),
against the hinged four-bar worked example's table of a(i, j) and b(i) (section 6), and,
for every preset and example, against the direct solver (``solve``) and the symbolic
equations written from the free bodies.

The yoke's x axis points the other way (its FR12x is our -Fx_B), and it writes the
guide's reaction as two forces FR4, FR4' a distance h2 apart (our couple M_guide = -FR4
h2).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import linkage_fmu
from linkage_fmu import presets
from linkage_fmu.equations import equations
from linkage_fmu.errors import InputError
from linkage_fmu.friction import Reactions
from linkage_fmu.friction import outputs as friction_outputs
from linkage_fmu.pairs import Prismatic, Revolute

#: angle [deg] -> FR23, FR4, FR12x, FR12y, Mb of the worked example
WORKED = {60: (313.3975, 195.8734, 20.0000, 278.7564, 15.6699),
          150: (350.0000, -378.8861, -34.6410, 330.0000, -30.3109),
          220: (464.2788, -444.5727, -30.6418, 489.9903, -35.5658)}
H2 = 0.08


@pytest.mark.parametrize("deg", WORKED)
def test_the_scotch_yoke_s_system_gives_the_worked_example_s_values(deg):
    eq = equations(presets.get("scotch_yoke"), math.radians(deg), 10.0, load=400.0)
    x = eq.solution
    FR23, FR4, FR12x, FR12y, Mb = WORKED[deg]
    got = (x["N_slot"], -x["M_guide"] / H2, -x["Fx_B"], x["Fy_B"], x["Mb"])
    assert got == pytest.approx((FR23, FR4, FR12x, FR12y, Mb), abs=5e-5)
    assert eq.residual <= 1e-12 * np.max(np.abs(eq.b))
    assert eq.cond < 10.0 and abs(eq.det) > 0.1


def test_the_rows_and_columns_are_labelled_and_the_solution_is_solve_s():
    """Three rows per moving link, moments about its group's point, a column per reaction
    component and effort; the solution equals ``solve(method="direct")`` to 1e-12,
    for a linkage driven by time too."""
    four = presets.get("four_bar")
    eq = equations(four, 0.3, 10.0, 5.0, load=2.0)
    sol = four.solve(0.3, 10.0, 5.0, load=2.0, method="direct")
    assert eq.rows[3:6] == ("link 2: ΣFx", "link 2: ΣFy", "link 2: ΣM about B")
    assert eq.unknowns == ("Fx_A", "Fy_A", "Fx_B", "Fy_B", "Fx_C", "Fy_C", "Fx_D", "Fy_D",
                           "Mb")
    assert eq.solution["Mb"] == pytest.approx(sol["Mb"], rel=1e-12)
    assert eq.solution["Fx_B"] == pytest.approx(-sol["F21x"], rel=1e-12)  # 1 on 2
    five = linkage_fmu.load(Path(__file__).resolve().parents[1] / "examples" / "five_bar.toml")
    state = dict(theta_A=1.8, theta_E=1.3, omega_A=2.0, alpha_E=-1.0, P=10.0)
    eq, sol = equations(five, **state), five.solve(**state)
    for e in ("Mb_A", "Mb_E"):
        assert eq.solution[e] == pytest.approx(sol[e], rel=1e-12)
    text = eq.to("text")
    assert "link 2: ΣM about" in text and "Mb_A = " in text
    assert eq.to("markdown").splitlines()[6].startswith("| i | equation | a(i, 1) |")


def test_what_it_cannot_write_is_refused_with_the_reason():
    yoke = presets.get("scotch_yoke")
    with pytest.raises(InputError, match="equations are of one state"):
        equations(yoke, [0.1, 0.2], 10.0)
    with pytest.raises(InputError, match="format 'pdf': the formats are text, markdown"):
        equations(yoke, 0.1, 10.0).to("pdf")
    with pytest.raises(InputError, match="a function file of its equations with friction "
                       "is not written"):
        equations(presets.get("scotch_yoke", mu_slot=0.1), 0.1, 10.0).to("matlab")


EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
LINKAGES = ([(n, lambda n=n: presets.get(n)) for n in presets.names()] +
            [(p.stem, lambda p=p: linkage_fmu.load(p)) for p in sorted(EXAMPLES.glob("*.toml"))] +
            [(f"joints/{p.stem}", lambda p=p: linkage_fmu.load(p))
             for p in sorted((EXAMPLES / "joints").glob("*.toml"))])


def random_states(mech, n: int, seed: int = 3):
    """``n`` states ``mech`` assembles at, as ``solve``'s keywords: a crank anywhere on
    its revolution, drivers by time near where they start; speeds, accelerations and
    input loads random."""
    rng = np.random.default_rng(seed)
    found = 0
    while found < n:
        state = {}
        for d in mech.drivers:
            q, v, a = d.inputs
            start = mech.start[q] if mech.rates else rng.uniform(0.0, 2 * math.pi)
            state[q] = start + (rng.uniform(-0.05, 0.05) if mech.rates else 0.0)
            state[v], state[a] = rng.uniform(-5.0, 5.0), rng.uniform(-20.0, 20.0)
        state.update({ld.name: rng.uniform(-100.0, 100.0) for ld in mech.input_loads})
        try:
            sol = mech.solve(**state, method="direct")
        except ValueError:
            continue
        found += 1
        yield state, sol


@pytest.mark.parametrize("name, make", LINKAGES, ids=[n for n, _ in LINKAGES])
def test_the_system_reproduces_solve_and_the_symbolic_equations_equal_it(name, make):
    """At random states: A x = b with residual <= 1e-12 |b|, x equal to ``solve``'s
    outputs to 1e-12 of the largest output of their unit, and the symbolic A and b,
    evaluated at the state, equal to the numeric ones to 1e-13 of their largest
    entry."""
    mech = make()
    for k, (state, sol) in enumerate(random_states(mech, 3)):
        eq = equations(mech, **state)
        x = np.linalg.solve(eq.A, eq.b)
        assert np.max(np.abs(eq.A @ x - eq.b)) <= 1e-12 * np.max(np.abs(eq.b))
        R, col = Reactions(), 0
        R.friction = {j.name: 0.0 for j in mech.joints}  # every mu is 0
        for j in mech.joints:
            R[j.name] = (x[col], x[col + 1])
            col += 2
        efforts = tuple(x[col:])
        if mech.rates:
            st = mech.kinematics(tuple(state[d.inputs[0]] for d in mech.drivers), 0,
                                 rates=tuple((state[d.inputs[1]], 0.0) for d in mech.drivers))
        else:
            st = mech.kinematics(state["theta"], order=0)
        lost = {o.name for o in friction_outputs(mech)}  # 0 without friction
        for out, fn in mech.output_functions:
            unit = mech.output_info[out][0]
            if unit not in ("N", "N.m") or out.startswith("shake") or out in lost:
                continue
            scale = max(abs(sol[o]) for o in mech.output_names if mech.output_info[o][0] == unit)
            got = fn(R, efforts if mech.rates else efforts[0], st)
            assert abs(got - sol[out]) <= 1e-12 * scale, (out, state)
        if k:
            continue  # the symbolic system once per linkage: sympy is slow
        A, b = eq.symbolic()
        values = eq.free_bodies.values
        An = np.array(A.subs(values).evalf(30), dtype=float)
        bn = np.array(b.subs(values).evalf(30), dtype=float).ravel()
        assert np.max(np.abs(An - eq.A)) <= 1e-13 * np.max(np.abs(eq.A))
        assert np.max(np.abs(bn - eq.b)) <= 1e-13 * np.max(np.abs(eq.b))


def test_the_four_bar_s_table_is_the_worked_example_s():
    """The hinged four-bar worked example's section 6: unknowns F21x F21y F32x F32y F43x
    F43y F14x F14y Mb, each link's moments about A, B and D, and its a(i, j) and b(i) in
    the crank's, coupler's and rocker's lengths and angles. Our unknowns are the action
    of each pair's first body on its second: F21 = -(Fx_B, Fy_B), F32 = -(Fx_C, Fy_C),
    F43 = (Fx_D, Fy_D), F14 = -(Fx_A, Fy_A). The text table is read back (six digits)."""
    four = presets.get("four_bar", m1=1.0, J_S2=0.02, l_BS2=0.15, beta3=0.3)
    theta, omega, alpha, Mr = 0.7, 10.0, 3.0, 4.0
    eq = equations(four, theta, omega, alpha, load=Mr)
    lines = eq.to("text").splitlines()
    head = lines[3].split()
    assert " ".join(head) == ("i equation " + " ".join(f"a(i, {j})" for j in range(1, 10))
                              + " b(i)").replace("a(i, ", "a(i,").replace("a(i,", "a(i, ")
    table = [line.split() for line in lines[4:13]]
    assert [r[0] for r in table] == [str(i) for i in range(1, 10)]
    got = np.array([[float(v) for v in r[-10:]] for r in table])
    p, st = four.parameters, four.kinematics(theta, order=2)
    phi = {k: math.atan2(st.u[k][1], st.u[k][0]) for k in ("1", "2", "3")}
    (cx, cy), (dx, dy) = st.p["C"], st.p["D"]
    phi["3"] = math.atan2(cy - dy, cx - dx)  # the rocker's line D -> C
    lAB, lBC, lCD = p["l_AB"], p["l_BC"], p["l_CD"]
    a = np.zeros((9, 9))
    a[0, 0], a[0, 6], a[1, 1], a[1, 7] = 1, -1, 1, -1
    a[2, 0], a[2, 1], a[2, 8] = -lAB * math.sin(phi["1"]), lAB * math.cos(phi["1"]), 1
    a[3, 0], a[3, 2], a[4, 1], a[4, 3] = -1, 1, -1, 1
    a[5, 2], a[5, 3] = -lBC * math.sin(phi["2"]), lBC * math.cos(phi["2"])
    a[6, 2], a[6, 4], a[7, 3], a[7, 5] = -1, 1, -1, 1
    a[8, 2], a[8, 3] = lCD * math.sin(phi["3"]), -lCD * math.cos(phi["3"])
    g = four.g
    acc = {k: st.acceleration(four.cg[k], omega, alpha) for k in ("2", "3")}
    eps = {k: st.w2[k] * omega ** 2 + st.w1[k] * alpha for k in ("2", "3")}
    G = {k: -p[f"m{k}"] * g for k in ("1", "2", "3")}  # signed y components
    m2, m3, (a2x, a2y), (a3x, a3y) = p["m2"], p["m3"], acc["2"], acc["3"]
    (bx, by), (s2x, s2y) = st.p["B"], st.p[four.cg["2"]]
    (s3x, s3y) = st.p[four.cg["3"]]
    lBS2, lDS3 = math.hypot(s2x - bx, s2y - by), math.hypot(s3x - dx, s3y - dy)
    phi2s, phi3s = math.atan2(s2y - by, s2x - bx), math.atan2(s3y - dy, s3x - dx)
    b = [0.0, -G["1"], 0.0, m2 * a2x, -G["2"] + m2 * a2y,
         p["J_S2"] * eps["2"] - lBS2 * math.cos(phi2s) * (G["2"] - m2 * a2y)
         + lBS2 * math.sin(phi2s) * (-m2 * a2x),
         m3 * a3x, -G["3"] + m3 * a3y,
         lDS3 * math.cos(phi3s) * (m3 * a3y - G["3"]) + lDS3 * math.sin(phi3s) * (-m3 * a3x)
         + p["J_S3"] * eps["3"] - Mr]
    # our columns in the worked example's order and sign
    order, sign = [2, 3, 4, 5, 6, 7, 0, 1, 8], [-1, -1, -1, -1, 1, 1, -1, -1, 1]
    ours = got[:, :9][:, order] * np.array(sign)
    assert ours == pytest.approx(a, rel=1e-5, abs=1e-6 * np.max(np.abs(a)))
    assert got[:, 9] == pytest.approx(b, rel=1e-5, abs=1e-6 * np.max(np.abs(b)))


def with_friction(name: str):
    """The preset ``name`` with mu 0.1 in every pair and pins of radius 10 mm."""
    params = presets.preset(name).parameters
    return presets.get(name, **{k: 0.1 if k.startswith("mu_") else 0.01 for k in params
                                if k.startswith(("mu_", "r_"))})


@pytest.mark.parametrize("name", presets.names())
def test_with_friction_the_system_at_the_solution_is_solve_s(name):
    """With friction (mu 0.1, pins of 10 mm): at random states A x = b at the solution
    to 1e-12 |b|, x equal to ``solve``'s to 1e-12 of its largest value, the symbolic
    system equal to the numeric to 1e-13, and each friction law, at the solution,
    equal to the solver's friction to 1e-12 of the largest."""
    mech = with_friction(name)
    assert mech.friction.active
    for k, (state, _) in enumerate(random_states(mech, 3, seed=5)):
        eq = equations(mech, **state)
        x = np.linalg.solve(eq.A, eq.b)
        assert np.max(np.abs(eq.A @ x - eq.b)) <= 1e-12 * np.max(np.abs(eq.b))
        direct = mech.solve(**state)
        assert x[-1] == pytest.approx(direct[mech.efforts[0].name], rel=1e-12)
        values = eq.free_bodies.values
        solved = dict(zip(eq.free_bodies.unknowns, x))
        frictions = [float(values[law.lhs]) for law in eq.free_bodies.laws]
        assert frictions, "a friction law per pair that rubs"
        for law, f in zip(eq.free_bodies.laws, frictions):
            assert f == pytest.approx(direct[str(law.lhs)], abs=1e-12 * max(map(abs, frictions)))
            at = float(law.rhs.subs(values).subs(solved))
            assert at == pytest.approx(f, abs=1e-12 * max(map(abs, frictions)))
        if k:
            continue
        A, b = eq.symbolic()
        An = np.array(A.subs(values).evalf(30), dtype=float)
        bn = np.array(b.subs(values).evalf(30), dtype=float).ravel()
        assert np.max(np.abs(An - eq.A)) <= 1e-13 * np.max(np.abs(eq.A))
        assert np.max(np.abs(bn - eq.b)) <= 1e-13 * np.max(np.abs(eq.b))


@pytest.mark.parametrize("length", [None, 0.05])
def test_each_pair_s_friction_formula_is_its_law(length):
    """The law shown (Pair.friction_formula) equals the one solved (friction_law) at
    random reactions, to 1e-14 relative."""
    rng = np.random.default_rng(1)
    pin, slider = Revolute("B", "B", "1", "2"), Prismatic("P", "C", "1", "4", (0.0, 1.0))
    for _ in range(50):
        a, b, s = rng.uniform(-100, 100), rng.uniform(-10, 10), rng.choice([-1.0, 1.0])
        for pair, radius in ((pin, 0.01), (slider, None)):
            law = pair.friction_law(np, 0.15, radius, length, s, (a, b), 1e-300)[0]
            shown = pair.friction_formula(np, 0.15, radius, length, s, a, b)
            assert shown == pytest.approx(law, rel=1e-14)
