"""The revolute dyad (RRR): two links joined at a middle joint."""

from __future__ import annotations

import math

import numpy as np

from ..pairs import Revolute
from .base import (
    OWNER,
    Drawing,
    Field,
    Group,
    KinematicState,
    angle_and_kappa,
    fmt,
    mode,
    moment_about,
    push,
)


def dyad_middle(st: KinematicState, E1, E2, L1, L2, branch, condition, what: str):
    """The middle joint of a dyad of arms ``L1`` from ``E1`` and ``L2`` from ``E2``
    (``branch`` +1: left of E1 -> E2); one that cannot close fails the state, with
    ``condition(d2)`` saying why (``d2 = |E1 E2|**2``) and ``what`` without numbers."""
    (x1, y1), (x2, y2) = E1, E2
    dx, dy = x2 - x1, y2 - y1
    d2 = dx * dx + dy * dy
    # (2*d*h)^2 as a product of two factors: no cancellation near a toggle
    hd2 = ((L1 + L2) ** 2 - d2) * (d2 - (L1 - L2) ** 2)
    hd = st.root(hd2, lambda: condition(d2), what)
    f = (L1 * L1 - L2 * L2 + d2) / (2.0 * d2)
    g = branch * hd / (2.0 * d2)
    return x1 + f * dx - g * dy, y1 + f * dy + g * dx


