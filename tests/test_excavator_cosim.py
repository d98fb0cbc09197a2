"""examples/excavator_cosim/run.py: the excavator's native FMU in libcosim over a
digging cycle given as tables, every output against ``Mechanism.solve`` to 1e-12 of the
largest output of its unit (the script's own exit status), and the figures it prints."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("libcosimpy")

SCRIPT = Path(__file__).resolve().parents[1] / "examples" / "excavator_cosim" / "run.py"


def test_the_cycle_in_libcosim_equals_the_library(tmp_path):
    run = subprocess.run([sys.executable, str(SCRIPT), "--out", str(tmp_path), "--step",
                          "0.02"], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    lines = run.stdout.splitlines()
    assert lines[0].startswith("Excavator.fmu in libcosim, 301 steps of 0.02 s: every "
                               "output within "), lines
    error = float(lines[0].split("within ")[1].split()[0])
    assert error <= 1e-12
    # the boom's cylinder pushes throughout, the stick's and the bucket's pull
    assert "  cyl1: Fb_cyl1 from 120.9 to 257.4 kN: 167 bar on the bore side to push" in lines
    assert any(line.startswith("  cyl2: Fb_cyl2 from -") and "to pull" in line
               for line in lines)
