"""The FMU variable table (linkage_fmu.fmi.variables) carries the library's own words:
every output's description, the friction outputs' sign conventions among them, and
every parameter's bounds (``min``, ``max``) as its validator has them, in both flavours,
both FMI versions and the drive FMU's modelDescription."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

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


def declared_bounds(xml: bytes) -> dict:
    """name -> (min, max) of every variable of a modelDescription (None: not declared)."""
    out = {}
    for element in ET.fromstring(xml).iter():
        name = element.get("name")
        if element.tag == "ScalarVariable":  # FMI 2.0: the type element holds them
            element = next(iter(element))
        if name is not None and element is not None:
            out[name] = tuple(None if element.get(k) is None else float(element.get(k))
                              for k in ("min", "max"))
    return out


def refuses(parameter, value) -> bool:
    try:
        parameter.validate(int(value) if parameter.kind == "branch" else value)
    except ValueError:
        return True
    return False


@pytest.mark.parametrize("fmi_version", [2, 3])
@pytest.mark.parametrize("flavour, drive", [("pythonfmu", False), ("native", False),
                                            ("native", True)],
                         ids=["pythonfmu", "native", "native-drive"])
@pytest.mark.parametrize("source", ["slider_crank", "coupler_four_bar"])
def test_the_bounds_declared_are_the_validators(source, flavour, drive, fmi_version):
    """Reference: the library's validator of each parameter
    (:meth:`~linkage_fmu.parameters.Parameter.validate`). Every real or integer parameter
    declares ``min`` where the validator has a lower bound (the smallest positive float64
    for ``> 0``, 0 for ``>= 0``, -1 for a sign or a branch, a description's ``min``) and
    ``max`` where it has an upper one (1 for a sign or a branch, a description's ``max``:
    the coupler four-bar's m2 <= 100): the validator takes the bound and refuses the next
    float64 outside it (the next integer for a branch); where none is declared it takes
    -1e300 or 1e300. The slider-crank has friction (mu >= 0, pin radii >= 0) and an offset
    e of either sign."""
    from linkage_fmu import load

    root = Path(__file__).resolve().parents[1]
    mech = (presets.preset(source).fmu_build() if source == "slider_crank" else
            load(root / "examples" / f"{source}.toml"))
    declared = declared_bounds(model_description(mech, flavour, fmi_version, "{guid}",
                                                 drive=drive))
    checked = 0
    for p in mech.description.parameter_specs():
        if p.kind == "choice":
            assert declared[p.name] == (None, None)
            continue
        low, high = declared[p.name]
        step = 1 if p.kind == "branch" else None
        for bound, outward, far in ((low, -math.inf, -1e300), (high, math.inf, 1e300)):
            if bound is None:
                assert not refuses(p, far), (p.name, far)
                continue
            outside = bound + math.copysign(1, outward) if step else math.nextafter(bound,
                                                                                     outward)
            assert not refuses(p, bound) and refuses(p, outside), (p.name, bound, outside)
            checked += 1
    assert checked >= 10
    if source == "coupler_four_bar":
        assert declared["m2"] == (0.0, 100.0)
    if drive:
        assert declared["tolerance"] == (1e-14, 0.1)
        assert declared["motion"] == (-1, 1)


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_every_unit_an_output_may_have_is_defined_in_the_model_description(fmi_version,
                                                                              tmp_path):
    """An output may be in each unit of :data:`linkage_fmu.units.PINT` (an energy in J, a
    pressure in Pa, an area in m2, a time in s): the four-bar with one such output of each
    writes a modelDescription that declares every unit a variable uses, and fmpy reads it
    (validating it) without a problem."""
    from fmpy import read_model_description

    from linkage_fmu import units

    d = presets.preset("four_bar").copy()
    extra = {"J": "E_x", "Pa": "p_x", "m2": "a_x", "s": "t_x"}
    for unit, name in extra.items():
        d.output("expression", name=name, expression="Fx_B", unit=unit,
                 description=f"a value in {unit}")
    mech = d._changed().build()
    xml = model_description(mech, "native", fmi_version, "{guid}")
    root = ET.fromstring(xml)
    declared = {u.get("name") for u in root.iter("Unit")}
    used = {v.get("unit") for v in root.iter() if v.get("unit")}
    assert set(extra) <= used <= declared and set(units.PINT) <= declared
    (tmp_path / "modelDescription.xml").write_bytes(xml)
    md = read_model_description(str(tmp_path / "modelDescription.xml"))
    assert {v.name: v.unit for v in md.modelVariables if v.name in extra.values()} == {
        name: unit for unit, name in extra.items()}
