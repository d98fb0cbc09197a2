"""The travel driver: a linear actuator (a hydraulic cylinder) of driven length, with the
link it moves."""

from __future__ import annotations

import numpy as np

from ..drivers import Driver
from ..pairs import Prismatic, Revolute
from .base import (
    OWNER,
    Field,
    Group,
    KinematicState,
    angle_and_kappa,
    fmt,
    mode,
    moment_about,
    push,
)
from .rrr import dyad_middle


class Cylinder(Group):
    """A dyad whose second side is a cylinder of driven length: ``link`` from ``end1``
    (``E1``) to ``middle`` (``C``), and a cylinder from ``end2`` (``E2``) to ``C``: its
    ``barrel`` pinned at ``E2``, its ``rod`` pinned to ``link`` at ``C``, the rod sliding
    in the barrel (the prismatic pair ``pair``) along the line E2 -> C.

    The driver's coordinate is the travel ``s`` from the drawn length ``length0``: the
    cylinder is ``length0 + s`` long. Its effort is the force ``Fb`` the barrel applies
    to the rod along E2 -> C (> 0 pushes the pins apart). ``branch = +1`` places ``C``
    to the left of the directed line E1 -> E2, ``-1`` to the right; ``link``'s
    direction is E1 -> C, the barrel's and the rod's E2 -> C.

    Examples
    --------
    A link 1 m long from the origin, a cylinder from (2, 0) drawn 1.5 m long, pushed
    out by 0.1 m at 0.2 m/s:

    >>> from linkage_fmu.numerics import SCALAR
    >>> st = KinematicState((0.1,), SCALAR, rates=((0.2, 0.0),))
    >>> st.p.update(O=(0.0, 0.0), E=(2.0, 0.0))
    >>> st.d1.update(O=(0.0, 0.0), E=(0.0, 0.0))
    >>> cyl = Cylinder("1", "b", "r", "O", "C", "E", "P", 1.0, 1.5, +1)
    >>> cyl.position(st); cyl.first(st)
    >>> x, y = st.p["C"]
    >>> round(x * x + y * y, 12), round((x - 2.0) ** 2 + y * y, 12)
    (1.0, 2.56)
    >>> ux, uy = st.u["b"]
    >>> vx, vy = st.d1["C"]  # C moves apart from E at the rod's speed
    >>> round(vx * ux + vy * uy, 12)
    0.2
    """

    kind = "cylinder"
    DRIVER = True
    FIELDS = {
        "link": Field("new link", "the link from end1 to middle"),
        "barrel": Field("new link", "the cylinder's barrel, pinned at end2"),
        "rod": Field("new link", "the cylinder's rod, pinned to link at middle, sliding in "
                                 "the barrel"),
        "end1": Field("point", "end of link, a placed point"),
        "middle": Field("new point", "joint of link and rod"),
        "end2": Field("point", "the barrel's pin, a placed point"),
        "pair": Field("new joint", "name of the prismatic pair of rod and barrel, whose "
                                   "travel drives"),
        "length1": Field("length", "length of link, from end1 to middle"),
        "length0": Field("length", "length of the cylinder from end2 to middle at zero "
                                   "travel"),
        "branch": Field("branch", "+1: middle to the left of the line end1 -> end2, "
                                  "-1: to the right"),
    }
    by_time = True

    def __init__(self, link: str, barrel: str, rod: str, E1: str, C: str, E2: str,
                 pair: str, L1: float, L0: float, branch: int):
        self.link, self.barrel, self.rod = link, barrel, rod
        self.E1, self.C, self.E2, self.pair = E1, C, E2, pair
        self.L1, self.L0 = L1, L0
        self.branch = mode(branch, f"the cylinder dyad {E1}-{C}-{E2}")
        self.needs = (E1, E2)
        self.places = (C,)
        self.links = (link, barrel, rod)
        self.joints = (Revolute(E1, E1, OWNER, link), Revolute(C, C, link, rod),
                       Revolute(E2, E2, OWNER, barrel),
                       Prismatic(pair, C, barrel, rod, barrel))
        self.owners = {}  # C belongs to the link and the rod
        self.key = C
        self.lengths = (L1, L0)
        self._cannot_close = f"the cylinder dyad {E1}-{C}-{E2} cannot close"
        self._retracted = f"the cylinder {E2}-{C} is retracted to no length"
        self._toggle = f"the cylinder dyad at {C} is at a toggle"

    @classmethod
    def from_spec(cls, spec, value):
        return cls(spec["link"], spec["barrel"], spec["rod"], spec["end1"], spec["middle"],
                   spec["end2"], spec["pair"], value("length1"), value("length0"),
                   value("branch"))

    @classmethod
    def pairs(cls, spec: dict, placed=None) -> tuple[str, ...]:
        """The pins at ``end1``, ``middle`` and ``end2``, and the sliding ``pair``.

        Examples
        --------
        >>> Cylinder.pairs({"end1": "O", "middle": "C", "end2": "E", "pair": "P"})
        ('O', 'C', 'E', 'P')
        """
        return super().pairs(spec, placed)

    def driver(self, effort: str, alone: bool = True) -> Driver:
        """Its travel drives the linkage (see :meth:`Group.driver`)."""
        return Driver.named(self.pair, "travel", effort, alone)

    @classmethod
    def drives(cls, spec: dict) -> tuple | None:
        """Its pair's travel, by time (see :meth:`Group.drives`)."""
        pair = spec.get("pair")
        return (pair, "travel", True) if isinstance(pair, str) else None

    def acts(self) -> tuple:
        """A force on the rod at ``middle`` along the barrel, its reaction on the
        barrel (see :meth:`Group.acts`)."""
        return self.rod, self.C, self.barrel, self.barrel

    def attach(self, before: tuple, frame_points: dict) -> None:
        self.index = sum(1 for grp in before if grp.DRIVER)

    def length(self, st: KinematicState):
        """The cylinder's length at ``st``, which must be > 0."""
        L2 = self.L0 + st.theta[self.index]
        return st.positive(L2, lambda: (f"{self._retracted}: its length "
                                        f"{fmt(self.L0)} m + travel is {fmt(L2)} m"),
                           self._retracted)

    def _condition(self, d2, L2) -> str:
        d, L2 = float(np.asarray(d2).flat[0]) ** 0.5, float(np.asarray(L2).flat[0])
        head = (f"the cylinder dyad {self.E1}-{self.C}-{self.E2} cannot close: "
                f"|{self.E1}{self.E2}| = {fmt(d)} m")
        reach, gap = self.L1 + L2, abs(self.L1 - L2)
        if d > 0.5 * (reach + gap):
            return (f"{head} > {self.E1}{self.C} + cylinder = {fmt(reach)} m "
                    f"(by {fmt(d - reach)} m)")
        return (f"{head} < |{self.E1}{self.C} - cylinder| = {fmt(gap)} m "
                f"(by {fmt(gap - d)} m)")

    def position(self, st: KinematicState) -> None:
        (x1, y1), (x2, y2) = st.p[self.E1], st.p[self.E2]
        L1, L2 = self.L1, self.length(st)
        cx, cy = dyad_middle(st, (x1, y1), (x2, y2), L1, L2, self.branch,
                             lambda d2: self._condition(d2, L2), self._cannot_close)
        st.p[self.C] = (cx, cy)
        st.u[self.link] = ((cx - x1) / L1, (cy - y1) / L1)
        st.u[self.barrel] = st.u[self.rod] = ((cx - x2) / L2, (cy - y2) / L2)

    def _arms(self, st: KinematicState):
        (c1, s1), (c2, s2) = st.u[self.link], st.u[self.barrel]
        L2 = self.L0 + st.theta[self.index]
        r1x, r1y, r2x, r2y = self.L1 * c1, self.L1 * s1, L2 * c2, L2 * s2
        return r1x, r1y, r2x, r2y, r1x * r2y - r1y * r2x

    def first(self, st: KinematicState) -> None:
        r1x, r1y, r2x, r2y, D = self._arms(st)
        v = st.rates[self.index][0]
        ux, uy = st.u[self.barrel]
        (a1x, a1y), (a2x, a2y) = st.d1[self.E1], st.d1[self.E2]
        # C = E1 + r1 = E2 + r2, the second arm growing at v along itself
        dvx, dvy = a2x - a1x + v * ux, a2y - a1y + v * uy
        w1 = (dvx * r2x + dvy * r2y) / D
        w2 = (dvx * r1x + dvy * r1y) / D
        st.w1[self.link] = w1
        st.w1[self.barrel] = st.w1[self.rod] = w2
        st.d1[self.C] = (a1x - w1 * r1y, a1y + w1 * r1x)

    def second(self, st: KinematicState) -> None:
        r1x, r1y, r2x, r2y, D = self._arms(st)
        v, a = st.rates[self.index]
        ux, uy = st.u[self.barrel]
        w1, w2 = st.w1[self.link], st.w1[self.barrel]
        (a1x, a1y), (a2x, a2y) = st.d2[self.E1], st.d2[self.E2]
        q1, q2, k = w1 * w1, w2 * w2, 2.0 * v * w2  # k: the Coriolis term's factor
        dax = a2x - a1x + q1 * r1x - q2 * r2x + a * ux - k * uy
        day = a2y - a1y + q1 * r1y - q2 * r2y + a * uy + k * ux
        e1 = (dax * r2x + day * r2y) / D
        e2 = (dax * r1x + day * r1y) / D
        st.w2[self.link] = e1
        st.w2[self.barrel] = st.w2[self.rod] = e2
        st.d2[self.C] = (a1x - e1 * r1y - q1 * r1x, a1y + e1 * r1x - q1 * r1y)

    def statics(self, mech, st, W, R):
        # the link and the cylinder (barrel and rod together: the pair's forces are
        # internal to it) about C, as a revolute dyad
        fix, fiy, mi = moment_about(mech, st, W, self.link, self.C)
        fbx, fby, mb = moment_about(mech, st, W, self.barrel, self.C)
        frx, fry, mr = moment_about(mech, st, W, self.rod, self.C)
        fjx, fjy, mj = fbx + frx, fby + fry, mb + mr
        (cx, cy), (e1x, e1y), (e2x, e2y) = st.p[self.C], st.p[self.E1], st.p[self.E2]
        ux, uy, wx, wy = e1x - cx, e1y - cy, e2x - cx, e2y - cy
        fx, fy = fix + fjx, fiy + fjy
        a, c = -mi, mj - (wx * fy - wy * fx)
        d = ux * wy - uy * wx
        r1x, r1y = (a * wx - ux * c) / d, (a * wy - uy * c) / d
        r2x, r2y = -fx - r1x, -fy - r1y
        R[self.E1], R[self.E2] = (r1x, r1y), (r2x, r2y)
        rcx, rcy = -r2x - fjx, -r2y - fjy  # the link on the rod, at C
        R[self.C] = (rcx, rcy)
        # the rod alone: the barrel holds it by N (normal), M and the driver's force
        tx, ty = st.u[self.barrel]
        sx, sy = frx + rcx, fry + rcy
        R[self.pair] = (-(ty * -sx + tx * sy), -mr)  # N along the left normal (-ty, tx)
        push(mech, st, W, mech.owner[self.E1], self.E1, -r1x, -r1y)
        push(mech, st, W, mech.owner[self.E2], self.E2, -r2x, -r2y)
        return -(sx * tx + sy * ty)

    def transmission(self, st, scale):
        """Angle between the link and the cylinder at ``C``, in [0, pi]; 0 and pi are
        toggles."""
        (c1, s1), (c2, s2) = st.u[self.link], st.u[self.barrel]
        sin_gamma, cos_gamma = c1 * s2 - s1 * c2, c1 * c2 + s1 * s2
        return angle_and_kappa(st.xp, sin_gamma, cos_gamma, self._toggle)
