"""The curves over the crank angle: an output (:func:`torque`), a pin force's polar
diagram (:func:`polar`), the shaking force and moment (:func:`shaking`), and the numbers
they are marked with (:func:`revolution_mean`, :func:`rounded`)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..drivers import one_crank
from ..errors import InputError, InputTypeError
from ..outputs import SHAKING
from ..printing import ZERO_FRACTION, number  # noqa: F401 (re-exported)
from .figures import degree_axis, figure_axes, greek, pyplot
from .inputs import crank_angles, finite_or_fail, input_values, inputs_text, solve_at
from .parts import find_pair

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..mechanism import Mechanism

# -- numbers behind the plots ------------------------------------------------------------
def revolution_mean(theta: np.ndarray, values: np.ndarray) -> float:
    """Mean of ``values`` over the crank angle ``theta`` (trapezoidal rule), over the
    intervals where both ends are finite: over a whole revolution sampled at equal
    steps, with the last angle the first plus 2 pi, the plain mean of all but the last.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 5)
    >>> revolution_mean(t, np.array([1.0, 2.0, 3.0, 2.0, 1.0]))
    2.0
    >>> revolution_mean(t, np.array([1.0, 2.0, np.nan, 2.0, 1.0]))  # 0..90 and 270..360
    1.5
    """
    y0, y1 = values[:-1], values[1:]
    dt = np.diff(theta)
    ok = np.isfinite(y0) & np.isfinite(y1)
    if not ok.any():
        finite = values[np.isfinite(values)]
        return float(finite.mean()) if finite.size else math.nan
    return float(np.sum(0.5 * (y0[ok] + y1[ok]) * dt[ok]) / np.sum(dt[ok]))


def rounded(value: float, scale: float) -> str:
    """``value`` to 4 significant digits, or ``"0"`` where it is within
    :data:`ZERO_FRACTION` of ``scale`` (e.g. the largest ``|value|`` of the curve whose
    mean it is): what rounding leaves of a zero sum of numbers that size is far less,
    and a real mean that small would not show on the curve either.

    Examples
    --------
    >>> rounded(3.534e-17, 18.92), rounded(-0.0, 0.0), rounded(0.123456, 18.92)
    ('0', '0', '0.1235')
    >>> rounded(2.5e-11, 18.92), rounded(float("nan"), 1.0)
    ('2.5e-11', 'nan')
    """
    return number(value, 4, scale=scale)


def _peak(values: np.ndarray) -> int:
    """Index of the largest finite ``|values|`` (the first if several)."""
    magnitude = np.abs(values)
    if not np.isfinite(magnitude).any():
        raise InputError("no finite value: the linkage cannot be assembled at any of the angles")
    return int(np.nanargmax(np.where(np.isfinite(magnitude), magnitude, np.nan)))


# -- torque ------------------------------------------------------------------------------
def _output(mech: "Mechanism", output: str | None) -> str:
    """``output`` checked against the outputs and diagnostics; the balancing effort if
    None."""
    one_crank(mech, "a plot over crank angles")
    if output is None:
        return mech.effort.name
    choices = mech.output_names + mech.diagnostic_names
    if output not in choices:
        raise InputError(f"{mech.name} has no output {output!r}; its outputs are: "
                         + ", ".join(choices))
    return output


def torque(mech: "Mechanism", theta=None, omega=None, alpha=None, *loads,
           output: str | None = None, theta_deg=None, ax: "Axes | None" = None,
           **named_loads) -> "Figure":
    """An output (the balancing effort by default) against the crank angle in degrees,
    with its mean over the angles and its peak magnitude marked.

    Parameters
    ----------
    mech : Mechanism
    theta : array_like, optional
        Crank angles [rad]; or ``theta_deg`` [deg]; default 0..360 deg, 721 angles.
    omega, alpha, *loads, **named_loads : float, optional
        Crank speed [rad/s], acceleration [rad/s2] and loads, by position or name;
        the linkage's start values if not given.
    output : str, optional
        An output or diagnostic name; default ``mech.effort.name``.
    theta_deg : array_like, optional
        Crank angles [deg], instead of ``theta``.
    ax : matplotlib Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    Figure
        Lines (gid): the output (``output``'s name; NaN where the linkage cannot be
        assembled, drawn as gaps), ``"mean"`` (horizontal, at
        :func:`revolution_mean` of the output; its legend label gives it
        :func:`rounded` against the peak) and ``"peak"`` (one point at the largest
        ``|output|``, annotated with its angle and value).

    Raises
    ------
    ValueError
        ``output`` is not an output of ``mech`` (the message lists them), or the
        linkage cannot be assembled at any angle.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from linkage_fmu import plot, presets
    >>> fig = plot.torque(presets.get("slider_crank"), omega=100.0, load=200.0)
    >>> ax = fig.axes[0]
    >>> [line.get_gid() for line in ax.lines]
    ['Mb', 'mean', 'peak', 'zero']
    >>> x, y = ax.lines[0].get_data()
    >>> len(x), float(x[0]), float(x[-1])
    (721, 0.0, 360.0)
    >>> abs(float(ax.lines[1].get_ydata()[0])) < 1e-12  # mean Mb: no work a turn
    True
    >>> ax.texts[0].get_text()                          # the peak
    '-18.92 N.m\\nat θ = 111.0°'
    """
    name = _output(mech, output)
    rad, deg = crank_angles(theta, theta_deg)
    inputs = input_values(mech, omega, alpha, loads, named_loads)
    sol = solve_at(mech, rad, inputs)
    values = np.asarray(sol[name], dtype=float)
    finite_or_fail(mech, values, deg, sol)
    unit, description = mech.output_info[name]

    fig, ax = figure_axes(ax)
    draw_curve(ax, rad, deg, values, name, unit)
    ax.set_title(f"{mech.name}: {description}\n{inputs_text(mech, inputs)}", fontsize=10)
    return fig


def draw_curve(ax: "Axes", rad: np.ndarray, deg: np.ndarray, values: np.ndarray, name: str,
                unit: str, scale: float = 0.0) -> None:
    """The curve of :func:`torque`: ``values`` against ``deg``, their mean over ``rad``
    and their peak magnitude, a line at 0, the axes' labels and the legend; the mean
    printed 0 within :data:`ZERO_FRACTION` of the peak or ``scale``, the peak within
    it of ``scale`` (the size of the terms the values are sums of)."""
    mean = revolution_mean(rad, values)
    i = _peak(values)
    scale = abs(scale) if math.isfinite(scale) else 0.0
    ax.plot(deg, values, color="C0", lw=1.6, label=name, gid=name)
    ax.axhline(mean, color="C1", ls="--", lw=1.2,
               label=f"mean {rounded(mean, max(abs(values[i]), scale))} {unit}", gid="mean")
    ax.plot([deg[i]], [values[i]], "o", color="C3", ms=7,
            label=f"peak |{name}| {number(abs(values[i]), scale=scale)} {unit}", gid="peak")
    # beside the peak on the side with room: to its left in the right half of the axes
    left = deg[i] > (float(np.nanmin(deg)) + float(np.nanmax(deg))) / 2.0
    ax.annotate(f"{number(values[i], scale=scale)} {unit}\n"
                f"at θ = {number(deg[i], 1, fixed=True)}°",
                (deg[i], values[i]), xytext=(-12 if left else 12, -14 if values[i] > 0 else 14),
                textcoords="offset points", ha="right" if left else "left",
                va="top" if values[i] > 0 else "bottom", fontsize=9, gid="peak label")
    ax.axhline(0.0, color="0.6", lw=0.8, zorder=0, gid="zero")
    degree_axis(ax, deg)
    ax.set_ylabel(f"{greek(name)} [{unit}]")
    ax.legend(loc="best", fontsize=9)


# -- polar -------------------------------------------------------------------------------
def polar(mech: "Mechanism", force: str | None = None, theta=None, omega=None, alpha=None,
          *loads, theta_deg=None, ax: "Axes | None" = None, **named_loads) -> "Figure":
    """The polar diagram of a pin force over the crank angles: the curve ``(Fx, Fy)``
    traced by the force vector (for bearing sizing), the origin, and the largest force.

    Parameters
    ----------
    mech : Mechanism
    force : str, optional
        A force pair of :func:`force_pairs`, by its name (``"F21"``, the six-bar's
        ``"O"``) or a component's (``"F21x"``); default the first pair.
    theta, omega, alpha, *loads, theta_deg, ax, **named_loads
        As for :func:`torque`.

    Returns
    -------
    Figure
        Lines (gid): the pair's name (x data ``Fx``, y data ``Fy``, equal aspect),
        ``"origin"`` (the point (0, 0)), ``"start"`` (the first angle),
        ``"peak"`` (the largest ``|F|``, annotated with it and its angle) and
        ``"peak vector"`` (origin to peak).

    Raises
    ------
    ValueError
        ``force`` is not a force pair of ``mech`` (the message lists them).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from linkage_fmu import plot, presets
    >>> fig = plot.polar(presets.get("four_bar"), "F21", omega=10.0)
    >>> ax = fig.axes[0]
    >>> [line.get_gid() for line in ax.lines]
    ['x axis', 'y axis', 'F21', 'origin', 'start', 'peak', 'peak vector']
    >>> plot.polar(presets.get("four_bar"), "F99")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError:
    four_bar has no force pair 'F99'; its force pairs are: F21 (F21x,
    F21y), ...
    """
    pair = find_pair(mech, force)
    rad, deg = crank_angles(theta, theta_deg)
    inputs = input_values(mech, omega, alpha, loads, named_loads)
    sol = solve_at(mech, rad, inputs)
    fx, fy = (np.asarray(sol[n], dtype=float) for n in (pair.x, pair.y))
    finite_or_fail(mech, fx, deg, sol)

    fig, ax = figure_axes(ax, figsize=(6.5, 6.5))
    _draw_hodograph(ax, fx, fy, deg, pair.name, pair.x, pair.y)
    who = f": force of link {pair.by} on link {pair.on}" if pair.by is not None else ""
    ax.set_title(f"{mech.name}, {pair.name}{who}\n{inputs_text(mech, inputs)}", fontsize=10)
    return fig


def _draw_hodograph(ax: "Axes", fx: np.ndarray, fy: np.ndarray, deg: np.ndarray, name: str,
                    x: str, y: str) -> None:
    """The diagram of :func:`polar`: the curve ``(fx, fy)`` [N] (gid ``name``; ``x``
    and ``y`` name its components on the axes), the origin, the first angle, the
    largest force, equal aspect, and the legend."""
    i = _peak(np.hypot(fx, fy))
    magnitude = math.hypot(fx[i], fy[i])
    ax.axhline(0.0, color="0.6", lw=0.8, zorder=0, gid="x axis")
    ax.axvline(0.0, color="0.6", lw=0.8, zorder=0, gid="y axis")
    ax.plot(fx, fy, color="C0", lw=1.6, label=f"{name} over θ", gid=name)
    ax.plot([0.0], [0.0], "+", color="k", ms=12, mew=1.5, label="origin", gid="origin")
    j = int(np.flatnonzero(np.isfinite(fx) & np.isfinite(fy))[0])
    ax.plot([fx[j]], [fy[j]], "s", color="C2", ms=6, label=f"θ = {number(deg[j], 6)}°",
            gid="start")
    ax.plot([fx[i]], [fy[i]], "o", color="C3", ms=7, label=f"max |{name}| {number(magnitude)} N",
            gid="peak")
    ax.plot([0.0, fx[i]], [0.0, fy[i]], "--", color="C3", lw=1.0, gid="peak vector")
    ax.annotate(f"|{name}| = {number(magnitude)} N\nat θ = {number(deg[i], 1, fixed=True)}°",
                (fx[i], fy[i]), xytext=(10, 10), textcoords="offset points", fontsize=9,
                gid="peak label")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"{x} [N]")
    ax.set_ylabel(f"{y} [N]")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=9)


# -- shaking force and moment ------------------------------------------------------------
def shaking(mech: "Mechanism", theta=None, omega=None, alpha=None, *loads, theta_deg=None,
            ax=None, **named_loads) -> "Figure":
    """What the moving links put on the frame over the crank angles: the polar diagram
    of the shaking force (the curve ``(shake_x, shake_y)`` traced by its tip, as
    :func:`polar` draws a pin force), and the shaking moment about the crank's pivot
    against the crank angle in degrees (as :func:`torque` draws an output).

    The shaking force and moment (:data:`~linkage_fmu.outputs.SHAKING`) are the
    resultant of the joint forces on the frame and the driver's reaction: what the
    foundation has to hold, and what balancing aims to make small.

    Parameters
    ----------
    mech : Mechanism
    theta, omega, alpha, *loads, theta_deg, **named_loads
        As for :func:`torque`.
    ax : pair of matplotlib Axes, optional
        Where to draw the force's diagram and the moment; a new figure with the two
        side by side if None.

    Returns
    -------
    Figure
        The figure of the axes. The force's axes hold lines (gid) ``"shake"`` (x data
        ``shake_x``, y data ``shake_y`` [N], equal aspect), ``"origin"``, ``"start"``,
        ``"peak"`` (the largest ``|(shake_x, shake_y)|``, annotated) and ``"peak
        vector"``; the moment's, ``"shake_M"`` (against the angle in degrees),
        ``"mean"``, ``"peak"`` and ``"zero"``, as :func:`torque`.

    Raises
    ------
    TypeError
        ``ax`` is not a pair of axes.
    ValueError
        The linkage cannot be assembled at any angle.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from linkage_fmu import plot, presets
    >>> mech = presets.get("four_bar")
    >>> fig = plot.shaking(mech, omega=10.0)
    >>> force, moment = fig.axes
    >>> [line.get_gid() for line in force.lines]
    ['x axis', 'y axis', 'shake', 'origin', 'start', 'peak', 'peak vector']
    >>> [line.get_gid() for line in moment.lines]
    ['shake_M', 'mean', 'peak', 'zero']
    >>> sol = mech.solve(np.radians(np.linspace(0, 360, 721)), omega=10.0)
    >>> x, y = force.lines[2].get_data()
    >>> bool(np.array_equal(x, sol["shake_x"])
    ...      and np.array_equal(y, sol["shake_y"]))
    True
    """
    if ax is not None:
        try:
            force_ax, moment_ax = ax
        except (TypeError, ValueError):
            raise InputTypeError("ax must be a pair of Axes: (the force's, the moment's), "
                                 f"got {ax!r}") from None
    rad, deg = crank_angles(theta, theta_deg)
    inputs = input_values(mech, omega, alpha, loads, named_loads)
    sol = solve_at(mech, rad, inputs)
    fx, fy, moment = (np.asarray(sol[n], dtype=float) for n in SHAKING)
    finite_or_fail(mech, fx, deg, sol)

    if ax is None:
        fig, (force_ax, moment_ax) = pyplot().subplots(
            1, 2, figsize=(13.0, 5.5), layout="constrained", width_ratios=(1.0, 1.3))
    else:
        fig = force_ax.figure
    x, y, m = SHAKING
    _draw_hodograph(force_ax, fx, fy, deg, "shake", x, y)
    force_ax.set_title(f"{mech.name}: shaking force, what the moving links put on the "
                       f"frame\n{inputs_text(mech, inputs)}", fontsize=10)
    # the moment is a sum of forces the size of the shaking force times lengths: the
    # scotch yoke's is zero but for rounding (1e-14 N m beside 10 N m)
    force = np.hypot(fx, fy)
    arm = float(np.nanmax(force, initial=0.0)) * mech.length_scale
    draw_curve(moment_ax, rad, deg, moment, m, mech.output_info[m][0], scale=arm)
    moment_ax.set_title(f"shaking moment about the crank pivot {mech.crank.pivot}, "
                        "counter-clockwise positive", fontsize=10)
    return fig


# -- friction losses ---------------------------------------------------------------------
def loss(mech: "Mechanism", theta=None, omega=None, alpha=None, *loads, theta_deg=None,
         ax=None, **named_loads) -> "Figure":
    """What friction in the joints costs over the crank angles: the power it dissipates,
    ``P_loss`` [W], with its mean and peak (as :func:`torque` draws an output), and
    below, the instantaneous efficiency ``eta`` (:mod:`~linkage_fmu.friction`) with
    its minimum marked and the frictionless 1.

    Parameters
    ----------
    mech : Mechanism
        A linkage with friction in its joints (a ``[friction.J]`` table; every preset).
    theta, omega, alpha, *loads, theta_deg, **named_loads
        As for :func:`torque`.
    ax : pair of matplotlib Axes, optional
        Where to draw ``P_loss`` and ``eta``; a new figure with the two one above the
        other (the angle axis shared) if None.

    Returns
    -------
    Figure
        The figure of the axes. The first axes hold lines (gid) ``"P_loss"`` (against
        the angle in degrees), ``"mean"``, ``"peak"`` and ``"zero"``, as
        :func:`torque`; the second, ``"eta"``, ``"min"`` (one point at its smallest
        value, annotated) and ``"ideal"`` (horizontal at 1, no friction).

    Raises
    ------
    TypeError
        ``ax`` is not a pair of axes.
    ValueError
        The linkage has no friction in its joints, or it cannot be assembled at any
        angle.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from linkage_fmu import plot, presets
    >>> mech = presets.get("slider_crank", mu_guide=0.1, mu_A=0.1, r_A=0.01)
    >>> fig = plot.loss(mech, omega=10.0, load=100.0)
    >>> power, eta = fig.axes
    >>> [line.get_gid() for line in power.lines]
    ['P_loss', 'mean', 'peak', 'zero']
    >>> [line.get_gid() for line in eta.lines]
    ['eta', 'ideal', 'min']
    """
    if "P_loss" not in mech.output_names:
        raise InputError(f"{mech.name} has no friction in its joints (no [friction.J] "
                         "table): no P_loss or eta to draw")
    if ax is not None:
        try:
            power_ax, eta_ax = ax
        except (TypeError, ValueError):
            raise InputTypeError("ax must be a pair of Axes: (P_loss's, eta's), "
                                 f"got {ax!r}") from None
    rad, deg = crank_angles(theta, theta_deg)
    inputs = input_values(mech, omega, alpha, loads, named_loads)
    sol = solve_at(mech, rad, inputs)
    power, eta = (np.asarray(sol[n], dtype=float) for n in ("P_loss", "eta"))
    finite_or_fail(mech, power, deg, sol)

    if ax is None:
        fig, (power_ax, eta_ax) = pyplot().subplots(2, 1, figsize=(8.0, 7.0), sharex=True,
                                                    layout="constrained")
    else:
        fig = power_ax.figure
    draw_curve(power_ax, rad, deg, power, "P_loss", mech.output_info["P_loss"][0])
    power_ax.set_title(f"{mech.name}: {mech.output_info['P_loss'][1]}\n"
                       f"{inputs_text(mech, inputs)}", fontsize=10)
    finite = np.isfinite(eta)
    i = int(np.flatnonzero(finite)[np.argmin(eta[finite])]) if finite.any() else None
    eta_ax.plot(deg, eta, color="C0", lw=1.6, label="η", gid="eta")
    eta_ax.axhline(1.0, color="0.6", ls=":", lw=1.0, label="no friction", gid="ideal")
    if i is not None:
        eta_ax.plot([deg[i]], [eta[i]], "o", color="C3", ms=7, label=f"min η {number(eta[i])}",
                    gid="min")
        eta_ax.annotate(f"{number(eta[i])}\nat θ = {number(deg[i], 1, fixed=True)}°",
                        (deg[i], eta[i]), xytext=(12, 14), textcoords="offset points",
                        va="bottom", fontsize=9, gid="min label")
    degree_axis(eta_ax, deg)
    eta_ax.set_ylabel("η [1]")
    eta_ax.set_title("instantaneous efficiency: 1 - P_loss / P_in (P_in: the power entering)",
                     fontsize=10)
    eta_ax.legend(loc="best", fontsize=9)
    return fig
