"""linkage_fmu.plot.animation and ``linkage-fmu animate``: the frames written, the crank
drawn at each frame's angle, the forces to one scale, the cursor on the curve, the
labels apart, and the errors.

References: the frames' angles are the documented ``360 / frames`` steps (arithmetic),
the crank's drawn angle is ``atan2`` of its drawn ends, the arrows and the curves are
``mech.solve`` at the same angle (1e-9 relative: the array solve against the scalar
one), the range of a crank that cannot turn is the four-bar's closed-form limit (the
law of cosines, to 1e-7 deg: the range's ends are found to 1e-9 rad), the singular
positions of a parallelogram four-bar are 0 and 180 deg (its links fold onto the line of
centres), and the GIF is read back with pillow.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.animation import FFMpegWriter  # noqa: E402
from PIL import Image  # noqa: E402

from linkage_fmu import plot, presets  # noqa: E402
from linkage_fmu.cli import main  # noqa: E402
from linkage_fmu.plot.animation import COND_BOUND, motion_range  # noqa: E402
from test_plot import (  # noqa: E402
    arrows_and_arcs,
    covered,
    label_boxes,
    link_lines,
    outside,
    overlaps,
)

SMALL = dict(figsize=(5.5, 2.4), dpi=30)  # fast where the pixels are not what is tested


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def gif_frames(path) -> list[np.ndarray]:
    """Every frame of the GIF at ``path`` as pillow composes it, RGB."""
    with Image.open(path) as im:
        out = []
        for k in range(im.n_frames):
            im.seek(k)
            out.append(np.asarray(im.convert("RGB")))
    return out


def artist(ax, gid: str):
    """The one line, patch or collection of ``ax`` with this gid."""
    (found,) = [a for a in ax.get_children() if a.get_gid() == gid]
    return found


def crank_angle(anim, mech) -> float:
    """The angle [deg] of the crank as drawn: its line from the pivot to the crank pin
    (the line's end that is not at the pivot)."""
    xy = np.c_[artist(anim.figure.axes[0], f"link:{mech.groups[0].link}").get_data()]
    pivot = np.array(mech.frame_points[mech.crank.pivot])
    at_pivot = np.all(np.isclose(xy, pivot, rtol=0, atol=1e-12), axis=1)
    assert xy.shape == (2, 2) and at_pivot.sum() == 1
    (dx, dy), = xy[~at_pivot] - pivot
    return math.degrees(math.atan2(dy, dx))


def test_cli_default_writes_72_differing_frames(tmp_path, capsys):
    """``linkage-fmu animate four_bar -o four_bar.gif`` writes
    at least 36 frames (72 by default, read back with pillow; small pixels here), each
    different from the one before (pillow would merge equal ones, and they are
    compared here pixel by pixel), and says what it wrote."""
    out = tmp_path / "four_bar.gif"
    assert main(["animate", "four_bar", "-o", str(out), "--dpi", "20"]) == 0
    frames = gif_frames(out)
    assert len(frames) == 72 >= 36
    for a, b in zip(frames, frames[1:] + frames[:1]):
        assert a.shape == b.shape and np.any(a != b)
    assert capsys.readouterr().err.strip() == f"wrote {out} (72 frames)"


@pytest.mark.parametrize("name, frames", [("four_bar", 8), ("slider_crank", 7)])
def test_the_crank_turns_360_over_frames_degrees_a_frame(name, frames):
    """Over a revolution the drawn crank (its line from the pivot to the pin) is at
    ``k * 360 / frames`` degrees in frame ``k``, so it moves by ``360 / frames`` between
    frames, and the last frame is one step short of the first (the loop closes)."""
    mech = presets.get(name)
    anim = plot.animate(mech, frames=frames, **SMALL)
    assert len(anim) == frames
    drawn = []
    for k in range(frames):
        anim.draw(k)
        drawn.append(crank_angle(anim, mech))
    step = np.diff(np.unwrap(np.radians(drawn + drawn[:1])))
    np.testing.assert_allclose(np.degrees(step), 360.0 / frames, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.array(drawn) % 360.0, 360.0 * np.arange(frames) / frames,
                               rtol=0, atol=1e-9)


def test_arrows_are_the_solved_forces_to_one_scale_and_the_cursor_is_on_the_curve():
    """At every frame the force arrows are ``mech.solve`` at the frame's angle times
    the animation's one scale (the largest force over all frames 0.4 of the linkage's
    extent; compared at each frame, so a per-frame scale would fail), and the cursor
    is at the frame's angle with a point on each force magnitude's curve at the
    solved value."""
    mech = presets.get("four_bar")
    anim = plot.animate(mech, frames=6, omega=12.0, load=3.0, **SMALL)
    link_ax, curve_ax = anim.figure.axes
    solved = mech.solve(np.radians(anim.theta_deg), omega=12.0, load=3.0)
    pairs = plot.force_pairs(mech)
    largest = max(np.max(np.hypot(solved[p.x], solved[p.y])) for p in pairs)
    points = np.array([[mech.kinematics(math.radians(d), order=0).p[p] for p in "ABCD"]
                       for d in anim.theta_deg]).reshape(-1, 2)
    size = np.max(points.max(axis=0) - points.min(axis=0))
    assert anim.scale == pytest.approx(0.4 * size / largest, rel=1e-9)
    for k, deg in enumerate(anim.theta_deg):
        anim.draw(k)
        quiver = artist(link_ax, "forces")
        sol = mech.solve(math.radians(deg), omega=12.0, load=3.0)
        np.testing.assert_allclose(quiver.U, [anim.scale * sol[p.x] for p in pairs],
                                   rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(quiver.V, [anim.scale * sol[p.y] for p in pairs],
                                   rtol=1e-9, atol=1e-12)
        assert list(artist(curve_ax, "cursor").get_xdata()) == [deg, deg]
        for p in pairs:
            x, y = artist(curve_ax, f"cursor:|{p.name}|").get_data()
            assert x[0] == deg
            assert y[0] == pytest.approx(math.hypot(sol[p.x], sol[p.y]), rel=1e-9)


@pytest.mark.parametrize("what, names", [("torque", ["Mb"]),
                                         ("shaking", ["shake_x", "shake_y", "|shake|"])])
def test_the_curve_is_the_solved_output_over_the_motion(what, names):
    """``what="torque"`` draws the balancing moment, ``"shaking"`` the shaking force's
    components and magnitude, over the revolution: the solver's values at the curve's
    angles."""
    mech = presets.get("slider_crank")
    anim = plot.animate(mech, frames=4, what=what, omega=100.0, load=50.0, **SMALL)
    curve_ax = anim.figure.axes[1]
    for name in names:
        x, y = artist(curve_ax, name).get_data()
        assert x[0] == 0.0 and x[-1] == 360.0
        sol = mech.solve(np.radians(x), omega=100.0, load=50.0)
        expected = (np.hypot(sol["shake_x"], sol["shake_y"]) if name == "|shake|" else
                    sol[name])
        np.testing.assert_allclose(y, expected, rtol=1e-9, atol=1e-9 * np.max(np.abs(expected)))


def test_an_engine_turns_over_its_cycle_of_two_revolutions():
    """examples/engine.toml's gas force is a table over period_deg = 720 (a four-stroke
    cycle, read from the file here): the frames go round twice, 720 / frames degrees
    apart, the crank drawn at each angle modulo 360, the curve over 0..720 deg; with the
    gas force given a value, one revolution."""
    import tomllib
    from pathlib import Path

    import linkage_fmu

    path = Path(__file__).parents[1] / "examples" / "engine.toml"
    (gas,) = tomllib.loads(path.read_text())["loads"]
    assert gas["period_deg"] == 720
    mech = linkage_fmu.load(path)
    anim = plot.animate(mech, frames=8, what="torque", **SMALL)
    np.testing.assert_array_equal(anim.theta_deg, 90.0 * np.arange(8))
    for k in (1, 5):
        anim.draw(k)
        assert crank_angle(anim, mech) % 360.0 == pytest.approx(anim.theta_deg[k] % 360.0,
                                                                abs=1e-9)
    x = artist(anim.figure.axes[1], "Mb").get_xdata()
    assert (x[0], x[-1], x.size) == (0.0, 720.0, 1441)
    steady = plot.animate(mech, frames=8, F_gas=1000.0, **SMALL)
    np.testing.assert_array_equal(steady.theta_deg, 45.0 * np.arange(8))


def rocker_limit(l_ab, l_ad, reach) -> float:
    """The crank angle [deg] where the distance from the crank pin B to the rocker's
    pivot D is ``reach`` (law of cosines)."""
    return math.degrees(math.acos((l_ab ** 2 + l_ad ** 2 - reach ** 2) / (2 * l_ab * l_ad)))


def test_a_crank_that_cannot_turn_goes_out_and_back_over_its_range():
    """The four-bar with a 0.3 m crank assembles while the distance from the crank pin
    B to the rocker's pivot D is at most l_BC + l_CD: for |theta| <= acos((l_AB^2 +
    l_AD^2 - (l_BC + l_CD)^2) / (2 l_AB l_AD)) (law of cosines), a range across 0. Its
    forces grow without bound only at the very ends (cond passes COND_BOUND within
    0.05 deg of them), so the motion is the range less at most 0.05 deg. The frames go
    from one end to the other and back, a constant step of 2 * (range) / frames
    degrees (also from the last frame to the first: the loop closes without a jump),
    and the crank is drawn at each frame's angle; an odd number of frames is refused
    (no constant step reaches both ends)."""
    mech = presets.get("four_bar", l_AB=0.3)
    p = mech.parameters
    limit = rocker_limit(p["l_AB"], p["l_AD"], p["l_BC"] + p["l_CD"])
    lo, hi, full = motion_range(mech)
    assert not full
    assert -limit < lo < -limit + 0.05 and limit - 0.05 < hi < limit
    anim = plot.animate(mech, frames=8, what="torque", **SMALL)
    expected = lo + (hi - lo) * np.array([0, 1, 2, 3, 4, 3, 2, 1]) / 4
    np.testing.assert_allclose(anim.theta_deg, expected, rtol=0, atol=1e-9)
    drawn = []
    for k in range(8):
        anim.draw(k)
        drawn.append(crank_angle(anim, mech))
    np.testing.assert_allclose(drawn, anim.theta_deg, rtol=0, atol=1e-9)
    steps = np.abs(np.diff(drawn + drawn[:1]))
    np.testing.assert_allclose(steps, 2 * (hi - lo) / 8, rtol=0, atol=1e-9)
    x = artist(anim.figure.axes[1], "Mb").get_xdata()
    assert (x[0], x[-1]) == pytest.approx((lo, hi), abs=1e-12)
    with pytest.raises(ValueError, match="frames must be even for four_bar, whose crank "
                                         "cannot turn a revolution.*got 9"):
        plot.animate(mech, frames=9, **SMALL)


def test_the_range_is_trimmed_by_the_forces_not_by_a_fraction():
    """The reviewer's case l_AB = l_CD = 0.1, l_BC = 0.4000001, l_AD = 0.4: almost a
    parallelogram, it assembles except within 0.07 deg of 0 (where B to D is below
    l_BC - l_CD: law of cosines), and its forces grow without bound toward those ends.
    The motion stops where cond reaches COND_BOUND: inside the assembly range, less
    than 2 deg from each end (a 2 % trim took 14 deg), cond below the bound at both
    ends and above it 0.05 deg beyond them."""
    mech = presets.get("four_bar", l_AB=0.1, l_CD=0.1, l_BC=0.4000001, l_AD=0.4)
    edge = rocker_limit(0.1, 0.4, 0.4000001 - 0.1)
    assert 0.05 < edge < 0.1
    lo, hi, full = motion_range(mech)
    assert not full
    assert edge < lo < edge + 2.0 and 360.0 - edge - 2.0 < hi < 360.0 - edge
    cond = mech.solve(np.radians([lo, hi, lo - 0.05, hi + 0.05]))["cond"]
    assert cond[0] < COND_BOUND and cond[1] < COND_BOUND
    assert cond[2] >= COND_BOUND and cond[3] >= COND_BOUND


PARALLELOGRAM = ["--set", "l_AB=0.1", "--set", "l_CD=0.1", "--set", "l_BC=0.4", "--set",
                 "l_AD=0.4"]


def test_a_singular_position_inside_the_motion_is_left_out_and_said(tmp_path, capsys):
    """The parallelogram four-bar (l_AB = l_CD, l_BC = l_AD) turns round but is
    singular at 0 and 180 deg, where the solve gives forces of 1e99 N with a solved
    status: those frames draw no force arrows, the arrows' scale is 0.4 of the
    linkage's extent over the largest force of the other frames (mech.solve), the
    curve's limits hold the other frames' values (not 1e99), and a UserWarning names
    the two angles; the command line prints it as one line and writes the file."""
    mech = presets.get("four_bar", l_AB=0.1, l_CD=0.1, l_BC=0.4, l_AD=0.4)
    with pytest.warns(UserWarning, match=r"no bound .* at theta = 0, 180 deg"):
        anim = plot.animate(mech, frames=8, **SMALL)
    good = [d for d in anim.theta_deg if d % 180.0 != 0.0]
    assert len(good) == 6
    sol = mech.solve(np.radians(good))
    pairs = plot.force_pairs(mech)
    largest = max(np.max(np.hypot(sol[p.x], sol[p.y])) for p in pairs)
    assert largest < 1e3
    points = np.array([[mech.kinematics(math.radians(d), order=0).p[p] for p in "ABCD"]
                       for d in anim.theta_deg]).reshape(-1, 2)
    size = np.max(points.max(axis=0) - points.min(axis=0))
    assert anim.scale == pytest.approx(0.4 * size / largest, rel=1e-9)
    for k in (0, 4):
        anim.draw(k)
        assert np.size(artist(anim.figure.axes[0], "forces").U) == 0
    anim.draw(1)
    assert np.size(artist(anim.figure.axes[0], "forces").U) == len(pairs)
    bottom, top = anim.figure.axes[1].get_ylim()
    assert largest <= top < 2.0 * largest and bottom <= 0.0

    out = tmp_path / "p.gif"
    assert main(["animate", "four_bar", *PARALLELOGRAM, "--frames", "8", "-o", str(out)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and err[1] == f"wrote {out} (8 frames)", err
    assert err[0].startswith("linkage-fmu: warning: four_bar: the forces have no bound")
    assert "theta = 0, 180 deg" in err[0]
    assert len(gif_frames(out)) == 8


def test_a_zero_load_is_not_drawn():
    """The four-bar's moment on the rocker is 0 by default: no arc, no head and no
    "load = 0" label in any frame; given 2 N.m it is drawn with its label."""
    mech = presets.get("four_bar")
    anim = plot.animate(mech, frames=4, **SMALL)
    for k in range(4):
        anim.draw(k)
        gids = [a.get_gid() or "" for a in anim.figure.axes[0].get_children()]
        assert not [g for g in gids if "load" in g], gids
    anim = plot.animate(mech, frames=4, load=2.0, **SMALL)
    anim.draw(1)
    gids = {a.get_gid() for a in anim.figure.axes[0].get_children()}
    assert {"load:load", "load head:load", "load label:load"} <= gids


@pytest.mark.parametrize("name, inputs", [
    ("four_bar", {}), ("four_bar", {"load": 2.0}),
    ("slider_crank", {"omega": 150.0, "load": 300.0}),
    ("six_bar", {}), ("six_bar", {"omega": 10.0}),
    ("crank_shaper", {}), ("scotch_yoke", {}), ("slotted_lever", {}),
], ids=["four_bar", "four_bar-load", "slider_crank", "six_bar", "six_bar-omega",
        "crank_shaper", "scotch_yoke", "slotted_lever"])
def test_labels_do_not_overlap_on_the_frames(name, inputs):
    """At every other frame of 36 (the forces to the animation's one scale, the view
    fixed) at the 80 dpi a GIF is written at by default, and at two frames at the
    figure's 100 dpi: no two labels of the linkage overlap as drawn, nor the scale's
    key; no label's box meets an arrow, an arc or a link's line (a bar's line, a
    plate's edges, with its width), as test_plot checks the picture; and every label
    lies inside the linkage's axes."""
    mech = presets.get(name)
    anim = plot.animate(mech, frames=36, **inputs)
    for k, dpi in [(k, 80) for k in range(0, 36, 2)] + [(3, 100), (21, 100)]:
        anim.draw(k)
        anim.figure.set_dpi(dpi)
        boxes = label_boxes(anim.figure)
        assert len(boxes) >= len(plot.force_pairs(mech)) + 3
        assert not overlaps(boxes), (k, dpi, overlaps(boxes))
        marks = arrows_and_arcs(anim.figure) + link_lines(anim.figure)
        assert not covered(boxes, marks), (k, dpi, covered(boxes, marks))
        assert not outside(boxes, anim.figure), (k, dpi, outside(boxes, anim.figure))


def test_the_peak_label_lies_inside_the_curves_axes_on_every_frame():
    """The four-bar's torque curve peaks at 308.5 deg, near the right end of its axes:
    its label (the value and its angle) is placed on the side of the peak with room, so
    that at every frame, at the 72 dpi of the documentation's GIF and the 80 dpi a GIF
    is written at by default, its box lies inside the curve's axes, and so inside the
    figure (it ran 28 px past the axes, to 2 px from the figure's edge at 72 dpi)."""
    anim = plot.animate(presets.get("four_bar"), frames=36, what="torque")
    fig, curve_ax = anim.figure, anim.figure.axes[1]
    (label,) = [t for t in curve_ax.texts if t.get_gid() == "peak label"]
    assert label.get_text().endswith("at θ = 308.5°")
    for dpi in (72, 80):
        fig.set_dpi(dpi)
        for k in range(len(anim)):
            anim.draw(k)
            fig.canvas.draw()
            box = label.get_window_extent(fig.canvas.get_renderer())
            x0, y0, x1, y1 = curve_ax.bbox.extents
            assert x0 <= box.x0 and box.x1 <= x1 and y0 <= box.y0 and box.y1 <= y1, (dpi, k)
            assert fig.bbox.contains(box.x0, box.y0) and fig.bbox.contains(box.x1, box.y1)


@pytest.mark.parametrize("name, share, crowded", [
    ("four_bar", 0.22, 0.05), ("six_bar", 0.18, 0.08), ("crank_shaper", 0.25, 0.09)])
def test_the_linkage_fills_its_panel_and_its_labels_have_room(name, share, crowded):
    """The linkage's axes, drawn to equal scales, fill the cell the layout gives them
    (the view widened to the cell's shape, the width shared between the two panels by
    the view's shape), so that their share of the 11 x 4.8 inch figure is at least
    ``share`` (it was 0.20 for the four-bar, the documentation's GIF, 0.09 for the tall
    six-bar, 0.21 for the crank shaper); and the labels of the linkage cover at most
    ``crowded`` of them at every other frame of 36 (0.049, 0.148 and 0.108 before)."""
    anim = plot.animate(presets.get(name), frames=36)
    fig, link_ax = anim.figure, anim.figure.axes[0]
    fig.set_dpi(80)
    for k in range(0, 36, 2):
        anim.draw(k)
        boxes = label_boxes(fig)  # draws the canvas
        drawn, cell = link_ax.get_window_extent(), link_ax.get_position(original=True)
        cell = cell.transformed(fig.transFigure)
        assert drawn.width >= 0.99 * cell.width and drawn.height >= 0.99 * cell.height, k
        assert drawn.width * drawn.height >= share * fig.bbox.width * fig.bbox.height, k
        area = sum(box.width * box.height for _, _, box, _ in boxes)
        assert area <= crowded * drawn.width * drawn.height, k


def test_gif_written_by_the_library(tmp_path):
    """``animate(mech, path)`` writes the GIF, one frame per frame asked for."""
    out = tmp_path / "yoke.gif"
    anim = plot.animate(presets.get("scotch_yoke"), out, frames=5, **SMALL)
    assert len(gif_frames(out)) == len(anim) == 5


def without_ffmpeg(monkeypatch):
    monkeypatch.setattr(FFMpegWriter, "isAvailable", classmethod(lambda cls: False))


def test_mp4_without_ffmpeg_says_what_is_missing(tmp_path, monkeypatch, capsys):
    """Without ffmpeg, an MP4 is refused before any work, saying what is missing, how
    to get it and that a GIF needs nothing more: a RuntimeError from the library, one
    line and status 2 from the command line (no traceback); no file is written."""
    without_ffmpeg(monkeypatch)
    out = tmp_path / "four_bar.mp4"
    with pytest.raises(RuntimeError, match=r"four_bar.mp4: writing an MP4 needs ffmpeg.*"
                                           r"install it.*\.gif"):
        plot.animate(presets.get("four_bar"), out, frames=3)
    assert main(["animate", "four_bar", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"linkage-fmu: -o {out}: writing an MP4 needs ffmpeg")
    assert "apt install ffmpeg" in err and ".gif" in err
    assert not out.exists()


@pytest.mark.skipif(not FFMpegWriter.isAvailable(), reason="ffmpeg is not installed")
def test_mp4_with_ffmpeg(tmp_path):  # pragma: no cover - where ffmpeg is installed
    out = tmp_path / "four_bar.mp4"
    plot.animate(presets.get("four_bar"), out, frames=4, **SMALL)
    assert out.read_bytes()[4:8] == b"ftyp"  # an MP4 (ISO base media) file


@pytest.mark.parametrize("kwargs, message", [
    ({"frames": 1}, "frames must be a whole number >= 2, got 1"),
    ({"frames": 2.5}, "frames must be a whole number >= 2, got 2.5"),
    ({"what": "polar"}, "what='polar': expected one of forces, torque, shaking"),
    ({"path": "x.avi"}, "x.avi: an animation is written to a .gif or .mp4 file, not .avi"),
    ({"path": "{tmp}/no/x.gif"}, "{tmp}/no/x.gif: there is no folder {tmp}/no"),
    ({"dpi": 0}, "dpi must be a finite number > 0, got 0"),
    ({"dpi": float("nan")}, "dpi must be a finite number > 0, got nan"),
    ({"dpi": "80"}, "dpi must be a finite number > 0, got '80'"),
    ({"figsize": (0, 0)}, "figsize must be each of (width, height) in inches, got (0, 0)"),
    ({"figsize": (5.0, float("inf"))},
     "figsize must be each of (width, height) in inches, got (5.0, inf)"),
    ({"figsize": 5.0}, "figsize must be (width, height) in inches, got 5.0"),
])
def test_library_errors(kwargs, message, tmp_path, monkeypatch):
    """Each bad argument: a ValueError naming it and why, before any work (the linkage
    is not solved)."""
    import linkage_fmu.plot.animation as animation

    kwargs = {k: v.format(tmp=tmp_path) if isinstance(v, str) and k == "path" else v
              for k, v in kwargs.items()}
    message = message.format(tmp=tmp_path)

    def no_work(*args, **kwargs):
        raise AssertionError("the linkage was solved before the arguments were checked")

    monkeypatch.setattr(animation, "scenes", no_work)
    monkeypatch.setattr(animation, "frame_angles", no_work)
    with pytest.raises(ValueError, match=re.escape(message)):
        plot.animate(presets.get("four_bar"), **kwargs)


@pytest.mark.parametrize("args, message", [
    (["-o", "{tmp}/x.avi"], "-o {tmp}/x.avi: the file must end in .gif or .mp4"),
    (["-o", "{tmp}/x.gif", "--frames", "1"], "--frames must be >= 2, got 1"),
    (["-o", "{tmp}/x.gif", "--what", "polar"],
     "--what polar: expected one of forces, torque, shaking"),
    (["-o", "{tmp}/x.gif", "--fps", "0"], "--fps must be a number > 0, got 0"),
    (["-o", "{tmp}/no/x.gif"], "-o {tmp}/no/x.gif: there is no folder {tmp}/no"),
    (["-o", "{tmp}/x.gif", "--set", "l_AB=3"], "cannot be assembled at any crank angle"),
])
def test_cli_errors(tmp_path, capsys, args, message):
    """Each bad input: status 2 and one line naming it and why; nothing written."""
    argv = ["animate", "four_bar"] + [a.format(tmp=tmp_path) for a in args]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message.format(tmp=tmp_path) in err, err
    assert not list(tmp_path.rglob("x.*"))


def test_cli_other_runtime_errors_are_not_called_an_output_error(monkeypatch):
    """Only ffmpeg missing is an ``-o`` error: another RuntimeError inside the work (a
    bug) is raised as it is, not turned into "linkage-fmu: -o ..." with status 2."""
    import linkage_fmu.plot.animation as animation

    def broken(*args, **kwargs):
        raise RuntimeError("the solver broke")

    monkeypatch.setattr(animation, "animate", broken)
    with pytest.raises(RuntimeError, match="the solver broke"):
        main(["animate", "four_bar", "-o", "x.gif"])


def test_a_linkage_driven_by_time_moves_over_its_motion(tmp_path):
    """The excavator over a motion of its cylinders (arrays over the times, one a
    function of the time): a frame per time, each frame's arrows the forces of solve at
    that time's inputs, the curves each driver's effort against the time with the
    cursor at the frame's; what it cannot take is refused with the reason."""
    from pathlib import Path

    import linkage_fmu

    mech = linkage_fmu.load(Path(__file__).resolve().parents[1] / "examples" /
                            "excavator.toml")
    t = np.linspace(0.0, 2.0, 6)
    motion = {"s_cyl1": 0.1 * t, "v_cyl1": np.full(6, 0.1), "s_cyl3": lambda x: -0.05 * x,
              "v_cyl3": lambda x: np.full_like(x, -0.05)}
    anim = plot.animate(mech, tmp_path / "dig.gif", what="efforts", t=t, motion=motion,
                        F_T=15000.0)
    assert len(anim) == 6 and anim.t.tolist() == t.tolist()
    assert (tmp_path / "dig.gif").stat().st_size > 0
    sol = mech.solve(s_cyl1=0.1 * t, v_cyl1=0.1, s_cyl2=0.0, s_cyl3=-0.05 * t,
                     v_cyl3=-0.05, F_T=15000.0)
    curve_ax = anim.figure.axes[1]
    for name in ("Fb_cyl1", "Fb_cyl2", "Fb_cyl3"):
        (line,) = [a for a in curve_ax.lines if a.get_gid() == name]
        np.testing.assert_allclose(line.get_ydata(), sol[name], rtol=1e-12)
    anim.draw(3)
    cursor = next(a for a in curve_ax.lines if a.get_gid() == "cursor")
    assert float(cursor.get_xdata()[0]) == t[3]
    forces = next(c for c in anim.figure.axes[0].collections if c.get_gid() == "forces")
    pair = plot.force_pairs(mech)[0]
    assert forces.U[0] == pytest.approx(anim.scale * sol[pair.x][3], rel=1e-12)
    assert "t = 1.2 s, s_cyl1 = 0.12 m" in anim.figure.axes[0].get_title()
    for kwargs, message in [
        ({}, "excavator is driven by time: animate it over a motion, t (the frames' times)"),
        ({"t": t, "motion": {"theta": t}}, "motion: theta: no input of excavator"),
        ({"t": t, "motion": motion, "what": "torque"}, "what='torque': expected one of "
                                                       "forces, efforts, shaking"),
        ({"t": [0.0, 0.0], "motion": motion}, "t must hold at least 2 times, strictly"),
    ]:
        with pytest.raises(linkage_fmu.errors.InputError, match=re.escape(message)):
            plot.animate(mech, **kwargs)
