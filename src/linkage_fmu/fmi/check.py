"""Run a linkage FMU with fmpy and compare every output with the direct solver.

The inputs cover a revolution (or the longest period of its loads over the cycle) with
time-varying speed and loads (:func:`~linkage_fmu.fmi.run.revolution`); the run goes
step by step (:func:`~linkage_fmu.fmi.run.step_fmu`), so each row holds the outputs of
its own inputs. A linkage that assembles over part of a revolution is checked where it
does; the FMU must discard the other steps.

A drive FMU (``<Model>Drive``, :func:`check_drive`) runs the same time under a constant
moment on its crank: its motion is compared with
:meth:`Mechanism.simulate <linkage_fmu.mechanism.Mechanism.simulate>`, and its outputs
with the direct solver at its own states.
"""

from __future__ import annotations

import math
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import ranges
from ..errors import AssemblyError, InputError, SelfLockingError, SingularPositionError
from ..mechanism import Mechanism
from .run import fmu_kind, revolution, step_fmu

#: the largest relative error of an FMU's outputs against the direct solver that its
#: check accepts, by flavour (the pythonfmu FMU's outputs cross Python and its C layer;
#: the native FMU computes the library's kernels in C), and a drive FMU's outputs at its
#: own states (measured 2.1e-14 for the four-bar)
TOLERANCE = {"pythonfmu": 1e-9, "native": 1e-12, "drive": 1e-9}


@dataclass(frozen=True)
class CheckResult:
    """Outcome of :func:`check_fmu`: worst relative error and its output, steps run,
    wall time [s], the ranges of the crank angle [deg] where the FMU discarded the
    steps (the linkage does not assemble there), the steps where the FMU and the
    direct solver disagree on whether there is a solution, and the tolerance of the
    outputs' error the check accepts (:data:`TOLERANCE`)."""

    model: str
    max_rel_error: float
    worst_output: str
    steps: int
    seconds: float
    unsolved_deg: tuple = ()
    mismatched: int = 0
    #: a drive FMU's: the largest error of theta and omega against ``simulate``, relative
    #: to 1 + |value| (None for the others)
    motion_error: float | None = None
    tolerance: float = TOLERANCE["pythonfmu"]

    def passed(self, tol: float | None = None) -> bool:
        """Whether the outputs are within ``tol`` (default :attr:`tolerance`), the FMU and
        the direct solver agree on every step's solution, and a drive FMU's motion is
        within :data:`MOTION_BOUND` of ``simulate``'s."""
        tol = self.tolerance if tol is None else tol
        return (self.max_rel_error <= tol and self.mismatched == 0
                and (self.motion_error is None or self.motion_error <= MOTION_BOUND))

    def verdict(self) -> str:
        """The outcome in words, against what it was checked and how closely (the
        command's line, after the FMU's path).

        Examples
        --------
        >>> print(CheckResult("FourBar", 3.1e-16, "F21x", 360, 0.41).verdict())
        ok: the outputs of FourBar are within 3.1e-16 (F21x) of the direct solver's over 360
        steps, relative to the largest output of its unit (the tolerance 1e-09)
        """
        within = (f"within {self.max_rel_error:.2g} ({self.worst_output or 'every output'}) "
                  f"of the direct solver's")
        if self.motion_error is None:
            text = (f"the outputs of {self.model} are {within} over {self.steps} steps, "
                    f"relative to the largest output of its unit (the tolerance "
                    f"{self.tolerance:g})")
        else:
            text = (f"the motion of {self.model} is within {self.motion_error:.2g} of "
                    f"simulate's (theta and omega, relative to 1 + |value|; the tolerance "
                    f"{MOTION_BOUND:g}) and its outputs at its states are {within} (relative "
                    f"to each output's largest; the tolerance {self.tolerance:g}), over "
                    f"{self.steps} steps")
        if self.mismatched and self.motion_error is None:
            text += (f"; at {self.mismatched} steps the FMU and the direct solver disagree on "
                     "whether there is a solution")
        elif self.mismatched:
            text += "; the FMU discarded a step where simulate goes on"
        return f"{'ok' if self.passed() else 'FAILED'}: {text}"


