"""What one FMI communication step costs: the project's FMUs against trivial pythonfmu FMUs.

    python benchmarks/fmu_timing.py

Builds the project's FMUs for ``four_bar`` and ``slider_crank`` (``build_fmu.py
--no-check``) and a *trivial* pythonfmu FMU for each with the same inputs and output
names, whose outputs are ``theta + k``. The trivial FMU is the baseline: what pythonfmu
and fmpy cost per step before the model does any work. Every FMU is loaded and timed in
a fresh Python process started outside the source tree, never in the process that built
it; this file is also the script those processes run (``fmu_timing.py --run JSON``).

Three ways of driving an FMU are timed:

``fmpy_api``
    ``FMU2Slave.setReal`` (4 inputs), ``doStep``, ``getReal`` (all outputs), one step
    per loop iteration; best and median over repeated loops, and the three calls timed
    separately in another loop.
``raw_ctypes``
    The same calls through the FMU's ``fmi2SetReal/fmi2DoStep/fmi2GetReal`` ctypes
    function pointers on preallocated arrays: no fmpy wrapper, no list conversions.
``simulate_fmu``
    ``fmpy.simulate_fmu`` over one revolution with an input table, all outputs recorded;
    from the ``.fmu`` file (extraction included) and from an extracted directory.
"""

from __future__ import annotations

import json
import math
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    from fmpy.fmi2 import FMU2Slave

#: inputs of every linkage FMU, in the order of the modelDescription
INPUTS = ("theta", "omega", "alpha", "load")
#: constant inputs of the benchmark (theta ramps over one revolution)
OMEGA, ALPHA, LOAD = 10.0, 0.0, 5.0
BUILD_SCRIPT = Path(__file__).resolve().parents[1] / "build_fmu.py"

# A plain pythonfmu slave. Inputs use pythonfmu's default attribute getters and setters;
# each output has a getter returning theta + k. The two module-level statements and the
# block in __init__ are what linkage_fmu.fmi.slave.hold_namespace and the framework's exit handler
# do, inlined so that the FMU bundles nothing but pythonfmu: without them a second
# instance or the process exit can crash (pythonfmu 0.7 wrapper defects). The class
# derives from a name spelled Fmi2Slave: the wrapper looks for it in the script text.
TRIVIAL_SCRIPT = '''"""Trivial pythonfmu slave with the interface of {model_of!r} (fmu_timing)."""
import atexit
import ctypes
import sys
from pathlib import Path

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real
from pythonfmu.osutil import get_lib_extension, get_platform

ctypes.pythonapi.Py_IncRef(ctypes.py_object(vars(sys.modules[{module!r}])))
_PINNED = globals().get("_PINNED", set())  # survives the wrapper re-running this script


class {model}(Fmi2Slave):
    """Outputs {outputs!r} = theta + 0, theta + 1, ...; doStep does nothing."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        if "logger" in kwargs:  # created by the FMU's wrapper, not by the builder
            binary = str(Path(self.resources).parent / "binaries" / get_platform()
                         / f"{model}.{{get_lib_extension()}}")
            if binary not in _PINNED:
                _PINNED.add(binary)
                atexit.register(ctypes.CDLL(binary).finalizePythonInterpreter)
        self.theta, self.omega, self.alpha, self.load = {starts!r}
        for name in {inputs!r}:
            self.register_variable(Real(name, causality=Fmi2Causality.input,
                                        variability=Fmi2Variability.continuous))
        for k, name in enumerate({outputs!r}):
            self.register_variable(Real(name, causality=Fmi2Causality.output,
                                        variability=Fmi2Variability.continuous,
                                        getter=lambda k=float(k): self.theta + k))

    def do_step(self, current_time, step_size):
        return True
'''


# -- building -----------------------------------------------------------------------
def output_names(preset: str) -> tuple[str, ...]:
    """Output names of the project's FMU for ``preset``: outputs, then diagnostics.

    Examples
    --------
    >>> output_names("four_bar")[-1]
    'cond'
    """
    from linkage_fmu import presets

    mech = presets.get(preset)
    return tuple(mech.output_names + mech.diagnostic_names)


