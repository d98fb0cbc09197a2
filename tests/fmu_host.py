"""Runs FMUs with fmpy in a fresh process (started by the FMU tests, never imported).

Usage: ``python fmu_host.py JOB.json`` prints a JSON result. The job lists FMU
instances (path, parameters) and one row of inputs per step; all instances run
interleaved in this one process with fmpy's order: set inputs at t, doStep(t, h), then
read every output. This process never imports linkage_fmu itself (unless the job asks
for ``preimport``), so each FMU runs the package it bundles. It exits normally, so the
FMUs' exit-time clean-up runs and a crash there fails the calling test.
"""

import json
import math
import sys

from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)

_CALLBACKS = []
STATUS = ("ok", "warning", "discard", "error", "fatal", "pending")


def _set(fmu, md, name, value):
    var = next(v for v in md.modelVariables if v.name == name)
    if var.type == "Real":
        fmu.setReal([var.valueReference], [value])
    elif var.type == "Integer":
        fmu.setInteger([var.valueReference], [int(value)])
    else:
        fmu.setString([var.valueReference], [value])


def _instance(spec, logs):
    md = read_model_description(spec["path"])

    def logger(component, instance_name, status, category, message):
        logs.append(f"{status}:{message.decode(errors='replace')}")

    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(spec["path"]),
                    modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName=spec.get("name", "instance"))
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = fmi2CallbackLoggerTYPE(logger)
    callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    _CALLBACKS.append(callbacks)  # must outlive the instance
    fmu.instantiate(loggingOn=True, callbacks=callbacks)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    for name, value in spec.get("params", {}).items():
        _set(fmu, md, name, value)
    fmu.exitInitializationMode()
    inputs = [v.valueReference for v in md.modelVariables if v.causality == "input"]
    outputs = [v for v in md.modelVariables if v.causality == "output"]
    return fmu, inputs, [v.valueReference for v in outputs], [v.name for v in outputs]


def main(job):
    for path in job.get("preimport", []):
        sys.path.insert(0, path)
        import linkage_fmu  # noqa: F401  the "foreign" copy a host may already hold
    result = {}
    runs = []
    for spec in job["fmus"]:
        for _ in range(spec.get("churn", 0)):  # instantiate and free first, then keep one
            fmu = _instance(spec, [])[0]
            fmu.terminate()
            fmu.freeInstance()
        logs = []
        entry = {"log": logs, "status": [], "outputs": []}
        result[spec["name"]] = entry
        try:
            runs.append((spec, entry) + _instance(spec, logs))
        except Exception as err:
            entry["instantiate_error"] = repr(err)
    h = job.get("h", 0.01)
    saved = {}
    for k, u in enumerate(job["inputs"]):
        t = k * h
        for spec, entry, fmu, vin, vout, names in runs:
            fmu.setReal(vin, u)
            status = fmu._functions["fmi2DoStep"](fmu.component, t, h, 1)  # raw: no raise
            entry["status"].append(STATUS[status])
            entry["names"] = names
            entry["outputs"].append([None if math.isnan(y) else y for y in fmu.getReal(vout)])
            if k == job.get("save_at"):
                saved[spec["name"]] = (fmu.getFMUstate(), u, entry["outputs"][-1])
    if "save_at" in job:  # restore the saved state, then again through bytes
        for spec, entry, fmu, vin, vout, _ in runs:
            state, u, expected = saved[spec["name"]]
            fmu.setFMUstate(state)
            entry["restored"] = fmu.getReal(vout)
            blob = fmu.serializeFMUstate(state)
            fmu.freeFMUstate(state)
            fmu.setReal(vin, [0.0, 0.0, 0.0, 0.0])
            fmu.setFMUstate(fmu.deSerializeFMUstate(blob))
            entry["deserialized"] = fmu.getReal(vout)
            entry["expected_after_restore"] = expected
    for _, _, fmu, *_ in runs:
        fmu.terminate()
        fmu.freeInstance()
    for k, sim in enumerate(job.get("simulate", [])):  # replay cross-check inputs
        from fmpy import simulate_fmu
        from fmpy.util import read_csv

        res = simulate_fmu(sim["fmu"], start_time=0.0, stop_time=sim["stop"],
                           step_size=sim["h"], output_interval=sim["h"],
                           input=read_csv(sim["input"]), start_values=sim.get("params", {}))
        result[f"simulate{k}"] = {n: res[n].tolist() for n in res.dtype.names}
    return result


if __name__ == "__main__":
    with open(sys.argv[1]) as f:
        print(json.dumps(main(json.load(f))), flush=True)
