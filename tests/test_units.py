"""Numbers with units (``linkage_fmu.units``, through pint) against the stated factors of
the definitions: 1 in = 0.0254 m, 1 lbf = 4.4482216152605 N, 1 bar = 1e5 Pa, 1 rpm =
2 pi / 60 rad/s, 1 deg = pi / 180 rad; and a wrong kind named with its key."""

from __future__ import annotations

import math
import re

import pytest

from linkage_fmu import presets, units
from linkage_fmu.expressions import evaluate
from linkage_fmu.parameters import Parameter
from linkage_fmu.units import has_units, to_si

FACTORS = [
    ("240 mm", "m", 0.240),
    ("9.5 in", "m", 9.5 * 0.0254),
    ("1800 rpm", "rad/s", 1800 * 2 * math.pi / 60),
    ("30 deg", "rad", math.pi / 6),
    ("30deg", "rad", math.pi / 6),
    ("4 kN", "N", 4000.0),
    ("12 lbf", "N", 12 * 4.4482216152605),
    ("2.5 kN*m", "N.m", 2500.0),
    ("1.2 kg*m**2", "kg.m2", 1.2),
    ("350 g", "kg", 0.350),
    ("1 ft", "m", 0.3048),
    ("32.174 ft/s**2", "m/s2", 32.174 * 0.3048),
    ("600 deg/s**2", "rad/s2", 600 * math.pi / 180),
    ("1e3 mm", "m", 1.0),
]


@pytest.mark.parametrize("text, unit, si", FACTORS)
def test_a_number_with_a_unit_is_taken_in_si(text, unit, si):
    """To 1e-15 relative: the factor is the definition's."""
    assert to_si(text, unit, "x") == pytest.approx(si, rel=1e-15)
    assert evaluate(text, unit, "x") == pytest.approx(si, rel=1e-15)


def test_an_expression_of_quantities_and_parameters():
    """A piston force from a pressure and a bore: 8 bar * pi * (86 mm)^2 / 4 =
    4647.0434... N (8e5 Pa * 0.005808804... m^2)."""
    area = math.pi * 0.086 ** 2 / 4
    assert evaluate("8 bar * pi * (86 mm)**2 / 4", "N", "F") == pytest.approx(8e5 * area,
                                                                              rel=1e-15)
    assert evaluate("800 kPa * pi * bore**2 / 4", "N", "F", {"bore": 0.086},
                    {"bore": (0.086, "m")}) == pytest.approx(8e5 * area, rel=1e-15)
    assert evaluate("2 * pi * 30 rad/s", "rad/s", "omega") == pytest.approx(60 * math.pi)


@pytest.mark.parametrize("text, unit, message", [
    ("1800 rpm", "m", r"l_AB = '1800 rpm' must be a length \(m\), but it is an angular speed"),
    ("4 kN", "N.m", r"l_AB = '4 kN' must be a moment \(N.m\), but it is a force \(N\)"),
    ("3 kg", "kg.m2", r"must be a moment of inertia \(kg.m2\), but it is a mass \(kg\)"),
    ("2 m + 3 s", "m", r"l_AB = '2 m \+ 3 s'"),
    ("3 furlongs_per_fortnight", "m", "is not a unit"),
    ("sin(3 m)", "rad", r"l_AB = 'sin\(3 m\)'"),
])
def test_a_number_of_the_wrong_kind_is_an_error_naming_the_key(text, unit, message):
    with pytest.raises(ValueError, match=message):
        evaluate(text, unit, "l_AB")


def test_plain_numbers_stay_si():
    assert not has_units("2 * l_AB") and not has_units(3.0) and has_units("3 mm")
    assert evaluate("pi / 2", "rad", "gamma") == math.pi / 2
    assert evaluate(0.2, "m", "l") == 0.2


def test_a_parameter_takes_a_unit_of_its_kind():
    """``Parameter.validate`` converts and checks: 120 mm is 0.12 m; an angle in degrees;
    a length in kg is refused, naming the parameter."""
    length = Parameter("l_AB", 0.1, "length", "crank")
    assert length.validate("120 mm") == pytest.approx(0.12, rel=1e-15)
    angle = Parameter("gamma", 0.0, "angle", "guide")
    assert angle.validate("90 deg") == pytest.approx(math.pi / 2, rel=1e-15)
    with pytest.raises(ValueError, match=r"l_AB = '2 kg' must be a length"):
        Parameter("l_AB", 0.1, "length", "crank").validate("2 kg")
    with pytest.raises(ValueError, match="l_AB must be > 0"):
        Parameter("l_AB", 0.1, "length", "crank").validate("-5 mm")


