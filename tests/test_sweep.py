"""Design sweeps (``linkage_fmu.sweep``): every summary against the direct solver of
that design's linkage, invalid and unassemblable designs reported, structures swept,
and a 2-worker Dask LocalCluster giving exactly the in-process table."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from linkage_fmu import presets, solver
from linkage_fmu.sweep import grid, sweep

THETA = np.linspace(0.0, 2.0 * math.pi, 90, endpoint=False)
REL = 1e-12


def expected(preset: str, params: dict, omega: float, load: float) -> dict:
    """The summaries of one design from the direct (LU) solver of its own linkage."""
    mech = presets.get(preset, **params)
    sol = mech.solve(THETA, omega, 0.0, load, method="direct")
    ok = sol.valid
    locked = sol.status == solver.LOCKED
    other = ~ok & ~locked
    out = {"unassembled": int(other.sum()),
           "first_unassembled_deg": float(np.degrees(THETA[other][0])) if other.any()
           else math.nan,
           "locked": int(locked.sum()),
           "first_locked_deg": float(np.degrees(THETA[locked][0])) if locked.any()
           else math.nan}
    if ok.any():
        e = sol[mech.effort.name][ok]
        out[f"{mech.effort.name}_peak"] = np.max(np.abs(e))
        out[f"{mech.effort.name}_rms"] = np.sqrt(np.mean(e * e))
        for name in mech.output_names:
            if name.endswith("x") and name[:-1] + "y" in mech.output_names:
                out[name[:-1].rstrip("_") + "_peak"] = np.max(np.hypot(sol[name][ok],
                                                           sol[name[:-1] + "y"][ok]))
        if "P_loss" in mech.output_names:
            loss = sol["P_loss"][ok]
            out["P_loss_peak"] = np.max(loss)
            out["P_loss_mean"] = np.mean(loss)
            eta = sol["eta"][ok]  # NaN where no power enters: skipped
            out["eta_min"] = np.min(eta[~np.isnan(eta)]) if (~np.isnan(eta)).any() else math.nan
            for name in mech.output_names:
                if name.startswith(("Mf_", "Ff_")):
                    out[name + "_peak"] = np.max(np.abs(sol[name][ok]))
        for name in mech.diagnostic_names:
            if name.startswith("gamma_"):
                gamma = np.degrees(sol[name][ok])
                out[name + "_min_deg"] = np.min(np.minimum(gamma, 180.0 - gamma))
    return out


def check_rows(preset: str, table: pd.DataFrame, omega: float, load: float) -> None:
    for i, row in table.iterrows():
        params = {k: row[k] for k in table.columns if k in presets.get(preset).parameters}
        if row["problem"]:
            continue
        for key, value in expected(preset, params, omega, load).items():
            if isinstance(value, float) and math.isnan(value):
                assert math.isnan(row[key]), (i, key)
            elif key in ("unassembled", "locked"):
                assert row[key] == value, (i, key)
            else:
                assert abs(row[key] - value) <= REL * max(abs(value), 1.0), (i, key, row[key],
                                                                             value)


def test_grid_is_every_combination():
    g = grid(l_AB=[0.1, 0.2], m2=[1.0, 2.0, 3.0])
    assert g.shape == (6, 2)
    assert sorted(map(tuple, g.to_numpy())) == [(a, b) for a in (0.1, 0.2)
                                                 for b in (1.0, 2.0, 3.0)]


def test_summaries_equal_the_direct_solver_of_each_design():
    """A four-bar grid that includes designs which cannot assemble over part of the
    revolution (l_AB = 0.3) and an invalid one (a negative length): each valid design's
    peak and RMS torque, pin-force peaks and minimum transmission angle equal the
    direct solver's to 1e-12; the first angle that cannot be assembled is reported; the
    invalid design says why and has no numbers."""
    designs = grid(l_AB=[0.08, 0.1, 0.3, -0.1], m2=[1.0, 4.0])
    table = sweep("four_bar", designs, THETA, 10.0, 0.0, 3.0)
    assert list(table.columns[:2]) == ["l_AB", "m2"] and len(table) == 8
    bad = table["l_AB"] < 0
    assert (~table.loc[bad, "valid"]).all()
    assert table.loc[bad, "problem"].str.contains("l_AB must be > 0").all()
    partial = table["l_AB"] == 0.3
    assert (~table.loc[partial, "valid"]).all() and (table.loc[partial, "unassembled"] > 0).all()
    assert table.loc[~bad & ~partial, "valid"].all()
    check_rows("four_bar", table, 10.0, 3.0)


def test_a_structure_parameter_can_be_swept():
    """Both assembly modes of the crank shaper, and the slider-crank's offset: the same
    summaries as each design's own direct solve."""
    table = sweep("crank_shaper", grid(branch=[1, -1], l_DE=[0.25, 0.3]), THETA, 5.0, 0.0,
                  100.0)
    assert table["valid"].all()
    check_rows("crank_shaper", table, 5.0, 100.0)
    table = sweep("slider_crank", {"e": [0.0, 0.01, -0.02]}, THETA, 20.0, 0.0, 50.0)
    check_rows("slider_crank", table, 20.0, 50.0)


