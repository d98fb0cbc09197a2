"""A joints-and-links linkage decomposed into the group form: the drivers, then Assur
groups.

:func:`decompose` takes a checked :class:`~linkage_fmu.descriptions.topology.Topology` and
returns the group-form tables that describe the same linkage (``[points]``,
``[[groups]]``, ``[bodies.L]``), which the description's checker and builder take as
they take a hand-written file. The drivers come first, each once what it needs is
placed (a crank on the frame at once, a motor after its first link, a cylinder with the
link its rod moves after its barrel's pin); then, as long as a link is not placed, the
first group a group type recognises is peeled off (each type that declares
its ``DRAWING`` recognises its own: :func:`recognisers`), trying the links two by two in
the order of [[links]] for the dyads (RRR, RRP: a rod and a slider on a frame guide, RPR:
a block sliding on a lever through the lever's pivot, RPP: a block in the slot of a yoke
on a frame guide); a link's further joints and its points become ``point`` groups on it.
What no dyad resolves is the smallest connected set of links that the placed ones hold
with mobility 0: a ``closure`` group (revolute pairs only).

Every number of the group form is an expression of the drawn coordinates (lengths,
guide points and angles, the points and centres of mass in each link's own frame), so
that it follows the parameters. The assembly modes (``branch``) are those of the drawn
pose at the parameters' defaults; where flipping one parameter of kind ``branch`` flips
a group's mode in the drawn pose, the group's branch is that parameter (times -1 where
needed). The builder checks that the linkage solved at the drawn crank angle
reproduces every drawn joint (:func:`check_pose`).

Pairs: a revolute pair takes its joint's name; at a compound joint J (on k links) the
pair J joins the first two of its links to be placed, and each further link L is
joined to the first by the pair ``J_L`` (its pin, the point ``J_L``, is a point of the
first link where J is); inside a class III (or higher) group, whose links are placed
together, each further link is pinned to the link listed before it. At a joint J on the frame (the
frame's entry in [[links]] lists it) with k moving links, the pair J joins the frame to the first of
them to be placed, and each further link L is joined to the frame by the pair ``J_L`` (at the
frame's point ``J_L``, where J is). A prismatic pair takes its joint's name.

Examples
--------
>>> from linkage_fmu.descriptions.topology import read
>>> t, _ = read({"joints": {"A": [0, 0], "B": [0.1, 0], "C": [0.3, 0.2], "D": [0.4, 0]},
...              "links": [{"name": "1", "joints": ["A", "B"]},
...                        {"name": "2", "joints": ["B", "C"]},
...                        {"name": "3", "joints": ["C", "D"]}],
...              "crank": {"link": "1", "pivot": "A"}}, {})
>>> dec = decompose(t, {})
>>> [(g["type"], g.get("branch")) for g in dec.groups]
[('crank', None), ('RRR', 1)]
>>> round(dec.groups[1]["length1"], 12)
0.282842712475
"""

from __future__ import annotations

import ast
import itertools
import math
from dataclasses import dataclass, field

from ..errors import LinkageFmuError
from ..expressions import Expression
from ..groups import Group
from .topology import Topology, inline

#: the largest sine of the angle between a prismatic pair's drawn slide and the guide its
#: group makes: an RPR's slot runs from its lever's pivot through the block's pin, and a
#: slide drawn within this of that line is taken for it (a direction typed to six
#: significant digits is within it); the others follow their drawn slide exactly
SLIDE_TOLERANCE = 1e-6


class DecompositionError(LinkageFmuError, ValueError):
    """The linkage cannot be decomposed; ``problems`` says why, naming the links."""

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        super().__init__("; ".join(problems))


@dataclass
class Decomposition:
    """The group form of a joints-and-links linkage.

    Attributes
    ----------
    points, groups, bodies : dict, list, dict
        The tables ``[points]``, ``[[groups]]`` and ``[bodies.L]``.
    pairs : list of (name, a, b)
        Every pair, as the action of body ``a`` (placed first; the frame first of all) on
        body ``b``.
    pose : dict
        Point -> (x, y, where): the drawn position of each point a group places, and the
        group that places it (``[[groups]] #k (type)``).
    theta : str, float or tuple
        The drawn crank angle; for a linkage driven by time (several drivers, a motor,
        a cylinder), each driver's coordinate where drawn, in the drivers' order.
    starts : dict
        For a linkage driven by time, each driver's coordinate input (``theta_<j>``,
        ``s_<j>``) -> its value where drawn; else empty.
    links : tuple of str
        The moving links, in the order of [[links]].
    tables : dict
        Moving link -> its number in [[links]] (from 1; the frame's entry counted).
    slides : dict
        Prismatic pair -> (dx, dy): its drawn direction of sliding, to check that the
        groups' guides follow it at every parameter set (:func:`check_pose`).
    checks : list of (str, str)
        ``(what, expression)``: an expression of the parameters that must stay at most
        :data:`SLIDE_TOLERANCE` where the parameters are a kernel's arguments (an FMU's
        set at run time, a sweep's), and what it is otherwise: the sine of a turning
        lever's slot off the line through its pivot, where the parameters move it.
    """

    points: dict = field(default_factory=dict)
    groups: list = field(default_factory=list)
    bodies: dict = field(default_factory=dict)
    pairs: list = field(default_factory=list)
    pose: dict = field(default_factory=dict)
    theta: object = 0.0
    starts: dict = field(default_factory=dict)
    links: tuple = ()
    checks: list = field(default_factory=list)
    tables: dict = field(default_factory=dict)
    slides: dict = field(default_factory=dict)


