"""Closed-form kinematics of a crank and the Assur groups it drives.

A linkage is a driver (the crank) followed by Assur groups, each placing new joints
from joints already placed. Every group works at three orders:

* ``position``: joint positions and link directions (unit vectors), with an explicit
  assembly ``branch``; a state that cannot be assembled is an error (scalars) or NaN
  with ``invalid = True`` (arrays), never clamped;
* ``first``: first-order coefficients ``dX/dtheta`` of every joint and ``dphi/dtheta``
  of every link (velocities at unit crank speed);
* ``second``: second-order coefficients ``d2X/dtheta2`` and ``d2phi/dtheta2``.

Velocity and acceleration follow as ``v = X'*omega`` and ``a = X''*omega**2 + X'*alpha``,
so a static scene needs none of the derivative work, and the equations of motion are
linear in ``omega**2``, ``alpha`` and the loads. Every formula is written once and runs
on floats (with :data:`~linkage_fmu.numerics.SCALAR`) or arrays (with
:data:`~linkage_fmu.numerics.ARRAY`).
"""

from __future__ import annotations

import math
from typing import Callable, NamedTuple

import numpy as np

from .numerics import SCALAR, Number

Vec = tuple  # (x, y) of floats or arrays


class KinematicState:
    """Positions and derivative coefficients of every joint and link at one or many states.

    Attributes
    ----------
    theta : float or ndarray
        Crank angle(s).
    xp : namespace
        :data:`SCALAR` or :data:`ARRAY`.
    p, d1, d2 : dict
        Point name -> ``(x, y)``, ``(x', y')``, ``(x'', y'')``.
    u, w1, w2 : dict
        Link name -> unit direction ``(cos phi, sin phi)``, ``phi'``, ``phi''``.
    invalid : ndarray of bool or None
        For arrays, the states that could not be assembled.
    on_invalid : callable
        ``on_invalid(condition)`` raises for a scalar state (set by the mechanism).
    """

    __slots__ = ("theta", "xp", "p", "d1", "d2", "u", "w1", "w2", "invalid", "on_invalid")

    def __init__(self, theta: Number, xp, on_invalid: Callable[[str], None] | None = None):
        self.theta = theta
        self.xp = xp
        self.p: dict = {}
        self.d1: dict = {}
        self.d2: dict = {}
        self.u: dict = {}
        self.w1: dict = {}
        self.w2: dict = {}
        self.invalid = None
        self.on_invalid = on_invalid or _raise_value_error

    def velocity(self, point: str, omega: Number) -> Vec:
        """Velocity of ``point`` at crank speed ``omega``."""
        x1, y1 = self.d1[point]
        return x1 * omega, y1 * omega

    def acceleration(self, point: str, omega: Number, alpha: Number) -> Vec:
        """Acceleration of ``point`` at crank speed ``omega`` and acceleration ``alpha``."""
        x1, y1 = self.d1[point]
        x2, y2 = self.d2[point]
        w2 = omega * omega
        return x2 * w2 + x1 * alpha, y2 * w2 + y1 * alpha

    def root(self, value: Number, condition: Callable[[], str]) -> Number:
        """``sqrt(value)``; a negative value is an assembly failure (raise, or NaN + mask)."""
        if self.xp.scalar:
            if value < 0.0:
                self.on_invalid(condition())
            return self.xp.sqrt(value)
        bad = value < 0.0
        if bad.any():
            self.invalid = bad if self.invalid is None else (self.invalid | bad)
            value = np.where(bad, np.nan, value)
        return np.sqrt(value)


#: Placeholder body names in joint declarations, resolved by the mechanism.
FRAME = "<frame>"
OWNER = "<owner of the point>"


class Joint(NamedTuple):
    """A kinematic pair between bodies ``a`` and ``b``; its reaction is the action of
    ``a`` on ``b``. A revolute pair (``normal is None``) transmits a force ``(Fx, Fy)``
    at ``point``; a prismatic pair transmits a force ``N`` along ``normal`` through
    ``point`` and a couple ``M``.
    """

    name: str
    point: str
    a: str
    b: str
    normal: tuple | None = None


def _normal(t: Vec) -> Vec:
    """Left normal of the unit vector ``t``."""
    return -t[1], t[0]


def _raise_value_error(condition: str) -> None:
    raise ValueError(condition)


def _fmt(x: Number) -> str:
    x = np.asarray(x)
    return f"{float(x):.6g}" if x.ndim == 0 else f"{float(x.flat[0]):.6g}"


def _unit_vector(angle: float) -> Vec:
    return math.cos(angle), math.sin(angle)


