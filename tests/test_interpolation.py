"""The interpolated table against the 40-digit reference, and its input checks."""

from __future__ import annotations

import numpy as np
import pytest

from linkage_fmu import presets
from linkage_fmu.interpolation import AngleTable
from linkage_fmu.precise import references, relative_error

THETA = np.random.default_rng(7).uniform(0.0, 2 * np.pi, 40)


@pytest.mark.parametrize("name, load, size, tol", [
    ("four_bar", 3.0, 1024, 5e-9), ("four_bar", 3.0, 4096, 5e-11),
    ("slider_crank", 50.0, 1024, 1e-10), ("slider_crank", 50.0, 4096, 1e-12),
])
def test_error_falls_with_the_fourth_power_of_the_grid(name, load, size, tol):
    """Against mpmath (measured: four-bar 1.6e-9 at 1024, 7.7e-12 at 4096; slider-crank
    2.4e-11, 9.7e-14): one scene for all angles, and a scene per state."""
    mech = presets.get(name)
    table = AngleTable(mech, size)
    ref = references(mech, THETA, 10.0, 4.0, load)
    assert relative_error(table(THETA, 10.0, 4.0, load), ref).max() <= tol
    per_state = table(THETA, np.full(THETA.size, 10.0), 4.0, np.full(THETA.size, load))
    assert relative_error(per_state, ref).max() <= tol


def test_scalar_state_gives_floats():
    mech = presets.get("slider_crank")
    out = AngleTable(mech, 512)(1.0, 10.0)
    assert isinstance(out["Mb"], float)
    assert out["Mb"] == pytest.approx(mech.solve(1.0, 10.0)["Mb"], rel=1e-8)


@pytest.mark.parametrize("size", [3, 4.0, "64"])
def test_bad_size_is_rejected(size):
    with pytest.raises(ValueError, match="size must be an integer >= 4"):
        AngleTable(presets.get("four_bar"), size)


def test_non_finite_state_is_rejected():
    with pytest.raises(ValueError, match="omega must be finite"):
        AngleTable(presets.get("four_bar"), 64)([0.0, 1.0], [1.0, np.nan])


def test_friction_is_refused_it_does_not_add_up():
    """Friction (|R|, the signs of motion, the states it locks) is not a sum of parts:
    the table refuses it, saying why; the same linkage with every mu 0 is taken."""
    with pytest.raises(ValueError, match="slider_crank: friction in its joints makes the "
                                         "outputs nonlinear in omega"):
        AngleTable(presets.get("slider_crank", mu_guide=0.2), 64)
    AngleTable(presets.get("slider_crank", mu_guide=0.0, r_A=0.01), 64)
