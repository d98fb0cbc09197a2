"""One status policy for every FMU: the pythonfmu and the native FourBar, FMI 2.0 and 3.0,
driven through the same calls (``policy_host.py``, each in a fresh process), answer each
call with the same status and log the same text, up to the standard's names of the
calls: an invalid parameter set makes the outputs read NaN with a warning and
ExitInitializationMode an error; inputs that cannot be solved make DoStep discard and
every read warn with NaN, logged once per change of the inputs with the inputs, the
time of the step's start and the reason; the next valid step is exact."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import pytest

from linkage_fmu import presets

HOST = Path(__file__).with_name("policy_host.py")
OK, WARNING, DISCARD, ERROR = range(4)
#: FMI 3.0's names of the calls, as FMI 2.0 names them
FMI2_NAMES = {"fmi3GetFloat64": "fmi2GetReal", "fmi3SetFloat64": "fmi2SetReal",
              "fmi3": "fmi2"}


def answers(fmu: Path, tmp_path: Path, *scenario: str) -> dict:
    """The answers of ``policy_host.py`` on ``fmu`` (to its own calls, or to those of
    the ``scenario`` file), FMI 3.0's names read as FMI 2.0's."""
    run = subprocess.run([sys.executable, str(HOST), str(fmu), *scenario], cwd=tmp_path,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-3000:]
    out = json.loads(run.stdout.splitlines()[-1])
    for entry in out["log"]:
        for name, fmi2 in FMI2_NAMES.items():
            entry[1] = entry[1].replace(name, fmi2)
    return out


@pytest.fixture(scope="module")
def runs(dist, native_dist, dist3, native3, tmp_path_factory) -> dict:
    folders = {"pythonfmu FMI 2.0": dist, "native FMI 2.0": native_dist,
               "pythonfmu FMI 3.0": dist3, "native FMI 3.0": native3}
    return {name: answers(folder / "FourBar.fmu", tmp_path_factory.mktemp("policy"))
            for name, folder in folders.items()}


def test_the_same_status_at_every_call_and_the_same_log(runs):
    reference = runs["native FMI 2.0"]
    for name, run in runs.items():
        statuses = [(op, status) for op, status, _ in run["answers"]]
        assert statuses == [(op, status) for op, status, _ in reference["answers"]], name
        assert run["log"] == reference["log"], name


def test_the_statuses_and_messages_are_the_policy(runs):
    run = runs["pythonfmu FMI 2.0"]
    statuses = [status for _, status, _ in run["answers"]]
    assert statuses == [OK, OK, WARNING, ERROR, OK, OK,
                        OK, OK, OK,
                        OK, WARNING, DISCARD, WARNING, DISCARD,
                        OK, OK, OK,
                        OK, DISCARD, WARNING,
                        OK, DISCARD, WARNING,
                        OK, OK,
                        OK, DISCARD, WARNING,
                        OK]
    log = run["log"]
    assert [status for status, _ in log] == [WARNING, ERROR, WARNING, DISCARD, DISCARD,
                                              DISCARD]
    inputs = "theta = 3.141592653589793, omega = 5.0, alpha = 0.0, load = 1.0"
    assert log == [
        [WARNING, "fmi2GetReal: the parameter set is invalid: l_AB must be > 0 (crank length "
                  "AB), got -0.1; the outputs are NaN"],
        [ERROR, "fmi2ExitInitializationMode: the parameter set is invalid: l_AB must be > 0 "
                "(crank length AB), got -0.1; the instance stays in initialisation mode until "
                "it is fixed"],
        [WARNING, f"fmi2GetReal: the inputs {inputs} cannot be solved at t = 0.1: the linkage "
                  "cannot be assembled: the dyad B-C-D cannot close; the outputs are NaN until "
                  "an input changes"],
        [DISCARD, "fmi2DoStep: the inputs theta = 0.5, omega = nan, alpha = 0.0, load = 1.0 "
                  "cannot be solved at t = 0.2: input omega = nan is not a finite number; the "
                  "outputs are NaN until an input changes"],
        [DISCARD, "fmi2DoStep: the inputs theta = 0.5, omega = 1e+160, alpha = 0.0, load = 1.0 "
                  "cannot be solved at t = 0.2: the outputs overflow float64: an input or a "
                  "parameter is too large in magnitude; the outputs are NaN until an input "
                  "changes"],
        [DISCARD, f"fmi2DoStep: the inputs {inputs} cannot be solved at t = 0.3: the linkage "
                  "cannot be assembled: the dyad B-C-D cannot close; the outputs are NaN until "
                  "an input changes"],
    ]


def test_the_values_are_the_direct_solver_or_nan(runs):
    """Every output read OK is the direct solver's at the inputs set (1e-12), every one
    read with a warning NaN; all four FMUs read the same bits."""
    mech = presets.get("four_bar", l_AB=0.3)
    expected = [mech.solve(0.5, 5.0, 0.0, 1.0, method="direct")[n]
                for n in mech.output_names + mech.diagnostic_names]
    reference = runs["native FMI 2.0"]["answers"]
    for name, run in runs.items():
        for (op, status, values), (_, _, ref_values) in zip(run["answers"], reference):
            if op not in ("outputs", "output") or not values:
                continue
            assert values == ref_values, name
            if status == WARNING:
                assert all(v is None for v in values), (name, op)
            elif op == "outputs":
                scale = max(abs(v) for v in expected[:-1])
                assert all(math.isclose(v, e, rel_tol=0, abs_tol=1e-12 * scale)
                           for v, e in zip(values, expected)), name


def test_no_message_names_another_standard(runs):
    for name, run in runs.items():
        if "3.0" in name:
            continue
        assert not any(re.search(r"fmi3|Float64", text) for _, text in run["log"]), name


# -- parameter sets whose arithmetic overflows, and outputs with no finite value ----------
def scenario(params: dict, inputs: tuple = (0.5, 10.0, 0.0, 0.0)) -> list:
    """A fresh instance with ``params``: read the outputs at the start inputs, step at
    ``inputs``, read them again, step at the same inputs again and read one output."""
    return [("enter", ()), *(("set", (k, v)) for k, v in params.items()), ("exit", ()),
            ("outputs", ()), ("inputs", inputs), ("step", (0.0, 0.1)), ("outputs", ()),
            ("step", (0.0, 0.1)), ("output", ()), ("terminate", ())]


def answers_to(fmu: Path, calls: list, tmp_path: Path) -> dict:
    """The answers of ``policy_host.py`` to ``calls`` (a scenario) on ``fmu``."""
    job = tmp_path / "scenario.json"
    job.write_text(json.dumps(calls))
    return answers(fmu, tmp_path, str(job))


#: model, parameters: every state the scenario steps to overflows (the four-bar's and
#: the slider-crank's lengths raise OverflowError in Python, where C gives inf), or a
#: diagnostic does (dJ_red was NaN and -inf under OK)
#: (at rest: SlottedLever's -inf was read at omega = 0)
OVERFLOWING = [("FourBar", {"l_CD": 1e308}, 10.0), ("SliderCrank", {"l_AB": 1e308}, 10.0),
               ("ScotchYoke", {"J3": 1e308}, 10.0), ("SlottedLever", {"J2": 1e308}, 0.0)]


@pytest.fixture(scope="module")
def flavours(dist, native_dist, dist3, native3) -> dict:
    """Each flavour's folder of FMUs (the pythonfmu FMI 3.0 one has the four-bar only)."""
    return {"pythonfmu FMI 2.0": dist, "native FMI 2.0": native_dist,
            "pythonfmu FMI 3.0": dist3, "native FMI 3.0": native3}


