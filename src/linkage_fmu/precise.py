"""A high-precision reference: the same equations evaluated in mpmath.

The kinematics, the loads and the equations of every moving link are the package's
own formulas, evaluated on mpmath numbers (40 significant digits by default) instead
of floats, and the equations are solved by mpmath's LU with partial pivoting. The
parameters and inputs are taken as the exact binary values of their floats, so the
difference between a float64 result and this reference is the float64 path's own
rounding error, which :func:`relative_error` measures.
"""

from __future__ import annotations

from types import SimpleNamespace

import mpmath
import numpy as np

from . import evaluation
from .linalg import solve_mpmath

#: evaluation mode of the formulas on mpmath numbers (see :mod:`linkage_fmu.numerics`);
#: the direct method solves its linear system with
#: :func:`~linkage_fmu.linalg.solve_mpmath`
MP = SimpleNamespace(scalar=True, sqrt=mpmath.sqrt, cos=mpmath.cos, sin=mpmath.sin,
                     atan2=mpmath.atan2, abs=abs, maximum=max, sign=mpmath.sign,
                     nan_where=lambda z: mpmath.nan if z else mpmath.mpf(0),
                     lu_solve=solve_mpmath,
                     eps=lambda: mpmath.mp.eps * 1000,
                     functions={"sqrt": mpmath.sqrt, "sin": mpmath.sin, "cos": mpmath.cos,
                                "tan": mpmath.tan, "asin": mpmath.asin, "acos": mpmath.acos,
                                "atan": mpmath.atan, "atan2": mpmath.atan2,
                                "hypot": mpmath.hypot, "radians": mpmath.radians,
                                "degrees": mpmath.degrees, "abs": abs, "min": min,
                                "max": max, "sign": mpmath.sign})


def reference(mech, theta: float, omega: float | None = None, alpha: float | None = None,
              *loads: float,
              dps: int = 40, **named_loads: float) -> dict:
    """Outputs of ``mech`` at one state, computed with ``dps`` significant digits.

    Parameters
    ----------
    mech : Mechanism
        The linkage.
    theta, omega, alpha, *loads, **named_loads : float
        The state, as for :meth:`~linkage_fmu.Mechanism.solve`.
    dps : int
        Decimal digits of the mpmath evaluation.

    Returns
    -------
    dict
        Output name -> :class:`mpmath.mpf` for every output of
        ``mech.output_names`` (the diagnostics are not included).

    Raises
    ------
    AssemblyError
        When the linkage cannot be assembled at ``theta``.
    ZeroDivisionError
        When the equations are exactly singular.

    Examples
    --------
    >>> import math
    >>> from linkage_fmu import presets
    >>> ref = reference(presets.get("scotch_yoke"), math.radians(60), 10.0, 0.0,
    ...                 400.0)
    >>> # the values the scotch yoke worked example quotes
    >>> round(float(ref["Mb"]), 4), round(float(ref["F23y"]), 4)
    (15.6699, 313.3975)
    """
    values, given = mech.inputs(omega, alpha, loads, named_loads)
    plan = mech.solver.plan(mech.output_names, False, "direct", given)
    with mpmath.workdps(dps):
        state = [mpmath.mpf(float(v)) for v in (theta, *values)]
        out, _ = evaluation.evaluate(mech, plan, state[0], state[1], state[2], state[3:], MP)
        return {name: +out[name] for name in mech.output_names}


def references(mech, theta, omega=None, alpha=None, *loads, dps: int = 40,
               **named_loads) -> dict:
    """:func:`reference` over arrays of states, rounded to float64 arrays.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> ref = references(presets.get("four_bar"), [0.0, 1.0], 10.0)
    >>> ref["Mb"].shape
    (2,)
    """
    values, given = mech.inputs(omega, alpha, loads, named_loads)
    arrays = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (theta, *values)))
    n = 3 + len(mech.input_loads)
    rows = [reference(mech, *map(float, s[:n]), dps=dps, **dict(zip(given, map(float, s[n:]))))
            for s in zip(*(a.ravel() for a in arrays))]
    return {n: np.array([float(r[n]) for r in rows]).reshape(arrays[0].shape)
            for n in mech.output_names}


def relative_error(values, ref) -> np.ndarray:
    """Normwise relative error per state: ``max |value - ref| / max |ref|`` over outputs.

    Components that are zero or small compared with the state's largest force would make
    a componentwise ratio meaningless, so every output of a state is measured against
    that state's largest reference output. Only the names in ``ref`` are compared; an
    output NaN in both (``eta`` where no power enters) agrees, one NaN in one only makes
    the error NaN.

    Examples
    --------
    >>> relative_error({"a": np.array([1.0, 2.0]), "b": np.array([0.0, 1e-3])},
    ...                {"a": np.array([1.0, 2.0]), "b": np.array([1e-16, 1e-3])})
    array([1.e-16, 0.e+00])
    >>> relative_error({"a": 2.0, "eta": float("nan")},
    ...                {"a": 2.0, "eta": float("nan")})
    np.float64(0.0)
    """
    errors, sizes = [], []
    for n in ref:
        v, r = np.asarray(values[n], float), np.asarray(ref[n], float)
        both = np.isnan(v) & np.isnan(r)
        errors.append(np.where(both, 0.0, np.abs(v - r)))
        sizes.append(np.where(both, 0.0, np.abs(r)))
    return np.max(errors, axis=0) / np.max(sizes, axis=0)
