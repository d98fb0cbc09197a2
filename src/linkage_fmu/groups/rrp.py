"""The rod-and-slider dyad (RRP) on a straight frame guide."""

from __future__ import annotations

import numpy as np

from ..pairs import Prismatic, Revolute
from .base import (
    FRAME,
    OWNER,
    Drawing,
    Field,
    Group,
    KinematicState,
    angle_and_kappa,
    fmt,
    left_normal,
    mode,
    moment_about,
    push,
    unit_vector,
)


class RRP(Group):
    """Dyad rod ``rod`` (``end`` - ``pin``; the arguments ``link``, ``E``, ``B``) +
    ``slider`` at ``pin`` on a straight frame guide (the pair ``guide``).

    The guide passes through ``guide_point`` (x, y) with direction angle ``gamma``.
    ``branch = +1`` puts ``B`` on the +gamma side of the foot of the perpendicular from
    ``E`` to the guide. The rod's direction is E -> B; the slider does not turn.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> st = KinematicState(0.0, SCALAR)
    >>> st.p["A"] = (0.0, 0.3)
    >>> RRP("2", "3", "A", "B", 0.5, (0.0, 0.0), 0.0, +1, "guide").position(st)
    >>> [round(v, 12) for v in st.p["B"]]
    [0.4, 0.0]
    """

    kind = "RRP"
    FIELDS = {
        "rod": Field("new link", "the rod, from end to pin"),
        "slider": Field("new link", "the slider, pinned to the rod at pin, on the frame guide"),
        "end": Field("point", "end of the rod, a placed point"),
        "pin": Field("new point", "joint of rod and slider, on the guide"),
        "length": Field("length", "length of the rod, from end to pin"),
        "guide_point": Field("vector", "a point [x, y] of the frame guide"),
        "guide_angle": Field("angle", "direction of the guide, counter-clockwise from +x"),
        "branch": Field("branch", "+1: pin on the guide_angle side of the foot of the "
                                  "perpendicular from end to the guide, -1: on the other"),
        "guide": Field("new joint", "name of the slider's prismatic pair on the guide"),
    }

    DRAWING = Drawing(2, 2, "a rod and a slider pinned together",
                      "the rod pinned to a placed joint, the slider on a frame guide "
                      "(listed by the slider only)")

    @classmethod
    def recognise(cls, drawn, links):
        """A rod and a slider pinned together at a joint not yet placed, the rod pinned
        to a placed joint, the slider on a frame guide (a prismatic joint that it alone
        lists).

        Examples
        --------
        >>> from pathlib import Path
        >>> import linkage_fmu
        >>> from linkage_fmu.descriptions import Description
        >>> root = Path(linkage_fmu.__file__).parents[2]
        >>> d = Description.read(root / "examples/joints/slider_crank.toml")
        >>> {k: d.groups[1][k] for k in ("type", "rod", "slider", "end", "pin", "guide")}
        {'type': 'RRP', 'rod': '2', 'slider': '3', 'end': 'A', 'pin': 'B', 'guide': 'guide'}
        """
        shape = drawn.dyad_of(*links)
        if shape is None:
            return False
        (kind_x, jx), pin, (kind_y, jy) = shape
        if drawn.t.joints[pin].prismatic or sorted((kind_x, kind_y)) != ["frame guide", "pin"]:
            return False
        x, y = links
        rod, slider = (x, y) if kind_x == "pin" else (y, x)
        end, guide = (jx, jy) if rod == x else (jy, jx)
        p = drawn.attach(end, rod)
        (ex, ey), (bx, by), (tx, ty) = drawn.pose_of(p), drawn.xy(pin), drawn.slide(guide)

        def sign(v):
            n = lambda s: drawn.num(s, v)  # noqa: E731
            return (n(bx) - n(ex)) * n(tx) + (n(by) - n(ey)) * n(ty)

        b = drawn.branch(sign, f"({bx} - {ex}) * {tx} + ({by} - {ey}) * {ty}")
        if b is None:
            drawn.refuse(f"[joints] {pin}: the rod {end}{pin} (link {rod}) is drawn square "
                         f"to the guide {guide}: the slider's assembly mode is undefined; "
                         "draw it apart")
        drawn.group({"type": cls.kind, "rod": rod, "slider": slider, "end": p, "pin": pin,
                     "length": f"hypot({bx} - {ex}, {by} - {ey})",
                     "guide_point": [drawn.fold(bx), drawn.fold(by)],
                     "guide_angle": f"atan2({ty}, {tx})", "branch": b, "guide": guide},
                    {pin: (bx, by)})
        drawn.pair(p, drawn.owner[p], rod)
        drawn.pair(pin, rod, slider)
        drawn.pair(guide, drawn.t.frame, slider)
        drawn.owner[pin], drawn.first[pin] = None, rod
        drawn.frame_[rod] = (p, (f"({bx} - {ex})", f"({by} - {ey})"))
        drawn.frame_[slider] = (pin, (tx, ty))
        drawn.finish(rod)
        drawn.finish(slider)
        return True

    def __init__(self, link: str, slider: str, E: str, B: str, L: float,
                 guide_point: tuple, gamma: float, branch: int, guide_joint: str):
        self.link, self.slider, self.E, self.B = link, slider, E, B
        self.L, self.branch = L, mode(branch, f"the slider at {B}")
        self.q = (guide_point[0], guide_point[1])
        self.t = unit_vector(gamma)
        self.guide_joint = guide_joint
        self.needs = (E,)
        self.places = (B,)
        self.links = (link, slider)
        self.joints = (Revolute(E, E, OWNER, link), Revolute(B, B, link, slider),
                       Prismatic(guide_joint, B, FRAME, slider, left_normal(self.t)))
        self.owners = {}  # B belongs to rod and slider
        self.key = B
        self.lengths = (L,)
        self._too_far = f"{E} is farther from the guide of {B} than {E}{B}"
        self._toggle = f"the dyad at {B} is at a toggle"

    @classmethod
    def from_spec(cls, spec, value):
        return cls(spec["rod"], spec["slider"], spec["end"], spec["pin"], value("length"),
                   value("guide_point"), value("guide_angle"), value("branch"), spec["guide"])

    def position(self, st: KinematicState) -> None:
        ex, ey = st.p[self.E]
        tx, ty = self.t
        dx, dy = self.q[0] - ex, self.q[1] - ey
        dt = dx * tx + dy * ty
        dn = dy * tx - dx * ty  # distance of E from the guide, signed
        L = self.L
        root = st.root((L - dn) * (L + dn), lambda: (
            f"{self.E} is {fmt(abs(np.asarray(dn).flat[0]))} m from the guide of {self.B}, "
            f"more than {self.E}{self.B} = {fmt(L)} m"), self._too_far)
        s = -dt + self.branch * root
        bx, by = self.q[0] + s * tx, self.q[1] + s * ty
        st.p[self.B] = (bx, by)
        st.u[self.link] = ((bx - ex) / L, (by - ey) / L)
        st.u[self.slider] = self.t

    def _axis(self, st: KinematicState):
        c, s = st.u[self.link]
        ux, uy = self.L * c, self.L * s
        return ux, uy, ux * self.t[0] + uy * self.t[1]

    def first(self, st: KinematicState) -> None:
        ux, uy, ut = self._axis(st)
        tx, ty = self.t
        ex, ey = st.d1[self.E]
        sp = (ux * ex + uy * ey) / ut
        bx, by = sp * tx, sp * ty
        st.d1[self.B] = (bx, by)
        st.w1[self.link] = (ux * (by - ey) - uy * (bx - ex)) / (self.L * self.L)
        st.w1[self.slider] = 0.0

    def second(self, st: KinematicState) -> None:
        ux, uy, ut = self._axis(st)
        tx, ty = self.t
        (e1x, e1y), (b1x, b1y) = st.d1[self.E], st.d1[self.B]
        ex, ey = st.d2[self.E]
        rx, ry = b1x - e1x, b1y - e1y
        spp = (ux * ex + uy * ey - (rx * rx + ry * ry)) / ut
        bx, by = spp * tx, spp * ty
        st.d2[self.B] = (bx, by)
        st.w2[self.link] = (ux * (by - ey) - uy * (bx - ex)) / (self.L * self.L)
        st.w2[self.slider] = 0.0

    def statics(self, mech, st, W, R):
        fix, fiy, mi = moment_about(mech, st, W, self.link, self.B)
        fjx, fjy, mj = moment_about(mech, st, W, self.slider, self.B)
        (bx, by), (ex, ey) = st.p[self.B], st.p[self.E]
        nx, ny = -self.t[1], self.t[0]
        ux, uy = ex - bx, ey - by
        fx, fy = fix + fjx, fiy + fjy
        # rod about B: u x (-F - N n) = -mi
        N = (mi - (ux * fy - uy * fx)) / (ux * ny - uy * nx)
        r1x, r1y = -fx - N * nx, -fy - N * ny
        R[self.E] = (r1x, r1y)
        R[self.B] = (-N * nx - fjx, -N * ny - fjy)
        R[self.guide_joint] = (N, -mj)
        push(mech, st, W, mech.owner[self.E], self.E, -r1x, -r1y)

    def transmission(self, st, scale):
        """Angle between the rod and the guide's normal, in [0, pi/2]; 0 is singular."""
        c, s = st.u[self.link]
        tx, ty = self.t
        ut = c * tx + s * ty
        un = s * tx - c * ty
        xp = st.xp
        return angle_and_kappa(xp, xp.abs(ut), xp.abs(un), self._toggle)
