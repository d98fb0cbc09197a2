"""One command line over the library: ``linkage-fmu info|table|sweep|plot|build|check``.

Every command takes a description file or a preset name; ``--set NAME=VALUE`` overrides
a parameter, and each load of the linkage is an option ``--NAME VALUE`` of ``table``.

Examples
--------
>>> main(["table", "scotch_yoke", "--n", "3", "--outputs", "Mb"])  # doctest: +NORMALIZE_WHITESPACE
              Mb
theta
0.000000  40.000000
3.141593 -40.000000
6.283185  40.000000
0
"""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from . import __version__, presets, ranges
from .solver import frame
from .spec import Description, DescriptionError

EPILOG = """examples:
  linkage-fmu info four_bar
  linkage-fmu table scotch_yoke --omega 10 --load 400
  linkage-fmu table my_linkage.toml --theta 0:360:15 --deg --F_P 80 --T4 120 --csv
  linkage-fmu table four_bar --theta 0:360:0.001 --deg -o revolution.parquet
  linkage-fmu sweep four_bar --grid l_AB=0.05:0.15:0.01 --grid l_BC=0.3,0.35 --omega 10 -o designs.csv
  linkage-fmu sweep four_bar --samples designs.csv --scheduler local
  linkage-fmu plot four_bar --what torque --omega 10 -o torque.png
  linkage-fmu plot four_bar --what polar F21 -o F21.svg
  linkage-fmu plot six_bar --what linkage --theta-deg 60 -o six_bar.png
  linkage-fmu plot four_bar --what mu --set l_AB=0.3 -o mu.png
  linkage-fmu build four_bar --set l_AB=0.12 --out dist
  linkage-fmu build --native my_linkage.toml --out dist/native
  linkage-fmu build --native --fmi 3 four_bar
  linkage-fmu check dist/FourBar.fmu
"""


class UsageError(Exception):
    """A command-line value that cannot be used; the message says which and why."""


def _parameter(text: str) -> tuple:
    name, sep, value = text.partition("=")
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    try:
        return name, int(value) if value.lstrip("+-").isdigit() else float(value)
    except ValueError:
        return name, value  # a choice parameter; the linkage checks it


def _linkage(parser: argparse.ArgumentParser, help: str, parameters: bool = True) -> None:
    """The linkage argument, and ``--set NAME=VALUE`` to override its parameters."""
    parser.add_argument("linkage", help=help)
    if parameters:
        parser.add_argument("--set", dest="params", metavar="NAME=VALUE", type=_parameter,
                            action="append", default=[],
                            help="override a parameter (repeatable)")


def _motion(parser: argparse.ArgumentParser) -> None:
    """``--omega`` and ``--alpha``; unset: the linkage's start values (:func:`speeds`)."""
    for name in ("omega", "alpha"):
        parser.add_argument(f"--{name}", type=float, default=None,
                            help=f"{name} (default: the linkage's start value)")


def speeds(d: Description, args) -> tuple[float, float]:
    """omega and alpha from the command line, or the linkage's start values."""
    return tuple(d.inputs[n] if getattr(args, n) is None else getattr(args, n)
                 for n in ("omega", "alpha"))


def loads(mech, args, rest: list[str], start: bool = True) -> dict:
    """The value of each load of ``mech`` from the options ``--NAME VALUE`` left in
    ``rest`` (each the load's start value if not given, or with ``start=False`` left
    out); an option that is not a load of the linkage is an error naming it."""
    parser = argparse.ArgumentParser(prog=f"linkage-fmu {args.command} {args.linkage}")
    for load in mech.loads:
        parser.add_argument(f"--{load.name}", type=float,
                            default=load.start if start else None,
                            help=f"{load.description} [{load.unit}] (default {load.start!r})")
    given = vars(parser.parse_args(rest))
    return {k: v for k, v in given.items() if v is not None}


def description(source: str) -> Description:
    """The description of a preset name or a description file."""
    if source in presets.NAMES:
        return presets.preset(source)
    return Description.read(source)


