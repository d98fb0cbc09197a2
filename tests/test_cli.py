"""The command line prints the seed 000 table and names bad input."""

from __future__ import annotations

import io
from contextlib import redirect_stderr, redirect_stdout

import numpy as np
import pandas as pd

from linkage_fmu.cli import main


def test_table_csv_reproduces_seed_quoted_mb():
    out = io.StringIO()
    with redirect_stdout(out):
        assert main(["table", "scotch_yoke", "--n", "7", "--csv"]) == 0
    df = pd.read_csv(io.StringIO(out.getvalue()), index_col="theta")
    assert len(df) == 7 and df["Mb"].iloc[0] == 40.0  # seed 000, theta = 0: Mb = 40.0000


def test_bad_parameter_is_reported_not_raised():
    err = io.StringIO()
    with redirect_stderr(err):
        assert main(["table", "four_bar", "--set", "l_AB=-1"]) == 2
    assert "l_AB must be > 0" in err.getvalue()


def test_table_to_csv_and_parquet_files_in_degrees(tmp_path):
    """-o FILE.csv and FILE.parquet hold the same rows (in pieces of 50,000: 120,001
    rows cross two boundaries), indexed in degrees, equal to the solver's values; any
    other suffix is an error naming the accepted ones."""
    from linkage_fmu import presets

    err = io.StringIO()
    with redirect_stderr(err):
        for name in ("t.csv", "t.parquet"):
            assert main(["table", "four_bar", "--theta", "0:360:0.003", "--deg", "--omega",
                         "10", "-o", str(tmp_path / name)]) == 0
        assert main(["table", "four_bar", "-o", str(tmp_path / "t.xlsx")]) == 2
    assert "must end in .csv or .parquet" in err.getvalue()
    csv = pd.read_csv(tmp_path / "t.csv", index_col="theta_deg")
    parquet = pd.read_parquet(tmp_path / "t.parquet")
    assert len(csv) == 120_001 and len(parquet) == 120_001
    theta = np.radians(0.003 * np.arange(120_001))  # as --theta 0:360:0.003 --deg makes them
    np.testing.assert_allclose(csv.index.to_numpy(), np.degrees(theta), rtol=1e-15)
    ref = presets.get("four_bar").solve(theta, 10.0)
    for name in ("Mb", "F21x", "mu_C"):
        np.testing.assert_array_equal(csv[name].to_numpy(), ref[name])  # CSV keeps 17 digits
        np.testing.assert_array_equal(parquet[name].to_numpy(), ref[name])


def test_sweep_command_grid_and_samples(tmp_path):
    """``sweep --grid`` makes every combination and ``--samples`` reads designs from a
    file; both give the library's sweep table."""
    from linkage_fmu.sweep import grid, sweep

    out = io.StringIO()
    with redirect_stdout(out), redirect_stderr(io.StringIO()):
        assert main(["sweep", "four_bar", "--grid", "l_AB=0.08,0.1", "--grid",
                     "m2=1:3:1", "--n", "72", "--omega", "10", "--load", "3"]) == 0
    table = pd.read_csv(io.StringIO(out.getvalue()))
    theta = np.linspace(0.0, 2.0 * np.pi, 72, endpoint=False)
    expected = sweep("four_bar", grid(l_AB=[0.08, 0.1], m2=[1.0, 2.0, 3.0]), theta, 10.0,
                     0.0, 3.0)
    assert len(table) == 6
    for name in ("Mb_peak", "Mb_rms", "F21_peak", "mu_C_min_deg"):
        np.testing.assert_allclose(table[name], expected[name], rtol=1e-15)
    expected.iloc[:, :2].to_csv(tmp_path / "designs.csv", index=False)
    with redirect_stderr(io.StringIO()):
        assert main(["sweep", "four_bar", "--samples", str(tmp_path / "designs.csv"), "--n",
                     "72", "--omega", "10", "--load", "3", "-o", str(tmp_path / "s.csv")]) == 0
    again = pd.read_csv(tmp_path / "s.csv")
    np.testing.assert_allclose(again["Mb_peak"], expected["Mb_peak"], rtol=1e-15)


def test_plot_command_writes_each_picture(tmp_path):
    """Each --what writes a PNG (or SVG); the drawing's data are tested in test_plot.py.
    A linkage picture needs one angle; an unknown kind is an error naming the kinds."""
    import pytest

    pytest.importorskip("matplotlib")
    err = io.StringIO()
    with redirect_stderr(err):
        for what, name in ((["torque"], "t.png"), (["polar", "F21"], "p.svg"),
                           (["mu"], "m.png")):
            assert main(["plot", "four_bar", "--what", *what, "--omega", "10",
                         "-o", str(tmp_path / name)]) == 0
        assert main(["plot", "crank_shaper", "--what", "linkage", "--theta-deg", "60",
                     "-o", str(tmp_path / "l.png")]) == 0
        assert main(["plot", "four_bar", "--what", "linkage", "-o", str(tmp_path / "x.png")]) == 2
        assert main(["plot", "four_bar", "--what", "pie", "-o", str(tmp_path / "x.png")]) == 2
    assert "needs one angle" in err.getvalue() and "expected torque [OUTPUT]" in err.getvalue()
    for name in ("t.png", "m.png", "l.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert b"<svg" in (tmp_path / "p.svg").read_bytes()[:400]
