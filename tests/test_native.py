"""The native FMUs (the linkage's kernels in C behind the FMI framework): fmpy validates
them, they match the direct solver over a revolution (1e-12) and their cross-check
files, and they run in a C host with no Python in the process. What they share with the
pythonfmu FMUs (the calls, the statuses, the states, memory) is tested for both flavours
in ``test_fmu_protocol.py`` and ``test_fmu_fuzz.py``."""

from __future__ import annotations

import csv
import shutil
import subprocess
import zipfile

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from conftest import MODELS
from linkage_fmu import presets
from linkage_fmu.fmi import check_fmu
from linkage_fmu.fmi.check import reference
from linkage_fmu.fmi.run import revolution, step_fmu
from linkage_fmu.solver import SOLVED
from test_c_host import compile_host, model_outputs

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


@pytest.mark.parametrize("preset", ["slider_crank", "crank_shaper"])
def test_the_kernel_without_friction_while_every_mu_is_0(native_dist, preset):
    """A preset's FMU carries each structure's kernel without friction (its model C, a
    kernel ``f<s>`` per structure beside ``s<s>``) and runs it while every coefficient
    of friction is 0, pin radii set or not; else the kernel with friction. Reference: the
    direct solver over a revolution with those parameters, 1e-12 of each output's
    largest value, and its friction values: 0 where every mu is 0, not 0 otherwise."""
    mech = presets.get(preset)
    fmu = native_dist / f"{MODELS[preset]}.fmu"
    with zipfile.ZipFile(fmu) as archive:
        model_c = archive.read("sources/model.c").decode()
    assert "#define FRICTIONLESS_KERNELS 1" in model_c and "f0_one(" in model_c
    mu = sorted(n for n in mech.parameters if n.startswith("mu_"))
    radii = {n: 0.02 * mech.length_scale for n in mech.parameters if n.startswith("r_")}
    friction = [n for n in mech.output_names if n.startswith(("Mf_", "Ff_"))]
    for params, rubs in (({}, False), (radii, False), ({**radii, mu[0]: 0.1}, True),
                         ({**radii, **dict.fromkeys(mu, 0.05)}, True)):
        linkage = presets.get(preset, **params)
        u = revolution(linkage, 90)
        names = list(linkage.output_names)
        rows, _ = step_fmu(fmu, u, params, names)
        ref = reference(linkage, u[:-1])
        ok = np.asarray(ref.valid)
        assert ok.sum() > 45 and np.array_equal(rows["solved"].to_numpy(), ok), params
        for n in names:
            got, want = rows[n].to_numpy()[ok], np.asarray(ref[n])[ok]
            scale = max(np.max(np.abs(want)), 1e-300)
            assert np.max(np.abs(got - want)) <= 1e-12 * scale, (params, n)
        moving = np.abs(np.concatenate([rows[n].to_numpy()[ok] for n in friction]))
        assert (moving.max() > 0.0) == rubs, params


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


def _random_rows(mech, rng, n=151):
    """``n`` rows of random states (crank angle, speed, acceleration, load) as
    step_fmu takes them."""
    u = np.zeros(n, dtype=[(name, np.float64) for name in ("time",) + mech.input_names])
    u["time"] = np.linspace(0.0, 0.01 * (n - 1), n)
    u["theta"] = rng.uniform(0.0, 2 * np.pi, n)
    u["omega"] = rng.uniform(-15.0, 15.0, n)
    u["alpha"] = rng.uniform(-50.0, 50.0, n)
    u[mech.input_names[3]] = rng.uniform(-100.0, 100.0, n)
    return u


def _equal_where_the_direct_solver_solves(fmu, mech, u, params):
    """The FMU's steps against the direct solver: the same states solved (the direct
    solver's status SOLVED: a self-locked state is not), each output within 1e-11 of its
    largest value."""
    names = list(mech.output_names)
    rows, _ = step_fmu(fmu, u, params, names)
    ref = reference(mech, u[:-1])
    ok = np.asarray(ref.status) == SOLVED
    assert ok.sum() > 0.6 * ok.size and np.array_equal(rows["solved"].to_numpy(), ok)
    for n in names:
        got, want = rows[n].to_numpy()[ok], np.asarray(ref[n])[ok]
        scale = max(np.max(np.abs(want)), 1e-300)
        assert np.max(np.abs(got - want)) <= 1e-11 * scale, n


def test_friction_set_after_the_build_solves_where_the_direct_solver_does(tmp_path):
    """Reference: the direct solver at the FMU's parameters. Tolerance: 1e-11 of each
    output's largest value. The slider-crank's native FMU built with its defaults (every
    mu 0), then run with mu 0.6 on every pair and 0.1 m pins set as parameters, over 150
    random states: it solves every state the direct solver solves (its kernels' friction
    iterations are loops, their decisions taken at run time)."""
    from fmu_cache import build_native_fmu

    fmu = build_native_fmu("slider_crank", tmp_path)
    big = {"mu_O": 0.6, "r_O": 0.1, "mu_A": 0.6, "r_A": 0.1, "mu_B": 0.6, "r_B": 0.1,
           "mu_guide": 0.6}
    mech = presets.get("slider_crank", **big)
    u = _random_rows(mech, np.random.default_rng(150))
    _equal_where_the_direct_solver_solves(fmu, mech, u, big)


def test_the_six_bar_driven_off_the_crank_with_friction_set_after_the_build(native_dist):
    """Reference: the direct solver at the FMU's parameters. Tolerance: 1e-11 of each
    output's largest value. The six-bar's native FMU (built with its defaults: OA
    driven, every mu 0) run driven at KD and at D with mu 0.3 on every pair and pins of
    0.05 of its length scale, over 100 random states each: the same states solved,
    the same outputs (the effort's secant iteration a loop of its kernel)."""
    fmu = native_dist / f"{MODELS['six_bar']}.fmu"
    base = presets.get("six_bar")
    params = {n: 0.3 for n in base.parameters if n.startswith("mu_")}
    params.update({n: 0.05 * base.length_scale for n in base.parameters
                   if n.startswith("r_")})
    for driver in ("KD", "D"):
        mech = presets.get("six_bar", driver=driver, **params)
        u = _random_rows(mech, np.random.default_rng(7), 101)
        _equal_where_the_direct_solver_solves(fmu, mech, u, {**params, "driver": driver})



def test_the_six_bar_with_friction_is_small_and_optimised(native_dist):
    """Reference: the targets of the six-bar's native FMU with friction (its 20
    structures): at most 4 MB of model C and a library of at most 3 MB, and no pragma in
    its sources that turns the optimiser off (the builds are -O2); its friction
    iterations are loops of its kernels, not unrolled steps."""
    fmu = native_dist / f"{MODELS['six_bar']}.fmu"
    with zipfile.ZipFile(fmu) as archive:
        model_c = archive.read("sources/model.c").decode()
        library = archive.getinfo(f"binaries/linux64/{MODELS['six_bar']}.so").file_size
    assert len(model_c) <= 4_000_000 and library <= 3_000_000, (len(model_c), library)
    assert "optimize" not in model_c and "for (int k" in model_c
