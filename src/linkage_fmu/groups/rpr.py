"""The slotted-lever dyad (RPR): a block turning on a pin and sliding along a lever."""

from __future__ import annotations

import math

import numpy as np

from ..pairs import Prismatic, Revolute
from .base import OWNER, Drawing, Field, Group, KinematicState, moment_about, push


class RPR(Group):
    """Block ``block`` turns on the pin ``pin`` (a point already placed on another link)
    and slides along ``lever``, which turns about the placed point ``pivot``.

    The lever's direction is pivot -> pin, so there is no assembly branch; the block
    turns with the lever. The only position that cannot be solved is pin = pivot, where
    the lever's direction is undefined. The slide pair ``slide`` transmits the block's
    force on the lever along the lever's left normal, through the pin, and a couple.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> st = KinematicState(0.0, SCALAR)
    >>> st.p.update(B=(0.3, 0.0), C=(0.0, -0.4))
    >>> RPR("2", "3", "B", "C", "slot").position(st)
    >>> [round(v, 12) for v in st.u["3"]]
    [0.6, 0.8]
    """

    kind = "RPR"
    fixed_size = False  # the pin slides along the lever
    FIELDS = {
        "block": Field("new link", "the block, turning on pin and sliding along the lever"),
        "lever": Field("new link", "the lever, turning about pivot, directed from pivot to pin"),
        "pin": Field("point", "the block's pin, a placed point of another link"),
        "pivot": Field("point", "the placed point the lever turns about"),
        "slide": Field("new joint", "name of the block's prismatic pair on the lever"),
    }

    DRAWING = Drawing(3, 2, "a block and a lever sliding in one another",
                      "each pinned to a placed joint; the guide's line through the block's "
                      "pin passes through the lever's pin (the lever carries the guide; see "
                      "below)")

    @classmethod
    def recognise(cls, drawn, links):
        """A block and a lever sliding in one another (the lever carries the guide), each
        pinned to a placed joint, the slide drawn through the lever's pin (to the
        decomposition's slide tolerance). A slide that misses it is noted for the
        decomposition's message (``drawn.missed``), and the links are no RPR.

        Examples
        --------
        >>> from pathlib import Path
        >>> import linkage_fmu
        >>> from linkage_fmu.descriptions import Description
        >>> root = Path(linkage_fmu.__file__).parents[2]
        >>> d = Description.read(root / "examples/joints/crank_shaper.toml")
        >>> {k: d.groups[1][k] for k in ("type", "block", "lever", "pin", "pivot", "slide")}
        {'type': 'RPR', 'block': '2', 'lever': '3', 'pin': 'B', 'pivot': 'C', 'slide': 'slot'}
        """
        shape = drawn.dyad_of(*links)
        if shape is None:
            return False
        (kind_x, jx), slot, (kind_y, jy) = shape
        if not drawn.t.joints[slot].prismatic or (kind_x, kind_y) != ("pin", "pin"):
            return False
        x, y = links
        lever = drawn.t.joints[slot].guide
        block = y if lever == x else x
        pivot, pin = (jx, jy) if lever == x else (jy, jx)
        (px, py), (cx, cy), (tx, ty) = drawn.xy(pin), drawn.xy(pivot), drawn.slide(slot)
        n = drawn.num
        ax, ay, dx, dy = n(cx) - n(px), n(cy) - n(py), n(tx), n(ty)
        if ax == 0.0 and ay == 0.0:
            return False
        sine = abs(ax * dy - ay * dx) / (math.hypot(ax, ay) * math.hypot(dx, dy))
        tolerance = drawn.slide_tolerance
        if not sine <= tolerance:  # the slot does not pass through the lever's pivot
            written = ", ".join(map(repr, drawn.t.joints[slot].slide))
            drawn.missed[slot] = (
                f"[joints] {slot} slide: [{written}] through the pin {pin} misses the pivot "
                f"{pivot} of the lever {lever} by {sine * math.hypot(ax, ay):.3g} m (the sine "
                f"of the angle between the slide and the line {pin}-{pivot} is {sine:.3g}; "
                f"the tolerance is {tolerance:g}): a block in the slot of a turning "
                "lever (an RPR dyad) slides on a line through the lever's pivot; write "
                f"slide = [\"x_{pin} - x_{pivot}\", \"y_{pin} - y_{pivot}\"] for a slot "
                "exactly through it")
            return False
        off = (f"abs(({cx} - {px}) * {ty} - ({cy} - {py}) * {tx}) / "
               f"(hypot({cx} - {px}, {cy} - {py}) * hypot({tx}, {ty}))")
        if drawn.moves(off):
            drawn.check(f"[joints] {slot} slide: the parameters turn the slide off the line "
                        f"{pin}-{pivot} through the lever's pivot (the sine of the angle "
                        f"between them above {tolerance:g}): the slot of a turning lever "
                        "runs through its pivot", off)
        p, c = drawn.attach(pin, block), drawn.attach(pivot, lever)
        drawn.group({"type": cls.kind, "block": block, "lever": lever, "pin": p, "pivot": c,
                     "slide": slot}, {})
        drawn.pair(p, drawn.owner[p], block)
        drawn.pair(slot, block, lever)
        drawn.pair(c, drawn.owner[c], lever)
        (px, py), (cx, cy) = drawn.pose_of(p), drawn.pose_of(c)
        drawn.frame_[lever] = (c, (f"({px} - {cx})", f"({py} - {cy})"))
        drawn.frame_[block] = (p, drawn.frame_[lever][1])
        drawn.finish(block)
        drawn.finish(lever)
        return True

    def __init__(self, block: str, lever: str, pin: str, pivot: str, slide_joint: str):
        self.block, self.lever, self.P, self.C = block, lever, pin, pivot
        self.slide_joint = slide_joint
        self.needs = (pin, pivot)
        self.places = ()
        self.links = (block, lever)
        self.joints = (Revolute(pin, pin, OWNER, block),
                       Prismatic(slide_joint, pin, block, lever, lever),
                       Revolute(pivot, pivot, OWNER, lever))
        self.owners = {}
        self.key = pin
        self._coincide = f"the lever's direction is undefined: {pin} coincides with {pivot}"

    @classmethod
    def from_spec(cls, spec, value):
        return cls(spec["block"], spec["lever"], spec["pin"], spec["pivot"], spec["slide"])

    def _arm(self, st: KinematicState, d: dict):
        (px, py), (cx, cy) = d[self.P], d[self.C]
        return px - cx, py - cy

    def position(self, st: KinematicState) -> None:
        rx, ry = self._arm(st, st.p)
        s = st.positive(st.xp.sqrt(rx * rx + ry * ry), lambda: self._coincide, self._coincide)
        u = (rx / s, ry / s)
        st.u[self.lever] = st.u[self.block] = u

    def _slide(self, st: KinematicState):
        """Distance pivot -> pin along the lever, and its first-order coefficient."""
        ux, uy = st.u[self.lever]
        rx, ry = self._arm(st, st.p)
        vx, vy = self._arm(st, st.d1)
        return rx * ux + ry * uy, vx * ux + vy * uy, (ux, uy, vx, vy)

    def first(self, st: KinematicState) -> None:
        s, _, (ux, uy, vx, vy) = self._slide(st)
        st.w1[self.lever] = st.w1[self.block] = (ux * vy - uy * vx) / s

    def second(self, st: KinematicState) -> None:
        s, s1, (ux, uy, _, _) = self._slide(st)
        w = st.w1[self.lever]
        ax, ay = self._arm(st, st.d2)
        # r'' = (s'' - s w^2) u + (2 s' w + s w') n, with n the left normal of u
        st.w2[self.lever] = st.w2[self.block] = ((ux * ay - uy * ax) - 2.0 * s1 * w) / s

    def statics(self, mech, st, W, R):
        fbx, fby, mb = moment_about(mech, st, W, self.block, self.P)
        flx, fly, ml = moment_about(mech, st, W, self.lever, self.C)
        ux, uy = st.u[self.lever]
        nx, ny = -uy, ux
        rx, ry = self._arm(st, st.p)
        # block about the pin: mb - M = 0; lever about the pivot: ml + s N + M = 0
        M = mb
        N = -(ml + M) / (rx * ux + ry * uy)
        r1x, r1y = N * nx - fbx, N * ny - fby  # owner of the pin on the block
        r2x, r2y = -flx - N * nx, -fly - N * ny  # owner of the pivot on the lever
        R[self.P], R[self.slide_joint], R[self.C] = (r1x, r1y), (N, M), (r2x, r2y)
        push(mech, st, W, mech.owner[self.P], self.P, -r1x, -r1y)
        push(mech, st, W, mech.owner[self.C], self.C, -r2x, -r2y)

    def transmission(self, st, scale):
        """The block's force on the lever is normal to it, as is the lever's motion at
        the pin: the transmission angle is always pi/2. The position and the slide force
        amplify rounding by ``scale / s`` as the pin nears the pivot."""
        rx, ry = self._arm(st, st.p)
        xp = st.xp
        s = xp.sqrt(rx * rx + ry * ry)
        if xp.scalar:
            kappa = xp.maximum(1.0, scale / s) if s > 0.0 else math.inf
        else:
            with np.errstate(divide="ignore"):
                kappa = xp.maximum(1.0, scale / s)
        return 0.5 * math.pi + 0.0 * s, kappa