def test_friction_summaries_equal_the_direct_solver_of_each_design():
    """Designs with and without friction in one sweep (friction with every mu 0 is
    solved without it, so they need two kernels): each design's P_loss_peak,
    P_loss_mean, eta_min and friction peaks equal numpy's over its own direct solve to
    1e-12; a design with every mu 0 loses nothing (P_loss 0, eta 1)."""
    designs = grid(mu_guide=[0.0, 0.1], mu_A=[0.0, 0.1], r_A=[0.01, 0.02])
    table = sweep("slider_crank", designs, THETA, 10.0, 0.0, 100.0)
    assert table["valid"].all()
    for name in ("P_loss_peak", "P_loss_mean", "eta_min", "Ff_guide_peak", "Mf_A_peak"):
        assert name in table.columns
    check_rows("slider_crank", table, 10.0, 100.0)
    none = (table["mu_guide"] == 0.0) & (table["mu_A"] == 0.0)
    assert (table.loc[none, "P_loss_peak"] == 0.0).all()
    assert (table.loc[none, "P_loss_mean"] == 0.0).all()
    assert (table.loc[none, "eta_min"] == 1.0).all()
    assert (table.loc[~none, "P_loss_mean"] > 0.0).all()
    # a four-bar driven clockwise, friction in every pin
    designs = grid(mu_A=[0.1], r_A=[0.01], mu_B=[0.0, 0.15], r_B=[0.01], mu_C=[0.1],
                   r_C=[0.005], drive=[-1.0])
    table = sweep("four_bar", designs, THETA, -10.0, 0.0, 3.0)
    assert table["valid"].all()
    check_rows("four_bar", table, -10.0, 3.0)


