"""An independent reference for linkages driven by several actuators: the constrained
Newton-Euler equations of the links as rigid bodies, with Lagrange multipliers.

It shares nothing with the library (nor with :mod:`newton_euler`): it reads a
joints-and-links description with :mod:`tomllib` and evaluates its coordinates itself,
then solves the linkage as a multibody code does (Nikravesh, *Computer-Aided Analysis of
Mechanical Systems*, ch. 6 and 13; Haug, *Computer Aided Kinematics and Dynamics*, ch. 6).

Coordinates. Each moving link ``i`` is its drawn self displaced by ``(dx_i, dy_i)`` (of
its centre of mass) and turned by ``phi_i``: its point ``P`` is at
``cg_i + d_i + R(phi_i) (P0 - cg_i)``.

Constraints ``Phi(q) = c``, one row per equation:

- a revolute joint on k moving links: the first link's copy of the joint is where each
  other's is (2 rows each); on the frame (one link lists it, or the frame's entry):
  each link's copy stays where drawn;
- a prismatic pair: on a frame guide, the link's point stays on the drawn line and the
  link does not turn; between a guide link ``a`` and a slider ``b``: ``phi_b = phi_a``,
  and ``n_a . (P_b - P_a) = 0`` with ``n_a`` the drawn normal turned with ``a``;
- a driver of a revolute pair: ``phi_b - phi_a = q - q_drawn`` (``phi_a`` = 0 on the
  frame), ``q`` the absolute or relative angle of the lines from the joint to each
  link's first other joint; of a prismatic pair (a cylinder): ``t_a . (P_b - P_a) = s``,
  the travel along the slide turned with the barrel.

Every row is built from the coordinates by the arithmetic of second-order jets (value,
gradient, and the second derivative along the velocity), so that the Jacobian
``Phi_q`` and the term ``(Phi_q qdot)_q qdot`` of the accelerations are exact. Positions
come from Newton with continuation from the drawn pose; ``Phi_q qdot = nu`` (the
drivers' speeds) and ``Phi_q qddot = nu' - (Phi_q qdot)_q qdot``.

Forces: ``M qddot + Phi_q^T lam = Q`` (``M`` = diag(m, m, J); ``Q`` the weights
``-m g`` in y and the loads), solved for the multipliers. A pin's row pair
``P_a - P_b`` puts ``-lam`` on ``a`` and ``+lam`` on ``b``: the force of ``a`` on ``b``
is ``lam`` (of the frame on a frame pin's link: ``-lam``). A driver's effort on its
second link is ``-lam``: the moment ``Mb`` of a revolute driver, the force ``Fb`` along
the slide of a cylinder.

Coulomb friction (``[friction.J]``: ``mu``, and a revolute pair's ``radius``): at a pin,
a moment ``mu r |lam|`` (its pin force's magnitude) against the relative rotation of
its two bodies; at a prismatic pair, a force ``mu |lam_n|`` (its normal force) along the
guide against the relative sliding, at the slider's point of the pair on both bodies;
none where the bodies do not move relative to each other. The friction enters ``Q``
and depends on the multipliers: they are iterated to a fixed point.
"""

from __future__ import annotations

import ast
import math
import operator
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: Newton's tolerance on the constraints (m, rad)
TOL = 1e-14
#: the continuation's largest step: of an angle (rad) and of a travel (m)
STEP_ANGLE, STEP_TRAVEL = math.radians(1.0), 0.005

_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
           ast.Div: operator.truediv, ast.Pow: operator.pow}
_CALLS = {"sqrt": math.sqrt, "cos": math.cos, "sin": math.sin, "tan": math.tan,
          "atan2": math.atan2, "hypot": math.hypot, "abs": abs}


class ReferenceError(ValueError):
    """The description cannot be read or solved by the reference."""


def evaluate(text, names: dict) -> float:
    """A number, or the arithmetic of an expression's text over ``names`` (a callable
    for a name that is resolved when used).

    >>> evaluate("2 * hypot(x, 4) - 1", {"x": 3.0})
    9.0
    """
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        return float(text)
    if not isinstance(text, str):
        raise ReferenceError(f"{text!r} is no number or expression")

    def walk(node):
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
            return float(node.value)
        if isinstance(node, ast.Name):
            if node.id not in names:
                raise ReferenceError(f"{text!r}: unknown name {node.id!r}")
            value = names[node.id]
            return value() if callable(value) else float(value)
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return _BINARY[type(node.op)](walk(node.left), walk(node.right))
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            return -walk(node.operand) if isinstance(node.op, ast.USub) else walk(node.operand)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and \
                node.func.id in _CALLS and not node.keywords:
            return float(_CALLS[node.func.id](*(walk(a) for a in node.args)))
        raise ReferenceError(f"{text!r}: {ast.dump(node)} is not arithmetic")

    return walk(ast.parse(text, mode="eval").body)


