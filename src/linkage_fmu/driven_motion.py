"""The motion of a linkage driven by several actuators under given efforts: the
kinetostatics run backwards, in the drivers' coordinates.

Each driver's effort (a crank's or motor's moment, a cylinder's force) is affine in the
drivers' accelerations: ``E(q, qdot, qddot) = E(q, qdot, 0) + M(q) qddot``, ``M`` the mass
matrix reduced to the drivers (:func:`~linkage_fmu.inertia.mass_matrix`). Efforts ``u``
applied at the drivers thus give ``qddot = M(q)^-1 (u - E(q, qdot, 0))``: Eksergian's
equation of motion, in n coordinates.
"""

from __future__ import annotations

import numpy as np

from .errors import AssemblyError, ComputationError, InputError, SingularPositionError
from .expressions import evaluate
from .numerics import finite_array, finite_float


def simulate(mech, efforts, t, q0=None, v0=None, rtol: float = 1e-10, atol: float = 1e-10,
             **loads):
    """The motion of the linkage driven by time (several drivers, a motor, a cylinder)
    under the efforts ``efforts`` at its drivers, and every output of ``solve`` along it.

    Integrates ``q' = v``, ``v' = M(q)^-1 (u(t, q, v) - E(q, v, 0))`` with scipy's
    ``solve_ivp`` (DOP853), ``E`` the efforts the linkage needs at zero acceleration
    (its effort-only solve) and ``M`` its mass matrix.

    Parameters
    ----------
    mech : Mechanism
        A linkage driven by time (``mech.rates``), without friction (refused so far).
    efforts : sequence or dict
        One effort per driver, in the drivers' order (or a dict by effort name,
        ``{"Mb_A": ..., "Fb_P": ...}``): the moment a crank or motor applies to its
        link [N m] or the force a cylinder applies to its rod [N], each a number; one
        value per entry of ``t``, interpolated linearly; or ``f(t, q, v)`` of the time
        and the drivers' coordinates and speeds (arrays), returning a float.
    t : array_like
        The output times [s]: at least 2, finite and strictly increasing.
    q0, v0 : sequence, optional
        The drivers' coordinates [rad or m] and speeds at ``t[0]`` (``theta0`` and
        ``omega0`` of :meth:`Mechanism.simulate <linkage_fmu.mechanism.Mechanism.simulate>`);
        default: the linkage's start values (``mech.start``). Text with a unit is taken
        in SI.
    rtol, atol : float
        The integrator's tolerances.
    **loads : float or str
        The input loads by name, constant over the motion.

    Returns
    -------
    pandas.DataFrame
        Indexed by ``t`` (``time``): each driver's coordinate, speed and acceleration
        (named as its inputs), then every output of ``solve`` along the motion, whose
        efforts equal those applied up to rounding.

    Raises
    ------
    InputError
        A bad ``t``, effort, start or load, naming it; a driver that moves no inertia;
        friction.
    AssemblyError, SingularPositionError
        The motion reaches a pose at which the linkage cannot be assembled, or at which
        its mass matrix is not finite or not positive definite to rounding (a singular
        position), naming it and the time; no rows are returned.

    Examples
    --------
    The dump body held by its cylinder's static force stays where it starts:

    >>> from pathlib import Path
    >>> import linkage_fmu
    >>> dump = linkage_fmu.load(Path(linkage_fmu.__file__).parents[2] /
    ...                         "examples/dump_body.toml")
    >>> hold = dump.solve(s_P=0.1, v_P=0.0, W=5000.0)["Fb_P"]
    >>> run = dump.simulate([hold], [0.0, 0.5], [0.1], [0.0], W=5000.0)
    >>> list(run.columns[:3]), round(float(run["s_P"].iloc[-1]), 9)
    (['s_P', 'v_P', 'a_P'], 0.1)
    """
    import pandas as pd
    from scipy.integrate import solve_ivp

    drivers = mech.drivers
    n = len(drivers)
    if mech.friction.active:  # E is then not affine in the accelerations
        raise InputError(f"{mech.name}: simulate moves a linkage driven by time without "
                         "friction, so far (with friction its efforts are not affine in "
                         "the accelerations); set every mu to 0")
    t = times(t)
    applied = _efforts(mech, efforts, t)
    q0 = _starts(mech, "q0", q0, 0)
    v0 = _starts(mech, "v0", v0, 1)
    names = tuple(d.effort for d in drivers)
    mech.solve(**_state(drivers, q0, v0), outputs=names, **loads)  # the loads, checked

    def acceleration(ti, q, v):
        try:
            sol = mech.solve(**_state(drivers, q, v), outputs=names, **loads)
            M = mech.mass_matrix(tuple(q))
        except (AssemblyError, SingularPositionError) as err:
            why = err.condition if isinstance(err, AssemblyError) else \
                str(err).split(": ", 1)[-1]
            raise type(err)(mech.name, err.theta, f"{why} (reached at t = {ti:.9g} s)") \
                from None
        u = np.array([f(ti, q, v) for f in applied])
        if not np.isfinite(M).all():  # a velocity without bound: at a toggle
            raise SingularPositionError(
                mech.name, {d.inputs[0]: float(x) for d, x in zip(drivers, q)},
                f"its mass matrix reduced to the drivers is not finite (reached at t = "
                f"{ti:.9g} s)")
        try:
            chol = np.linalg.cholesky(M)
        except np.linalg.LinAlgError:
            if np.any(np.diag(M) <= 0.0):
                raise InputError(f"{mech.name}: its mass matrix reduced to the drivers is "
                                 f"not positive definite at {_words(drivers, q)}: a driver "
                                 "moves no inertia; the motion is not defined") from None
            raise SingularPositionError(
                mech.name, {d.inputs[0]: float(x) for d, x in zip(drivers, q)},
                f"its mass matrix reduced to the drivers is not positive definite to "
                f"rounding (a singular position; reached at t = {ti:.9g} s)") from None
        rhs = u - np.array([sol[e] for e in names])
        return np.linalg.solve(chol.T, np.linalg.solve(chol, rhs))

    def rhs(ti, y):
        q, v = y[:n], y[n:]
        return np.concatenate([v, acceleration(ti, q, v)])

    res = solve_ivp(rhs, (t[0], t[-1]), np.concatenate([q0, v0]), method="DOP853",
                    t_eval=t, rtol=rtol, atol=atol)
    if res.status != 0:
        raise ComputationError(f"{mech.name}: the integration failed: {res.message}")
    q, v = res.y[:n], res.y[n:]
    a = np.array([acceleration(ti, q[:, k], v[:, k]) for k, ti in enumerate(t)]).T
    out = {}
    for k, d in enumerate(drivers):
        out.update(zip(d.inputs, (q[k], v[k], a[k])))
    sol = mech.solve(**out, **loads)
    out.update((k, np.asarray(val)) for k, val in sol.items())
    return pd.DataFrame(out, index=pd.Index(t, name="time"))


