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
import re
from pathlib import Path

import jinja2

from .. import __version__
from ..errors import InputError
from ..kernels.c_source import c_literal
from ..units import TABLE
from .variables import (
    MOTION_STATE,
    TOLERANCE,
    Variable,
    bounds,
    crank_choices,
    drive_variables,
    variables,
)

TEMPLATES = Path(__file__).with_name("templates")
#: unit -> (SI base-unit exponents, display units as (name, factor)): every unit of
#: :data:`linkage_fmu.units.TABLE`, in its order
UNITS = {u.symbol: (u.base, u.display) for u in TABLE}
LOG_CATEGORIES = ("logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
                  "logAll")
#: the C framework's names of the types, kinds and rules
_TYPES = {"Real": "REAL", "Integer": "INTEGER", "Boolean": "BOOLEAN", "String": "STRING"}
_TYPES3 = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean", "String": "String"}
_RULES = {"finite": "FINITE", "> 0": "POSITIVE", ">= 0": "NONNEGATIVE", "+1 or -1": "SIGN"}
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
    if v.state:
        return "STATE"
    if v.discrete:
        return "DISCRETE"
    if v.derivative or v.event:  # computed, whatever its causality
        return "OUTPUT"
    if v.causality == "parameter":
        return "TUNABLE" if v.variability == "tunable" else "FIXED"
    return {"input": "INPUT", "output": "OUTPUT"}.get(v.causality, "OTHER")


def model_name(mech, drive: bool = False) -> str:
    """The model identifier of the FMU of ``mech``: its description's ``model``, with
    ``Drive`` after it for the drive FMU.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> model_name(presets.get("four_bar")), model_name(presets.get("four_bar"), drive=True)
    ('FourBar', 'FourBarDrive')
    """
    return mech.description.model + ("Drive" if drive else "")


def table_of(mech, flavour: str, drive: bool = False) -> list[Variable]:
    """The variable table of the FMU of ``mech``: the drive FMU's (native only), or the
    one of ``flavour``."""
    if drive and flavour != "native":
        raise InputError(f"a drive FMU is native, not {flavour}")
    return drive_variables(mech) if drive else variables(mech, flavour)


def _xml_value(value) -> str:
    return repr(float(value)) if isinstance(value, float) else str(value)


def _environment(autoescape: bool) -> jinja2.Environment:
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(TEMPLATES), autoescape=autoescape,
                             trim_blocks=True, lstrip_blocks=True, keep_trailing_newline=True,
                             undefined=jinja2.StrictUndefined)
    env.filters.update(c_string=c_string, c_double=lambda v: c_literal(float(v)),
                       xml_double=lambda v: repr(float(v)), xml_value=_xml_value, py_repr=repr)
    env.globals.update(TYPES=_TYPES, TYPES3=_TYPES3, RULES=_RULES, kind=_kind, bounds=bounds)
    return env


_C, _XML = _environment(False), _environment(True)


def _stop(mech) -> float:
    """A revolution at the start speed (1 s for a linkage that starts at rest, or one
    driven by time)."""
    if mech.rates:
        return 1.0
    w0 = abs(mech.start["omega"])
    return 2.0 * math.pi / w0 if w0 else 1.0


