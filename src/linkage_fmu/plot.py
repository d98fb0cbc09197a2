"""Plots of a linkage's kinetostatics: driving torque, pin-force polars, the linkage
with its joint forces and loads, transmission angles, and the shaking force and moment.

Every public function returns a :class:`matplotlib.figure.Figure` and draws into the
``ax`` given, or into a new figure (made with :mod:`matplotlib.pyplot`, so ``plt.show()``
shows it). matplotlib is needed only here: ``pip install "linkage_fmu[plot]"``.

Angles: ``theta`` is the crank angle in radians (as in :meth:`Mechanism.solve
<linkage_fmu.Mechanism.solve>`), or give ``theta_deg`` in degrees instead; without
either, a revolution of :data:`N_ANGLES` angles 0, 0.5, ..., 360 degrees. The plots'
horizontal axes are in degrees: the given ``theta_deg`` itself, else ``degrees(theta)``.

Inputs: ``omega``, ``alpha`` and each load (by position after ``alpha``, as in
:meth:`~linkage_fmu.Mechanism.solve`, or by name) that are not given take the linkage's
start values (its ``[inputs]`` table and each load's ``start``), as ``mech.solve`` and
``linkage-fmu table`` do; a load over the cycle is computed at each angle unless given
by name.

What is drawn carries a ``gid`` (``artist.get_gid()``), so that scripts and tests can
find it: the curves by output name, ``"mean"``, ``"peak"``, ``"origin"``,
``"forces"`` (a quiver), ``"load:<name>"``, ``"toggle:<mu>"`` and so on (see each
function).

Examples
--------
>>> import matplotlib
>>> matplotlib.use("Agg")
>>> import io
>>> from linkage_fmu import plot, presets
>>> mech = presets.get("four_bar")
>>> fig = plot.torque(mech, omega=10.0, load=5.0)
>>> fig.savefig(io.BytesIO(), format="png")
>>> [p.name for p in plot.force_pairs(mech)]
['F21', 'F32', 'F43', 'F14']
"""

from __future__ import annotations

import math
import re
from typing import TYPE_CHECKING, NamedTuple, Sequence

import numpy as np

from .outputs import SHAKING, joint_between

try:  # the linkage's label placer is an artist; without matplotlib, _pyplot() says so
    from matplotlib.artist import Artist as _Artist
    from matplotlib.text import Text as _Text
except ImportError:  # pragma: no cover
    _Artist = _Text = object

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from .loads import Load
    from .mechanism import Mechanism

__all__ = ["torque", "polar", "linkage", "transmission", "shaking", "ForcePair",
           "force_pairs", "link_points", "revolution_mean", "rounded", "toggles",
           "place_boxes", "N_ANGLES", "ARROW_FRACTION", "MOMENT_FRACTION", "TOGGLE_TOL",
           "ZERO_FRACTION"]

#: the default crank angles: 0, 0.5, ..., 360 degrees (both ends: a closed curve)
N_ANGLES = 721
#: the default arrow scale makes the largest joint force this fraction of the linkage size
ARROW_FRACTION = 0.4
#: a transmission angle within this of 0 or pi [rad] is a toggle
TOGGLE_TOL = 1e-6
#: a mean within this fraction of its curve's largest magnitude is printed as 0
ZERO_FRACTION = 1e-12
#: a moment load is drawn as an arc of this radius, as a fraction of the linkage size
MOMENT_FRACTION = 0.06

_INSTALL = ('linkage_fmu.plot needs matplotlib (>= 3.7): pip install "linkage_fmu[plot]" '
            "(or pip install matplotlib)")
_LINK_COLORS = ("C0", "C1", "C2", "C4", "C9", "C6", "C8", "C5", "C7")  # no red: the forces
_LOAD_COLOR = "k"
_DEFAULT_FORCE = re.compile(r"^force of link (.+) on link (.+), ([xy]) component$")


def _pyplot():
    """matplotlib.pyplot, or an ImportError that says how to install it."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as err:
        raise ImportError(_INSTALL) from err
    return plt


def _axes(ax: "Axes | None", figsize=(8.0, 4.5)) -> tuple["Figure", "Axes"]:
    """``(figure, ax)``: the given axes' figure, or a new figure with one axes."""
    if ax is not None:
        return ax.figure, ax
    fig, ax = _pyplot().subplots(figsize=figsize, layout="constrained")
    return fig, ax


# -- what a linkage has ------------------------------------------------------------------
class ForcePair(NamedTuple):
    """A force output with both components: ``x`` and ``y`` are the output names of
    the force of body ``by`` on body ``on`` in the frame's axes; it acts at ``point``,
    the point of the ``joint`` between the two bodies (both None if not known)."""

    name: str
    x: str
    y: str
    by: str | None
    on: str | None
    joint: str | None
    point: str | None


def force_pairs(mech: "Mechanism") -> tuple[ForcePair, ...]:
    """The force outputs of ``mech`` that have both an x and a y component, in output
    order.

    They come from the linkage's description (its ``force`` outputs, whatever their
    component names, e.g. the six-bar's ``XO``/``YO``); for a mechanism built without
    one, from output names ``<stem>x``/``<stem>y`` (the joint is known when the
    outputs keep their default descriptions). The shaking force is not a joint's: see
    :func:`shaking`.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> force_pairs(presets.get("six_bar"))[0]
    ForcePair(name='O', x='XO', y='YO', by='0', on='OA', joint='O', point='O')
    >>> [(p.name, p.point) for p in force_pairs(presets.get("slider_crank"))]
    [('F21', 'A'), ('F32', 'B'), ('F14', 'O')]
    """
    names = set(mech.output_names)
    specs = []  # (name, x, y, by, on)
    if mech.description is not None:
        for spec in mech.description.outputs:
            if spec["kind"] == "force" and {"x", "y"} <= set(spec.get("components", "xy")):
                x, y = spec.get("x", spec["name"] + "x"), spec.get("y", spec["name"] + "y")
                specs.append((spec["name"], x, y, spec["by"], spec["on"]))
    else:
        for x in mech.output_names:
            y = x[:-1] + "y"
            if x.endswith("x") and y in names and x not in SHAKING:
                bx, by = (_DEFAULT_FORCE.match(mech.output_info[n][1]) for n in (x, y))
                known = bx and by and bx.group(1, 2) == by.group(1, 2)
                specs.append((x[:-1], x, y, *(bx.group(1, 2) if known else (None, None))))
    pairs = []
    for name, x, y, by, on in specs:
        if x not in names or y not in names:
            continue
        joint = joint_between(mech, by, on, name)[0] if by is not None else None
        pairs.append(ForcePair(name, x, y, by, on, joint and joint.name, joint and joint.point))
    return tuple(pairs)


