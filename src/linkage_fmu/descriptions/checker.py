"""Checking a description: every problem at once, each naming its table and key.

:class:`Checker` runs one method per table of a description (:mod:`.schema` lists what
each takes); :meth:`Description.check <linkage_fmu.descriptions.Description.check>` and
the reader of description files report what it finds.
"""

from __future__ import annotations

import math
import re
import warnings
from typing import Any

from ..drivers import EFFORTS
from ..drivers import KINDS as DRIVER_KINDS
from ..errors import ParameterError
from ..expressions import Expression, check_units
from ..groups import OWNER, Field, Group, LinkJoints
from ..outputs import SHAKING, Output
from ..parameters import KINDS, Parameter
from ..units import unit_problem
from .schema import (
    CG_KEYS,
    EFFORT_KEYS,
    FRICTION_KEYS,
    INPUT_NAMES,
    INPUT_UNITS,
    LOAD_KEYS,
    TABLE_DEFAULTS,
)

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


#: a driver's input's name (before ``_<j>``) -> its unit
DRIVER_INPUTS = {n: u for names, units in DRIVER_KINDS.values() for n, u in zip(names, units)}


def driver_inputs(groups: list) -> tuple[str, ...]:
    """The names of the inputs of the drivers of the group tables ``groups``:
    ``theta``, ``omega``, ``alpha`` for one crank on the frame, else each driver's
    three named after its pair.

    Examples
    --------
    >>> driver_inputs([{"type": "cylinder", "pair": "P"}, {"type": "RRR"}])
    ('s_P', 'v_P', 'a_P')
    >>> driver_inputs([{"type": "crank", "pivot": "A"}])
    ('theta', 'omega', 'alpha')
    """
    if not driver_efforts(groups):
        return INPUT_NAMES
    return tuple(f"{name}_{pair}" for pair, kind, _ in _drives(groups)
                 for name in DRIVER_KINDS[kind][0])


def _drives(groups: list) -> list:
    """What each driver of the group tables ``groups`` drives, (pair, kind, by time)."""
    drives = []
    for spec in groups:
        cls = Group.registry.get(spec.get("type")) if isinstance(spec, dict) else None
        if cls is not None and cls.DRIVER and cls.drives(spec) is not None:
            drives.append(cls.drives(spec))
    return drives


def driver_efforts(groups: list) -> dict:
    """Effort name -> unit of each driver of the group tables ``groups`` when they
    drive the linkage by time (several drivers, a motor, a cylinder: ``Mb_<j>`` in N.m,
    ``Fb_<j>`` in N); empty for one crank on the frame, whose effort an [effort] names.

    Examples
    --------
    >>> driver_efforts([{"type": "crank", "pivot": "A"}, {"type": "crank", "pivot": "E"}])
    {'Mb_A': 'N.m', 'Mb_E': 'N.m'}
    >>> driver_efforts([{"type": "crank", "pivot": "A"}, {"type": "RRR"}])
    {}
    """
    drives = _drives(groups)
    if len(drives) < 2 and not any(timed for _, _, timed in drives):
        return {}
    return {f"{EFFORTS[kind]}_{pair}": ("N.m" if kind == "angle" else "N")
            for pair, kind, _ in drives}


def _finite(value: Any) -> bool:
    return not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value)


def is_identifier(name: Any) -> bool:
    """Whether ``name`` may name a parameter, load, output or model: letters, digits and
    ``_``, not a digit first.

    Examples
    --------
    >>> is_identifier("l_AB"), is_identifier("2nd"), is_identifier(3)
    (True, False, False)
    """
    return isinstance(name, str) and bool(_IDENTIFIER.match(name))


