"""The drive FMU (``linkage-fmu build --native --drive``): the four-bar driven by a moment
``tau`` on its crank, its continuous states integrated by the framework
(``fmi/continuous.c``) in co-simulation, or by fmpy's CVode in model exchange.

References: :meth:`Mechanism.simulate <linkage_fmu.mechanism.Mechanism.simulate>`
(scipy's DOP853 at ``rtol = atol = 1e-13``, the library's own equations of motion); the
energy balance (the work of ``tau`` against the change of ``J_red omega**2 / 2`` plus
the weights' potential energy); the inverse native FMU on the drive's motion; the
assembly limit of a four-bar that cannot turn fully (:func:`linkage_fmu.ranges.assembles`).
Raw calls (FMU states, bad calls, the discard) run in a fresh process
(``drive_host.py``), so that a crash fails the test instead of ending pytest.
"""

from __future__ import annotations

import functools
import inspect
import math
import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

import fmu_cache
import fmu_fuzz
from conftest import run_host
from fmu_cache import build_native_fmu
from fmu_fuzz import run_drive
from linkage_fmu import presets, ranges
from linkage_fmu.cli import main
from test_c_host import compile_host, model_outputs

HOST = Path(__file__).with_name("drive_host.py")
MECH = presets.get("four_bar")  # g = 9.81, no load
THETA0, OMEGA0, STOP, H = 0.3, 5.0, 1.0, 0.01
#: a moment that makes the crank swing back and forth, and one that makes it revolve
#: (to about 190 rad/s after 1 s)
TAUS = (0.5, 2.0)
OK, WARNING, DISCARD, ERROR, FATAL = range(5)


@pytest.fixture(scope="module")
def fmus(tmp_path_factory) -> dict:
    """The drive FMUs of the four-bar (FMI 2.0 and 3.0), of the four-bar with
    ``l_AB = 0.3`` (it turns from 0 to 135.95 degrees only), and the four-bar's inverse
    native FMU."""
    out = tmp_path_factory.mktemp("drive")
    return {2: build_native_fmu("four_bar", out / "2", 2, drive=True),
            3: build_native_fmu("four_bar", out / "3", 3, drive=True),
            "limit2": build_native_fmu("four_bar", out / "limit2", 2, drive=True, l_AB=0.3),
            "limit3": build_native_fmu("four_bar", out / "limit3", 3, drive=True, l_AB=0.3),
            "inverse": build_native_fmu("four_bar", out / "inverse", 2)}


@pytest.fixture(scope="module")
def reference() -> dict:
    """The library's motion under each of :data:`TAUS`, at the output times."""
    t = np.linspace(0.0, STOP, round(STOP / H) + 1)
    return {tau: MECH.simulate(tau, t, theta0=THETA0, omega0=OMEGA0, rtol=1e-13, atol=1e-13)
            for tau in TAUS}


def cosimulate(fmu, tau, tolerance=1e-8, outputs=("theta", "omega"), **kw):
    start = {"tau": tau, "theta0": THETA0, "omega0": OMEGA0, "tolerance": tolerance}
    return simulate_fmu(str(fmu), stop_time=STOP, output_interval=H, fmi_type="CoSimulation",
                        start_values=start, output=list(outputs), **kw)


def relative_error(result, ref, name) -> float:
    """The largest error of ``name`` over the run, relative to 1 + |reference|."""
    r = ref[name].to_numpy()
    return float(np.max(np.abs(result[name] - r) / (1.0 + np.abs(r))))


def host(job: dict, tmp_path: Path) -> dict:
    return run_host(HOST, job, tmp_path, timeout=300)


@pytest.mark.parametrize("version", (2, 3))
def test_fmpy_finds_no_problem(fmus, version):
    """``fmpy validate`` finds nothing in the drive FMU (co-simulation and model exchange
    in one modelDescription), whose states are ``theta`` and ``omega``."""
    assert validate_fmu(str(fmus[version])) == []
    from fmpy import read_model_description
    md = read_model_description(str(fmus[version]))
    assert md.modelExchange.modelIdentifier == md.coSimulation.modelIdentifier == "FourBarDrive"
    assert [d.variable.derivative.name for d in md.derivatives] == ["theta", "omega"]


@pytest.mark.parametrize("tau", TAUS)
def test_cosimulation_against_the_library(fmus, reference, tau):
    """Co-simulation at the tolerances 1e-8 and 1e-10 against ``Mechanism.simulate``:
    ``theta`` within 20 tol and ``omega`` within 1000 tol of 1 + |value| (a global error
    from a local-error controller: over the revolving crank's 11 turns, with the
    acceleration swinging by 2e4 rad/s2 per turn, a phase error in theta is one of omega
    2e2 times larger), 5 times smaller or better from 1e-8 to 1e-10; along the motion
    ``Mb`` (the inverse kinetostatics at the FMU's theta, omega, alpha) equals ``tau`` to
    1e-12 of max(1, |Mb|), and the joint forces and ``J_red`` equal the library's direct
    solve at the FMU's states to 1e-12 of their largest value."""
    ref, errors = reference[tau], {}
    names = ("theta", "omega", "alpha", "Mb", "F21x", "F43y", "J_red")
    for tol in (1e-8, 1e-10):
        r = cosimulate(fmus[2], tau, tol, names)
        errors[tol] = relative_error(r, ref, "theta"), relative_error(r, ref, "omega")
        assert errors[tol][0] <= 20 * tol and errors[tol][1] <= 1000 * tol, (tol, errors[tol])
        assert np.max(np.abs(r["Mb"] - tau)) <= 1e-12 * max(1.0, np.max(np.abs(r["Mb"])))
        sol = MECH.solve(r["theta"], r["omega"], r["alpha"], method="direct")
        for name in ("F21x", "F43y", "J_red"):
            assert np.max(np.abs(r[name] - sol[name])) <= 1e-12 * np.max(np.abs(sol[name]))
    assert errors[1e-10][0] * 5 <= errors[1e-8][0] and errors[1e-10][1] * 5 <= errors[1e-8][1]


@pytest.mark.parametrize("version", (2, 3))
def test_fmpys_defaults_meet_the_default_tolerance(fmus, version):
    """``fmpy.simulate_fmu(fmu)`` with every default: fmpy steps at the default
    experiment's ``stepSize`` (it ignores ``step_size`` in co-simulation), declared a
    round 1 ms (a degree of the revolution at 10 rad/s is 1.75 ms), with the tolerance
    1e-8 of the parameter ``tolerance``; the run, one revolution at the start speed
    under tau = 0 from theta = 0, agrees with ``Mechanism.simulate`` at 1e-13 within
    that tolerance of 1 + |value| for theta and omega (measured 2.1e-11 and 4.1e-10)."""
    from fmpy import read_model_description

    experiment = read_model_description(str(fmus[version])).defaultExperiment
    assert (float(experiment.stepSize), float(experiment.tolerance)) == (1e-3, 1e-8)
    assert float(experiment.stopTime) == 2 * math.pi / MECH.start["omega"]
    result = simulate_fmu(str(fmus[version]), fmi_type="CoSimulation", step_size=1e-4)
    t = result["time"]
    assert len(t) == 630 and np.allclose(np.diff(t[:-1]), 1e-3, rtol=1e-9, atol=0)
    ref = MECH.simulate(0.0, t, rtol=1e-13, atol=1e-13)
    assert relative_error(result, ref, "theta") <= 1e-8
    assert relative_error(result, ref, "omega") <= 1e-8


def test_fmi3_cosimulation_is_fmi2s(fmus):
    """The FMI 3.0 drive FMU runs the same framework and kernels: every value of a run is
    FMI 2.0's, bit for bit."""
    a = cosimulate(fmus[2], 2.0, 1e-8, ("theta", "omega", "alpha", "F21x"))
    b = cosimulate(fmus[3], 2.0, 1e-8, ("theta", "omega", "alpha", "F21x"))
    for name in ("theta", "omega", "alpha", "F21x"):
        assert np.array_equal(a[name], b[name]), name


