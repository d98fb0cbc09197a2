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

from conftest import MODELS
from linkage_fmu import presets
from linkage_fmu.fmi.run import revolution

ROOT = Path(__file__).resolve().parents[1]
HOST = Path(__file__).with_name("fmu_host.py")


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
    u = revolution(presets.get(preset), steps)
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


@pytest.mark.parametrize("preset", presets.names())
def test_each_fmu_alone_in_a_fresh_process(dist, tmp_path, preset):
    inputs = rows(preset)
    out = host({"fmus": [{"name": "a", "path": str(dist / f"{MODELS[preset]}.fmu")}],
                "inputs": inputs}, tmp_path)
    assert out["a"]["status"] == ["ok"] * len(inputs)
    assert_matches_direct(out["a"], preset, inputs)


def test_all_presets_interleaved_in_one_process(dist, tmp_path):
    inputs = rows("four_bar")  # one input stream; each model's reference at the same inputs
    fmus = [{"name": p, "path": str(dist / f"{m}.fmu")} for p, m in MODELS.items()]
    fmus[1]["params"] = {"l_AB": 0.12, "m2": 3.0, "branch": -1, "method": "direct"}
    out = host({"fmus": fmus, "inputs": inputs}, tmp_path)
    for preset in MODELS:
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


def test_unsolvable_inputs_discard_with_nan_outputs_and_the_next_valid_step_works(dist,
                                                                                  tmp_path):
    """l_AB = 0.3 cannot assemble at theta = pi; NaN omega and infinite load cannot be
    solved: those steps answer fmi2Discard with every output NaN and a log naming the
    cause; the valid steps around them match the direct solver."""
    steps = [[0.0, 5.0, 0.0, 1.0], [math.pi, 5.0, 0.0, 1.0], [0.5, 5.0, 0.0, 1.0],
             [1.0, math.nan, 0.0, 1.0], [1.0, 5.0, 0.0, math.inf], [1.5, 5.0, 0.0, 1.0]]
    out = host({"fmus": [{"name": "a", "path": str(dist / "FourBar.fmu"),
                          "params": {"l_AB": 0.3}}], "inputs": steps}, tmp_path)["a"]
    assert out["status"] == ["ok", "discard", "ok", "discard", "discard", "ok"]
    ok = [s == "ok" for s in out["status"]]
    for k, good in enumerate(ok):
        assert all((y is not None) == good for y in out["outputs"][k]), k
    log = "\n".join(out["log"])
    assert "the linkage cannot be assembled: the dyad B-C-D cannot close" in log
    assert "input omega = nan is not a finite number" in log
    assert "input load = inf is not a finite number" in log
    good = [[u for u, g in zip(steps, ok) if g]]
    entry = {"names": out["names"], "outputs": [y for y, g in zip(out["outputs"], ok) if g]}
    assert_matches_direct(entry, "four_bar", good[0], {"l_AB": 0.3})


@pytest.mark.parametrize("model, params, call, message", [
    ("FourBar", {"l_AB": -0.1}, "fmi2ExitInitializationMode",
     "l_AB must be > 0 (crank length AB), got -0.1"),
    ("SixBar", {"l_KD": 1e308}, "fmi2ExitInitializationMode",  # its mass rho l_KD: inf
     "is not finite"),
    ("FourBar", {"branch": 0}, "fmi2SetInteger", "branch must be +1 or -1"),
    ("FourBar", {"method": "lu"}, "fmi2SetString",
     "method must be one of 'closed_form', 'direct', 'interpreted', got 'lu'"),
])
def test_an_invalid_parameter_is_an_error_naming_it(dist, tmp_path, model, params, call,
                                                    message):
    """fmpy raises where the FMU answers fmi2Error: a value out of its rule or options at
    the set call, a set the linkage cannot take (a derived mass that is not finite) at
    fmi2ExitInitializationMode; the log names the problem."""
    out = host({"fmus": [{"name": "a", "path": str(dist / f"{model}.fmu"), "params": params}],
                "inputs": [[0.3, 1.0, 0.0, 0.0]] * 2}, tmp_path)["a"]
    assert call in out["instantiate_error"]
    assert message in "\n".join(out["log"])


def test_simulate_fmu_ends_the_run_at_the_first_unassemblable_step(dist, tmp_path):
    """fmpy's simulate_fmu over one revolution of a four-bar whose crank (l_AB = 0.3) is
    too long to turn fully: the FMU discards the first step whose inputs cannot be
    assembled and says the run should end (fmi2Terminated); fmpy ends it there, quietly,
    and every row it returns holds the direct solver's values."""
    model = "FourBar"
    write_steps = 90
    u = revolution(presets.get("four_bar", l_AB=0.3), write_steps)
    names = ("time", "theta", "omega", "alpha", "load")
    path = tmp_path / "in.csv"
    np.savetxt(path, np.column_stack([u[n] for n in names]), delimiter=",",
               header=",".join(f'"{n}"' for n in names), comments="", fmt="%.17g")
    h = float(u["time"][1] - u["time"][0])
    sim = {"fmu": str(dist / f"{model}.fmu"), "input": str(path), "stop": float(u["time"][-1]),
           "h": h, "params": {"l_AB": 0.3}}
    out = host({"fmus": [], "inputs": [], "simulate": [sim]}, tmp_path)["simulate0"]
    mech = presets.get("four_bar", l_AB=0.3)
    ref = mech.solve(u["theta"], u["omega"], u["alpha"], u["load"], method="direct")
    first = int(np.argmin(ref.valid))
    assert 0 < first < write_steps  # the range really is partly unassemblable
    # rows 0 .. first: the outputs of the inputs one row before; then fmpy's row at the
    # last successful time, NaN
    got = np.array([np.nan if v is None else v for v in out["Mb"]], dtype=float)
    assert len(got) == first + 2 and out["time"][-1] == out["time"][-2]
    lagged = np.concatenate([ref["Mb"][:1], ref["Mb"][:first]])
    np.testing.assert_allclose(got[:-1], lagged, rtol=0, atol=1e-9 * np.max(np.abs(lagged)))
    assert np.isnan(got[-1])


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


