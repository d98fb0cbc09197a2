"""Run a linkage FMU with fmpy and compare every output with the direct solver.

The inputs cover a revolution (or the longest period of its loads over the cycle) with
time-varying speed and loads (:func:`~linkage_fmu.fmi.run.revolution`); the run goes
step by step (:func:`~linkage_fmu.fmi.run.step_fmu`), so each row holds the outputs of
its own inputs. A linkage that assembles over part of a revolution is checked where it
does; the FMU must discard the other steps.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import ranges
from ..mechanism import Mechanism
from .run import fmu_linkage, revolution, step_fmu


@dataclass(frozen=True)
class CheckResult:
    """Outcome of :func:`check_fmu`: worst relative error and its output, steps run,
    wall time [s], the ranges of the crank angle [deg] where the FMU discarded the
    steps (the linkage does not assemble there), and the steps where the FMU and the
    direct solver disagree on whether there is a solution."""

    model: str
    max_rel_error: float
    worst_output: str
    steps: int
    seconds: float
    unsolved_deg: tuple = ()
    mismatched: int = 0

    def passed(self, tol: float = 1e-9) -> bool:
        return self.max_rel_error <= tol and self.mismatched == 0


def reference(mech: Mechanism, inputs: np.ndarray):
    """The direct (LU) solver's outputs at every row of ``inputs`` (an
    :class:`~linkage_fmu.solver.ArraySolution`: NaN and ``valid = False`` where the
    linkage cannot be assembled)."""
    return mech.solve(*(inputs[n] for n in mech.input_names), method="direct")


def compare(rows, ref, names) -> tuple[float, str]:
    """Worst relative error of the FMU's ``rows`` against ``ref`` (the same rows), and
    the output where it is; each output's error is scaled by its largest magnitude over
    the rows. NaN in both agrees (``eta`` where no power enters); NaN in one is an
    error of NaN.

    Examples
    --------
    >>> compare({"eta": [0.5, float("nan")]}, {"eta": [0.5, float("nan")]}, ["eta"])
    (0.0, '')
    >>> err, where = compare({"eta": [0.5, 0.9]}, {"eta": [0.5, float("nan")]}, ["eta"])
    >>> bool(np.isnan(err)), where
    (True, 'eta')
    """
    worst, where = 0.0, ""
    for name in names:
        got, expected = (np.asarray(a[name], dtype=float) for a in (rows, ref))
        both = np.isnan(got) & np.isnan(expected)
        got, expected = got[~both], expected[~both]
        scale = np.max(np.abs(expected), initial=0.0)
        diff = np.max(np.abs(got - expected), initial=0.0)
        err = diff / scale if scale > 0 else diff
        if not err <= worst:  # also catches NaN
            worst, where = err, name
    return worst, where


def check_fmu(fmu: str | Path, steps: int = 360) -> CheckResult:
    """Run ``fmu`` with fmpy over :func:`~linkage_fmu.fmi.run.revolution` of its own
    linkage, step by step, and compare every output with the direct solver where the
    linkage assembles; where it does not, the FMU must discard the step (the result
    says over which angles, ``unsolved_deg``, and counts the rows where the FMU and the
    solver disagree on it, ``mismatched``).

    Raises
    ------
    ValueError
        The linkage assembles at none of the angles of the run.
    """
    mech = fmu_linkage(fmu)
    u = revolution(mech, steps)
    names = list(mech.output_names + mech.diagnostic_names)
    t0 = time.perf_counter()
    rows, _ = step_fmu(fmu, u, None, names)
    seconds = time.perf_counter() - t0
    ref = reference(mech, u[:-1])
    valid = np.asarray(ref.valid)
    if not valid.any():
        raise ValueError(f"{Path(fmu).name}: {mech.name} assembles at none of the {len(valid)} "
                         "crank angles of the check")
    solved = rows["solved"].to_numpy()
    both = solved & valid
    err, where = compare({n: rows[n].to_numpy()[both] for n in names},
                         {n: np.asarray(ref[n])[both] for n in names}, names)
    unsolved = ranges.runs(np.degrees(u["theta"][:-1]), ~solved)
    return CheckResult(mech.description.model, float(err), where, len(rows), seconds,
                       tuple(unsolved), int(np.sum(solved != valid)))


def write_crosscheck(out: str | Path, mech: Mechanism, steps: int = 360) -> list[Path]:
    """Write the FMI cross-check files ``<M>_in.csv``, ``<M>_ref.csv``, ``<M>_ref.opt``.

    The reference is the direct solver at each row's own inputs (the exact
    direct-feedthrough answer); an importer that samples outputs after the step, as
    fmpy does, sees it one row later.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    model = mech.description.model
    u = revolution(mech, steps)
    ref = reference(mech, u)
    names = mech.output_names + mech.diagnostic_names

    def write(path: Path, columns: dict) -> None:
        header = ",".join(f'"{n}"' for n in columns)
        rows = np.column_stack([np.asarray(v, dtype=float) for v in columns.values()])
        np.savetxt(path, rows, delimiter=",", header=header, comments="", fmt="%.17g")

    write(out / f"{model}_in.csv", {n: u[n] for n in ("time",) + mech.input_names})
    write(out / f"{model}_ref.csv", {"time": u["time"], **{n: ref[n] for n in names}})
    h = float(u["time"][1] - u["time"][0])
    (out / f"{model}_ref.opt").write_text(
        f"StartTime,0.0\nStopTime,{float(u['time'][-1])!r}\nStepSize,{h!r}\nRelTol,1e-9\n")
    return [out / f"{model}{s}" for s in ("_in.csv", "_ref.csv", "_ref.opt")]
