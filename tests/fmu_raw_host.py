"""Drives FMUs through fmpy's raw FMI 2 function pointers, in a fresh process.

Usage: ``python fmu_raw_host.py JOB.json`` prints a JSON result. Started by the FMU
protocol tests and ``benchmarks/fmu_fuzz.py``; never imported by them, and it never
imports linkage_fmu, so every FMU runs the package it bundles.

No call raises here: each answers its status code, so a test can count them. The job
holds FMU paths (and, optionally, the folder each is unpacked into) and a list of
operations ``[instance, op, *args]``; the result has one
``[status, payload]`` per operation (``payload`` holds values read, NaN as None), the
log messages by status, and the peak resident memory.
"""

import ctypes
import json
import math
import pathlib
import resource
import sys
import zlib
from ctypes import byref, c_char_p, c_double, c_int, c_size_t, c_uint, c_void_p

from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)

LAST_SUCCESSFUL_TIME, TERMINATED = 2, 3  # fmi2StatusKind


class Host:
    def __init__(self, fmus: dict, keep_log: int, unzip: dict | None = None):
        self.units = {}  # fmu key -> (md, unzip dir, library owner FMU2Slave)
        for key, path in fmus.items():
            md = read_model_description(path)
            self.units[key] = (md, extract(path, (unzip or {}).get(key)))
        self.instances = {}  # name -> (FMU2Slave, component)
        self.states = {}
        self.blobs = {}
        self.log = {}
        self.keep_log = keep_log
        self.counts = [0] * 6
        self.last = None  # the last message logged
        self._callbacks = []

    def _logger(self, component, instance, status, category, message):
        self.counts[min(status, 5)] += 1
        self.last = message.decode(errors="replace")
        lst = self.log.setdefault(str(status), [])
        if len(lst) < self.keep_log:
            lst.append(message.decode(errors="replace"))

    def new(self, name, key, guid=None, logging=True, resources=None):
        md, unzip = self.units[key]
        fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        callbacks = fmi2CallbackFunctions()
        callbacks.logger = fmi2CallbackLoggerTYPE(self._logger)
        callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self._callbacks.append(callbacks)  # outlives the instance
        f = fmu._functions["fmi2Instantiate"]
        location = resources if resources is not None else \
            pathlib.Path(unzip, "resources").as_uri()
        component = f(name.encode(), 1, (md.guid if guid is None else guid).encode(),
                      location.encode(), byref(callbacks), 0, int(logging))
        if not component:
            return 3, None
        self.instances[name] = (fmu, component, md)
        return 0, None

    def call(self, name, fname, *args):
        fmu, component, _ = self.instances[name]
        return fmu._functions[fname](component, *args)

    def vrs(self, refs):
        return (c_uint * len(refs))(*refs), len(refs)

    def run(self, name, op, *a):
        if op == "new":
            return self.new(name, *a)
        if op == "steps":  # many steps at once: (inputs per step, h, vrs to read)
            return self.steps(name, *a)
        if op == "cycles":  # instantiate/free cycles: (fmu key, count, a parameter's vr)
            return self.cycles(*a)
        if op == "rss":  # resident memory now, KiB
            with open("/proc/self/statm") as f:
                return 0, int(f.read().split()[1]) * resource.getpagesize() // 1024
        fmu, component, md = self.instances[name]
        fn = fmu._functions
        if op == "free":
            fn["fmi2FreeInstance"](component)
            del self.instances[name]
            return 0, None
        if op == "setup":
            start, stop = a
            return fn["fmi2SetupExperiment"](component, 0, 0.0, start, int(stop is not None),
                                              0.0 if stop is None else stop), None
        simple = {"enter": "fmi2EnterInitializationMode", "exit": "fmi2ExitInitializationMode",
                  "terminate": "fmi2Terminate", "reset": "fmi2Reset", "cancel": "fmi2CancelStep"}
        if op in simple:
            return fn[simple[op]](component), None
        if op == "doStep":
            t, h = a
            return fn["fmi2DoStep"](component, t, h, 1), None
        if op in ("setReal", "setInteger", "setBoolean", "setString"):
            refs, values = a
            vr, n = self.vrs(refs)
            if op == "setReal":
                arr = (c_double * n)(*values)
            elif op == "setString":
                arr = (c_char_p * n)(*(None if v is None else bytes.fromhex(v) for v in values))
            else:
                arr = (c_int * n)(*values)
            return fn["fmi2" + op[0].upper() + op[1:]](component, vr, n, arr), None
        if op in ("getReal", "getInteger", "getBoolean", "getString"):
            (refs,) = a
            vr, n = self.vrs(refs)
            ctype = {"getReal": c_double, "getString": c_char_p}.get(op, c_int)
            arr = (ctype * n)()
            status = fn["fmi2" + op[0].upper() + op[1:]](component, vr, n, arr)
            if op == "getReal":
                values = [None if math.isnan(v) else v for v in arr]
            elif op == "getString":
                values = [None if v is None else v.decode(errors="replace") for v in arr]
            else:
                values = list(arr)
            return status, values
        if op == "derivative":  # directional derivatives: (unknowns, knowns, seeds)
            unknowns, knowns, seeds = a
            (vu, nu), (vk, nk) = self.vrs(unknowns), self.vrs(knowns)
            out = (c_double * max(nu, 1))()
            status = fn["fmi2GetDirectionalDerivative"](component, vu, nu, vk, nk,
                                                        (c_double * max(nk, 1))(*seeds), out)
            return status, [None if math.isnan(v) else v for v in out[:nu]]
        if op == "getState":
            (slot,) = a
            state = self.states.get(slot, c_void_p())
            status = fn["fmi2GetFMUstate"](component, byref(state))
            self.states[slot] = state
            return status, None
        if op == "setState":
            (slot,) = a
            return fn["fmi2SetFMUstate"](component, self.states[slot]), None
        if op == "freeState":
            (slot,) = a
            state = self.states.pop(slot)
            return fn["fmi2FreeFMUstate"](component, byref(state)), None
        if op == "serialize":
            slot, blob = a
            size = c_size_t()
            status = fn["fmi2SerializedFMUstateSize"](component, self.states[slot], byref(size))
            if status > 1:
                return status, None
            buf = ctypes.create_string_buffer(size.value)
            status = fn["fmi2SerializeFMUstate"](component, self.states[slot], buf, size)
            self.blobs[blob] = buf.raw
            return status, len(buf.raw)
        if op == "deserialize":
            # edit: None | ["flip", i, byte] | ["cut", n] | ["hex", str] | ["forge", i, hex]
            # (hex's bytes written at i of the payload, its CRC-32 made valid again)
            blob, slot, edit = a
            data = bytearray(self.blobs[blob])
            if edit and edit[0] == "flip":
                data[edit[1] % len(data)] ^= edit[2]
            elif edit and edit[0] == "forge":
                payload = data[:-4]
                at = edit[1] % len(payload)
                raw = bytes.fromhex(edit[2])[:len(payload) - at]
                payload[at:at + len(raw)] = raw
                data = payload + zlib.crc32(payload).to_bytes(4, "little")
            elif edit and edit[0] == "cut":
                data = data[:edit[1]]
            elif edit and edit[0] == "hex":
                data = bytearray(bytes.fromhex(edit[1]))
            buf = ctypes.create_string_buffer(bytes(data), len(data))
            state = c_void_p()
            status = fn["fmi2DeSerializeFMUstate"](component, buf, len(data), byref(state))
            if state:
                self.states[slot] = state
            return status, None
        if op == "realStatus":
            value = c_double()
            status = fn["fmi2GetRealStatus"](component, a[0], byref(value))
            return status, value.value
        if op == "boolStatus":
            value = c_int()
            status = fn["fmi2GetBooleanStatus"](component, a[0], byref(value))
            return status, value.value
        if op == "lastLog":  # the last message logged since the last lastLog, by any call
            last, self.last = self.last, None
            return 0, last
        if op == "statusKinds":  # every status query with each kind: [status, its log]
            answers = {}
            for query, ctype in (("fmi2GetStatus", c_int), ("fmi2GetRealStatus", c_double),
                                 ("fmi2GetIntegerStatus", c_int),
                                 ("fmi2GetBooleanStatus", c_int),
                                 ("fmi2GetStringStatus", c_char_p)):
                for kind in a[0]:
                    self.last, value = None, ctype()
                    status = fn[query](component, kind, byref(value))
                    answers[f"{query}({kind})"] = [status, self.last]
            return 0, answers
        if op == "nulls":  # NULL arrays and pointers where the standard wants them
            return 0, [
                fn["fmi2SetReal"](component, None, 2, None),
                fn["fmi2GetReal"](component, None, 1, None),
                fn["fmi2GetFMUstate"](component, None),
                fn["fmi2SetFMUstate"](component, None),
                fn["fmi2GetRealStatus"](component, LAST_SUCCESSFUL_TIME, None),
                fn["fmi2GetBooleanStatus"](component, TERMINATED, None),
                fn["fmi2DoStep"](None, 0.0, 0.1, 1),
                fn["fmi2SetString"](component, None, 1, None),
            ]
        if op == "debugLogging":
            on, categories = a
            arr = (c_char_p * len(categories))(*(c.encode() for c in categories))
            return fn["fmi2SetDebugLogging"](component, int(on), len(categories), arr), None
        raise ValueError(f"unknown op {op!r}")


    def cycles(self, key, count, parameter_vr):
        """``count`` cycles of instantiate, setup, enter, set a parameter, exit, step, read,
        free of the FMU ``key``, with one set of callbacks and one loaded library; the
        count of each status."""
        md, unzip = self.units[key]
        fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName="x")
        fn = fmu._functions
        callbacks = fmi2CallbackFunctions()
        callbacks.logger = fmi2CallbackLoggerTYPE(self._logger)
        callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self._callbacks.append(callbacks)
        location = pathlib.Path(unzip, "resources").as_uri().encode()
        outs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
        vp, _ = self.vrs([parameter_vr])
        vout, n_out = self.vrs(outs)
        y, p = (c_double * n_out)(), (c_double * 1)()
        counts = [0] * 6
        for k in range(count):
            c = fn["fmi2Instantiate"](b"x", 1, md.guid.encode(), location, byref(callbacks), 0, 1)
            p[0] = 0.09 + 1e-6 * (k % 1000)
            for status in (fn["fmi2SetupExperiment"](c, 0, 0.0, 0.0, 0, 0.0),
                           fn["fmi2EnterInitializationMode"](c), fn["fmi2SetReal"](c, vp, 1, p),
                           fn["fmi2ExitInitializationMode"](c),
                           fn["fmi2DoStep"](c, 0.0, 0.1, 1), fn["fmi2GetReal"](c, vout, n_out, y),
                           fn["fmi2Terminate"](c)):
                counts[status] += 1
            fn["fmi2FreeInstance"](c)
        return 0, {"counts": counts}

    def steps(self, name, rows, h, refs):
        """Set the 4 inputs, doStep, get ``refs`` per row; count statuses and NaN reads.
        ``rows`` is a list of rows, or ``{"pattern": rows, "repeat": n}``."""
        fmu, component, _ = self.instances[name]
        fn = fmu._functions
        set_real, do_step, get_real = fn["fmi2SetReal"], fn["fmi2DoStep"], fn["fmi2GetReal"]
        vin, n_in = self.vrs([0, 1, 2, 3])
        vout, n_out = self.vrs(refs)
        u, y = (c_double * 4)(), (c_double * n_out)()
        counts, nan_rows, t = [0] * 6, 0, 0.0
        if isinstance(rows, dict):
            pattern, repeat = rows["pattern"], rows["repeat"]
            rows = (row for _ in range(repeat) for row in pattern)
        for row in rows:
            u[:] = row
            counts[set_real(component, vin, n_in, u)] += 1
            counts[do_step(component, t, h, 1)] += 1
            counts[get_real(component, vout, n_out, y)] += 1
            nan_rows += any(map(math.isnan, y))
            t += h
        return 0, {"counts": counts, "nan_rows": nan_rows}


def main(job):
    host = Host(job["fmus"], job.get("keep_log", 50), job.get("unzip"))
    results = []
    for entry in job["ops"]:
        results.append(list(host.run(*entry)))
    for name in list(host.instances):
        host.run(name, "free")
    peak_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {"results": results, "log": host.log, "logged": host.counts, "peak_kib": peak_kib}


if __name__ == "__main__":
    with open(sys.argv[1]) as f:
        print(json.dumps(main(json.load(f))), flush=True)