def fold(text):
    """A number for an expression without names, else the expression with its parts
    without names computed, and ``x - 0``, ``x * 1``, ``1 * x``, ``x / 1`` written
    ``x``: the same value to the last bit (the evaluator computes each part so, and
    these identities are exact, the sign of a zero included).

    Examples
    --------
    >>> fold("hypot((0.3) - (0.1), (0.2) - (0))"), fold("atan2((0) - (0), (l) - (0))")
    (0.282842712474619, 'atan2(0.0, l)')
    >>> fold("(0 - 0.5) ** a - 0")
    '(-0.5) ** a'
    """
    if isinstance(text, (int, float)):
        return float(text)
    e = Expression(text)
    if not e.names:
        return e({})
    return ast.unparse(_folded(ast.parse(text, mode="eval").body))


def _constant(x: float) -> ast.expr:
    """A number as a node: a negative one as a negation, so that it keeps its place
    when written out (``(-0.5) ** 2``, not ``-0.5 ** 2``)."""
    if math.copysign(1.0, x) < 0.0:
        return ast.UnaryOp(ast.USub(), ast.Constant(-x))
    return ast.Constant(x)


def _number(node: ast.expr) -> float | None:
    """The value of a node that is a number (or a negated one), else None."""
    if isinstance(node, ast.Constant):
        return float(node.value)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub) and \
            isinstance(node.operand, ast.Constant):
        return -float(node.operand.value)
    return None


def _folded(node: ast.expr) -> ast.expr:
    """``node`` with each part without names computed by the expressions' evaluator."""
    if isinstance(node, ast.Name) and node.id == "pi":
        return _constant(math.pi)
    if isinstance(node, ast.BinOp):
        parts = [_folded(node.left), _folded(node.right)]
    elif isinstance(node, ast.UnaryOp):
        parts = [_folded(node.operand)]
    elif isinstance(node, ast.Call):
        parts = [_folded(a) for a in node.args]
    else:
        return node
    numbers = [_number(p) for p in parts]
    rebuilt = (ast.BinOp(parts[0], node.op, parts[1]) if isinstance(node, ast.BinOp) else
               ast.UnaryOp(node.op, parts[0]) if isinstance(node, ast.UnaryOp) else
               ast.Call(node.func, parts, []))
    if all(n is not None for n in numbers):
        try:
            return _constant(Expression(ast.unparse(rebuilt))({}))
        except (ValueError, ZeroDivisionError, OverflowError):
            return rebuilt
    if isinstance(node, ast.BinOp):
        left, right = numbers
        if isinstance(node.op, ast.Sub) and right == 0.0 and math.copysign(1.0, right) > 0.0:
            return parts[0]
        if isinstance(node.op, (ast.Mult, ast.Div)) and right == 1.0:
            return parts[0]
        if isinstance(node.op, ast.Mult) and left == 1.0:
            return parts[1]
    return rebuilt


def body_table(drawn: Decomposition | None, link: str) -> str:
    """How messages name the table of ``link``'s mass and inertia: ``[bodies.L]``, or in
    a linkage written as joints and links (``drawn``, its decomposition) its
    ``[[links]] #k (L)``.

    Examples
    --------
    >>> body_table(None, "3"), body_table(Decomposition(links=("2", "3")), "3")
    ('[bodies.3]', '[[links]] #2 (3)')
    """
    if drawn is None or link not in drawn.links:
        return f"[bodies.{link}]"
    number = drawn.tables.get(link, drawn.links.index(link) + 1)
    return f"[[links]] #{number} ({link})"