def test_self_locked_angles_are_counted_apart_from_unassembled_ones():
    """The massless slider-crank (l_OA = 0.18, l_AB = 0.2: it assembles everywhere) with
    guide friction mu 0.6 driven against its load locks where cos(phi) - mu |sin(phi)| s
    < 0 (s the sign of the piston's velocity: the hand solution's denominator, see
    test_friction): those angles are ``locked``, ``unassembled`` is 0, and the design is
    not valid; the same with mu 0 has none; l_OA = 0.25 > l_AB also cannot be assembled
    over part of the revolution. Reference: that count, and each design's direct solve
    (its status LOCKED), exactly; the summaries in C and with numpy."""
    base = dict(m1=0.0, J1=0.0, m2=0.0, J2=0.0, m3=0.0, g=0.0, l_AB=0.2)
    designs = grid(mu_guide=[0.0, 0.6], l_OA=[0.18, 0.25])
    for fused in (True, False):
        table = sweep("slider_crank", designs.assign(**base), THETA, 5.0, 0.0, 250.0,
                      fused=fused)
        check_rows("slider_crank", table, 5.0, 250.0)
        short = table["l_OA"] == 0.18
        sphi = -0.18 * np.sin(THETA) / 0.2
        cphi = np.sqrt(1.0 - sphi * sphi)
        s = np.sign(0.18 * np.sin(np.arctan2(sphi, cphi) - THETA) / cphi)  # omega > 0
        hand = cphi - 0.6 * np.abs(sphi) * s < 0.0
        assert 0 < hand.sum() < THETA.size
        row = table[short & (table["mu_guide"] == 0.6)].iloc[0]
        assert (row["unassembled"], row["locked"]) == (0, int(hand.sum()))
        assert row["first_locked_deg"] == np.degrees(THETA[hand][0])
        assert math.isnan(row["first_unassembled_deg"]) and not row["valid"]
        row = table[short & (table["mu_guide"] == 0.0)].iloc[0]
        assert (row["unassembled"], row["locked"], row["valid"]) == (0, 0, True)
        assert math.isnan(row["first_locked_deg"])
        assert (table.loc[~short, "unassembled"] > 0).all()


def test_bad_arguments_name_themselves():
    with pytest.raises(TypeError, match="four_bar has no parameter 'lAB'"):
        sweep("four_bar", {"lAB": [0.1]})
    with pytest.raises(ValueError, match="omega must be finite"):
        sweep("four_bar", {"l_AB": [0.1]}, THETA, math.nan)


def test_a_two_worker_local_cluster_gives_the_in_process_table():
    """The same designs on a 2-worker Dask LocalCluster (processes), in chunks of a few
    designs each: the table equals the in-process one exactly."""
    distributed = pytest.importorskip("dask.distributed")
    designs = grid(l_AB=np.linspace(0.05, 0.3, 12), l_CD=[0.25, 0.3, 0.35])
    here = sweep("four_bar", designs, THETA, 10.0, 0.0, 3.0, states_per_task=500)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        there = sweep("four_bar", designs, THETA, 10.0, 0.0, 3.0, scheduler=client,
                      states_per_task=500)
    pd.testing.assert_frame_equal(here, there)
    assert (~here["valid"]).any() and here["valid"].any()


@pytest.mark.parametrize("preset", presets.names())
def test_fused_summaries_equal_numpy_over_the_materialised_block(preset):
    """On every preset, the summaries computed in the C (the default) against the
    reference, numpy over every output of every state (``fused=False``), to 1e-12
    relative with NaN in the same places and the same columns in the same order: the
    first length at its default, 3 times it (angles that cannot be assembled where the
    linkage does not turn) and negative (an invalid design), each without and with
    friction in the crank's pin (mu_A = 0.1, r_A = 0.01); two threads give the table one
    thread gives."""
    mech = presets.get(preset)
    length = next(p for p in mech.description.parameter_specs() if p.kind == "length")
    designs = grid(**{length.name: [length.default, 3.0 * length.default, -length.default]},
                   mu_A=[0.0, 0.1], r_A=[0.01])
    reference = sweep(preset, designs, THETA, 10.0, 0.0, 3.0, fused=False)
    fused = sweep(preset, designs, THETA, 10.0, 0.0, 3.0, threads=1)
    pd.testing.assert_frame_equal(fused, reference, check_exact=False, rtol=REL, atol=0.0)
    assert (~fused["valid"]).any() and fused["valid"].any()
    assert fused["P_loss_mean"].max() > 0.0
    pd.testing.assert_frame_equal(sweep(preset, designs, THETA, 10.0, 0.0, 3.0, threads=2),
                                  fused, check_exact=True)


