"""The labelled equilibrium equations A x = b (linkage_fmu.equations) against the scotch
yoke worked example's MATLAB function F(x), whose values at 60, 150 and 220 deg it
quotes to four decimals (lAB 0.1 m, h2 0.08 m, 10 rad/s, G2 40 N, G3 100 N, Fr 400 N).

Its x axis points the other way (its FR12x is our -Fx_B), and it writes the guide's
reaction as two forces FR4, FR4' a distance h2 apart (our couple M_guide = -FR4 h2).
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
    """Three rows per moving link about its centre of mass, a column per reaction
    component and effort; the solution equals ``solve(method="direct")`` to 1e-12,
    for a linkage driven by time too."""
    four = presets.get("four_bar")
    eq = equations(four, 0.3, 10.0, 5.0, load=2.0)
    sol = four.solve(0.3, 10.0, 5.0, load=2.0, method="direct")
    assert eq.rows[3:6] == ("link 2: ΣFx", "link 2: ΣFy", "link 2: ΣM about S2")
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
    assert "link 2: ΣM about S2" in text and "Mb_A = " in text
    assert eq.to("markdown").splitlines()[2] == "| i | equation | a(i, j) | b(i) |"


def test_what_it_cannot_write_is_refused_with_the_reason():
    yoke = presets.get("scotch_yoke")
    with pytest.raises(InputError, match="equations are of one state"):
        equations(yoke, [0.1, 0.2], 10.0)
    with pytest.raises(InputError, match="format 'latex': the formats are text, markdown"):
        equations(yoke, 0.1, 10.0).to("latex")
    with pytest.raises(InputError, match="with friction are not written yet"):
        equations(presets.get("scotch_yoke", mu_slot=0.1), 0.1, 10.0)