class Decomposer:
    """One decomposition (see :func:`decompose`): what is placed so far, and the tables
    made from it.

    A group type's ``recognise`` (:meth:`linkage_fmu.groups.Group.recognise`) reads the
    linkage ``t`` (its joints, links and frame) and what is placed (:meth:`placed`,
    :meth:`anchors`, :meth:`dyad_of`, :meth:`connected`, :meth:`mobility`,
    :meth:`held_twice`), and adds a group it recognises: the points it uses
    (:meth:`attach`: a placed joint, or the pin a further link takes there), the drawn
    pose as expressions (:meth:`xy`, :meth:`slide`, :meth:`pose_of`, :meth:`num`,
    :meth:`branch`), its table (:meth:`group`), its pairs (:meth:`pair`), who holds each
    point it places (``owner``: the body, None if shared; ``first``: the link a further
    link is pinned to), each new link's own frame (``frame_``: link -> (point,
    direction)), then its links' other joints and points (:meth:`finish`); or it refuses
    a drawing that cannot be solved (:meth:`refuse`).
    """

    def __init__(self, t: Topology, values: dict, branches: tuple, at_points: set):
        self.t, self.values, self.branches, self.at_points = t, values, branches, at_points
        self.params = set(values)
        self.out = Decomposition(links=tuple(t.links), tables=dict(t.tables))
        self.placed_links: list = []
        self.owner: dict = {}  # placed point -> the body it is fixed in, None if shared
        self.first: dict = {}  # placed point -> the link to attach further links to
        self.pair_names: set = set()
        self.frame_ = {}  # link -> (from point, direction (ux, uy) expressions)
        self.missed: dict = {}  # slot -> why its dyad is no RPR (the slot misses the pivot)

    # -- expressions of the drawn pose -------------------------------------------------
    def xy(self, joint: str) -> tuple:
        at = self.t.joints[joint].at
        return tuple(f"({inline(v, self.t.joints, self.params)})" for v in at)

    def slide(self, joint: str) -> tuple:
        return tuple(f"({inline(v, self.t.joints, self.params)})"
                     for v in self.t.joints[joint].slide)

    def num(self, text, values: dict | None = None) -> float:
        return Expression(text)(self.values if values is None else values)

    def where(self) -> str:
        g = self.out.groups
        return f"[[groups]] #{len(g)} ({g[-1]['type']})"

    # -- the output tables ---------------------------------------------------------------
    def group(self, spec: dict, places: dict) -> None:
        """Add a group; ``places`` maps each point it places to its drawn (x, y)."""
        fields = Group.registry[spec["type"]].FIELDS  # a name is never folded
        self.out.groups.append({k: fold(v) if isinstance(v, str) and k in fields and
                                not fields[k].is_name else v for k, v in spec.items()})
        for p, (x, y) in places.items():
            self.out.pose[p] = (x, y, self.where())

    def pair(self, name: str, a: str, b: str) -> None:
        self.pair_names.add(name)
        self.out.pairs.append((name, a, b))

    def local(self, link: str, x: str, y: str) -> dict:
        """{from, along, across} of the drawn point (x, y) in link's own frame."""
        ref, (ux, uy) = self.frame_[link]
        rx, ry = self.pose_of(ref)
        n = f"hypot({ux}, {uy})"
        dx, dy = f"(({x}) - ({rx}))", f"(({y}) - ({ry}))"
        return {"from": ref, "along": fold(f"({dx} * {ux} + {dy} * {uy}) / {n}"),
                "across": fold(f"({dy} * {ux} - {dx} * {uy}) / {n}")}

    def pose_of(self, point: str) -> tuple:
        if point in self.out.points:
            return tuple(f"({v})" for v in self.out.points[point])
        return self.out.pose[point][:2]

    # -- placing -----------------------------------------------------------------------
    def placed(self, joint: str) -> bool:
        return joint in self.owner

    def attach(self, joint: str, link: str) -> str:
        """The point of ``joint`` that ``link`` is pinned to: the joint itself, or at a
        compound joint whose pair is made, the point ``J_link`` on its first link (on
        the frame, for a joint on the frame)."""
        if self.owner[joint] is not None and joint not in self.pair_names:
            self.pair_names.add(joint)  # its pair is made now: a further link takes a copy
            return joint
        copy = f"{joint}_{link}"
        on = self.first[joint]
        if on == self.t.frame:
            self.fresh(copy, f"the pin of link {link} at the frame joint {joint}")
            self.out.points[copy] = self.out.points[joint]
            self.owner[copy] = self.first[copy] = on
            self.pair_names.add(copy)
            return copy
        self.fresh(copy, f"the pin of link {link} at the compound joint {joint}")
        x, y = self.pose_of(joint)
        self.group({"type": "point", "link": on, "from": joint, "name": copy}, {copy: (x, y)})
        self.owner[copy] = self.first[copy] = on
        self.pair_names.add(copy)
        return copy

    def fresh(self, name: str, what: str) -> None:
        """A name the group form makes must not be a joint's."""
        if name in self.t.joints or any(name in n.points for n in self.t.links.values()):
            raise DecompositionError([f"[joints] {name}: the decomposition names {what} "
                                      f"{name}; name the joint otherwise"])

    def finish(self, link: str) -> None:
        """Place the link's further joints and its points on it, and its centre of mass."""
        spec = self.t.links[link]
        for j in spec.joints:
            joint = self.t.joints[j]
            needed = joint.prismatic and j in self.at_points and self.slides(j) == link
            if self.placed(j) or (joint.prismatic and not needed):
                continue
            x, y = self.xy(j)
            self.group({"type": "point", "link": link, "name": j, **self.local(link, x, y)},
                       {j: (x, y)})
            self.owner[j] = self.first[j] = link
        for point, at in spec.points.items():
            x, y = (f"({inline(v, self.t.joints, self.params)})" for v in at)
            self.group({"type": "point", "link": link, "name": point,
                        **self.local(link, x, y)}, {point: (x, y)})
        cg = tuple(f"({inline(v, self.t.joints, self.params)})" for v in spec.cg)
        place = self.local(link, *cg)
        self.out.bodies[link] = {"mass": spec.mass, "inertia": spec.inertia,
                                 "cg": {k: v for k, v in place.items()
                                        if k == "from" or v != 0.0}}
        self.placed_links.append(link)

    def slides(self, joint: str) -> str:
        """The link that slides in a prismatic pair (the one that does not carry it)."""
        return next(n for n in self.t.on(joint) if n != self.t.joints[joint].guide)

    def branch(self, sign_of, text: str) -> object:
        """The assembly mode of the drawn pose, whose sign the expression ``text`` of the
        parameters is (``sign_of(values)`` its value): None where it is 0 (a toggle), the
        expression ``sign(text)`` where a real-valued parameter moves the pose (so that
        a kernel, an FMU or a sweep that takes parameters takes the mode they draw),
        else its value at the defaults, times the branch parameters that flip it."""
        s = sign_of(self.values)
        if s == 0.0:
            return None
        if any(name in self.params and name not in self.branches
               for name in Expression(text).names):
            return f"sign({fold(text)})"
        flips = []
        for name in self.branches:
            flipped = dict(self.values, **{name: -self.values[name]})
            try:
                if sign_of(flipped) * s < 0.0:
                    flips.append(name)
            except (ValueError, ZeroDivisionError, OverflowError):
                continue
        b = 1 if s > 0.0 else -1
        if not flips:
            return b
        b *= math.prod(int(self.values[n]) for n in flips)
        return " * ".join(([] if b == 1 else ["-1"]) + flips)

    # -- the decomposition ---------------------------------------------------------------
    def run(self) -> Decomposition:
        t = self.t
        for j, joint in t.joints.items():
            if t.grounded(j) and not joint.prismatic:
                self.out.points[j] = tuple(fold(inline(v, t.joints, self.params))
                                           for v in joint.at)
                self.owner[j] = self.first[j] = t.frame
            if joint.prismatic:
                self.out.slides[j] = tuple(fold(v) for v in self.slide(j))
        pending, starts = list(t.driven), {}
        while pending or len(self.placed_links) < len(t.links):
            ready = next((d for d in pending if self.drive(d, starts)), None)
            if ready is not None:
                pending.remove(ready)
                continue
            if len(self.placed_links) == len(t.links) or not self.step(pending):
                self.unplaced(pending)
            taken = [d for d in pending if d.second in self.placed_links]
            if taken:
                self.unplaced(taken)
        timed = len(t.driven) > 1 or any(d.first != t.frame or d.kind != "angle"
                                         for d in t.driven)
        self.out.theta = tuple(starts.values()) if timed else next(iter(starts.values()))
        self.out.starts = starts if timed else {}
        return self.out

    def unplaced(self, drives: list) -> None:
        """Refuse the drivers ``drives``, which the decomposition cannot place."""
        def why(d):
            if d.kind == "travel":
                return (f"a cylinder is placed with a link it moves, its barrel's pin "
                        f"placed first and its rod's pin not: links {d.first}, {d.second}")
            if d.first == self.t.frame:
                return f"link {d.second} is placed by a group around it"
            return (f"a motor is placed once its first link {d.first} and its joint are, "
                    f"before its second link {d.second}")
        self.refuse(*(f"{d.where}: the decomposition cannot place this driver ({why(d)}); "
                      "a driver moves links that no group holds yet (not one inside a "
                      "class III group or a closure)" for d in drives))

    def drive(self, d, starts: dict) -> bool:
        """Place the driver ``d`` where what it needs is placed: whether it is. Its
        coordinate where drawn goes into ``starts`` (input name -> expression)."""
        t = self.t
        if d.kind == "travel":
            return self.cylinder(d, starts)
        if d.first != t.frame and not (d.first in self.placed_links and self.placed(d.joint)):
            return False
        link, pivot = d.second, d.joint
        tip = next(j for j in t.links[link].joints if j != pivot)
        if t.joints[tip].prismatic:
            whose = ("[crank] link: the crank's" if d.where == "[crank]" else
                     f"{d.where}: the driven link {link}'s")
            raise DecompositionError([f"{whose} first other joint {tip} is a prismatic "
                                      f"pair; list a revolute joint after the "
                                      f"{'pivot' if d.where == '[crank]' else 'driven one'}"])
        if self.placed(tip):
            return False
        pin = self.attach(pivot, link)
        (px, py), (bx, by) = self.xy(pivot), self.xy(tip)
        angle = f"atan2({by} - {py}, {bx} - {px})"
        spec = {"type": "crank", "link": link, "pivot": pin, "tip": tip,
                "length": f"hypot({bx} - {px}, {by} - {py})"}
        if d.first != t.frame:  # a motor: its zero is the first link's direction
            _, (ux, uy) = self.frame_[d.first]
            other = next(j for j in t.links[d.first].joints if j != pivot)
            ox, oy = self.xy(other)
            fx, fy = f"({ox} - {px})", f"({oy} - {py})"
            spec["base"] = d.first
            spec["offset"] = f"atan2({ux} * {fy} - {uy} * {fx}, {ux} * {fx} + {uy} * {fy})"
            angle = (f"atan2({fx} * ({by} - {py}) - {fy} * ({bx} - {px}), "
                     f"{fx} * ({bx} - {px}) + {fy} * ({by} - {py}))")
        self.group(spec, {tip: (bx, by)})
        if not starts:  # the angle a closure is drawn at, with one crank
            self.out.theta = fold(angle)
        self.pair(pin, self.owner[pin] if d.first != t.frame else t.frame, link)
        starts[f"theta_{pin}"] = fold(angle)
        self.owner[tip] = self.first[tip] = link
        self.frame_[link] = (pin, (f"({bx} - {px})", f"({by} - {py})"))
        self.finish(link)
        return True

    def cylinder(self, d, starts: dict) -> bool:
        """Place the cylinder ``d`` (barrel ``d.first``, rod ``d.second``) with the link
        its rod's pin moves, where its barrel's pin is placed: whether it is."""
        t, barrel, rod = self.t, d.first, d.second
        e2 = next(j for j in t.links[barrel].joints if j != d.joint)
        c = next(j for j in t.links[rod].joints if j != d.joint)
        if not self.placed(e2) or self.placed(c):
            return False
        moved = self.moved(c, rod)
        if moved is None:
            return False
        link, end = moved
        p1, p2 = self.attach(end, link), self.attach(e2, barrel)
        (x1, y1), (x2, y2), (cx, cy) = self.pose_of(p1), self.pose_of(p2), self.xy(c)
        sx, sy = self.slide(d.joint)
        along = self.num(f"({sx}) * (({cx}) - ({x2})) + ({sy}) * (({cy}) - ({y2}))")
        off = self.num(f"(({sx}) * (({cy}) - ({y2})) - ({sy}) * (({cx}) - ({x2}))) / "
                       f"(hypot({sx}, {sy}) * hypot(({cx}) - ({x2}), ({cy}) - ({y2})))")
        if not (along > 0.0 and abs(off) <= SLIDE_TOLERANCE):
            self.refuse(f"[joints] {d.joint} slide: a cylinder's slide points from its "
                        f"barrel's pin {e2} to its rod's pin {c} (its travel is positive "
                        "along it); it is drawn "
                        + ("the other way" if abs(off) <= SLIDE_TOLERANCE else
                           f"off that line (sine {off:.3g})"))

        def sign(v):
            n = lambda s: self.num(s, v)  # noqa: E731
            return ((n(x2) - n(x1)) * (n(cy) - n(y1)) - (n(y2) - n(y1)) * (n(cx) - n(x1)))

        b = self.branch(sign, f"({x2} - {x1}) * ({cy} - {y1}) - ({y2} - {y1}) * ({cx} - {x1})")
        if b is None:
            self.refuse(f"[joints] {c}: the cylinder dyad {p1}-{c}-{p2} (link {link}, "
                        f"cylinder {barrel}, {rod}) is drawn at a toggle (in line): its "
                        "assembly mode is undefined; draw it apart")
        self.group({"type": "cylinder", "link": link, "barrel": barrel, "rod": rod,
                    "end1": p1, "middle": c, "end2": p2, "pair": d.joint,
                    "length1": f"hypot({cx} - {x1}, {cy} - {y1})",
                    "length0": f"hypot({cx} - {x2}, {cy} - {y2})", "branch": b},
                   {c: (cx, cy)})
        self.pair(p1, self.owner[p1], link)
        self.pair(c, link, rod)
        self.pair(p2, self.owner[p2], barrel)
        self.pair(d.joint, barrel, rod)
        starts[f"s_{d.joint}"] = 0.0
        self.owner[c], self.first[c] = None, link
        self.frame_[link] = (p1, (f"({cx} - {x1})", f"({cy} - {y1})"))
        self.frame_[barrel] = (p2, (f"({cx} - {x2})", f"({cy} - {y2})"))
        self.frame_[rod] = (c, (f"({cx} - {x2})", f"({cy} - {y2})"))
        for placed in (link, barrel, rod):
            self.finish(placed)
        return True

    def moved(self, joint: str, rod: str) -> tuple | None:
        """``(link, its pin)``: the first link not placed at ``joint`` besides the rod
        ``rod`` that is pinned to a placed joint and to nothing else placed, else None."""
        for link in self.t.on(joint):
            if link == rod or link in self.placed_links:
                continue
            to_placed, shared = self.anchors(link, rod)
            if shared == [joint] and len(to_placed) == 1 and to_placed[0][0] == "pin":
                return link, to_placed[0][1]
        return None

    def anchors(self, link: str, partner: str) -> tuple[list, list] | None:
        """(the link's pairs to placed bodies, each (kind, joint): kind ``pin``,
        ``frame guide`` or ``guide`` (a prismatic pair with a placed link), and its
        joints not yet placed that it shares with ``partner``)."""
        to_placed, shared = [], []
        for j in self.t.links[link].joints:
            joint, on = self.t.joints[j], self.t.on(j)
            if partner in on and not self.placed(j):
                shared.append(j)
            elif joint.prismatic:
                other = [n for n in on if n != link]
                if not other:
                    to_placed.append(("frame guide", j))
                elif other[0] in self.placed_links:
                    to_placed.append(("guide", j))
            elif self.placed(j):
                to_placed.append(("pin", j))
        return to_placed, shared

    def dyad_of(self, x: str, y: str) -> tuple | None:
        """``(x's pair, the joint they share, y's pair)`` where the links ``x`` and ``y``
        are drawn as a dyad: each with one pair to the placed bodies (``(kind, joint)``,
        as :meth:`anchors` gives it) and one joint not yet placed that they share; else
        None."""
        ax, sx = self.anchors(x, y)
        ay, _ = self.anchors(y, x)
        if len(sx) != 1 or len(ax) != 1 or len(ay) != 1:
            return None
        return ax[0], sx[0], ay[0]

    def step(self, pending: list = ()) -> bool:
        """Add the next group: the first that a group type recognises among the links not
        yet placed, trying each size of group smallest first (every set of that many
        links in the order of [[links]], and for each set the types in their order),
        then the types of any size (:func:`recognisers`); False where none is found and
        drivers are ``pending`` (not placed yet)."""
        free = [n for n in self.t.links if n not in self.placed_links]
        types = recognisers()
        for size in sorted({cls.DRAWING.size for cls in types} - {None}):
            fitting = [cls for cls in types if cls.DRAWING.size == size]
            for links in itertools.combinations(free, size):
                if any(cls.recognise(self, links) for cls in fitting):
                    return True
        if any(cls.recognise(self, tuple(free)) for cls in types if cls.DRAWING.size is None):
            return True
        if pending:
            return False
        raise DecompositionError([
            f"[[links]]: a group the decomposition cannot solve: links {', '.join(free)} are "
            "left, and no connected set of them is held by the placed links with mobility 0"])

    # -- for the group types' recognise: the links' structure and the tables ----------------
    def connected(self, subset: tuple) -> bool:
        """Whether the links ``subset`` are connected through their joints."""
        seen, todo = {subset[0]}, [subset[0]]
        while todo:
            link = todo.pop()
            for j in self.t.links[link].joints:
                for other in self.t.on(j):
                    if other in subset and other not in seen:
                        seen.add(other)
                        todo.append(other)
        return len(seen) == len(subset)

    def held_twice(self, link: str, subset: tuple) -> bool:
        """Whether ``link`` has two pairs or more within the group ``subset`` or to
        placed bodies (a link of an Assur group does; one with a single pair would
        turn freely while the count of the group says 0)."""
        held = 0
        for j in self.t.links[link].joints:
            on = self.t.on(j)
            if (self.placed(j) or len(on) == 1 or any(n in self.placed_links for n in on)
                    or any(n in subset and n != link for n in on)):
                held += 1
        return held >= 2

    def mobility(self, subset: tuple) -> int:
        """Gruebler's count of the links ``subset`` held by the placed bodies."""
        pairs = 0
        for j in {j for n in subset for j in self.t.links[n].joints}:
            on = self.t.on(j)
            inside = sum(n in subset for n in on)
            held = self.placed(j) or len(on) == 1 or any(n in self.placed_links for n in on)
            pairs += inside if held else inside - 1
        return 3 * len(subset) - 2 * pairs

    #: see :data:`SLIDE_TOLERANCE`
    slide_tolerance = SLIDE_TOLERANCE

    @staticmethod
    def fold(text):
        """:func:`fold`: an expression of the drawn pose as the group form writes it."""
        return fold(text)

    def moves(self, text: str) -> bool:
        """Whether the expression ``text`` uses a parameter."""
        return any(name in self.params for name in Expression(text).names)

    def check(self, what: str, text: str) -> None:
        """Check at every parameter set that the expression ``text`` is at most
        :data:`SLIDE_TOLERANCE` (see ``Decomposition.checks``); ``what`` says what it is."""
        self.out.checks.append((what, fold(text)))

    @staticmethod
    def refuse(*problems: str) -> None:
        """Raise the DecompositionError of ``problems``: the links form a group that
        cannot be decomposed."""
        raise DecompositionError(list(problems))


