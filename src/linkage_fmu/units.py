"""Numbers with units where people type them: ``"240 mm"``, ``"1800 rpm"``, ``"30 deg"``,
``"800 kPa * pi * bore**2 / 4"``, through pint.

Everything the package computes is SI with angles in radians; a plain number is taken
as that. A number followed by a unit (a space between them is optional; a unit is one
word of pint's, such as ``mm``, ``kN``, ``rpm``, ``deg``, ``kg*m**2``, ``m/s**2``; put
spaces around an operator after it: ``800 kPa * A``, since ``kPa*A`` is kilopascal
ampere) is converted to SI, and the whole value is checked against the unit of what it
gives: a length given in rpm is an error. pint is imported only for text with a unit.

Examples
--------
>>> to_si("240 mm", "m", "l_AB")
0.24
>>> round(to_si("1800 rpm", "rad/s", "omega"), 6)
188.495559
>>> to_si("1800 rpm", "m", "l_AB")
Traceback (most recent call last):
...
linkage_fmu.errors.InputError:
l_AB = '1800 rpm' must be a length (m), but it is an angular speed (rad/s)
"""

from __future__ import annotations

import functools
import re
from typing import NamedTuple

from .errors import InputError

#: degrees in a radian, the factor of the FMUs' display units of angles
RAD2DEG = 57.29577951308232


class Unit(NamedTuple):
    """A unit the package names.

    ``symbol`` is how the tables, the messages and the FMUs' modelDescription write it,
    ``pint`` pint's spelling, ``measures`` what it measures (in messages), ``base`` its
    SI base-unit exponents and ``display`` its display units, (name, factor from the
    unit), as the modelDescription defines them. ``described`` is False for a unit that
    only a diagnostic output has: no value or output of a description may be in it.
    """

    symbol: str
    pint: str
    measures: str
    base: dict
    display: tuple = ()
    described: bool = True


#: every unit the package names, in the order they are listed (the FMUs'
#: modelDescription defines them in this order)
TABLE = (
    Unit("rad", "rad", "an angle", {"rad": 1}, (("deg", RAD2DEG),)),
    Unit("rad/s", "rad/s", "an angular speed", {"rad": 1, "s": -1}, (("deg/s", RAD2DEG),)),
    Unit("rad/s2", "rad/s**2", "an angular acceleration", {"rad": 1, "s": -2},
         (("deg/s2", RAD2DEG),)),
    Unit("m", "m", "a length", {"m": 1}),
    Unit("m/s", "m/s", "a speed", {"m": 1, "s": -1}),
    Unit("m/s2", "m/s**2", "an acceleration", {"m": 1, "s": -2}),
    Unit("kg", "kg", "a mass", {"kg": 1}),
    Unit("kg/m", "kg/m", "a mass per length", {"kg": 1, "m": -1}),
    Unit("kg.m2", "kg*m**2", "a moment of inertia", {"kg": 1, "m": 2}),
    # the reduced inertia's derivative by the crank angle (dJ_red)
    Unit("kg.m2/rad", "kg*m**2/rad", "a moment of inertia per angle",
         {"kg": 1, "m": 2, "rad": -1}, described=False),
    Unit("N", "N", "a force", {"kg": 1, "m": 1, "s": -2}),
    Unit("N.m", "N*m", "a moment", {"kg": 1, "m": 2, "s": -2}),
    Unit("W", "W", "a power", {"kg": 1, "m": 2, "s": -3}),
    Unit("J", "J", "an energy", {"kg": 1, "m": 2, "s": -2}),
    Unit("Pa", "Pa", "a pressure", {"kg": 1, "m": -1, "s": -2}),
    Unit("m2", "m**2", "an area", {"m": 2}),
    Unit("s", "s", "a time", {"s": 1}),
    Unit("1", "dimensionless", "a number", {}),
)
#: the units of the values and outputs of a description -> pint's spelling
PINT = {u.symbol: u.pint for u in TABLE if u.described}
#: what each of :data:`PINT` measures, for messages
NAMES = {u.symbol: u.measures for u in TABLE if u.described}
#: the units of the crank's motion, the inputs every linkage has
MOTION_UNITS = {"theta": "rad", "omega": "rad/s", "alpha": "rad/s2"}
#: a number, then a unit: a word that starts with a letter (letters, digits, _ * / ^ .);
#: never the exponent of the number (``1e3`` is a number, not 1 of the unit ``e3``)
_QUANTITY = re.compile(r"(?<![\w.])((?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)[ \t]*"
                       r"(?![eE][+-]?\d)([A-Za-z_°µΩ][\w°µΩ*/^.]*)")


