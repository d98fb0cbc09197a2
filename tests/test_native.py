"""The native FMUs (the linkage's kernels in C behind the FMI 2.0 framework): fmpy
validates them, they match the direct solver over a revolution (1e-12) and their
cross-check files, they run in a C host with no Python in the process, and from fresh
host processes they keep every promise the pythonfmu FMUs keep: bad calls are fmi2Error,
unsolvable inputs are fmi2Discard with NaN outputs and the next valid step is right,
states round-trip bit for bit, many instances coexist, memory stays flat."""

from __future__ import annotations

import csv
import math
import shutil
import subprocess
import zipfile

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from conftest import MODELS
from fmu_fuzz import DISCARD, ERROR, OK, WARNING, run
from linkage_fmu import presets
from linkage_fmu.fmi import check_fmu
from test_c_host import compile_host, model_outputs
from test_fmu_protocol import (LAST_SUCCESSFUL_TIME, TERMINATED, check_reads, close,
                               interleaved, raw, reference, start, variables)

NATIVE_MODELS = (*MODELS.values(), "CouplerFourBar")


@pytest.mark.parametrize("model", NATIVE_MODELS)
def test_valid_and_equal_to_the_direct_solver(native_dist, model):
    """``fmpy validate`` finds nothing; a revolution with varying speed and loads through
    ``simulate_fmu`` matches the direct solver to 1e-12 of each output's largest value;
    the modelDescription says no execution tool is needed and ships the C sources."""
    fmu = native_dist / f"{model}.fmu"
    assert validate_fmu(str(fmu)) == []
    result = check_fmu(fmu)
    assert result.steps == 360 and result.passed(1e-12), result
    with zipfile.ZipFile(fmu) as archive:
        names = set(archive.namelist())
        xml = archive.read("modelDescription.xml").decode()
    assert 'needsExecutionTool="false"' in xml and '<File name="fmi2.c"' in xml
    assert {"sources/fmi2.c", "sources/backend_native.c", "sources/model.c",
            "sources/config.h", f"binaries/linux64/{model}.so"} <= names


@pytest.mark.parametrize("model", NATIVE_MODELS)
def test_cross_check_files(native_dist, model):
    """The FMU run on its ``<M>_in.csv`` inputs (written from the linkage, not the FMU)
    reproduces ``<M>_ref.csv`` (the direct solver) to 1e-12 of each column's scale."""
    with open(native_dist / f"{model}_in.csv") as f:
        rows = list(csv.reader(f))
    names = rows[0]
    u = np.array([tuple(map(float, r)) for r in rows[1:]],
                 dtype=[(n, np.float64) for n in names])
    ref = np.genfromtxt(native_dist / f"{model}_ref.csv", delimiter=",", names=True)
    h = float(u["time"][1] - u["time"][0])
    out_names = [n for n in ref.dtype.names if n != "time"]
    result = simulate_fmu(str(native_dist / f"{model}.fmu"), stop_time=float(u["time"][-1]),
                          output_interval=h, input=u, output=out_names)
    for name in out_names:  # row k holds the outputs of the inputs of row k - 1
        expected = np.concatenate([ref[name][:1], ref[name][:-1]])
        scale = max(np.max(np.abs(expected)), 1e-300)
        assert np.max(np.abs(result[name] - expected)) <= 1e-12 * scale, name


@pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc is not on PATH")
def test_a_c_host_with_no_python_in_the_process(native_dist, tmp_path):
    """The C host runs the native FourBar with an environment that has no Python at all
    (no LD_PRELOAD, no PYTHONPATH, no PYTHONHOME): every output of a revolution matches
    the direct solver to 1e-12, and neither the FMU's binary nor the host links
    libpython."""
    unzipped = tmp_path / "FourBar"
    with zipfile.ZipFile(native_dist / "FourBar.fmu") as archive:
        archive.extractall(unzipped)
    binary = unzipped / "binaries" / "linux64" / "FourBar.so"
    host = compile_host(tmp_path)
    for exe in (binary, host):
        assert "libpython" not in subprocess.run(["ldd", str(exe)], capture_output=True,
                                                 text=True).stdout
    model, guid, outputs = model_outputs(unzipped / "modelDescription.xml")
    steps, omega, load = 72, 10.0, 5.0
    run_ = subprocess.run([str(host), str(unzipped), model, guid, str(steps), repr(omega),
                           repr(load), *map(str, outputs.values())], cwd=tmp_path,
                          env={"PATH": "/usr/bin:/bin"}, capture_output=True, text=True,
                          timeout=60)
    assert run_.returncode == 0, run_.stderr
    table = np.loadtxt(run_.stdout.splitlines(), delimiter=",", ndmin=2)
    expected = presets.get("four_bar").solve(table[:, 0], omega, 0.0, load, method="direct")
    for column, name in enumerate(outputs, start=1):
        scale = np.max(np.abs(expected[name]))
        np.testing.assert_allclose(table[:, column], expected[name], rtol=0,
                                   atol=1e-12 * scale, err_msg=name)


def test_unsolvable_inputs_discard_and_the_next_valid_step_is_right(native_dist, tmp_path):
    """Not finite (setReal answers fmi2Discard), omega = 1e300 or 1e160 (outputs overflow),
    an unassemblable angle (l_AB = 0.3 at theta = pi): the step is fmi2Discard,
    fmi2Terminated then says true and fmi2LastSuccessfulTime stays at the last good
    step, every output reads NaN with fmi2Warning; the next valid step is OK and right,
    and fmi2Terminated is false again."""
    dist = native_dist
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
                ["a", "getReal", outs], ["a", "setReal", [0, 1, 2, 3], good],
                ["a", "doStep", t + 0.1, 0.1], ["a", "boolStatus", TERMINATED],
                ["a", "getReal", outs]]
    out = raw(dist, ops, tmp_path)
    r = out["results"][n0:]
    expected = reference("four_bar", good, {"l_AB": 0.3}, names)
    for k, row in enumerate(rows):
        got = r[9 * k: 9 * k + 9]
        finite = all(map(math.isfinite, row))
        assert got[0][0] == (OK if finite else DISCARD), row
        assert got[1][0] == DISCARD and got[2] == [OK, True], row
        assert got[3][0] == OK and math.isclose(got[3][1], 0.2 * k if k else 0.0), row
        assert got[4][0] == WARNING and all(y is None for y in got[4][1]), row
        assert [s for s, _ in got[5:8]] == [OK, OK, OK] and got[7][1] == 0, row
        assert close(got[8][1], expected), row
    log = "\n".join(out["log"]["2"])
    assert "cannot be assembled, or is singular, at theta = 3.14159" in log
    assert "omega = nan is not finite" in log and "the outputs overflow" in log


def test_bad_calls_and_parameters_are_errors(native_dist, tmp_path):
    """An invalid parameter (a negative length) fails exitInitializationMode with
    fmi2Error naming it, and the instance stays in initialisation mode until it is
    fixed; a branch this FMU was not built for, a method other than the closed form, an
    output set, a fixed parameter set after initialisation are fmi2Error; the other
    branch, selected before initialisation, gives the direct solver's outputs."""
    dist = native_dist
    v = variables(dist, "FourBar")
    outs = [vr for vr, kind, c in v.values() if c == "output"]
    names = [n for n, (vr, kind, c) in v.items() if c == "output"]
    ops = [["a", "new", "FourBar"], ["a", "setup", 0.0, None], ["a", "enter"],
           ["a", "setReal", [v["l_BC"][0]], [-0.35]], ["a", "exit"],
           ["a", "setReal", [v["l_BC"][0]], [0.35]],
           ["a", "setInteger", [v["branch"][0]], [2]],
           ["a", "setString", [v["method"][0]], ["direct".encode().hex()]],
           ["a", "setInteger", [v["branch"][0]], [-1]], ["a", "exit"],
           ["a", "setReal", [v["l_AB"][0]], [0.2]], ["a", "setReal", [outs[0]], [1.0]],
           ["a", "setReal", [0, 1, 2, 3], [0.7, 3.0, 1.0, 2.0]], ["a", "doStep", 0.0, 0.1],
           ["a", "getReal", outs]]
    out = raw(dist, ops, tmp_path)
    r = out["results"]
    assert [s for s, _ in r] == [OK, OK, OK, OK, ERROR, OK, ERROR, ERROR, OK, OK, ERROR,
                                 ERROR, OK, OK, OK]
    assert close(r[-1][1], reference("four_bar", [0.7, 3.0, 1.0, 2.0], {"branch": -1},
                                     names))
    errors = "\n".join(out["log"]["3"])
    assert "parameter l_BC = -0.35" in errors and "must be > 0" in errors
    assert "branch = 2 is not a value this FMU was built for" in errors
    assert "a native FMU computes the closed form only" in errors


