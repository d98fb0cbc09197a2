"""The FMI 2.0 FMUs of both flavours (pythonfmu and native: one C framework) driven
through fmpy's raw FMI 2 functions, from fresh host processes: every bad call answers
fmi2Error (never Fatal, never a crash) and leaves the instance usable, the FMI 2.0 state
machine is enforced, an unsolvable input discards the step and reads NaN with a warning,
no output is stale under OK, a value read is the value set, serialized states are
checked, and memory stays flat while steps keep failing and instances come and go.

Each case runs ``fmu_raw_host.py`` in a new process and checks its statuses and values
against the direct solver computed here; each runs once per flavour (``fmu2``).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description

from conftest import FLAVOURS, MODELS
from linkage_fmu import presets

HOST = Path(__file__).with_name("fmu_raw_host.py")
OK, WARNING, DISCARD, ERROR, FATAL = range(5)
LAST_SUCCESSFUL_TIME, TERMINATED = 2, 3
PRESET_OF = {model: preset for preset, model in MODELS.items()}


def raw(dist: Path, ops: list, tmp_path: Path, models=("FourBar",), keep_log=200,
        unzip=None) -> dict:
    """Run ``ops`` in a fresh host process (cwd outside the repository), each FMU
    unpacked into a temporary folder or the one ``unzip`` names for its model."""
    job = {"fmus": {m: str(dist / f"{m}.fmu") for m in models}, "ops": ops,
           "keep_log": keep_log, "unzip": unzip or {}}
    cwd = tmp_path / "cwd"
    cwd.mkdir(exist_ok=True)
    (cwd / "job.json").write_text(json.dumps(job))
    run = subprocess.run([sys.executable, str(HOST), "job.json"], cwd=cwd, capture_output=True,
                         text=True, timeout=900)
    assert run.returncode == 0, f"host died with {run.returncode}: {run.stderr[-3000:]}"
    out = json.loads(run.stdout.splitlines()[-1])
    assert out["logged"][FATAL] == 0
    assert all(r[0] != FATAL for r in out["results"])
    return out


def variables(dist: Path, model: str) -> dict:
    """name -> (valueReference, type, causality) from the FMU's modelDescription."""
    md = read_model_description(str(dist / f"{model}.fmu"))
    return {v.name: (v.valueReference, v.type, v.causality) for v in md.modelVariables}


def start(name="a", model="FourBar", params=None, dist=None) -> list:
    """Ops that instantiate ``name`` and bring it to step mode with ``params``."""
    ops = [[name, "new", model], [name, "setup", 0.0, None], [name, "enter"]]
    for key, value in (params or {}).items():
        vr, kind, _ = variables(dist, model)[key]
        op = {"Real": "setReal", "Integer": "setInteger"}.get(kind, "setString")
        ops.append([name, op, [vr], [value if op != "setString" else value.encode().hex()]])
    return ops + [[name, "exit"]]


def reference(preset: str, u, params=None, names=None) -> list:
    """Direct-solver outputs at inputs ``u`` (NaN where they cannot be solved)."""
    mech = presets.get(preset, **(params or {}))
    names = names or list(mech.output_names + mech.diagnostic_names)
    try:
        sol = mech.solve(*u, method="direct")
        values = [sol[n] for n in names]
    except ValueError:
        return [math.nan] * len(names)
    return values if all(map(math.isfinite, values)) else [math.nan] * len(names)


def close(got, expected, rel=1e-9) -> bool:
    got = np.array([math.nan if v is None else v for v in got], dtype=float)
    expected = np.asarray(expected, dtype=float)
    if not np.array_equal(np.isnan(got), np.isnan(expected)):
        return False
    fine = ~np.isnan(expected)
    scale = max(np.max(np.abs(expected[fine]), initial=0.0), 1e-300)
    return bool(np.all(np.abs(got[fine] - expected[fine]) <= rel * scale))