def times(t) -> np.ndarray:
    """The output times ``t``, checked: a 1-d array of at least 2, finite and strictly
    increasing.

    Examples
    --------
    >>> times([0.0, 0.5]).tolist()
    [0.0, 0.5]
    """
    t = np.asarray(finite_array("t", t), dtype=float)
    if t.ndim != 1 or t.size < 2:
        raise InputError(f"t must be a 1-d array of at least 2 times, got shape {t.shape}")
    step = np.diff(t)
    if not (step > 0).all():
        k = int(np.argmin(step > 0)) + 1
        raise InputError(f"t must be strictly increasing: t[{k}] = {float(t[k])!r} <= "
                         f"t[{k - 1}] = {float(t[k - 1])!r}")
    return t


def _state(drivers, q, v) -> dict:
    """The solve's keywords: each driver's coordinate and speed, no acceleration."""
    out = {}
    for d, qk, vk in zip(drivers, q, v):
        out.update(zip(d.inputs, (float(qk), float(vk), 0.0)))
    return out


def _words(drivers, q) -> str:
    return ", ".join(f"{d.inputs[0]} = {float(x):.6g}" for d, x in zip(drivers, q))


def _efforts(mech, efforts, t: np.ndarray) -> list:
    """Each driver's effort as a function ``(t, q, v) -> float``."""
    drivers = mech.drivers
    names = [d.effort for d in drivers]
    if isinstance(efforts, dict):
        unknown = sorted(set(efforts) - set(names))
        missing = [n for n in names if n not in efforts]
        if unknown or missing:
            raise InputError(f"{mech.name}: efforts must give each driver's, "
                             f"{', '.join(names)}"
                             + (f"; unknown: {', '.join(map(str, unknown))}" if unknown else "")
                             + (f"; missing: {', '.join(missing)}" if missing else ""))
        efforts = [efforts[n] for n in names]
    elif callable(efforts) or isinstance(efforts, (str, bytes)) or \
            not hasattr(efforts, "__len__") or len(efforts) != len(drivers):
        raise InputError(f"{mech.name}: efforts must be one per driver ({', '.join(names)}): "
                         f"a sequence of {len(drivers)} or a dict by name, got {efforts!r}")
    return [_effort(name, spec, t) for name, spec in zip(names, efforts)]


def _effort(name: str, spec, t: np.ndarray):
    if callable(spec):
        def effort(ti, q, v):
            return finite_float(f"{name}(t, q, v)", float(spec(ti, q, v)))
        return effort
    if np.ndim(spec) == 0:
        value = finite_float(name, spec.item() if isinstance(spec, np.ndarray) else spec)
        return lambda ti, q, v: value
    values = finite_array(name, spec)
    if values.shape != t.shape:
        raise InputError(f"{name} must be a number, a callable or one value per time: "
                         f"{t.size} values, got shape {values.shape}")
    return lambda ti, q, v: float(np.interp(ti, t, values))


def _starts(mech, key: str, given, which: int) -> np.ndarray:
    """The drivers' coordinates (``which`` 0) or speeds (1) at the start."""
    drivers = mech.drivers
    if given is None:
        return np.array([float(mech.start.get(d.inputs[which], 0.0)) for d in drivers])
    if isinstance(given, (str, bytes)) or not hasattr(given, "__len__") or \
            len(given) != len(drivers):
        raise InputError(f"{key} must give each driver's "
                         f"{'coordinate' if which == 0 else 'speed'} "
                         f"({', '.join(d.inputs[which] for d in drivers)}), got {given!r}")
    out = []
    for d, value in zip(drivers, given):
        name = f"{d.inputs[which]} of {key}"
        if isinstance(value, str):
            value = evaluate(value, d.units[which], name)
        out.append(finite_float(name, value))
    return np.array(out)
