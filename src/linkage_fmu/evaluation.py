"""The one sequence of formulas of a linkage: its kinematics, its loads, the reactions
solve its plan asks for, and its outputs, on any kind of number.

The functions here take a mechanism's data (:class:`~linkage_fmu.mechanism.Mechanism`:
its groups, bodies, loads, friction, outputs) and a plan
(:class:`~linkage_fmu.solver.Plan`), and call nothing of the mechanism back: the
solver, the precise solve and the traced kernels all evaluate through them, on floats,
numpy arrays, mpmath numbers or traced numbers (:mod:`~linkage_fmu.numerics`).

Examples
--------
>>> from linkage_fmu import presets
>>> from linkage_fmu.numerics import SCALAR
>>> yoke = presets.get("scotch_yoke")
>>> plan = yoke.solver.plan(("Mb",), False, "closed_form")
>>> out, state = evaluate(yoke, plan, 0.5, 10.0, 0.0, [100.0], SCALAR)
>>> out["Mb"] == yoke.solve(0.5, 10.0, 0.0, 100.0)["Mb"]
True
"""

from __future__ import annotations

import numpy as np

from . import diagnostics, friction, kinetostatics
from .errors import AssemblyError, InputError
from .groups import KinematicState
from .loads import powers, wrenches
from .numerics import ARRAY, SCALAR, finite_array, finite_float


def split(mech, values) -> tuple:
    """``(theta, omega, alpha, loads)`` of a state's values in ``mech``'s input order:
    the crank's three inputs, or, for a linkage driven by time
    (:attr:`KinematicState.rates <linkage_fmu.groups.KinematicState>`), the tuples of
    the drivers' coordinates, speeds and accelerations.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> split(presets.get("four_bar"), [0.5, 10.0, 0.0, 3.0])
    (0.5, 10.0, 0.0, [3.0])
    """
    if not mech.rates:
        return values[0], values[1], values[2], values[3:]
    n = 3 * len(mech.drivers)
    return (tuple(values[0:n:3]), tuple(values[1:n:3]), tuple(values[2:n:3]),
            list(values[n:]))


def still(mech, values) -> bool:
    """Whether the state ``values`` (floats or arrays) is static: every driver's speed
    and acceleration zero."""
    if not mech.rates:
        return not (np.any(values[1]) or np.any(values[2]))
    n = 3 * len(mech.drivers)
    return not any(np.any(values[k]) for k in range(n) if k % 3)


def state_words(mech, theta) -> float | dict:
    """The state for an error's message: the crank angle, or each driver's coordinate
    by name (its first value over arrays)."""
    if not mech.rates:
        return theta
    names = [d.inputs[0] for d in mech.drivers]
    return {n: float(np.asarray(q).flat[0]) for n, q in zip(names, theta)}


