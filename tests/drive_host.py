"""Drives a drive FMU (FMI 2.0 or 3.0) through fmpy's raw classes, in a fresh process, for
``test_drive.py``: a crash of the FMU is this process's exit, which fails the test, never
pytest's.

Usage: ``python drive_host.py JOB.json`` prints a JSON result. It never imports
linkage_fmu. Jobs (``job["job"]``), each on the FMU ``job["fmu"]`` with the start values
``job["start"]`` and a constant ``tau``:

- ``run``: co-simulation steps of ``h`` from 0 until ``stop`` or a Discard: per step the
  status, the last successful time, and ``theta``, ``omega``; the outputs read after it;
- ``states``: a run of ``n`` steps; the FMU state taken after ``n // 2`` of them, set,
  and the second half run again; the state serialized, deserialized into a fresh
  instance and the second half run there: the rows of each, to be identical;
- ``bad``: calls that are wrong, each with its status and log (co-simulation and model
  exchange instances);
- ``exchange``: a model-exchange instance's derivatives at given states;
- ``initial``: in initialisation mode of a co-simulation and a model-exchange instance,
  the start values ``job["start"]`` set (NaN and infinities too), then ``theta`` and
  ``omega`` read, and the continuous states (model exchange): each status, the values and
  the log;
- ``strings``: the strings ``job["strings"]`` set in initialisation mode, then
  exitInitializationMode: each status and the log;
- ``steps``: co-simulation steps ``job["steps"]`` (``[tau, h]`` each), each from the last
  successful time of the one before (a Discard too): per step the status, the last
  successful time, ``theta`` and ``omega`` with the read's status, the CPU time it took (reported,
  never judged here) and what it logged.
"""

import json
import math
import sys
import time
from ctypes import byref, c_double, c_int, c_uint, c_void_p

from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave, fmi3Boolean, fmi3Float64

DISCARD = 2


class Drive:
    """One instance of a drive FMU, co-simulation or model exchange, FMI 2.0's and 3.0's
    calls under the same names."""

    def __init__(self, unzip, md, exchange=False, name="drive"):
        self.md, self.v3, self.log = md, md.fmiVersion.startswith("3"), []
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        cls = {(False, False): FMU2Slave, (False, True): FMU2Model,
               (True, False): FMU3Slave, (True, True): FMU3Model}[(self.v3, exchange)]
        ident = (md.modelExchange if exchange else md.coSimulation).modelIdentifier
        self.s = cls(guid=md.guid, unzipDirectory=unzip, modelIdentifier=ident,
                     instanceName=name)
        if self.v3:
            self.s.instantiate(loggingOn=True, logMessage=lambda env, status, cat, msg:
                               self.log.append([status, msg.decode(errors="replace")]))
        else:
            from fmpy import calloc, free
            from fmpy.fmi2 import (
                fmi2CallbackAllocateMemoryTYPE,
                fmi2CallbackFreeMemoryTYPE,
                fmi2CallbackFunctions,
                fmi2CallbackLoggerTYPE,
            )
            cb = fmi2CallbackFunctions()
            cb.logger = fmi2CallbackLoggerTYPE(lambda c, inst, status, cat, msg: self.log.append(
                [status, msg.decode(errors="replace")]))
            cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
            cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
            self._cb = cb
            self.s.instantiate(callbacks=cb, loggingOn=True)

    def call(self, f, *args):
        """(status, value) of a call through fmpy (which raises above Warning)."""
        try:
            return 0, f(*args)
        except FMICallException as e:
            return e.status, None

    def set(self, values):
        names = list(values)
        f = self.s.setFloat64 if self.v3 else self.s.setReal
        return self.call(f, [self.vr[n] for n in names], [float(values[n]) for n in names])[0]

    def component(self):
        c = self.s.component
        return c if isinstance(c, c_void_p) else c_void_p(c)

    def get(self, names):
        """(status, {name: value}) of one read of ``names``, the status as answered."""
        n = len(names)
        vr, values = (c_uint * n)(*(self.vr[k] for k in names)), (c_double * n)()
        if self.v3:
            status = self.s.dll.fmi3GetFloat64(self.component(), vr, n, values, n)
        else:
            status = self.s.dll.fmi2GetReal(self.component(), vr, n, values)
        return status, (dict(zip(names, values)) if status <= 1 else None)

    def set_string(self, values):
        names = list(values)
        f = self.s.setString
        return self.call(f, [self.vr[n] for n in names], [values[n] for n in names])[0]

    def initialise(self, start):
        if self.v3:
            self.s.enterInitializationMode(startTime=0.0)
        else:
            self.s.setupExperiment(startTime=0.0)
            self.s.enterInitializationMode()
        status = self.set(start)
        exit_status = self.call(self.s.exitInitializationMode)[0]
        return max(status, exit_status)

    def step(self, t, h):
        """(status, last successful time) of one co-simulation step."""
        if self.v3:
            ev, term, early, last = fmi3Boolean(), fmi3Boolean(), fmi3Boolean(), fmi3Float64()
            status = self.s.dll.fmi3DoStep(self.component(), c_double(t), c_double(h),
                                           fmi3Boolean(True), byref(ev), byref(term),
                                           byref(early), byref(last))
            return status, last.value
        status = self.s.dll.fmi2DoStep(self.component(), c_double(t), c_double(h), c_int(1))
        last = c_double()
        self.s.dll.fmi2GetRealStatus(self.component(), c_int(2), byref(last))  # LastSuccessfulTime
        return status, last.value


