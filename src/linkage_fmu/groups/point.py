"""A point fixed on a link: a centre of mass, or a joint such as the tip of a lever."""

from __future__ import annotations

from .. import numerics
from .base import Field, Group, KinematicState


class LinkPoint(Group):
    """Point ``name`` fixed on ``link`` at ``(along, across)`` in the link's own frame,
    measured from the link's point ``from`` (the argument ``ref``): ``along`` in the
    link's direction, ``across`` to its left (counter-clockwise). Or, with ``distance``,
    at that distance from ``from`` in the direction ``angle`` counter-clockwise from the
    link's.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> st = KinematicState(0.0, SCALAR)
    >>> st.p["B"], st.u["2"] = (1.0, 0.0), (0.0, 1.0)
    >>> LinkPoint("2", "B", "S2", 0.5, 0.1).position(st)
    >>> st.p["S2"]
    (0.9, 0.5)
    """

    kind = "point"
    FIELDS = {
        "link": Field("link", "the link the point is fixed on, added by an earlier group"),
        "from": Field("point", "the link's point the new point is measured from"),
        "name": Field("new point", "the point fixed on the link"),
        "along": Field("coordinate", "distance from 'from' along the link's direction"),
        "across": Field("coordinate", "distance from 'from' to the left of the link"),
        "distance": Field("coordinate", "distance from 'from' (with angle, instead of "
                                        "along and across)"),
        "angle": Field("angle", "direction from 'from', counter-clockwise from the link's"),
    }
    OPTIONAL = ("along", "across", "distance", "angle")

    def __init__(self, link: str, ref: str, name: str, along: float = 0.0, across: float = 0.0,
                 distance: float | None = None, angle: float = 0.0):
        self.link, self.ref, self.name = link, ref, name
        self.along, self.across = along, across
        self.polar = None if distance is None else (distance, numerics.cos(angle),
                                                        numerics.sin(angle))
        self.needs = (ref,)
        self.places = (name,)
        self.owners = {name: link}

    @classmethod
    def from_spec(cls, spec, value):
        if "distance" in spec:
            return cls(spec["link"], spec["from"], spec["name"], distance=value("distance"),
                       angle=value("angle") if "angle" in spec else 0.0)
        return cls(spec["link"], spec["from"], spec["name"],
                   value("along") if "along" in spec else 0.0,
                   value("across") if "across" in spec else 0.0)

    @classmethod
    def pairs(cls, spec: dict, placed=None) -> tuple[str, ...]:
        """None: the point is fixed on its link, it joins nothing.

        Examples
        --------
        >>> LinkPoint.pairs({"link": "2", "from": "B", "name": "P", "along": 0.1})
        ()
        """
        return ()

    def _arm(self, st: KinematicState):
        c, s = st.u[self.link]
        if self.polar is not None:
            d, ca, sa = self.polar
            return d * (c * ca - s * sa), d * (s * ca + c * sa)
        a, b = self.along, self.across
        return a * c - b * s, a * s + b * c

    def position(self, st: KinematicState) -> None:
        rx, ry = self._arm(st)
        x, y = st.p[self.ref]
        st.p[self.name] = (x + rx, y + ry)

    def first(self, st: KinematicState) -> None:
        rx, ry = self._arm(st)
        w = st.w1[self.link]
        x, y = st.d1[self.ref]
        st.d1[self.name] = (x - w * ry, y + w * rx)

    def second(self, st: KinematicState) -> None:
        rx, ry = self._arm(st)
        w, e = st.w1[self.link], st.w2[self.link]
        x, y = st.d2[self.ref]
        q = w * w
        st.d2[self.name] = (x - e * ry - q * rx, y + e * rx - q * ry)

    def statics(self, mech, st, W, R):
        """A point carries no joint: nothing to solve."""
        return None

    def transmission(self, st, scale):
        return None
