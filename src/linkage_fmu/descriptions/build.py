"""From a checked description and parameter values to a Mechanism."""

from __future__ import annotations

import functools
import math
import warnings
from pathlib import Path

from .. import numerics
from ..bodies import Body, Effort
from ..errors import InputError, LinkageError, LoadError, NearSingularWarning, OutputError
from ..expressions import Expression
from ..friction import Declared, Friction
from ..groups import Group, LinkJoints
from ..kernels.trace import Reason
from ..loads import Load
from ..mechanism import Mechanism
from ..outputs import EffortOutput, Output
from ..parameters import resolve
from ..tables import PeriodicTable
from .assur import body_table
from .checker import driver_efforts
from .schema import INPUT_NAMES


def build(d, given: dict, symbols: dict | None = None, friction: bool = False) -> Mechanism:
    """The linkage ``d`` (checked) with the parameter values ``given`` over its defaults.

    With ``symbols`` (parameter name -> traced number, see
    :mod:`~linkage_fmu.kernels.trace`), those parameters enter as the traced numbers:
    everything computed from them is recorded, so a kernel takes them as arguments.
    The friction of the joints is solved where a ``mu`` is not 0, or with ``friction``
    (an FMU, whose parameters change after it is built); otherwise its parameters are
    no kernel arguments (:class:`~linkage_fmu.friction.Declared`).
    Their values were checked as floats (``given``); the rules on computed values (every
    one finite, a length > 0) are recorded as checks of the kernel's parameter step, so
    that it refuses exactly the parameter sets this function refuses. The mechanism can
    build itself again this way (its ``rebuild``).

    Raises
    ------
    TypeError
        An unknown parameter name.
    ValueError
        An invalid parameter value, or a value computed from the parameters that the
        linkage cannot take (a length that is not positive, ...), naming it.
    """
    params = resolve(d.parameter_specs(), given, d.name)
    origin = _origin(d)
    numbers = {k: v for k, v in params.items() if isinstance(v, (int, float))}
    floats = dict(numbers)
    if symbols:
        numbers.update(symbols)
        params = {**params, **symbols}

    def number(where: str, source, rule: str = "") -> float:
        try:
            x = _parsed(source)(numbers)
        except (ValueError, ZeroDivisionError, OverflowError) as err:
            raise InputError(f"{origin}: {where} = {source!r}: {err}") from None
        if hasattr(x, "traced"):  # recorded as checks of the parameter step
            abs(x) < math.inf  # noqa: B015 -- false for inf and NaN
            numerics.label(x, Reason("parameter", f"{where} = {source!r} is not finite"))
            if rule == "length":
                x > 0.0  # noqa: B015
                numerics.label(x, Reason("parameter", f"{where} = {source!r} must be > 0"))
            elif rule in ("friction", "distance"):
                x >= 0.0  # noqa: B015
                numerics.label(x, Reason("parameter", f"{where} = {source!r} must be >= 0"))
            elif rule == "sign":
                abs(abs(x) - 1.0) <= 0.0  # noqa: B015 -- an order comparison: recorded
                numerics.label(x, Reason("parameter", f"{where} = {source!r} must be +1 or -1"))
            return x
        # an expression's value is said after it; a number's once
        said = f"{where} = {source!r}" + (f" = {x!r}" if isinstance(source, str) else "")
        if not math.isfinite(x):
            raise InputError(f"{origin}: {said} is not finite")
        if rule == "length" and not x > 0.0:
            raise InputError(f"{origin}: {said} must be > 0")
        if rule == "branch" and x == 0.0 and isinstance(source, str):
            return x  # a mode drawn at a toggle: the group says which (groups.base.mode)
        if rule in ("branch", "sign") and x not in (1.0, -1.0):
            raise InputError(f"{origin}: {said} must be +1 or -1")
        if rule in ("friction", "distance") and not x >= 0.0:
            raise InputError(f"{origin}: {said} must be >= 0")
        return x

    def start(where: str, source) -> float:
        """A start value: of the parameters' values, never traced."""
        try:
            return _parsed(source)(floats)
        except (ValueError, ZeroDivisionError, OverflowError) as err:
            raise InputError(f"{origin}: {where} = {source!r}: {err}") from None

    def vector(where: str, xy) -> tuple:
        return number(where + " x", xy[0]), number(where + " y", xy[1])

    frame_points = {name: vector(f"[points] {name}", xy) for name, xy in d.points.items()}
    groups = []
    placed = set(frame_points)
    for k, spec in enumerate(d.groups):
        cls = Group.registry[spec["type"]]
        where = f"[[groups]] #{k + 1} ({spec['type']})"

        def value(key, spec=spec, cls=cls, where=where, placed=frozenset(placed)):
            role = cls.FIELDS[key].role
            if role == "vector":
                return vector(f"{where} {key}", spec[key])
            if role == "pose":
                return {p: vector(f"{where} {key} {p}", xy) for p, xy in spec[key].items()}
            if role == "link joints":
                links = {link: tuple(joints) for link, joints in spec[key].items()}
                return LinkJoints(links, placed & {p for js in links.values() for p in js})
            x = number(f"{where} {key}", spec[key], role)
            # a mode the parameters draw is traced with them (the group checks it)
            return int(x) if role == "branch" and not hasattr(x, "traced") else x

        try:
            groups.append(cls.from_spec(spec, value))
        except ValueError as err:
            raise InputError(f"{origin}: {err}") from None
        placed.update(groups[-1].places)

    bodies = []
    for link, spec in d.bodies.items():
        where = f"[bodies.{link}]"
        cg = spec["cg"]
        place = {key: number(f"{where} cg {key}", cg[key])
                 for key in ("along", "across", "distance", "angle") if key in cg}
        mass, inertia = number(f"{where} mass", spec["mass"]), number(f"{where} inertia",
                                                                      spec["inertia"])
        try:
            bodies.append(Body(link, mass, inertia, cg["from"], **place))
        except ValueError as err:  # written as joints and links: its [[links]] table
            raise InputError(f"{origin}: {body_table(d.drawn, link)}: {err}") from None

    loads = []
    for spec in d.loads:
        where = f"[[loads]] {spec['name']}"
        direction = (vector(f"{where} direction", spec["direction"])
                     if spec["kind"] == "force" else (0.0, 0.0))
        over_cycle = {}
        if "value" in spec:
            over_cycle = dict(value=Expression(spec["value"]), parameters=numbers)
        elif "table" in spec:
            rows = tuple(tuple(map(float, r)) for r in spec["table"])
            scale = spec.get("scale", 1.0)
            if spec.get("table_unit"):
                scale = f"1 {spec['table_unit']} * ({scale})"
            over_cycle = dict(table=_table(rows, float(spec["period_deg"]), where),
                              scale=number(f"{where} scale", scale))
        value = start(f"{where} start", spec.get("start", 0.0))
        try:
            loads.append(Load(spec["name"], spec["body"], spec["kind"], spec.get("at", ""),
                              direction, spec.get("fixed_in", "frame"), spec.get("unit", ""),
                              spec.get("description", ""), value, **over_cycle))
        except LoadError as err:  # the load's table: [[loads]] NAME
            raise InputError(f"{origin}: {where}: {err.problem}") from None
        except ValueError as err:
            raise InputError(f"{origin}: {where}: {err}") from None

    chosen, effort = None, None
    if driver_efforts(d.groups):  # its drivers apply the efforts
        chosen = {}
    for when, spec in d.efforts.items():
        if when is None or params[when[0]] == when[1]:
            chosen = spec
    if chosen is None:
        options = [w[1] for w in d.efforts]
        raise InputError(f"{origin}: no [effort] option for {next(iter(d.efforts))[0]} = "
                         f"{params[next(iter(d.efforts))[0]]!r}; the options are "
                         + ", ".join(map(repr, options)))
    if chosen:
        effort = Effort(chosen["name"], chosen["body"], chosen.get("at", ""),
                        _unit(vector("[effort] direction", chosen["direction"]))
                        if "direction" in chosen else None)

    outputs, keys = [], {}  # keys: output name -> where the description declares it
    for k, spec in enumerate(d.outputs):
        made = Output.registry[spec["kind"]].from_spec(spec, d)
        keys.update((o.name, f"[[outputs]] #{k + 1} ({spec['name']})") for o in made)
        outputs += made
    for name in dict.fromkeys(e["name"] for e in d.efforts.values()):  # always reported
        if name not in keys:
            outputs += EffortOutput.from_spec({"name": name}, d)
    declared = _friction(d, number, friction)

    def rebuild(traced: dict) -> Mechanism:
        return build(d, given, traced, declared.active)

    gravity = number("[linkage] gravity", d.gravity)
    inputs = {k: start(f"[inputs] {k}", v) for k, v in d.inputs.items()
              if not (effort is None and k in INPUT_NAMES)}  # a crank's, not the drivers
    try:
        mech = Mechanism(d.name, d.frame, frame_points, groups, bodies, effort, outputs, loads,
                         gravity, params, d, rebuild, inputs, declared)
    except OutputError as err:  # the output's table: [[outputs]] #3 (F03) for F03x
        text = f"{keys[err.output]}: {err.problem}" if err.output in keys else str(err)
        raise InputError(f"{origin}: {text}") from None
    except LinkageError as err:  # named by its description's file, not its name
        raise InputError(f"{origin}: {err.problem}") from None
    except ValueError as err:
        if type(err) is not ValueError:
            raise
        raise InputError(f"{origin}: {err}") from None
    if d.drawn is not None and symbols:  # the parameter step refuses what the pose check does
        from .assur import SLIDE_TOLERANCE

        for what, off in d.drawn.checks:
            x = number(what, off)
            x <= SLIDE_TOLERANCE  # noqa: B015 -- an order comparison of parameters: recorded
            numerics.label(x, Reason("parameter", what))
    if d.drawn is not None and not symbols:  # written as joints and links: where drawn
        from .assur import check_pose, near_toggles

        problem = check_pose(mech, d.drawn, floats)
        if problem:
            raise InputError(f"{origin}: {problem}")
        for note in near_toggles(mech, d.drawn, floats):
            warnings.warn(f"{origin}: {note}", NearSingularWarning, stacklevel=3)
    return mech


