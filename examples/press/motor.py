"""The press's motor as an FMU of its own: FMI 2.0 co-simulation, native, built on
linkage_fmu's FMI framework (``framework.c`` and its FMI 2.0 adapter ``fmi2.c``, which own
the state machine, the argument checks, the parameter rules, the status policy and FMU
states) with a backend of a few lines (``motor/backend_motor.c``).

The motor is algebraic: its linear torque-speed line referred to the crank (through the
press's gearbox: a motor line T_m0, omega_m0 behind a reduction n is T_stall = n T_m0,
omega_noload = omega_m0 / n)::

    tau = T_stall * (1 - omega / omega_noload)

Input ``omega`` (the crank's speed), outputs ``tau`` (the moment on the crank) and ``P``
(the power it puts into the crank, ``tau * omega``). Its rotor's inertia turns with the
crank, so the system gives it to the press as an inertia on the crank (see ``press.py``).

Everything the FMU says of its variables (``config.h`` for the C, ``modelDescription.xml``)
is written from one table, :data:`VARIABLES`.
"""

from __future__ import annotations

import shutil
import tempfile
import uuid
import zipfile
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

from linkage_fmu import __version__
from linkage_fmu.fmi import build
from linkage_fmu.fmi.platforms import host
from linkage_fmu.fmi.writers import UNITS, c_string

HERE = Path(__file__).parent
MODEL = "Motor"


@dataclass(frozen=True)
class Variable:
    """One variable of the motor FMU; its value reference is its position in
    :data:`VARIABLES`."""

    name: str
    causality: str  # input, parameter or output
    unit: str
    description: str
    start: float | None = None


VARIABLES = (
    Variable("omega", "input", "rad/s", "crank angular speed", 0.0),
    Variable("T_stall", "parameter", "N.m", "stall torque referred to the crank", 100.0),
    Variable("omega_noload", "parameter", "rad/s", "no-load speed referred to the crank", 10.0),
    Variable("tau", "output", "N.m",
             "moment of the motor on the crank, counter-clockwise positive: "
             "T_stall * (1 - omega / omega_noload)"),
    Variable("P", "output", "W", "power the motor puts into the crank: tau * omega"),
)
VR = {v.name: vr for vr, v in enumerate(VARIABLES)}
#: the C framework's kinds
_KINDS = {"input": "K_INPUT", "parameter": "K_FIXED", "output": "K_OUTPUT"}


def _of(causality: str) -> list[int]:
    return [vr for vr, v in enumerate(VARIABLES) if v.causality == causality]


def config_header(guid: str) -> str:
    """``config.h`` of the motor FMU: its identity, backend and variable table.

    Examples
    --------
    >>> print(config_header("{1}").splitlines()[1])
    #define MODEL_IDENTIFIER "Motor"
    """
    inputs, outputs = _of("input"), _of("output")
    index = {vr: k for group in (inputs, _of("parameter"), outputs) for k, vr in enumerate(group)}
    rows = []
    for vr, v in enumerate(VARIABLES):
        rule = ", .rule = RULE_POSITIVE" if v.causality == "parameter" else ""
        rows.append(f"    [{vr}] = {{.type = T_REAL, .kind = {_KINDS[v.causality]}, "
                    f".name = {c_string(v.name)}, .meaning = {c_string(v.description)}, "
                    f".index = {index[vr]}, .start = {float(v.start or 0.0)!r}{rule}, "
                    f".min = -INFINITY, .max = INFINITY}},")
    return "\n".join([
        "/* config.h of the press's motor FMU: written by examples/press/motor.py */",
        f"#define MODEL_IDENTIFIER {c_string(MODEL)}",
        f"#define MODEL_GUID {c_string(guid)}",
        '#define BACKEND "backend_motor.c"',
        f"#define N_VARIABLES {len(VARIABLES)}u",
        f"#define N_INPUTS {len(inputs)}",
        f"#define N_OUTPUTS {len(outputs)}",
        f"#define VR_OMEGA {VR['omega']}",
        f"#define VR_T_STALL {VR['T_stall']}",
        f"#define VR_OMEGA_NOLOAD {VR['omega_noload']}",
        f"#define Y_TAU {outputs.index(VR['tau'])}",
        f"#define Y_POWER {outputs.index(VR['P'])}",
        "static const Variable VARIABLES[N_VARIABLES] = {", *rows, "};",
        f"static const ValueReference INPUTS[N_INPUTS] = {{{', '.join(map(str, inputs))}}};",
        f"static const ValueReference OUTPUTS[N_OUTPUTS] = {{{', '.join(map(str, outputs))}}};",
        ""])


