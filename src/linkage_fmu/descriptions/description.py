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
an angle in radians. ``docs/description.md`` is the full reference
(:mod:`~linkage_fmu.descriptions.reference` writes it).
:meth:`Description.build` checks everything, reporting every problem at once with the
file, table and key, and returns a :class:`~linkage_fmu.mechanism.Mechanism`.

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
import math
import re
import tomllib
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..expressions import Expression, check_units
from ..groups import OWNER, Field, Group, LinkJoints
from ..outputs import SHAKING
from ..parameters import KINDS, Parameter
from ..units import unit_problem

INPUT_NAMES = ("theta", "omega", "alpha")
#: the tables of a description written as joints and links (:mod:`.topology`), which
#: take the place of [points], [[groups]] and [bodies]
JOINT_TABLES = ("joints", "links", "crank")
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")

# What a description file may hold, table by table: each mapping below gives the keys
# the reader and the checker accept and what each means, and is what the reference of
# the format (docs/description.md, written by linkage_fmu.descriptions.reference) lists.

#: table -> (its header in a description file, what it holds), in the order of a file
TABLES: dict[str, tuple[str, str]] = {
    "linkage": ("[linkage]", "what the linkage is: its name, title, the FMU's model "
                             "identifier, the frame's body name and gravity"),
    "parameters": ("[parameters]", "the parameters the linkage is built with (its FMUs' "
                                   "parameters), NAME = { default, kind, ... }"),
    "points": ("[points]", "the points fixed in the frame, NAME = [x, y] in m"),
    "groups": ("[[groups]]", "the driver, then the groups that place the other points and "
                             "links from placed ones, one table each, in order"),
    "bodies": ("[bodies.L]", "the mass, moment of inertia and centre of mass of each moving "
                             "link L"),
    "loads": ("[[loads]]", "the named loads: a force or a moment on a moving link, an input "
                           "or given over the cycle"),
    "effort": ("[effort]", "where the balancing effort acts (a moment on the driver, or a "
                           "force), or which effort each value of a choice parameter takes"),
    "outputs": ("[[outputs]]", "what the linkage reports besides the outputs every linkage "
                               "has"),
    "friction": ("[friction.J]", "Coulomb friction in the pair J: its coefficient, and a "
                                 "revolute pair's pin radius or a slider's length"),
    "inputs": ("[inputs]", "start values of the crank's motion"),
}
#: key of [linkage] -> what it is
LINKAGE_KEYS = {
    "name": "name of the linkage in messages (default: the file's name without .toml)",
    "title": "one line saying what it is",
    "model": "model identifier of its FMUs, a C identifier (required; written as joints "
             "and links, a file without it takes its name where that is a C identifier)",
    "frame": "name of the frame body in output names (default \"0\")",
    "gravity": "gravitational acceleration along -y, m/s2 (default 0; usually the "
               "parameter g)",
    "drive": "the crank's drive direction, +1 (counter-clockwise, default) or -1: where "
             "the crank stands, friction opposes the motion it would start this way",
    "default_outputs": "written as joints and links: true (default) to report, besides "
                       "its [[outputs]], the force of each pair they do not report and "
                       "each effort; false for its [[outputs]] only (and each effort, "
                       "which every linkage reports)",
}
#: key of a [friction.J] table -> what it is
FRICTION_KEYS = {
    "mu": "coefficient of friction, >= 0 (required)",
    "radius": "pin radius of a revolute pair, m, >= 0 (required for a revolute pair): "
              "friction moment mu * radius * |R|",
    "length": "length of the slider of a prismatic pair, m, > 0 (optional): friction "
              "mu * (|N1| + |N2|) from its two end contacts, mu * |N| without it",
}
#: key of a parameter's table in [parameters] -> what it is
PARAMETER_KEYS = {
    "default": "its value unless another is given (required): for a real kind a number, "
               "a number with a unit or an expression of numbers; +1 or -1 for a branch; "
               "one of choices for a choice",
    "kind": "what it is: its unit and rule (required)",
    "description": "what it is, in one phrase",
    "min": "least value of a real kind (inclusive), in its unit",
    "max": "greatest value of a real kind (inclusive), in its unit",
    "choices": "the values of a choice parameter, a list",
}
#: key of [bodies.L] -> what it is
BODY_KEYS = {
    "mass": "mass of the link, kg (default 0)",
    "inertia": "moment of inertia about its centre of mass, kg.m2 (default 0)",
    "cg": "where its centre of mass is, in the link's own frame: { from, along, across } "
          "or { from, distance, angle }",
}
#: key of a body's cg -> what it is
CG_KEYS = {
    "from": "the link's point it is measured from, a placed point (required)",
    "along": "distance from 'from' along the link's direction, m (default 0)",
    "across": "distance from 'from' to the left of the link's direction, m (default 0)",
    "distance": "distance from 'from', m (with angle, instead of along and across)",
    "angle": "direction from 'from', counter-clockwise from the link's, rad (default 0)",
}
#: key of a [[loads]] table -> what it is
LOAD_KEYS = {
    "name": "name of the load, an identifier: the input's name for a load that is an "
            "input (required)",
    "body": "the moving link it acts on (required)",
    "kind": "\"force\" or \"moment\" (a moment is counter-clockwise positive; required)",
    "at": "a force's point of application, a placed point of body (required for a force)",
    "direction": "a force's direction [x, y], of any length: the direction of a positive "
                 "value (required for a force)",
    "fixed_in": "what a force's direction is fixed in: \"frame\", or \"link\" (then "
                "it is in the link's own frame, x along the link)",
    "unit": "its unit, in SI: \"N\" for a force, \"N.m\" for a moment (a value with "
            "another unit is converted)",
    "description": "what the load is, in one phrase",
    "start": "start value of a load that is an input, N or N.m",
    "value": "a load over the cycle: an expression of theta (rad), the parameters and the "
             "positions x_P, y_P (m) of the placed points P, in N or N.m",
    "table": "a load over the cycle: a CSV file \"FILE.csv\" (columns theta_deg and "
             "value; relative to the description file) or a list [[theta_deg, value], "
             "...]: the periodic cubic spline through its points",
    "period_deg": "the table's period, degrees of crank angle (720 for a four-stroke "
                  "engine)",
    "table_unit": "unit of the table's values, such as \"bar\" or \"kN\" (default: the "
                  "load's, N or N.m)",
    "scale": "factor of the table's values, a number or an expression of the parameters "
             "(an area with table_unit = \"bar\")",
}
#: the keys of a load with a default, and those defaults
LOAD_DEFAULTS = {"fixed_in": "frame", "unit": "", "description": "", "start": 0.0}
#: the keys of a load given by a table, and their defaults
TABLE_DEFAULTS = {"period_deg": 360.0, "table_unit": "", "scale": 1.0}
#: key of [effort] (or of one of its options) -> what it is
EFFORT_KEYS = {
    "name": "name of the balancing effort, as an output of kind effort (required)",
    "body": "the moving link it acts on (required)",
    "at": "for a force: the placed point of body it acts at (with direction)",
    "direction": "for a force: its direction [x, y] (with at); without at and direction "
                 "the effort is a moment on body",
}
#: key of [effort] when a choice parameter selects the effort -> what it is
EFFORT_CHOICE_KEYS = {
    "choose": "the choice parameter whose value selects the effort",
    "options": "VALUE = { name, body, ... }: the effort for each value of that parameter",
}
#: kind of a [[outputs]] table -> what it reports
OUTPUT_KINDS = {
    "force": "components of the force one body exerts on another through their joint, N",
    "normal": "normal force of a prismatic pair along its normal, N",
    "couple": "couple transmitted by a prismatic pair, counter-clockwise positive, N.m",
    "effort": "the balancing effort of an [effort] (zero when a choice makes another "
              "the effort)",
    "expression": "an expression of the joint reactions, the effort and the parameters",
}
#: kind of a [[outputs]] table -> its keys besides kind -> what each is
OUTPUT_KEYS = {
    "force": {
        "name": "stem of the outputs' names: NAMEx and NAMEy (required)",
        "by": "the body that exerts the force, a moving link or the frame (required)",
        "on": "the body it acts on, joined to by (required)",
        "components": "the components reported, a list of \"x\" and/or \"y\" (default "
                      "both)",
        "x": "name of the x component (default NAMEx)",
        "y": "name of the y component (default NAMEy)",
        "magnitude": "also report the force's magnitude (a prismatic pair's: its normal "
                     "force): true for NAME_abs, or its name",
        "description": "what the force is; the outputs' descriptions add the component",
    },
    "normal": {
        "name": "name of the output (required)",
        "joint": "the prismatic pair, by its name (required)",
        "description": "what it is",
    },
    "couple": {
        "name": "name of the output (required)",
        "joint": "the prismatic pair, by its name (required)",
        "description": "what it is",
    },
    "effort": {
        "name": "the name of an [effort] (required)",
        "unit": "its unit (default: N.m for a moment, N for a force)",
        "description": "what it is",
    },
    "expression": {
        "name": "name of the output (required)",
        "expression": "an expression of N_J, M_J (the normal force and couple of a "
                      "prismatic pair J), Fx_J, Fy_J (the force of a revolute pair J), "
                      "the efforts' names and the parameters (required)",
        "unit": "its unit (default N)",
        "description": "what it is",
    },
}
#: the units of the inputs
INPUT_UNITS = {"theta": "rad", "omega": "rad/s", "alpha": "rad/s2"}

