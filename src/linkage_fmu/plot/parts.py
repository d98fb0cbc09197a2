"""What of a linkage the plots draw: its force outputs paired by component, each with
the joint it acts at, the points each link carries and the outline they make."""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

from ..errors import InputError
from ..outputs import SHAKING, joint_between

if TYPE_CHECKING:  # pragma: no cover
    from ..mechanism import Mechanism

_DEFAULT_FORCE = re.compile(r"^force of link (.+) on link (.+), ([xy]) component$")


class ForcePair(NamedTuple):
    """A force output with both components: ``x`` and ``y`` are the output names of
    the force of body ``by`` on body ``on`` in the frame's axes; it acts at ``point``,
    the point of the ``joint`` between the two bodies (both None if not known)."""

    name: str
    x: str
    y: str
    by: str | None
    on: str | None
    joint: str | None
    point: str | None


def force_pairs(mech: "Mechanism") -> tuple[ForcePair, ...]:
    """The force outputs of ``mech`` that have both an x and a y component, in output
    order.

    They come from the linkage's description (its ``force`` outputs, whatever their
    component names, e.g. the six-bar's ``XO``/``YO``); for a mechanism built without
    one, from output names ``<stem>x``/``<stem>y`` (the joint is known when the
    outputs keep their default descriptions). The shaking force is not a joint's: see
    :func:`shaking`.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> force_pairs(presets.get("six_bar"))[0]
    ForcePair(name='O', x='XO', y='YO', by='0', on='OA', joint='O', point='O')
    >>> [(p.name, p.point) for p in force_pairs(presets.get("slider_crank"))]
    [('F21', 'A'), ('F32', 'B'), ('F14', 'O')]
    """
    names = set(mech.output_names)
    specs = []  # (name, x, y, by, on)
    if mech.description is not None:
        for spec in mech.description.outputs:
            if spec["kind"] == "force" and {"x", "y"} <= set(spec.get("components", "xy")):
                x, y = spec.get("x", spec["name"] + "x"), spec.get("y", spec["name"] + "y")
                specs.append((spec["name"], x, y, spec["by"], spec["on"]))
    else:
        for x in mech.output_names:
            y = x[:-1] + "y"
            if x.endswith("x") and y in names and x not in SHAKING:
                bx, by = (_DEFAULT_FORCE.match(mech.output_info[n][1]) for n in (x, y))
                known = bx and by and bx.group(1, 2) == by.group(1, 2)
                specs.append((x[:-1], x, y, *(bx.group(1, 2) if known else (None, None))))
    pairs = []
    for name, x, y, by, on in specs:
        if x not in names or y not in names:
            continue
        joint = joint_between(mech, by, on, name)[0] if by is not None else None
        pairs.append(ForcePair(name, x, y, by, on, joint and joint.name, joint and joint.point))
    return tuple(pairs)


def find_pair(mech: "Mechanism", force: str | None) -> ForcePair:
    """The pair named ``force`` (its name or a component's), the first if None."""
    pairs = force_pairs(mech)
    if not pairs:
        raise InputError(f"{mech.name} has no force output with x and y components")
    if force is None:
        return pairs[0]
    for p in pairs:
        if force in (p.name, p.x, p.y):
            return p
    raise InputError(f"{mech.name} has no force pair {force!r}; its force pairs are: "
                     + ", ".join(f"{p.name} ({p.x}, {p.y})" for p in pairs))


def link_points(mech: "Mechanism") -> dict[str, tuple[str, ...]]:
    """Moving link -> the points it carries: its joints' points (in joint order), then
    the points placed on it alone (a coupler point, a lever's tip). Centres of mass are
    not among them.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> link_points(presets.get("four_bar"))
    {'1': ('A', 'B'), '2': ('B', 'C'), '3': ('C', 'D')}
    >>> link_points(presets.get("slider_crank"))["3"]
    ('B',)
    """
    points: dict[str, list] = {b.name: [] for b in mech.bodies}
    for j in mech.joints:
        for body in (j.a, j.b):
            if body in points and j.point not in points[body]:
                points[body].append(j.point)
    for point, link in mech.owner.items():
        if link in points and point not in points[link]:
            points[link].append(point)
    return {k: tuple(v) for k, v in points.items()}


def hull(points: Sequence[str], pos: dict) -> list[str]:
    """The points of ``points`` on their convex hull, counter-clockwise from the lowest
    (then leftmost); points on an edge (within 1e-9 of the points' extent, what
    rounding leaves of a point placed on a line) are left out, so points on one line
    give the two ends of it.

    A link is drawn as this hull: a plate if it has three or more corners, else a bar.

    Examples
    --------
    >>> pos = {"A": (0.0, 0.0), "B": (1.0, 0.0), "C": (0.5, 1.0), "M": (0.5, 0.2)}
    >>> hull(["A", "B", "C", "M"], pos)
    ['A', 'B', 'C']
    >>> hull(["B", "M", "A"], {"A": (0.0, 0.0), "B": (1.0, 0.0), "M": (0.4, 0.0)})
    ['A', 'B']
    """
    order = sorted(dict.fromkeys(points), key=lambda p: (pos[p][0], pos[p][1]))
    if len(order) < 3:
        return order

    xs, ys = zip(*(pos[p] for p in order))
    size = max(max(xs) - min(xs), max(ys) - min(ys))
    flat = 1e-9 * size * size  # |o a| times the distance of b from the line o a

    def turn(o, a, b):  # > 0: o -> a -> b turns counter-clockwise
        (ox, oy), (ax, ay), (bx, by) = pos[o], pos[a], pos[b]
        return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox)

    def chain(seq):  # Andrew's monotone chain, one side
        out: list[str] = []
        for p in seq:
            while len(out) >= 2 and turn(out[-2], out[-1], p) <= flat:
                out.pop()
            out.append(p)
        return out

    lower, upper = chain(order), chain(order[::-1])
    ring = lower[:-1] + upper[:-1]
    if len(ring) < 3:  # all on one line: its two ends
        return [order[0], order[-1]]
    start = min(range(len(ring)), key=lambda k: (pos[ring[k]][1], pos[ring[k]][0]))
    return ring[start:] + ring[:start]
