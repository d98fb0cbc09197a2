"""The inertia of a linkage reduced to its crank, and its derivative: what the equation
of motion of a crank-driven linkage (Eksergian's) needs, from the linkage's own
kinematics.
"""

from __future__ import annotations

import numpy as np

from .drivers import one_crank
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
