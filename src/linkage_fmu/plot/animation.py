"""The linkage in motion (:func:`animate`): the picture of :func:`~.picture.linkage` at
each frame's crank angle, its forces to one scale for the whole motion, beside a curve
over the motion with a cursor at the frame's angle; written as a GIF (pillow) or an MP4
(ffmpeg)."""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .. import ranges
from ..drivers import one_crank
from ..errors import InputError, LinkageFmuError
from ..flywheel import cycle_revolutions
from ..outputs import SHAKING
from ..printing import number
from ..solver import SOLVED
from .curves import draw_curve
from .figures import degree_axis, pyplot
from .inputs import N_ANGLES, finite_or_fail, input_values, inputs_text
from .picture import ARROW_FRACTION, Scene, draw_scene, drawn_points, linkage_size, scenes

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.animation import FuncAnimation
    from matplotlib.figure import Figure

    from ..mechanism import Mechanism

#: frames by default: 5 degrees apart over a revolution
N_FRAMES = 72
#: what the curve beside the linkage shows
WHATS = ("forces", "torque", "shaking")
#: a state's forces are bounded where it is solved and its ``cond`` (the condition
#: number of the equations the forces solve) is finite and below this. Away from a
#: singular position cond is of order 1 to 100; it passes 1e4 within about a degree of
#: a position where the forces grow without bound (at it, they are rounding: 1e99 N)
COND_BOUND = 1e4
#: the step [deg] of the grid on which a crank that cannot turn finds the ends of its
#: motion: the first and last angles of its assembly range with bounded forces
TRIM_STEP_DEG = 0.01
#: the files an animation is written to, by suffix
SUFFIXES = (".gif", ".mp4")
#: the figure's size in inches (width, height), unless ``animate`` is given another
FIGSIZE = (11.0, 4.8)
#: a frame's width and height in pixels are below this: matplotlib's renderer (Agg) and a
#: GIF (16-bit sizes) draw no larger
MAX_PIXELS = 2 ** 16


def frame_pixels(dpi: float, figsize=FIGSIZE) -> tuple[int, int]:
    """The size (width, height) in pixels of a frame of ``figsize`` inches at ``dpi``
    pixels an inch; a ValueError naming ``dpi`` where a side would reach
    :data:`MAX_PIXELS`.

    Examples
    --------
    >>> frame_pixels(80.0)
    (880, 384)
    >>> frame_pixels(1e9)
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError:
    dpi 1e+09 draws frames of 1.1e+10 x 4.8e+09 pixels; a frame is less than
    65536 pixels a side (matplotlib's and a GIF's limit): dpi 5957 at most for 11 x 4.8 inches
    """
    width, height = (float(v) * dpi for v in figsize)
    if not max(width, height) < MAX_PIXELS:
        most = math.floor((MAX_PIXELS - 1) / max(float(v) for v in figsize))
        raise InputError(f"dpi {dpi:g} draws frames of {width:.4g} x {height:.4g} pixels; a "
                         f"frame is less than {MAX_PIXELS} pixels a side (matplotlib's and a "
                         f"GIF's limit): dpi {most} at most for {figsize[0]:g} x "
                         f"{figsize[1]:g} inches")
    return round(width), round(height)


