"""Flywheel sizing: the turning-moment diagram of a linkage at a constant mean speed, the
fluctuation of energy over its cycle, the flywheel that keeps the speed within a
coefficient of fluctuation, and the periodic motion with that flywheel.

The textbook chain (Khurmi & Gupta, *Theory of Machines*, ch. 16, "Turning Moment
Diagrams and Flywheel"): a crank driven by a constant torque equal to the cycle mean of
the torque it needs gains speed where the mean exceeds the need and loses it where the
mean falls short. The largest swing over a cycle of the energy so stored, the maximum
fluctuation of energy ``delta_E``, is what the rotating inertia ``I`` gives and takes:
``delta_E = I (omega_max**2 - omega_min**2) / 2 = I Cs omega_mean**2`` with
``omega_mean = (omega_max + omega_min) / 2`` and the coefficient of fluctuation of speed
``Cs = (omega_max - omega_min) / omega_mean``; so ``I = delta_E / (Cs omega_mean**2)``.

:func:`energy_fluctuation` and :func:`flywheel_inertia` are that chain on numbers;
:func:`flywheel` runs it on a linkage and checks the result against the linkage's own
equation of motion (:func:`periodic_motion`, :func:`~linkage_fmu.motion.simulate`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from . import motion
from .errors import ComputationError, InputError, InputTypeError
from .expressions import evaluate
from .numerics import finite_array, finite_float
from .printing import number

if TYPE_CHECKING:  # pragma: no cover
    import pandas as pd

#: Gauss-Legendre points per interval of the turning-moment diagram
GAUSS = 8
#: intervals per revolution of the turning-moment diagram (0.5 degree)
INTERVALS = 720
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(GAUSS)
#: Newton steps at most on the periodic motion of a linkage with friction
PERIODIC_STEPS = 12


class Fluctuation(NamedTuple):
    """The maximum fluctuation of energy of a turning-moment diagram
    (:func:`energy_fluctuation`)."""

    #: the largest minus the smallest surplus energy over the cycle [J]
    delta_E: float
    #: the torque's mean over the cycle [N m]
    mean: float
    #: where the surplus energy is largest (the speed highest) and smallest [rad]
    theta_max: float
    theta_min: float


def energy_fluctuation(theta, torque) -> Fluctuation:
    """The maximum fluctuation of energy of a turning-moment diagram: ``torque`` over one
    cycle against a constant torque equal to its mean.

    The surplus energy ``E(theta) = integral from theta[0] to theta of (torque - mean)``
    is what the crank's inertia stores; ``delta_E = max E - min E``. ``torque`` is a
    driving torque (an engine's turning moment) against a constant resistance; against
    a resisting torque that is not constant, give their difference (its mean is then
    the net torque, zero in a steady state). For a torque a machine needs from a
    constant motor (a press, ``Mb``), ``delta_E`` is the same and ``theta_max`` and
    ``theta_min`` swap: the speed is lowest where ``E`` is largest.

    Parameters
    ----------
    theta : array_like
        Crank angles [rad], increasing, spanning one cycle from the first to the last
        (e.g. ``linspace(0, 2 pi, n)``: the last the first again).
    torque : array_like
        The torque at each angle [N m].

    Returns
    -------
    Fluctuation
        ``(delta_E, mean, theta_max, theta_min)``: the integrals by the trapezoidal
        rule, exact for a torque linear between the samples (a diagram given as a
        polygon), else with an error of order ``step**2`` (for a smooth torque of
        period ``p`` sampled ``n`` times a period, about ``(2 pi / n)**2 / 24`` relative:
        4e-8 for ``n = 4000``); ``theta_max`` and ``theta_min`` are samples.

    Raises
    ------
    ValueError
        ``theta`` or ``torque`` not 1-d, of other lengths, with fewer than 2 samples,
        not finite, or ``theta`` not increasing.

    Examples
    --------
    Khurmi & Gupta, *Theory of Machines*, Example 16.11: an engine's turning moment
    ``T = 20000 + 9500 sin(2 theta) - 5700 cos(2 theta)`` N m, its period 180 degrees;
    the book's fluctuation of energy is 11 078 N m (the amplitude
    ``sqrt(9500**2 + 5700**2) = 11078.8``):

    >>> import numpy as np
    >>> theta = np.linspace(0.0, np.pi, 100_001)
    >>> T = 20000 + 9500 * np.sin(2 * theta) - 5700 * np.cos(2 * theta)
    >>> f = energy_fluctuation(theta, T)
    >>> round(f.delta_E, 1), round(f.mean, 6)
    (11078.8, 20000.0)
    """
    th = finite_array("theta", theta).astype(float)
    tq = finite_array("torque", torque).astype(float)
    if th.ndim != 1 or th.size < 2:
        raise InputError(f"theta must be a 1-d array of at least 2 angles, got shape "
                         f"{th.shape}")
    if tq.shape != th.shape:
        raise InputError(f"torque must have one value per angle: shape {th.shape}, got "
                         f"{tq.shape}")
    step = np.diff(th)
    if not (step > 0).all():
        k = int(np.argmin(step > 0)) + 1
        raise InputError(f"theta must be increasing: theta[{k}] = {float(th[k])!r} <= "
                         f"theta[{k - 1}] = {float(th[k - 1])!r}")
    parts = 0.5 * (tq[1:] + tq[:-1]) * step
    mean = math.fsum(parts) / float(th[-1] - th[0])
    energy = np.concatenate([[0.0], np.cumsum(parts - mean * step)])
    i, j = int(np.argmax(energy)), int(np.argmin(energy))
    return Fluctuation(float(energy[i] - energy[j]), mean, float(th[i]), float(th[j]))


def flywheel_inertia(delta_E, omega_mean, Cs) -> float:
    """The moment of inertia that holds the speed within the coefficient of fluctuation
    ``Cs`` while it gives and takes the energy ``delta_E``: ``delta_E / (Cs
    omega_mean**2)``.

    From ``delta_E = I (omega_max**2 - omega_min**2) / 2`` with ``omega_mean =
    (omega_max + omega_min) / 2`` and ``Cs = (omega_max - omega_min) / omega_mean``:
    exact for a constant inertia; for a linkage it is the total inertia on the crank,
    the linkage's own included (see :func:`flywheel`).

    Parameters
    ----------
    delta_E : float or str
        The maximum fluctuation of energy [J], >= 0; text with a unit (``"11 kJ"``) is
        taken in SI.
    omega_mean : float or str
        The mean speed [rad/s], > 0 (``"180 rpm"``).
    Cs : float or str
        ``(omega_max - omega_min) / omega_mean``, between 0 and 1 (``"2 percent"``).

    Returns
    -------
    float
        The moment of inertia [kg m2].

    Raises
    ------
    ValueError
        An input not finite or out of its range, naming it.

    Examples
    --------
    Khurmi & Gupta, *Theory of Machines*, Example 16.11: 11 078 N m at 180 rpm within
    1 % gives 3121 kg m2 in the book, which rounds ``omega**2 Cs`` to 3.55; unrounded:

    >>> round(flywheel_inertia("11078 N*m", "180 rpm", 0.01), 1)
    3117.9
    """
    energy = _value(delta_E, "J", "delta_E")
    if energy < 0.0:
        raise InputError(f"delta_E must be >= 0 (an energy, J), got {energy!r}")
    return energy / (_fraction(Cs) * _speed(omega_mean, "omega_mean") ** 2)


@dataclass(frozen=True)
class PeriodicMotion:
    """The steady periodic motion of a linkage under a constant torque on its crank
    (:func:`periodic_motion`). Angles [rad], speeds [rad/s]."""

    #: the linkage's name
    linkage: str
    #: the mean speed over the cycle (the cycle's angle over its time)
    omega_mean: float
    #: revolutions of the crank in the cycle
    revolutions: int
    #: the constant torque on the crank [N m]: the cycle mean of Mb at constant speed
    tau: float
    #: the flywheel's moment of inertia [kg m2], on top of the linkage's own
    flywheel: float
    #: the speed at theta = 0
    omega0: float
    #: the highest and lowest speed over the cycle, and where
    omega_max: float
    omega_min: float
    theta_omega_max: float
    theta_omega_min: float
    #: how far the integrated motion, started at (0, omega0), is from closing after one
    #: cycle: max(|theta(T) - cycle| / cycle, |omega(T) - omega0| / omega_mean)
    periodic_error: float
    #: the motion over the cycle, integrated by :func:`~linkage_fmu.motion.simulate`
    #: (indexed by time; ``theta``, ``omega``, ``alpha``, ``tau``, the outputs, ``J_red``)
    motion: "pd.DataFrame" = field(compare=False, repr=False)

    @property
    def Cs(self) -> float:
        """The coefficient of fluctuation of speed: ``(omega_max - omega_min) /
        omega_mean``."""
        return (self.omega_max - self.omega_min) / self.omega_mean


@dataclass(frozen=True)
class FlywheelSizing:
    """A flywheel sized for a linkage (:func:`flywheel`). SI units: angles [rad], speeds
    [rad/s], torque [N m], energy [J], inertia [kg m2]."""

    #: the linkage's name
    linkage: str
    #: the mean speed and the coefficient of fluctuation of speed asked for
    omega_mean: float
    Cs: float
    #: revolutions of the crank in the cycle
    revolutions: int
    #: the constant driving torque: the cycle mean of Mb at constant speed
    tau_mean: float
    #: the range of Mb at constant speed over the cycle (at the Gauss-Legendre points)
    Mb_min: float
    Mb_max: float
    #: the cycle mean of the power friction dissipates at constant speed [W] (in
    #: ``tau_mean * omega_mean``; 0 without friction)
    P_loss_mean: float
    #: the maximum fluctuation of energy over the cycle, and where the surplus energy is
    #: largest and smallest (where the speed is highest and lowest, to first order)
    delta_E: float
    theta_E_max: float
    theta_E_min: float
    #: ``delta_E / (Cs omega_mean**2)``: the inertia the crank needs, all told
    inertia: float
    #: the linkage's own inertia reduced to the crank: its mean over the cycle, its range
    J_red_mean: float
    J_red_min: float
    J_red_max: float
    #: the flywheel to add: ``inertia - J_red_mean``, or 0 where the linkage has enough
    flywheel: float
    #: the periodic motion with that flywheel, from the equation of motion
    run: PeriodicMotion = field(compare=False, repr=False)

    @property
    def Cs_simulated(self) -> float:
        """The coefficient of fluctuation of the motion with the flywheel (``run.Cs``)."""
        return self.run.Cs

    @property
    def omega_max(self) -> float:
        """The highest speed of the motion with the flywheel."""
        return self.run.omega_max

    @property
    def omega_min(self) -> float:
        """The lowest speed of the motion with the flywheel."""
        return self.run.omega_min

    @property
    def motion(self) -> "pd.DataFrame":
        """The motion with the flywheel over the cycle (``run.motion``)."""
        return self.run.motion

    def __str__(self) -> str:
        rpm = 30.0 / math.pi
        turns = "revolution" if self.revolutions == 1 else "revolutions"
        deg = math.degrees

        def n(value: float) -> str:
            return number(value, 6)

        # a mean within rounding of the sum of Mb (conservative loads) is printed as 0
        tau = number(self.tau_mean, 6, scale=max(abs(self.Mb_min), abs(self.Mb_max)))
        added = (f"{n(self.flywheel)} kg.m2" if self.flywheel > 0.0 else
                 f"none, the linkage's own is enough ({n(self.inertia - self.J_red_mean)})")
        lines = [
            f"{self.linkage}: a flywheel for {n(self.omega_mean)} rad/s "
            f"({n(self.omega_mean * rpm)} rpm) within Cs = {n(self.Cs)}, over a cycle of "
            f"{360 * self.revolutions} deg ({self.revolutions} {turns})",
            f"  driving torque, constant   tau_mean = {tau} N.m (the cycle mean of Mb "
            f"at constant speed, {n(self.Mb_min)} .. {n(self.Mb_max)})",
            *([f"  friction losses            P_loss   = {n(self.P_loss_mean)} W mean at "
               f"constant speed (in tau_mean: {n(self.P_loss_mean / self.omega_mean)} N.m)"]
              if self.P_loss_mean else []),
            f"  fluctuation of energy      delta_E  = {n(self.delta_E)} J (surplus largest "
            f"at theta = {number(deg(self.theta_E_max), 2, fixed=True)} deg, smallest at "
            f"{number(deg(self.theta_E_min), 2, fixed=True)} deg)",
            f"  inertia needed             I        = {n(self.inertia)} kg.m2 "
            "= delta_E / (Cs omega_mean**2)",
            f"  the linkage's own          J_red    = {n(self.J_red_mean)} kg.m2 mean "
            f"({n(self.J_red_min)} .. {n(self.J_red_max)})",
            f"  flywheel to add            I - J_red = {added}",
            f"  with it (equation of motion): omega = {n(self.omega_min)} .. "
            f"{n(self.omega_max)} rad/s ({n(self.omega_min * rpm)} .. "
            f"{n(self.omega_max * rpm)} rpm), Cs = {n(self.Cs_simulated)}",
        ]
        return "\n".join(lines)


def flywheel(mech, omega_mean, Cs, revolutions: int | None = None,
             intervals: int = INTERVALS, samples: int | None = None,
             rtol: float = 1e-10, **loads) -> FlywheelSizing:
    """The flywheel that holds the crank's speed within the coefficient of fluctuation
    ``Cs`` at the mean speed ``omega_mean``, driven by a constant torque, and the motion
    with it.

    1. The turning-moment diagram: ``Mb(theta)``, the moment the crank needs at the
       constant speed ``omega_mean`` (``alpha = 0``) with the loads given, over a cycle.
       It holds the linkage's own inertia at constant speed, ``dJ/2 omega**2`` (the
       kinetic energy ``J(theta) omega**2 / 2`` of the links changes with the crank
       angle even at constant crank speed), as well as the loads and weights: the
       standard turning-moment diagram of a machine at its mean speed.
    2. The driving torque is constant, ``tau_mean``, the cycle mean of ``Mb``; the
       surplus energy is ``E(theta) = integral of (tau_mean - Mb)``, and ``delta_E = max
       E - min E``.
    3. ``inertia = delta_E / (Cs omega_mean**2)`` (:func:`flywheel_inertia`): the inertia
       on the crank, all told. The linkage's own counts, to first order by its mean
       ``J_red_mean``: the flywheel to add is ``inertia - J_red_mean`` (0 if that is
       negative: the linkage alone keeps within ``Cs``).
    4. The linkage with that flywheel under the constant torque ``tau_mean``: the
       periodic motion whose mean speed is ``omega_mean`` (:func:`periodic_motion`), its
       highest and lowest speed and its coefficient of fluctuation ``Cs_simulated``.
       The formula makes that close to ``Cs``, not equal: it is linear in the swing of
       the speed, takes the mean speed for ``(omega_max + omega_min) / 2`` (the
       motion's is its time mean) and the linkage's inertia for its mean; the
       difference is of order ``Cs`` relative (below ``0.2 Cs`` for the presets and
       the engine of ``examples/``, ``tests/test_flywheel.py``).

    With friction in the joints (a ``mu`` not 0), the diagram's ``Mb`` is the solve's
    with friction at ``(theta, omega_mean, 0)``: it holds the friction losses at
    constant speed (the reactions hold the inertia forces of that speed), so
    ``tau_mean`` pays for them and ``P_loss_mean`` reports their mean power. Step 4 has
    no energy integral then (the losses depend on the speed and the acceleration):
    the periodic motion is found by Newton's method on
    :func:`~linkage_fmu.motion.simulate` with friction, its torque ``run.tau`` and its
    start speed such that the motion closes after the cycle's time (``run.tau`` differs
    from ``tau_mean`` by how the losses change with the swing of the speed: of order
    ``Cs``), and its highest and lowest speeds from the samples of the motion, each
    refined by a parabola through the three about it.

    ``tau_mean`` and ``delta_E`` come from a composite 8-point Gauss-Legendre rule over
    ``intervals`` intervals per revolution, the extremes of ``E`` refined between them
    (a bounded Brent search, ``E`` again by Gauss-Legendre): for a smooth ``Mb`` (every
    preset) that is exact to rounding, 4e-16 relative against the scotch yoke's closed
    form; a load given by a table (a cubic spline) is exact where its knots fall on the
    interval ends and adds the error of the intervals that hold one otherwise (1e-12
    relative for ``examples/engine.toml`` with 719 intervals per revolution, its knots
    every 2 degrees, against 720).

    For a linkage that delivers power (an engine), ``tau_mean`` is negative: the
    driven machine's resisting torque is ``-tau_mean``.

    Parameters
    ----------
    mech : Mechanism
        A linkage whose balancing effort is a moment on its crank, that turns through
        every angle of the cycle.
    omega_mean : float or str
        The mean speed [rad/s], > 0, or text with a unit (``"1800 rpm"``); None: the
        linkage's start speed.
    Cs : float or str
        The coefficient of fluctuation of speed, ``(omega_max - omega_min) /
        omega_mean``, between 0 and 1 (``0.02``, ``"2 percent"``).
    revolutions : int, optional
        Revolutions of the crank in a cycle; default: 1, or the most any load's table
        over the cycle needs (``period_deg = 720`` of a four-stroke engine: 2). Give it
        for a load whose expression has a longer period.
    intervals : int
        Intervals of the turning-moment diagram per revolution, >= 16 (default 720).
    samples : int, optional
        Rows of ``motion`` over the cycle, both ends included (default ``intervals *
        revolutions + 1``).
    rtol : float
        The integrator's tolerances (``rtol`` and ``atol``) for ``motion``.
    **loads : float or str
        The loads, constant over the cycle, as :meth:`~linkage_fmu.Mechanism.solve`
        takes them by name (a load not given takes its start value; a load over the
        cycle is computed at each angle unless given).

    Returns
    -------
    FlywheelSizing
        The sizing (printing it gives a report), with ``run``, the periodic motion with
        the flywheel, and from it ``Cs_simulated``, ``omega_max``, ``omega_min`` and
        ``motion`` (a DataFrame over one cycle, as
        :func:`~linkage_fmu.motion.simulate` gives it).

    Raises
    ------
    ValueError
        ``omega_mean``, ``Cs``, ``revolutions``, ``intervals``, ``samples`` or a load
        invalid, naming it; a linkage whose effort is not a moment on its crank, or that
        cannot be assembled at some angle of the cycle (naming the first).
    TypeError
        A load the linkage does not have.

    Examples
    --------
    The scotch yoke with no load: ``J = (4 + 10 cos(theta)**2) 0.1**2``, so at constant
    speed ``Mb = dJ/2 omega**2 = -0.05 sin(2 theta) omega**2`` and ``E = 0.05
    sin(theta)**2 omega**2``: ``delta_E = 0.05 omega**2``, 5 J at 10 rad/s:

    >>> from linkage_fmu import presets
    >>> yoke = presets.get("scotch_yoke")
    >>> fw = yoke.flywheel(10.0, 0.02, load=0.0)
    >>> abs(fw.tau_mean) < 1e-12, round(fw.delta_E, 12), round(fw.inertia, 12)
    (True, 5.0, 2.5)
    >>> round(fw.J_red_mean, 12), round(fw.flywheel, 12)    # 0.04 + 0.1 / 2
    (0.09, 2.41)
    >>> round(fw.Cs_simulated, 6), round(fw.omega_max, 4), round(fw.omega_min, 4)
    (0.020005, 10.1013, 9.9012)
    """
    effort = motion.crank_moment(mech, "a flywheel is sized for a moment on the crank")
    omega = _speed(mech.start["omega"] if omega_mean is None else omega_mean, "omega_mean")
    cs = _fraction(Cs)
    named = motion.constant_loads(mech, loads)
    cycle = _Cycle(mech, effort, omega, cycle_revolutions(mech, revolutions, named),
                   _count("intervals", intervals, 16), named)
    e_max, th_e_max = cycle.extreme(cycle.energy, cycle.energy_at, +1)
    e_min, th_e_min = cycle.extreme(cycle.energy, cycle.energy_at, -1)
    delta_E = e_max - e_min
    inertia = flywheel_inertia(delta_E, omega, cs)
    J_mean = float(np.mean(cycle.J))  # the periodic trapezoidal rule
    added = max(inertia - J_mean, 0.0)
    run = _periodic(cycle, added, samples, rtol)
    return FlywheelSizing(
        linkage=mech.name, omega_mean=omega, Cs=cs, revolutions=cycle.revolutions,
        tau_mean=cycle.tau, Mb_min=cycle.low, Mb_max=cycle.high, P_loss_mean=cycle.loss,
        delta_E=delta_E,
        theta_E_max=_wrap(th_e_max, cycle.span), theta_E_min=_wrap(th_e_min, cycle.span),
        inertia=inertia, J_red_mean=J_mean, J_red_min=float(cycle.J.min()),
        J_red_max=float(cycle.J.max()), flywheel=added, run=run)


def periodic_motion(mech, omega_mean, flywheel=0.0, revolutions: int | None = None,
                    intervals: int = INTERVALS, samples: int | None = None,
                    rtol: float = 1e-10, **loads) -> PeriodicMotion:
    """The steady periodic motion of a linkage with a flywheel, driven by the constant
    torque that keeps its mean speed ``omega_mean``.

    The torque is ``tau``, the cycle mean of ``Mb`` at the constant speed ``omega_mean`` (as
    :func:`flywheel` takes it); with friction, see below. ``Mb(theta, omega, 0) = M(theta) +
    dJ/2 omega**2``, with ``M`` the moment of the loads and weights alone, so the energy
    equation integrates: ``(J(theta) + I) omega**2 / 2 = c + W(theta)``, ``W`` the work of
    ``tau - M`` from ``theta = 0``, which is periodic (its mean is zero, as ``dJ``'s is):
    every ``c`` gives a periodic motion, and the one whose cycle takes ``cycle /
    omega_mean`` is found by Brent's method on ``c`` (the cycle's time by the periodic
    trapezoidal rule over the nodes of the turning-moment diagram). Its highest and lowest
    speed are refined between the nodes. The motion is then integrated over the cycle by
    :func:`~linkage_fmu.motion.simulate` from ``theta = 0`` at that speed; how far it closes
    on its start is ``periodic_error`` (about ``rtol``).

    With friction in the joints there is no such integral: ``tau`` and the start speed
    are found together by Newton's method on :func:`~linkage_fmu.motion.simulate` (with
    friction), from the cycle mean and the integral's speed, so that the motion from
    ``theta = 0`` closes after ``cycle / omega_mean`` (within ``100 rtol``; the
    Jacobian by forward differences, at most :data:`PERIODIC_STEPS` steps); the
    highest and lowest speed are the samples' refined by a parabola through three.

    Parameters
    ----------
    mech : Mechanism
    omega_mean : float or str
        The mean speed [rad/s], > 0, or text with a unit; None: the start speed.
    flywheel : float or str
        The flywheel's moment of inertia [kg m2], >= 0, added to the linkage's own.
    revolutions, intervals, samples, rtol, **loads
        As for :func:`flywheel`.

    Returns
    -------
    PeriodicMotion

    Raises
    ------
    ValueError, TypeError
        As for :func:`flywheel`; ``flywheel`` invalid; no inertia on the crank at some
        angle (a massless linkage without a flywheel).

    Examples
    --------
    The scotch yoke with no load turns freely (``tau = 0``), so ``J omega**2`` is
    constant: ``omega`` is highest where ``J`` is smallest, at 90 degrees:

    >>> import math
    >>> from linkage_fmu import presets
    >>> run = periodic_motion(presets.get("scotch_yoke"), 10.0, load=0.0)
    >>> abs(run.tau) < 1e-12, round(math.degrees(run.theta_omega_max), 6)
    (True, 90.0)
    >>> round(run.omega_max / run.omega_min, 12), round(math.sqrt(0.14 / 0.04), 12)
    (1.870828693387, 1.870828693387)
    >>> run.periodic_error < 1e-8
    True
    """
    effort = motion.crank_moment(mech, "a flywheel is sized for a moment on the crank")
    omega = _speed(mech.start["omega"] if omega_mean is None else omega_mean, "omega_mean")
    inertia = _value(flywheel, "kg.m2", "flywheel")
    if inertia < 0.0:
        raise InputError(f"flywheel must be >= 0 (a moment of inertia, kg m2), got {inertia!r}")
    named = motion.constant_loads(mech, loads)
    cycle = _Cycle(mech, effort, omega, cycle_revolutions(mech, revolutions, named),
                   _count("intervals", intervals, 16), named)
    return _periodic(cycle, inertia, samples, rtol)


class _Cycle:
    """The turning-moment diagram of ``mech`` over a cycle at the constant speed
    ``omega``: ``Mb`` at 8 Gauss-Legendre points of each of the intervals (its range
    ``low``, ``high``), the constant torque ``tau`` (its mean), the surplus energy
    ``energy`` and the reduced inertia ``J`` at the nodes ``theta`` (0, h, ..., the
    cycle less h)."""

    def __init__(self, mech, effort: str, omega: float, revolutions: int, intervals: int,
                 loads: dict):
        self.mech, self.effort, self.omega, self.loads = mech, effort, omega, loads
        self.revolutions = revolutions
        self.span = 2.0 * math.pi * revolutions
        n = intervals * revolutions
        self.h = self.span / n
        self.theta = self.h * np.arange(n)
        moment = self.moment(self.theta[:, None] + 0.5 * self.h * (1.0 + _NODES))
        self.low, self.high = float(moment.min()), float(moment.max())
        parts = 0.5 * self.h * (moment @ _WEIGHTS)
        self.tau = math.fsum(parts) / self.span
        #: the cycle mean of the power friction dissipates at constant speed [W]
        self.loss = 0.0
        if mech.friction.active:
            theta = self.theta[:, None] + 0.5 * self.h * (1.0 + _NODES)
            lost = mech.solve(theta, omega, 0.0, outputs=("P_loss",), **loads)["P_loss"]
            self.loss = math.fsum(0.5 * self.h * (np.asarray(lost) @ _WEIGHTS)) / self.span
        self.energy = np.concatenate([[0.0], np.cumsum(self.tau * self.h - parts)[:-1]])
        self.J = np.asarray(mech.reduced_inertia(self.theta)[0], dtype=float)

    def moment(self, theta: np.ndarray) -> np.ndarray:
        """``Mb`` at the angles ``theta`` at constant speed, or a ValueError naming the
        first angle where the linkage cannot be assembled."""
        sol = self.mech.solve(theta, self.omega, 0.0, outputs=(self.effort,), **self.loads)
        values = np.asarray(sol[self.effort], dtype=float)
        bad = ~np.isfinite(values)
        if bad.any():
            first = float(np.degrees(np.asarray(theta, dtype=float)[bad].min()))
            raise InputError(f"{self.mech.name} cannot be assembled (or is singular) at "
                             f"theta = {first:.6g} deg: the crank must turn through the whole "
                             f"cycle of {360 * self.revolutions} deg")
        return values

    def energy_at(self, theta: float) -> float:
        """The surplus energy at any angle: from the node below it, by Gauss-Legendre."""
        k = math.floor(theta / self.h)
        base = k * self.h
        if theta == base:
            return float(self.energy[k % self.energy.size])
        half = 0.5 * (theta - base)
        part = half * float(self.moment(base + half * (1.0 + _NODES)) @ _WEIGHTS)
        return float(self.energy[k % self.energy.size]) + self.tau * (theta - base) - part

    def extreme(self, values: np.ndarray, f, sign: int) -> tuple[float, float]:
        """The largest (``sign = 1``) or smallest (-1) value of ``f`` over the cycle,
        and where: the best node of ``values`` (``f`` at the nodes), refined within an
        interval of it by a bounded Brent search."""
        from scipy.optimize import minimize_scalar

        k = int(np.argmax(sign * values))
        best, where = float(values[k]), float(self.theta[k])
        res = minimize_scalar(lambda x: -sign * f(x), bounds=(where - self.h, where + self.h),
                              method="bounded", options={"xatol": 1e-12 * self.span})
        # the node stands unless the search finds more than rounding would
        if -res.fun - sign * best > 1e-15 * float(np.max(np.abs(values))):
            best, where = float(-sign * res.fun), float(res.x)
        return best, where


def _periodic(cycle: _Cycle, inertia: float, samples: int | None,
              rtol: float) -> PeriodicMotion:
    """The periodic motion at the mean speed of ``cycle`` with a flywheel of ``inertia``
    (see :func:`periodic_motion`)."""
    from scipy.optimize import brentq

    mech, omega = cycle.mech, cycle.omega
    half_w2 = 0.5 * omega * omega
    work = cycle.energy + half_w2 * (cycle.J - cycle.J[0])  # of tau - M, from theta = 0
    total = cycle.J + inertia
    if not (total > 0.0).all():
        k = int(np.argmin(total > 0.0))
        raise InputError(f"{mech.name}: the inertia on the crank is {float(total[k])!r} at "
                         f"theta = {math.degrees(cycle.theta[k]):.6g} deg; the motion is "
                         "not defined (add a flywheel)")
    target = cycle.span / omega

    def period(c: float) -> float:
        return cycle.h * float(np.sum(np.sqrt(total / (2.0 * (c + work)))))

    # c_hi gives omega >= omega_mean at every node, so a cycle no longer than the target;
    # just above -min(work) the crank almost stops at a node, so a cycle far too long
    c_hi = float(np.max(half_w2 * total - work))
    floor = -float(np.min(work))
    gap = c_hi - floor
    while period(floor + gap) <= target:
        gap *= 0.5
        if gap <= 1e-300:  # pragma: no cover - the period grows without bound
            raise ComputationError(f"{mech.name}: no periodic motion at {omega!r} rad/s found")
    c = brentq(lambda x: period(x) - target, floor + gap, c_hi, xtol=1e-15 * abs(c_hi),
               rtol=4.0 * np.finfo(float).eps)
    nodes = np.sqrt(2.0 * (c + work) / total)
    count = cycle.theta.size + 1 if samples is None else _count("samples", samples, 2)
    if mech.friction.active:  # the energy equation holds to first order only: a start
        return _periodic_with_friction(cycle, inertia, float(nodes[0]), count, rtol)

    def speed(theta: float) -> float:
        J = mech.reduced_inertia(theta)[0]
        w = cycle.energy_at(theta) + half_w2 * (J - cycle.J[0])
        return math.sqrt(max(2.0 * (c + w) / (J + inertia), 0.0))

    w_max, th_max = cycle.extreme(nodes, speed, +1)
    w_min, th_min = cycle.extreme(nodes, speed, -1)
    omega0 = float(nodes[0])
    run = motion.simulate(mech, cycle.tau, np.linspace(0.0, target, count), theta0=0.0,
                          omega0=omega0, rtol=rtol, atol=rtol, flywheel=inertia,
                          **cycle.loads)
    end = run.iloc[-1]
    error = max(abs(float(end["theta"]) - cycle.span) / cycle.span,
                abs(float(end["omega"]) - omega0) / omega)
    return PeriodicMotion(mech.name, omega, cycle.revolutions, cycle.tau, inertia, omega0,
                          w_max, w_min, _wrap(th_max, cycle.span), _wrap(th_min, cycle.span),
                          error, run)


def _periodic_with_friction(cycle: _Cycle, inertia: float, omega0: float, count: int,
                            rtol: float) -> PeriodicMotion:
    """The periodic motion of a linkage with friction at the mean speed of ``cycle`` (see
    :func:`periodic_motion`): the torque ``tau`` and the start speed ``omega0`` for which
    the motion from ``theta = 0`` closes after the cycle's time, by Newton's method on
    :func:`~linkage_fmu.motion.simulate` (its Jacobian by forward differences), from the
    diagram's mean torque and the frictionless energy equation's start speed."""
    mech, omega, span = cycle.mech, cycle.omega, cycle.span
    target = span / omega
    scale = max(abs(cycle.low), abs(cycle.high), abs(cycle.tau))

    def run(x, n: int = 2):
        return motion.simulate(mech, float(x[0]), np.linspace(0.0, target, n), theta0=0.0,
                               omega0=float(x[1]), rtol=rtol, atol=rtol, flywheel=inertia,
                               **cycle.loads)

    def residual(x) -> np.ndarray:
        end = run(x).iloc[-1]
        return np.array([(float(end["theta"]) - span) / span,
                         (float(end["omega"]) - x[1]) / omega])

    x = np.array([cycle.tau, omega0])
    steps = np.array([1e-6 * scale, 1e-6 * omega])
    r = residual(x)
    for _ in range(PERIODIC_STEPS):
        if np.max(np.abs(r)) <= 100.0 * rtol:
            break
        jac = np.column_stack([(residual(x + np.eye(2)[j] * steps[j]) - r) / steps[j]
                               for j in range(2)])
        x = x - np.linalg.solve(jac, r)
        r = residual(x)
    else:
        raise ComputationError(f"{mech.name}: no periodic motion at {omega!r} rad/s found with "
                               f"friction in {PERIODIC_STEPS} Newton steps (closes to "
                               f"{float(np.max(np.abs(r))):.3g} relative)")
    motion_ = run(x, count)
    t = motion_.index.to_numpy()
    w = motion_["omega"].to_numpy()
    th = motion_["theta"].to_numpy()
    w_max, th_max = _vertex(t, w, th, int(np.argmax(w)))
    w_min, th_min = _vertex(t, w, th, int(np.argmin(w)))
    end = motion_.iloc[-1]
    error = max(abs(float(end["theta"]) - span) / span, abs(float(end["omega"]) - x[1]) / omega)
    return PeriodicMotion(mech.name, omega, cycle.revolutions, float(x[0]), inertia,
                          float(x[1]), w_max, w_min, _wrap(th_max, span), _wrap(th_min, span),
                          error, motion_)


def _vertex(t: np.ndarray, w: np.ndarray, th: np.ndarray, k: int) -> tuple[float, float]:
    """The extreme of ``w`` about the sample ``k`` (the first and last are one, the
    motion being periodic), and the angle there: the vertex of the parabola through
    the three samples about it (an error of order ``step**3``)."""
    n = w.size - 1  # the last sample is the first again
    k %= n
    i, j = (k - 1) % n, (k + 1) % n
    h = t[1] - t[0]
    a, b, c = w[i], w[k], w[j]
    curvature = a - 2.0 * b + c
    s = 0.0 if curvature == 0.0 else 0.5 * (a - c) / curvature  # in steps, within +-1/2
    s = min(max(s, -0.5), 0.5)
    value = b - 0.25 * (a - c) * s
    # theta about the sample: theta' = omega, so theta(s) = th_k + h (b s + (c - a) s^2/4)
    return float(value), float(th[k] + h * (b * s + 0.25 * (c - a) * s * s))


def _wrap(theta: float, span: float) -> float:
    return theta % span


def _value(value, unit: str, name: str) -> float:
    if isinstance(value, str):
        value = evaluate(value, unit, name)
    return finite_float(name, value.item() if isinstance(value, np.ndarray) else value)


def _speed(value, name: str) -> float:
    omega = _value(value, "rad/s", name)
    if not omega > 0.0:
        raise InputError(f"{name} must be > 0 (the crank's mean speed, rad/s), got {omega!r}")
    return omega


def _fraction(value) -> float:
    cs = _value(value, "1", "Cs")
    if not 0.0 < cs < 1.0:
        raise InputError(f"Cs must be between 0 and 1 ((omega_max - omega_min) / omega_mean, "
                         f"e.g. 0.02), got {cs!r}")
    return cs


def _count(name: str, value, least: int) -> int:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise InputTypeError(f"{name} must be an integer, got {type(value).__name__} {value!r}")
    if value < least:
        raise InputError(f"{name} must be >= {least}, got {value!r}")
    return int(value)


def cycle_revolutions(mech, revolutions: int | None = None, given=()) -> int:
    """The revolutions of the crank in a cycle: ``revolutions`` if given, else 1 or the
    most that a load's table over the cycle needs (the loads named in ``given`` are
    given values: no table). The four-stroke engine of ``examples/engine.toml``, its gas
    force a table over ``period_deg = 720``: 2.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> cycle_revolutions(presets.get("four_bar")), cycle_revolutions(presets.get("four_bar"), 3)
    (1, 3)
    """
    if revolutions is not None:
        return _count("revolutions", revolutions, 1)
    return max([1] + [math.ceil(ld.table.period_deg / 360.0 - 1e-9)
                      for ld in mech.computed_loads
                      if ld.table is not None and ld.name not in given])