def _find_pair(mech: "Mechanism", force: str | None) -> ForcePair:
    """The pair named ``force`` (its name or a component's), the first if None."""
    pairs = force_pairs(mech)
    if not pairs:
        raise ValueError(f"{mech.name} has no force output with x and y components")
    if force is None:
        return pairs[0]
    for p in pairs:
        if force in (p.name, p.x, p.y):
            return p
    raise ValueError(f"{mech.name} has no force pair {force!r}; its force pairs are: "
                     + ", ".join(f"{p.name} ({p.x}, {p.y})" for p in pairs))


def _output(mech: "Mechanism", output: str | None) -> str:
    """``output`` checked against the outputs and diagnostics; the balancing effort if
    None."""
    if output is None:
        return mech.effort.name
    choices = mech.output_names + mech.diagnostic_names
    if output not in choices:
        raise ValueError(f"{mech.name} has no output {output!r}; its outputs are: "
                         + ", ".join(choices))
    return output


def link_points(mech: "Mechanism") -> dict[str, tuple[str, ...]]:
    """Moving link -> the points it carries: its joints' points (in joint order), then
    the points placed on it alone (a coupler point, a lever's tip). Centres of mass are
    not among them.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> link_points(presets.get("four_bar"))
    {'1': ('A', 'B'), '2': ('B', 'C'), '3': ('C', 'D')}
    >>> link_points(presets.get("slider_crank"))["3"]
    ('B',)
    """
    points: dict[str, list] = {b.name: [] for b in mech.bodies}
    for j in mech.joints:
        for body in (j.a, j.b):
            if body in points and j.point not in points[body]:
                points[body].append(j.point)
    for point, link in mech.owner.items():
        if link in points and point not in points[link]:
            points[link].append(point)
    return {k: tuple(v) for k, v in points.items()}


