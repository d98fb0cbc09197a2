"""Where to put the balancing effort (the six-bar coursework's task 2): the six-bar's five
places against solving it with each ``driver`` value, the places of any linkage against
virtual work, the power against the virtual power, the refusals and the command."""

from __future__ import annotations

import io
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import linkage_fmu
from linkage_fmu import Mechanism, presets
from linkage_fmu.cli import main
from linkage_fmu.effort_places import effort_places, places, recommend
from linkage_fmu.errors import InputError
from linkage_fmu.loads import powers

ROOT = Path(__file__).resolve().parents[1]
#: a revolution, 360 angles (2 pi left out: it is 0)
REVOLUTION = np.linspace(0.0, 2.0 * np.pi, 360, endpoint=False)
#: the six-bar's places: the values of its choice parameter ``driver``, and its effort
SIX_BAR = {"OA": "Mb", "AB": "Mb", "O1B": "Mb", "KD": "Mb", "D": "Pb"}
#: the six-bar's outputs of each pair's reaction (by the seed's names)
SIX_BAR_PAIRS = {"O": ("XO", "YO"), "A": ("XA", "YA"), "B": ("XB", "YB"),
                 "O1": ("XO1", "YO1"), "K": ("XK", "YK"), "D": ("XD", "YD"), "guide": ("N4",)}


def magnitude(sol, names: tuple) -> np.ndarray:
    return np.hypot(sol[names[0]], sol[names[1]]) if len(names) == 2 else np.abs(sol[names[0]])


@pytest.mark.parametrize("omega, alpha", [(0.0, 0.0), (3.0, 2.0)], ids=["static", "dynamic"])
def test_six_bar_places_are_solving_it_with_each_driver(omega, alpha):
    """Named reference: ``presets.get("six_bar", driver=X).solve`` over a revolution, for
    each of the five places X: the peak and rms of its effort, the peak reaction of each
    pair (|(X, Y)| of a pin, |N4| of the guide) and the largest of them, to 1e-12
    relative; the slider, which only translates, takes no moment: no place of it."""
    table = effort_places(presets.get("six_bar"), REVOLUTION, omega, alpha, load=100.0)
    assert list(table.index) == [*SIX_BAR]
    for place, effort in SIX_BAR.items():
        ref = presets.get("six_bar", driver=place).solve(REVOLUTION, omega, alpha, load=100.0)
        row = table.loc[place]
        assert (row["effort"], row["unit"], row["reason"]) == (
            effort, "N" if effort == "Pb" else "N.m", "")
        np.testing.assert_allclose(row["peak"], np.max(np.abs(ref[effort])), rtol=1e-12)
        np.testing.assert_allclose(row["rms"], np.sqrt(np.mean(ref[effort] ** 2)), rtol=1e-12)
        peaks = {p: np.max(magnitude(ref, names)) for p, names in SIX_BAR_PAIRS.items()}
        for pair, value in peaks.items():
            np.testing.assert_allclose(row[f"peak_{pair}"], value, rtol=1e-12)
        np.testing.assert_allclose(row["peak_reaction"], max(peaks.values()), rtol=1e-12)


def test_six_bar_figures_at_the_default_parameters():
    """The figures of the static six-bar over a revolution (360 angles) this package
    computes, their reference the test above: the peak effort of each place with a 100
    N load on the slider, and the recommended place, the crank, whose peak reaction (in
    O1, 451.27 N) is the lowest. The force at D acts where the load does, along the
    same line: it is the unloaded one less the load (29087.65 N without it)."""
    table = effort_places(presets.get("six_bar"), REVOLUTION, load=100.0)
    expected = {"OA": 44.715680609, "AB": 21276.182512, "O1B": 776.39695249,
                "KD": 2679.2859503, "D": 28987.651394}
    for place, peak in expected.items():
        np.testing.assert_allclose(table.loc[place, "peak"], peak, rtol=1e-9)
    unloaded = effort_places(presets.get("six_bar"), REVOLUTION)
    np.testing.assert_allclose(table.loc["D", "peak"], unloaded.loc["D", "peak"] - 100.0,
                               rtol=1e-12)
    place, why = recommend(table)
    assert place == "OA"
    assert why.startswith("OA: the lowest peak reaction in the pairs, 451.3 N (in pair O1). "
                          "Peak effort and peak power by place: OA 44.72 N.m, 0 W; AB "
                          "2.128e+04 N.m, 0 W; O1B 776.4 N.m, 0 W; KD 2679 N.m, 0 W; D "
                          "2.899e+04 N, 0 W.")
    np.testing.assert_allclose(table.loc["OA", "peak_reaction"], 451.27243533, rtol=1e-9)
    effort = places(presets.get("six_bar"))["D"].effort
    assert (effort.name, effort.body, effort.point) == ("Pb", "slider", "D")
    np.testing.assert_allclose(effort.direction, (0.0, 1.0), atol=0.0)


