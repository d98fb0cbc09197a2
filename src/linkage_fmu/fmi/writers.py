"""One writer per generated artefact of an FMU, each a template (``templates/``) filled
from the linkage's variable table (:func:`~linkage_fmu.fmi.variables.variables`):

- :func:`model_description`: ``modelDescription.xml``, FMI 2.0 or 3.0, either flavour;
- :func:`config_header`: ``config.h``, the model's identity, backend and variable table
  for the C framework (``framework.c``);
- :func:`model_source`: ``model.c`` of a native FMU, its kernels and their tables;
- :func:`build_description`: ``sources/buildDescription.xml`` of an FMI 3.0 source FMU;
- :func:`slave_script`: the Python script of a pythonfmu FMU.

The templates are jinja2's, as fmpy's are; XML values are escaped by the templates
(autoescape), C strings and doubles by the filters :func:`c_string` and
:func:`~linkage_fmu.kernels.c_source.c_literal`.

Examples
--------
>>> from linkage_fmu import presets
>>> mech = presets.get("four_bar")
>>> print(config_header(mech, "native", "{1}").splitlines()[2])
#define MODEL_IDENTIFIER "FourBar"
>>> b"fmiVersion=\\"3.0\\"" in model_description(mech, "native", 3, "{1}")
True
"""

from __future__ import annotations

import datetime
import itertools
import math
from pathlib import Path

import jinja2

from .. import __version__
from ..kernels.c_source import c_literal
from .variables import Variable, variables

TEMPLATES = Path(__file__).with_name("templates")
#: unit -> (SI base-unit exponents, display units as (name, factor))
RAD2DEG = 57.29577951308232
UNITS = {
    "rad": ({"rad": 1}, [("deg", RAD2DEG)]),
    "rad/s": ({"rad": 1, "s": -1}, [("deg/s", RAD2DEG)]),
    "rad/s2": ({"rad": 1, "s": -2}, [("deg/s2", RAD2DEG)]),
    "m": ({"m": 1}, []),
    "m/s2": ({"m": 1, "s": -2}, []),
    "kg": ({"kg": 1}, []),
    "kg/m": ({"kg": 1, "m": -1}, []),
    "kg.m2": ({"kg": 1, "m": 2}, []),
    "kg.m2/rad": ({"kg": 1, "m": 2, "rad": -1}, []),
    "N": ({"kg": 1, "m": 1, "s": -2}, []),
    "N.m": ({"kg": 1, "m": 2, "s": -2}, []),
    "1": ({}, []),
}
LOG_CATEGORIES = ("logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
                  "logAll")
#: the C framework's names of the types, kinds and rules
_TYPES = {"Real": "REAL", "Integer": "INTEGER", "Boolean": "BOOLEAN", "String": "STRING"}
_TYPES3 = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String"}
_RULES = {"finite": "FINITE", "> 0": "POSITIVE", ">= 0": "NONNEGATIVE"}
_TOOLS = {"pythonfmu": "pythonfmu {pythonfmu} behind the linkage_fmu FMI framework",
          "native": "linkage_fmu {version} (native C kernels)"}


def c_string(text: str) -> str:
    """``text`` as a C string literal.

    Examples
    --------
    >>> print(c_string('a "b"\\\\'))
    "a \\"b\\"\\\\"
    """
    escaped = text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
    return f'"{escaped}"'


def _kind(v: Variable) -> str:
    return {"input": "INPUT", "output": "OUTPUT", "parameter": "FIXED"}.get(v.causality, "OTHER")


def _xml_value(value) -> str:
    return repr(float(value)) if isinstance(value, float) else str(value)


def _environment(autoescape: bool) -> jinja2.Environment:
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(TEMPLATES), autoescape=autoescape,
                             trim_blocks=True, lstrip_blocks=True, keep_trailing_newline=True,
                             undefined=jinja2.StrictUndefined)
    env.filters.update(c_string=c_string, c_double=lambda v: c_literal(float(v)),
                       xml_double=lambda v: repr(float(v)), xml_value=_xml_value, py_repr=repr)
    env.globals.update(TYPES=_TYPES, TYPES3=_TYPES3, RULES=_RULES, kind=_kind)
    return env


_C, _XML = _environment(False), _environment(True)


def _stop(mech) -> float:
    """A revolution at the start speed (1 s for a linkage that starts at rest)."""
    w0 = abs(mech.start["omega"])
    return 2.0 * math.pi / w0 if w0 else 1.0


def dependencies(table: list[Variable]) -> tuple[dict, dict]:
    """The value references each output of ``table`` depends on: after initialisation
    (the inputs it is computed from) and in initialisation mode (those and every
    parameter), as ``{output vr: sorted vrs}`` each.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> table = variables(presets.get("four_bar"))
    >>> depends, initial = dependencies(table)
    >>> depends[len(table) - 1], len(initial[len(table) - 1])
    ([0], 20)
    """
    vr_of = {v.name: vr for vr, v in enumerate(table)}
    parameters = [vr for vr, v in enumerate(table) if v.causality == "parameter"]
    depends, initial = {}, {}
    for vr, v in enumerate(table):
        if v.causality == "output":
            depends[vr] = sorted(vr_of[n] for n in v.depends)
            initial[vr] = sorted(set(depends[vr]) | set(parameters))
    return depends, initial


