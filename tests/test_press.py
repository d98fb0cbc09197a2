"""The crank press of ``examples/press``: a motor FMU of the project's own (FMI 2.0 on the
project's FMI framework, ``examples/press/motor.py``) driving the press's drive FMU, as
an OSP system structure that libcosim runs.

The reference is ``Mechanism.simulate`` (scipy's DOP853 over the library's solver) of the
same press, with the same friction in its pins and guide, under the same motor law, its
rotor a flywheel on the crank. libcosim's
fixed-step algorithm holds the motor's torque over each communication step, so the two
differ by a coupling error of first order in the step; the example's claim is that at a
fine step it is within 1e-6 of the speed.
"""

from __future__ import annotations

import doctest
import math
import sys
from pathlib import Path

import numpy as np
import pytest

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "press"
sys.path.insert(0, str(EXAMPLE))

import motor  # noqa: E402
import press  # noqa: E402
import run  # noqa: E402

#: the press at work: the crank at speed, the ram 34 deg into its working stroke
AT_WORK = {"theta0": math.pi / 2 + 0.6, "omega0": 6.0}


@pytest.fixture(scope="module")
def fmus(tmp_path_factory) -> Path:
    return press.build(tmp_path_factory.mktemp("press"))


@pytest.mark.parametrize("module", [motor, press, run], ids=["motor", "press", "run"])
def test_the_examples_in_the_docstrings(module):
    """The examples of ``motor.py``, ``press.py`` and ``run.py`` hold (they are outside
    the package, which pytest's doctest collection covers)."""
    failed, tried = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
    assert tried > 0 and failed == 0


def test_the_motor_fmu_is_a_valid_fmu(fmus):
    """fmpy's validation (the FMI 2.0 schema and its rules on the model structure) finds no
    problem in the motor FMU's hand-written modelDescription, nor in the press's."""
    validation = pytest.importorskip("fmpy.validation")
    assert validation.validate_fmu(str(fmus / press.MOTOR_FMU)) == []
    assert validation.validate_fmu(str(fmus / press.PRESS_FMU)) == []


def motor(fmus, tmp_path, T_stall: float, omega_noload: float):
    """The motor FMU instantiated through fmpy with this line and initialised: the slave
    and its value references by name."""
    fmpy = pytest.importorskip("fmpy")
    from fmpy.fmi2 import FMU2Slave

    path = str(fmus / press.MOTOR_FMU)
    md = fmpy.read_model_description(path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    slave = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(path, str(tmp_path)),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="motor")
    slave.instantiate()
    slave.setReal([vr["T_stall"], vr["omega_noload"]], [T_stall, omega_noload])
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    return slave, vr


def test_the_motor_fmu_computes_its_line(fmus, tmp_path):
    """The motor FMU stepped through fmpy: at crank speeds from reverse to past no-load,
    ``tau`` is the line ``T_stall * (1 - omega / omega_noload)`` and ``P = tau * omega``,
    to 1e-15 relative of the formula evaluated here."""
    T0, w0 = 150.0, 8.0
    slave, vr = motor(fmus, tmp_path, T0, w0)
    got = []
    for k, omega in enumerate([-2.0, 0.0, 3.5, 8.0, 11.0]):
        slave.setReal([vr["omega"]], [omega])
        slave.doStep(k * 0.01, 0.01)
        tau, power = slave.getReal([vr["tau"], vr["P"]])
        expected = T0 * (1.0 - omega / w0)
        got.append((tau, power, expected, expected * omega))
    slave.terminate()
    slave.freeInstance()
    tau, power, expected, expected_power = np.array(got).T
    assert np.allclose(tau, expected, rtol=1e-15, atol=1e-13), got
    assert np.allclose(power, expected_power, rtol=1e-15, atol=1e-13), got
    assert list(expected) == [187.5, 150.0, 84.375, 0.0, -56.25]


