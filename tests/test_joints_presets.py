"""Every preset written as joints and links (examples/joints/) agrees with the preset.

The reference is the preset's own group form, written by hand (src/linkage_fmu/linkages);
the joints-and-links file gives the same linkage by its drawn pose, decomposed by
linkage_fmu.descriptions.assur. The states: angles over the revolution, with omega, alpha and
the load varying from state to state, for several parameter sets, most with Coulomb
friction in every pair. Every output agrees to 1e-14 of its scale: the largest magnitude,
over the states, of the outputs of its unit (every force in N, every moment in N.m, ...;
transmission angles: pi). The joints-and-links form computes its lengths from drawn
coordinates, which round differently in the last bit; the linkage amplifies that by its
condition number (the diagnostic ``cond``, up to about 8000 in these states), so one
output compared against its own largest value would see up to 1.1e-14. ``cond`` itself
agrees to 1e-12, relative, state by state.
"""

from pathlib import Path

import numpy as np
import pytest

from linkage_fmu import presets
from linkage_fmu.descriptions import Description

EXAMPLES = Path(__file__).parents[1] / "examples" / "joints"
TOLERANCE = 1e-14
COND_TOLERANCE = 1e-12

#: preset -> parameter sets besides the defaults (each assembles at the drawn angle 0)
PARAMETER_SETS = {
    "four_bar": [
        dict(l_AB=0.12, l_BC=0.33, l_CD=0.32, l_AD=0.38, branch=-1, l_AS1=0.02, beta1=0.1,
             J1=0.001, beta2=0.3, beta3=-0.2, mu_A=0.1, r_A=0.01, mu_B=0.15, r_B=0.008,
             mu_C=0.1, r_C=0.01, mu_D=0.2, r_D=0.012),
        dict(l_BC=0.5, l_CD=0.45, drive=-1.0, mu_A=0.05, r_A=0.02, mu_C=0.2, r_C=0.005),
    ],
    "slider_crank": [
        dict(e=0.02, gamma=0.3, l_OS1=0.01, m1=0.5, J1=0.001, mu_O=0.1, r_O=0.01, mu_A=0.1,
             r_A=0.01, mu_B=0.12, r_B=0.008, mu_guide=0.1),
        dict(e=-0.01, gamma=-1.2, l_AB=0.3, mu_guide=0.2, drive=-1.0),
    ],
    "scotch_yoke": [
        dict(l_AB=0.12, h2=0.1, m1=1.0, J1=0.002, g=9.81, mu_A=0.1, r_A=0.01, mu_B=0.1,
             r_B=0.01, mu_slot=0.1, mu_guide=0.1),
    ],
    "slotted_lever": [
        dict(l_AB=0.5, mu_A=0.1, r_A=0.01, mu_B=0.1, r_B=0.01, mu_slot=0.15, mu_C=0.1,
             r_C=0.02),
        dict(l_AB=0.2, l_CS3=-0.1, mu_slot=0.1, drive=-1.0),
    ],
    "crank_shaper": [
        dict(branch=-1, mu_A=0.1, r_A=0.01, mu_B=0.1, r_B=0.01, mu_slot=0.1, mu_C=0.1,
             r_C=0.01, mu_D=0.1, r_D=0.01, mu_E=0.1, r_E=0.01, mu_guide=0.1),
        dict(l_CD=0.8, h_E=0.35, l_DS4=0.1, mu_guide=0.2),
    ],
    "six_bar": [
        dict(branch_B=-1, branch_D=-1, driver="D", mu_O=0.1, r_O=0.01, mu_A=0.1, r_A=0.01,
             mu_B=0.1, r_B=0.01, mu_O1=0.1, r_O1=0.01, mu_K=0.1, r_K=0.01, mu_D=0.1,
             r_D=0.01, mu_guide=0.1),
        dict(driver="O1B", a=0.45, b=0.4, rho=12.0, mu_guide=0.15),
        dict(driver="KD", branch_D=-1),
    ],
}


def _states(n: int = 181):
    """Angles over the revolution, and omega, alpha and the load varying among them."""
    theta = np.linspace(0.0, 2.0 * np.pi, n)
    k = np.arange(n)
    omega = np.array([10.0, -3.0, 7.5, 0.0])[k % 4]
    alpha = np.array([5.0, 0.0, -12.0])[k % 3]
    load = np.array([40.0, -250.0, 0.0, 900.0, 3.5])[k % 5]
    return theta, omega, alpha, load


def _cases():
    for name in presets.NAMES:
        for k, params in enumerate([{}] + PARAMETER_SETS[name]):
            yield pytest.param(name, params, id=f"{name}-{k}")


def test_every_preset_has_its_joints_form():
    assert sorted(p.stem for p in EXAMPLES.glob("*.toml")) == sorted(presets.NAMES)


@pytest.mark.parametrize("name, params", list(_cases()))
def test_both_forms_agree(name, params):
    by_groups = presets.get(name, **params)
    d = Description.read(EXAMPLES / f"{name}.toml")
    assert d.groups[0]["type"] == "crank"
    by_joints = d.build(**params)
    assert by_joints.output_names == by_groups.output_names
    assert by_joints.diagnostic_names == by_groups.diagnostic_names
    theta, omega, alpha, load = _states()
    # the group formulas run on numpy arrays: what the compiled kernels run, without a
    # compilation for each of the two forms of each parameter set
    want = by_groups.solve(theta, omega, alpha, load, method="interpreted")
    got = by_joints.solve(theta, omega, alpha, load, method="interpreted")
    assert list(got) == list(want)
    units = {k: by_groups.output_info[k][0] for k in want}
    scale = {}
    for key, unit in units.items():
        w = np.abs(np.asarray(want[key], float))
        biggest = np.max(w[np.isfinite(w)], initial=0.0)
        scale[unit] = max(scale.get(unit, 0.0), biggest)
    scale["rad"] = np.pi
    compared = 0
    for key in want:
        w, g = np.asarray(want[key], float), np.asarray(got[key], float)
        np.testing.assert_array_equal(np.isnan(g), np.isnan(w), err_msg=key)
        np.testing.assert_array_equal(np.isinf(g), np.isinf(w), err_msg=key)
        ok = np.isfinite(w)
        allowed = (TOLERANCE * scale[units[key]] if key != "cond" else
                   COND_TOLERANCE * np.abs(w[ok]))
        assert np.all(np.abs(g[ok] - w[ok]) <= allowed), (
            key, np.max(np.abs(g[ok] - w[ok]), initial=0.0), scale[units[key]])
        compared += ok.sum()
    assert compared > 0.9 * len(theta) * len(want)  # most states assemble
