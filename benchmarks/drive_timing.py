"""What the drive FMU's step costs, and its accuracy against its run time.

    python benchmarks/drive_timing.py [--friction] [--out FOLDER | --results]

Builds ``FourBarDrive.fmu`` (``linkage-fmu build --native --drive four_bar``, FMI 2.0)
and drives the four-bar from ``theta0 = 0.3`` rad, ``omega0 = 5`` rad/s with ``tau = 2``
N.m for 1 s (to about 190 rad/s, 11 revolutions; the reference is
``Mechanism.simulate`` at ``rtol = atol = 1e-13``). It measures:

``step``
    The cost of one communication step (set ``tau``, doStep, get every output) at steps
    of 0.1, 1 and 10 ms and the default tolerance 1e-8: through fmpy's ``FMU2Slave``
    ctypes functions on preallocated arrays, and from the C host ``tests/c_host/host.c``
    (``-d``); best of 5 runs over 1 s of motion.
``work-precision``
    Simulated revolutions per second of run time against the largest error of theta
    (relative to 1 + |theta|, at 10 ms intervals), for the FMU in co-simulation (steps
    of 10 ms, raw ctypes calls) at tolerances 1e-4 to 1e-12, and for scipy's
    ``solve_ivp`` (DOP853 and RK45) at the same tolerances on the same equations
    (``omega' = (tau - Mb(alpha = 0)) / J_red`` with ``Mb`` and ``J_red`` from the
    library's effort-only plan, ``mech.solve(theta, omega, 0, outputs=("Mb", "J_red"))``);
    best of 3.

``friction``
    The cost of a step of ``SliderCrankDrive.fmu`` with friction against the same FMU
    with every ``mu`` 0 (its kernels without friction, Eksergian's equation): 1 s of
    motion from ``theta0 = 0.3``, ``omega0 = 5`` under ``tau = 1`` N.m and 20 N on the
    piston, a 0.02 kg.m2 flywheel on the crank, steps of 1 ms, tolerance 1e-8, through
    fmpy's ctypes functions; best of 5, in wall time and in the thread's CPU time (which
    a machine shared with other work inflates less: a longer run is preempted more).

Writes ``drive_step.csv``, ``drive_work_precision.csv``, ``drive_work_precision.png``,
``drive_friction.csv`` and ``drive_four_bar.png`` (the motion through the FMU in
co-simulation and model exchange against the library's) to ``build/benchmarks/``
(``--out`` another folder; ``--results``: the committed ``benchmarks/results/``, and
the figure to ``docs/``: see ``folders.py``); prints the tables. ``--friction``
measures only the friction's cost.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
import zipfile
from ctypes import c_double, c_uint
from pathlib import Path

import numpy as np

import folders

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
TAU, THETA0, OMEGA0, STOP, H = 2.0, 0.3, 5.0, 1.0, 0.01
TOLERANCES = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)


class Drive:
    """One co-simulation instance of the drive FMU through fmpy's ctypes functions."""

    def __init__(self, fmu: Path, tolerance: float):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.md = read_model_description(str(fmu))
        self.unzip = extract(str(fmu))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.s = FMU2Slave(guid=self.md.guid, unzipDirectory=self.unzip,
                           modelIdentifier=self.md.coSimulation.modelIdentifier)
        self.s.instantiate()
        self.s.setupExperiment(startTime=0.0)
        self.s.enterInitializationMode()
        self.s.setReal([self.vr[n] for n in ("theta0", "omega0", "tolerance", "tau")],
                       [THETA0, OMEGA0, tolerance, TAU])
        self.s.exitInitializationMode()
        self.outputs = [v.name for v in self.md.modelVariables if v.causality == "output"]

    def run(self, h: float, outputs: list[int]) -> tuple[float, np.ndarray]:
        """Seconds for 1 s of motion in steps of ``h`` (set tau, doStep, get ``outputs``),
        and the values read at each step."""
        n, m = round(STOP / h), len(outputs)
        vr_in, u = (c_uint * 1)(self.vr["tau"]), (c_double * 1)(TAU)
        vr_out, y = (c_uint * m)(*outputs), (c_double * m)()
        rows = np.empty((n, m))
        c, set_real, do_step, get_real = (self.s.component, self.s.fmi2SetReal,
                                          self.s.fmi2DoStep, self.s.fmi2GetReal)
        start = time.perf_counter()
        for k in range(n):
            set_real(c, vr_in, 1, u)
            do_step(c, k * h, h, 1)
            get_real(c, vr_out, m, y)
            rows[k] = y[:]
        return time.perf_counter() - start, rows

    def free(self):
        self.s.terminate()
        self.s.freeInstance()