def test_states_instances_and_memory(native_dist, tmp_path):
    """1000 instantiate/free cycles, then 20 interleaved instances of four native FMUs
    with their own parameters match the direct solver; a state saved, serialized and
    restored gives bit-identical outputs, every single-byte flip of the serialized state
    is fmi2Error; 10^6 steps (two unsolvable for one solvable) leave resident memory
    within 1 MB."""
    dist = native_dist
    models, ops, reads = interleaved(dist, 1000, 10)
    outs = [vr for vr, kind, c in variables(dist, "FourBar").values() if c == "output"]
    first = len(ops)
    ops += [["i1", "getReal", outs], ["i1", "getState", "k"], ["i1", "serialize", "k", "b"],
            ["i1", "setReal", [0], [2.0]], ["i1", "doStep", 5.0, 0.1],
            ["i1", "deserialize", "b", "k2", None], ["i1", "setState", "k2"],
            ["i1", "getReal", outs], ["i1", "serialize", "k", "probe"]]
    r = raw(dist, ops, tmp_path, tuple(models))["results"]
    assert all(s == OK for s, _ in r)
    check_reads(dist, r, reads)
    assert r[first + 7][1] == r[first][1]  # bit-exact
    size = r[-1][1]
    flips = [["i1", "deserialize", "b", "x", ["flip", i, 1 << (i % 8)]] for i in range(size)]
    r2 = raw(dist, ops + flips, tmp_path, tuple(models))["results"]
    assert [s for s, _ in r2[len(ops):]] == [ERROR] * size

    bad, good = [math.pi, 5.0, 0.0, 1.0], [0.3, 5.0, 0.0, 1.0]
    n = 333_334
    ops = start("a", params={"l_AB": 0.3}, dist=dist) + [
        ["a", "steps", {"pattern": [bad, bad, good], "repeat": 10_000}, 1e-3, outs],
        ["a", "rss"],
        ["a", "steps", {"pattern": [bad, bad, good], "repeat": n}, 1e-3, outs], ["a", "rss"]]
    out = raw(dist, ops, tmp_path, keep_log=5)
    (_, warm), (_, before), (_, steps), (_, after) = out["results"][-4:]
    assert steps["counts"][DISCARD] == 2 * n and steps["nan_rows"] == 2 * n
    assert after - before < 1024, (before, after)


@pytest.mark.parametrize("preset", presets.names())
def test_fuzz(native_dist, preset):
    """10^4 fuzzed steps per native FMU (10^5 for the four-bar): no Fatal, no crash,
    every answer as the checker expects (``fmu_fuzz.check``)."""
    steps = 100_000 if preset == "four_bar" else 10_000
    tally, _ = run(native_dist, preset, steps, seed=sum(map(ord, preset)), native=True)
    assert tally["read equal to the direct solver"] > steps // 2
    assert tally[("status", ERROR)] > steps // 10 and tally[("status", DISCARD)] > 100
