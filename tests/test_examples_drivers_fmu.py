"""The examples driven by several actuators (examples/five_bar.toml, dump_body.toml,
excavator.toml) as FMUs of both flavours and FMI versions.

``linkage-fmu check`` is the test of each FMU: ``fmpy validate`` finds nothing, and the
drivers moving about their start over 1 s with the loads varying equal the direct
solver (``Mechanism.solve`` on the description the FMU bundles) to 1e-9 of the largest
output of each unit for the pythonfmu FMU and 1e-12 for the native one, at every one
of 360 steps, none discarded. The native FMU of the excavator is also stepped by hand
through fmpy, its cylinders' forces against the library reading the example file.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

import fmu_cache
import linkage_fmu
from linkage_fmu.cli import main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TOLERANCE = {"pythonfmu": 1e-9, "native": 1e-12}
BUILD = {"pythonfmu": fmu_cache.build_fmu, "native": fmu_cache.build_native_fmu}


@pytest.mark.parametrize("fmi_version", [2, 3])
@pytest.mark.parametrize("flavour", BUILD)
@pytest.mark.parametrize("name", ["five_bar", "dump_body", "excavator"])
def test_the_example_fmu_passes_the_check(name, flavour, fmi_version, tmp_path, capsys):
    fmu = BUILD[flavour](str(EXAMPLES / f"{name}.toml"), tmp_path, fmi_version)
    assert main(["check", "--json", str(fmu)]) == 0
    result = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert result["validate"] == [] and result["steps"] == 360, result
    assert result["unsolved_deg"] == [] and result["mismatched"] == 0, result
    assert result["max_rel_error"] <= TOLERANCE[flavour], result


def test_the_native_excavator_fmu_gives_the_library_s_cylinder_forces(tmp_path):
    """fmpy's FMU2Slave, one doStep per state (8 states of the three travels, speeds
    and accelerations, the load F_T 12 kN), then each cylinder's force and the boom
    foot's force: within 1e-12 of the largest each reaches, against the library."""
    from fmpy import extract, instantiate_fmu, read_model_description

    source = EXAMPLES / "excavator.toml"
    fmu = fmu_cache.build_native_fmu(str(source), tmp_path)
    mech = linkage_fmu.load(source)
    rng = np.random.default_rng(3)
    states = [dict(zip(mech.input_names, [*[x for _ in range(3) for x in
                                             (rng.uniform(-0.15, 0.3), rng.uniform(-0.2, 0.2),
                                              rng.uniform(-0.5, 0.5))], 12000.0]))
              for _ in range(8)]
    names = ("Fb_cyl1", "Fb_cyl2", "Fb_cyl3", "F0_boomx", "F0_boomy")
    md = read_model_description(str(fmu))
    refs = {v.name: v.valueReference for v in md.modelVariables}
    unzipped = extract(str(fmu))
    slave = instantiate_fmu(unzipped, md, "CoSimulation")
    got = []
    try:
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        for k, state in enumerate(states):
            slave.setReal([refs[n] for n in state], list(state.values()))
            slave.doStep(currentCommunicationPoint=k * 0.01, communicationStepSize=0.01)
            got.append(slave.getReal([refs[n] for n in names]))
        slave.terminate()
    finally:
        slave.freeInstance()
        shutil.rmtree(unzipped, ignore_errors=True)
    want = np.array([[mech.solve(**state)[n] for n in names] for state in states])
    scale = np.max(np.abs(want), axis=0)
    assert np.all(scale > 1000.0), scale  # forces of a 20 t machine, not rounding
    error = np.max(np.abs(np.array(got) - want), axis=0) / scale
    assert np.all(error <= 1e-12), dict(zip(names, error))


def test_the_dump_body_fmu_with_friction_passes_the_check(tmp_path, capsys):
    """Friction in every pair, the cylinder's guide included (a parameter ``mu``, 0.1):
    the native FMU equals the direct solver with friction to 1e-12."""
    text = (EXAMPLES / "dump_body.toml").read_text().replace(
        "[parameters]\n", '[parameters]\nmu = { default = 0.1, kind = "friction", '
        'description = "friction in every pair" }\n')
    text += "".join(f'\n[friction.{j}]\nmu = "mu"\nradius = 0.03\n' for j in "ODE")
    text += '\n[friction.P]\nmu = "mu"\n'
    source = tmp_path / "dump_body.toml"
    source.write_text(text)
    fmu = fmu_cache.build_native_fmu(str(source), tmp_path)
    assert main(["check", "--json", str(fmu)]) == 0
    result = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert result["steps"] == 360 and result["mismatched"] == 0, result
    assert result["max_rel_error"] <= TOLERANCE["native"], result
    assert linkage_fmu.load(source).friction.active
