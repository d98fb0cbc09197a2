"""A quantity given over the cycle as a table: a periodic cubic spline of the crank angle.

An engine's indicator diagram over 720 degrees, a press's force over its stroke: a
:class:`PeriodicTable` interpolates the points ``(theta_deg, value)`` by the periodic
cubic spline through them (scipy's ``CubicSpline``, ``bc_type="periodic"``) and
evaluates it at any crank angle, also beyond one period. One evaluation, written once,
runs on floats, numpy arrays, mpmath numbers and traced numbers; a trace records it as a
call of the table (:meth:`~linkage_fmu.kernels.trace.Tape.extern`), whose C definition
carries the spline's coefficients: the same floats in every kernel and FMU.

Examples
--------
>>> import math
>>> t = PeriodicTable([0, 90, 180, 270], [0.0, 1.0, 0.0, -1.0])
>>> round(t(math.radians(90.0)), 12), round(t(math.radians(450.0)), 12)
(1.0, 1.0)
"""

from __future__ import annotations

import bisect
import csv
import hashlib
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .errors import InputError


class PeriodicTable:
    """The periodic cubic spline through the points ``(theta_deg[k], values[k])``, of
    period ``period_deg`` (the points lie within one period, increasing; the spline
    closes on the first point one period on).

    Raises
    ------
    ValueError
        Fewer than three points, an angle or value that is not finite, angles that do
        not increase or span a period or more, a period that is not positive.
    """

    def __init__(self, theta_deg: Sequence[float], values: Sequence[float],
                 period_deg: float = 360.0, label: str = "table"):
        x = np.asarray(theta_deg, dtype=float)
        y = np.asarray(values, dtype=float)
        if x.ndim != 1 or x.shape != y.shape or x.size < 3:
            raise InputError(f"{label}: needs three or more points (theta_deg, value), got "
                             f"{x.size}")
        if not (np.isfinite(x).all() and np.isfinite(y).all()):
            raise InputError(f"{label}: every angle and value must be a finite number")
        if not (math.isfinite(period_deg) and period_deg > 0):
            raise InputError(f"{label}: period_deg = {period_deg!r} must be a number > 0")
        if not (np.diff(x) > 0).all():
            raise InputError(f"{label}: the angles must increase")
        if not x[-1] - x[0] < period_deg:
            raise InputError(f"{label}: the angles span {float(x[-1] - x[0])!r} deg, not less "
                             f"than the period {float(period_deg)!r} deg (the point one period "
                             "on is the first one)")
        from scipy.interpolate import CubicSpline

        self.theta_deg, self.values, self.period_deg = x, y, float(period_deg)
        xr = np.radians(np.append(x, x[0] + period_deg))
        spline = CubicSpline(xr, np.append(y, y[0]), bc_type="periodic")
        #: the first angle [rad], the period [rad], the breakpoints from the first angle
        self.x0 = float(xr[0])
        self.period = float(math.radians(period_deg))
        self.breaks = [float(b) for b in xr[:-1] - xr[0]]
        #: the cubic on piece i: ((c0 d + c1) d + c2) d + c3, d from its breakpoint
        self.coefficients = [[float(c) for c in row] for row in spline.c]
        digest = hashlib.sha256(np.concatenate([x, y, [period_deg]]).tobytes()).hexdigest()
        #: the C identifier of its evaluation in generated code
        self.name = f"lk_table_{digest[:16]}"
        self._arrays = [np.array(row) for row in self.coefficients]
        #: the derivative's cubic on piece i: (3 c0 d + 2 c1) d + c2
        c = self.coefficients
        self._slopes = [[3.0 * v for v in c[0]], [2.0 * v for v in c[1]], c[2]]

    @classmethod
    def read(cls, path: str | Path, period_deg: float = 360.0) -> "PeriodicTable":
        """The table of a CSV file with the columns ``theta_deg`` and ``value`` (other
        columns are ignored): :func:`read_rows`."""
        rows = read_rows(path)
        return cls([r[0] for r in rows], [r[1] for r in rows], period_deg, label=str(path))

    def _phase(self, theta, floor):
        t = theta - self.x0
        return t - floor(t / self.period) * self.period

    def __call__(self, theta, xp=None):
        """The spline at the crank angle ``theta`` [rad]: a float, a numpy array, an
        mpmath number or a traced number (recorded as a call of this table)."""
        if hasattr(theta, "tape"):
            return theta.tape.extern(self, theta)
        if isinstance(theta, np.ndarray):
            t = self._phase(theta, np.floor)
            i = np.clip(np.searchsorted(self.breaks, t, side="right") - 1, 0,
                        len(self.breaks) - 1)
            d = t - np.asarray(self.breaks)[i]
            c0, c1, c2, c3 = (a[i] for a in self._arrays)
            return ((c0 * d + c1) * d + c2) * d + c3
        t = self._phase(theta, math.floor)  # an int: exact times the period
        i = min(max(bisect.bisect_right(self.breaks, t) - 1, 0), len(self.breaks) - 1)
        d = t - self.breaks[i]
        c0, c1, c2, c3 = (row[i] for row in self.coefficients)
        return ((c0 * d + c1) * d + c2) * d + c3

    def derivative(self, theta: float) -> float:
        """The spline's derivative by ``theta`` at the crank angle ``theta`` [rad] (a
        float): the operations of :meth:`c_derivative`, in the same order (the kernels'
        forward mode, in Python or C).

        Examples
        --------
        >>> t = PeriodicTable([0, 90, 180, 270], [0.0, 1.0, 0.0, -1.0])
        >>> h = 1e-6   # against a central difference
        >>> abs(t.derivative(1.0) - (t(1.0 + h) - t(1.0 - h)) / (2 * h)) < 1e-9
        True
        """
        t = self._phase(theta, math.floor)
        i = min(max(bisect.bisect_right(self.breaks, t) - 1, 0), len(self.breaks) - 1)
        d = t - self.breaks[i]
        c0, c1, c2 = (row[i] for row in self._slopes)
        return (c0 * d + c1) * d + c2

    def c_definition(self) -> str:
        """The C function ``double <name>(double theta)``: the same operations as the
        float evaluation, in the same order."""
        return self._c_function(self.name, self.coefficients,
                                "((c0[i] * d + c1[i]) * d + c2[i]) * d + c3[i]")

    def c_derivative(self) -> str:
        """The C function ``double <name>_d(double theta)``: the derivative of the spline
        with respect to ``theta`` (for the kernels' directional derivatives)."""
        return self._c_function(f"{self.name}_d", self._slopes,
                                "(c0[i] * d + c1[i]) * d + c2[i]")

    def _c_function(self, name: str, coefficients: list, value: str) -> str:
        """A C function of ``theta`` that finds its piece and returns ``value`` of the
        offset ``d`` and the piece's ``coefficients`` (arrays ``c0``, ``c1``, ...)."""
        from .kernels.c_source import c_literal

        n = len(self.breaks)

        def array(name, values):
            return f"    static const double {name}[{len(values)}] = {{" + ", ".join(
                c_literal(v) for v in values) + "};"

        return "\n".join([
            f"static double {name}(double theta) {{",
            array("b", self.breaks),
            *(array(f"c{k}", row) for k, row in enumerate(coefficients)),
            f"    double t = theta - {c_literal(self.x0)};",
            f"    t = t - floor(t / {c_literal(self.period)}) * {c_literal(self.period)};",
            f"    int lo = 0, hi = {n};",
            "    while (lo < hi) { const int mid = (lo + hi) / 2; if (t < b[mid]) hi = mid; "
            "else lo = mid + 1; }",
            f"    const int i = lo - 1 < 0 ? 0 : lo - 1 > {n - 1} ? {n - 1} : lo - 1;",
            "    const double d = t - b[i];",
            f"    return {value};",
            "}",
        ])

    def rows(self) -> list[list[float]]:
        """The points as ``[theta_deg, value]`` pairs (for a description file)."""
        return [[float(a), float(b)] for a, b in zip(self.theta_deg, self.values)]


def read_rows(path: str | Path) -> list[list[float]]:
    """The points ``[theta_deg, value]`` of a CSV file with the columns ``theta_deg``
    and ``value`` (other columns are ignored); a ValueError naming the file says what
    is wrong with it.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     path = os.path.join(tmp, "f.csv")
    ...     _ = open(path, "w").write("theta_deg,value\\n0,1.5\\n90,2\\n")
    ...     read_rows(path)
    [[0.0, 1.5], [90.0, 2.0]]
    """
    path = Path(path)
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    except OSError as err:
        raise InputError(f"{path}: cannot read it: {err.strerror}") from None
    except (UnicodeDecodeError, csv.Error) as err:
        raise InputError(f"{path}: not a CSV file: {err}") from None
    if not rows or not {"theta_deg", "value"} <= set(rows[0]):
        raise InputError(f"{path}: needs a header with the columns theta_deg and value, and "
                         "one row per point")
    out = []
    for k, r in enumerate(rows):
        try:
            out.append([float(r["theta_deg"]), float(r["value"])])
        except (TypeError, ValueError):
            raise InputError(f"{path}: row {k + 2}: theta_deg = {r['theta_deg']!r} and value "
                             f"= {r['value']!r} must be numbers") from None
    return out