@functools.lru_cache(maxsize=1)
def registry():
    """pint's unit registry (imported on first use)."""
    import pint

    return pint.UnitRegistry()


def has_units(text) -> bool:
    """Whether ``text`` holds a number with a unit.

    Examples
    --------
    >>> has_units("2 * l_AB"), has_units("30 deg"), has_units(3.0)
    (False, True, False)
    """
    return isinstance(text, str) and _QUANTITY.search(text) is not None


def quantity(number: str, unit: str):
    """The pint quantity ``number unit``, the unit cut at its longest prefix pint knows
    that ends before a ``*`` or ``/`` (``kPa*A`` is ``kPa`` times ``A``); the quantity
    and the length of the unit's text used. A ValueError if pint knows no prefix."""
    import pint

    ureg = registry()
    cuts = [len(unit)] + [i for i in range(len(unit) - 1, 0, -1) if unit[i] in "*/"]
    last = None
    for cut in cuts:
        try:
            return ureg.Quantity(float(number), ureg.parse_units(unit[:cut])), cut
        except (pint.errors.PintError, ValueError, TypeError, AttributeError) as err:
            last = err
    raise InputError(f"{unit!r} after {number} is not a unit ({last})")


def substitute(text: str) -> tuple[str, list]:
    """``text`` with each number-with-unit replaced by a name ``__q<k>__``, and the list
    of the quantities (pint) in order.

    Examples
    --------
    >>> source, qs = substitute("800 kPa*area + 2 mm")
    >>> source, [f"{q:~}" for q in qs]
    ('__q0__*area + __q1__', ['800.0 kPa', '2.0 mm'])
    """
    out, quantities, pos = [], [], 0
    for match in _QUANTITY.finditer(text):
        q, cut = quantity(match.group(1), match.group(2))
        out += [text[pos:match.start()], f"__q{len(quantities)}__"]
        quantities.append(q)
        pos = match.start(2) + cut
    out.append(text[pos:])
    return "".join(out), quantities


def si(q) -> float:
    """The magnitude of the pint quantity ``q`` in SI base units, correctly rounded where
    the unit is a decimal fraction of its base (``86 mm`` is 0.086, not 86 * 0.001 =
    0.08600000000000001).

    Examples
    --------
    >>> si(registry().Quantity(86, "mm")), si(registry().Quantity(620, "g"))
    (0.086, 0.62)
    """
    factor = registry().Quantity(1.0, q.units).to_base_units().magnitude
    inverse = 1.0 / factor
    if inverse > 1.0 and inverse == round(inverse):  # a division is exact where a product
        return float(q.magnitude) / round(inverse)  # by 0.001 is not
    return float(q.magnitude) * factor


def dimension(unit: str):
    """pint's dimensionality of the package's ``unit`` (``"m"``, ``"rad/s"``, ...)."""
    return registry().parse_units(PINT.get(unit, unit)).dimensionality


def check(value, unit: str, where: str, source) -> float:
    """The SI magnitude of the pint quantity ``value``, which must measure what ``unit``
    measures (a ValueError naming ``where`` and ``source`` if not)."""
    ureg = registry()
    target = ureg.parse_units(PINT.get(unit, unit))
    if not isinstance(value, ureg.Quantity):
        value = ureg.Quantity(value, "dimensionless")
    if value.dimensionality != target.dimensionality:
        raise InputError(f"{where} = {source!r} must be {NAMES.get(unit, unit)} ({unit}), but "
                         f"it is {measures(value.dimensionality)}{suggestion(source, unit)}")
    return si(value) / si(ureg.Quantity(1.0, target))