@dataclass(frozen=True)
class Link:
    name: str
    joints: tuple
    mass: float
    inertia: float
    cg: np.ndarray


@dataclass(frozen=True)
class Driver:
    """``kind`` "angle" or "travel" of the pair ``joint``, of link ``second`` (index)
    relative to ``first`` (None: the frame), from its drawn value ``drawn``."""

    kind: str
    joint: str
    first: int | None
    second: int
    drawn: float


class Model:
    """A joints-and-links linkage as rigid bodies; see the module's docstring."""

    def __init__(self, data: dict):
        params = {k: v["default"] for k, v in data.get("parameters", {}).items()
                  if isinstance(v, dict) and isinstance(v.get("default"), (int, float))}
        self.frame = str(data.get("linkage", {}).get("frame", "0"))
        self.g = float(data.get("linkage", {}).get("gravity", 9.81))
        raw = data["joints"]
        cache: dict = {}
        names = dict(params)

        def coordinate(joint, axis):
            def get():
                if (joint, axis) not in cache:
                    spec = raw[joint]
                    at = spec["at"] if isinstance(spec, dict) else spec
                    cache[joint, axis] = evaluate(at["xy".index(axis)], names)
                return cache[joint, axis]
            return get

        for j in raw:
            names[f"x_{j}"], names[f"y_{j}"] = coordinate(j, "x"), coordinate(j, "y")
        self.at = {j: np.array([names[f"x_{j}"](), names[f"y_{j}"]()]) for j in raw}
        self.slides = {}
        for j, spec in raw.items():
            if isinstance(spec, dict):
                s = np.array([evaluate(v, names) for v in spec["slide"]])
                self.slides[j] = (s / np.hypot(*s), spec.get("guide", ""))
        self.links, self.points, self.on_frame = [], {}, set()
        for spec in data["links"]:
            if spec["name"] == self.frame:
                self.on_frame |= set(spec["joints"])
                continue
            for p, xy in spec.get("points", {}).items():
                self.points[p] = np.array([evaluate(v, names) for v in xy])
            cg = spec.get("cg")
            cg = self.at[spec["joints"][0]] if cg is None else np.array(
                [evaluate(v, names) for v in cg])
            self.links.append(Link(spec["name"], tuple(spec["joints"]),
                                   evaluate(spec.get("mass", 0.0), names),
                                   evaluate(spec.get("inertia", 0.0), names), cg))
        self.index = {link.name: i for i, link in enumerate(self.links)}
        self.drivers = [self._driver(spec) for spec in data["drivers"]]
        self.loads = []
        for spec in data.get("loads", []):
            d = np.array([float(v) for v in spec.get("direction", [0.0, 0.0])])
            self.loads.append((spec["name"], self.index[spec["body"]], spec["kind"],
                               spec.get("at", ""), d / (np.hypot(*d) or 1.0)))
        self.n = 3 * len(self.links)
        self.friction = {}
        for j, spec in data.get("friction", {}).items():
            if "length" in spec:
                raise ReferenceError(f"[friction.{j}]: a slider's length is not modelled")
            self.friction[j] = (evaluate(spec["mu"], names),
                                evaluate(spec.get("radius", 0.0), names))

    def on(self, joint: str) -> list:
        return [i for i, link in enumerate(self.links) if joint in link.joints]

    def grounded(self, joint: str) -> bool:
        return joint in self.on_frame or len(self.on(joint)) == 1

    def drawn(self, name: str) -> np.ndarray:
        return self.at[name] if name in self.at else self.points[name]

    def _direction(self, i: int, joint: str) -> np.ndarray:
        other = next(j for j in self.links[i].joints if j != joint)
        return self.drawn(other) - self.drawn(joint)

    def _driver(self, spec: dict) -> Driver:
        j = spec["joint"]
        on = self.on(j)
        if j in self.slides:
            guide = self.index[self.slides[j][1]]
            return Driver("travel", j, guide, next(i for i in on if i != guide), 0.0)
        first, second = (None, on[0]) if self.grounded(j) else (on[0], on[1])
        if "links" in spec:
            a, b = spec["links"]
            first, second = (None if a == self.frame else self.index[a]), self.index[b]
        u = self._direction(second, j)
        angle = math.atan2(u[1], u[0])
        if first is not None:
            f = self._direction(first, j)
            angle = math.atan2(f[0] * u[1] - f[1] * u[0], f @ u)
        return Driver("angle", j, first, second, angle)

    # -- the constraints, as jets ----------------------------------------------------
    def rows(self, q: np.ndarray, qd: np.ndarray | None = None) -> list:
        """The constraints' jets at ``q`` (their second derivative along ``qd``), the
        drivers' rows last, in their order."""
        jet = _Jets(q, np.zeros_like(q) if qd is None else qd)
        out = []
        for j in self.at:
            on = self.on(j)
            if j in self.slides:
                t, guide = self.slides[j]
                n0 = np.array([-t[1], t[0]])
                if len(on) == 1:  # on a frame guide
                    p = jet.point(self, on[0], j)
                    out += [(p[0] - self.at[j][0]) * n0[0] + (p[1] - self.at[j][1]) * n0[1],
                            jet.phi(on[0])]
                else:
                    a = self.index[guide]
                    b = next(i for i in on if i != a)
                    out += [jet.phi(b) - jet.phi(a), jet.along(self, a, b, j, n0)]
            elif self.grounded(j):
                for i in on:
                    p = jet.point(self, i, j)
                    out += [p[0] - self.at[j][0], p[1] - self.at[j][1]]
            else:
                for i in on[1:]:
                    pa, pb = jet.point(self, on[0], j), jet.point(self, i, j)
                    out += [pa[0] - pb[0], pa[1] - pb[1]]
        for d in self.drivers:
            if d.kind == "travel":
                out.append(jet.along(self, d.first, d.second, d.joint, self.slides[d.joint][0]))
            else:
                out.append(jet.phi(d.second) - (0.0 if d.first is None else jet.phi(d.first)))
        if len(out) != self.n:
            raise ReferenceError(f"{len(out)} constraints for {self.n} coordinates")
        return out

    def _driven(self, values) -> np.ndarray:
        """``values`` in the drivers' rows, zeros elsewhere."""
        c = np.zeros(self.n)
        c[self.n - len(self.drivers):] = values
        return c

    def _targets(self, coords) -> np.ndarray:
        """The rows' values at the drivers' coordinates ``coords``."""
        return self._driven(np.subtract(coords, [d.drawn for d in self.drivers]))

    def positions(self, coords, q0=None, coords0=None) -> np.ndarray:
        """The coordinates at the drivers' ``coords``, continued from ``q0`` at
        ``coords0`` (default: the drawn pose)."""
        if q0 is None:
            q0, coords0 = np.zeros(self.n), [d.drawn for d in self.drivers]
        span = max(abs(b - a) / (STEP_TRAVEL if d.kind == "travel" else STEP_ANGLE)
                   for d, a, b in zip(self.drivers, coords0, coords))
        q = q0.copy()
        for t in np.linspace(0.0, 1.0, max(1, math.ceil(span)) + 1)[1:]:
            target = self._targets([a + t * (b - a) for a, b in zip(coords0, coords)])
            for _ in range(50):
                rows = self.rows(q)
                res = np.array([r.v for r in rows]) - target
                if np.max(np.abs(res)) < TOL:
                    break
                q = q - np.linalg.solve(np.array([r.g for r in rows]), res)
            else:
                raise ReferenceError(f"Newton did not converge at {coords}")
        return q

    def solve(self, coords, speeds, accels, loads: dict | None = None, q=None) -> dict:
        """Every pin's force, each driver's effort and the motion at one state."""
        q = self.positions(coords) if q is None else q
        jac = np.array([r.g for r in self.rows(q)])
        qd = np.linalg.solve(jac, self._driven(speeds))
        h = np.array([r.h for r in self.rows(q, qd)])
        qdd = np.linalg.solve(jac, self._driven(accels) - h)
        mass = np.concatenate([[link.mass, link.mass, link.inertia] for link in self.links])
        force = np.zeros(self.n)
        for i, link in enumerate(self.links):
            force[3 * i + 1] -= link.mass * self.g
        for name, i, kind, at, direction in self.loads:
            value = (loads or {}).get(name, 0.0)
            if kind == "moment":
                force[3 * i + 2] += value
                continue
            f, r = value * direction, _rot(q[3 * i + 2]) @ (self.drawn(at) - self.links[i].cg)
            force[3 * i:3 * i + 2] += f
            force[3 * i + 2] += r[0] * f[1] - r[1] * f[0]
        lam = np.linalg.solve(jac.T, force - mass * qdd)
        for _ in range(500 if self.friction else 0):  # to the friction's fixed point
            last = lam
            lam = np.linalg.solve(jac.T, force - mass * qdd + self._friction(q, qd, lam))
            if np.max(np.abs(lam - last)) <= 1e-15 * np.max(np.abs(lam)):
                break
        else:
            if self.friction:
                raise ReferenceError("the friction's fixed point was not reached")
        return {"q": q, "qd": qd, "qdd": qdd, "lam": lam,
                "pins": self._pins(lam),
                "efforts": [-v for v in lam[self.n - len(self.drivers):]],
                "hessian": self._hessian(jac, mass)}

    def _velocity(self, i: int, at: np.ndarray, q, qd) -> np.ndarray:
        """The velocity of the material point of link ``i`` now at ``at``."""
        r = at - (self.links[i].cg + q[3 * i:3 * i + 2])
        return qd[3 * i:3 * i + 2] + qd[3 * i + 2] * np.array([-r[1], r[0]])

    def _friction(self, q, qd, lam) -> np.ndarray:
        """The generalised forces of the friction at the multipliers ``lam``."""
        out = np.zeros(self.n)

        def put(i, f, at, couple=0.0):
            if i is None:
                return
            r = at - (self.links[i].cg + q[3 * i:3 * i + 2])
            out[3 * i:3 * i + 2] += f
            out[3 * i + 2] += r[0] * f[1] - r[1] * f[0] + couple

        def omega(i):
            return 0.0 if i is None else qd[3 * i + 2]

        k = 0
        for j in self.at:
            on = self.on(j)
            mu, radius = self.friction.get(j, (0.0, 0.0))
            if j in self.slides:
                if len(on) == 1:
                    a, b = None, on[0]
                else:
                    a = self.index[self.slides[j][1]]
                    b = next(i for i in on if i != a)
                t0 = self.slides[j][0]
                t = t0 if a is None else _rot(q[3 * a + 2]) @ t0
                at = self.point(self.links[b].name, j, q)
                slide = t @ (self._velocity(b, at, q, qd) -
                             (0.0 if a is None else self._velocity(a, at, q, qd)))
                f = -mu * abs(lam[k + (0 if a is None else 1)]) * np.sign(slide) * t
                put(b, f, at)
                put(a, -f, at)
                k += 2
                continue
            pairs = [(None, i) for i in on] if self.grounded(j) else [(on[0], i) for i in on[1:]]
            for a, b in pairs:
                m = -mu * radius * np.hypot(*lam[k:k + 2]) * np.sign(omega(b) - omega(a))
                put(b, np.zeros(2), np.zeros(2), m)
                put(a, np.zeros(2), np.zeros(2), -m)
                k += 2
        return out

    def _pins(self, lam) -> dict:
        """(by, on) -> the force of body ``by`` (a link's name, the frame's) on ``on``
        through a revolute joint, in the rows' order."""
        out, k = {}, 0
        for j in self.at:
            on = self.on(j)
            if j in self.slides:
                k += 2
            elif self.grounded(j):
                for i in on:
                    out[(self.frame, self.links[i].name, j)] = -lam[k:k + 2]
                    k += 2
            else:
                for i in on[1:]:
                    out[(self.links[on[0]].name, self.links[i].name, j)] = lam[k:k + 2]
                    k += 2
        return out

    def _hessian(self, jac, mass) -> np.ndarray:
        """The Hessian of the kinetic energy ``T(u)`` by the drivers' speeds ``u``. ``T``
        is a quadratic form, so ``H[k, l] = T(e_k + e_l) - T(e_k) - T(e_l)`` exactly
        (polarisation), each ``T`` of the links' velocities at those speeds."""
        m = len(self.drivers)

        def energy(u):
            qd = np.linalg.solve(jac, self._driven(u))
            return 0.5 * float(qd @ (mass * qd))

        unit = np.eye(m)
        return np.array([[energy(unit[k] + unit[j]) - energy(unit[k]) - energy(unit[j])
                          for j in range(m)] for k in range(m)])


    def point(self, link: str, name: str, q: np.ndarray) -> np.ndarray:
        """Where the point ``name`` of ``link`` is at the coordinates ``q``."""
        i = self.index[link]
        cg = self.links[i].cg
        return cg + q[3 * i:3 * i + 2] + _rot(q[3 * i + 2]) @ (self.drawn(name) - cg)

    def energy(self, coords, speeds) -> tuple:
        """``(T, V)``: the kinetic energy at the drivers' coordinates and speeds, and the
        weights' potential energy (``m g y`` of each centre of mass)."""
        q = self.positions(coords)
        jac = np.array([r.g for r in self.rows(q)])
        qd = np.linalg.solve(jac, self._driven(speeds))
        mass = np.concatenate([[link.mass, link.mass, link.inertia] for link in self.links])
        V = sum(link.mass * self.g * (link.cg[1] + q[3 * i + 1])
                for i, link in enumerate(self.links))
        return 0.5 * float(qd @ (mass * qd)), float(V)


