"""The motion of a crank-driven linkage under a given driving torque: the kinetostatics
run backwards.

The balancing moment on the crank is affine in the crank acceleration,
``Mb(theta, omega, alpha, loads) = Mb(theta, omega, 0, loads) + J(theta) * alpha`` with
``J`` the inertia reduced to the crank (:mod:`~linkage_fmu.inertia`), so a motor torque
``tau`` gives ``alpha = (tau - Mb(theta, omega, 0, loads)) / J(theta)`` (Eksergian's
equation of motion; with no loads and no gravity ``Mb(theta, omega, 0) = dJ/2 omega**2``).
A flywheel on the crank adds its constant inertia to ``J``.

With friction in the joints the balancing moment is no longer affine in ``alpha`` (the
friction grows with the reactions, which hold the inertia forces): the acceleration
solves ``tau - flywheel * alpha = Mb(theta, omega, alpha)`` by Newton's method, its slope
``dMb/dalpha`` from the kernels' forward mode (:func:`moment_and_slope`), and at rest the
crank sticks while the torque lies within the friction band (:func:`simulate`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from . import driven_motion
from .drivers import one_crank
from .errors import (
    AssemblyError,
    ComputationError,
    InputError,
    OverflowInputError,
    SelfLockingError,
    SingularPositionError,
)
from .expressions import evaluate
from .numerics import finite_array, finite_float


def simulate(mech, tau, t, theta0=None, omega0=None, rtol: float = 1e-10,
             atol: float = 1e-10, flywheel=0.0, **loads):
    """The motion of the linkage driven by the moment ``tau`` on its crank, and every
    output of :meth:`~linkage_fmu.mechanism.Mechanism.solve` along it.

    Integrates ``theta' = omega``, ``omega' = (tau - Mb(theta, omega, 0, loads)) /
    (J(theta) + flywheel)`` with scipy's ``solve_ivp`` (DOP853), each step evaluating the
    balancing moment alone (the effort-only plan) and the reduced inertia. A linkage
    with friction (a ``mu`` not 0) follows the rules of the Notes below.

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
        [kg m2], the linkage's own (the flywheel's not in it). With friction, also
        ``stuck`` (bool: the crank stands held by friction), and ``attrs["switches"]``,
        the list of the :class:`Switch` es of the motion (see the Notes).

    Raises
    ------
    ValueError
        ``t``, ``tau``, ``theta0``, ``omega0``, ``flywheel`` or a load invalid, naming
        it; a linkage whose effort is not a moment on its crank, or with no inertia
        reduced to the crank.
    AssemblyError, SingularPositionError
        The motion reaches (or the integrator tries) a crank angle at which the linkage
        cannot be assembled, or is singular: raised, naming the time and the angle, no
        rows returned (nothing is silently cut short).
    SelfLockingError
        With friction: no crank acceleration balances the torque at a state the motion
        reaches (friction locks the linkage, or the moment it takes falls as the crank
        accelerates, ``dMb/dalpha + flywheel <= 0``), naming the time and the angle.
    RuntimeError
        The integrator fails (its message), or the motion switches between sticking
        and moving more than :data:`MAX_SWITCHES` times, or :data:`STALLED` times at
        one instant.

    Notes
    -----
    **Friction.** With a ``mu`` not 0, ``Mb`` depends on ``alpha`` through the
    reactions, and its friction on the direction of motion (``sign(omega)``, and where
    ``omega = 0`` the linkage's ``drive`` parameter; :mod:`~linkage_fmu.friction`).
    ``M(d; theta, omega, alpha)`` below is ``Mb`` of the linkage with ``drive = d``. The
    motion is integrated in segments, each moving in one direction ``d`` or standing:

    1. *Moving* in the direction ``d = +1`` or ``-1``: ``alpha`` solves
       ``tau(t, theta, omega) - flywheel * alpha = M(d; theta, d |omega|, alpha)`` by
       Newton's method from ``alpha = 0`` (its first step is Eksergian's formula with the
       friction at ``alpha = 0``), the slope ``dM/dalpha + flywheel`` from
       :func:`moment_and_slope`, until a step is within 4 ulp of ``alpha`` (and of the
       residual's rounding, over the slope), or, once the steps stop shrinking by half,
       within :data:`ROUNDING` of that size (the floor of ``Mb``'s rounding). The steps
       keep inside the bracket of the root that the residual's signs give (``Mb`` grows
       with ``alpha``): a step out of it, or one that has not halved after
       :data:`STALLED_STEPS` steps, bisects it, and a bracket closed to 4 ulp ends the
       iteration, as do :data:`NEWTON_STEPS` steps with a bracket (its middle is taken:
       where the torque and ``Mb``'s terms nearly cancel, the residual's sign is
       rounding within it); a slope that is not > 0, or no bracket and no convergence,
       is a ``SelfLockingError``. ``Mb`` depends on
       ``omega`` only through ``omega**2`` and the direction, so ``d |omega|`` extends
       the segment's equation smoothly past ``omega = 0`` (the integrator's stages may
       step there) with the friction of direction ``d``. The segment ends where
       ``d omega`` falls to 0, located by DOP853's dense output as a terminal event
       (to about 4 ulp of the time): the crank stops there, ``omega = 0`` exactly,
       and rule 2 decides at once what it does next.
    2. *At rest* at an angle ``theta`` (``omega = 0``): the friction band is ``[lo, hi]``
       with ``lo = M(-1; theta, 0, 0)``, the torque that just holds the crank against
       moving backwards, and ``hi = M(+1; theta, 0, 0)``, the torque that just starts
       it forwards (one Coulomb coefficient: the static friction is the sliding one).
       With ``tq = tau(t, theta, 0)``: ``tq > hi`` moves it forwards (a segment ``d =
       +1`` from ``omega = 0``), ``tq < lo`` backwards (``d = -1``), and otherwise it
       *sticks*: ``theta`` stays, ``omega = alpha = 0``, while ``tq`` stays within the
       band. ``tq`` is watched at the output times and at 8 points between each two,
       and where it leaves the band, the time it crosses the edge is found by Brent's
       method (to about 4 ulp); the crank breaks away there, in the direction it left.
    3. The start: ``omega0 != 0`` moves in its direction; ``omega0 = 0`` is at rest.

    The rows at the output times carry, while moving, every output of ``solve`` at
    ``(theta, omega, alpha)`` of the linkage with ``drive = d`` (``Mb = tau - flywheel
    * alpha`` to rounding). While stuck the friction in each pair is not determined by
    the torque (any friction within the band holds it): the reactions and friction
    values are those at rest with friction at its limit against the way ``tau`` pushes
    the crank (of the linkage with ``drive = +1`` where ``tau`` lies at or above the
    band's middle, else ``-1``), as the drive FMU reports them; ``Mb`` is ``tau`` (the
    crank is held: the linkage takes it all) and ``P_loss`` is 0. ``attrs["switches"]`` lists each
    change, a :class:`Switch` ``(time, theta, to)``: ``to`` = +1 or -1 where the crank starts to
    move from rest in that direction (breaks away, or reverses at once after a stop), 0
    where it comes to rest and sticks; a start at rest is the first entry.

    Examples
    --------
    >>> import numpy as np
    >>> from linkage_fmu import presets
    >>> yoke = presets.get("scotch_yoke")      # J = (4 + 10 cos^2 theta) * 0.1^2
    >>> run = yoke.simulate(2.0, np.linspace(0.0, 0.5, 6), theta0=0.0, omega0=1.0,
    ...                     load=0.0)
    >>> list(run.columns[:4]), run.index.name
    (['theta', 'omega', 'alpha', 'tau'], 'time')
    >>> a0 = float(run["alpha"].iloc[0])        # 2 / J(0), dJ(0) = 0: no speed term
    >>> round(a0, 12), round(float(run["Mb"].iloc[-1]), 9)  # Mb along it is tau
    (14.285714285714, 2.0)

    With friction: the slider-crank at 1 rad, its load pushing the piston, holds from
    rest while the torque lies within its band, ``[-0.9168, -0.7107]`` N m there; a
    ramp from -0.8 N m breaks away where it crosses the upper edge (the static ``Mb``
    with ``drive = +1``, the preset's default):

    >>> press = presets.get("slider_crank", mu_O=0.1, r_O=0.01, mu_A=0.1, r_A=0.01,
    ...                     mu_guide=0.1)
    >>> held = press.simulate(-0.8, [0.0, 0.1], theta0=1.0, omega0=0.0, load=20.0)
    >>> held["stuck"].tolist(), held["theta"].tolist(), held["Mb"].tolist()
    ([True, True], [1.0, 1.0], [-0.8, -0.8])
    >>> ramp = press.simulate(lambda t, th, w: -0.8 + t, [0.0, 0.1, 0.2],
    ...                       theta0=1.0, omega0=0.0, load=20.0)
    >>> start, away = ramp.attrs["switches"]
    >>> start, away.to, round(away.time, 12), ramp["stuck"].tolist()
    (Switch(time=0.0, theta=1.0, to=0), 1, 0.089321752569, [True, False, False])
    >>> edge = press.solve(1.0, 0.0, 0.0, load=20.0)["Mb"]
    >>> round(edge + 0.8, 12)
    0.089321752569
    """
    import pandas as pd
    from scipy.integrate import solve_ivp

    if mech.rates:  # several drivers, a motor, a cylinder: one effort each
        if flywheel != 0.0:
            raise InputError(f"{mech.name}: a flywheel is on a crank driven alone; "
                             "this linkage is driven by time")
        return driven_motion.simulate(mech, tau, t, theta0, omega0, rtol, atol, **loads)
    effort = crank_moment(mech, "simulate drives the crank with a moment")
    t = driven_motion.times(t)
    torque = _torque(tau, t)
    theta0 = _start(mech, "theta", theta0, "rad")
    omega0 = _start(mech, "omega", omega0, "rad/s")
    extra = finite_float("flywheel", evaluate(flywheel, "kg.m2", "flywheel")
                         if isinstance(flywheel, str) else flywheel)
    if extra < 0.0:
        raise InputError(f"flywheel must be >= 0 (a moment of inertia, kg m2), got {extra!r}")
    named = constant_loads(mech, loads)
    if mech.friction.active:
        return _with_friction(mech, effort, torque, t, theta0, omega0, rtol, atol, extra,
                              named)

    def acceleration(ti, th, w):
        try:
            # one solve gives both (its kernel, where the linkage has one)
            sol = mech.solve(th, w, 0.0, outputs=(effort, "J_red"), **named)
            m0, J = sol[effort], sol["J_red"] + extra
        except (AssemblyError, SingularPositionError) as err:
            raise type(err)(mech.name, th, f"{_why(err)} "
                            f"(reached at t = {ti:.9g} s)") from None
        if not J > 0.0:
            with_flywheel = f" (a flywheel of {extra!r} kg m2 included)" if extra else ""
            raise InputError(f"{mech.name}: the inertia reduced to the crank is {J!r} at "
                             f"theta = {th!r} rad{with_flywheel}; the motion is not defined")
        return (torque(ti, th, w) - m0) / J

    def rhs(ti, y):
        th, w = float(y[0]), float(y[1])
        return [w, acceleration(ti, th, w)]

    res = solve_ivp(rhs, (t[0], t[-1]), [theta0, omega0], method="DOP853", t_eval=t,
                    rtol=rtol, atol=atol)
    if res.status != 0:
        raise ComputationError(f"{mech.name}: the integration failed: {res.message}")
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
    one_crank(mech, job.split(";")[0])
    if not mech.effort_on_crank:
        raise InputError(f"{mech.name}: its balancing effort {mech.effort.name} does not act "
                         f"on the crank; {job}")
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
        raise InputError(f"tau must be a number, a callable or one value per time: "
                         f"{t.size} values (t has {t.size}), got shape {values.shape}")
    return lambda ti, th, w: float(np.interp(ti, t, values))


# -- friction ------------------------------------------------------------------------------
#: Newton steps at most on the crank acceleration of one state (with friction)
NEWTON_STEPS = 50
#: Newton steps after which steps that no longer halve bisect the bracket of the root
STALLED_STEPS = 8
#: the largest step, relative to alpha's size, that counts as rounding once Newton's
#: steps stop shrinking (Mb sums terms that may cancel: its rounding can exceed 4 ulp)
ROUNDING = 1e-11
#: changes between sticking and moving at most in one simulation (a guard against chatter)
MAX_SWITCHES = 100_000
#: switches at one time at most (no progress: a torque that touches the band's edge)
STALLED = 50
#: points at which a stuck crank's torque is watched between two output times
WATCH = 8
_EPS = float(np.finfo(float).eps)
#: what a state the linkage cannot take raises
_STATE_ERRORS = (AssemblyError, SingularPositionError, SelfLockingError, OverflowInputError)


class Switch(NamedTuple):
    """A change of a motion with friction (:func:`simulate`): at ``time`` [s], the crank at
    ``theta`` [rad] with ``omega = 0``, starts to move in the direction ``to`` (+1 or
    -1) or comes to rest and sticks (``to = 0``)."""

    time: float
    theta: float
    to: int


def moment_and_slope(mech, **loads) -> Callable[[float, float, float], tuple]:
    """``f(theta, omega, alpha) -> (Mb, dMb/dalpha)``: the balancing moment on the crank
    at a state, with the loads given, and its derivative by the crank acceleration.

    Both come from one call of the forward-mode kernel of the effort's plan: the
    compiled one (:meth:`Kernel.tangent <linkage_fmu.kernels.Kernel.tangent>`), or
    without a C compiler its Python twin (:meth:`Kernel.python_tangent
    <linkage_fmu.kernels.Kernel.python_tangent>`, the same floats): ``Mb`` the kernel's
    own floats, the derivative exact through every traced operation (friction's Newton
    steps included). Where the kernel does not take the state (a guard fails, or the
    derivative is not finite), ``Mb`` is :meth:`~linkage_fmu.Mechanism.solve`'s and the
    derivative a forward difference of it, step ``1e-6 max(1, |alpha|, omega**2)``
    (about 1e-6 relative: Newton's method on it still converges, a little slower).
    Without friction the derivative is ``J_red`` (``Mb`` is affine in ``alpha``).

    Parameters
    ----------
    mech : Mechanism
        A linkage whose balancing effort is a moment on its crank.
    **loads : float or str
        The loads by name, fixed for the function (as :func:`simulate` takes them).

    Returns
    -------
    callable
        ``f(theta, omega, alpha)`` of floats: ``(Mb, dMb/dalpha)`` as floats. It raises
        the library's error of a state without outputs (``AssemblyError``, ...).

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("slider_crank", mu_A=0.1, r_A=0.01, mu_guide=0.1)
    >>> f = moment_and_slope(mech, load=50.0)
    >>> Mb, slope = f(0.7, 10.0, 3.0)
    >>> Mb == mech.solve(0.7, 10.0, 3.0, outputs=("Mb",), load=50.0)["Mb"]
    True
    >>> J = mech.reduced_inertia(0.7)[0]  # friction adds to the frictionless J
    >>> bool(abs(slope - J) < 0.2 * J), round(slope, 6) != round(J, 6)
    (True, True)
    """
    from .ccompiler import CompilerError

    effort = crank_moment(mech, "its moment's slope is taken by the crank acceleration")
    named = constant_loads(mech, loads)
    values, given = mech.inputs(0.0, 0.0, (), named)
    fixed = [float(v) for v in values[2:]]
    outputs = (effort,)
    try:
        kernel = mech.solver.kernel(outputs, False, given)
    except ValueError:  # no witness state
        kernel = tangent = None
    if kernel is not None:
        try:
            tangent = kernel.tangent()
        except CompilerError:  # the compiler failed
            tangent = None
        if tangent is None:  # no C compiler: the same derivatives in Python
            try:
                tangent = kernel.python_tangent()
            except ValueError:  # an operation without a derivative rule
                tangent = None
    along = np.zeros(3 + len(fixed))
    along[2] = 1.0

    def moment(theta: float, omega: float, alpha: float) -> float:
        return mech.solve(theta, omega, alpha, outputs=outputs, **named)[effort]

    def f(theta: float, omega: float, alpha: float) -> tuple:
        if tangent is not None:
            try:
                r = tangent([theta, omega, alpha, *fixed], along)
            except (ArithmeticError, ValueError):  # Python's math: C gives inf or NaN
                r = None
            if type(r) is tuple:
                m, dm = float(r[0][0]), float(r[1][0])
                if math.isfinite(m + dm):
                    return m, dm
        m = moment(theta, omega, alpha)
        h = 1e-6 * max(1.0, abs(alpha), omega * omega)
        return m, (moment(theta, omega, alpha + h) - m) / h

    return f


def driven(mech, drive: float):
    """``mech`` with its crank's drive direction ``drive`` (+1 or -1): the direction
    friction opposes where the crank stands (:mod:`~linkage_fmu.friction`); ``mech``
    itself where it has that already. Built again from its description, with the
    parameter ``drive`` is its ``[linkage] drive`` (every preset), else with that
    written in.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> back = driven(presets.get("four_bar", mu_A=0.1, r_A=0.01), -1.0)
    >>> back.friction.drive, back.parameters["drive"]
    (-1.0, -1.0)
    """
    if mech.friction.drive == drive:
        return mech
    d = mech.description
    if d is None:
        raise InputError(f"{mech.name} was not built from a description: it cannot be "
                         "built again with the other drive direction")
    if str(d.drive).strip() in d.parameters:
        return d.build(**{**mech.parameters, str(d.drive).strip(): float(drive)})
    return d.with_drive(float(drive)).build(**mech.parameters)


class _Direction:
    """The linkage with the drive direction ``d``, its moment and slope, and the crank
    acceleration of the equation of motion with it (the Notes of :func:`simulate`)."""

    def __init__(self, mech, d: int, named: dict, extra: float):
        self.d = d
        self.mech = driven(mech, float(d))
        self.named, self.extra = named, extra
        self.moment = moment_and_slope(self.mech, **named)

    def acceleration(self, ti: float, th: float, w: float, tq: float) -> float:
        """``alpha`` solving ``tq - extra alpha = Mb(th, w, alpha)`` (Newton from 0, kept
        inside the bracket that the residual's signs give)."""
        # Not the drive FMU's bracketed secant from Eksergian's estimate
        # (fmi/backend_native.c), on purpose: here each step is a call from Python, so
        # the fewest steps win, and one call of the tangent kernel gives Mb and the exact
        # slope together; Mb is the library's own floats (the kernel's loops run as solve
        # runs them), so that a row of the motion is solve's at its alpha. The FMU's
        # secant saves C runs of the kernel instead. Both find the root to rounding
        # (tests/test_drive.py compares them state by state).
        extra = self.extra
        a, last, before = 0.0, math.inf, math.inf
        lo, hi = -math.inf, math.inf  # the root lies between: the residual's signs
        for n in range(NEWTON_STEPS):
            try:
                m, dm = self.moment(th, w, a)
            except _STATE_ERRORS as err:
                raise _at_time(err, self.mech.name, th, ti) from None
            slope = dm + extra
            if not slope > 0.0:
                J = self.mech.reduced_inertia(th)[0] + extra
                if not J > 0.0:  # no inertia at all: as without friction
                    with_flywheel = f" (a flywheel of {extra!r} kg m2 included)" if extra else ""
                    raise InputError(f"{self.mech.name}: the inertia reduced to the crank is "
                                     f"{J!r} at theta = {th!r} rad{with_flywheel}; the motion "
                                     f"is not defined (reached at t = {ti:.9g} s)")
                raise SelfLockingError(
                    self.mech.name, th,
                    f"no crank acceleration balances tau = {tq!r} N m: dMb/dalpha + flywheel "
                    f"= {slope!r} kg m2 at alpha = {a!r} rad/s2, omega = {w!r} rad/s "
                    f"(reached at t = {ti:.9g} s)")
            residual = tq - extra * a - m  # falls as alpha grows (slope > 0)
            if residual == 0.0:
                return a
            if residual > 0.0:
                lo = a
            else:
                hi = a
            step = residual / slope
            bracketed = math.isfinite(lo) and math.isfinite(hi)
            bisect = bracketed and (not lo < a + step < hi or (
                n >= STALLED_STEPS and abs(step) > 0.5 * before))
            if bisect:
                # a step out of the bracket, or Newton's steps long past shrinking (the
                # floor of Mb's rounding below the test's, or a kink): bisect it
                step = 0.5 * (lo + hi) - a
            before, last = last, abs(step)
            a += step
            size = abs(a) + (abs(tq) + abs(m)) / slope
            # within 4 ulp; or at the floor of rounding (of Mb's own terms, which may
            # cancel), where Newton's steps no longer shrink; or the bracket closed to 4 ulp
            if abs(step) <= 4.0 * _EPS * size or (
                    not bisect and abs(step) >= 0.5 * before and abs(step) <= ROUNDING * size
            ) or (bracketed and hi - lo <= 4.0 * _EPS * max(abs(lo), abs(hi), size)):
                return a
        if math.isfinite(lo) and math.isfinite(hi):
            # the residual's sign changes at random within [lo, hi]: Mb's rounding there
            return 0.5 * (lo + hi)
        raise SelfLockingError(
            self.mech.name, th, f"Newton's method on the crank acceleration does not "
            f"converge in {NEWTON_STEPS} steps (last {a!r} rad/s2, step {step!r}) at omega "
            f"= {w!r} rad/s under tau = {tq!r} N m (reached at t = {ti:.9g} s)")

    def band_edge(self, ti: float, th: float) -> float:
        """The static balancing moment ``M(d; th, 0, 0)``: an edge of the band."""
        try:
            return self.moment(th, 0.0, 0.0)[0]
        except _STATE_ERRORS as err:
            raise _at_time(err, self.mech.name, th, ti) from None


def _at_time(err, name: str, th: float, ti: float):
    """The state's error ``err`` again, saying when the motion reached it."""
    where = f"(reached at t = {ti:.9g} s)"
    if isinstance(err, SelfLockingError):
        what = str(err).split(": ", 1)[-1] if ": " in str(err) else "friction locks it"
        return SelfLockingError(name, th, f"{what} {where}")
    if isinstance(err, OverflowInputError):
        return OverflowInputError(name, f"{str(err).split(': ', 1)[-1]} {where}")
    return type(err)(name, th, f"{_why(err)} {where}")


def _with_friction(mech, effort: str, torque, t: np.ndarray, theta0: float, omega0: float,
                   rtol: float, atol: float, extra: float, named: dict):
    """:func:`simulate` of a linkage with friction: segments moving in one direction or
    stuck (the Notes of :func:`simulate`)."""
    import pandas as pd
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    directions: dict = {}

    def direction(d: int) -> _Direction:
        if d not in directions:
            directions[d] = _Direction(mech, d, named, extra)
        return directions[d]

    def band(ti: float, th: float) -> tuple:
        return direction(-1).band_edge(ti, th), direction(+1).band_edge(ti, th)

    def at_rest(ti: float, th: float) -> int:
        """+1 or -1: it moves off in that direction; 0: it sticks."""
        lo, hi = band(ti, th)
        tq = torque(ti, th, 0.0)
        return 1 if tq > hi else -1 if tq < lo else 0

    end = float(t[-1])
    rows: list = []  # (time, theta, omega, direction or 0 where stuck)
    switches: list = []
    k = 0  # the next output time to fill

    def moving(t0: float, th0: float, w0: float, d: int):
        nonlocal k
        dr = direction(d)

        def rhs(ti, y):
            th, w = float(y[0]), float(y[1])
            # d |w|: the segment's equation, continued smoothly past its stop
            return [w, dr.acceleration(ti, th, d * abs(w), torque(ti, th, w))]

        def stops(ti, y):
            return d * y[1]

        stops.terminal, stops.direction = True, -1
        res = solve_ivp(rhs, (t0, end), [th0, w0], method="DOP853", t_eval=t[k:],
                        rtol=rtol, atol=atol, events=stops)
        if res.status == -1:
            raise ComputationError(f"{mech.name}: the integration failed: {res.message}")
        # no output time within the segment: scipy gives empty lists
        times = np.asarray(res.t, dtype=float)
        rows.extend((ti, th, w, d) for ti, th, w in zip(
            times, *np.asarray(res.y, dtype=float).reshape(2, times.size)))
        k += times.size
        if res.status == 1:
            return float(res.t_events[0][0]), float(res.y_events[0][0][0])
        return None

    def stuck(t0: float, th: float):
        nonlocal k
        lo, hi = band(t0, th)

        def out_of_band(ti: float) -> float:
            tq = torque(ti, th, 0.0)
            return tq - hi if tq > hi else tq - lo if tq < lo else 0.0

        marks = t[k:]
        watch = [t0]
        for a, b in zip([t0, *marks[:-1]], marks):
            watch.extend(a + (b - a) * np.arange(1, WATCH + 1) / WATCH)
        before = t0
        for ti in watch[1:]:
            ti = float(ti)
            leave = out_of_band(ti)
            if leave:
                edge = hi if leave > 0.0 else lo
                tb = brentq(lambda s: torque(s, th, 0.0) - edge, before, ti,  # noqa: B023
                            xtol=4.0 * _EPS * max(abs(before), abs(ti)), rtol=4.0 * _EPS)
                n = int(np.searchsorted(t, tb, side="right")) - k
                rows.extend((float(s), th, 0.0, 0) for s in t[k:k + n])
                k += n
                return tb, (1 if leave > 0.0 else -1)
            before = ti
        rows.extend((float(s), th, 0.0, 0) for s in t[k:])
        k = t.size
        return None

    ti, th, w = float(t[0]), theta0, omega0
    d = (1 if w > 0.0 else -1) if w != 0.0 else at_rest(ti, th)
    if w == 0.0:
        switches.append(Switch(ti, th, d))
    for _ in range(MAX_SWITCHES):
        if d:
            stop = moving(ti, th, w, d)
            if stop is None:
                break
            ti, th = stop
            w = 0.0
            d = at_rest(ti, th)
        else:
            leave = stuck(ti, th)
            if leave is None:
                break
            ti, d = leave
        if len(switches) >= STALLED and switches[-STALLED].time == ti:
            raise ComputationError(f"{mech.name}: the motion switched between sticking and "
                                   f"moving {STALLED} times at t = {ti:.9g} s, theta = {th:.9g} "
                                   "rad without moving on (the torque touches the band's edge "
                                   "there)")
        switches.append(Switch(ti, th, d))
        if ti >= end:  # stopped or left exactly at the last time
            break
    else:
        raise ComputationError(f"{mech.name}: the motion switched between sticking and moving "
                               f"{MAX_SWITCHES} times before t = {ti:.9g} s; it chatters")
    if k < t.size:  # the last output times at the very end of a stop
        rows.extend((float(s), th, 0.0, d if d else 0) for s in t[k:])

    times, theta, omega, seg = (np.array(c) for c in zip(*rows))
    seg = seg.astype(int)
    tau = np.array([torque(*s) for s in zip(times, theta, omega)])
    alpha = np.zeros(times.size)
    out = {}
    for d in (1, -1):
        where = np.flatnonzero(seg == d)
        if not where.size:
            continue
        dr = direction(d)
        w = d * np.abs(omega[where])
        alpha[where] = [dr.acceleration(*s) for s in zip(times[where], theta[where], w,
                                                        tau[where])]
        sol = dr.mech.solve(theta[where], w, alpha[where], **named)
        for name, v in sol.items():
            out.setdefault(name, np.full(times.size, np.nan))[where] = v
    where = np.flatnonzero(seg == 0)
    if where.size:
        # the friction holding it is not determined: the state at rest with friction at
        # its limit against the way tau pushes it (the band's edge on tau's side of its
        # middle), as the drive FMU reports it; the linkage takes tau all the same
        edges = {d: direction(d).mech.solve(theta[where], 0.0, 0.0, **named)
                 for d in (1, -1)}
        middle = 0.5 * (edges[1][effort] + edges[-1][effort])
        side = tau[where] >= middle
        for name in edges[1]:
            column = out.setdefault(name, np.full(times.size, np.nan))
            column[where] = np.where(side, edges[1][name], edges[-1][name])
        out[effort][where] = tau[where]
    frame = {"theta": theta, "omega": omega, "alpha": alpha, "tau": tau}
    frame.update((name, out[name]) for name in mech.output_names + mech.diagnostic_names)
    frame["J_red"] = mech.reduced_inertia(theta)[0]
    frame["stuck"] = seg == 0
    run = pd.DataFrame(frame, index=pd.Index(t, name="time"))
    run.attrs["switches"] = switches
    return run
