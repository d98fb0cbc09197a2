"""Run an FMU of a linkage with fmpy and get rows that cannot mislead: each row holds
inputs and the outputs computed from exactly those inputs, and a discarded step is said.

The run goes step by step through fmpy's FMI 2.0 and 3.0 classes: at each input row it
sets the inputs, calls doStep from that row's time and reads the outputs, so a row holds
the outputs of its own inputs (fmpy's ``simulate_fmu`` samples them one row later, and
ends a run at the first discarded step). A discarded step (inputs the linkage cannot
take: an angle where it does not assemble) leaves the FMU at its last time; the next
row's inputs go on from there, as the FMUs allow.

Examples
--------
>>> from linkage_fmu.fmi.run import run_fmu   # doctest: +SKIP
>>> rows = run_fmu("dist/native/FourBar.fmu", steps=72)   # doctest: +SKIP
>>> rows[["theta", "Mb"]].head(2)   # doctest: +SKIP
"""

from __future__ import annotations

import ctypes
import functools
import math
import shutil
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pandas as pd

from ..descriptions import Description
from ..errors import ComputationError, InputError, LinkageFmuError
from ..mechanism import Mechanism

#: fmpy's status of a discarded step (fmi2Discard, fmi3Discard)
DISCARD = 2
#: the middle of the range of a load whose start value is zero, by its unit
_NOMINAL_LOAD = {"N": 100.0, "N.m": 10.0}


def fmu_linkage(fmu: str | Path) -> Mechanism:
    """The linkage an FMU built by :func:`~linkage_fmu.fmi.build.build_fmu` or
    :func:`~linkage_fmu.fmi.build.build_native_fmu` computes (the drive FMU's too): its
    bundled description file, with the FMU's parameter start values.

    Raises
    ------
    ValueError
        ``fmu`` is not an FMU (a zip archive with a modelDescription.xml), or not one of
        a linkage built by this package (no description file of its model).
    """
    return fmu_kind(fmu)[0]


def fmu_kind(fmu: str | Path) -> tuple[Mechanism, bool]:
    """The linkage of ``fmu`` (:func:`fmu_linkage`), and whether the FMU is its drive FMU
    (model ``<Model>Drive``: the linkage driven by a moment ``tau`` on its crank)."""
    try:
        with zipfile.ZipFile(fmu) as archive:
            root = ET.fromstring(archive.read("modelDescription.xml"))
            cs = root.find("CoSimulation")
            model = "" if cs is None else cs.get("modelIdentifier", "")
            names = set(archive.namelist())
            drive = f"resources/{model}.toml" not in names and model.endswith("Drive")
            name = f"resources/{model[:-len('Drive')] if drive else model}.toml"
            if name not in names:
                raise InputError(f"{fmu}: not an FMU of a linkage built by linkage_fmu (it has "
                                 f"no {name})")
            text = archive.read(name).decode("utf-8")
    except zipfile.BadZipFile:
        raise InputError(f"{fmu}: not an FMU (an FMU is a zip archive)") from None
    except KeyError:
        raise InputError(f"{fmu}: not an FMU (it has no modelDescription.xml)") from None
    except ET.ParseError as err:
        raise InputError(f"{fmu}: its modelDescription.xml is not XML ({err})") from None
    return Description.from_toml(text, f"{fmu}:{name}").build(), drive


def revolution(mech: Mechanism, steps: int = 360) -> np.ndarray:
    """Inputs over a revolution, or over as many as the longest period of the linkage's
    loads given by a table (two for a four-stroke engine's 720 deg): speed +-20 %, each
    input load +-50 % around its start value (a load whose start value is zero varies
    around 100 N or 10 N.m), ``steps`` steps per revolution. For a linkage driven by
    time, each driver's motion about its start over 1 s (:func:`_strokes`).

    Returns a structured array with fields ``time`` and the linkage's inputs, one row
    per communication point, as fmpy's ``simulate_fmu`` takes it.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> u = revolution(presets.get("four_bar"), steps=4)
    >>> u.dtype.names, round(float(u["theta"][-1]), 12) == round(2 * math.pi, 12)
    (('time', 'theta', 'omega', 'alpha', 'load'), True)
    """
    if mech.rates:
        return _strokes(mech, steps)
    turns = max([1] + [math.ceil(ld.table.period_deg / 360.0 - 1e-9)
                       for ld in mech.computed_loads if ld.table is not None])
    w0 = mech.start["omega"] or 2.0 * math.pi
    period = 2.0 * math.pi / abs(w0)
    t = np.linspace(0.0, turns * period, turns * steps + 1)
    k = 2.0 * math.pi / period
    u = np.zeros(t.size, dtype=[(n, np.float64) for n in ("time",) + mech.input_names])
    u["time"] = t
    u["theta"] = mech.start["theta"] + w0 * (t - 0.2 / k * (np.cos(k * t) - 1.0))
    u["omega"] = w0 * (1.0 + 0.2 * np.sin(k * t))
    u["alpha"] = w0 * 0.2 * k * np.cos(k * t)
    for j, load in enumerate(mech.input_loads):
        load0 = load.start or _NOMINAL_LOAD.get(load.unit, 1.0)
        u[load.name] = load0 * (1.0 + 0.5 * np.sin((2.0 + j) * k * t))
    return u


