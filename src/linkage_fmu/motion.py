"""The motion of a crank-driven linkage under a given driving torque: the kinetostatics
run backwards.

The balancing moment on the crank is affine in the crank acceleration,
``Mb(theta, omega, alpha, loads) = Mb(theta, omega, 0, loads) + J(theta) * alpha`` with
``J`` the inertia reduced to the crank (:mod:`~linkage_fmu.inertia`), so a motor torque
``tau`` gives ``alpha = (tau - Mb(theta, omega, 0, loads)) / J(theta)`` (Eksergian's
equation of motion; with no loads and no gravity ``Mb(theta, omega, 0) = dJ/2 omega**2``).
A flywheel on the crank adds its constant inertia to ``J``.
"""

from __future__ import annotations

import numpy as np

from .errors import AssemblyError, SingularPositionError
from .expressions import evaluate
from .numerics import finite_array, finite_float


def simulate(mech, tau, t, theta0=None, omega0=None, rtol: float = 1e-10,
             atol: float = 1e-10, flywheel=0.0, **loads):
    """The motion of the linkage driven by the moment ``tau`` on its crank, and every
    output of :meth:`~linkage_fmu.mechanism.Mechanism.solve` along it.

    Integrates ``theta' = omega``, ``omega' = (tau - Mb(theta, omega, 0, loads)) /
    (J(theta) + flywheel)`` with scipy's ``solve_ivp`` (DOP853), each step evaluating the
    balancing moment alone (the effort-only plan) and the reduced inertia.

    Parameters
    ----------
    mech : Mechanism
        A linkage whose balancing effort is a moment on the crank (``Mb``).
    tau : float, array_like or callable
        The moment the motor applies to the crank [N m], counter-clockwise positive: a
        constant; one value per entry of ``t``, interpolated linearly between them; or
        ``tau(t, theta, omega)`` returning a float.
    t : array_like
        The output times [s]: at least 2, finite and strictly increasing; the motion
        starts at ``t[0]``.
    theta0, omega0 : float or str, optional
        The crank angle [rad] and speed [rad/s] at ``t[0]``; default: the linkage's start
        values (``mech.start``: its description's, 0 where it gives none). Text with a
        unit (``"30 deg"``, ``"100 rpm"``) is taken in SI.
    rtol, atol : float
        The integrator's relative and absolute tolerances (on ``theta`` [rad] and
        ``omega`` [rad/s]). The default ``atol`` is not smaller on purpose: with
        ``atol = 1e-12`` a slider-crank at 470 rad/s took steps whose error DOP853
        misjudged (energy balance off by 3e-6 relative, 1.5e-9 with ``atol = 1e-10``).
    flywheel : float or str
        The moment of inertia of a flywheel on the crank [kg m2], >= 0 (text with a unit,
        ``"2.5 kg*m**2"``, is taken in SI); default none.
    **loads : float or str
        The input loads by name, constant over the motion, as ``solve`` takes them (a
        load not given takes its start value; a load over the cycle is computed by the
        linkage at each state unless given).

    Returns
    -------
    pandas.DataFrame
        Indexed by ``t`` (index name ``time``): ``theta``, ``omega``, ``alpha`` (of the
        motion), ``tau``, every output and diagnostic of ``solve`` at ``(theta, omega,
        alpha)`` (so ``Mb`` equals ``tau - flywheel * alpha`` up to rounding: the moment
        the linkage takes from the crank, the flywheel taking the rest), and ``J_red``
        [kg m2], the linkage's own (the flywheel's not in it).

    Raises
    ------
    ValueError
        ``t``, ``tau``, ``theta0``, ``omega0``, ``flywheel`` or a load invalid, naming
        it; a linkage whose effort is not a moment on its crank, with no inertia
        reduced to the crank, or with friction in its joints (not modelled here yet).
    AssemblyError, SingularPositionError
        The motion reaches (or the integrator tries) a crank angle at which the linkage
        cannot be assembled, or is singular: raised, naming the time and the angle, no
        rows returned (nothing is silently cut short).
    RuntimeError
        The integrator fails (its message).

    Examples
    --------
    >>> import numpy as np
    >>> from linkage_fmu import presets
    >>> yoke = presets.get("scotch_yoke")      # J = (4 + 10 cos^2 theta) * 0.1^2
    >>> run = yoke.simulate(2.0, np.linspace(0.0, 0.5, 6), theta0=0.0, omega0=1.0, load=0.0)
    >>> list(run.columns[:4]), run.index.name
    (['theta', 'omega', 'alpha', 'tau'], 'time')
    >>> a0 = float(run["alpha"].iloc[0])        # 2 / J(0), dJ(0) = 0: no speed term
    >>> round(a0, 12), round(float(run["Mb"].iloc[-1]), 9)        # Mb along it is tau
    (14.285714285714, 2.0)
    """
    import pandas as pd
    from scipy.integrate import solve_ivp

    effort = crank_moment(mech, "simulate drives the crank with a moment")
    t = np.asarray(finite_array("t", t), dtype=float)
    if t.ndim != 1 or t.size < 2:
        raise ValueError(f"t must be a 1-d array of at least 2 times, got shape {t.shape}")
    step = np.diff(t)
    if not (step > 0).all():
        k = int(np.argmin(step > 0)) + 1
        raise ValueError(f"t must be strictly increasing: t[{k}] = {float(t[k])!r} <= "
                         f"t[{k - 1}] = {float(t[k - 1])!r}")
    torque = _torque(tau, t)
    theta0 = _start(mech, "theta", theta0, "rad")
    omega0 = _start(mech, "omega", omega0, "rad/s")
    extra = finite_float("flywheel", evaluate(flywheel, "kg.m2", "flywheel")
                         if isinstance(flywheel, str) else flywheel)
    if extra < 0.0:
        raise ValueError(f"flywheel must be >= 0 (a moment of inertia, kg m2), got {extra!r}")
    named = constant_loads(mech, loads)

    def acceleration(ti, th, w):
        try:
            m0 = mech.solve(th, w, 0.0, outputs=(effort,), **named)[effort]
            J = mech.reduced_inertia(th)[0] + extra
        except (AssemblyError, SingularPositionError) as err:
            raise type(err)(mech.name, th, f"{_why(err)} "
                            f"(reached at t = {ti:.9g} s)") from None
        if not J > 0.0:
            with_flywheel = f" (a flywheel of {extra!r} kg m2 included)" if extra else ""
            raise ValueError(f"{mech.name}: the inertia reduced to the crank is {J!r} at "
                             f"theta = {th!r} rad{with_flywheel}; the motion is not defined")
        return (torque(ti, th, w) - m0) / J

    def rhs(ti, y):
        th, w = float(y[0]), float(y[1])
        return [w, acceleration(ti, th, w)]

    res = solve_ivp(rhs, (t[0], t[-1]), [theta0, omega0], method="DOP853", t_eval=t,
                    rtol=rtol, atol=atol)
    if res.status != 0:
        raise RuntimeError(f"{mech.name}: the integration failed: {res.message}")
    theta, omega = res.y
    alpha = np.array([acceleration(*s) for s in zip(t, theta, omega)])
    sol = mech.solve(theta, omega, alpha, **named)
    out = {"theta": theta, "omega": omega, "alpha": alpha,
           "tau": np.array([torque(*s) for s in zip(t, theta, omega)])}
    out.update((k, np.asarray(v)) for k, v in sol.items())
    out["J_red"] = mech.reduced_inertia(theta)[0]
    return pd.DataFrame(out, index=pd.Index(t, name="time"))


