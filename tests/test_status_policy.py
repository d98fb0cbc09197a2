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


def answers(fmu: Path, tmp_path: Path) -> dict:
    run = subprocess.run([sys.executable, str(HOST), str(fmu)], cwd=tmp_path,
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
                  "cannot be solved at t = 0.2: the outputs overflow float64: an input is too "
                  "large in magnitude; the outputs are NaN until an input changes"],
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