def _rot(phi: float) -> np.ndarray:
    c, s = math.cos(phi), math.sin(phi)
    return np.array([[c, -s], [s, c]])


@dataclass
class _Jet:
    """A function of the coordinates: its value ``v``, gradient ``g`` and second
    derivative ``h`` along the velocity (``d2/dt2`` without the ``g . qddot`` term)."""

    v: float
    g: np.ndarray
    h: float
    qd: np.ndarray

    def _rate(self) -> float:
        return float(self.g @ self.qd)

    def __add__(self, o):
        if not isinstance(o, _Jet):
            return _Jet(self.v + o, self.g, self.h, self.qd)
        return _Jet(self.v + o.v, self.g + o.g, self.h + o.h, self.qd)

    __radd__ = __add__

    def __neg__(self):
        return _Jet(-self.v, -self.g, -self.h, self.qd)

    def __sub__(self, o):
        return self + (-o)

    def __rsub__(self, o):
        return (-self) + o

    def __mul__(self, o):
        if not isinstance(o, _Jet):
            return _Jet(self.v * o, self.g * o, self.h * o, self.qd)
        return _Jet(self.v * o.v, self.g * o.v + self.v * o.g,
                    self.h * o.v + 2.0 * self._rate() * o._rate() + self.v * o.h, self.qd)

    __rmul__ = __mul__

    def unary(self, f: float, df: float, d2f: float):
        return _Jet(f, df * self.g, df * self.h + d2f * self._rate() ** 2, self.qd)


