"""The inertia of a linkage reduced to its crank, and its derivative: what the equation
of motion of a crank-driven linkage (Eksergian's) needs, from the linkage's own
kinematics; and, for a linkage with several drivers, its mass matrix reduced to their
coordinates.
"""

from __future__ import annotations

import numpy as np

from .drivers import one_crank
from .errors import InputError
from .expressions import evaluate
from .numerics import ARRAY, finite_array


def reduced_inertia(mech, theta, xp=None) -> tuple:
    """The moment of inertia of the whole linkage reduced to the crank, ``J``, and
    its derivative ``dJ`` with respect to the crank angle.

    The kinetic energy of the moving links is ``T = J(theta) * omega**2 / 2`` with
    ``J = sum(m_i |v_Si / omega|**2 + J_Si (omega_i / omega)**2)`` over the bodies.
    The first derivative coefficients of the linkage's kinematics
    (:meth:`~linkage_fmu.mechanism.Mechanism.kinematics`) are those velocity ratios, and
    its second ones their derivatives, so ``dJ = 2 sum(m_i v_Si . a_Si
    + J_Si omega_i eps_i)`` taken at ``omega = 1``, ``alpha = 0``: exact, no finite
    differences. With no loads and no gravity the balancing moment on the crank is
    ``Mb = J * alpha + dJ / 2 * omega**2``.

    Parameters
    ----------
    mech : Mechanism
        The linkage (this module imports nothing of :mod:`~linkage_fmu.mechanism`,
        which calls it).
    theta : float, array_like or str
        Crank angle(s) [rad]; text with a unit (``"30 deg"``) is taken in SI.
    xp : namespace, optional
        Evaluate on the numbers of this namespace (e.g.
        :data:`linkage_fmu.precise.MP` with ``theta`` an mpmath number); default:
        floats for a scalar ``theta``, arrays otherwise.

    Returns
    -------
    J, dJ : float or ndarray
        ``J`` [kg m2] and ``dJ/dtheta`` [kg m2/rad]: floats for a scalar ``theta``,
        arrays of its shape otherwise, NaN where the linkage cannot be assembled.

    Raises
    ------
    AssemblyError
        Scalar ``theta`` at which the linkage cannot be assembled (as ``Mechanism.solve``).
    ValueError
        ``theta`` not finite, naming it.

    Examples
    --------
    >>> import math
    >>> from linkage_fmu import presets
    >>> yoke = presets.get("scotch_yoke")   # block 4 kg at the pin, yoke 10 kg
    >>> J, dJ = yoke.reduced_inertia(math.pi / 4)   # (4 + 10 cos^2) * 0.1^2
    >>> round(J, 12), round(dJ, 12)           # dJ = -10 * 0.1^2 * sin(2 theta)
    (0.09, -0.1)
    >>> yoke.reduced_inertia([0.0, math.pi / 2])[0].round(12)
    array([0.14, 0.04])
    """
    one_crank(mech, "the inertia reduced to the crank")
    if isinstance(theta, str):  # a number with a unit, an expression
        theta = evaluate(theta, "rad", "theta")
    if xp is None and np.ndim(theta) != 0:
        theta = finite_array("theta", theta)
        with np.errstate(divide="ignore", invalid="ignore"):
            J, dJ = reduced_inertia(mech, theta, ARRAY)
        zeros = np.zeros(theta.shape)
        J, dJ = J + zeros, dJ + zeros  # arrays of theta's shape, a link at rest too
        return J, dJ
    return at_state(mech, mech.kinematics(theta, 2, xp))


