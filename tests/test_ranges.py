"""Where a linkage assembles (``linkage_fmu.ranges``), against the closure condition of
the four-bar derived by hand: B-C-D closes when |BD| <= BC + CD, |BD|^2 = AB^2 + AD^2 -
2 AB AD cos(theta)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from linkage_fmu import presets
from linkage_fmu.ranges import assembles, runs, text


@pytest.mark.parametrize("l_ab", [0.3, 0.28, 0.2])
def test_the_four_bar_assembles_where_its_dyad_closes(l_ab):
    """The ends to 1e-9 rad: cos(theta) = (AB^2 + AD^2 - (BC + CD)^2) / (2 AB AD)."""
    ab, bc, cd, ad = l_ab, 0.35, 0.30, 0.40
    c = (ab * ab + ad * ad - (bc + cd) ** 2) / (2 * ab * ad)
    limit = math.degrees(math.acos(c)) if c > -1 else 180.0
    got = assembles(presets.get("four_bar", l_AB=l_ab))
    if c <= -1:
        assert got == [(0.0, 360.0)]
    else:
        assert got[0][0] == 0.0 and got[-1][1] == 360.0 and len(got) == 2
        assert got[0][1] == pytest.approx(limit, abs=math.degrees(1e-9))
        assert got[1][0] == pytest.approx(360.0 - limit, abs=math.degrees(1e-9))


def test_a_narrow_range_and_none():
    """A slider-crank with a 2 mm rod whose guide is e = sin(0.7) off the pivot of a 1 m
    crank assembles only within about 0.003 rad of 0.7 and pi - 0.7 (|e - sin(theta)| <=
    0.002); moved to e = 1.5 it assembles nowhere."""
    mech = presets.get("slider_crank", l_OA=1.0, l_AB=0.002, e=math.sin(0.7))
    got = assembles(mech)
    assert len(got) == 2
    for (a, b), centre in zip(got, (0.7, math.pi - 0.7)):
        lo, hi = math.radians(a), math.radians(b)
        assert lo < centre < hi and hi - lo < 0.007
        for end in (lo, hi):  # each end is where |e - sin(theta)| = l_AB, to 1e-8
            assert abs(math.sin(end) - math.sin(0.7)) == pytest.approx(0.002, abs=1e-8)
    assert assembles(presets.get("slider_crank", l_OA=1.0, l_AB=0.002, e=1.5)) == []


def test_runs_and_their_words():
    ok = np.array([0, 1, 1, 0, 0, 1, 0, 1], bool)
    x = np.arange(8.0) * 10
    assert runs(x, ok) == [(10.0, 20.0), (50.0, 50.0), (70.0, 70.0)]
    assert text(runs(x, ok)) == "10 to 20, 50 and 70 deg"
    assert text([]) == "none" and runs(x, np.zeros(8, bool)) == []
