"""One command line over the library: ``linkage-fmu info|table|equations|efforts|report|
sweep|optimize|plot|animate|simulate|flywheel|build|check|reference``.

Every command takes a description file or a preset name; ``--set NAME=VALUE`` overrides
a parameter, and each load of the linkage is an option ``--NAME VALUE`` of ``table``,
``equations``, ``efforts``, ``report``, ``sweep``, ``optimize``, ``plot``, ``animate``,
``simulate`` and ``flywheel`` (listed by
their ``--help`` once the linkage is named). Values may carry units and be expressions,
as in a description file: ``--set l_AB=120mm``, ``--set gamma=pi/2``,
``--omega "1800 rpm"``, ``--F_P "0.2 kN"``, ``--theta "0:360:15 deg"``; plain numbers are
SI, angles in radians.

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
import re
import sys
import warnings
from pathlib import Path

import numpy as np

from . import __version__, presets, ranges
from .descriptions import Description, DescriptionError
from .descriptions.assur import outline
from .descriptions.checker import driver_efforts
from .drivers import MEANINGS, one_crank
from .equations import FORMATS
from .errors import LinkageFmuError
from .expressions import evaluate
from .printing import number
from .solver import frame

EPILOG = """examples:
  linkage-fmu info four_bar
  linkage-fmu table scotch_yoke --omega 10 --load 400
  linkage-fmu table examples/coupler_four_bar.toml --theta 0:360:15 --deg \\
      --F_P 80 --T4 120 --csv
  linkage-fmu table four_bar --theta 0:360:0.001 --deg -o revolution.parquet
  linkage-fmu sweep four_bar --grid l_AB=0.05:0.15:0.01 --grid l_BC=0.3,0.35 \\
      --omega 10 -o designs.csv
  linkage-fmu sweep four_bar --samples examples/four_bar_designs.csv \\
      --scheduler local
  linkage-fmu optimize four_bar --vary l_BC=0.3:0.45 --vary l_CD=0.25:0.4 \\
      --minimize Mb_peak --subject-to "gamma_C_min_deg >= 45" \\
      --subject-to valid --seed 1 --plot convergence.png
  linkage-fmu plot four_bar --what torque --omega 10 -o torque.png
  linkage-fmu plot four_bar --what polar F21 -o F21.svg
  linkage-fmu plot six_bar --what linkage --theta-deg 60 -o six_bar.png
  linkage-fmu plot four_bar --what gamma --set l_AB=0.3 -o gamma.png
  linkage-fmu plot examples/engine.toml --what speed --Cs 0.02 -o speed.png
  linkage-fmu plot slider_crank --what loss --set mu_guide=0.1 --omega 10 \\
      --load 100 -o loss.png
  linkage-fmu animate four_bar -o four_bar.gif
  linkage-fmu animate four_bar --set l_AB=0.3 --what torque --frames 36 \\
      -o rocker.gif
  linkage-fmu animate slider_crank --what shaking --omega 200 --frames 36 \\
      -o engine.gif
  linkage-fmu simulate four_bar --tau 2 --t-end 1 --theta0 "30 deg" \\
      --omega0 5 --n 11
  linkage-fmu simulate slider_crank --set mu_guide=0.1 --tau 0.5 --t-end 1 \\
      --omega0 0 --load 20
  linkage-fmu flywheel examples/engine.toml --omega-mean "3000 rpm" --Cs 0.02
  linkage-fmu flywheel slider_crank --set mu_guide=0.1 --omega-mean 100 \\
      --Cs 0.02 --load 200
  linkage-fmu build four_bar --set l_AB=0.12 --out dist  # dist/FourBar.fmu
  linkage-fmu build --native examples/coupler_four_bar.toml --out dist/native
  linkage-fmu build --native --fmi 3 four_bar       # dist/native3/FourBar.fmu
  linkage-fmu build --native --fmi 3 --platforms all four_bar
  linkage-fmu build --native --platforms x86_64-linux,x86_64-windows four_bar
  linkage-fmu build --native --drive four_bar   # dist/native/FourBarDrive.fmu
  linkage-fmu check dist/FourBar.fmu
"""


class UsageError(LinkageFmuError):
    """A command-line value that cannot be used; the message says which and why."""


def _parameter(text: str) -> tuple:
    name, sep, value = text.partition("=")
    if not sep or not name:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    try:
        return name, int(value) if value.lstrip("+-").isdigit() else float(value)
    except ValueError:
        return name, value  # a number with a unit, an expression or a choice: checked later


def _linkage(parser: argparse.ArgumentParser, help: str, parameters: bool = True) -> None:
    """The linkage argument, and ``--set NAME=VALUE`` to override its parameters."""
    parser.add_argument("linkage", help=help)
    if parameters:
        parser.add_argument("--set", dest="params", metavar="NAME=VALUE", type=_parameter,
                            action="append", default=[],
                            help="override a parameter (repeatable); a value may have a "
                                 "unit or be an expression: l_AB=120mm, gamma=pi/2")


def _motion(parser: argparse.ArgumentParser) -> None:
    """``--omega`` and ``--alpha``; unset: the linkage's start values (:func:`speeds`)."""
    for name, unit, example in (("omega", "rad/s", "1800 rpm"),
                                ("alpha", "rad/s2", "100 rad/s^2")):
        parser.add_argument(f"--{name}", default=None, metavar="VALUE",
                            help=f"{name} [{unit}], or with a unit (\"{example}\"); default "
                                 "the linkage's start value")


def _revolution(parser: argparse.ArgumentParser) -> None:
    """The crank angles of each design (``--theta``, ``--deg``, ``--n``; :func:`angles`),
    and :func:`_motion`."""
    parser.add_argument("--theta", help="angle(s): a list a,b,c or START:STOP:STEP")
    parser.add_argument("--deg", action="store_true", help="--theta in degrees")
    parser.add_argument("--n", type=int, default=360,
                        help="without --theta: N angles over a revolution (default 360)")
    _motion(parser)


def speeds(args) -> tuple:
    """omega and alpha from the command line in SI (None where not given: the
    linkage's start value)."""
    return tuple(None if getattr(args, n) is None else
                 evaluate(getattr(args, n), unit, f"--{n}")
                 for n, unit in (("omega", "rad/s"), ("alpha", "rad/s2")))


#: the commands that take the loads of the linkage as options
LOAD_COMMANDS = ("table", "equations", "sweep", "optimize", "plot", "animate", "simulate",
                 "flywheel", "report", "efforts")