def test_a_rejected_set_real_changes_nothing_and_no_output_is_stale(fmu2, tmp_path):
    """The fuzzed case: ScotchYoke ``setReal([theta, <output>], [1.2, 5.0])`` used to apply
    theta, return OK and leave the old outputs cached. Now it is fmi2Error and changes
    nothing: the outputs read afterwards are those of the inputs still set (theta = 0.3);
    setting theta = 1.2 alone then gives the outputs at 1.2."""
    dist = fmu2
    v = variables(dist, "ScotchYoke")
    outs = [vr for vr, kind, c in v.values() if c == "output"]
    names = [n for n, (vr, kind, c) in v.items() if c == "output"]
    f4p = v["F4p"][0]
    ops = start("y", "ScotchYoke") + [
        ["y", "setReal", [0, 1, 2, 3], [0.3, 10.0, 0.0, 400.0]], ["y", "doStep", 0.0, 0.01],
        ["y", "getReal", outs],
        ["y", "setReal", [0, f4p], [1.2, 5.0]], ["y", "doStep", 0.01, 0.01],
        ["y", "getReal", outs],
        ["y", "setReal", [0], [1.2]], ["y", "doStep", 0.02, 0.01], ["y", "getReal", outs],
    ]
    r = raw(dist, ops, tmp_path, ("ScotchYoke",))["results"][len(start("y", "ScotchYoke")):]
    at03 = reference("scotch_yoke", (0.3, 10.0, 0.0, 400.0), names=names)
    at12 = reference("scotch_yoke", (1.2, 10.0, 0.0, 400.0), names=names)
    assert [s for s, _ in r] == [OK, OK, OK, ERROR, OK, OK, OK, OK, OK]
    assert close(r[2][1], at03) and close(r[5][1], at03) and close(r[8][1], at12)
    assert not close(r[5][1], at12)


def test_every_bad_call_is_an_error_and_the_instance_stays_usable(fmu2, tmp_path):
    """Unknown and wrong-type references, outputs set, strings that are not UTF-8, NULL
    pointers, fixed parameters set after initialisation, bad step sizes and times: each
    is fmi2Error with a log naming the call and the reason, and afterwards a valid step
    gives the direct solver's outputs."""
    dist = fmu2
    v = variables(dist, "FourBar")
    outs = [vr for vr, kind, c in v.values() if c == "output"]
    names = [n for n, (vr, kind, c) in v.items() if c == "output"]
    n_vars = len(v)
    bad = [
        ["a", "setReal", [0, n_vars + 5], [0.4, 1.0]],          # unknown reference
        ["a", "setReal", [v["Mb"][0]], [1.0]],                   # an output
        ["a", "setReal", [v["l_AB"][0]], [0.2]],                 # fixed, after init
        ["a", "setReal", [v["branch"][0]], [1.0]],               # an Integer
        ["a", "setInteger", [v["l_AB"][0]], [1]],                # a Real
        ["a", "setInteger", [n_vars + 1], [1]],                  # unknown
        ["a", "setString", [v["method"][0]], ["ff00"]],          # fixed (and not UTF-8)
        ["a", "setString", [v["l_AB"][0]], ["61"]],              # a Real
        ["a", "getReal", [n_vars + 3]],                          # unknown
        ["a", "getReal", [v["method"][0]]],                      # a String
        ["a", "getString", [n_vars]],                            # unknown
        ["a", "getInteger", [v["l_AB"][0]]],                     # a Real
        ["a", "doStep", 0.0, 0.0],
        ["a", "doStep", 0.0, -0.1],
        ["a", "doStep", 0.0, math.nan],
        ["a", "doStep", math.nan, 0.1],
        ["a", "doStep", 0.0, math.inf],
        ["a", "setup", 0.0, None],                               # not in step mode
        ["a", "enter"],
        ["a", "exit"],
        ["a", "cancel"],
        ["a", "debugLogging", True, ["noSuchCategory"]],
    ]
    ops = start("a", dist=dist)
    n0 = len(ops)
    u = [0.7, 8.0, 1.0, 3.0]
    for op in bad:
        ops += [op, ["a", "setReal", [0, 1, 2, 3], u], ["a", "doStep", 0.0, 0.01],
                ["a", "getReal", outs]]
    ops += [["a", "nulls"], ["a", "getReal", [v["l_AB"][0], v["branch"][0]]]]
    out = raw(dist, ops, tmp_path)
    r = out["results"][n0:]
    expected = reference("four_bar", u, names=names)
    for k, op in enumerate(bad):
        status, _ = r[4 * k]
        assert status == ERROR, (op, status)
        assert [s for s, _ in r[4 * k + 1: 4 * k + 4]] == [OK, OK, OK], op
        assert close(r[4 * k + 3][1], expected), op
    assert r[-2][1] == [ERROR] * 8  # every NULL-pointer call
    errors = "\n".join(out["log"]["3"])
    for text in ("is not a variable of FourBar", "is an output: it cannot be set",
                 "'l_AB' (value reference", "is a fixed parameter", "is a Real, not a Integer",
                 "communicationStepSize = 0 is not a positive", "currentCommunicationPoint = nan",
                 "fmi2SetupExperiment is not allowed in state StepComplete",
                 "unknown log category 'noSuchCategory'"):
        assert text in errors, text