@pytest.mark.parametrize("version", (2, 3))
def test_model_exchange_against_the_library(fmus, reference, version):
    """Model exchange, fmpy's CVode at rtol 1e-10, against ``Mechanism.simulate``: theta
    within 1e-6 of 1 + |theta|, omega within 1e-5 of 1 + |omega|."""
    for tau in TAUS:
        r = simulate_fmu(str(fmus[version]), stop_time=STOP, output_interval=H,
                         fmi_type="ModelExchange", relative_tolerance=1e-10,
                         start_values={"tau": tau, "theta0": THETA0, "omega0": OMEGA0},
                         output=["theta", "omega"])
        assert relative_error(r, reference[tau], "theta") <= 1e-6, tau
        assert relative_error(r, reference[tau], "omega") <= 1e-5, tau


def test_model_exchange_derivatives(fmus, tmp_path):
    """GetDerivatives at given states is ``(omega, (tau - Mb(alpha = 0)) / J_red)`` of the
    library to 1e-12 relative (FMI 2.0 and 3.0); at a position where the linkage cannot
    be assembled it is Discard, with NaN and a log that says why."""
    states = [[0.3, 5.0], [2.0, -3.0], [5.0, 40.0]]
    for version in (2, 3):
        out = host({"job": "exchange", "fmu": str(fmus[version]), "tau": 0.7, "start": {},
                    "states": states}, tmp_path)
        for (theta, omega), (status, dx) in zip(states, out["derivatives"]):
            mb0 = MECH.solve(theta, omega, 0.0, outputs=("Mb",))["Mb"]
            alpha = (0.7 - mb0) / MECH.reduced_inertia(theta)[0]
            assert status == OK and dx[0] == omega
            assert abs(dx[1] - alpha) <= 1e-12 * max(1.0, abs(alpha)), (theta, omega)
        out = host({"job": "exchange", "fmu": str(fmus[f"limit{version}"]), "tau": 0.7,
                    "start": {}, "states": [[3.1, 1.0]]}, tmp_path)
        assert out["derivatives"] == [[DISCARD, [1.0, None]]] or \
            out["derivatives"] == [[DISCARD, [None, None]]]
        assert any("cannot be assembled" in text for _, text in out["log"])


def test_energy_balance(fmus):
    """The work of ``tau`` equals the change of the kinetic energy ``J_red omega**2 / 2``
    (``J_red`` from the FMU) plus the weights' potential energy (``g`` sum ``m y`` at the
    centres of mass, from the linkage's kinematics) to 1e-8 of the largest term, at the
    tolerance 1e-10, for both moments."""
    for tau in TAUS:
        r = cosimulate(fmus[2], tau, 1e-10, ("theta", "omega", "J_red"))
        st = MECH.kinematics(r["theta"], order=0)
        potential = MECH.g * sum(b.mass * st.p[b.cg][1] for b in MECH.bodies)
        kinetic = 0.5 * r["J_red"] * r["omega"] ** 2
        work = tau * (r["theta"] - THETA0)
        balance = work - (kinetic - kinetic[0]) - (potential - potential[0])
        scale = max(np.max(np.abs(work)), np.max(np.abs(kinetic)), np.max(np.abs(potential)))
        assert np.max(np.abs(balance)) <= 1e-8 * scale, (tau, np.max(np.abs(balance)) / scale)


def inverse_run(fmu, theta, omega, alpha, outputs, h=H):
    """The inverse FMU's outputs for each row of (theta, omega, alpha), load 0, a row
    every ``h`` (fmpy's rows hold the outputs of the previous row's inputs: shifted
    back)."""
    n = len(theta)
    u = np.zeros(n + 1, dtype=[("time", float), ("theta", float), ("omega", float),
                               ("alpha", float), ("load", float)])
    u["time"] = np.arange(n + 1) * h
    for name, values in (("theta", theta), ("omega", omega), ("alpha", alpha)):
        u[name][:n], u[name][n] = values, values[-1]
    r = simulate_fmu(str(fmu), stop_time=n * h, output_interval=h, input=u, output=outputs)
    return {name: r[name][1:n + 1] for name in outputs}


def test_the_inverse_fmu_on_the_drives_motion(fmus):
    """The inverse native FMU at the drive's theta, omega and alpha gives back ``Mb =
    tau`` to 1e-12 of max(1, |Mb|), and the drive's joint forces to 1e-12 of their
    largest value."""
    names = ["F21x", "F21y", "F32x", "F43y", "shake_M"]
    d = cosimulate(fmus[2], 2.0, 1e-8, ("theta", "omega", "alpha", "Mb", *names))
    inv = inverse_run(fmus["inverse"], d["theta"], d["omega"], d["alpha"], ["Mb", *names])
    assert np.max(np.abs(inv["Mb"] - 2.0)) <= 1e-12 * max(1.0, np.max(np.abs(inv["Mb"])))
    for name in names:
        assert np.max(np.abs(inv[name] - d[name])) <= 1e-12 * np.max(np.abs(d[name])), name


def prescribed(t):
    """A crank motion: theta, omega, alpha at the times ``t``."""
    return (0.3 + 6.0 * t + 0.4 * np.sin(5.0 * t), 6.0 + 2.0 * np.cos(5.0 * t),
            -10.0 * np.sin(5.0 * t))


def test_the_inverse_fmus_torque_drives_the_motion_back(fmus, tmp_path):
    """The torque the inverse FMU computes along a prescribed motion, given to the drive
    FMU (held over each step at its value at the step's midpoint), reproduces the motion:
    theta within 2e-4 rad and omega within 4e-3 rad/s over 1 s at steps of 2 ms, and the
    error falls as the square of the step (a ratio of 3.5 to 4.5 from 2 ms to 1 ms)."""
    errors = []
    for h in (0.002, 0.001):
        t = np.arange(round(STOP / h)) * h
        tau = inverse_run(fmus["inverse"], *prescribed(t + 0.5 * h), ["Mb"], h)["Mb"]
        u = np.zeros(len(t) + 1, dtype=[("time", float), ("tau", float), ("load", float)])
        u["time"], u["tau"][:-1], u["tau"][-1] = np.append(t, STOP), tau, tau[-1]
        r = simulate_fmu(str(fmus[2]), stop_time=STOP, output_interval=h, input=u,
                         start_values={"theta0": 0.3, "omega0": 8.0, "tolerance": 1e-10},
                         output=["theta", "omega"])
        theta, omega, _ = prescribed(r["time"])
        errors.append((np.max(np.abs(r["theta"] - theta)), np.max(np.abs(r["omega"] - omega))))
    assert errors[0][0] <= 2e-4 and errors[0][1] <= 4e-3, errors
    for k in (0, 1):
        assert 3.5 <= errors[0][k] / errors[1][k] <= 4.5, errors


@pytest.mark.parametrize("version", (2, 3))
def test_discard_at_the_assembly_limit(fmus, tmp_path, version):
    """The four-bar with ``l_AB = 0.3`` turns from 0 to 135.95 degrees only: driven by 5
    N.m from 10 rad/s it reaches the limit at t = 0.1112 s, inside the twelfth step of 10
    ms. That step is Discard, its lastSuccessfulTime inside the step, theta there within
    1e-8 rad of the limit (:func:`~linkage_fmu.ranges.assembles`, 1e-9 rad) and omega
    near 0 (the reduced inertia grows without bound there); the outputs read afterwards
    are those of that last good state, finite and with OK; the log says why."""
    out = host({"job": "run", "fmu": str(fmus[f"limit{version}"]), "tau": 5.0, "h": 0.01,
                "stop": 1.0, "start": {"theta0": 0.0, "omega0": 10.0, "tolerance": 1e-8},
                "outputs": ["alpha", "F21x", "J_red"]}, tmp_path)
    rows = out["rows"]
    assert out["init"] == OK and [r["status"] for r in rows] == [OK] * 11 + [DISCARD]
    last = rows[-1]
    limit = math.radians(ranges.assembles(presets.get("four_bar", l_AB=0.3))[0][1])
    assert 0.11 < last["last"] < 0.12 and abs(last["last"] - 0.1112) < 1e-4
    assert abs(last["theta"] - limit) <= 1e-8 and abs(last["omega"]) < 1e-3
    assert last["read"] == OK and all(math.isfinite(last[n]) for n in ("alpha", "F21x"))
    assert last["J_red"] > 1e6 * rows[0]["J_red"]
    assert "cannot be assembled" in out["log"][-1][1] and "lastSuccessfulTime" in out["log"][-1][1]


