"""The six-bar's native FMU with friction: today's build against the unrolled -O0 one.

    python benchmarks/six_bar_build.py [--steps N] [--rounds N] [--out FOLDER | --results]

Until commit :data:`UNROLLED` friction's iterations were unrolled in the traced kernels, a
fixed number of steps with the build-time state's sign and branch decisions, so the
six-bar's native FMU was too large to optimise and was compiled at -O0. Since then they
are loops decided at run time and it compiles at -O2. Both FMUs are built here in one
run: the old one from the project's own history (``git archive UNROLLED src`` into a
temporary folder, built by that tree's ``build_native_fmu("six_bar")`` in a subprocess
with that tree's ``src`` on ``PYTHONPATH``), today's by this tree's, each in a fresh
process with an empty kernel cache, for this machine's platform only (FMI 2.0). For
each: the wall time of the build, the size of its model C (``sources/model.c``) and
of its library (``binaries/linux64/SixBar.so``), and the cost of one co-simulation step
through fmpy's ``fmi2SetReal``/``fmi2DoStep``/``fmi2GetReal`` ctypes functions (set the
4 inputs, doStep, get every output) at the same inputs: mu = :data:`MU` in every pair,
every pin of radius :data:`PIN` m, driven at OA (the crank) and at KD (off the crank,
the effort's secant iteration in the kernel), ``steps`` states over one revolution at
omega = 10 rad/s, alpha = 0, the FMU's default load. Each FMU is timed in its own fresh
process, the two alternately in ``rounds`` rounds (this machine's drift hits both
alike); the best of each is kept. The steps each FMU discarded (states it refused) are
counted, and among them those this tree's direct solver solves (refused wrongly: the
unrolled kernels' fixed iteration counts took some solvable states for self-locked).

Where git, the project's history or the commit is not available, the old FMU's rows say
so and carry no figures (the run goes on). The old build takes minutes at -O0: ``run.py``
runs this in its full mode only (``--quick --six-bar-build`` forces it). On its own it
writes ``six_bar_build.csv`` to ``build/benchmarks/`` (``--out`` another folder,
``--results`` the committed ``benchmarks/results/``: see ``folders.py``) and prints the
table.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

import folders

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
#: the last commit whose kernels unrolled friction's iterations (the six-bar's FMU at -O0)
UNROLLED = "b2ecb6f"
MU, PIN = 0.1, 0.02
DRIVERS = ("OA", "KD")
OMEGA = 10.0
MODEL = "SixBar"
BUILD = ("import json, sys, time\n"
         "from pathlib import Path\n"
         "import linkage_fmu\n"
         "from linkage_fmu.fmi import build_native_fmu\n"
         "start = time.perf_counter()\n"
         "fmu = build_native_fmu('six_bar', Path(sys.argv[1]))\n"
         "print(json.dumps({'fmu': str(fmu), 'seconds': time.perf_counter() - start,\n"
         "                  'package': linkage_fmu.__file__}))\n")


def friction_values(parameters) -> dict[str, float]:
    """The start values of the benchmark: :data:`MU` on every ``mu_`` parameter
    and :data:`PIN` on every ``r_`` parameter among ``parameters`` (names).

    Examples
    --------
    >>> friction_values(["l_OA", "mu_O", "r_O", "mu_B", "driver"])
    {'mu_O': 0.1, 'r_O': 0.02, 'mu_B': 0.1}
    """
    return {n: (PIN if n.startswith("r_") else MU) for n in parameters
            if n.startswith(("mu_", "r_"))}


def states(steps: int):
    """The benchmark's crank angles: ``steps`` over one revolution, off pi/2's multiples."""
    import numpy as np

    return 2.0 * math.pi * (np.arange(steps) + 0.25) / steps


def refused_solvable(driver: str, load: float, discarded: list[int], steps: int) -> int:
    """How many of the ``discarded`` states (indices into :func:`states`) this tree's
    direct solver solves (status SOLVED) at the benchmark's friction and ``driver``."""
    import numpy as np

    from linkage_fmu import presets
    from linkage_fmu.solver import SOLVED

    mech = presets.get("six_bar", driver=driver,
                       **friction_values(presets.get("six_bar").parameters))
    sol = mech.solve(states(steps), OMEGA, 0.0, load, method="direct")
    return int(np.sum(np.asarray(sol.status)[discarded] == SOLVED))


