"""An independent Newton-Euler reference for linkages written as joints and links.

It shares nothing with the library's groups, kinematics, kinetostatics or solver: it reads
the description file with :mod:`tomllib` itself, and solves the linkage the way a
multibody textbook does (Nikravesh, *Computer-Aided Analysis of Mechanical Systems*,
ch. 4 and 6), so that it cannot repeat a mistake of the group decomposition.

Positions. Every moving link is a rigid copy of its drawn self: link ``i`` is displaced by
``d_i`` (of its centre of mass) and turned by ``phi_i`` from where it is drawn, so a
point ``P`` of it is at ``cg_i + d_i + R(phi_i) (P0 - cg_i)``. A rigid motion keeps
every distance between the link's joints at its drawn value: these are the links'
distance constraints, written without the singularity the bare distances have when a
link's joints are collinear. The constraints are

- a joint shared by moving links: each of them puts its copy of the joint at the same
  place (two equations per pair of links on the pin: a compound joint is one pin);
- a joint listed by one moving link only, or by the frame's entry in ``[[links]]`` (the
  table named as the frame, ``name`` and ``joints`` only): each moving link's copy of it
  stays where the joint is drawn (k links on a frame joint: k pins to the frame);
- a slider ``{ at = [x, y], slide = [dx, dy] }`` listed by one moving link: that link
  translates (its angle stays as drawn) with the point on the line through ``at`` along
  ``slide`` (a prismatic pair on a frame guide);
- the crank: its angle is ``theta``, i.e. ``phi_crank = theta - theta_drawn``, where
  ``theta`` is the absolute angle of the line from the pivot to the crank's first other
  joint.

They are solved by Newton from the drawn pose (``q = 0`` at ``theta_drawn``) with
continuation in crank-angle steps of at most :data:`STEP` rad. Velocities and
accelerations come from the differentiated constraints: ``Phi_q qdot = (0, ..., omega)``
and ``Phi_q qddot = gamma`` with the quadratic terms written out.

Forces. Per moving link, Newton and Euler: ``m a_cg = sum F`` (weight ``-m g`` in y, the
named loads, the reactions) and ``J alpha_link = sum M`` about the centre of mass. The
unknowns are every pin's reactions (for a pin shared by links ``L1 .. Lk``: the force of
``L1`` on each of ``L2 .. Lk``; for a frame pin: the force of the frame on each link on
it), each slider's normal force and couple, and the driving moment ``Mb`` on the crank.
The system is square when the linkage's mobility is one; it is solved directly, and the
residual of every link's equations is returned.

Shaking (as :class:`linkage_fmu.outputs.Shaking` defines it): the resultant of what the
moving links exert on the frame through its joints and through the driver (the frame
takes ``-Mb``), ``shake_x``, ``shake_y``, and its moment ``shake_M`` about the crank's
pivot, counter-clockwise positive.

Values: plain numbers (SI), a number with a length unit (``"120 mm"``), or a string that
is a key of ``values`` (resolved numbers for parameters or expressions; a bare parameter
name also takes its ``[parameters]`` default).

Named points of a link that are not joints (a foot, a coupler point) are drawn in their
link's table, ``points = { P = [x, y] }``; loads act at a joint or such a point
(``at``), or as a moment on a body.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

#: largest crank-angle step of the continuation (rad)
STEP = math.radians(1.0)
#: Newton's tolerance on the constraint residual (m, rad)
TOL = 1e-14
_LENGTH = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}
_NUMBER_UNIT = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z]*)\s*$")


class ReferenceError(ValueError):
    """The description cannot be read or solved by the reference."""


@dataclass(frozen=True)
class Link:
    """A moving link: its joints, named points, mass, inertia about and drawn cg."""

    name: str
    joints: tuple
    points: tuple
    mass: float
    inertia: float
    cg: np.ndarray


@dataclass(frozen=True)
class Linkage:
    """A linkage as joints and links, every coordinate where drawn (m)."""

    frame: str
    joints: dict            # joint -> drawn position
    slides: dict            # slider joint -> unit direction of its frame guide
    points: dict            # point (not a joint) -> drawn position
    links: tuple            # moving links, in file order
    crank: str
    pivot: str
    loads: tuple = ()       # dicts: name, body, kind, at, direction, start
    frame_joints: frozenset = field(default_factory=frozenset)  # listed by the frame

    @property
    def index(self) -> dict:
        return {link.name: i for i, link in enumerate(self.links)}

    def on(self, joint: str) -> list:
        """Moving links listing ``joint``, in file order."""
        return [link.name for link in self.links if joint in link.joints]

    def grounded(self, joint: str) -> bool:
        """Whether ``joint`` joins its links to the frame."""
        return joint in self.frame_joints or len(self.on(joint)) == 1

    @property
    def crank_tip(self) -> str:
        link = self.links[self.index[self.crank]]
        return next(j for j in link.joints if j != self.pivot)

    @property
    def theta_drawn(self) -> float:
        p, t = self.joints[self.pivot], self.joints[self.crank_tip]
        return math.atan2(t[1] - p[1], t[0] - p[0])


def _number(value, what: str, values: dict, length: bool = False) -> float:
    """A plain number, a key of ``values``, or (a ``length``) a length with a unit."""
    if isinstance(value, bool):
        raise ReferenceError(f"{what}: {value!r} is not a number")
    if isinstance(value, (int, float)):
        return float(value)
    if isinstance(value, str):
        if value in values:
            return float(values[value])
        match = _NUMBER_UNIT.match(value)
        if match and (match[2] == "" or (length and match[2] in _LENGTH)):
            return float(match[1]) * _LENGTH.get(match[2] or "m")
    units = ", a length with a unit (m, cm, mm)" if length else ""
    raise ReferenceError(f"{what}: {value!r} is neither a number{units} nor a resolved value")


def _xy(value, what: str, values: dict) -> np.ndarray:
    if not isinstance(value, list) or len(value) != 2:
        raise ReferenceError(f"{what}: expected [x, y], got {value!r}")
    return np.array([_number(v, what, values, length=True) for v in value])


def from_data(data: dict, values: dict | None = None) -> Linkage:
    """The :class:`Linkage` of a joints-and-links description (a parsed TOML table).

    Examples
    --------
    >>> data = {"joints": {"A": [0, 0], "B": [0.1, 0], "C": [0.2, 0.3], "D": [0.4, 0]},
    ...         "links": [{"name": "1", "joints": ["A", "B"]},
    ...                   {"name": "2", "joints": ["B", "C"], "mass": 1.0, "cg": [0.15, 0.15]},
    ...                   {"name": "3", "joints": ["C", "D"]}],
    ...         "crank": {"link": "1", "pivot": "A"}}
    >>> lk = from_data(data)
    >>> lk.crank_tip, lk.theta_drawn, lk.grounded("D")
    ('B', 0.0, True)
    """
    resolved = {name: spec["default"] for name, spec in data.get("parameters", {}).items()
                if isinstance(spec, dict) and isinstance(spec.get("default"), (int, float))}
    resolved.update(values or {})
    frame = str(data.get("linkage", {}).get("frame", "0"))
    joints, slides = {}, {}
    for name, spec in data.get("joints", {}).items():
        if isinstance(spec, dict):
            joints[name] = _xy(spec["at"], f"[joints] {name}.at", resolved)
            s = _xy(spec["slide"], f"[joints] {name}.slide", resolved)
            slides[name] = s / np.hypot(*s)
        else:
            joints[name] = _xy(spec, f"[joints] {name}", resolved)
    points: dict = {}
    links, frame_joints = [], set()
    for k, spec in enumerate(data.get("links", [])):
        name = str(spec.get("name", k + 1))
        listed = tuple(spec.get("joints", ()))
        for j in listed:
            if j not in joints:
                raise ReferenceError(f"link {name}: joint {j!r} is not in [joints]")
        drawn = spec.get("points", {})
        if not isinstance(drawn, dict):
            raise ReferenceError(f"link {name}: points must be a table {{ P = [x, y] }}")
        for j, xy in drawn.items():
            if j in joints or j in points:
                raise ReferenceError(f"link {name}: point {j!r} is already a joint or a point")
            points[j] = _xy(xy, f"link {name}.points.{j}", resolved)
        if name == frame:
            extra = set(spec) - {"name", "joints"}
            if extra:
                raise ReferenceError(f"the frame's entry {name}: it lists joints only, not "
                                     f"{', '.join(sorted(extra))}")
            frame_joints.update(listed)
            continue
        if len(listed) < 2 and not any(j in slides for j in listed):
            raise ReferenceError(f"link {name}: {len(listed)} joint(s); a link needs two")
        cg = spec.get("cg")
        links.append(Link(name, listed, tuple(drawn),
                          _number(spec.get("mass", 0.0), f"link {name}.mass", resolved),
                          _number(spec.get("inertia", 0.0), f"link {name}.inertia", resolved),
                          joints[listed[0]].copy() if cg is None
                          else _xy(cg, f"link {name}.cg", resolved)))
    crank = data.get("crank", {})
    loads = []
    for spec in data.get("loads", []):
        d = spec.get("direction", [0.0, 0.0])
        loads.append(dict(name=spec["name"], body=str(spec["body"]), kind=spec["kind"],
                          at=spec.get("at", ""), start=float(spec.get("start", 0.0)),
                          direction=np.array([float(v) for v in d]) / (np.hypot(*d) or 1.0)))
    lk = Linkage(frame, joints, slides, points, tuple(links), str(crank["link"]),
                 str(crank["pivot"]), tuple(loads), frozenset(frame_joints))
    if lk.crank not in lk.index:
        raise ReferenceError(f"[crank] link {lk.crank!r} is not a moving link")
    if not lk.grounded(lk.pivot) or lk.pivot not in lk.links[lk.index[lk.crank]].joints:
        raise ReferenceError(f"[crank] pivot {lk.pivot!r} is not the crank's joint with the frame")
    return lk


def read(path: str | Path, values: dict | None = None) -> Linkage:
    """The :class:`Linkage` of the description file at ``path``."""
    with open(path, "rb") as f:
        return from_data(tomllib.load(f), values)


# --- positions -------------------------------------------------------------------------

def _rot(phi: float) -> np.ndarray:
    c, s = math.cos(phi), math.sin(phi)
    return np.array([[c, -s], [s, c]])


_TURN = np.array([[0.0, -1.0], [1.0, 0.0]])  # d R(phi) / d phi = _TURN @ R(phi)


@dataclass(frozen=True)
class _Row:
    """A constraint: ``kind`` 'pin' (p_a(joint) = p_b(joint), b None: the drawn place),
    'slide' (the point on the guide line, the link's angle fixed) or 'crank'."""

    kind: str
    joint: str = ""
    a: int = -1
    b: int | None = None


def _rows(lk: Linkage) -> list:
    rows = []
    idx = lk.index
    for j in lk.joints:
        on = [idx[name] for name in lk.on(j)]
        if not on:
            raise ReferenceError(f"joint {j!r} is on no moving link")
        if j in lk.slides:
            if len(on) != 1:
                raise ReferenceError(f"slider {j!r}: only a slider on a frame guide "
                                     f"(listed by one moving link) is supported")
            rows.append(_Row("slide", j, on[0]))
        elif lk.grounded(j):
            rows += [_Row("pin", j, i) for i in on]
        else:
            rows += [_Row("pin", j, on[0], i) for i in on[1:]]
    rows.append(_Row("crank", lk.pivot, idx[lk.crank]))
    eqs = sum(1 if r.kind == "crank" else 2 for r in rows)
    if eqs != 3 * len(lk.links):
        raise ReferenceError(f"mobility {3 * len(lk.links) - eqs + 1}: "
                             f"{3 * len(lk.links)} coordinates, {eqs - 1} constraint equations")
    return rows


def _point(lk: Linkage, i: int, name: str, q: np.ndarray) -> np.ndarray:
    link = lk.links[i]
    drawn = lk.joints[name] if name in lk.joints else lk.points[name]
    return link.cg + q[3 * i:3 * i + 2] + _rot(q[3 * i + 2]) @ (drawn - link.cg)


def _arm(lk: Linkage, i: int, name: str, q: np.ndarray) -> np.ndarray:
    """From link ``i``'s centre of mass to its point ``name``."""
    link = lk.links[i]
    drawn = lk.joints[name] if name in lk.joints else lk.points[name]
    return _rot(q[3 * i + 2]) @ (drawn - link.cg)


def _normal(lk: Linkage, joint: str) -> np.ndarray:
    dx, dy = lk.slides[joint]
    return np.array([-dy, dx])


def _residual(lk, rows, q, theta):
    out = []
    for r in rows:
        if r.kind == "crank":
            out.append(q[3 * r.a + 2] - (theta - lk.theta_drawn))
        elif r.kind == "slide":
            out += [_normal(lk, r.joint) @ (_point(lk, r.a, r.joint, q) - lk.joints[r.joint]),
                    q[3 * r.a + 2]]
        else:
            other = lk.joints[r.joint] if r.b is None else _point(lk, r.b, r.joint, q)
            out += list(_point(lk, r.a, r.joint, q) - other)
    return np.array(out)


def _jacobian(lk, rows, q):
    jac = np.zeros((3 * len(lk.links), 3 * len(lk.links)))
    k = 0
    for r in rows:
        if r.kind == "crank":
            jac[k, 3 * r.a + 2] = 1.0
            k += 1
            continue
        if r.kind == "slide":
            n = _normal(lk, r.joint)
            jac[k, 3 * r.a:3 * r.a + 2] = n
            jac[k, 3 * r.a + 2] = n @ (_TURN @ _arm(lk, r.a, r.joint, q))
            jac[k + 1, 3 * r.a + 2] = 1.0
            k += 2
            continue
        for i, sign in ((r.a, 1.0), (r.b, -1.0)):
            if i is None:
                continue
            jac[k:k + 2, 3 * i:3 * i + 2] += sign * np.eye(2)
            jac[k:k + 2, 3 * i + 2] += sign * (_TURN @ _arm(lk, i, r.joint, q))
        k += 2
    return jac


def _newton(lk, rows, q, theta):
    for _ in range(50):
        res = _residual(lk, rows, q, theta)
        if np.max(np.abs(res)) < TOL:
            return q
        q = q - np.linalg.solve(_jacobian(lk, rows, q), res)
    raise ReferenceError(f"Newton did not converge at theta = {math.degrees(theta):.6f} deg "
                         f"(residual {np.max(np.abs(res)):.3g})")


def positions(lk: Linkage, theta: float, q0: np.ndarray | None = None,
              theta0: float | None = None) -> np.ndarray:
    """The links' displacements ``q`` (``dx, dy, phi`` of each) at crank angle ``theta``,
    continued from ``q0`` at ``theta0`` (default: the drawn pose) in steps of at most
    :data:`STEP`. ``theta`` is taken as it is (not modulo a turn): the path from the
    drawn angle is the one the crank turns through."""
    rows = _rows(lk)
    if q0 is None:
        q0, theta0 = np.zeros(3 * len(lk.links)), lk.theta_drawn
    n = max(1, math.ceil(abs(theta - theta0) / STEP))
    q = q0
    for t in np.linspace(theta0, theta, n + 1)[1:]:
        q = _newton(lk, rows, q, t)
    return q


def where(lk: Linkage, q: np.ndarray) -> dict:
    """Joint and point name -> position at the displacements ``q``."""
    out = {j: lk.joints[j].copy() for j in lk.joints if lk.grounded(j) and j not in lk.slides}
    for i, link in enumerate(lk.links):
        for name in link.joints + link.points:
            out.setdefault(name, _point(lk, i, name, q))
    return out


def motion(lk: Linkage, q: np.ndarray, omega: float, alpha: float):
    """Velocities and accelerations of the links' coordinates at ``q``."""
    rows = _rows(lk)
    jac = _jacobian(lk, rows, q)
    nu = np.zeros(len(q))
    nu[-1] = omega
    qd = np.linalg.solve(jac, nu)
    gamma = np.zeros(len(q))
    k = 0
    for r in rows:
        if r.kind == "crank":
            gamma[k] = alpha
            k += 1
            continue
        if r.kind == "slide":  # the link does not turn: no quadratic term
            k += 2
            continue
        # d2/dt2 of cg + d + R s = d'' + phi'' T R s - phi'^2 R s
        for i, sign in ((r.a, 1.0), (r.b, -1.0)):
            if i is not None:
                gamma[k:k + 2] += sign * qd[3 * i + 2] ** 2 * _arm(lk, i, r.joint, q)
        k += 2
    return qd, np.linalg.solve(jac, gamma)


# --- forces ----------------------------------------------------------------------------

def solve(lk: Linkage, theta: float, omega: float, alpha: float, g: float,
          loads: dict | None = None, q: np.ndarray | None = None) -> dict:
    """Newton-Euler at one state: ``Mb``, ``shake_x``, ``shake_y``, ``shake_M``, the
    reactions (``R``: (joint, link it acts on) -> force on that link, (joint, 'N'/'M') of
    a slider), the positions (``p``), ``q`` and the largest equation ``residual``.

    ``loads`` gives the named loads' magnitudes (default: each load's ``start``).

    Examples
    --------
    A parallelogram at 45 deg with a 2 kg coupler: by virtual work the crank holds
    ``m g l cos 45``, and the frame carries the weight.

    >>> c = 0.1 * math.cos(math.pi / 4)
    >>> data = {"joints": {"A": [0, 0], "B": [c, c], "C": [0.2 + c, c], "D": [0.2, 0]},
    ...         "links": [{"name": "1", "joints": ["A", "B"]},
    ...                   {"name": "2", "joints": ["B", "C"], "mass": 2.0, "cg": [0.1 + c, c]},
    ...                   {"name": "3", "joints": ["C", "D"]}],
    ...         "crank": {"link": "1", "pivot": "A"}}
    >>> r = solve(from_data(data), math.pi / 4, 0.0, 0.0, 10.0)
    >>> round(r["Mb"] - 2.0 * 10.0 * c, 12), round(r["shake_y"], 12)
    (0.0, -20.0)
    """
    idx = lk.index
    q = positions(lk, theta) if q is None else q
    qd, qdd = motion(lk, q, omega, alpha)
    named = {ld["name"]: ld["start"] for ld in lk.loads}
    named.update(loads or {})
    n = len(lk.links)
    # unknown columns: (kind, joint, link index, force direction or None)
    cols = []
    for j in lk.joints:
        on = [idx[name] for name in lk.on(j)]
        if j in lk.slides:
            cols += [("N", j, on[0]), ("M", j, on[0])]
        elif lk.grounded(j):   # the frame's force on each link on the pin
            cols += [(axis, j, i) for i in on for axis in ("x", "y")]
        else:                  # the first link's force on each other link on the pin
            cols += [(axis, j, i) for i in on[1:] for axis in ("x", "y")]
    cols.append(("Mb", lk.pivot, idx[lk.crank]))
    a = np.zeros((3 * n, len(cols)))
    b = np.zeros(3 * n)

    def put(col, i, force, arm, couple=0.0):
        a[3 * i:3 * i + 2, col] += force
        a[3 * i + 2, col] += arm[0] * force[1] - arm[1] * force[0] + couple

    for c, (kind, j, i) in enumerate(cols):
        if kind == "Mb":
            put(c, i, np.zeros(2), np.zeros(2), 1.0)
        elif kind == "N":
            put(c, i, _normal(lk, j), _arm(lk, i, j, q))
        elif kind == "M":
            put(c, i, np.zeros(2), np.zeros(2), 1.0)
        else:
            f = np.array([1.0, 0.0] if kind == "x" else [0.0, 1.0])
            put(c, i, f, _arm(lk, i, j, q))
            if not lk.grounded(j):  # its reaction on the pin's first link
                first = idx[lk.on(j)[0]]
                put(c, first, -f, _arm(lk, first, j, q))
    for i, link in enumerate(lk.links):
        # m a - external forces = reactions; J alpha - external moments = reaction moments
        b[3 * i:3 * i + 2] = link.mass * qdd[3 * i:3 * i + 2] + np.array([0.0, link.mass * g])
        b[3 * i + 2] = link.inertia * qdd[3 * i + 2]
    for ld in lk.loads:
        i, value = idx[ld["body"]], float(named[ld["name"]])
        if ld["kind"] == "moment":
            b[3 * i + 2] -= value
        else:
            f = value * ld["direction"]
            arm = _arm(lk, i, ld["at"], q)
            b[3 * i:3 * i + 2] -= f
            b[3 * i + 2] -= arm[0] * f[1] - arm[1] * f[0]
    x = np.linalg.solve(a, b)
    residual = float(np.max(np.abs(a @ x - b)))
    p = where(lk, q)
    pivot = lk.joints[lk.pivot]
    shake = np.zeros(2)
    moment = 0.0
    reactions = {}
    for value, (kind, j, i) in zip(x, cols):
        name = lk.links[i].name
        if kind in "xy":
            reactions.setdefault((j, name), np.zeros(2))["xy".index(kind)] += value
        elif kind in "NM":
            reactions[(j, kind)] = value
    for (j, what), value in reactions.items():
        if what == "N":    # the frame's normal force on the link: the link's on the frame
            f = -value * _normal(lk, j)
            shake += f
            r = p[j] - pivot
            moment += r[0] * f[1] - r[1] * f[0]
        elif what == "M":
            moment -= value
        elif lk.grounded(j):
            f = -value
            shake += f
            r = lk.joints[j] - pivot
            moment += r[0] * f[1] - r[1] * f[0]
    mb = float(x[-1])
    return {"Mb": mb, "shake_x": float(shake[0]), "shake_y": float(shake[1]),
            "shake_M": float(moment - mb), "R": reactions, "p": p, "q": q,
            "qd": qd, "qdd": qdd, "residual": residual}


def sweep(lk: Linkage, thetas) -> list:
    """Displacements along increasing or decreasing crank angles ``thetas``, each
    continued from the one before (the first from the drawn pose)."""
    out, q, t0 = [], None, None
    for t in thetas:
        q = positions(lk, float(t), q, t0)
        t0 = float(t)
        out.append(q)
    return out


def distances(lk: Linkage, q: np.ndarray) -> dict:
    """(link, joint, joint) -> distance at ``q``, for every pair of a link's joints."""
    p = where(lk, q)
    out = {}
    for link in lk.links:
        names = link.joints + link.points
        for k, u in enumerate(names):
            for v in names[k + 1:]:
                out[(link.name, u, v)] = float(np.hypot(*(p[u] - p[v])))
    return out


def assemble(fixed: dict, guess: dict, lengths: list, tol: float = 1e-15) -> dict:
    """Joint positions from link lengths: Newton (Gauss-Newton if the equations are more
    than the unknowns) on ``|P - Q| = L`` for each ``(P, Q, L)`` of ``lengths``, with the
    joints of ``fixed`` where they are and the others started at ``guess`` (which picks
    the assembly mode). Used to draw a linkage whose lengths are given.

    Examples
    --------
    >>> p = assemble({"A": (0.0, 0.0), "D": (2.0, 0.0)}, {"C": (1.0, 1.0)},
    ...              [("A", "C", 2.0 ** 0.5), ("D", "C", 2.0 ** 0.5)])
    >>> [round(float(v), 12) for v in p["C"]]
    [1.0, 1.0]
    """
    free = list(guess)
    x = np.array([v for name in free for v in guess[name]], dtype=float)

    def at(name, x):
        if name in fixed:
            return np.asarray(fixed[name], dtype=float)
        k = free.index(name)
        return x[2 * k:2 * k + 2]

    for _ in range(100):
        res = np.array([np.hypot(*(at(u, x) - at(v, x))) - length for u, v, length in lengths])
        if np.max(np.abs(res)) < tol:
            break
        jac = np.zeros((len(lengths), len(x)))
        for row, (u, v, _length) in enumerate(lengths):
            e = at(u, x) - at(v, x)
            e = e / np.hypot(*e)
            for name, sign in ((u, 1.0), (v, -1.0)):
                if name not in fixed:
                    k = free.index(name)
                    jac[row, 2 * k:2 * k + 2] += sign * e
        x = x - np.linalg.lstsq(jac, res, rcond=None)[0]
    else:
        raise ReferenceError(f"cannot assemble: residual {np.max(np.abs(res)):.3g}")
    out = {name: np.asarray(v, dtype=float) for name, v in fixed.items()}
    out.update({name: x[2 * k:2 * k + 2].copy() for k, name in enumerate(free)})
    return out


# --- checks of a solution that need none of the reaction unknowns -----------------------

def power_balance(lk: Linkage, r: dict, g: float, loads: dict | None = None) -> tuple:
    """(``Mb`` times the crank's speed plus the power of the weights and loads, the rate
    of change of the kinetic energy) of the solution ``r``: equal by virtual power."""
    loads = loads or {}
    qd, qdd = r["qd"], r["qdd"]
    power = r["Mb"] * qd[3 * lk.index[lk.crank] + 2]
    kinetic = 0.0
    for i, link in enumerate(lk.links):
        v, a = qd[3 * i:3 * i + 2], qdd[3 * i:3 * i + 2]
        power -= link.mass * g * v[1]
        kinetic += link.mass * v @ a + link.inertia * qd[3 * i + 2] * qdd[3 * i + 2]
    for ld in lk.loads:
        i = lk.index[ld["body"]]
        value = loads.get(ld["name"], ld["start"])
        if ld["kind"] == "moment":
            power += value * qd[3 * i + 2]
        else:  # the load point's velocity: v_cg + w x arm
            arm = _arm(lk, i, ld["at"], r["q"])
            w = qd[3 * i + 2]
            power += value * ld["direction"] @ (qd[3 * i:3 * i + 2]
                                                + w * np.array([-arm[1], arm[0]]))
    return float(power), float(kinetic)


def momentum_balance(lk: Linkage, r: dict, g: float, loads: dict | None = None) -> np.ndarray:
    """The weights and loads of the moving links minus their ``m a``: the force they put
    on the frame, which ``shake_x``, ``shake_y`` must equal."""
    loads = loads or {}
    total = np.zeros(2)
    for i, link in enumerate(lk.links):
        total += -link.mass * r["qdd"][3 * i:3 * i + 2] - np.array([0.0, link.mass * g])
    for ld in lk.loads:
        if ld["kind"] == "force":
            total += loads.get(ld["name"], ld["start"]) * ld["direction"]
    return total
