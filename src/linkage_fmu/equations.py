"""The equilibrium equations of a linkage at one state, as the source documents write
them: each moving link's ``ΣFx = 0``, ``ΣFy = 0`` and ``ΣM = 0`` about its centre of
mass, assembled into ``A x = b`` with every row and column labelled, in SI units, and
solved (:func:`equations`).

The system is the one the direct solver solves (:func:`~linkage_fmu.kinetostatics.
equilibrium_entries`), with its scaling undone: a moment row in N.m, a prismatic pair's
couple and a moment effort in N.m. The unknowns are each pair's two reaction
components, the action of its first body on its second (``Fx_<pair>``, ``Fy_<pair>``
for a revolute pair, ``N_<pair>``, ``M_<pair>`` for a prismatic one, as a description's
expressions name them), then each effort.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import evaluation, kinetostatics
from .errors import InputError
from .loads import wrenches
from .numerics import SCALAR


@dataclass(frozen=True)
class Equations:
    """``A x = b`` of a linkage at one state: ``unknowns`` (column labels), ``rows``
    (row labels, ``"link 2: ΣFx"``), ``A`` and ``b`` (numpy, SI), and ``solution``
    (unknown -> value, ``A \\ b``); :attr:`residual`, :attr:`det` and :attr:`cond`;
    :meth:`to` writes it out."""

    name: str
    unknowns: tuple
    rows: tuple
    A: np.ndarray
    b: np.ndarray

    @property
    def solution(self) -> dict:
        return dict(zip(self.unknowns, np.linalg.solve(self.A, self.b).tolist()))

    @property
    def residual(self) -> float:
        """``|A x - b|`` (largest entry) at the solution."""
        x = np.array(list(self.solution.values()))
        return float(np.max(np.abs(self.A @ x - self.b)))

    @property
    def det(self) -> float:
        return float(np.linalg.det(self.A))

    @property
    def cond(self) -> float:
        return float(np.linalg.cond(self.A))

    def to(self, fmt: str = "text") -> str:
        """The system as text: ``"text"`` (each equation's nonzero a(i, j) and b(i), as
        the hinged four-bar worked example tables them) or ``"markdown"`` (the same
        table), then the solution."""
        if fmt not in ("text", "markdown"):
            raise InputError(f"format {fmt!r}: the formats are text, markdown")
        lines = [f"{self.name}: A x = b, {len(self.rows)} equations"]
        if fmt == "markdown":
            lines = [f"**{lines[0]}**", "", "| i | equation | a(i, j) | b(i) |",
                     "|---|---|---|---|"]
        for i, row in enumerate(self.rows):
            terms = " + ".join(f"{self.A[i, j]:.6g} {u}" for j, u in enumerate(self.unknowns)
                               if self.A[i, j] != 0.0) or "0"
            if fmt == "markdown":
                lines.append(f"| {i + 1} | {row} | {terms} | {self.b[i]:.6g} |")
            else:
                lines.append(f"{i + 1:3d}  {row:22s} {terms} = {self.b[i]:.6g}")
        lines += ["", "solution:"] + [f"  {u} = {v:.6g}" for u, v in self.solution.items()]
        lines.append(f"residual {self.residual:.3g}, det A {self.det:.6g}, cond {self.cond:.3g}")
        return "\n".join(lines) + "\n"


def equations(mech, theta=None, omega=None, alpha=None, *loads, **named) -> Equations:
    """The labelled system ``A x = b`` of ``mech`` at one state (its inputs as
    ``Mechanism.solve`` takes them, one value each), solved.

    Examples
    --------
    The scotch yoke worked example's eight equations at 60 deg, 10 rad/s, Fr 400 N:

    >>> import math
    >>> from linkage_fmu import presets
    >>> yoke = presets.get("scotch_yoke")
    >>> eq = equations(yoke, math.radians(60), 10.0, load=400.0)
    >>> len(eq.rows), eq.rows[:3], eq.unknowns[-1]
    (9, ('link 1: ΣFx', 'link 1: ΣFy', 'link 1: ΣM about A'), 'Mb')
    >>> round(eq.solution["Mb"], 4), round(eq.solution["Fy_B"], 4)
    (15.6699, 278.7564)
    """
    if mech.friction.active:
        raise InputError(f"{mech.name}: its equations with friction are not written yet; "
                         "set every mu to 0")
    if mech.rates:
        values, given = mech.input_table.every((theta, omega, alpha, *loads), named)
    else:
        rest, given = mech.inputs(omega, alpha, loads, named)
        values = [theta, *rest]
    if any(np.ndim(v) for v in values):
        raise InputError("equations are of one state: give each input one value")
    values = [float(v) for v in values]
    theta, omega, alpha, loads = evaluation.split(mech, values)
    if mech.rates:
        st = evaluation.kinematics(mech, theta, 2, SCALAR, tuple(zip(omega, alpha)))
        omega, alpha = 1.0, 0.0
    else:
        st = evaluation.kinematics(mech, theta, 2, SCALAR)
    W = wrenches(mech, st, omega, alpha, evaluation.every_load(mech, given, loads), False)
    n, entries, rhs = kinetostatics.equilibrium_entries(mech, st, W)
    A, b = np.zeros((n, n)), np.zeros(n)
    for r, c, v in entries:
        A[r, c] += v
    for r, v in rhs:
        b[r] += v
    L = mech.length_scale
    rows, columns = np.ones(n), np.ones(n)  # the scaling of equilibrium_entries, undone
    rows[2::3] = L
    names = []
    for k, j in enumerate(mech.joints):
        names += [f"{c}_{j.name}" for c in j.components]
        columns[2 * k + 1] = j.column_scale(L)
    for k, e in enumerate(mech.efforts):
        names.append(e.name)
        columns[2 * len(mech.joints) + k] = L if e.direction is None else 1.0
    labels = []
    for body in mech.bodies:
        labels += [f"link {body.name}: ΣFx", f"link {body.name}: ΣFy",
                   f"link {body.name}: ΣM about {mech.cg[body.name]}"]
    return Equations(mech.name, tuple(names), tuple(labels),
                     rows[:, None] * A / columns[None, :], rows * b)