def recognisers() -> list[type]:
    """The group types that a linkage written as joints and links may show (those that
    declare their ``DRAWING``), in the order the decomposition tries them: by size,
    those of any size last, then by rank and kind.

    Examples
    --------
    >>> [cls.kind for cls in recognisers()]
    ['RRR', 'RRP', 'RPR', 'RPP', 'closure']
    """
    found = [cls for cls in Group.registry.values() if cls.__dict__.get("DRAWING")]
    return sorted(found, key=lambda cls: (cls.DRAWING.size is None, cls.DRAWING.size or 0,
                                          cls.DRAWING.rank, cls.kind))


def decompose(t: Topology, values: dict, branches: tuple = (), at_points: set = frozenset()
              ) -> Decomposition:
    """The group form of the joints-and-links linkage ``t``.

    Parameters
    ----------
    t : Topology
        The checked linkage (:func:`~linkage_fmu.descriptions.topology.read`).
    values : dict
        Parameter name -> default value, to evaluate the drawn pose.
    branches : tuple of str
        The parameters of kind ``branch``.
    at_points : set of str
        The prismatic pairs a load or effort acts at (their point on the sliding link).

    Raises
    ------
    DecompositionError
        A group the decomposition cannot solve, or a drawn pose at a toggle.
    """
    return Decomposer(t, values, tuple(branches), set(at_points)).run()


