"""The command line prints the seed 000 table and names bad input."""

from __future__ import annotations

import io
from contextlib import redirect_stderr, redirect_stdout

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
