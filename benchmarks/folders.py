"""Where a benchmark writes its results: ``build/benchmarks/`` by default (git ignores
``build/``), so that a run never rewrites the committed ``benchmarks/results/``; those
only with ``--results``, or any folder with ``--out``.

Every benchmark script that writes results takes these options (:func:`add_options`)
and asks :func:`folder` where to write.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

HERE = Path(__file__).resolve().parent
#: the committed results (README quotes them): written only with ``--results``
RESULTS = HERE / "results"
#: the committed figures of the documentation that a benchmark draws
DOCS = HERE.parent / "docs"
#: where a run writes by default
DEFAULT = HERE.parent / "build" / "benchmarks"


def add_options(parser: argparse.ArgumentParser) -> None:
    """``--out FOLDER`` and ``--results`` (either one) on ``parser``.

    Examples
    --------
    >>> parser = argparse.ArgumentParser()
    >>> add_options(parser)
    >>> folder(parser.parse_args([])) == DEFAULT
    True
    >>> folder(parser.parse_args(["--results"])) == RESULTS
    True
    >>> folder(parser.parse_args(["--out", "elsewhere"])).name
    'elsewhere'
    """
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--out", type=Path, default=None,
                       help=f"folder to write the results to (default: {DEFAULT})")
    where.add_argument("--results", action="store_true",
                       help=f"write the committed results, {RESULTS} (and the documentation's "
                            "figures a benchmark draws, in docs/)")


def folder(args: argparse.Namespace) -> Path:
    """Where the run of ``args`` (:func:`add_options`) writes: ``--out``, the committed
    results with ``--results``, else :data:`DEFAULT` (the caller creates it)."""
    return RESULTS if args.results else (args.out or DEFAULT)


def docs(args: argparse.Namespace) -> Path:
    """Where the documentation's figures go: ``docs/`` with ``--results``, else beside
    the results (:func:`folder`)."""
    return DOCS if args.results else folder(args)


def write_csv(path: Path, rows: list[dict]) -> None:
    """``rows`` (dicts with the same keys) as a CSV file with a header line."""
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