def drive_step(stop: float) -> float:
    """The drive FMU's default communication step for a run of ``stop`` seconds: the
    largest 1, 2 or 5 times a power of ten not above ``stop / 360`` (a degree of the
    revolution at the start speed), so that an importer's default grid (fmpy's
    ``simulate_fmu`` samples at the default experiment's ``stepSize``) has round times.

    The integrator holds its own substeps to ``tolerance`` whatever the step; inputs are
    held over a step, so a varying ``tau`` needs steps as short as its variation asks.

    Examples
    --------
    >>> drive_step(2 * 3.141592653589793 / 10), drive_step(1.0), drive_step(0.02)
    (0.001, 0.002, 5e-05)
    """
    fine = stop / 360.0
    power = 10.0 ** math.floor(math.log10(fine))
    return max(m * power for m in (1, 2, 5) if m * power <= fine * (1 + 1e-12))


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
    ([0], 29)
    """
    vr_of = {v.name: vr for vr, v in enumerate(table)}
    parameters = [vr for vr, v in enumerate(table) if v.causality == "parameter"]
    states = {vr for vr, v in enumerate(table) if v.state}
    depends, initial = {}, {}
    for vr, v in enumerate(table):
        if v.causality == "output" or v.derivative or v.event:
            depends[vr] = sorted(vr_of[n] for n in v.depends)
            # the states are computed in initialisation mode: from their start parameters
            initial[vr] = sorted(set(depends[vr]) - states | set(parameters))
    return depends, initial


def model_description(mech, flavour: str, fmi_version: int, guid: str,
                      sources: tuple = (), drive: bool = False) -> bytes:
    """``modelDescription.xml`` of the FMU of ``mech`` (FMI ``fmi_version`` 2 or 3,
    ``flavour`` ``pythonfmu`` or ``native``; with ``drive``, the native drive FMU, model
    exchange and co-simulation), with the GUID (FMI 3.0: instantiation token) ``guid``
    and, for an FMI 2.0 source FMU, its source files."""
    import pythonfmu

    table = table_of(mech, flavour, drive)
    depends, initial = dependencies(table)
    if fmi_version == 2:  # FMI 2.0 lists the knowns by index (from 1), not value reference
        def index(known):
            return [k + 1 for k in known]
        # the inverse FMU's InitialUnknowns list what its Outputs do (no state to start)
        initial = {vr: index(initial[vr] if drive else depends[vr]) for vr in depends}
        depends = {vr: index(known) for vr, known in depends.items()}
    vr_of = {v.name: vr for vr, v in enumerate(table)}
    d = mech.description
    what = ("its motion under a moment on the crank, with the friction of its joints "
            "(sticking at rest inside the friction band), and its joint reactions" if drive
            else "joint reactions and balancing effort (kinetostatics)")
    return _XML.get_template(f"modelDescription{fmi_version}.xml").render(
        model=model_name(mech, drive), guid=guid, flavour=flavour, version=__version__,
        title=f"{d.title or d.name}: {what}", drive=drive,
        derivative_of={vr: vr_of[v.derivative] for vr, v in enumerate(table) if v.derivative},
        events=[vr for vr, v in enumerate(table) if v.event],
        # in the order of the states
        derivatives=[vr for s in table if s.state for vr, v in enumerate(table)
                     if v.derivative == s.name],
        tool=_TOOLS[flavour].format(version=__version__, pythonfmu=pythonfmu.__version__),
        now=datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        sources=sources, units=UNITS.items(), categories=LOG_CATEGORIES, stop=_stop(mech),
        step=drive_step(_stop(mech)) if drive else _stop(mech) / 360.0,
        tolerance=TOLERANCE if drive else None,
        variables=list(enumerate(table)), depends=depends, initial=initial).encode("utf-8")


def config_header(mech, flavour: str, guid: str, defines: dict | None = None,
                  drive: bool = False) -> str:
    """``config.h`` of the FMU of ``mech`` in ``flavour`` (the backend it includes; with
    ``drive``, the native drive FMU, whose continuous states it names), with the GUID
    ``guid`` and the backend's own ``defines`` (name -> C text)."""
    table = table_of(mech, flavour, drive)
    depends, initial = dependencies(table)
    vr_of = {v.name: vr for vr, v in enumerate(table)}
    states = [vr for vr, v in enumerate(table) if v.state]
    derivative = {v.derivative: v.index for v in table if v.derivative}
    return _C.get_template("config.h").render(
        model=model_name(mech, drive), guid=guid, flavour=flavour,
        defines=list((defines or {}).items()), variables=list(enumerate(table)),
        depends=depends, initial=initial,
        inputs=[vr for vr, v in enumerate(table) if v.causality == "input"],
        outputs=[vr for vr, v in enumerate(table) if _kind(v) == "OUTPUT"], states=states,
        starts=[vr_of[f"{table[vr].name}0"] for vr in states],
        derivatives=[derivative[table[vr].name] for vr in states],
        tolerance=vr_of.get("tolerance"), motion=vr_of.get(MOTION_STATE),
        events=[v.index for v in table if v.event])