def model_description(mech, flavour: str, fmi_version: int, guid: str,
                      sources: tuple = ()) -> bytes:
    """``modelDescription.xml`` of the FMU of ``mech`` (FMI ``fmi_version`` 2 or 3,
    ``flavour`` ``pythonfmu`` or ``native``), with the GUID (FMI 3.0: instantiation token)
    ``guid`` and, for an FMI 2.0 source FMU, its source files."""
    import pythonfmu

    table = variables(mech, flavour)
    depends, initial = dependencies(table)
    if fmi_version == 2:  # FMI 2.0 lists the inputs by index (from 1), not value reference
        depends = {vr: [k + 1 for k in known] for vr, known in depends.items()}
    d = mech.description
    return _XML.get_template(f"modelDescription{fmi_version}.xml").render(
        model=d.model, guid=guid, flavour=flavour, version=__version__,
        title=f"{d.title or d.name}: joint reactions and balancing effort (kinetostatics)",
        tool=_TOOLS[flavour].format(version=__version__, pythonfmu=pythonfmu.__version__),
        now=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        sources=sources, units=UNITS.items() if fmi_version == 2 else
        {**UNITS, "s": ({"s": 1}, [])}.items(), categories=LOG_CATEGORIES, stop=_stop(mech),
        variables=list(enumerate(table)), depends=depends, initial=initial).encode("utf-8")


def config_header(mech, flavour: str, guid: str, defines: dict | None = None) -> str:
    """``config.h`` of the FMU of ``mech`` in ``flavour`` (the backend it includes),
    with the GUID ``guid`` and the backend's own ``defines`` (name -> C text)."""
    table = variables(mech, flavour)
    depends, initial = dependencies(table)
    return _C.get_template("config.h").render(
        model=mech.description.model, guid=guid, flavour=flavour,
        defines=list((defines or {}).items()), variables=list(enumerate(table)),
        depends=depends, initial=initial,
        inputs=[vr for vr, v in enumerate(table) if v.causality == "input"],
        outputs=[vr for vr, v in enumerate(table) if v.causality == "output"])


def structures(mech) -> list[dict]:
    """Every combination of the linkage's branch and choice parameters, the built one
    first."""
    specs = [p for p in mech.description.parameter_specs() if p.kind in ("branch", "choice")]
    options = [[mech.parameters[p.name]] + [v for v in (
        (1, -1) if p.kind == "branch" else p.choices) if v != mech.parameters[p.name]]
        for p in specs]
    return [dict(zip((p.name for p in specs), combo)) for combo in itertools.product(*options)]


def model_source(mech, rebuild) -> tuple[str, list[dict]]:
    """``model.c`` of the native FMU of ``mech``: one kernel per structure that can be
    traced (``rebuild(**structure)`` builds the linkage in it), and the structures
    built.

    Raises
    ------
    ValueError
        The linkage cannot be assembled at any witness angle in any structure.
    """
    table = variables(mech, "native")
    vr_of = {v.name: vr for vr, v in enumerate(table)}
    integers = [v.name for v in table if v.type == "Integer"]
    strings = [v.name for v in table if v.type == "String" and v.name != "method"]
    kernels, built, errors = [], [], []
    for combo in structures(mech):
        try:
            k = rebuild(**combo).kernel(None, False)
        except ValueError as err:  # cannot be assembled anywhere: no kernel for this structure
            errors.append(f"{combo}: {err}")
            continue
        if k.parameters != mech.kernel_parameters or (kernels and k.outputs != kernels[0].outputs):
            raise ValueError(f"{mech.name}: the structure {combo} has other parameters or "
                             "outputs than the one built")
        kernels.append(k)
        built.append(combo)
    if not kernels:
        raise ValueError(f"{mech.name} cannot be assembled in any structure, so it has no "
                         "kernel to build: " + "; ".join(errors))
    words = "; ".join(", ".join(f"{n} = {v}" for n, v in c.items()) for c in built)
    outputs = kernels[0].outputs
    source = _C.get_template("model.c").render(
        model=mech.description.model,
        kernels=[k.c_source(array=False, prefix=f"s{s}", tangent=True)
                 for s, k in enumerate(kernels)],
        parameters=[vr_of[n] for n in mech.kernel_parameters],
        n_q=max(len(k.frozen) for k in kernels), built=words or "one structure",
        cond=outputs.index("cond") if "cond" in outputs else -1,
        integers=[vr_of[n] for n in integers], strings=[vr_of[n] for n in strings],
        checked=[int(i in kernels[0].checked) for i in range(len(outputs))],
        structures=[{"integers": [c[n] for n in integers], "strings": [str(c[n]) for n in strings],
                     # the framework says "the parameter set is invalid" itself
                     "reasons": [r.what if r.kind == "parameter" else r.text
                                 for r in k.reasons]} for c, k in zip(built, kernels)])
    return source, built


def build_description(model: str, adapter: str = "fmi3.c") -> bytes:
    """``sources/buildDescription.xml``: how to compile a native FMI 3.0 FMU's C (FMI
    3.0's replacement of FMI 2.0's ``<SourceFiles>``)."""
    return _XML.get_template("buildDescription.xml").render(
        model=model, adapter=adapter).encode("utf-8")


def slave_script(mech, description: str, fingerprint: str) -> str:
    """The slave script of the pythonfmu FMU of ``mech``: its class, named as the model,
    reads the description file ``description`` from the FMU's resources."""
    return _C.get_template("slave.py.in").render(
        model=mech.description.model, description=description, fingerprint=fingerprint)
