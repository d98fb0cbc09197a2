"""The four FMUs, run by fmpy in fresh processes outside the source tree, against the
direct solver; bad input, state save/restore, several instances, the cross-check
files, and a clean ``fmpy validate``."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from linkage_fmu import presets
from linkage_fmu.check import MODEL_NAMES, revolution, write_crosscheck

ROOT = Path(__file__).resolve().parents[1]
HOST = Path(__file__).with_name("fmu_host.py")


@pytest.fixture(scope="module")
def dist(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("dist")
    subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), "--no-check", "--out", str(out)],
                   cwd=ROOT, check=True, capture_output=True)
    for preset in MODEL_NAMES:
        write_crosscheck(out, preset, steps=90)
    return out


def host(job: dict, tmp_path: Path) -> dict:
    """Run ``fmu_host.py`` on ``job`` in a new process whose cwd is outside the repo."""
    cwd = tmp_path / "cwd"
    cwd.mkdir(exist_ok=True)
    (cwd / "job.json").write_text(json.dumps(job))
    run = subprocess.run([sys.executable, str(HOST), "job.json"], cwd=cwd,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout.splitlines()[-1])


def rows(preset: str, steps: int = 90) -> list:
    u = revolution(preset, steps)
    return np.column_stack([u[n] for n in ("theta", "omega", "alpha", "load")]).tolist()


def assert_matches_direct(entry: dict, preset: str, inputs: list, params=None, tol=1e-9):
    """Every output after doStep(t_k) equals the direct solver at the inputs set at t_k."""
    mech = presets.get(preset, **(params or {}))
    u = np.array(inputs)
    ref = mech.solve(u[:, 0], u[:, 1], u[:, 2], u[:, 3], method="direct")
    got = np.array(entry["outputs"], dtype=float)
    assert entry["names"] == list(mech.output_names + mech.diagnostic_names)
    for j, name in enumerate(entry["names"]):
        scale = max(np.max(np.abs(ref[name])), 1e-300)
        err = np.max(np.abs(got[:, j] - ref[name])) / scale
        assert err <= tol, (preset, name, err)


@pytest.mark.parametrize("preset", list(MODEL_NAMES))
def test_each_fmu_alone_in_a_fresh_process(dist, tmp_path, preset):
    inputs = rows(preset)
    out = host({"fmus": [{"name": "a", "path": str(dist / f"{MODEL_NAMES[preset]}.fmu")}],
                "inputs": inputs}, tmp_path)
    assert out["a"]["status"] == ["ok"] * len(inputs)
    assert_matches_direct(out["a"], preset, inputs)


def test_all_four_interleaved_in_one_process(dist, tmp_path):
    inputs = rows("four_bar")  # one input stream; each model's reference at the same inputs
    fmus = [{"name": p, "path": str(dist / f"{m}.fmu")} for p, m in MODEL_NAMES.items()]
    fmus[1]["params"] = {"l_AB": 0.12, "m2": 3.0, "branch": -1, "method": "direct"}
    out = host({"fmus": fmus, "inputs": inputs}, tmp_path)
    for preset in MODEL_NAMES:
        params = {"l_AB": 0.12, "m2": 3.0, "branch": -1} if preset == "four_bar" else None
        assert_matches_direct(out[preset], preset, inputs, params)


def test_several_instances_of_one_fmu_in_one_process(dist, tmp_path):
    """Three FourBar instances with different parameters, interleaved step by step, after
    instantiate/free cycles of the same FMU: each matches the direct solver with its own
    parameters, and the process exits cleanly (``host`` asserts exit status 0)."""
    inputs = rows("four_bar", 40)
    params = [{}, {"l_AB": 0.12, "branch": -1}, {"m3": 9.0, "method": "direct"}]
    fmus = [{"name": f"i{k}", "path": str(dist / "FourBar.fmu"), "params": p, "churn": 3 * k}
            for k, p in enumerate(params)]
    out = host({"fmus": fmus, "inputs": inputs}, tmp_path)
    for k, p in enumerate(params):
        assert out[f"i{k}"]["status"] == ["ok"] * len(inputs)
        p = {n: v for n, v in p.items() if n != "method"}
        assert_matches_direct(out[f"i{k}"], "four_bar", inputs, p)


def test_bad_inputs_are_discarded_and_the_next_valid_step_works(dist, tmp_path):
    """l_AB = 0.3 cannot assemble at theta = pi; NaN omega is rejected; no stale output."""
    steps = [[0.0, 5.0, 0.0, 1.0], [math.pi, 5.0, 0.0, 1.0], [0.5, 5.0, 0.0, 1.0],
             [1.0, math.nan, 0.0, 1.0], [1.0, 5.0, 0.0, math.inf], [1.5, 5.0, 0.0, 1.0]]
    out = host({"fmus": [{"name": "a", "path": str(dist / "FourBar.fmu"),
                          "params": {"l_AB": 0.3}}], "inputs": steps}, tmp_path)["a"]
    ok = [s == "ok" for s in out["status"]]
    assert ok == [True, False, True, False, False, True]
    assert all("fmi2Discard" in s or "2" in s for s, good in zip(out["status"], ok) if not good)
    for k, good in enumerate(ok):
        assert all((y is not None) == good for y in out["outputs"][k]), k
    log = "\n".join(out["log"])
    assert "cannot be assembled at theta = 3.14159 rad" in log and "BC + CD" in log
    assert "input omega = nan is not a finite number" in log
    assert "input load = inf is not a finite number" in log
    good = [[u for u, g in zip(steps, ok) if g]]
    entry = {"names": out["names"], "outputs": [y for y, g in zip(out["outputs"], ok) if g]}
    assert_matches_direct(entry, "four_bar", good[0], {"l_AB": 0.3})


@pytest.mark.parametrize("params, message", [
    ({"l_AB": -0.1}, "l_AB must be > 0 (crank length AB), got -0.1"),
    ({"branch": 0}, "branch must be +1 or -1"),
    ({"method": "lu"}, "method must be one of ('closed_form', 'direct'), got 'lu'"),
])
def test_invalid_parameter_discards_every_step_and_names_it(dist, tmp_path, params, message):
    out = host({"fmus": [{"name": "a", "path": str(dist / "FourBar.fmu"), "params": params}],
                "inputs": [[0.3, 1.0, 0.0, 0.0]] * 2}, tmp_path)["a"]
    assert "instantiate_error" not in out
    assert all(s != "ok" for s in out["status"])
    assert all(y is None for row in out["outputs"] for y in row)
    assert message in "\n".join(out["log"])


def test_state_save_restore_and_serialize(dist, tmp_path):
    inputs = rows("slider_crank", 20)
    out = host({"fmus": [{"name": "a", "path": str(dist / "SliderCrank.fmu"),
                          "params": {"e": 0.01, "method": "direct"}}],
                "inputs": inputs, "save_at": 7}, tmp_path)["a"]
    assert out["restored"] == out["expected_after_restore"]
    assert out["deserialized"] == out["expected_after_restore"]
    assert out["restored"] != out["outputs"][-1]


def test_refuses_a_foreign_linkage_fmu(dist, tmp_path):
    """A host that already imported another linkage_fmu: the FMU says so and does not run."""
    foreign = tmp_path / "foreign"
    shutil.copytree(ROOT / "src" / "linkage_fmu", foreign / "linkage_fmu",
                    ignore=shutil.ignore_patterns("__pycache__"))
    with open(foreign / "linkage_fmu" / "presets.py", "a") as f:
        f.write("\n# a different version\n")
    out = host({"preimport": [str(foreign)], "inputs": [[0.0, 1.0, 0.0, 0.0]],
                "fmus": [{"name": "a", "path": str(dist / "FourBar.fmu")}]}, tmp_path)["a"]
    assert "instantiate_error" in out
    assert "this FMU bundles linkage_fmu" in "\n".join(out["log"])


@pytest.mark.parametrize("preset", list(MODEL_NAMES))
def test_crosscheck_files_replay(dist, tmp_path, preset):
    """fmpy's simulate_fmu on <M>_in.csv reproduces <M>_ref.csv (one-row sampling lag),
    twice in one process: fmpy deletes the first run's extraction folder, from which
    the bundled package stays imported."""
    model = MODEL_NAMES[preset]
    opt = dict(line.split(",") for line in (dist / f"{model}_ref.opt").read_text().split())
    sim = {"fmu": str(dist / f"{model}.fmu"), "input": str(dist / f"{model}_in.csv"),
           "stop": float(opt["StopTime"]), "h": float(opt["StepSize"])}
    out = host({"fmus": [], "inputs": [], "simulate": [sim, sim]}, tmp_path)
    ref = np.genfromtxt(dist / f"{model}_ref.csv", delimiter=",", names=True)
    for run in ("simulate0", "simulate1"):
        assert len(out[run]["time"]) == len(ref)
        for name in ref.dtype.names[1:]:
            expected = np.concatenate([ref[name][:1], ref[name][:-1]])
            scale = max(np.max(np.abs(expected)), 1e-300)
            got = np.array(out[run][name])
            assert np.max(np.abs(got - expected)) <= 1e-9 * scale, (run, name)


@pytest.mark.parametrize("preset", list(MODEL_NAMES))
def test_fmpy_validate_is_clean(dist, preset):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(dist / f"{MODEL_NAMES[preset]}.fmu")) == []
