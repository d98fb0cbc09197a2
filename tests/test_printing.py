"""Numbers as printed for people (linkage_fmu.printing.number): a zero is "0", never
"-0", "-0.000000" or the rounding left of a zero sum; other values keep the figures
asked for. The references are Python's own format() of the same value."""

from __future__ import annotations

import math

import pytest

from linkage_fmu.printing import ZERO_FRACTION, number


@pytest.mark.parametrize("value, digits, fixed, text", [
    (-0.0, 4, False, "0"),  # format(-0.0, ".4g") is "-0"
    (0.0, 4, False, "0"),
    (-0.0, 6, True, "0"),  # "-0.000000"
    (-4.99e-7, 6, True, "0"),  # rounds to -0.000000 at the precision shown
    (4.99e-7, 6, True, "0"),  # rounds to 0.000000
    (-5.01e-7, 6, True, "-0.000001"),  # rounds to a figure shown: kept
    (1.5, 6, True, "1.500000"),
    (-0.04, 1, True, "0"),  # an angle "-0.0" deg
    (-2.345e-17, 4, False, "-2.345e-17"),  # significant figures: only zero rounds to 0
    (1234.5678, 4, False, "1235"),
    (-1234.5678, 10, False, "-1234.5678"),
])
def test_zeros_print_as_0_and_the_rest_to_the_figures_asked(value, digits, fixed, text):
    assert number(value, digits, fixed=fixed) == text
    if text != "0":  # the same as Python's own format
        assert text == format(value, f".{digits}{'f' if fixed else 'g'}")


def test_a_sum_zero_but_for_rounding_prints_0_against_its_scale():
    """The four-bar's cycle mean of Mb at 10 rad/s with no load is -2.3447e-17 N m, of
    Mb values up to 0.27 N m: zero (its loads are conservative), printed 0; a value
    just over 1e-12 of the scale is a real one and is printed."""
    assert number(-2.344714332739879e-17, scale=0.27) == "0"
    assert number(-2.344714332739879e-17) == "-2.345e-17"  # no scale: as it is
    assert number(0.99 * ZERO_FRACTION * 5.0, scale=5.0) == "0"
    assert number(1.02 * ZERO_FRACTION * 5.0, scale=-5.0) == "5.1e-12"


def test_not_finite_values_print_as_python_does():
    assert [number(v) for v in (math.nan, math.inf, -math.inf)] == ["nan", "inf", "-inf"]
    assert number(math.nan, scale=math.inf) == "nan"
