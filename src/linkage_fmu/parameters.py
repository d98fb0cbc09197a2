"""Named, validated parameters of a linkage: kinds with their units and rules, bounds."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .errors import InputError, InputTypeError, ParameterError
from .expressions import evaluate
from .numerics import finite_float

#: kind -> (unit, check description, predicate) for the real-valued kinds
_REAL_KINDS = {
    "length": ("m", "> 0", lambda v: v > 0.0),
    "distance": ("m", ">= 0", lambda v: v >= 0.0),
    "coordinate": ("m", "finite", lambda v: True),
    "angle": ("rad", "finite", lambda v: True),
    "mass": ("kg", ">= 0", lambda v: v >= 0.0),
    "inertia": ("kg.m2", ">= 0", lambda v: v >= 0.0),
    "density": ("kg/m", ">= 0", lambda v: v >= 0.0),
    "gravity": ("m/s2", ">= 0", lambda v: v >= 0.0),
    "force": ("N", "finite", lambda v: True),
    "moment": ("N.m", "finite", lambda v: True),
    "number": ("1", "finite", lambda v: True),
    "friction": ("1", ">= 0", lambda v: v >= 0.0),
    "sign": ("1", "+1 or -1", lambda v: v in (1.0, -1.0)),
}
#: the largest coefficient of friction taken (a parameter of kind ``friction`` without a
#: ``maximum`` of its own has this one). The friction of a pair is mu times its normal
#: force, and a normal force that is 0 comes out of the arithmetic as rounding, about
#: 1e-16 of the loads: up to 1e6 that gives friction of 1e-10 of the loads at most;
#: from about 1e15 rounding decides whether the pair locks, and the methods disagree
MU_MAX = 1e3
#: kind -> the rule of a value of the kinds that are not real numbers
_OTHER_KINDS = {"branch": "+1 or -1", "choice": "one of its choices"}
#: every kind: the real-valued ones, ``branch`` (+1 or -1) and ``choice`` (one of a list)
KINDS = tuple(_REAL_KINDS) + tuple(_OTHER_KINDS)


def unit_and_rule(kind: str) -> tuple[str, str]:
    """The SI unit of a parameter of ``kind`` ('' for a branch or a choice) and the rule
    its value meets, in words.

    Parameters
    ----------
    kind : str
        One of :data:`KINDS`.

    Returns
    -------
    tuple of str
        ``(unit, rule)``: the unit as in :data:`~linkage_fmu.units.PINT`; the rule
        ``'> 0'``, ``'>= 0'`` or ``'finite'`` for a real kind, else what the value is.

    Raises
    ------
    ValueError
        An unknown kind.

    Examples
    --------
    >>> unit_and_rule("length"), unit_and_rule("angle"), unit_and_rule("branch")
    (('m', '> 0'), ('rad', 'finite'), ('', '+1 or -1'))
    """
    if kind in _REAL_KINDS:
        unit, rule, _ = _REAL_KINDS[kind]
        return unit, rule + (f" and <= {MU_MAX:g}" if kind == "friction" else "")
    if kind in _OTHER_KINDS:
        return "", _OTHER_KINDS[kind]
    raise InputError(f"unknown parameter kind {kind!r}; the kinds are {', '.join(KINDS)}")


@dataclass(frozen=True)
class Parameter:
    """One parameter of a preset: name, default, kind and meaning.

    ``kind`` is one of ``length, distance, coordinate, angle, mass, inertia, density,
    gravity, force, moment, number, friction`` (a coefficient, >= 0), ``sign`` (a real
    +1 or -1: a direction) (real numbers with a unit and a rule),
    ``branch`` (+1 or -1) or ``choice`` (one of ``choices``). ``minimum`` and
    ``maximum``, when given, bound a real value (inclusive); a ``friction`` coefficient's
    ``maximum`` is at most :data:`MU_MAX`. A real value may be given
    as text: a number with a unit of its kind (``"120 mm"``), or an expression of
    numbers (``"pi / 2"``); it is taken in SI.

    Examples
    --------
    >>> p = Parameter("l_AB", 0.1, "length", "crank length")
    >>> p.unit, p.validate(0.2)
    ('m', 0.2)
    >>> p.validate(-1)
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError: l_AB must be > 0 (crank length), got -1.0
    >>> p.validate("120 mm")
    0.12
    """

    name: str
    default: Any
    kind: str
    description: str
    choices: tuple = ()
    minimum: float | None = None
    maximum: float | None = None

    def __post_init__(self):
        if self.kind == "friction" and self.maximum is not None and self.maximum > MU_MAX:
            raise ParameterError(self.name, f"max = {self.maximum:g} is above the largest "
                                            f"coefficient of friction taken ({MU_MAX:g})")
        if self.kind == "friction" and self.maximum is None:
            object.__setattr__(self, "maximum", MU_MAX)

    @property
    def unit(self) -> str:
        """SI unit of the value ('' for branch and choice parameters)."""
        return _REAL_KINDS[self.kind][0] if self.kind in _REAL_KINDS else ""

    @property
    def rule(self) -> str:
        """The rule a real value must meet ('> 0', '>= 0' or 'finite'; '' otherwise)."""
        return _REAL_KINDS[self.kind][1] if self.kind in _REAL_KINDS else ""

    def validate(self, value: Any) -> Any:
        """Return the checked value, or raise a ``TypeError``/``ValueError`` naming it."""
        if self.kind == "branch":
            if isinstance(value, bool) or value not in (1, -1):
                raise InputError(
                    f"{self.name} must be +1 or -1 ({self.description}), got {value!r}")
            return int(value)
        if self.kind == "choice":
            if value not in self.choices:
                raise InputError(
                    f"{self.name} must be one of {', '.join(map(repr, self.choices))}, "
                    f"got {value!r}"
                )
            return value
        unit, rule, ok = _REAL_KINDS[self.kind]
        if isinstance(value, str):  # a number with a unit, or an expression of numbers
            value = evaluate(value, unit, self.name)
        x = finite_float(self.name, value)
        if not ok(x):
            raise InputError(f"{self.name} must be {rule} ({self.description}), got {x!r}")
        if self.minimum is not None and x < self.minimum:
            raise InputError(f"{self.name} must be >= {self.minimum!r} ({self.description}), "
                             f"got {x!r}")
        if self.maximum is not None and x > self.maximum:
            raise InputError(f"{self.name} must be <= {self.maximum!r} ({self.description}), "
                             f"got {x!r}")
        return x


def resolve(specs: tuple[Parameter, ...], given: Mapping[str, Any], preset: str) -> dict:
    """Merge ``given`` into the defaults of ``specs``, checking every name and value.

    Examples
    --------
    >>> specs = (Parameter("g", 9.81, "gravity", "gravity"),)
    >>> resolve(specs, {"g": 0}, "demo")
    {'g': 0.0}
    >>> resolve(specs, {"G": 0}, "demo")
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputTypeError: demo has no parameter 'G'; its parameters are: g
    """
    known = {p.name: p for p in specs}
    for name in given:
        if name not in known:
            raise InputTypeError(
                f"{preset} has no parameter {name!r}; its parameters are: {', '.join(known)}"
            )
    return {p.name: p.validate(given.get(p.name, p.default)) for p in specs}
