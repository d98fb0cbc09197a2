"""Known loads on every moving body: d'Alembert inertia, weight and the named loads.

A named load is an input (its magnitude given at each state, an FMU input), or a load
over the cycle, computed at each state: an expression of the crank angle ``theta``, the
parameters and the positions ``x_P``, ``y_P`` of the linkage's points, or a periodic
table of the crank angle (:class:`~linkage_fmu.tables.PeriodicTable`) times a factor.

Each body's loads are reduced to a wrench ``[Fx, Fy, M]`` at its centre of mass. Terms a
scene does not have are not computed: no inertia in a static scene or for a massless
body, no weight when ``g = 0``, no moment of a force acting at the centre of mass.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from . import numerics
from .errors import LoadError
from .expressions import Expression
from .groups import KinematicState
from .numerics import Number
from .tables import PeriodicTable


@dataclass(frozen=True)
class Load:
    """A named load of a linkage: a force on ``body`` at its point ``at`` along the
    unit vector ``direction`` (fixed in the frame, or in the body when ``fixed_in =
    'link'``: then ``direction`` is in the body's own frame, x along its direction), or
    a moment on ``body`` (``kind = 'moment'``, counter-clockwise positive).

    Its magnitude is an input with the ``start`` value, or, over the cycle, ``value``
    (an expression of ``theta``, the ``parameters`` it names and ``x_P``/``y_P``) or
    ``table`` times ``scale``: then it is computed at each state (:meth:`at_state`).

    Examples
    --------
    >>> Load("F_P", "2", "force", at="P", direction=(0.0, -2.0)).direction
    (0.0, -1.0)
    >>> Load("F", "2", "force", at="P", direction=(0.0, 0.0))
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.LoadError: load F: direction (0.0, 0.0) has no length
    """

    name: str
    body: str
    kind: str
    at: str = ""
    direction: tuple = (0.0, 0.0)
    fixed_in: str = "frame"
    unit: str = ""
    description: str = ""
    start: float = 0.0
    value: Expression | None = None
    table: PeriodicTable | None = None
    scale: float = 1.0
    parameters: dict = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self):
        if self.kind not in ("force", "moment"):
            raise LoadError(self.name, f"kind must be 'force' or 'moment', got {self.kind!r}")
        if self.kind == "force":
            x, y = (numerics.real(v) for v in self.direction)
            norm = numerics.hypot(x, y)
            if not norm > 0.0 or not (hasattr(norm, "traced") or math.isfinite(norm)):
                raise LoadError(self.name, f"direction {self.direction!r} has no length")
            if norm != 1.0:
                object.__setattr__(self, "direction", (x / norm, y / norm))
            if self.fixed_in not in ("frame", "link"):
                raise LoadError(self.name, "fixed_in must be 'frame' or 'link'")
        if not self.unit:
            object.__setattr__(self, "unit", "N" if self.kind == "force" else "N.m")
        if self.value is not None and self.table is not None:
            raise LoadError(self.name, "give a value or a table, not both")

    @property
    def computed(self) -> bool:
        """Whether the load is computed at each state (given over the cycle), not an
        input."""
        return self.value is not None or self.table is not None

    @property
    def positions(self) -> tuple:
        """The points whose positions its value uses (``x_P``, ``y_P``)."""
        if self.value is None:
            return ()
        return tuple(sorted({n[2:] for n in self.value.names if n[:2] in ("x_", "y_")
                             and n not in self.parameters}))

    def vector(self, st: KinematicState, value) -> tuple:
        """The force ``(Fx, Fy)`` in the frame of a force load of magnitude ``value``
        (a component along which it has no direction in the frame is 0.0)."""
        ux, uy = self.direction
        if self.fixed_in == "link":
            c, s = st.u[self.body]
            ux, uy = c * ux - s * uy, s * ux + c * uy
            return ux * value, uy * value
        return (ux * value if ux else 0.0), (uy * value if uy else 0.0)

    def at_state(self, st: KinematicState):
        """The load's magnitude at the state ``st`` (floats, arrays, traced or mpmath
        numbers, as ``st`` holds them)."""
        return self.magnitude(st.theta, st.xp, st.p)

    def magnitude(self, theta, xp, p: dict | None = None):
        """The load's magnitude at the crank angle ``theta`` (numbers of the namespace
        ``xp``), with ``p`` the positions of the points it uses (:attr:`positions`)."""
        if self.table is not None:
            return self.table(theta) * self.scale
        names = dict(self.parameters, theta=theta)
        for point in self.positions:
            names["x_" + point], names["y_" + point] = p[point]
        return self.value(names, numerics.functions(xp))


def wrenches(mech, st: KinematicState, omega: Number, alpha: Number, loads: Sequence[Number],
             static: bool) -> dict:
    """Wrench of all known loads on each moving body of ``mech``, about its centre of mass.

    Parameters
    ----------
    mech : Mechanism
        The linkage (bodies with mass, inertia, centre of mass; its loads; g).
    st : KinematicState
        Positions, and for a dynamic scene the first and second derivative coefficients.
    omega, alpha : float or ndarray
        Crank speed and acceleration.
    loads : sequence of float or ndarray or None
        The magnitude of each of ``mech.loads``, in that order; None for a load over the
        cycle that is computed here.
    static : bool
        True when ``omega = alpha = 0`` everywhere: inertia terms are skipped.

    Returns
    -------
    dict
        Body name -> ``[Fx, Fy, M]`` (floats or arrays; a body with no load gets zeros).

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("scotch_yoke")
    >>> st = mech.kinematics(0.0, order=0)
    >>> wrenches(mech, st, 0.0, 0.0, (400.0,), static=True)["3"]
    [0.0, -400.0, 0.0]
    """
    g = mech.g
    out = {}
    if not static:
        w2 = omega * omega
    for body in mech.bodies:
        fx = fy = m = 0.0
        if body.mass:
            if not static:
                (x1, y1), (x2, y2) = st.d1[body.cg], st.d2[body.cg]
                fx = -body.mass * (x2 * w2 + x1 * alpha)
                fy = -body.mass * (y2 * w2 + y1 * alpha)
            if g:
                fy = fy - body.mass * g
        if body.inertia and not static:
            m = -body.inertia * (st.w2[body.name] * w2 + st.w1[body.name] * alpha)
        out[body.name] = [fx, fy, m]
    for load, value in zip(mech.loads, loads):
        if value is None:
            value = load.at_state(st)
        w = out[load.body]
        if load.kind == "moment":
            w[2] = w[2] + value
            continue
        fx, fy = load.vector(st, value)
        turning = load.fixed_in == "link"
        if turning or load.direction[0]:
            w[0] = w[0] + fx
        if turning or load.direction[1]:
            w[1] = w[1] + fy
        cg = mech.cg[load.body]
        if load.at != cg:
            (px, py), (sx, sy) = st.p[load.at], st.p[cg]
            w[2] = w[2] + (px - sx) * fy - (py - sy) * fx
    return out


def powers(mech, st: KinematicState, omega: Number, alpha: Number, loads: Sequence[Number],
           static: bool) -> list:
    """The power of each known load per unit of crank speed (a power is this times
    ``omega``): the d'Alembert inertia's (``-dT/dt``, the kinetic energy the links give
    up, 0 in a static scene), gravity's, then each of ``mech.loads``' (``loads`` as for
    :func:`wrenches`). Needs first-order kinematics (second-order for the inertia).

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("scotch_yoke")
    >>> st = mech.kinematics(0.5, order=2)
    >>> inertia, gravity, load = powers(mech, st, 10.0, 0.0, (400.0,), static=False)
    >>> y1 = st.d1["S3"][1]  # the yoke's load acts along -y at its centre of mass
    >>> bool(abs(load - (-400.0) * y1) < 1e-12)
    True
    """
    inertia = gravity = 0.0
    if not static:
        w2 = omega * omega
    for body in mech.bodies:
        (x1, y1) = st.d1[body.cg]
        if body.mass and not static:
            (x2, y2) = st.d2[body.cg]
            inertia = inertia - body.mass * ((x2 * w2 + x1 * alpha) * x1
                                             + (y2 * w2 + y1 * alpha) * y1)
        if body.mass and mech.g:
            gravity = gravity - body.mass * mech.g * y1
        if body.inertia and not static:
            w1 = st.w1[body.name]
            inertia = inertia - body.inertia * (st.w2[body.name] * w2 + w1 * alpha) * w1
    out = [inertia, gravity]
    for load, value in zip(mech.loads, loads):
        if value is None:
            value = load.at_state(st)
        if load.kind == "moment":
            out.append(value * st.w1[load.body])
            continue
        # the velocity of the body's material point at ``at``, as wrenches() reduces
        # the force to the centre of mass
        fx, fy = load.vector(st, value)
        cg, w1 = mech.cg[load.body], st.w1[load.body]
        (vx, vy), (px, py), (sx, sy) = st.d1[cg], st.p[load.at], st.p[cg]
        out.append(fx * (vx - w1 * (py - sy)) + fy * (vy + w1 * (px - sx)))
    return out