def virtual_work(mech, place, theta, load: float) -> np.ndarray:
    """The effort of ``place`` by virtual work in a static scene: effort times its speed
    per unit crank speed plus the power of the weights and the load per unit crank speed
    (:func:`linkage_fmu.loads.powers`) is zero."""
    st = mech.kinematics(theta, order=1)
    _, gravity, loaded = powers(mech, st, 0.0, 0.0, (load,), static=True)
    e = place.effort
    if e.direction is None:
        speed = st.w1[e.body]
    else:  # a slider translates: every point has the velocity of its pin
        speed = st.d1[e.point][0] * e.direction[0] + st.d1[e.point][1] * e.direction[1]
    return -(gravity + loaded) / speed


@pytest.mark.parametrize("name, load", [("four_bar", 2.0), ("slider_crank", 50.0)])
def test_places_of_a_linkage_without_choices_by_virtual_work(name, load):
    """Independent reference: virtual work, ``M_k w1_k + (power of the loads and weights
    per unit crank speed) = 0`` for a moment on link k (``w1_k = dphi_k/dtheta``), and the
    same with the slider's speed along its guide for a force at the piston: the peak over
    a revolution (shifted off the dead centres, where the coupler of the slider-crank stops
    turning and the piston stops) to 1e-9 relative, and each angle's |effort| alone."""
    mech = presets.get(name)
    theta = REVOLUTION + 0.01
    table = effort_places(mech, theta, 0.0, 0.0, load=load)
    built = places(mech)
    expected = ["moment on 1", "moment on 2"] + (  # the piston does not turn
        ["force at 3"] if name == "slider_crank" else ["moment on 3"])
    assert list(table.index) == expected
    for place, m in built.items():
        assert table.loc[place, "reason"] == ""
        ref = virtual_work(mech, m, theta, load)
        np.testing.assert_allclose(table.loc[place, "peak"], np.max(np.abs(ref)), rtol=1e-9)
        for k in (0, 97, 211):
            one = effort_places(mech, theta[k:k + 1], 0.0, 0.0, load=load)
            np.testing.assert_allclose(one.loc[place, "peak"], abs(ref[k]), rtol=1e-9)
    # the place of the description's own effort is solving the linkage as it is
    ref = mech.solve(theta, 0.0, 0.0, load=load)
    np.testing.assert_allclose(table.loc["moment on 1", "peak"], np.max(np.abs(ref["Mb"])),
                               rtol=1e-12)
    force = built["force at 3"].effort if name == "slider_crank" else None
    if force is not None:  # along the guide's sliding direction, +x for gamma = 0
        np.testing.assert_allclose(force.direction, (1.0, 0.0), atol=1e-16)


def test_power_of_the_crank_place_and_the_virtual_power():
    """Dynamic six-bar (omega = 3 rad/s, alpha = 2 rad/s2, a 100 N load): the crank's
    peak and mean power are those of ``Mb * omega`` from solving it; and at every place
    the effort's power is the virtual power, ``-(power of the inertia, the weights and
    the load)`` (:func:`linkage_fmu.loads.powers` times omega, ``= dT/dt - P_loads``),
    to 1e-9 of its peak."""
    mech = presets.get("six_bar")
    omega, alpha = 3.0, 2.0
    table = effort_places(mech, REVOLUTION, omega, alpha, load=100.0)
    crank = mech.solve(REVOLUTION, omega, alpha, load=100.0)["Mb"] * omega
    np.testing.assert_allclose(table.loc["OA", "peak_power"], np.max(np.abs(crank)),
                               rtol=1e-12)
    np.testing.assert_allclose(table.loc["OA", "mean_power"], np.mean(crank),
                               atol=1e-12 * np.max(np.abs(crank)))
    st = mech.kinematics(REVOLUTION, order=2)
    virtual = -omega * sum(powers(mech, st, omega, alpha, (100.0,), static=False))
    for place in SIX_BAR:
        np.testing.assert_allclose(table.loc[place, "peak_power"], np.max(np.abs(virtual)),
                                   rtol=1e-9)
        np.testing.assert_allclose(table.loc[place, "mean_power"], np.mean(virtual),
                                   atol=1e-9 * np.max(np.abs(virtual)))
    assert table.loc["OA", "peak_power"] > 100.0  # not the static scene's zero


def test_friction_is_solved_at_each_place_and_locking_is_reported():
    """With friction in the pin A and the guide (mu 0.2), omega = 3 rad/s: the crank's
    row is solving the six-bar with that friction (1e-12 relative), its power the
    crank's ``Mb * omega``; the places where friction locks the linkage at some angles
    say how many (the count of the solve's locked states) and have no numbers."""
    friction = dict(mu_A=0.2, r_A=0.02, mu_guide=0.2)
    table = effort_places(presets.get("six_bar", **friction), REVOLUTION, 3.0, 0.0,
                          load=100.0)
    ref = presets.get("six_bar", driver="OA", **friction).solve(REVOLUTION, 3.0, 0.0,
                                                                load=100.0)
    np.testing.assert_allclose(table.loc["OA", "peak"], np.max(np.abs(ref["Mb"])), rtol=1e-12)
    np.testing.assert_allclose(table.loc["OA", "peak_power"], np.max(np.abs(3.0 * ref["Mb"])),
                               rtol=1e-12)
    for place in ("AB", "O1B", "KD", "D"):
        sol = presets.get("six_bar", driver=place, **friction).solve(REVOLUTION, 3.0, 0.0,
                                                                     load=100.0)
        locked = int(np.count_nonzero(sol.status != 0))
        assert locked > 0 and np.isnan(table.loc[place, "peak"])
        assert table.loc[place, "reason"] == (
            f"locked by friction at {locked} of 360 angles: friction locks the linkage "
            "against its driver")
    assert recommend(table)[0] == "OA"


