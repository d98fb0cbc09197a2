"""The reference of the description file format, written from what the code declares.

:func:`markdown` writes ``docs/description.md``: the tables of a description file
(:data:`~linkage_fmu.descriptions.schema.TABLES`) and every key each takes, from the
mappings the reader and checker use (:mod:`~linkage_fmu.descriptions.schema`); the
parameter kinds with their units and rules (:mod:`~linkage_fmu.parameters`); every group
type in :attr:`Group.registry <linkage_fmu.groups.Group.registry>` with its fields; the
outputs every linkage has, with the descriptions a built linkage gives them; what
expressions may hold (:mod:`~linkage_fmu.expressions`); the units
(:mod:`~linkage_fmu.units`); friction in the joints, with the outputs it adds and
their sign conventions (:mod:`~linkage_fmu.friction`); and a complete description file.
A group type, key, kind, function or unit added to the code is in the reference the next
time it is written.

``linkage-fmu reference -o docs/description.md`` writes it; run as a script, it
prints it::

    python -m linkage_fmu.manual.reference > docs/description.md
"""

from __future__ import annotations

import inspect
import json
import re
import sys
import tomllib
import warnings
from pathlib import Path
from typing import Any

from .. import expressions, parameters, presets, units
from ..descriptions import assur, topology
from ..descriptions import schema as spec
from ..descriptions.description import Description
from ..friction import FrictionOutput, LossOutput
from ..groups import ROLE_MEANINGS, ROLES, Group
from ..mechanism import Mechanism
from ..outputs import SHAKING
from ..pairs import Prismatic, Revolute

#: the description file shown whole at the end of the reference
EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "coupler_four_bar.toml"

#: loads over the cycle and an expression output, each a table that the example file
#: (:data:`EXAMPLE`) may take as it is
CYCLE_LOADS = (
    '''[[loads]]
name = "F_spring"
body = "3"
kind = "force"
at = "C"
direction = [0, -1]
value = "20 N + 400 N/m * (y_C - 100 mm)"  # a spring from C down to the frame
description = "spring force at C"
''',
    '''[[loads]]
name = "T_cam"
body = "3"
kind = "moment"
value = "5 N*m * sin(2 * theta)"
''',
    '''[[loads]]
name = "F_gas"
body = "2"
kind = "force"
at = "P"
direction = [-1, 0]
fixed_in = "link"  # along -x of link 2's own frame: against B -> C
table = [[0, 1.0], [90, 6.0], [180, 2.0], [270, 1.0]]  # [theta_deg, bar]
period_deg = 360
table_unit = "bar"
scale = "pi * (40 mm)**2 / 4"  # the piston's area
''',
)
EXPRESSION_OUTPUT = '''[[outputs]]
kind = "expression"
name = "F_C"
expression = "sqrt(Fx_C**2 + Fy_C**2)"
description = "magnitude of the force in the pair C"
unit = "N"
'''


def markdown() -> str:
    """The reference of the description file format, in Markdown.

    Everything it lists is read from the code when it is called: the tables and their
    keys, the parameter kinds, the group types registered at that moment, the outputs
    a built linkage reports, the expression functions and the units. The example file
    is :data:`EXAMPLE` (the shipped ``four_bar`` where the package is installed without
    the examples folder).

    Returns
    -------
    str
        The text of ``docs/description.md``; the same text at every call while the
        code is the same.

    Examples
    --------
    >>> text = markdown()
    >>> print(text.splitlines()[0])
    # Description files: the reference
    >>> [line for line in text.splitlines() if line.startswith("### `RRR`")]
    ['### `RRR`']
    >>> "| `period_deg` | `360.0` |" in text
    True
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mech = _demo().build()
    angle_note = next(str(w.message) for w in caught if "taken in radians" in str(w.message))
    sections = [
        _intro(),
        _units(angle_note),
        _tables(),
        _linkage(),
        _parameters(),
        _points(),
        _groups(),
        _bodies(),
        _joints_and_links(),
        _loads(),
        _effort(),
        _outputs(mech),
        _friction(),
        _inputs(mech),
        _expressions(),
        _unit_names(),
        _example(),
    ]
    return "\n\n".join(s.strip("\n") for s in sections) + "\n"


# -- the sections ------------------------------------------------------------------------
def _intro() -> str:
    tables = ", ".join(f"`{header}`" for header, _ in spec.TABLES.values())
    return f"""# Description files: the reference