def test_solve_takes_inputs_and_parameters_with_units():
    """The scotch yoke at 60 deg, 95.4929... rpm (10 rad/s) and 0.4 kN gives the scotch
    yoke worked example's quoted Mb = 15.6699 N m and F23 = 313.3975 N; with
    l_AB = "100 mm" the same."""
    yoke = presets.get("scotch_yoke", l_AB="100 mm")
    rpm = 10.0 * 60 / (2 * math.pi)
    sol = yoke.solve("60 deg", f"{rpm!r} rpm", "0 rad/s**2", "0.4 kN")
    assert sol["Mb"] == pytest.approx(15.6699, abs=5e-5)
    assert sol["F23y"] == pytest.approx(313.3975, abs=5e-5)
    with pytest.raises(ValueError, match=r"omega = '1800 mm' must be an angular speed"):
        yoke.solve(0.0, "1800 mm")
    with pytest.raises(ValueError, match=r"theta = '3 N' must be an angle"):
        yoke.solve("3 N")

@pytest.mark.parametrize("text, si", [("1e3", 1e3), ("1E3", 1e3), ("1e300", 1e300),
                                      ("2.5e-3", 2.5e-3), (".5e2", 50.0)])
def test_a_number_in_exponent_form_is_a_number_not_a_unit(text, si):
    """``1e3`` is the float 1000.0 (Python's reading of the text), not 1 of a unit
    ``e3``; ``2.5e-3 m`` stays 2.5 mm."""
    assert evaluate(text, "N.m", "tau") == si == float(text)
    assert evaluate(f"{text} m", "m", "l") == float(text)


@pytest.mark.parametrize("text, fixed", [("3 Nm", "3 N*m"), ("2.5 kNm", "2.5 kN*m")])
def test_a_moment_written_as_one_word_is_refused_with_the_unit_meant(text, fixed):
    """pint reads ``Nm`` as a number-metre ([length] / [mass]); the error names the key
    and the product of units meant, which is taken: 3 N*m = 3.0 N.m."""
    with pytest.raises(ValueError, match=rf"^T = '{text}' must be a moment \(N.m\), but it "
                                         rf"is .*; did you mean '{re.escape(fixed)}'\?$"):
        evaluate(text, "N.m", "T")
    assert evaluate(fixed, "N.m", "T") == float(text.split()[0]) * (1e3 if "k" in text else 1.0)


@pytest.mark.parametrize("unit", units.TABLE, ids=[u.symbol for u in units.TABLE])
def test_each_units_base_and_display_units_are_pints(unit):
    """Reference: pint's own definitions. The SI base-unit exponents the FMUs'
    modelDescription writes are those of the unit's pint spelling (coherent: factor 1),
    and each display unit's factor is pint's conversion (1 deg = pi / 180 rad), to 1e-15."""
    ureg = units.registry()
    base = ureg.Quantity(1.0, unit.pint).to_base_units()
    short = {"kilogram": "kg", "meter": "m", "second": "s", "radian": "rad"}
    assert {short[k]: v for k, v in base.unit_items()} == unit.base
    assert base.magnitude == pytest.approx(1.0, rel=1e-15)
    for name, factor in unit.display:
        spelled = name.replace("s2", "s**2")
        assert ureg.Quantity(1.0, unit.pint).to(spelled).magnitude == pytest.approx(
            factor, rel=1e-15)
        assert factor == pytest.approx(180.0 / math.pi, rel=1e-15)


def test_the_units_named_and_defined_are_the_tables():
    """The units a description may use (their pint spelling, what each measures), the
    ones the FMUs' modelDescription defines and the units of the crank's motion are
    read from one table: every unit a value may have is defined for the FMUs."""
    from linkage_fmu.fmi.writers import UNITS

    assert list(UNITS) == [u.symbol for u in units.TABLE]
    assert list(units.PINT) == list(units.NAMES) == [u.symbol for u in units.TABLE
                                                      if u.described]
    assert set(units.MOTION_UNITS.values()) <= set(units.PINT)
    mech = presets.get("four_bar")
    assert {k: mech.input_units[k] for k in units.MOTION_UNITS} == units.MOTION_UNITS
