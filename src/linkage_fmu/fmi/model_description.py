"""Complete pythonfmu's modelDescription.xml so that importing tools can trust it.

pythonfmu 0.7 writes no units, an empty ``InitialUnknowns`` and default capability
flags. :func:`complete` adds UnitDefinitions (``rad`` with display unit ``deg``, ...),
the capability flags, and a ModelStructure listing every output with the inputs it
depends on. It works on the ``xml.etree`` element at build time (``Fmi2Slave.to_xml``).
"""

from __future__ import annotations

from xml.etree.ElementTree import Element, SubElement

from pythonfmu import Real

RAD2DEG = 57.29577951308232
#: unit -> (SI base-unit exponents, display units as (name, factor))
UNITS = {
    "rad": ({"rad": 1}, [("deg", RAD2DEG)]),
    "rad/s": ({"rad": 1, "s": -1}, [("deg/s", RAD2DEG)]),
    "rad/s2": ({"rad": 1, "s": -2}, [("deg/s2", RAD2DEG)]),
    "m": ({"m": 1}, []),
    "m/s2": ({"m": 1, "s": -2}, []),
    "kg": ({"kg": 1}, []),
    "kg/m": ({"kg": 1, "m": -1}, []),
    "kg.m2": ({"kg": 1, "m": 2}, []),
    "N": ({"kg": 1, "m": 1, "s": -2}, []),
    "N.m": ({"kg": 1, "m": 2, "s": -2}, []),
    "1": ({}, []),
}
CAPABILITIES = {
    "canHandleVariableCommunicationStepSize": "true",
    "canGetAndSetFMUstate": "true",
    "canSerializeFMUstate": "true",
    "canInterpolateInputs": "false",
    "canBeInstantiatedOnlyOncePerProcess": "false",
    # pythonfmu FMUs run in the importing process's Python, which must have numpy
    "needsExecutionTool": "true",
}


class RealWithUnit(Real):
    """A pythonfmu ``Real`` variable that also writes ``unit`` and ``displayUnit``."""

    def __init__(self, name: str, unit: str = "", display_unit: str = "", **kwargs):
        super().__init__(name, **kwargs)
        self.unit, self.display_unit = unit, display_unit

    def to_xml(self) -> Element:
        node = super().to_xml()
        real = node.find("Real")
        if self.unit:
            real.set("unit", self.unit)
        if self.display_unit:
            real.set("displayUnit", self.display_unit)
        return node


def complete(root: Element, dependencies: dict) -> Element:
    """Add units, capabilities and the model structure to a modelDescription element.

    Parameters
    ----------
    root : Element
        ``<fmiModelDescription>`` as produced by ``Fmi2Slave.to_xml``.
    dependencies : dict
        Output name -> names of the inputs it depends on.

    Returns
    -------
    Element
        ``root``, changed in place.
    """
    variables = root.find("ModelVariables").findall("ScalarVariable")
    index = {v.get("name"): i + 1 for i, v in enumerate(variables)}
    cosim = root.find("CoSimulation")
    for key, value in CAPABILITIES.items():
        cosim.set(key, value)
    old = root.find("UnitDefinitions")
    if old is not None:
        root.remove(old)
    units = Element("UnitDefinitions")
    for name, (base, displays) in UNITS.items():
        unit = SubElement(units, "Unit", name=name)
        SubElement(unit, "BaseUnit", {k: str(v) for k, v in base.items()})
        for display, factor in displays:
            SubElement(unit, "DisplayUnit", name=display, factor=repr(factor))
    root.insert(list(root).index(cosim) + 1, units)  # schema order: right after CoSimulation

    structure = root.find("ModelStructure")
    for child in list(structure):
        structure.remove(child)
    outputs = [v.get("name") for v in variables if v.get("causality") == "output"]
    for tag in ("Outputs", "InitialUnknowns"):
        parent = SubElement(structure, tag)
        for name in outputs:
            deps = sorted(index[d] for d in dependencies[name])
            SubElement(parent, "Unknown", index=str(index[name]),
                       dependencies=" ".join(map(str, deps)),
                       dependenciesKind=" ".join(["dependent"] * len(deps)))
    return root