@pytest.mark.parametrize("model, params, omega", OVERFLOWING,
                         ids=[m for m, _, _ in OVERFLOWING])
def test_a_parameter_set_that_overflows_is_a_discard_in_both_flavours(model, params, omega,
                                                                     flavours, tmp_path):
    """Parameter sets that overflow: the pythonfmu FMUs answered the four-bar's with Error
    and the Python exception's text (OverflowError), and both flavours read ScotchYoke's
    dJ_red = NaN and SlottedLever's -inf under OK. Now every flavour answers as the native
    FMU did: the parameters are taken (OK), every read Warning with every output NaN,
    doStep Discard, a reason in words logged once per change of the inputs (the read at
    the start inputs, then the step's), never Error."""
    calls = scenario(params, (0.5, omega, 0.0, 0.0))
    runs = {name: answers_to(folder / f"{model}.fmu", calls, tmp_path)
            for name, folder in flavours.items() if (folder / f"{model}.fmu").exists()}
    assert len(runs) >= 3
    for name, run in runs.items():
        assert [(op, status) for op, status, _ in run["answers"]] == [
            ("enter", OK), *(("set", OK) for _ in params), ("exit", OK),
            ("outputs", WARNING), ("inputs", OK), ("step", DISCARD), ("outputs", WARNING),
            ("step", DISCARD), ("output", WARNING), ("terminate", OK)], name
        for op, _, values in run["answers"]:
            assert values is None or all(v is None for v in values), (name, op)
        log = run["log"]
        assert [status for status, _ in log] == [WARNING, DISCARD], name
        assert re.fullmatch(r"fmi2GetReal: the inputs theta = 0.0, .* cannot be solved at "
                            r"t = 0.0: the (linkage|outputs) .+; the outputs are NaN until an "
                            r"input changes", log[0][1]), (name, log[0][1])
        assert log[1][1].startswith(f"fmi2DoStep: the inputs theta = 0.5, omega = {omega}, "
                                    "alpha = 0.0, load = 0.0 cannot be solved at t = 0.0: "), name
        assert "rror" not in " ".join(text for _, text in log), name