class DescriptionError(ValueError):
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
                raise ValueError(f"load {name} table: {problem}")
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
        """An output: ``force`` (components of the force of body ``by`` on body ``on``),
        ``normal`` or ``couple`` of a prismatic pair, ``effort``, or ``expression``."""
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
        checker = _Checker(d)
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
            checker = _Checker(self)
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
        lines += ["", "[inputs]"] + [f"{k} = {_toml(v)}" for k, v in self.inputs.items()]
        for joint, spec in self.friction.items():
            lines += ["", f"[friction.{_key(joint)}]"] + [f"{k} = {_toml(v)}"
                                                          for k, v in spec.items()]
        return "\n".join(lines) + "\n"


# -- reading the tables --------------------------------------------------------------
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
    checker = _Checker(d)
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
    if "model" not in data.get("linkage", {}) and _is_identifier(d.name):
        d.model = d.name
    if not d.efforts:
        d.efforts[None] = {"name": "Mb", "body": t.crank}
    if "theta" not in data.get("inputs", {}):  # it starts where it is drawn
        d.inputs["theta"] = dec.theta
    if data.get("linkage", {}).get("default_outputs", True) is not False:
        d.outputs.extend(assur.default_outputs(dec.pairs, d.efforts, d.outputs))
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
        if key not in INPUT_NAMES:
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