# -- what the decomposition is, for people ---------------------------------------------
def outline(groups: list[dict]) -> list[tuple[str, str, tuple, tuple]]:
    """For each group-form table: (class, type, its new links, its joints or points).

    The class is ``crank`` for a crank or motor, ``driver`` for another driver (a
    cylinder: a dyad of driven length), ``II`` for a dyad, ``III`` for a closure of
    four links with one ternary link (Assur's class III triad), ``IV`` for one with two
    ternary links, ``n links`` for another closure, and ``point`` for a point on a link
    (its link is the one it is on, not a new one).

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> for row in outline(presets.preset("crank_shaper").groups):
    ...     print(row)
    ('crank', 'crank', ('1',), ('A', 'B'))
    ('II', 'RPR', ('2', '3'), ('B', 'C', 'slot'))
    ('point', 'point', ('3',), ('D',))
    ('II', 'RRP', ('4', '5'), ('D', 'E', 'guide'))
    """
    rows = []
    for spec in groups:
        kind = spec.get("type")
        if kind == "point":
            rows.append(("point", kind, (spec.get("link"),), (spec.get("name"),)))
            continue
        if kind == "closure":
            links = spec.get("links", {})
            ternary = sum(len(v) >= 3 for v in links.values())
            cls = ("III" if len(links) == 4 and ternary == 1 else
                   "IV" if len(links) == 4 and ternary == 2 else f"{len(links)} links")
            joints = tuple(dict.fromkeys(j for v in links.values() for j in v))
            rows.append((cls, kind, tuple(links), joints))
            continue
        group = Group.registry.get(kind)
        if group is None:
            rows.append(("?", str(kind), (), ()))
            continue
        links = tuple(spec[k] for k, f in group.FIELDS.items() if f.role == "new link")
        if group.DRIVER and kind == "crank":
            rows.append(("crank", kind, links, (spec.get("pivot"), spec.get("tip"))))
        elif group.DRIVER:  # a cylinder: a dyad of driven length
            rows.append(("driver", kind, links, tuple(group.pairs(spec))))
        else:
            rows.append(("II", kind, links, tuple(group.pairs(spec))))
    return rows