#: the amplitude of each driver's motion in :func:`revolution`: of an angle (rad) and a
#: travel (m)
STROKES = {"angle": 0.2, "travel": 0.05}


def _strokes(mech: Mechanism, steps: int) -> np.ndarray:
    """For a linkage driven by time: over 1 s in ``steps`` steps, each driver ``k``
    swings about its start by :data:`STROKES` as ``sin(2 pi (k + 1) t)`` (its speed and
    acceleration the derivatives), each input load as in :func:`revolution`."""
    t = np.linspace(0.0, 1.0, steps + 1)
    u = np.zeros(t.size, dtype=[(n, np.float64) for n in ("time",) + mech.input_names])
    u["time"] = t
    for k, driver in enumerate(mech.drivers):
        w, amplitude = 2.0 * math.pi * (k + 1), STROKES[driver.kind]
        q, v, a = driver.inputs
        u[q] = mech.start[q] + amplitude * np.sin(w * t)
        u[v] = amplitude * w * np.cos(w * t)
        u[a] = -amplitude * w * w * np.sin(w * t)
    for j, load in enumerate(mech.input_loads):
        load0 = load.start or _NOMINAL_LOAD.get(load.unit, 1.0)
        u[load.name] = load0 * (1.0 + 0.5 * np.sin((2.0 + j) * 2.0 * math.pi * t))
    return u


class FMURunError(LinkageFmuError, RuntimeError):
    """A run that ended before its last step: ``step`` (the row index of the inputs),
    ``time`` and the FMU's ``messages``."""

    def __init__(self, message: str, step: int, time: float, messages: list[str]):
        super().__init__(message)
        self.step, self.time, self.messages = step, time, messages


def step_fmu(fmu: str | Path, inputs: np.ndarray, start_values: dict | None = None,
             outputs=None, stop: bool = False) -> tuple[pd.DataFrame, list[str]]:
    """Run ``fmu`` through the rows of ``inputs`` (fields ``time``, equally spaced, and
    the FMU's inputs), one doStep per row but the last; with ``stop``, none after the
    first discarded step (an FMU with states, the drive FMU, stays at its time: the
    rows after it are unsolved).

    Returns
    -------
    rows : DataFrame
        Per row but the last: ``time``, the inputs, ``solved`` (False where the FMU
        discarded the step: its outputs are NaN there) and the ``outputs`` (default
        every output of the FMU).
    messages : list of str
        What the FMU logged with status Warning or worse.

    Raises
    ------
    RuntimeError
        The FMU cannot be instantiated (what it logged, or fmpy's message).
    """
    from fmpy import extract, instantiate_fmu, read_model_description
    from fmpy.fmi1 import FMICallException
    from fmpy.simulation import apply_start_values

    md = read_model_description(str(fmu))
    refs = {v.name: v.valueReference for v in md.modelVariables}
    names = list(outputs or [v.name for v in md.modelVariables if v.causality == "output"])
    given = [n for n in inputs.dtype.names if n != "time"]
    t = np.asarray(inputs["time"], dtype=float)
    h = float(t[1] - t[0])
    messages: list[str] = []

    def logger(*args):  # FMI 2.0: (env, instance, status, category, message); 3.0: no instance
        status, message = args[-3], args[-1]
        if status >= 1:  # warnings and worse
            text = message.decode("utf-8", "replace") if isinstance(message, bytes) else message
            messages.append(str(text).replace("%%", "%"))

    unzipped = extract(str(fmu))
    fmi3 = md.fmiVersion.startswith("3")
    try:
        slave = instantiate_fmu(unzipped, md, "CoSimulation", debug_logging=True,
                                logger=logger)
    except Exception as err:  # noqa: BLE001 -- fmpy's own, a plain Exception, for NULL
        shutil.rmtree(unzipped, ignore_errors=True)
        if not fmi3:
            _default_logger()
        said = " ".join("; ".join(messages).split())  # one line
        raise ComputationError(f"the FMU cannot be instantiated: {said or err}") from None
    try:
        if fmi3:
            slave.enterInitializationMode(startTime=float(t[0]))
            set_inputs, get_outputs = slave.setFloat64, slave.getFloat64
        else:
            slave.setupExperiment(startTime=float(t[0]))
            slave.enterInitializationMode()
            set_inputs, get_outputs = slave.setReal, slave.getReal
        apply_start_values(slave, md, start_values or {})
        slave.exitInitializationMode()
        in_refs = [refs[n] for n in given]
        out_refs = [refs[n] for n in names]
        values = np.column_stack([np.asarray(inputs[n], dtype=float) for n in given])
        solved = np.ones(len(t) - 1, dtype=bool)
        result = np.full((len(t) - 1, len(names)), np.nan)
        for k in range(len(t) - 1):
            set_inputs(in_refs, list(values[k]))
            try:
                slave.doStep(currentCommunicationPoint=float(t[k]), communicationStepSize=h)
            except FMICallException as err:
                if err.status != DISCARD:
                    raise
                solved[k] = False
                if stop:
                    solved[k:] = False
                    break
            result[k] = get_outputs(out_refs, len(out_refs)) if fmi3 else get_outputs(out_refs)
        slave.terminate()
    finally:
        slave.freeInstance()
        shutil.rmtree(unzipped, ignore_errors=True)
        if not fmi3:
            _default_logger()
    rows = pd.DataFrame({n: inputs[n][:-1] for n in inputs.dtype.names})
    rows["solved"] = solved
    for j, name in enumerate(names):
        rows[name] = result[:, j]
    return rows, messages


