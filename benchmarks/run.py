"""Run time against error for the four-bar and the slider-crank, in one run.

    pip install -e ".[bench]" && python benchmarks/run.py [--quick [--six-bar-build]]
        [--out FOLDER | --results]
    python benchmarks/run.py --scalar [--states N] [--rounds N] [--out FOLDER | --results]

Writes to ``build/benchmarks/`` (``--out``: another folder; ``--results``: the
committed ``benchmarks/results/`` that README quotes, see ``folders.py``):
``work_precision.csv`` (every method: seconds per crank angle and its maximum
relative error against the 40-digit mpmath reference), ``scalar.csv`` (one state
per call of ``solve`` against the source documents' way, timed in alternating rounds),
``fmu.csv``, ``c_host.csv``, ``communication.csv``, ``scale.csv``, ``first_calls.csv``,
``sweep.csv`` (design sweeps in this process and on Dask), ``sweep_fused.csv`` (a sweep's
cost per state against the array kernels and memory's floor: ``sweep_timing.py``),
``optimize.csv`` (the four-bar's peak torque minimised against grids of the same budget:
``optimize_timing.py``), ``press_coupling.csv`` (the crank press of ``examples/press`` in
libcosim: its coupling error against the communication step, ``press_coupling.py``),
``drive_friction.csv`` (the drive FMU's step with friction against every mu 0:
``drive_timing.py --friction``), ``six_bar_build.csv`` (the six-bar's native FMU with
friction, built and timed against its last unrolled -O0 build from the project's git
history: ``six_bar_build.py``; minutes, so only in the full run, or with ``--quick
--six-bar-build``), ``results.md`` (the tables and the targets) and
``work_precision.png`` (log-log, time per angle against error).

``--scalar`` measures only ``scalar.csv`` (seconds; ``--states`` and ``--rounds`` make
it smaller).

Common states: 360 crank angles over a revolution, omega = 10 rad/s, alpha = 0, load
3 N.m (four-bar, on the rocker) or 50 N (slider-crank, on the piston). Error is the
normwise relative error per state (:func:`linkage_fmu.precise.relative_error`), its
maximum over the states. Times are the best of several repeats (this machine is noisy).
The friction rows: the slider-crank with mu = 0.1 in every pair and 0.01 m pins against
its default (mu = 0), arrays and the compiled one-state kernel, the error on 50 states;
the targets: friction's cost per state in the array kernel <= 3x frictionless, the drive
FMU's step with friction <= 2x without, and (where the six-bar was built) its native
FMU's model C <= 4 MB and library <= 3 MB.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
import time
from pathlib import Path

import numpy as np

import drive_timing
import fmu_timing
import folders
import kinepy_peer
import optimize_timing
import peers
import press_coupling
import source_way
import six_bar_build
import sweep_timing
from linkage_fmu import presets
from linkage_fmu.interpolation import AngleTable
from linkage_fmu.precise import references, relative_error

#: names of the friction's targets (issue: friction in motion)
FRICTION_ARRAYS = "friction (mu 0.1) / no friction, per state, array kernel"
FRICTION_DRIVE = "drive FMU step with friction / every mu 0 (1 ms steps)"
HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
PRESETS = {"four_bar": 3.0, "slider_crank": 50.0}  # preset -> load
OMEGA, ALPHA, N_ANGLES = 10.0, 0.0, 360
FMU_ROUNDS = 5  # alternating timing rounds of each FMU (see fmu_rows)
SCALAR_ROUNDS = 40  # alternating timing rounds of the one-state solves (see scalar_rows)
#: the source documents' way (benchmarks/source_way.py): its label in the results
SOURCE = "source documents' way"
SCALAR_KINDS = (SOURCE, "closed_form scalar", "closed_form scalar, positional")
SOURCE_WAY = {"four_bar": source_way.four_bar, "slider_crank": source_way.slider_crank}
TARGETS = {f"vectorised / {SOURCE} per angle": 500.0, f"scalar / {SOURCE} per angle": 10.0,
           f"scalar, positional / {SOURCE} per angle": 10.0,
           "FMU step / trivial FMU step": 1.1, "max relative error (exact methods)": 1e-12,
           "FMU step / trivial FMU step, median of alternating rounds": 1.3,
           "native FMU step / trivial native FMU step (fmpy)": 1.1,
           "C host: pythonfmu FMU step / native FMU step": 20.0,
           "peer / our scalar, at equal or better error": 1.0,
           FRICTION_ARRAYS: 3.0, FRICTION_DRIVE: 2.0,
           "six-bar native FMU with friction: model C (MB)": 4.0,
           "six-bar native FMU with friction: library (MB)": 3.0}


def best_time(fn, repeats: int = 25) -> float:
    """Best wall time of ``fn()`` over ``repeats`` calls, in seconds."""
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def angles(n: int) -> np.ndarray:
    """``n`` crank angles over one revolution, off the exact multiples of pi/2."""
    return 2.0 * math.pi * (np.arange(n) + 0.25) / n


def row(preset, method, variant, seconds_per_angle, error, note=""):
    return {"preset": preset, "method": method, "variant": variant,
            "us_per_angle": seconds_per_angle * 1e6, "max_rel_error": error, "note": note}


def ours(preset: str, load: float, ref: dict, static_ref: dict, big: int) -> list[dict]:
    """Our solvers: the closed form (traced kernels: Python for one state, compiled C for
    arrays), the interpreted group formulas and the direct solve, per angle and batched;
    the effort alone, the static scene, and the interpolated table at several sizes."""
    mech = presets.get(preset)
    theta = angles(N_ANGLES)
    many = np.random.default_rng(0).uniform(0.0, 2 * math.pi, big)
    rows = []
    for method in ("closed_form", "interpreted", "direct"):
        if method != "closed_form":  # closed_form scalar: scalar_rows, against the sources
            sols = [mech.solve(float(t), OMEGA, ALPHA, load, method=method) for t in theta]
            got = {n: np.array([s[n] for s in sols]) for n in mech.output_names}
            t = best_time(lambda: [mech.solve(float(x), OMEGA, ALPHA, load, method=method)
                                   for x in theta]) / N_ANGLES
            rows.append(row(preset, f"{method} scalar", "per angle", t,
                            relative_error(got, ref).max()))
        t = best_time(lambda: mech.solve(many, OMEGA, ALPHA, load, method=method),
                      3 if method == "direct" else 9) / big
        err = relative_error(mech.solve(theta, OMEGA, ALPHA, load, method=method), ref).max()
        rows.append(row(preset, f"{method} vectorised", f"{big} angles", t, err))
    effort = mech.effort.name
    t = best_time(lambda: mech.solve(many, OMEGA, ALPHA, load, outputs=(effort,)), 9) / big
    # measured against each state's largest output, as for the full solves (the effort
    # alone crosses zero, where its own size is no scale)
    got = mech.solve(theta, OMEGA, ALPHA, load, outputs=(effort,))[effort]
    err = np.max(np.abs(got - ref[effort])
                 / np.max([np.abs(ref[n]) for n in mech.output_names], axis=0))
    rows.append(row(preset, f"{effort} only", f"{big} angles", t, err,
                    "virtual power, no reactions"))
    t = best_time(lambda: mech.solve(many, 0.0, 0.0, load), 9) / big
    err = relative_error(mech.solve(theta, 0.0, 0.0, load), static_ref).max()
    rows.append(row(preset, "static scene", f"{big} angles", t, err, "omega = alpha = 0"))
    for size in (64, 256, 1024, 4096, 16384):
        build = best_time(lambda: AngleTable(mech, size), 3)
        table = AngleTable(mech, size)
        t = best_time(lambda: table(many, OMEGA, ALPHA, load), 3) / big
        err = relative_error(table(theta, OMEGA, ALPHA, load), ref).max()
        rows.append(row(preset, "table", f"{size} grid angles", t, err,
                        f"built once in {build * 1e3:.1f} ms"))
    return rows


#: the slider-crank with friction in every pair: mu on each, a pin radius on each pin
FRICTION = dict(mu_O=0.1, mu_A=0.1, mu_B=0.1, mu_guide=0.1, r_O=0.01, r_A=0.01, r_B=0.01)
FRICTION_STATES = 50  # states of its mpmath reference (each one a Newton in mpmath)


def friction_rows(big: int = 100_000) -> list[dict]:
    """The cost of Coulomb friction per state: the slider-crank with :data:`FRICTION`
    against its default (every mu 0, friction not solved), both by the compiled array
    kernel over ``big`` states and by the compiled one-state kernel (hot: after
    HOT_CALLS calls), each with its error against the mpmath reference on
    :data:`FRICTION_STATES` states."""
    from linkage_fmu.solver import HOT_CALLS

    preset, load = "slider_crank", PRESETS["slider_crank"]
    theta = angles(FRICTION_STATES)
    many = np.random.default_rng(0).uniform(0.0, 2 * math.pi, big)
    rows = []
    for label, params in (("no friction (mu = 0)", {}), ("friction, mu = 0.1", FRICTION)):
        mech = presets.get(preset, **params)
        ref = references(mech, theta, OMEGA, ALPHA, load)
        mech.solve(many[:10], OMEGA, ALPHA, load)  # trace and compile first
        t = best_time(lambda: mech.solve(many, OMEGA, ALPHA, load), 9) / big
        err = relative_error(mech.solve(theta, OMEGA, ALPHA, load), ref).max()
        rows.append(row(preset, f"{label}, vectorised", f"{big} angles", t, err,
                        f"error on {FRICTION_STATES} states"))
        for x in many[:HOT_CALLS + 10]:  # the plan gets hot: its compiled kernel
            mech.solve(float(x), OMEGA, ALPHA, load)
        sols = [mech.solve(float(x), OMEGA, ALPHA, load) for x in theta]
        got = {n: np.array([s[n] for s in sols]) for n in mech.output_names}
        t = best_time(lambda: [mech.solve(float(x), OMEGA, ALPHA, load) for x in many[:2000]],
                      5) / 2000
        rows.append(row(preset, f"{label}, scalar", "compiled one-state kernel", t,
                        relative_error(got, ref).max(), f"error on {FRICTION_STATES} states"))
    return rows


def scalar_rows(preset: str, load: float, ref: dict, n: int = N_ANGLES,
                rounds: int = SCALAR_ROUNDS) -> list[dict]:
    """One state per call at the ``n`` common angles: the source documents' way
    (kinematics, the 9x9 matrix with numpy, ``np.linalg.solve``) and ``mech.solve`` of
    plain floats, with keywords as a user writes it
    (``solve(theta, omega=..., alpha=..., load=...)``) and positionally, timed alternately in ``rounds`` rounds (a loaded machine's drift hits
    them alike), the best of each; the compiled kernel hot first. Errors against
    ``ref``, the mpmath reference at those angles."""
    from linkage_fmu.solver import HOT_CALLS

    mech = presets.get(preset)
    p, fn, theta = mech.parameters, SOURCE_WAY[preset], [float(t) for t in angles(n)]
    for k in range(HOT_CALLS + 10):  # hot: the compiled one-state kernel
        mech.solve(theta[k % n], OMEGA, ALPHA, load)

    def source():
        return [fn(p, t, OMEGA, ALPHA, load) for t in theta]

    def keywords():
        return [mech.solve(t, omega=OMEGA, alpha=ALPHA, load=load) for t in theta]

    def positional():
        return [mech.solve(t, OMEGA, ALPHA, load) for t in theta]

    kinds = {SOURCE: source, "closed_form scalar": keywords,
             "closed_form scalar, positional": positional}
    best = dict.fromkeys(kinds, math.inf)
    for _ in range(rounds):
        for kind, loop in kinds.items():
            start = time.perf_counter()
            loop()
            best[kind] = min(best[kind], (time.perf_counter() - start) / n)
    # here and for the peers: their outputs only (the shaking force and moment are ours)
    x = np.array(source())
    got = dict(zip(mech.output_names, x.T))
    rows = [row(preset, SOURCE, "9x9 np.linalg.solve per angle", best[SOURCE],
                relative_error(got, {k: ref[k] for k in got}).max())]
    for kind, variant in (("closed_form scalar", "solve(theta, omega=, alpha=, load=)"),
                          ("closed_form scalar, positional", "solve(theta, omega, alpha, load)")):
        sols = kinds[kind]()
        got = {k: np.array([s[k] for s in sols]) for k in mech.output_names}
        rows.append(row(preset, kind, variant, best[kind], relative_error(got, ref).max(),
                        f"{SOURCE} / this: {best[SOURCE] / best[kind]:.3g} "
                        f"(alternating rounds, best of {rounds})"))
    return rows


def scalar_only(out: Path, n: int, rounds: int) -> list[dict]:
    """``--scalar``: :func:`scalar_rows` of both presets, written to ``out/scalar.csv``."""
    rows = []
    for preset, load in PRESETS.items():
        mech = presets.get(preset)
        ref = references(mech, angles(n), OMEGA, ALPHA, load)
        rows += scalar_rows(preset, load, ref, n, rounds)
    out.mkdir(parents=True, exist_ok=True)
    folders.write_csv(out / "scalar.csv", rows)
    return rows


def peer_rows(preset: str, load: float, ref: dict) -> list[dict]:
    """fourbarhinge (four-bar only) and kinepy on the same states; exudyn at several
    step sizes,
    its errors against our direct solver at its own sample angles (float64, ~1e-15)."""
    mech = presets.get(preset)
    theta = angles(N_ANGLES)
    rows = []
    versions = peers.available()
    if preset == "four_bar" and versions["fourbarhinge"]:
        p = peers.FOURBARHINGE_PARAMS
        got = peers.fourbarhinge_four_bar(p, theta, OMEGA, ALPHA, load)
        t = best_time(lambda: peers.fourbarhinge_four_bar(p, theta, OMEGA, ALPHA, load),
                      3) / N_ANGLES
        rows.append(row(preset, "fourbarhinge", versions["fourbarhinge"], t,
                        relative_error(got, {n: ref[n] for n in got}).max()))
    if kinepy_peer.kinepy_version():  # stencils of 3 samples: see kinepy_peer
        fn = getattr(kinepy_peer, f"kinepy_{preset}")
        p = {"four_bar": kinepy_peer.KINEPY_PARAMS,
             "slider_crank": kinepy_peer.KINEPY_SLIDER_PARAMS}[preset]
        for extrapolate in (False, True):
            got = fn(p, theta, OMEGA, ALPHA, load, extrapolate=extrapolate)
            t = best_time(lambda: fn(p, theta, OMEGA, ALPHA, load, extrapolate=extrapolate),
                          3) / N_ANGLES
            rows.append(row(preset, "kinepy", ("Richardson, 2 solves" if extrapolate else
                                               "3-sample stencil per angle"), t,
                            relative_error(got, {n: ref[n] for n in got}).max(),
                            f"kinepy {kinepy_peer.kinepy_version()}"))
    if versions["exudyn"]:
        for steps in (90, 360, 1440, 5760):
            runs = [peers.exudyn_run(preset, steps, OMEGA, load) for _ in range(3)]
            th, got, _ = runs[0]
            solve = min(r[2]["solve_s"] for r in runs)
            setup = min(r[2]["setup_s"] for r in runs)
            exact = mech.solve(th, OMEGA, ALPHA, load, method="direct")
            err = relative_error(got, {n: exact[n] for n in got}).max()
            rows.append(row(preset, "exudyn", f"{steps} steps/rev", solve / (steps + 1), err,
                            f"exudyn {versions['exudyn']}; setup {setup * 1e3:.1f} ms"))
    return rows


def fmu_rows(built: dict, trivial: dict, steps: int) -> tuple[list[dict], list[dict]]:
    """Per step through fmpy: our FMUs of each flavour and a trivial FMU of that flavour
    with the same I/O (``trivial[flavour][preset]``), timed alternately in FMU_ROUNDS
    rounds. The FMUs' error is the build check's (against the direct solver, 360
    steps)."""
    work, fmu = [], []
    for preset, flavour in ((p, f) for p in PRESETS for f in ("pythonfmu", "native")):
        ours_path = built[flavour][preset]
        check = subprocess.run([sys.executable, "-m", "linkage_fmu.cli", "check", "--json",
                                str(ours_path)],
                               capture_output=True, text=True, cwd=tempfile.gettempdir())
        if not check.stdout.strip():
            raise RuntimeError(f"linkage-fmu check {ours_path} failed: {check.stderr[-3000:]}")
        error = json.loads(check.stdout.splitlines()[-1])["max_rel_error"]
        ours = "linkage_fmu" if flavour == "pythonfmu" else "linkage_fmu native"
        kinds = ((ours, ours_path), (f"trivial {flavour}", trivial[flavour][preset]))
        # alternately, ours then the trivial one, in rounds (each a fresh process):
        # slow drift of this machine's speed hits both alike; each keeps its best loop
        loops = {kind: [] for kind, _ in kinds}
        for _ in range(FMU_ROUNDS):
            for kind, path in kinds:
                loops[kind].append(fmu_timing.time_step_loop(path, steps))
        for kind, path in kinds:
            loop = min(loops[kind], key=lambda m: m["fmpy_api"]["us_per_step"])
            sim = fmu_timing.time_simulate_fmu(path, steps)
            rounds = sorted(m["fmpy_api"]["us_per_step"] for m in loops[kind])
            fmu.append({"preset": preset, "fmu": kind,
                        "fmpy_us_per_step": loop["fmpy_api"]["us_per_step"],
                        "fmpy_us_per_step_median_of_rounds": rounds[len(rounds) // 2],
                        "raw_ctypes_us_per_step": loop["raw_ctypes"]["us_per_step"],
                        "set_us": loop["split"]["set"], "doStep_us": loop["split"]["do_step"],
                        "get_us": loop["split"]["get"],
                        "simulate_fmu_us_per_step": sim["extracted"]["us_per_step"]})
            if kind == ours:
                work.append(row(preset, f"FMU ({flavour}), FMU2Slave loop", f"{steps} steps",
                                loop["fmpy_api"]["us_per_step"] * 1e-6, error,
                                "error: build check against the direct solver"))
                work.append(row(preset, "FMU, simulate_fmu", f"{steps} steps",
                                sim["extracted"]["us_per_step"] * 1e-6, error,
                                "error: build check against the direct solver"))
    return work, fmu


def c_host_rows(built: dict, tmp: Path, steps: int) -> list[dict]:
    """Per step from the C host (``tests/c_host/host.c``, printing nothing): the native
    FMU with no Python in the process, the pythonfmu FMU with this interpreter's
    libpython preloaded; alternately in FMU_ROUNDS rounds, best of each."""
    import sysconfig
    import zipfile

    import fmpy

    exe = tmp / "host"
    subprocess.run(["gcc", "-std=c99", "-O2", "-o", str(exe), str(ROOT / "tests" / "c_host" /
                    "host.c"), "-I", str(Path(fmpy.__file__).parent / "c-code"), "-ldl"],
                   check=True)
    libpython = Path(sysconfig.get_config_var("LIBDIR")) / (
        sysconfig.get_config_var("INSTSONAME") or sysconfig.get_config_var("LDLIBRARY"))
    python_env = {**os.environ, "LD_PRELOAD": str(libpython),
                  "PYTHONPATH": sysconfig.get_paths()["purelib"], "HOST_QUIET": "1"}
    rows = []
    for preset in PRESETS:
        best = {}
        for _ in range(FMU_ROUNDS):
            for flavour, env in (("native", {"PATH": os.environ["PATH"], "HOST_QUIET": "1"}),
                                 ("pythonfmu", python_env)):
                folder = tmp / "host_fmus" / flavour / preset
                if not folder.is_dir():
                    with zipfile.ZipFile(built[flavour][preset]) as archive:
                        archive.extractall(folder)
                root = ET.parse(folder / "modelDescription.xml").getroot()
                outs = [v.get("valueReference") for v in root.iter("ScalarVariable")
                        if v.get("causality") == "output"]
                model = root.find("CoSimulation").get("modelIdentifier")
                run = subprocess.run([str(exe), str(folder), model, root.get("guid"),
                                      str(steps), "10.0", "5.0", *outs], env=env,
                                     capture_output=True, text=True, check=True)
                us = float(run.stderr.strip().splitlines()[-1].split("= ")[1].split()[0])
                best[flavour] = min(best.get(flavour, math.inf), us)
        rows.append({"preset": preset, "native_us_per_step": best["native"],
                     "pythonfmu_us_per_step": best["pythonfmu"],
                     "ratio": best["pythonfmu"] / best["native"]})
    return rows


def sweep_rows(designs: int) -> list[dict]:
    """Design sweeps of the four-bar: ``designs`` designs (l_AB x l_BC x m2) x 360 angles,
    in this process and on a local Dask cluster of 1 and 2 worker processes (started
    before the clock), best of 3; and Dask's overhead per task, from 400 tasks that do
    nothing."""
    from dask.distributed import Client, LocalCluster

    from linkage_fmu.sweep import grid, sweep

    side = round(designs ** (1 / 3))
    table = grid(l_AB=np.linspace(0.05, 0.15, side), l_BC=np.linspace(0.3, 0.4, side),
                 m2=np.linspace(1.0, 3.0, max(1, designs // side ** 2)))
    theta = np.linspace(0.0, 2.0 * math.pi, 360, endpoint=False)
    sweep("four_bar", table.iloc[:10], theta, 10.0, 0.0, 3.0)  # trace and compile first
    rows = []
    t = best_time(lambda: sweep("four_bar", table, theta, 10.0, 0.0, 3.0), 3)
    rows.append({"where": "this process", "designs": len(table), "seconds": t,
                 "designs_per_s": len(table) / t, "task_overhead_ms": math.nan})
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            sweep("four_bar", table.iloc[:10], theta, 10.0, 0.0, 3.0, scheduler=client)
            t = best_time(lambda: sweep("four_bar", table, theta, 10.0, 0.0, 3.0,
                                        scheduler=client), 3)
            t0 = time.perf_counter()
            client.gather(client.map(lambda k: k, range(400), pure=False))
            overhead = (time.perf_counter() - t0) / 400 * workers
        rows.append({"where": f"LocalCluster, {workers} worker(s)", "designs": len(table),
                     "seconds": t, "designs_per_s": len(table) / t,
                     "task_overhead_ms": overhead * 1e3})
    return rows


def communication(dist: Path) -> list[dict]:
    """A master running the FMU over one revolution at constant speed: the cycle-mean
    torque and the energy per revolution it computes from the sampled Mb (rectangle
    rule on fmpy's output rows), against the exact values (periodic trapezoid on 65536
    angles of the closed form, exact to rounding for a smooth periodic Mb)."""
    rows = []
    for preset, load in PRESETS.items():
        mech = presets.get(preset)
        fine = mech.solve(2 * math.pi * np.arange(65536) / 65536, OMEGA, 0.0, load)["Mb"]
        exact_energy = float(np.mean(fine)) * 2 * math.pi
        steps = [8, 16, 32, 64, 128, 256, 1024]
        job = {"fmu": str(dist / f"{presets.preset(preset).model}.fmu"), "steps": steps,
               "omega": OMEGA, "load": load}
        run = subprocess.run([sys.executable, __file__, "--master", json.dumps(job)],
                             capture_output=True, text=True, cwd=tempfile.gettempdir())
        if run.returncode != 0:
            raise RuntimeError(run.stderr[-2000:])
        scale = float(np.max(np.abs(fine))) * 2 * math.pi  # amplitude x one revolution
        for n, (lagged, paired) in zip(steps, json.loads(run.stdout.splitlines()[-1])):
            rows.append({"preset": preset, "steps_per_rev": n,
                         "energy_error_as_sampled": abs(lagged - exact_energy) / scale,
                         "energy_error_paired": abs(paired - exact_energy) / scale})
    return rows


def master(job: dict) -> list[tuple[float, float]]:
    """(In a fresh process.) Energy per revolution seen by a master: simulate_fmu with
    a theta ramp at constant speed, energy = sum of Mb x omega x h over the rows at
    t_0 ... t_(n-1) as they come (each row holds the outputs for the previous row's
    inputs), and over t_1 ... t_n, i.e. each output paired with the inputs it answers."""
    from fmpy import simulate_fmu

    out = []
    for n in job["steps"]:
        h = 2 * math.pi / job["omega"] / n
        t = np.arange(n + 1) * h
        u = np.zeros(n + 1, dtype=[("time", float), ("theta", float), ("omega", float),
                                    ("alpha", float), ("load", float)])
        u["time"], u["theta"], u["omega"], u["load"] = t, job["omega"] * t, job["omega"], job["load"]
        res = simulate_fmu(job["fmu"], stop_time=t[-1], step_size=h, output_interval=h,
                           input=u, output=["Mb"])
        out.append((float(np.sum(res["Mb"][:n]) * job["omega"] * h),
                    float(np.sum(res["Mb"][1:n + 1]) * job["omega"] * h)))
    return out


def scale(sizes) -> list[dict]:
    """Time and peak traced memory of the vectorised closed form, each size in a fresh
    process (four-bar, all outputs)."""
    code = ("import sys, time, tracemalloc, numpy as np; from linkage_fmu import presets; "
            "m = presets.get('four_bar'); n = int(sys.argv[1]); th = np.linspace(0, 6.283, n); "
            "m.solve(th[:2], 10.0, 0.0, 3.0); best = 1e9\n"
            "for _ in range(3):\n t = time.perf_counter(); m.solve(th, 10.0, 0.0, 3.0); "
            "best = min(best, time.perf_counter() - t)\n"
            "tracemalloc.start(); m.solve(th, 10.0, 0.0, 3.0); "
            "print(best, tracemalloc.get_traced_memory()[1])")
    rows = []
    for n in sizes:
        run = subprocess.run([sys.executable, "-c", code, str(n)], capture_output=True,
                             text=True, check=True)
        seconds, peak = run.stdout.split()
        rows.append({"angles": n, "seconds": float(seconds),
                     "ns_per_angle": float(seconds) / n * 1e9,
                     "peak_MB": int(peak) / 1e6, "peak_bytes_per_angle": int(peak) / n})
    return rows


def first_calls() -> list[dict]:
    """What the first call of each path costs, in fresh processes: the Python kernel
    (trace and generation) on the first one-state solve; the compiled array kernel
    (trace, C generation and compilation) on the first array solve; the compiled
    one-state kernel (the cffi module a hot plan gets); with an empty cache, then
    loading from the cache in a new process (four-bar, all outputs)."""
    code = ("import sys, time, numpy as np; from linkage_fmu import presets; "
            "m = presets.get('four_bar'); th = np.linspace(0, 6.283, 1000)\n"
            "t = time.perf_counter(); m.solve(0.3, 10.0, 0.0, 3.0); a = time.perf_counter() - t\n"
            "t = time.perf_counter(); m.solve(0.4, 10.0, 0.0, 3.0); b = time.perf_counter() - t\n"
            "t = time.perf_counter(); m.solve(th, 10.0, 0.0, 3.0); c = time.perf_counter() - t\n"
            "t = time.perf_counter(); m.solve(th, 10.0, 0.0, 3.0); d = time.perf_counter() - t\n"
            "t = time.perf_counter(); m.kernel().compile(); e = time.perf_counter() - t\n"
            "print(a, b, c, d, e)")
    rows = []
    with tempfile.TemporaryDirectory(prefix="linkage_bench_cache_") as cache:
        env = {**os.environ, "LINKAGE_FMU_CACHE": cache}
        for label in ("empty cache", "cache hit"):
            run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                 check=True, env=env)
            first, second, first_array, second_array, compile_one = map(float,
                                                                        run.stdout.split())
            rows.append({"cache": label, "first_scalar_ms": first * 1e3,
                         "next_scalar_ms": second * 1e3, "first_array_ms": first_array * 1e3,
                         "next_array_ms": second_array * 1e3,
                         "compile_scalar_ms": compile_one * 1e3})
    return rows


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(PRESETS), figsize=(12, 6.2), sharey=True)
    floor = 1e-17
    methods = list(dict.fromkeys(r["method"] for r in rows))
    colors = plt.get_cmap("tab20").colors
    style = {m: (colors[2 * k % 20 + (k >= 10)], "osD^v<>ph*"[k % 10])
             for k, m in enumerate(methods)}
    for ax, preset in zip(axes, PRESETS):
        mine = [r for r in rows if r["preset"] == preset]
        for method in methods:
            pts = [r for r in mine if r["method"] == method]
            if not pts:
                continue
            color, marker = style[method]
            ax.loglog([max(r["max_rel_error"], floor) for r in pts],
                      [r["us_per_angle"] for r in pts], marker=marker, color=color,
                      ls="-" if len(pts) > 1 else "", label=method)
        ax.axvline(1e-12, color="grey", ls=":", lw=1)
        ax.set_title(preset)
        ax.set_xlabel("max relative error vs mpmath (40 digits)")
        ax.grid(True, which="major", alpha=0.3)
    axes[0].set_ylabel("run time per crank angle [us]")
    handles = {}
    for ax in axes:
        for h, label in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(label, h)
    fig.legend(handles.values(), handles.keys(), loc="lower center", ncol=5, fontsize=8)
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    fig.savefig(path, dpi=110)


def md_table(header: list, body: list) -> list[str]:
    """Lines of a markdown table."""
    return (["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            + ["| " + " | ".join(str(c) for c in cells) + " |" for cells in body])


def friction_targets(work: list[dict], drive: list[dict],
                     six_bar: list[dict] | str) -> list[tuple[str, str, float]]:
    """(preset, target's name, measured) of friction's targets: its cost per state in the
    array kernel (:func:`friction_rows`), the drive FMU's step (``drive_timing.friction``)
    and, where measured, the six-bar's native FMU's sizes (``six_bar_build``)."""
    us = {r["method"]: r["us_per_angle"] for r in work if r["preset"] == "slider_crank"}
    with_mu = next(r for r in drive if r["friction"] == "with friction")
    out = [("slider_crank", FRICTION_ARRAYS, us["friction, mu = 0.1, vectorised"]
            / us["no friction (mu = 0), vectorised"]),
           ("slider_crank", FRICTION_DRIVE, with_mu["ratio"])]
    if not isinstance(six_bar, str):
        today = next(r for r in six_bar if r["fmu"].startswith("loops"))
        out += [("six_bar", "six-bar native FMU with friction: model C (MB)",
                 today["model_c_MB"]),
                ("six_bar", "six-bar native FMU with friction: library (MB)",
                 today["library_MB"])]
    return out


def friction_sections(drive: list[dict], six_bar: list[dict] | str) -> list[str]:
    """results.md's sections of the drive FMU's step with friction and of the six-bar's
    native FMU with friction against its unrolled -O0 build (or why it was not run)."""
    lines = ["", "## Drive FMU step with friction (us; benchmarks/drive_timing.py --friction)",
             "", "The slider-crank's drive FMU (`SliderCrankDrive`), 1 s from theta0 = 0.3 "
             "rad, omega0 = 5 rad/s under tau = 1 N.m and 20 N on the piston, a 0.02 kg.m2 "
             "flywheel, steps of 1 ms at the tolerance 1e-8 (set tau, doStep, get every "
             "output through fmpy's ctypes functions), best of 5: with every mu 0 and with "
             "mu 0.15 to 0.2 on 15 to 20 mm pins.", ""] + drive_timing.friction_markdown(drive)
    lines += ["", "## Six-bar native FMU with friction: loops at -O2 against the unrolled "
              "-O0 build (benchmarks/six_bar_build.py)", ""]
    if isinstance(six_bar, str):
        return lines + [f"Not measured in this run: {six_bar}."]
    ratio = six_bar_build.ratios(six_bar)
    lines += [f"Both built in this run for this machine (FMI 2.0, a fresh kernel cache "
              f"each): the last commit with friction's iterations unrolled "
              f"({six_bar_build.UNROLLED}, from the project's history) and this tree. A "
              f"step through fmpy's ctypes functions (set 4 inputs, doStep, get every "
              f"output), mu {six_bar_build.MU} in every pair, {six_bar_build.PIN} m pins, "
              f"{six_bar[0]['steps']} states over a revolution at omega 10 rad/s, each FMU "
              f"in fresh processes in alternating rounds, best of each. Step of the "
              f"unrolled build / today's: "
              + ", ".join(f"{ratio[d]:.3g} driven at {d}" if not math.isnan(ratio[d])
                          else f"not measured at {d}" for d in ratio) + ".", ""]
    return lines + six_bar_build.markdown(six_bar)


def summary(work, fmu, host, comm, scl, first, sweeps, fused, optima, machine: str,
            seconds: float, drive: list[dict], six_bar: list[dict] | str) -> str:
    def get(preset, method):
        return next(r for r in work if r["preset"] == preset and r["method"] == method)

    lines = ["# Benchmark results", "", f"Machine: {machine}. Command: `python benchmarks/run.py`"
             f" ({seconds:.0f} s). Times are the best of repeats; error is the maximum over "
             "360 states of the normwise relative error against the 40-digit reference.", "",
             "## Targets", "", "| preset | measure | measured | target | met |",
             "|---|---|---|---|---|"]
    for preset in PRESETS:
        source = get(preset, SOURCE)["us_per_angle"]
        vec = get(preset, "closed_form vectorised")["us_per_angle"]
        sca = get(preset, "closed_form scalar")["us_per_angle"]
        pos = get(preset, "closed_form scalar, positional")["us_per_angle"]
        def step(kind):
            return next(r for r in fmu if r["preset"] == preset and r["fmu"] == kind)

        ours_fmu, triv = step("linkage_fmu"), step("trivial pythonfmu")
        native, triv_native = step("linkage_fmu native"), step("trivial native")
        c_host = next(r for r in host if r["preset"] == preset)
        exact = max(r["max_rel_error"] for r in work if r["preset"] == preset
                    and r["method"] in ("closed_form scalar", "closed_form vectorised",
                                        "direct scalar", "direct vectorised"))
        checks = [(f"vectorised / {SOURCE} per angle", source / vec, ">="),
                  (f"scalar / {SOURCE} per angle", source / sca, ">="),
                  (f"scalar, positional / {SOURCE} per angle", source / pos, ">="),
                  ("FMU step / trivial FMU step",
                   ours_fmu["fmpy_us_per_step"] / triv["fmpy_us_per_step"], "<="),
                  ("FMU step / trivial FMU step, median of alternating rounds",
                   ours_fmu["fmpy_us_per_step_median_of_rounds"]
                   / triv["fmpy_us_per_step_median_of_rounds"], "<="),
                  ("native FMU step / trivial native FMU step (fmpy)",
                   native["fmpy_us_per_step"] / triv_native["fmpy_us_per_step"], "<="),
                  ("C host: pythonfmu FMU step / native FMU step", c_host["ratio"], ">="),
                  ("max relative error (exact methods)", exact, "<=")]
        for peer in ("fourbarhinge", "kinepy", "exudyn"):
            runs = [r for r in work if r["preset"] == preset and r["method"] == peer]
            if runs:  # its most accurate run; our scalar path is at least as accurate
                best = min(runs, key=lambda r: r["max_rel_error"])
                assert best["max_rel_error"] >= get(preset, "closed_form scalar")["max_rel_error"]
                checks.append((f"{peer} ({best['variant']}) / our scalar, per angle",
                               best["us_per_angle"] / sca, ">="))
        for name, value, sense in checks:
            target = TARGETS.get(name, TARGETS["peer / our scalar, at equal or better error"])
            met = value >= target if sense == ">=" else value <= target
            lines.append(f"| {preset} | {name} | {value:.3g} | {sense} {target:g} | "
                         f"{'yes' if met else 'no'} |")
    fused_rows, ratios = fused
    for name, target in sweep_timing.TARGETS.items():
        lines.append(f"| four_bar | {name} | {ratios[name]:.3g} | <= {target:g} | "
                     f"{'yes' if ratios[name] <= target else 'no'} |")
    for preset, name, value in friction_targets(work, drive, six_bar):
        lines.append(f"| {preset} | {name} | {value:.3g} | <= {TARGETS[name]:g} | "
                     f"{'yes' if value <= TARGETS[name] else 'no'} |")
    lines += ["", "## Run time and error", ""] + md_table(
        ["preset", "method", "variant", "us per angle", "max rel. error", "note"],
        [[r["preset"], r["method"], r["variant"], f"{r['us_per_angle']:.3g}",
          f"{r['max_rel_error']:.2g}", r["note"]] for r in work])
    lines += ["", "## FMU step (us)", ""] + md_table(
        ["preset", "FMU", "fmpy loop", "raw ctypes", "set", "doStep", "get", "simulate_fmu"],
        [[r["preset"], r["fmu"]] + [f"{r[k]:.1f}" for k in (
            "fmpy_us_per_step", "raw_ctypes_us_per_step", "set_us", "doStep_us", "get_us",
            "simulate_fmu_us_per_step")] for r in fmu])
    lines += ["", "## FMU step from a C host (us; tests/c_host/host.c, no output printed)", "",
              "The native FMU runs with no Python in the process; the pythonfmu FMU needs "
              "this interpreter's libpython preloaded and its site-packages on PYTHONPATH."
              "", ""] + md_table(
        ["preset", "native", "pythonfmu", "pythonfmu / native"],
        [[r["preset"], f"{r['native_us_per_step']:.3g}", f"{r['pythonfmu_us_per_step']:.3g}",
          f"{r['ratio']:.3g}"] for r in host])
    lines += ["", "## Communication step vs cycle-mean torque and energy (master's view)", "",
              "Error of the energy per revolution (2 pi x the cycle-mean torque, so the "
              "same relative error for both), relative to the torque's amplitude x 2 pi. "
              "*As sampled*: the rows of fmpy's result as they come (each holds the "
              "outputs for the previous row's inputs). *Paired*: each output with the "
              "inputs it answers.", ""] + md_table(
        ["preset", "steps per rev", "as sampled", "paired"],
        [[r["preset"], r["steps_per_rev"], f"{r['energy_error_as_sampled']:.2g}",
          f"{r['energy_error_paired']:.2g}"] for r in comm])
    lines += ["", "## First calls (four-bar, all outputs; ms)", "",
              "A one-state solve traces its plan into a Python kernel on first use; an array "
              "solve also compiles the kernel's C, and a plan that served 1000 one-state "
              "calls is compiled too (both cached on disk by source and flags, so a new "
              "process only loads them). Each line is a fresh process.", ""] + md_table(
        ["cache", "first one-state solve", "next", "first 1000-state solve", "next",
         "compiling the one-state kernel"],
        [[r["cache"]] + [f"{r[k]:.3g}" for k in (
            "first_scalar_ms", "next_scalar_ms", "first_array_ms", "next_array_ms",
            "compile_scalar_ms")] for r in first])
    lines += ["", "## Design sweeps (four-bar, 360 angles per design)", "",
              "`linkage_fmu.sweep`: chunks of about 50,000 states per task. The per-task "
              "overhead is Dask's, from tasks that do nothing (per worker).", ""] + md_table(
        ["where", "designs", "seconds", "designs per s", "overhead per task (ms)"],
        [[r["where"], r["designs"], f"{r['seconds']:.3g}", f"{r['designs_per_s']:.4g}",
          f"{r['task_overhead_ms']:.3g}"] for r in sweeps])
    lines += ["", "## Sweep cost per state (four-bar, ns; benchmarks/sweep_timing.py)", "",
              f"{fused_rows[0]['states'] // N_ANGLES} designs x {N_ANGLES} angles, the "
              "measures timed in alternating rounds, best of each. *fused*: the summaries "
              "computed in the C loop; *numpy*: every output into arrays, then numpy's "
              "reductions; *floor*: a loop that only writes that many doubles per state.",
              ""] + sweep_timing.markdown(fused_rows, ratios)
    lines += ["", "## Design optimisation (four-bar; benchmarks/optimize_timing.py)", "",
              "Minimise `Mb_peak` over l_AB, l_BC, l_CD, l_AD subject to `gamma_C_min_deg >= "
              "40` and `valid`; differential evolution against grids of the same number of "
              "evaluations.", ""] + optimize_timing.markdown(optima)
    lines += friction_sections(drive, six_bar)
    lines += ["", "## Scale (four-bar, closed form, all outputs)", ""] + md_table(
        ["angles", "seconds", "ns per angle", "peak MB", "bytes per angle"],
        [[r["angles"]] + [f"{r[k]:.3g}" for k in (
            "seconds", "ns_per_angle", "peak_MB", "peak_bytes_per_angle")] for r in scl])
    return "\n".join(lines) + "\n"


def machine() -> str:
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    import numpy

    return (f"{cpu}, {os.cpu_count()} cores, {platform.system()} {platform.machine()}, "
            f"Python {platform.python_version()}, numpy {numpy.__version__}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="fewer states and sizes (a smoke run; results not for publishing)")
    folders.add_options(parser)
    parser.add_argument("--scalar", action="store_true",
                        help=f"only one state per call of solve against the {SOURCE} "
                             "(scalar.csv; seconds)")
    parser.add_argument("--states", type=int, default=N_ANGLES,
                        help=f"with --scalar: crank angles (default {N_ANGLES})")
    parser.add_argument("--rounds", type=int, default=SCALAR_ROUNDS,
                        help=f"with --scalar: alternating timing rounds (default {SCALAR_ROUNDS})")
    parser.add_argument("--six-bar-build", action="store_true",
                        help="with --quick, build and time the six-bar's unrolled -O0 FMU "
                             "against today's too (minutes; the full run always does)")
    parser.add_argument("--master", help=argparse.SUPPRESS)  # fresh-process helper
    args = parser.parse_args(argv)
    if args.master:
        print(json.dumps(master(json.loads(args.master))))
        return 0
    args.out = folders.folder(args)
    if args.scalar:
        rows = scalar_only(args.out, args.states, args.rounds)
        print("\n".join(md_table(["preset", "call", "us per angle", "max rel. error", "note"],
                                 [[r["preset"], f"{r['method']}: {r['variant']}",
                                   f"{r['us_per_angle']:.3g}", f"{r['max_rel_error']:.2g}",
                                   r["note"]] for r in rows])))
        print(f"\nwrote {args.out / 'scalar.csv'}")
        return 0
    start = time.perf_counter()
    big = 20_000 if args.quick else 200_000
    work = []
    for preset, load in PRESETS.items():
        mech = presets.get(preset)
        theta = angles(N_ANGLES)
        print(f"{preset}: mpmath reference ...", flush=True)
        ref = references(mech, theta, OMEGA, ALPHA, load)
        static_ref = references(mech, theta, 0.0, 0.0, load)
        print(f"{preset}: ours, {SOURCE}, peers ...", flush=True)
        work += ours(preset, load, ref, static_ref, big)
        work += scalar_rows(preset, load, ref)
        work += peer_rows(preset, load, ref)
    print("friction ...", flush=True)
    work += friction_rows(10_000 if args.quick else 100_000)
    print("drive FMU with friction ...", flush=True)
    drive = drive_timing.friction(args.out)
    with tempfile.TemporaryDirectory(prefix="linkage_bench_") as tmp:
        tmp = Path(tmp)
        print("FMUs ...", flush=True)
        dist = tmp / "dist"
        built = fmu_timing.build_project(list(PRESETS), dist)
        trivial = {"pythonfmu": {p: fmu_timing.build_trivial(p, tmp / "trivial")
                                 for p in PRESETS},
                   "native": {p: fmu_timing.build_trivial_native(built["native"][p],
                                                                 tmp / "trivial")
                              for p in PRESETS}}
        fmu_work, fmu = fmu_rows(built, trivial, 500 if args.quick else 2000)
        work += fmu_work
        host = c_host_rows(built, tmp, 2000 if args.quick else 20000)
        comm = communication(dist)
    print("scale ...", flush=True)
    scl = scale([1, 10, 100, 1000, 10**4, 10**5] + ([] if args.quick else [10**6, 10**7]))
    print("first calls ...", flush=True)
    first = first_calls()
    print("sweeps ...", flush=True)
    sweeps = sweep_rows(1000 if args.quick else 10_000)
    print("sweep cost per state ...", flush=True)
    fused = sweep_timing.run(200 if args.quick else 1000, 3 if args.quick else 10)
    print("design optimisation ...", flush=True)
    optima = optimize_timing.optimisation_rows(1 if args.quick else 3)
    if args.quick and not args.six_bar_build:
        six_bar = "the run was --quick (add --six-bar-build, or run the full benchmark)"
    else:
        print("six-bar with friction: the unrolled -O0 build against today's ...", flush=True)
        six_bar = six_bar_build.measure(500 if args.quick else 2000, 1 if args.quick else 3)
    args.out.mkdir(parents=True, exist_ok=True)
    folders.write_csv(args.out / "work_precision.csv", work)
    folders.write_csv(args.out / "scalar.csv", [r for r in work if r["method"] in SCALAR_KINDS])
    folders.write_csv(args.out / "fmu.csv", fmu)
    folders.write_csv(args.out / "c_host.csv", host)
    folders.write_csv(args.out / "communication.csv", comm)
    folders.write_csv(args.out / "scale.csv", scl)
    folders.write_csv(args.out / "first_calls.csv", first)
    folders.write_csv(args.out / "sweep.csv", sweeps)
    folders.write_csv(args.out / "sweep_fused.csv", fused[0])
    folders.write_csv(args.out / "optimize.csv", optima)
    if not isinstance(six_bar, str):
        folders.write_csv(args.out / "six_bar_build.csv", six_bar)
    plot(work, args.out / "work_precision.png")
    print("press coupling ...", flush=True)
    press = press_coupling.markdown(press_coupling.write(
        args.out, press_coupling.STEPS[:-1] if args.quick else press_coupling.STEPS))
    text = summary(work, fmu, host, comm, scl, first, sweeps, fused, optima, machine(),
                   time.perf_counter() - start, drive, six_bar) + press
    (args.out / "results.md").write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