# -- checking the structure -----------------------------------------------------------
def _finite(value: Any) -> bool:
    return not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value)


def _is_identifier(name: Any) -> bool:
    return isinstance(name, str) and bool(_IDENTIFIER.match(name))


class _Checker:
    """Every problem of a description, each naming its table and key.

    One method per table, run in the order of the messages; what a table defines for
    the later ones (points placed, links added, pairs, load names) is kept here. Group
    types are known only through their contract (``FIELDS``, ``OPTIONAL``, ``DRIVER``,
    ``pairs``), so a new type is checked like the shipped ones.

    Examples
    --------
    >>> d = Description("demo", model="Demo").point("A", 0, 0)
    >>> for problem in _Checker(d).problems():
    ...     print(problem)
    [[groups]]: there are none; the first must be the crank
    [effort]: missing: where does the balancing effort act?
    [[outputs]]: there are none
    """

    def __init__(self, d: Description):
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
        elif not _is_identifier(model):
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
            except ValueError as err:  # a bound the kind cannot have
                self.found.append(f"{where}: {str(err).removeprefix(f'{name}: ')}")
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
        if not self.d.efforts:
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
        if k > 0 and cls.DRIVER:
            self.found.append(
                f"{where}: only one {kind} (the first group) drives the linkage: a linkage "
                "has mobility 1, so one driver moves it, with the inputs theta, omega and "
                "alpha (its angle, speed and acceleration), and every later group follows "
                "from the points placed before it (a group type that is no driver has "
                "DRIVER = False)")
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
        if not _is_identifier(name):
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
        """One output; the names it gives must not be in ``used`` (then they are)."""
        kind = spec.get("kind")
        where = f"[[outputs]] #{k + 1} ({spec.get('name', kind)})"
        if kind not in OUTPUT_KEYS:
            self.found.append(f"{where} kind: {kind!r} is not one of {', '.join(OUTPUT_KEYS)}")
            return
        unknown = set(spec) - set(OUTPUT_KEYS[kind]) - {"kind"}
        if unknown:
            self.found.append(f"{where}: unknown key(s) {', '.join(sorted(unknown))}")
        name = spec.get("name")
        if not _is_identifier(name):
            self.found.append(f"{where} name: {name!r} must be an identifier")
            return
        names = {"force": self.force_output, "normal": self.pair_output,
                 "couple": self.pair_output, "effort": self.effort_output,
                 "expression": self.expression_output}[kind](where, name, spec)
        for n in names:
            if n in used or n in self.taken or n in self.load_names:
                self.found.append(f"{where}: output name {n!r} is used twice")
            used.append(n)

    def force_output(self, where: str, name: str, spec: dict) -> list:
        for key in ("by", "on"):
            if spec.get(key) not in self.links and spec.get(key) != self.d.frame:
                self.found.append(f"{where} {key}: {spec.get(key)!r} is not a body")
        comps = spec.get("components", ["x", "y"])
        if not set(comps) <= {"x", "y"} or not comps:
            self.found.append(f"{where} components: must be a list of 'x' and/or 'y'")
        names = [spec.get(c, name + c) for c in comps]
        if spec.get("magnitude"):
            m = spec["magnitude"]
            names.append(m if isinstance(m, str) else f"{name}_abs")
        return names

    def pair_output(self, where: str, name: str, spec: dict) -> list:
        if spec.get("joint") not in self.joints:
            self.found.append(f"{where} joint: {spec.get('joint')!r} is not a pair")
        return [name]

    def effort_names(self) -> set:
        return {spec.get("name") for spec in self.d.efforts.values() if isinstance(spec, dict)}

    def effort_output(self, where: str, name: str, spec: dict) -> list:
        if name not in self.effort_names():
            self.found.append(f"{where} name: {name!r} is not the name of an [effort]")
        elif "unit" in spec and not self.unit(f"{where} unit", spec["unit"]):
            kinds = {"N" if "direction" in e else "N.m" for e in self.d.efforts.values()
                     if isinstance(e, dict) and e.get("name") == name}
            if spec["unit"] not in kinds:
                what = "a force" if kinds == {"N"} else "a moment"
                self.found.append(f"{where} unit: {spec['unit']!r}: {name} is {what}, in "
                                  f"{' or '.join(sorted(kinds))}")
        return [name]

    def expression_output(self, where: str, name: str, spec: dict) -> list:
        joint_vars = {f"{v}_{j}" for j in self.joints for v in ("N", "M", "Fx", "Fy")}
        self.expr(f"{where} expression", spec.get("expression", ""),
                  set(self.d.parameters) | joint_vars | self.effort_names())
        if "unit" in spec:
            self.unit(f"{where} unit", spec["unit"])
        return [name]

    def unit(self, where: str, unit: Any) -> str:
        """An output's unit, which must be one of the package's (the output is computed
        in SI); the problem found ('' if none)."""
        problem = unit_problem(unit, where)
        if problem:
            self.found.append(problem)
        return problem


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
    raise TypeError(f"cannot write {value!r} to a description file")