def old_tree(dest: Path, commit: str = UNROLLED) -> Path | str:
    """Export ``commit``'s ``src`` from the project's git history into ``dest``; return
    the folder to put on ``PYTHONPATH``, or a sentence saying why it cannot be had."""
    git = shutil.which("git")
    if git is None:
        return "git is not installed"
    probe = subprocess.run([git, "-C", str(ROOT), "rev-parse", "--verify", "--quiet",
                            f"{commit}^{{commit}}"], capture_output=True, text=True)
    if probe.returncode != 0:
        return f"commit {commit} is not in the git history here (no checkout, or a shallow one)"
    dest.mkdir(parents=True, exist_ok=True)
    archive = subprocess.run([git, "-C", str(ROOT), "archive", "--format=tar", commit, "src"],
                             capture_output=True)
    if archive.returncode != 0:
        return f"git archive {commit} failed: {archive.stderr.decode()[-300:]}"
    subprocess.run(["tar", "-x", "-C", str(dest)], input=archive.stdout, check=True)
    return dest / "src"


def build(src: Path, out: Path, cache: Path) -> dict:
    """Build the six-bar's native FMU with the tree ``src`` in a fresh process (its only
    ``linkage_fmu``, the kernel cache ``cache``); its path and wall seconds, model C and
    library bytes."""
    env = {**os.environ, "PYTHONPATH": str(src), "LINKAGE_FMU_CACHE": str(cache)}
    run = subprocess.run([sys.executable, "-c", BUILD, str(out)], capture_output=True,
                         text=True, env=env, cwd=tempfile.gettempdir())
    if run.returncode != 0:
        raise RuntimeError(f"building the six-bar with {src} failed: {run.stderr[-3000:]}")
    done = json.loads(run.stdout.splitlines()[-1])
    if not Path(done["package"]).resolve().is_relative_to(Path(src).resolve()):
        raise RuntimeError(f"the build meant for {src} imported {done['package']}")
    fmu = Path(done["fmu"])
    with zipfile.ZipFile(fmu) as archive:
        model_c = archive.read("sources/model.c")
        library = archive.getinfo(f"binaries/linux64/{MODEL}.so").file_size
    # the unrolled kernels were too large to optimise: pragmas turned the optimiser off
    level = "-O0" if b'optimize ("O0")' in model_c or b"optimize off" in model_c else "-O2"
    return {"fmu": fmu, "build_s": done["seconds"], "model_c_MB": len(model_c) / 1e6,
            "library_MB": library / 1e6, "level": level}


def time_steps(fmu: Path, driver: str, steps: int, repeats: int = 5) -> dict:
    """In a fresh process (fmpy only): microseconds per step of ``fmu`` driven at
    ``driver`` with friction (best of ``repeats`` loops over ``steps`` states), and how
    many of the states it discarded."""
    job = json.dumps({"fmu": str(fmu), "driver": driver, "steps": steps, "repeats": repeats})
    with tempfile.TemporaryDirectory(prefix="six_bar_step_") as cwd:
        run = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--job", job],
                             capture_output=True, text=True, cwd=cwd)
    if run.returncode != 0:
        raise RuntimeError(f"timing {fmu} at {driver} failed: {run.stderr[-3000:]}")
    return json.loads(run.stdout.splitlines()[-1])


def step_job(fmu: str, driver: str, steps: int, repeats: int) -> dict:
    """The fresh process's side of :func:`time_steps`."""
    from ctypes import c_double, c_uint

    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave
    from fmpy.simulation import apply_start_values

    md = read_model_description(fmu)
    var = {v.name: v for v in md.modelVariables}
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bench")
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    parameters = [v.name for v in md.modelVariables if v.causality == "parameter"]
    apply_start_values(slave, md, {**friction_values(parameters), "driver": driver})
    slave.exitInitializationMode()
    inputs = ("theta", "omega", "alpha", "load")
    names = [v.name for v in md.modelVariables if v.causality == "output"]
    outputs = [var[n].valueReference for n in names]
    loss = names.index("P_loss")
    # the library's own functions: fmpy's wrappers raise on a discarded step
    set_real, do_step, get_real = (getattr(slave.dll, f) for f in
                                   ("fmi2SetReal", "fmi2DoStep", "fmi2GetReal"))
    comp, n_out = slave.component, len(outputs)
    vr_i, vr_o = (c_uint * 4)(*(var[n].valueReference for n in inputs)), (c_uint * n_out)(*outputs)
    u = (c_double * 4)(0.0, OMEGA, 0.0, float(var["load"].start))
    y = (c_double * n_out)()
    h = 2.0 * math.pi / OMEGA / steps
    thetas = states(steps).tolist()
    best, t = math.inf, 0.0
    for _ in range(repeats + 1):  # the first loop warms up
        worst, discarded = 0, []
        peak_loss = 0.0
        start = time.perf_counter()
        for i, theta in enumerate(thetas):
            u[0] = theta
            worst |= set_real(comp, vr_i, 4, u)
            status = do_step(comp, t, h, 1)
            if status == 2:  # fmi2Discard: a state the FMU refused
                discarded.append(i)
            worst |= status & ~2
            worst |= get_real(comp, vr_o, n_out, y)
            if status != 2:
                peak_loss = max(peak_loss, y[loss])
            t += h
        best = min(best, time.perf_counter() - start)
        if worst > 1:
            raise RuntimeError(f"an FMI call returned status bits {worst}")
    slave.terminate()
    slave.freeInstance()
    if not peak_loss > 0.0:  # friction taken: the kernels with friction ran
        raise RuntimeError(f"{fmu} driven at {driver} lost no power to friction")
    return {"us_per_step": best / steps * 1e6, "discarded": discarded,
            "P_loss_peak": peak_loss, "load": u[3]}