def kinematics(mech, theta, order: int = 2, xp=None, rates=None) -> KinematicState:
    """The position of every point and link of ``mech`` at the crank angle(s)
    ``theta``, and their first and second derivatives with respect to ``theta``.

    The points are named as the description names them: the frame's points, the
    joints and points the groups place, and each link's centre of mass ``S<link>``
    (``S2`` for link ``2``, ``Scrank`` for a link named ``crank``) where it is off the
    link's point ``ref``; where it is on it, the centre of mass is that point.
    ``mech.cg`` maps each moving link to its centre of mass's point.

    Parameters
    ----------
    mech : Mechanism
        The linkage.
    theta : float or array_like
        Crank angle(s) [rad], finite.
    order : {0, 1, 2}
        Positions only (0), with the first derivatives (1), and the second (2).
    xp : namespace, optional
        The numbers to compute on (:data:`~linkage_fmu.numerics.SCALAR`,
        :data:`~linkage_fmu.numerics.ARRAY`, :data:`linkage_fmu.precise.MP`); default
        floats for one angle, numpy arrays for many.
    rates : tuple, optional
        For a linkage driven by time (several drivers, a motor, a cylinder): each
        driver's ``(speed, acceleration)``, ``theta`` then the tuple of their
        coordinates; ``d1`` and ``d2`` are then velocities and accelerations.

    Returns
    -------
    KinematicState
        ``st.p[point]``, ``st.d1[point]``, ``st.d2[point]``: the point's position
        ``(x, y)`` [m] and its derivatives ``(dx/dtheta, dy/dtheta)`` [m/rad] and
        ``(d2x/dtheta2, d2y/dtheta2)`` [m/rad2]; ``st.u[link]``, ``st.w1[link]``,
        ``st.w2[link]``: the link's direction ``(cos phi, sin phi)`` and
        ``dphi/dtheta``, ``d2phi/dtheta2``. At crank speed ``omega`` and acceleration
        ``alpha``, a point's velocity is ``d1 omega`` (``st.velocity(point, omega)``),
        its acceleration ``d2 omega**2 + d1 alpha`` (``st.acceleration(point, omega,
        alpha)``), a link's angular speed ``w1 omega``. For arrays, ``st.invalid``
        marks the angles the linkage cannot be assembled at (NaN there).


    Raises
    ------
    AssemblyError
        One angle the linkage cannot be assembled at.
    ValueError
        An angle that is not a finite number.

    Examples
    --------
    The four-bar (crank AB 0.1 m, coupler BC 0.35 m, rocker CD 0.3 m, D 0.4 m from A
    along x), its coupler's centre of mass ``S2`` 0.175 m from B along BC:

    >>> import math
    >>> from linkage_fmu import presets
    >>> mech = presets.get("four_bar")
    >>> st = kinematics(mech, 0.5)
    >>> sorted(st.p), mech.cg
    (['A', 'B', 'C', 'D', 'S2', 'S3'], {'1': 'A', '2': 'S2', '3': 'S3'})
    >>> [round(v, 6) for v in st.p["B"]] == [round(0.1 * math.cos(0.5), 6),
    ...                                      round(0.1 * math.sin(0.5), 6)]
    True
    >>> (B, C), S2 = (st.p["B"], st.p["C"]), st.p["S2"]
    >>> [round(s - (b + c) / 2, 12) for s, b, c in zip(S2, B, C)]  # mid BC
    [0.0, 0.0]
    >>> [round(v, 6) for v in st.velocity("B", 10.0)]  # B turns at 1 m/s
    [-0.479426, 0.877583]
    >>> round(st.w1["1"], 12), [round(v, 6) for v in st.u["1"]]
    (1.0, [0.877583, 0.479426])
    >>> [round(v, 6) for v in kinematics(mech, 0.0, order=0).p["C"]]
    [0.304167, 0.284282]
    """
    if mech.rates:
        if rates is None:
            raise InputError(f"{mech.name} is driven by {_drivers(mech)}: its kinematics "
                             "take each driver's coordinate, and its speed and acceleration "
                             "(rates)")
        theta, rates, xp = _by_time(mech, theta, rates, xp)
    elif xp is None:
        if np.ndim(theta) == 0:
            xp = SCALAR
            theta = finite_float("theta", theta.item() if isinstance(theta, np.ndarray)
                                 else theta)
        else:
            xp = ARRAY
            theta = finite_array("theta", theta)

    def fail(condition: str, what: str = ""):
        raise AssemblyError(mech.name, state_words(mech, theta), condition, what)

    st = KinematicState(theta, xp, fail, rates)
    zero = (0.0, 0.0)
    for p, xy in mech.frame_points.items():
        st.p[p], st.d1[p], st.d2[p] = xy, zero, zero
    for grp in mech.groups:
        grp.position(st)
    if order >= 1:
        for grp in mech.groups:
            grp.first(st)
    if order >= 2:
        for grp in mech.groups:
            grp.second(st)
    return st


def _drivers(mech) -> str:
    return ", ".join(f"{d.kind} {d.inputs[0]}" for d in mech.drivers)


def _by_time(mech, theta, rates, xp) -> tuple:
    """The coordinates and rates of a linkage driven by time, checked: one per driver,
    finite, and of one kind of number (floats, or arrays of one shape)."""
    names = [d.inputs for d in mech.drivers]
    if len(theta) != len(names) or len(rates) != len(names):
        raise InputError(f"{mech.name} is driven by {_drivers(mech)}: give "
                         f"{len(names)} coordinate(s) and (speed, acceleration) pair(s), "
                         f"got {len(theta)} and {len(rates)}")
    values = [v for q, (w, a) in zip(theta, rates) for v in (q, w, a)]
    flat = [n for three in names for n in three]
    if xp is None:
        if all(np.ndim(v) == 0 for v in values):
            xp = SCALAR
            values = [finite_float(n, v.item() if isinstance(v, np.ndarray) else v)
                      for n, v in zip(flat, values)]
        else:
            xp = ARRAY
            values = np.broadcast_arrays(*(finite_array(n, v) for n, v in zip(flat, values)))
    return (tuple(values[0::3]), tuple(zip(values[1::3], values[2::3])), xp)


def order(mech, plan) -> int:
    """The derivatives of the kinematics ``plan`` needs: none for positions alone, the
    first for a static scene's reactions where friction, ``eta`` or an effort off the
    crank asks for them, both for a moving scene.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("four_bar")
    >>> order(mech, mech.solver.plan(("Mb",), True, "closed_form"))  # virtual power
    1
    >>> order(mech, mech.solver.plan(("Mb",), False, "closed_form"))
    2
    """
    k = 0
    if plan.reactions or plan.effort:
        if not plan.static:
            k = 2
        elif not plan.reactions or mech.friction.active or "eta" in plan.outputs or (
                plan.method != "direct" and not mech.effort_on_crank):
            k = 1
    return max(k, diagnostics.order(mech, plan.outputs))