# -- inputs ------------------------------------------------------------------------------
def _angles(theta, theta_deg, scalar: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """``(radians, degrees)`` of the crank angles: ``theta`` [rad] or ``theta_deg``
    [deg], a revolution of :data:`N_ANGLES` if neither."""
    if theta is not None and theta_deg is not None:
        raise TypeError("give the crank angle as theta [rad] or as theta_deg [deg], not both")
    if theta is None and theta_deg is None:
        if scalar:
            raise TypeError("give the crank angle: theta [rad] or theta_deg [deg]")
        deg = np.linspace(0.0, 360.0, N_ANGLES)
        return np.radians(deg), deg
    given = theta if theta is not None else theta_deg
    if scalar and np.ndim(given) != 0:
        raise ValueError(f"the crank angle must be one number, got shape {np.shape(given)}")
    values = np.atleast_1d(np.asarray(given, dtype=float))
    if values.ndim != 1 or not values.size:
        raise ValueError(f"the crank angles must be a non-empty 1-D array, got shape "
                         f"{np.shape(given)}")
    if not np.isfinite(values).all():
        raise ValueError("the crank angles must be finite")
    if theta is not None:
        return values, np.degrees(values)
    return np.radians(values), values


def _inputs(mech: "Mechanism", omega, alpha, loads: Sequence, named: dict) -> dict:
    """``{omega, alpha, <input load>: value}``: what is given, else the start values
    (a load over the cycle given by name too)."""
    values, given = mech.inputs(omega, alpha, tuple(loads), named)
    return dict(zip(mech.input_names[1:] + given, map(float, values)))


def _solve(mech: "Mechanism", theta, inputs: dict):
    """Every output, as ``mech.solve`` gives them by default: the balancing effort from
    the reactions (``outputs=("Mb",)`` would take it from the power balance, equal to
    rounding only), so that a plot shows the very numbers of a plain solve."""
    loads = {k: v for k, v in inputs.items() if k not in ("omega", "alpha")}
    return mech.solve(theta, inputs["omega"], inputs["alpha"], **loads)


def _inputs_text(mech: "Mechanism", inputs: dict) -> str:
    units = {"omega": "rad/s", "alpha": "rad/s²", **{l.name: l.unit for l in mech.loads}}
    greek = {"omega": "ω", "alpha": "α"}
    return ", ".join(f"{greek.get(k, k)} = {v:g} {units[k]}" for k, v in inputs.items())


def _greek(name: str) -> str:
    return "μ" + name[2:] if name.startswith("mu_") else name


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
    if abs(value) <= ZERO_FRACTION * abs(scale):
        return "0"
    return f"{value:.4g}"


def _peak(values: np.ndarray) -> int:
    """Index of the largest finite ``|values|`` (the first if several)."""
    magnitude = np.abs(values)
    if not np.isfinite(magnitude).any():
        raise ValueError("no finite value: the linkage cannot be assembled at any of the angles")
    return int(np.nanargmax(np.where(np.isfinite(magnitude), magnitude, np.nan)))


def _finite_or_fail(mech: "Mechanism", values: np.ndarray, deg: np.ndarray) -> None:
    if not np.isfinite(values).any():
        raise ValueError(f"{mech.name} cannot be assembled at any of the {deg.size} crank "
                         f"angles {deg[0]:g}..{deg[-1]:g} deg")


def _degree_axis(ax: "Axes", deg: np.ndarray) -> None:
    ax.set_xlabel("crank angle θ [°]")
    lo, hi = float(np.min(deg)), float(np.max(deg))
    if hi > lo:
        ax.set_xlim(lo, hi)
        step = 45.0 if hi - lo <= 360.0 else 90.0
        ax.set_xticks(np.arange(math.ceil(lo / step) * step, hi + 1e-9, step))
    ax.grid(True, alpha=0.3)


# -- 1. torque ---------------------------------------------------------------------------
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
    >>> abs(float(ax.lines[1].get_ydata()[0])) < 1e-12  # mean Mb: no net work per turn
    True
    >>> ax.texts[0].get_text()                          # the peak
    '-18.92 N.m\\nat θ = 111.0°'
    """
    name = _output(mech, output)
    rad, deg = _angles(theta, theta_deg)
    inputs = _inputs(mech, omega, alpha, loads, named_loads)
    values = np.asarray(_solve(mech, rad, inputs)[name], dtype=float)
    _finite_or_fail(mech, values, deg)
    unit, description = mech.output_info[name]

    fig, ax = _axes(ax)
    _draw_curve(ax, rad, deg, values, name, unit)
    ax.set_title(f"{mech.name}: {description}\n{_inputs_text(mech, inputs)}", fontsize=10)
    return fig


def _draw_curve(ax: "Axes", rad: np.ndarray, deg: np.ndarray, values: np.ndarray, name: str,
                unit: str) -> None:
    """The curve of :func:`torque`: ``values`` against ``deg``, their mean over ``rad``
    and their peak magnitude, a line at 0, the axes' labels and the legend."""
    mean = revolution_mean(rad, values)
    i = _peak(values)
    ax.plot(deg, values, color="C0", lw=1.6, label=name, gid=name)
    ax.axhline(mean, color="C1", ls="--", lw=1.2,
               label=f"mean {rounded(mean, abs(values[i]))} {unit}", gid="mean")
    ax.plot([deg[i]], [values[i]], "o", color="C3", ms=7,
            label=f"peak |{name}| {abs(values[i]):.4g} {unit}", gid="peak")
    ax.annotate(f"{values[i]:.4g} {unit}\nat θ = {deg[i]:.1f}°", (deg[i], values[i]),
                xytext=(12, -14 if values[i] > 0 else 14), textcoords="offset points",
                va="top" if values[i] > 0 else "bottom", fontsize=9, gid="peak label")
    ax.axhline(0.0, color="0.6", lw=0.8, zorder=0, gid="zero")
    _degree_axis(ax, deg)
    ax.set_ylabel(f"{_greek(name)} [{unit}]")
    ax.legend(loc="best", fontsize=9)


# -- 2. polar ----------------------------------------------------------------------------
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
    ValueError: four_bar has no force pair 'F99'; its force pairs are: F21 (F21x, F21y), ...
    """
    pair = _find_pair(mech, force)
    rad, deg = _angles(theta, theta_deg)
    inputs = _inputs(mech, omega, alpha, loads, named_loads)
    sol = _solve(mech, rad, inputs)
    fx, fy = (np.asarray(sol[n], dtype=float) for n in (pair.x, pair.y))
    _finite_or_fail(mech, fx, deg)

    fig, ax = _axes(ax, figsize=(6.5, 6.5))
    _draw_hodograph(ax, fx, fy, deg, pair.name, pair.x, pair.y)
    who = f": force of link {pair.by} on link {pair.on}" if pair.by is not None else ""
    ax.set_title(f"{mech.name}, {pair.name}{who}\n{_inputs_text(mech, inputs)}", fontsize=10)
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
    ax.plot([fx[j]], [fy[j]], "s", color="C2", ms=6, label=f"θ = {deg[j]:g}°", gid="start")
    ax.plot([fx[i]], [fy[i]], "o", color="C3", ms=7, label=f"max |{name}| {magnitude:.4g} N",
            gid="peak")
    ax.plot([0.0, fx[i]], [0.0, fy[i]], "--", color="C3", lw=1.0, gid="peak vector")
    ax.annotate(f"|{name}| = {magnitude:.4g} N\nat θ = {deg[i]:.1f}°", (fx[i], fy[i]),
                xytext=(10, 10), textcoords="offset points", fontsize=9, gid="peak label")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"{x} [N]")
    ax.set_ylabel(f"{y} [N]")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=9)


# -- 3. the linkage and its joint forces -------------------------------------------------
def _size(points: Sequence[tuple[float, float]], fallback: float) -> float:
    """The larger side of the bounding box of ``points``; ``fallback`` if zero."""
    xy = np.asarray(points, dtype=float)
    size = float(np.max(np.ptp(xy, axis=0))) if len(xy) else 0.0
    return size if size > 0.0 else float(fallback)


def _ordered(points: Sequence[str], pos: dict) -> list[str]:
    """``points`` around their centroid, so that a link of three or more points is
    drawn as a polygon that does not cross itself."""
    if len(points) < 3:
        return list(points)
    xy = np.array([pos[p] for p in points])
    c = xy.mean(axis=0)
    order = np.argsort(np.arctan2(xy[:, 1] - c[1], xy[:, 0] - c[0]), kind="stable")
    return [points[k] for k in order]


def _overlapping(boxes: np.ndarray, taken: np.ndarray, pad: float) -> np.ndarray:
    """For each of ``boxes`` (rows ``x0, y0, x1, y1``), whether it comes within ``pad``
    of any of ``taken``."""
    b, t = boxes[:, None, :], taken[None, :, :]
    return ((b[..., 0] < t[..., 2] + pad) & (t[..., 0] < b[..., 2] + pad) &
            (b[..., 1] < t[..., 3] + pad) & (t[..., 1] < b[..., 3] + pad)).any(axis=1)


#: the directions tried about a label's anchor: the preferred one, then the others in
#: pairs on either side of it, 22.5 degrees apart
_TURNS = np.radians(22.5) * np.array([0] + [s * k for k in range(1, 9) for s in (1, -1)][:15])


def place_boxes(anchors, sizes, toward, taken=(), frame=None, gap: float = 1.0,
                avoid=(), cover: float = 0.0, leave: float = math.inf
                ) -> tuple[np.ndarray, np.ndarray]:
    """Centres for boxes of the ``sizes`` ``(w, h)``, each near its anchor, such that no
    two come within ``gap`` of each other or of the boxes ``taken``.

    Each box in turn, from the first, is tried on rings about its anchor (distances
    ``gap * (1, 2, 4, 7, 11, ...)`` from the anchor to the box's edge) in 16 directions
    22.5 degrees apart, the direction ``toward`` [rad] first, then the others by how far
    they turn from it. Of the spots clear of the boxes placed before it and of
    ``taken``, it takes the one of least cost: its distance, plus ``cover`` if it comes
    within ``gap`` of one of the boxes ``avoid`` (lines it had better not hide), plus
    ``leave`` if it is not inside ``frame`` (``x0, y0, x1, y1``); of equal costs, the
    first tried. Any unit of length will do (display pixels in :func:`linkage`); the
    result depends on nothing else.

    Returns
    -------
    centres : ndarray, shape (n, 2)
    distances : ndarray, shape (n,)
        From each anchor to its box's edge along the direction taken.

    Examples
    --------
    Two boxes 4 wide and 2 high anchored at the same point, both wanting to lie to its
    right: the first does, one gap away; the second, kept a gap off the first, takes
    the first clear direction on the same ring, turned 157.5 degrees to the upper left.

    >>> centres, distances = place_boxes([(0, 0), (0, 0)], [(4, 2), (4, 2)], [0.0, 0.0])
    >>> centres.round(3).tolist(), distances.tolist()
    ([[3.0, 0.0], [-2.924, 1.211]], [1.0, 1.0])

    In a frame that ends at x = -1 it goes to the fourth ring instead, 45 degrees up:

    >>> centres, distances = place_boxes([(0, 0), (0, 0)], [(4, 2), (4, 2)], [0.0, 0.0],
    ...                                  frame=(-1, -10, 10, 10))
    >>> centres.round(3).tolist(), distances.tolist()
    ([[3.0, 0.0], [3.828, 3.828]], [1.0, 4.0])
    """
    if not gap > 0.0:
        raise ValueError(f"gap must be > 0, got {gap!r}")
    anchors = np.asarray(anchors, dtype=float).reshape(-1, 2)
    sizes = np.asarray(sizes, dtype=float).reshape(-1, 2)
    boxes = [np.asarray(taken, dtype=float).reshape(-1, 4)]
    avoid = np.asarray(avoid, dtype=float).reshape(-1, 4)
    x0, y0, x1, y1 = (-math.inf, -math.inf, math.inf, math.inf) if frame is None else frame
    centres, distances = np.empty_like(anchors), np.empty(len(anchors))
    for n, ((ax, ay), (w, h), a) in enumerate(zip(anchors, sizes, np.broadcast_to(
            np.asarray(toward, dtype=float), len(anchors)))):
        c, s = np.cos(a + _TURNS), np.sin(a + _TURNS)
        with np.errstate(divide="ignore"):  # along an axis, one side sets the edge
            edge = np.minimum(0.5 * w / np.abs(c), 0.5 * h / np.abs(s))
        now = np.concatenate(boxes)
        best, best_cost, k = None, math.inf, 0
        while True:
            r = gap * (1 + k * (k + 1) // 2)
            if r >= best_cost or (best is not None and r > 1e6 * max(gap, w, h)):
                break  # no farther spot can cost less (or only infinite costs are left)
            cx, cy = ax + (r + edge) * c, ay + (r + edge) * s
            spots = np.c_[cx - 0.5 * w, cy - 0.5 * h, cx + 0.5 * w, cy + 0.5 * h]
            cost = r + cover * _overlapping(spots, avoid, gap) + np.where(
                (spots[:, 0] >= x0) & (spots[:, 1] >= y0) & (spots[:, 2] <= x1) &
                (spots[:, 3] <= y1), 0.0, leave)
            clear = np.flatnonzero(~_overlapping(spots, now, gap))
            if clear.size:
                j = clear[np.argmin(cost[clear])]
                if best is None or cost[j] < best_cost:
                    best, best_cost = (spots[j], r), cost[j]
            k += 1
        box, distances[n] = best
        centres[n] = 0.5 * (box[:2] + box[2:])
        boxes.append(box[None, :])
    return centres, distances


class _LabelPlacer(_Artist):
    """Places the labels of :func:`linkage` where they do not overlap, at each draw,
    before the labels are drawn and once the layout has fixed the axes' transform (the
    size of a text is in points and the linkage in metres, so where they collide
    depends on the figure): with :func:`place_boxes` in display pixels, in the order
    they were added, kept off each other, the marks (joint circles), the frame points'
    symbols and the scale's key, and, where it costs at most :attr:`COVER_PT` more
    distance, off the arrows and the links' lines too; inside the axes unless that
    costs :attr:`LEAVE_PT` more. A label farther than :attr:`LEADER_PT` from its anchor
    gets a thin line to it."""

    GAP_PT = 3.0  # spacing of the rings, and the least gap between labels
    MARK_PT = 5.0  # half the side of the square kept clear about a mark
    LEADER_PT = 16.0
    COVER_PT = 18.0
    LEAVE_PT = 60.0

    def __init__(self, ax: "Axes"):
        super().__init__()
        self.set_zorder(-math.inf)  # drawn before the axes' other artists
        self.set_in_layout(False)
        self.labels: list = []  # (annotation, anchor [m], preferred direction [m])
        self.marks = np.empty((0, 2))  # [m]
        self.blocks = np.empty((0, 4))  # x0, y0, x1, y1 [m]: the frame points' symbols
        self.segments = np.empty((0, 4))  # x, y, u, v [m]: arrows, links
        self.key = None
        ax.add_artist(self)

    def add(self, text: str, xy, toward, color: str, **kwargs):
        """A label ``text`` of the point ``xy`` [m], preferably in the direction of the
        vector ``toward`` [m] from it."""
        ann = self.axes.annotate(
            text, xy, xytext=(0.0, 0.0), textcoords="offset points", ha="center",
            va="center", color=color, arrowprops=dict(arrowstyle="-", color=color, lw=0.6,
                                                      shrinkA=1.0, shrinkB=2.0), **kwargs)
        ann.arrow_patch.set_visible(False)
        ann.set_in_layout(False)  # placed after the layout: it must not move the axes
        self.labels.append((ann, np.asarray(xy, float), np.asarray(toward, float)))
        return ann

    def _taken(self, renderer, px: float) -> np.ndarray:
        """The boxes [display px] labels keep off: the marks, the frame points'
        symbols, the scale's key."""
        to = self.axes.transData.transform
        m = self.MARK_PT * px
        marks = to(self.marks).reshape(-1, 2)
        blocks = to(self.blocks.reshape(-1, 2)).reshape(-1, 4)
        boxes = [np.c_[marks - m, marks + m], np.c_[np.minimum(blocks[:, :2], blocks[:, 2:]),
                                                    np.maximum(blocks[:, :2], blocks[:, 2:])]]
        if self.key is not None and self.key.get_visible():
            key = self.key
            x, y = self.axes.transAxes.transform((key.X, key.Y))
            length = abs(to((key.U, 0.0))[0] - to((0.0, 0.0))[0])  # the key's tip is at X
            text = key.text.get_window_extent(renderer)
            half = max(0.5 * text.height, 3.0 * px)
            sep = 7.2 * px  # QuiverKey's labelsep, 0.1 inch
            boxes.append([[x - length, y - half, x + sep + text.width, y + half]])
        return np.concatenate([np.reshape(b, (-1, 4)) for b in boxes])

    def _lines(self, px: float) -> np.ndarray:
        """Small boxes [display px] along the segments, every 2 px."""
        to = self.axes.transData.transform
        boxes = [np.empty((0, 4))]
        for x, y, u, v in self.segments:
            a, b = to([(x, y), (x + u, y + v)])
            n = int(min(np.hypot(*(b - a)) / (2.0 * px), 1000)) + 2
            along = a + np.linspace(0.0, 1.0, n)[:, None] * (b - a)
            boxes.append(np.c_[along - px, along + px])
        return np.concatenate(boxes)

    def draw(self, renderer):
        labels = [(a, xy, d) for a, xy, d in self.labels if a.get_visible()]
        if not self.get_visible() or not labels:
            return
        px = renderer.points_to_pixels(1.0)
        to = self.axes.transData.transform
        anchors, sizes, toward, shifts = [], [], [], []
        for ann, xy, direction in labels:
            ann.update_positions(renderer)
            box = _Text.get_window_extent(ann, renderer)  # the text, not its leader
            at = to(xy)
            d = to(xy + direction) - at
            anchors.append(at)
            sizes.append((box.width, box.height))
            toward.append(math.atan2(d[1], d[0]) if np.hypot(*d) > 0 else math.pi / 4)
            # the box's centre from the text's position (its alignment, its descent)
            shifts.append(np.array(box.corners().mean(axis=0)) -
                          ann.get_transform().transform(ann.xyann))
        centres, distances = place_boxes(
            anchors, sizes, toward, self._taken(renderer, px), self.axes.bbox.extents,
            self.GAP_PT * px, self._lines(px), self.COVER_PT * px, self.LEAVE_PT * px)
        for (ann, _, _), at, centre, shift, r in zip(labels, anchors, centres, shifts,
                                                      distances):
            offset = tuple((centre - shift - at) / px)
            if not np.allclose(offset, ann.xyann, rtol=0.0, atol=1e-3):
                ann.xyann = offset  # only if it moved: no redraw for nothing
            leader = bool(r > self.LEADER_PT * px)
            if ann.arrow_patch.get_visible() != leader:
                ann.arrow_patch.set_visible(leader)


def _nice(value: float) -> float:
    """1, 2 or 5 times a power of ten, at most ``value`` (> 0)."""
    power = 10.0 ** math.floor(math.log10(value))
    return max(m for m in (1.0, 2.0, 5.0) if m * power <= value * (1 + 1e-12)) * power


class _LoadAt(NamedTuple):
    """A load at one state: its ``value`` and, for a force, its unit ``direction`` in
    the frame's axes (None for a moment)."""

    load: "Load"
    value: float
    direction: tuple[float, float] | None


def _loads_at(mech: "Mechanism", st, inputs: dict) -> list[_LoadAt]:
    """Each of ``mech.loads`` at the kinematic state ``st``: its value given in
    ``inputs``, else (a load over the cycle) computed there."""
    out = []
    for load in mech.loads:
        value = inputs[load.name] if load.name in inputs else load.at_state(st)
        direction = None
        if load.kind == "force":
            ux, uy = (float(c) for c in load.direction)
            if load.fixed_in == "link":  # given in the link's own axes
                c, s = (float(c) for c in st.u[load.body])
                ux, uy = c * ux - s * uy, s * ux + c * uy
            direction = (ux, uy)
        out.append(_LoadAt(load, float(value), direction))
    return out


def _draw_loads(ax: "Axes", loads: Sequence[_LoadAt], pos: dict, links: dict, scale: float,
                size: float, labels: _LabelPlacer) -> np.ndarray:
    """Draws each load, each labelled with its name and value: a force as an arrow
    ``value * direction * scale`` [m] ending at its point, a moment as an arc about the
    middle of its link's points, with its head in the moment's sense; a load of 0 in
    its positive sense, faint, a force ``0.15 * size`` long. Returns the segments drawn
    (``x, y, u, v`` [m]): lines for the labels to keep clear of, and ends for the axes'
    limits."""
    from matplotlib.patches import FancyArrowPatch

    segments = []
    for load, value, direction in loads:
        faint = value == 0.0  # no sense to show: the positive one, as a reminder
        style = dict(color=_LOAD_COLOR, alpha=0.35 if faint else 1.0, zorder=5)
        text = f"{load.name} = {value:.4g} {load.unit}"
        if direction is not None:
            (x, y), length = pos[load.at], 0.15 * size if faint else value * scale
            u, v = length * direction[0], length * direction[1]
            ax.quiver([x], [y], [u], [v], angles="xy", scale_units="xy", scale=1.0,
                      pivot="tip", width=0.006, gid=f"load:{load.name}", **style)
            segments.append((x - u, y - v, u, v))
            labels.add(text, (x - u, y - v), (-u, -v), _LOAD_COLOR, fontsize=8,
                       gid=f"load label:{load.name}")  # beyond the tail
            continue
        cx, cy = np.mean([pos[p] for p in links[load.body]], axis=0)
        r = MOMENT_FRACTION * size
        phi = np.radians(np.linspace(-45.0, 225.0, 61))  # open at the bottom
        if value < 0.0:
            phi = phi[::-1]
        x, y = cx + r * np.cos(phi), cy + r * np.sin(phi)
        ax.plot(x, y, lw=1.6, gid=f"load:{load.name}", **style)
        ax.add_patch(FancyArrowPatch((x[-2], y[-2]), (x[-1], y[-1]), arrowstyle="-|>",
                                     mutation_scale=14, shrinkA=0.0, shrinkB=0.0, lw=1.6,
                                     gid=f"load head:{load.name}", **style))
        segments += [(a, b, c - a, d - b) for a, b, c, d in zip(x, y, x[1:], y[1:])]
        labels.add(text, (cx, cy + r), (0.0, 1.0), _LOAD_COLOR, fontsize=8,
                   gid=f"load label:{load.name}")
    return np.array(segments, dtype=float).reshape(-1, 4)


def _draw_frame_point(ax, x: float, y: float, s: float, name: str) -> None:
    from matplotlib.patches import Polygon, Rectangle

    ax.add_patch(Polygon([(x, y), (x - s, y - 1.6 * s), (x + s, y - 1.6 * s)], closed=True,
                         facecolor="0.85", edgecolor="k", lw=1.0, zorder=1,
                         gid=f"frame:{name}"))
    ax.add_patch(Rectangle((x - 1.6 * s, y - 2.2 * s), 3.2 * s, 0.6 * s, facecolor="none",
                           edgecolor="k", hatch="////", lw=0.0, zorder=1,
                           gid=f"ground:{name}"))


def linkage(mech: "Mechanism", theta=None, omega=None, alpha=None, *loads, theta_deg=None,
            scale: float | None = None, ax: "Axes | None" = None, **named_loads) -> "Figure":
    """The linkage at one crank angle, with every joint force drawn as an arrow from its
    joint and every external load at its point or on its link, the forces to one scale.

    Links are lines between the points they carry (:func:`link_points`; a polygon for
    three or more), a slider a square, revolute joints circles, frame points hatched
    triangles and fixed guides dashed lines. Each :func:`force_pairs` force whose joint is
    known is an arrow ``F * scale`` [m] starting at its joint's point, labelled with its
    name and magnitude beyond its tip. Each load is labelled with its name and value
    (as given, or, over the cycle, at this angle): a force as an arrow ``value *
    direction * scale`` [m] ending at its point, so that it points the way the force
    acts, a moment as an arc about the middle of its link's points with its head in
    the moment's sense (counter-clockwise for a positive value); a load of 0 is drawn
    faint, in its positive sense (a force 0.15 of the linkage's size long).
    The labels are placed when the figure is drawn
    (their size is in points, the linkage's in metres), each as near its point or tip
    as it can be without covering another label, a joint, a frame point's symbol or the
    scale, nor, unless that takes it much farther, an arrow or a link
    (:func:`place_boxes`); with a thin line to it if it had to move away.

    Parameters
    ----------
    mech : Mechanism
    theta : float, optional
        The crank angle [rad]; or ``theta_deg`` [deg]. One of them is required.
    omega, alpha, *loads, **named_loads : float, optional
        As for :func:`torque`.
    theta_deg : float, optional
        The crank angle [deg], instead of ``theta``.
    scale : float, optional
        Arrow length per force [m/N]; default so that the largest force (joint force
        or load) is :data:`ARROW_FRACTION` (0.4) of the linkage's size (the larger side
        of the bounding box of its points at this angle).
    ax : matplotlib Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    Figure
        Its axes hold the quiver ``gid="forces"`` (``X, Y`` the joint points, ``U, V``
        the forces times ``scale``, in :func:`force_pairs` order), the quiver key
        ``gid="scale"`` (a round force to scale; the title gives the scale in m/N),
        lines ``gid="link:<name>"`` (a patch for a slider) and ``gid="joints"``; each
        load's quiver ``gid="load:<name>"`` (one arrow: ``X, Y`` its point, the tip;
        ``U, V`` the force times ``scale``) or, for a moment, line
        ``gid="load:<name>"`` (the arc, from its tail to its head, :data:`MOMENT_FRACTION`
        of the size in radius) and patch ``gid="load head:<name>"``; and the labels
        (annotations) ``gid="force:<name>"``, ``"load label:<name>"`` and
        ``"point:<name>"``.

    Raises
    ------
    AssemblyError
        The linkage cannot be assembled at ``theta`` (a ``ValueError``).

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from linkage_fmu import plot, presets
    >>> mech = presets.get("four_bar")
    >>> fig = plot.linkage(mech, theta_deg=30.0, omega=10.0, load=5.0, scale=1e-3)
    >>> ax = fig.axes[0]
    >>> quiver = next(c for c in ax.collections if c.get_gid() == "forces")
    >>> sol = mech.solve(np.radians(30.0), omega=10.0, load=5.0)
    >>> bool(np.isclose(quiver.U[0], 1e-3 * sol["F21x"]))  # F21 at B, in m
    True
    >>> [t.get_text() for t in ax.texts if t.get_gid() == "load label:load"]  # on the rocker
    ['load = 5 N.m']
    """
    rad, deg = _angles(theta, theta_deg, scalar=True)
    th, th_deg = float(rad[0]), float(deg[0])
    inputs = _inputs(mech, omega, alpha, loads, named_loads)
    st = mech.kinematics(th, order=0)
    pos = {p: (float(x), float(y)) for p, (x, y) in st.p.items()}
    pairs = [p for p in force_pairs(mech) if p.point is not None]
    effort = mech.effort.name if mech.effort.name in mech.output_names else None
    sol = _solve(mech, th, inputs)
    forces = np.array([(sol[p.x], sol[p.y]) for p in pairs], dtype=float).reshape(-1, 2)
    origins = np.array([pos[p.point] for p in pairs], dtype=float).reshape(-1, 2)
    loads_now = _loads_at(mech, st, inputs)

    links = link_points(mech)
    drawn = sorted({p for pts in links.values() for p in pts} | set(mech.frame_points))
    size = _size([pos[p] for p in drawn], mech.length_scale)
    largest = max([0.0, *np.hypot(forces[:, 0], forces[:, 1]),
                   *(abs(ld.value) for ld in loads_now if ld.direction is not None)])
    if scale is None:
        scale = ARROW_FRACTION * size / largest if largest > 0.0 else 1.0
    elif not (math.isfinite(scale) and scale > 0.0):
        raise ValueError(f"scale must be a finite number > 0 [m/N], got {scale!r}")

    fig, ax = _axes(ax, figsize=(8.0, 6.5))
    from matplotlib.patches import Polygon, Rectangle

    s = 0.025 * size
    for name in mech.frame_points:
        _draw_frame_point(ax, *pos[name], s, name)
    for j in mech.joints:  # fixed guides
        if j.normal is not None and not isinstance(j.normal, str) and mech.frame in (j.a, j.b):
            (x, y), (nx, ny) = pos[j.point], j.normal
            tx, ty = ny, -nx
            h = 0.35 * size
            ax.plot([x - h * tx, x + h * tx], [y - h * ty, y + h * ty], ls=(0, (6, 3)),
                    color="0.4", lw=1.2, zorder=1, gid=f"guide:{j.name}")
    lines = []
    for k, (link, pts) in enumerate(links.items()):
        color = _LINK_COLORS[k % len(_LINK_COLORS)]
        if len(pts) == 1:  # a slider or block: a square along its direction
            (x, y), (ux, uy) = pos[pts[0]], st.u.get(link, (1.0, 0.0))
            ax.add_patch(Rectangle((x - 2 * s, y - 1.2 * s), 4 * s, 2.4 * s,
                                   angle=math.degrees(math.atan2(float(uy), float(ux))),
                                   rotation_point="center", facecolor=color, alpha=0.35,
                                   edgecolor=color, lw=1.5, zorder=2, gid=f"link:{link}"))
            continue
        ring = _ordered(pts, pos)
        xy = [pos[p] for p in ring] + ([pos[ring[0]]] if len(ring) > 2 else [])
        lines += [(x0, y0, x1 - x0, y1 - y0) for (x0, y0), (x1, y1) in zip(xy, xy[1:])]
        ax.plot(*zip(*xy), "-", color=color, lw=3.0, solid_capstyle="round", zorder=2,
                label=f"link {link}", gid=f"link:{link}")
        if len(ring) > 2:
            ax.add_patch(Polygon(xy, closed=True, facecolor=color, alpha=0.15, lw=0, zorder=1))
    revolute = [j.point for j in mech.joints if j.normal is None]
    jx, jy = zip(*[pos[p] for p in revolute]) if revolute else ((), ())
    ax.plot(jx, jy, "o", ms=7, mfc="white", mec="k", mew=1.3, ls="none", zorder=4,
            gid="joints")
    labels = _LabelPlacer(ax)
    labels.marks = np.array([pos[p] for p in drawn], dtype=float).reshape(-1, 2)
    labels.blocks = np.array([(pos[p][0] - 1.6 * s, pos[p][1] - 2.2 * s, pos[p][0] + 1.6 * s,
                               pos[p][1]) for p in mech.frame_points]).reshape(-1, 4)
    for p in drawn:  # up and to the left, as far as the others let them
        labels.add(p, pos[p], (-1.0, 1.0), "0.25", fontsize=9, gid=f"point:{p}")

    u, v = forces[:, 0] * scale, forces[:, 1] * scale
    quiver = ax.quiver(origins[:, 0], origins[:, 1], u, v, angles="xy", scale_units="xy",
                       scale=1.0, color="crimson", width=0.006, zorder=5, gid="forces")
    for p, (x, y), du, dv, (fx, fy) in zip(pairs, origins, u, v, forces):
        labels.add(f"{p.name}\n{math.hypot(fx, fy):.3g} N", (x + du, y + dv), (du, dv),
                   "crimson", fontsize=8, gid=f"force:{p.name}")  # beyond the tip
    drawn_loads = _draw_loads(ax, loads_now, pos, links, scale, size, labels)
    labels.segments = np.r_[np.c_[origins, u, v], drawn_loads,
                            np.array(lines, dtype=float).reshape(-1, 4)]
    if largest > 0.0:
        ref = _nice(0.5 * largest)
        key = ax.quiverkey(quiver, 0.5, 0.04, ref * scale, f"{ref:g} N", labelpos="E",
                           coordinates="axes", color="crimson")
        key.set_gid("scale")
        labels.key = key

    tips = np.concatenate([np.array([pos[p] for p in drawn]), origins + np.c_[u, v],
                           drawn_loads[:, :2], drawn_loads[:, :2] + drawn_loads[:, 2:]])
    lo, hi = tips.min(axis=0) - 0.12 * size, tips.max(axis=0) + 0.12 * size
    lo[1] -= 2.2 * s + 0.12 * size  # the ground hatching, and a band for the scale
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    title = f"{mech.name} at θ = {th_deg:.4g}°, {_inputs_text(mech, inputs)}\n"
    if effort is not None:
        title += f"{effort} = {sol[effort]:.4g} {mech.output_info[effort][0]}; "
    title += f"forces to scale {scale:.4g} m/N (1 N = {1000 * scale:.3g} mm)"
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.2)
    return fig