def build_trivial(preset: str, out: Path) -> Path:
    """Build ``out/Trivial<Model>.fmu``: the interface of ``preset``'s FMU, no model.

    Parameters
    ----------
    preset : str
        ``'four_bar'`` (model ``FourBar``) or ``'slider_crank'`` (``SliderCrank``); any
        preset of ``linkage_fmu.presets`` works.
    out : Path
        Folder for the FMU (created if missing).

    Returns
    -------
    Path
        The FMU. Inputs ``theta, omega, alpha, load`` (continuous Reals); outputs the
        preset's output and diagnostic names, output ``k`` being ``theta + k``.
    """
    from linkage_fmu import presets
    from pythonfmu.builder import FmuBuilder

    d = presets.preset(preset)
    start = {**d.inputs, "load": d.loads[0]["start"]}
    model = f"Trivial{d.model}"
    module = f"linkage_fmu_bench_trivial_{preset}_slave"  # unique module name
    with tempfile.TemporaryDirectory(prefix="fmu_timing_build_") as tmp:
        script = Path(tmp) / f"{module}.py"
        script.write_text(TRIVIAL_SCRIPT.format(
            model=model, model_of=d.model, module=module, inputs=INPUTS,
            outputs=output_names(preset), starts=tuple(float(start[n]) for n in INPUTS)))
        out.mkdir(parents=True, exist_ok=True)
        FmuBuilder.build_FMU(script, dest=out)
    return out / f"{model}.fmu"