def run(d, tau, h, stop, outputs):
    rows, t = [], 0.0
    d.set({"tau": tau})
    while t < stop - 0.5 * h:
        status, last = d.step(t, h)
        got = d.get(["theta", "omega", *outputs])
        rows.append({"status": status, "last": last, "read": got[0], **(got[1] or {})})
        if status:
            break
        t = last
    return rows


def steps(d, plan):
    rows, t = [], 0.0
    for tau, h in plan:
        d.set({"tau": tau})
        n = len(d.log)
        cpu = time.process_time()
        status, last = d.step(t, h)
        cpu = time.process_time() - cpu
        read, got = d.get(["theta", "omega"])
        rows.append({"status": status, "last": last, "cpu": cpu, "read": read, **(got or {}),
                     "said": [text for _, text in d.log[n:]]})
        t = last
    return rows


def main():
    with open(sys.argv[1]) as f:
        job = json.load(f)
    md = read_model_description(job["fmu"])
    unzip = extract(job["fmu"])
    out = {}
    if job["job"] == "run":
        d = Drive(unzip, md)
        out["init"] = d.initialise(job["start"])
        out["rows"] = run(d, job["tau"], job["h"], job["stop"], job.get("outputs", []))
        out["log"] = d.log
    elif job["job"] == "states":
        d = Drive(unzip, md)
        d.initialise(job["start"])
        n, h, names = job["n"], job["h"], ["theta", "omega", *job.get("outputs", [])]
        d.set({"tau": job["tau"]})

        def half(inst, k0):
            rows = []
            for k in range(k0, n):
                inst.step(k * h, h)
                rows.append(inst.get(names)[1])
            return rows

        first = []
        for k in range(n // 2):
            d.step(k * h, h)
            first.append(d.get(names)[1])
        state = d.s.getFMUState() if d.v3 else d.s.getFMUstate()
        second = half(d, n // 2)
        (d.s.setFMUState if d.v3 else d.s.setFMUstate)(state)
        again = half(d, n // 2)
        data = (d.s.serializeFMUState if d.v3 else d.s.serializeFMUstate)(state)
        fresh = Drive(unzip, md, name="fresh")
        restored = (fresh.s.deserializeFMUState if d.v3 else fresh.s.deSerializeFMUstate)(data)
        (fresh.s.setFMUState if d.v3 else fresh.s.setFMUstate)(restored)
        fresh.set({"tau": job["tau"]})
        out.update(first=first, second=second, again=again, fresh=half(fresh, n // 2),
                   size=len(data), log=d.log + fresh.log)
    elif job["job"] == "bad":
        answers = {}
        d = Drive(unzip, md)
        answers["set state theta"] = d.set({"theta": 1.0})
        answers["tolerance 0"] = d.initialise({"tolerance": 0.0})
        answers["tolerance back"] = max(d.set({"tolerance": 1e-8}),
                                        d.call(d.s.exitInitializationMode)[0])
        answers["tau nan"] = d.set({"tau": math.nan})
        answers["step nan"] = d.step(0.0, 0.01)[0]
        got = d.get(["alpha", "theta"])
        answers["read nan"] = [got[0], [None if v != v else v for v in got[1].values()]]
        d.set({"tau": 0.1})
        answers["step fine"] = d.step(0.0, 0.01)[0]
        answers["tolerance tuned"] = d.set({"tolerance": 1e-10})
        answers["tolerance tuned 0"] = d.set({"tolerance": 0.0})
        answers["step tuned"] = d.step(0.01, 0.01)[0]
        answers["tolerance read"] = d.get(["tolerance"])[1]["tolerance"]
        answers["step h 0"] = d.step(0.02, 0.0)[0]
        m = Drive(unzip, md, exchange=True, name="exchange")
        m.initialise({})
        x = (c_double * 3)()
        answers["enter continuous"] = m.call(m.s.enterContinuousTimeMode)[0]
        answers["tolerance in continuous time"] = m.set({"tolerance": 1e-10})
        answers["set states n=3"] = m.call(m.s.setContinuousStates, x, 3)[0]
        x[0], x[1] = math.nan, 1.0
        answers["set states nan"] = m.call(m.s.setContinuousStates, x, 2)[0]
        get_dx = m.s.getContinuousStateDerivatives if m.v3 else m.s.getDerivatives
        answers["derivatives n=1"] = m.call(get_dx, x, 1)[0]
        answers["do step in model exchange"] = m.step(0.0, 0.01)[0]
        answers["set time inf"] = m.call(m.s.setTime, math.inf)[0]
        x[0], x[1] = 0.3, 2.0
        answers["set states fine"] = m.call(m.s.setContinuousStates, x, 2)[0]
        answers["derivatives fine"] = m.call(get_dx, x, 2)[0]
        out["answers"] = answers
        out["log"] = d.log + m.log
    elif job["job"] == "steps":
        d = Drive(unzip, md)
        out["init"] = d.initialise(job.get("start", {}))
        out["rows"] = steps(d, job["steps"])
    elif job["job"] == "strings":
        d = Drive(unzip, md)
        if d.v3:
            d.s.enterInitializationMode(startTime=0.0)
        else:
            d.s.setupExperiment(startTime=0.0)
            d.s.enterInitializationMode()
        out["set"] = d.set_string(job["strings"])
        out["exit"] = d.call(d.s.exitInitializationMode)[0]
        out["log"] = d.log
    elif job["job"] == "exchange":
        m = Drive(unzip, md, exchange=True)
        m.initialise(job["start"])
        m.set({"tau": job["tau"]})
        m.s.enterContinuousTimeMode()
        x, dx = (c_double * 2)(), (c_double * 2)()
        get_dx = m.s.getContinuousStateDerivatives if m.v3 else m.s.getDerivatives
        out["derivatives"] = []
        for theta, omega in job["states"]:
            x[0], x[1] = theta, omega
            m.s.setContinuousStates(x, 2)
            status = m.call(get_dx, dx, 2)[0]
            out["derivatives"].append([status, [v if v == v else None for v in dx]])
        out["log"] = m.log
    elif job["job"] == "initial":
        for kind in ("cs", "me"):
            d = Drive(unzip, md, exchange=kind == "me")
            if d.v3:
                d.s.enterInitializationMode(startTime=0.0)
            else:
                d.s.setupExperiment(startTime=0.0)
                d.s.enterInitializationMode()
            row = {"set": d.set(job["start"])}
            row["read"], got = d.get(["theta", "omega"])
            row["values"] = [None if v != v else v for v in (got or {}).values()]
            if kind == "me":
                x = (c_double * 2)()
                f = d.s.dll.fmi3GetContinuousStates if d.v3 else d.s.dll.fmi2GetContinuousStates
                row["states"] = f(d.component(), x, 2)
            row["log"] = d.log
            out[kind] = row
    print(json.dumps(out))


if __name__ == "__main__":
    main()
