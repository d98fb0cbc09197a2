"""What a plot is given and solves: the crank angles (``theta`` [rad] or ``theta_deg``
[deg], a revolution by default), the inputs (the linkage's start values where not
given), every output at them, and the inputs as a title gives them."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..drivers import one_crank
from ..errors import InputError, InputTypeError
from ..printing import number
from ..solver import UNASSEMBLED

if TYPE_CHECKING:  # pragma: no cover
    from ..mechanism import Mechanism

#: the default crank angles: 0, 0.5, ..., 360 degrees (both ends: a closed curve)
N_ANGLES = 721


def crank_angles(theta, theta_deg, scalar: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """``(radians, degrees)`` of the crank angles: ``theta`` [rad] or ``theta_deg``
    [deg], a revolution of :data:`N_ANGLES` if neither."""
    if theta is not None and theta_deg is not None:
        raise InputTypeError("give the crank angle as theta [rad] or as theta_deg [deg], not both")
    if theta is None and theta_deg is None:
        if scalar:
            raise InputTypeError("give the crank angle: theta [rad] or theta_deg [deg]")
        deg = np.linspace(0.0, 360.0, N_ANGLES)
        return np.radians(deg), deg
    given = theta if theta is not None else theta_deg
    if scalar and np.ndim(given) != 0:
        raise InputError(f"the crank angle must be one number, got shape {np.shape(given)}")
    values = np.atleast_1d(np.asarray(given, dtype=float))
    if values.ndim != 1 or not values.size:
        raise InputError(f"the crank angles must be a non-empty 1-D array, got shape "
                         f"{np.shape(given)}")
    if not np.isfinite(values).all():
        raise InputError("the crank angles must be finite")
    if theta is not None:
        return values, np.degrees(values)
    return np.radians(values), values


def input_values(mech: "Mechanism", omega, alpha, loads: Sequence, named: dict) -> dict:
    """``{omega, alpha, <input load>: value}``: what is given, else the start values
    (a load over the cycle given by name too); a linkage driven by time is refused."""
    one_crank(mech, "a plot over crank angles")
    values, given = mech.inputs(omega, alpha, tuple(loads), named)
    return dict(zip(mech.input_names[1:] + given, map(float, values)))


def solve_at(mech: "Mechanism", theta, inputs: dict):
    """Every output, as ``mech.solve`` gives them by default: the balancing effort from
    the reactions (``outputs=("Mb",)`` would take it from the power balance, equal to
    rounding only), so that a plot shows the very numbers of a plain solve."""
    loads = {k: v for k, v in inputs.items() if k not in ("omega", "alpha")}
    return mech.solve(theta, inputs["omega"], inputs["alpha"], **loads)


def inputs_text(mech: "Mechanism", inputs: dict) -> str:
    """``inputs`` as a title gives them: ``ω = 10 rad/s, α = 0 rad/s², ...``; for a
    linkage driven by time each driver's coordinate, and its speed and acceleration
    where they are not 0."""
    units = {"omega": "rad/s", "alpha": "rad/s²", **{load.name: load.unit for load in mech.loads}}
    greek = {"omega": "ω", "alpha": "α"}
    if mech.rates:
        rates = {n for d in mech.drivers for n in d.inputs[1:]}
        units.update((n, u) for d in mech.drivers for n, u in zip(d.inputs, d.units))
        inputs = {k: v for k, v in inputs.items() if k not in rates or v != 0.0}
    return ", ".join(f"{greek.get(k, k)} = {number(v, 6)} {units[k]}" for k, v in inputs.items())


def finite_or_fail(mech: "Mechanism", values: np.ndarray, deg: np.ndarray, sol=None) -> None:
    """A ValueError unless some of ``values`` (at the angles ``deg``) are finite; with
    the array solution ``sol``, saying why its first state has no outputs where that is
    not that the linkage cannot be assembled (friction locks it, ...)."""
    if not np.isfinite(values).any():
        angles = f"{deg.size} crank angles {number(deg[0], 6)}..{number(deg[-1], 6)} deg"
        problems = getattr(sol, "problems", None) or {}
        if problems and UNASSEMBLED not in problems:
            first = min(problems.values(), key=lambda p: p.first)
            raise InputError(f"{mech.name} has no outputs at any of the {angles}: "
                             f"{first.message}")
        raise InputError(f"{mech.name} cannot be assembled at any of the {angles}")