def test_the_state_machine_is_enforced(fmu2, tmp_path):
    """doStep before initialisation and after terminate, terminate twice, setReal of a
    fixed parameter after exitInitializationMode (it does not take effect), and getReal
    before enterInitializationMode: all fmi2Error. fmi2Terminated is false and
    fmi2LastSuccessfulTime is the end of the last step."""
    dist = fmu2
    v = variables(dist, "FourBar")
    l_ab = v["l_AB"][0]
    ops = [["a", "new", "FourBar"], ["a", "doStep", 0.0, 0.1], ["a", "getReal", [0]],
           ["a", "setup", 0.0, 1.0], ["a", "enter"], ["a", "doStep", 0.0, 0.1],
           ["a", "setReal", [l_ab], [0.11]], ["a", "exit"],
           ["a", "setReal", [l_ab], [0.2]], ["a", "getReal", [l_ab]],
           ["a", "doStep", 0.0, 0.25], ["a", "boolStatus", TERMINATED],
           ["a", "realStatus", LAST_SUCCESSFUL_TIME],
           ["a", "terminate"], ["a", "terminate"], ["a", "doStep", 0.25, 0.1],
           ["a", "getReal", [l_ab]], ["a", "reset"], ["a", "doStep", 0.0, 0.1],
           ["a", "setup", 0.0, None], ["a", "enter"], ["a", "exit"], ["a", "doStep", 0.0, 0.1]]
    r = raw(dist, ops, tmp_path)["results"]
    assert [s for s, _ in r] == [OK, ERROR, ERROR, OK, OK, ERROR, OK, OK, ERROR, OK, OK, OK,
                                 OK, OK, ERROR, ERROR, OK, OK, ERROR, OK, OK, OK, OK]
    assert r[9][1] == [0.11]  # the fixed parameter kept its initialisation value
    assert r[11][1] == 0 and r[12][1] == 0.25


@pytest.fixture(scope="module", params=FLAVOURS)
def four_bar2(request, tmp_path_factory) -> Path:
    """The folder of the four-bar's FMI 2.0 FMU of one flavour (built once: fmu_cache)."""
    from fmu_cache import build_fmu, build_native_fmu

    out = tmp_path_factory.mktemp(f"four_bar-{request.param}")
    (build_fmu if request.param == "pythonfmu" else build_native_fmu)("four_bar", out)
    return out


#: fmi2StatusKind: DoStepStatus, PendingStatus, LastSuccessfulTime, Terminated
KINDS = {0: "fmi2DoStepStatus", 1: "fmi2PendingStatus", 2: "fmi2LastSuccessfulTime",
         3: "fmi2Terminated"}


def test_every_status_kind_that_cannot_be_retrieved_is_discard_with_a_log(four_bar2, tmp_path):
    """FMI 2.0 (4.2.3): 'if a status is required which cannot be retrieved by the slave it
    returns fmi2Discard'. Kind -1 used to answer Error with no log from fmi2GetStatus, its
    Integer and its String variants, and every other kind Discard with a log: now every
    kind but fmi2LastSuccessfulTime (Real) and fmi2Terminated (Boolean) is Discard, from
    every query, with one log naming the call and the kind."""
    kinds = [-1, *KINDS, 4, 7, 2 ** 31 - 1, -2 ** 31]
    ops = start(dist=four_bar2) + [["a", "doStep", 0.0, 0.25], ["a", "statusKinds", kinds]]
    answers = raw(four_bar2, ops, tmp_path)["results"][-1][1]
    queries = ("fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus",
               "fmi2GetBooleanStatus", "fmi2GetStringStatus")
    assert sorted(answers) == sorted(f"{q}({k})" for q in queries for k in kinds)
    given = {("fmi2GetRealStatus", 2), ("fmi2GetBooleanStatus", 3)}
    for q in queries:
        for k in kinds:
            status, said = answers[f"{q}({k})"]
            if (q, k) in given:
                assert (status, said) == (OK, None), (q, k)
                continue
            assert status == DISCARD, (q, k, status)
            name = f" ({KINDS[k]})" if k in KINDS else ""
            assert said.startswith(f"{q}: status kind {k}{name} cannot be retrieved: "), said