def build_project(presets: Sequence[str], out: Path) -> dict[str, dict[str, Path]]:
    """Build the project's FMUs with ``build_fmu.py --no-check`` in a new process.

    Returns
    -------
    dict
        ``"pythonfmu"`` and ``"native"`` -> preset -> path of its FMU.
    """
    args = [sys.executable, str(BUILD_SCRIPT), "--no-check", "--out", str(out)]
    for preset in presets:
        args += ["--preset", preset]
    with tempfile.TemporaryDirectory(prefix="fmu_timing_cwd_") as cwd:
        run = subprocess.run(args, check=False, cwd=cwd, capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError(f"build_fmu.py failed (exit {run.returncode}): {run.stderr[-2000:]}")
    built = [Path(line.rsplit(": ", 1)[0]) for line in run.stdout.splitlines()]
    return {"pythonfmu": dict(zip(presets, built[0::2], strict=True)),
            "native": dict(zip(presets, built[1::2], strict=True))}


def build_trivial_native(native: Path, out: Path) -> Path:
    """``out/Trivial<Model>.fmu``: the native FMU ``native`` with its kernel replaced by
    one that copies ``theta`` to every output: what the framework and fmpy cost per step
    before the model does any work (same variables, same checks, same backend)."""
    import shutil
    import zipfile

    from linkage_fmu.ccompiler import compile_shared
    from linkage_fmu.fmi.build import FLAGS

    with tempfile.TemporaryDirectory(prefix="fmu_timing_native_") as tmp:
        root = Path(tmp) / "fmu"
        with zipfile.ZipFile(native) as archive:
            archive.extractall(root)
        model_c = root / "sources" / "model.c"
        text = model_c.read_text()
        table = text[text.index("static int (*const ONE[N_STRUCTURES])"):]
        table = table[:table.index("};") + 2]
        trivial = ("static int trivial_one(const double *q, const double *x, double *y) {\n"
                   "    (void)q;\n    for (int k = 0; k < N_OUTPUTS; k++) y[k] = x[0];\n"
                   "    return 0;\n}\n")
        n = table.count("_one")
        model_c.write_text(text.replace(table, trivial + "static int (*const ONE[N_STRUCTURES])"
                                        "(const double *, const double *, double *) = {"
                                        + ", ".join(["trivial_one"] * n) + "};"))
        binary = next((root / "binaries" / "linux64").glob("*.so"))
        compile_shared([root / "sources" / "fmi2.c"], binary, include=[root / "sources"],
                       flags=FLAGS, libraries=["m"])
        out.mkdir(parents=True, exist_ok=True)
        target = out / f"Trivial{native.stem}.fmu"
        with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as archive:
            for path in sorted(root.rglob("*")):
                if path.is_file():
                    archive.write(path, path.relative_to(root).as_posix())
        shutil.rmtree(root)
    return target


# -- timing in a fresh process ------------------------------------------------------
def run_fresh(job: str, **kwargs: object) -> dict:
    """Run ``job`` (a name in :func:`jobs`) in a new Python process outside the source
    tree and return its JSON result; raise ``RuntimeError`` unless it exits with 0."""
    spec = json.dumps({"job": job, **kwargs})
    with tempfile.TemporaryDirectory(prefix="fmu_timing_cwd_") as cwd:
        run = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--run", spec],
                             check=False, cwd=cwd, capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError(f"{job} on {kwargs.get('fmu')} exited with {run.returncode}: "
                           f"{run.stderr[-2000:]}")
    return json.loads(run.stdout.splitlines()[-1])


def time_step_loop(fmu: Path, steps: int, repeats: int = 5) -> dict:
    """Time set 4 inputs / doStep / get all outputs through fmpy's ``FMU2Slave``.

    Runs in a fresh process. Each loop is ``steps`` steps over one revolution (theta
    ramp, omega 10, alpha 0, load 5); the best and the median of ``repeats`` loops are
    reported, in microseconds per step.

    Returns
    -------
    dict
        ``{"steps", "fmpy_api": {...}, "raw_ctypes": {...}, "split": {...}}``. The first
        two hold ``us_per_step`` (best) and ``us_per_step_median``; ``fmpy_api`` also
        appears flattened at the top level (``us_per_step``, ``us_per_step_median``).
        ``split`` holds the best (over loops) microseconds per step spent in ``set``,
        ``do_step`` and ``get`` through the fmpy API, timed call by call, and ``total``.
    """
    result = run_fresh("step_loop", fmu=str(Path(fmu).resolve()), steps=steps,
                       repeats=repeats)
    return {"us_per_step": result["fmpy_api"]["us_per_step"],
            "us_per_step_median": result["fmpy_api"]["us_per_step_median"], **result}


def time_simulate_fmu(fmu: Path, steps: int, repeats: int = 3) -> dict:
    """Time ``fmpy.simulate_fmu`` over one revolution with ``steps`` communication steps.

    Runs in a fresh process. Input table: theta ramp over one revolution, omega 10,
    alpha 0, load 5; every output recorded at every step.

    Returns
    -------
    dict
        ``{"steps", "with_extraction": {...}, "extracted": {...}}``: simulating the
        ``.fmu`` file (fmpy unzips it on every call) and an already extracted directory.
        Each holds ``seconds`` (best), ``seconds_median``, ``us_per_step`` (best) and
        ``us_per_step_median``.
    """
    return run_fresh("simulate", fmu=str(Path(fmu).resolve()), steps=steps, repeats=repeats)


# -- what the fresh process runs (imports fmpy and numpy only, never linkage_fmu) ----
def summarize(seconds: Sequence[float], steps: int) -> dict:
    """Best and median of loop times ``seconds``, also per step in microseconds.

    Examples
    --------
    >>> summarize([2.0, 1.0, 3.0], 1000)["us_per_step"]
    1000.0
    """
    best, median = min(seconds), statistics.median(seconds)
    return {"seconds": best, "seconds_median": median, "us_per_step": best / steps * 1e6,
            "us_per_step_median": median / steps * 1e6}


def revolution_thetas(steps: int) -> list[float]:
    """Crank angles of ``steps`` steps over one revolution, as plain floats.

    Examples
    --------
    >>> revolution_thetas(4)[1] == math.pi / 2
    True
    """
    return [2.0 * math.pi * i / steps for i in range(steps)]


def open_slave(fmu: str) -> tuple:
    """Extract, load and initialise ``fmu`` with fmpy's ``FMU2Slave``.

    Returns
    -------
    tuple
        ``(slave, input value references, output value references)``; inputs in the
        order of :data:`INPUTS`, outputs in the order of the modelDescription.
    """
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    md = read_model_description(fmu)
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bench")
    slave.instantiate()
    slave.setupExperiment(startTime=0.0, stopTime=None)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    outputs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    return slave, [vrs[n] for n in INPUTS], outputs


def loop_fmpy(slave: FMU2Slave, vr_in: list, vr_out: list, thetas: list, h: float,
              t0: float) -> float:
    """One loop through the fmpy API; return its wall time [s]."""
    set_real, do_step, get_real = slave.setReal, slave.doStep, slave.getReal
    clock = time.perf_counter
    start = clock()
    for i, theta in enumerate(thetas):
        set_real(vr_in, [theta, OMEGA, ALPHA, LOAD])
        do_step(t0 + i * h, h)
        get_real(vr_out)
    return clock() - start


def loop_split(slave: FMU2Slave, vr_in: list, vr_out: list, thetas: list, h: float,
               t0: float) -> tuple[float, float, float, float]:
    """One loop through the fmpy API timing each call; return the seconds spent in
    setReal, doStep and getReal, and the loop's wall time."""
    set_real, do_step, get_real = slave.setReal, slave.doStep, slave.getReal
    clock = time.perf_counter
    t_set = t_do = t_get = 0.0
    start = clock()
    for i, theta in enumerate(thetas):
        a = clock()
        set_real(vr_in, [theta, OMEGA, ALPHA, LOAD])
        b = clock()
        do_step(t0 + i * h, h)
        c = clock()
        get_real(vr_out)
        d = clock()
        t_set += b - a
        t_do += c - b
        t_get += d - c
    return t_set, t_do, t_get, clock() - start


def loop_raw(slave: FMU2Slave, vr_in: list, vr_out: list, thetas: list, h: float,
             t0: float) -> float:
    """One loop through the raw ctypes function pointers on preallocated arrays; return
    its wall time [s]. Raise ``RuntimeError`` if any call returned a status above
    fmi2Warning."""
    from ctypes import c_double, c_uint

    set_real, do_step, get_real = (getattr(slave.dll, f) for f in
                                   ("fmi2SetReal", "fmi2DoStep", "fmi2GetReal"))
    comp, n_in, n_out = slave.component, len(vr_in), len(vr_out)
    vr_i, vr_o = (c_uint * n_in)(*vr_in), (c_uint * n_out)(*vr_out)
    u, y = (c_double * n_in)(0.0, OMEGA, ALPHA, LOAD), (c_double * n_out)()
    worst = 0
    clock = time.perf_counter
    start = clock()
    for i, theta in enumerate(thetas):
        u[0] = theta
        worst |= set_real(comp, vr_i, n_in, u)
        worst |= do_step(comp, t0 + i * h, h, 1)
        worst |= get_real(comp, vr_o, n_out, y)
    seconds = clock() - start
    if worst > 1:
        raise RuntimeError(f"a raw FMI call returned status bits {worst}")
    return seconds


def job_step_loop(fmu: str, steps: int, repeats: int) -> dict:
    """The fresh process's side of :func:`time_step_loop`."""
    h = 2.0 * math.pi / OMEGA / steps
    thetas = revolution_thetas(steps)
    slave, vr_in, vr_out = open_slave(fmu)
    runs: dict[str, list] = {"fmpy": [], "raw": [], "split": []}
    t0 = 0.0
    loop_fmpy(slave, vr_in, vr_out, thetas[: steps // 10 + 1], h, t0)  # warm-up
    for _ in range(repeats):
        for name, loop in (("fmpy", loop_fmpy), ("raw", loop_raw), ("split", loop_split)):
            t0 += steps * h
            runs[name].append(loop(slave, vr_in, vr_out, thetas, h, t0))
    last = slave.getReal(vr_out)
    slave.terminate()
    slave.freeInstance()
    split = {key: min(r[j] for r in runs["split"]) / steps * 1e6
             for j, key in enumerate(("set", "do_step", "get", "total"))}
    return {"steps": steps, "fmpy_api": summarize(runs["fmpy"], steps),
            "raw_ctypes": summarize(runs["raw"], steps), "split": split,
            "outputs": len(vr_out), "finite_outputs": all(map(math.isfinite, last))}


def input_table(steps: int) -> np.ndarray:
    """fmpy input table over one revolution: ``steps + 1`` rows of time and inputs."""
    import numpy as np

    period = 2.0 * math.pi / OMEGA
    u = np.zeros(steps + 1, dtype=[(n, np.float64) for n in ("time",) + INPUTS])
    u["time"] = np.linspace(0.0, period, steps + 1)
    u["theta"] = OMEGA * u["time"]
    u["omega"], u["alpha"], u["load"] = OMEGA, ALPHA, LOAD
    return u


def simulate_seconds(target: str, u: np.ndarray, outputs: list, repeats: int) -> list[float]:
    """Wall times [s] of ``repeats`` ``fmpy.simulate_fmu`` runs of ``target`` (an FMU file
    or an extracted directory) over the input table ``u``."""
    from fmpy import simulate_fmu

    h = float(u["time"][1] - u["time"][0])
    seconds = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = simulate_fmu(target, start_time=0.0, stop_time=float(u["time"][-1]),
                              step_size=h, output_interval=h, input=u, output=outputs)
        seconds.append(time.perf_counter() - start)
    if len(result) != len(u):
        raise RuntimeError(f"simulate_fmu returned {len(result)} rows, expected {len(u)}")
    return seconds


def job_simulate(fmu: str, steps: int, repeats: int) -> dict:
    """The fresh process's side of :func:`time_simulate_fmu`.

    The runs from the ``.fmu`` file come last, while the directory of the first runs
    still exists. pythonfmu's wrapper puts each instance's ``resources`` first on
    ``sys.path``, so the process keeps the ``linkage_fmu`` imported from the first
    extraction; fmpy deletes an extraction of its own after the run, and the next
    instance's ``check_bundle`` then fingerprints a deleted folder, raises ImportError
    in the wrapper and the host segfaults in ``fmi2Instantiate`` (measured with
    linkage_fmu 0.1.0, pythonfmu 0.7.0, fmpy 0.3.32: the second
    ``simulate_fmu("FourBar.fmu")`` in a process crashes).
    """
    import shutil

    from fmpy import extract, read_model_description

    md = read_model_description(fmu)
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    u = input_table(steps)
    unzipped = extract(fmu)
    try:
        extracted = simulate_seconds(unzipped, u, outputs, repeats)
        # Still inside the try: the project's FMU needs the directory it first ran from
        # (see job_simulate's docstring).
        with_extraction = simulate_seconds(fmu, u, outputs, repeats)
    finally:
        shutil.rmtree(unzipped, ignore_errors=True)
    return {"steps": steps, "with_extraction": summarize(with_extraction, steps),
            "extracted": summarize(extracted, steps)}


def jobs() -> dict[str, Callable[..., dict]]:
    """Jobs a fresh process can run, by name."""
    return {"step_loop": job_step_loop, "simulate": job_simulate}


# -- the benchmark ------------------------------------------------------------------
def measure(fmu: Path, steps: int) -> dict:
    """All timings of one FMU: ``{"loop": time_step_loop(...), "sim": time_simulate_fmu(...)}``."""
    return {"loop": time_step_loop(fmu, steps), "sim": time_simulate_fmu(fmu, steps)}


def rows(m: dict) -> dict[str, float]:
    """The table's numbers (microseconds per step) from one :func:`measure` result."""
    loop, sim = m["loop"], m["sim"]
    return {"fmpy_api": loop["fmpy_api"]["us_per_step"],
            "fmpy_api med": loop["fmpy_api"]["us_per_step_median"],
            "raw_ctypes": loop["raw_ctypes"]["us_per_step"],
            "  setReal(4)": loop["split"]["set"],
            "  doStep": loop["split"]["do_step"],
            "  getReal(all)": loop["split"]["get"],
            "simulate_fmu .fmu": sim["with_extraction"]["us_per_step"],
            "simulate_fmu dir": sim["extracted"]["us_per_step"]}


def print_table(results: dict[str, dict[str, dict]], steps: int) -> None:
    """Print microseconds per step for every preset: project, trivial, ratio."""
    print(f"us per step, {steps} steps, best of repeats (fmpy {fmpy_version()}, "
          f"{sys.version.split()[0]})")
    for preset, pair in results.items():
        project, trivial = rows(pair["project"]), rows(pair["trivial"])
        print(f"\n{preset:<20}{'project':>10}{'trivial':>10}{'ratio':>8}")
        for key, value in project.items():
            print(f"{key:<20}{value:>10.2f}{trivial[key]:>10.2f}{value / trivial[key]:>8.2f}")


def fmpy_version() -> str:
    """Installed fmpy version."""
    from importlib.metadata import version

    return version("fmpy")


def main(steps: int = 2000) -> int:
    """Build the four FMUs, time them in fresh processes and print the table."""
    chosen = ("four_bar", "slider_crank")
    results: dict[str, dict[str, dict]] = {}
    with tempfile.TemporaryDirectory(prefix="fmu_timing_") as tmp:
        out = Path(tmp)
        project = build_project(chosen, out / "project")
        for preset in chosen:
            trivial = build_trivial(preset, out / "trivial")
            results[preset] = {"project": measure(project[preset], steps),
                               "trivial": measure(trivial, steps)}
    print_table(results, steps)
    return 0


def cli(argv: list[str]) -> int:
    """``fmu_timing.py`` runs :func:`main`; ``fmu_timing.py --run JSON`` runs one job of
    :func:`jobs` and prints its result as JSON."""
    if argv[:1] == ["--run"]:
        spec = json.loads(argv[1])
        print(json.dumps(jobs()[spec.pop("job")](**spec)))
        return 0
    return main()


if __name__ == "__main__":
    sys.exit(cli(sys.argv[1:]))
