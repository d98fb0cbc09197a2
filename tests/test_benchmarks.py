"""The benchmark scripts write where they are told: ``build/benchmarks/`` by default,
the committed ``benchmarks/results/`` only with ``--results``."""

from __future__ import annotations

import argparse
import csv
import importlib
import importlib.util
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
#: the scripts that write results, each taking folders.add_options
WRITERS = ("run", "drive_timing", "optimize_timing", "press_coupling", "six_bar_build",
           "sweep_timing")


@pytest.fixture
def folders(monkeypatch):
    monkeypatch.syspath_prepend(str(BENCHMARKS))
    return importlib.import_module("folders")


def _committed(folders) -> dict:
    """Name -> (bytes, modification time) of every committed result."""
    return {p.name: (p.read_bytes(), p.stat().st_mtime_ns)
            for p in sorted(folders.RESULTS.iterdir()) if p.is_file()}


def test_a_benchmark_run_writes_to_build_and_leaves_the_committed_results(folders, monkeypatch,
                                                                           tmp_path):
    """run.py --scalar on 4 angles and 1 round, with no folder named: scalar.csv (both
    presets, the source documents' way and the two call forms: 6 rows) appears in the default folder
    (here moved under tmp_path), and every file of benchmarks/results keeps its bytes and
    its modification time."""
    monkeypatch.setattr(folders, "DEFAULT", tmp_path / "build" / "benchmarks")
    # by its path: another test's module named run (the press example's) may be imported
    spec = importlib.util.spec_from_file_location("benchmarks_run", BENCHMARKS / "run.py")
    run = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(run)
    before = _committed(folders)
    assert run.main(["--scalar", "--states", "4", "--rounds", "1"]) == 0
    with open(tmp_path / "build" / "benchmarks" / "scalar.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [(r["preset"], r["method"]) for r in rows] == [
        (p, m) for p in run.PRESETS for m in run.SCALAR_KINDS]
    assert all(float(r["us_per_angle"]) > 0 and float(r["max_rel_error"]) < 1e-12
               for r in rows)
    assert _committed(folders) == before


def test_the_committed_results_are_written_only_when_asked(folders):
    """No option: build/benchmarks of the project; --results: benchmarks/results;
    --out: that folder; --out and --results together: refused."""
    parser = argparse.ArgumentParser()
    folders.add_options(parser)
    assert folders.folder(parser.parse_args([])) == BENCHMARKS.parent / "build" / "benchmarks"
    assert folders.folder(parser.parse_args(["--results"])) == BENCHMARKS / "results"
    assert folders.folder(parser.parse_args(["--out", "x"])) == Path("x")
    assert folders.docs(parser.parse_args(["--results"])) == BENCHMARKS.parent / "docs"
    assert folders.docs(parser.parse_args([])) == folders.DEFAULT
    with pytest.raises(SystemExit):
        parser.parse_args(["--out", "x", "--results"])


@pytest.mark.parametrize("script", WRITERS)
def test_every_script_that_writes_results_takes_the_folder_options(script, folders):
    """Each writer's source asks folders where to write and names no results folder of
    its own (read from the source: running them takes minutes)."""
    source = (BENCHMARKS / f"{script}.py").read_text()
    assert "folders.add_options(parser)" in source
    assert '"results"' not in source and "RESULTS" not in source
