"""What a description file may hold, table by table.

Each mapping below gives the keys the reader (:mod:`.description`) and the checker
(:mod:`.checker`) accept and what each means, and is what the reference of the format
(``docs/description.md``, written by :mod:`linkage_fmu.manual.reference`) lists.

Examples
--------
>>> [header for header, _ in TABLES.values()][:3]
['[linkage]', '[parameters]', '[points]']
>>> OUTPUT_KEYS["normal"]["joint"]
'the prismatic pair, by its name (required)'
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping

from ..outputs import Output
from ..units import MOTION_UNITS


class _PerKind(Mapping):
    """Kind -> the class fact ``fact`` of each output kind, read from
    :attr:`Output.registry <linkage_fmu.outputs.Output.registry>` when asked: a kind
    defined after this module is imported is in it."""

    def __init__(self, fact: str):
        self._fact = fact

    def __getitem__(self, kind: str):
        return getattr(Output.registry[kind], self._fact)

    def __iter__(self) -> Iterator[str]:
        return iter(Output.registry)

    def __len__(self) -> int:
        return len(Output.registry)

    def __repr__(self) -> str:
        return repr(dict(self))


INPUT_NAMES = ("theta", "omega", "alpha")
#: the tables of a description written as joints and links (:mod:`.topology`), which
#: take the place of [points], [[groups]] and [bodies]
JOINT_TABLES = ("joints", "links", "crank", "drivers")

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
#: kind of a [[outputs]] table -> what it reports, of every output kind defined
OUTPUT_KINDS: Mapping[str, str] = _PerKind("REPORTS")
#: kind of a [[outputs]] table -> its keys besides kind -> what each is
OUTPUT_KEYS: Mapping[str, dict[str, str]] = _PerKind("KEYS")
#: the units of the inputs
INPUT_UNITS = MOTION_UNITS