def test_fused_four_bar_with_a_crank_too_long_to_assemble():
    """Four-bars that cannot be assembled over part of the revolution (l_AB = 0.3) or
    any of it (l_AB = 2), both assembly modes, with friction: the C's summaries equal
    numpy's over the materialised block to 1e-12 (NaN summaries where no angle
    assembles, every angle counted unassembled, the first at 0 deg)."""
    designs = grid(l_AB=[0.1, 0.3, 2.0], branch=[1, -1], mu_B=[0.0, 0.15], r_B=[0.01])
    reference = sweep("four_bar", designs, THETA, 10.0, 0.0, 3.0, fused=False)
    fused = sweep("four_bar", designs, THETA, 10.0, 0.0, 3.0)
    pd.testing.assert_frame_equal(fused, reference, check_exact=False, rtol=REL, atol=0.0)
    never = fused[fused["l_AB"] == 2.0]
    assert (never["unassembled"] == THETA.size).all()
    assert (never["first_unassembled_deg"] == 0.0).all() and never["Mb_peak"].isna().all()
    partial = fused[fused["l_AB"] == 0.3]
    assert ((partial["unassembled"] > 0) & (partial["unassembled"] < THETA.size)).all()
    assert partial["Mb_peak"].notna().all()


def test_threads_must_be_a_positive_integer():
    with pytest.raises(ValueError, match="threads must be a positive integer, got 0"):
        sweep("four_bar", {"l_AB": [0.1]}, THETA, threads=0)


def test_a_column_of_numbers_and_text_with_units():
    """A column mixing text with units and numbers: "100 mm" is the design 0.1 (the
    same row as the number 0.1, to the bit, and as the direct solver's), an invalid one
    says why, and the fused and numpy paths give one table."""
    designs = {"l_AB": ["100 mm", 0.1, "-1 m", 0.08]}
    fused = sweep("four_bar", designs, THETA, 10.0, 0.0, 3.0)
    reference = sweep("four_bar", designs, THETA, 10.0, 0.0, 3.0, fused=False)
    pd.testing.assert_frame_equal(fused, reference, check_exact=False, rtol=REL, atol=0.0)
    summaries = fused.columns[fused.columns.get_loc("valid"):]
    pd.testing.assert_series_equal(fused.loc[0, summaries], fused.loc[1, summaries],
                                   check_names=False)
    assert fused.loc[2, "problem"].startswith("l_AB must be > 0")
    assert fused.loc[[0, 1, 3], "valid"].all()
    ref = expected("four_bar", {"l_AB": 0.08}, 10.0, 3.0)
    assert abs(fused.loc[3, "Mb_peak"] - ref["Mb_peak"]) <= REL * ref["Mb_peak"]


@pytest.mark.parametrize("preset, parameter", [("six_bar", "l_OA"), ("slider_crank", "l_AB"),
                                               ("four_bar", "l_BC")])
def test_a_parameter_set_the_parameter_step_cannot_build(preset, parameter):
    """A length of 1e300 passes the parameter's own check but not the kernel's parameter
    step (a check of it fails, a value it computes overflows, or in Python its square
    raises): the design's row says the set cannot be built, counts every angle
    unassembled and has NaN summaries, in the C's table and numpy's alike; the default
    beside it is valid."""
    mech = presets.get(preset)
    designs = {parameter: [1e300, mech.parameters[parameter]]}
    fused = sweep(preset, designs, THETA, 10.0, 0.0, 3.0)
    reference = sweep(preset, designs, THETA, 10.0, 0.0, 3.0, fused=False)
    pd.testing.assert_frame_equal(fused, reference, check_exact=False, rtol=REL, atol=0.0)
    assert fused.loc[0, "problem"].startswith("the parameter set cannot be built")
    assert fused.loc[0, "unassembled"] == THETA.size and not fused.loc[0, "valid"]
    assert math.isnan(fused.loc[0, f"{mech.effort.name}_peak"])
    assert fused.loc[1, "valid"] and fused.loc[1, "problem"] == ""