def test_near_singular_places_are_flagged_not_recommended():
    """The slider-crank's coupler at theta = 90 deg: it stops turning, so a moment on it
    is unbounded there (the solve gives about 1e17 N.m, its condition estimate 7e16):
    the row keeps the solved numbers and says why; the recommendation passes over it."""
    table = effort_places(presets.get("slider_crank"), REVOLUTION, load=50.0)
    row = table.loc["moment on 2"]
    assert row["peak"] > 1e15 and row["reason"].startswith(
        "near-singular at 2 of 360 angles (cond up to 7.1e+16 at theta = 90 deg)")
    assert table.loc["force at 3", "reason"].startswith("singular at 1 of 360 angles")
    place, why = recommend(table)
    assert place == "moment on 1" and "moment on 2: unsuitable (near-singular" in why


def test_refusals_say_why():
    """Driven by time, built without a description, angles where the linkage cannot be
    assembled, angles that are not finite numbers, and a table with no suitable place."""
    five = linkage_fmu.load(ROOT / "examples" / "five_bar.toml")
    with pytest.raises(InputError, match=r"five_bar is driven by time \(its drivers: A, E\): "
                       "each driver applies its own effort, so there is no balancing effort "
                       "to place"):
        effort_places(five, REVOLUTION)
    m = presets.get("four_bar")
    bare = Mechanism("demo", m.frame, m.frame_points, m.groups[:3], m.bodies, m.effort, [], [],
                     0.0)
    with pytest.raises(InputError, match="demo was built without a description"):
        effort_places(bare, REVOLUTION)
    with pytest.raises(InputError, match=r"four_bar cannot be assembled at 2 of 3 angles "
                       r"\(theta = 177.617 to 183.346 deg\), wherever its effort is"):
        effort_places(presets.get("four_bar", l_AB=0.3), [0.1, 3.1, 3.2])
    for theta in ([], [0.1, np.nan]):
        with pytest.raises(InputError, match="theta must be one or more finite crank angles"):
            effort_places(m, theta)
    with pytest.raises(InputError, match="theta must be crank angles in rad"):
        effort_places(m, "abc")
    table = effort_places(presets.get("slider_crank"), [0.0, 1.0])
    table = table.loc[["force at 3"]]  # the piston: it stops at theta = 0
    with pytest.raises(InputError, match="no place balances the linkage at every angle"):
        recommend(table)


def run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        status = main(argv)
    return status, out.getvalue(), err.getvalue()


def test_cli_efforts_prints_the_table_and_the_recommendation(tmp_path):
    """``efforts six_bar --n 36 --load 100 --csv``: the library's table over 36 angles of
    a revolution (CSV keeps every digit), then the recommendation; ``-o`` writes the CSV;
    a linkage driven by time is refused with status 2."""
    status, out, _ = run(["efforts", "six_bar", "--n", "36", "--load", "100", "--csv"])
    assert status == 0
    text, _, last = out.rstrip("\n").rpartition("\n")
    ref = effort_places(presets.get("six_bar"), np.linspace(0.0, 2.0 * np.pi, 36,
                                                            endpoint=False), load=100.0)
    df = pd.read_csv(io.StringIO(text), index_col="place", keep_default_na=False,
                     na_values=[""])
    np.testing.assert_array_equal(df["peak"].to_numpy(), ref["peak"].to_numpy())
    assert list(df.index) == list(ref.index)
    assert last == f"recommended: {recommend(ref)[1]}"
    assert last.startswith("recommended: OA: the lowest peak reaction in the pairs, 451.3 N")
    target = tmp_path / "places.csv"
    status, out, _ = run(["efforts", "slider_crank", "--theta", "10:350:20", "--deg",
                          "--omega", "100 rpm", "-o", str(target)])
    written = pd.read_csv(target, index_col="place")
    theta = np.radians(np.arange(10.0, 351.0, 20.0))
    ref = effort_places(presets.get("slider_crank"), theta, "100 rpm", None)
    assert status == 0 and out.startswith("recommended: moment on 1: ")
    np.testing.assert_allclose(written["peak_power"], ref["peak_power"], rtol=1e-15)
    five = str(ROOT / "examples" / "five_bar.toml")
    status, _, err = run(["efforts", five])
    assert status == 2 and "linkage-fmu efforts takes a linkage driven by one crank" in err
