"""Design optimisation (``linkage_fmu.optimize``): the optimum of differential evolution
and of a grid with its polish against a fine brute-force grid through the sweep, the
constraint parser, bad inputs named, no feasible design reported, determinism with a
seed, and a Dask cluster giving the in-process search."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from linkage_fmu.optimize import (
    INFEASIBLE,
    Constraint,
    NoFeasibleDesignError,
    OptimizationResult,
    optimize,
    parse_constraint,
)
from linkage_fmu.sweep import grid, sweep

THETA = np.radians(np.arange(0.0, 360.0, 5.0))  # 72 angles: the same for every search
VARY = {"l_BC": (0.30, 0.45), "l_CD": (0.25, 0.40)}
LIMIT = "gamma_C_min_deg >= 45"
FINE = 121  # values of each parameter in the brute-force grid: steps of 0.00125 m


@pytest.fixture(scope="module")
def brute_force() -> tuple[float, float, pd.DataFrame]:
    """The four-bar at 10 rad/s, l_BC and l_CD varied, Mb_peak minimised subject to
    gamma_C_min_deg >= 45 and valid, over a 121 x 121 grid through ``sweep``: the best
    feasible value, the grid's resolution effect (the largest change of Mb_peak between
    the best feasible design and its eight neighbours, a step of 0.00125 m away), and
    the best design's row. Without the constraint the best is at l_BC = 0.45 with
    gamma_C_min_deg = 41.2: the constraint is active (asserted here)."""
    a, b = (np.linspace(lo, hi, FINE) for lo, hi in VARY.values())
    table = sweep("four_bar", grid(l_BC=a, l_CD=b), THETA, 10.0)
    feasible = table["valid"] & (table["gamma_C_min_deg"] >= 45.0)
    best = table["Mb_peak"].where(feasible).idxmin()
    f = table["Mb_peak"].to_numpy().reshape(FINE, FINE)
    i, j = divmod(best, FINE)
    around = f[max(i - 1, 0):i + 2, max(j - 1, 0):j + 2]
    resolution = float(np.nanmax(np.abs(around - f[i, j])))
    free = table.loc[table["Mb_peak"].where(table["valid"]).idxmin()]
    assert free["l_BC"] == 0.45 and 41.0 < free["gamma_C_min_deg"] < 41.5
    assert abs(table.loc[best, "gamma_C_min_deg"] - 45.0) < 0.1
    return float(f[i, j]), resolution, table


@pytest.mark.parametrize("method, options", [("differential_evolution", {"seed": 1, "maxiter": 30}),
                                             ("grid", {"budget": 400})])
def test_optimum_against_a_fine_brute_force_grid(brute_force, method, options):
    """Reference: the 121 x 121 grid's best feasible Mb_peak (2.375 N.m). Tolerance: the
    grid's resolution effect (about 0.003 N.m, see the fixture) either way. The optimum
    (over 400 to 1000 evaluations, 1/15 to 1/35 of the grid's) is no worse than the grid's
    best by more than that, and no better (the continuous optimum lies within a cell of
    a grid point); its design meets both constraints, lies within the bounds, and its
    row is the sweep's at that design (to the last digit)."""
    ref, resolution, _ = brute_force
    assert 0.0 < resolution < 0.01 * ref
    res = optimize("four_bar", VARY, "Mb_peak", [LIMIT, "valid"], theta=THETA, omega=10.0,
                   method=method, **options)
    assert isinstance(res, OptimizationResult) and res.feasible
    assert ref - resolution <= res.value <= ref + resolution
    assert bool(res.summary["valid"]) and res.summary["gamma_C_min_deg"] >= 45.0
    for name, (lo, hi) in VARY.items():
        assert lo <= res.design[name] <= hi
    again = sweep("four_bar", pd.DataFrame([res.design]), THETA, 10.0).iloc[0]
    assert again["Mb_peak"] == res.value and again["gamma_C_min_deg"] == res.summary[
        "gamma_C_min_deg"]
    assert res.evaluations == res.history["evaluations"].iloc[-1] < FINE ** 2 / 10
    best = res.history["best"].to_numpy()
    assert np.all(np.diff(best[~np.isnan(best)]) <= 0.0)  # the best so far never worsens
    assert best[-1] == res.value


def test_maximising_on_a_grid_is_the_sweeps_best_of_the_same_grid():
    """"-gamma_C_min_deg" maximises the transmission angle's distance from a toggle over
    l_AB in [0.05, 0.15], l_AD in [0.35, 0.45] without a polish: reference, the largest
    gamma_C_min_deg of ``sweep`` over the same 7 x 7 grid (equal exactly: the same
    designs)."""
    vary = {"l_AB": (0.05, 0.15), "l_AD": (0.35, 0.45)}
    res = optimize("four_bar", vary, "-gamma_C_min_deg", ["valid"], theta=THETA, omega=10.0,
                   method="grid", budget=50, polish=False)
    table = sweep("four_bar", grid(l_AB=np.linspace(0.05, 0.15, 7),
                                   l_AD=np.linspace(0.35, 0.45, 7)), THETA, 10.0)
    best = table.loc[table["gamma_C_min_deg"].idxmax()]
    assert res.evaluations == 49 and len(res.history) == 1
    assert res.value == best["gamma_C_min_deg"] == res.history["best"].iloc[0]
    assert res.design == {"l_AB": best["l_AB"], "l_AD": best["l_AD"]}


def test_the_same_seed_gives_the_same_search():
    """Determinism: two runs with seed 7 give equal histories and designs; seed 8 takes
    another path (its first generation differs)."""
    kw = dict(theta=THETA, omega=10.0, maxiter=4, polish=False)
    a = optimize("four_bar", VARY, "Mb_peak", [LIMIT], seed=7, **kw)
    b = optimize("four_bar", VARY, "Mb_peak", [LIMIT], seed=7, **kw)
    c = optimize("four_bar", VARY, "Mb_peak", [LIMIT], seed=8, **kw)
    assert a.design == b.design and a.value == b.value
    pd.testing.assert_frame_equal(a.history, b.history)
    assert a.history["best"].iloc[0] != c.history["best"].iloc[0]


def test_no_feasible_design_is_an_error_holding_the_closest():
    """gamma_C_min_deg <= 5 (a toggle within 5 deg) is met by no design of the four-bar that
    assembles over these bounds (its smallest is 17 deg on a 4 x 4 grid, see
    ``sweep``): an error naming the constraint, with the design that broke it least."""
    vary = {"l_AB": (0.05, 0.1), "l_BC": (0.3, 0.4)}
    table = sweep("four_bar", grid(l_AB=np.linspace(0.05, 0.1, 4),
                                   l_BC=np.linspace(0.3, 0.4, 4)), THETA, 10.0)
    assert table["gamma_C_min_deg"].min() > 5.0 and table["valid"].all()
    with pytest.raises(NoFeasibleDesignError, match=r"breaks gamma_C_min_deg <= 5") as err:
        optimize("four_bar", vary, "Mb_peak", ["gamma_C_min_deg <= 5", "valid"], theta=THETA,
                 omega=10.0, method="grid", budget=16, polish=False)
    res = err.value.result
    assert not res.feasible and res.evaluations == 16
    assert res.summary["gamma_C_min_deg"] == table["gamma_C_min_deg"].min()
    assert res.history["best"].isna().all()


@pytest.mark.parametrize("vary, minimize, subject_to, options, error, words", [
    ({"l_XY": (0.1, 0.2)}, "Mb_peak", [], {}, TypeError, "no parameter 'l_XY'"),
    ({"l_AB": (0.15, 0.05)}, "Mb_peak", [], {}, ValueError,
     "l_AB needs lo < hi, got lo = 0.15, hi = 0.05"),
    ({"l_AB": (0.1, 0.1)}, "Mb_peak", [], {}, ValueError, "l_AB needs lo < hi"),
    ({"l_AB": (-0.1, 0.1)}, "Mb_peak", [], {}, ValueError, "l_AB must be > 0"),
    ({"m2": (-1.0, 2.0)}, "Mb_peak", [], {}, ValueError, "m2 must be >= 0"),
    ({"branch": (-1, 1)}, "Mb_peak", [], {}, ValueError, "branch is a branch parameter"),
    ({"l_AB": (0.1,)}, "Mb_peak", [], {}, ValueError, "l_AB needs bounds (lo, hi)"),
    ({}, "Mb_peak", [], {}, ValueError, "vary must map one or more parameters"),
    ({"l_AB": (0.05, 0.15)}, "Mb_peek", [], {}, ValueError,
     "'Mb_peek' is not a numeric summary of the sweep of four_bar; they are: "
     "unassembled, first_unassembled_deg, locked, first_locked_deg, Mb_peak"),
    ({"l_AB": (0.05, 0.15)}, "valid", [], {}, ValueError, "'valid' is not a numeric summary"),
    ({"l_AB": (0.05, 0.15)}, "Mb_peak", ["gamma_X_min_deg >= 40"], {}, ValueError,
     "constraint 'gamma_X_min_deg >= 40': 'gamma_X_min_deg' is not a summary"),
    ({"l_AB": (0.05, 0.15)}, "Mb_peak", ["F21_peak == 4"], {}, ValueError,
     "constraint 'F21_peak == 4': expected NAME OP VALUE"),
    ({"l_AB": (0.05, 0.15)}, "Mb_peak", [], {"method": "nelder"}, ValueError,
     "method 'nelder': expected one of differential_evolution, grid"),
    ({"l_AB": (0.05, 0.15)}, "Mb_peak", [], {"budget": 10}, ValueError,
     "budget 10 is less than one population of differential evolution (15"),
    ({"l_AB": (0.05, 0.15), "l_BC": (0.3, 0.4)}, "Mb_peak", [],
     {"budget": 3, "method": "grid"}, ValueError, "it needs two values of each, 4 designs"),
    ({"l_AB": (0.05, 0.15)}, "Mb_peak", [], {"popsize": 0}, ValueError,
     "popsize must be an integer >= 1, got 0"),
    ({"l_AB": (0.05, 0.15)}, "Mb_peak", [], {"tol": -0.01}, ValueError,
     "tol must be a number >= 0, got -0.01"),
    ({"l_AB": (0.05, 0.15)}, "Mb_peak", [], {"tol": float("nan")}, ValueError,
     "tol must be a number >= 0, got nan"),
    ({"l_AB": (0.05, 0.15)}, "Mb_peak", [], {"F_P": 3.0}, TypeError, "F_P"),
])
def test_bad_input_is_an_error_naming_it(vary, minimize, subject_to, options, error, words):
    """Each bad input raises before any search, its message naming the input and why."""
    with pytest.raises(error) as err:
        optimize("four_bar", vary, minimize, subject_to, theta=THETA, **options)
    assert words in str(err.value)


@pytest.mark.parametrize("text, expected", [
    ("gamma_C_min_deg >= 40", ("gamma_C_min_deg", ">=", 40.0)),
    ("F21_peak<=500", ("F21_peak", "<=", 500.0)),
    ("  eta_min > 0.9 ", ("eta_min", ">", 0.9)),
    ("P_loss_mean < 1.5e-3", ("P_loss_mean", "<", 0.0015)),
    ("shake_M_peak <= -2", ("shake_M_peak", "<=", -2.0)),
    ("valid", ("valid", None, None)),
    (("Mb_peak", "<", 3), ("Mb_peak", "<", 3.0)),
])
def test_constraint_parser_reads_each_operator(text, expected):
    assert parse_constraint(text) == Constraint(*expected)


@pytest.mark.parametrize("text, words", [
    ("F21_peak == 500", "expected NAME OP VALUE"),
    ("F21_peak => 500", "expected NAME OP VALUE"),
    ("500 >= F21_peak", "expected NAME OP VALUE"),
    ("F21_peak <=", "expected NAME OP VALUE"),
    ("__import__('os').system('true') <= 1", "expected NAME OP VALUE"),
    ("F21_peak <= abc", "the value 'abc' is not a finite number"),
    ("F21_peak <= nan", "the value 'nan' is not a finite number"),
    ("F21_peak <= inf", "the value 'inf' is not a finite number"),
    ("F21_peak <= 1 + 2", "expected NAME OP VALUE"),
    ("valid == 1", "expected NAME OP VALUE"),
    (("Mb_peak", "==", 3), "expected (name, op, value)"),
])
def test_constraint_parser_refuses_other_text_naming_it(text, words):
    with pytest.raises(ValueError) as err:
        parse_constraint(text)
    assert words in str(err.value) and repr(text) in str(err.value)


def test_constraint_satisfied_and_violation():
    """>= 40 on [39, 40, 41, NaN]: met at 40 and 41; violated by 1/40 (relative to the
    bound) at 39, by 1 at NaN. > 40 is not met at 40 (the penalty still ranks it above
    every feasible design, at INFEASIBLE). ``valid``: violated by the fraction of the
    angles that do not assemble or that friction locks."""
    table = pd.DataFrame({"mu": [39.0, 40.0, 41.0, math.nan], "valid": [True, False,
                                                                           False, False],
                          "unassembled": [0, 18, 0, 72], "locked": [0, 0, 9, 0]})
    c = parse_constraint("mu >= 40")
    assert c.satisfied(table).tolist() == [False, True, True, False]
    np.testing.assert_array_equal(c.violation(table, 72), [1 / 40, 0.0, 0.0, 1.0])
    assert parse_constraint("mu > 40").satisfied(table).tolist() == [False, False, True,
                                                                     False]
    np.testing.assert_array_equal(parse_constraint("mu <= 0").violation(table, 72),
                                  [39.0, 40.0, 41.0, 1.0])
    v = parse_constraint("valid")
    assert v.satisfied(table).tolist() == [True, False, False, False]
    np.testing.assert_array_equal(v.violation(table, 72), [0.0, 0.25, 0.125, 1.0])
    assert INFEASIBLE > 1e15


def test_on_a_local_dask_cluster_the_search_is_the_same():
    """Two worker processes, a generation split between them: the same history and
    design as in this process (the sweep gives the same table on Dask)."""
    distributed = pytest.importorskip("dask.distributed")
    kw = dict(theta=THETA, omega=10.0, maxiter=3, seed=3)
    here = optimize("four_bar", VARY, "Mb_peak", [LIMIT, "valid"], **kw)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        there = optimize("four_bar", VARY, "Mb_peak", [LIMIT, "valid"], scheduler=client,
                         **kw)
    assert there.design == here.design and there.value == here.value
    pd.testing.assert_frame_equal(there.history, here.history)
