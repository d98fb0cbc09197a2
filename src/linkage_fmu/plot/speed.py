"""The crank's speed over a cycle of its steady motion under a constant torque, with a
flywheel or without (:func:`speed`)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputTypeError
from ..flywheel import flywheel as size_flywheel
from ..flywheel import periodic_motion
from ..printing import number
from .figures import degree_axis, figure_axes
from .inputs import input_values

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..mechanism import Mechanism

_RPM = 30.0 / math.pi


def speed(mech: "Mechanism", omega=None, *loads, Cs=None, flywheel=None,
          revolutions: int | None = None, ax: "Axes | None" = None,
          **named_loads) -> "Figure":
    """The crank's speed against the crank angle in degrees over a cycle of the steady
    periodic motion at the mean speed ``omega``, driven by the constant torque that
    keeps it (the cycle mean of ``Mb`` at constant speed): the linkage alone, with a
    flywheel of inertia ``flywheel``, or with the flywheel sized for ``Cs``
    (:func:`~linkage_fmu.flywheel.flywheel`).

    Parameters
    ----------
    mech : Mechanism
        A linkage whose balancing effort is a moment on its crank.
    omega : float or str, optional
        The mean speed [rad/s] (or text with a unit); the linkage's start speed if not
        given.
    *loads, **named_loads : float, optional
        The loads, by position (as after ``alpha`` in
        :meth:`~linkage_fmu.Mechanism.solve`) or name; start values if not given.
    Cs : float or str, optional
        Size the flywheel for this coefficient of fluctuation of speed, and mark the
        width it allows, ``Cs omega``, about the middle of the speed's swing.
    flywheel : float or str, optional
        Or the flywheel's moment of inertia [kg m2] (default none).
    revolutions : int, optional
        Revolutions in the cycle (default as :func:`~linkage_fmu.flywheel.flywheel`).
    ax : matplotlib Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    Figure
        Lines (gid): ``"omega"`` (the integrated motion's speed [rad/s] against its
        angle [deg]), ``"mean"`` (the mean speed), ``"max"`` and ``"min"`` (the highest
        and lowest speed, each one point, refined between the samples) and, with
        ``Cs``, two lines ``"band"`` at ``(omega_max + omega_min) / 2 +- Cs omega / 2``
        (the speed stays between them if the flywheel holds it within ``Cs``). A second
        axis on the right gives rpm.

    Raises
    ------
    TypeError
        ``Cs`` and ``flywheel`` both given; an unknown load.
    ValueError
        As :func:`~linkage_fmu.flywheel.flywheel` raises.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from linkage_fmu import plot, presets
    >>> fig = plot.speed(presets.get("four_bar"), 10.0, load=3.0, Cs=0.05)
    >>> ax = fig.axes[0]
    >>> [line.get_gid() for line in ax.lines]
    ['omega', 'mean', 'band', 'band', 'max', 'min']
    >>> x, y = ax.lines[0].get_data()
    >>> float(x[0]), round(float(x[-1]), 6), len(x)  # the motion's angles: a turn
    (0.0, 360.0, 721)
    >>> ax.lines[1].get_label()
    'mean 10 rad/s (95.49 rpm)'
    """
    if Cs is not None and flywheel is not None:
        raise InputTypeError("give Cs (to size the flywheel) or flywheel (its inertia), not both")
    inputs = input_values(mech, omega, None, loads, named_loads)
    named = {k: v for k, v in inputs.items() if k not in ("omega", "alpha")}
    if Cs is not None:
        sized = size_flywheel(mech, inputs["omega"], Cs, revolutions=revolutions, **named)
        run, asked = sized.run, sized.Cs
    else:
        run = periodic_motion(mech, inputs["omega"], 0.0 if flywheel is None else flywheel,
                              revolutions=revolutions, **named)
        asked = None
    deg = np.degrees(run.motion["theta"].to_numpy())
    w = run.motion["omega"].to_numpy()
    mean = run.omega_mean

    fig, ax = figure_axes(ax)
    ax.plot(deg, w, color="C0", lw=1.6, label="ω", gid="omega")
    ax.axhline(mean, color="C1", ls="--", lw=1.2,
               label=f"mean {number(mean)} rad/s ({number(mean * _RPM)} rpm)", gid="mean")
    if asked is not None:  # the width Cs asks for, about the middle of the swing
        middle = 0.5 * (run.omega_max + run.omega_min)
        for k, sign in enumerate((1.0, -1.0)):
            ax.axhline(middle + sign * asked * mean / 2.0, color="0.5", ls=":", lw=1.0,
                       label=f"width Cs ω_mean, Cs = {number(asked, 6)}" if k == 0 else None,
                       gid="band")
    for gid, value, where, colour in (("max", run.omega_max, run.theta_omega_max, "C3"),
                                      ("min", run.omega_min, run.theta_omega_min, "C2")):
        ax.plot([math.degrees(where)], [value], "o", color=colour, ms=6,
                label=f"{gid} {number(value, 5)} rad/s at "
                f"θ = {number(math.degrees(where), 1, fixed=True)}°", gid=gid)
    degree_axis(ax, deg)
    ax.set_ylabel("crank speed ω [rad/s]")
    rpm = ax.secondary_yaxis("right", functions=(lambda v: v * _RPM, lambda v: v / _RPM))
    rpm.set_ylabel("[rpm]")
    ax.legend(loc="best", fontsize=9)
    what = (f"flywheel {number(run.flywheel)} kg·m² (sized for Cs = {number(asked, 6)})"
            if asked is not None else f"flywheel {number(run.flywheel)} kg·m²"
            if run.flywheel else "no flywheel")
    # tau is the mean of Mb at constant speed over the cycle: zero for conservative
    # loads, to within the rounding of a sum of Mb's values (four-bar, 10 rad/s, no
    # load: -2.3e-17 N m of Mb up to 0.27 N m)
    effort = mech.solve(np.radians(deg), mean, 0.0, outputs=(mech.effort.name,),
                        **named)[mech.effort.name]
    size = float(np.nanmax(np.abs(effort), initial=0.0))
    ax.set_title(f"{mech.name}: crank speed under a constant torque "
                 f"τ = {number(run.tau, scale=size)} N·m, {what}\n"
                 f"Cs = (ω_max - ω_min) / ω_mean = {number(run.Cs)}", fontsize=10)
    return fig