@pytest.fixture(scope="module")
def four_bar_drive(tmp_path_factory) -> Path:
    """The folder of the four-bar's drive FMU (FMI 2.0) (built once: fmu_cache)."""
    from fmu_cache import build_native_fmu

    out = tmp_path_factory.mktemp("four_bar-drive")
    build_native_fmu("four_bar", out, drive=True)
    return out


@pytest.mark.parametrize("which", ["four_bar", "drive"])
def test_a_value_just_outside_a_declared_bound_is_refused(four_bar2, four_bar_drive, which,
                                                          tmp_path):
    """Every ``min`` and ``max`` the modelDescription declares (read by fmpy), the
    next float64 outside it (the next integer for an Integer) set in initialisation
    mode: the set or exitInitializationMode answers Error, and the log names the
    parameter; at the bound itself, no log names the parameter's rule. Both flavours
    of the four-bar, and its drive FMU (tolerance in [1e-14, 0.1], drive +1 or -1)."""
    dist = four_bar2 if which == "four_bar" else four_bar_drive
    model = "FourBar" if which == "four_bar" else "FourBarDrive"
    md = read_model_description(str(dist / f"{model}.fmu"))
    cases = []
    for v in md.modelVariables:
        if v.causality != "parameter":
            continue
        for bound, sign in ((v.min, -1), (v.max, 1)):
            if bound is None:
                continue
            if v.type == "Integer":
                cases.append((v, int(bound), int(bound) + sign))
            else:
                cases.append((v, float(bound), math.nextafter(float(bound), sign * math.inf)))
    assert len(cases) >= (20 if which == "four_bar" else 22)
    ops = []
    for k, (v, at, outside) in enumerate(cases):
        op = "setInteger" if v.type == "Integer" else "setReal"
        for value in (outside, at):
            name = f"{k}-{value!r}"
            ops += [[name, "new", model], [name, "setup", 0.0, None], [name, "enter"],
                    [name, op, [v.valueReference], [value]], [name, "exit"],
                    [name, "lastLog"], [name, "free"]]
    results = raw(dist, ops, tmp_path, models=(model,))["results"]
    for k, (v, at, outside) in enumerate(cases):
        (_, _), (_, _), (_, _), (set_out, _), (exit_out, _), (_, said), _ = \
            results[14 * k: 14 * k + 7]
        assert ERROR in (set_out, exit_out), (v.name, outside)
        assert f"{v.name} must be" in said, (v.name, outside, said)
        (set_at, _), (exit_at, _), (_, said_at) = (results[14 * k + 10], results[14 * k + 11],
                                                   results[14 * k + 12])
        assert set_at == OK and exit_at == OK, (v.name, at, set_at, exit_at)
        assert f"{v.name} must be" not in (said_at or ""), (v.name, at, said_at)


def test_an_invalid_parameter_set_fails_exit_initialization_until_it_is_fixed(fmu2, tmp_path):
    """exitInitializationMode answers fmi2Error naming every invalid parameter; the
    instance stays in initialisation mode, and once fixed the linkage solves."""
    dist = fmu2
    v = variables(dist, "FourBar")
    outs = [vr for vr, kind, c in v.values() if c == "output"]
    names = [n for n, (vr, kind, c) in v.items() if c == "output"]
    ops = [["a", "new", "FourBar"], ["a", "setup", 0.0, None], ["a", "enter"],
           ["a", "setReal", [v["l_AB"][0]], [-0.1]], ["a", "exit"], ["a", "doStep", 0.0, 0.1],
           ["a", "setReal", [v["l_AB"][0]], [math.nan]], ["a", "exit"],
           ["a", "setReal", [v["l_AB"][0]], [0.12]], ["a", "exit"],
           ["a", "setReal", [0, 1, 2, 3], [1.0, 4.0, 0.0, 2.0]], ["a", "doStep", 0.0, 0.1],
           ["a", "getReal", outs]]
    out = raw(dist, ops, tmp_path)
    r = out["results"]
    assert [s for s, _ in r] == [OK, OK, OK, OK, ERROR, ERROR, OK, ERROR, OK, OK, OK, OK, OK]
    assert close(r[-1][1], reference("four_bar", (1.0, 4.0, 0.0, 2.0), {"l_AB": 0.12}, names))
    errors = "\n".join(out["log"]["3"])
    assert "l_AB must be > 0 (crank length AB), got -0.1" in errors
    assert "l_AB must be a finite number, got nan" in errors


