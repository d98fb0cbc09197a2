"""The diagnostics of a state: the transmission angle of each dyad and an estimate of the
condition number of the outputs, and the words for a singular position.

Examples
--------
>>> from linkage_fmu import presets
>>> mech = presets.get("four_bar")
>>> sorted(values(mech, mech.kinematics(0.3, order=0), ("mu_C", "cond")))
['cond', 'mu_C']
"""

from __future__ import annotations

import math
from typing import Iterable

import numpy as np

from . import kinetostatics, numerics
from .groups import KinematicState
from .kernels.trace import Reason


def values(mech, st: KinematicState, wanted: Iterable[str] = ("cond",)) -> dict:
    """The transmission angles ``mu_<joint>`` and the condition estimate ``cond``
    named in ``wanted``, at the kinematic state ``st`` (positions; ``cond`` of a
    linkage whose effort is not on the crank needs first-order coefficients)."""
    out = {}
    cond = mech.offset_scale  # 1.0 unless a centre of mass lies beyond length_scale
    for d in mech.dyads:
        mu, kappa = d.transmission(st, mech.length_scale)
        out[f"mu_{d.key}"] = mu
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
            return f"the dyad at {d.key} is at a toggle"
    if not mech.effort_on_crank and not kinetostatics.effort_coefficient(mech, st):
        return "the link of the balancing effort does not move"
    return "the equations have no unique solution"


def singular_detail(mech, st: KinematicState) -> str:
    """The transmission angles at a singular position ``st``, for a message."""
    parts = [f"mu_{d.key} = {d.transmission(st, mech.length_scale)[0]:.3g} rad"
             for d in mech.dyads]
    return ("the equations have no unique solution (transmission angles: "
            + ", ".join(parts) + "); the balancing effort or reactions are unbounded")
