"""Command line: ``linkage-fmu table PRESET`` prints one revolution as a table.

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
import sys

import numpy as np

from . import presets


def _parameter(text: str) -> tuple:
    name, sep, value = text.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got {text!r}")
    try:
        return name, float(value) if name not in ("driver",) else value
    except ValueError:
        raise argparse.ArgumentTypeError(f"{name}: {value!r} is not a number") from None


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = argparse.ArgumentParser(prog="linkage-fmu", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    table = sub.add_parser("table", help="outputs over one revolution (seed 000's table by default)")
    table.add_argument("preset", choices=presets.names())
    table.add_argument("--set", dest="params", metavar="NAME=VALUE", type=_parameter,
                       action="append", default=[], help="override a parameter (repeatable)")
    table.add_argument("--n", type=int, default=36, help="angles in linspace(0, 2*pi, n)")
    for name in ("omega", "alpha", "load"):
        table.add_argument(f"--{name}", type=float, default=None,
                           help=f"{name} (default: the preset's start value)")
    table.add_argument("--method", choices=("closed_form", "direct"), default="closed_form")
    table.add_argument("--outputs", nargs="+", default=None)
    table.add_argument("--csv", action="store_true", help="print CSV instead of a table")
    info = sub.add_parser("info", help="parameters, inputs and outputs of a preset")
    info.add_argument("preset", choices=presets.names())
    args = parser.parse_args(argv)

    spec = presets.preset(args.preset)
    if args.command == "info":
        print(f"{spec.name}: {spec.title}")
        for p in spec.parameters:
            print(f"  {p.name:8s} = {p.default!r:8} {p.unit:6s} {p.description}")
        mech = presets.get(spec.name)
        print("outputs:", ", ".join(mech.output_names + mech.diagnostic_names))
        return 0
    try:
        mech = presets.get(args.preset, **dict(args.params))
        inputs = {k: getattr(spec.inputs, k) if getattr(args, k) is None else getattr(args, k)
                  for k in ("omega", "alpha", "load")}
        df = mech.table(np.linspace(0.0, 2.0 * np.pi, args.n), method=args.method,
                        outputs=args.outputs, **inputs)
    except (TypeError, ValueError) as err:
        print(f"linkage-fmu: {err}", file=sys.stderr)
        return 2
    print(df.to_csv() if args.csv else df.to_string(float_format=lambda v: f"{v:.6f}"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