def _load_options(parser: argparse.ArgumentParser, d: Description) -> None:
    """Each load of the linkage ``d`` as an option ``--NAME VALUE`` of ``parser``, so
    that its ``--help`` lists them."""
    group = parser.add_argument_group(
        f"loads of {d.name} (default: the start value; a number in SI or with a unit)")
    for spec in d.loads:
        unit = spec.get("unit") or ("N" if spec.get("kind") == "force" else "N.m")
        text = spec.get("description") or f"{spec.get('kind')} on link {spec.get('body')}"
        if "value" in spec or "table" in spec:
            how = (f"= {spec['value']}" if "value" in spec else
                   f"from a table over {spec.get('period_deg', 360.0):g} deg")
            default = f"over the cycle, {how}; a value here replaces it"
        else:
            default = f"start {spec.get('start', 0.0)}"
        try:
            group.add_argument(f"--{spec['name']}", dest=f"load:{spec['name']}", default=None,
                               metavar="VALUE", help=f"{text} [{unit}] ({default})")
        except argparse.ArgumentError:
            raise UsageError(f"the load {spec['name']} of {d.name} has the name of an option of "
                             f"this command; rename the load to use it here") from None


def loads(args) -> dict:
    """The loads given as options (name -> value as typed; the linkage converts units)."""
    return {k.partition(":")[2]: v for k, v in vars(args).items()
            if k.startswith("load:") and v is not None}


def _named_linkage(argv: list[str]) -> tuple[str | None, Description | None]:
    """The command, and the description of the linkage it names if it takes loads and
    the linkage can be read (else None: the error comes with the command)."""
    for i, word in enumerate(argv):
        if word in LOAD_COMMANDS:
            for candidate in argv[i + 1:]:
                if candidate.startswith("-"):
                    continue
                try:
                    return word, description(candidate)
                except (DescriptionError, UsageError, ValueError, OSError):
                    continue
            return word, None
        if not word.startswith("-"):
            return word, None
    return None, None


def description(source: str) -> Description:
    """The description of a preset name or a description file."""
    if source in presets.NAMES:
        return presets.preset(source)
    if not source.endswith(".toml") and not Path(source).exists():
        raise UsageError(f"{source}: no such file, and not a preset; the presets are "
                         + ", ".join(presets.NAMES))
    return Description.read(source)


def typed(spec: str, where: str = "--theta") -> tuple[np.ndarray, str]:
    """The numbers of an angle option as typed: a value, a comma list, or
    START:STOP:STEP (STOP included when a step lands on it), and the unit written after
    them ('' if none); errors name the option ``where``.

    Examples
    --------
    >>> typed("0:90:45 deg")
    (array([ 0., 45., 90.]), 'deg')
    >>> typed("0.1,0.2")
    (array([0.1, 0.2]), '')
    """
    text, unit = spec.strip(), ""
    found = re.fullmatch(r"(.*?[\d.])\s*(?![eE][+-]?\d)([A-Za-z°][\w°]*)", text)  # 1e2: a number
    if found:
        text, unit = found.groups()
    try:
        if ":" in text:
            start, stop, step = (float(v) for v in text.split(":"))
            if not step > 0 or not stop >= start:
                raise UsageError(f"{where} {spec!r}: need START <= STOP and STEP > 0")
            count = math.floor((stop - start) / step * (1 + 1e-12)) + 1
            return start + step * np.arange(count), unit
        return np.array([float(v) for v in text.split(",")]), unit
    except ValueError:
        raise UsageError(f"{where} {spec!r}: expected a number, a list a,b,c or "
                         "START:STOP:STEP, optionally with a unit") from None


def revolution(n: int) -> np.ndarray:
    """``--n`` angles over a revolution [rad], 2 pi left out (it is 0).

    Examples
    --------
    >>> revolution(4).round(6).tolist()
    [0.0, 1.570796, 3.141593, 4.712389]
    """
    if n < 1:
        raise UsageError(f"--n must be >= 1, got {n}")
    return np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)


def angles(spec: str | None, n: int, degrees: bool) -> np.ndarray:
    """Crank angles [rad] from ``--theta``: a value, a comma list, or START:STOP:STEP,
    in radians, or in degrees with ``degrees`` or a unit (``"0:360:15 deg"``); without
    ``--theta``, ``linspace(0, 2 pi, n)``. Plain values beyond 2 pi warn once (60 is 60
    rad).

    Examples
    --------
    >>> angles("0:90:45", 0, degrees=True).round(6).tolist()
    [0.0, 0.785398, 1.570796]
    >>> angles("0.1,0.2", 0, degrees=False).tolist()
    [0.1, 0.2]
    >>> angles("90 deg", 0, degrees=False).round(6).tolist()
    [1.570796]
    """
    if spec is None:
        if n < 1:
            raise UsageError(f"--n must be >= 1, got {n}")
        return np.linspace(0.0, 2.0 * np.pi, n)
    values, unit = typed(spec)
    if unit:
        if degrees:
            raise UsageError(f"--theta {spec!r} has a unit: leave out --deg")
        return values * evaluate(f"1 {unit}", "rad", "--theta")
    if degrees:
        return np.radians(values)
    if np.any(np.abs(values) > 2.0 * math.pi):
        big = values[np.argmax(np.abs(values))]
        print(f"linkage-fmu: --theta {spec} is in radians ({big:g} rad = "
              f"{math.degrees(big):.6g} deg); add --deg, or a unit ({big:g}deg), for "
              "degrees", file=sys.stderr)
    return values


def _index(spec: str | None, theta: np.ndarray, degrees: bool) -> tuple[np.ndarray, str]:
    """The index of a table: the angles as typed in degrees (``--deg`` or a degree
    unit: no rounding through radians), else in radians."""
    if spec is not None:
        values, unit = typed(spec)
        if degrees or (unit and evaluate(f"1 {unit}", "rad", "--theta") == math.pi / 180):
            return values, "theta_deg"
    return theta, "theta"


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status. Warnings are printed as lines of
    the command (``linkage-fmu: warning: ...``), not with the library's source line."""
    with warnings.catch_warnings():
        warnings.showwarning = _warning
        return _main(argv)


def _warning(message, category, filename, lineno, file=None, line=None) -> None:
    print(f"linkage-fmu: warning: {message}", file=file or sys.stderr)


class Parser(argparse.ArgumentParser):
    """An argument parser that keeps what it is given, so that the command-line
    reference can be written from it (:mod:`linkage_fmu.manual.cli_reference`):
    ``arguments``, every argument's action in the order added; ``commands``, each
    command's parser by name, and on each, ``summary``, the help its command was added
    with."""

    def __init__(self, *args, **kwargs):
        self.arguments: list[argparse.Action] = []
        self.commands: dict[str, Parser] = {}
        self.summary: str | None = None
        super().__init__(*args, **kwargs)

    def add_argument(self, *args, **kwargs) -> argparse.Action:
        action = super().add_argument(*args, **kwargs)
        self.arguments.append(action)
        return action

    def add_subparsers(self, **kwargs):
        action = super().add_subparsers(**kwargs)
        add = action.add_parser

        def add_parser(name: str, **options) -> Parser:
            parser = add(name, **options)
            parser.summary = options.get("help")
            self.commands[name] = parser
            return parser

        action.add_parser = add_parser
        return action


