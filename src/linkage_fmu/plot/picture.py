"""The picture of the linkage at one crank angle (:func:`linkage`): its links, joints,
frame points and guides, every joint force as an arrow from its joint and every external
load, the forces to one scale."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from ..errors import InputError, InputTypeError
from ..printing import number
from .figures import figure_axes
from .inputs import crank_angles, input_values, inputs_text, solve_at
from .parts import force_pairs, hull, link_points

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..loads import Load
    from ..mechanism import Mechanism
    from .label_placer import LabelPlacer

#: the default arrow scale makes the largest joint force this fraction of the linkage size
ARROW_FRACTION = 0.4
#: a moment load is drawn as an arc of this radius, as a fraction of the linkage size
MOMENT_FRACTION = 0.06

_LINK_COLORS = ("C0", "C1", "C2", "C4", "C9", "C6", "C8", "C5", "C7")  # no red: the forces
_LOAD_COLOR = "k"


def linkage_size(points: Sequence[tuple[float, float]], fallback: float) -> float:
    """The larger side of the bounding box of ``points``; ``fallback`` if zero.

    Examples
    --------
    >>> linkage_size([(0.0, 0.0), (0.4, 0.0), (0.3, 0.25)], 1.0), linkage_size([], 0.1)
    (0.4, 0.1)
    """
    xy = np.asarray(points, dtype=float)
    size = float(np.max(np.ptp(xy, axis=0))) if len(xy) else 0.0
    return size if size > 0.0 else float(fallback)


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
                size: float, labels: LabelPlacer) -> np.ndarray:
    """Draws each load, each labelled with its name and value: a force as an arrow
    ``value * direction * scale`` [m] ending at its point, a moment as an arc about the
    middle of its link's points, with its head in the moment's sense; a load of 0 in
    its positive sense, faint, a force ``0.15 * size`` long; each arrow and arc one
    that ``labels`` keep off. Returns the segments drawn (``x, y, u, v`` [m]), whose
    ends set the axes' limits."""
    from matplotlib.patches import FancyArrowPatch

    segments = []
    for load, value, direction in loads:
        faint = value == 0.0  # no sense to show: the positive one, as a reminder
        style = dict(color=_LOAD_COLOR, alpha=0.35 if faint else 1.0, zorder=5)
        text = f"{load.name} = {number(value)} {load.unit}"
        if direction is not None:
            (x, y), length = pos[load.at], 0.15 * size if faint else value * scale
            u, v = length * direction[0], length * direction[1]
            labels.quivers.append(ax.quiver(
                [x], [y], [u], [v], angles="xy", scale_units="xy", scale=1.0, pivot="tip",
                width=0.006, gid=f"load:{load.name}", **style))
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
        labels.curves.append((np.c_[x, y], 1.6))
        # the head: 0.4 of the mutation scale long, 0.2 either side, with its edge
        labels.heads.append((x[-1], y[-1], 0.4 * 14 + 1.6))
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

    A link is drawn as the convex hull of the points it carries (:func:`link_points`,
    :func:`hull`): a bar between two (or between the ends of points on one line), a
    lightly filled plate with an outline for three or more, a slider a square, revolute
    joints circles, frame points hatched triangles and fixed guides dashed lines. Each
    :func:`force_pairs` force whose joint is known is an arrow ``F * scale`` [m]
    starting at its joint's point, labelled with its name and magnitude beyond its tip.
    Each load is labelled with its name and value (as given, or, over the cycle, at this
    angle): a force as an arrow ``value * direction * scale`` [m] ending at its point,
    so that it points the way the force acts, a moment as an arc about the middle of its
    link's points with its head in the moment's sense (counter-clockwise for a positive
    value); a load of 0 is drawn faint, in its positive sense (a force 0.15 of the
    linkage's size long). The labels are placed when the figure is drawn (their size is
    in points, the linkage's in metres), each as near its point or tip as it can be
    inside the axes without covering another label, a joint, a frame point's symbol,
    the scale, an arrow, an arc, a guide, a link's line or a plate's edge
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
        lines ``gid="link:<name>"`` (a patch for a slider, a ``Polygon`` of the hull's
        corners, counter-clockwise, for a plate) and ``gid="joints"``; each
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
    >>> [t.get_text() for t in ax.texts  # on the rocker
    ...  if t.get_gid() == "load label:load"]
    ['load = 5 N.m']
    """
    if mech.rates:  # driven by time: the drivers' inputs and the loads by name
        if theta is not None or theta_deg is not None or omega is not None or \
                alpha is not None or loads:
            raise InputTypeError(f"{mech.name} is driven by time: give its inputs by name "
                                 f"({', '.join(mech.input_names)})")
        values, given = mech.input_table.every((), named_loads)
        inputs = dict(zip(mech.input_names + tuple(given), map(float, values)))
        sol = mech.solve(**inputs)  # raises where it cannot be assembled
        q = tuple(inputs[d.inputs[0]] for d in mech.drivers)
        st = mech.kinematics(q, order=0, rates=tuple((0.0, 0.0) for _ in q))
        scene = _scene(mech, st, lambda name: float(sol[name]), math.nan, inputs)
    else:
        rad, deg = crank_angles(theta, theta_deg, scalar=True)
        inputs = input_values(mech, omega, alpha, loads, named_loads)
        th = float(rad[0])
        st = mech.kinematics(th, order=0)  # raises where it cannot be assembled
        sol = solve_at(mech, th, inputs)
        scene = _scene(mech, st, lambda name: float(sol[name]), float(deg[0]), inputs)
    size = linkage_size([scene.pos[p] for p in drawn_points(mech)], mech.length_scale)
    largest = scene.largest
    if scale is None:
        scale = ARROW_FRACTION * size / largest if largest > 0.0 else 1.0
    elif not (math.isfinite(scale) and scale > 0.0):
        raise InputError(f"scale must be a finite number > 0 [m/N], got {scale!r}")

    fig, ax = figure_axes(ax, figsize=(8.0, 6.5))
    tips = draw_scene(ax, mech, scene, scale, size, largest)
    lo, hi = tips.min(axis=0) - 0.12 * size, tips.max(axis=0) + 0.12 * size
    lo[1] -= 2.2 * 0.025 * size + 0.12 * size  # the ground hatching, and a band for the scale
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_title(scene_title(mech, scene, inputs, scale, largest, size), fontsize=10)
    return fig


class Scene(NamedTuple):
    """The linkage at one state, what :func:`draw_scene` draws: the crank angle
    ``theta_deg`` [deg], the points' positions ``pos`` [m], the links' unit directions
    ``u``, the :func:`force_pairs` forces that act at a point (``forces``, shape
    ``(n, 2)`` [N], their ``pairs``), the loads and the efforts (name -> value; None
    where none is an output). A linkage driven by time has no crank angle: NaN."""

    theta_deg: float
    pos: dict
    u: dict
    pairs: tuple
    forces: np.ndarray
    loads: list
    effort: float | None

    @property
    def largest(self) -> float:
        """The largest finite joint force or load force [N] (0 if none)."""
        magnitudes = [*np.hypot(self.forces[:, 0], self.forces[:, 1]),
                      *(abs(ld.value) for ld in self.loads if ld.direction is not None)]
        return max([0.0, *(m for m in magnitudes if math.isfinite(m))])


class _StateAt:
    """One state of an array kinematic state, as floats: what a load's value at a
    state needs (its angle, its points, the links' directions)."""

    def __init__(self, st, k: int):
        from ..numerics import SCALAR

        self.theta, self.xp = float(np.asarray(st.theta).reshape(-1)[k]), SCALAR
        self.p = {n: _pick(v, k) for n, v in st.p.items()}
        self.u = {n: _pick(v, k) for n, v in st.u.items()}


def _pick(xy, k: int) -> tuple[float, float]:
    """``(x, y)`` of the ``k``-th state, each an array over the states or one number."""
    return tuple(float(np.asarray(c).reshape(-1)[k] if np.ndim(c) else c) for c in xy)


def drawn_points(mech: "Mechanism") -> list[str]:
    """The points the picture draws: every link's and the frame's, sorted.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> drawn_points(presets.get("four_bar"))
    ['A', 'B', 'C', 'D']
    """
    return sorted({p for pts in link_points(mech).values() for p in pts} |
                  set(mech.frame_points))


def scenes(mech: "Mechanism", theta: np.ndarray, inputs: dict, count: int | None = None):
    """``(scenes, solution)``: the :class:`Scene` at each of the first ``count`` (all
    if None) crank angles of ``theta`` [rad] (a 1-D array), and the solution at every
    angle, from one array kinematics and one array solve.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> from linkage_fmu.plot.inputs import input_values
    >>> mech = presets.get("four_bar")
    >>> inputs = input_values(mech, 10.0, 0.0, (), {})
    >>> frames, sol = scenes(mech, np.radians([0.0, 90.0, 180.0]), inputs, count=2)
    >>> len(frames), sol["F21x"].shape, [p.name for p in frames[1].pairs]
    (2, (3,), ['F21', 'F32', 'F43', 'F14'])
    >>> bool(np.allclose(frames[1].pos["B"], (0.0, 0.1)))  # the crank pin, at 90 deg
    True
    """
    theta = np.asarray(theta, dtype=float).reshape(-1)
    st = mech.kinematics(theta, order=0)
    sol = solve_at(mech, theta, inputs)
    pairs = tuple(p for p in force_pairs(mech) if p.point is not None)
    values: dict = {}

    def at(k: int):
        def value(name: str) -> float:
            if name not in values:
                values[name] = np.broadcast_to(np.asarray(sol[name], float), theta.shape)
            return float(values[name][k])
        return value

    n = theta.size if count is None else count
    return [_scene(mech, _StateAt(st, k), at(k), math.degrees(theta[k]), inputs, pairs)
            for k in range(n)], sol


def driven_scenes(mech: "Mechanism", rows: dict, sol) -> list[Scene]:
    """The :class:`Scene` at each row of a linkage driven by time: ``rows`` holds each
    input's values, one per row (arrays of one length), ``sol`` the solution there.

    Examples
    --------
    >>> from pathlib import Path
    >>> import linkage_fmu
    >>> dump = linkage_fmu.load(Path(linkage_fmu.__file__).parents[2] /
    ...                         "examples/dump_body.toml")
    >>> rows = {"s_P": np.array([0.0, 0.2]), "v_P": np.zeros(2), "a_P": np.zeros(2),
    ...         "W": np.full(2, 1000.0)}
    >>> frames = driven_scenes(dump, rows, dump.solve(**rows))
    >>> [round(f.effort["Fb_P"], 3) for f in frames] == [
    ...     round(dump.solve(s_P=s, v_P=0.0, W=1000.0)["Fb_P"], 3) for s in (0.0, 0.2)]
    True
    """
    q = tuple(rows[d.inputs[0]] for d in mech.drivers)
    st = mech.kinematics(q, order=0, rates=tuple((0.0, 0.0) for _ in q))
    n = len(q[0])
    pairs = tuple(p for p in force_pairs(mech) if p.point is not None)

    def at(k: int):
        return lambda name: float(np.broadcast_to(np.asarray(sol[name], float), (n,))[k])

    return [_scene(mech, _StateAt(st, k), at(k), math.nan, {i: v[k] for i, v in rows.items()},
                   pairs) for k in range(n)]


def _scene(mech: "Mechanism", st, value, theta_deg: float, inputs: dict,
           pairs: tuple | None = None) -> Scene:
    """The :class:`Scene` at the state ``st`` (floats), ``value(name)`` giving each
    output there; ``pairs`` the force pairs that act at a point, if known."""
    if pairs is None:
        pairs = tuple(p for p in force_pairs(mech) if p.point is not None)
    forces = np.array([(value(p.x), value(p.y)) for p in pairs], dtype=float).reshape(-1, 2)
    efforts = {e.name: value(e.name) for e in mech.efforts if e.name in mech.output_names}
    return Scene(theta_deg, {p: (float(x), float(y)) for p, (x, y) in st.p.items()},
                 {n: (float(c), float(s)) for n, (c, s) in st.u.items()}, pairs, forces,
                 _loads_at(mech, st, inputs), efforts or None)


def scene_title(mech: "Mechanism", scene: Scene, inputs: dict, scale: float, largest: float,
                size: float) -> str:
    """The picture's title: the angle, the inputs, the effort, the scale."""
    at = "" if math.isnan(scene.theta_deg) else f" at θ = {number(scene.theta_deg)}°"
    title = f"{mech.name}{at}, {inputs_text(mech, inputs)}\n"
    for e in mech.efforts:
        if scene.effort is None or e.name not in scene.effort:
            continue
        # a sum of forces times lengths: what rounding leaves of a zero is 0 (the scotch
        # yoke's Mb at 90 deg, 1.8e-15 N m beside 260 N on a 0.1 m crank)
        arm = size if e.direction is None else 1.0
        title += (f"{e.name} = {number(scene.effort[e.name], scale=largest * arm)} "
                  f"{mech.output_info[e.name][0]}; ")
    if len(mech.efforts) > 1:  # the efforts fill a line
        title = title[:-2] + "\n"
    return title + f"forces to scale {number(scale)} m/N (1 N = {number(1000 * scale, 3)} mm)"


def draw_scene(ax: "Axes", mech: "Mechanism", scene: Scene, scale: float, size: float,
               largest: float) -> np.ndarray:
    """Draws ``scene`` into ``ax`` as :func:`linkage` does (the forces ``scale`` [m/N],
    the symbols for a linkage ``size`` [m] across, the scale's key a round force near
    half ``largest`` [N]), its labels placed at each draw, equal aspect; the limits
    and the title left to the caller. Returns the points drawn (shape ``(n, 2)`` [m]: the
    points, the arrows' tips and tails), whose extent the limits should hold."""
    from matplotlib.colors import to_rgba
    from matplotlib.patches import Polygon, Rectangle

    from .label_placer import LabelPlacer  # a matplotlib artist: imported to draw

    pos, links = scene.pos, link_points(mech)
    drawn = drawn_points(mech)
    ok = np.isfinite(scene.forces).all(axis=1)  # no arrow where there is no force
    pairs = [p for p, good in zip(scene.pairs, ok) if good]
    forces = scene.forces[ok]
    origins = np.array([pos[p.point] for p in pairs], dtype=float).reshape(-1, 2)
    s = 0.025 * size
    for name in mech.frame_points:
        _draw_frame_point(ax, *pos[name], s, name)
    guides = []
    for j in mech.joints:  # fixed guides
        normal = j.guide(None)
        if normal is not None and mech.frame in (j.a, j.b):
            (x, y), (nx, ny) = pos[j.point], normal
            tx, ty = ny, -nx
            h = 0.35 * size
            ends = np.array([(x - h * tx, y - h * ty), (x + h * tx, y + h * ty)])
            ax.plot(*ends.T, ls=(0, (6, 3)), color="0.4", lw=1.2, zorder=1,
                    gid=f"guide:{j.name}")
            guides.append(ends)
    lines = []
    for k, (link, pts) in enumerate(links.items()):
        color = _LINK_COLORS[k % len(_LINK_COLORS)]
        if len(pts) == 1:  # a slider or block: a square along its direction
            (x, y), (ux, uy) = pos[pts[0]], scene.u.get(link, (1.0, 0.0))
            ax.add_patch(Rectangle((x - 2 * s, y - 1.2 * s), 4 * s, 2.4 * s,
                                   angle=math.degrees(math.atan2(float(uy), float(ux))),
                                   rotation_point="center", facecolor=color, alpha=0.35,
                                   edgecolor=color, lw=1.5, zorder=2, gid=f"link:{link}"))
            continue
        ring = hull(pts, pos)
        xy = [pos[p] for p in ring] + ([pos[ring[0]]] if len(ring) > 2 else [])
        lines += [(x0, y0, x1 - x0, y1 - y0) for (x0, y0), (x1, y1) in zip(xy, xy[1:])]
        if len(ring) > 2:  # a plate: its joints' and points' hull, lightly filled
            ax.add_patch(Polygon(xy[:-1], closed=True, facecolor=to_rgba(color, 0.2),
                                 edgecolor=color, lw=2.0, joinstyle="round", zorder=2,
                                 label=f"link {link}", gid=f"link:{link}"))
            continue
        ax.plot(*zip(*xy), "-", color=color, lw=3.0, solid_capstyle="round", zorder=2,
                label=f"link {link}", gid=f"link:{link}")
    revolute = [j.point for j in mech.joints if j.draws_pin]
    jx, jy = zip(*[pos[p] for p in revolute]) if revolute else ((), ())
    ax.plot(jx, jy, "o", ms=7, mfc="white", mec="k", mew=1.3, ls="none", zorder=4,
            gid="joints")
    labels = LabelPlacer(ax)
    labels.curves += [(ends, 1.2) for ends in guides]  # a dashed guide read as an arrow
    labels.marks = np.array([pos[p] for p in drawn], dtype=float).reshape(-1, 2)
    labels.blocks = np.array([(pos[p][0] - 1.6 * s, pos[p][1] - 2.2 * s, pos[p][0] + 1.6 * s,
                               pos[p][1]) for p in mech.frame_points]).reshape(-1, 4)
    for p in drawn:  # up and to the left, as far as the others let them
        labels.add(p, pos[p], (-1.0, 1.0), "0.25", fontsize=9, gid=f"point:{p}")

    u, v = forces[:, 0] * scale, forces[:, 1] * scale
    quiver = ax.quiver(origins[:, 0], origins[:, 1], u, v, angles="xy", scale_units="xy",
                       scale=1.0, color="crimson", width=0.006, zorder=5, gid="forces")
    for p, (x, y), du, dv, (fx, fy) in zip(pairs, origins, u, v, forces):
        labels.add(f"{p.name}\n{number(math.hypot(fx, fy), 3)} N", (x + du, y + dv), (du, dv),
                   "crimson", fontsize=8, gid=f"force:{p.name}")  # beyond the tip
    drawn_loads = _draw_loads(ax, scene.loads, pos, links, scale, size, labels)
    labels.quivers.append(quiver)
    labels.segments = np.array(lines, dtype=float).reshape(-1, 4)
    if largest > 0.0:
        ref = _nice(0.5 * largest)
        key = ax.quiverkey(quiver, 0.5, 0.04, ref * scale, f"{number(ref, 6)} N", labelpos="E",
                           coordinates="axes", color="crimson")
        key.set_gid("scale")
        labels.key = key

    tips = np.concatenate([np.array([pos[p] for p in drawn]), origins + np.c_[u, v],
                           drawn_loads[:, :2], drawn_loads[:, :2] + drawn_loads[:, 2:]])
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, alpha=0.2)
    return tips
