"""Joint reactions and balancing effort from the equations of every moving link.

Every moving link obeys three equations (forces x, y and moment about its centre of
mass) under the known wrench of :mod:`~linkage_fmu.loads` and the unknown reactions
of its joints. The unknowns are, per revolute pair, the force ``(Fx, Fy)`` of body
``a`` on body ``b``; per prismatic pair, the normal force ``N`` along the pair's
normal and the couple ``M`` of ``a`` on ``b``; and the balancing effort (a moment on a
link, or a force on a slider). Three solutions of the same equations:

* :func:`closed_form`: group by group from the last Assur group back to the crank, a
  few closed-form expressions per group and no global matrix (the fast path);
* :func:`direct`: the full system ``A x = b`` assembled and LU-solved, batched over
  states (the reference, as the source documents do it);
* :func:`virtual_effort`: the balancing effort alone, from the power balance on the
  first-order kinematic coefficients (no reactions at all).

Reactions are returned as a dict joint name -> ``(c0, c1)``: ``(Fx, Fy)`` for a
revolute pair, ``(N, M)`` for a prismatic pair.
"""

from __future__ import annotations

import numpy as np

from . import linalg
from .groups import KinematicState
from .groups.base import moment_about, push
from .numerics import Number


def add_effort(mech, st: KinematicState, W: dict, effort: Number) -> None:
    """Add the balancing ``effort`` to the wrench of the body it acts on."""
    e = mech.effort
    if e.direction is None:
        W[e.body][2] = W[e.body][2] + effort
    else:
        push(mech, st, W, e.body, e.point, effort * e.direction[0], effort * e.direction[1])


def state_count(mech, st: KinematicState) -> int:
    """How many states ``st`` holds: 1 on numbers, the size of its coordinates' arrays
    (broadcast together, for several drivers)."""
    if st.xp.scalar:
        return 1
    return np.broadcast(*st.theta).size if mech.rates else np.size(st.theta)


def closed_form(mech, st: KinematicState, W: dict):
    """Reactions and balancing effort, group by group from the last back to the crank.

    With the effort on the crank, the crank's moment equation gives it last. With the
    effort elsewhere (another link, or a slider), it comes first from
    :func:`virtual_effort` and then acts as a known load; the crank's moment equation is
    then satisfied identically. ``W`` is consumed (reactions are added into it).

    Returns
    -------
    (dict, float or ndarray)
        Reactions by joint name, and the balancing effort.

    Examples
    --------
    >>> import math
    >>> from linkage_fmu import presets
    >>> from linkage_fmu.loads import wrenches
    >>> mech = presets.get("scotch_yoke")
    >>> st = mech.kinematics(math.radians(60), order=2)
    >>> R, Mb = closed_form(mech, st, wrenches(mech, st, 10.0, 0.0, (400.0,), static=False))
    >>> round(Mb, 4), round(R["slot"][0], 4)
    (15.6699, 313.3975)
    """
    if mech.rates:  # each driver's effort, from its own group's equations
        R, efforts = {}, [None] * len(mech.drivers)
        for g in reversed(mech.groups):
            effort = g.statics(mech, st, W, R)
            if g.DRIVER:
                efforts[g.index] = effort
        return R, tuple(efforts)
    effort = None
    if not mech.effort_on_crank:
        effort = virtual_effort(mech, st, W)
        add_effort(mech, st, W, effort)
    R: dict = {}
    for g in reversed(mech.groups):
        moment = g.statics(mech, st, W, R)
    # the crank, solved last, returns the moment the drive must add about its pivot
    return R, (moment if effort is None else effort)


def virtual_effort(mech, st: KinematicState, W: dict):
    """Balancing effort from virtual power: ``effort * q' + sum(F . S' + M * phi') = 0``.

    ``q'`` is the effort's own first-order coefficient (``phi'`` of its link, or the
    slider's velocity coefficient along the force). Needs first-order kinematics only.

    Examples
    --------
    >>> import math
    >>> from linkage_fmu import presets
    >>> from linkage_fmu.loads import wrenches
    >>> mech = presets.get("scotch_yoke")
    >>> st = mech.kinematics(math.radians(60), order=2)
    >>> round(virtual_effort(mech, st, wrenches(mech, st, 10.0, 0.0, (400.0,), False)), 4)
    15.6699
    """
    power = 0.0
    for body in mech.bodies:
        fx, fy, m = W[body.name]
        x1, y1 = st.d1[body.cg]
        power = power + fx * x1 + fy * y1 + m * st.w1[body.name]
    return -power / effort_coefficient(mech, st)


def effort_coefficient(mech, st: KinematicState):
    """First-order coefficient of the balancing effort's own motion (``q'``)."""
    e = mech.effort
    if e.direction is None:
        return st.w1[e.body]
    x1, y1 = st.d1[e.point]
    return e.direction[0] * x1 + e.direction[1] * y1