def angles(spec: str | None, n: int, degrees: bool) -> np.ndarray:
    """Crank angles [rad] from ``--theta``: a value, a comma list, or START:STOP:STEP
    (STOP included when a step lands on it); without ``--theta``, ``linspace(0, 2 pi, n)``.

    Examples
    --------
    >>> angles("0:90:45", 0, degrees=True).round(6).tolist()
    [0.0, 0.785398, 1.570796]
    >>> angles("0.1,0.2", 0, degrees=False).tolist()
    [0.1, 0.2]
    """
    if spec is None:
        if n < 1:
            raise UsageError(f"--n must be >= 1, got {n}")
        return np.linspace(0.0, 2.0 * np.pi, n)
    try:
        if ":" in spec:
            start, stop, step = (float(v) for v in spec.split(":"))
            if not step > 0 or not stop >= start:
                raise UsageError(f"--theta {spec}: need START <= STOP and STEP > 0")
            count = math.floor((stop - start) / step * (1 + 1e-12)) + 1
            values = start + step * np.arange(count)
        else:
            values = np.array([float(v) for v in spec.split(",")])
    except ValueError:
        raise UsageError(f"--theta {spec!r}: expected a number, a list a,b,c or "
                         "START:STOP:STEP") from None
    return np.radians(values) if degrees else values


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = argparse.ArgumentParser(
        prog="linkage-fmu", description="Kinetostatics of crank-driven planar linkages: "
        "joint reactions and driving torque, as tables and FMUs.", epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"linkage-fmu {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    linkage_help = "a description file (.toml) or a preset: " + ", ".join(presets.NAMES)

    info = sub.add_parser("info", help="parameters, inputs (and where each load acts), outputs")
    _linkage(info, linkage_help, parameters=False)

    table = sub.add_parser("table", help="outputs over crank angles", epilog=EPILOG,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(table, linkage_help)
    table.add_argument("--theta", help="angle(s): a value, a list a,b,c or START:STOP:STEP")
    table.add_argument("--deg", action="store_true", help="--theta and the index in degrees")
    table.add_argument("--n", type=int, default=36,
                       help="without --theta: angles linspace(0, 2*pi, N) (default 36)")
    _motion(table)
    table.add_argument("--method", choices=("closed_form", "direct"), default="closed_form")
    table.add_argument("--outputs", nargs="+", default=None)
    table.add_argument("--csv", action="store_true", help="print CSV instead of a table")
    table.add_argument("--strict", action="store_true",
                       help="exit with status 2 if an angle cannot be solved (default: its "
                            "row is NaN, with a warning)")
    table.add_argument("-o", "--output", help="write the table to FILE.csv or FILE.parquet")

    sweep = sub.add_parser("sweep", help="many designs over a revolution, summarised",
                           epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(sweep, linkage_help, parameters=False)
    sweep.add_argument("--grid", metavar="NAME=VALUES", action="append", default=[],
                       help="a parameter's values: a,b,c or START:STOP:STEP (repeatable; "
                            "the designs are every combination)")
    sweep.add_argument("--samples", help="designs from FILE.csv or FILE.parquet, one per row, "
                                         "one column per parameter")
    sweep.add_argument("--theta", help="angle(s): a list a,b,c or START:STOP:STEP")
    sweep.add_argument("--deg", action="store_true", help="--theta in degrees")
    sweep.add_argument("--n", type=int, default=360,
                       help="without --theta: N angles over a revolution (default 360)")
    _motion(sweep)
    sweep.add_argument("--scheduler", help="'local' for a local Dask cluster, or a Dask "
                                           "scheduler's address (tcp://host:8786); default: "
                                           "this process")
    sweep.add_argument("-o", "--output", help="write the table to FILE.csv or FILE.parquet")

    plot = sub.add_parser("plot", help="a picture: torque curve, force polar, the linkage "
                                       "with its forces, transmission angles",
                          epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(plot, linkage_help)
    plot.add_argument("--what", nargs="+", required=True, metavar="KIND [NAME]",
                      help="torque [OUTPUT] | polar [FORCE] | linkage | mu")
    plot.add_argument("--theta-deg", dest="theta_deg",
                      help="angle(s) in degrees: a value (linkage), a list or START:STOP:STEP "
                           "(default a revolution in 0.5 degree steps)")
    _motion(plot)
    plot.add_argument("-o", "--output", required=True, help="FILE.png, .svg or .pdf")

    build = sub.add_parser("build", help="build the linkage's FMU")
    _linkage(build, linkage_help)
    build.add_argument("--out", default=None,
                       help="output folder (default dist, dist/fmi3 with --fmi 3; dist/native "
                            "and dist/native3 with --native)")
    build.add_argument("--native", action="store_true",
                       help="a native FMU: the linkage's kernels in C, no Python in the "
                            "importing tool (default: the pythonfmu FMU)")
    build.add_argument("--fmi", type=int, choices=(2, 3), default=2,
                       help="FMI version (default 2)")

    check = sub.add_parser("check", help="run an FMU with fmpy against the direct solver")
    check.add_argument("fmu")
    check.add_argument("--steps", type=int, default=360)

    args, rest = parser.parse_known_args(argv)
    try:
        if args.command == "check":
            return _check(parser, args, rest)
        d = description(args.linkage)
        if args.command == "info":
            if rest:
                parser.error(f"unrecognized arguments: {' '.join(rest)}")
            return _info(d)
        if args.command == "sweep":
            return _sweep(d, args, rest)
        if args.command == "plot":
            return _plot(d, args, rest)
        if args.command == "build":
            if rest:
                parser.error(f"unrecognized arguments: {' '.join(rest)}")
            from .ccompiler import CompilerError
            from .fmi import build_fmu, build_native_fmu

            try:
                if args.native:
                    path = build_native_fmu(d, args.out, args.fmi, **dict(args.params))
                else:
                    out = args.out or ("dist" if args.fmi == 2 else "dist/fmi3")
                    path = build_fmu(d, out, args.fmi, **dict(args.params))
            except CompilerError as err:
                print(f"linkage-fmu: {err}", file=sys.stderr)
                return 2
            where = ranges.assembles(d.build(**dict(args.params)))
            if where != [(0.0, 360.0)]:
                print(f"linkage-fmu: {d.name} assembles over theta = {ranges.text(where)} "
                      "only; the FMU discards the steps at other angles", file=sys.stderr)
            print(path)
            return 0
        return _table(d, args, rest)
    except (DescriptionError, UsageError, TypeError, ValueError) as err:
        print(f"linkage-fmu: {err}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader went away (| head): end quietly
        sys.stderr.close()
        return 0


def _check(parser, args, rest) -> int:
    import json

    from fmpy.validation import validate_fmu

    from .fmi import check_fmu

    if rest:
        parser.error(f"unrecognized arguments: {' '.join(rest)}")
    result = check_fmu(args.fmu, args.steps)
    problems = validate_fmu(args.fmu)
    if result.unsolved_deg:
        print(f"linkage-fmu: {result.model} assembles over part of the revolution: the FMU "
              f"discarded the steps at theta = {ranges.text(result.unsolved_deg, digits=4)}, "
              "where the linkage cannot be solved; the others were checked", file=sys.stderr)
    if result.mismatched:
        print(f"linkage-fmu: at {result.mismatched} steps the FMU and the direct solver "
              "disagree on whether there is a solution", file=sys.stderr)
    print(json.dumps({**result.__dict__, "validate": problems}))
    return 0 if result.passed() and not problems else 1


def _info(d: Description) -> int:
    mech = d.build()
    print(f"{d.name}: {d.title}" + (f" (FMU model {d.model})" if d.model else ""))
    print("parameters:")
    for p in d.parameter_specs():
        print(f"  {p.name:8s} = {p.default!r:8} {p.unit:6s} {p.description}")
    print("inputs:")
    print("  theta    [rad]    crank angle from +x, counter-clockwise "
          f"(start {d.inputs['theta']!r})")
    print(f"  omega    [rad/s]  crank speed (start {d.inputs['omega']!r})")
    print(f"  alpha    [rad/s2] crank acceleration (start {d.inputs['alpha']!r})")
    for load in mech.loads:
        where = (f"moment on link {load.body}" if load.kind == "moment" else
                 f"force on link {load.body} at {load.at}, direction "
                 f"({load.direction[0]:.6g}, {load.direction[1]:.6g}) fixed in the "
                 f"{load.fixed_in}")
        print(f"  {load.name:8s} [{load.unit}] {where}: {load.description} "
              f"(start {load.start!r})")
    print("outputs:")
    for name in mech.output_names + mech.diagnostic_names:
        unit, text = mech.output_info[name]
        print(f"  {name:8s} [{unit}] {text}")
    return 0


def _table(d: Description, args, rest: list[str]) -> int:
    mech = d.build(**dict(args.params))
    theta = angles(args.theta, args.n, args.deg)
    omega, alpha = speeds(d, args)
    sol = mech.solve(theta, omega, alpha, method=args.method, outputs=args.outputs,
                     **loads(mech, args, rest))
    df = frame(sol, theta)
    if args.deg:
        df.index = np.degrees(df.index.to_numpy())
        df.index.name = "theta_deg"
    if sol.problems:
        bad = sol.status.reshape(-1) != 0
        first = min(sol.problems.values(), key=lambda p: p.first)
        where = ranges.text(ranges.runs(np.degrees(theta), bad), digits=6)
        message = (f"{mech.name} cannot be solved at {int(bad.sum())} of {theta.size} angles "
                   f"(theta = {where}): {first.message}")
        if args.strict:
            raise UsageError(message)
        print(f"linkage-fmu: {message}; their rows are NaN", file=sys.stderr)
    if args.output:
        write_table(df, args.output)
    elif args.csv:
        _in_pieces(df, lambda part, first: sys.stdout.write(part.to_csv(header=first)))
    else:
        _in_pieces(df, lambda part, first: sys.stdout.write(part.to_string(
            header=first, float_format=lambda v: f"{v:.6f}") + "\n"))
    return 0


#: rows per piece of a long output, and the length from which a terminal shows progress
PIECE, LONG = 50_000, 200_000


def _in_pieces(df, write) -> None:
    """``write(piece, first)`` for successive row ranges of ``df``, with a progress bar
    on a terminal when the table is long."""
    starts = range(0, max(len(df), 1), PIECE)
    if len(df) >= LONG and sys.stderr.isatty():
        from tqdm import tqdm

        starts = tqdm(starts, desc="rows", unit_scale=PIECE, unit="row")
    for i in starts:
        write(df.iloc[i:i + PIECE], i == 0)


def write_table(df, path: str) -> None:
    """Write ``df`` to ``path``: CSV or Parquet by its suffix (Parquet needs pyarrow)."""
    if path.endswith(".csv"):
        with open(path, "w", newline="") as f:
            _in_pieces(df, lambda part, first: part.to_csv(f, header=first))
    elif path.endswith(".parquet"):
        try:
            df.to_parquet(path)
        except ImportError:
            raise UsageError(f"-o {path}: writing Parquet needs pyarrow (pip install pyarrow); "
                             "or write .csv") from None
    else:
        raise UsageError(f"-o {path}: the file must end in .csv or .parquet")
    print(f"wrote {len(df)} rows to {path}", file=sys.stderr)


def _values(spec: str) -> tuple[str, list]:
    name, sep, text = spec.partition("=")
    if not sep or not name:
        raise UsageError(f"--grid {spec!r}: expected NAME=a,b,c or NAME=START:STOP:STEP")
    if ":" in text:
        return name, angles(text, 0, False).tolist()
    return name, [_parameter(f"{name}={v}")[1] for v in text.split(",")]


def _plot(d: Description, args, rest: list[str]) -> int:
    try:
        import matplotlib
    except ImportError:
        raise UsageError('plots need matplotlib: pip install "linkage_fmu[plot]"') from None
    matplotlib.use("Agg")
    from . import plot

    mech = d.build(**dict(args.params))
    given = loads(mech, args, rest, start=False)
    kind, names = args.what[0], args.what[1:]
    if kind not in ("torque", "polar", "linkage", "mu") or len(names) > 1 or (
            names and kind in ("linkage", "mu")):
        raise UsageError(f"--what {' '.join(args.what)}: expected torque [OUTPUT], polar "
                         "[FORCE], linkage or mu")
    theta_deg = None if args.theta_deg is None else angles(args.theta_deg, 0, False)
    motion = {"omega": args.omega, "alpha": args.alpha}
    if kind == "torque":
        fig = plot.torque(mech, theta_deg=theta_deg, output=names[0] if names else None,
                          **motion, **given)
    elif kind == "polar":
        fig = plot.polar(mech, names[0] if names else None, theta_deg=theta_deg, **motion,
                         **given)
    elif kind == "linkage":
        if theta_deg is None or theta_deg.size != 1:
            raise UsageError("--what linkage needs one angle: --theta-deg VALUE")
        fig = plot.linkage(mech, theta_deg=float(theta_deg[0]), **motion, **given)
    else:
        fig = plot.transmission(mech, theta_deg=theta_deg)
    if not args.output.endswith((".png", ".svg", ".pdf")):
        raise UsageError(f"-o {args.output}: the file must end in .png, .svg or .pdf")
    fig.savefig(args.output, dpi=120, bbox_inches="tight")
    print(f"wrote {args.output}", file=sys.stderr)
    return 0


def _sweep(d: Description, args, rest: list[str]) -> int:
    import pandas as pd

    from .sweep import grid, sweep

    mech = d.build()
    values = loads(mech, args, rest)
    if bool(args.grid) == bool(args.samples):
        raise UsageError("give the designs as --grid NAME=VALUES (repeatable) or --samples FILE")
    if args.samples:
        designs = (pd.read_parquet(args.samples) if args.samples.endswith(".parquet")
                   else pd.read_csv(args.samples))
    else:
        designs = grid(**dict(map(_values, args.grid)))
    theta = (np.linspace(0.0, 2.0 * np.pi, args.n, endpoint=False) if args.theta is None
             else angles(args.theta, 0, args.deg))
    omega, alpha = speeds(d, args)
    table = sweep(mech, designs, theta, omega, alpha, scheduler=args.scheduler,
                  progress=args.scheduler is None and sys.stderr.isatty(), **values)
    if args.output:
        write_table(table, args.output)
    else:
        print(table.to_csv(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
