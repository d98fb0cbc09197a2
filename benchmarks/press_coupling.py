"""The crank press's coupling error against libcosim's communication step.

    python benchmarks/press_coupling.py [--quick] [--out FOLDER | --results]

Builds the two FMUs of ``examples/press`` (the motor and the press's drive FMU), runs
the system (the press with friction in its pins and guide) in libcosim from rest for 3 s
(run-up and two strokes) at communication steps
of 1e-2 to 1e-6 s (``--quick``: to 1e-5 s), and compares the crank speed, sampled every
10 ms, with ``Mechanism.simulate`` under the same motor law at ``rtol = atol = 1e-12``.
The error is the largest difference of the crank speed relative to the largest speed.
libcosim holds the motor's torque over each step, so the error falls like the step.

Writes ``press_coupling.csv``, ``press_coupling.md`` and ``press_coupling.png`` to
``build/benchmarks/`` (``--out`` another folder, ``--results`` the committed
``benchmarks/results/``: see ``folders.py``); ``benchmarks/run.py`` calls
:func:`write`.
"""

from __future__ import annotations

import argparse
import csv
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "examples" / "press"))

import folders  # noqa: E402
import press  # noqa: E402

STEPS = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6)
T_END, EVERY = 3.0, 1e-2


def rows(steps=STEPS, t_end: float = T_END) -> list[dict]:
    """One row per communication step: the coupling error, the error per second of step
    and libcosim's run time."""
    out = []
    with tempfile.TemporaryDirectory(prefix="press_coupling_") as tmp:
        press.build(tmp)
        for h in steps:
            start = time.perf_counter()
            run = press.cosimulate(tmp, h, t_end, EVERY)
            seconds = time.perf_counter() - start
            error = press.coupling_error(run, press.simulate(run.t))
            out.append({"step_s": h, "steps": round(t_end / h), "max_rel_speed_error": error,
                        "error_per_step_s": error / h, "libcosim_s": seconds,
                        "us_per_step": seconds / round(t_end / h) * 1e6})
            print(f"press coupling: h = {h:g} s: error {error:.3e} ({seconds:.1f} s)",
                  flush=True)
    return out


def markdown(table: list[dict]) -> str:
    """The rows as the section of ``results.md``."""
    lines = ["", "## Crank press: coupling error against the communication step "
             "(examples/press; benchmarks/press_coupling.py)", "",
             "The motor FMU and the press's drive FMU in libcosim (fixed step), from rest "
             f"for {T_END:g} s, against `Mechanism.simulate` under the same motor law "
             "(rtol = atol = 1e-12). Error: the largest difference of the crank speed, "
             "relative to the largest speed. Friction in the press's pins and guide ("
             + ", ".join(f"{k} = {v:g}" for k, v in press.FRICTION.items()) + ").", "",
             "Run times on a shared machine, loading the system included: libcosim's own "
             "work and the press FMU's step with friction (its cost alone: "
             "`drive_friction.csv`).", "",
             "| step (s) | steps | max rel. speed error | error / step (1/s) | libcosim (s) "
             "| us per step |", "|---|---|---|---|---|---|"]
    lines += [f"| {r['step_s']:g} | {r['steps']} | {r['max_rel_speed_error']:.3g} | "
              f"{r['error_per_step_s']:.3g} | {r['libcosim_s']:.3g} | {r['us_per_step']:.3g} |"
              for r in table]
    return "\n".join(lines) + "\n"


def plot(table: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = [r["step_s"] for r in table]
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.loglog(h, [r["max_rel_speed_error"] for r in table], "o-", label="libcosim vs simulate")
    ax.loglog(h, [table[-1]["error_per_step_s"] * x for x in h], ":", color="gray",
              label="first order")
    ax.axhline(1e-6, color="tab:red", lw=0.8, ls="--", label="1e-6")
    ax.set_xlabel("communication step [s]")
    ax.set_ylabel("max relative crank speed error")
    ax.set_title("Crank press: coupling error", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write(out: Path = folders.DEFAULT, steps=STEPS) -> list[dict]:
    """Measure and write ``press_coupling.csv``, ``.md`` and ``.png`` into ``out``."""
    table = rows(steps)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "press_coupling.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(table[0]))
        writer.writeheader()
        writer.writerows(table)
    (out / "press_coupling.md").write_text(markdown(table).lstrip())
    plot(table, out / "press_coupling.png")
    return table


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="steps down to 1e-5 s only")
    folders.add_options(parser)
    args = parser.parse_args(argv)
    print(markdown(write(folders.folder(args), STEPS[:-1] if args.quick else STEPS)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
