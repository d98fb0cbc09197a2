"""The command line prints the table of the scotch yoke worked example and names bad input."""

from __future__ import annotations

import io
import math
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from linkage_fmu.cli import main


def test_table_csv_reproduces_the_worked_example_quoted_mb():
    out = io.StringIO()
    with redirect_stdout(out):
        assert main(["table", "scotch_yoke", "--n", "7", "--csv"]) == 0
    df = pd.read_csv(io.StringIO(out.getvalue()), index_col="theta")
    # the scotch yoke worked example, theta = 0: Mb = 40.0000
    assert len(df) == 7 and df["Mb"].iloc[0] == 40.0


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
    for name in ("Mb", "F21x", "gamma_C"):
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
    for name in ("Mb_peak", "Mb_rms", "F21_peak", "gamma_C_min_deg"):
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
                           (["gamma"], "m.png"), (["shaking"], "s.png"), (["speed"], "v.png"),
                           (["loss"], "f.png")):
            assert main(["plot", "four_bar", "--what", *what, "--omega", "10",
                         "-o", str(tmp_path / name)]) == 0
        assert main(["plot", "crank_shaper", "--what", "linkage", "--theta-deg", "60",
                     "-o", str(tmp_path / "l.png")]) == 0
        assert main(["plot", "four_bar", "--what", "linkage", "-o", str(tmp_path / "x.png")]) == 2
        assert main(["plot", "four_bar", "--what", "pie", "-o", str(tmp_path / "x.png")]) == 2
    assert "needs one angle" in err.getvalue() and "expected torque [OUTPUT]" in err.getvalue()
    assert "linkage, gamma, shaking, speed or loss" in err.getvalue()
    for name in ("t.png", "m.png", "l.png", "s.png", "v.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert b"<svg" in (tmp_path / "p.svg").read_bytes()[:400]


def run(argv: list[str]) -> tuple[int, str, str]:
    """Exit status, standard output and standard error of the command line."""
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main(argv)
    return status, out.getvalue(), err.getvalue()


def test_values_with_units_and_expressions_on_the_command_line():
    """--set, --omega and a load take units and expressions, as a description file does:
    the slider-crank with gamma = pi/2, l_AB = 200 mm at 1800 rpm and a load of 0.2 kN
    equals the library's solve with those values in SI (to the last digit of the CSV)."""
    from linkage_fmu import presets

    status, out, _ = run(["table", "slider_crank", "--set", "gamma=pi/2", "--set",
                          "l_AB=200mm", "--theta", "0.5,1.5", "--omega", "1800 rpm",
                          "--load", "0.2 kN", "--csv", "--outputs", "Mb", "F32x"])
    assert status == 0
    df = pd.read_csv(io.StringIO(out), index_col="theta")
    ref = presets.get("slider_crank", gamma=np.pi / 2, l_AB=0.2).solve(
        np.array([0.5, 1.5]), 1800 * 2 * np.pi / 60, None, 200.0)
    np.testing.assert_array_equal(df["Mb"].to_numpy(), ref["Mb"])
    np.testing.assert_array_equal(df["F32x"].to_numpy(), ref["F32x"])
    status, _, err = run(["table", "slider_crank", "--set", "l_AB=3rpm"])
    assert status == 2 and "l_AB = '3rpm' must be a length (m), but it is an angular" in err
    status, _, err = run(["table", "slider_crank", "--omega", "5 m"])
    assert status == 2 and "--omega = '5 m' must be an angular speed" in err


def test_theta_in_degrees_by_a_unit_and_a_warning_for_large_radians():
    """--theta "0:360:15 deg" equals --theta 0:360:15 --deg, its index exactly the
    degrees typed (60.0, not 59.99999999999999); --theta 60 is 60 rad, with one warning
    saying so."""
    a = run(["table", "four_bar", "--theta", "0:360:15 deg", "--csv", "--outputs", "Mb"])
    b = run(["table", "four_bar", "--theta", "0:360:15", "--deg", "--csv", "--outputs", "Mb"])
    assert a[0] == b[0] == 0 and a[1] == b[1]
    index = pd.read_csv(io.StringIO(a[1]))["theta_deg"].to_numpy()
    np.testing.assert_array_equal(index, 15.0 * np.arange(25))
    assert "60.0," in a[1] and "59.99" not in a[1]
    status, _, err = run(["table", "four_bar", "--theta", "60,70", "--outputs", "Mb"])
    assert status == 0 and err.count("is in radians (70 rad = 4010.7 deg)") == 1


def test_loads_are_options_listed_in_help():
    """The loads of the named linkage are options of table, with their unit and start
    value in --help; a load the linkage does not have is an unrecognised option."""
    import pytest

    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), pytest.raises(SystemExit):
        main(["table", "examples/coupler_four_bar.toml", "--help"])
    text = out.getvalue()
    assert "loads of coupler_four_bar" in text
    assert "--F_P VALUE" in text and "[N] (start 80.0)" in text and "--T4 VALUE" in text
    with redirect_stderr(err), pytest.raises(SystemExit) as exit_:
        main(["table", "four_bar", "--F_P", "3"])
    assert exit_.value.code == 2 and "unrecognized arguments: --F_P 3" in err.getvalue()