class Crank:
    """The driver: link ``link`` turns about the frame point ``pivot``; its tip is ``tip``.

    The link direction is the crank angle itself, so ``phi' = 1`` and ``phi'' = 0``.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> st = KinematicState(math.pi / 2, SCALAR)
    >>> st.p["A"] = (0.0, 0.0); st.d1["A"] = st.d2["A"] = (0.0, 0.0)
    >>> c = Crank("1", "A", "B", 0.1)
    >>> c.position(st); c.first(st)
    >>> [round(v, 12) for v in st.p["B"] + st.d1["B"]]
    [0.0, 0.1, -0.1, 0.0]
    """

    def __init__(self, link: str, pivot: str, tip: str, length: float):
        self.link, self.pivot, self.tip, self.length = link, pivot, tip, float(length)
        self.needs = (pivot,)
        self.places = (tip,)
        self.links = (link,)
        self.joints = (Joint(pivot, pivot, FRAME, link),)
        self.owners = {tip: link}

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

    def transmission(self, st: KinematicState):
        """A crank has no transmission angle."""
        return None


class RRR:
    """Dyad of two links joined at ``C``: ``link1`` = E1-C and ``link2`` = C-E2.

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

    def __init__(self, link1: str, link2: str, E1: str, C: str, E2: str,
                 L1: float, L2: float, branch: int):
        self.link1, self.link2 = link1, link2
        self.E1, self.C, self.E2 = E1, C, E2
        self.L1, self.L2, self.branch = float(L1), float(L2), int(branch)
        self.needs = (E1, E2)
        self.places = (C,)
        self.links = (link1, link2)
        self.joints = (Joint(E1, E1, OWNER, link1), Joint(C, C, link1, link2),
                       Joint(E2, E2, OWNER, link2))
        self.owners = {}  # C belongs to both links
        self.key = C

    def _condition(self, d2: Number) -> str:
        d = math.sqrt(float(np.asarray(d2).flat[0]))
        name = f"{self.E1}{self.E2}"
        reach, gap = self.L1 + self.L2, abs(self.L1 - self.L2)
        head = f"the dyad {self.E1}-{self.C}-{self.E2} cannot close: |{name}| = {_fmt(d)} m"
        if d > 0.5 * (reach + gap):
            return (f"{head} > {self.E1}{self.C} + {self.C}{self.E2} = {_fmt(reach)} m "
                    f"(by {_fmt(d - reach)} m)")
        return (f"{head} < |{self.E1}{self.C} - {self.C}{self.E2}| = {_fmt(gap)} m "
                f"(by {_fmt(gap - d)} m)")

    def position(self, st: KinematicState) -> None:
        (x1, y1), (x2, y2) = st.p[self.E1], st.p[self.E2]
        L1, L2 = self.L1, self.L2
        dx, dy = x2 - x1, y2 - y1
        d2 = dx * dx + dy * dy
        # (2*d*h)^2 as a product of two factors: no cancellation near a toggle
        hd2 = ((L1 + L2) ** 2 - d2) * (d2 - (L1 - L2) ** 2)
        hd = st.root(hd2, lambda: self._condition(d2))
        f = (L1 * L1 - L2 * L2 + d2) / (2.0 * d2)
        g = self.branch * hd / (2.0 * d2)
        cx, cy = x1 + f * dx - g * dy, y1 + f * dy + g * dx
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

    def transmission(self, st: KinematicState):
        """Angle between the two links at ``C``, in [0, pi]; 0 and pi are toggles.

        Returns ``(mu, kappa)`` with ``kappa`` the 2-norm condition number of the
        dyad's normalised 2x2 core system, ``(1 + |cos mu|) / |sin mu|``.
        """
        (c1, s1), (c2, s2) = st.u[self.link1], st.u[self.link2]
        sin_mu, cos_mu = c1 * s2 - s1 * c2, c1 * c2 + s1 * s2
        return _angle_and_kappa(st.xp, sin_mu, cos_mu)


def _angle_and_kappa(xp, sin_mu, cos_mu):
    a = xp.abs(sin_mu)
    mu = xp.atan2(a, cos_mu)
    if xp.scalar:
        kappa = (1.0 + abs(cos_mu)) / a if a > 0.0 else math.inf
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            kappa = (1.0 + np.abs(cos_mu)) / a
    return mu, kappa


class RRP:
    """Dyad rod ``link`` (E-B) + ``slider`` at ``B`` on a straight frame guide.

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

    def __init__(self, link: str, slider: str, E: str, B: str, L: float,
                 guide_point: tuple, gamma: float, branch: int, guide_joint: str):
        self.link, self.slider, self.E, self.B = link, slider, E, B
        self.L, self.branch = float(L), int(branch)
        self.q = (float(guide_point[0]), float(guide_point[1]))
        self.t = _unit_vector(gamma)
        self.guide_joint = guide_joint
        self.needs = (E,)
        self.places = (B,)
        self.links = (link, slider)
        self.joints = (Joint(E, E, OWNER, link), Joint(B, B, link, slider),
                       Joint(guide_joint, B, FRAME, slider, _normal(self.t)))
        self.owners = {}  # B belongs to rod and slider
        self.key = B

    def position(self, st: KinematicState) -> None:
        ex, ey = st.p[self.E]
        tx, ty = self.t
        dx, dy = self.q[0] - ex, self.q[1] - ey
        dt = dx * tx + dy * ty
        dn = dy * tx - dx * ty  # distance of E from the guide, signed
        L = self.L
        root = st.root((L - dn) * (L + dn), lambda: (
            f"{self.E} is {_fmt(abs(np.asarray(dn).flat[0]))} m from the guide of {self.B}, "
            f"more than {self.E}{self.B} = {_fmt(L)} m"))
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

    def transmission(self, st: KinematicState):
        """Angle between the rod and the guide's normal, in [0, pi/2]; 0 is singular."""
        c, s = st.u[self.link]
        tx, ty = self.t
        ut = c * tx + s * ty
        un = s * tx - c * ty
        xp = st.xp
        return _angle_and_kappa(xp, xp.abs(ut), xp.abs(un))


