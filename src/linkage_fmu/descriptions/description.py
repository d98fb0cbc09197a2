"""A linkage as data: a description, composed in Python or read from a TOML file.

:class:`Description` is the public builder; a description file is its serialisation,
one TOML table per builder call::

    [linkage]    name, title, model (the FMU's model identifier), frame (the frame's
                 body name in output names), gravity (along -y; default 0)
    [parameters] NAME = { default, kind, description, min, max, choices }
    [points]     NAME = [x, y]               frame points
    [[groups]]   type = "crank" | "RRR" | "RRP" | "RPP" | "RPR" | "point" | "closure", and
                 the type's fields, in an order in which every point is placed before use
    [bodies.L]   mass, inertia (about the centre of mass), cg = { from, along, across }:
                 the centre of mass in link L's own frame, measured from its point
                 ``from``: ``along`` the link's direction, ``across`` to its left; or
                 cg = { from, distance, angle }: ``angle`` counter-clockwise from the
                 link's direction
    [[loads]]    name, body, kind = "force" | "moment", at, direction = [x, y],
                 fixed_in = "frame" | "link", unit, description, and its magnitude:
                 start (an input), or value = EXPR (of theta, the parameters, x_P,
                 y_P), or table = "FILE.csv" | [[theta_deg, value], ...] with
                 period_deg, table_unit, scale (loads over the cycle)
    [effort]     name, body (a moment on a link), or at + direction (a force), or
                 choose = PARAMETER with options = { VALUE = {...} }
    [[outputs]]  kind = "force" | "normal" | "couple" | "effort" | "expression", ...
    [inputs]     start values of theta, omega, alpha

Numbers may be given as expressions of the parameters (:mod:`~.expressions`) and with
units (``"240 mm"``, ``"1800 rpm"``, :mod:`~linkage_fmu.units`); a plain number is SI,
an angle in radians. The keys each table takes are in :mod:`~.schema`;
``docs/description.md`` is the full reference (:mod:`~linkage_fmu.manual.reference`
writes it). :meth:`Description.build` checks everything (:mod:`~.checker`), reporting
every problem at once with the file, table and key, and returns a
:class:`~linkage_fmu.mechanism.Mechanism`.

Examples
--------
>>> d = (Description("demo", model="Demo", frame="0")
...      .parameter("r", 0.1, "length", "crank radius")
...      .point("A", 0, 0)
...      .group("crank", link="1", pivot="A", tip="B", length="r")
...      .body("1", mass=1.0, cg={"from": "A", "along": "r / 2"})
...      .load("T", body="1", kind="moment", description="torque on the crank")
...      .effort("Mb", body="1")
...      .output("effort", name="Mb"))
>>> mech = d.build()
>>> round(mech.solve(0.0, omega=2.0, T=3.0)["Mb"], 12)
-3.0
"""

from __future__ import annotations

import copy
import json
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import InputError, InputTypeError, LinkageFmuError
from ..expressions import Expression
from ..parameters import Parameter
from .checker import DRIVER_INPUTS, Checker, driver_efforts, driver_inputs, is_identifier
from .schema import (
    BODY_KEYS,
    CG_KEYS,
    EFFORT_CHOICE_KEYS,
    EFFORT_KEYS,
    FRICTION_KEYS,
    INPUT_NAMES,
    INPUT_UNITS,
    JOINT_TABLES,
    LINKAGE_KEYS,
    LOAD_DEFAULTS,
    LOAD_KEYS,
    OUTPUT_KEYS,
    OUTPUT_KINDS,
    PARAMETER_KEYS,
    TABLE_DEFAULTS,
    TABLES,
)

# the schema's mappings are read from here too (description.TABLES, ...)
__all__ = ["Description", "DescriptionError", "BODY_KEYS", "CG_KEYS", "EFFORT_CHOICE_KEYS",
           "EFFORT_KEYS", "FRICTION_KEYS", "INPUT_NAMES", "INPUT_UNITS", "JOINT_TABLES",
           "LINKAGE_KEYS", "LOAD_DEFAULTS", "LOAD_KEYS", "OUTPUT_KEYS", "OUTPUT_KINDS",
           "PARAMETER_KEYS", "TABLE_DEFAULTS", "TABLES"]