#: the most substeps one doStep takes (``MAX_SUBSTEPS`` in fmi/continuous.c)
MAX_SUBSTEPS = 1000


@pytest.mark.parametrize("version", (2, 3))
def test_a_step_takes_a_bounded_number_of_substeps(fmus, tmp_path, version):
    """tau = 1e10 spins the crank to 2e7 rad/s within 45 microseconds: a step of 10 ms
    would need millions of substeps (each doStep took a million, 0.35-0.67 s, then a Discard
    saying only "more than 1000000 substeps"). Now the step ends where 1000 substeps
    reach: Discard, lastSuccessfulTime there, theta and omega that state's (read with
    OK); the log gives the speed (the omega read, to the last digit) and the substeps the
    tolerance would need (more than 1000), and steps that fit. The next steps, at
    tau = 1 with the crank still spinning, answer the same. tau = 1e300 discards the step
    at t = 0, nothing changed, naming omega, alpha and the resolution of the time."""
    plan = [[1e10, 0.01], [1e10, 0.01], [1.0, 0.01], [1.0, 0.01]]
    out = host({"job": "steps", "fmu": str(fmus[version]), "steps": plan,
                "start": {"theta0": THETA0, "omega0": OMEGA0}}, tmp_path)
    assert out["init"] == OK
    start = 0.0
    call = "fmi3DoStep" if version == 3 else "fmi2DoStep"
    for row in out["rows"]:
        assert row["status"] == DISCARD and row["read"] == OK
        assert start < row["last"] < start + 0.01 and math.isfinite(row["theta"])
        said = row["said"][-1]
        assert said.startswith(f"{call}: the step from t = {start!r} ends at t = "
                               f"{row['last']!r} (theta = {row['theta']!r}, omega = "
                               f"{row['omega']!r}; lastSuccessfulTime)"), said
        words = re.search(r"1000 substeps, the most one step takes, end there: the crank "
                          r"turns at omega = (\S+) rad/s, and the tolerance 1e-08 needs "
                          r"about (\S+) substeps for the whole step \(steps of about (\S+) s "
                          r"fit\)$", said)
        assert words, said
        assert float(words[1]) == row["omega"] and abs(row["omega"]) > 1e6
        assert float(words[2]) > MAX_SUBSTEPS
        assert float(words[3]) == pytest.approx(row["last"] - start, rel=0.05)
        start = row["last"]
    out = host({"job": "steps", "fmu": str(fmus[version]), "steps": [[1e300, 0.01]],
                "start": {"theta0": THETA0, "omega0": OMEGA0}}, tmp_path)
    (row,) = out["rows"]
    assert (row["status"], row["last"], row["theta"], row["omega"]) == (DISCARD, 0.0, THETA0,
                                                                       OMEGA0)
    words = re.search(r"the motion cannot start at t = 0.0 from theta = 0.3, omega = 5.0: at "
                      r"omega = 5.0 rad/s and alpha = (\S+) rad/s2 the tolerance 1e-08 needs "
                      r"substeps shorter than the resolution of the time \((\S+) s\)$",
                      row["said"][-1])
    assert words, row["said"]
    j_red = MECH.solve(THETA0, OMEGA0, 0.0)["J_red"]
    assert float(words[1]) == pytest.approx(1e300 / j_red, rel=1e-6)
    assert float(words[2]) == pytest.approx(4 * np.finfo(float).eps * 0.01, rel=0.05)


@pytest.mark.parametrize("version", (2, 3))
def test_states_round_trip(fmus, tmp_path, version):
    """An FMU state taken halfway through 40 steps, set again, and serialized into a fresh
    instance: the second half runs bit for bit as it did (the integrator's next substep
    is part of the state)."""
    out = host({"job": "states", "fmu": str(fmus[version]), "tau": 2.0, "h": 0.01, "n": 40,
                "start": {"theta0": THETA0, "omega0": OMEGA0}, "outputs": ["alpha", "F21x"]},
               tmp_path)
    assert len(out["second"]) == 20 and out["second"][-1]["omega"] > 50.0
    assert out["again"] == out["second"] and out["fresh"] == out["second"]


@pytest.mark.parametrize("version", (2, 3))
def test_bad_calls_are_errors_never_fatal(fmus, tmp_path, version):
    """Setting a state as a variable, a tolerance of 0 (at initialisation, or tuned
    between steps: it keeps its value), a step of 0, a DoStep in model exchange, the
    tolerance in continuous-time mode, SetContinuousStates with 3 values or a NaN,
    GetDerivatives with 1, a time of inf: Error, with a log naming the call; tau = NaN
    makes the step Discard and the outputs NaN with a Warning (the state keeps its
    value); the tolerance tuned between steps holds; the instance goes on."""
    out = host({"job": "bad", "fmu": str(fmus[version]), "start": {}}, tmp_path)
    a = out["answers"]
    assert a == {"set state theta": ERROR, "tolerance 0": ERROR, "tolerance back": OK,
                 "tau nan": OK, "step nan": DISCARD, "read nan": [WARNING, [None, 0.0]],
                 "step fine": OK, "tolerance tuned": OK, "tolerance tuned 0": ERROR,
                 "step tuned": OK, "tolerance read": 1e-10, "step h 0": ERROR,
                 "enter continuous": OK, "tolerance in continuous time": ERROR,
                 "set states n=3": ERROR, "set states nan": ERROR, "derivatives n=1": ERROR,
                 "do step in model exchange": ERROR, "set time inf": ERROR,
                 "set states fine": OK, "derivatives fine": OK}
    log = " | ".join(text for _, text in out["log"])
    for words in ("'theta' (value reference", "tolerance must be > 0",
                  "input tau = nan is not a finite number", "nContinuousStates = 3",
                  "the continuous state theta = nan"):
        assert words in log, words
    assert all(status != FATAL for status, _ in out["log"])


@pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc is not on PATH")
def test_the_c_host_runs_it_as_fmpy_does(fmus, tmp_path):
    """The C host (``tests/c_host/host.c -d``, no Python in the process) steps the drive
    FMU for 1 s in 100 steps with tau = 2 N.m from the linkage's start values: every
    output it prints equals fmpy's co-simulation of the same steps to 1e-10 of its
    largest value (the hosts' step sizes differ in the last bit: k h against fmpy's
    differences of its times)."""
    unzipped = tmp_path / "fmu"
    with zipfile.ZipFile(fmus[2]) as archive:
        archive.extractall(unzipped)
    model, guid, outputs = model_outputs(unzipped / "modelDescription.xml")
    names = ["theta", "omega", "alpha", "F21x", "J_red"]
    run = subprocess.run([str(compile_host(tmp_path)), "-d", str(unzipped), model, guid,
                          "100", "2.0", "0.0", *(str(outputs[n]) for n in names)],
                         capture_output=True, text=True, env={"PATH": os.environ["PATH"]})
    assert run.returncode == 0, run.stderr
    rows = np.array([[float(v) for v in line.split(",")] for line in run.stdout.split()])
    r = simulate_fmu(str(fmus[2]), stop_time=STOP, output_interval=H,
                     start_values={"tau": 2.0}, output=names)
    assert rows.shape == (100, 6) and np.array_equal(rows[:, 0], r["time"][1:])
    for k, name in enumerate(names, 1):
        assert np.max(np.abs(rows[:, k] - r[name][1:])) <= 1e-10 * np.max(np.abs(rows[:, k])), \
            (name, np.max(np.abs(rows[:, k] - r[name][1:])) / np.max(np.abs(rows[:, k])))