def test_the_motor_fmu_discards_what_it_cannot_compute(fmus, tmp_path):
    """A crank speed that is not finite, or whose power overflows float64, discards the
    step (status 2, Discard: the step not taken; never Fatal); the next finite speed
    steps on with the line's values."""
    slave, vr = motor(fmus, tmp_path, 1e10, 1.0)
    from fmpy.fmi1 import FMICallException

    for omega in (math.nan, 1e300):  # 1e300: tau = -1e310 overflows
        slave.setReal([vr["omega"]], [omega])
        with pytest.raises(FMICallException) as err:
            slave.doStep(0.0, 0.01)
        assert err.value.status == 2, (omega, err.value.status)
    slave.setReal([vr["omega"]], [0.5])
    slave.doStep(0.0, 0.01)
    assert slave.getReal([vr["tau"], vr["P"]]) == [5e9, 2.5e9]
    slave.terminate()
    slave.freeInstance()


def test_the_motor_fmu_refuses_a_bad_line(fmus):
    """A stall torque <= 0 is refused at the end of initialisation with Error naming it
    (the framework's parameter rules)."""
    fmpy = pytest.importorskip("fmpy")
    messages = []
    with pytest.raises(Exception, match="fmi2ExitInitializationMode"):
        fmpy.simulate_fmu(str(fmus / press.MOTOR_FMU), stop_time=1.0,
                          start_values={"T_stall": -1.0},
                          logger=lambda *args: messages.append(args[-1].decode()))
    assert any("T_stall must be > 0" in m for m in messages), messages


def test_the_system_structure_holds_every_value_once():
    """The system's file sets the press's parameters (the rotor's inertia in J1, every
    coefficient of friction), the start, the motor's line, and connects speed and torque
    both ways."""
    xml = press.system_structure(1e-6)
    assert "<BaseStepSize>1e-06</BaseStepSize>" in xml
    assert f'<InitialValue variable="J1"><Real value="{press.J_ROTOR!r}"/>' in xml
    assert f'variable="T_stall"><Real value="{press.MOTOR["T_stall"]!r}"/>' in xml
    for mu, value in press.FRICTION.items():
        assert value > 0.0
        assert f'variable="{mu}"><Real value="{value!r}"/>' in xml
    with pytest.raises(ValueError, match="whole number of nanoseconds"):
        press.system_structure(1.5e-10)


def test_libcosim_follows_simulate_at_a_fine_step(fmus):
    """The press with friction at work (at 6 rad/s, into its working stroke) for 0.2 s at
    a communication step of 1e-6 s: the crank speed from libcosim is within 1e-6 of the
    largest speed of ``simulate``'s, sampled every ms, and the drive FMU's friction loss
    ``P_loss`` within 1e-6 of the largest of ``simulate``'s (the kinetostatic solve with
    friction at its states), which is tens of watts here."""
    pytest.importorskip("libcosimpy", reason="libcosimpy (the Open Simulation Platform's "
                                             "libcosim) is not installed")
    run = press.cosimulate(fmus, 1e-6, 0.2, 1e-3, start=AT_WORK)
    reference = press.simulate(run.t, start=AT_WORK)
    assert np.allclose(run.t, reference.index.to_numpy(), rtol=0, atol=1e-12)
    assert len(run.t) == 200 and run.t[-1] == pytest.approx(0.2, abs=1e-12)
    # the ram takes energy: the crank slows down over the stroke
    assert reference["omega"].iloc[-1] < AT_WORK["omega0"] - 0.1
    assert press.coupling_error(run, reference) <= 1e-6
    loss = reference["P_loss"].to_numpy()
    assert np.max(loss) > 20.0 and np.min(loss) >= 0.0
    assert np.max(np.abs(run["P_loss"] - loss)) <= 1e-6 * np.max(loss)