class DescriptionError(LinkageFmuError, ValueError):
    """A description with problems; ``problems`` lists every one of them."""

    def __init__(self, source: str, problems: list[str]):
        self.source, self.problems = source, list(problems)
        n = len(self.problems)
        if n == 1:  # one line: the file, the key, what is wrong
            super().__init__(f"{source}: {self.problems[0]}")
        else:
            super().__init__(f"{source}: {n} problems:\n"
                             + "\n".join(f"  {p}" for p in self.problems))


@dataclass
class Description:
    """The data of one linkage; each method adds one table and returns the description.

    Parameters
    ----------
    name : str
        Name of the linkage in messages (and of a shipped preset).
    title : str
        One line saying what it is.
    model : str
        Model identifier of its FMUs (a C identifier).
    frame : str
        Name of the frame body in output names.
    gravity : number or expression
        Gravitational acceleration along -y (usually the parameter ``g``).
    drive : number or expression
        The crank's drive direction, +1 or -1 (see :mod:`~linkage_fmu.friction`).
    source : str
        Where the description came from, for messages (a file path).
    """

    name: str
    title: str = ""
    model: str = ""
    frame: str = "0"
    gravity: Any = 0.0
    drive: Any = 1.0
    source: str = field(default="<python>", compare=False)
    parameters: dict = field(default_factory=dict)
    points: dict = field(default_factory=dict)
    groups: list = field(default_factory=list)
    bodies: dict = field(default_factory=dict)
    loads: list = field(default_factory=list)
    efforts: dict = field(default_factory=dict)
    outputs: list = field(default_factory=list)
    inputs: dict = field(default_factory=lambda: dict.fromkeys(INPUT_NAMES, 0.0))
    friction: dict = field(default_factory=dict)
    #: a description written as joints and links: its drawn pose, which the built
    #: linkage must reproduce at the drawn crank angle (:func:`.assur.check_pose`)
    drawn: Any = field(default=None, compare=False)
    _checked: bool = field(default=False, repr=False, compare=False)

    # -- the builder -----------------------------------------------------------------
    def parameter(self, name: str, default: Any, kind: str, description: str = "",
                  min: float | None = None, max: float | None = None,
                  choices: tuple = ()) -> "Description":
        """A parameter: name, default, kind (unit and rule, see
        :mod:`~linkage_fmu.parameters`), meaning, and optional bounds."""
        self.parameters[name] = dict(default=default, kind=kind, description=description,
                                     min=min, max=max, choices=tuple(choices))
        return self._changed()

    def point(self, name: str, x: Any, y: Any) -> "Description":
        """A point fixed in the frame."""
        self.points[name] = (x, y)
        return self._changed()

    def group(self, type: str, **fields) -> "Description":
        """The next group: the crank first, then groups placing points from placed ones."""
        self.groups.append({"type": type, **fields})
        return self._changed()

    def body(self, link: str, mass: Any = 0.0, inertia: Any = 0.0,
             cg: dict | None = None) -> "Description":
        """Mass, moment of inertia about the centre of mass, and where that is."""
        self.bodies[link] = {"mass": mass, "inertia": inertia, "cg": dict(cg or {})}
        return self._changed()

    def load(self, name: str, body: str, kind: str, at: str = "", direction: Any = None,
             fixed_in: str = "frame", unit: str = "", description: str = "",
             start: Any = 0.0, value: Any = None, table: Any = None,
             period_deg: float = 360.0, table_unit: str = "", scale: Any = 1.0
             ) -> "Description":
        """A load: a force on ``body`` at its point ``at`` along ``direction`` (fixed in
        the frame or in the link), or a moment on ``body``. Its magnitude is an input
        (``start``: its start value), or given over the cycle: ``value``, an expression
        of ``theta``, the parameters and the points' positions ``x_P``, ``y_P``; or
        ``table``, a CSV file (columns ``theta_deg`` and ``value``, read now; a
        ValueError if it cannot be) or a list of ``[theta_deg, value]`` points of period
        ``period_deg``, its values in ``table_unit`` (default the load's), times
        ``scale``."""
        spec = {"name": name, "body": body, "kind": kind, "fixed_in": fixed_in, "unit": unit,
                "description": description, "start": start}
        if at:
            spec["at"] = at
        if direction is not None:
            spec["direction"] = direction
        if value is not None:
            spec["value"] = value
        if table is not None:
            spec.update(table=table, period_deg=period_deg, table_unit=table_unit, scale=scale)
            problem = _read_table(spec, Path.cwd())
            if problem:
                raise InputError(f"load {name} table: {problem}")
        self.loads.append(spec)
        return self._changed()

    def effort(self, name: str, body: str, at: str = "", direction: Any = None,
               when: tuple | None = None) -> "Description":
        """Where the balancing effort acts: a moment on ``body``, or a force at its point
        ``at`` along ``direction``. ``when = (parameter, value)`` makes it the effort
        only for that value of a choice parameter."""
        spec = {"name": name, "body": body}
        if at:
            spec["at"] = at
        if direction is not None:
            spec["direction"] = direction
        self.efforts[when] = spec
        return self._changed()

    def output(self, kind: str, **fields) -> "Description":
        """An output of the kind ``kind``: ``force`` (components of the force of body
        ``by`` on body ``on``), ``normal`` or ``couple`` of a prismatic pair, ``effort``,
        ``expression``, or another in :attr:`Output.registry
        <linkage_fmu.outputs.Output.registry>`, with the keys it declares."""
        self.outputs.append({"kind": kind, **fields})
        return self._changed()

    def joint_friction(self, joint: str, mu: Any, radius: Any = None,
                       length: Any = None) -> "Description":
        """Coulomb friction in the pair ``joint``: coefficient ``mu``, and the pin
        ``radius`` of a revolute pair or the ``length`` of a prismatic pair's slider."""
        spec = {"mu": mu}
        spec.update({k: v for k, v in (("radius", radius), ("length", length)) if v is not None})
        self.friction[joint] = spec
        return self._changed()

    def start(self, **values: float) -> "Description":
        """Start values of the inputs theta, omega, alpha."""
        self.inputs.update(values)
        return self._changed()

    def _changed(self) -> "Description":
        self._checked = False
        return self

    # -- reading ---------------------------------------------------------------------
    @classmethod
    def from_toml(cls, text: str, source: str = "<string>") -> "Description":
        """Read a description file's text; problems are reported with ``source``."""
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as err:
            raise DescriptionError(source, [f"not valid TOML: {err}"]) from None
        problems = []
        for key in data:
            if key not in TABLES and key not in JOINT_TABLES:
                problems.append(f"[{key}]: unknown table; the tables are {', '.join(TABLES)} "
                                f"(or, written as joints and links, {', '.join(JOINT_TABLES)} "
                                "instead of points, groups and bodies)")
        head = data.get("linkage", {})
        if not isinstance(head, dict):
            head = {}
        for key in head:
            if key not in LINKAGE_KEYS:
                problems.append(f"[linkage] {key}: unknown key; the keys are "
                                f"{', '.join(LINKAGE_KEYS)}")
        d = cls(name=str(head.get("name", Path(source).stem)), title=str(head.get("title", "")),
                model=str(head.get("model", "")), frame=str(head.get("frame", "0")),
                gravity=head.get("gravity", 0.0), drive=head.get("drive", 1.0), source=source)
        problems += _read_tables(d, data)
        defaults = head.get("default_outputs", True)
        if not isinstance(defaults, bool):
            problems.append(f"[linkage] default_outputs: {defaults!r} must be true or false")
        elif "default_outputs" in head and not set(JOINT_TABLES) & set(data):
            problems.append("[linkage] default_outputs: a description written as groups has "
                            "no default outputs: its [[outputs]] tables are its outputs (and "
                            "each effort); the key is for one written as joints and links")
        if set(JOINT_TABLES) & set(data):
            drawn = _read_joints_form(d, data)
            if drawn:  # the group form it makes is incomplete: its checks would mislead
                raise DescriptionError(source, problems + drawn)
        names = driver_inputs(d.groups)
        problems += [f"[inputs] {k}: no input of this linkage; its drivers' inputs are "
                     f"{', '.join(names)}" for k in _table(data, "inputs")
                     if isinstance(k, str) and k not in names and
                     (k in INPUT_NAMES or k.split("_")[0] in DRIVER_INPUTS)]
        checker = Checker(d)
        problems += _as_links(d, checker.problems())  # every problem at once
        checker.warn()
        if problems:
            raise DescriptionError(source, problems)
        d._checked = True
        return d

    @classmethod
    def read(cls, path: str | Path) -> "Description":
        """Read the description file at ``path``."""
        path = Path(path)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as err:
            raise DescriptionError(str(path), [f"cannot read it: {err.strerror}"]) from None
        except UnicodeDecodeError as err:
            raise DescriptionError(str(path), [f"not UTF-8 text: byte {err.object[err.start]:#x} "
                                               f"at {err.start}"]) from None
        return cls.from_toml(text, str(path))

    # -- checking --------------------------------------------------------------------
    def parameter_specs(self) -> tuple[Parameter, ...]:
        """The parameters as :class:`~linkage_fmu.parameters.Parameter` objects."""
        return tuple(Parameter(n, p["default"], p["kind"], p["description"], p["choices"],
                               p["min"], p["max"]) for n, p in self.parameters.items())

    def check(self) -> "Description":
        """Raise :class:`DescriptionError` listing every problem; return self if none."""
        if not self._checked:
            checker = Checker(self)
            problems = checker.problems()
            checker.warn()
            if problems:
                raise DescriptionError(self.source, problems)
            self._checked = True
        return self

    def build(self, **parameters) -> "Mechanism":  # noqa: F821
        """Check the description and build the linkage with ``parameters`` overriding
        the defaults (an unknown name is a ``TypeError``, an invalid value a
        ``ValueError``, each naming the parameter)."""
        from .build import build

        return build(self.check(), parameters)

    def fmu_build(self, **parameters) -> "Mechanism":  # noqa: F821
        """:meth:`build` for an FMU: the friction of the joints is solved even where every
        ``mu`` is 0 now, since an FMU's parameters change after it is built (the native
        FMU also carries the kernels without friction, and runs them while every
        coefficient is 0)."""
        from .build import build

        return build(self.check(), parameters, friction=True)

    def friction_parameters(self, keys: tuple = ("mu", "radius", "length")) -> frozenset:
        """The parameters the ``keys`` of the [friction.J] tables use (with ``radius``,
        also those of ``drive``).

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> sorted(presets.preset("slider_crank").friction_parameters(("mu",)))
        ['mu_A', 'mu_B', 'mu_O', 'mu_guide']
        """
        names = {n for spec in self.friction.values() for k, v in spec.items() if k in keys
                 for n in Expression(v).names}
        if "radius" in keys:
            names.update(Expression(self.drive).names)
        return frozenset(names)

    def copy(self) -> "Description":
        return copy.deepcopy(self)

    def with_defaults(self, values: dict) -> "Description":
        """A copy whose parameter defaults are ``values`` (e.g. a built linkage's)."""
        d = self.copy()
        for name, value in values.items():
            d.parameters[name]["default"] = value
        return d._changed()

    def with_drive(self, drive: Any) -> "Description":
        """A copy whose crank's drive direction is ``drive`` (+1 or -1, or an expression)."""
        d = self.copy()
        d.drive = drive
        return d._changed()

    # -- writing ---------------------------------------------------------------------
    def to_toml(self) -> str:
        """The description file of this description (:meth:`from_toml` reads it back).

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> d = presets.preset("four_bar")
        >>> Description.from_toml(d.to_toml()) == d
        True
        """
        lines = ["[linkage]"]
        lines += [f"{k} = {_toml(v)}" for k, v in (("name", self.name), ("title", self.title),
                                                   ("model", self.model), ("frame", self.frame),
                                                   ("gravity", self.gravity))]
        if self.drive != 1.0:
            lines.append(f"drive = {_toml(self.drive)}")
        lines += ["", "[parameters]"]
        for name, p in self.parameters.items():
            spec = {"default": p["default"], "kind": p["kind"], "description": p["description"]}
            spec.update({k: p[k] for k in ("min", "max") if p[k] is not None})
            if p["choices"]:
                spec["choices"] = list(p["choices"])
            lines.append(f"{_key(name)} = {_toml(spec)}")
        lines += ["", "[points]"] + [f"{_key(n)} = {_toml(list(xy))}"
                                     for n, xy in self.points.items()]
        for spec in self.groups:
            lines += ["", "[[groups]]"] + [f"{_key(k)} = {_toml(v)}" for k, v in spec.items()]
        for link, spec in self.bodies.items():
            lines += ["", f"[bodies.{_key(link)}]"]
            lines += [f"{k} = {_toml(v)}" for k, v in spec.items()]
        for spec in self.loads:
            lines += ["", "[[loads]]"] + [f"{_key(k)} = {_toml(v)}" for k, v in spec.items()]
        if None in self.efforts:
            lines += ["", "[effort]"]
            lines += [f"{_key(k)} = {_toml(v)}" for k, v in self.efforts[None].items()]
        elif self.efforts:
            choose = next(iter(self.efforts))[0]
            lines += ["", "[effort]", f"choose = {_toml(choose)}"]
            lines += [f"options.{_key(str(w[1]))} = {_toml(spec)}"
                      for w, spec in self.efforts.items()]
        for spec in self.outputs:
            lines += ["", "[[outputs]]"] + [f"{_key(k)} = {_toml(v)}" for k, v in spec.items()]
        names = driver_inputs(self.groups)  # a crank's defaults are none of the drivers'
        lines += ["", "[inputs]"] + [f"{k} = {_toml(v)}" for k, v in self.inputs.items()
                                     if k in names or k not in INPUT_NAMES]
        for joint, spec in self.friction.items():
            lines += ["", f"[friction.{_key(joint)}]"] + [f"{k} = {_toml(v)}"
                                                          for k, v in spec.items()]
        return "\n".join(lines) + "\n"