def reactions(mech, st: KinematicState, W: dict, plan, omega, xp):
    """The reactions and balancing effort the ``plan`` asks for (its method; the effort
    alone by virtual power): with the friction in the joints where the linkage has some
    (:func:`linkage_fmu.friction.solve`), else by :mod:`~linkage_fmu.kinetostatics`
    alone, its declared friction then reported as none. ``W`` is consumed.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> from linkage_fmu.loads import wrenches
    >>> from linkage_fmu.numerics import SCALAR
    >>> yoke = presets.get("scotch_yoke")
    >>> plan = yoke.solver.plan(("Mb",), True, "closed_form")
    >>> st = kinematics(yoke, 0.5, 1)
    >>> R, effort = reactions(yoke, st, wrenches(yoke, st, 0.0, 0.0, [100.0], True),
    ...                       plan, 0.0, SCALAR)
    >>> round(effort, 9) == round(yoke.solve(0.5, 0.0, 0.0, 100.0)["Mb"], 9)
    True
    """
    if mech.friction.active:
        return friction.solve(mech, st, W, plan, omega, xp)
    if plan.reactions and plan.method == "direct":
        R, effort = kinetostatics.direct(mech, st, W, xp, kinetostatics.state_count(mech, st))
    elif plan.reactions or mech.rates:
        R, effort = kinetostatics.closed_form(mech, st, W)
    else:
        R, effort = {}, kinetostatics.virtual_effort(mech, st, W)
    if mech.friction.joints:  # declared, every mu 0
        R = friction.unsolved(mech, st, R, effort, omega, plan.static)
    return R, effort


def every_load(mech, given: tuple, loads: list) -> list:
    """The value of each of ``mech.loads``, in order, from ``loads`` (the input loads,
    then the loads over the cycle named in ``given``): None for a load over the cycle
    not given (computed at the state).

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> every_load(presets.get("four_bar"), (), [3.0])
    [3.0]
    """
    if not mech.computed_loads:
        return loads
    named = dict(zip(given, loads[len(mech.input_loads):]))
    inputs = iter(loads)
    return [named.get(ld.name) if ld.computed else next(inputs) for ld in mech.loads]


def at_state(mech, theta, omega, alpha, order: int, xp) -> tuple:
    """``(st, omega, alpha)``: the kinematics of a state to ``order`` (:func:`split`'s
    ``theta``, ``omega``, ``alpha``) and the crank speed and acceleration its
    coefficients are taken at: the crank's own, or for a linkage driven by time 1 and 0,
    its ``d1``, ``d2`` being the velocities and accelerations.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> four = presets.get("four_bar")
    >>> st, omega, alpha = at_state(four, 0.5, 10.0, 0.0, 0, None)
    >>> omega, alpha, sorted(st.p)[:2]
    (10.0, 0.0, ['A', 'B'])
    """
    if mech.rates:  # d1, d2 are the velocities and accelerations: unit speed, time
        return kinematics(mech, theta, order, xp, tuple(zip(omega, alpha))), 1.0, 0.0
    return kinematics(mech, theta, order, xp), omega, alpha


def evaluate(mech, plan, theta, omega, alpha, loads, xp) -> tuple[dict, KinematicState]:
    """The outputs of ``plan`` (and whatever it computes besides) on numbers of the
    namespace ``xp``, and the kinematic state: the one sequence of formulas behind every
    path, floats, arrays, mpmath and the traced kernels.

    ``plan`` (:class:`~linkage_fmu.solver.Plan`) says which outputs, whether the scene
    is static (``omega = alpha = 0``: no derivative kinematics, no inertia) and the
    method (``direct``: the assembled linear system; otherwise group by group); the
    effort alone needs no reactions (virtual power). ``loads`` are the input loads, then
    the loads over the cycle the plan's ``given`` names. ``mech.solve`` and
    ``mech.table`` make the plan (``mech.solver.plan``) and call this; use them.
    """
    st, omega, alpha = at_state(mech, theta, omega, alpha, order(mech, plan), xp)
    R, effort = {}, 0.0
    if plan.reactions or plan.effort:
        loads = every_load(mech, plan.given, loads)
        W = wrenches(mech, st, omega, alpha, loads, plan.static)
        R, effort = reactions(mech, st, W, plan, omega, xp)
        if "eta" in plan.outputs and mech.friction.joints:  # what each source puts in
            R.sources = powers(mech, st, omega, alpha, loads, plan.static)
    out = {}
    for name, fn in mech.output_functions:
        if name in plan.outputs:
            out[name] = fn(R, effort, st)
    if plan.diagnostics:
        out.update(diagnostics.values(mech, st, plan.outputs))
    return out, st