def suggestion(source, unit: str) -> str:
    """``"; did you mean ..."`` where a unit in ``source`` written as one word is two
    units whose product measures what ``unit`` does (pint reads ``Nm`` as a
    number-metre, not a newton metre), else ``""``.

    Examples
    --------
    >>> suggestion("3 Nm", "N.m")
    "; did you mean '3 N*m'?"
    >>> suggestion("3 m", "N.m")
    ''
    """
    if not isinstance(source, str):
        return ""
    import pint

    ureg, target = registry(), dimension(unit)
    for match in _QUANTITY.finditer(source):
        word = match.group(2)
        for cut in range(1, len(word) if word.isalpha() else 0):
            try:
                product = ureg.parse_units(word[:cut]) * ureg.parse_units(word[cut:])
            except (pint.errors.PintError, ValueError, TypeError, AttributeError):
                continue
            if product.dimensionality == target:
                fixed = (source[:match.start(2)] + f"{word[:cut]}*{word[cut:]}"
                         + source[match.end(2):])
                return f"; did you mean {fixed!r}?"
    return ""


def measures(dimensionality) -> str:
    """What a pint dimensionality measures, in words where it is one of :data:`NAMES`
    (the first that fits: an energy is called a moment)."""
    for unit, name in NAMES.items():
        if unit != "1" and dimension(unit) == dimensionality:
            return f"{name} ({unit})"
    return "a number" if not dimensionality else str(dimensionality)


def to_si(text, unit: str, where: str) -> float:
    """A number, or the text of a number with a unit, in SI (``unit``), checked.

    Examples
    --------
    >>> to_si("30 deg", "rad", "angle") == 3.141592653589793 / 6
    True
    """
    if not isinstance(text, str):
        return float(text)
    match = _QUANTITY.fullmatch(text.strip())
    if match is None:
        return float(text)  # a plain number in text: SI
    q, cut = quantity(match.group(1), match.group(2))
    if cut != len(match.group(2)):
        raise InputError(f"{where} = {text!r}: {match.group(2)!r} is not a unit")
    return check(q, unit, where, text)


def unit_problem(unit, where: str) -> str:
    """What is wrong with ``unit`` as the unit of a value the package computes (an
    output: it is in SI), naming ``where``; '' for one of the package's units
    (:data:`PINT`).

    Examples
    --------
    >>> unit_problem("N.m", "[[outputs]] #2 (Q) unit")
    ''
    >>> unit_problem("kN", "[[outputs]] #2 (Q) unit")
    "[[outputs]] #2 (Q) unit: 'kN' is not SI, and the output is computed in SI: write 'N'"
    >>> print(unit_problem("ZZ", "[[outputs]] #2 (Q) unit"))  # doctest: +ELLIPSIS
    [[outputs]] #2 (Q) unit: 'ZZ' is not a unit (pint knows no 'ZZ'); the units of an output
    are rad, rad/s, ...
    """
    if unit in PINT:
        return ""
    known = ", ".join(PINT)
    if not isinstance(unit, str) or not unit.strip():
        return f"{where}: {unit!r} is not a unit; the units of an output are {known}"
    import pint

    try:
        dimensionality = registry().parse_units(unit).dimensionality
    except (pint.errors.PintError, ValueError, TypeError, AttributeError, AssertionError):
        return (f"{where}: {unit!r} is not a unit (pint knows no {unit!r}); the units of an "
                f"output are {known}")
    same = [u for u in PINT if dimension(u) == dimensionality]
    if not same:
        return f"{where}: {unit!r} is not one of the units of an output: {known}"
    factor = registry().Quantity(1.0, unit).to(PINT[same[0]]).magnitude
    if abs(factor - 1.0) <= 1e-15:
        return f"{where}: {unit!r} is written {same[0]!r} here"
    return f"{where}: {unit!r} is not SI, and the output is computed in SI: write {same[0]!r}"