@functools.cache
def _printing_logger():
    # kept for the life of the process: the proxy holds its address
    from fmpy.fmi2 import fmi2CallbackLoggerTYPE, printLogMessage

    return fmi2CallbackLoggerTYPE(printLogMessage)


def _default_logger() -> None:
    """Point fmpy's logger proxy back at fmpy's own printing logger. The proxy (it
    formats the variadic message in C) forwards the messages of every FMI 2.0 instance
    in the process to the last logger registered with it, so after ours is gone an
    instance made with fmpy's default callbacks would call freed memory when it logs."""
    try:
        from fmpy.logging import addLoggerProxy
    except Exception:  # no proxy on this platform: nothing was registered
        return
    from fmpy.fmi2 import fmi2CallbackFunctions

    callbacks = fmi2CallbackFunctions()  # the proxy takes the logger out of it
    callbacks.logger = _printing_logger()
    addLoggerProxy(ctypes.byref(callbacks))


def run_fmu(fmu: str | Path, inputs: np.ndarray | None = None, steps: int = 360,
            start_values: dict | None = None, outputs=None, strict: bool = True
            ) -> pd.DataFrame:
    """Run ``fmu`` through ``inputs`` with fmpy and return one row per input row: the
    inputs and the outputs they give.

    Parameters
    ----------
    fmu : path
        An FMU built by this package (either flavour).
    inputs : structured array, optional
        Fields ``time`` (equally spaced) and the linkage's inputs; default
        :func:`revolution` with ``steps`` steps (speed and loads
        varying).
    start_values : dict, optional
        Parameter values for the FMU.
    outputs : list of str, optional
        Outputs to record (default all).
    strict : bool
        True: a discarded step ends the run with :class:`FMURunError`; False: its row
        has ``solved = False`` and NaN outputs, and the run goes on.

    Returns
    -------
    DataFrame
        Columns ``time``, the inputs, ``solved``, the outputs; the last input row has no
        answer (the run ends there) and is not included.

    Raises
    ------
    FMURunError
        With ``strict``, the first discarded step: which, at what time, and what the
        FMU logged.
    ValueError
        ``fmu`` is not an FMU of a linkage, or is a drive FMU and no ``inputs`` are
        given.
    """
    mech, drive = fmu_kind(fmu)
    if drive and inputs is None:  # revolution() gives the inverse FMU's inputs
        raise InputError(f"{fmu}: a drive FMU, whose inputs are tau and the loads: give "
                         "them as inputs (or check it: linkage-fmu check)")
    u = revolution(mech, steps) if inputs is None else inputs
    rows, messages = step_fmu(fmu, u, start_values,
                              outputs or list(mech.output_names + mech.diagnostic_names))
    if strict and not rows["solved"].all():
        k = int(np.argmin(rows["solved"].to_numpy()))
        t = float(rows["time"][k])
        reason = next((m for m in messages if "cannot be solved" in m),
                      messages[-1] if messages else "no message from the FMU")
        raise FMURunError(f"{Path(fmu).name}: the run ended at step {k} of {len(u) - 1} "
                          f"(t = {t!r}): {reason}", k, t, messages)
    return rows
