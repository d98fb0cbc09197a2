"""The FMU variable table (linkage_fmu.fmi.variables) carries the library's own words:
every output's description, the friction outputs' sign conventions among them, in
both flavours, both FMI versions and the drive FMU's modelDescription."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest

from linkage_fmu import presets
from linkage_fmu.fmi.variables import drive_variables, variables
from linkage_fmu.fmi.writers import model_description

FRICTION = ("Mf_A", "Ff_guide", "P_loss", "eta")


@pytest.mark.parametrize("fmi_version", [2, 3])
@pytest.mark.parametrize("flavour, drive", [("pythonfmu", False), ("native", False),
                                            ("native", True)],
                         ids=["pythonfmu", "native", "native-drive"])
def test_the_friction_outputs_descriptions_reach_every_model_description(flavour, drive,
                                                                         fmi_version):
    """Reference: Mechanism.output_info, the descriptions the library gives its outputs
    (which name the pair's two links and the positive sense). Exact text, read back from
    the XML written for the FMU (the drive FMU is native only)."""
    mech = presets.preset("slider_crank").fmu_build()
    info = mech.output_info
    assert info["Mf_A"][1].startswith("friction moment in the pin A of link 1 on link 2, "
                                      "counter-clockwise positive")
    assert info["Ff_guide"][1].startswith("friction force in the prismatic pair guide of "
                                          "link 4 on link 3, positive along")
    assert info["eta"][1].startswith("instantaneous efficiency 1 - P_loss / P_in")
    table = drive_variables(mech) if drive else variables(mech, flavour)
    assert {v.name: v.description for v in table if v.name in FRICTION} == {
        n: info[n][1] for n in FRICTION}
    root = ET.fromstring(model_description(mech, flavour, fmi_version, "{guid}", drive=drive))
    written = {v.get("name"): v.get("description") for v in root.iter()
               if v.get("name") in FRICTION and v.get("causality") == "output"}
    assert written == {n: info[n][1] for n in FRICTION}
