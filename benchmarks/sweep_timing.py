"""What a design sweep costs per state, against the kernels it runs and memory's floor.

    python benchmarks/sweep_timing.py [--designs 1000] [--rounds 10] [--out FOLDER | --results]

The four-bar (``four_bar`` preset) at ``--designs`` designs (a grid of l_AB, l_BC and
m2) x 360 crank angles, omega = 10 rad/s, alpha = 0, load 3 N.m. In one run, in
alternating rounds (each measure 3 times in a row per round, the best over ``--rounds``
rounds; this machine is shared), ns per state of:

``sweep (fused)``
    ``linkage_fmu.sweep.sweep``: the summaries computed in the C kernel, the designs
    split between two threads (the default).
``sweep (fused), 1 thread``
    The same in one thread.
``summary kernel alone``
    The C reductions it calls (``Kernel.summary``) on the designs' parameter matrix,
    two threads: the sweep without its Python (validation, grouping, the table).
``sweep (numpy)``
    ``sweep(..., fused=False)``: every output of every state into a numpy block (the
    array kernel, one call per design), then numpy's reductions (the reference).
``array kernel, all outputs``
    The compiled array kernel of every output and diagnostic, one call over all the
    states (its OpenMP threads), into preallocated arrays.
``array kernel, all outputs, a call per design``
    The same, one call of 360 states per design (as the numpy sweep calls it).
``array kernel, Mb only``
    The kernel of the balancing torque alone, one call over all the states.
``floor: write 11 doubles`` and ``floor: write <n> doubles``
    A C loop that only writes 11 doubles per state (and as many as the all-outputs
    kernel has outputs) into preallocated arrays, built like the array kernel
    (``-O2``, OpenMP threads over the same states): what memory alone costs.

Writes ``sweep_fused.csv`` to ``build/benchmarks/`` (``--out`` another folder,
``--results`` the committed ``benchmarks/results/``: see ``folders.py``) and prints a
markdown table with the
ratios and their targets (sweep <= 1.5x the array kernel and <= 2x the Mb-only kernel;
the array kernel within 3x of the 11-double floor).
"""

from __future__ import annotations

import argparse
import csv
import ctypes
import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np

import folders
from linkage_fmu.ccompiler import compile_shared
from linkage_fmu.kernels.compiled import FLAGS
from linkage_fmu.presets import linkage
from linkage_fmu.sweep import THREADS, _reductions, grid, sweep

HERE = Path(__file__).resolve().parent
OMEGA, ALPHA, LOAD, N_ANGLES = 10.0, 0.0, 3.0, 360
BURST = 3  # calls of a measure in a row, each round
TARGETS = {"sweep (fused) / array kernel": 1.5, "sweep (fused) / Mb-only kernel": 2.0,
           "array kernel / floor (11 doubles)": 3.0}


def floor_source(k: int) -> str:
    """A loop writing ``k`` doubles per state: ``floor_<k>(n, x, y)``."""
    ys = "\n".join(f"    double *restrict y{j} = y[{j}];" for j in range(k))
    writes = "\n".join(f"        y{j}[i] = v + {j}.0;" for j in range(k))
    return (f"#include <stddef.h>\n"
            f"void floor_{k}(size_t n, const double *restrict x, double *const *y) {{\n"
            f"{ys}\n"
            f"#pragma omp parallel for schedule(static) if (n > 8192)\n"
            f"    for (size_t i = 0; i < n; i++) {{\n"
            f"        const double v = x[i];\n{writes}\n    }}\n}}\n")


def floor_kernels(counts: tuple, folder: Path) -> dict:
    """The floor loops of ``counts`` doubles, compiled into ``folder``."""
    c = folder / "floor.c"
    c.write_text("\n".join(floor_source(k) for k in counts))
    lib = ctypes.CDLL(str(compile_shared([c], folder / "floor.so", flags=(*FLAGS, "-fopenmp"))))
    out = {}
    for k in counts:
        f = getattr(lib, f"floor_{k}")
        f.restype = None
        f.argtypes = [ctypes.c_size_t, ctypes.c_void_p, ctypes.POINTER(ctypes.c_void_p)]
        out[k] = f
    return out


def address(a: np.ndarray) -> int:
    return a.__array_interface__["data"][0]