def measure(steps: int = 2000, rounds: int = 3) -> list[dict]:
    """Rows of the comparison (see the module's docstring): one per FMU and driver."""
    rows = []
    with tempfile.TemporaryDirectory(prefix="six_bar_build_") as tmp:
        tmp = Path(tmp)
        builds = {}
        old = old_tree(tmp / "old")
        if isinstance(old, Path):
            print(f"six-bar: building the FMU of {UNROLLED} (minutes at -O0) ...", flush=True)
            try:
                builds[f"unrolled ({UNROLLED})"] = build(old, tmp / "old_fmu",
                                                         tmp / "old_cache")
            except RuntimeError as err:  # the old tree in today's environment
                old = f"the build of {UNROLLED} failed: {str(err).strip().splitlines()[-1]}"
        print("six-bar: building today's FMU ...", flush=True)
        builds["loops (this tree)"] = build(ROOT / "src", tmp / "new_fmu", tmp / "new_cache")
        for driver in DRIVERS:
            times = {name: [] for name in builds}
            for _ in range(rounds):
                for name, b in builds.items():
                    times[name].append(time_steps(b["fmu"], driver, steps))
            for name, b in builds.items():
                fastest = min(times[name], key=lambda r: r["us_per_step"])
                refused = refused_solvable(driver, fastest["load"], fastest["discarded"],
                                           steps)
                rows.append({"fmu": name, "driver": driver, "us_per_step": fastest["us_per_step"],
                             "discarded": len(fastest["discarded"]), "steps": steps,
                             "discarded_solvable": refused,
                             "P_loss_peak_W": fastest["P_loss_peak"],
                             "build_s": b["build_s"], "model_c_MB": b["model_c_MB"],
                             "library_MB": b["library_MB"], "level": b["level"],
                             "note": ""})
        if not isinstance(old, Path):
            for driver in DRIVERS:
                rows.append({"fmu": f"unrolled ({UNROLLED})", "driver": driver,
                             "us_per_step": math.nan, "discarded": "", "steps": steps,
                             "discarded_solvable": "",
                             "P_loss_peak_W": math.nan,
                             "build_s": math.nan, "model_c_MB": math.nan,
                             "library_MB": math.nan, "level": "",
                             "note": f"not measured: {old}"})
    return rows


def ratios(rows: list[dict]) -> dict[str, float]:
    """Per driver: the unrolled FMU's step over today's (NaN where it was not measured)."""
    out = {}
    for driver in DRIVERS:
        mine = {r["fmu"].split(" ")[0]: r["us_per_step"] for r in rows if r["driver"] == driver}
        out[driver] = mine.get("unrolled", math.nan) / mine["loops"]
    return out


def markdown(rows: list[dict]) -> list[str]:
    """Lines of the results' table of :func:`measure`'s ``rows``."""
    lines = ["| FMU | driver | us per step | states discarded (of them, the direct solver "
             "solves) | peak P_loss (W) | build (s) | model C (MB) | library (MB) | compiled | "
             "note |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["note"]:  # not measured
            lines.append(f"| {r['fmu']} | {r['driver']} |" + " - |" * 7 + f" {r['note']} |")
            continue
        lines.append(f"| {r['fmu']} | {r['driver']} | {r['us_per_step']:.3g} | "
                     f"{r['discarded']} of {r['steps']} ({r['discarded_solvable']}) | "
                     f"{r['P_loss_peak_W']:.6g} | "
                     f"{r['build_s']:.3g} | "
                     f"{r['model_c_MB']:.3g} | {r['library_MB']:.3g} | {r['level']} | "
                     f"{r['note']} |")
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--rounds", type=int, default=3)
    folders.add_options(parser)
    parser.add_argument("--job", help=argparse.SUPPRESS)  # the fresh timing process
    args = parser.parse_args(argv)
    if args.job:
        print(json.dumps(step_job(**json.loads(args.job))))
        return 0
    rows = measure(args.steps, args.rounds)
    out = folders.folder(args)
    out.mkdir(parents=True, exist_ok=True)
    folders.write_csv(out / "six_bar_build.csv", rows)
    print("\n".join(markdown(rows)))
    print({d: round(x, 3) for d, x in ratios(rows).items()})
    return 0


if __name__ == "__main__":
    sys.exit(main())
