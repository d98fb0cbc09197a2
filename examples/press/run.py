"""Build the crank press's two FMUs, run the system in libcosim and compare the crank's
speed with ``Mechanism.simulate`` under the same motor law (see ``press.py``).

    python examples/press/run.py                      # h = 1e-6 s over 6 s, ~4 min
    python examples/press/run.py --step 1e-4 --no-plots

Prints the coupling error (the largest difference of the crank speed, relative to the
largest speed) and the motor-sizing figures of the last stroke (``press.stroke``), and
exits with status 1 where the error exceeds ``--tolerance``: by default the coupling
error's own size, which is first order in the step, :data:`ERROR_PER_SECOND` times the
step in seconds (1.5e-6 at 1e-6 s, 1.5e-4 at 1e-4 s; measured 0.99 times the step over
6 s); writes ``docs/press_speed.png`` and ``docs/press_loss.png`` (``--plots DIR``
elsewhere, ``--no-plots`` none) and, with ``--json FILE``, the figures and the sampled
motion. A value it cannot run with (a step longer than the run, a run of no whole
stroke, a time libcosim's clock cannot count) ends it with status 2 and one line saying
which and why.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import press  # noqa: E402

ROOT = HERE.parent.parent
#: the default ``--tolerance`` per second of ``--step``: the coupling error is first order
#: in the step, 0.9 to 1.0 times it (in s) relative to the largest speed, from 1e-2 to
#: 1e-6 s (``benchmarks/press_coupling.py``); half as much again is the margin
ERROR_PER_SECOND = 1.5
#: the longest time libcosim's clock counts: int64 nanoseconds [s]
LONGEST = (2 ** 63 - 1) * 1e-9


def problem(step: float, t_end: float, every: float, tolerance: float | None) -> str:
    """What is wrong with the run's options, naming the option and the reason, or ''.

    Examples
    --------
    >>> problem(1e-4, 6.0, 1e-3, None)
    ''
    >>> problem(2.0, 1.0, 1e-3, None)
    '--step 2 is longer than --t-end 1: the run is a whole number of steps'
    >>> problem(1e300, 1e300, 1e-3, None)
    "--step 1e+300: libcosim's clock counts int64 nanoseconds: at most 9.22337e+09 s"
    """
    for option, value in (("--step", step), ("--t-end", t_end), ("--every", every)):
        if not (math.isfinite(value) and value > 0.0):
            return f"{option} {value:g}: must be a number of seconds > 0"
        if value > LONGEST:
            return (f"{option} {value:g}: libcosim's clock counts int64 nanoseconds: at most "
                    f"{LONGEST:g} s")
    if tolerance is not None and not (math.isfinite(tolerance) and tolerance > 0.0):
        return f"--tolerance {tolerance:g}: must be a number > 0"
    if abs(step * 1e9 - round(step * 1e9)) > 1e-6 * step * 1e9:
        return (f"--step {step:g}: libcosim steps in whole nanoseconds: the step must be a "
                "whole number of them")
    if step > t_end:
        return (f"--step {step:g} is longer than --t-end {t_end:g}: the run is a whole "
                "number of steps")
    steps = t_end / step
    if abs(steps - round(steps)) > 1e-9 * steps:
        return (f"--t-end {t_end:g} is not a whole number of steps of {step:g} s "
                f"({steps:.6g}): the run would end at {round(steps) * step:g} s")
    if every > t_end:
        return f"--every {every:g} is longer than --t-end {t_end:g}: no sample"
    return ""


def plot(run, reference, cycle: dict, folder: Path) -> list[Path]:
    """Draw ``press_speed.png`` (the crank speed of both, and their difference) and
    ``press_loss.png`` (the motor's torque, its power and the friction loss, the stroke
    ``cycle`` of :func:`press.stroke` marked) into ``folder``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    folder.mkdir(parents=True, exist_ok=True)
    t, omega = run.t, reference["omega"].to_numpy()
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 5.5),
                                      height_ratios=(3, 1.3))
    top.plot(t, run["omega"], lw=2.2, color="tab:blue", label="libcosim: motor FMU + drive FMU")
    top.plot(t, omega, lw=1.0, ls="--", color="k", label="Mechanism.simulate, same motor law")
    top.axhline(press.MOTOR["omega_noload"], color="tab:gray", lw=0.8, ls=":",
                label="motor's no-load speed")
    top.set_ylabel("crank speed [rad/s]")
    top.legend(loc="lower right", fontsize=8)
    top.set_title(f"Crank press with friction started from rest (communication step "
                  f"{run.h:g} s)", fontsize=10)
    bottom.plot(t, (run["omega"] - omega) / np.max(np.abs(omega)), color="tab:red", lw=0.9)
    bottom.set_ylabel("difference /\nmax speed")
    bottom.set_xlabel("time [s]")
    bottom.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    fig.tight_layout()
    speed = folder / "press_speed.png"
    fig.savefig(speed, dpi=110)
    plt.close(fig)

    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7.5, 5.5),
                                      height_ratios=(1, 1.4))
    for ax in (top, bottom):
        ax.axvspan(cycle["t_start"], cycle["t_stop"], color="tab:gray", alpha=0.12, lw=0)
    top.plot(t, run["motor.tau"], color="tab:blue", lw=1.2, label="motor torque")
    top.axhline(cycle["tau_rms"], color="tab:blue", lw=0.8, ls="--",
                label=f"rms over the last stroke: {cycle['tau_rms']:.0f} N m")
    top.set_ylabel("torque at the crank [N m]")
    top.legend(loc="upper right", fontsize=8)
    top.set_title("Crank press: the motor's torque and power, the friction loss "
                  "(last stroke shaded)", fontsize=10)
    bottom.plot(t, run["motor.P"], color="tab:blue", lw=1.2, label="motor's power into the crank")
    bottom.plot(t, run["P_loss"], color="tab:red", lw=1.4,
                label="friction loss in the pins and guide (drive FMU's P_loss)")
    bottom.axhline(cycle["P_loss_mean"], color="tab:red", lw=0.8, ls="--",
                   label=f"mean loss over the last stroke: {cycle['P_loss_mean']:.1f} W "
                         f"({cycle['E_loss']:.1f} J a stroke)")
    bottom.set_xlabel("time [s]")
    bottom.set_ylabel("power [W]")
    bottom.set_ylim(0.0, 1.35 * max(np.max(run["motor.P"]), np.max(run["P_loss"])))
    bottom.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    loss = folder / "press_loss.png"
    fig.savefig(loss, dpi=110)
    plt.close(fig)
    return [speed, loss]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--step", type=float, default=1e-6, help="communication step [s]")
    parser.add_argument("--t-end", type=float, default=6.0, help="end time [s]")
    parser.add_argument("--every", type=float, default=1e-3, help="sampling interval [s]")
    parser.add_argument("--out", type=Path, default=ROOT / "dist" / "press",
                        help="folder of the FMUs and OspSystemStructure.xml")
    parser.add_argument("--tolerance", type=float, default=None,
                        help="the largest coupling error accepted (default "
                             f"{ERROR_PER_SECOND:g} x the step in s: the error is first "
                             "order in the step)")
    parser.add_argument("--plots", type=Path, default=ROOT / "docs", help="folder of the plots")
    parser.add_argument("--no-plots", action="store_true", help="draw no plots")
    parser.add_argument("--json", type=Path, help="write the figures and the motion here")
    args = parser.parse_args(argv)
    wrong = problem(args.step, args.t_end, args.every, args.tolerance)
    if wrong:
        print(f"press: {wrong}", file=sys.stderr)
        return 2
    tolerance = ERROR_PER_SECOND * args.step if args.tolerance is None else args.tolerance
    t = press.sample_times(args.step, args.t_end, args.every)
    reference = press.simulate(t)  # the reference first: a run of no whole stroke is said
    try:                           # before the co-simulation
        press.stroke(t, reference["theta"], reference["omega"], reference["tau"],
                     reference["P_loss"])
    except ValueError as err:
        print(f"press: --t-end {args.t_end:g}: {err} (from rest, the first whole stroke "
              "ends at t = 2.72 s)", file=sys.stderr)
        return 2

    press.build(args.out)
    start = time.perf_counter()
    try:
        run = press.cosimulate(args.out, args.step, args.t_end, args.every)
        seconds = time.perf_counter() - start
    except ValueError as err:  # a parameter an FMU refuses
        print(f"press: {err}", file=sys.stderr)
        return 2
    error = press.coupling_error(run, reference)
    steps = round(args.t_end / args.step)
    print(f"press: {steps} steps of {args.step:g} s in libcosim ({seconds:.1f} s); crank "
          f"speed: max {np.max(run['omega']):.6f} rad/s; coupling error (max |omega - "
          f"simulate's| / max |omega|): {error:.3e}")
    cycle = press.stroke(run.t, run["theta"], run["omega"], run["motor.tau"], run["P_loss"])
    print(f"press: last stroke, t = {cycle['t_start']:.3f} to {cycle['t_stop']:.3f} s "
          f"({cycle['omega_mean']:.3f} rad/s mean): motor torque rms {cycle['tau_rms']:.1f} "
          f"N m, {cycle['tau_min']:.1f} to {cycle['tau_max']:.1f} N m; motor's work "
          f"{cycle['E_motor']:.1f} J ({cycle['P_motor_mean']:.1f} W mean); friction loss "
          f"{cycle['E_loss']:.2f} J ({cycle['P_loss_mean']:.2f} W mean, "
          f"{cycle['P_loss_max']:.1f} W peak)")
    if not args.no_plots:
        for path in plot(run, reference, cycle, args.plots):
            print(f"wrote {path}")
    if args.json:
        args.json.write_text(json.dumps({
            "step": args.step, "t_end": args.t_end, "error": error,
            "seconds": seconds, "stroke": cycle, "t": run.t.tolist(), "omega": run["omega"].tolist(),
            "omega_simulate": reference["omega"].tolist(),
            "P_loss": run["P_loss"].tolist()}))
    if not error <= tolerance:
        print(f"press: the coupling error {error:.3e} exceeds the tolerance {tolerance:g}")
        return 1
    print(f"press: the coupling error is within the tolerance {tolerance:g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