class _Jets:
    """The coordinates as jets, and the points and directions of the links."""

    def __init__(self, q: np.ndarray, qd: np.ndarray):
        self.q, self.qd = q, qd

    def var(self, k: int) -> _Jet:
        g = np.zeros(len(self.q))
        g[k] = 1.0
        return _Jet(float(self.q[k]), g, 0.0, self.qd)

    def phi(self, i: int) -> _Jet:
        return self.var(3 * i + 2)

    def turned(self, i: int, r) -> tuple:
        """``R(phi_i) r`` for a drawn vector ``r``."""
        phi = self.phi(i)
        c = phi.unary(math.cos(phi.v), -math.sin(phi.v), -math.cos(phi.v))
        s = phi.unary(math.sin(phi.v), math.cos(phi.v), -math.sin(phi.v))
        return c * r[0] - s * r[1], s * r[0] + c * r[1]

    def point(self, model: Model, i: int, name: str) -> tuple:
        link = model.links[i]
        rx, ry = self.turned(i, model.drawn(name) - link.cg)
        return (rx + self.var(3 * i) + link.cg[0], ry + self.var(3 * i + 1) + link.cg[1])

    def along(self, model: Model, a: int, b: int, joint: str, u0) -> _Jet:
        """``u_a . (P_b - P_a)``: the drawn direction ``u0`` turned with link ``a``, the
        pair's point on each link."""
        ux, uy = self.turned(a, u0)
        pa, pb = self.point(model, a, joint), self.point(model, b, joint)
        return ux * (pb[0] - pa[0]) + uy * (pb[1] - pa[1])


def read(path: str | Path) -> Model:
    with open(path, "rb") as f:
        return Model(tomllib.load(f))
