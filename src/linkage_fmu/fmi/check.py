"""Run a linkage FMU with fmpy and compare every output with the direct solver.

The inputs cover one revolution with time-varying speed and load. fmpy's
co-simulation loop sets the inputs at ``t``, calls doStep and samples the outputs at
``t + h``; for a direct-feedthrough model the row at ``t_k`` (``k >= 1``) therefore
holds the outputs for the inputs of ``t_(k-1)``. :func:`compare` accounts for that.
"""

from __future__ import annotations

import math
import time
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..mechanism import Mechanism
from ..spec import Description

_NOMINAL_LOAD = {"N": 100.0, "N.m": 10.0}


@dataclass(frozen=True)
class CheckResult:
    """Outcome of :func:`check_fmu`: worst relative error, steps run, wall time [s]."""

    model: str
    max_rel_error: float
    worst_output: str
    steps: int
    seconds: float

    def passed(self, tol: float = 1e-9) -> bool:
        return self.max_rel_error <= tol


def fmu_linkage(fmu: str | Path) -> Mechanism:
    """The linkage an FMU built by :func:`~linkage_fmu.fmi.build.build_fmu` computes: its
    bundled description file, with the FMU's parameter start values."""
    with zipfile.ZipFile(fmu) as archive:
        root = ET.fromstring(archive.read("modelDescription.xml"))
        model = root.find("CoSimulation").get("modelIdentifier")
        name = f"resources/{model}.toml"
        text = archive.read(name).decode("utf-8")
    return Description.from_toml(text, f"{fmu}:{name}").build()


def revolution(mech: Mechanism, steps: int = 360) -> np.ndarray:
    """Inputs over one revolution: speed +-20 %, each load +-50 % around the start values
    (a load whose start value is zero varies around 100 N or 10 N.m).

    Returns a structured array with fields ``time`` and the linkage's inputs, one row
    per communication point (``steps + 1`` rows), as fmpy's ``simulate_fmu`` takes it.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> u = revolution(presets.get("four_bar"), steps=4)
    >>> u.dtype.names, round(float(u["theta"][-1]), 12) == round(2 * math.pi, 12)
    (('time', 'theta', 'omega', 'alpha', 'load'), True)
    """
    start = mech.description.inputs
    w0 = start.get("omega", 0.0) or 2.0 * math.pi
    period = 2.0 * math.pi / abs(w0)
    t = np.linspace(0.0, period, steps + 1)
    k = 2.0 * math.pi / period
    u = np.zeros(steps + 1, dtype=[(n, np.float64) for n in ("time",) + mech.input_names])
    u["time"] = t
    u["theta"] = start.get("theta", 0.0) + w0 * (t - 0.2 / k * (np.cos(k * t) - 1.0))
    u["omega"] = w0 * (1.0 + 0.2 * np.sin(k * t))
    u["alpha"] = w0 * 0.2 * k * np.cos(k * t)
    for j, load in enumerate(mech.loads):
        load0 = load.start or _NOMINAL_LOAD.get(load.unit, 1.0)
        u[load.name] = load0 * (1.0 + 0.5 * np.sin((2.0 + j) * k * t))
    return u


def reference(mech: Mechanism, inputs: np.ndarray) -> dict:
    """The direct (LU) solver's outputs at every row of ``inputs``."""
    return dict(mech.solve(*(inputs[n] for n in mech.input_names), method="direct"))


def compare(result: np.ndarray, ref: dict, names) -> tuple[float, str]:
    """Worst relative error of fmpy ``result`` rows against ``ref`` (one-step lag handled).

    Each output's error is scaled by its largest magnitude over the run.
    """
    worst, where = 0.0, ""
    for name in names:
        expected = np.concatenate([ref[name][:1], ref[name][:-1]])  # row k <- inputs of k-1
        scale = np.max(np.abs(expected))
        diff = np.max(np.abs(result[name] - expected))
        err = diff / scale if scale > 0 else diff
        if not err <= worst:  # also catches NaN
            worst, where = err, name
    return worst, where


def check_fmu(fmu: str | Path, steps: int = 360) -> CheckResult:
    """Simulate ``fmu`` with fmpy over :func:`revolution` of its own linkage and compare
    every output with the direct solver."""
    from fmpy import simulate_fmu

    mech = fmu_linkage(fmu)
    u = revolution(mech, steps)
    names = list(mech.output_names + mech.diagnostic_names)
    h = float(u["time"][1] - u["time"][0])
    t0 = time.perf_counter()
    result = simulate_fmu(str(fmu), start_time=0.0, stop_time=float(u["time"][-1]),
                          output_interval=h, input=u, output=names)
    seconds = time.perf_counter() - t0
    err, where = compare(result, reference(mech, u), names)
    return CheckResult(mech.description.model, float(err), where, len(result) - 1, seconds)


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