def structures(mech, choices: dict | None = None) -> list[dict]:
    """Every combination of the linkage's branch and choice parameters, the built one
    first; a choice named in ``choices`` takes only the values listed there."""
    specs = [p for p in mech.description.parameter_specs() if p.kind in ("branch", "choice")]
    allowed = {p.name: (1, -1) if p.kind == "branch" else (choices or {}).get(p.name, p.choices)
               for p in specs}
    options = [[mech.parameters[p.name]] + [v for v in allowed[p.name]
                                            if v != mech.parameters[p.name]] for p in specs]
    return [dict(zip((p.name for p in specs), combo)) for combo in itertools.product(*options)]


def model_source(mech, rebuild, drive: bool = False,
                 frictionless=None) -> tuple[str, list[dict]]:
    """``model.c`` of the native FMU of ``mech``: one kernel per structure that can be
    traced (``rebuild(**structure)`` builds the linkage in it), and the structures
    built. The drive FMU's (``drive``) has a second kernel per structure, that of its
    motion: the balancing moment (with the friction of the joints) and the reduced
    inertia at (theta, omega, alpha, loads), with its forward-mode derivatives (Newton on
    alpha); its structures are those whose effort is a moment on the crank
    (:func:`~linkage_fmu.fmi.variables.crank_choices`).

    ``frictionless``, ``(build, names)``: ``build(**structure)`` builds the linkage
    without friction, where the parameters ``names`` (those its coefficients of friction
    are functions of) are all 0. Each structure then has that kernel too (a fraction of
    the operations; the drive FMU's kernel of its motion too), which the FMU runs while
    those parameters are all 0; None where they being 0 leaves some friction (a constant
    coefficient).

    Raises
    ------
    ValueError
        The linkage cannot be assembled at any witness angle in any structure; a drive
        FMU of a linkage with friction whose ``drive`` direction is no parameter (its
        friction at rest must be had both ways).
    """
    table = table_of(mech, "native", drive)
    vr_of = {v.name: vr for vr, v in enumerate(table)}
    integers = [v.name for v in table if v.type == "Integer" and not v.discrete]
    strings = [v.name for v in table if v.type == "String" and v.name != "method"]
    kernels, rhs, built, errors, plains, plain_rhs = [], [], [], [], [], []
    for combo in structures(mech, crank_choices(mech) if drive else None):
        try:
            twin = rebuild(**combo)
            k = twin.kernel(None, False)
            r = twin.kernel(RHS_OUTPUTS, False) if drive else None
        except ValueError as err:  # cannot be assembled anywhere: no kernel for this structure
            errors.append(f"{combo}: {err}")
            continue
        if drive and not twin.effort_on_crank:  # a combination no drive FMU can run
            continue
        if k.parameters != mech.kernel_parameters or (kernels and k.outputs != kernels[0].outputs) \
                or (r is not None and r.parameters != mech.kernel_parameters):
            raise InputError(f"{mech.name}: the structure {combo} has other parameters or "
                             "outputs than the one built")
        kernels.append(k)
        rhs.append(r)
        built.append(combo)
        if frictionless is not None:
            plain = frictionless[0](**combo)
            k0 = plain.kernel(None, False)
            g0 = plain.kernel(RHS_OUTPUTS, False) if drive else None
            if plain.friction.active or k0.outputs != k.outputs or k0.checked != k.checked \
                    or (plains and k0.parameters != plains[0].parameters) \
                    or (g0 is not None and g0.parameters != k0.parameters):
                # a constant coefficient of friction (or kernels of other parameters, which
                # one table of their value references could not serve): none in C
                frictionless = None
            else:
                plains.append(k0)
                plain_rhs.append(g0)
    if not kernels:
        raise InputError(f"{mech.name} cannot be assembled in any structure, so it has no "
                         "kernel to build: " + "; ".join(errors))
    words = "; ".join(", ".join(f"{n} = {v}" for n, v in c.items()) for c in built)
    outputs = kernels[0].outputs

    def reasons(k):  # the framework says "the parameter set is invalid" itself
        return [r.what if r.kind == "parameter" else r.text for r in k.reasons]

    drive_tables = {}
    if drive:
        computed = [v for v in table if _kind(v) == "OUTPUT"]
        index = {v.name: v.index for v in computed}
        names = rhs[0].outputs
        direction = mech.description.drive
        friction = bool(mech.friction.active)
        rhs_sources = [r.c_source(array=False, prefix=f"r{s}", tangent=friction, settle=True,
                                  vary=2 if friction else None) for s, r in enumerate(rhs)]
        if friction and direction not in mech.kernel_parameters:
            raise InputError(f"{mech.name}: a drive FMU needs the friction's drive direction "
                             f"as a parameter (its drive is {direction!r}): at rest, friction "
                             "opposes the motion the crank is pushed to, either way")
        drive_tables = dict(
            # friction's loops stop once converged: Mb is a residual of the root alpha,
            # several runs per evaluation of the derivatives (a quarter of the time);
            # what alpha (input 2) does not change runs once per state
            rhs_kernels=rhs_sources, n_rf=max(int(re.search(r"_N_F (\d+)", c).group(1))
                                              for c in rhs_sources) if friction else 0,
            n_r=max(len(r.frozen) for r in rhs), rhs_outputs=names, rhs_mb=names.index("Mb"),
            rhs_j=names.index("J_red"), rhs_reasons=[reasons(r) for r in rhs],
            alpha=index["alpha"], dtheta=index["der(theta)"], kernel_at=index[outputs[0]],
            effort_at=outputs.index(mech.effort.name),
            friction=int(friction),
            drive_p=mech.kernel_parameters.index(direction) if friction else -1,
            plain_rhs=[] if frictionless is None else
            [g.c_source(array=False, prefix=f"g{s}") for s, g in enumerate(plain_rhs)],
            n_g=0 if frictionless is None else max(len(g.frozen) for g in plain_rhs),
            plain_rhs_reasons=[] if frictionless is None else [reasons(g) for g in plain_rhs])
    plain = dict(plain_kernels=()) if frictionless is None else dict(
        plain_kernels=[k.c_source(array=False, prefix=f"f{s}", tangent=not drive)
                       for s, k in enumerate(plains)],
        plain_parameters=[vr_of[n] for n in plains[0].parameters],
        n_q0=max(len(k.frozen) for k in plains), plain_reasons=[reasons(k) for k in plains],
        friction_parameters=[vr_of[n] for n in sorted(frictionless[1])])
    source = _C.get_template("model.c").render(**plain,
        model=model_name(mech, drive),
        kernels=[k.c_source(array=False, prefix=f"s{s}", tangent=not drive)
                 for s, k in enumerate(kernels)],
        parameters=[vr_of[n] for n in mech.kernel_parameters],
        n_q=max(len(k.frozen) for k in kernels), built=words or "one structure",
        cond=outputs.index("cond") if "cond" in outputs else -1,
        integers=[vr_of[n] for n in integers], strings=[vr_of[n] for n in strings],
        checked=[int(i in kernels[0].checked) for i in range(len(outputs))],
        structures=[{"integers": [c[n] for n in integers], "strings": [str(c[n]) for n in strings],
                     "reasons": reasons(k)} for c, k in zip(built, kernels)],
        drive=drive, **drive_tables)
    return source, built


#: the outputs of the drive FMU's kernel of its motion: the balancing moment and the
#: inertia reduced to the crank (without friction no reaction is solved for: at ``alpha =
#: 0`` they give Eksergian's equation; with it, tau = Mb(alpha) is solved by Newton)
RHS_OUTPUTS = ("Mb", "J_red")


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