def test_a_foreign_guid_is_refused(fmu2, tmp_path):
    dist = fmu2
    out = raw(dist, [["a", "new", "FourBar", "{not-this-fmu}"],
                     ["b", "new", "FourBar"]], tmp_path)
    assert [s for s, _ in out["results"]] == [ERROR, OK]
    assert "GUID {not-this-fmu} does not match" in "\n".join(out["log"]["3"])


def test_unsolvable_inputs_discard_the_step_and_read_nan(fmu2, tmp_path):
    """Not finite, omega = 1e300 or 1e160 (the outputs overflow), an unassemblable angle
    (l_AB = 0.3 at theta = pi): setting them is OK, the step is fmi2Discard with
    fmi2Terminated true and fmi2LastSuccessfulTime at the step's start, every output reads
    NaN with fmi2Warning; the next valid step is OK and right and fmi2Terminated is false
    again. One log per change of the inputs names them, the step's start and the reason."""
    dist = fmu2
    v = variables(dist, "FourBar")
    outs = [vr for vr, kind, c in v.values() if c == "output"]
    names = [n for n, (vr, kind, c) in v.items() if c == "output"]
    rows = [[math.pi, 5.0, 0.0, 1.0], [0.2, math.nan, 0.0, 1.0], [0.2, 5.0, -math.inf, 1.0],
            [0.2, 1e300, 0.0, 1.0], [0.2, 1e160, 0.0, 1.0], [0.2, 5.0, 0.0, 1e308]]
    good = [0.4, 5.0, 0.0, 1.0]
    ops = start("a", params={"l_AB": 0.3}, dist=dist)
    n0 = len(ops)
    for k, row in enumerate(rows):
        t = 0.2 * k
        ops += [["a", "setReal", [0, 1, 2, 3], row], ["a", "doStep", t, 0.1],
                ["a", "boolStatus", TERMINATED], ["a", "realStatus", LAST_SUCCESSFUL_TIME],
                ["a", "getReal", outs], ["a", "getReal", outs[:1]],
                ["a", "setReal", [0, 1, 2, 3], good], ["a", "doStep", t + 0.1, 0.1],
                ["a", "boolStatus", TERMINATED], ["a", "getReal", outs]]
    out = raw(dist, ops, tmp_path)
    r = out["results"][n0:]
    expected = reference("four_bar", good, {"l_AB": 0.3}, names)
    for k, row in enumerate(rows):
        got = r[10 * k: 10 * k + 10]
        assert got[0][0] == OK and got[1][0] == DISCARD and got[2] == [OK, True], row
        # the step from t = 0.2 k was not taken: the last successful time is its start
        assert got[3][0] == OK and math.isclose(got[3][1], 0.2 * k, abs_tol=1e-12), row
        for read in got[4:6]:  # all outputs, or one: the same fate
            assert read[0] == WARNING and all(y is None for y in read[1]), row
        assert [s for s, _ in got[6:9]] == [OK, OK, OK] and got[8][1] == 0, row
        assert close(got[9][1], expected), row
    discards = out["log"]["2"]
    assert len(discards) == len(rows)  # once per change of the inputs
    assert discards[0] == (
        "fmi2DoStep: the inputs theta = 3.141592653589793, omega = 5.0, alpha = 0.0, load = 1.0 "
        "cannot be solved at t = 0.0: the linkage cannot be assembled: the dyad B-C-D cannot "
        "close; the outputs are NaN until an input changes")
    assert "input omega = nan is not a finite number" in discards[1]
    assert "at t = 0.6000000000000001: the outputs overflow float64: an input or a " \
           "parameter is too large in magnitude" in discards[3]
    assert "1e+160" in discards[4] and "load = 1e+308" in discards[5]
    assert not out["log"].get("1")  # the reads warn by status; the step said why


