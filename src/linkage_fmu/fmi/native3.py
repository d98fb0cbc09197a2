"""What an FMI 3.0 native FMU has that the FMI 2.0 one has not: the same ``config.h``
and ``model.c`` (:mod:`~linkage_fmu.fmi.native` builds both versions), behind the FMI
3.0 framework ``fmi3.c``, which includes ``backend_native.c`` through ``backend_fmi3.h``.

The modelDescription.xml comes from the same variable table
(:func:`~linkage_fmu.fmi.variables.variables`). Differences from FMI 2.0:

- ``instantiationToken`` instead of ``guid``; capability flags spelled ``...FMUState``;
  ``hasEventMode="false"``; no ``SourceFiles`` (FMI 3.0 lists them in
  ``sources/buildDescription.xml``, :func:`build_description`); the binary in
  ``binaries/x86_64-linux``;
- one element per variable named by its type (``Float64``, ``Int32``, ``String``), a
  string's start value as a ``<Start value=.../>`` child;
- the independent variable ``time`` (FMI 3.0 requires exactly one), value reference
  ``len(table)``, right after the table's (the FMU answers it from the last successful
  communication point);
- ``ModelStructure`` lists ``<Output valueReference=...>`` and ``<InitialUnknown ...>``
  by value reference (FMI 2.0: by 1-based index). In initialisation mode an output also
  depends on the parameters (``initial="exact"`` knowns), so the InitialUnknowns list
  them too; the Outputs list the inputs only, as in FMI 2.0.
"""

from __future__ import annotations

import math
from xml.etree import ElementTree as ET

from .. import __version__
from .model_description import UNITS
from .variables import variables

#: the framework, its FMI 3.0 names for the backend interface, the backend
FRAMEWORK = ("fmi3.c", "fmi_common.h", "backend_fmi3.h", "backend_native.c")
#: the FMI 3.0 headers (from fmpy), copied beside them
HEADERS = ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h")
#: FMI 3.0 platform tuple (FMI 2.0: linux64)
PLATFORM = "x86_64-linux"

TYPES = {"Real": "Float64", "Integer": "Int32", "String": "String"}
#: FMI 3.0 adds the unit of the independent variable
UNITS3 = {**UNITS, "s": ({"s": 1}, [])}
TIME = "time"


def time_reference(mech) -> int:
    """The value reference of the independent variable: right after the table's."""
    return len(variables(mech))


def model_description3(mech, d, token: str) -> bytes:
    """``modelDescription.xml`` (FMI 3.0, co-simulation) of the native FMU of ``mech``
    (``d``: its description with the parameters' values as defaults, ``token``: the
    instantiation token compiled into the binary)."""
    table = variables(mech)
    vr_of = {v.name: vr for vr, v in enumerate(table)}
    w0 = abs(d.inputs.get("omega", 0.0))
    stop = 2.0 * math.pi / w0 if w0 else 1.0
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": "3.0", "modelName": d.model, "instantiationToken": token,
        "description": f"{d.title or d.name}: joint reactions and balancing effort "
                       "(kinetostatics)",
        "author": "linkage_fmu", "version": __version__,
        "generationTool": f"linkage_fmu {__version__} (native C kernels, FMI 3.0)",
        "variableNamingConvention": "structured"})
    ET.SubElement(root, "CoSimulation", {
        "modelIdentifier": d.model,
        "needsExecutionTool": "false",
        "canBeInstantiatedOnlyOncePerProcess": "false",
        "canGetAndSetFMUState": "true",
        "canSerializeFMUState": "true",
        "providesDirectionalDerivatives": "false",
        "providesAdjointDerivatives": "false",
        "providesPerElementDependencies": "false",
        "canHandleVariableCommunicationStepSize": "true",
        "maxOutputDerivativeOrder": "0",
        "providesIntermediateUpdate": "false",
        "mightReturnEarlyFromDoStep": "false",
        "canReturnEarlyAfterIntermediateUpdate": "false",
        "hasEventMode": "false",
        "providesEvaluateDiscreteStates": "false"})
    units = ET.SubElement(root, "UnitDefinitions")
    for name, (base, displays) in UNITS3.items():
        unit = ET.SubElement(units, "Unit", name=name)
        ET.SubElement(unit, "BaseUnit", {k: str(v) for k, v in base.items()})
        for display, factor in displays:
            ET.SubElement(unit, "DisplayUnit", name=display, factor=repr(factor))
    categories = ET.SubElement(root, "LogCategories")
    for name, text in (("logStatusWarning", "fmi3Warning"), ("logStatusDiscard", "fmi3Discard"),
                       ("logStatusError", "fmi3Error"), ("logStatusFatal", "fmi3Fatal")):
        ET.SubElement(categories, "Category", name=name,
                      description=f"Log messages with {text} status.")
    ET.SubElement(categories, "Category", name="logAll", description="Log all messages.")
    ET.SubElement(root, "DefaultExperiment", startTime="0.0", stopTime=repr(stop),
                  stepSize=repr(stop / 360.0))
    model_variables = ET.SubElement(root, "ModelVariables")
    for vr, v in enumerate(table):
        text = v.description
        if v.name == "method":
            text = ("solver: closed_form (a native FMU computes the closed form; its check "
                    "runs it against the direct solver)")
        attrs = {"name": v.name, "valueReference": str(vr), "description": text,
                 "causality": v.causality, "variability": v.variability}
        if v.type == "Real":
            if v.start is not None:
                attrs["start"] = repr(float(v.start))
            if v.unit:
                attrs["unit"] = v.unit
            if v.display_unit:
                attrs["displayUnit"] = v.display_unit
        elif v.type == "Integer" and v.start is not None:
            attrs["start"] = str(int(v.start))
        node = ET.SubElement(model_variables, TYPES[v.type], attrs)
        if v.type == "String" and v.start is not None:
            ET.SubElement(node, "Start", value=str(v.start))
    ET.SubElement(model_variables, "Float64", name=TIME, valueReference=str(len(table)),
                  description="simulation time: the last successful communication point",
                  causality="independent", variability="continuous", unit="s")
    structure = ET.SubElement(root, "ModelStructure")
    parameters = [vr for vr, v in enumerate(table)
                  if v.causality == "parameter" and v.name != "method"]
    outputs = [(vr, v) for vr, v in enumerate(table) if v.causality == "output"]
    for tag, extra in (("Output", []), ("InitialUnknown", parameters)):
        for vr, v in outputs:
            deps = sorted({vr_of[n] for n in v.depends} | set(extra))
            ET.SubElement(structure, tag, valueReference=str(vr),
                          dependencies=" ".join(map(str, deps)),
                          dependenciesKind=" ".join(["dependent"] * len(deps)))
    ET.indent(root, "\t")
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)


def build_description(model: str, sources=("fmi3.c",)) -> bytes:
    """``sources/buildDescription.xml``: how to compile the shipped C (FMI 3.0's
    replacement of FMI 2.0's ``<SourceFiles>``)."""
    root = ET.Element("fmiBuildDescription", fmiVersion="3.0")
    config = ET.SubElement(root, "BuildConfiguration", modelIdentifier=model,
                           description="fmi3.c includes config.h, fmi_common.h, backend_fmi3.h, "
                                       "backend_native.c and model.c; link with -lm")
    files = ET.SubElement(config, "SourceFileSet", language="C99")
    for name in sources:
        ET.SubElement(files, "SourceFile", name=name)
    ET.SubElement(config, "Library", name="m", external="true", description="the C math library")
    ET.indent(root, "\t")
    return ET.tostring(root, encoding="UTF-8", xml_declaration=True)