def model_description(guid: str) -> str:
    """``modelDescription.xml`` of the motor FMU (FMI 2.0 co-simulation).

    Examples
    --------
    >>> import xml.etree.ElementTree as ET
    >>> root = ET.fromstring(model_description("{1}"))
    >>> [(v.get("name"), v.get("causality")) for v in root.iter("ScalarVariable")][:3]
    [('omega', 'input'), ('T_stall', 'parameter'), ('omega_noload', 'parameter')]
    """
    units = []
    for name in sorted({v.unit for v in VARIABLES}):
        base = " ".join(f'{k}="{e}"' for k, e in UNITS[name][0].items())
        units.append(f'\t\t<Unit name="{name}"><BaseUnit {base}/></Unit>')
    variables = []
    for vr, v in enumerate(VARIABLES):
        variability = "fixed" if v.causality == "parameter" else "continuous"
        start = "" if v.start is None else f' start="{float(v.start)!r}"'
        variables.append(
            f'\t\t<ScalarVariable name="{v.name}" valueReference="{vr}" '
            f'description={quoteattr(v.description)} causality="{v.causality}" '
            f'variability="{variability}"><Real{start} unit="{v.unit}"/></ScalarVariable>')
    # FMI 2.0 names the knowns by their index (value reference + 1)
    omega, parameters = VR["omega"] + 1, [vr + 1 for vr in _of("parameter")]
    outputs = [f'\t\t\t<Unknown index="{vr + 1}" dependencies="{omega}" '
               f'dependenciesKind="dependent"/>' for vr in _of("output")]
    initial = " ".join(map(str, sorted([omega, *parameters])))
    initial_unknowns = [
        f'\t\t\t<Unknown index="{vr + 1}" dependencies="{initial}" '
        f'dependenciesKind="{" ".join(["dependent"] * len(parameters + [omega]))}"/>'
        for vr in _of("output")]
    return "\n".join([
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<fmiModelDescription fmiVersion="2.0" modelName="{MODEL}" guid="{guid}" '
        'description="Motor with a linear torque-speed line, referred to the crank" '
        f'author="linkage_fmu" version="{__version__}" '
        f'generationTool="linkage_fmu {__version__} examples/press/motor.py" '
        'variableNamingConvention="flat">',
        f'\t<CoSimulation modelIdentifier="{MODEL}" needsExecutionTool="false" '
        'canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" '
        'canBeInstantiatedOnlyOncePerProcess="false" canGetAndSetFMUstate="true" '
        'canSerializeFMUstate="true" providesDirectionalDerivative="false"/>',
        "\t<UnitDefinitions>", *units, "\t</UnitDefinitions>",
        "\t<ModelVariables>", *variables, "\t</ModelVariables>",
        "\t<ModelStructure>",
        "\t\t<Outputs>", *outputs, "\t\t</Outputs>",
        "\t\t<InitialUnknowns>", *initial_unknowns, "\t\t</InitialUnknowns>",
        "\t</ModelStructure>",
        "</fmiModelDescription>", ""])


def build_motor_fmu(out: str | Path) -> Path:
    """Build ``out/Motor.fmu`` for this machine's platform and return its path.

    Raises
    ------
    CompilerError
        No C compiler, or the library is not a proper FMI 2.0 binary (nothing written).
    """
    guid = str(uuid.uuid4())
    platform = host()
    with tempfile.TemporaryDirectory(prefix="press_motor_") as tmp:
        src = Path(tmp) / "sources"
        src.mkdir()
        for name in ("fmi2.c", "framework.h", "framework.c"):
            shutil.copy(build.HERE / name, src / name)
        for name in build.HEADERS[2]:
            shutil.copy(build.fmi_headers() / name, src / name)
        shutil.copy(HERE / "motor" / "backend_motor.c", src / "backend_motor.c")
        (src / "config.h").write_text(config_header(guid))
        library = build.compile_for(platform, [src / "fmi2.c"],
                                    Path(tmp) / platform.library(MODEL), 2, include=[src])
        target = Path(out) / f"{MODEL}.fmu"
        target.parent.mkdir(parents=True, exist_ok=True)
        staged = Path(tmp) / "staged.fmu"
        with zipfile.ZipFile(staged, "w", zipfile.ZIP_DEFLATED) as archive:
            archive.writestr("modelDescription.xml", model_description(guid))
            archive.write(library, f"binaries/{platform.folder(2)}/{library.name}")
        return Path(shutil.move(staged, target))