def motion_range(mech: "Mechanism", given=()) -> tuple[float, float, bool]:
    """``(first, last, full)``: the crank angles [deg] the animation goes between, and
    whether the crank turns round: from 0 over a revolution (``0, 360, True``), or over
    the revolutions of a cycle where a load's table needs several
    (:func:`~linkage_fmu.flywheel.cycle_revolutions`; ``given``, the loads given a
    value: a four-stroke engine's 720 deg unless its gas force is given). Otherwise the
    range where the linkage assembles (:func:`linkage_fmu.ranges.assembles`; one that
    runs over 360 deg joined, as from -136 to 136 deg) that holds the start angle (else
    the longest), from the first to the last angle of it where the forces are bounded
    (:func:`bounded`), on a grid :data:`TRIM_STEP_DEG` apart: its ends are toggles,
    where the forces grow without bound.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> motion_range(presets.get("four_bar"))
    (0.0, 360.0, True)
    >>> [round(v, 2) for v in motion_range(presets.get("four_bar", l_AB=0.3))[:2]]
    [-135.93, 135.93]
    """
    where = ranges.assembles(mech)
    if where == [(0.0, 360.0)]:
        return 0.0, 360.0 * cycle_revolutions(mech, None, given), True
    if not where:
        raise InputError(f"{mech.name} cannot be assembled at any crank angle: nothing to "
                         "animate")
    if len(where) > 1 and where[0][0] == 0.0 and where[-1][1] == 360.0:  # one range over 0
        where = [(where[-1][0] - 360.0, where[0][1])] + where[1:-1]
    start = math.degrees(mech.start["theta"]) % 360.0
    holding = [(a, b) for a, b in where if a <= start <= b or a <= start - 360.0 <= b]
    lo, hi = max(holding or where, key=lambda r: r[1] - r[0])
    grid = np.linspace(lo, hi, max(int(math.ceil((hi - lo) / TRIM_STEP_DEG)), 2) + 1)
    ok = np.flatnonzero(bounded(mech, mech.solve(np.radians(grid))))
    if not ok.size:
        raise InputError(f"{mech.name}: its forces have no bound (cond > {COND_BOUND:g}) "
                         f"anywhere in its range {number(lo, 6)}..{number(hi, 6)} deg: "
                         "nothing to animate")
    return float(grid[ok[0]]), float(grid[ok[-1]]), False


def bounded(mech: "Mechanism", sol) -> np.ndarray:
    """Where the array solution ``sol`` has bounded forces: the state solved, and its
    ``cond`` (where the linkage has it) finite and below :data:`COND_BOUND`.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("four_bar", l_AB=0.1, l_CD=0.1, l_BC=0.4, l_AD=0.4)
    >>> bounded(mech, mech.solve(np.radians([0.0, 90.0, 180.0]))).tolist()
    [False, True, False]
    """
    ok = np.asarray(sol.status) == SOLVED
    if "cond" in mech.diagnostic_names:
        cond = np.asarray(sol["cond"], dtype=float)
        with np.errstate(invalid="ignore"):
            ok = ok & np.isfinite(cond) & (cond < COND_BOUND)
    return np.broadcast_to(ok, np.shape(sol.valid)).copy()