#: the friction's benchmark: the slider-crank's pairs (mu 0.15 to 0.2 on 15 to 20 mm pins)
FRICTION = dict(mu_O=0.15, r_O=0.02, mu_A=0.15, r_A=0.02, mu_B=0.2, r_B=0.015,
                mu_guide=0.15)


def friction_costs(fmu: Path, h: float = 1e-3) -> list[dict]:
    """Microseconds per step (set tau, doStep, get every output) of the slider-crank's
    drive FMU ``fmu`` without friction and with :data:`FRICTION`, best of 5."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    md = read_model_description(str(fmu))
    unzip = extract(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    outputs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    rows = []
    for name, friction in (("without friction (every mu 0)", {}), ("with friction", FRICTION)):
        start = {"theta0": 0.3, "omega0": 5.0, "tolerance": 1e-8, "tau": 1.0, "load": 20.0,
                 "J1": 0.02, **friction}
        times, cpu = [], []
        for _ in range(5):
            s = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                          modelIdentifier=md.coSimulation.modelIdentifier)
            s.instantiate()
            s.setupExperiment(startTime=0.0)
            s.enterInitializationMode()
            s.setReal([vr[k] for k in start], list(start.values()))
            s.exitInitializationMode()
            n, m = round(STOP / h), len(outputs)
            vr_in, u = (c_uint * 1)(vr["tau"]), (c_double * 1)(1.0)
            vr_out, y = (c_uint * m)(*outputs), (c_double * m)()
            c = s.component
            begin, begin_cpu = time.perf_counter(), time.thread_time()
            for k in range(n):
                s.fmi2SetReal(c, vr_in, 1, u)
                s.fmi2DoStep(c, k * h, h, 1)
                s.fmi2GetReal(c, vr_out, m, y)
            times.append(1e6 * (time.perf_counter() - begin) / n)
            cpu.append(1e6 * (time.thread_time() - begin_cpu) / n)
            s.terminate()
            s.freeInstance()
        rows.append({"model": "SliderCrankDrive", "friction": name, "step_s": h,
                     "fmpy_us": min(times), "cpu_us": min(cpu), "theta_end": y[0]})
    base, base_cpu = rows[0]["fmpy_us"], rows[0]["cpu_us"]
    for r in rows:
        r["ratio"], r["cpu_ratio"] = r["fmpy_us"] / base, r["cpu_us"] / base_cpu
    return rows


def best(fn, repeats: int):
    results = [fn() for _ in range(repeats)]
    return min(results, key=lambda r: r[0])


def reference(mech, t):
    return mech.simulate(TAU, t, theta0=THETA0, omega0=OMEGA0, rtol=1e-13, atol=1e-13)


def error(theta, ref_theta) -> float:
    return float(np.max(np.abs(theta - ref_theta) / (1.0 + np.abs(ref_theta))))


def fmu_run(fmu: Path, tolerance: float, h: float, outputs: list[str]):
    def once():
        d = Drive(fmu, tolerance)
        try:
            return d.run(h, [d.vr[n] for n in outputs])
        finally:
            d.free()
    return once


def step_costs(fmu: Path, host: Path | None) -> list[dict]:
    d = Drive(fmu, 1e-8)
    names, vrs = d.outputs, [d.vr[n] for n in d.outputs]
    d.free()
    rows = []
    for h in (1e-4, 1e-3, 1e-2):
        seconds, _ = best(fmu_run(fmu, 1e-8, h, names), 5)
        row = {"step_s": h, "fmpy_us": 1e6 * seconds * h / STOP, "c_host_us": ""}
        if host:
            row["c_host_us"] = c_host_us(host, fmu, round(STOP / h), vrs)
        rows.append(row)
    return rows


def c_host_us(host: Path, fmu: Path, steps: int, outputs: list[int]) -> float:
    """Best of 5 of the C host's own timing of a step, in microseconds (at the default
    theta0, omega0: the host sets only tau and the load)."""
    with tempfile.TemporaryDirectory() as tmp:
        with zipfile.ZipFile(fmu) as archive:
            archive.extractall(tmp)
        from fmpy import read_model_description
        guid = read_model_description(tmp).guid
        times, cpu = [], []
        for _ in range(5):
            run = subprocess.run([str(host), "-d", tmp, "FourBarDrive", guid, str(steps),
                                  repr(TAU), "0.0", *map(str, outputs)], capture_output=True,
                                 text=True, env={**os.environ, "HOST_QUIET": "1"}, check=True)
            times.append(float(run.stderr.split(" = ")[-1].split(" us/step")[0]))
        return min(times)


def compile_host(out: Path) -> Path | None:
    import fmpy

    exe = out / "host"
    run = subprocess.run(["cc", "-std=c99", "-O2", "-o", str(exe),
                          str(ROOT / "tests" / "c_host" / "host.c"), "-I",
                          str(Path(fmpy.__file__).parent / "c-code"), "-ldl"],
                         capture_output=True, text=True)
    return exe if run.returncode == 0 else None


def scipy_run(mech, method: str, tolerance: float, t: np.ndarray):
    from scipy.integrate import solve_ivp

    def rhs(_, y):
        s = mech.solve(float(y[0]), float(y[1]), 0.0, outputs=("Mb", "J_red"))
        return [y[1], (TAU - s["Mb"]) / s["J_red"]]

    def once():
        start = time.perf_counter()
        r = solve_ivp(rhs, (0.0, STOP), [THETA0, OMEGA0], method=method, t_eval=t,
                      rtol=tolerance, atol=tolerance)
        return time.perf_counter() - start, r.y[0]
    return once


def work_precision(mech, fmu: Path) -> list[dict]:
    t = np.linspace(0.0, STOP, round(STOP / H) + 1)
    ref = reference(mech, t)["theta"].to_numpy()
    revolutions = (ref[-1] - THETA0) / (2.0 * math.pi)
    rows = []
    for tolerance in TOLERANCES:
        seconds, values = best(fmu_run(fmu, tolerance, H, ["theta"]), 3)
        rows.append({"solver": "drive FMU (co-simulation, 10 ms steps)", "tolerance": tolerance,
                     "seconds": seconds, "revolutions_per_s": revolutions / seconds,
                     "error": error(values[:, 0], ref[1:])})
        for method in ("DOP853", "RK45"):
            if method == "RK45" and tolerance < 1e-10:
                continue  # a 5th-order pair at 1e-12 takes minutes here
            seconds, theta = best(scipy_run(mech, method, tolerance, t), 3)
            rows.append({"solver": f"scipy solve_ivp {method}", "tolerance": tolerance,
                         "seconds": seconds, "revolutions_per_s": revolutions / seconds,
                         "error": error(theta, ref)})
    return rows


def agreement_figure(mech, fmu: Path, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from fmpy import simulate_fmu

    t = np.linspace(0.0, STOP, 1001)
    ref = reference(mech, t)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    top.plot(t, ref["omega"], "k", lw=2.5, label="Mechanism.simulate (DOP853, 1e-13)")
    start = {"tau": TAU, "theta0": THETA0, "omega0": OMEGA0}
    for tolerance, style in ((1e-6, "C0"), (1e-8, "C1"), (1e-10, "C2")):
        r = simulate_fmu(str(fmu), stop_time=STOP, output_interval=0.001,
                         start_values={**start, "tolerance": tolerance},
                         output=["theta", "omega"])
        if tolerance == 1e-8:
            top.plot(r["time"], r["omega"], "C1--", lw=1.2, label="drive FMU, co-simulation")
        bottom.semilogy(r["time"], np.abs(r["theta"] - ref["theta"]) + 1e-17, style,
                        label=f"co-simulation, tolerance {tolerance:g}")
    r = simulate_fmu(str(fmu), stop_time=STOP, output_interval=0.001,
                     fmi_type="ModelExchange", relative_tolerance=1e-10, start_values=start,
                     output=["theta", "omega"])
    bottom.semilogy(r["time"], np.abs(r["theta"] - ref["theta"]) + 1e-17, "C3",
                    label="model exchange, fmpy CVode rtol 1e-10")
    top.set_ylabel("omega [rad/s]")
    top.set_title(f"FourBarDrive: tau = {TAU} N.m from theta = {THETA0} rad, omega = "
                  f"{OMEGA0} rad/s")
    top.legend(loc="upper left")
    bottom.set_ylabel("|theta - reference| [rad]")
    bottom.set_xlabel("time [s]")
    bottom.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def work_precision_figure(rows: list[dict], path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 5))
    for k, solver in enumerate(dict.fromkeys(r["solver"] for r in rows)):
        mine = [r for r in rows if r["solver"] == solver]
        ax.loglog([r["error"] for r in mine], [r["revolutions_per_s"] for r in mine], "o-",
                  color=f"C{k}", label=solver)
        for r in mine:
            ax.annotate(f"{r['tolerance']:g}", (r["error"], r["revolutions_per_s"]),
                        textcoords="offset points", xytext=(4, 4), fontsize=7, color=f"C{k}")
    ax.set_xlabel("largest error of theta over 1 s, relative to 1 + |theta|")
    ax.set_ylabel("simulated revolutions per second of run time")
    ax.set_title("Four-bar driven by 2 N.m: work against precision (labels: tolerance)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def friction(out: Path = folders.DEFAULT) -> list[dict]:
    """Build the slider-crank's drive FMU, measure :func:`friction_costs` on it and write
    them to ``out/drive_friction.csv`` (``run.py`` calls this too)."""
    from linkage_fmu.fmi import build_native_fmu

    with tempfile.TemporaryDirectory(prefix="drive_friction_") as tmp:
        rows = friction_costs(build_native_fmu("slider_crank", Path(tmp), 2, drive=True))
    out.mkdir(parents=True, exist_ok=True)
    folders.write_csv(out / "drive_friction.csv", rows)
    return rows


def friction_markdown(rows: list[dict]) -> list[str]:
    """Lines of the table of :func:`friction`'s rows."""
    return (["| drive FMU | friction | us per step (1 ms) | ratio | CPU us per step | ratio |",
             "|---|---|---|---|---|---|"]
            + [f"| {r['model']} | {r['friction']} | {r['fmpy_us']:.3g} | {r['ratio']:.3g} | "
               f"{r['cpu_us']:.3g} | {r['cpu_ratio']:.3g} |" for r in rows])


