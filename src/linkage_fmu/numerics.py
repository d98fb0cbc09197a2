"""Elementary functions for the two evaluation modes, and input checks.

Every formula in the package is written once and evaluated either on plain floats
(with :mod:`math`; one state, e.g. an FMU step) or on numpy arrays (many states at
once). The mode is a namespace of the few non-arithmetic functions the formulas use.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from types import SimpleNamespace

import numpy as np

from .errors import InputError, InputTypeError
from .kernels.trace import sign

Number = float | np.ndarray


def array_sign(x: np.ndarray) -> np.ndarray:
    """:func:`~linkage_fmu.kernels.trace.sign` element by element."""
    return np.greater(x, 0.0) * 1.0 - np.less(x, 0.0)


def scalar_nan_where(z: float) -> float:
    """:func:`~linkage_fmu.kernels.trace.nan_where` of a float: NaN where ``z`` is 1, 0
    where it is 0."""
    return math.nan if z else 0.0


def array_nan_where(z: np.ndarray) -> np.ndarray:
    """:func:`~linkage_fmu.kernels.trace.nan_where` element by element."""
    return np.where(z != 0.0, np.nan, 0.0)


#: Functions for one state given as Python floats.
SCALAR = SimpleNamespace(
    scalar=True, sqrt=math.sqrt, cos=math.cos, sin=math.sin, atan2=math.atan2, abs=abs,
    maximum=max, sign=sign, nan_where=scalar_nan_where
)
#: Functions for many states given as numpy arrays.
ARRAY = SimpleNamespace(
    scalar=False, sqrt=np.sqrt, cos=np.cos, sin=np.sin, atan2=np.arctan2, abs=np.abs,
    maximum=np.maximum, sign=array_sign, nan_where=array_nan_where
)


def _on_traced(fn: Callable) -> Callable:
    # a traced number (kernels.trace.Sym) records the call instead of taking a float
    def call(*args):
        for a in args:
            if hasattr(a, "traced"):
                return a.traced(fn.__name__, fn, *args)
        return fn(*args)

    call.__name__ = call.__qualname__ = fn.__name__
    call.__doc__ = f"``math.{fn.__name__}``, also on traced numbers (build-time values)."
    return call


#: :mod:`math` functions for values computed from parameters when a linkage is built:
#: on floats, or on traced numbers when the parameters are kernel arguments
cos, sin, tan, asin, acos, atan, atan2, hypot, sqrt, radians, degrees = map(_on_traced, (
    math.cos, math.sin, math.tan, math.asin, math.acos, math.atan, math.atan2, math.hypot,
    math.sqrt, math.radians, math.degrees))
minimum, maximum = _on_traced(min), _on_traced(max)
#: -1, 0 or 1 as the value is negative, zero or positive (a drawn pose's assembly mode),
#: an operation of the kernels, not a branch
signum = _on_traced(sign)
signum.__doc__ = ":func:`~linkage_fmu.kernels.trace.sign`, also on traced numbers."


#: the functions an expression may call, on floats or traced numbers
FUNCTIONS = {"sqrt": sqrt, "sin": sin, "cos": cos, "tan": tan, "asin": asin, "acos": acos,
             "atan": atan, "atan2": atan2, "hypot": hypot, "radians": radians,
             "degrees": degrees, "abs": abs, "min": minimum, "max": maximum, "sign": signum}
#: the same on numpy arrays (element by element)
ARRAY_FUNCTIONS = {"sqrt": np.sqrt, "sin": np.sin, "cos": np.cos, "tan": np.tan,
                   "asin": np.arcsin, "acos": np.arccos, "atan": np.arctan,
                   "atan2": np.arctan2, "hypot": np.hypot, "radians": np.radians,
                   "degrees": np.degrees, "abs": np.abs, "min": np.minimum, "max": np.maximum,
                   "sign": array_sign}


def functions(xp) -> dict:
    """The functions an expression calls on the numbers of the namespace ``xp``: its own
    (``xp.functions``, mpmath's), or :data:`FUNCTIONS` for one state (floats, traced),
    :data:`ARRAY_FUNCTIONS` for arrays."""
    own = getattr(xp, "functions", None)
    return own if own is not None else FUNCTIONS if xp.scalar else ARRAY_FUNCTIONS


def label(value, reason) -> None:
    """Say why the comparison just made on the traced ``value`` fails (a
    :class:`~linkage_fmu.kernels.trace.Reason`); nothing for a plain number.

    A kernel returns the code of a guard that fails, and its reason says what failed in
    words that are the same in every flavour of FMU.
    """
    tape = getattr(value, "tape", None)
    if tape is not None:
        tape.label(reason)


def real(value) -> float:
    """``float(value)``; a traced number stays traced.

    Examples
    --------
    >>> real(3), largest([0.1, 0.4, 0.3])
    (3.0, 0.4)
    """
    return value if hasattr(value, "traced") else float(value)


def largest(values) -> float:
    """The largest of ``values`` as ``max`` picks it, recorded as one operation per pair
    (not as a branch) for traced numbers."""
    values = list(values)
    best = values[0]
    for v in values[1:]:
        best = maximum(best, v)
    return best


def finite_float(name: str, value: object) -> float:
    """Return ``value`` as a float, or raise naming ``name`` if it is not a finite number.

    Examples
    --------
    >>> finite_float("omega", 3)
    3.0
    >>> finite_float("omega", float("nan"))
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError: omega must be a finite number, got nan
    """
    if type(value) is float and value - value == 0.0:  # the common case, finite
        return value
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.number)):
        raise InputTypeError(f"{name} must be a real number, got {type(value).__name__} {value!r}")
    try:
        x = float(value)
    except OverflowError:  # an int past float64's range
        raise InputError(f"{name} must be a finite number, got an integer of "
                         f"{int(value).bit_length()} bits, past float64's range") from None
    if not math.isfinite(x):
        raise InputError(f"{name} must be a finite number, got {x!r}")
    return x


def finite_array(name: str, value: np.ndarray) -> np.ndarray:
    """Return ``value`` as a float64 array, or raise naming ``name`` and the first bad entry.

    Examples
    --------
    >>> finite_array("theta", np.array([0.0, np.inf]))
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError: theta must be finite: entry (1,) is inf
    """
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as err:
        raise InputTypeError(f"{name} must be an array of real numbers: {err}") from None
    except OverflowError:  # an int past float64's range
        raise InputError(f"{name} must be finite: an entry is an integer past float64's "
                         "range") from None
    if not np.isfinite(arr).all():
        where = tuple(int(i) for i in np.argwhere(~np.isfinite(arr))[0])
        raise InputError(f"{name} must be finite: entry {where} is {float(arr[where])!r}")
    return arr
