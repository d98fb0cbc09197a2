"""The block-and-yoke dyad (RPP): a block in a slot of a yoke sliding on a frame guide."""

from __future__ import annotations

from .. import numerics
from ..errors import InputError
from ..kernels.trace import Reason
from ..numerics import SCALAR
from ..pairs import Prismatic, Revolute
from .base import (
    FRAME,
    OWNER,
    Drawing,
    Field,
    Group,
    KinematicState,
    angle_and_kappa,
    left_normal,
    moment_about,
    names_in,
    push,
    unit_vector,
)


class RPP(Group):
    """Dyad block ``block`` (on the pin ``pin``, the argument ``E``) + ``yoke``: the block
    slides in a straight slot of the yoke (direction ``slot_angle``, the pair ``slot``),
    the yoke slides on a straight frame guide (through ``guide_point``, direction
    ``guide_angle``, the pair ``guide``). The yoke's reference point ``ref`` is where the
    slot's centre line crosses the guide line.

    Examples
    --------
    >>> import math
    >>> from linkage_fmu.numerics import SCALAR
    >>> st = KinematicState(0.0, SCALAR)
    >>> st.p["B"] = (0.05, 0.0866)
    >>> RPP("2", "3", "B", "S3", 0.0, (0.0, 0.0), math.pi / 2, "slot", "guide").position(st)
    >>> [round(v, 12) for v in st.p["S3"]]
    [0.0, 0.0866]
    """

    kind = "RPP"
    FIELDS = {
        "block": Field("new link", "the block, turning on pin and sliding in the yoke's slot"),
        "yoke": Field("new link", "the yoke, sliding on the frame guide"),
        "pin": Field("point", "the block's pin, a placed point of another link"),
        "ref": Field("new point", "the yoke's reference point, where the slot's centre line "
                                  "crosses the guide line"),
        "slot_angle": Field("angle", "direction of the slot, counter-clockwise from +x"),
        "guide_point": Field("vector", "a point [x, y] of the frame guide"),
        "guide_angle": Field("angle", "direction of the frame guide, counter-clockwise from +x"),
        "slot": Field("new joint", "name of the block's prismatic pair in the slot"),
        "guide": Field("new joint", "name of the yoke's prismatic pair on the guide"),
    }

    DRAWING = Drawing(4, 2, "a block and a yoke sliding in one another",
                      "the block pinned to a placed joint, the yoke on a frame guide")

    @classmethod
    def recognise(cls, drawn, links):
        """A block and a yoke sliding in one another, the block pinned to a placed joint,
        the yoke on a frame guide (a prismatic joint that it alone lists); the yoke's
        reference point is named ``GUIDE_ref``.

        Examples
        --------
        >>> from pathlib import Path
        >>> import linkage_fmu
        >>> from linkage_fmu.descriptions import Description
        >>> root = Path(linkage_fmu.__file__).parents[2]
        >>> d = Description.read(root / "examples/joints/scotch_yoke.toml")
        >>> {k: d.groups[1][k] for k in ("type", "block", "yoke", "pin", "ref", "slot")}
        {'type': 'RPP', 'block': '2', 'yoke': '3', 'pin': 'B', 'ref': 'guide_ref', 'slot': 'slot'}
        """
        shape = drawn.dyad_of(*links)
        if shape is None:
            return False
        (kind_x, jx), slot, (kind_y, jy) = shape
        if not drawn.t.joints[slot].prismatic or sorted((kind_x, kind_y)) != ["frame guide",
                                                                              "pin"]:
            return False
        x, y = links
        block, yoke = (x, y) if kind_x == "pin" else (y, x)
        pin, guide = (jx, jy) if block == x else (jy, jx)
        p = drawn.attach(pin, block)
        (ex, ey), (t1x, t1y), (t2x, t2y) = drawn.pose_of(p), drawn.slide(slot), drawn.slide(guide)
        qx, qy = drawn.xy(guide)
        # how far along the guide the slot's line through the pin crosses it
        s = (f"((({ex}) - {qx}) * {t1y} - (({ey}) - {qy}) * {t1x}) "
             f"/ ({t2x} * {t1y} - {t2y} * {t1x})")
        ref = f"{guide}_ref"
        drawn.fresh(ref, f"the point of yoke {yoke} where the slot's line crosses the guide "
                         f"{guide}")
        rx, ry = f"({qx} + {s} * {t2x})", f"({qy} + {s} * {t2y})"
        drawn.group({"type": cls.kind, "block": block, "yoke": yoke, "pin": p, "ref": ref,
                     "slot_angle": f"atan2({t1y}, {t1x})",
                     "guide_point": [drawn.fold(qx), drawn.fold(qy)],
                     "guide_angle": f"atan2({t2y}, {t2x})", "slot": slot, "guide": guide},
                    {ref: (rx, ry)})
        drawn.pair(p, drawn.owner[p], block)
        drawn.pair(slot, block, yoke)
        drawn.pair(guide, drawn.t.frame, yoke)
        drawn.owner[ref] = drawn.first[ref] = yoke
        drawn.frame_[block] = (p, (t1x, t1y))
        drawn.frame_[yoke] = (ref, (t2x, t2y))
        drawn.finish(block)
        drawn.finish(yoke)
        return True

    def __init__(self, block: str, yoke: str, E: str, ref: str, slot_angle: float,
                 guide_point: tuple, guide_angle: float, slot_joint: str, guide_joint: str):
        self.block, self.yoke, self.E, self.ref = block, yoke, E, ref
        self.t1 = unit_vector(slot_angle)
        self.t2 = unit_vector(guide_angle)
        self.q = (guide_point[0], guide_point[1])
        self.cross = self.t2[0] * self.t1[1] - self.t2[1] * self.t1[0]
        parallel = abs(self.cross) < 1e-12
        numerics.label(self.cross, Reason("parameter", "slot_angle and guide_angle must not "
                                                       "be parallel"))
        if parallel:
            raise InputError("slot_angle and guide_angle must not be parallel")
        self.slot_joint, self.guide_joint = slot_joint, guide_joint
        self.needs = (E,)
        self.places = (ref,)
        self.links = (block, yoke)
        self.joints = (Revolute(E, E, OWNER, block),
                       Prismatic(slot_joint, E, block, yoke, left_normal(self.t1)),
                       Prismatic(guide_joint, ref, FRAME, yoke, left_normal(self.t2)))
        self.owners = {ref: yoke}
        self.key = E

    @classmethod
    def from_spec(cls, spec, value):
        return cls(spec["block"], spec["yoke"], spec["pin"], spec["ref"], value("slot_angle"),
                   value("guide_point"), value("guide_angle"), spec["slot"], spec["guide"])

    @classmethod
    def pairs(cls, spec: dict, placed=None) -> tuple[str, ...]:
        """The pin, the slot and the guide: ``ref`` is a point of the yoke, no joint.

        Examples
        --------
        >>> RPP.pairs({"pin": "B", "ref": "S3", "slot": "slot", "guide": "guide"})
        ('B', 'slot', 'guide')
        """
        return names_in(spec, ("pin", "slot", "guide"))

    def _along(self, x, y):
        return (x * self.t1[1] - y * self.t1[0]) / self.cross

    def position(self, st: KinematicState) -> None:
        ex, ey = st.p[self.E]
        s = self._along(ex - self.q[0], ey - self.q[1])
        st.p[self.ref] = (self.q[0] + s * self.t2[0], self.q[1] + s * self.t2[1])
        st.u[self.block], st.u[self.yoke] = self.t1, self.t2

    def first(self, st: KinematicState) -> None:
        s = self._along(*st.d1[self.E])
        st.d1[self.ref] = (s * self.t2[0], s * self.t2[1])
        st.w1[self.block] = st.w1[self.yoke] = 0.0

    def second(self, st: KinematicState) -> None:
        s = self._along(*st.d2[self.E])
        st.d2[self.ref] = (s * self.t2[0], s * self.t2[1])
        st.w2[self.block] = st.w2[self.yoke] = 0.0

    def statics(self, mech, st, W, R):
        fix, fiy, mi = moment_about(mech, st, W, self.block, self.E)
        fjx, fjy, mj = moment_about(mech, st, W, self.yoke, self.ref)
        (ex, ey), (rx, ry) = st.p[self.E], st.p[self.ref]
        n1x, n1y = -self.t1[1], self.t1[0]
        n2x, n2y = -self.t2[1], self.t2[0]
        d = n1x * n2y - n1y * n2x
        N1 = -(fjx * n2y - fjy * n2x) / d
        N2 = (fjx * n1y - fjy * n1x) / d
        M2 = -mi - N1 * ((ex - rx) * n1y - (ey - ry) * n1x) - mj
        r1x, r1y = N1 * n1x - fix, N1 * n1y - fiy
        R[self.E] = (r1x, r1y)
        R[self.slot_joint] = (N1, mi)
        R[self.guide_joint] = (N2, M2)
        push(mech, st, W, mech.owner[self.E], self.E, -r1x, -r1y)

    def transmission(self, st, scale):
        """Angle between slot and guide, in [0, pi/2] (constant: the design's)."""
        (a, b), (c, d) = self.t1, self.t2
        return angle_and_kappa(SCALAR, abs(a * d - b * c), abs(a * c + b * d),
                               f"the slot and the guide of the dyad at {self.E} are parallel")