def test_cli(tmp_path, capsys):
    """``linkage-fmu build --native --drive`` builds FourBarDrive.fmu; without --native,
    or for a linkage whose effort is not a moment on its crank (the six-bar driven at its
    slider), it refuses, saying why."""
    assert main(["build", "--native", "--drive", "four_bar", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "FourBarDrive.fmu").is_file()
    assert main(["build", "--drive", "four_bar", "--out", str(tmp_path)]) == 2
    assert "--drive is for native FMUs" in capsys.readouterr().err
    assert main(["build", "--native", "--drive", "six_bar", "--set", "driver=D",
                 "--out", str(tmp_path)]) == 2
    assert "cannot be driven by a torque" in capsys.readouterr().err


def test_check_compares_the_drive_with_simulate(fmus, tmp_path, capsys):
    """``linkage-fmu check`` on a drive FMU (it read resources/FourBarDrive.toml, which
    is not there, and printed a KeyError's traceback): the motion under a constant moment
    over a revolution's time against ``Mechanism.simulate`` (rtol = atol = 1e-13), within
    1e-6 of 1 + |value| (measured 2.1e-12 for the four-bar, 4.5e-8 at most over the
    presets and examples: the crank shaper, whose J_red swings 200-fold), and the outputs
    at the FMU's own states against the direct solver within 1e-9 (measured 2.1e-14).
    The same FMU with its bundled description's coupler mass changed (2 to 2.5 kg) fails
    the check: the reference is the description, the binary another linkage. The FourBar
    of l_AB = 0.3 stops next to its assembly limit, arccos(-0.71875) = 135.95 deg: the
    FMU discards that step, simulate stops in it, the steps before are checked."""
    import json

    for version in (2, 3):
        assert main(["check", "--json", str(fmus[version])]) == 0
        result = json.loads(capsys.readouterr().out)
        assert result["model"] == "FourBarDrive" and result["steps"] == 360
        assert result["motion_error"] <= 1e-6 and result["max_rel_error"] <= 1e-9, result
    heavier = tmp_path / "FourBarDrive.fmu"
    fmu_cache.heavier_coupler(fmus[2], heavier)
    assert main(["check", "--json", str(heavier)]) == 1
    assert json.loads(capsys.readouterr().out)["motion_error"] > 1e-4
    assert main(["check", "--json", str(fmus["limit2"])]) == 0
    captured = capsys.readouterr()
    result = json.loads(captured.out)
    (stop, _), = result["unsolved_deg"]
    limit = math.degrees(math.acos(-0.71875))
    assert limit - 1.0 < stop < limit and result["mismatched"] == 0
    assert f"reached theta = {stop:.6g} deg" in captured.err and "as simulate stops" in captured.err
    assert "Traceback" not in captured.err
    from linkage_fmu.fmi.run import run_fmu

    with pytest.raises(ValueError, match="a drive FMU, whose inputs are tau and the loads"):
        run_fmu(fmus[2])  # revolution() would set theta, an output of the drive FMU


@pytest.mark.parametrize("which", (2, "limit2"))
def test_fuzz(fmus, which):
    """3,000 fuzzed steps from a fresh process (``fmu_fuzz.generate_drive``): moments good,
    huge and not finite, steps of any size and bad ones, tolerances out of range, states
    and parameters set as variables, FMU states restored whole or corrupted, directional
    derivatives asked for: no Fatal and no crash; each bad call Error; each read after a
    step OK with every output finite and Mb equal to tau (1e-12 of the larger of tau and
    J_red alpha), or NaN with a Warning
    where tau is not finite (the step Discarded at its start)."""
    tally, _ = run_drive(fmus[which], 3000, seed=11)
    assert tally[("status", FATAL)] == 0
    assert tally["Mb equal to tau"] > 1000 and tally["nan read"] > 20
    assert tally[("status", ERROR)] > 500 and tally["discard: moment not finite"] > 20
    if which == "limit2":  # the crank reaches the ends of its range
        assert tally["discard in the step"] > 20


# -- friction ---------------------------------------------------------------------------
#: friction in every pair of the slider-crank (pins of 15 to 20 mm on a 50 mm crank), and
#: a flywheel on the crank: parameters set after the build (built with every mu 0)
FRICTION = fmu_fuzz.ENERGY_PARAMETERS
LOAD = fmu_fuzz.ENERGY_LOAD
#: (tau, omega0, stop) of two motions from theta0 = 0.3 with the load on the piston: a
#: crank driven on (to 35 rad/s), and one that slows, stops at t = 0.17 s and sticks
MOTIONS = {"driven": (1.0, 5.0, 0.4), "stops": (-0.5, 3.0, 0.5)}


def friction_reference(tau, omega0, t, theta0=0.3):
    """theta and omega of the slider-crank with :data:`FRICTION` under ``tau`` and
    :data:`LOAD` at the times ``t``, independently of the FMU: scipy's DOP853 (rtol = atol
    = 1e-12) on alpha found by brentq on the direct solver's Mb with friction (within a
    bracket placed about the closed form's root by the secant method), the friction at
    omega = 0 opposing the way the crank moves (the linkage built with that ``drive``);
    omega = 0 a terminal event, after which the band at rest (the direct solver's static
    Mb with drive -1 and +1) says whether the crank sticks (to the end: tau is constant)
    or moves off, and which way."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    from linkage_fmu.presets import linkage

    mechs = {d: linkage("slider_crank", drive=float(d), **FRICTION) for d in (1, -1)}

    def mb(d, th, w, a, method="direct"):
        return float(mechs[d].solve(th, w, a, method=method, load=LOAD, outputs=("Mb",))["Mb"])

    def acceleration(d, th, w):
        a0, a1 = 0.0, 1.0
        f0, f1 = mb(d, th, w, a0, "closed_form") - tau, mb(d, th, w, a1, "closed_form") - tau
        for _ in range(20):
            if f1 == f0 or abs(a1 - a0) <= 1e-12 * (1.0 + abs(a1)):
                break
            a0, a1, f0 = a1, a1 - f1 * (a1 - a0) / (f1 - f0), f1
            f1 = mb(d, th, w, a1, "closed_form") - tau
        width = 1e-9 * (1.0 + abs(a1))

        @functools.cache  # brentq asks again for the bracket's ends
        def f(a):
            return mb(d, th, w, a) - tau

        while f(a1 - width) * f(a1 + width) > 0.0:
            width *= 10.0
        return brentq(f, a1 - width, a1 + width, xtol=1e-14, rtol=1e-15)

    theta, omega = np.full(len(t), np.nan), np.full(len(t), np.nan)
    t0, x = t[0], np.array([theta0, omega0])
    while True:
        if x[1] == 0.0:
            lo, hi = mb(-1, x[0], 0.0, 0.0), mb(1, x[0], 0.0, 0.0)
            d = 1 if tau > hi else -1 if tau < lo else 0
            if d == 0:
                theta[t >= t0], omega[t >= t0] = x[0], 0.0
                return theta, omega
        else:
            d = 1 if x[1] > 0.0 else -1

        def stop(s, y):
            return y[1]

        stop.terminal, stop.direction = True, -d
        keep = np.flatnonzero(t >= t0)
        sol = solve_ivp(lambda s, y, d=d: [y[1], acceleration(d, y[0], y[1])], (t0, t[-1]), x,
                        method="DOP853", rtol=1e-12, atol=1e-12, t_eval=t[keep], events=stop)
        theta[keep[:len(sol.t)]], omega[keep[:len(sol.t)]] = sol.y
        if sol.status != 1:
            return theta, omega
        t0, x = sol.t_events[0][0], np.array([sol.y_events[0][0][0], 0.0])


@pytest.fixture(scope="module")
def friction_fmus(tmp_path_factory) -> dict:
    """The slider-crank's drive FMUs (FMI 2.0 and 3.0, built with every mu 0)."""
    out = tmp_path_factory.mktemp("friction")
    return {v: build_native_fmu("slider_crank", out / str(v), v, drive=True) for v in (2, 3)}


@pytest.fixture(scope="module")
def six_bar_drives(tmp_path_factory) -> dict:
    """The six-bar's drive FMUs (FMI 2.0 and 3.0): its C with friction takes the
    compiler about 20 s a version, so only the test that needs them builds them."""
    out = tmp_path_factory.mktemp("six_bar")
    return {v: build_native_fmu("six_bar", out / str(v), v, drive=True) for v in (2, 3)}


@pytest.fixture(scope="module")
def friction_references() -> dict:
    """:func:`friction_reference` of each of :data:`MOTIONS` every 10 ms (theta, omega),
    computed once for the package's sources, this module's reference, numpy's and scipy's
    versions (``fmu_cache``; it takes a minute)."""
    import scipy

    def compute(folder: Path) -> None:
        for name, (tau, omega0, stop) in MOTIONS.items():
            t = np.linspace(0.0, stop, round(stop / H) + 1)
            np.save(folder / f"{name}.npy", np.array(friction_reference(tau, omega0, t)))

    made = fmu_cache.entry("reference-" + fmu_cache.key(
        "friction_reference", inspect.getsource(friction_reference), MOTIONS, FRICTION, LOAD,
        H, np.__version__, scipy.__version__), compute)
    return {name: tuple(np.load(made / f"{name}.npy")) for name in MOTIONS}


def friction_run(fmu, name, fmi_type="CoSimulation", **kw):
    tau, omega0, stop = MOTIONS[name]
    start = {**FRICTION, "tau": tau, "load": LOAD, "theta0": 0.3, "omega0": omega0}
    if fmi_type == "CoSimulation":
        start["tolerance"] = kw.pop("tolerance", 1e-12)
    return simulate_fmu(str(fmu), stop_time=stop, output_interval=H, fmi_type=fmi_type,
                        start_values=start, output=["theta", "omega", "alpha", "Mb", "motion"],
                        **kw)


@pytest.mark.parametrize("version", (2, 3))
@pytest.mark.parametrize("name", MOTIONS)
def test_friction_cosimulation_against_the_reference(friction_fmus, friction_references,
                                                      version, name):
    """The slider-crank's drive FMU with friction set after the build, co-simulated by
    fmpy at the tolerance 1e-12, follows :func:`friction_reference` to 1e-6 rad in theta
    (measured: 1.2e-9 rad driven, 8.5e-13 rad through the stop) and 1e-5 rad/s in omega;
    where it moves, the direct solver's Mb at its theta, omega, alpha equals tau to 1e-9
    of max(1, |J_red alpha|); the crank that stops does so between 0.16 and 0.18 s and
    stays (motion 0, theta constant to the bit, omega and alpha 0)."""
    from linkage_fmu.presets import linkage

    r = friction_run(friction_fmus[version], name)
    theta, omega = friction_references[name]
    assert np.max(np.abs(r["theta"] - theta)) <= 1e-6
    assert np.max(np.abs(r["omega"] - omega)) <= 1e-5
    moving = r["omega"] != 0.0
    mech = linkage("slider_crank", **FRICTION)
    sol = mech.solve(r["theta"][moving], r["omega"][moving], r["alpha"][moving],
                     method="direct", load=LOAD)
    tau = MOTIONS[name][0]
    assert np.all(np.abs(sol["Mb"] - tau) <= 1e-9 * np.maximum(1.0, np.abs(
        sol["J_red"] * r["alpha"][moving])))
    if name == "stops":
        stuck = np.flatnonzero(r["motion"] == 0)
        assert 0.16 <= r["time"][stuck[0]] <= 0.18 and stuck[-1] == len(r) - 1
        assert np.all(np.diff(stuck) == 1) and np.all(r["theta"][stuck] == r["theta"][-1])
        assert np.all(r["omega"][stuck] == 0.0) and np.all(r["alpha"][stuck] == 0.0)
    else:
        assert np.all(r["motion"] == 1)


@pytest.mark.parametrize("version", (2, 3))
def test_friction_model_exchange_against_the_reference(friction_fmus, friction_references,
                                                       version):
    """Model exchange through fmpy's CVode (rtol 1e-10) with its state events (the event
    indicators ``z_forwards``, ``z_backwards``; the stop an event, the band deciding in
    the event update) follows :func:`friction_reference` to 1e-6 rad in theta
    (measured: 8e-9 rad driven, 3e-10 rad through the stop); the crank that stops stays,
    motion 0."""
    for name in MOTIONS:
        r = friction_run(friction_fmus[version], name, "ModelExchange",
                         relative_tolerance=1e-10, record_events=False)
        theta, omega = friction_references[name]
        assert np.max(np.abs(r["theta"] - theta)) <= 1e-6, name
        assert np.max(np.abs(r["omega"] - omega)) <= 1e-4, name
        assert r["motion"][-1] == (0 if name == "stops" else 1)


def test_from_rest_the_band_holds_or_lets_go(friction_fmus):
    """From rest at theta0 = 0.3 with the load on the piston, the band [lo, hi] is the
    direct solver's static Mb with drive -1 and +1 there. A moment inside it (its middle,
    and 1 % of its width from either edge) leaves theta unchanged over 200 steps of 10
    ms (to 1e-9 rad; the FMU keeps it to the bit), motion 0; a moment 1e-3 N.m past
    either edge breaks away that way within the first step (motion +-1, theta moved that
    way)."""
    lo, hi = band_at_rest()
    assert hi - lo > 0.1  # a band to stick in
    for tau, way in ((0.5 * (lo + hi), 0), (lo + 0.01 * (hi - lo), 0),
                     (hi - 0.01 * (hi - lo), 0), (hi + 1e-3, 1), (lo - 1e-3, -1)):
        r = simulate_fmu(str(friction_fmus[2]), stop_time=2.0 if not way else H,
                         output_interval=H, fmi_type="CoSimulation",
                         start_values={**FRICTION, "tau": tau, "load": LOAD, "theta0": 0.3,
                                       "omega0": 0.0, "tolerance": 1e-10},
                         output=["theta", "omega", "motion", "Mb", "F21x"])
        if not way:
            assert len(r) == 201 and np.max(np.abs(r["theta"] - 0.3)) <= 1e-9, tau
            assert np.all(r["motion"][1:] == 0) and np.all(r["omega"] == 0.0), tau
            # held: the linkage takes tau; the reactions are those at the band's edge on
            # tau's side of its middle (the direct solver's), as simulate reports them
            assert np.all(r["Mb"][1:] == tau), tau
            if tau != 0.5 * (lo + hi):
                ref = edge_state(1.0 if tau > 0.5 * (lo + hi) else -1.0)["F21x"]
                assert np.allclose(r["F21x"][1:], ref, rtol=1e-12, atol=0.0), tau
        else:
            assert r["motion"][-1] == way and way * (r["theta"][-1] - 0.3) > 0.0, tau


@pytest.mark.parametrize("version", (2, 3))
def test_friction_states_round_trip(friction_fmus, tmp_path, version):
    """With friction, an FMU state taken at t = 0.15 s, before the crank of the "stops"
    motion stops (0.17 s) and sticks, set again and serialized into a fresh instance: the
    second half, through the stop and the sticking, runs bit for bit as it did."""
    tau, omega0, _ = MOTIONS["stops"]
    out = host({"job": "states", "fmu": str(friction_fmus[version]), "tau": tau, "h": 0.01,
                "n": 30, "start": {**FRICTION, "load": LOAD, "theta0": 0.3, "omega0": omega0},
                "outputs": ["alpha", "F21x", "Mf_A", "P_loss"]}, tmp_path)
    assert out["first"][-1]["omega"] > 0.0 and out["second"][-1]["omega"] == 0.0
    assert out["again"] == out["second"] and out["fresh"] == out["second"]


def edge_state(drive, theta=0.3):
    """The direct solver's outputs at rest at ``theta`` with friction opposing a start
    in the direction ``drive``."""
    from linkage_fmu.presets import linkage

    return linkage("slider_crank", drive=drive, **FRICTION).solve(
        theta, 0.0, 0.0, method="direct", load=LOAD)


def band_at_rest(theta=0.3):
    """The friction band at rest of the slider-crank with :data:`FRICTION` and
    :data:`LOAD` at ``theta``: the direct solver's static Mb with drive -1 and +1."""
    from linkage_fmu.presets import linkage

    return tuple(float(linkage("slider_crank", drive=d, **FRICTION).solve(
        theta, 0.0, 0.0, method="direct", load=LOAD)["Mb"]) for d in (-1.0, 1.0))


@pytest.mark.parametrize("version", (2, 3))
def test_model_exchange_from_rest(friction_fmus, version):
    """Model exchange from rest (the initial event update decides): tau in the middle of
    the band leaves theta at 0.3 exactly for 0.5 s (motion 0); 1e-3 N.m past either edge
    it breaks away that way."""
    lo, hi = band_at_rest()
    for tau, way in ((0.5 * (lo + hi), 0), (hi + 1e-3, 1), (lo - 1e-3, -1)):
        r = simulate_fmu(str(friction_fmus[version]), stop_time=0.5, output_interval=H,
                         fmi_type="ModelExchange",
                         start_values={**FRICTION, "tau": tau, "load": LOAD, "theta0": 0.3,
                                       "omega0": 0.0}, output=["theta", "omega", "motion"])
        if not way:
            assert np.all(r["theta"] == 0.3) and np.all(r["motion"][1:] == 0), tau
        else:
            assert np.all(r["motion"][1:] == way), tau
            assert np.all(way * np.diff(r["theta"]) > 0.0), tau


def test_a_torque_ramp_breaks_away_where_it_crosses_the_band(friction_fmus):
    """From rest, tau rising at 1 N.m/s from the middle of the band crosses its upper
    edge at t* = (hi - tau0) / 1 N.m/s (0.179 s). Model exchange (CVode, the indicator
    z_forwards crossing 0) breaks away at t* to 1e-9 s: theta is 0.3 exactly until then,
    and grows after; co-simulation (tau held over each 1 ms step, the band deciding at its
    start) in the first step that starts past t*."""
    lo, hi = band_at_rest()
    tau0 = 0.5 * (lo + hi)
    t_star = hi - tau0
    ramp = np.array([(0.0, tau0, LOAD), (1.0, tau0 + 1.0, LOAD)],
                    dtype=[("time", float), ("tau", float), ("load", float)])
    start = {**FRICTION, "theta0": 0.3, "omega0": 0.0}
    r = simulate_fmu(str(friction_fmus[2]), stop_time=0.3, output_interval=0.001,
                     fmi_type="ModelExchange", input=ramp, start_values=start,
                     output=["theta", "motion"])
    first = np.flatnonzero(r["motion"] != 0)[0]
    assert abs(r["time"][first] - t_star) <= 1e-9, (r["time"][first], t_star)
    assert np.all(r["theta"][:first + 1] == 0.3) and np.all(np.diff(r["theta"][first:]) > 0)
    r = simulate_fmu(str(friction_fmus[2]), stop_time=0.3, output_interval=0.001,
                     input=ramp, start_values={**start, "tolerance": 1e-10},
                     output=["theta", "motion"])
    moved = np.flatnonzero(r["theta"] != 0.3)[0]
    assert r["time"][moved - 1] <= t_star + 0.001 < r["time"][moved] + 1e-12, \
        (r["time"][moved], t_star)
    assert np.all(r["motion"][moved:] == 1) and np.all(r["motion"][1:moved] == 0)


@pytest.mark.slow
@pytest.mark.parametrize("version", (2, 3))
def test_six_bar_drive_takes_only_the_crank_moment(six_bar_drives, tmp_path, version):
    """The six-bar's drive FMU is built for ``driver = OA`` only (its structures are those
    whose effort is a moment on the crank): setting ``driver`` to AB, O1B, KD or D is
    Error (never Fatal), with a log naming the parameter and the value allowed, and the
    instance initialises on with OA; the modelDescription says so."""
    from fmpy import read_model_description

    md = read_model_description(str(six_bar_drives[version]))
    (driver,) = [v for v in md.modelVariables if v.name == "driver"]
    assert "one of OA: a drive FMU drives the crank" in driver.description
    for value in ("AB", "O1B", "KD", "D"):
        out = host({"job": "strings", "fmu": str(six_bar_drives[version]),
                    "strings": {"driver": value}}, tmp_path)
        assert out["set"] == ERROR and out["exit"] == OK, (value, out)
        assert all(status != FATAL for status, _ in out["log"])
        assert any("driver must be one of 'OA'" in text for _, text in out["log"]), out["log"]


def test_friction_fuzz_and_energy(friction_fmus):
    """The drive fuzz (``fmu_fuzz.generate_drive``, 2,000 steps) with random friction in
    every pair in half its episodes, some from rest, some moments small: no Fatal, every
    read where the crank moves with Mb equal to tau, some stuck;
    and the energy balance over 2,000 random-moment steps of 1 ms
    (``fmu_fuzz.run_energy``: the crank sticks, breaks away, reverses): the work of tau,
    minus the friction's loss, plus the load's and gravity's work, equals the change of
    the kinetic energy to 2e-5 of the work (measured 5.7e-6; Simpson's rule on P_loss
    over each step is the limit: P_loss has kinks where a reaction passes through 0).
    ``python tests/fmu_fuzz.py DIR --drive --energy --steps 10000`` runs 10^4."""
    tally, _ = run_drive(friction_fmus[2], 2000, seed=5, preset="slider_crank")
    assert tally[("status", FATAL)] == 0
    assert tally["Mb equal to tau"] > 500 and tally["stuck"] > 10
    energy = fmu_fuzz.run_energy(friction_fmus[2], 2000, seed=1)
    assert energy["relative"] <= 2e-5, energy
    assert energy["stuck steps"] > 10 and energy["reversals"] >= 2, energy


def test_the_two_roots_of_the_acceleration_with_friction_agree(friction_fmus, tmp_path):
    """With friction, alpha solves tau = Mb(alpha) twice, by two algorithms kept apart on
    purpose: simulate's Newton (motion.py, from alpha = 0, the library's kernel and its
    exact tangent) and the drive FMU's bracketed secant (backend_native.c, from
    Eksergian's estimate, its kernel's loops stopping once they converge). At 72 states
    of the slider-crank with :data:`FRICTION` (12 angles over the turn, moving forwards
    and backwards at three speeds, one near rest) under a driving and a braking moment,
    the FMU's derivative of omega (model exchange, the crank moving the way of omega)
    equals simulate's alpha to 1e-12 of the root's scale ``|alpha| + (|tau| + |Mb|) /
    (dMb/dalpha)``, the size both iterations' tests are relative to (measured 4.3e-16:
    both stop within rounding of one root)."""
    from linkage_fmu import motion
    from linkage_fmu.presets import linkage

    mech = linkage("slider_crank", **FRICTION)
    angles = np.linspace(0.0, 2.0 * np.pi, 12, endpoint=False) + 0.1
    for d in (1, -1):
        way = motion._Direction(mech, d, {"load": LOAD}, 0.0)
        states = [[float(th), d * w] for th in angles for w in (1e-3, 3.0, 40.0)]
        for tau in (1.0, -0.5):
            out = host({"job": "exchange", "fmu": str(friction_fmus[2]), "tau": tau,
                        "start": {**FRICTION, "load": LOAD, "theta0": 0.3,
                                  "omega0": d * 5.0}, "states": states}, tmp_path)
            for (theta, omega), (status, dx) in zip(states, out["derivatives"]):
                assert status == OK and dx[0] == omega, (theta, omega, out["log"])
                alpha = way.acceleration(0.0, theta, omega, tau)
                Mb, slope = way.moment(theta, omega, alpha)
                scale = abs(alpha) + (abs(tau) + abs(Mb)) / slope
                assert abs(dx[1] - alpha) <= 1e-12 * scale, (theta, omega, tau, dx[1], alpha)


# -- stops, breakaways and reversals in every importer ------------------------------------
def test_a_decelerating_crank_stops_and_sticks_in_cosimulation(friction_fmus):
    """From theta0 = 0.3 at 0.01 rad/s under a tau 90 % of the way up the band (friction
    of :data:`FRICTION`, the load on the piston) the crank decelerates and stops, and
    sticks: ``Mechanism.simulate`` (rtol 1e-12) stops it at t_s = 5.9695 ms. Co-simulated
    at the tolerances 1e-8 and 1e-12 with steps of 1 ms and 10 us, FMI 2.0 and 3.0, every
    step is OK to 10 ms (before, a stop's substeps shrank towards it until 1000 of them
    and a Discard); motion is 1 until the step that holds t_s and 0 from the end of it,
    and theta equals the library's to 1e-9 rad all along."""
    from linkage_fmu.presets import linkage

    lo, hi = band_at_rest()
    tau, stop = lo + 0.9 * (hi - lo), 0.01
    mech = linkage("slider_crank", **FRICTION)
    for h in (1e-3, 1e-5):
        t = np.linspace(0.0, stop, round(stop / h) + 1)
        ref = mech.simulate(tau, t, theta0=0.3, omega0=0.01, load=LOAD, rtol=1e-12,
                            atol=1e-12)
        (stuck,) = ref.attrs["switches"]  # it starts moving: the stop alone
        assert stuck.to == 0 and 5.96e-3 < stuck.time < 5.98e-3, stuck
        for version in (2, 3):
            for tol in (1e-8, 1e-12):
                r = simulate_fmu(str(friction_fmus[version]), stop_time=stop, output_interval=h,
                                 fmi_type="CoSimulation", output=["theta", "motion"],
                                 start_values={**FRICTION, "tau": tau, "load": LOAD,
                                               "theta0": 0.3, "omega0": 0.01,
                                               "tolerance": tol})
                assert len(r) == len(t) and r["time"][-1] == pytest.approx(stop), (h, tol)
                assert np.max(np.abs(r["theta"] - ref["theta"].to_numpy())) <= 1e-9, (h, tol)
                moving = r["time"] < stuck.time - 1e-12
                assert np.all(r["motion"][1:][moving[1:]] == 1), (h, tol)
                assert np.all(r["motion"][r["time"] >= stuck.time + h] == 0), (h, tol)


#: The three motions of the four-bar with friction in every pin (mu 0.2, pins of 10 mm,
#: set at run time where the importer can) from rest at theta0 = 3 rad, every 1 ms; the
#: band at rest there is [lo, hi] = [-1.90458, -1.70524] N.m:
#:
#: - "coast": tau = 0. Gravity swings the crank away at once; it turns round 8 times and
#:   sticks at 2.1232 s (10 switches, the start among them); 2.5 s.
#: - "ramp forwards": tau rises from -1.805 N.m (the band's middle) at 2 N.m/s until
#:   t = 0.05 s and then holds -1.705 N.m: the crank sticks while tau lies in the band,
#:   breaks away forwards where tau crosses hi (t = 49.8817 ms), creeps 1.2 mrad and
#:   sticks again (0.668 s); 1 s.
#: - "ramp backwards": tau falls from -1.805 N.m at 2 N.m/s until 0.05 s, then holds
#:   -1.905 N.m: breaks away backwards at 49.7876 ms, sticks again at 0.6805 s; 1 s.
#:
#: The torque ramps only while the crank sticks, and holds from a communication point on,
#: so that every importer applies the same torque to a moving crank: fmpy's and fmusim's
#: CVode set a continuous input only in their root function, so that their right-hand
#: side holds its value from the last root check, an error of the ramp over a step.
#: Each entry: (tau at 0, its rate until RAMP_END, stop time).
FRICTION_MOTIONS = {"coast": (0.0, 0.0, 2.5), "ramp forwards": (-1.805, 2.0, 1.0),
                    "ramp backwards": (-1.805, -2.0, 1.0)}
FOUR_BAR_FRICTION = {f"{k}_{p}": (0.2 if k == "mu" else 0.01) for p in "ABCD"
                     for k in ("mu", "r")}
MOTION_START = {"theta0": 3.0, "omega0": 0.0}
RAMP_END, MOTION_H, CS_TOLERANCE = 0.05, 1e-3, 1e-10


def motion_inputs(name) -> list:
    """(time, tau) rows of the motion's torque, linear between them."""
    tau0, rate, stop = FRICTION_MOTIONS[name]
    if not rate:
        return [(0.0, tau0), (stop, tau0)]
    held = tau0 + rate * RAMP_END
    return [(0.0, tau0), (RAMP_END, held), (stop, held)]


def motion_torque(name, hold=None):
    """The motion's tau(t, theta, omega) for ``simulate``: as the inputs say, or (``hold``)
    held over each communication step from its start, as a co-simulation importer sets it."""
    rows = np.array(motion_inputs(name))

    def tau(t, th, w):
        if hold:
            t = hold * math.floor(t / hold + 1e-9)
        return float(np.interp(t, rows[:, 0], rows[:, 1]))
    return tau


@pytest.fixture(scope="module")
def motion_references() -> dict:
    """``Mechanism.simulate`` (rtol = atol = 1e-12) of each of :data:`FRICTION_MOTIONS`
    every :data:`MOTION_H`, under the torque of model exchange and, held over each step,
    of co-simulation: theta and the switches' ``to``, computed once per sources
    (``fmu_cache``)."""
    import scipy

    from linkage_fmu.presets import linkage

    def compute(folder: Path) -> None:
        mech = linkage("four_bar", **FOUR_BAR_FRICTION)
        for k, name in enumerate(FRICTION_MOTIONS):
            stop = FRICTION_MOTIONS[name][2]
            t = np.linspace(0.0, stop, round(stop / MOTION_H) + 1)
            for kind, hold in (("me", None), ("cs", MOTION_H)):
                run = mech.simulate(motion_torque(name, hold), t, theta0=3.0, omega0=0.0,
                                    rtol=1e-12, atol=1e-12)
                np.save(folder / f"{k}-{kind}.npy", run["theta"].to_numpy())
                np.save(folder / f"{k}-{kind}-to.npy", [s.to for s in run.attrs["switches"]])

    made = fmu_cache.entry("reference-" + fmu_cache.key(
        "motion_references", inspect.getsource(motion_torque), FRICTION_MOTIONS,
        FOUR_BAR_FRICTION, RAMP_END, MOTION_H, np.__version__, scipy.__version__), compute)
    return {(name, kind): (np.load(made / f"{k}-{kind}.npy"),
                           np.load(made / f"{k}-{kind}-to.npy").tolist())
            for k, name in enumerate(FRICTION_MOTIONS) for kind in ("me", "cs")}


def on_the_grid(time, theta, motion, stop):
    """theta at each multiple of :data:`MOTION_H` (the last row at it: an importer may
    record an event's two sides), and the switches: the changes of ``motion`` after t = 0."""
    k = np.round(np.asarray(time) / MOTION_H)
    last = {}
    for i in np.flatnonzero(np.abs(np.asarray(time) - k * MOTION_H) <= 1e-9):
        last[int(k[i])] = i
    assert sorted(last) == list(range(round(stop / MOTION_H) + 1)), "rows missing"
    switches = []
    for m in np.asarray(motion)[np.asarray(time) > 0]:
        if not switches or switches[-1] != m:
            switches.append(int(m))
    return np.asarray(theta)[[last[j] for j in sorted(last)]], switches


def check_motion(references, name, kind, time, theta, motion, tolerance):
    """The run's theta within ``tolerance`` of the reference at every step and its
    switches those of the reference, all of them; the largest error."""
    ref, to = references[(name, kind)]
    on, switches = on_the_grid(time, theta, motion, FRICTION_MOTIONS[name][2])
    error = float(np.max(np.abs(on - ref)))
    assert switches == to, (name, kind, switches, to)
    assert error <= tolerance, (name, kind, error)
    return error


#: explicit Euler's step in the motions, and its bound on theta's error: first order,
#: 300 h (measured: 160 h to 170 h in the coast at h = 1e-4, 2e-5 and 1e-5, the ramps'
#: far less)
EULER_H, EULER_BOUND = 1e-4, 300.0


@pytest.mark.parametrize("version", (2, 3))
@pytest.mark.parametrize("name", FRICTION_MOTIONS)
def test_friction_motions_through_fmpy(fmus, motion_references, version, name):
    """fmpy runs each of :data:`FRICTION_MOTIONS` on the four-bar's drive FMU (built
    without friction, friction set as start values), FMI 2.0 and 3.0, with every switch
    of ``Mechanism.simulate``'s (10 of 10 in the coast): co-simulation at the tolerance
    1e-10 (against the torque held over each step) and model exchange with CVode
    (rtol 1e-10, its state events) within 1e-7 rad of theta (measured: 8.1e-9 and
    3.2e-8 rad in the coast), explicit Euler at 0.1 ms within 300 h. Every event
    indicator recorded, on both sides of every event, is nonzero."""
    tau0, rate, stop = FRICTION_MOTIONS[name]
    inputs = np.array(motion_inputs(name), dtype=[("time", float), ("tau", float)])
    start = {**FOUR_BAR_FRICTION, **MOTION_START}
    common = dict(stop_time=stop, input=inputs, output=["theta", "motion"])
    r = simulate_fmu(str(fmus[version]), fmi_type="CoSimulation", output_interval=MOTION_H,
                     start_values={**start, "tolerance": CS_TOLERANCE}, **common)
    check_motion(motion_references, name, "cs", r["time"], r["theta"], r["motion"], 1e-7)
    r = simulate_fmu(str(fmus[version]), fmi_type="ModelExchange", solver="CVode",
                     relative_tolerance=1e-10, output_interval=MOTION_H, start_values=start,
                     **{**common, "output": ["theta", "motion", "z_forwards", "z_backwards"]})
    check_motion(motion_references, name, "me", r["time"], r["theta"], r["motion"], 1e-7)
    assert np.all(r["z_forwards"] != 0.0) and np.all(r["z_backwards"] != 0.0)
    r = simulate_fmu(str(fmus[version]), fmi_type="ModelExchange", solver="Euler",
                     step_size=EULER_H, output_interval=EULER_H, start_values=start, **common)
    check_motion(motion_references, name, "me", r["time"], r["theta"], r["motion"],
                 EULER_BOUND * EULER_H)


def importer(variable: str, command: str) -> str:
    """The importer's executable: ``$variable``, else ``command`` on PATH; the test is
    skipped, saying so, where there is neither."""
    exe = os.environ.get(variable) or shutil.which(command)
    if not exe:
        pytest.skip(f"no {command}: set ${variable} to its executable or put it on PATH")
    return exe


def motion_csv(name, path: Path, before: dict | None = None) -> Path:
    """The motion's torque as an importer's input file, after the columns ``before``: the
    FMU Compliance Checker reads a parameter's column right only before the inputs'
    (measured with tolerance, tau and load in each of the six orders: with tolerance
    after an input it set tolerance to another column's value)."""
    before = before or {}
    lines = [",".join(["time", *before, "tau"])]
    lines += [",".join(repr(float(v)) for v in (t, *before.values(), tau))
              for t, tau in motion_inputs(name)]
    path.write_text("\n".join(lines) + "\n")
    return path


def read_csv(path: Path) -> dict:
    import csv

    with open(path) as f:
        rows = [r for r in csv.reader(f) if r]
    names = [n.strip().strip('"') for n in rows[0]]
    data = np.array([[float(x) for x in r] for r in rows[1:]])
    return {n: data[:, j] for j, n in enumerate(names)}


@pytest.mark.parametrize("version", (2, 3))
def test_friction_motions_through_fmusim(fmus, motion_references, tmp_path, version):
    """fmusim (Reference-FMUs 0.0.39, ``$FMUSIM`` or ``fmusim`` on PATH) runs each of
    :data:`FRICTION_MOTIONS` (friction and start as ``--start-value``), FMI 2.0 and 3.0,
    with every switch: co-simulation at the tolerance 1e-10 and model exchange with CVode
    (``--tolerance 1e-10``) within 1e-7 rad of theta (measured: 8.1e-9 and 3.2e-8 rad in
    the coast, 5.7e-8 rad at most in the ramps), its explicit Euler (one step per output
    interval, 0.1 ms) within 300 h."""
    exe = importer("FMUSIM", "fmusim")
    start = [a for k, v in {**FOUR_BAR_FRICTION, **MOTION_START}.items()
             for a in ("--start-value", k, repr(v))]
    for name, (_, _, stop) in FRICTION_MOTIONS.items():
        csv_in = motion_csv(name, tmp_path / "in.csv")
        for kind, options, h, bound in (
                ("cs", ["--start-value", "tolerance", repr(CS_TOLERANCE)], MOTION_H, 1e-7),
                ("me", ["--solver", "cvode", "--tolerance", "1e-10"], MOTION_H, 1e-7),
                ("me", ["--solver", "euler"], EULER_H, EULER_BOUND * EULER_H)):
            out = tmp_path / "out.csv"
            out.unlink(missing_ok=True)
            run = subprocess.run(
                [exe, "--interface-type", kind, "--input-file", str(csv_in), "--stop-time",
                 repr(stop), "--output-interval", repr(h), "--output-variable", "theta",
                 "--output-variable", "motion", *start, *options, "--output-file", str(out),
                 str(fmus[version])], capture_output=True, text=True, timeout=300)
            assert run.returncode == 0 and out.is_file(), (name, kind, run.stdout + run.stderr)
            r = read_csv(out)
            check_motion(motion_references, name, kind, r["time"], r["theta"], r["motion"],
                         bound)


@pytest.fixture(scope="module")
def motion_fmu(tmp_path_factory) -> Path:
    """The four-bar's drive FMU (FMI 2.0) with the motions' friction and start as its
    defaults: the FMU Compliance Checker sets the variables of its input file at every
    step, where a fixed parameter cannot be set (the tolerance is tunable)."""
    from linkage_fmu import presets

    d = presets.preset("four_bar").copy().start(theta=3.0, omega=0.0)
    return build_native_fmu(d, tmp_path_factory.mktemp("motion"), 2, drive=True,
                            **FOUR_BAR_FRICTION)


def test_friction_motions_through_the_compliance_checker(motion_references, tmp_path,
                                                          request):
    """The FMU Compliance Checker (``$FMUCHECK`` or ``fmuCheck.linux64`` on PATH; it reads
    FMI 1.0 and 2.0 only) runs each of :data:`FRICTION_MOTIONS` with every switch (10 of
    10 in the coast; before, its model exchange found 1): co-simulation at the tolerance
    1e-10 (a column of its input file: the Checker sets it at every step, which the
    tunable ``tolerance`` takes) within 1e-7 rad of theta, and its model exchange
    (explicit Euler, 0.1 ms, an event at the step after each indicator changes sign)
    within 300 h."""
    exe = importer("FMUCHECK", "fmuCheck.linux64")
    fmu = request.getfixturevalue("motion_fmu")
    for name, (_, _, stop) in FRICTION_MOTIONS.items():
        for kind, h, bound in (("cs", MOTION_H, 1e-7), ("me", EULER_H, EULER_BOUND * EULER_H)):
            csv_in = motion_csv(name, tmp_path / "in.csv",
                                {"tolerance": CS_TOLERANCE} if kind == "cs" else None)
            out, log = tmp_path / "out.csv", tmp_path / "log.txt"
            out.unlink(missing_ok=True)
            run = subprocess.run([exe, "-k", kind, "-n", "0", "-h", repr(h), "-s", repr(stop),
                                  "-i", str(csv_in), "-f", "-l", "3", "-e", str(log), "-o",
                                  str(out), str(fmu)], capture_output=True, text=True,
                                 timeout=300)
            assert run.returncode == 0 and out.stat().st_size, (name, kind, log.read_text())
            r = read_csv(out)
            check_motion(motion_references, name, kind, r["time"], r["theta"], r["motion"],
                         bound)


@pytest.mark.parametrize("version", (2, 3))
def test_a_start_value_that_is_not_finite_reads_with_a_warning(fmus, tmp_path, version):
    """In initialisation mode, with omega0 (or theta0) set to NaN or an infinity, the
    reads of theta and omega, and the model exchange's continuous states, answer Warning
    (before: OK with NaN), the log naming the start parameter; a finite start reads OK."""
    for start in ({"omega0": math.nan}, {"omega0": math.inf}, {"theta0": -math.inf},
                  {"omega0": 2.5}):
        out = host({"job": "initial", "fmu": str(fmus[version]), "start": start}, tmp_path)
        (name, value), = start.items()
        for kind in ("cs", "me"):
            row = out[kind]
            assert row["set"] == OK, (start, kind)
            if math.isfinite(value):
                assert row["read"] == OK and row["values"][name == "omega0"] == value
                assert row.get("states", OK) == OK
                continue
            assert row["read"] == WARNING, (start, kind, row)
            assert row.get("states", WARNING) == WARNING, (start, kind, row)
            assert any(status == WARNING and f"it starts at {name} = " in text
                       for status, text in row["log"]), row["log"]
