"""Transmission angles over the crank angle (:func:`transmission`), and the toggle
positions, where a dyad's angle reaches 0 or pi (:func:`toggles`)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..drivers import one_crank
from ..errors import InputError
from ..printing import number
from .figures import degree_axis, figure_axes, greek
from .inputs import crank_angles, finite_or_fail

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..mechanism import Mechanism

#: a transmission angle within this of 0 or pi [rad] is a toggle
TOGGLE_TOL = 1e-6


def _valid_at(mech: "Mechanism", name: str, t: float) -> bool:
    return bool(mech.solve(np.array([t]), outputs=(name,)).valid[0])


def _distance_to_toggle(mech: "Mechanism", name: str, t: float) -> float:
    gamma = float(mech.solve(np.array([t]), outputs=(name,))[name][0])
    return min(gamma, math.pi - gamma) if math.isfinite(gamma) else math.inf


def toggles(mech: "Mechanism", name: str, theta: np.ndarray, gamma: np.ndarray,
            valid: np.ndarray) -> list[float]:
    """Crank angles [rad] within ``theta`` at which the dyad of the transmission angle
    ``name`` is at a toggle (``gamma`` = 0 or pi): the limits of the ranges where the
    linkage cannot be assembled (found by bisection to 1e-12 rad, on the side where it
    can), and, where it can, angles where ``gamma`` touches 0 or pi (local minima of
    ``min(gamma, pi - gamma)`` refined on the solver, kept if below :data:`TOGGLE_TOL`).
    ``gamma`` and ``valid`` are the solver's at ``theta``.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("slider_crank", l_OA=0.2, l_AB=0.15)  # too short a rod
    >>> t = np.radians(np.linspace(0, 360, 73))
    >>> sol = mech.solve(t, outputs=("gamma_B",))
    >>> [round(float(np.degrees(a)), 4)
    ...  for a in toggles(mech, "gamma_B", t, sol["gamma_B"], sol.valid)]
    [48.5904, 131.4096, 228.5904, 311.4096]
    """
    found = []
    for i in np.flatnonzero(valid[:-1] != valid[1:]):
        good, bad = (theta[i], theta[i + 1]) if valid[i] else (theta[i + 1], theta[i])
        while abs(bad - good) > 1e-12:
            mid = 0.5 * (good + bad)
            if mid in (good, bad):
                break
            good, bad = (mid, bad) if _valid_at(mech, name, mid) else (good, mid)
        found.append(float(good))
    d = np.minimum(gamma, np.pi - gamma)
    inner = np.flatnonzero(valid[1:-1] & valid[:-2] & valid[2:]) + 1
    for i in inner:
        if d[i] < d[i - 1] and d[i] <= d[i + 1] and d[i] < math.radians(10.0):
            from scipy.optimize import minimize_scalar

            lo, hi = sorted((theta[i - 1], theta[i + 1]))
            res = minimize_scalar(lambda t: _distance_to_toggle(mech, name, t),
                                  bounds=(lo, hi), method="bounded",
                                  options={"xatol": 1e-12})
            if res.fun < TOGGLE_TOL:
                found.append(float(res.x))
    return sorted(found)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """``(first, last)`` index of each run of True in ``mask``.

    Examples
    --------
    >>> _runs(np.array([True, True, False, True]))
    [(0, 1), (3, 3)]
    """
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return [(int(a), int(b) - 1) for a, b in zip(np.flatnonzero(edges == 1),
                                                  np.flatnonzero(edges == -1))]


def transmission(mech: "Mechanism", theta=None, *, theta_deg=None,
                 ax: "Axes | None" = None) -> "Figure":
    """Every transmission angle ``gamma_<joint>`` in degrees against the crank angle in
    degrees, with each one's minimum and the toggle positions marked.

    Parameters
    ----------
    mech : Mechanism
    theta : array_like, optional
        Crank angles [rad]; or ``theta_deg`` [deg]; default 0..360 deg, 721 angles.
    theta_deg : array_like, optional
        Crank angles [deg], instead of ``theta``.
    ax : matplotlib Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    Figure
        Lines (gid): ``gamma_<joint>`` (``degrees(gamma)``; gaps where the linkage cannot
        be assembled, shaded ``gid="invalid"``), ``min:gamma_<joint>`` (one point at the
        smallest angle, annotated) and ``toggle:gamma_<joint>`` (a vertical line at each
        :func:`toggles` angle, in degrees).

    Raises
    ------
    ValueError
        ``mech`` has no transmission angle (no dyad), or cannot be assembled at any angle.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from linkage_fmu import plot, presets
    >>> # |BD| reaches BC + CD
    >>> fig = plot.transmission(presets.get("four_bar", l_AB=0.3))
    >>> # the last line of each gid
    >>> lines = {line.get_gid(): line for line in fig.axes[0].lines}
    >>> sorted(lines)
    ['gamma_C', 'min:gamma_C', 'toggle:gamma_C']
    >>> [round(float(line.get_xdata()[0]), 3) for line in fig.axes[0].lines
    ...  if line.get_gid() == "toggle:gamma_C"]
    [135.951, 224.049]
    """
    one_crank(mech, "a plot over crank angles")
    names = [n for n in mech.diagnostic_names if n.startswith("gamma_")]
    if not names:
        raise InputError(f"{mech.name} has no dyad, so no transmission angle")
    rad, deg = crank_angles(theta, theta_deg)
    sol = mech.solve(rad, outputs=tuple(names))
    valid = np.broadcast_to(np.asarray(sol.valid, dtype=bool), rad.shape)

    fig, ax = figure_axes(ax)
    for lo, hi in _runs(~valid):  # shade the angles where it cannot be assembled
        a, b = deg[max(lo - 1, 0)], deg[min(hi + 1, deg.size - 1)]
        ax.axvspan(min(a, b), max(a, b), color="0.9", lw=0, zorder=0, gid="invalid")
    for k, name in enumerate(names):
        gamma = np.asarray(sol[name], dtype=float)
        finite_or_fail(mech, gamma, deg)
        color = f"C{k % 10}"
        label = greek(name)
        ax.plot(deg, np.degrees(gamma), color=color, lw=1.6, label=label, gid=name)
        i = int(np.nanargmin(gamma))
        ax.plot([deg[i]], [np.degrees(gamma[i])], "v", color=color, ms=8,
                label=f"min {label} = {number(np.degrees(gamma[i]), 1, fixed=True)}°",
                gid=f"min:{name}")
        ax.annotate(f"min {label} = {number(np.degrees(gamma[i]), 1, fixed=True)}°\n"
                    f"at θ = {number(deg[i], 1, fixed=True)}°",
                    (deg[i], np.degrees(gamma[i])), xytext=(8, -18), textcoords="offset points",
                    fontsize=9, color=color, gid=f"min label:{name}")
        for j, t in enumerate(toggles(mech, name, rad, gamma, valid)):
            ax.axvline(np.degrees(t), color=color, ls="--", lw=1.0,
                       label=f"toggle of {label}" if not j else None, gid=f"toggle:{name}")
    ax.axhspan(40.0, 140.0, color="C2", alpha=0.06, zorder=0, gid="good range")
    degree_axis(ax, deg)
    ax.set_ylim(0.0, 180.0)
    ax.set_yticks(np.arange(0.0, 181.0, 30.0))
    ax.set_ylabel("transmission angle γ [°]")
    ax.set_title(f"{mech.name}: transmission angles (0° or 180°: toggle; "
                 "shaded 40°-140°)", fontsize=10)
    ax.legend(loc="best", fontsize=9)
    return fig