class RRR(Group):
    """Dyad of two links joined at ``middle`` (the argument ``C``): ``link1`` from
    ``end1`` (``E1``) to ``middle`` and ``link2`` from ``end2`` (``E2``) to ``middle``.

    ``branch = +1`` places ``C`` to the left of the directed line E1 -> E2, ``-1`` to
    the right. ``link1``'s direction is E1 -> C, ``link2``'s is E2 -> C.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> st = KinematicState(0.0, SCALAR)
    >>> st.p.update(B=(0.0, 0.0), D=(2.0, 0.0))
    >>> RRR("2", "3", "B", "C", "D", 2 ** 0.5, 2 ** 0.5, +1).position(st)
    >>> [round(v, 12) for v in st.p["C"]]
    [1.0, 1.0]
    """

    kind = "RRR"
    FIELDS = {
        "link1": Field("new link", "the link from end1 to middle"),
        "link2": Field("new link", "the link from end2 to middle"),
        "end1": Field("point", "end of link1, a placed point"),
        "middle": Field("new point", "joint of link1 and link2"),
        "end2": Field("point", "end of link2, a placed point"),
        "length1": Field("length", "length of link1, from end1 to middle"),
        "length2": Field("length", "length of link2, from end2 to middle"),
        "branch": Field("branch", "+1: middle to the left of the line end1 -> end2, "
                                  "-1: to the right"),
    }

    DRAWING = Drawing(1, 2, "two links pinned together", "each pinned to a placed joint")

    @classmethod
    def recognise(cls, drawn, links):
        """Two links pinned together at a joint not yet placed, each pinned to a placed
        joint: ``link1`` is the first of ``links``.

        Examples
        --------
        >>> from linkage_fmu.descriptions.topology import read
        >>> from linkage_fmu.descriptions.assur import decompose
        >>> t, _ = read({"joints": {"A": [0, 0], "B": [0.1, 0], "C": [0.3, 0.2],
        ...                         "D": [0.4, 0]},
        ...              "links": [{"name": "1", "joints": ["A", "B"]},
        ...                        {"name": "2", "joints": ["B", "C"]},
        ...                        {"name": "3", "joints": ["C", "D"]}],
        ...              "crank": {"link": "1", "pivot": "A"}}, {})
        >>> {k: decompose(t, {}).groups[1][k] for k in ("type", "end1", "middle", "end2")}
        {'type': 'RRR', 'end1': 'B', 'middle': 'C', 'end2': 'D'}
        """
        shape = drawn.dyad_of(*links)
        if shape is None:
            return False
        (kind1, e1), c, (kind2, e2) = shape
        if drawn.t.joints[c].prismatic or (kind1, kind2) != ("pin", "pin"):
            return False
        l1, l2 = links
        p1, p2 = drawn.attach(e1, l1), drawn.attach(e2, l2)
        (x1, y1), (x2, y2), (cx, cy) = drawn.pose_of(p1), drawn.pose_of(p2), drawn.xy(c)

        def sign(v):
            n = lambda s: drawn.num(s, v)  # noqa: E731
            return ((n(x2) - n(x1)) * (n(cy) - n(y1)) - (n(y2) - n(y1)) * (n(cx) - n(x1)))

        b = drawn.branch(sign,
                         f"({x2} - {x1}) * ({cy} - {y1}) - ({y2} - {y1}) * ({cx} - {x1})")
        if b is None:
            drawn.refuse(f"[joints] {c}: the dyad {e1}-{c}-{e2} (links {l1}, {l2}) is drawn "
                         f"at a toggle ({e1}, {c}, {e2} in line): its assembly mode is "
                         "undefined; draw it apart")
        drawn.group({"type": cls.kind, "link1": l1, "link2": l2, "end1": p1, "middle": c,
                     "end2": p2, "length1": f"hypot({cx} - {x1}, {cy} - {y1})",
                     "length2": f"hypot({cx} - {x2}, {cy} - {y2})", "branch": b},
                    {c: (cx, cy)})
        drawn.pair(p1, drawn.owner[p1], l1)
        drawn.pair(c, l1, l2)
        drawn.pair(p2, drawn.owner[p2], l2)
        drawn.owner[c], drawn.first[c] = None, l1
        drawn.frame_[l1] = (p1, (f"({cx} - {x1})", f"({cy} - {y1})"))
        drawn.frame_[l2] = (p2, (f"({cx} - {x2})", f"({cy} - {y2})"))
        drawn.finish(l1)
        drawn.finish(l2)
        return True

    def __init__(self, link1: str, link2: str, E1: str, C: str, E2: str,
                 L1: float, L2: float, branch: int):
        self.link1, self.link2 = link1, link2
        self.E1, self.C, self.E2 = E1, C, E2
        self.L1, self.L2, self.branch = L1, L2, mode(branch, f"the dyad {E1}-{C}-{E2}")
        self.needs = (E1, E2)
        self.places = (C,)
        self.links = (link1, link2)
        self.joints = (Revolute(E1, E1, OWNER, link1), Revolute(C, C, link1, link2),
                       Revolute(E2, E2, OWNER, link2))
        self.owners = {}  # C belongs to both links
        self.key = C
        self.lengths = (L1, L2)
        self._cannot_close = f"the dyad {E1}-{C}-{E2} cannot close"
        self._toggle = f"the dyad at {C} is at a toggle"

    @classmethod
    def from_spec(cls, spec, value):
        return cls(spec["link1"], spec["link2"], spec["end1"], spec["middle"], spec["end2"],
                   value("length1"), value("length2"), value("branch"))

    def _condition(self, d2) -> str:
        d = math.sqrt(float(np.asarray(d2).flat[0]))
        name = f"{self.E1}{self.E2}"
        reach, gap = self.L1 + self.L2, abs(self.L1 - self.L2)
        head = f"the dyad {self.E1}-{self.C}-{self.E2} cannot close: |{name}| = {fmt(d)} m"
        if d > 0.5 * (reach + gap):
            return (f"{head} > {self.E1}{self.C} + {self.C}{self.E2} = {fmt(reach)} m "
                    f"(by {fmt(d - reach)} m)")
        return (f"{head} < |{self.E1}{self.C} - {self.C}{self.E2}| = {fmt(gap)} m "
                f"(by {fmt(gap - d)} m)")

    def position(self, st: KinematicState) -> None:
        (x1, y1), (x2, y2) = st.p[self.E1], st.p[self.E2]
        L1, L2 = self.L1, self.L2
        cx, cy = dyad_middle(st, (x1, y1), (x2, y2), L1, L2, self.branch, self._condition,
                             self._cannot_close)
        st.p[self.C] = (cx, cy)
        st.u[self.link1] = ((cx - x1) / L1, (cy - y1) / L1)
        st.u[self.link2] = ((cx - x2) / L2, (cy - y2) / L2)

    def _arms(self, st: KinematicState):
        (c1, s1), (c2, s2) = st.u[self.link1], st.u[self.link2]
        r1x, r1y, r2x, r2y = self.L1 * c1, self.L1 * s1, self.L2 * c2, self.L2 * s2
        return r1x, r1y, r2x, r2y, r1x * r2y - r1y * r2x

    def first(self, st: KinematicState) -> None:
        r1x, r1y, r2x, r2y, D = self._arms(st)
        (a1x, a1y), (a2x, a2y) = st.d1[self.E1], st.d1[self.E2]
        dvx, dvy = a2x - a1x, a2y - a1y
        w1 = (dvx * r2x + dvy * r2y) / D
        w2 = (dvx * r1x + dvy * r1y) / D
        st.w1[self.link1], st.w1[self.link2] = w1, w2
        st.d1[self.C] = (a1x - w1 * r1y, a1y + w1 * r1x)

    def second(self, st: KinematicState) -> None:
        r1x, r1y, r2x, r2y, D = self._arms(st)
        w1, w2 = st.w1[self.link1], st.w1[self.link2]
        (a1x, a1y), (a2x, a2y) = st.d2[self.E1], st.d2[self.E2]
        q1, q2 = w1 * w1, w2 * w2
        dax = a2x - a1x + q1 * r1x - q2 * r2x
        day = a2y - a1y + q1 * r1y - q2 * r2y
        e1 = (dax * r2x + day * r2y) / D
        e2 = (dax * r1x + day * r1y) / D
        st.w2[self.link1], st.w2[self.link2] = e1, e2
        st.d2[self.C] = (a1x - e1 * r1y - q1 * r1x, a1y + e1 * r1x - q1 * r1y)

    def statics(self, mech, st, W, R):
        fix, fiy, mi = moment_about(mech, st, W, self.link1, self.C)
        fjx, fjy, mj = moment_about(mech, st, W, self.link2, self.C)
        (cx, cy), (e1x, e1y), (e2x, e2y) = st.p[self.C], st.p[self.E1], st.p[self.E2]
        ux, uy, wx, wy = e1x - cx, e1y - cy, e2x - cx, e2y - cy
        fx, fy = fix + fjx, fiy + fjy
        # link1 about C: u x R1 = -mi;  link2 about C with R2 = -F - R1: w x R1 = mj - w x F
        a, c = -mi, mj - (wx * fy - wy * fx)
        d = ux * wy - uy * wx
        r1x, r1y = (a * wx - ux * c) / d, (a * wy - uy * c) / d
        r2x, r2y = -fx - r1x, -fy - r1y
        R[self.E1], R[self.E2] = (r1x, r1y), (r2x, r2y)
        R[self.C] = (-r2x - fjx, -r2y - fjy)
        push(mech, st, W, mech.owner[self.E1], self.E1, -r1x, -r1y)
        push(mech, st, W, mech.owner[self.E2], self.E2, -r2x, -r2y)

    def transmission(self, st, scale):
        """Angle between the two links at ``C``, in [0, pi]; 0 and pi are toggles."""
        (c1, s1), (c2, s2) = st.u[self.link1], st.u[self.link2]
        sin_gamma, cos_gamma = c1 * s2 - s1 * c2, c1 * c2 + s1 * s2
        return angle_and_kappa(st.xp, sin_gamma, cos_gamma, self._toggle)
