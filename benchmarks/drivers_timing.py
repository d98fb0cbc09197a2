"""Linkages driven by several actuators against the four-bar: the array solve per state.

    python benchmarks/drivers_timing.py [--states N] [--rounds N] [--out FOLDER | --results]

Each of the five-bar robot (two cranks), the dump body (one cylinder) and the excavator
arm (three cylinders), all written as joints and links in ``examples/``, and the
four-bar preset, is solved over ``N`` states in one call of ``Mechanism.solve`` (every
output, the closed form: the compiled array kernel, warmed first), its drivers' inputs
drawn at random within the ranges the tests use, nonzero speeds and accelerations. The
linkages are timed in turn in each of ``rounds`` rounds (this machine's drift hits them
alike); each row holds the best time per state and the median over the rounds of its
ratio to the four-bar's time in the same round. The error column is the largest
difference from the direct solver (LU of the assembled ``A x = b``) over the states,
relative to the largest output of its unit. On its own it writes ``drivers.csv`` to
``build/benchmarks/`` (``--out`` another folder, ``--results`` the committed
``benchmarks/results/``: see ``folders.py``) and prints the table.
"""

from __future__ import annotations

import argparse
import csv
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import folders  # noqa: E402

import linkage_fmu  # noqa: E402
from linkage_fmu import presets  # noqa: E402
from linkage_fmu.fmi.check import compare  # noqa: E402

EXAMPLES = HERE.parent / "examples"
#: linkage -> each driver's coordinate range (as tests/test_examples_drivers.py) and its loads
CASES = {
    "five_bar": ([(1.6, 2.2), (0.9, 1.5)], {"P": 12.0}),
    "dump_body": ([(-0.1, 0.4)], {"W": 20000.0}),
    "excavator": ([(-0.3, 0.5), (-0.4, 0.6), (-0.15, 0.4)], {"F_T": 15000.0}),
}


def inputs(mech, ranges, n: int, rng) -> dict:
    out = {}
    for d, (a, b) in zip(mech.drivers, ranges):
        out.update(zip(d.inputs, (rng.uniform(a, b, n), rng.uniform(-1.0, 1.0, n),
                                  rng.uniform(-2.0, 2.0, n))))
    return out


def error(mech, kw: dict) -> float:
    got, ref = mech.solve(**kw), mech.solve(**kw, method="direct")
    names = list(mech.output_names)
    return float(compare(got, ref, names, {n: mech.output_info[n][0] for n in names})[0])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--states", type=int, default=200_000)
    parser.add_argument("--rounds", type=int, default=7)
    folders.add_options(parser)
    args = parser.parse_args(argv)
    rng = np.random.default_rng(2026)
    jobs = {"four_bar": (presets.get("four_bar"),
                         {"theta": rng.uniform(0.0, 2 * np.pi, args.states),
                          "omega": rng.uniform(-30.0, 30.0, args.states),
                          "alpha": rng.uniform(-100.0, 100.0, args.states), "load": 3.0})}
    for name, (ranges, loads) in CASES.items():
        mech = linkage_fmu.load(EXAMPLES / f"{name}.toml")
        jobs[name] = (mech, {**inputs(mech, ranges, args.states, rng), **loads})
    for mech, kw in jobs.values():  # compile and warm each kernel
        mech.solve(**kw)
    times = {name: [] for name in jobs}
    for _ in range(args.rounds):
        for name, (mech, kw) in jobs.items():
            t0 = time.perf_counter()
            mech.solve(**kw)
            times[name].append((time.perf_counter() - t0) / args.states)
    rows = []
    for name, (mech, kw) in jobs.items():
        ratio = statistics.median(a / b for a, b in zip(times[name], times["four_bar"]))
        rows.append({"linkage": name, "drivers": len(mech.drivers),
                     "outputs": len(mech.output_names), "states": args.states,
                     "ns_per_state": round(min(times[name]) * 1e9, 1),
                     "ratio_to_four_bar": round(ratio, 2),
                     "max_rel_error_vs_direct": f"{error(mech, kw):.1e}"})
    out = folders.folder(args)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "drivers.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(" | ".join(rows[0]))
    for r in rows:
        print(" | ".join(str(v) for v in r.values()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