A description file is a [TOML](https://toml.io) file that describes a linkage: its
parameters, the points fixed in the frame, the driver and the groups that place every
other point, the bodies, the loads, where the balancing effort acts, and what it reports.
`linkage_fmu.load(path)`, `Description.read(path)` and every `linkage-fmu` command
read it; the check reports every problem at once, each with its table and key.

This reference is written from the code by `linkage_fmu.manual.reference` (do not edit it:
run `linkage-fmu reference -o docs/description.md`). The tables, in the
order a file usually has them:
{tables}.
An example file is at the end."""


def _units(angle_note: str) -> str:
    examples = ", ".join(f'`"{t}"`' for t in ("240 mm", "1800 rpm", "30 deg",
                                               "8 bar * pi * bore**2 / 4"))
    try:
        expressions.evaluate("1800 rpm", "m", "l_AB")
    except ValueError as err:
        refused = str(err)
    force = expressions.Expression("8 bar * pi * bore**2 / 4").measure({"bore": (0.086, "m")})
    newtons = force.to(units.PINT["N"]).magnitude
    return f"""## Units and angles

**Everything is SI, and angles are radians unless a unit says otherwise.** A plain number
is taken in the SI unit of what it gives: metres, kilograms, newtons, radians, rad/s.

A number may carry a unit, in text:
{examples}.
It is converted to SI and checked against what the value gives (a parameter's kind, a
field's role, a key's unit):

- `l_AB = "1800 rpm"` is refused: `{refused}`;
- `"8 bar * pi * bore**2 / 4"` with `bore` = 0.086 m is a force of {newtons:.1f} N.

Write a space between a number and its unit or not (`"240mm"`), and spaces around an
operator after a unit (`"800 kPa * A"`: `"kPa*A"` is kilopascal ampere). A unit is any
word of [pint](https://pint.readthedocs.io)'s (`mm`, `kN`, `bar`, `rpm`, `deg`, `kg*m**2`,
`m/s**2`); the units the package itself names are listed under
[Unit names](#unit-names).

A plain angle beyond 2 pi is taken in radians, and warns, as it is probably meant in
degrees: `{angle_note}`"""


def _tables() -> str:
    rows = [(f"`{header}`", holds) for header, holds in spec.TABLES.values()]
    rows += [(f"`{header}`", f"{holds} ([joints and links](#joints-and-links), instead of "
              "`[points]`, `[[groups]]` and `[bodies.L]`)")
             for header, holds in topology.TABLES.values()]
    return "## The tables\n\n" + _table(("table", "holds"), rows) + """

A file has these tables and no others. The names of parameters, loads and outputs are
identifiers (letters, digits and `_`, not starting with a digit); points, links and
joints are named by any text, such as `"1"` or `"slider"`."""


def _linkage() -> str:
    return "## `[linkage]`\n\n" + _keys(spec.LINKAGE_KEYS)


def _parameters() -> str:
    kinds = []
    for kind in parameters.KINDS:
        unit, rule = parameters.unit_and_rule(kind)
        kinds.append((f"`{kind}`", _code(unit), units.NAMES.get(unit, "") if unit else "",
                      rule))
    return f"""## `[parameters]`

One line per parameter, `NAME = {{ default = ..., kind = "...", description = "..." }}`:
a value the linkage is built with (and an FMU parameter), used by name in the
expressions of the other tables. A name is not an input's
({", ".join(f"`{n}`" for n in spec.INPUT_NAMES)}).

{_keys(spec.PARAMETER_KEYS)}

The kinds, each with its SI unit and the rule its value meets:

{_table(("kind", "unit", "measures", "rule"), kinds)}

A value outside its rule, `min` or `max` is refused, naming the parameter. An FMU's
modelDescription declares the same bounds as each variable's `min` and `max` (`> 0` as
`min="5e-324"`, the smallest positive float64; `>= 0` as `min="0.0"`; a branch or a sign
as -1 and 1), and the FMU refuses a value outside them with an Error (a real at
`ExitInitializationMode`, an integer when it is set)."""


def _points() -> str:
    return """## `[points]`

`NAME = [x, y]`: a point fixed in the frame, its coordinates in m (numbers, numbers with
units, or expressions of the parameters). The frame's points are placed from the start;
every other point is placed by a group."""


def _groups() -> str:
    roles = [(f"`{role}`", _code(unit), _cell(ROLE_MEANINGS.get(role, "")))
             for role, unit in ROLES.items()]
    types = sorted(Group.registry.items(), key=lambda kc: (not kc[1].DRIVER, kc[0].lower()))
    drivers = " or ".join(f"`{kind}`" for kind, cls in types if cls.DRIVER)
    out = [f"""## `[[groups]]`

One table per group, `type = "..."` and the type's fields. The first group is a
driver ({drivers}). A later driver (a second crank, a motor between two links with
`base`, a cylinder) makes the linkage one driven by time: its inputs are then each
driver's coordinate, speed and acceleration (`theta_<j>`, `omega_<j>`, `alpha_<j>` for
an angle about the pair `j`, `s_<j>`, `v_<j>`, `a_<j>` for a travel), its efforts each
driver's (`Mb_<j>`, the moment on the driver's link; `Fb_<j>`, a cylinder's force on its
rod, > 0 pushing its pins apart), and it takes no `[effort]`. Each group places points
and adds links from points already placed, so the order of the tables is an order
in which every point is placed before it is used. A field's value is a name, or a
number (a number with a unit, an expression of the parameters) in the field's unit; a
field whose key is not optional must be given.