def output_name(by: str, on: str) -> str:
    """The name of the force output of body ``by`` on body ``on``: ``F<by><on>``, or
    ``F<by>_<on>`` when a name is longer than one character.

    Examples
    --------
    >>> output_name("2", "1"), output_name("OA", "0")
    ('F21', 'FOA_0')
    """
    return f"F{by}{on}" if len(by) == len(on) == 1 else f"F{by}_{on}"


def default_outputs(pairs: list, efforts: dict, declared: list = ()) -> list[dict]:
    """The [[outputs]] a joints-and-links linkage has besides those it ``declared`` (its
    [[outputs]] tables): the force of each pair, as the action of the body placed first
    on the other (one output per two bodies), then each effort; a pair whose reaction a
    declared output reports (a force between its two bodies, the normal or couple of a
    prismatic pair between them, an expression of the pair's ``N_J``, ``M_J``, ``Fx_J``
    or ``Fy_J``) and an effort a declared output names are left out.

    Examples
    --------
    >>> pairs = [("A", "0", "1"), ("B", "1", "slider"), ("guide", "0", "slider")]
    >>> for o in default_outputs(pairs, {None: {"name": "Mb"}}):
    ...     print(o)
    {'kind': 'force', 'name': 'F01', 'by': '0', 'on': '1'}
    {'kind': 'force', 'name': 'F1_slider', 'by': '1', 'on': 'slider'}
    {'kind': 'force', 'name': 'F0_slider', 'by': '0', 'on': 'slider'}
    {'kind': 'effort', 'name': 'Mb'}
    >>> [o["name"] for o in default_outputs(pairs, {None: {"name": "Mb"}},
    ...                                     [{"kind": "force", "name": "F10", "by": "1",
    ...                                       "on": "0", "magnitude": True},
    ...                                      {"kind": "normal", "name": "N", "joint": "guide"}])]
    ['F1_slider', 'Mb']
    """
    bodies = {name: frozenset((a, b)) for name, a, b in pairs}
    seen, named = set(), set()
    for spec in declared:
        kind = spec.get("kind")
        if kind == "force":
            seen.add(frozenset((spec.get("by"), spec.get("on"))))
        elif kind in ("normal", "couple") and spec.get("joint") in bodies:
            seen.add(bodies[spec["joint"]])
        elif kind == "expression":
            try:
                used = Expression(spec.get("expression", "")).names
            except ValueError:  # the checker says why
                used = ()
            seen.update(bodies[n.split("_", 1)[1]] for n in used
                        if n.split("_", 1)[0] in ("N", "M", "Fx", "Fy")
                        and n.split("_", 1)[-1] in bodies)
        elif kind == "effort":
            named.add(spec.get("name"))
    out = []
    for _, a, b in pairs:
        if frozenset((a, b)) not in seen:
            seen.add(frozenset((a, b)))
            out.append({"kind": "force", "name": output_name(a, b), "by": a, "on": b})
    names = dict.fromkeys(s["name"] for s in efforts.values() if isinstance(s, dict))
    out += [{"kind": "effort", "name": n} for n in names if n not in named]
    return out