def test_state_round_trips_are_bit_exact_and_bad_states_are_rejected(fmu2, tmp_path):
    """get/set and serialize/deserialize give back bit-identical outputs. Random bytes, a
    truncated state, every single-byte flip of a serialized state, a state of another
    model (serialized or in memory) are fmi2Error, and the instance keeps working."""
    dist = fmu2
    v = variables(dist, "FourBar")
    outs = [vr for vr, kind, c in v.values() if c == "output"]
    ops = start("a", params={"l_AB": 0.11}, dist=dist) + start("s", "SliderCrank")
    ops += [["a", "setReal", [0, 1, 2, 3], [0.9, 7.0, 1.0, 2.0]], ["a", "doStep", 0.0, 0.1]]
    reads = [len(ops)]
    ops += [["a", "getReal", outs], ["a", "getState", "k"], ["a", "serialize", "k", "blob"],
            ["s", "getState", "other"], ["s", "serialize", "other", "foreign"],
            ["a", "setReal", [0, 1, 2, 3], [2.0, 1.0, 0.0, 0.0]], ["a", "doStep", 0.1, 0.1],
            ["a", "setState", "k"]]
    reads.append(len(ops))
    ops += [["a", "getReal", outs], ["a", "setReal", [0, 1, 2, 3], [2.0, 1.0, 0.0, 0.0]],
            ["a", "deserialize", "blob", "k2", None], ["a", "setState", "k2"]]
    reads.append(len(ops))
    ops += [["a", "getReal", outs], ["a", "realStatus", LAST_SUCCESSFUL_TIME]]
    n_ok = len(ops)
    bad = [["a", "deserialize", "blob", "x", ["hex", "00" * 7]],
           ["a", "deserialize", "blob", "x", ["hex", bytes(range(256)).hex()]],
           ["a", "deserialize", "foreign", "x", None],
           ["a", "setState", "other"]]
    bad += [["a", "deserialize", "blob", "x", ["cut", n]] for n in (0, 10, 60, -1)]
    models = ("FourBar", "SliderCrank")
    out = raw(dist, ops + bad + [["a", "serialize", "k", "probe"]], tmp_path, models)
    r = out["results"]
    size = r[-1][1]
    flips = [["a", "deserialize", "blob", "x", ["flip", i, 1 << (i % 8)]] for i in range(size)]
    out2 = raw(dist, ops + flips + [["a", "getReal", outs]], tmp_path, models)
    assert all(s == OK for s, _ in r[:n_ok]), [s for s, _ in r[:n_ok]]
    first = r[reads[0]][1]
    assert r[reads[1]][1] == first and r[reads[2]][1] == first  # bit-exact
    assert r[n_ok - 1][1] == 0.1
    assert [s for s, _ in r[n_ok:-1]] == [ERROR] * len(bad)
    r2 = out2["results"]
    assert [s for s, _ in r2[n_ok:-1]] == [ERROR] * size  # every byte of the state counts
    assert r2[-1][0] == OK and r2[-1][1] == first
    errors = "\n".join(out["log"]["3"] + out2["log"]["3"])
    assert "checksum mismatch" in errors and "is not of model FourBar" in errors


def interleaved(dist: Path, cycles: int, rows: int) -> tuple[list, list, list]:
    """Ops for ``cycles`` instantiate/free cycles of the four FMUs of ``MODELS`` in turn,
    then 20 instances of them with their own parameters, stepped interleaved through
    ``rows`` random inputs and read; the models, the ops, and the reads as (op index,
    model, parameters, inputs)."""
    models = [m for m in PRESET_OF if m in ("FourBar", "SliderCrank", "ScotchYoke", "SixBar")]
    ops = []
    for k in range(cycles):
        ops += [[f"c{k}", "new", models[k % 4]], [f"c{k}", "free"]]
    insts = []
    for k in range(20):
        model = models[k % 4]
        params = {"FourBar": {"l_AB": 0.08 + 0.002 * k}, "SliderCrank": {"e": 0.001 * k},
                  "ScotchYoke": {"m3": 5.0 + k}, "SixBar": {"rho": 5.0 + k}}[model]
        insts.append((f"i{k}", model, params))
        ops += start(f"i{k}", model, params, dist)
    rng = np.random.default_rng(7)
    reads = []
    for t, u in enumerate(rng.uniform([0, -20, -50, -10], [2 * np.pi, 20, 50, 10],
                                      size=(rows, 4)).tolist()):
        for name, model, params in insts:
            outs = [vr for vr, kind, c in variables(dist, model).values() if c == "output"]
            ops += [[name, "setReal", [0, 1, 2, 3], u], [name, "doStep", 0.1 * t, 0.1]]
            reads.append((len(ops), model, params, u))
            ops.append([name, "getReal", outs])
    return models, ops, reads


