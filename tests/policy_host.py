"""Drive one FourBar FMU (FMI 2.0 or 3.0, either flavour) through the same calls in this
fresh process and print, as JSON, the status of each call and every log message: the
scenario of ``test_status_policy.py``, which compares the four FMUs' answers. Never
imported by the tests, and it never imports linkage_fmu: each FMU runs what it bundles.

    python tests/policy_host.py FourBar.fmu [SCENARIO.json]

SCENARIO.json, where given, holds other calls in the form of :data:`SCENARIO` (a list of
[operation, arguments]), for any FMU whose inputs are theta, omega, alpha and load.
"""

from __future__ import annotations

import ctypes
import json
import math
import pathlib
import sys

from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi1 import FMICallException

#: the calls, as (operation, arguments); "inputs" sets theta, omega, alpha, load
SCENARIO = [
    ("enter", ()),
    ("set", ("l_AB", -0.1)),                  # an invalid parameter set
    ("outputs", ()),                          # ... outputs NaN, with a warning saying why
    ("exit", ()),                             # ... refused, still in initialisation
    ("set", ("l_AB", 0.3)),                   # fixed: the crank cannot turn a revolution
    ("exit", ()),
    ("inputs", (0.5, 5.0, 0.0, 1.0)), ("step", (0.0, 0.1)), ("outputs", ()),
    ("inputs", (math.pi, 5.0, 0.0, 1.0)),     # cannot be assembled
    ("outputs", ()),                          # read first: a warning says why
    ("step", (0.1, 0.1)),                     # discarded, nothing new to say
    ("output", ()),                           # one output: the same fate as all
    ("step", (0.1, 0.1)),                     # the same inputs again: discarded again
    ("inputs", (0.5, 5.0, 0.0, 1.0)), ("step", (0.1, 0.1)), ("outputs", ()),
    ("inputs", (0.5, math.nan, 0.0, 1.0)),    # not finite
    ("step", (0.2, 0.1)), ("outputs", ()),
    ("inputs", (0.5, 1e160, 0.0, 1.0)),       # the outputs overflow
    ("step", (0.2, 0.1)), ("outputs", ()),
    ("inputs", (0.5, 5.0, 0.0, 1.0)), ("step", (0.2, 0.1)),
    ("inputs", (math.pi, 5.0, 0.0, 1.0)),     # cannot be assembled, stepped first
    ("step", (0.3, 0.1)), ("outputs", ()),
    ("terminate", ()),
]


def status_of(call) -> int:
    try:
        return int(call() or 0)
    except FMICallException as err:
        return err.status


def main(path: str, scenario: list = SCENARIO) -> dict:
    md = read_model_description(path)
    version = md.fmiVersion[0]
    vr = {v.name: v.valueReference for v in md.modelVariables}
    outputs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    inputs = [vr[n] for n in ("theta", "omega", "alpha", "load")]
    unzip = extract(path)
    log = []
    if version == "2":
        from fmpy.fmi2 import (
            FMU2Slave,
            fmi2CallbackAllocateMemoryTYPE,
            fmi2CallbackFreeMemoryTYPE,
            fmi2CallbackFunctions,
            fmi2CallbackLoggerTYPE,
        )

        fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName="a")
        fn = fmu._functions
        callbacks = fmi2CallbackFunctions()
        callbacks.logger = fmi2CallbackLoggerTYPE(
            lambda env, name, status, category, message: log.append(
                [status, message.decode().replace("%%", "%")]))
        callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        c = fn["fmi2Instantiate"](b"a", 1, md.guid.encode(),
                                  pathlib.Path(unzip, "resources").as_uri().encode(),
                                  ctypes.byref(callbacks), 0, 1)
        refs = lambda r: ((ctypes.c_uint * len(r))(*r), len(r))  # noqa: E731
        reals = lambda x: (ctypes.c_double * len(x))(*x)  # noqa: E731

        def get(r):
            arr, n = refs(r)
            y = (ctypes.c_double * n)()
            return fn["fmi2GetReal"](c, arr, n, y), [None if math.isnan(v) else v for v in y]

        calls = {
            "enter": lambda: [fn["fmi2SetupExperiment"](c, 0, 0.0, 0.0, 0, 0.0),
                              fn["fmi2EnterInitializationMode"](c)][-1],
            "exit": lambda: fn["fmi2ExitInitializationMode"](c),
            "set": lambda name, x: fn["fmi2SetReal"](c, *refs([vr[name]]), reals([x])),
            "inputs": lambda *x: fn["fmi2SetReal"](c, *refs(inputs), reals(x)),
            "step": lambda t, h: fn["fmi2DoStep"](c, t, h, 1),
            "outputs": lambda: get(outputs),
            "output": lambda: get(outputs[-3:-2]),
            "terminate": lambda: fn["fmi2Terminate"](c),
        }
        free_ = lambda: fn["fmi2FreeInstance"](c)  # noqa: E731
    else:
        from fmpy.fmi3 import FMU3Slave

        fmu = FMU3Slave(guid=md.guid, unzipDirectory=unzip,
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName="a")
        fmu.instantiate(loggingOn=True, logMessage=lambda env, status, category, message:
                        log.append([status, message.decode()]))
        flags = [ctypes.c_bool(), ctypes.c_bool(), ctypes.c_bool(), ctypes.c_double()]

        def get(r):
            y = (ctypes.c_double * len(r))()
            status = status_of(lambda: fmu.fmi3GetFloat64(
                fmu.component, (ctypes.c_uint32 * len(r))(*r), len(r), y, len(r)))
            return status, [None if math.isnan(v) else v for v in y]

        calls = {
            "enter": lambda: fmu.enterInitializationMode(startTime=0.0),
            "exit": lambda: fmu.exitInitializationMode(),
            "set": lambda name, x: fmu.setFloat64([vr[name]], [x]),
            "inputs": lambda *x: fmu.setFloat64(inputs, list(x)),
            "step": lambda t, h: fmu.fmi3DoStep(fmu.component, t, h, True,
                                                *map(ctypes.byref, flags)),
            "outputs": lambda: get(outputs),
            "output": lambda: get(outputs[-3:-2]),
            "terminate": lambda: fmu.terminate(),
        }
        free_ = fmu.freeInstance
    answers = []
    for op, args in scenario:
        if op in ("outputs", "output"):
            status, values = calls[op]()
            answers.append([op, status, values])
        else:
            answers.append([op, status_of(lambda: calls[op](*args)), None])  # noqa: B023
    free_()
    return {"answers": answers, "log": log}


if __name__ == "__main__":
    calls = SCENARIO
    if len(sys.argv) > 2:
        calls = json.loads(pathlib.Path(sys.argv[2]).read_text(), parse_constant=float)
    print(json.dumps(main(sys.argv[1], calls)), flush=True)