Each field has a role, which says what its value must be:

{_table(("role", "unit", "value"), roles)}

The group types:"""]
    for kind, cls in types:
        out.append(_group_type(kind, cls))
    return "\n\n".join(out)


def _group_type(kind: str, cls: type) -> str:
    """The section of one group type: its summary, whether it drives, its fields."""
    doc = inspect.cleandoc(cls.__dict__.get("__doc__") or "")
    summary = " ".join(doc.split("\n\n")[0].split()) if doc else ""
    rows = [(f"`{key}`", f.role, _code(f.unit), "yes" if key in cls.OPTIONAL else "",
             _cell(_rst_to_markdown(f.description))) for key, f in cls.FIELDS.items()]
    shipped = sorted(name for name in presets.names()
                     if any(g.get("type") == kind for g in presets.preset(name).groups))
    lines = [f"### `{kind}`", ""]
    if summary:
        lines += [_cell(_rst_to_markdown(summary)), ""]
    if cls.DRIVER:
        lines += ["It drives the linkage: its coordinate is an input.", ""]
    lines.append(_table(("key", "role", "unit", "optional", "description"), rows))
    if shipped:
        lines += ["", "In the shipped linkages " + ", ".join(f"`{n}`" for n in shipped) + "."]
    return "\n".join(lines)


def _bodies() -> str:
    return f"""## `[bodies.L]`

One table per moving link `L` (every link a group adds), its mass properties:

{_keys(spec.BODY_KEYS)}

`cg` is an inline table, `{{ from = "B", along = "l_BC / 2" }}`: the centre of mass in the
link's own frame, measured from its point `from`, either `along` and `across` its
direction or at `distance` in the direction `angle`:

{_keys(spec.CG_KEYS)}"""


def _joints_and_links() -> str:
    return f"""## Joints and links

A linkage may be written as joints and links instead, as it is drawn (in PMKS+, SAM or on
paper): `[joints]`, `[[links]]` and `[crank]` take the place of `[points]`, `[[groups]]`
and `[bodies.L]` (a file with both is refused); the other tables are the same. The
reader decomposes it into the groups above (`linkage-fmu info FILE` lists them, in the
order they are solved), and everything else (kernels, FMUs, sweeps, friction, the drive)
takes the linkage as it takes one written as groups. `examples/joints/` holds every
preset written so.

```toml
[linkage]
name = "drawn_four_bar"
frame = "0"                 # the frame's name (default "0")

[parameters]
l_AB = {{ default = 0.1, kind = "length", description = "crank length AB" }}

# every joint where it is drawn, one pose of the linkage: numbers in m, with
# units, or expressions of the parameters and of the drawn coordinates x_J, y_J
[joints]
A = [0, 0]
B = ["l_AB", 0]
C = ["300 mm", "y_B + 0.2"]
D = [0.4, 0]
# a prismatic pair: P = {{ at = [x, y], slide = [dx, dy], guide = "L" }}

[[links]]                   # the frame's entry (optional): its joints
name = "0"
joints = ["A", "D"]

[[links]]                   # a moving link: joints, mass, inertia, cg as drawn
name = "1"
joints = ["A", "B"]
mass = 0.5
inertia = 0.001
cg = [0.05, 0]

[[links]]
name = "2"
joints = ["B", "C"]
mass = 1.2
inertia = 0.01
cg = ["(x_B + x_C) / 2", "(y_B + y_C) / 2"]

[[links]]
name = "3"
joints = ["C", "D"]
mass = 0.8
inertia = 0.006
cg = [0.35, 0.1]

[crank]                     # the driven link and its pivot on the frame
link = "1"
pivot = "A"
```

