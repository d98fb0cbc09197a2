"""Design optimisation of the four-bar against a brute-force grid of the same size.

    python benchmarks/optimize_timing.py [--seeds 3] [--out FOLDER | --results]

Minimises the peak driving torque ``Mb_peak`` of the four-bar over four parameters,
l_AB in [0.05, 0.15], l_BC in [0.25, 0.45], l_CD in [0.20, 0.40], l_AD in [0.30, 0.50]
(m), subject to ``gamma_C_min_deg >= 40`` and ``valid``, at 360 crank angles, omega = 10
rad/s, load 3 N.m on the rocker (as ``benchmarks/run.py``):

- differential evolution (``linkage_fmu.optimize``: popsize 15, at most 100
  generations, then the Nelder-Mead polish), one run per seed, with scipy's default
  tolerance of convergence, 0.01 (it may stop early), and with 0 (all 100 generations);
- a brute-force grid with as many evaluations as the first seed's run of each (no
  polish), and the same grid followed by the polish;
- the designs per second of a plain sweep of 4096 designs (an 8**4 grid) in this
  process, and on a local Dask cluster of 2 worker processes (``scheduler=client``,
  the cluster started before the clock; its start-up time reported apart), best of 3,
  and one seed of differential evolution on that cluster, if dask.distributed is
  importable.

Writes ``optimize.csv`` to ``build/benchmarks/`` (``--out`` another folder,
``--results`` the committed ``benchmarks/results/``: see ``folders.py``) and prints a
Markdown table.
"""

from __future__ import annotations

import argparse
import csv
import math
import time
from pathlib import Path

import numpy as np

import folders
from linkage_fmu.optimize import optimize
from linkage_fmu.sweep import grid, sweep

VARY = {"l_AB": (0.05, 0.15), "l_BC": (0.25, 0.45), "l_CD": (0.20, 0.40),
        "l_AD": (0.30, 0.50)}
SUBJECT_TO = ["gamma_C_min_deg >= 40", "valid"]
THETA = np.linspace(0.0, 2.0 * math.pi, 360, endpoint=False)
OMEGA, LOAD = 10.0, 3.0
COLUMNS = ["run", "scheduler", "evaluations", "seconds", "designs_per_s", "Mb_peak",
           "gamma_C_min_deg", *VARY]


def optimum_row(run: str, scheduler: str, res) -> dict:
    """A row of the table for the optimisation result ``res``."""
    return {"run": run, "scheduler": scheduler, "evaluations": res.evaluations,
            "seconds": res.seconds, "designs_per_s": res.evaluations / res.seconds,
            "Mb_peak": res.value, "gamma_C_min_deg": float(res.summary["gamma_C_min_deg"]),
            **res.design}


def best_time(fn, repeats: int = 3) -> float:
    """Best wall time of ``fn()`` over ``repeats`` calls, in seconds."""
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def optimisation_rows(seeds: int = 3) -> list[dict]:
    """Differential evolution (tol 0.01 and 0, ``seeds`` seeds) and grids of the same
    budgets, with and without the polish, in this process."""
    common = dict(theta=THETA, omega=OMEGA, loads=(LOAD,))
    sweep("four_bar", grid(l_AB=[0.1]), THETA, OMEGA, 0.0, LOAD)  # trace and compile first
    rows = []
    for tol in (0.01, 0.0):
        for seed in range(1, seeds + 1):
            res = optimize("four_bar", VARY, "Mb_peak", SUBJECT_TO, seed=seed, tol=tol,
                           **common)
            rows.append(optimum_row(f"differential evolution, tol {tol:g}, seed {seed}",
                                    "this process", res))
    for budget in sorted({rows[0]["evaluations"], rows[seeds]["evaluations"]}):
        for polish in (False, True):
            res = optimize("four_bar", VARY, "Mb_peak", SUBJECT_TO, method="grid",
                           budget=budget, polish=polish, **common)
            rows.append(optimum_row(f"grid of <= {budget} designs"
                                    + (" + polish" if polish else ""), "this process", res))
    return rows


def throughput_rows() -> list[dict]:
    """Designs per second of a plain sweep in this process and on 2 Dask workers, and one
    seed of differential evolution on them (no Dask rows where it is not importable)."""
    designs = grid(**{k: np.linspace(lo, hi, 8) for k, (lo, hi) in VARY.items()})
    t = best_time(lambda: sweep("four_bar", designs, THETA, OMEGA, 0.0, LOAD))
    plain = {k: math.nan for k in COLUMNS}
    rows = [{**plain, "run": f"sweep of {len(designs)} designs", "scheduler": "this process",
             "evaluations": len(designs), "seconds": t, "designs_per_s": len(designs) / t}]
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        print("dask.distributed is not importable: no Dask rows")
        return rows
    t0 = time.perf_counter()
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        start = time.perf_counter() - t0
        where = "LocalCluster, 2 workers"
        sweep("four_bar", designs.iloc[:10], THETA, OMEGA, 0.0, LOAD, scheduler=client)
        t = best_time(lambda: sweep("four_bar", designs, THETA, OMEGA, 0.0, LOAD,
                                    scheduler=client))
        rows.append({**plain, "run": f"sweep of {len(designs)} designs", "scheduler": where,
                     "evaluations": len(designs), "seconds": t,
                     "designs_per_s": len(designs) / t})
        res = optimize("four_bar", VARY, "Mb_peak", SUBJECT_TO, seed=1, scheduler=client,
                       theta=THETA, omega=OMEGA, loads=(LOAD,))
        rows.append(optimum_row("differential evolution, tol 0.01, seed 1", where, res))
    rows.append({**plain, "run": "start-up of the cluster", "scheduler": where,
                 "seconds": start})
    return rows


def markdown(rows: list[dict]) -> list[str]:
    """The rows as Markdown lines."""
    lines = ["| run | where | evaluations | s | designs/s | Mb_peak [N.m] | gamma_C_min [deg] | "
             + " | ".join(f"{k} [m]" for k in VARY) + " |", "|" + "---|" * len(COLUMNS)]
    for r in rows:
        cells = [r["run"], r["scheduler"]]
        cells.append("" if math.isnan(r["evaluations"]) else f"{r['evaluations']:.0f}")
        cells += [f"{r['seconds']:.3f}", "" if math.isnan(r["designs_per_s"])
                  else f"{r['designs_per_s']:.0f}"]
        cells += ["" if math.isnan(r[k]) else f"{r[k]:.6g}"
                  for k in ("Mb_peak", "gamma_C_min_deg", *VARY)]
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3, help="seeds of differential "
                                                             "evolution (default 3)")
    folders.add_options(parser)
    args = parser.parse_args()
    out = folders.folder(args)
    rows = optimisation_rows(args.seeds) + throughput_rows()
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "optimize.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerows(rows)
    print("\n".join(markdown(rows)))
    print(f"\nwrote {out / 'optimize.csv'}")

if __name__ == "__main__":
    main()