def check_reads(dist: Path, results: list, reads: list) -> None:
    """Every read of :func:`interleaved` matches the direct solver."""
    for index, model, params, u in reads:
        names = [n for n, (vr, kind, c) in variables(dist, model).items() if c == "output"]
        assert close(results[index][1], reference(PRESET_OF[model], u, params, names)), (
            model, u)


def test_many_instances_interleaved_and_instantiate_free_cycles(fmu2, tmp_path):
    """20 interleaved instances of four FMUs with their own parameters after 100
    instantiate/free cycles: every output matches the direct solver."""
    dist = fmu2
    models, ops, reads = interleaved(dist, 100, 15)
    r = raw(dist, ops, tmp_path, tuple(models))["results"]
    assert all(s == OK for s, _ in r)
    check_reads(dist, r, reads)


def test_memory_is_flat_while_every_step_fails(fmu2, tmp_path):
    """4 x 10^5 steps that cannot be solved (FourBar with l_AB = 0.3, theta = pi), with
    logging on, after 30,000 steps to warm up, alternating with a valid step now and
    then so that new reasons keep being logged: resident memory grows by less than 800
    KiB (2 bytes a step, as 2 MiB over 10^6 rows; pythonfmu's wrapper leaks ~211 bytes
    per message its slave logs, which would be ~30 MB), and every such step discards and
    every read warns with NaN outputs."""
    dist = fmu2
    v = variables(dist, "FourBar")
    outs = [vr for vr, kind, c in v.values() if c == "output"]
    bad, good = [math.pi, 5.0, 0.0, 1.0], [0.3, 5.0, 0.0, 1.0]
    pattern = [bad, bad, good]
    n = 200_000  # 4 x 10^5 unsolvable rows
    ops = start("a", params={"l_AB": 0.3}, dist=dist) + [
        ["a", "steps", {"pattern": pattern, "repeat": 10_000}, 1e-3, outs], ["a", "rss"],
        ["a", "steps", {"pattern": pattern, "repeat": n}, 1e-3, outs], ["a", "rss"]]
    out = raw(dist, ops, tmp_path, keep_log=5)
    (_, warm), (_, before), (_, run), (_, after) = out["results"][-4:]
    # at each of the 2 n unsolvable rows, doStep discards and getReal warns
    assert run["counts"][DISCARD] == 2 * n and run["counts"][WARNING] == 2 * n
    assert run["counts"][ERROR] == 0
    assert run["nan_rows"] == 2 * n
    print(f"resident memory {before} KiB -> {after} KiB over {3 * n} steps")
    assert after - before < 800, (before, after)


@pytest.mark.slow
def test_instantiate_free_cycles_keep_no_memory(fmu2):
    """Four windows of 750 cycles of instantiate, initialise with other parameters, step,
    read and free, after 200 to warm up: in one of them at least, resident memory grows
    by less than 48 KiB (65 bytes a cycle), and every answer is OK. A leak of 100 bytes a
    cycle grows every window by 73 KiB (pythonfmu's wrapper kept about 1 KB per instance
    it created, 4.5 KB with the slave script of before: 730 KiB a window); the
    allocator's arenas, once filled, grow a window now and then and stay (measured over
    30,000 cycles in windows of 5,000: +470, +0, +16, +16, +0 KiB; pythonfmu, 500 then
    three windows of 5,000: +1052, +1892, +16 KiB; native, 500 then six windows of 1,000:
    +48, +16, +40, +28, +0, +4 KiB; pythonfmu, 100 then six of 500: +48, +44, +0, +0,
    +20, -28 KiB). Long runs: ``tests/fmu_fuzz.py --memory``
    (``benchmarks/results/fuzz.md``)."""
    from fmu_fuzz import memory

    windows, cycles = 4, 750
    rss = memory(fmu2 / "FourBar.fmu", windows, cycles, warm=200)  # every answer OK
    print(f"resident memory {' -> '.join(map(str, rss))} KiB over {windows} x {cycles} cycles")
    assert min(b - a for a, b in zip(rss, rss[1:])) < 48, rss
