"""A linkage written as joints and links: its tables read and checked, its pairs and
its mobility.

The joints-and-links form of a description file (the way PMKS+ and SAM take a linkage)
names every joint where it is drawn and every moving link by the joints it carries::

    [linkage]   name, frame (the frame's name, default "0"), ...
    [joints]    J = [x, y]                                 a revolute joint
                J = { at = [x, y], slide = [dx, dy], guide = "L" }   a prismatic pair
    [[links]]   name, joints = [...] (>= 2), mass, inertia, cg = [x, y],
                points = { P = [x, y] }                    a moving link
                name = FRAME, joints = [...]               the frame's entry (optional)
    [crank]     link, pivot                                the one crank, or
    [[drivers]] joint, links = [first, second]             each driven pair

A joint listed by one moving link joins it to the frame; by two, joins them; by k >= 3,
it is a compound joint of k - 1 revolute pairs. A joint the frame's entry lists (the
[[links]] table named as the frame) is on the frame: each of the k moving links that
list it is pinned to the frame there (k pairs), as PMKS+ draws one ground pin with
several links. A coordinate may be an expression of the
parameters and of the coordinates ``x_J``, ``y_J`` of the joints (their drawn ones).
:func:`read` checks the tables and the topology (every joint on a moving link, every
link on two joints, the crank's pivot on the frame or each driver's pair one it can
drive, a mobility equal to the number of drivers, by Gruebler's count);
:mod:`~linkage_fmu.descriptions.assur` decomposes it into the group form.

Examples
--------
>>> t, problems = read({"joints": {"A": [0, 0], "B": [0.1, 0], "C": [0.3, 0.2],
...                                "D": [0.4, 0]},
...                     "links": [{"name": "1", "joints": ["A", "B"]},
...                               {"name": "2", "joints": ["B", "C"]},
...                               {"name": "3", "joints": ["C", "D"]}],
...                     "crank": {"link": "1", "pivot": "A"}}, {})
>>> problems, t.mobility(), t.on("A"), t.pair_count()
([], 1, ('1',), 4)

The rocker 3 pinned to the frame at the crank's pivot A (a rod from C to A), with the
frame's entry listing A: A is two pairs with the frame.

>>> t, problems = read({"joints": {"A": [0, 0], "B": [0.1, 0], "C": [0.3, 0.2]},
...                     "links": [{"name": "0", "joints": ["A"]},
...                               {"name": "1", "joints": ["A", "B"]},
...                               {"name": "2", "joints": ["B", "C"]},
...                               {"name": "3", "joints": ["C", "A"]}],
...                     "crank": {"link": "1", "pivot": "A"}}, {})
>>> problems, t.mobility(), t.on("A"), t.on_frame, t.pair_count()
([], 1, ('1', '3'), frozenset({'A'}), 4)
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

from ..errors import LinkageFmuError
from ..expressions import Expression, check_units

#: table -> (its header in a description file, what it holds), for the joints-and-links form
TABLES: dict[str, tuple[str, str]] = {
    "joints": ("[joints]", "every joint where it is drawn: J = [x, y] (a revolute joint) "
                           "or J = { at, slide, guide } (a prismatic pair)"),
    "links": ("[[links]]", "each moving link: its name, its joints, mass, inertia and "
                           "centre of mass where drawn; and, optionally, the frame's entry: "
                           "its name and its joints"),
    "crank": ("[crank]", "the driven link and its pivot on the frame"),
    "drivers": ("[[drivers]]", "instead of [crank], each driven pair: a revolute pair's "
                               "angle (a crank, a motor between two links) or a prismatic "
                               "pair's travel (a cylinder)"),
}
#: key of a prismatic joint's table in [joints] -> what it is
JOINT_KEYS = {
    "at": "where the pair is drawn, [x, y]: a point of the link that slides, on the guide's "
          "line (required)",
    "slide": "direction of the guide, [dx, dy], of any length but not zero (required)",
    "guide": "the link that carries the guide (default: the frame when one moving link "
             "lists the joint; required when two do)",
}
#: key of a [[links]] table -> what it is
LINK_KEYS = {
    "name": "name of the moving link (required), as in output names; the table named as "
            "the frame ([linkage] frame) is the frame's entry (see below)",
    "joints": "the joints it carries, a list of two or more names of [joints] (required)",
    "mass": "mass of the link, kg (default 0)",
    "inertia": "moment of inertia about its centre of mass, kg.m2 (default 0)",
    "cg": "its centre of mass where drawn, [x, y] in m (default: its first joint)",
    "points": "points fixed on it that join nothing (a coupler point, where a load acts), "
              "{ P = [x, y] } where drawn",
}
#: key of the frame's entry in [[links]] (the table named as the frame) -> what it is
FRAME_KEYS = {
    "name": "the frame's name, [linkage] frame (default \"0\")",
    "joints": "the joints on the frame, a list of one or more names of [joints]: each "
              "moving link that lists one is pinned to the frame there (k links on it: k "
              "pairs)",
}
#: key of [crank] -> what it is
CRANK_KEYS = {
    "link": "the driven link (required)",
    "pivot": "its joint with the frame it turns about (required); theta is the angle of "
             "the line from the pivot to the link's first other joint",
}
#: key of a [[drivers]] table -> what it is
DRIVER_KEYS = {
    "joint": "the driven pair, a joint of [joints] (required). A revolute joint's angle: on "
             "the frame a crank, its angle absolute as [crank]'s; between two moving links a "
             "motor, the angle of the second link relative to the first, each link's "
             "direction the line from the joint to its first other joint. A prismatic "
             "pair's travel: a cylinder, its barrel (the guide) and its rod each pinned at "
             "its far end, slide pointing from the barrel's pin to the rod's; the travel is "
             "0 as drawn, positive along slide",
    "links": "[first, second]: the pair's links, the frame's name for the frame (default: "
             "the frame first, then the links in the order of [[links]]; a cylinder's "
             "barrel first)",
}
_COORDINATE = re.compile(r"\b([xy])_([A-Za-z_][A-Za-z0-9_]*)\b")


@dataclass(frozen=True)
class Joint:
    """A joint where drawn: ``at`` = (x, y) as expressions (text or numbers) of the
    parameters; a prismatic pair also has ``slide`` (its direction) and ``guide`` (the
    link that carries the guide, '' for the frame)."""

    name: str
    at: tuple
    slide: tuple | None = None
    guide: str = ""

    @property
    def prismatic(self) -> bool:
        return self.slide is not None


@dataclass(frozen=True)
class Link:
    """A moving link: its joints (in the order given), mass, inertia and drawn cg."""

    name: str
    joints: tuple
    mass: Any = 0.0
    inertia: Any = 0.0
    cg: tuple = ()
    points: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Drive:
    """A driven pair: the angle (``kind`` "angle") of link ``second`` relative to
    ``first`` (the frame's name for a crank) at the revolute joint ``joint``, or the
    travel ("travel") of the rod ``second`` in the barrel ``first`` at the prismatic
    pair ``joint``; ``where`` names its table."""

    joint: str
    kind: str
    first: str
    second: str
    where: str = "[crank]"


@dataclass(frozen=True)
class Topology:
    """A checked joints-and-links linkage (see :func:`read`): ``driven`` holds its
    drivers (:class:`Drive`, the [crank] or each [[drivers]] table), ``on_frame`` the
    joints the frame's entry in [[links]] lists, ``tables`` each moving link's number
    in [[links]] (from 1, the frame's entry counted)."""

    frame: str
    joints: dict
    links: dict
    driven: tuple
    on_frame: frozenset = frozenset()
    tables: dict = field(default_factory=dict)

    def on(self, joint: str) -> tuple:
        """The moving links that list ``joint``, in the order of [[links]]."""
        return tuple(name for name, link in self.links.items() if joint in link.joints)

    def grounded(self, joint: str) -> bool:
        """Whether ``joint`` joins its moving links to the frame: the frame's entry lists
        it, or one moving link only does."""
        return joint in self.on_frame or len(self.on(joint)) == 1

    def pair_count(self) -> int:
        """Number of pairs: one per joint on one link (to the frame), k - 1 per joint on
        k >= 2 links (a compound joint), k per joint of the frame's entry on k links."""
        return sum(len(self.on(j)) if j in self.on_frame else max(1, len(self.on(j)) - 1)
                   for j in self.joints)

    def mobility(self) -> int:
        """Gruebler's count, 3 n - 2 p, for n moving links and p lower pairs."""
        return 3 * len(self.links) - 2 * self.pair_count()

    @property
    def drivers(self) -> tuple[str, ...]:
        """The pairs that drive it, one per degree of freedom its mobility must have."""
        return tuple(d.joint for d in self.driven)


class CycleError(LinkageFmuError, ValueError):
    """A drawn position that uses itself; ``cycle`` holds the joints around the loop."""

    def __init__(self, message: str, cycle: tuple):
        super().__init__(message)
        self.cycle = cycle


def inline(source: Any, joints: dict, parameters: set, seen: tuple = ()) -> Any:
    """``source`` with every ``x_J``/``y_J`` of a joint J (not a parameter) replaced by
    the expression of J's drawn coordinate, recursively; a :class:`CycleError` (a
    ValueError) for a loop.

    Examples
    --------
    >>> inline("x_B + 1", {"B": Joint("B", ("l", 0))}, {"l"})
    '(l) + 1'
    """
    if not isinstance(source, str):
        return source

    def replace(m):
        axis, name = m[1], m[2]
        if m[0] in parameters or name not in joints:
            return m[0]
        if name in seen:
            loop = seen[seen.index(name):]
            raise CycleError(f"the drawn position of {name} uses itself "
                             f"({' -> '.join(seen + (name,))})", loop)
        value = joints[name].at["xy".index(axis)]
        return f"({inline(value, joints, parameters, seen + (name,))})"

    return _COORDINATE.sub(replace, source)


def read(data: dict, values: dict, frame: str = "0", measures: dict | None = None
         ) -> tuple[Topology | None, list[str]]:
    """The topology of the joints-and-links tables of ``data`` (a description file's
    TOML), and the problems found, each naming its table and key. ``values`` are the
    parameters' default values, to evaluate the drawn pose; ``measures`` (name ->
    (value, unit)) what each measures, to check coordinates with units (which are
    taken in SI: a coordinate is in m).

    Examples
    --------
    >>> t, problems = read({"joints": {"A": [0, 0], "B": [1, 0]},
    ...                     "links": [{"name": "1", "joints": ["A", "B"]}],
    ...                     "crank": {"link": "1", "pivot": "A"}}, {})
    >>> print(problems[0])
    [[links]]: the linkage's mobility is -1, not 1: 3 x 1 moving links - 2 x 2 pairs (Gruebler's
    count; a joint on one link is a pair with the frame, a joint on k links k - 1 pairs)
    """
    found: list[str] = []
    units = {} if measures is None else measures
    joints, broken = _joints(data.get("joints", {}), values, found, units)
    ground: dict = {}  # the frame's entry: "where" (its table) and "joints"
    links = _links(data.get("links", []), joints, broken, values, frame, found, units,
                   ground)
    if joints is None or broken or links is None:
        return None, found
    on = {j: tuple(n for n, link in links.items() if j in link.joints) for j in joints}
    on_frame = frozenset(ground.get("joints", ()))
    for name, joint in joints.items():
        where = f"[joints] {name}"
        if not on[name] and name in on_frame:
            found.append(f"{ground['where']} joints: {name} is on the frame only: no moving "
                         "link lists it, so it joins nothing")
        elif not on[name]:
            found.append(f"{where}: a joint on no link: no [[links]] table lists it")
        if joint.prismatic and name in on_frame and len(on[name]) >= 2:
            found.append(f"{where}: a prismatic pair joins two bodies; the frame's entry "
                         f"and {len(on[name])} moving links list it: {', '.join(on[name])}")
        elif joint.prismatic:
            if len(on[name]) >= 3:
                found.append(f"{where}: a prismatic pair joins two links (or a link and the "
                             f"frame); it is listed by {len(on[name])}: {', '.join(on[name])}")
            elif len(on[name]) == 2 and joint.guide not in on[name]:
                found.append(f"{where} guide: two links list this prismatic pair "
                             f"({', '.join(on[name])}): say which carries the guide, "
                             f"guide = \"{on[name][0]}\" or \"{on[name][1]}\""
                             + (f" (got {joint.guide!r})" if joint.guide else ""))
            elif len(on[name]) == 1 and joint.guide not in ("", frame):
                found.append(f"{where} guide: only link {on[name][0]} lists this pair: the "
                             f"frame {frame!r} carries its guide, not {joint.guide!r}")
        elif joint.guide:
            found.append(f"{where} guide: only a prismatic pair (with slide) has a guide")
    driven = _driven(data, joints, links, on, on_frame, frame, found)
    t = Topology(frame, joints, links, driven, on_frame, ground.get("tables", {}))
    if not found and t.mobility() != len(t.drivers):
        n, p = len(links), t.pair_count()
        count = (f"{len(t.drivers)}, the number of its drivers" if "drivers" in data
                 else "1")
        found.append(f"[[links]]: the linkage's mobility is {t.mobility()}, not "
                     f"{count}: 3 x {n} "
                     f"moving links - 2 x {p} pairs (Gruebler's count; a joint on one link "
                     "is a pair with the frame, a joint on k links k - 1 pairs"
                     + (", a joint of the frame's entry on k links k pairs)" if on_frame
                        else ")"))
    return (None if found else t), found


def _vector(where: str, value: Any, found: list, values: dict, joints: dict | None = None,
            of: tuple = (), measures: dict | None = None, broken: tuple = (),
            cycles: set | None = None) -> tuple | None:
    """``[x, y]`` of numbers or expressions, each evaluable over ``values`` (and the
    drawn coordinates of ``joints``; ``of`` the joint whose position it is), with any
    unit taken in SI (checked to be a length, with ``measures``). One that uses the
    coordinates of a joint of ``broken`` (a joint whose own position has a problem,
    reported) is not evaluated, and None with no problem of its own; a loop of drawn
    positions is reported once, for the first of its joints (``cycles``: the loops
    reported so far)."""
    if not (isinstance(value, (list, tuple)) and len(value) == 2):
        found.append(f"{where}: must be [x, y], got {value!r}")
        return None
    out = []
    for axis, v in zip("xy", value):
        try:
            e = Expression(v)
        except ValueError as err:
            found.append(f"{where} {axis}: {err}")
            return None
        if e.has_units and measures is not None:
            try:
                check_units(e, "m", f"{where} {axis}", measures)
            except ValueError as err:  # it names where
                found.append(str(err))
                return None
        v = e.in_si()
        if joints is not None:
            try:
                e = Expression(inline(v, joints, set(values), of))
            except CycleError as err:  # a drawn position that uses itself
                if cycles is None or frozenset(err.cycle) not in cycles:
                    found.append(f"{where} {axis}: {err}")
                if cycles is not None:
                    cycles.add(frozenset(err.cycle))
                return None
            if any(n[:2] in ("x_", "y_") and n[2:] in broken for n in e.names):
                return None  # the cause is that joint's, reported
        try:
            x = e(values)
        except (ValueError, ZeroDivisionError, OverflowError, TypeError) as err:
            found.append(f"{where} {axis} = {v!r}: {err}")
            return None
        if not math.isfinite(x):
            found.append(f"{where} {axis}: {v!r} is not finite")
            return None
        out.append(v)
    return tuple(out)


def _in_si(value: Any) -> Any:
    """A coordinate with its units taken in SI; as it is if it is no expression (the
    checks of the joint say why)."""
    try:
        return Expression(value).in_si()
    except ValueError:
        return value


def _joints(table: Any, values: dict, found: list, measures: dict
            ) -> tuple[dict | None, tuple]:
    """The joints of ``[joints]`` whose positions are read, and the names of those whose
    are not (their problems in ``found``); None for the joints where the table is none."""
    if not isinstance(table, dict) or not table:
        found.append("[joints]: must be a table of JOINT = [x, y] (or { at, slide }), "
                     "one per joint")
        return None, ()
    raw = {}
    for name, spec in table.items():
        where = f"[joints] {name}"
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
            found.append(f"{where}: a joint's name must be an identifier")
        if isinstance(spec, dict):
            unknown = set(spec) - set(JOINT_KEYS)
            if unknown:
                found.append(f"{where}: unknown key(s) {', '.join(sorted(unknown))}; the keys "
                             f"are {', '.join(JOINT_KEYS)}")
            if "at" not in spec or "slide" not in spec:
                found.append(f"{where}: a prismatic pair needs at = [x, y] and slide = [dx, dy]")
                continue
            guide = spec.get("guide", "")
            if not isinstance(guide, str):
                found.append(f"{where} guide: must be a link's name")
                guide = ""
            raw[name] = (spec["at"], spec["slide"], guide)
        else:
            raw[name] = (spec, None, "")
    # the drawn positions may use the joints' coordinates: check them once all are known
    stand_in = {n: Joint(n, tuple(map(_in_si, at)) if isinstance(at, list) and len(at) == 2
                         else (0, 0)) for n, (at, _, _) in raw.items()}
    joints, cycles = {}, set()
    for name, (at, slide, guide) in raw.items():
        where = f"[joints] {name}" + (" at" if slide is not None else "")
        xy = _vector(where, at, found, values, stand_in, (name,), measures, cycles=cycles)
        direction = None
        if slide is not None:
            direction = _vector(f"[joints] {name} slide", slide, found, values, stand_in,
                                (name,), cycles=cycles)
            if direction is not None:
                dx, dy = (Expression(inline(v, stand_in, set(values)))(values) for v in direction)
                if math.hypot(dx, dy) == 0.0:
                    found.append(f"[joints] {name} slide: {list(slide)!r} has no length: the "
                                 "direction of the guide must not be zero")
        if xy is not None and (slide is None or direction is not None):
            joints[name] = Joint(name, xy, direction, guide)
    return joints, tuple(n for n in raw if n not in joints)


def _frame_entry(where: str, spec: dict, joints: dict | None, found: list,
                 ground: dict) -> None:
    """Read the frame's entry in [[links]] into ``ground``: its joints only."""
    if ground:
        found.append(f"{where} name: the frame is listed twice (first as {ground['where']})")
        return
    ground["where"] = where
    others = [k for k in spec if k not in FRAME_KEYS]
    if others:
        found.append(f"{where}: the frame's entry gives {', '.join(others)}; it lists the "
                     "frame's joints only (name, joints): the frame has no mass, inertia, "
                     "cg or points")
    listed = spec.get("joints")
    if not isinstance(listed, list) or not listed or \
            not all(isinstance(j, str) for j in listed):
        found.append(f"{where} joints: must be a list of the joints on the frame (one or "
                     "more names of [joints])")
        return
    if len(set(listed)) != len(listed):
        found.append(f"{where} joints: a joint is listed twice")
    if joints is not None:
        _unknown_joints(where, listed, joints, found)
    ground["joints"] = tuple(j for j in listed if joints is None or j in joints)


def _unknown_joints(where: str, listed: list, joints: dict, found: list) -> bool:
    """Report the names in ``listed`` that are no joint of ``joints``; whether any is."""
    unknown = [j for j in listed if j not in joints]
    if unknown:
        found.append(f"{where} joints: {', '.join(map(repr, unknown))} "
                     f"{'is no joint' if len(unknown) == 1 else 'are no joints'} of "
                     f"[joints]; the joints are {', '.join(joints)}")
    return bool(unknown)


def _links(table: Any, joints: dict | None, broken: tuple, values: dict, frame: str,
           found: list, measures: dict, ground: dict) -> dict | None:
    """The moving links of ``[[links]]`` (the frame's entry read into ``ground``), None
    where one cannot be read; an expression that uses a joint of ``broken`` (one whose
    position could not be read, said) is not evaluated, and its link not read."""
    # every joint's name, those whose positions could not be read too, in their order
    names = None if joints is None else {**dict.fromkeys(broken), **joints}
    if not isinstance(table, list) or not table:
        found.append("[[links]]: must be a list of tables, one per moving link")
        return None
    links, ok, taken, tables = {}, True, {}, {}
    for k, spec in enumerate(table):
        where = f"[[links]] #{k + 1}"
        if not isinstance(spec, dict):
            found.append(f"{where}: must be a table")
            ok = False
            continue
        name = spec.get("name")
        where += f" ({name})"
        if name == frame:
            _frame_entry(where, spec, names, found, ground)
            continue
        unknown = set(spec) - set(LINK_KEYS)
        if unknown:
            found.append(f"{where}: unknown key(s) {', '.join(sorted(unknown))}; the keys are "
                         f"{', '.join(LINK_KEYS)}")
        if not isinstance(name, str) or not name:
            found.append(f"{where} name: must be a name")
            ok = False
            continue
        if name in links:
            found.append(f"{where} name: link {name!r} is listed twice")
        listed = spec.get("joints")
        if not isinstance(listed, list) or not all(isinstance(j, str) for j in listed):
            found.append(f"{where} joints: must be a list of joint names")
            ok = False
            continue
        if len(listed) < 2:
            found.append(f"{where} joints: a link with fewer than two joints ({len(listed)}: "
                         f"{', '.join(listed) or 'none'}); a link carries two joints or more")
        if len(set(listed)) != len(listed):
            found.append(f"{where} joints: a joint is listed twice")
        if names is not None and _unknown_joints(where, listed, names, found):
            ok = False
        cg = listed[0] if listed else None
        if "cg" in spec:
            cg = _vector(f"{where} cg", spec["cg"], found, values, joints or {}, (),
                         measures, broken)
            ok = ok and cg is not None
        elif joints is not None and cg in joints:
            cg = joints[cg].at
        points = {}
        table = spec.get("points", {})
        if not isinstance(table, dict):
            found.append(f"{where} points: must be a table {{ P = [x, y], ... }}")
            table = {}
        for point, xy in table.items():
            if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", point):
                found.append(f"{where} points: {point!r}: a point's name must be an identifier")
            elif names is not None and point in names:
                found.append(f"{where} points: {point!r} is a joint; a point of a link joins "
                             "nothing")
            elif point in taken:
                found.append(f"{where} points: {point!r} is already a point of link "
                             f"{taken[point]}")
            else:
                points[point] = _vector(f"{where} points {point}", xy, found, values,
                                        joints or {}, (), measures, broken)
                taken[point] = name
                ok = ok and points[point] is not None
        links[name] = Link(name, tuple(listed), spec.get("mass", 0.0), spec.get("inertia", 0.0),
                           cg, points)
        tables[name] = k + 1
    ground["tables"] = tables
    return links if ok and joints is not None else None


def _driven(data: dict, joints: dict, links: dict, on: dict, on_frame: frozenset,
            frame: str, found: list) -> tuple:
    """The drivers of [crank] or [[drivers]] (one form, not both), each checked."""
    if "crank" in data and "drivers" in data:
        found.append("[crank], [[drivers]]: a linkage is driven either by [crank] (its one "
                     "crank) or by [[drivers]] (each driven pair), not both")
        return ()
    if "drivers" not in data:
        link, pivot = _crank(data.get("crank"), joints, links, on, on_frame, found)
        return (Drive(pivot, "angle", frame, link),) if link else ()
    table = data["drivers"]
    if not isinstance(table, list) or not table or \
            not all(isinstance(spec, dict) for spec in table):
        found.append("[[drivers]]: must be a list of tables, one per driven pair, "
                     "{ joint = \"A\" }")
        return ()
    out, seen = [], {}
    for k, spec in enumerate(table):
        where = f"[[drivers]] #{k + 1}"
        unknown = set(spec) - set(DRIVER_KEYS)
        if unknown:
            found.append(f"{where}: unknown key(s) {', '.join(sorted(unknown))}; the keys "
                         f"are {', '.join(DRIVER_KEYS)}")
        joint = spec.get("joint")
        if not isinstance(joint, str) or joint not in joints:
            found.append(f"{where} joint: {joint!r} is no joint of [joints]; the joints are "
                         f"{', '.join(joints)}")
            continue
        where += f" ({joint})"
        if joint in seen:
            found.append(f"{where}: the pair {joint} is driven twice (first by {seen[joint]}); "
                         "a pair takes one driver")
            continue
        seen[joint] = where
        drive = _drive(where, joint, spec.get("links"), joints, links, on, on_frame, frame,
                       found)
        if drive is not None:
            out.append(drive)
    return tuple(out)


def _drive(where: str, joint: str, given: Any, joints: dict, links: dict, on: dict,
           on_frame: frozenset, frame: str, found: list) -> Drive | None:
    """The driver of the pair ``joint`` (its [[drivers]] table ``where``, its ``links``
    key ``given``), or None with the problem in ``found``."""
    listed, prismatic = on[joint], joints[joint].prismatic
    grounded = joint in on_frame or len(listed) == 1
    if given is not None:
        if not (isinstance(given, list) and len(given) == 2 and
                all(isinstance(n, str) for n in given) and given[0] != given[1]):
            found.append(f"{where} links: must be [first, second], two links' names, got "
                         f"{given!r}")
            return None
        bodies = set(listed) | ({frame} if grounded and not prismatic else set())
        if not set(given) <= bodies:
            found.append(f"{where} links: {given!r} are not the links of the pair {joint}, "
                         f"which joins {', '.join(sorted(bodies))}")
            return None
        if given[1] == frame:
            found.append(f"{where} links: the frame is first: a crank's angle is the link's "
                         f"on the frame, links = [{frame!r}, {given[0]!r}]")
            return None
    if prismatic:
        return _cylinder(where, joint, given, joints, links, on, frame, found)
    if given is not None:
        first, second = given
    elif grounded and len(listed) == 1:
        first, second = frame, listed[0]
    elif len(listed) == 2 and not grounded:
        first, second = listed
    else:
        found.append(f"{where} links: the joint {joint} joins "
                     f"{', '.join(([frame] if grounded else []) + list(listed))}: say which "
                     "pair is driven, links = [first, second]")
        return None
    if len(links[second].joints) < 2:
        return None  # [[links]] says why
    return Drive(joint, "angle", first, second, where)


def _cylinder(where: str, joint: str, given: Any, joints: dict, links: dict, on: dict,
              frame: str, found: list) -> Drive | None:
    """The travel driver of the prismatic pair ``joint``: a cylinder, its barrel (the
    guide) and its rod each pinned at its far end; or None with the problem."""
    listed = on[joint]
    if len(listed) != 2:
        found.append(f"{where}: a driven prismatic pair is a cylinder between two links, "
                     f"its barrel and its rod; {joint} joins link {listed[0]} to the frame "
                     "(a driven slider on a frame guide is not one yet: draw the actuator as "
                     "a cylinder, barrel and rod, pinned to the frame and to the slider)")
        return None
    barrel = joints[joint].guide
    rod = next(n for n in listed if n != barrel)
    if given is not None and tuple(given) != (barrel, rod):
        found.append(f"{where} links: a cylinder's first link is its barrel, the guide "
                     f"{barrel!r}: links = [{barrel!r}, {rod!r}]")
        return None
    for name, what in ((barrel, "barrel"), (rod, "rod")):
        others = [j for j in links[name].joints if j != joint]
        if len(others) != 1 or joints[others[0]].prismatic:
            found.append(f"{where}: the cylinder's {what} {name} is pinned at one end: it "
                         f"lists {joint} and one revolute joint, not "
                         f"{', '.join(links[name].joints)}")
            return None
    return Drive(joint, "travel", barrel, rod, where)


def _crank(spec: Any, joints: dict, links: dict, on: dict, on_frame: frozenset,
           found: list) -> tuple:
    if not isinstance(spec, dict):
        found.append("[crank]: missing: the driven link and its pivot, "
                     "{ link = \"1\", pivot = \"A\" } (or [[drivers]], each driven pair)")
        return "", ""
    unknown = set(spec) - set(CRANK_KEYS)
    if unknown:
        found.append(f"[crank]: unknown key(s) {', '.join(sorted(unknown))}; the keys are "
                     f"{', '.join(CRANK_KEYS)}")
    link, pivot = spec.get("link"), spec.get("pivot")
    if link not in links:
        found.append(f"[crank] link: {link!r} is not a link of [[links]]")
        return "", ""
    if pivot not in links[link].joints:
        found.append(f"[crank] pivot: {pivot!r} is not a joint of link {link} (its joints: "
                     f"{', '.join(links[link].joints)})")
        return "", ""
    if joints[pivot].prismatic or (on[pivot] != (link,) and pivot not in on_frame):
        others = [n for n in on[pivot] if n != link]
        found.append(f"[crank] pivot: the crank pivot {pivot} is not on the frame: "
                     + ("it is a prismatic pair" if joints[pivot].prismatic else
                        f"it joins link {link} to {', '.join(others)}")
                     + "; the pivot is a revolute joint that only the crank lists, or one "
                     "the frame's entry in [[links]] lists")
    return link, pivot