def at_state(mech, st, derivative: bool = True) -> tuple:
    """``(J, dJ)`` of :func:`reduced_inertia` at the kinematic state ``st`` of ``mech``
    (first-order coefficients; second-order ones for ``dJ``, which is None without
    ``derivative``): what the linkage's kernels compute as the outputs ``J_red`` and
    ``dJ_red``.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> yoke = presets.get("scotch_yoke")
    >>> J, dJ = at_state(yoke, yoke.kinematics(0.0, order=1), derivative=False)
    >>> round(J, 12), dJ
    (0.14, None)
    """
    J, dJ = 0.0, (0.0 if derivative else None)
    for body in mech.bodies:
        if body.mass:
            x1, y1 = st.d1[body.cg]
            J = J + body.mass * (x1 * x1 + y1 * y1)
            if derivative:
                x2, y2 = st.d2[body.cg]
                dJ = dJ + 2.0 * body.mass * (x1 * x2 + y1 * y2)
        if body.inertia:
            w1 = st.w1[body.name]
            J = J + body.inertia * (w1 * w1)
            if derivative:
                dJ = dJ + 2.0 * body.inertia * (w1 * st.w2[body.name])
    if st.invalid is not None:  # arrays: NaN where it cannot be assembled
        J = np.where(st.invalid, np.nan, J)
        if derivative:
            dJ = np.where(st.invalid, np.nan, dJ)
    return J, dJ


def mass_matrix(mech, q) -> np.ndarray:
    """The mass matrix ``M(q)`` reduced to the drivers' coordinates: the kinetic energy
    of the moving links is ``T = qdot @ M @ qdot / 2`` for the drivers' speeds
    ``qdot``, with ``M[k, l] = sum(m_i v_Si,k . v_Si,l + J_Si w_i,k w_i,l)``, the
    velocities at unit speed of driver ``k`` alone (from the linkage's own kinematics:
    exact, no finite differences). With one crank on the frame it is ``[[J_red]]``.

    Parameters
    ----------
    mech : Mechanism
        The linkage.
    q : float or sequence
        The drivers' coordinates (the crank angle, for one crank), each a float or an
        array (of one shape).

    Returns
    -------
    ndarray
        ``(n, n)`` for n drivers, or ``(..., n, n)`` for arrays of coordinates (NaN
        where the linkage cannot be assembled); symmetric.

    Raises
    ------
    AssemblyError
        Scalar coordinates at which the linkage cannot be assembled.
    InputError
        Not one coordinate per driver.

    Examples
    --------
    Two cranks of a five-bar at rest: the coupler's mass couples them.

    >>> from pathlib import Path
    >>> import linkage_fmu
    >>> five = linkage_fmu.load(Path(linkage_fmu.__file__).parents[2] /
    ...                         "examples/five_bar.toml")
    >>> M = five.mass_matrix((1.9, 1.2))
    >>> M.shape, bool(abs(M[0, 1] - M[1, 0]) < 1e-15), bool(M[0, 1] != 0.0)
    ((2, 2), True, True)
    """
    n = len(mech.drivers)
    if not mech.rates:
        J, _ = reduced_inertia(mech, q[0] if np.ndim(q) and n == 1 and
                               not isinstance(q, np.ndarray) else q)
        return np.asarray(J, dtype=float)[..., None, None]
    if isinstance(q, (str, bytes)) or not hasattr(q, "__len__") or len(q) != n:
        raise InputError(f"{mech.name}: the mass matrix takes one coordinate per driver "
                         f"({', '.join(d.inputs[0] for d in mech.drivers)}), got {q!r}")
    q = tuple(q)
    columns = []  # per driver: each body's (v_S, w) at its unit speed
    for k in range(n):
        rates = tuple((1.0 if j == k else 0.0, 0.0) for j in range(n))
        st = mech.kinematics(q, order=1, rates=rates)
        columns.append([(st.d1[b.cg], st.w1[b.name]) for b in mech.bodies])
    shape = np.broadcast(*q).shape if any(np.ndim(v) for v in q) else ()
    M = np.zeros(shape + (n, n))
    for k in range(n):
        for j in range(k, n):
            total = 0.0
            for body, (vk, wk), (vj, wj) in zip(mech.bodies, columns[k], columns[j]):
                total = total + body.mass * (vk[0] * vj[0] + vk[1] * vj[1]) + \
                    body.inertia * wk * wj
            M[..., k, j] = M[..., j, k] = total
    if shape and st.invalid is not None:
        M[np.asarray(st.invalid)] = np.nan
    return M
