"""An independent reference for the assembly mode a class III group follows: the
pseudo-arclength continuation of the whole six-bar (crank angle and plate points
together) from its drawn pose, written here with numpy alone, from the drawn pose and
the links' rigid distances, not from the library's groups.

The linkage is the triad six-bar: a crank A -> B (A at the origin), and a ternary
plate E, F, G held by three rods: B-E, C-F and D-G, with C and D frame pivots. Its
configurations with the crank at theta form curves in (theta, E, F, G); the drawn
pose is a point of one of them. :class:`Branch` follows that curve from the drawn
pose both ways in small arclength steps, each a tangent predictor and a Newton
corrector on the distances plus the arclength condition, until the crank angle has
moved half a turn or turns back (a limit position, located where the curve's
tangent is square to the crank angle's axis). A state at crank angle ``theta`` is
reached from the drawn pose the shorter way round when the curve gets there that way
before it turns back; the position there is Newton's at that angle from the curve.

Examples
--------
>>> import math
>>> d = Design(0.05, 0.5, (0.55, 0.05), (0.15, 0.5),
...            {"E": (0.25, 0.2), "F": (0.45, 0.25), "G": (0.35, 0.38)})
>>> b = Branch(d)
>>> b.limits        # the six-bar of tests/test_closure.py turns fully both ways
(None, None)
>>> x = b.at(0.9)     # E at 0.9 rad, as tests/test_closure.py's own continuation has it
>>> [round(float(v), 9) for v in x[:2]]
[0.247251084, 0.202696781]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: the rigid distances, by point: every pair of joints of one link
PAIRS = (("B", "E"), ("C", "F"), ("D", "G"), ("E", "F"), ("E", "G"), ("F", "G"))
#: the points the group places, in the order of the unknowns
PLACED = ("E", "F", "G")


@dataclass
class Design:
    """The triad six-bar drawn at the crank angle ``theta0``: crank length ``r``, frame
    pivots ``C`` and ``D``, the plate's points ``pose`` (E, F, G)."""

    r: float
    theta0: float
    C: tuple
    D: tuple
    pose: dict

    def B(self, theta: float) -> np.ndarray:
        return self.r * np.array([math.cos(theta), math.sin(theta)])

    def points(self, theta: float, x: np.ndarray) -> dict:
        return {"B": self.B(theta), "C": np.asarray(self.C, float),
                "D": np.asarray(self.D, float), "E": x[0:2], "F": x[2:4], "G": x[4:6]}

    @property
    def drawn(self) -> np.ndarray:
        return np.array([v for p in PLACED for v in self.pose[p]], float)

    @property
    def lengths(self) -> dict:
        p = self.points(self.theta0, self.drawn)
        return {(i, j): float(np.linalg.norm(p[i] - p[j])) for i, j in PAIRS}