def equilibrium_entries(mech, st: KinematicState, W: dict | None = None,
                        about: dict | None = None, scale=None):
    """The equations of all moving links as the nonzero entries of ``A x = b``.

    Rows: per moving body, forces x, y and the moment about its centre of mass (or the
    point ``about[body]``) divided by the length scale ``L`` (``scale``, by default the
    mechanism's; 1 gives the equations in SI units). Columns: the joint reactions in
    ``mech.joints`` order (couples of prismatic pairs divided by ``L``), then each of
    ``mech.efforts`` (divided by ``L`` if it is a moment; a driver's reaction on its
    base with the opposite sign). This scaling keeps every
    entry of ``A`` of order one. Values are whatever ``st`` and ``W`` hold (floats,
    arrays over states, traced or mpmath numbers).

    Returns
    -------
    n : int
        Number of equations (and unknowns).
    a : list of (row, column, value)
    b : list of (row, value), empty when ``W`` is None

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("slider_crank")
    >>> n, a, b = equilibrium_entries(mech, mech.kinematics(0.3, order=0))
    >>> n, len(a), b
    (9, 25, [])
    """
    L = mech.length_scale if scale is None else scale
    rows = {b.name: 3 * i for i, b in enumerate(mech.bodies)}
    centre = dict(mech.cg, **(about or {}))
    a = []

    def arm(point, body):
        (px, py), (sx, sy) = st.p[point], st.p[centre[body]]
        return (px - sx) / L, (py - sy) / L

    col = 0
    for j in mech.joints:
        for body, sign in ((j.b, 1.0), (j.a, -1.0)):
            if body == mech.frame:
                continue
            a += j.entries(st, rows[body], col, sign, arm(j.point, body))
        col += 2
    for e in mech.efforts:
        # the effort on its body, its reaction (a driver's) on its base
        for body, sign in ((e.body, 1.0), (e.base, -1.0)):
            if not body or body == mech.frame:
                continue
            r = rows[body]
            if e.direction is None:
                a.append((r + 2, col, sign))
                continue
            dx, dy = st.u[e.direction] if isinstance(e.direction, str) else e.direction
            ax, ay = arm(e.point, body)
            a += [(r, col, sign * dx), (r + 1, col, sign * dy),
                  (r + 2, col, sign * (ax * dy - ay * dx))]
        col += 1
    b = []
    if W is not None:
        for body in mech.bodies:
            r = rows[body.name]
            fx, fy, m = W[body.name]
            if centre[body.name] != mech.cg[body.name]:  # W's moment is about the cg
                fx, fy, m = moment_about(mech, st, W, body.name, centre[body.name])
            b += [(r, -fx), (r + 1, -fy), (r + 2, -m / L)]
    return 3 * len(mech.bodies), a, b


def equilibrium_system(mech, st: KinematicState, W: dict | None = None, n_states: int = 1):
    """Assemble :func:`equilibrium_entries` as numpy arrays, batched over states.

    Returns
    -------
    A : ndarray, shape (n_states, n, n)
    b : ndarray, shape (n_states, n), or None when ``W`` is None

    Examples
    --------
    >>> import numpy as np
    >>> from linkage_fmu import presets
    >>> mech = presets.get("four_bar")
    >>> A, b = equilibrium_system(mech, mech.kinematics(0.3, order=0))
    >>> A.shape, b is None, bool(np.linalg.cond(A[0]) < 100)
    ((1, 9, 9), True, True)
    """
    n, a, b = equilibrium_entries(mech, st, W)
    A = np.zeros((n_states, n, n))
    for r, c, v in a:
        A[:, r, c] = v
    if W is None:
        return A, None
    B = np.empty((n_states, n))
    for r, v in b:
        B[:, r] = v
    return A, B


def unknowns(mech, x) -> tuple[dict, object]:
    """Reactions by joint name and the balancing effort from the solution ``x`` of
    :func:`equilibrium_system`, undoing its column scaling; ``x[k]`` is unknown ``k``
    (a number, or an array over states)."""
    L = mech.length_scale
    R = {}
    col = 0
    for j in mech.joints:
        R[j.name] = (x[col], x[col + 1] * j.column_scale(L))
        col += 2
    efforts = tuple(x[col + k] * (L if e.direction is None else 1.0)
                    for k, e in enumerate(mech.efforts))
    return R, (efforts if mech.rates else efforts[0])


def direct(mech, st: KinematicState, W: dict, xp, n_states: int = 1):
    """Reactions and balancing effort by assembling ``A x = b`` and LU-solving it.

    The reference solution: the same equations as :func:`closed_form`, solved as one
    linear system per state (``numpy.linalg.solve``, batched over states, for floats
    and arrays), as the source documents do (``X = A \\ B``); a namespace ``xp`` with
    its own ``lu_solve(n, a, b)`` (:data:`linkage_fmu.precise.MP`) solves it in its own
    numbers. A singular state gives NaN/inf, not an error.

    Examples
    --------
    >>> import math
    >>> from linkage_fmu import presets
    >>> from linkage_fmu.loads import wrenches
    >>> from linkage_fmu.numerics import SCALAR
    >>> mech = presets.get("scotch_yoke")
    >>> st = mech.kinematics(math.radians(60), order=2)
    >>> R, Mb = direct(mech, st, wrenches(mech, st, 10.0, 0.0, (400.0,), static=False), SCALAR)
    >>> round(Mb, 4)
    15.6699
    """
    lu_solve = getattr(xp, "lu_solve", None)
    if lu_solve is not None:
        return unknowns(mech, lu_solve(*equilibrium_entries(mech, st, W)))
    A, b = equilibrium_system(mech, st, W, n_states)
    R, effort = unknowns(mech, linalg.solve_batch(A, b).T)
    if xp.scalar:
        R = {k: (float(a[0]), float(b[0])) for k, (a, b) in R.items()}
        effort = tuple(float(e[0]) for e in effort) if mech.rates else float(effort[0])
    return R, effort