def test_table_writes_nan_rows_where_the_linkage_does_not_assemble():
    """four_bar with l_AB = 0.3 assembles for cos(theta) >= -0.71875 (|BD| <= BC + CD):
    at 140..220 deg the rows are NaN and a warning gives the range; --strict exits 2."""
    status, out, err = run(["table", "four_bar", "--set", "l_AB=0.3", "--theta", "120:240:20",
                            "--deg", "--csv", "--outputs", "Mb"])
    assert status == 0
    df = pd.read_csv(io.StringIO(out), index_col="theta_deg")
    bad = np.cos(np.radians(df.index.to_numpy())) < -0.71875
    assert df["Mb"].isna().to_numpy().tolist() == bad.tolist() and bad.sum() == 5
    assert "cannot be solved at 5 of 7 angles (theta = 140 to 220 deg)" in err
    assert "their rows are NaN" in err
    status, out, err = run(["table", "four_bar", "--set", "l_AB=0.3", "--theta", "120:240:20",
                            "--deg", "--strict"])
    assert status == 2 and out == "" and "cannot be solved at 5 of 7 angles" in err


def test_sweep_csv_has_no_unnamed_index_column(tmp_path):
    status, _, _ = run(["sweep", "four_bar", "--grid", "l_AB=0.08,0.1", "--n", "12",
                        "-o", str(tmp_path / "s.csv")])
    assert status == 0
    header = (tmp_path / "s.csv").read_text().splitlines()[0].split(",")
    assert header[:3] == ["l_AB", "valid", "problem"] and "" not in header


def test_build_refuses_a_linkage_that_assembles_nowhere_and_says_where_one_does(tmp_path):
    """l_AD = 2 m: |BD| >= 1.9 m > BC + CD = 0.65 m at every angle: no FMU, the reason
    named. l_AB = 0.3: an FMU, and the range where it assembles, arccos(-0.71875) =
    135.95 deg."""
    status, out, err = run(["build", "--native", "four_bar", "--set", "l_AD=2", "--out",
                            str(tmp_path)])
    assert status == 2 and out == "" and not list(tmp_path.iterdir())
    assert "four_bar cannot be assembled at any crank angle (the dyad B-C-D cannot close" in err
    assert "Traceback" not in err
    status, out, err = run(["build", "four_bar", "--set", "l_AB=0.3", "--out", str(tmp_path)])
    assert status == 0 and out.strip().endswith("FourBar.fmu")
    assert "assembles over theta = 0 to 135.95 and 224.05 to 360 deg only" in err


def test_reference_writes_the_description_formats_reference(tmp_path):
    """``linkage-fmu reference`` prints, and with -o writes, the reference of the
    description format, which is the committed docs/description.md."""
    from pathlib import Path

    committed = (Path(__file__).parents[1] / "docs" / "description.md").read_text()
    status, out, _ = run(["reference"])
    assert status == 0 and out == committed
    status, _, err = run(["reference", "-o", str(tmp_path / "d.md")])
    assert status == 0 and (tmp_path / "d.md").read_text() == committed


def test_the_plot_usage_says_one_kind_and_an_optional_name():
    import pytest

    out = io.StringIO()
    with redirect_stdout(out), pytest.raises(SystemExit):
        main(["plot", "--help"])
    assert out.getvalue().startswith("usage: linkage-fmu plot LINKAGE --what KIND [NAME] -o FILE")
    assert "[KIND ...]" not in out.getvalue() and "[NAME] [KIND" not in out.getvalue()


def test_plot_speed_takes_Cs_or_a_flywheel_and_nothing_of_the_other_kinds(tmp_path):
    """--what speed draws the crank's speed at the mean speed --omega, with a flywheel
    sized for --Cs or of inertia --flywheel; those options belong to it alone, and it
    takes no angle or acceleration."""
    import pytest

    pytest.importorskip("matplotlib")
    png = str(tmp_path / "v.png")
    assert run(["plot", "examples/engine.toml", "--what", "speed", "--Cs", "0.02",
                "-o", png])[0] == 0
    assert (tmp_path / "v.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert run(["plot", "four_bar", "--what", "speed", "--flywheel", "2 kg*m**2", "--load",
                "3", "-o", png])[0] == 0
    for argv, message in (
            (["--what", "torque", "--Cs", "0.02"], "--Cs and --flywheel are for --what speed"),
            (["--what", "speed", "--Cs", "0.02", "--flywheel", "1"], "not both"),
            (["--what", "speed", "--theta-deg", "0:90:1"], "no --theta-deg or --alpha"),
            (["--what", "speed", "--Cs", "2"], "Cs must be between 0 and 1")):
        status, _, err = run(["plot", "four_bar", *argv, "-o", png])
        assert status == 2 and message in err, (argv, err)


def test_simulate_command_prints_and_writes_the_motion(tmp_path):
    """``simulate`` is Mechanism.simulate under a constant torque over linspace(0,
    T_END, N), its start, flywheel and loads with units; --outputs picks columns, -o
    writes every column."""
    from linkage_fmu import presets

    argv = ["simulate", "four_bar", "--tau", "2 N*m", "--t-end", "500 ms", "--n", "6",
            "--theta0", "30 deg", "--omega0", "60 rpm", "--flywheel", "0.01", "--load", "0.5"]
    status, out, _ = run(argv + ["--csv", "--outputs", "theta", "omega", "Mb"])
    assert status == 0
    df = pd.read_csv(io.StringIO(out), index_col="time")
    ref = presets.get("four_bar").simulate(2.0, np.linspace(0.0, 0.5, 6), np.pi / 6,
                                           2 * np.pi, flywheel=0.01, load=0.5)
    assert list(df.columns) == ["theta", "omega", "Mb"]
    np.testing.assert_array_equal(df.index.to_numpy(), ref.index.to_numpy())
    for name in df.columns:
        np.testing.assert_array_equal(df[name].to_numpy(), ref[name].to_numpy())
    status, out, _ = run(argv + ["--outputs", "omega"])
    assert status == 0 and out.splitlines()[0].split() == ["omega"]
    assert len(out.splitlines()) == 8  # the header, the index name, 6 rows
    status, _, err = run(argv + ["-o", str(tmp_path / "m.csv")])
    assert status == 0 and "wrote 6 rows" in err
    written = pd.read_csv(tmp_path / "m.csv", index_col="time")
    assert list(written.columns) == list(ref.columns)
    for argv_bad, message in (
            (["--tau", "1", "--t-end", "0"], "--t-end must be > 0"),
            (["--tau", "1", "--t-end", "1", "--n", "1"], "--n must be >= 2"),
            (["--tau", "2 m", "--t-end", "1"], "--tau = '2 m' must be a moment"),
            (["--tau", "1", "--t-end", "1", "--outputs", "Mx"], "--outputs Mx: not a column"),
            (["--tau", "1", "--t-end", "1", "--flywheel", "-1"], "flywheel must be >= 0")):
        status, _, err = run(["simulate", "four_bar", *argv_bad])
        assert status == 2 and message in err, (argv_bad, err)