def test_refuses_an_edited_bundled_copy_and_says_so(dist, tmp_path):
    """The linkage_fmu inside the FMU edited after the build: the FMU refuses to run and
    says that its own bundle changed (not that another copy was imported)."""
    import zipfile

    edited = tmp_path / "FourBar.fmu"
    with zipfile.ZipFile(dist / "FourBar.fmu") as src, zipfile.ZipFile(edited, "w") as dst:
        for info in src.infolist():
            data = src.read(info)
            if info.filename == "resources/linkage_fmu/presets.py":
                data += b"\n# edited in place\n"
            dst.writestr(info, data)
    out = host({"inputs": [[0.0, 1.0, 0.0, 0.0]],
                "fmus": [{"name": "a", "path": str(edited)}]}, tmp_path)["a"]
    assert "instantiate_error" in out
    log = "\n".join(out["log"])
    assert "bundled in this FMU" in log and "was changed after the FMU was built" in log
    assert "already imported" not in log


@pytest.mark.parametrize("preset", presets.names())
def test_crosscheck_files_replay(dist, tmp_path, preset):
    """fmpy's simulate_fmu on <M>_in.csv reproduces <M>_ref.csv (one-row sampling lag),
    twice in one process: fmpy deletes the first run's extraction folder, from which
    the bundled package stays imported."""
    model = MODELS[preset]
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


@pytest.mark.parametrize("preset", presets.names())
def test_fmpy_validate_is_clean(dist, preset):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(dist / f"{MODELS[preset]}.fmu")) == []


def test_a_description_file_builds_an_fmu_that_passes_the_check(tmp_path):
    """The README's coupler four-bar (two loads) through the command line, each step in
    a fresh process: ``build`` makes CouplerFourBar.fmu with one input per load (and its
    unit); ``check`` finds no ``fmpy validate`` problem and fmpy's run over a revolution,
    with both loads varying, equal to the direct solver to 1e-9 relative."""
    from fmpy import read_model_description

    example = ROOT / "examples" / "coupler_four_bar.toml"
    build = subprocess.run([sys.executable, "-m", "linkage_fmu", "build", str(example),
                            "--out", str(tmp_path)], cwd=tmp_path, capture_output=True,
                           text=True, timeout=300)
    assert build.returncode == 0, build.stderr
    fmu = tmp_path / "CouplerFourBar.fmu"
    inputs = {v.name: v.unit for v in read_model_description(str(fmu)).modelVariables
              if v.causality == "input"}
    assert inputs == {"theta": "rad", "omega": "rad/s", "alpha": "rad/s2", "F_P": "N",
                      "T4": "N.m"}
    check = subprocess.run([sys.executable, "-m", "linkage_fmu", "check", "--json", str(fmu)],
                           cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert check.returncode == 0, check.stdout + check.stderr
    result = json.loads(check.stdout.splitlines()[-1])
    assert result["validate"] == [] and result["max_rel_error"] <= 1e-9
    assert result["steps"] == 360


@pytest.mark.parametrize("flavour", ["pythonfmu", "native"])
def test_the_engine_fmus_carry_their_pressure_table(dist, tmp_path, flavour):
    """The README's engine (examples/engine.toml, a gas-pressure table over 720 deg), as
    built by build_fmu.py: no input for the gas force; the table travels in the FMU (in
    the pythonfmu FMU's description file, inline; as C data in the native FMU's
    kernels); ``check`` in a fresh process runs the two revolutions of the cycle, 720
    steps, every output within 1e-12 of the direct solver."""
    import zipfile

    from fmpy import read_model_description

    fmu = (dist / "native" if flavour == "native" else dist) / "Engine.fmu"
    inputs = [v.name for v in read_model_description(str(fmu)).modelVariables
              if v.causality == "input"]
    assert inputs == ["theta", "omega", "alpha"]
    with zipfile.ZipFile(fmu) as archive:
        description = archive.read("resources/Engine.toml").decode()
        assert "table = [[0.0, -0.05], [2.0, -0.05]," in description
        if flavour == "native":
            model_c = archive.read("sources/model.c").decode()
            # the spline once, and its derivative once (for the directional derivatives)
            assert model_c.count("static double lk_table_") == 2
            assert model_c.count("_d(double theta) {") == 1
    check = subprocess.run([sys.executable, "-m", "linkage_fmu", "check", "--json", str(fmu)],
                           cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert check.returncode == 0, check.stdout + check.stderr
    result = json.loads(check.stdout.splitlines()[-1])
    assert result["validate"] == [] and result["max_rel_error"] <= 1e-12
    assert result["steps"] == 720 and result["unsolved_deg"] == []