class RPP:
    """Dyad block ``block`` (pin at ``E``) + ``yoke``: the block slides in a straight slot
    of the yoke (direction ``slot_angle``), the yoke slides on a straight frame guide
    (through ``guide_point``, direction ``guide_angle``). The yoke's reference point
    ``ref`` is where the slot's centre line crosses the guide line.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> st = KinematicState(0.0, SCALAR)
    >>> st.p["B"] = (0.05, 0.0866)
    >>> RPP("2", "3", "B", "S3", 0.0, (0.0, 0.0), math.pi / 2, "slot", "guide").position(st)
    >>> [round(v, 12) for v in st.p["S3"]]
    [0.0, 0.0866]
    """

    def __init__(self, block: str, yoke: str, E: str, ref: str, slot_angle: float,
                 guide_point: tuple, guide_angle: float, slot_joint: str, guide_joint: str):
        self.block, self.yoke, self.E, self.ref = block, yoke, E, ref
        self.t1 = _unit_vector(slot_angle)
        self.t2 = _unit_vector(guide_angle)
        self.q = (float(guide_point[0]), float(guide_point[1]))
        self.cross = self.t2[0] * self.t1[1] - self.t2[1] * self.t1[0]
        if abs(self.cross) < 1e-12:
            raise ValueError("slot_angle and guide_angle must not be parallel")
        self.slot_joint, self.guide_joint = slot_joint, guide_joint
        self.needs = (E,)
        self.places = (ref,)
        self.links = (block, yoke)
        self.joints = (Joint(E, E, OWNER, block),
                       Joint(slot_joint, E, block, yoke, _normal(self.t1)),
                       Joint(guide_joint, ref, FRAME, yoke, _normal(self.t2)))
        self.owners = {ref: yoke}
        self.key = E

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

    def transmission(self, st: KinematicState):
        """Angle between slot and guide, in [0, pi/2] (constant: the design's)."""
        (a, b), (c, d) = self.t1, self.t2
        return _angle_and_kappa(SCALAR, abs(a * d - b * c), abs(a * c + b * d))


class LinkPoint:
    """A point ``name`` fixed on ``link`` at ``dist`` from the link's joint ``ref``, in
    the direction (link angle - ``beta``): a centre of mass, or a joint such as K.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> st = KinematicState(0.0, SCALAR)
    >>> st.p["B"], st.u["2"] = (1.0, 0.0), (0.0, 1.0)
    >>> LinkPoint("2", "B", "S2", 0.5, 0.0).position(st)
    >>> st.p["S2"]
    (1.0, 0.5)
    """

    def __init__(self, link: str, ref: str, name: str, dist: float, beta: float = 0.0):
        self.link, self.ref, self.name = link, ref, name
        self.dist = float(dist)
        self.cb, self.sb = math.cos(beta), math.sin(beta)
        self.needs = (ref,)
        self.places = (name,)
        self.links = ()
        self.joints = ()
        self.owners = {name: link}

    def _arm(self, st: KinematicState):
        c, s = st.u[self.link]
        d = self.dist
        return d * (c * self.cb + s * self.sb), d * (s * self.cb - c * self.sb)

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

    def transmission(self, st: KinematicState):
        return None