def test_a_design_whose_outputs_overflow_is_invalid_with_a_reason():
    """The slotted lever with J2 = 1e308 assembles and is not locked at any angle, but
    its arithmetic overflows: the C's table said valid, with Mb_rms = inf and no reason.
    Now the row is invalid and says why (numpy's table refused the set already: its
    parameter step overflows in Python); the default beside it is valid. A coefficient
    of friction of 1e308 is refused, naming it."""
    for fused in (True, False):
        table = sweep("slotted_lever", {"J2": [1e308, 0.3]}, THETA, 10.0, fused=fused)
        assert not table.loc[0, "valid"] and table.loc[0, "problem"], fused
        assert table.loc[1, "valid"] and table.loc[1, "problem"] == "", fused
        friction = sweep("slotted_lever", {"mu_slot": [1e308]}, THETA, 10.0, fused=fused)
        assert friction.loc[0, "problem"].startswith("mu_slot must be <= 1000.0"), fused
    fused = sweep("slotted_lever", {"J2": [1e308]}, THETA, 10.0)
    assert fused.loc[0, "problem"] == ("the outputs overflow float64: a parameter is too "
                                       "large in magnitude")


def test_no_designs_and_no_angles():
    """No design: an empty table of the designs' columns (it raised KeyError 'valid');
    no angle: a ValueError naming theta (the summaries were taken over nothing)."""
    table = sweep(presets.get("four_bar"), pd.DataFrame({"l_AB": []}),
                  np.linspace(0.0, 6.0, 4), 10.0)
    assert table.empty and list(table.columns)[:1] == ["l_AB"]
    with pytest.raises(ValueError, match="theta must hold at least one crank angle"):
        sweep(presets.get("four_bar"), {"l_AB": [0.1]}, [], 10.0)



def forget_kernels():
    """Empty the per-process caches of the sweep's structures and of the warning that
    there is no compiler."""
    from linkage_fmu import sweep as module
    from linkage_fmu.kernels import compiled

    module._structure.cache_clear()
    compiled._no_compiler_warning.cache_clear()


def test_without_a_compiler_a_sweep_solves_each_design_on_numpy(monkeypatch):
    """Without a C compiler (CC names none: how the package chooses one,
    ``ccompiler.find_compiler``) a sweep, which raised a RuntimeError, builds and solves
    each design on numpy, after the library's one warning: its table has the compiled
    sweep's rows and columns, each design's summaries those of its own direct solve
    (check_rows, 1e-12), friction's locked angles counted apart, a design the parameters
    refuse refused with its reason, as the compiled sweep does."""
    base = dict(m1=0.0, J1=0.0, m2=0.0, J2=0.0, m3=0.0, g=0.0, l_AB=0.2)
    designs = grid(mu_guide=[0.0, 0.6], l_OA=[0.18, 0.25, -1.0]).assign(**base)
    compiled_table = sweep("slider_crank", designs, THETA, 5.0, 0.0, 250.0)
    forget_kernels()
    monkeypatch.setenv("CC", "no-such-c-compiler")
    try:
        with pytest.warns(RuntimeWarning, match="no C compiler found"):
            table = sweep("slider_crank", designs, THETA, 5.0, 0.0, 250.0)
    finally:
        monkeypatch.undo()
        forget_kernels()
    assert list(table.columns) == list(compiled_table.columns)
    check_rows("slider_crank", table, 5.0, 250.0)
    for name in ("locked", "unassembled"):  # NaN in the refused design's row
        np.testing.assert_array_equal(table[name].to_numpy(float),
                                      compiled_table[name].to_numpy(float))
    assert table["locked"].max() > 0 and table["unassembled"].max() > 0
    refused = table["l_OA"] == -1.0
    assert table.loc[refused, "problem"].str.contains("l_OA must be > 0").all()
    assert table["problem"].tolist() == compiled_table["problem"].tolist()