def main(argv=None) -> int:
    from linkage_fmu import presets
    from linkage_fmu.fmi import build_native_fmu

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--friction", action="store_true",
                        help="measure only the friction's cost (drive_friction.csv)")
    folders.add_options(parser)
    args = parser.parse_args(argv)
    out = folders.folder(args)
    print("\n".join(friction_markdown(friction(out))))
    if args.friction:
        return 0
    mech = presets.get("four_bar")
    with tempfile.TemporaryDirectory(prefix="drive_timing_") as tmp:
        fmu = build_native_fmu("four_bar", Path(tmp), 2, drive=True)
        host = compile_host(Path(tmp))
        steps = step_costs(fmu, host)
        precision = work_precision(mech, fmu)
        folders.write_csv(out / "drive_step.csv", steps)
        folders.write_csv(out / "drive_work_precision.csv", precision)
        work_precision_figure(precision, out / "drive_work_precision.png")
        agreement_figure(mech, fmu, folders.docs(args) / "drive_four_bar.png")
    print("| step | fmpy (ctypes), us per step | C host, us per step |\n|---|---|---|")
    for r in steps:
        host_us = f"{r['c_host_us']:.3g}" if r["c_host_us"] != "" else "-"
        print(f"| {r['step_s'] * 1e3:g} ms | {r['fmpy_us']:.3g} | {host_us} |")
    print("\n| solver | tolerance | run time [s] | revolutions per s | max rel. error |\n"
          "|---|---|---|---|---|")
    for r in precision:
        print(f"| {r['solver']} | {r['tolerance']:g} | {r['seconds']:.3g} | "
              f"{r['revolutions_per_s']:.3g} | {r['error']:.2g} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