def frame_angles(mech: "Mechanism", frames: int, given=()) -> np.ndarray:
    """The crank angle [deg] of each frame: where the crank turns round, a revolution
    (or a cycle of several) ``360 / frames`` (``720 / frames``, ...) degrees apart from
    0 (360 left out: it is the first frame again, and the animation loops); else out and
    back over :func:`motion_range`, ``2 * (last - first) / frames`` degrees apart: from
    the first angle to the last at frame ``frames / 2`` and back, the first left out at
    the end (the loop closes; ``frames`` must then be even, so that both ends are
    frames and every step is the same).

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> frame_angles(presets.get("four_bar"), 4).tolist()
    [0.0, 90.0, 180.0, 270.0]
    >>> frame_angles(presets.get("four_bar", l_AB=0.3), 4).round(2).tolist()
    [-135.93, 0.0, 135.93, 0.0]
    """
    lo, hi, full = motion_range(mech, given)
    if full:
        return hi * np.arange(frames) / frames
    if frames % 2:
        raise InputError(f"frames must be even for {mech.name}, whose crank cannot turn a "
                         f"revolution and goes out and back over {number(lo, 4)}.."
                         f"{number(hi, 4)} deg, got {frames}")
    out = np.linspace(lo, hi, frames // 2 + 1)
    return np.concatenate([out, out[-2:0:-1]])


class LinkageAnimation:
    """The animation :func:`animate` makes: ``figure`` (the linkage's axes first, the
    curve's second), ``animation`` (a :class:`matplotlib.animation.FuncAnimation`,
    e.g. for ``to_jshtml()`` in a notebook), ``theta_deg`` (each frame's crank angle
    [deg]), ``scale`` (the arrows' length per force [m/N], one for every frame) and
    ``what``; :meth:`draw` draws a frame, :meth:`save` writes the file."""

    def __init__(self, figure: "Figure", scenes_: list[Scene], draw_frame, scale: float,
                 what: str):
        self.figure = figure
        self.theta_deg = np.array([s.theta_deg for s in scenes_])
        #: the frames' times [s] of a linkage driven by time (its theta_deg NaN), or None
        self.t: np.ndarray | None = None
        self.scale = scale
        self.what = what
        self._draw = draw_frame
        self._animation: "FuncAnimation | None" = None

    @property
    def animation(self) -> "FuncAnimation":
        """The :class:`matplotlib.animation.FuncAnimation` of the frames, made when
        first asked for (matplotlib warns of one deleted before it is shown)."""
        if self._animation is None:
            from matplotlib.animation import FuncAnimation

            self._animation = FuncAnimation(self.figure, lambda k: self._draw(k) or [],
                                            frames=len(self), init_func=lambda: [],
                                            blit=False, cache_frame_data=False, repeat=True)
        return self._animation

    def __len__(self) -> int:
        return self.theta_deg.size

    def draw(self, k: int) -> None:
        """Draws the ``k``-th frame into :attr:`figure` (the labels are placed when the
        figure is rendered)."""
        self._draw(k)

    def save(self, path, fps: float = 12.0, dpi: float = 80.0) -> Path:
        """Writes the animation to ``path``: a ``.gif`` (with pillow) or an ``.mp4``
        (with ffmpeg, which must be installed), ``fps`` frames a second, ``dpi`` pixels
        an inch of the figure. Returns the path."""
        path = Path(path)
        writer = _writer(path, fps)
        # frame by frame, as Animation.save does, without its redraw of the canvas after
        # each frame (a third of the time: the frame is drawn again when it is grabbed)
        with writer.saving(self.figure, str(path), dpi):
            for k in range(len(self)):
                self._draw(k)
                writer.grab_frame()
        return path


class MissingFFmpegError(LinkageFmuError, RuntimeError):
    """An MP4 asked for where ffmpeg is not installed (raised before any work)."""


def _suffix(path) -> str:
    suffix = Path(path).suffix.lower()
    if suffix not in SUFFIXES:
        raise InputError(f"{path}: an animation is written to a .gif or .mp4 file, not "
                         f"{suffix or 'a file without a suffix'}")
    return suffix


def _writer(path: Path, fps: float):
    """The matplotlib writer for ``path``'s suffix; a RuntimeError saying how to get
    ffmpeg for an MP4 where it is not installed."""
    from matplotlib import animation, rcParams

    if not (math.isfinite(fps) and fps > 0):
        raise InputError(f"fps must be a number > 0, got {fps!r}")
    if _suffix(path) == ".gif":
        return animation.PillowWriter(fps=fps)
    if not animation.FFMpegWriter.isAvailable():
        raise MissingFFmpegError(
            f"{path}: writing an MP4 needs ffmpeg, and there is no "
            f"{rcParams['animation.ffmpeg_path']!r} on the PATH; install it (apt install "
            "ffmpeg, brew install ffmpeg, conda install ffmpeg, or from https://ffmpeg.org), "
            "or write a .gif, which needs nothing more")
    return animation.FFMpegWriter(fps=fps)


def animate(mech: "Mechanism", path=None, *, what: str = "forces", frames: int = N_FRAMES,
            omega=None, alpha=None, fps: float = 12.0, dpi: float = 80.0,
            figsize=FIGSIZE, t=None, motion=None, **named_loads) -> LinkageAnimation:
    """The linkage moving over a revolution (or the cycle of several a load's table
    needs, as a four-stroke engine's; where the crank cannot turn round, out and back
    over its range: :func:`motion_range`, :func:`frame_angles`), with its joint forces
    and loads drawn as :func:`~linkage_fmu.plot.linkage` draws them (a load of 0 not
    drawn at all: nothing to show), and beside it a curve over the motion
    with a cursor at each frame's crank angle; written to ``path`` if given.

    Every frame is solved in one array call. The arrows are to one scale for the whole
    motion (the largest force of any frame :data:`ARROW_FRACTION` of the largest extent
    of the linkage over the motion), so that their lengths compare between frames; the
    view is fixed, and the labels are placed at each frame, inside the linkage's axes,
    so that none overlaps another, an arrow, an arc, a link's line or a joint.

    Parameters
    ----------
    mech : Mechanism
    path : str or Path, optional
        Write the animation there: ``.gif`` (pillow, which matplotlib installs) or
        ``.mp4`` (needs ffmpeg on the PATH). None: only make it.
    what : {"forces", "torque", "shaking"}
        The curve: the magnitude of each joint force; the balancing effort (``Mb``)
        with its mean and peak; or the shaking force ``shake_x``, ``shake_y`` and its
        magnitude.
    frames : int
        Frames (>= 2): over a revolution, ``360 / frames`` degrees apart (5 by
        default); over a cycle of two, ``720 / frames``; out and back over a range,
        an even number.
    omega, alpha, **named_loads : float or str, optional
        The crank's speed [rad/s] and acceleration [rad/s2] and the loads by name, as
        for :func:`~linkage_fmu.plot.torque`; the linkage's start values if not given.
    fps, dpi : float
        Frames a second, and pixels an inch of the figure (``figsize`` inches), of the
        file written.
    t, motion : array_like and dict, for a linkage driven by time
        The frames' times [s], and its inputs over them by name, each an array of one
        value per time or a function of the time; an input not in ``motion`` is given
        by name in ``named_loads`` or takes its start value. ``what`` is then
        ``"forces"``, ``"efforts"`` (each driver's) or ``"shaking"``, the curves
        against the time, and ``frames`` is the number of times.

    Returns
    -------
    LinkageAnimation
        Its ``figure``'s first axes hold the linkage as :func:`~linkage_fmu.plot.linkage`
        draws it at the frame last drawn (``gid="link:<name>"``, ``"forces"``, ...);
        the second the curve(s) (gid: the output's name, ``"|F21|"``, ``"|shake|"``),
        the line ``gid="cursor"`` at the frame's angle and a point
        ``gid="cursor:<curve>"`` on each curve.

    Raises
    ------
    ValueError
        ``what``, ``frames`` or ``path``'s suffix is not one of the above (``frames``
        odd where the crank goes out and back), ``dpi`` or ``figsize`` is not finite and
        > 0 or makes a frame too large to draw (:func:`frame_pixels`), ``path``'s folder
        does not exist, or the linkage cannot be assembled anywhere.

    Warns
    -----
    UserWarning
        Frames where the forces have no bound (:func:`bounded`: a singular position
        inside the motion, as a parallelogram four-bar's at 0 and 180 deg), naming
        their angles: they draw no force arrows, and the arrows' scale and the curve's
        limits are made without them (the curve has a gap there).
    RuntimeError
        An ``.mp4`` without ffmpeg installed.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from linkage_fmu import plot, presets
    >>> anim = plot.animate(presets.get("four_bar"), frames=8, what="torque")
    >>> len(anim), anim.theta_deg.tolist()
    (8, [0.0, 45.0, 90.0, 135.0, 180.0, 225.0, 270.0, 315.0])
    >>> anim.draw(2)
    >>> cursor = next(line for line in anim.figure.axes[1].lines
    ...               if line.get_gid() == "cursor")
    >>> float(cursor.get_xdata()[0])
    90.0
    """
    if mech.rates:
        return _over_time(mech, path, what, t, motion, fps, dpi, figsize, named_loads)
    one_crank(mech, "a plot over crank angles")
    if what not in WHATS:
        raise InputError(f"what={what!r}: expected one of {', '.join(WHATS)}")
    if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < 2:
        raise InputError(f"frames must be a whole number >= 2, got {frames!r}")
    _check_output(path, fps, dpi, figsize)
    inputs = input_values(mech, omega, alpha, (), named_loads)
    deg = frame_angles(mech, int(frames), named_loads)
    lo, hi, full = motion_range(mech, named_loads)
    turns = round(hi / 360.0) if full else 1  # 0.5 degrees apart over a revolution
    curve_deg = np.linspace(lo, hi, (N_ANGLES - 1) * turns + 1)
    frames_, sol = scenes(mech, np.radians(np.concatenate([deg, curve_deg])), inputs,
                          count=deg.size)
    ok = bounded(mech, sol)
    frames_ = [s._replace(theta_deg=float(d), loads=[ld for ld in s.loads if ld.value != 0.0])
               if good else _unbounded(s._replace(theta_deg=float(d)))
               for s, d, good in zip(frames_, deg, ok)]  # the angle as given; no zero load
    curves, unit, title = _curves(mech, what, sol, deg.size)
    curves = {name: np.where(ok, values, np.nan) for name, values in curves.items()}
    finite_or_fail(mech, np.concatenate([c[deg.size:] for c in curves.values()]), curve_deg,
                   sol)
    if not ok[:deg.size].all():
        left = ", ".join(number(d, 4) for d in deg[~ok[:deg.size]])
        warnings.warn(f"{mech.name}: the forces have no bound (singular, or cond > "
                      f"{COND_BOUND:g}) at theta = {left} deg: those frames draw no force "
                      "arrows, and the arrows' scale and the curve's limits leave them out",
                      UserWarning, stacklevel=2)
    limits = _limits(curves, ok, deg, curve_deg, full)

    effort = mech.effort.name

    def label(k: int, s, size: float, largest: float) -> str:
        text = f"θ = {number(deg[k], 1, fixed=True)}°"
        if not ok[k]:
            text += ", forces unbounded (a singular position)"
        elif s.effort is not None:
            arm = size if mech.effort.direction is None else 1.0
            text += (f", {effort} = {number(s.effort[effort], 4, scale=largest * arm)} "
                     f"{mech.output_info[effort][0]}")
        return text

    def curves_on(ax):
        cursor = _draw_curves(ax, mech, curves, deg, curve_deg, unit, title)
        if limits is not None:
            ax.set_ylim(*limits)
        return cursor

    return _assembled(mech, frames_, curves_on, label, inputs, figsize, what, path, fps, dpi)


def _check_output(path, fps: float, dpi: float, figsize) -> None:
    """Refuse, naming it, a ``dpi``, ``figsize`` or ``path`` that the animation cannot
    be drawn with or written to (before any work)."""
    _positive("dpi", dpi)
    try:
        width, height = (float(v) for v in figsize)
    except (TypeError, ValueError):
        raise InputError(f"figsize must be (width, height) in inches, got {figsize!r}"
                         ) from None
    for value in (width, height):
        _positive("figsize", value, f"each of (width, height) in inches, got {figsize!r}")
    frame_pixels(dpi, (width, height))
    if path is not None:
        _suffix(path)
        if not Path(path).resolve().parent.is_dir():
            raise InputError(f"{path}: there is no folder {Path(path).parent}")
        _writer(Path(path), fps)  # no ffmpeg: said before the work


#: the curves an animation over time draws
OVER_TIME = ("forces", "efforts", "shaking")


def _over_time(mech: "Mechanism", path, what: str, t, motion, fps: float, dpi: float,
               figsize, named: dict) -> LinkageAnimation:
    """:func:`animate` of a linkage driven by time over its inputs ``motion`` at the
    times ``t``."""
    from ..numerics import finite_array
    from .picture import driven_scenes

    if what not in OVER_TIME:
        raise InputError(f"what={what!r}: expected one of {', '.join(OVER_TIME)} (a linkage "
                         "driven by time)")
    if t is None or motion is None:
        raise InputError(f"{mech.name} is driven by time: animate it over a motion, t (the "
                         "frames' times) and motion (its inputs over them by name: "
                         f"{', '.join(mech.input_names)})")
    t = np.asarray(finite_array("t", t), dtype=float).reshape(-1)
    if t.size < 2 or not (np.diff(t) > 0).all():
        raise InputError("t must hold at least 2 times, strictly increasing")
    unknown = [n for n in motion if n not in mech.input_names]
    if unknown:
        raise InputError(f"motion: {', '.join(map(str, unknown))}: no input of {mech.name}; "
                         f"its inputs are {', '.join(mech.input_names)}")
    _check_output(path, fps, dpi, figsize)
    values, given = mech.input_table.every((), {
        **{d.inputs[0]: mech.start[d.inputs[0]] for d in mech.drivers}, **named})
    rows = {n: np.full(t.size, float(v)) for n, v in zip(mech.input_names + tuple(given),
                                                        values)}
    for name, spec in motion.items():
        column = np.asarray(spec(t) if callable(spec) else spec, dtype=float)
        rows[name] = np.broadcast_to(finite_array(f"motion[{name!r}]", column), t.shape)
    sol = mech.solve(**rows)
    if not np.asarray(sol.valid).any():
        raise InputError(f"{mech.name} cannot be assembled at any of the {t.size} times")
    ok = bounded(mech, sol)
    frames_ = [s._replace(loads=[ld for ld in s.loads if ld.value != 0.0]) if good else
               _unbounded(s) for s, good in zip(driven_scenes(mech, rows, sol), ok)]
    if what == "efforts":
        curves = {e.name: np.asarray(sol[e.name], float) for e in mech.efforts}
        units = {mech.output_info[e.name][0] for e in mech.efforts}
        unit, title = ", ".join(sorted(units)), "each driver's effort"
    else:
        curves, unit, title = _curves(mech, what, sol, 0)
    curves = {n: np.where(ok, np.broadcast_to(v, t.shape), np.nan) for n, v in curves.items()}
    constant = {n: v[0] for n, v in rows.items() if n not in motion}

    def label(k: int, s, size: float, largest: float) -> str:
        text = f"t = {number(t[k], 4)} s"
        if not ok[k]:
            return text + ", forces unbounded (a singular position)"
        return text + "".join(f", {d.inputs[0]} = {number(rows[d.inputs[0]][k], 4)} "
                              f"{d.units[0]}" for d in mech.drivers)

    def curves_on(ax):
        for j, (name, values) in enumerate(curves.items()):
            ax.plot(t, values, color=f"C{j}", lw=1.4, label=name, gid=name)
        ax.set_xlabel("t [s]")
        ax.set_ylabel(f"[{unit}]")
        ax.set_title(title, fontsize=10)
        return _cursor(ax, curves, t)

    anim = _assembled(mech, frames_, curves_on, label, constant, figsize, what, path, fps,
                      dpi)
    anim.t = t
    return anim


def _assembled(mech, frames_: list, curves_on, label, inputs: dict, figsize, what: str,
               path, fps: float, dpi: float) -> LinkageAnimation:
    """The animation of the scenes ``frames_``: the linkage's panel to one scale and
    view for every frame, beside the curves ``curves_on(ax)`` draws (it returns the
    cursor, ``cursor(k)``), each frame titled ``label(k, scene, size, largest)`` (the
    linkage's size over the motion and the largest force); written to ``path`` if
    given."""
    import matplotlib

    drawn = drawn_points(mech)
    size = linkage_size([s.pos[p] for s in frames_ for p in drawn
                  if all(map(math.isfinite, s.pos[p]))], mech.length_scale)
    largest = max(s.largest for s in frames_)
    scale = ARROW_FRACTION * size / largest if largest > 0.0 else 1.0

    fig, (link_ax, curve_ax) = pyplot().subplots(1, 2, figsize=figsize, width_ratios=(1.1, 1.0),
                                                 layout="constrained")
    given = inputs_text(mech, inputs)
    fig.suptitle(f"{mech.name}: {given + '; ' if given else ''}forces to scale "
                 f"{number(scale)} m/N (1 N = {number(1000 * scale, 3)} mm)", fontsize=10)
    tips = []
    for s in frames_:  # the view holds every frame
        tips.append(draw_scene(link_ax, mech, s, scale, size, largest))
        link_ax.clear()
    tips = np.concatenate(tips)
    tips = tips[np.isfinite(tips).all(axis=1)]
    lo_xy, hi_xy = tips.min(axis=0) - VIEW_MARGIN * size, tips.max(axis=0) + VIEW_MARGIN * size
    lo_xy[1] -= (2.2 * 0.025 + VIEW_MARGIN) * size  # the ground's hatching, the scale's band

    cursor = curves_on(curve_ax)

    def draw_frame(k: int) -> list:
        s = frames_[k]
        link_ax.clear()
        draw_scene(link_ax, mech, s, scale, size, largest)
        link_ax.set_xlim(lo_xy[0], hi_xy[0])
        link_ax.set_ylim(lo_xy[1], hi_xy[1])
        link_ax.set_title(label(k, s, size, largest), fontsize=10)
        cursor(k)
        return []

    draw_frame(0)
    fig.canvas.draw()  # the layout, once for every frame: the view stays still
    view = lo_xy, hi_xy
    for _ in range(2):  # the panels' widths to the view, the view to its panel's shape
        _share_width(link_ax, curve_ax, (hi_xy[0] - lo_xy[0]) / (hi_xy[1] - lo_xy[1]))
        fig.canvas.draw()
        lo_xy, hi_xy = _filling(link_ax, *view)
        draw_frame(0)
        fig.canvas.draw()
    with matplotlib.rc_context({"figure.autolayout": False,
                                "figure.constrained_layout.use": False}):
        fig.set_layout_engine(None)  # none at all: saving a frame then draws it once
    anim = LinkageAnimation(fig, frames_, draw_frame, scale, what)
    if path is not None:
        anim.save(path, fps=fps, dpi=dpi)
    return anim


#: the linkage's axes, as a fraction of the width of both axes, at least and at most
LINKAGE_WIDTH = (0.3, 0.6)
#: the view's margin beyond the points and arrows of every frame, as a fraction of the
#: linkage's size (and as much again below, beside the scale's key)
VIEW_MARGIN = 0.06


def _filling(ax, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The view ``lo``..``hi`` [m] widened about its middle, along x or y, to the shape
    of the axes ``ax`` as laid out, so that the linkage, to equal scales, fills them."""
    box = ax.get_position(original=True)
    width, height = ax.figure.get_size_inches()
    shape = box.width * width / (box.height * height)
    middle, half = (lo + hi) / 2.0, (hi - lo) / 2.0
    if half[0] / half[1] < shape:
        half[0] = half[1] * shape
    else:
        half[1] = half[0] / shape
    return middle - half, middle + half


def _share_width(link_ax, curve_ax, aspect: float) -> None:
    """The width of the axes, as laid out, shared between the linkage's and the
    curve's so that the linkage, to equal scales, fills the height of its axes: their
    width the view's ``aspect`` (width / height) times their height, within
    :data:`LINKAGE_WIDTH` of the two."""
    link, curve = (ax.get_position(original=True) for ax in (link_ax, curve_ax))
    width, height = link_ax.figure.get_size_inches()
    both = link.width + curve.width
    wanted = aspect * link.height * height / width
    wanted = min(max(wanted, LINKAGE_WIDTH[0] * both), LINKAGE_WIDTH[1] * both)
    link_ax.get_subplotspec().get_gridspec().set_width_ratios([wanted, both - wanted])


def _positive(name: str, value, expected: str = "") -> None:
    """A ValueError naming ``name`` unless ``value`` is a finite number > 0."""
    try:
        good = not isinstance(value, bool) and math.isfinite(value) and value > 0
    except TypeError:
        good = False
    if not good:
        raise InputError(f"{name} must be {expected or f'a finite number > 0, got {value!r}'}")


def _unbounded(scene: Scene) -> Scene:
    """``scene`` without its forces (NaN: no arrows) and its effort: they have no
    bound there."""
    return scene._replace(forces=np.full_like(scene.forces, np.nan), effort=None,
                          loads=[ld for ld in scene.loads if ld.value != 0.0])


def _limits(curves: dict, ok: np.ndarray, deg: np.ndarray, curve_deg: np.ndarray,
            full: bool) -> tuple[float, float] | None:
    """The curve axes' y limits where some frames' forces have no bound: the values
    at the bounded frames and at the curve's angles bounded and more than a frame's
    step from any unbounded frame, with a margin (None where every frame is bounded:
    matplotlib's own)."""
    n = deg.size
    if ok[:n].all():
        return None
    step = (deg[-1] - deg[0]) / max(n - 1, 1) if not full else deg[1] - deg[0]
    far = np.ones(curve_deg.size, bool)
    for d in deg[~ok[:n]]:
        gap = np.abs(curve_deg - d)
        if full:
            gap = np.minimum(gap, 360.0 * round((curve_deg[-1] - curve_deg[0]) / 360.0) - gap)
        far &= gap > abs(step)
    keep = np.concatenate([ok[:n], ok[n:] & far])
    values = np.concatenate([np.asarray(v, float)[keep] for v in curves.values()])
    values = values[np.isfinite(values)]
    if not values.size:
        return None
    a, b = float(values.min()), float(values.max())
    pad = 0.05 * (b - a) if b > a else 0.05 * max(abs(a), 1.0)
    return min(a - pad, 0.0) if a >= 0.0 else a - pad, b + pad


def _curves(mech: "Mechanism", what: str, sol, n: int) -> tuple[dict, str, str]:
    """``({label: values at the frames then at the curve's angles}, unit, title)``."""
    def get(name):
        return np.asarray(sol[name], dtype=float)

    if what == "torque":
        name = mech.effort.name
        if name not in mech.output_names:
            raise InputError(f"{mech.name} has no output of its balancing effort {name}: "
                             "animate what='forces' or 'shaking'")
        unit, description = mech.output_info[name]
        return {name: get(name)}, unit, description
    if what == "shaking":
        if not set(SHAKING[:2]) <= set(mech.output_names):
            raise InputError(f"{mech.name} has no shaking force outputs "
                             f"{', '.join(SHAKING[:2])}")
        x, y = get(SHAKING[0]), get(SHAKING[1])
        return ({SHAKING[0]: x, SHAKING[1]: y, "|shake|": np.hypot(x, y)}, "N",
                "shaking force, what the moving links put on the frame")
    from .parts import force_pairs

    pairs = force_pairs(mech)
    if not pairs:
        raise InputError(f"{mech.name} has no force output with x and y components: "
                         "animate what='torque'")
    return ({f"|{p.name}|": np.hypot(get(p.x), get(p.y)) for p in pairs}, "N",
            "the magnitude of each joint force")


def _draw_curves(ax, mech: "Mechanism", curves: dict, deg: np.ndarray, curve_deg: np.ndarray,
                 unit: str, title: str):
    """The curves over ``curve_deg`` with a cursor; returns ``cursor(k)``, which moves
    it to the ``k``-th frame (its angle ``deg[k]``, the values the curves' first
    ``deg.size`` values)."""
    n = deg.size
    if len(curves) == 1:  # the effort: its mean and peak, as plot.torque draws it
        (name, values), = curves.items()
        draw_curve(ax, np.radians(curve_deg), curve_deg, values[n:], name, unit)
    else:
        for k, (name, values) in enumerate(curves.items()):
            ax.plot(curve_deg, values[n:], color=f"C{k}", lw=1.4 if name != "|shake|" else 2.0,
                    label=name, gid=name)
        degree_axis(ax, curve_deg)
        ax.set_ylabel(f"[{unit}]")
    ax.set_title(title, fontsize=10)
    return _cursor(ax, curves, deg)


def _cursor(ax, curves: dict, xs: np.ndarray):
    """The legend beside the axes, a cursor line and a dot on each curve; returns
    ``cursor(k)``, which moves them to the ``k``-th frame (at ``xs[k]``, the curves'
    ``k``-th values)."""
    # beside the axes: a legend inside would move as the cursor does ("best"), and one
    # below would take from the height the linkage's panel has too
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    line = ax.axvline(xs[0], color="0.3", lw=1.0, ls=":", gid="cursor")
    dots = {name: ax.plot([xs[0]], [values[0]], "o", ms=6, mfc="white",
                          mec=f"C{k}" if len(curves) > 1 else "C0", mew=1.8, zorder=6,
                          gid=f"cursor:{name}")[0]
            for k, (name, values) in enumerate(curves.items())}

    def cursor(k: int) -> None:
        line.set_xdata([xs[k], xs[k]])
        for name, dot in dots.items():
            dot.set_data([xs[k]], [curves[name][k]])

    return cursor