#: how far from its drawn position the linkage may place a joint at the drawn crank angle
POSE_TOLERANCE = 1e-12


def drawn_coordinates(drawn: Decomposition, values: dict) -> tuple:
    """``(theta, rates, where)``: the drivers' coordinates where drawn (the crank angle;
    for a linkage driven by time their tuple, and their rates, zero), at the
    parameters' ``values``, and words saying where that is."""
    if not isinstance(drawn.theta, tuple):
        theta = Expression(drawn.theta)(values)
        return theta, None, f"at the drawn crank angle {math.degrees(theta):.6g} deg"
    theta = tuple(Expression(v)(values) for v in drawn.theta)
    words = ", ".join(f"{name} = {math.degrees(v):.6g} deg" if name.startswith("theta_")
                      else f"{name} = {v:.6g} m" for name, v in zip(drawn.starts, theta))
    return theta, tuple((0.0, 0.0) for _ in theta), f"at the drivers' drawn {words}"


def check_pose(mech, drawn: Decomposition, values: dict) -> str:
    """What is wrong when ``mech``, solved at the drawn crank angle, does not reproduce
    every drawn point to :data:`POSE_TOLERANCE` m (its parameters' ``values``), or ''.

    Examples
    --------
    >>> from pathlib import Path
    >>> from linkage_fmu.descriptions import Description
    >>> import linkage_fmu
    >>> path = Path(linkage_fmu.__file__).parents[2] / "examples/joints/four_bar.toml"
    >>> d = Description.read(path)
    >>> check_pose(d.build(), d.drawn, {"l_AB": 0.1, "l_BC": 0.35, "l_CD": 0.3,
    ...                                 "l_AD": 0.4, "branch": 1})
    ''
    >>> print(check_pose(d.build(), d.drawn, {"l_AB": 0.1, "l_BC": 0.35, "l_CD": 0.3,
    ...                                       "l_AD": 0.4, "branch": -1}))
    [[groups]] #2 (RRR): a drawn pose from which a group cannot be assembled: at the drawn crank
    angle 0 deg it places C at (0.304166667, 0.284281502), 0.569 m from where C is drawn
    (0.304166667, -0.284281502); the tolerance is 1e-12 m
    """
    theta, rates, at = drawn_coordinates(drawn, values)
    try:
        st = mech.kinematics(theta, order=0, rates=rates)
    except ValueError as err:
        return f"a drawn pose from which a group cannot be assembled: {at}: {err}"
    for p, (x, y, where) in drawn.pose.items():
        dx, dy = Expression(x)(values), Expression(y)(values)
        px, py = st.p[p]
        distance = math.hypot(px - dx, py - dy)
        if not distance <= POSE_TOLERANCE:
            return (f"{where}: a drawn pose from which a group cannot be assembled: {at} "
                    f"it places {p} at "
                    f"({px:.9g}, {py:.9g}), {distance:.3g} m from where {p} is drawn "
                    f"({dx:.9g}, {dy:.9g}); the tolerance is {POSE_TOLERANCE:g} m")
    pairs = {j.name: j for j in mech.joints}
    for name, (x, y) in drawn.slides.items():
        # a group keeps the guide's direction as its own geometry makes it (an RPR's slot
        # along its lever): a drawn slide that parameters turn off it would be dropped
        tx, ty = Expression(x)(values), Expression(y)(values)
        nx, ny = pairs[name].normal_at(st)
        off = abs(nx * tx + ny * ty) / math.hypot(tx, ty)
        if not off <= SLIDE_TOLERANCE:
            return (f"[joints] {name} slide: a drawn pose from which a group cannot be "
                    f"assembled: {at} the pair slides along ({-ny:.9g}, {nx:.9g}), not "
                    f"along its drawn slide ({tx:.9g}, {ty:.9g}) (sine of the angle "
                    f"between them {off:.3g}; the tolerance is {SLIDE_TOLERANCE:g})")
    return ""