def _origin(d) -> str:
    """How messages name the description ``d``: its file, or its name where it has none
    the user wrote (a preset's file is in the package; one made in Python has none)."""
    if d.source.startswith("<") or Path(d.source).parent == Path(__file__).parents[1] / "linkages":
        return d.name
    return d.source


def _friction(d, number, forced: bool) -> Declared:
    """The friction of the description ``d``'s joints, its values by ``number``."""
    if not d.friction:
        return Declared()
    frictions = []
    for joint, spec in d.friction.items():
        where = f"[friction.{joint}]"
        frictions.append(Friction(joint, number(f"{where} mu", spec["mu"], "friction"),
                                  *(number(f"{where} {k}", spec[k], rule)
                                    if k in spec else None
                                    for k, rule in (("radius", "distance"), ("length", "length")))))
    drive = number("[linkage] drive", d.drive, "sign")
    active = forced or any(hasattr(f.mu, "traced") or f.mu != 0.0 for f in frictions)
    return Declared(tuple(frictions), drive, active, d.friction_parameters())


@functools.lru_cache(maxsize=4096)
def _parsed(source) -> Expression:
    """The parsed expression ``source``, parsed once (descriptions are built again for
    every parameter set, and one written as joints and links has long expressions)."""
    return Expression(source)


@functools.lru_cache(maxsize=32)
def _table(rows: tuple, period_deg: float, where: str) -> PeriodicTable:
    """The spline of a load's table, made once per table (descriptions are built again
    for every parameter set)."""
    return PeriodicTable([r[0] for r in rows], [r[1] for r in rows], period_deg, where)


def _unit(v: tuple) -> tuple:
    n = numerics.hypot(*v)
    if not n > 0.0:
        raise InputError(f"direction {v!r} has no length")
    return v if n == 1.0 else (v[0] / n, v[1] / n)