def build_parser() -> Parser:
    """The command line's parser, every command a subparser of it (the loads of a named
    linkage are added to its command's by :func:`_main`);
    :mod:`linkage_fmu.manual.cli_reference` writes the command-line reference from it.

    Examples
    --------
    >>> sorted(subcommands(build_parser()))[:3]
    ['animate', 'build', 'check']
    """
    parser = Parser(
        prog="linkage-fmu", description="Kinetostatics of crank-driven planar linkages: "
        "joint reactions and driving torque, as tables and FMUs.", epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"linkage-fmu {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    linkage_help = "a description file (.toml) or a preset: " + ", ".join(presets.NAMES)

    info = sub.add_parser("info", help="its groups (the decomposition), parameters, inputs (and "
                          "where each load acts), outputs")
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
    table.add_argument("--inputs", metavar="FILE.csv",
                       help="a linkage driven by time (several drivers, a motor, a "
                            "cylinder): its inputs row by row, a column per input (one not "
                            "given takes its start value), a time column as the index")

    eqs = sub.add_parser("equations", help="the equilibrium equations A x = b at one state, "
                         "each row and column labelled, and their solution", epilog=EPILOG,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(eqs, linkage_help)
    eqs.add_argument("--theta", required=True,
                     help="the crank angle: a value (rad; with --deg or a unit, deg)")
    eqs.add_argument("--deg", action="store_true", help="--theta in degrees")
    _motion(eqs)
    eqs.add_argument("--format", choices=FORMATS, default="text",
                     help="text or markdown (the a(i, j) and b(i) table, each link's free "
                          "body and equations, the solution), latex, mathml, or a function "
                          "file of the inputs returning A \\ b: matlab (Octave, MATLAB) or "
                          "python (numpy)")
    eqs.add_argument("-o", "--output", help="write it to FILE (default: print it); a "
                                            "matlab function file is NAME.m, NAME the "
                                            "linkage's")

    efforts = sub.add_parser("efforts", help="where to put the balancing effort: each place "
                             "(a moment on a link, a force along a slider's guide) with its "
                             "peak effort, bearing reactions and power over the angles, and "
                             "the place with the lowest peak reaction", epilog=EPILOG,
                             formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(efforts, linkage_help)
    _revolution(efforts)
    efforts.add_argument("--csv", action="store_true", help="print CSV instead of a table")
    efforts.add_argument("-o", "--output", help="write the table to FILE.csv or FILE.parquet")

    report = sub.add_parser("report", help="a web page of its kinetostatics: parameters, "
                            "picture, groups, the equations at chosen angles (MathML), the "
                            "table over the cycle, curves and extremes, where to put the effort",
                            epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(report, linkage_help)
    report.add_argument("-o", "--output", required=True, metavar="DIR",
                        help="write DIR/index.html and its PNG pictures (DIR is made)")
    report.add_argument("--positions", default="60,150,220",
                        help="the crank angles of the equations, in degrees: a,b,c or "
                             "START:STOP:STEP (default 60,150,220)")
    _motion(report)
    report.add_argument("--variants", metavar="FILE.csv",
                        help="one report per row (a column per parameter, an optional first "
                             "column 'variant' naming it) in DIR/<variant>/, and DIR/index.html "
                             "comparing them")

    sweep = sub.add_parser("sweep", help="many designs over a revolution, summarised",
                           epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(sweep, linkage_help, parameters=False)
    sweep.add_argument("--grid", metavar="NAME=VALUES", action="append", default=[],
                       help="a parameter's values: a,b,c or START:STOP:STEP (repeatable; "
                            "the designs are every combination)")
    sweep.add_argument("--samples", help="designs from FILE.csv or FILE.parquet, one per row, "
                                         "one column per parameter")
    _revolution(sweep)
    sweep.add_argument("--scheduler", help="'local' for a local Dask cluster, or a Dask "
                                           "scheduler's address (tcp://host:8786); default: "
                                           "this process")
    sweep.add_argument("-o", "--output", help="write the table to FILE.csv or FILE.parquet")

    opt = sub.add_parser("optimize", help="the design within bounds that minimises a sweep's "
                                          "summary subject to constraints on the summaries",
                         epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(opt, linkage_help)
    opt.add_argument("--vary", metavar="NAME=LO:HI", action="append", default=[],
                     help="a parameter varied between bounds (repeatable; SI, or with a "
                          "unit: l_AB=50mm:150mm)")
    opt.add_argument("--minimize", required=True, metavar="SUMMARY",
                     help="the summary minimised (Mb_peak, F21_peak, ...; -NAME maximises it)")
    opt.add_argument("--subject-to", dest="subject_to", metavar="CONSTRAINT", action="append",
                     default=[], help="a constraint (repeatable): 'NAME OP VALUE' with OP "
                                      "one of <=, >=, <, > ('gamma_C_min_deg >= 40'), or 'valid' "
                                      "(the design assembles at every angle, "
                                      "friction locking it at none)")
    _revolution(opt)
    opt.add_argument("--method", choices=("de", "grid"), default="de",
                     help="differential evolution (de, default) or a grid of --budget designs, "
                          "each followed by a Nelder-Mead polish")
    opt.add_argument("--budget", type=int, default=None,
                     help="designs evaluated by the search at most (default: popsize x "
                          "parameters x (maxiter + 1))")
    opt.add_argument("--maxiter", type=int, default=100,
                     help="generations of differential evolution at most (default 100)")
    opt.add_argument("--popsize", type=int, default=15,
                     help="population per parameter (default 15)")
    opt.add_argument("--tol", type=float, default=0.0,
                     help="differential evolution's relative tolerance of convergence "
                          "(default 0: every generation; 0.01 may stop in a local optimum)")
    opt.add_argument("--seed", type=int, default=None, help="the random seed: the same "
                                                            "result every run")
    opt.add_argument("--no-polish", dest="polish", action="store_false",
                     help="no Nelder-Mead polish after the search")
    opt.add_argument("--plot", metavar="FILE", help="draw the convergence to FILE.png, .svg "
                                                    "or .pdf")
    opt.add_argument("--csv", metavar="FILE", help="write the convergence history to FILE.csv")
    opt.add_argument("--progress", action="store_true", help="a progress bar over the "
                                                             "generations")
    opt.add_argument("--scheduler", help="'local' for a local Dask cluster, or a Dask "
                                         "scheduler's address (tcp://host:8786); default: "
                                         "this process")

    plot = sub.add_parser("plot", help="a picture: torque curve, force polar, the linkage "
                                       "with its forces, transmission angles, shaking force, "
                                       "speed over a cycle, friction losses",
                          usage="linkage-fmu plot LINKAGE --what KIND [NAME] -o FILE [options]",
                          epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(plot, linkage_help)
    plot.add_argument("--what", nargs="+", required=True, metavar=("KIND", "NAME"),
                      help="what to draw, one of: torque [OUTPUT] | polar [FORCE] | linkage | "
                           "gamma | shaking | speed | loss")
    plot.add_argument("--theta-deg", dest="theta_deg",
                      help="angle(s) in degrees: a value (linkage), a list or START:STOP:STEP "
                           "(default a revolution in 0.5 degree steps)")
    _motion(plot)
    plot.add_argument("--Cs", default=None, metavar="VALUE",
                      help="with --what speed: size a flywheel for this coefficient of "
                           "fluctuation of speed (--omega is the mean speed)")
    plot.add_argument("--flywheel", default=None, metavar="VALUE",
                      help="with --what speed: a flywheel of this inertia [kg.m2] (default "
                           "none)")
    plot.add_argument("-o", "--output", required=True, help="FILE.png, .svg or .pdf")

    anim = sub.add_parser("animate", help="the linkage moving over a revolution (or the "
                                          "range it assembles over) with its forces, beside "
                                          "a curve with a cursor: a GIF or an MP4",
                          usage="linkage-fmu animate LINKAGE -o FILE.gif|FILE.mp4 [options]",
                          epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(anim, linkage_help)
    anim.add_argument("-o", "--output", required=True,
                      help="FILE.gif (written with pillow) or FILE.mp4 (needs ffmpeg)")
    anim.add_argument("--what", default="forces", metavar="KIND",
                      help="the curve beside the linkage: forces (each joint force's "
                           "magnitude, the default), torque (the balancing effort) or shaking "
                           "(the shaking force)")
    anim.add_argument("--frames", type=int, default=72,
                      help="frames over the motion (default 72: 5 degrees apart over a "
                           "revolution; even where the crank cannot turn and swings out "
                           "and back)")
    _motion(anim)
    anim.add_argument("--fps", type=float, default=12.0, help="frames a second (default 12)")
    anim.add_argument("--dpi", type=float, default=80.0,
                      help="pixels an inch of the 11 x 4.8 inch figure (default 80)")

    simulate = sub.add_parser("simulate", help="the motion under a constant torque on the "
                                               "crank, over time", epilog=EPILOG,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(simulate, linkage_help)
    simulate.add_argument("--tau", required=True, metavar="VALUE",
                          help="the torque on the crank [N.m], counter-clockwise positive")
    simulate.add_argument("--t-end", dest="t_end", required=True, metavar="VALUE",
                          help="the end time [s] (or with a unit: \"500 ms\"); the motion "
                               "starts at 0")
    simulate.add_argument("--n", type=int, default=101,
                          help="output times linspace(0, T_END, N) (default 101)")
    for name, unit, example in (("theta0", "rad", "30 deg"), ("omega0", "rad/s", "100 rpm")):
        simulate.add_argument(f"--{name}", default=None, metavar="VALUE",
                              help=f"{name[:-1]} at time 0 [{unit}], or with a unit "
                                   f"(\"{example}\"); default the linkage's start value")
    simulate.add_argument("--flywheel", default=None, metavar="VALUE",
                          help="a flywheel on the crank [kg.m2] (default none)")
    simulate.add_argument("--outputs", nargs="+", default=None,
                          help="the columns to show (default all: theta, omega, alpha, tau, "
                               "every output, J_red; with friction also stuck)")
    simulate.add_argument("--csv", action="store_true", help="print CSV instead of a table")
    simulate.add_argument("-o", "--output", help="write the motion to FILE.csv or "
                                                 "FILE.parquet")

    fly = sub.add_parser("flywheel", help="size a flywheel for a coefficient of fluctuation of "
                                          "speed, and check it by the equation of motion",
                         epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    _linkage(fly, linkage_help)
    fly.add_argument("--omega-mean", dest="omega_mean", default=None, metavar="VALUE",
                     help="the mean speed [rad/s], or with a unit (\"3000 rpm\"); default "
                          "the linkage's start speed")
    fly.add_argument("--Cs", required=True, metavar="VALUE",
                     help="the coefficient of fluctuation of speed, (omega_max - omega_min) "
                          "/ omega_mean, e.g. 0.02")
    fly.add_argument("--revolutions", type=int, default=None,
                     help="revolutions in a cycle (default 1, or what a load's table needs)")
    fly.add_argument("-o", "--output", help="write the motion with the flywheel over a cycle "
                                            "to FILE.csv or FILE.parquet")

    build = sub.add_parser("build", help="build the linkage's FMU")
    _linkage(build, linkage_help)
    build.add_argument("--out", default=None,
                       help="output folder (default dist, dist/fmi3 with --fmi 3; dist/native "
                            "and dist/native3 with --native)")
    build.add_argument("--native", action="store_true",
                       help="a native FMU: the linkage's kernels in C, no Python in the "
                            "importing tool (default: the pythonfmu FMU)")
    build.add_argument("--drive", action="store_true",
                       help="with --native: the drive FMU <Model>Drive, the linkage driven by a "
                            "moment tau on its crank (co-simulation and model exchange)")
    build.add_argument("--fmi", type=int, choices=(2, 3), default=2,
                       help="FMI version (default 2)")
    build.add_argument("--platforms", default=None, metavar="all|LIST",
                       help="with --native: the binaries' platforms, 'all' or a comma-separated "
                            "list of x86_64-linux, aarch64-linux (FMI 3 only), x86_64-windows, "
                            "x86_64-darwin, aarch64-darwin (default: this machine's); built "
                            "with zig: pip install \"linkage-fmu[cross]\"")

    check = sub.add_parser("check", help="run an FMU with fmpy against the direct solver "
                                         "(a drive FMU: its motion against simulate, its "
                                         "outputs against the direct solver at its states), "
                                         "and say whether it passes and against what "
                                         "tolerance (exit status 1 if not)")
    check.add_argument("fmu", help="an FMU built by linkage-fmu build")
    check.add_argument("--steps", type=int, default=360,
                       help="steps per revolution of the run (default 360)")
    check.add_argument("--json", action="store_true",
                       help="print the outcome as one JSON object (its figures, the "
                            "tolerance, fmpy's validation and passed) instead of a line")

    reference = sub.add_parser("reference", help="the reference of the description file "
                                                 "format, made from the code (Markdown)")
    reference.add_argument("-o", "--output", help="write it to FILE (default: print it)")
    return parser


def subcommands(parser: Parser) -> dict[str, Parser]:
    """The parser of each command of ``parser``, by name, in the order they were added."""
    return dict(parser.commands)


def _main(argv: list[str] | None) -> int:
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        command, named = _named_linkage(argv)
        if named is not None:  # its loads are options of the command, in its --help
            _load_options(subcommands(parser)[command], named)
        args = parser.parse_args(argv)
        _writable(args)
        if args.command == "check":
            return _check(args)
        if args.command == "reference":
            return _reference(args)
        d = description(args.linkage)
        if args.command == "info":
            return _info(d)
        if args.command not in ("build", "table") and driver_efforts(d.groups):
            one_crank(d.build(), f"linkage-fmu {args.command}")  # driven by time
        if args.command == "equations":
            return _equations(d, args)
        if args.command == "efforts":
            return _efforts(d, args)
        if args.command == "sweep":
            return _sweep(d, args)
        if args.command == "report":
            return _report(d, args)
        if args.command == "optimize":
            return _optimize(d, args)
        if args.command == "plot":
            return _plot(d, args)
        if args.command == "animate":
            return _animate(d, args)
        if args.command == "simulate":
            return _simulate(d, args)
        if args.command == "flywheel":
            return _flywheel(d, args)
        if args.command == "build":
            from .ccompiler import CompilerError
            from .fmi import build_fmu, build_native_fmu

            if args.platforms is not None and not args.native:
                raise UsageError("--platforms is for native FMUs (--native): the pythonfmu "
                                 "FMU is for linux64 only")
            if args.drive and not args.native:
                raise UsageError("--drive is for native FMUs: add --native")
            try:
                if args.native:
                    path = build_native_fmu(d, args.out, args.fmi, args.platforms,
                                            drive=args.drive, **dict(args.params))
                else:
                    out = args.out or ("dist" if args.fmi == 2 else "dist/fmi3")
                    path = build_fmu(d, out, args.fmi, **dict(args.params))
            except CompilerError as err:
                print(f"linkage-fmu: {err}", file=sys.stderr)
                return 2
            built = d.build(**dict(args.params))
            where = [(0.0, 360.0)] if built.rates else ranges.assembles(built)
            if where != [(0.0, 360.0)]:
                print(f"linkage-fmu: {d.name} assembles over theta = {ranges.text(where)} "
                      "only; the FMU discards the steps at other angles", file=sys.stderr)
            print(path)
            return 0
        return _table(d, args)
    except (DescriptionError, UsageError, TypeError, ValueError) as err:
        print(f"linkage-fmu: {err}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader went away (| head): end quietly
        sys.stderr.close()
        return 0
    except OSError as err:  # a file that cannot be read or written
        where = f"{err.filename}: " if err.filename else ""
        print(f"linkage-fmu: {where}{err.strerror or err}", file=sys.stderr)
        return 2
    except ImportError as err:  # an optional dependency (dask, pyarrow): its message says how
        print(f"linkage-fmu: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("linkage-fmu: interrupted", file=sys.stderr)
        return 130


def _writable(args) -> None:
    """A UsageError, before any work, if a file the command writes is in no folder (a
    long sweep's table would be lost at the end)."""
    for attr, option in (("output", "-o"), ("csv", "--csv"), ("plot", "--plot")):
        path = getattr(args, attr, None)
        if isinstance(path, str) and not Path(path).resolve().parent.is_dir():
            raise UsageError(f"{option} {path}: there is no folder "
                             f"{Path(path).parent}")


def _check(args) -> int:
    import json

    from fmpy.validation import validate_fmu

    from .fmi import check_fmu

    if args.steps < 1:
        raise UsageError(f"--steps must be >= 1, got {args.steps}")
    if not Path(args.fmu).is_file():
        raise UsageError(f"{args.fmu}: no such file" if not Path(args.fmu).exists() else
                         f"{args.fmu}: a folder, not an FMU file")
    from fmpy.fmi1 import FMICallException

    try:
        result = check_fmu(args.fmu, args.steps)
    except (FMICallException, RuntimeError) as err:  # the FMU failed a call, or the run
        print(f"linkage-fmu: {args.fmu}: the check failed: {err}", file=sys.stderr)
        return 1
    problems = validate_fmu(args.fmu)
    if result.motion_error is not None:  # a drive FMU
        if result.unsolved_deg:
            print(f"linkage-fmu: the motion of {result.model} reached theta = "
                  f"{result.unsolved_deg[0][0]:.6g} deg, next to where the linkage cannot be "
                  "assembled: the FMU discarded the step there, "
                  + ("as simulate stops in it" if not result.mismatched else
                     "but simulate goes on") + "; the steps before it were checked",
                  file=sys.stderr)
    elif result.unsolved_deg:
        print(f"linkage-fmu: {result.model} assembles over part of the revolution: the FMU "
              f"discarded the steps at theta = {ranges.text(result.unsolved_deg, digits=4)}, "
              "where the linkage cannot be solved; the others were checked", file=sys.stderr)
    passed = result.passed() and not problems
    if args.json:
        print(json.dumps({**result.__dict__, "validate": problems, "passed": passed}))
    else:
        verdict = result.verdict()
        if problems and result.passed():
            verdict = "FAILED" + verdict.removeprefix("ok")
        print(f"{args.fmu}: {verdict}; fmpy validate: {'; '.join(problems) or 'no problems'}")
    return 0 if passed else 1


def _reference(args) -> int:
    from .manual.reference import markdown

    text = markdown()
    if args.output:
        with open(args.output, "w", encoding="utf-8") as f:
            f.write(text)
        print(f"wrote {args.output}", file=sys.stderr)
    else:
        sys.stdout.write(text)
    return 0


def _drivers(mech) -> None:
    """Print the drivers of a linkage driven by time: each one's inputs and effort."""
    for driver, effort in zip(mech.drivers, mech.efforts):
        print(f"  driver {driver.name} ({driver.kind}), effort {effort.name} "
              f"[{mech.output_info[effort.name][0]}]:")
        for k, (name, unit) in enumerate(zip(driver.inputs, driver.units)):
            word = MEANINGS[driver.kind][k]
            print(f"    {name:9s} [{unit}] {word} (start {mech.start[name]!r})")


def _info(d: Description) -> int:
    mech = d.build()
    print(f"{d.name}: {d.title}" + (f" (FMU model {d.model})" if d.model else ""))
    print("groups, in the order they are solved (" + ("decomposed from its joints and "
          "links" if d.drawn is not None else "as written") + "):")
    for k, (cls, kind, links, joints) in enumerate(outline(d.groups), 1):
        if kind == "point":
            print(f"  {k:2d}. point       {joints[0]} on link {links[0]}")
        else:
            name = f"II ({kind})" if cls == "II" else cls
            print(f"  {k:2d}. {name:11s} link{'s' if len(links) > 1 else ''} "
                  f"{', '.join(links)}; joints {', '.join(joints)}")
    print("parameters:")
    for p in d.parameter_specs():
        print(f"  {p.name:8s} = {mech.parameters[p.name]!r:8} {p.unit:6s} {p.description}")
    print("inputs (angles in rad):")
    start = mech.start
    if mech.rates:
        _drivers(mech)
    else:
        print(f"  theta    [rad]    crank angle from +x, counter-clockwise (start "
              f"{start['theta']!r})")
        print(f"  omega    [rad/s]  crank speed (start {start['omega']!r})")
        print(f"  alpha    [rad/s2] crank acceleration (start {start['alpha']!r})")
    for load in mech.loads:
        where = (f"moment on link {load.body}" if load.kind == "moment" else
                 f"force on link {load.body} at {load.at}, direction "
                 f"({number(load.direction[0], 6)}, {number(load.direction[1], 6)}) fixed in the "
                 f"{load.fixed_in}")
        value = (f"start {load.start!r}" if not load.computed else
                 f"over the cycle: {load.value.source}" if load.value is not None else
                 f"over the cycle: a table of {len(load.table.values)} points over "
                 f"{load.table.period_deg:g} deg, times {load.scale!r}")
        print(f"  {load.name:8s} [{load.unit}] {where}: {load.description} ({value})")
    print("outputs:")
    for name in mech.output_names + mech.diagnostic_names:
        unit, text = mech.output_info[name]
        print(f"  {name:8s} [{unit}] {text}")
    return 0


def _table(d: Description, args) -> int:
    mech = d.build(**dict(args.params))
    if mech.rates or args.inputs is not None:
        return _driven_table(mech, args)
    theta = angles(args.theta, args.n, args.deg)
    omega, alpha = speeds(args)
    sol = mech.solve(theta, omega, alpha, method=args.method, outputs=args.outputs,
                     **loads(args))
    df = frame(sol, theta)
    index, name = _index(args.theta, theta, args.deg)
    if name != "theta":
        df.index = index
        df.index.name = name
    if sol.problems:
        bad = sol.status.reshape(-1) != 0
        first = min(sol.problems.values(), key=lambda p: p.first)
        where = ranges.text(ranges.runs(np.degrees(theta), bad), digits=6)
        message = (f"{mech.name} cannot be solved at {int(bad.sum())} of {theta.size} angles "
                   f"(theta = {where}): {first.message}")
        if args.strict:
            raise UsageError(message)
        print(f"linkage-fmu: {message}; their rows are NaN", file=sys.stderr)
    return _emit(df, args)


def _report(d: Description, args) -> int:
    """``linkage-fmu report``: the web page of the linkage, or one per variant."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise UsageError('a report draws with matplotlib: pip install "linkage_fmu[plot]"') \
            from None
    from .report import write_report, write_variants

    positions, unit = typed(args.positions, "--positions")
    if unit not in ("", "deg", "°"):
        raise UsageError(f"--positions {args.positions!r}: degrees, without another unit")
    mech = d.build(**dict(args.params))
    omega, alpha = speeds(args)
    if args.variants:
        path = write_variants(mech, args.variants, args.output, positions.tolist(), omega,
                              alpha, **loads(args))
    else:
        path = write_report(mech, args.output, positions.tolist(), omega, alpha, **loads(args))
    print(f"wrote {path}", file=sys.stderr)
    return 0


def _equations(d: Description, args) -> int:
    """``linkage-fmu equations``: the labelled system at one crank angle, written out."""
    from .equations import equations

    theta = angles(args.theta, 1, args.deg)
    if theta.size != 1:
        raise UsageError(f"--theta {args.theta}: the equations are of one state; give one "
                         "angle")
    omega, alpha = speeds(args)
    text = equations(d.build(**dict(args.params)), float(theta[0]), omega, alpha,
                     **loads(args)).to(args.format)
    if args.output:
        Path(args.output).write_text(text, encoding="utf-8")
    else:
        sys.stdout.write(text)
    return 0


def _efforts(d: Description, args) -> int:
    """``linkage-fmu efforts``: the places of the balancing effort over the angles (a
    revolution without --theta), and the recommended one."""
    from .effort_places import effort_places, recommend

    theta = revolution(args.n) if args.theta is None else angles(args.theta, 1, args.deg)
    omega, alpha = speeds(args)
    table = effort_places(d.build(**dict(args.params)), theta, omega, alpha, **loads(args))
    _emit(table, args)
    print(f"recommended: {recommend(table)[1]}")
    return 0


def _driven_table(mech, args) -> int:
    """The table of a linkage driven by time over the rows of ``--inputs``."""
    import pandas as pd

    names = ", ".join(mech.input_names)
    if not mech.rates:
        raise UsageError(f"--inputs is for a linkage driven by time; {mech.name} is driven by "
                         "one crank: give --theta (and --omega, --alpha)")
    drivers = ", ".join(d.inputs[0] for d in mech.drivers)
    if args.inputs is None:
        raise UsageError(f"{mech.name} is driven by time ({drivers}): give its inputs row by "
                         f"row, --inputs FILE.csv with a column per input ({names})")
    given = [f"--{n}" for n in ("theta", "omega", "alpha") if getattr(args, n) is not None]
    if given:
        raise UsageError(f"{', '.join(given)}: {mech.name} is driven by time ({drivers}); "
                         f"its inputs come from --inputs ({names})")
    rows = pd.read_csv(args.inputs)
    unknown = [c for c in rows.columns if c != "time" and c not in mech.input_names]
    if unknown:
        raise UsageError(f"{args.inputs}: {', '.join(map(str, unknown))}: no input of "
                         f"{mech.name}; its inputs are {names} (and a time column)")
    columns = {d.inputs[0]: float(mech.start[d.inputs[0]]) for d in mech.drivers}
    columns.update((c, rows[c].to_numpy(dtype=float)) for c in rows.columns if c != "time")
    sol = mech.solve(**columns, **loads(args), method=args.method, outputs=args.outputs)
    df = pd.DataFrame({k: np.broadcast_to(np.asarray(v, float), (len(rows),))
                       for k, v in sol.items()})
    df.index = pd.Index(rows["time"], name="time") if "time" in rows else \
        pd.Index(range(len(rows)), name="row")
    if sol.problems:
        bad = np.flatnonzero(sol.status.reshape(-1) != 0)
        first = min(sol.problems.values(), key=lambda p: p.first)
        message = (f"{mech.name} cannot be solved at {bad.size} of {len(rows)} rows (first "
                   f"row {int(bad[0])}): {first.message}")
        if args.strict:
            raise UsageError(message)
        print(f"linkage-fmu: {message}; their rows are NaN", file=sys.stderr)
    return _emit(df, args)


def _emit(df, args) -> int:
    """Write the table ``df`` to ``--output``, or print it (``--csv``: as CSV) in pieces."""
    if args.output:
        write_table(df, args.output)
    elif args.csv:
        _in_pieces(df, lambda part, first: sys.stdout.write(part.to_csv(header=first)))
    else:
        _in_pieces(df, lambda part, first: sys.stdout.write(part.to_string(
            header=first, float_format=lambda v: number(v, 6, fixed=True)) + "\n"))
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


def write_table(df, path: str, index: bool = True) -> None:
    """Write ``df`` to ``path``: CSV or Parquet by its suffix (Parquet needs pyarrow),
    with its index as the first column or not."""
    if path.endswith(".csv"):
        with open(path, "w", newline="") as f:
            _in_pieces(df, lambda part, first: part.to_csv(f, header=first, index=index))
    elif path.endswith(".parquet"):
        try:
            df.to_parquet(path, index=index)
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
        values, unit = typed(text, f"--grid {name}")
        if unit:
            raise UsageError(f"--grid {spec!r}: START:STOP:STEP in SI, without a unit")
        return name, values.tolist()
    return name, [_parameter(f"{name}={v}")[1] for v in text.split(",")]


def _plot(d: Description, args) -> int:
    try:
        import matplotlib
    except ImportError:
        raise UsageError('plots need matplotlib: pip install "linkage_fmu[plot]"') from None
    matplotlib.use("Agg")
    from . import plot

    mech = d.build(**dict(args.params))
    given = loads(args)
    kind, names = args.what[0], args.what[1:]
    kinds = ("torque", "polar", "linkage", "gamma", "shaking", "speed", "loss")
    if kind not in kinds or len(names) > 1 or (names and kind not in ("torque", "polar")):
        raise UsageError(f"--what {' '.join(args.what)}: expected torque [OUTPUT], polar "
                         "[FORCE], linkage, gamma, shaking, speed or loss")
    if kind != "speed" and (args.Cs is not None or args.flywheel is not None):
        raise UsageError("--Cs and --flywheel are for --what speed")
    if kind == "speed" and (args.theta_deg is not None or args.alpha is not None):
        raise UsageError("--what speed draws a cycle of the steady motion at the mean speed "
                         "--omega: no --theta-deg or --alpha")
    theta_deg = None
    if args.theta_deg is not None:
        theta_deg, unit = typed(args.theta_deg, "--theta-deg")
        if unit:
            raise UsageError(f"--theta-deg {args.theta_deg!r}: degrees, without a unit")
    omega, alpha = speeds(args)
    motion = {"omega": omega, "alpha": alpha}
    if kind == "torque":
        fig = plot.torque(mech, theta_deg=theta_deg, output=names[0] if names else None,
                          **motion, **given)
    elif kind == "polar":
        fig = plot.polar(mech, names[0] if names else None, theta_deg=theta_deg, **motion,
                         **given)
    elif kind == "shaking":
        fig = plot.shaking(mech, theta_deg=theta_deg, **motion, **given)
    elif kind == "loss":
        try:
            fig = plot.loss(mech, theta_deg=theta_deg, **motion, **given)
        except ValueError as err:
            raise UsageError(f"--what loss: {err}") from None
    elif kind == "speed":
        if args.Cs is not None and args.flywheel is not None:
            raise UsageError("give --Cs (to size a flywheel) or --flywheel, not both")
        fig = plot.speed(mech, omega, Cs=args.Cs, flywheel=args.flywheel, **given)
    elif kind == "linkage":
        if theta_deg is None or theta_deg.size != 1:
            raise UsageError("--what linkage needs one angle: --theta-deg VALUE")
        fig = plot.linkage(mech, theta_deg=float(theta_deg[0]), **motion, **given)
    else:
        fig = plot.transmission(mech, theta_deg=theta_deg)
    if not args.output.endswith((".png", ".svg", ".pdf")):
        raise UsageError(f"-o {args.output}: the file must end in .png, .svg or .pdf")
    fig.savefig(args.output, dpi=120, bbox_inches="tight")
    _close(fig)
    print(f"wrote {args.output}", file=sys.stderr)
    return 0


def _close(fig) -> None:
    """Let pyplot forget a figure once written: a command run in a long process (a
    notebook, a test session) keeps no figure it made."""
    import matplotlib.pyplot as plt

    plt.close(fig)


def _animate(d: Description, args) -> int:
    """Check what can be checked before the linkage is solved, then animate it."""
    suffixes = (".gif", ".mp4")
    if not args.output.lower().endswith(suffixes):
        raise UsageError(f"-o {args.output}: the file must end in .gif or .mp4")
    kinds = ("forces", "torque", "shaking")
    if args.what not in kinds:
        raise UsageError(f"--what {args.what}: expected one of {', '.join(kinds)}")
    if args.frames < 2:
        raise UsageError(f"--frames must be >= 2, got {args.frames}")
    for option in ("fps", "dpi"):
        value = getattr(args, option)
        if not (math.isfinite(value) and value > 0):
            raise UsageError(f"--{option} must be a number > 0, got {value:g}")
    try:
        import matplotlib
    except ImportError:
        raise UsageError('animations need matplotlib: pip install "linkage_fmu[plot]"') from None
    matplotlib.use("Agg")
    from .plot.animation import MissingFFmpegError, animate, frame_pixels

    try:
        frame_pixels(args.dpi)
    except ValueError as err:  # said before the work
        raise UsageError(f"--{err}") from None

    mech = d.build(**dict(args.params))
    omega, alpha = speeds(args)
    try:
        anim = animate(mech, args.output, what=args.what, frames=args.frames, omega=omega,
                       alpha=alpha, fps=args.fps, dpi=args.dpi, **loads(args))
    except MissingFFmpegError as err:  # said before the work: the message says how to get it
        raise UsageError(f"-o {err}") from None
    _close(anim.figure)
    print(f"wrote {args.output} ({len(anim)} frames)", file=sys.stderr)
    return 0


def _simulate(d: Description, args) -> int:
    mech = d.build(**dict(args.params))
    t_end = evaluate(args.t_end, "s", "--t-end")
    if not t_end > 0:
        raise UsageError(f"--t-end must be > 0, got {args.t_end}")
    if args.n < 2:
        raise UsageError(f"--n must be >= 2, got {args.n}")
    start = {name: None if getattr(args, name) is None else
             evaluate(getattr(args, name), unit, f"--{name}")
             for name, unit in (("theta0", "rad"), ("omega0", "rad/s"))}
    flywheel = 0.0 if args.flywheel is None else evaluate(args.flywheel, "kg.m2", "--flywheel")
    try:
        run = mech.simulate(evaluate(args.tau, "N.m", "--tau"), np.linspace(0.0, t_end, args.n),
                            flywheel=flywheel, **start, **loads(args))
    except RuntimeError as err:  # the integrator failed, or the motion chatters
        raise UsageError(str(err)) from None
    for s in run.attrs.get("switches", ()):  # with friction: where it sticks or moves off
        what = "sticks" if s.to == 0 else f"moves off {'forwards' if s.to > 0 else 'backwards'}"
        print(f"linkage-fmu: at t = {s.time:.9g} s the crank at theta = {s.theta:.9g} rad "
              f"{what}", file=sys.stderr)
    if args.outputs:
        unknown = [c for c in args.outputs if c not in run.columns]
        if unknown:
            raise UsageError(f"--outputs {' '.join(unknown)}: not a column of the motion; "
                             "they are: " + ", ".join(run.columns))
        run = run[list(args.outputs)]
    return _emit(run, args)


def _flywheel(d: Description, args) -> int:
    mech = d.build(**dict(args.params))
    omega = None if args.omega_mean is None else evaluate(args.omega_mean, "rad/s",
                                                          "--omega-mean")
    try:
        sizing = mech.flywheel(omega, evaluate(args.Cs, "1", "--Cs"),
                               revolutions=args.revolutions, **loads(args))
    except RuntimeError as err:  # no periodic motion found (with friction)
        raise UsageError(str(err)) from None
    print(sizing)
    if args.output:
        write_table(sizing.motion, args.output)
    return 0


def _sweep(d: Description, args) -> int:
    from .sweep import grid, sweep

    mech = d.build()
    if bool(args.grid) == bool(args.samples):
        raise UsageError("give the designs as --grid NAME=VALUES (repeatable) or --samples FILE")
    if args.samples:
        designs = samples(args.samples)
    else:
        designs = grid(**dict(map(_values, args.grid)))
    theta = (revolution(args.n) if args.theta is None else angles(args.theta, 0, args.deg))
    omega, alpha = speeds(args)
    names = [p.name for p in mech.description.parameter_specs()]
    for name in designs.columns:
        if name not in names:  # said here, naming the file that has it
            raise UsageError(f"{f'--samples {args.samples}: ' if args.samples else ''}"
                             f"{mech.name} has no parameter {name!r}; its parameters are: "
                             + ", ".join(names))
    table = sweep(mech, designs, theta, omega, alpha, scheduler=args.scheduler,
                  progress=args.scheduler is None and sys.stderr.isatty(), **loads(args))
    if args.output:
        write_table(table, args.output, index=False)  # a design's row is its parameters
    else:
        print(table.to_csv(index=False))
    return 0


def samples(path: str):
    """The designs of ``--samples``: a CSV file (a header line of parameter names, then
    one design per line) or a Parquet file (one column per parameter)."""
    import pandas as pd

    if not Path(path).is_file():
        raise UsageError(f"--samples {path}: no such file")
    try:
        table = pd.read_parquet(path) if path.endswith(".parquet") else pd.read_csv(path)
    except ImportError:
        raise UsageError(f"--samples {path}: reading Parquet needs pyarrow (pip install "
                         "pyarrow); or write .csv") from None
    except (ValueError, pd.errors.ParserError, pd.errors.EmptyDataError) as err:
        what = "CSV" if not path.endswith(".parquet") else "Parquet"
        reason = " ".join(str(err).split())
        raise UsageError(f"--samples {path}: not a {what} table of designs ({reason}); "
                         "write a header line of parameter names, then one design per "
                         "line") from None
    if table.empty:
        raise UsageError(f"--samples {path}: no designs (columns {', '.join(table.columns)} "
                         "and no row)")
    return table


def _bounds(spec: str) -> tuple[str, tuple]:
    """``NAME=LO:HI`` of ``--vary``: the name and the two bounds as typed (numbers, or
    text with a unit, checked by the linkage)."""
    name, sep, text = spec.partition("=")
    parts = text.split(":")
    if not sep or not name or len(parts) != 2 or not all(p.strip() for p in parts):
        raise UsageError(f"--vary {spec!r}: expected NAME=LO:HI, as in l_AB=0.05:0.15")
    return name, tuple(_parameter(f"{name}={p.strip()}")[1] for p in parts)


def _optimize(d: Description, args) -> int:
    from .optimize import NoFeasibleDesignError, optimize

    if not args.vary:
        raise UsageError("give the parameters varied as --vary NAME=LO:HI (repeatable)")
    vary = dict(map(_bounds, args.vary))
    if len(vary) != len(args.vary):
        raise UsageError("--vary: a parameter is given twice")
    if args.plot and not args.plot.endswith((".png", ".svg", ".pdf")):
        raise UsageError(f"--plot {args.plot}: the file must end in .png, .svg or .pdf")
    if args.csv and not args.csv.endswith(".csv"):
        raise UsageError(f"--csv {args.csv}: the file must end in .csv")
    mech = d.build(**dict(args.params))
    theta = (revolution(args.n) if args.theta is None else angles(args.theta, 0, args.deg))
    omega, alpha = speeds(args)
    status = 0
    try:
        result = optimize(mech, vary, args.minimize, args.subject_to, theta=theta,
                          omega=omega, alpha=alpha,
                          method="grid" if args.method == "grid" else "differential_evolution",
                          budget=args.budget, maxiter=args.maxiter, popsize=args.popsize,
                          tol=args.tol, seed=args.seed, polish=args.polish,
                          scheduler=args.scheduler, progress=args.progress, **loads(args))
    except NoFeasibleDesignError as err:
        print(f"linkage-fmu: {err}", file=sys.stderr)
        result, status = err.result, 1
    print(result)
    if args.csv:
        result.history.to_csv(args.csv, index=False)
        print(f"wrote {len(result.history)} rows to {args.csv}", file=sys.stderr)
    if args.plot:
        try:
            import matplotlib
        except ImportError:
            raise UsageError('plots need matplotlib: pip install "linkage_fmu[plot]"') from None
        matplotlib.use("Agg")
        fig = result.plot()
        fig.savefig(args.plot, dpi=120, bbox_inches="tight")
        _close(fig)
        print(f"wrote {args.plot}", file=sys.stderr)
    return status


if __name__ == "__main__":
    sys.exit(main())
