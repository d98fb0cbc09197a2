"""linkage_fmu.plot.animation and ``linkage-fmu animate``: the frames written, the crank
drawn at each frame's angle, the forces to one scale, the cursor on the curve, the
labels apart, and the errors.

References: the frames' angles are the documented ``360 / frames`` steps (arithmetic),
the crank's drawn angle is ``atan2`` of its drawn ends, the arrows and the curves are
``mech.solve`` at the same angle (1e-9 relative: the array solve against the scalar
one), the range of a crank that cannot turn is the four-bar's closed-form limit (the
law of cosines, to 1e-7 deg: the range's ends are found to 1e-9 rad), and the GIF is read
back with pillow.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.animation import FFMpegWriter  # noqa: E402
from PIL import Image  # noqa: E402

from linkage_fmu import plot, presets  # noqa: E402
from linkage_fmu.cli import main  # noqa: E402
from linkage_fmu.plot.animation import EDGE_FRACTION, motion_range  # noqa: E402
from test_plot import arrows_and_arcs, covered, label_boxes, overlaps  # noqa: E402

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
    """The issue's "done when": ``linkage-fmu animate four_bar -o four_bar.gif`` writes
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


def test_a_crank_that_cannot_turn_moves_over_its_range():
    """The four-bar with a 0.3 m crank assembles while the distance from the crank pin
    B to the rocker's pivot D is at most l_BC + l_CD: for |theta| <= acos((l_AB^2 +
    l_AD^2 - (l_BC + l_CD)^2) / (2 l_AB l_AD)) (law of cosines), a range across 0. The
    frames go from one end of it to the other, less EDGE_FRACTION of it at each end
    (the toggles, where the forces have no bound), evenly, and the crank is drawn at
    each frame's angle."""
    mech = presets.get("four_bar", l_AB=0.3)
    p = mech.parameters
    limit = math.degrees(math.acos((p["l_AB"] ** 2 + p["l_AD"] ** 2 - (p["l_BC"] + p["l_CD"])
                                    ** 2) / (2 * p["l_AB"] * p["l_AD"])))
    edge = EDGE_FRACTION * 2 * limit
    lo, hi, full = motion_range(mech)
    assert not full
    assert (lo, hi) == pytest.approx((-limit + edge, limit - edge), abs=1e-7)
    anim = plot.animate(mech, frames=9, what="torque", **SMALL)
    np.testing.assert_allclose(anim.theta_deg, np.linspace(lo, hi, 9), rtol=0, atol=1e-12)
    for k in (0, 4, 8):
        anim.draw(k)
        assert crank_angle(anim, mech) == pytest.approx(anim.theta_deg[k], abs=1e-9)
    x = artist(anim.figure.axes[1], "Mb").get_xdata()
    assert (x[0], x[-1]) == pytest.approx((lo, hi), abs=1e-12)


@pytest.mark.parametrize("name, params, inputs", [
    ("four_bar", {}, {"load": 2.0}),
    ("slider_crank", {}, {"omega": 150.0, "load": 300.0}),
    ("six_bar", {}, {"omega": 10.0}),
    ("crank_shaper", {}, {}),
], ids=["four_bar", "slider_crank", "six_bar", "crank_shaper"])
def test_labels_do_not_overlap_on_the_frames(name, params, inputs):
    """At sampled frames (the forces to the animation's one scale, the view fixed), no
    two labels of the linkage overlap as drawn, nor the scale's key, and no label's box
    meets an arrow or an arc, as test_plot checks the picture; at the figure's 100 dpi
    and at the 80 dpi a GIF is written at by default."""
    mech = presets.get(name, **params)
    anim = plot.animate(mech, frames=12, **inputs)
    for k, dpi in ((0, 100), (2, 80), (5, 100), (7, 80), (10, 100)):
        anim.draw(k)
        anim.figure.set_dpi(dpi)
        boxes = label_boxes(anim.figure)
        assert len(boxes) >= len(plot.force_pairs(mech)) + 3
        assert not overlaps(boxes), (k, dpi, overlaps(boxes))
        marks = arrows_and_arcs(anim.figure)
        assert not covered(boxes, marks), (k, dpi, covered(boxes, marks))


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
])
def test_library_errors(kwargs, message, tmp_path):
    """Each bad argument: a ValueError naming it and why, before any work."""
    kwargs = {k: v.format(tmp=tmp_path) if isinstance(v, str) else v for k, v in kwargs.items()}
    message = message.format(tmp=tmp_path)
    with pytest.raises(ValueError, match=message.replace(".", r"\.").replace("(", r"\(")):
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