# -- reading the tables --------------------------------------------------------------
def _table(data: dict, key: str) -> dict:
    """The table ``key`` of ``data``, empty where it is none (its reading says why)."""
    value = data.get(key, {})
    return value if isinstance(value, dict) else {}


def _as_links(d: Description, problems: list[str]) -> list[str]:
    """The problems, those of a link's mass or inertia named as its [[links]] table
    gives them where the description is written as joints and links."""
    if d.drawn is None:
        return problems
    from .assur import body_table

    out = []
    for p in problems:
        for link in d.drawn.links:
            for key in ("mass", "inertia"):
                p = p.replace(f"[bodies.{link}] {key}", f"{body_table(d.drawn, link)} {key}")
        out.append(p)
    return out


def _read_joints_form(d: Description, data: dict) -> list[str]:
    """Read the joints-and-links tables of ``data`` into ``d``'s group form: its points,
    groups and bodies, after its [[outputs]] the default ones (a force per pair they do
    not report, each effort; none with ``default_outputs = false``), and where none are
    given its effort (a moment ``Mb`` on the crank) and its model (its name)."""
    from ..parameters import resolve
    from . import assur, topology

    mixed = [f"[{k}]" for k in ("points", "groups", "bodies") if k in data]
    if mixed:
        return [f"{', '.join(mixed)}: a description is written either as groups ([points], "
                "[[groups]], [bodies]) or as joints and links ([joints], [[links]], [crank]), "
                "not both"]
    checker = Checker(d)
    checker.parameters()
    if checker.found:
        return checker.found
    try:
        values = resolve(d.parameter_specs(), {}, d.name)
    except (TypeError, ValueError) as err:
        return [f"[parameters]: {err}"]
    numbers = {k: v for k, v in values.items() if isinstance(v, (int, float))}
    t, problems = topology.read(data, numbers, d.frame, checker.measures)
    if t is None:
        return problems
    at_points = {s.get("at") for s in d.loads} | {s.get("at") for s in d.efforts.values()
                                                   if isinstance(s, dict)}
    for s in d.loads:  # a load's value may use the position x_P, y_P of a pair's point
        try:
            at_points.update(n[2:] for n in Expression(s.get("value", 0.0)).names
                             if n[:2] in ("x_", "y_"))
        except ValueError:  # the checker says why
            pass
    branches = tuple(n for n, p in d.parameters.items() if p["kind"] == "branch")
    try:
        dec = assur.decompose(t, numbers, branches, at_points)
    except assur.DecompositionError as err:
        return err.problems
    d.points, d.groups, d.bodies = dec.points, dec.groups, dec.bodies
    d.drawn = dec
    if "model" not in data.get("linkage", {}) and is_identifier(d.name):
        d.model = d.name
    timed = driver_efforts(dec.groups)  # several drivers, a motor, a cylinder
    if not d.efforts and not timed:
        d.efforts[None] = {"name": "Mb", "body": t.driven[0].second}
    given = data.get("inputs", {})
    starts = dec.starts or {"theta": dec.theta}
    d.inputs.update({k: v for k, v in starts.items() if k not in given})  # as drawn
    if data.get("linkage", {}).get("default_outputs", True) is not False:
        efforts = d.efforts or {name: {"name": name} for name in timed}
        d.outputs.extend(assur.default_outputs(dec.pairs, efforts, d.outputs))
    return []