It has no `[effort]` and no `[[outputs]]`: the effort is `Mb` on the crank, and the
outputs are the x and y components of `F01`, `F12`, `F23` and `F03`, and `Mb` (see
below).

### `[joints]`

`J = [x, y]` is a revolute joint where it is drawn. A joint listed by one moving link
joins that link to the frame; by two, joins them; by k of them, it is a compound joint
of k - 1 revolute pairs. A joint the frame's entry lists (see below) is on the frame:
each of the k moving links that list it is pinned to the frame there (k pairs). A
prismatic pair is a table:

{_keys(topology.JOINT_KEYS)}

### `[[links]]`

Each moving link is a table:

{_keys(topology.LINK_KEYS)}

### The frame's entry in `[[links]]`

The frame may have an entry too, as PMKS+ draws the ground as a link: the table whose
`name` is the frame's (`[linkage] frame`, default `"0"`), with these keys only (the frame
has no mass, inertia, cg or points, and an entry that gives one is refused):

{_keys(topology.FRAME_KEYS)}

So several links pinned to the frame at one place share one joint: with
`joints = ["Z"]` in the frame's entry, a triangle `["Z", "B", "D"]` and a rocker
`["Z", "C"]` are each pinned to the frame at Z (two pairs), where without the entry Z
would join them to each other. A joint the frame's entry lists must be on a moving link
(it joins nothing else). Without a frame entry, a joint on the frame is one that one
moving link only lists, and two links pinned to the frame at one place are two joints
drawn at the same place. `examples/jansen.toml` has one.

### `[crank]`

{_keys(topology.CRANK_KEYS)}

The crank angle `theta` is absolute: the angle from +x of the line from the pivot to the
crank's first other joint (which must be revolute), as in the group form. The drawn crank
angle is that line's angle in the drawn pose.

### `[[drivers]]`

Instead of `[crank]`, a linkage may list its drivers, one table per driven pair (a
linkage with several degrees of freedom lists one per degree):

{_keys(topology.DRIVER_KEYS)}

- **A revolute pair's angle.** On the frame it is a crank, as `[crank]`'s. Between two
  moving links it is a motor at an elbow: its angle is that of the second link relative
  to the first, each link's direction the line from the joint to the link's first other
  joint (the second's revolute), counter-clockwise positive. Its inputs are `theta_<j>`,
  `omega_<j>` and `alpha_<j>` (rad, rad/s, rad/s2) and its effort `Mb_<j>` (N.m), the
  moment it applies to its second link; the first (or the frame) takes the reaction.
- **A prismatic pair's travel: a cylinder.** Its barrel and its rod are two links, each
  with the pair and one revolute joint (their pins); the pair's `guide` is the barrel, and
  its `slide` points from the barrel's pin to the rod's. The travel is 0 as drawn and
  positive along `slide`: the cylinder is its drawn length plus the travel. Its inputs
  are `s_<j>`, `v_<j>` and `a_<j>` (m, m/s, m/s2) and its effort `Fb_<j>` (N), the force
  the barrel applies to the rod along `slide` (> 0 pushes the pins apart). A cylinder is
  a binary link of driven length: with the link its rod's pin moves (pinned to a placed
  joint), it is a `cylinder` group, its barrel's pin placed before it.

A linkage with one crank on the frame keeps `theta`, `omega`, `alpha` and `Mb`, and
`[[drivers]]` with one such table is `[crank]`. With several drivers, a motor or a
cylinder, the linkage is driven by time: each driver's coordinate starts where it is
drawn, and each effort is an output (`[effort]` is refused).

### What the reader checks