def test_the_coupling_error_is_first_order(fmus):
    """From rest over 3 s (run-up and two strokes), steps of 1e-3 and 1e-4 s: the
    difference from ``simulate`` shrinks tenfold with the step (9 to 11 times), as the
    held torque's error does; a difference in the models would not shrink. At 1 ms the
    figures a motor is sized by over the last stroke (the torque's rms, the motor's work,
    the friction loss) are those of ``simulate``'s motion to 1e-3 relative."""
    pytest.importorskip("libcosimpy", reason="libcosimpy (the Open Simulation Platform's "
                                             "libcosim) is not installed")
    errors, strokes = [], []
    for h in (1e-3, 1e-4):
        run = press.cosimulate(fmus, h, 3.0, 1e-2)
        reference = press.simulate(run.t)
        errors.append(press.coupling_error(run, reference))
        strokes.append((press.stroke(run.t, run["theta"], run["omega"], run["motor.tau"],
                                     run["P_loss"]),
                        press.stroke(run.t, reference["theta"], reference["omega"],
                                     reference["tau"], reference["P_loss"])))
    assert 9.0 <= errors[0] / errors[1] <= 11.0, errors
    assert errors[1] <= 2e-4, errors
    got, expected = strokes[0]
    assert expected["E_loss"] > 10.0
    for name in ("tau_rms", "E_motor", "E_loss"):
        assert got[name] == pytest.approx(expected[name], rel=1e-3), name


@pytest.mark.parametrize("argv, line", [
    (["--t-end", "0"], "--t-end 0: must be a number of seconds > 0"),
    (["--t-end", "-1"], "--t-end -1: must be a number of seconds > 0"),
    (["--step", "2", "--t-end", "1"], "--step 2 is longer than --t-end 1: the run is a whole "
                                      "number of steps"),
    (["--step", "1e300", "--t-end", "1e300"], "--step 1e+300: libcosim's clock counts int64 "
                                              "nanoseconds: at most 9.22337e+09 s"),
    (["--step", "0.3", "--t-end", "1"], "--t-end 1 is not a whole number of steps of 0.3 s "
                                        "(3.33333): the run would end at 0.9 s"),
    (["--step", "1.5e-10"], "--step 1.5e-10: libcosim steps in whole nanoseconds: the step "
                            "must be a whole number of them"),
    (["--tolerance", "-1"], "--tolerance -1: must be a number > 0"),
    (["--t-end", "0.5", "--step", "1e-3"],
     "--t-end 0.5: the motion holds no whole revolution from one top dead centre to the "
     "next: run it longer (from rest, the first whole stroke ends at t = 2.72 s)"),
])
def test_a_run_it_cannot_make_is_one_line(argv, line, tmp_path, capsys):
    """Options the example cannot run with (no time, a step longer than the run or one
    libcosim's nanosecond clock cannot count, a run of no whole stroke) end it with
    status 2 and one line naming the option and why, before any FMU is built (they
    ended in tracebacks: an IndexError, an OverflowError, the stroke's ValueError)."""
    status = run.main([*argv, "--no-plots", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert status == 2 and err == f"press: {line}\n"
    assert not (tmp_path / "out").exists()


def test_the_readmes_second_command_runs(tmp_path):
    """``python examples/press/run.py --step 1e-4 --no-plots`` (the README's second
    command; here with its FMUs in a folder of the test's) exits 0: the tolerance
    follows the step (1.5 x 1e-4), where a tolerance of 1e-6 failed it with status 1.
    The coupling error it prints is first order in the step: between 0.5 and 1.5 times
    it (README: 0.9 times, from rest over 3 s)."""
    pytest.importorskip("libcosimpy", reason="libcosimpy (the Open Simulation Platform's "
                                             "libcosim) is not installed")
    import re
    import subprocess

    done = subprocess.run([sys.executable, str(EXAMPLE / "run.py"), "--step", "1e-4",
                           "--no-plots", "--out", str(tmp_path)], capture_output=True,
                          text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    error = float(re.search(r"coupling error \(max \|omega - simulate's\| / max \|omega\|\): "
                            r"(\S+)", done.stdout)[1])
    assert 0.5e-4 <= error <= 1.5e-4
    assert done.stdout.splitlines()[-1] == ("press: the coupling error is within the "
                                            "tolerance 0.00015")