def _read_tables(d: Description, data: dict) -> list[str]:
    problems = []

    def table(key, kind=dict):
        value = data.get(key, kind())
        if not isinstance(value, kind):
            problems.append(f"[{key}]: must be a {'table' if kind is dict else 'list of tables'}")
            return kind()
        return value

    for name, spec in table("parameters").items():
        where = f"[parameters] {name}"
        if not isinstance(spec, dict):
            problems.append(f"{where}: must be a table {{ default, kind, description }}")
            continue
        unknown = set(spec) - set(PARAMETER_KEYS)
        if unknown:
            problems.append(f"{where}: unknown key(s) {', '.join(sorted(unknown))}")
        if "default" not in spec or "kind" not in spec:
            problems.append(f"{where}: needs 'default' and 'kind'")
            continue
        d.parameters[name] = dict(default=spec["default"], kind=spec["kind"],
                                  description=str(spec.get("description", "")),
                                  min=spec.get("min"), max=spec.get("max"),
                                  choices=tuple(spec.get("choices", ())))
    for name, xy in table("points").items():
        d.points[name] = tuple(xy) if isinstance(xy, list) else xy
    for k, spec in enumerate(table("groups", list)):
        if not isinstance(spec, dict):
            problems.append(f"[[groups]] #{k + 1}: must be a table")
            continue
        d.groups.append(dict(spec))
    for link, spec in table("bodies").items():
        if not isinstance(spec, dict):
            problems.append(f"[bodies.{link}]: must be a table")
            continue
        unknown = set(spec) - set(BODY_KEYS)
        if unknown:
            problems.append(f"[bodies.{link}]: unknown key(s) {', '.join(sorted(unknown))}; the "
                            "keys are mass, inertia, cg")
        d.bodies[link] = {"mass": spec.get("mass", 0.0), "inertia": spec.get("inertia", 0.0),
                          "cg": spec.get("cg", {})}
    for k, spec in enumerate(table("loads", list)):
        if not isinstance(spec, dict):
            problems.append(f"[[loads]] #{k + 1}: must be a table")
            continue
        spec = {**LOAD_DEFAULTS, **spec}
        if "table" in spec:
            spec = {**spec, **{k: v for k, v in TABLE_DEFAULTS.items() if k not in spec}}
            base = Path(d.source).parent if Path(d.source).is_file() else Path.cwd()
            problem = _read_table(spec, base)
            if problem:
                problems.append(f"[[loads]] #{k + 1} ({spec.get('name')}) table: {problem}")
        d.loads.append(spec)
    effort = table("effort")
    if "choose" in effort:
        options = effort.get("options", {})
        if set(effort) - set(EFFORT_CHOICE_KEYS) or not isinstance(options, dict):
            problems.append("[effort]: with 'choose', give only 'options' = { VALUE = {...} }")
        else:
            for value, spec in options.items():
                d.efforts[(effort["choose"], value)] = spec
    elif effort:
        d.efforts[None] = effort
    for k, spec in enumerate(table("outputs", list)):
        if not isinstance(spec, dict):
            problems.append(f"[[outputs]] #{k + 1}: must be a table")
            continue
        d.outputs.append(dict(spec))
    for joint, spec in table("friction").items():
        where = f"[friction.{joint}]"
        if not isinstance(spec, dict):
            problems.append(f"{where}: must be a table {{ mu, radius }} or {{ mu, length }}")
            continue
        d.friction[joint] = dict(spec)
    inputs = table("inputs")
    for key, value in inputs.items():
        head = key.split("_")[0] if isinstance(key, str) and "_" in key else None
        if key not in INPUT_NAMES and head not in ("theta", "omega", "alpha", "s", "v", "a"):
            problems.append(f"[inputs] {key}: unknown input; the inputs with start values here "
                            "are theta, omega, alpha (a load's start value is in its table)")
        d.inputs[key] = value
    return problems


def _read_table(spec: dict, base: Path) -> str:
    """Replace a load's ``table = "FILE.csv"`` (relative to ``base``) by its points;
    what is wrong with the file, or ''."""
    from ..tables import read_rows

    if isinstance(spec.get("table"), (str, Path)):
        try:
            spec["table"] = read_rows(base / spec["table"])
        except ValueError as err:
            return str(err)
    return ""


# -- writing ---------------------------------------------------------------------------
def _key(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)


def _toml(value) -> str:
    """A TOML value: strings, numbers, booleans, lists and inline tables."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)  # JSON's string escapes are TOML's basic-string escapes
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_toml(v)}" for k, v in value.items()) + " }"
    raise InputTypeError(f"cannot write {value!r} to a description file")

