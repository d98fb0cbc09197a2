"""Build the crank press's two FMUs, run the system in libcosim and compare the crank's
speed with ``Mechanism.simulate`` under the same motor law (see ``press.py``).

    python examples/press/run.py                      # h = 1e-6 s over 3 s, ~1 min
    python examples/press/run.py --step 1e-4 --no-plots
    python examples/press/run.py --friction           # mu = 0.1 in the pins and guide

Prints the coupling error (the largest difference of the crank speed, relative to the
largest speed) and exits with status 1 where it exceeds ``--tolerance`` (1e-6); writes
``docs/press_speed.png`` and ``docs/press_loss.png`` (``--plots DIR`` elsewhere,
``--no-plots`` none) and, with ``--json FILE``, the figures and the sampled motion.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import press  # noqa: E402

ROOT = HERE.parent.parent


def plot(run, reference, folder: Path, friction: bool) -> list[Path]:
    """Draw ``press_speed.png`` (the crank speed of both, and their difference) and
    ``press_loss.png`` (the motor's power and the friction loss) into ``folder``."""
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
    top.set_title(f"Crank press started from rest (communication step {run.h:g} s)", fontsize=10)
    bottom.plot(t, (run["omega"] - omega) / np.max(np.abs(omega)), color="tab:red", lw=0.9)
    bottom.set_ylabel("difference /\nmax speed")
    bottom.set_xlabel("time [s]")
    bottom.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    fig.tight_layout()
    speed = folder / "press_speed.png"
    fig.savefig(speed, dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    ax.plot(t, run["motor.P"], color="tab:blue", lw=1.2, label="motor's power into the crank")
    ax.plot(t, run["P_loss"], color="tab:red", lw=1.6,
            label="friction loss (drive FMU's P_loss)" if friction else
            "friction loss (drive FMU's P_loss; mu = 0 in this run)")
    if not friction:  # what the pins and guide would take along this motion
        mech = press.description().build(**press.parameters(friction=True))
        estimate = mech.solve(run["theta"], run["omega"], run["alpha"], load=0.0)["P_loss"]
        mu = ", ".join(f"{k} {v:g}" for k, v in press.FRICTION.items())
        ax.plot(t, np.asarray(estimate), color="tab:orange", lw=1.0, ls="--",
                label=f"friction loss along this motion with {mu} (kinetostatics)")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("power [W]")
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title("Crank press: the motor's power and the friction loss", fontsize=10)
    fig.tight_layout()
    loss = folder / "press_loss.png"
    fig.savefig(loss, dpi=110)
    plt.close(fig)
    return [speed, loss]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--step", type=float, default=1e-6, help="communication step [s]")
    parser.add_argument("--t-end", type=float, default=3.0, help="end time [s]")
    parser.add_argument("--every", type=float, default=1e-3, help="sampling interval [s]")
    parser.add_argument("--out", type=Path, default=ROOT / "dist" / "press",
                        help="folder of the FMUs and OspSystemStructure.xml")
    parser.add_argument("--friction", action="store_true", default=None,
                        help=f"friction in the pins and guide ({press.FRICTION}), whatever "
                             f"press.FRICTION_ON says ({press.FRICTION_ON})")
    parser.add_argument("--tolerance", type=float, default=1e-6,
                        help="the largest coupling error accepted")
    parser.add_argument("--plots", type=Path, default=ROOT / "docs", help="folder of the plots")
    parser.add_argument("--no-plots", action="store_true", help="draw no plots")
    parser.add_argument("--json", type=Path, help="write the figures and the motion here")
    args = parser.parse_args(argv)
    friction = press.FRICTION_ON if args.friction is None else args.friction

    press.build(args.out)
    start = time.perf_counter()
    try:
        run = press.cosimulate(args.out, args.step, args.t_end, args.every, friction)
        seconds = time.perf_counter() - start
        reference = press.simulate(run.t, friction)
    except ValueError as err:  # a parameter an FMU or simulate refuses: friction, today
        print(f"press: {err}", file=sys.stderr)
        return 2
    error = press.coupling_error(run, reference)
    steps = round(args.t_end / args.step)
    print(f"press: {steps} steps of {args.step:g} s in libcosim ({seconds:.1f} s), friction "
          f"{'on' if friction else 'off'}; crank speed: max {np.max(run['omega']):.6f} rad/s; "
          f"coupling error (max |omega - simulate's| / max |omega|): {error:.3e}")
    if not args.no_plots:
        for path in plot(run, reference, args.plots, friction):
            print(f"wrote {path}")
    if args.json:
        args.json.write_text(json.dumps({
            "step": args.step, "t_end": args.t_end, "friction": friction, "error": error,
            "seconds": seconds, "t": run.t.tolist(), "omega": run["omega"].tolist(),
            "omega_simulate": reference["omega"].tolist(),
            "P_loss": run["P_loss"].tolist()}))
    if not error <= args.tolerance:
        print(f"press: the coupling error {error:.3e} exceeds {args.tolerance:g}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
