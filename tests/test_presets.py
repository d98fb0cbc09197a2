"""Presets carry exactly the parameter names, defaults and output names of MECHANISMS.md,
plus the friction's (``mu_<pair>``, ``r_<pin>``, ``drive``; ``Mf_<pin>``, ``Ff_<slide>``,
``P_loss``, ``eta``), and every one of them is a description file that reads back what it writes."""

from __future__ import annotations

import pytest

from linkage_fmu import presets

SPEC = {
    "scotch_yoke": (
        {"l_AB": 0.1, "h2": 0.08, "m1": 0.0, "J1": 0.0, "m2": 4.0, "m3": 10.0, "J3": 0.0, "g": 0.0},
        ("F12x", "F12y", "F23y", "F4", "F4p", "F41x", "F41y", "Mb"),
        (0.0, 10.0, 0.0, 400.0),
    ),
    "four_bar": (
        {"l_AB": 0.10, "l_BC": 0.35, "l_CD": 0.30, "l_AD": 0.40, "m1": 1.0, "J1": 0.0,
         "l_AS1": 0.0, "beta1": 0.0, "m2": 2.0, "J_S2": 0.02, "l_BS2": 0.175, "beta2": 0.0,
         "m3": 1.5, "J_S3": 0.012, "l_DS3": 0.15, "beta3": 0.0, "g": 9.81, "branch": 1},
        ("F21x", "F21y", "F32x", "F32y", "F43x", "F43y", "F14x", "F14y", "Mb"),
        (0.0, 10.0, 0.0, 0.0),
    ),
    "six_bar": (
        {"l_OA": 0.15, "l_AB": 0.97, "l_O1B": 0.66, "l_O1K": 0.25, "l_KD": 0.86, "a": 0.50,
         "b": 0.37, "rho": 10.0, "m4": 20.0, "g": 9.81, "driver": "OA", "branch_B": 1,
         "branch_D": 1},
        ("XO", "YO", "XA", "YA", "XB", "YB", "XO1", "YO1", "XK", "YK", "XD", "YD", "N4", "Mb",
         "Pb"),
        (0.0, 0.0, 0.0, 0.0),
    ),
    "slider_crank": (
        {"l_OA": 0.05, "l_AB": 0.20, "e": 0.0, "gamma": 0.0, "m1": 0.0, "J1": 0.0, "l_OS1": 0.0,
         "m2": 0.8, "J2": 0.004, "l_AS2": 0.06, "m3": 0.6, "g": 9.81},
        ("F21x", "F21y", "F32x", "F32y", "N43", "F14x", "F14y", "Mb"),
        (0.0, 10.0, 0.0, 0.0),
    ),
    "slotted_lever": (
        {"l_AB": 0.15, "l_AC": 0.40, "m1": 2.0, "J1": 0.005, "m2": 0.5, "J2": 0.001, "m3": 8.0,
         "J_S3": 0.33, "l_CS3": 0.35, "g": 9.81},
        ("F01x", "F01y", "F12x", "F12y", "N23", "M23", "F03x", "F03y", "Mb"),
        (0.0, 5.0, 0.0, 0.0),
    ),
    "crank_shaper": (
        {"l_AB": 0.15, "l_AC": 0.40, "l_CD": 0.70, "l_DE": 0.30, "h_E": 0.28, "m1": 2.0,
         "J1": 0.005, "m2": 0.5, "J2": 0.001, "m3": 8.0, "J_S3": 0.33, "l_CS3": 0.35, "m4": 2.0,
         "J_S4": 0.015, "l_DS4": 0.15, "m5": 15.0, "g": 9.81, "branch": 1},
        ("F01x", "F01y", "F12x", "F12y", "N23", "M23", "F03x", "F03y", "F34x", "F34y", "F45x",
         "F45y", "N05", "Mb"),
        (0.0, 5.0, 0.0, 1000.0),
    ),
}


#: the pairs with friction, in output order: pins (moment Mf_, radius r_) and slides (Ff_)
FRICTION = {
    "scotch_yoke": (("A", "pin"), ("B", "pin"), ("slot", "slide"), ("guide", "slide")),
    "four_bar": (("A", "pin"), ("B", "pin"), ("C", "pin"), ("D", "pin")),
    "six_bar": (("O", "pin"), ("A", "pin"), ("B", "pin"), ("O1", "pin"), ("K", "pin"),
                ("D", "pin"), ("guide", "slide")),
    "slider_crank": (("O", "pin"), ("A", "pin"), ("B", "pin"), ("guide", "slide")),
    "slotted_lever": (("A", "pin"), ("B", "pin"), ("slot", "slide"), ("C", "pin")),
    "crank_shaper": (("A", "pin"), ("B", "pin"), ("slot", "slide"), ("C", "pin"), ("D", "pin"),
                     ("E", "pin"), ("guide", "slide")),
}


def _with_friction(name):
    """SPEC's names plus the friction's: mu_J (and r_J of a pin) default 0, drive +1;
    the outputs Mf_J / Ff_J, P_loss and eta after the specification's."""
    params, outputs, inputs = SPEC[name]
    params = dict(params)
    for j, kind in FRICTION[name]:
        params[f"mu_{j}"] = 0.0
        if kind == "pin":
            params[f"r_{j}"] = 0.0
    params["drive"] = 1.0
    outputs = outputs + tuple(f"{'Mf' if kind == 'pin' else 'Ff'}_{j}"
                              for j, kind in FRICTION[name]) + ("P_loss", "eta")
    return params, outputs, inputs


@pytest.mark.parametrize("name", list(SPEC))
def test_names_defaults_and_outputs(name):
    params, outputs, inputs = _with_friction(name)
    spec = presets.preset(name)
    assert {p.name: p.default for p in spec.parameter_specs()} == params
    mech = presets.get(name)
    # the specification's outputs, the friction's, then the shaking force and moment every
    # linkage has
    assert mech.output_names == outputs + ("shake_x", "shake_y", "shake_M")
    assert mech.parameters == params
    i = spec.inputs
    assert (i["theta"], i["omega"], i["alpha"], mech.loads[0].start) == inputs
    assert mech.input_names == ("theta", "omega", "alpha", "load")
    assert all(p.description for p in spec.parameter_specs())


def test_every_preset_is_listed():
    assert presets.names() == tuple(SPEC)


@pytest.mark.parametrize("name", list(SPEC))
def test_description_file_round_trip(name):
    """``to_toml`` writes the file :meth:`Description.from_toml` reads back unchanged, and
    the linkage built from it gives the preset's numbers bit for bit."""
    from linkage_fmu.descriptions import Description

    d = presets.preset(name)
    again = Description.from_toml(d.to_toml(), "round trip")
    assert again == d
    a = d.build().solve(0.7, 3.0, 1.0, 20.0)
    b = again.build().solve(0.7, 3.0, 1.0, 20.0)
    assert dict(a) == dict(b)