#: the drive FMU's integrator tolerance in a check, and the bound on the error of its
#: motion against ``simulate`` (at rtol = atol = 1e-13), relative to 1 + |value|: the
#: global error of a local-error controller (measured over the presets and examples:
#: at most 4.5e-8, the crank shaper, whose J_red swings 200-fold, the others 5e-10)
DRIVE_TOLERANCE, MOTION_BOUND = 1e-12, 1e-6


def reference(mech: Mechanism, inputs: np.ndarray):
    """The direct (LU) solver's outputs at every row of ``inputs`` (an
    :class:`~linkage_fmu.solver.ArraySolution`: NaN and ``valid = False`` where the
    linkage cannot be assembled)."""
    return mech.solve(*(inputs[n] for n in mech.input_names), method="direct")


def compare(rows, ref, names, units: dict | None = None) -> tuple[float, str]:
    """Worst relative error of the FMU's ``rows`` against ``ref`` (the same rows), and
    the output where it is; each output's error is scaled by its largest magnitude over
    the rows, or with ``units`` (output -> unit) by the largest of the outputs of its
    unit (a small force computed from large ones, as a cylinder's pair carries beside
    its thrust, has their rounding). NaN in both agrees (``eta`` where no power
    enters); NaN in one is an error of NaN.

    Examples
    --------
    >>> compare({"eta": [0.5, float("nan")]}, {"eta": [0.5, float("nan")]}, ["eta"])
    (0.0, '')
    >>> err, where = compare({"eta": [0.5, 0.9]}, {"eta": [0.5, float("nan")]}, ["eta"])
    >>> bool(np.isnan(err)), where
    (True, 'eta')
    >>> err, where = compare({"F": [1.001], "G": [1000.0]}, {"F": [1.0], "G": [1000.0]},
    ...                      ["F", "G"], {"F": "N", "G": "N"})
    >>> round(float(err), 12), where
    (1e-06, 'F')
    """
    pairs, peaks = {}, {}
    for name in names:
        got, expected = (np.asarray(a[name], dtype=float) for a in (rows, ref))
        both = np.isnan(got) & np.isnan(expected)
        pairs[name] = got[~both], expected[~both]
        unit = units.get(name, name) if units else name
        peaks[unit] = max(peaks.get(unit, 0.0),
                          np.max(np.abs(pairs[name][1]), initial=0.0))
    worst, where = 0.0, ""
    for name, (got, expected) in pairs.items():
        scale = peaks[units.get(name, name) if units else name]
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
    mech, drive = fmu_kind(fmu)
    if drive:
        return check_drive(fmu, mech, steps)
    with zipfile.ZipFile(fmu) as archive:  # a native FMU carries its C
        native = "sources/model.c" in archive.namelist()
    u = revolution(mech, steps)
    names = list(mech.output_names + mech.diagnostic_names)
    t0 = time.perf_counter()
    rows, _ = step_fmu(fmu, u, None, names)
    seconds = time.perf_counter() - t0
    ref = reference(mech, u[:-1])
    valid = np.asarray(ref.valid)
    if not valid.any():
        raise InputError(f"{Path(fmu).name}: {mech.name} assembles at none of the {len(valid)} "
                         "crank angles of the check")
    solved = rows["solved"].to_numpy()
    both = solved & valid
    err, where = compare({n: rows[n].to_numpy()[both] for n in names},
                         {n: np.asarray(ref[n])[both] for n in names}, names,
                         {n: mech.output_info[n][0] for n in names})
    # where the FMU discards: the crank angles (deg), or for a linkage driven by time
    # the times (s)
    along = u["time"] if mech.rates else np.degrees(u["theta"])
    unsolved = ranges.runs(along[:-1], ~solved)
    return CheckResult(mech.description.model, float(err), where, len(rows), seconds,
                       tuple(unsolved), int(np.sum(solved != valid)),
                       tolerance=TOLERANCE["native" if native else "pythonfmu"])