# -- 4. transmission angles --------------------------------------------------------------
def _valid_at(mech: "Mechanism", name: str, t: float) -> bool:
    return bool(mech.solve(np.array([t]), outputs=(name,)).valid[0])


def _distance_to_toggle(mech: "Mechanism", name: str, t: float) -> float:
    mu = float(mech.solve(np.array([t]), outputs=(name,))[name][0])
    return min(mu, math.pi - mu) if math.isfinite(mu) else math.inf


def toggles(mech: "Mechanism", name: str, theta: np.ndarray, mu: np.ndarray,
            valid: np.ndarray) -> list[float]:
    """Crank angles [rad] within ``theta`` at which the dyad of the transmission angle
    ``name`` is at a toggle (``mu`` = 0 or pi): the limits of the ranges where the
    linkage cannot be assembled (found by bisection to 1e-12 rad, on the side where it
    can), and, where it can, angles where ``mu`` touches 0 or pi (local minima of
    ``min(mu, pi - mu)`` refined on the solver, kept if below :data:`TOGGLE_TOL`).
    ``mu`` and ``valid`` are the solver's at ``theta``.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("slider_crank", l_OA=0.2, l_AB=0.15)   # the rod cannot reach
    >>> t = np.radians(np.linspace(0, 360, 73))
    >>> sol = mech.solve(t, outputs=("mu_B",))
    >>> [round(float(np.degrees(a)), 4) for a in toggles(mech, "mu_B", t, sol["mu_B"], sol.valid)]
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
    d = np.minimum(mu, np.pi - mu)
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
    """Every transmission angle ``mu_<joint>`` in degrees against the crank angle in
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
        Lines (gid): ``mu_<joint>`` (``degrees(mu)``; gaps where the linkage cannot be
        assembled, shaded ``gid="invalid"``), ``min:mu_<joint>`` (one point at the
        smallest angle, annotated) and ``toggle:mu_<joint>`` (a vertical line at each
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
    >>> fig = plot.transmission(presets.get("four_bar", l_AB=0.3))  # |BD| reaches BC + CD
    >>> lines = {line.get_gid(): line for line in fig.axes[0].lines}  # the last of each gid
    >>> sorted(lines)
    ['min:mu_C', 'mu_C', 'toggle:mu_C']
    >>> [round(float(line.get_xdata()[0]), 3) for line in fig.axes[0].lines
    ...  if line.get_gid() == "toggle:mu_C"]
    [135.951, 224.049]
    """
    names = [n for n in mech.diagnostic_names if n.startswith("mu_")]
    if not names:
        raise ValueError(f"{mech.name} has no dyad, so no transmission angle")
    rad, deg = _angles(theta, theta_deg)
    sol = mech.solve(rad, outputs=tuple(names))
    valid = np.broadcast_to(np.asarray(sol.valid, dtype=bool), rad.shape)

    fig, ax = _axes(ax)
    for lo, hi in _runs(~valid):  # shade the angles where it cannot be assembled
        a, b = deg[max(lo - 1, 0)], deg[min(hi + 1, deg.size - 1)]
        ax.axvspan(min(a, b), max(a, b), color="0.9", lw=0, zorder=0, gid="invalid")
    for k, name in enumerate(names):
        mu = np.asarray(sol[name], dtype=float)
        _finite_or_fail(mech, mu, deg)
        color = f"C{k % 10}"
        label = _greek(name)
        ax.plot(deg, np.degrees(mu), color=color, lw=1.6, label=label, gid=name)
        i = int(np.nanargmin(mu))
        ax.plot([deg[i]], [np.degrees(mu[i])], "v", color=color, ms=8,
                label=f"min {label} = {np.degrees(mu[i]):.1f}°", gid=f"min:{name}")
        ax.annotate(f"min {label} = {np.degrees(mu[i]):.1f}°\nat θ = {deg[i]:.1f}°",
                    (deg[i], np.degrees(mu[i])), xytext=(8, -18), textcoords="offset points",
                    fontsize=9, color=color, gid=f"min label:{name}")
        for j, t in enumerate(toggles(mech, name, rad, mu, valid)):
            ax.axvline(np.degrees(t), color=color, ls="--", lw=1.0,
                       label=f"toggle of {label}" if not j else None, gid=f"toggle:{name}")
    ax.axhspan(40.0, 140.0, color="C2", alpha=0.06, zorder=0, gid="good range")
    _degree_axis(ax, deg)
    ax.set_ylim(0.0, 180.0)
    ax.set_yticks(np.arange(0.0, 181.0, 30.0))
    ax.set_ylabel("transmission angle μ [°]")
    ax.set_title(f"{mech.name}: transmission angles (0° or 180°: toggle; "
                 "shaded 40°-140°)", fontsize=10)
    ax.legend(loc="best", fontsize=9)
    return fig


# -- 5. shaking force and moment ---------------------------------------------------------
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
    >>> bool(np.array_equal(x, sol["shake_x"]) and np.array_equal(y, sol["shake_y"]))
    True
    """
    if ax is not None:
        try:
            force_ax, moment_ax = ax
        except (TypeError, ValueError):
            raise TypeError("ax must be a pair of Axes: (the force's, the moment's), "
                            f"got {ax!r}") from None
    rad, deg = _angles(theta, theta_deg)
    inputs = _inputs(mech, omega, alpha, loads, named_loads)
    sol = _solve(mech, rad, inputs)
    fx, fy, moment = (np.asarray(sol[n], dtype=float) for n in SHAKING)
    _finite_or_fail(mech, fx, deg)

    if ax is None:
        fig, (force_ax, moment_ax) = _pyplot().subplots(
            1, 2, figsize=(13.0, 5.5), layout="constrained", width_ratios=(1.0, 1.3))
    else:
        fig = force_ax.figure
    x, y, m = SHAKING
    _draw_hodograph(force_ax, fx, fy, deg, "shake", x, y)
    force_ax.set_title(f"{mech.name}: shaking force, what the moving links put on the "
                       f"frame\n{_inputs_text(mech, inputs)}", fontsize=10)
    _draw_curve(moment_ax, rad, deg, moment, m, mech.output_info[m][0])
    moment_ax.set_title(f"shaking moment about the crank pivot {mech.crank.pivot}, "
                        "counter-clockwise positive", fontsize=10)
    return fig