def crank_moment(mech, job: str) -> str:
    """The name of the balancing effort of ``mech``, or a ValueError saying that it
    does not act on the crank as a moment, which ``job`` needs.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> crank_moment(presets.get("four_bar"), "simulate drives the crank with a moment")
    'Mb'
    """
    if not mech.effort_on_crank:
        raise ValueError(f"{mech.name}: its balancing effort {mech.effort.name} does not act "
                         f"on the crank; {job}")
    if mech.friction.active:  # the acceleration would solve a nonlinear equation
        raise ValueError(f"{mech.name}: its joints have friction (a mu is not 0), which the "
                         f"equations of motion do not model yet; {job} without it")
    return mech.effort.name


def constant_loads(mech, loads: dict) -> dict:
    """The loads given by name, checked (a TypeError names one the linkage does not
    have), text with units taken in SI: each input load (its start value where not
    given) and each load over the cycle that is given, as finite floats.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> constant_loads(presets.get("four_bar"), {"load": "2 N*m"})
    {'load': 2.0}
    """
    values, given = mech.inputs(0.0, 0.0, (), loads)
    return {name: finite_float(name, v) for name, v in zip(
        [ld.name for ld in mech.input_loads] + list(given), values[2:])}


def _why(err) -> str:
    return err.condition if isinstance(err, AssemblyError) else str(err).split(": ", 1)[-1]


def _start(mech, name: str, value, unit: str) -> float:
    key = f"{name}0"
    if value is None:
        return finite_float(key, float(mech.start.get(name, 0.0)))
    if isinstance(value, str):
        value = evaluate(value, unit, key)
    return finite_float(key, value)


def _torque(tau, t: np.ndarray):
    """``tau`` as a function ``(t, theta, omega) -> float``."""
    if callable(tau):
        def torque(ti, th, w):
            return finite_float("tau(t, theta, omega)", float(tau(ti, th, w)))
        return torque
    if np.ndim(tau) == 0:
        value = finite_float("tau", tau.item() if isinstance(tau, np.ndarray) else tau)
        return lambda ti, th, w: value
    values = finite_array("tau", tau)
    if values.shape != t.shape:
        raise ValueError(f"tau must be a number, a callable or one value per time: "
                         f"{t.size} values (t has {t.size}), got shape {values.shape}")
    return lambda ti, th, w: float(np.interp(ti, t, values))
