"""The diagnostics of a state: the transmission angle of each dyad, an estimate of the
condition number of the outputs, the inertia reduced to the crank and its derivative
(functions of the position alone), and the words for a singular position.

Examples
--------
>>> from linkage_fmu import presets
>>> mech = presets.get("four_bar")
>>> sorted(values(mech, mech.kinematics(0.3, order=0), ("gamma_C", "cond")))
['cond', 'gamma_C']
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from . import inertia, kinetostatics, numerics
from .groups import KinematicState
from .kernels.trace import Reason

#: the diagnostics every linkage has, after the transmission angle of each dyad
NAMES = ("cond", "J_red", "dJ_red")


def info(mech) -> dict:
    """Diagnostic name -> (unit, description) for the linkage ``mech``."""
    out = {f"gamma_{d.key}": ("rad", f"transmission angle of the group at {d.key} (0 or "
                                     "pi: toggle)") for d in mech.dyads}
    out["cond"] = ("1", "estimated condition number of the outputs, including the scale of "
                        "the centre-of-mass offsets: relative rounding error about cond x "
                        "1e-16 (inf: singular)")
    out["J_red"] = ("kg.m2", "inertia reduced to the crank (kinetic energy J_red omega^2/2)")
    out["dJ_red"] = ("kg.m2/rad", "derivative of J_red with respect to theta")
    return out


def order(mech, wanted: Iterable[str]) -> int:
    """The order of the kinematics the diagnostics in ``wanted`` need: 2 for ``dJ_red``,
    1 for ``J_red`` (and ``cond`` of a linkage whose effort is not on the crank), else
    0 (positions)."""
    if "dJ_red" in wanted:
        return 2
    return int("J_red" in wanted or ("cond" in wanted and not mech.effort_on_crank))


def values(mech, st: KinematicState, wanted: Iterable[str] = ("cond",)) -> dict:
    """The transmission angles ``gamma_<joint>``, the condition estimate ``cond``, the
    reduced inertia ``J_red`` and its derivative ``dJ_red`` named in ``wanted``, at the
    kinematic state ``st`` (of the :func:`order` they need)."""
    out = {}
    if "J_red" in wanted or "dJ_red" in wanted:
        out["J_red"], out["dJ_red"] = inertia.at_state(mech, st, "dJ_red" in wanted)
    cond = mech.offset_scale  # 1.0 unless a centre of mass lies beyond length_scale
    for d in mech.dyads:
        gamma, kappa = d.transmission(st, mech.length_scale)
        out[f"gamma_{d.key}"] = gamma
        # kappa twice: the dyad's position amplifies rounding by kappa, and its
        # equilibrium (whose forces grow like kappa) amplifies that angle error again
        cond = cond * kappa * kappa
    if not mech.effort_on_crank and "cond" in wanted:
        # effort on another link/slider: its own motion q' divides the power balance
        q = st.xp.abs(kinetostatics.effort_coefficient(mech, st))
        scale = 1.0 if mech.effort.direction is None else mech.crank.length
        if st.xp.scalar:
            moves = bool(q)
            numerics.label(q, Reason("singular", "the link of the balancing effort does "
                                                 "not move"))
            cond = cond * scale / q if moves else math.inf
        else:
            cond = cond * scale / q
    if not st.xp.scalar and st.invalid is not None:
        cond = np.where(st.invalid, np.nan, cond)
    out["cond"] = cond
    return {k: v for k, v in out.items() if k in wanted}


def singular_what(mech, st: KinematicState) -> str:
    """Why the equations are singular at the position ``st`` (one state), in the
    words of the kernels' guards: the first dyad at a toggle, a balancing effort
    that cannot move, or no unique solution."""
    for d in mech.dyads:
        if math.isinf(d.transmission(st, mech.length_scale)[1]):
            # a group with its own words for it (a closure) says them as its kernels do
            return getattr(d, "singular", f"the dyad at {d.key} is at a toggle")
    if not mech.effort_on_crank and not kinetostatics.effort_coefficient(mech, st):
        return "the link of the balancing effort does not move"
    return "the equations have no unique solution"


def singular_detail(mech, st: KinematicState) -> str:
    """The transmission angles at a singular position ``st``, for a message."""
    parts = [f"gamma_{d.key} = {d.transmission(st, mech.length_scale)[0]:.3g} rad"
             for d in mech.dyads]
    return ("the equations have no unique solution (transmission angles: "
            + ", ".join(parts) + "); the balancing effort or reactions are unbounded")
