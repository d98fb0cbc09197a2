"""The angle driver: a crank turning about a frame point, or a motor between two links."""

from __future__ import annotations

from ..drivers import Driver
from ..errors import InputError
from ..pairs import Revolute
from .base import FRAME, Field, Group, KinematicState, moment_about, names_in, push


class Crank(Group):
    """Link ``link`` turns about the point ``pivot``; its tip is ``tip``.

    On the frame (no ``base``) the link's direction is the crank angle itself, so
    ``phi' = 1`` and ``phi'' = 0``. With a ``base`` link (a motor at an elbow, pivot a
    point of the base) its direction is the base's turned by ``offset`` plus the
    driver's angle, and the motor's reaction acts on the base.

    Examples
    --------
    >>> import math
    >>> from linkage_fmu.numerics import SCALAR
    >>> st = KinematicState(math.pi / 2, SCALAR)
    >>> st.p["A"] = (0.0, 0.0); st.d1["A"] = st.d2["A"] = (0.0, 0.0)
    >>> c = Crank("1", "A", "B", 0.1)
    >>> c.position(st); c.first(st)
    >>> [round(v, 12) for v in st.p["B"] + st.d1["B"]]
    [0.0, 0.1, -0.1, 0.0]
    """

    kind = "crank"
    DRIVER = True
    FIELDS = {
        "link": Field("new link", "the crank, turning about pivot"),
        "pivot": Field("point", "the placed point the crank turns about"),
        "tip": Field("new point", "end of the crank, placed at length from pivot"),
        "length": Field("length", "length of the crank, from pivot to tip"),
        "base": Field("link", "a motor's base: the link it turns the crank against, "
                              "pivot a point of it (default: the frame)"),
        "offset": Field("angle", "a motor's angle from the base's direction to its zero "
                                 "(default 0)"),
    }
    OPTIONAL = ("base", "offset")

    def __init__(self, link: str, pivot: str, tip: str, length: float, base: str = "",
                 offset: float = 0.0):
        self.link, self.pivot, self.tip, self.length = link, pivot, tip, length
        self.base, self.offset = base, offset
        self.by_time = bool(base)
        self.needs = (pivot,)
        self.places = (tip,)
        self.links = (link,)
        self.joints = (Revolute(pivot, pivot, base or FRAME, link),)
        self.owners = {tip: link}
        self.lengths = (length,)

    @classmethod
    def from_spec(cls, spec, value):
        return cls(spec["link"], spec["pivot"], spec["tip"], value("length"),
                   spec.get("base", ""), value("offset") if "offset" in spec else 0.0)

    def attach(self, before: tuple, frame_points: dict) -> None:
        self.index = sum(1 for grp in before if grp.DRIVER)
        if self.base and not any(self.base in grp.links for grp in before):
            raise InputError(f"the motor at {self.pivot}: its base {self.base!r} is not a "
                             "link of a group before it")

    @classmethod
    def pairs(cls, spec: dict, placed=None) -> tuple[str, ...]:
        """Only the pivot: the tip is a joint of the group that uses it.

        Examples
        --------
        >>> Crank.pairs({"link": "1", "pivot": "A", "tip": "B", "length": 0.1})
        ('A',)
        """
        return names_in(spec, ("pivot",))

    def driver(self, effort: str, alone: bool = True) -> Driver:
        """Its angle about the pivot drives the linkage (see :meth:`Group.driver`)."""
        return Driver.named(self.pivot, "angle", effort, alone)

    @classmethod
    def drives(cls, spec: dict) -> tuple | None:
        """Its pivot's angle; by time with a ``base`` (see :meth:`Group.drives`)."""
        pivot = spec.get("pivot")
        return (pivot, "angle", bool(spec.get("base"))) if isinstance(pivot, str) else None

    def acts(self) -> tuple:
        """A moment on the crank, its reaction on the base (see :meth:`Group.acts`)."""
        return self.link, "", None, self.base or FRAME

    def position(self, st: KinematicState) -> None:
        xp, L = st.xp, self.length
        if st.rates is None:
            c, s = xp.cos(st.theta), xp.sin(st.theta)
        else:
            q = st.theta[self.index]
            c, s = xp.cos(q + self.offset), xp.sin(q + self.offset)
            if self.base:  # turned from the base's direction
                c0, s0 = st.u[self.base]
                c, s = c0 * c - s0 * s, s0 * c + c0 * s
        x0, y0 = st.p[self.pivot]
        st.u[self.link] = (c, s)
        st.p[self.tip] = (x0 + L * c, y0 + L * s)

    def first(self, st: KinematicState) -> None:
        c, s = st.u[self.link]
        L = self.length
        if st.rates is None:
            st.d1[self.tip] = (-L * s, L * c)
            st.w1[self.link] = 1.0
            return
        w = st.rates[self.index][0]
        if self.base:
            w = w + st.w1[self.base]
        vx, vy = st.d1[self.pivot]
        st.d1[self.tip] = (vx - w * L * s, vy + w * L * c)
        st.w1[self.link] = w

    def second(self, st: KinematicState) -> None:
        c, s = st.u[self.link]
        L = self.length
        if st.rates is None:
            st.d2[self.tip] = (-L * c, -L * s)
            st.w2[self.link] = 0.0
            return
        w, e = st.w1[self.link], st.rates[self.index][1]
        if self.base:
            e = e + st.w2[self.base]
        ax, ay = st.d2[self.pivot]
        w2 = w * w
        st.d2[self.tip] = (ax - e * L * s - w2 * L * c, ay + e * L * c - w2 * L * s)
        st.w2[self.link] = e

    def statics(self, mech, st, W, R):
        fx, fy, m = moment_about(mech, st, W, self.link, self.pivot)
        R[self.pivot] = (-fx, -fy)
        if self.base:  # the pin's force and the motor's reaction act on the base
            push(mech, st, W, self.base, self.pivot, fx, fy)
            W[self.base][2] = W[self.base][2] + m
        return -m  # the moment the drive must add for equilibrium about the pivot

    def transmission(self, st, scale):
        """A crank has no transmission angle."""
        return None
