"""Shared fixtures: the presets in every variant, and reference helpers."""

from __future__ import annotations

import mpmath
import pytest

from linkage_fmu import presets
from linkage_fmu.precise import MP  # noqa: F401  (re-exported for the tests)

#: (preset, parameters) covering every preset and every six-bar driver
VARIANTS = [
    ("scotch_yoke", {}),
    ("scotch_yoke", {"m1": 1.5, "J1": 0.01, "J3": 0.2, "g": 9.81}),
    ("four_bar", {}),
    ("four_bar", {"branch": -1, "beta2": 0.4, "beta3": -0.3, "l_AS1": 0.03, "J1": 0.001}),
    ("slider_crank", {}),
    ("slider_crank", {"e": 0.02, "gamma": 0.7, "m1": 0.5, "J1": 1e-3, "l_OS1": 0.02}),
    ("six_bar", {"driver": "OA"}),
    ("six_bar", {"driver": "AB"}),
    ("six_bar", {"driver": "O1B"}),
    ("six_bar", {"driver": "KD"}),
    ("six_bar", {"driver": "D"}),
]
IDS = [f"{n}-{'-'.join(f'{k}={v}' for k, v in p.items()) or 'defaults'}" for n, p in VARIANTS]

#: the scalar formulas are evaluated at 40 digits in the tests that use MP
mpmath.mp.dps = 40


@pytest.fixture(params=VARIANTS, ids=IDS)
def mech(request):
    name, params = request.param
    return presets.get(name, **params)


def effort_name(mech) -> str:
    return mech.effort.name