def measures(designs: int, folder: Path) -> dict:
    """name -> (callable, states it solves)."""
    mech = linkage("four_bar")
    side = round(designs ** (1 / 3))
    table = grid(l_AB=np.linspace(0.06, 0.12, side), l_BC=np.linspace(0.3, 0.4, side),
                 m2=np.linspace(1.0, 4.0, -(-designs // side ** 2)))[:designs]
    theta = 2.0 * math.pi * np.arange(N_ANGLES) / N_ANGLES
    n = len(table) * N_ANGLES
    every = mech.solver.kernel(None, False, ())
    effort = mech.solver.kernel(("Mb",), False, ())
    inputs = [np.tile(theta, len(table)), np.full(1, OMEGA), np.full(1, ALPHA), np.full(1, LOAD)]
    per_design = [theta] + inputs[1:]
    full, mb = every.array(), effort.array()
    out_full = [np.empty(n) for _ in every.outputs]
    out_mb = [np.empty(n)]
    out_design = np.empty((len(every.outputs), N_ANGLES))
    frozen = [every.prepare(*(row.get(k, mech.parameters[k]) for k in every.parameters))
              for row in table.to_dict("records")]
    names, reductions = _reductions(mech, every.outputs)
    summary = every.summary(reductions)
    params = np.array([[row.get(k, mech.parameters[k]) for k in every.parameters]
                       for row in table.to_dict("records")])
    floors = floor_kernels((11, len(every.outputs)), folder)
    x = inputs[0]
    ys = {k: [np.empty(n) for _ in range(k)] for k in floors}
    yp = {k: (ctypes.c_void_p * k)(*(address(a) for a in ys[k])) for k in floors}

    def per_call():
        for q in frozen:
            full(per_design, N_ANGLES, out_design, q)

    out = {
        "sweep (fused)": (lambda: sweep(mech, table, theta, OMEGA, ALPHA, LOAD), n),
        "sweep (fused), 1 thread": (
            lambda: sweep(mech, table, theta, OMEGA, ALPHA, LOAD, threads=1), n),
        "summary kernel alone": (lambda: summary(params, per_design, N_ANGLES, THREADS), n),
        "sweep (numpy)": (lambda: sweep(mech, table, theta, OMEGA, ALPHA, LOAD, fused=False), n),
        f"array kernel, all {len(every.outputs)} outputs": (lambda: full(inputs, n, out_full), n),
        f"array kernel, all {len(every.outputs)} outputs, a call per design": (per_call, n),
        "array kernel, Mb only": (lambda: mb(inputs, n, out_mb), n),
    }
    for k, f in floors.items():
        # the arrays go with the call (yp holds their addresses only)
        out[f"floor: write {k} doubles"] = (
            lambda f=f, k=k, arrays=ys[k]: f(n, address(x), yp[k]), n)
    return out


def run(designs: int = 1000, rounds: int = 10) -> tuple[list[dict], dict]:
    """Time every measure in alternating rounds; rows (ns per state) and the ratios."""
    with tempfile.TemporaryDirectory(prefix="linkage_fmu_sweep_timing_") as tmp:
        runs = measures(designs, Path(tmp))
        for fn, _ in runs.values():  # trace, compile and touch every buffer first
            fn()
        best = {name: math.inf for name in runs}
        for _ in range(rounds):  # alternating rounds: load on the machine hits all
            for name, (fn, _) in runs.items():
                for _ in range(BURST):  # the first after another measure starts cold
                    start = time.perf_counter()
                    fn()
                    best[name] = min(best[name], time.perf_counter() - start)
    rows = [{"measure": name, "ns_per_state": 1e9 * best[name] / states, "states": states,
             "calls": rounds * BURST} for name, (_, states) in runs.items()]
    ns = {r["measure"]: r["ns_per_state"] for r in rows}
    array = next(v for k, v in ns.items() if k.startswith("array kernel, all")
                 and "per design" not in k)
    ratios = {"sweep (fused) / array kernel": ns["sweep (fused)"] / array,
              "sweep (fused) / Mb-only kernel": ns["sweep (fused)"] / ns["array kernel, Mb only"],
              "array kernel / floor (11 doubles)": array / ns["floor: write 11 doubles"],
              "sweep (numpy) / sweep (fused)": ns["sweep (numpy)"] / ns["sweep (fused)"]}
    return rows, ratios


def markdown(rows: list[dict], ratios: dict) -> list[str]:
    """The measures and the ratios against their targets, as Markdown lines."""
    lines = ["| measure | ns per state |", "|---|---:|"]
    lines += [f"| {r['measure']} | {r['ns_per_state']:.1f} |" for r in rows]
    lines += ["", "| ratio | measured | target |", "|---|---:|---:|"]
    for name, value in ratios.items():
        target = TARGETS.get(name)
        verdict = "" if target is None else (
            f"<= {target:g} ({'met' if value <= target else 'missed'})")
        lines.append(f"| {name} | {value:.2f} | {verdict} |")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=1000)
    parser.add_argument("--rounds", type=int, default=10)
    folders.add_options(parser)
    args = parser.parse_args()
    out = folders.folder(args)
    rows, ratios = run(args.designs, args.rounds)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "sweep_fused.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan
    print(f"four_bar, {rows[0]['states'] // N_ANGLES} designs x {N_ANGLES} angles, best of "
          f"{args.rounds} rounds of {BURST} calls, {os.cpu_count()} cores (load average "
          f"{load:.2f})\n")
    print("\n".join(markdown(rows, ratios)))

if __name__ == "__main__":
    main()
