"""Known loads on every moving body: d'Alembert inertia, weight and the external load.

Each body's loads are reduced to a wrench ``[Fx, Fy, M]`` at its centre of mass. Terms a
scene does not have are not computed: no inertia in a static scene or for a massless
body, no weight when ``g = 0``, no external term where the load acts elsewhere.
"""

from __future__ import annotations

from .kinematics import KinematicState
from .numerics import Number


def wrenches(mech, st: KinematicState, omega: Number, alpha: Number, load: Number,
             static: bool) -> dict:
    """Wrench of all known loads on each moving body of ``mech``, about its centre of mass.

    Parameters
    ----------
    mech : Mechanism
        The linkage (bodies with mass, inertia, centre of mass; unit external loads; g).
    st : KinematicState
        Positions, and for a dynamic scene the first and second derivative coefficients.
    omega, alpha, load : float or ndarray
        Crank speed and acceleration, and the magnitude of the external load.
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
    >>> wrenches(mech, st, 0.0, 0.0, 400.0, static=True)["3"]
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
        unit = mech.unit_load.get(body.name)
        if unit is not None:
            ux, uy, um = unit
            if ux:
                fx = fx + ux * load
            if uy:
                fy = fy + uy * load
            if um:
                m = m + um * load
        out[body.name] = [fx, fy, m]
    return out