def test_simulate_and_flywheel_take_friction():
    """With --set mu_...: ``simulate`` prints Mechanism.simulate's motion with friction
    (its ``stuck`` column) and says on stderr where the crank sticks or moves off;
    ``flywheel`` prints the sizing with its friction losses; friction that locks the
    linkage is an error naming the time and the angle, not a traceback."""
    from linkage_fmu import presets

    params = {"mu_A": 0.1, "r_A": 0.01, "mu_guide": 0.1, "mu_O": 0.1, "r_O": 0.01}
    sets = [a for k, v in params.items() for a in ("--set", f"{k}={v}")]
    # the load on the piston drives the crank: at 1 rad the band is [-0.917, -0.711] N.m
    argv = ["simulate", "slider_crank", *sets, "--t-end", "0.2", "--n", "5", "--theta0", "1",
            "--omega0", "0", "--load", "20", "--csv"]
    status, out, err = run(argv + ["--tau", "-0.8"])
    assert status == 0
    df = pd.read_csv(io.StringIO(out), index_col="time")
    ref = presets.get("slider_crank", **params).simulate(-0.8, np.linspace(0.0, 0.2, 5), 1.0,
                                                         0.0, load=20.0)
    assert list(df.columns) == list(ref.columns) and df["stuck"].all()  # within the band
    np.testing.assert_array_equal(df["theta"].to_numpy(), 1.0)
    np.testing.assert_array_equal(df["Mb"].to_numpy(), -0.8)
    assert "at t = 0 s the crank at theta = 1 rad sticks" in err
    status, out, err = run(argv + ["--tau", "0"])
    assert status == 0 and "at t = 0 s the crank at theta = 1 rad moves off forwards" in err
    df = pd.read_csv(io.StringIO(out), index_col="time")
    ref = presets.get("slider_crank", **params).simulate(0.0, np.linspace(0.0, 0.2, 5), 1.0,
                                                         0.0, load=20.0)
    np.testing.assert_array_equal(df["theta"].to_numpy(), ref["theta"].to_numpy())
    assert not df["stuck"].any() and df["theta"].iloc[-1] > 1.1
    status, out, _ = run(["flywheel", "slider_crank", *sets, "--omega-mean", "100", "--Cs",
                          "0.02", "--load", "200"])
    expected = presets.get("slider_crank", **params).flywheel(100.0, 0.02, load=200.0)
    assert status == 0 and out == str(expected) + "\n"
    assert f"friction losses            P_loss   = {expected.P_loss_mean:.6g} W" in out
    status, _, err = run(["simulate", "slider_crank", "--set", "mu_guide=5", "--tau", "0",
                          "--t-end", "0.1", "--theta0", "1.2", "--omega0", "10", "--load",
                          "-50"])
    assert status == 2 and err.startswith("linkage-fmu: slider_crank locks at theta = 1.2 rad")
    assert "(reached at t = 0 s)" in err and "Traceback" not in err


def test_flywheel_command_prints_the_sizing_and_writes_the_motion(tmp_path):
    """``flywheel`` prints Mechanism.flywheel's report (the mean speed with a unit, the
    loads as options) and with -o writes the motion with the flywheel over the cycle."""
    from linkage_fmu import presets

    status, out, err = run(["flywheel", "four_bar", "--omega-mean", "95.5 rpm", "--Cs",
                            "2 percent", "--load", "3", "-o", str(tmp_path / "f.csv")])
    assert status == 0
    expected = presets.get("four_bar").flywheel("95.5 rpm", 0.02, load=3.0)
    assert out == str(expected) + "\n"
    assert f"flywheel to add            I - J_red = {expected.flywheel:.6g} kg.m2" in out
    written = pd.read_csv(tmp_path / "f.csv", index_col="time")
    assert len(written) == 721 and "wrote 721 rows" in err
    np.testing.assert_array_equal(written["omega"].to_numpy(), expected.motion["omega"])
    status, out, _ = run(["flywheel", "examples/engine.toml", "--Cs", "0.02"])  # 3000 rpm
    assert status == 0 and "over a cycle of 720 deg (2 revolutions)" in out
    assert "(3000 rpm)" in out
    for argv, message in ((["--Cs", "0"], "Cs must be between 0 and 1"),
                          (["--Cs", "0.02", "--omega-mean", "3 m"],
                           "--omega-mean = '3 m' must be an angular speed"),
                          (["--Cs", "0.02", "--revolutions", "0"], "revolutions must be >= 1"),
                          (["--Cs", "0.02", "--set", "l_AB=0.3"], "cannot be assembled")):
        status, _, err = run(["flywheel", "four_bar", *argv])
        assert status == 2 and message in err, (argv, err)