The mobility, by Gruebler's count `3 n - 2 p` (n moving links, p pairs: one per joint
on one link, k - 1 per joint on k links, k per joint of the frame's entry on k links),
must be 1 (with `[[drivers]]`, their number), and the message gives both counts. Every
joint is on a moving link, every link carries two joints or more, the crank's pivot is a
revolute joint on the frame (no other link lists it, or the frame's entry lists it),
every name a link lists is a joint, every slide has a length, a prismatic pair of two
links says which carries the guide. A driver names a joint of `[joints]`, a pair takes
one driver, a joint with more than two bodies says which pair is driven (`links`), a
cylinder's barrel and rod are each pinned at one end, and a driven slider on a frame
guide is refused (draw the actuator as a cylinder).

### The decomposition

The drivers come first, each as soon as what it needs is placed (a motor its first
link, a cylinder its barrel's pin). Then, as long as a link is not placed, the first
dyad the library solves is taken off, trying the links two by two in the order of
`[[links]]`, and the drivers that it lets be placed follow:

{_drawn_groups()}

A link's other joints and its `points` become `point` groups on it, once it is placed
(a load or an effort may act at them, and a load's `value` may use their `x_P`, `y_P`);
its centre of mass becomes its `cg = {{ from, along, across }}` in the group type's link direction.
What no dyad resolves is the smallest connected set of the links left that the placed links hold
with mobility 0, solved as one `closure` group (its pairs revolute: a group of more than
two links with a prismatic pair, or a dyad with one that the table above does not list,
is refused as a group the decomposition cannot solve). A driver that no step can place
(one inside a class III group or a closure, or a cylinder whose rod's pin is placed
first) is refused, naming its `[[drivers]]` table; a closure in a linkage driven by
time is refused, so far.

An `RPR` lever's guide runs from its pin through the block's, as its own geometry makes
it: a `slide` drawn within {assur.SLIDE_TOLERANCE:g} of that line (the sine of the angle
between them: a direction typed to six significant digits) is taken for it, and the
slide is checked against it at every parameter set. One further off is refused, naming
the distance by which it misses the lever's pin; written as the pins' difference
(`slide = ["x_A - x_O3", "y_A - y_O3"]` for a block's pin A and a lever's pin O3) it
passes through it exactly.

Every length, angle, guide point and position in a link's own frame is an expression of
the drawn coordinates, so it follows the parameters. The assembly modes (`branch`) are
those of the drawn pose at the parameters' defaults; where flipping a parameter of kind
`branch` flips a dyad's mode in the drawn pose at the defaults, the dyad's branch is that
parameter (times -1 where needed), so that a drawn pose written with a branch parameter
keeps following it. Building the linkage solves it at the drawn crank angle and checks
that every drawn joint is where it is drawn to {assur.POSE_TOLERANCE:g} m; else it is
refused as a drawn pose from which a group cannot be assembled, naming the group, the
joint and the distance. A dyad drawn at a toggle (its three joints in line, a rod square
to its guide) has no mode: draw it apart.

### Pairs and their names

A revolute pair takes its joint's name; at a compound joint J the pair J joins the first
two of its links to be placed, and each further link L is joined to the first by the
pair `J_L` (at the point `J_L` of the first link, where J is). At a joint J of the
frame's entry, the pair J joins the frame to the first of its links to be placed, and
each further link L is joined to the frame by the pair `J_L` (at the frame's point
`J_L`, where J is).

A prismatic pair takes its joint's name; its normal force acts through, and its couple
is taken about, the pin of the dyad that makes it (an `RRP`'s and an `RPR`'s pin, the
`RPP` slot's pin), or for an `RPP`'s frame guide the yoke's point `GUIDE_ref` where the
slot's line crosses the guide's. The `at` of a prismatic pair is a point of the link
that slides (not the one that carries the guide): a load or an effort may act at it by
the pair's name, and a load's `value` may use its `x_J`, `y_J`.

### What is made when it is not given

- `[[outputs]]`: after the file's own `[[outputs]]` tables, for each two bodies joined
  by a pair whose reaction none of them reports (as a force between the two bodies, the
  normal force or couple of their prismatic pair, or an expression of its `N_J`, `M_J`,
  `Fx_J`, `Fy_J`), the force of the body placed first (the frame first of all) on the
  other, `kind = "force"`, named `F<by><on>` (`F<by>_<on>` when a name is longer than
  one character), as listed by `linkage-fmu info`; then each effort they do not name.
  `[linkage] default_outputs = false` keeps the file's tables only (and each effort,
  which every linkage reports: see `[[outputs]]`);
- `[effort]`: a moment named `Mb` on the crank;
- `[inputs] theta`: the drawn crank angle (the linkage starts where it is drawn);
- `[linkage] model`: the name.

`Mb`, the shaking force and moment, `J_red` and the diagnostics follow as for any
linkage."""  # noqa: E501 (the tables' rows)


def _drawn_groups() -> str:
    """The table of the group types of a fixed size the decomposition recognises, in the
    order it tries them, each as its ``DRAWING`` says."""
    rows = [f"| `{cls.kind}` | {_cell(cls.DRAWING.links)} | {_cell(cls.DRAWING.pairs)} |"
            for cls in assur.recognisers() if cls.DRAWING.size is not None]
    return "\n".join(["| dyad | its links | their pairs |", "| --- | --- | --- |", *rows])


def _loads() -> str:
    defaults = {**spec.LOAD_DEFAULTS, **spec.TABLE_DEFAULTS}
    rows = [(f"`{key}`", _code(_toml_value(defaults[key])) if key in defaults else "",
             _cell(meaning)) for key, meaning in spec.LOAD_KEYS.items()]
    examples = "\n\n".join(f"```toml\n{text}```" for text in CYCLE_LOADS)
    return f"""## `[[loads]]`

One table per named load: a force on a moving link at one of its points, or a moment on
it. Its magnitude is given in one of three ways:

- as an input: its value is given at each state (an FMU input, an option of
  `linkage-fmu table`), starting at `start`;
- over the cycle by `value = "EXPR"`: an expression of the crank angle `theta` (rad),
  the parameters and the positions `x_P`, `y_P` (m) of every placed point `P`, computed
  at each state;
- over the cycle by `table`: the points `[theta_deg, value]` of one period
  (`period_deg`, default {spec.TABLE_DEFAULTS["period_deg"]:g} degrees), from a CSV file
  `table = "FILE.csv"` with the columns `theta_deg` and `value` (relative to the
  description file) or inline, `table = [[theta_deg, value], ...]`; the load is the
  periodic cubic spline through them, its values in `table_unit` (default the load's),
  times `scale`.

A load over the cycle is no input and has no `start`; `period_deg`, `table_unit` and
`scale` belong to a table.

{_table(("key", "default", "meaning"), rows)}

Loads over the cycle, each a table the [example](#an-example) may take as it is:

{examples}"""


def _effort() -> str:
    chooser = next(name for name in presets.names()
                   if any(w is not None for w in presets.preset(name).efforts))
    d = presets.preset(chooser)
    choose = next(iter(d.efforts))[0]
    text = d.to_toml()
    parameter = next(line for line in text.splitlines() if line.startswith(f"{choose} = "))
    block = next(b for b in text.split("\n\n") if b.startswith("[effort]"))
    return f"""## `[effort]`

Where the balancing effort acts: the moment on a link (the driver's, for the driving
moment) that keeps the linkage in equilibrium with its loads, weights and inertia, or a
force at a point. An output of kind `effort` reports it.

{_keys(spec.EFFORT_KEYS)}

Or a choice parameter selects it, one option per value:

{_keys(spec.EFFORT_CHOICE_KEYS)}

The shipped `{chooser}` does this with its parameter `{choose}`:

```toml
[parameters]
{parameter}

{block}
```"""


def _outputs(mech: Mechanism) -> str:
    kinds = [(f"`{kind}`", _cell(spec.OUTPUT_KINDS.get(kind, ""))) for kind in spec.OUTPUT_KEYS]
    out = [f"""## `[[outputs]]`

One table per output, `kind = "..."` and its keys. Every linkage reports its balancing
effort: an `[effort]` that no table of kind `effort` names is reported after the
tables, as one would (a linkage written as joints and links also reports the force of
each of its pairs the tables do not report, unless `[linkage] default_outputs = false`:
see Joints and links). An output is computed in SI: its `unit` is one of the package's
units (`"N"`, `"N.m"`, ...; see Unit names), and an effort's is that of the effort. The kinds:

{_table(("kind", "reports"), kinds)}"""]
    for kind, keys in spec.OUTPUT_KEYS.items():
        out.append(f"### `kind = \"{kind}\"`\n\n" + _keys(keys))
    out.append(f"```toml\n{EXPRESSION_OUTPUT}```")
    every = [name for name in mech.output_info if name in SHAKING] + list(
        mech.diagnostic_names)
    rows = [(f"`{name}`", _code(mech.output_info[name][0]), _cell(mech.output_info[name][1]))
            for name in every]
    out.append(f"""### The outputs every linkage has

Besides those of its `[[outputs]]`, every linkage reports these (`gamma_<joint>` once for
each group with a transmission angle, named by its joint); no other output or load may
take their names:

{_table(("output", "unit", "meaning"), rows)}""")
    return "\n\n".join(out)


def _friction() -> str:
    shown = "slider_crank"
    d = presets.preset(shown)
    text = d.to_toml()
    blocks = [b.strip("\n") for b in text.split("\n\n") if b.startswith("[friction.")]
    pin, slide = (next(b for b in blocks if b.startswith(f"[friction.{j}]"))
                  for j in ("A", "guide"))
    mech = d.build()
    named = [(f"`{jf.output}`", _code(mech.output_info[jf.output][0]),
              _cell(mech.output_info[jf.output][1])) for jf in mech.friction.joints]
    rows = [(f"`{o.name}`", _code(o.unit), _cell(o.description)) for o in (
        FrictionOutput("Mf_<J>", Revolute("<J>", "<J>", "<a>", "<b>")),
        FrictionOutput("Ff_<J>", Prismatic("<J>", "<J>", "<a>", "<b>", (0.0, 1.0))),
        FrictionOutput("Ff_<J>", Prismatic("<J>", "<J>", "<a>", "<b>", "<L>")),
        LossOutput("P_loss"), LossOutput("eta"))]
    return f"""## `[friction.J]`

One table per pair `J` with Coulomb friction (a joint a group declares), its keys
numbers, numbers with units or expressions of the parameters:

{_keys(spec.FRICTION_KEYS)}

The shipped `{shown}` declares one in each of its pairs through parameters; those of
its pin A and of its prismatic pair guide:

```toml
{pin}

{slide}
```

A revolute pair resists the relative rotation of its two links with a moment `mu *
radius * |R|`, `R` its reaction; a prismatic pair resists their relative sliding with
a force `mu * |N|`, `N` its normal force (with a `length`, `mu * (|N1| + |N2|)` from the
slider's two end contacts). The friction opposes the relative motion; where the crank
stands (`omega = 0`) it opposes the motion the crank would start in the direction
`drive` of `[linkage]`. Where no finite balancing effort moves the linkage, friction
locks it: one state raises `SelfLockingError`, and arrays have no outputs there (`valid`
False, `status` `LOCKED`; a sweep counts them in `locked`).

A linkage with friction reports one output per pair and two more:

{_table(("output", "unit", "meaning"), rows)}

`<a>` and `<b>` are the pair's two links, in the order its group declares the joint
(its reaction is the action of `<a>` on `<b>`). The friction acts on link `<b>` with the
value reported and on link `<a>` with its opposite: `Mf_J` is counter-clockwise
positive, `Ff_J` positive along the pair's sliding direction `t = (n_y, -n_x)` (its
normal `n` turned 90 degrees clockwise; for a guide on a moving link `<L>`, along that
link's direction). A built linkage's outputs, and its FMUs' variables, name the links;
the `{shown}`'s:

{_table(("output", "unit", "meaning"), named)}

`eta = 1 - P_loss / P_in`: `P_in` is the power that enters the linkage at that instant,
the sum of the powers that are positive among the balancing effort's, each load's,
gravity's and the kinetic energy the links give up (`-dT/dt`, the power of the
d'Alembert inertia). Their sum is `P_loss` (the power balance), so `eta` is in `[0,
1]`: 1 without friction, 0 where friction takes all the power that enters, NaN where
none enters. At `omega = 0` the powers are taken per unit of speed as the crank starts
in its `drive` direction."""


def _inputs(mech: Mechanism) -> str:
    from ..fmi.variables import variables

    meanings = {v.name: v.description for v in variables(mech) if v.name in spec.INPUT_UNITS}
    start = Description("start").inputs
    rows = [(f"`{name}`", _code(unit), _code(_toml_value(start.get(name, 0.0))),
             _cell(meanings.get(name, ""))) for name, unit in spec.INPUT_UNITS.items()]
    return f"""## `[inputs]`

The start values of the crank's motion, which the linkage takes where none is given (in
`solve`, `linkage-fmu table`, an FMU's start values). A load's start value is its `start`
in `[[loads]]`.

{_table(("key", "unit", "default", "meaning"), rows)}

`omega = "1800 rpm"` is {units.to_si("1800 rpm", "rad/s", "omega"):.6g} rad/s."""


def _expressions() -> str:
    functions = ", ".join(f"`{name}`" for name in sorted(expressions.FUNCTIONS))
    constants = ", ".join(f"`{name}`" for name in expressions.CONSTANTS)
    binary = " ".join(f"`{op}`" for op in expressions.BINARY_OPERATORS)
    signs = " ".join(f"`{op}`" for op in expressions.SIGNS)
    disagree = "its units do not agree"
    try:
        expressions.evaluate("1 m + 1 s", "m", "l_AB")
    except ValueError as err:  # what pint says after it depends on its version
        refused = str(err)[:str(err).index(disagree) + len(disagree)]
    rows = [
        ("a parameter's `default`", "none: an expression of numbers (`\"pi / 2\"`, "
                                    "`\"120 mm\"`)"),
        ("a load's `value`", "`theta` (rad), the parameters, `x_P` and `y_P` (m) of every "
                             "placed point `P`"),
        ("an output's `expression`", "`N_J`, `M_J`, `Fx_J`, `Fy_J` of every pair `J`, the "
                                     "efforts' names, the parameters"),
        ("every other number: group fields, `[points]`, `[bodies.L]`, `gravity`, a "
         "load's `start` and `scale`, `[inputs]`", "the parameters"),
    ]
    return f"""## Expressions

Where a number is expected, text may give an expression: `"l_BC / 2"`,
`"-l_AS1 * sin(beta1)"`, `"pi / 2"`, `"120 mm + 2 * l_OA"`. It is parsed, never run as
code, and may hold

- numbers, numbers with units (`"40 mm"`), and names;
- the operators {binary}, the signs {signs}, and parentheses;
- the constant {constants};
- calls of the functions {functions} (as Python's `math` and builtins: angles in
  radians; `degrees` and `radians` convert; `sign(x)` is -1, 0 or 1 as `x` is negative,
  zero or positive).

The names it may use depend on where it is:

{_table(("where", "names"), rows)}

An expression with units is checked as a number with a unit is, its names taken in their
units (a parameter's kind, `theta` in rad, `x_P` in m): `"1 m + 1 s"` is refused,
`{refused}`."""


def _unit_names() -> str:
    rows = [(_code(unit), units.NAMES.get(unit, ""), _code(pint)) for unit, pint in
            units.PINT.items()]
    return f"""## Unit names

The units the package names (in the tables above, in its FMUs' `modelDescription`), what
each measures, and pint's spelling of it, which a value's text may use too:

{_table(("unit", "measures", "pint"), rows)}"""


def _example() -> str:
    path = EXAMPLE if EXAMPLE.is_file() else presets.path("four_bar")
    shown = ("examples/coupler_four_bar.toml" if path == EXAMPLE else
             "linkage_fmu/linkages/four_bar.toml")
    text = path.read_text(encoding="utf-8")
    title = tomllib.loads(text)["linkage"]["title"]
    return f"""## An example

`{shown}`: {title}.

```toml
{text.rstrip()}
```"""


# -- helpers ------------------------------------------------------------------------------
def _demo() -> Description:
    """A small linkage with a dyad whose joint is named ``<joint>`` and a centre of mass
    at ``angle = 90`` (meant in degrees): what every linkage reports, and the warning
    such an angle gives, as the code words them."""
    return (Description("demo", model="Demo", source="linkage.toml")
            .point("A", 0, 0).point("D", 1, 0)
            .group("crank", link="1", pivot="A", tip="B", length=0.3)
            .group("RRR", link1="2", link2="3", end1="B", middle="<joint>", end2="D",
                   length1=1, length2=1, branch=1)
            .body("1", cg={"from": "A", "distance": 0.1, "angle": 90})
            .body("2", cg={"from": "B"}).body("3", cg={"from": "D"})
            .effort("Mb", body="1").output("effort", name="Mb"))


def _keys(keys: dict[str, str]) -> str:
    """The table of a mapping key -> meaning."""
    return _table(("key", "meaning"), [(f"`{k}`", _cell(v)) for k, v in keys.items()])


def _table(head: tuple[str, ...], rows: list[tuple[str, ...]]) -> str:
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join("---" for _ in head) + "|"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def _code(text: str) -> str:
    return f"`{text}`" if text else ""


def _toml_value(value: Any) -> str:
    return json.dumps(value) if isinstance(value, str) else repr(value)


def _rst_to_markdown(text: str) -> str:
    """Docstring text in Markdown: ``code`` and :role:`~a.b` as `code`."""
    text = re.sub(r":\w+:`~?([^`]*)`", r"``\1``", text)
    return text.replace("``", "`")


def _cell(text: str) -> str:
    """Text for a table cell: ``|`` and ``<`` escaped outside code spans."""
    parts = text.split("`")
    for k in range(0, len(parts), 2):
        parts[k] = parts[k].replace("|", "\\|").replace("<", "\\<")
    return "`".join(parts)


if __name__ == "__main__":
    sys.stdout.write(markdown())
