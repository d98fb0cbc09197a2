"""The joints-and-links examples (examples/jansen.toml, klann.toml, triad_six_bar.toml) as
FMUs of both flavours, pythonfmu and native, each checked against the direct solver.

``linkage-fmu check`` is the test of each FMU: ``fmpy validate`` finds nothing, and a
revolution through fmpy with the speed and the loads varying equals the direct solver
(``Mechanism.solve`` on the description the FMU bundles) to 1e-9 relative for the
pythonfmu FMU and 1e-12 for the native one, at every one of 360 steps, none discarded.
The native FMU of the class III six-bar is also run by hand through fmpy's own FMI 2.0
calls, at crank angles around the turn, against the library reading the example file.
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

import fmu_cache
from linkage_fmu.cli import main
from linkage_fmu.descriptions import Description

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
#: the check's tolerance on each output, relative to its largest value over the turn,
#: as build_fmu.py's for each flavour
TOLERANCE = {"pythonfmu": 1e-9, "native": 1e-12}
BUILD = {"pythonfmu": fmu_cache.build_fmu, "native": fmu_cache.build_native_fmu}
NAMES = ("triad_six_bar", "jansen", "klann")


@pytest.mark.parametrize("flavour", BUILD)
@pytest.mark.parametrize("name", NAMES)
def test_the_example_fmu_passes_the_check(name, flavour, tmp_path, capsys):
    """``linkage-fmu check`` exits 0, and its report says why: no ``fmpy validate``
    problem, 360 steps, none discarded (each example assembles over the whole turn),
    none where the FMU and the direct solver disagree on whether there is a solution,
    and the largest error within the flavour's tolerance."""
    fmu = BUILD[flavour](str(EXAMPLES / f"{name}.toml"), tmp_path)
    assert main(["check", "--json", str(fmu)]) == 0
    result = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert result["validate"] == [] and result["steps"] == 360, result
    assert result["unsolved_deg"] == [] and result["mismatched"] == 0, result
    assert result["max_rel_error"] <= TOLERANCE[flavour], result


def test_the_native_triad_fmu_equals_the_library(tmp_path):
    """fmpy's FMU2Slave, one doStep per state (theta every 45 deg from the drawn 30 deg,
    omega 10 rad/s, alpha 5 rad/s^2, the plate's torque T -8 N.m), then the outputs: Mb,
    shake_x and shake_y within 1e-12 of the largest magnitude each reaches over these
    states, against ``Description.read(...).build().solve(...)`` of the same file. The
    angles go once round, so the FMU's continuation of the class III group from the
    drawn pose is exercised at up to 180 deg from it, both ways."""
    from fmpy import extract, instantiate_fmu, read_model_description

    source = EXAMPLES / "triad_six_bar.toml"
    fmu = fmu_cache.build_native_fmu(str(source), tmp_path)
    thetas = math.radians(30.0) + np.radians(np.arange(0.0, 360.0, 45.0))
    omega, alpha, torque = 10.0, 5.0, -8.0
    names = ("Mb", "shake_x", "shake_y")

    md = read_model_description(str(fmu))
    refs = {v.name: v.valueReference for v in md.modelVariables}
    unzipped = extract(str(fmu))
    slave = instantiate_fmu(unzipped, md, "CoSimulation")
    got = []
    try:
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        h = 0.01
        for k, theta in enumerate(thetas):
            slave.setReal([refs[n] for n in ("theta", "omega", "alpha", "T")],
                          [float(theta), omega, alpha, torque])
            slave.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
            got.append(slave.getReal([refs[n] for n in names]))
        slave.terminate()
    finally:
        slave.freeInstance()
        shutil.rmtree(unzipped, ignore_errors=True)
    got = np.array(got)

    mech = Description.read(source).build()
    want = np.array([[mech.solve(float(t), omega, alpha, T=torque)[n] for n in names]
                     for t in thetas])
    assert np.all(np.isfinite(want))
    scale = np.max(np.abs(want), axis=0)
    assert np.all(scale > 1.0), scale  # N.m and N: forces, not rounding
    error = np.max(np.abs(got - want), axis=0) / scale
    assert np.all(error <= 1e-12), dict(zip(names, error))
