"""Numbers as people read them (tables printed, summaries, plot titles and labels):
:func:`number`, the one place they are rounded. A zero is printed ``0``: never ``-0``
or ``-0.000000``, and not ``-2.345e-17`` for a sum of numbers near 1 that is zero but
for rounding. Files for programs (CSV, Parquet) keep every bit instead."""

from __future__ import annotations

import math

#: a value within this fraction of the ``scale`` it is printed against is printed as 0:
#: what rounding leaves of a zero sum of numbers that size is far less (about 1e-16 of
#: it per term), and a real value that small would not show beside them either
ZERO_FRACTION = 1e-12


def number(value: float, digits: int = 4, *, fixed: bool = False, scale: float = 0.0) -> str:
    """``value`` to ``digits`` significant figures (``fixed``: ``digits`` after the
    point), or ``"0"`` where it is zero as shown: zero or negative zero, a value that
    rounds to zero at that precision, or one within :data:`ZERO_FRACTION` of ``scale``
    (the size of the numbers it is a sum or mean of, e.g. the largest of a curve).
    ``nan``, ``inf`` and ``-inf`` as Python prints them.

    Parameters
    ----------
    value : float
    digits : int, optional
        Significant figures (default 4), or with ``fixed`` figures after the point.
    fixed : bool, optional
        Fixed-point (``f`` format) instead of significant figures (``g``).
    scale : float, optional
        The size the value is shown against (default 0: only a zero at the precision
        shown is 0).

    Examples
    --------
    >>> number(-0.0), number(-2.345e-17), number(-2.345e-17, scale=0.27)
    ('0', '-2.345e-17', '0')
    >>> number(-4e-7, 6, fixed=True), number(-0.0000006, 6, fixed=True), number(1.5, 6, fixed=True)
    ('0', '-0.000001', '1.500000')
    >>> number(1234.5678), number(0.000123456, 3), number(float("nan"))
    ('1235', '0.000123', 'nan')
    """
    value = float(value)
    if not math.isfinite(value):
        return str(value)
    if abs(value) <= ZERO_FRACTION * abs(scale):
        return "0"
    text = f"{value:.{digits}f}" if fixed else f"{value:.{digits}g}"
    return "0" if float(text) == 0.0 else text
