"""The driver: a crank turning about a placed point."""

from __future__ import annotations

from ..drivers import Driver
from ..pairs import Revolute
from .base import FRAME, Field, Group, KinematicState, moment_about, names_in


class Crank(Group):
    """Link ``link`` turns about the point ``pivot``; its tip is ``tip``.

    The link direction is the crank angle itself, so ``phi' = 1`` and ``phi'' = 0``.

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
    }

    def __init__(self, link: str, pivot: str, tip: str, length: float):
        self.link, self.pivot, self.tip, self.length = link, pivot, tip, length
        self.needs = (pivot,)
        self.places = (tip,)
        self.links = (link,)
        self.joints = (Revolute(pivot, pivot, FRAME, link),)
        self.owners = {tip: link}
        self.lengths = (length,)

    @classmethod
    def from_spec(cls, spec, value):
        return cls(spec["link"], spec["pivot"], spec["tip"], value("length"))

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

    def position(self, st: KinematicState) -> None:
        xp, L = st.xp, self.length
        c, s = xp.cos(st.theta), xp.sin(st.theta)
        x0, y0 = st.p[self.pivot]
        st.u[self.link] = (c, s)
        st.p[self.tip] = (x0 + L * c, y0 + L * s)

    def first(self, st: KinematicState) -> None:
        c, s = st.u[self.link]
        L = self.length
        st.d1[self.tip] = (-L * s, L * c)
        st.w1[self.link] = 1.0

    def second(self, st: KinematicState) -> None:
        c, s = st.u[self.link]
        L = self.length
        st.d2[self.tip] = (-L * c, -L * s)
        st.w2[self.link] = 0.0

    def statics(self, mech, st, W, R):
        fx, fy, m = moment_about(mech, st, W, self.link, self.pivot)
        R[self.pivot] = (-fx, -fy)
        return -m  # the moment the drive must add for equilibrium about the pivot

    def transmission(self, st, scale):
        """A crank has no transmission angle."""
        return None