class Checker:
    """Every problem of a description, each naming its table and key.

    One method per table, run in the order of the messages; what a table defines for
    the later ones (points placed, links added, pairs, load names) is kept here. Group
    types are known only through their contract (``FIELDS``, ``OPTIONAL``, ``DRIVER``,
    ``pairs``), and output kinds through theirs (``KEYS``, ``check``:
    :class:`~linkage_fmu.outputs.Output`), so a new type or kind is checked like the
    shipped ones.

    Examples
    --------
    >>> from linkage_fmu.descriptions import Description
    >>> d = Description("demo", model="Demo").point("A", 0, 0)
    >>> for problem in Checker(d).problems():
    ...     print(problem)
    [[groups]]: there are none; the first must be the crank or cylinder
    [effort]: missing: where does the balancing effort act?
    [[outputs]]: there are none
    """

    def __init__(self, d: "Description"):  # noqa: F821 -- .description imports this
        self.d = d
        self.found: list[str] = []
        self.placed: dict[str, str] = {}  # point -> where it was placed
        self.links: dict[str, str] = {}  # moving link -> where it was added
        self.joints: dict[str, str] = {}  # pair -> where it was made
        self.prismatic: set = set()  # the pairs that slide
        #: moving link -> the points on it (its joints', those placed on it), and point
        #: -> the link that owns it; None once a group could not be read for them
        self.on: dict[str, set] | None = {}
        self.owner: dict[str, str] = {}
        self.load_names: list = []
        # names a load or output cannot take: inputs, parameters, the outputs every
        # linkage has
        self.taken = set(INPUT_NAMES) | set(d.parameters) | set(SHAKING) | {"cond"}
        #: name -> (value, unit) of each parameter, to check the units of expressions
        self.measures: dict[str, tuple] = {}
        #: name -> default value of each parameter that has a valid one
        self.values: dict[str, Any] = {}
        #: what is allowed but probably not meant (a plain angle above 2 pi)
        self.notes: list[str] = []

    def problems(self) -> list[str]:
        """Check every table (once per checker); the problems, in the order of the tables."""
        for table in (self.linkage, self.parameters, self.inputs, self.points, self.groups,
                      self.bodies, self.loads, self.effort, self.outputs, self.friction):
            table()
        return self.found

    def warn(self) -> None:
        """A warning for each value that is allowed but probably not meant."""
        for note in self.notes:
            warnings.warn(f"{self.d.source}: {note}", UserWarning, stacklevel=4)

    # -- helpers ----------------------------------------------------------------------
    def expr(self, where: str, value: Any, names: set | None = None, unit: str = "",
             measures: dict | None = None) -> None:
        """An expression over the parameters (or over ``names``); with numbers that carry
        units, it must measure what ``unit`` does (its names measured by ``measures``,
        default the parameters'). A plain angle beyond 2 pi is noted."""
        try:
            e = Expression(value)
        except ValueError as err:
            self.found.append(f"{where}: {err}")
            return
        known = self.d.parameters if names is None else names
        unknown = [n for n in e.names if n not in known]
        if unknown:
            which = "is not a parameter" if len(unknown) == 1 else "are not parameters"
            self.found.append(f"{where}: {value!r} uses {', '.join(map(repr, unknown))}, which "
                              f"{which}")
            return
        if unit and e.has_units:
            try:
                check_units(e, unit, where, {**self.measures, **(measures or {})})
            except ValueError as err:
                self.found.append(str(err))
        elif unit == "rad" and _finite(value) and abs(value) > 2.0 * math.pi:
            self.notes.append(f"{where} = {value!r} is taken in radians ({math.degrees(value):g}"
                              f" deg); write \"{value!r} deg\" for degrees")

    def not_negative(self, where: str, value: Any, unit: str) -> None:
        """A value that must be >= 0 (a mass, an inertia), at the parameters' defaults;
        one that cannot be evaluated there is said by the other checks."""
        try:
            x = Expression(value)(self.values)
        except (ValueError, TypeError, ZeroDivisionError, OverflowError):
            return
        if not (math.isfinite(x) and x >= 0.0):
            said = f"{value!r}" + (f" = {x!r}" if isinstance(value, str) else "")
            self.found.append(f"{where}: {said} must be a finite number >= 0 ({unit})")

    def vector(self, where: str, value: Any, unit: str = "") -> bool:
        """``[x, y]`` of expressions (of ``unit``); False if it is not a pair."""
        if not (isinstance(value, (list, tuple)) and len(value) == 2):
            self.found.append(f"{where}: must be [x, y]")
            return False
        self.expr(f"{where} x", value[0], unit=unit)
        self.expr(f"{where} y", value[1], unit=unit)
        return True

    # -- the tables -------------------------------------------------------------------
    def linkage(self) -> None:
        model = self.d.model
        if not model:
            self.found.append(
                "[linkage] model: missing or empty: the model identifier of the linkage's "
                "FMUs is required, a C identifier such as \"FourBar\" (letters, digits and _, "
                "not a digit first)" + ("; written as joints and links, a file without the "
                                        "key takes its name where that is one"
                                        if self.d.drawn is not None else ""))
        elif not is_identifier(model):
            self.found.append(f"[linkage] model: {model!r} must be a C identifier (the "
                              "FMU's model identifier)")
        self.expr("[linkage] gravity", self.d.gravity, unit="m/s2")
        self.expr("[linkage] drive", self.d.drive)

    def parameters(self) -> None:
        for name, p in self.d.parameters.items():
            where = f"[parameters] {name}"
            if not _IDENTIFIER.match(name):
                self.found.append(f"{where}: not an identifier")
            if name in INPUT_NAMES:
                self.found.append(f"{where}: {name} is an input, not a parameter")
            if p["kind"] not in KINDS:
                self.found.append(f"{where}: kind {p['kind']!r} is unknown; the kinds are "
                                  f"{', '.join(KINDS)}")
                continue
            try:
                spec = Parameter(name, p["default"], p["kind"], p["description"],
                                 p["choices"], p["min"], p["max"])
            except ParameterError as err:  # a bound the kind cannot have
                self.found.append(f"{where}: {err.problem}")
                continue
            try:
                value = spec.validate(p["default"])
            except (TypeError, ValueError) as err:
                self.found.append(f"{where}: default: {err}")
                continue
            self.values[name] = value
            if spec.unit:
                self.measures[name] = (float(value), spec.unit)

    def inputs(self) -> None:
        for key, value in self.d.inputs.items():
            if key in INPUT_UNITS:
                self.expr(f"[inputs] {key}", value, unit=INPUT_UNITS[key])
            elif "_" in key and key.split("_")[0] in DRIVER_INPUTS:
                self.expr(f"[inputs] {key}", value, unit=DRIVER_INPUTS[key.split("_")[0]])

    def points(self) -> None:
        for name, xy in self.d.points.items():
            if self.vector(f"[points] {name}", xy, "m"):
                self.placed[name] = f"[points] {name}"

    def groups(self) -> None:
        if not self.d.groups:
            self.found.append(f"[[groups]]: there are none; the first must be the "
                              f"{self.drivers()}")
        for k, spec in enumerate(self.d.groups):
            self.group(k, spec)

    def bodies(self) -> None:
        for link, where in self.links.items():
            if link not in self.d.bodies:
                self.found.append(f"[bodies.{link}]: missing: link {link!r} ({where}) needs a "
                                  "body (mass, inertia, cg)")
        for link, spec in self.d.bodies.items():
            self.body(f"[bodies.{link}]", link, spec)

    def loads(self) -> None:
        for k, spec in enumerate(self.d.loads):
            self.load(k, spec)

    def effort(self) -> None:
        by_time = driver_efforts(self.d.groups)
        if by_time and self.d.efforts:
            self.found.append(f"[effort]: the linkage is driven by {len(by_time)} driver(s), "
                              f"each with its own effort ({', '.join(by_time)}): it takes "
                              "no [effort]")
            return
        if not self.d.efforts and not by_time:
            self.found.append("[effort]: missing: where does the balancing effort act?")
        for when, spec in self.d.efforts.items():
            self.effort_option(when, spec)

    def outputs(self) -> None:
        names: list = []
        for k, spec in enumerate(self.d.outputs):
            self.output(k, spec, names)
        if not self.d.outputs:
            self.found.append("[[outputs]]: there are none")

    # -- groups -----------------------------------------------------------------------
    @staticmethod
    def drivers() -> str:
        """The driver types, for messages."""
        return " or ".join(sorted(k for k, cls in Group.registry.items() if cls.DRIVER))

    def group(self, k: int, spec: dict) -> None:
        kind = spec.get("type")
        cls = Group.registry.get(kind)
        if cls is None:
            self.found.append(f"[[groups]] #{k + 1} type: {kind!r} is not a group type; the "
                              f"types are {', '.join(sorted(Group.registry))}")
            return
        where = f"[[groups]] #{k + 1} ({kind})"
        before = frozenset(self.placed)
        if k == 0 and not cls.DRIVER:
            self.found.append(f"{where}: the first group must be the {self.drivers()}")
        if cls.DRIVER and cls.drives(spec) is not None:
            pair = cls.drives(spec)[0]
            earlier = [f"[[groups]] #{i + 1}" for i, s in enumerate(self.d.groups[:k])
                       if Group.registry.get(s.get("type")) is not None and
                       Group.registry[s["type"]].DRIVER and
                       (Group.registry[s["type"]].drives(s) or ("",))[0] == pair]
            if earlier:
                self.found.append(f"{where}: the pair {pair} is driven twice (also by "
                                  f"{earlier[0]}): a pair has one driver")
        for key in spec:
            if key != "type" and key not in cls.FIELDS:
                self.found.append(f"{where} {key}: unknown field; a {kind} has "
                                  f"{', '.join(cls.FIELDS)}")
        added: dict[str, list] = {"new point": [], "new link": []}
        for key, f in cls.FIELDS.items():
            if key in spec:
                self.field(f"{where} {key}", f, spec[key], added)
            elif key not in cls.OPTIONAL:
                self.found.append(f"{where} {key}: missing")
        self.found += [f"{where} {problem}" for problem in cls.problems(spec, before)]
        # placed and added once the whole group is read: no field uses another's
        self.placed.update(dict.fromkeys(added["new point"], where))
        self.links.update(dict.fromkeys(added["new link"], where))
        for joint in cls.pairs(spec, before):
            if joint in self.joints:
                self.found.append(f"{where}: joint {joint!r} is already a pair of "
                                  f"{self.joints[joint]}: a point may join two links only; "
                                  "name the points apart")
            self.joints[joint] = where
        self.prismatic.update(spec[k] for k, f in cls.FIELDS.items()
                              if f.role == "new joint" and isinstance(spec.get(k), str))
        self.points_on_links(cls, spec, before)

    def points_on_links(self, cls: type, spec: dict, before: frozenset) -> None:
        """Which points the group puts on which link: built with stand-in numbers (its
        pairs and points are names, whatever the numbers); a group that cannot be built
        so (a problem listed above) ends this bookkeeping, and the linkage's own check
        refuses a load off its body then."""
        if self.on is None:
            return
        stand_in = {"vector": (1.0, 0.0), "branch": 1}

        def value(key):
            role = cls.FIELDS[key].role
            if role == "pose":
                return dict.fromkeys(spec[key], (1.0, 0.0))
            if role == "link joints":
                links = {link: tuple(joints) for link, joints in spec[key].items()}
                return LinkJoints(links, before & {p for js in links.values() for p in js})
            return stand_in.get(role, 1.0)

        try:
            grp = cls.from_spec(spec, value)
            joints, owners = grp.joints, dict(grp.owners)
        except Exception:  # noqa: BLE001 -- a group with problems: listed by the checks
            self.on = None
            return
        for point, link in owners.items():
            self.on.setdefault(link, set()).add(point)
        for j in joints:
            a = self.owner.get(j.point, owners.get(j.point)) if j.a == OWNER else j.a
            for link in (a, j.b):
                self.on.setdefault(link, set()).add(j.point)
        self.owner.update(owners)

    def friction(self) -> None:
        for joint, spec in self.d.friction.items():
            where = f"[friction.{joint}]"
            if joint not in self.joints:
                self.found.append(f"{where}: {joint!r} is no pair of the linkage; its pairs "
                                  f"are {', '.join(self.joints) or 'none'}")
                continue
            unknown = set(spec) - set(FRICTION_KEYS)
            if unknown:
                self.found.append(f"{where}: unknown key(s) {', '.join(sorted(unknown))}; the "
                                  f"keys are {', '.join(FRICTION_KEYS)}")
            sliding = joint in self.prismatic
            needed = ("mu",) if sliding else ("mu", "radius")
            for key in needed:
                if key not in spec:
                    self.found.append(f"{where} {key}: missing")
            wrong = "radius" if sliding else "length"
            if wrong in spec:
                self.found.append(f"{where} {wrong}: a {'prismatic' if sliding else 'revolute'} "
                                  f"pair has no {wrong}")
            for key, unit in (("mu", ""), ("radius", "m"), ("length", "m")):
                if key in spec and key != wrong:
                    self.expr(f"{where} {key}", spec[key], unit=unit)

    def field(self, where: str, f: Field, value: Any, added: dict[str, list]) -> None:
        """One field of a group, by its role; new points and links go to ``added``."""
        role = f.role
        if f.is_name:
            if not isinstance(value, str) or not value:
                self.found.append(f"{where}: must be a name")
            elif role == "point" and value not in self.placed:
                self.found.append(f"{where}: point {value!r} is not placed before this group "
                                  f"(placed so far: {', '.join(self.placed) or 'none'})")
            elif role == "link" and value not in self.links:
                self.found.append(f"{where}: link {value!r} is not added by an earlier group")
            elif role in added:
                self.new_name(where, role, value)
                added[role].append(value)
        elif role == "vector":
            self.vector(where, value, f.unit)
        elif role == "link joints":
            self.link_joints(where, value, added)
        elif role == "pose":
            if not isinstance(value, dict) or not value:
                self.found.append(f"{where}: must be a table {{ POINT = [x, y], ... }}")
                return
            for point, xy in value.items():
                self.vector(f"{where} {point}", xy, f.unit)
        else:
            self.expr(where, value, unit=f.unit)

    def link_joints(self, where: str, value: Any, added: dict[str, list]) -> None:
        """New links, each with its joints: the points not placed yet are new points."""
        if not isinstance(value, dict) or not value:
            self.found.append(f"{where}: must be a table {{ LINK = [POINT, POINT, ...], ... }}")
            return
        for link, joints in value.items():
            at = f"{where} {link}"
            self.new_name(at, "new link", link)
            added["new link"].append(link)
            if not isinstance(joints, (list, tuple)) or not all(
                    isinstance(p, str) and p for p in joints):
                self.found.append(f"{at}: must be a list of point names")
                continue
            if len(joints) < 2:
                self.found.append(f"{at}: a link has two joints or more; it has {len(joints)}")
            twice = [p for k, p in enumerate(joints) if p in joints[:k]]
            if twice:
                self.found.append(f"{at}: lists {twice[0]} twice")
            for p in joints:
                if p not in self.placed and p not in added["new point"]:
                    added["new point"].append(p)

    def new_name(self, where: str, role: str, value: str) -> None:
        """A point or link a group adds must not be there yet."""
        if role == "new point" and value in self.placed:
            self.found.append(f"{where}: point {value!r} is already placed by "
                              f"{self.placed[value]}")
        elif role == "new link" and value == self.d.frame:
            self.found.append(f"{where}: link {value!r} is already the frame")
        elif role == "new link" and value in self.links:
            self.found.append(f"{where}: link {value!r} is already added by "
                              f"{self.links[value]}")

    # -- bodies, loads, effort ----------------------------------------------------------
    def body(self, where: str, link: str, spec: dict) -> None:
        if link not in self.links:
            self.found.append(f"{where}: no group adds a link {link!r}: a body without a link")
            return
        for key, unit in (("mass", "kg"), ("inertia", "kg.m2")):
            self.expr(f"{where} {key}", spec[key], unit=unit)
            self.not_negative(f"{where} {key}", spec[key], unit)
        cg = spec["cg"]
        if not isinstance(cg, dict) or "from" not in cg:
            self.found.append(f"{where} cg: needs {{ from = POINT, along = ..., across = ... }}")
            return
        unknown = set(cg) - set(CG_KEYS)
        if unknown:
            self.found.append(f"{where} cg: unknown key(s) {', '.join(sorted(unknown))}; the "
                              "keys are from, along, across (or distance, angle)")
        if ({"along", "across"} & set(cg)) and ({"distance", "angle"} & set(cg)):
            self.found.append(f"{where} cg: give along/across or distance/angle, not both")
        if cg["from"] not in self.placed:
            self.found.append(f"{where} cg from: point {cg['from']!r} is not placed")
        elif self.on is not None:  # the point its centre of mass is placed from: on it
            self.on.setdefault(link, set()).add(cg["from"])
        for key in ("along", "across", "distance", "angle"):
            if key in cg:
                self.expr(f"{where} cg {key}", cg[key], unit="rad" if key == "angle" else "m")

    def load(self, k: int, spec: dict) -> None:
        name = spec.get("name", "")
        where = f"[[loads]] #{k + 1} ({name or 'no name'})"
        unknown = set(spec) - set(LOAD_KEYS)
        if unknown:
            self.found.append(f"{where}: unknown key(s) {', '.join(sorted(unknown))}")
        if not is_identifier(name):
            self.found.append(f"{where} name: {name!r} must be an identifier")
        elif name in self.taken or name in self.load_names:
            self.found.append(f"{where} name: {name!r} is already an input or parameter name")
        self.load_names.append(name)
        if spec.get("body") not in self.links:
            self.found.append(f"{where} body: {spec.get('body')!r} is not a moving link")
        kind = spec.get("kind")
        if kind == "force":
            self.force_load(where, spec)
        elif kind == "moment":
            for key in ("at", "direction"):
                if key in spec:
                    self.found.append(f"{where} {key}: a moment has no {key}")
        else:
            self.found.append(f"{where} kind: {kind!r} must be 'force' or 'moment'")
        unit = {"force": "N", "moment": "N.m"}.get(kind, "")
        if spec.get("unit", "") not in ("", unit):
            self.found.append(f"{where} unit: {spec['unit']!r}: a load is in SI, "
                              f"{unit or 'N or N.m'}; a value with a unit is converted")
        if "value" in spec or "table" in spec:
            self.cycle_load(where, spec, unit)
        else:
            for key in TABLE_DEFAULTS:
                if key in spec:
                    self.found.append(f"{where} {key}: only a load given by a table has it")
            self.expr(f"{where} start", spec.get("start", 0.0), unit=unit)

    def cycle_load(self, where: str, spec: dict, unit: str) -> None:
        """A load over the cycle: ``value`` = EXPR, or ``table`` with its keys."""
        if spec.get("start", 0.0) != 0.0:
            self.found.append(f"{where} start: a load over the cycle is computed, it has no "
                              "start value")
        if "value" in spec and "table" in spec:
            self.found.append(f"{where}: give value or table, not both")
            return
        if "value" in spec:
            for key in TABLE_DEFAULTS:
                if key in spec:
                    self.found.append(f"{where} {key}: only a load given by a table has it")
            points = [p for p in self.placed]
            positions = {f"{a}_{p}": (0.1, "m") for p in points for a in "xy"}
            self.expr(f"{where} value", spec["value"],
                      set(self.d.parameters) | {"theta"} | set(positions), unit,
                      {"theta": (0.3, "rad"), **positions})
            return
        from ..tables import PeriodicTable

        rows, period = spec["table"], spec.get("period_deg", 360.0)
        if not _finite(period) or not period > 0:
            self.found.append(f"{where} period_deg: {period!r} must be a number > 0 (degrees)")
        elif not isinstance(rows, list) or not all(
                isinstance(r, (list, tuple)) and len(r) == 2 and all(map(_finite, r))
                for r in rows):
            self.found.append(f"{where} table: must be a CSV file (columns theta_deg, value) or "
                              "a list of [theta_deg, value] pairs of numbers")
        else:
            try:
                PeriodicTable([r[0] for r in rows], [r[1] for r in rows], period)
            except ValueError as err:
                self.found.append(f"{where} table: {err}")
        table_unit = spec.get("table_unit", "")
        self.expr(f"{where} scale", spec.get("scale", 1.0), unit="" if table_unit else "1")
        if not isinstance(table_unit, str):
            self.found.append(f"{where} table_unit: must be a unit, such as \"bar\" or \"kN\"")
        elif table_unit:
            self.expr(f"{where} table_unit and scale",
                      f"1 {table_unit} * ({spec.get('scale', 1.0)})", unit=unit)

    def force_load(self, where: str, spec: dict) -> None:
        at, body = spec.get("at"), spec.get("body")
        if at not in self.placed:
            self.found.append(f"{where} at: a force needs the placed point it acts at, got "
                              f"{at!r}")
        elif self.on is not None and body in self.links and at not in self.on.get(body, ()):
            points = ", ".join(sorted(self.on.get(body, ())))
            self.found.append(f"{where} at: load {spec.get('name')} acts on body {body} at "
                              f"point {at}, which is not a point of body {body} (its points: "
                              f"{points})")
        self.vector(f"{where} direction", spec.get("direction"))
        if spec.get("fixed_in") not in ("frame", "link"):
            self.found.append(f"{where} fixed_in: must be 'frame' or 'link'")

    def effort_option(self, when: tuple | None, spec: Any) -> None:
        where = "[effort]" if when is None else f"[effort] options.{when[1]}"
        params = self.d.parameters
        if when is not None and (when[0] not in params or params[when[0]]["kind"] != "choice"):
            self.found.append(f"[effort] choose: {when[0]!r} is not a choice parameter")
        if not isinstance(spec, dict):
            self.found.append(f"{where}: must be a table")
            return
        unknown = set(spec) - set(EFFORT_KEYS)
        if unknown:
            self.found.append(f"{where}: unknown key(s) {', '.join(sorted(unknown))}")
        if spec.get("body") not in self.links:
            self.found.append(f"{where} body: {spec.get('body')!r} is not a moving link")
        if "at" in spec or "direction" in spec:
            if spec.get("at") not in self.placed:
                self.found.append(f"{where} at: {spec.get('at')!r} is not a placed point")
            self.vector(f"{where} direction", spec.get("direction"))

    # -- outputs ----------------------------------------------------------------------
    def output(self, k: int, spec: dict, used: list) -> None:
        """One output, checked by its kind; the names it gives must not be in ``used``
        (then they are)."""
        kind = spec.get("kind")
        where = f"[[outputs]] #{k + 1} ({spec.get('name', kind)})"
        cls = Output.registry.get(kind)
        if cls is None:
            self.found.append(f"{where} kind: {kind!r} is not one of "
                              f"{', '.join(Output.registry)}")
            return
        unknown = set(spec) - set(cls.KEYS) - {"kind"}
        if unknown:
            self.found.append(f"{where}: unknown key(s) {', '.join(sorted(unknown))}")
        name = spec.get("name")
        if not is_identifier(name):
            self.found.append(f"{where} name: {name!r} must be an identifier")
            return
        for n in cls.check(self, where, name, spec):
            if n in used or n in self.taken or n in self.load_names:
                self.found.append(f"{where}: output name {n!r} is used twice")
            used.append(n)

    def effort_names(self) -> set:
        """The names of the efforts of [effort], or of the drivers'."""
        return {spec.get("name") for spec in self.d.efforts.values() if isinstance(spec, dict)
                } | set(driver_efforts(self.d.groups))

    def unit(self, where: str, unit: Any) -> str:
        """An output's unit, which must be one of the package's (the output is computed
        in SI); the problem found ('' if none)."""
        problem = unit_problem(unit, where)
        if problem:
            self.found.append(problem)
        return problem
