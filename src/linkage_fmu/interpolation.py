"""Outputs interpolated from a table over the crank angle: speed traded for accuracy.

At a given crank angle every output is linear in ``omega**2``, ``alpha`` and each load
(inertia is ``m (x'' omega**2 + x' alpha)``, a load enters once), plus a part from
gravity. :class:`AngleTable` solves the mechanism once on a uniform grid of crank
angles for each of these parts, and then evaluates any state by cubic
(4-point Lagrange) interpolation in the angle. A load over the cycle is a part of
unit magnitude too, times its exact value at the state (a table's spline, or its
expression), so that a load of any period is exact. Its error falls like ``size**-4`` for
smooth outputs and grows near toggles, where the outputs vary fast; measure it with
:mod:`linkage_fmu.precise` before trusting a size.
"""

from __future__ import annotations

import math

import numpy as np

from .errors import InputError
from .numerics import ARRAY, finite_array


class AngleTable:
    """The outputs of ``mech`` tabulated over one crank revolution.

    Parameters
    ----------
    mech : Mechanism
        The linkage, without friction in its joints (every ``mu`` 0); it must be
        assembled at every grid angle to give finite values there (angles next to an
        unassemblable one interpolate to NaN).
    size : int
        Number of grid angles over ``[0, 2 pi)``, at least 4.
    method : {'closed_form', 'direct'}
        Solver used to fill the table.

    Raises
    ------
    ValueError
        ``size`` is not an integer >= 4; the linkage has friction in its joints.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> mech = presets.get("four_bar")
    >>> table = AngleTable(mech, size=4096)
    >>> exact = mech.solve(0.7, omega=10.0, alpha=3.0, load=2.0)["Mb"]
    >>> bool(abs(table(0.7, 10.0, 3.0, 2.0)["Mb"] - exact) < 1e-9 * abs(exact))
    True
    """

    def __init__(self, mech, size: int = 4096, method: str = "closed_form"):
        if not isinstance(size, int) or size < 4:
            raise InputError(f"size must be an integer >= 4, got {size!r}")
        if mech.friction.active:
            # |R| and the signs of motion: no sum of parts, and which states friction
            # locks depends on the whole state, not on its parts
            raise InputError(f"{mech.name}: friction in its joints makes the outputs "
                             "nonlinear in omega**2, alpha and the loads, which an "
                             "AngleTable adds up: solve the states themselves (mech.solve), "
                             "or tabulate the linkage with every mu 0")
        self.mech = mech
        self.names = mech.output_names
        self.size = size
        theta = np.arange(size) * (2.0 * math.pi / size)
        names = [load.name for load in mech.input_loads + mech.computed_loads]

        def part(omega, alpha, which=None):
            loads = {n: 1.0 if n == which else 0.0 for n in names}
            sol = mech.solve(theta, omega, alpha, method=method, outputs=self.names, **loads)
            return np.array([sol[n] for n in self.names])

        base = part(0.0, 0.0)  # gravity
        #: (3 + loads, outputs, size): gravity, per omega**2, per alpha, per unit of each
        #: load (the input loads, then the loads over the cycle)
        self.parts = np.stack([base, part(1.0, 0.0) - base, part(0.0, 1.0) - base]
                              + [part(0.0, 0.0, n) - base for n in names])

    def __call__(self, theta, omega=None, alpha=None, *loads, **named_loads) -> dict:
        """Interpolated outputs at the given states (floats or arrays, broadcast); an
        input not given takes its start value, as in :meth:`~linkage_fmu.Mechanism.solve`.

        Returns
        -------
        dict
            Output name -> float or ndarray of the broadcast shape.
        """
        mech = self.mech
        values, given = mech.inputs(omega, alpha, loads, named_loads)
        values = [theta, *values]
        if mech.computed_loads:  # each at its value over the cycle, unless given
            values = values[:len(mech.input_names)] + self._over_cycle(
                theta, dict(zip(given, values[len(mech.input_names):])))
        names = mech.input_names + tuple(ld.name for ld in mech.computed_loads)
        arrays = np.broadcast_arrays(*(finite_array(n, v) for n, v in zip(names, values)))
        shape = arrays[0].shape
        one_scene = all(np.ptp(a) == 0.0 for a in arrays[1:]) if arrays[0].size else True
        if one_scene:
            # one scene for all angles: combine the parts on the grid, interpolate once;
            # rows of (grid angle -> all outputs) make each lookup one contiguous read
            w, a, *f = (float(v.flat[0]) if v.size else 0.0 for v in arrays[1:])
            grids = [np.tensordot((1.0, w * w, a, *f), self.parts, axes=1).T.copy()]
        else:
            grids = [p.T.copy() for p in self.parts]
        flat = [v.reshape(-1) for v in arrays]  # views where possible
        out = np.empty((flat[0].size, len(self.names)))
        for start in range(0, flat[0].size, 8192):
            part = slice(start, start + 8192)
            u = flat[0][part] * (self.size / (2.0 * math.pi))
            i = np.floor(u)
            t = (u - i)[:, None]
            i = i.astype(np.int64) % self.size
            tm, tp, t2 = t - 1.0, t + 1.0, t - 2.0
            rows = [(i + k) % self.size for k in (-1, 1, 2)]
            vals = [(-t * tm * t2 / 6.0) * g[rows[0]] + (tp * tm * t2 / 2.0) * g[i]
                    - (tp * t * t2 / 2.0) * g[rows[1]] + (tp * t * tm / 6.0) * g[rows[2]]
                    for g in grids]
            if one_scene:
                out[part] = vals[0]
            else:
                w, a, *f = (v[part][:, None] for v in flat[1:])
                total = vals[0] + w * w * vals[1] + a * vals[2]
                for fk, vk in zip(f, vals[3:]):
                    total = total + fk * vk
                out[part] = total
        if not shape:
            return {n: float(out[0, k]) for k, n in enumerate(self.names)}
        return {n: out[:, k].reshape(shape) for k, n in enumerate(self.names)}

    def _over_cycle(self, theta, given: dict) -> list:
        """The magnitude of each load over the cycle at ``theta``: as ``given``, or
        computed (the positions it uses exact, not interpolated)."""
        mech = self.mech
        theta = finite_array("theta", theta)
        st, out = None, []
        for load in mech.computed_loads:
            if load.name in given:
                out.append(given[load.name])
                continue
            if load.positions and st is None:
                st = mech.kinematics(theta, order=0)
            out.append(load.magnitude(theta, ARRAY, st.p if st else None))
        return out