#: the condition number of a dyad drawn as joints and links (its transmission's ``kappa``)
#: in its drawn pose above which building warns: the drawing barely fixes its mode (as
#: :data:`linkage_fmu.groups.closure.NEAR_SINGULAR` for a closure)
NEAR_TOGGLE = 1e3


def near_toggles(mech, drawn: Decomposition, values: dict) -> list[str]:
    """A message for each dyad of ``mech`` whose drawn pose (at the drawn crank angle, its
    parameters' ``values``) is so near a toggle that the drawing barely fixes its
    assembly mode: its condition number there (the transmission's ``kappa``) above
    :data:`NEAR_TOGGLE`. A closure group says so itself, when it is attached.

    Examples
    --------
    >>> from linkage_fmu.descriptions import Description
    >>> d = Description.from_toml('''
    ... [linkage]
    ... name = "flat"
    ... [joints]
    ... A = [0, 0]
    ... B = [0.1, 0]
    ... C = [0.3, 1e-5]
    ... D = [0.5, 0]
    ... [[links]]
    ... name = "1"
    ... joints = ["A", "B"]
    ... [[links]]
    ... name = "2"
    ... joints = ["B", "C"]
    ... [[links]]
    ... name = "3"
    ... joints = ["C", "D"]
    ... [crank]
    ... link = "1"
    ... pivot = "A"
    ... ''', "flat.toml")
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     mech = d.build()
    >>> print(near_toggles(mech, d.drawn, {})[0])
    [joints] C: the dyad B-C-D is drawn near a toggle: the condition number of its position
    there is 2e+04 (above 1000), so the drawing barely fixes its assembly mode; draw it farther
    from where its joints line up
    """
    theta, rates, _ = drawn_coordinates(drawn, values)
    st = mech.kinematics(theta, order=0, rates=rates)
    found = []
    for grp in mech.groups:
        if grp.kind not in ("RRR", "RRP"):
            continue
        kappa = grp.transmission(st, mech.length_scale)[1]
        if kappa > NEAR_TOGGLE:
            what = (f"the dyad {grp.E1}-{grp.C}-{grp.E2}" if grp.kind == "RRR" else
                    f"the slider at {grp.B} (rod {grp.E}{grp.B})")
            found.append(f"[joints] {grp.key}: {what} is drawn near a toggle: the condition "
                         f"number of its position there is {kappa:.3g} (above "
                         f"{NEAR_TOGGLE:g}), so the drawing barely fixes its assembly mode; "
                         "draw it farther from where its joints line up")
    return found