def test_optimize_command_prints_the_librarys_optimum_and_writes_its_history(tmp_path):
    """``optimize`` gives the library's ``optimize`` with the same inputs (the bounds
    typed with a unit, --method grid, --budget): the design printed to 10 digits, the
    history written by --csv equal to the result's, a PNG by --plot."""
    from linkage_fmu.optimize import optimize

    theta = np.linspace(0.0, 2.0 * np.pi, 36, endpoint=False)
    ref = optimize("four_bar", {"l_BC": (0.3, 0.45), "l_CD": (0.25, 0.4)}, "Mb_peak",
                   ["gamma_C_min_deg >= 45", "valid"], theta=theta, omega=10.0, loads=(2.0,),
                   method="grid", budget=25)
    status, out, err = run(["optimize", "four_bar", "--vary", "l_BC=0.3:0.45", "--vary",
                            "l_CD=250mm:400mm", "--minimize", "Mb_peak", "--subject-to",
                            "gamma_C_min_deg >= 45", "--subject-to", "valid", "--n", "36",
                            "--omega", "10", "--load", "2", "--method", "grid",
                            "--budget", "25", "--csv", str(tmp_path / "h.csv"),
                            "--plot", str(tmp_path / "c.png")])
    assert status == 0, err
    assert f"l_BC = {ref.design['l_BC']:.10g}\n" in out
    assert f"l_CD = {ref.design['l_CD']:.10g}\n" in out
    assert f"Mb_peak = {ref.value:.10g}\n" in out and "(grid, " in out
    history = pd.read_csv(tmp_path / "h.csv")
    np.testing.assert_array_equal(history["best"], ref.history["best"])
    np.testing.assert_array_equal(history["evaluations"], ref.history["evaluations"])
    assert (tmp_path / "c.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_optimize_command_names_bad_input_and_no_feasible_design():
    """A --vary without bounds, a bad constraint, an unknown summary: status 2 with the
    reason; no feasible design: status 1, the closest printed, the reason on stderr."""
    base = ["optimize", "four_bar", "--n", "12", "--minimize", "Mb_peak"]
    status, _, err = run(base + ["--vary", "l_AB=0.1"])
    assert status == 2 and "--vary 'l_AB=0.1': expected NAME=LO:HI" in err
    status, _, err = run(base + ["--vary", "l_AB=0.05:0.15", "--subject-to", "gamma_C_min_deg"])
    assert status == 2 and "constraint 'gamma_C_min_deg': expected NAME OP VALUE" in err
    status, _, err = run(["optimize", "four_bar", "--vary", "l_AB=0.05:0.15", "--minimize",
                          "Mb_max"])
    assert status == 2 and "'Mb_max' is not a numeric summary" in err
    status, _, err = run(base + ["--vary", "l_AB=0.15:0.05"])
    assert status == 2 and "l_AB needs lo < hi" in err
    status, out, err = run(base + ["--vary", "l_AB=0.05:0.15", "--subject-to",
                                   "gamma_C_min_deg <= 5", "--method", "grid", "--budget", "5"])
    assert status == 1 and "breaks gamma_C_min_deg <= 5" in err
    assert "no design meets every constraint; the one that breaks them least:" in out


def test_a_printed_table_shows_zeros_as_0():
    """The scotch yoke at 90 and 270 deg with no load: several outputs are zero but for
    rounding (F12x is -1e-15 or so), and the table printed used to show them as
    -0.000000. Each cell is now the solver's value to 6 decimals, or 0 where that
    rounds to zero; the CSV keeps every bit."""
    from linkage_fmu import presets

    status, out, _ = run(["table", "scotch_yoke", "--theta", "90,270", "--deg", "--load", "0"])
    assert status == 0
    rows = [line.split() for line in out.splitlines()[2:]]
    assert not {"-0.000000", "0.000000", "-0"} & {cell for row in rows for cell in row}
    names = out.splitlines()[0].split()
    sol = presets.get("scotch_yoke").solve(np.radians([90.0, 270.0]), None, None, 0.0)
    zeros = 0
    for k, row in enumerate(rows):
        assert float(row[0]) == [90.0, 270.0][k]
        for name, cell in zip(names, row[1:]):
            value = float(sol[name][k])
            expected = "0" if abs(value) < 5e-7 else f"{value:.6f}"
            assert cell == expected, (name, value, cell)
            zeros += expected == "0" and value != 0.0 and math.copysign(1.0, value) < 0
    assert zeros >= 3  # negative values that round to zero were among them
    status, csv, _ = run(["table", "scotch_yoke", "--theta", "90", "--deg", "--load", "0",
                          "--csv"])
    df = pd.read_csv(io.StringIO(csv), index_col=0)
    np.testing.assert_array_equal(df.iloc[0].to_numpy(),
                                  [float(sol[n][0]) for n in df.columns])


def test_info_prints_a_load_direction_without_negative_zero():
    """The slider-crank's piston force acts along -x: its direction is (-1, -0.0) as
    the preset computes it, and info used to print "(-1, -0)"."""
    from linkage_fmu import presets

    (load,) = presets.get("slider_crank").loads
    assert load.direction[0] == -1.0 and math.copysign(1.0, load.direction[1]) < 0  # the case
    status, out, _ = run(["info", "slider_crank"])
    assert status == 0 and "direction (-1, 0) fixed in the" in out and "-0)" not in out


def bad_inputs(tmp_path) -> list:
    """(argv, the one line expected on stderr) of user errors, each naming the file or
    the option and what is wrong; the files are made in ``tmp_path``."""
    import zipfile
    from pathlib import Path

    example = (Path(__file__).parents[1] / "examples" / "coupler_four_bar.toml").read_text()
    files = {"mu.toml": example + "\n[friction.C]\nmu = -0.1\nradius = 0.01\n",
             "unjoined.toml": example.replace('name = "F03"\nby = "0"\non = "3"',
                                              'name = "F03"\nby = "0"\non = "2"'),
             "empty.csv": "", "columns.csv": "l_AB,nope\n0.1,1\n", "text.fmu": "not a zip",
             "header.csv": "l_AB\n",
             "mu_max.toml": example.replace(
                 "[parameters]\n", '[parameters]\nmu_x = { default = 0.1, kind = "friction", '
                 'description = "a pin", max = 5000 }\n', 1)}
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    (tmp_path / "latin1.toml").write_bytes(b"# \xe9\n[linkage]\n")
    with zipfile.ZipFile(tmp_path / "other.fmu", "w") as fmu:
        fmu.writestr("modelDescription.xml", '<fmiModelDescription fmiVersion="2.0">'
                     '<CoSimulation modelIdentifier="Other"/></fmiModelDescription>')
    (tmp_path / "folder.fmu").mkdir()
    (tmp_path / "folder.csv").mkdir()
    t = str(tmp_path)
    return [
        (["check", f"{t}/none.fmu"], f"{t}/none.fmu: no such file"),
        (["check", f"{t}/folder.fmu"], f"{t}/folder.fmu: a folder, not an FMU file"),
        (["check", f"{t}/text.fmu"], f"{t}/text.fmu: not an FMU (an FMU is a zip archive)"),
        (["check", f"{t}/other.fmu"], f"{t}/other.fmu: not an FMU of a linkage built by "
                                      "linkage_fmu (it has no resources/Other.toml)"),
        (["sweep", "four_bar", "--samples", f"{t}/none.csv"], f"--samples {t}/none.csv: no "
                                                                "such file"),
        (["sweep", "four_bar", "--samples", f"{t}/empty.csv"], f"--samples {t}/empty.csv: "
                                                                 "not a CSV table of designs"),
        (["sweep", "four_bar", "--samples", f"{t}/header.csv"],
         f"--samples {t}/header.csv: no designs (columns l_AB and no row)"),
        (["sweep", "four_bar", "--grid", "l_AB=0.1", "--n", "0"], "--n must be >= 1, got 0"),
        (["sweep", "four_bar", "--samples", f"{t}/columns.csv"],
         f"--samples {t}/columns.csv: four_bar has no parameter 'nope'"),
        (["info", f"{t}/mu_max.toml"], f"{t}/mu_max.toml: [parameters] mu_x: max = 5000 is "
                                        "above the largest coefficient of friction taken (1000)"),
        (["table", f"{t}/mu.toml"], f"{t}/mu.toml: [friction.C] mu = -0.1 must be >= 0"),
        (["info", f"{t}/unjoined.toml"], f"{t}/unjoined.toml: [[outputs]] #3 (F03): no joint "
                                         "between bodies '0' and '2'"),
        (["table", f"{t}/none.toml"], f"{t}/none.toml: cannot read it: No such file or "
                                      "directory"),
        (["info", f"{t}/latin1.toml"], f"{t}/latin1.toml: not UTF-8 text: byte 0xe9 at 2"),
        (["info", "four_bars"], "four_bars: no such file, and not a preset; the presets are"),
        (["table", "four_bar", "--load", "3 Nm"], "load = '3 Nm' must be a moment (N.m), but "
                                                  "it is [length] / [mass]; did you mean "
                                                  "'3 N*m'?"),
        (["table", "four_bar", "-o", f"{t}/none/x.csv"], f"-o {t}/none/x.csv: there is no "
                                                         f"folder {t}/none"),
        (["reference", "-o", f"{t}/none/d.md"], f"-o {t}/none/d.md: there is no folder"),
        (["plot", "four_bar", "--what", "gamma", "-o", f"{t}/none/m.png"],
         f"-o {t}/none/m.png: there is no folder {t}/none"),
        (["optimize", "four_bar", "--vary", "l_AB=0.1:0.2", "--minimize", "Mb_peak", "--csv",
          f"{t}/none/h.csv"], f"--csv {t}/none/h.csv: there is no folder {t}/none"),
        (["table", "four_bar", "-o", f"{t}/text.fmu/x.csv"], f"-o {t}/text.fmu/x.csv: there is "
                                                             "no folder"),
        (["table", "four_bar", "-o", f"{t}/folder.csv"], f"{t}/folder.csv: Is a directory"),
        (["table", "four_bar", "--theta", "0:1:0"], "--theta '0:1:0': need START <= STOP"),
        (["sweep", "four_bar", "--grid", "l_AB=1:0:1"], "--grid l_AB '1:0:1': need START"),
        (["table", "four_bar", "--omega", "1 furlong"], "--omega = '1 furlong' must be an "
                                                        "angular speed"),
        (["check", f"{t}/none.fmu", "--steps", "0"], "--steps must be >= 1, got 0"),
        (["animate", "four_bar", "--dpi", "1e9", "-o", f"{t}/a.gif"],
         "--dpi 1e+09 draws frames of 1.1e+10 x 4.8e+09 pixels; a frame is less than 65536 "
         "pixels a side (matplotlib's and a GIF's limit): dpi 5957 at most for 11 x 4.8 "
         "inches"),
    ]


def test_no_traceback_from_bad_input(tmp_path):
    """Every user error ends the command with status 2 and one line on stderr: the file
    or option, the key, what is wrong (a missing FMU, a drive FMU and a missing samples
    file printed tracebacks; the drive FMU's check is in test_drive.py)."""
    for argv, line in bad_inputs(tmp_path):
        status, out, err = run(argv)
        assert status == 2 and out == "", (argv, status, err)
        assert err.count("\n") == 1 and err.startswith(f"linkage-fmu: {line}"), (argv, err)


def test_a_warning_is_a_line_of_the_command(tmp_path):
    """A description's warning (a plain cg angle of 90: radians) is one line
    ``linkage-fmu: warning: FILE: KEY ...``, not Python's warning with a source line of
    the library; the command goes on (status 0)."""
    from pathlib import Path

    example = (Path(__file__).parents[1] / "examples" / "coupler_four_bar.toml").read_text()
    path = tmp_path / "angle.toml"
    path.write_text(example.replace('cg = { from = "A" }  # a massless crank',
                                    'cg = { from = "A", distance = 0.01, angle = 90 }'))
    status, _, err = run(["info", str(path)])
    assert status == 0 and err == (f"linkage-fmu: warning: {path}: [bodies.1] cg angle = 90 "
                                   'is taken in radians (5156.62 deg); write "90 deg" for '
                                   "degrees\n")


def test_a_missing_optional_dependency_is_one_line(monkeypatch):
    """``sweep --scheduler local`` without dask.distributed: status 2 and the library's
    line saying what to install, not an ImportError's traceback."""
    import sys

    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # import fails
    status, out, err = run(["sweep", "four_bar", "--grid", "l_AB=0.1", "--n", "4",
                            "--scheduler", "local"])
    assert status == 2 and out == "" and err.count("\n") == 1
    assert err.startswith("linkage-fmu: a sweep on Dask needs dask.distributed: pip install")


def test_every_example_in_the_help_is_taken():
    """Each option's help that shows a value with a unit, ("1800 rpm"), and says its unit,
    [rad/s], is taken as that option's value (--alpha offered "1800 rpm" and refused it);
    --alpha "100 rad/s^2" gives the library's solve at alpha = 100 rad/s2, to the digit."""
    import argparse
    import re

    from linkage_fmu import presets
    from linkage_fmu.expressions import evaluate

    captured = {}
    original = argparse.ArgumentParser.parse_args

    def capture(self, args=None, namespace=None):
        captured["parser"] = self
        raise SystemExit(0)

    argparse.ArgumentParser.parse_args = capture
    try:
        try:
            main(["info", "four_bar"])
        except SystemExit:
            pass
    finally:
        argparse.ArgumentParser.parse_args = original
    subparsers = next(a for a in captured["parser"]._actions
                      if isinstance(a, argparse._SubParsersAction))
    examples = []
    for name, sub in subparsers.choices.items():
        for action in sub._actions:
            help_ = action.help or ""
            unit = re.search(r"\[([^\]]+)\]", help_)
            for example in re.findall(r'\("([^"]+)"\)', help_):
                assert unit, (name, action.dest, help_)
                examples.append((name, action.option_strings[0], example))
                evaluate(example, unit.group(1), action.option_strings[0])
    assert ("table", "--alpha", "100 rad/s^2") in examples
    assert ("simulate", "--theta0", "30 deg") in examples and len(examples) >= 10
    status, out, _ = run(["table", "four_bar", "--theta", "0.5", "--alpha", "100 rad/s^2",
                          "--omega", "1e1", "--csv", "--outputs", "Mb"])
    assert status == 0
    ref = presets.get("four_bar").solve(np.array([0.5]), 10.0, 100.0, outputs=["Mb"])
    assert pd.read_csv(io.StringIO(out))["Mb"].iloc[0] == ref["Mb"][0]


def test_the_examples_of_the_help_run(tmp_path, monkeypatch):
    """Each command of ``linkage-fmu --help``'s examples runs as written (status 0),
    from a folder holding the project's examples/; those that build FMUs, check them or
    start a Dask cluster aside (their commands are tested in test_drive.py, test_fmu.py
    and above; test_cli_reference.py parses every example)."""
    import os
    import shlex
    from pathlib import Path

    import pytest

    from linkage_fmu.cli import EPILOG

    pytest.importorskip("matplotlib")
    examples = Path(__file__).parents[1] / "examples"
    os.symlink(examples, tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    lines = EPILOG.replace("\\\n", " ").splitlines()[1:]
    skipped = ("build", "check", "--samples")
    ran = []
    for line in lines:
        argv = shlex.split(line, comments=True)
        assert argv[0] == "linkage-fmu", line
        if any(word in argv for word in skipped) or not argv[1:]:
            continue
        status, _, err = run(argv[1:])
        assert status == 0, (line, err)
        ran.append(argv[1])
    assert {"info", "table", "sweep", "optimize", "plot", "animate", "simulate",
            "flywheel"} <= set(ran)


def test_an_angle_in_exponent_notation_is_a_number():
    """``--theta 1E2`` is 100 rad (it was split into 1 and a unit 'E2' and refused);
    reference: the same table asked with --theta 100."""
    status, out, err = run(["table", "four_bar", "--theta", "1E2", "--outputs", "Mb"])
    assert status == 0, err
    assert out == run(["table", "four_bar", "--theta", "100", "--outputs", "Mb"])[1]


def test_info_prints_the_decomposition_of_a_linkage_drawn_as_joints_and_links(tmp_path):
    """The crank shaper written as joints and links: its groups in the order they are
    solved, as the preset writes them by hand (src/linkage_fmu/linkages/crank_shaper.toml:
    crank, RPR, the lever's point D, RRP); a bad file: one line naming it, status 2."""
    from pathlib import Path

    path = Path(__file__).parents[1] / "examples" / "joints" / "crank_shaper.toml"
    status, out, err = run(["info", str(path)])
    assert status == 0 and err == ""
    assert out.splitlines()[1:6] == [
        "groups, in the order they are solved (decomposed from its joints and links):",
        "   1. crank       link 1; joints A, B",
        "   2. II (RPR)    links 2, 3; joints B, C, slot",
        "   3. point       D on link 3",
        "   4. II (RRP)    links 4, 5; joints D, E, guide"]
    bad = tmp_path / "pivot.toml"
    bad.write_text(path.read_text().replace('pivot = "A"', 'pivot = "B"'))
    status, out, err = run(["info", str(bad)])
    assert (status, out) == (2, "")
    assert err == (f"linkage-fmu: {bad}: [crank] pivot: the crank pivot B is not on the "
                   "frame: it joins link 1 to 2; the pivot is a revolute joint that only the "
                   "crank lists, or one the frame's entry in [[links]] lists\n")


def test_the_commands_that_draw_leave_no_figure_open(tmp_path):
    """plot and animate run in one process many times (a notebook, a test session): each
    closes the figure it wrote, so pyplot keeps none of them."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.close("all")
    assert main(["plot", "four_bar", "--what", "torque", "-o", str(tmp_path / "t.png")]) == 0
    assert main(["animate", "four_bar", "--frames", "4", "--dpi", "20",
                 "-o", str(tmp_path / "a.gif")]) == 0
    assert plt.get_fignums() == []


def test_sweep_and_optimize_without_a_compiler_run_on_numpy(monkeypatch):
    """CC names no compiler (the package's way of choosing one): sweep and optimize,
    which ended in a RuntimeError's traceback, run on numpy (status 0), their only line
    on stderr the library's warning that says so. The sweep's table is the one the
    compiled kernels give (to 1e-12 relative); the design optimize returns has the
    Mb_peak it prints, by the compiled sweep of that design."""
    import re

    from linkage_fmu import sweep as module
    from linkage_fmu.kernels import compiled

    sweep = ["sweep", "four_bar", "--grid", "l_AB=0.08,0.1", "--grid", "m2=1,3", "--n", "36",
             "--omega", "10"]
    status, reference, _ = run(sweep)
    assert status == 0
    module._structure.cache_clear()
    compiled._no_compiler_warning.cache_clear()
    monkeypatch.setenv("CC", "no-such-c-compiler")
    try:
        status, out, err = run(sweep)
        assert status == 0 and err.count("\n") == 1, err
        assert err.startswith("linkage-fmu: warning: no C compiler found")
        status, printed, err = run(["optimize", "four_bar", "--vary", "l_BC=0.3:0.45",
                                    "--minimize", "Mb_peak", "--maxiter", "2", "--seed", "1",
                                    "--n", "36", "--no-polish"])
        assert status == 0 and err == "", err  # the warning is said once a process
    finally:
        monkeypatch.undo()
        module._structure.cache_clear()
        compiled._no_compiler_warning.cache_clear()
    got, want = (pd.read_csv(io.StringIO(text)) for text in (out, reference))
    assert list(got.columns) == list(want.columns) and len(got) == 4
    numbers = want.select_dtypes("number").columns
    np.testing.assert_allclose(got[numbers], want[numbers], rtol=1e-12, atol=1e-300)
    best = float(re.search(r"l_BC = (\S+)", printed)[1])
    peak = float(re.search(r"Mb_peak = (\S+)", printed)[1])
    status, check, _ = run(["sweep", "four_bar", "--grid", f"l_BC={best!r}", "--n", "36"])
    assert status == 0
    assert pd.read_csv(io.StringIO(check))["Mb_peak"].iloc[0] == pytest.approx(peak, rel=1e-9)


@pytest.mark.parametrize("flavour, tolerance", [("pythonfmu", 1e-9), ("native", 1e-12)])
def test_check_says_ok_or_failed_and_against_what(flavour, tolerance, tmp_path):
    """``linkage-fmu check FMU`` prints one line (it printed a bare JSON dict): the
    verdict, the largest error and its output, what it is against and the flavour's
    tolerance, fmpy's validation; ``--json`` prints the same figures as one object, with
    the tolerance and ``passed``. The same FMU whose bundled description has another
    coupler mass (2 to 2.5 kg: the reference is the description, the binary another
    linkage) fails: ``FAILED``, exit status 1."""
    import json

    import fmu_cache

    build = fmu_cache.build_native_fmu if flavour == "native" else fmu_cache.build_fmu
    fmu = build("four_bar", tmp_path)
    status, out, _ = run(["check", "--json", str(fmu)])
    result = json.loads(out)
    assert status == 0 and result["passed"] and result["tolerance"] == tolerance
    assert result["max_rel_error"] <= tolerance and result["validate"] == []
    status, out, _ = run(["check", str(fmu)])
    assert status == 0 and out == (
        f"{fmu}: ok: the outputs of FourBar are within {result['max_rel_error']:.2g} "
        f"({result['worst_output']}) of the direct solver's over 360 steps, relative to "
        f"the largest output of its unit (the tolerance {tolerance:g}); fmpy validate: no "
        "problems\n")
    heavier = tmp_path / "heavier" / "FourBar.fmu"
    heavier.parent.mkdir()
    fmu_cache.heavier_coupler(fmu, heavier)
    status, out, _ = run(["check", str(heavier)])
    assert status == 1 and out.startswith(f"{heavier}: FAILED: the outputs of FourBar are "
                                          "within ")
    assert f"(the tolerance {tolerance:g}); fmpy validate: no problems\n" in out
    status, out, _ = run(["check", "--json", str(heavier)])
    assert status == 1 and json.loads(out)["passed"] is False


def test_check_of_an_fmu_that_cannot_be_instantiated_is_one_line(tmp_path):
    """A pythonfmu FMU built from another linkage_fmu than the one this process imported
    (its slave's fingerprint of the package it bundles differs) refuses to be
    instantiated in it: ``check`` says so in one line, with what the FMU logged, and
    exits 1 (fmpy's plain Exception was a traceback)."""
    import re
    import zipfile

    import fmu_cache

    fmu = fmu_cache.build_fmu("four_bar", tmp_path)
    other = tmp_path / "other" / "FourBar.fmu"
    other.parent.mkdir()
    with zipfile.ZipFile(fmu) as source, zipfile.ZipFile(other, "w") as copy:
        for item in source.infolist():
            data = source.read(item)
            if re.fullmatch(r"resources/linkage_fmu_FourBar_\w+\.py", item.filename):
                data, n = re.subn(rb"FINGERPRINT = '[0-9a-f]+'", b"FINGERPRINT = '" +
                                  b"0" * 64 + b"'", data)
                assert n == 1
            copy.writestr(item, data)
    import subprocess
    import sys

    # in a new process: one that ran this FMU's slave keeps it imported
    done = subprocess.run([sys.executable, "-m", "linkage_fmu", "check", str(other)],
                          capture_output=True, text=True, timeout=300, cwd=tmp_path)
    status, out, err = done.returncode, done.stdout, done.stderr
    assert (status, out) == (1, "") and err.count("\n") == 1, err
    assert err.startswith(f"linkage-fmu: {other}: the check failed: the FMU cannot be "
                          "instantiated: ")
    assert "fingerprint" in err


def test_the_table_of_a_linkage_driven_by_time_takes_its_inputs_row_by_row(tmp_path):
    """``table FILE --inputs ROWS.csv``: a row per row of the file, indexed by its time
    column, each output the library's at that row's inputs (a driver's coordinate not
    given at its start); a row that cannot be solved is NaN with a warning, or exit 2
    with ``--strict``; what the command cannot take is refused with the reason."""
    from pathlib import Path

    import linkage_fmu

    source = str(Path(__file__).resolve().parents[1] / "examples" / "excavator.toml")
    rows = tmp_path / "dig.csv"
    t = np.linspace(0.0, 2.0, 5)
    pd.DataFrame({"time": t, "s_cyl1": 0.1 * t, "v_cyl1": 0.1, "s_cyl3": -0.05 * t,
                  "v_cyl3": -0.05}).to_csv(rows, index=False)
    out = tmp_path / "out.csv"
    status, _, _ = run(["table", source, "--inputs", str(rows), "--F_T", "15000", "-o",
                        str(out)])
    got = pd.read_csv(out, index_col="time")
    want = linkage_fmu.load(source).solve(s_cyl1=0.1 * t, v_cyl1=0.1, s_cyl2=0.0,
                                          s_cyl3=-0.05 * t, v_cyl3=-0.05, F_T=15000.0)
    assert status == 0 and got.index.tolist() == t.tolist()
    for name in ("Fb_cyl1", "Fb_cyl2", "Fb_cyl3", "F0_boomx", "shake_M"):
        assert got[name].to_numpy() == pytest.approx(want[name], rel=1e-15), name
    far = tmp_path / "far.csv"
    pd.DataFrame({"s_cyl1": [0.1, 2.0]}).to_csv(far, index=False)
    status, out_text, err = run(["table", source, "--inputs", str(far), "--csv"])
    assert status == 0 and "cannot be solved at 1 of 2 rows (first row 1)" in err
    assert out_text.splitlines()[2].split(",")[1] == ""  # NaN
    status, _, err = run(["table", source, "--inputs", str(far), "--strict"])
    assert status == 2 and "the cylinder dyad O-D1-E1 cannot close" in err
    for argv, message in [
        ([], "excavator is driven by time (s_cyl1, s_cyl2, s_cyl3): give its inputs row by "
             "row, --inputs FILE.csv with a column per input (s_cyl1, v_cyl1"),
        (["--inputs", str(rows), "--omega", "3"], "--omega: excavator is driven by time"),
    ]:
        status, _, err = run(["table", source, *argv])
        assert status == 2 and message in err, err
    bad = tmp_path / "bad.csv"
    pd.DataFrame({"s_cyl1": [0.1], "theta": [1.0]}).to_csv(bad, index=False)
    status, _, err = run(["table", source, "--inputs", str(bad)])
    assert status == 2 and "bad.csv: theta: no input of excavator" in err
    status, _, err = run(["table", "four_bar", "--inputs", str(rows)])
    assert status == 2 and "--inputs is for a linkage driven by time" in err


def test_equations_prints_the_labelled_system_and_its_solution(tmp_path):
    """``equations PRESET --theta 60 --deg --omega 10 --load 400``: the scotch yoke's nine
    equations, row by row, then the solution (the worked example's Mb 15.6699 N.m at
    60 deg); markdown to a file; one angle only, and one crank only, with the reason."""
    status, out, _ = run(["equations", "scotch_yoke", "--theta", "60", "--deg", "--omega",
                          "10", "--load", "400"])
    lines = out.splitlines()
    assert status == 0 and lines[0] == ("scotch_yoke at theta = 1.0472, omega = 10, "
                                        "alpha = 0, load = 400: A x = b, 9 equations")
    assert lines[6].split()[:5] == ["3", "link", "1:", "ΣM", "about"]
    assert "  Mb = 15.6699" in lines
    target = tmp_path / "yoke.md"
    status, _, _ = run(["equations", "scotch_yoke", "--theta", "60", "--deg", "--format",
                        "markdown", "-o", str(target)])
    assert status == 0 and "| i | equation | a(i, 1) |" in target.read_text()
    target = tmp_path / "scotch_yoke.m"
    status, _, _ = run(["equations", "scotch_yoke", "--theta", "60", "--deg", "--format",
                        "matlab", "-o", str(target)])
    assert status == 0 and target.read_text().startswith(
        "function x = scotch_yoke(theta, omega, alpha, load)\n")
    status, _, err = run(["equations", "scotch_yoke", "--theta", "0:90:45", "--deg"])
    assert status == 2 and "the equations are of one state; give one angle" in err
    five = str(Path(__file__).resolve().parents[1] / "examples" / "five_bar.toml")
    status, _, err = run(["equations", five, "--theta", "1"])
    assert status == 2 and "linkage-fmu equations takes a linkage driven by one crank" in err