def check_drive(fmu: str | Path, mech: Mechanism, steps: int = 360) -> CheckResult:
    """Run the drive FMU ``fmu`` of ``mech`` with fmpy, step by step over the time of
    :func:`~linkage_fmu.fmi.run.revolution` from the linkage's start angle and speed (2 pi
    rad/s where it is 0), under the constant moment whose work over a revolution is
    twice the start's kinetic energy (``J_red`` averaged over it), the loads at their
    start values, at the tolerance
    :data:`DRIVE_TOLERANCE`. Its ``theta`` and ``omega`` are compared with
    :meth:`~linkage_fmu.mechanism.Mechanism.simulate` at ``rtol = atol = 1e-13``
    (``motion_error``), and every output at its own states with the direct solver
    (``max_rel_error``). Where the motion reaches an angle at which the linkage cannot
    be assembled the FMU must discard the step and ``simulate`` must stop in it
    (``mismatched`` counts the one that does not); the steps before it are checked and
    ``unsolved_deg`` holds the angle it stopped at.

    Raises
    ------
    ValueError
        The linkage assembles at none of the angles of a revolution.
    """
    u = revolution(mech, steps)
    t = u["time"]
    theta0 = mech.start["theta"]
    omega0 = mech.start["omega"] or 2.0 * np.pi
    loads = {ld.name: ld.start for ld in mech.input_loads}
    turn = mech.solve(theta0 + np.linspace(0.0, 2.0 * np.pi, 360, endpoint=False), omega0,
                      0.0, **loads, outputs=["J_red"])
    if not np.asarray(turn.valid).any():
        raise InputError(f"{Path(fmu).name}: {mech.name} assembles at none of 360 crank "
                         "angles of a revolution")
    # over a revolution, tau's work is twice the start's kinetic energy: the speed rises
    # to about sqrt(3) omega0, where the linkage's own torques do not hold it
    tau = float(np.nanmean(turn["J_red"])) * omega0 * abs(omega0) / (2.0 * math.pi)
    inputs = np.zeros(t.size, dtype=[(n, np.float64) for n in ("time", "tau", *loads)])
    inputs["time"], inputs["tau"] = t, tau
    for name, value in loads.items():
        inputs[name] = value
    names = ["theta", "omega", "alpha", *mech.output_names, *mech.diagnostic_names]
    start = {"theta0": theta0, "omega0": omega0, "tolerance": DRIVE_TOLERANCE}
    t0 = time.perf_counter()
    rows, _ = step_fmu(fmu, inputs, start, names, stop=True)
    seconds = time.perf_counter() - t0
    solved = rows["solved"].to_numpy()
    reached = int(np.argmin(solved)) if not solved.all() else len(solved)
    mismatched, unsolved = 0, ()
    if reached < len(solved):  # the FMU stopped in step `reached`: simulate must too
        try:  # at simulate's default tolerances: at 1e-13 it creeps to the limit (73 s)
            mech.simulate(tau, t[:reached + 2], theta0, omega0, **loads)
            mismatched = 1
        except (AssemblyError, SingularPositionError, SelfLockingError, RuntimeError):
            pass  # it cannot go on either: the linkage does not assemble, or locks
        where = float(np.degrees(rows["theta"].iloc[reached - 1] if reached else theta0))
        unsolved = ((where, where),)
    motion_error = 0.0
    if reached > 0:
        ref = mech.simulate(tau, t[:reached + 1], theta0, omega0, rtol=1e-13, atol=1e-13,
                            **loads).iloc[1:]
        for name in ("theta", "omega"):
            got, expected = rows[name].to_numpy()[:reached], ref[name].to_numpy()
            err = float(np.max(np.abs(got - expected) / (1.0 + np.abs(expected))))
            motion_error = err if not err <= motion_error else motion_error
    err, worst = 0.0, ""
    if reached > 0:
        done = rows.iloc[:reached]
        own = mech.solve(done["theta"].to_numpy(), done["omega"].to_numpy(),
                         done["alpha"].to_numpy(), **loads, method="direct")
        outputs = list(mech.output_names + mech.diagnostic_names)
        err, worst = compare({n: done[n].to_numpy() for n in outputs}, own, outputs)
    return CheckResult(f"{mech.description.model}Drive", float(err), worst, reached,
                       seconds, unsolved, mismatched, motion_error, TOLERANCE["drive"])


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
