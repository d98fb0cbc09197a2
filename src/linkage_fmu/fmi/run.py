"""Run an FMU of a linkage with fmpy and get rows that cannot mislead: each row holds
inputs and the outputs computed from exactly those inputs, and a run that stops early
raises, naming the step and the FMU's reason.

fmpy's ``simulate_fmu`` sets the inputs at ``t``, calls doStep and samples at ``t + h``:
its row at ``t_k`` holds the outputs for the inputs of ``t_(k-1)``, and it ends a run at
the first discarded step without a message unless logging is on. :func:`run_fmu` pairs
the rows and checks the length.

Examples
--------
>>> from linkage_fmu.fmi.run import run_fmu   # doctest: +SKIP
>>> rows = run_fmu("dist/native/FourBar.fmu", steps=72)   # doctest: +SKIP
>>> rows[["theta", "Mb"]].head(2)   # doctest: +SKIP
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd

from .check import fmu_linkage, revolution


class FMURunError(RuntimeError):
    """A run that ended before its last step: ``step`` (the row index of the inputs),
    ``time`` and the FMU's ``messages``."""

    def __init__(self, message: str, step: int, time: float, messages: list[str]):
        super().__init__(message)
        self.step, self.time, self.messages = step, time, messages


def run_fmu(fmu: str | Path, inputs: np.ndarray | None = None, steps: int = 360,
            start_values: dict | None = None, outputs=None) -> pd.DataFrame:
    """Run ``fmu`` through ``inputs`` with fmpy and return one row per input row: the
    inputs and the outputs they give.

    Parameters
    ----------
    fmu : path
        An FMU built by this package (either flavour).
    inputs : structured array, optional
        Fields ``time`` (equally spaced) and the linkage's inputs; default
        :func:`~linkage_fmu.fmi.check.revolution` with ``steps`` steps (speed and loads
        varying).
    start_values : dict, optional
        Parameter values for the FMU.
    outputs : list of str, optional
        Outputs to record (default all).

    Returns
    -------
    DataFrame
        Columns ``time``, the inputs, the outputs; the last input row has no answer
        (the run ends there) and is not included.

    Raises
    ------
    FMURunError
        The run ended early (a discarded step): which step, at what time, and what the
        FMU logged.
    """
    from fmpy import simulate_fmu
    from fmpy.fmi1 import FMICallException

    mech = fmu_linkage(fmu)
    u = revolution(mech, steps) if inputs is None else inputs
    names = list(outputs or (mech.output_names + mech.diagnostic_names))
    t = np.asarray(u["time"], dtype=float)
    h = float(t[1] - t[0])
    messages: list[str] = []

    def logger(*args):  # FMI 2.0: (env, instance, status, category, message); 3.0: no instance
        status, message = args[-3], args[-1]
        if status >= 1:  # warnings and worse
            text = message.decode("utf-8", "replace") if isinstance(message, bytes) else message
            messages.append(str(text).replace("%%", "%"))

    try:
        result = simulate_fmu(str(fmu), start_time=float(t[0]), stop_time=float(t[-1]),
                              output_interval=h, input=u, output=names,
                              start_values=start_values or {}, debug_logging=True,
                              logger=logger)
        end = float(result["time"][-1])
    except FMICallException as err:  # fmpy 0.3's FMI 3.0 path raises at a discarded step
        found = re.search(r"DoStep: the inputs .* cannot be solved at t = ([-+0-9.eE]+)",
                          messages[-1] if messages else "")
        if err.status != 2 or found is None:  # not a discard: fmpy's own error
            raise
        result, end = None, float(found.group(1))
    if result is None or len(result) < len(t) or end < t[-1]:
        # the step from the last successful time failed
        k = int(np.argmin(np.abs(t - end)))
        reason = messages[-1] if messages else "no message from the FMU"
        raise FMURunError(f"{Path(fmu).name}: the run ended at step {k} of {len(t) - 1} "
                          f"(t = {float(t[k])!r}): {reason}", k, float(t[k]), messages)
    rows = pd.DataFrame({n: u[n][:-1] for n in u.dtype.names})
    for name in names:
        rows[name] = result[name][1:]
    return rows
