"""Each moving link's free body, symbolically: every force and couple acting on it (its
weight, the d'Alembert force and couple, the loads, each pair's reaction and the
efforts), as sympy expressions in the link's parameters and kinematic quantities, with
their values at one state, and its three equations ``ΣFx = 0``, ``ΣFy = 0`` and
``ΣM = 0`` about the point its group chooses (:meth:`Group.moment_point
<linkage_fmu.groups.Group.moment_point>`).

The symbols: ``x_P``, ``y_P`` a point's coordinates, ``phi_k`` link ``k``'s angle,
``m_k``, ``J_k`` its mass and moment of inertia about its centre of mass, ``ax_S``,
``ay_S`` the acceleration of the centre of mass ``S``, ``eps_k`` the link's angular
acceleration, ``g`` gravity, a load by its name, and the unknowns as
:mod:`~linkage_fmu.equations` names them. A load's or an effort's direction that is not
along an axis is a pair of symbols too (``ux_<name>``, ``uy_<name>``); a guide fixed in
the frame has its normal's numbers. Each pair says what its reaction is
(:meth:`Pair.reaction <linkage_fmu.pairs.Pair.reaction>`). This module writes
the equations from the free bodies alone; the numeric system the solver solves is
:func:`~linkage_fmu.kinetostatics.equilibrium_entries`', and the two agree (tested).
sympy is imported where a free body is made.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace

from .groups import KinematicState


@dataclass(frozen=True)
class Action:
    """One force or couple on a link: ``what`` it is, the point ``at`` which a force
    acts ('' for a couple) and its components ``fx``, ``fy`` and couple ``m`` (sympy
    expressions, 0 where it has none)."""

    what: str
    at: str
    fx: object
    fy: object
    m: object


@dataclass(frozen=True)
class FreeBodies:
    """The free bodies of a linkage's moving links at one state: ``actions`` (link ->
    its :class:`Action` s), ``about`` (link -> its moment point), ``values`` (each
    known symbol -> its value at the state, SI), ``unknowns`` (sympy symbols, in the
    order of :attr:`Equations.unknowns <linkage_fmu.equations.Equations.unknowns>`)."""

    actions: dict
    about: dict
    values: dict
    unknowns: tuple
    #: each friction's law of its pair's reaction (sympy ``Eq``: ``Mf_B = ...``); its
    #: value at the solution is in :attr:`values`
    laws: tuple = ()

    def equations(self) -> list:
        """The left-hand sides of each link's ``ΣFx = 0``, ``ΣFy = 0`` and ``ΣM = 0``
        about its point, three per link in the order of :attr:`actions`."""
        import sympy

        out = []
        for link, actions in self.actions.items():
            xp, yp = _point(self.about[link])
            fx = sympy.Add(*(a.fx for a in actions))
            fy = sympy.Add(*(a.fy for a in actions))
            m = sympy.Add(*(a.m + _arm(a, xp, yp) for a in actions))
            out += [fx, fy, m]
        return out

    def matrices(self) -> tuple:
        """``(A, b)``: the equations as sympy matrices, ``A x = b`` in :attr:`unknowns`."""
        import sympy

        return sympy.linear_eq_to_matrix(self.equations(), list(self.unknowns))


def _exact(expr):
    """``expr`` with a factor of exactly 1.0 or -1.0 (an axis's direction) as an
    integer."""
    import sympy

    return expr.xreplace({sympy.Float(1.0): sympy.Integer(1),
                          sympy.Float(-1.0): sympy.Integer(-1)})


def _point(name: str) -> tuple:
    import sympy

    return sympy.Symbol(f"x_{name}"), sympy.Symbol(f"y_{name}")


def _arm(a: Action, xp, yp):
    """The moment about ``(xp, yp)`` of the force of ``a``."""
    if not a.at:
        return 0
    x, y = _point(a.at)
    return (x - xp) * a.fy - (y - yp) * a.fx


def free_bodies(mech, st: KinematicState, omega: float, alpha: float, loads: list,
                unknowns: tuple, about: dict, friction: dict | None = None,
                signs: dict | None = None) -> FreeBodies:
    """The free bodies of ``mech``'s moving links at the state ``st`` (positions and,
    for a dynamic scene, derivatives; ``omega``, ``alpha`` the crank's, 1 and 0 for a
    linkage driven by time, whose ``st`` holds the rates), with the value of each of
    ``mech.loads`` in ``loads`` (None: computed at the state), the names of the
    ``unknowns`` (each pair's components in ``mech.joints`` order, then each effort)
    and each link's moment point ``about``. With friction, ``friction`` holds each
    pair's friction at the solution and ``signs`` the sign of its motion: the friction
    acts on the links as a known value, and its law is in :attr:`FreeBodies.laws`.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> from linkage_fmu.equations import equations
    >>> fb = equations(presets.get("four_bar"), 0.3, 10.0).free_bodies
    >>> [a.what for a in fb.actions["1"]]  # doctest: +NORMALIZE_WHITESPACE
    ['reaction of the frame on 1 at A', 'reaction of 2 on 1 at B',
     'balancing moment Mb', 'weight of 1', "d'Alembert force of 1"]
    >>> fb.equations()[2]
    Fx_B*(-y_A + y_B) - Fy_B*(-x_A + x_B) + Mb
    """
    import sympy

    S = sympy.Symbol
    values = {}
    static = not (omega or alpha)

    def known(name: str, value: float):
        s = S(name)
        values[s] = float(value)
        return s

    def direction(name: str, v: tuple) -> tuple:
        """A fixed unit vector: integers along an axis, else the symbols ``name``."""
        if all(c in (0.0, 1.0, -1.0) for c in v) and abs(v[0]) + abs(v[1]) == 1.0:
            return tuple(sympy.Integer(int(c)) for c in v)
        return known(f"ux_{name}", v[0]), known(f"uy_{name}", v[1])

    def angle(link: str) -> tuple:
        c, s = st.u[link]
        phi = known(f"phi_{link}", math.atan2(s, c))
        return sympy.cos(phi), sympy.sin(phi)

    def label(body: str) -> str:
        return "the frame" if body == mech.frame else body

    actions = {b.name: [] for b in mech.bodies}
    used = set()

    def act(body, what, at="", fx=0, fy=0, m=0):
        if body in actions:
            fx, fy, m = (_exact(sympy.sympify(v)) for v in (fx, fy, m))
            actions[body].append(Action(what, at, fx, fy, m))
            if at:
                used.add(at)

    class Angles(dict):
        def __missing__(self, link):
            self[link] = angle(link)
            return self[link]

    symbolic = SimpleNamespace(u=Angles())
    by = dict(zip(unknowns, (S(u) for u in unknowns)))
    names = iter(unknowns)
    for j in mech.joints:
        fx, fy, m = j.reaction(symbolic, by[next(names)], by[next(names)])
        for body, other, sign in ((j.b, j.a, 1), (j.a, j.b, -1)):
            act(body, f"reaction of {label(other)} on {body} at {j.point}", j.point,
                sign * fx, sign * fy, sign * m)
    laws = []
    for jf in mech.friction.joints if friction else ():
        if not jf.mu:  # no friction in this pair
            continue
        j = jf.joint
        f = known(jf.output, friction[j.name])
        what = f"friction {jf.output} in {j.point}"

        def couple(body, v, what=what, j=j):
            act(body, what if body == j.b else f"{what}, its reaction", m=v)

        def force(body, point, fx, fy, what=what, j=j):
            act(body, what if body == j.b else f"{what}, its reaction", point, fx, fy)

        j.apply_friction(symbolic, f, couple, force)
        c = [S(f"{k}_{j.name}") for k in j.components]
        radius = known(f"r_{j.name}", jf.radius) if jf.radius else 0
        length = None if jf.length is None else known(f"l_{j.name}", jf.length)
        laws.append(sympy.Eq(f, j.friction_formula(
            sympy, known(f"mu_{j.name}", jf.mu), radius, length,
            known(f"s_{j.name}", signs[j.name]), *c)))
    for e in mech.efforts:
        x = by[next(names)]
        kind = "balancing moment" if e.direction is None else "balancing force"
        for body, sign, what in ((e.body, 1, f"{kind} {e.name}"),
                                 (e.base, -1, f"reaction of {kind} {e.name}")):
            if e.direction is None:
                act(body, what, m=sign * x)
                continue
            d = angle(e.direction) if isinstance(e.direction, str) else direction(
                e.name, e.direction)
            act(body, what, e.point, sign * x * d[0], sign * x * d[1])
    for body in mech.bodies:
        k, cg = body.name, mech.cg[body.name]
        if body.mass and mech.g:
            act(k, f"weight of {k}", cg, 0, -known(f"m_{k}", body.mass) * known("g", mech.g))
        if body.mass and not static:
            (x1, y1), (x2, y2) = st.d1[cg], st.d2[cg]
            ax = known(f"ax_{cg}", x2 * omega * omega + x1 * alpha)
            ay = known(f"ay_{cg}", y2 * omega * omega + y1 * alpha)
            m = known(f"m_{k}", body.mass)
            act(k, f"d'Alembert force of {k}", cg, -m * ax, -m * ay)
        if body.inertia and not static:
            eps = known(f"eps_{k}", st.w2[k] * omega * omega + st.w1[k] * alpha)
            act(k, f"d'Alembert couple of {k}", m=-known(f"J_{k}", body.inertia) * eps)
    for load, value in zip(mech.loads, loads):
        v = known(load.name, load.at_state(st) if value is None else value)
        if load.kind == "moment":
            act(load.body, f"load {load.name}", m=v)
            continue
        d = direction(load.name, load.direction)
        if load.fixed_in == "link":
            c, s = angle(load.body)
            d = (c * d[0] - s * d[1], s * d[0] + c * d[1])
        act(load.body, f"load {load.name}", load.at, v * d[0], v * d[1])
    used.update(about.values())
    for p in sorted(used):
        x, y = _point(p)
        values[x], values[y] = (float(c) for c in st.p[p])
    return FreeBodies(actions, dict(about), values, tuple(by.values()), tuple(laws))