def test_an_output_without_a_finite_value_is_a_warning(flavours, tmp_path):
    """The four-bar with g = 0 at rest with no load: no power enters, so eta is NaN (its
    documented value there) while every other output is solved. The step is taken
    (OK), but no read answers OK with a NaN: every read that includes eta is a Warning,
    logged once per change of the inputs, naming the output; a read of another output
    alone is OK. The same statuses and log in every flavour."""
    calls = [("enter", ()), ("set", ("g", 0.0)), ("exit", ()), ("inputs", (0.5, 0.0, 0.0, 0.0)),
             ("step", (0.0, 0.1)), ("outputs", ()), ("output", ()), ("outputs", ()),
             ("terminate", ())]
    runs = {name: answers_to(folder / "FourBar.fmu", calls, tmp_path)
            for name, folder in flavours.items()}
    mech = presets.get("four_bar", g=0.0)
    names = list(mech.output_names + mech.diagnostic_names)
    assert math.isnan(mech.solve(0.5, 0.0, 0.0, 0.0)["eta"])
    reference = runs["native FMI 2.0"]
    for name, run in runs.items():
        assert [(op, status) for op, status, _ in run["answers"]] == [
            ("enter", OK), ("set", OK), ("exit", OK), ("inputs", OK), ("step", OK),
            ("outputs", WARNING), ("output", OK), ("outputs", WARNING), ("terminate", OK)], name
        values = run["answers"][5][2]
        assert [n for n, v in zip(names, values) if v is None] == ["eta"], name
        assert run["log"] == reference["log"], name
    assert reference["log"] == [
        [WARNING, "fmi2GetReal: output eta has no finite value at the inputs theta = 0.5, "
                  "omega = 0.0, alpha = 0.0, load = 0.0 at t = 0.1: it reads nan"]]


def test_a_coefficient_of_friction_beyond_the_largest_taken_is_refused_alike(flavours,
                                                                            tmp_path):
    """ScotchYoke with mu_guide = 1e308 stepped OK in the native FMU (its guide's normal
    force is 0 up to rounding, times 1e308) where the library's methods disagreed. Every
    coefficient of friction above 1000 (parameters.MU_MAX) is refused: the same Error
    and log from every flavour, then fixed, the instance goes on."""
    calls = [("enter", ()), ("set", ("mu_guide", 1e308)), ("outputs", ()), ("exit", ()),
             ("set", ("mu_guide", 1000.0)), ("exit", ()), ("inputs", (0.5, 10.0, 0.0, 0.0)),
             ("step", (0.0, 0.1)), ("terminate", ())]
    runs = {name: answers_to(folder / "ScotchYoke.fmu", calls, tmp_path)
            for name, folder in flavours.items() if (folder / "ScotchYoke.fmu").exists()}
    assert len(runs) >= 3
    why = ("the parameter set is invalid: mu_guide must be <= 1000.0 (coefficient of friction "
           "in the prismatic pair guide (links 4 and 3)), got 1e+308")
    for name, run in runs.items():
        assert [status for _, status, _ in run["answers"]] == [
            OK, OK, WARNING, ERROR, OK, OK, OK, OK, OK], name
        assert run["log"] == [
            [WARNING, f"fmi2GetReal: {why}; the outputs are NaN"],
            [ERROR, f"fmi2ExitInitializationMode: {why}; the instance stays in "
                    "initialisation mode until it is fixed"]], name