class Branch:
    """The drawn pose's curve of configurations of ``design``, followed both ways from
    the drawn angle in arclength steps of at most ``ds`` (metres; the crank angle
    counts ``design.r`` metres per radian).

    Attributes
    ----------
    limits : tuple
        The crank angle at which the curve turns back, going forwards (increasing
        theta) and backwards, or None where it does not within half a turn.
    """

    def __init__(self, design: Design, ds: float = 5e-3):
        self.d = design
        self.L2 = np.array([design.lengths[p] ** 2 for p in PAIRS])
        self.scale = design.r  # metres per radian of the crank angle, in the arclength
        self.ds = ds
        names = ("B", "C", "D", *PLACED)
        self._i = np.array([names.index(i) for i, _ in PAIRS])
        self._j = np.array([names.index(j) for _, j in PAIRS])
        #: +1 where a pair's first point is the point (column), -1 its second
        self._incidence = np.zeros((len(PAIRS), len(names)))
        self._incidence[np.arange(len(PAIRS)), self._i] += 1.0
        self._incidence[np.arange(len(PAIRS)), self._j] -= 1.0
        self._frame = np.array([design.C, design.D], float)
        y0 = np.array([design.theta0 * self.scale, *design.drawn])
        self.paths, limits = [], []
        #: the configuration at each limit (of the way the crank angle moved to it)
        self.turns: dict = {}
        for way in (1.0, -1.0):
            path, limit = self._follow(y0, way)
            self.paths.append(path)
            limits.append(limit)
        self.limits = tuple(limits)

    # the distances, their Jacobian in (theta * scale, E, F, G) -----------------------
    def _points(self, y: np.ndarray) -> np.ndarray:
        theta = y[0] / self.scale
        B = self.d.r * np.array([[math.cos(theta), math.sin(theta)]])
        return np.vstack([B, self._frame, y[1:].reshape(3, 2)])

    def _f(self, y: np.ndarray) -> np.ndarray:
        P = self._points(y)
        diff = P[self._i] - P[self._j]
        return 0.5 * ((diff * diff).sum(axis=1) - self.L2)

    def _J(self, y: np.ndarray) -> np.ndarray:
        theta = y[0] / self.scale
        P = self._points(y)
        diff = P[self._i] - P[self._j]
        dB = self.d.r * np.array([-math.sin(theta), math.cos(theta)]) / self.scale
        J = np.empty((len(PAIRS), 7))
        J[:, 0] = self._incidence[:, 0] * (diff @ dB)
        J[:, 1::2] = self._incidence[:, 3:] * diff[:, :1]
        J[:, 2::2] = self._incidence[:, 3:] * diff[:, 1:]
        return J

    def _tangent(self, y: np.ndarray, previous: np.ndarray) -> np.ndarray:
        _, _, vt = np.linalg.svd(self._J(y))
        t = vt[-1]
        return t if t @ previous > 0 else -t

    def _correct(self, guess: np.ndarray, y: np.ndarray, t: np.ndarray, s: float):
        """Newton on the distances and ``t . (z - y) = s`` from ``guess``; None where it
        does not converge in 12 iterations (to 4e-15, or where its steps stop shrinking
        below 1e-13, at rounding: near a limit the system's condition is about 1e3)."""
        z, last = guess.copy(), math.inf
        for _ in range(12):
            A = np.vstack([self._J(z), t])
            r = np.append(self._f(z), t @ (z - y) - s)
            dz = np.linalg.solve(A, r)
            z -= dz
            step, size = np.abs(dz).max(), 1.0 + np.abs(z).max()
            if step <= 4e-15 * size or (step <= 1e-13 * size and step >= 0.5 * last):
                return z
            last = step
        return None

    def _follow(self, y0: np.ndarray, way: float):
        """The curve from ``y0`` with the crank angle moving ``way`` at the start, until
        it has moved half a turn or turns back: its steps, each ``(y, t, s)`` (a point,
        its tangent, the arclength to the next point, or to the limit for the last),
        and the limit's crank angle (None where it does not turn back)."""
        t = self._tangent(y0, np.array([way, 0, 0, 0, 0, 0, 0]))
        steps, y, ds = [], y0, self.ds
        theta0 = y0[0]
        while abs(y[0] - theta0) < math.pi * self.scale:
            z = self._correct(y + ds * t, y, t, ds)
            if z is None:
                ds *= 0.5
                if ds < 1e-14:
                    raise RuntimeError("the reference continuation stalls")
                continue
            tz = self._tangent(z, t)
            if tz @ t < math.cos(math.radians(3.0)):  # a bend: shorter steps there
                ds *= 0.5
                continue
            if tz[0] * way <= 0.0:  # the crank angle turns back within this step
                s, limit, self.turns[way] = self._limit(y, t, ds, way)
                steps.append((y, t, s))
                return steps, limit / self.scale
            steps.append((y, t, ds))
            y, t = z, tz
            ds = min(self.ds, 1.5 * ds)
        steps.append((y, t, 0.0))
        return steps, None

    def _limit(self, y: np.ndarray, t: np.ndarray, ds: float, way: float):
        """Where between ``y`` and one step ``ds`` on the crank angle is extreme (the
        tangent's crank-angle part 0), by bisection on the step: the step and the angle
        (times ``scale``)."""
        lo, hi, best = 0.0, ds, (0.0, y[0], y)
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            z = self._correct(y + mid * t, y, t, mid)
            if z is None:
                hi = mid
                continue
            if (z[0] - best[1]) * way > 0:
                best = (mid, z[0], z)
            if self._tangent(z, t)[0] * way > 0.0:
                lo = mid
            else:
                hi = mid
            if hi - lo <= 1e-15 * ds:
                break
        return best

    # states --------------------------------------------------------------------------
    def delta(self, theta: float) -> float:
        """The crank's turn from the drawn angle to ``theta`` the shorter way round."""
        return math.atan2(math.sin(theta - self.d.theta0), math.cos(theta - self.d.theta0))

    def margin(self, theta: float) -> float:
        """How far short of the limit the shorter way to ``theta`` ends, rad: negative
        for a state past it (not reached), inf where the curve does not turn back."""
        delta = self.delta(theta)
        limit = self.limits[0 if delta >= 0 else 1]
        if limit is None:
            return math.inf
        return abs(limit - self.d.theta0) - abs(delta)

    def at(self, theta: float) -> np.ndarray:
        """E, F, G at ``theta`` on the curve, reached the shorter way round (check
        :meth:`margin` first): on the step of the curve that passes the angle, by
        regula falsi on its arclength, then Newton at the angle itself."""
        delta = self.delta(theta)
        way = 1.0 if delta >= 0 else -1.0
        steps = self.paths[0 if delta >= 0 else 1]
        target = (self.d.theta0 + delta) * self.scale
        limit = self.limits[0 if delta >= 0 else 1]
        # near enough for Newton at the angle: far inside the distance to the other mode
        # at the angle, which shrinks with the square root of the distance to the limit
        near = min(1e-9, 1e-3 * abs(self.margin(theta))) * self.scale
        for k, (y, t, s) in enumerate(steps):
            if s == 0.0:
                continue
            end = steps[k + 1][0][0] if k + 1 < len(steps) else limit * self.scale
            if (end - target) * way < 0:
                continue
            # the crank angle grows along the step: Illinois' regula falsi on its length
            lo, hi, z = 0.0, s, y
            g_lo, g_hi = (y[0] - target) * way, (end - target) * way
            for _ in range(200):
                mid = 0.5 * (lo + hi) if g_hi is None or g_hi <= g_lo else \
                    lo + (hi - lo) * g_lo / (g_lo - g_hi)
                trial = self._correct(y + mid * t, y, t, mid)
                if trial is None:
                    hi, g_hi = mid, None
                    continue
                z = trial
                g = (z[0] - target) * way
                if abs(g) <= near or hi - lo <= 1e-16 * s:
                    break
                if g < 0:
                    lo, g_lo = mid, g
                    if g_hi is not None:
                        g_hi *= 0.5
                else:
                    hi, g_hi = mid, g
                    g_lo *= 0.5
            x = z[1:].copy()
            break
        else:
            x = steps[-1][0][1:].copy()
        for _ in range(50):
            y = np.array([target, *x])
            dx = np.linalg.solve(self._J(y)[:, 1:], self._f(y))
            x -= dx
            if np.abs(dx).max() <= 1e-16:
                break
        return x

    def beyond(self, way: float, eps: float) -> np.ndarray:
        """E, F, G on the other side of the limit that the crank angle reaches moving
        ``way``, ``eps`` rad back from it: where the curve goes on after it turns back
        (Newton at that angle from the reflection, through the limit's configuration,
        of the point on this side)."""
        limit = self.limits[0 if way > 0 else 1]
        theta = limit - way * eps
        here, turn = self.at(theta), self.turns[way][1:]
        x = 2.0 * turn - here
        for _ in range(50):
            y = np.array([theta * self.scale, *x])
            dx = np.linalg.solve(self._J(y)[:, 1:], self._f(y))
            x -= dx
            if np.abs(dx).max() <= 1e-16:
                break
        return x

    def rates(self, theta: float, x: np.ndarray) -> np.ndarray:
        """``dE/dtheta``, ``dF/dtheta``, ``dG/dtheta`` at the configuration ``x`` at
        ``theta``: from the distances' Jacobian, ``J_x x' = -J_theta``."""
        J = self._J(np.array([theta * self.scale, *x]))
        return -np.linalg.solve(J[:, 1:], J[:, 0] * self.scale)

