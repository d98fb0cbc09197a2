"""Drives one FMU (FMI 2.0 or 3.0, either flavour) through fmpy's slave classes, in a
fresh process, for the FMU state tests (``test_fmu_states.py``): a crash of the FMU is
this process's exit, which fails the test, never pytest's.

Usage: ``python state_host.py JOB.json`` prints a JSON result. It never imports
linkage_fmu, so a pythonfmu FMU runs the package it bundles. Jobs (``job["job"]``):

- ``forge``: an instance is initialised and stepped, its state serialized, and stepped
  again; then each forged payload (the state with one field edited and its CRC-32
  recomputed) is deserialized: its status, the log, and whether every variable reads as
  before; an accepted payload is then set and its values read;
- ``fresh``: the state of a stepped instance, serialized, restored into a freshly
  instantiated one (instantiate, deserialize, set, read, step: fmusim's
  ``--initial-fmu-state-file`` flow), which is read and stepped through rows of inputs;
- ``pointers``: SetFMUState and its kin with pointers that are not live states of the
  instance (NULL, freed, another instance's, garbage);
- ``structure`` (FMI 3.0): the dependencies each variable answers before and after
  initialisation, and a run through event mode;
- ``resources`` (FMI 3.0): instances made with each of a list of resource paths;
- ``huge`` (FMI 3.0): every typed get and set called in step mode with
  nValueReferences = nValues = 2**31 on a small array whose first entry is unknown (the
  count past the array must not be read: a read past it is this process's crash), then
  one valid read; then those of the types with variables with four of their references,
  the same count and a NULL value array (named before any reference past the four is
  read).
"""

import json
import math
import struct
import sys
import zlib
from ctypes import (
    CDLL,
    POINTER,
    byref,
    c_bool,
    c_char_p,
    c_double,
    c_float,
    c_int,
    c_int8,
    c_int16,
    c_int32,
    c_int64,
    c_size_t,
    c_uint,
    c_uint8,
    c_uint16,
    c_uint32,
    c_uint64,
    c_void_p,
    cast,
)

from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)
from fmpy.fmi3 import FMU3Slave, fmi3FMUState

KINDS = ("input", "parameter")


class Slave:
    """One instance, with FMI 2.0's and 3.0's calls under the same names."""

    def __init__(self, path, unzip, md, name, log, event_mode=False):
        self.md, self.v3 = md, md.fmiVersion.startswith("3")
        self.log = log
        kw = dict(guid=md.guid, unzipDirectory=unzip,
                  modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        if self.v3:
            self.s = FMU3Slave(**kw)
            self.s.instantiate(loggingOn=True, eventModeUsed=event_mode,
                               logMessage=lambda env, status, cat, msg: log.append(
                                   [status, msg.decode(errors="replace")]))
        else:
            self.s = FMU2Slave(**kw)
            cb = fmi2CallbackFunctions()
            cb.logger = fmi2CallbackLoggerTYPE(lambda c, inst, status, cat, msg: log.append(
                [status, msg.decode(errors="replace")]))
            cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
            cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
            self._cb = cb
            self.s.instantiate(callbacks=cb, loggingOn=True)
        self.types = {v.valueReference: v.type for v in md.modelVariables}

    def status(self, call, *args):
        try:
            return 0, call(*args)
        except FMICallException as e:
            return e.status, None

    def get(self, vr):
        t = self.types[vr]
        if t in ("Real", "Float64"):
            f = self.s.getFloat64 if self.v3 else self.s.getReal
        elif t in ("Integer", "Int32"):
            f = self.s.getInt32 if self.v3 else self.s.getInteger
        else:
            f = self.s.getString
        value = f([vr])[0]
        return value.decode() if isinstance(value, bytes) else value

    def set(self, values: dict):
        for vr, value in values.items():
            t = self.types[vr]
            if t in ("Real", "Float64"):
                (self.s.setFloat64 if self.v3 else self.s.setReal)([vr], [value])
            elif t in ("Integer", "Int32"):
                (self.s.setInt32 if self.v3 else self.s.setInteger)([vr], [value])
            else:
                self.s.setString([vr], [value])

    def initialise(self, parameters):
        if self.v3:
            self.s.enterInitializationMode(startTime=0.0)
        else:
            self.s.setupExperiment(startTime=0.0)
            self.s.enterInitializationMode()
        self.set(parameters)
        self.s.exitInitializationMode()

    def step(self, t, h):
        return self.s.doStep(t, h)

    def get_state(self):
        return self.s.getFMUState() if self.v3 else self.s.getFMUstate()

    def set_state(self, state):
        return (self.s.setFMUState if self.v3 else self.s.setFMUstate)(state)

    def free_state(self, state):
        return (self.s.freeFMUState if self.v3 else self.s.freeFMUstate)(state)

    def serialize(self, state):
        return (self.s.serializeFMUState if self.v3 else self.s.serializeFMUstate)(state)

    def deserialize(self, blob, state=None):
        return (self.s.deserializeFMUState if self.v3 else self.s.deSerializeFMUstate)(
            blob, state)

    def snapshot(self, vrs):
        """Every variable's value, comparable exactly (NaN as 'nan')."""
        return [repr(self.get(vr)) for vr in vrs]


def kept(md):
    """(value reference, type) of what a state holds, by value reference."""
    return sorted((v.valueReference, v.type) for v in md.modelVariables
                  if v.causality in KINDS)


def parse(blob, md):
    """The fields of a serialized state, in order: [key, format, value]."""
    fields, p = [], 0

    def take(key, fmt, n=None):
        nonlocal p
        if fmt == "bytes":
            value = blob[p:p + n].hex()
            p += n
        else:
            (value,) = struct.unpack_from("<" + fmt, blob, p)
            p += struct.calcsize(fmt)
        fields.append([key, fmt, value])
        return value

    take("magic", "bytes", 8)
    take("format", "I")
    take("id", "bytes", take("nid", "I"))
    take("guid", "bytes", take("nguid", "I"))
    take("mode", "I")
    take("time", "d")
    for vr, t in kept(md):
        if t in ("Real", "Float64"):
            take(f"value {vr}", "d")
        elif t in ("Integer", "Int32"):
            take(f"value {vr}", "i")
        else:
            take(f"value {vr}", "bytes", take(f"length {vr}", "I"))
    assert len(blob) - p == 4, (len(blob), p)
    return fields


def build(fields, tail=b"", cut=0):
    out = b"".join(bytes.fromhex(v) if f == "bytes" else struct.pack("<" + f, v)
                   for _, f, v in fields)
    out = (out + tail)[:len(out) + len(tail) - cut]
    return out + struct.pack("<I", zlib.crc32(out))


def forge(fields, edit):
    """``fields`` with one edit: ``{"key", "value"}`` (a string value's text also sets its
    length; ``"hex"`` gives raw bytes), or ``{"tail": hex}`` / ``{"cut": n}``."""
    fields = [list(f) for f in fields]
    if "tail" in edit or "cut" in edit:
        return build(fields, bytes.fromhex(edit.get("tail", "")), edit.get("cut", 0))
    index = {f[0]: f for f in fields}
    field = index[edit["key"]]
    value = edit["value"]
    if field[1] == "bytes":
        raw = bytes.fromhex(value) if edit.get("hex") else value.encode()
        field[2] = raw.hex()
        length = "length" + edit["key"][5:] if edit["key"].startswith("value") else \
            {"id": "nid", "guid": "nguid"}.get(edit["key"])
        if length and not edit.get("keep_length"):
            index[length][2] = len(raw)
    else:
        field[2] = value
    return build(fields)


def forge_job(job, s, log):
    md = s.md
    vrs = [v.valueReference for v in md.modelVariables if v.causality in (*KINDS, "output")]
    s.initialise(job["parameters"])
    s.set(job["inputs"][0])
    s.step(0.0, 0.1)
    state = s.get_state()
    blob = s.serialize(state)
    fields = parse(blob, md)
    s.set(job["inputs"][1])
    s.step(0.1, 0.1)
    before = s.snapshot(vrs)
    kept_state = s.get_state()  # a live state, which a refused payload must leave alone
    results = []
    for edit in job["edits"]:
        n = len(log)
        forged = forge(fields, edit)
        reuse = edit.get("reuse", False)
        target = kept_state if reuse else None
        status, new = s.status(s.deserialize, forged, target)
        unchanged = s.snapshot(vrs) == before
        said = [m for st, m in log[n:] if st >= 3]
        read = None
        if status == 0:
            set_status, _ = s.status(s.set_state, new)
            read = {str(vr): s.get(vr) for vr in vrs}
            s.set_state(kept_state)
            if not reuse:
                s.free_state(new)
            status = max(status, set_status)
        results.append({"edit": edit, "status": status, "unchanged": unchanged,
                        "said": said[-1] if said else "", "read": read})
    s.set_state(kept_state)
    after = s.snapshot(vrs)
    step_status, _ = s.status(s.step, 0.2, 0.1)
    return {"fields": fields, "results": results, "kept_state_intact": after == before,
            "step_after": step_status}


def fresh_job(job, path, unzip, md, log):
    a = Slave(path, unzip, md, "a", log)
    outs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    if job.get("mode") != "initialization":
        a.initialise(job["parameters"])
        a.set(job["inputs"][0])
        a.step(0.0, 0.1)
    else:
        if a.v3:
            a.s.enterInitializationMode(startTime=0.0)
        else:
            a.s.setupExperiment(startTime=0.0)
            a.s.enterInitializationMode()
        a.set(job["parameters"])
        a.set(job["inputs"][0])
    blob = a.serialize(a.get_state())
    taken = [a.get(vr) for vr in outs]
    a.s.freeInstance()
    b = Slave(path, unzip, md, "b", log)
    b.set_state(b.deserialize(blob))
    restored = [b.get(vr) for vr in outs]
    t = 0.1
    if job.get("mode") == "initialization":
        b.s.exitInitializationMode()
    rows = []
    for row in job["inputs"][1:]:
        b.set(row)
        b.step(t, 0.1)
        t += 0.1
        rows.append([b.get(vr) for vr in outs])
    time = b.get(len(md.modelVariables) - 1) if b.v3 else None
    return {"taken": taken, "restored": restored, "rows": rows, "time": time,
            "errors": [m for st, m in log if st >= 3]}


def pointers_job(job, path, unzip, md, log):
    a = Slave(path, unzip, md, "a", log)
    other = Slave(path, unzip, md, "other", log)
    a.initialise(job["parameters"])
    other.initialise(job["parameters"])
    a.step(0.0, 0.1)
    mine, theirs = a.get_state(), other.get_state()
    freed = a.get_state()
    address = freed.value
    a.free_state(freed)
    garbage = (c_void_p * 4)()  # memory that is no state
    cases = {"NULL": None, "freed": address, "another instance's": theirs.value,
             "garbage": cast(garbage, c_void_p).value, "odd address": 0x11}
    p, s = ("fmi3", "State") if a.v3 else ("fmi2", "state")
    holder_type = fmi3FMUState if a.v3 else c_void_p

    def call(name, *args):
        return a.status(getattr(a.s, p + name), a.s.component, *args)[0]

    results = {}
    for name, address in cases.items():
        n = len(log)
        statuses = [call(f"SetFMU{s}", holder_type(address)),
                    call(f"SerializedFMU{s}Size", holder_type(address), byref(c_size_t()))]
        if address is not None:  # FreeFMUState of NULL is a no-op in both standards
            statuses.append(call(f"FreeFMU{s}", byref(holder_type(address))))
            statuses.append(call(f"GetFMU{s}", byref(holder_type(address))))
            # the standards leave *state undefined on entry: a new state is made instead
            status, made = a.status(a.deserialize, a.serialize(mine), holder_type(address))
            # a new live state (malloc may give a freed one's address again): freeing it is OK
            fresh = made is not None and made.value not in (None, mine.value)
            deserialized = [status, a.status(a.free_state, made)[0] if fresh else "not a new state"]
        results[name] = {"statuses": statuses, "said": [m for st, m in log[n:] if st >= 3]}
        if address is not None:
            results[name]["deserialized"] = deserialized
    # the state itself where its address belongs (fmusim 0.0.39): freed, with a Warning
    given = a.get_state()
    n = len(log)
    failed, answer = a.status(getattr(a.s, f"{p}FreeFMU{s}"), a.s.component,
                              cast(given, POINTER(holder_type)))
    said = " ".join(m for _, m in log[n:])
    by_value = [failed or answer, call(f"SetFMU{s}", given), said]
    a.set_state(mine)
    return {"results": results, "by_value": by_value,
            "step_after": a.status(a.step, 0.1, 0.1)[0]}


def structure_job(job, path, unzip, md, log):
    s = Slave(path, unzip, md, "a", log, event_mode=True)
    vrs = [v.valueReference for v in md.modelVariables]

    def answers():  # through the raw functions (fmpy 0.3's wrapper of the first is broken)
        out = {}
        for vr in vrs:
            n = c_size_t()
            s.s.fmi3GetNumberOfVariableDependencies(s.s.component, vr, byref(n))
            n = n.value
            element, independent = (c_size_t * n)(), (c_uint * n)()
            element2, kinds = (c_size_t * n)(), (c_int * n)()
            s.s.fmi3GetVariableDependencies(s.s.component, vr, element, independent, element2,
                                            kinds, n)
            assert list(element) == list(element2) == [0] * n
            out[str(vr)] = [list(independent), list(kinds)]
        return out

    before = answers()
    s.s.enterInitializationMode(startTime=0.0)
    during = answers()
    s.set(job["parameters"])
    s.s.exitInitializationMode()
    after = answers()
    outs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    flags = [list(s.s.updateDiscreteStates())]
    s.s.enterStepMode()
    rows, t = [], 0.0
    for row in job["inputs"]:
        s.s.enterEventMode()
        s.set(row)
        in_event = [s.get(vr) for vr in outs]
        flags.append(list(s.s.updateDiscreteStates()))
        s.s.enterStepMode()
        event, terminate, early, last = s.step(t, 0.1)
        t += 0.1
        rows.append({"event": in_event, "step": [s.get(vr) for vr in outs],
                     "flags": [event, terminate, early], "last": last})
    return {"before": before, "during": during, "after": after, "rows": rows,
            "flags": flags, "errors": [m for st, m in log if st >= 3]}


def resources_job(job, path, unzip, md, log):
    """FMI 3.0 instances made with each of ``job["paths"]`` as the resourcePath: made or
    not, what was logged, and the outputs of one step of those made."""
    from fmpy.fmi3 import (
        fmi3Boolean,
        fmi3InstanceEnvironment,
        fmi3IntermediateUpdateCallback,
        fmi3LogMessageCallback,
        fmi3ValueReference,
    )

    results = []
    outs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    for k, resource_path in enumerate(job["paths"]):
        n = len(log)
        s = FMU3Slave(guid=md.guid, unzipDirectory=unzip,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName=f"r{k}")
        s.logMessage = fmi3LogMessageCallback(lambda env, status, cat, msg: log.append(
            [status, msg.decode(errors="replace")]))
        s.intermediateUpdate = fmi3IntermediateUpdateCallback()
        s.component = s.fmi3InstantiateCoSimulation(
            s.instanceName.encode(), md.guid.encode(), resource_path.encode(), fmi3Boolean(0),
            fmi3Boolean(1), fmi3Boolean(0), fmi3Boolean(0), (fmi3ValueReference * 0)(), 0,
            fmi3InstanceEnvironment(), s.logMessage, s.intermediateUpdate)
        outputs = None
        if s.component:
            s.enterInitializationMode(startTime=0.0)
            s.exitInitializationMode()
            row = job["inputs"][0]
            s.setFloat64(list(row), list(row.values()))
            s.doStep(0.0, 0.1)
            outputs = s.getFloat64(outs)
            s.freeInstance()
        results.append({"made": bool(s.component), "outputs": outputs,
                        "said": " | ".join(m for st, m in log[n:] if st >= 3)})
    return {"results": results}


#: FMI 3.0's typed get and set functions: (type, the C type of one value)
TYPES3 = [("Float32", c_float), ("Float64", c_double), ("Int8", c_int8), ("UInt8", c_uint8),
          ("Int16", c_int16), ("UInt16", c_uint16), ("Int32", c_int32), ("UInt32", c_uint32),
          ("Int64", c_int64), ("UInt64", c_uint64), ("Boolean", c_bool), ("String", c_char_p),
          ("Binary", c_void_p), ("Clock", c_bool)]


def huge_job(job, path, unzip, md, log):
    """Each typed get and set with a count of 2**31 over an array of four references whose
    first is unknown: {call: [status, what it logged]}, and a valid read after them."""
    s = Slave(path, unzip, md, "a", log)
    s.initialise({})
    raw = CDLL(s.s.dll._name)  # fresh function objects: argtypes set here, not fmpy's
    n = 2 ** 31
    unknown = max(v.valueReference for v in md.modelVariables) + 1000
    refs = (c_uint * 4)(unknown, 0, 0, 0)
    results = {}
    for name, ctype in TYPES3:
        for verb in ("Get", "Set"):
            call = f"fmi3{verb}{name}"
            f = getattr(raw, call)
            f.restype = c_int
            values = (ctype * 4)()
            args = [c_void_p(s.s.component), refs, c_size_t(n)]
            if name == "Binary":
                args.append((c_size_t * 4)())  # valueSizes
            args.append(values)
            if name != "Clock":
                args.append(c_size_t(n))  # nValues
            k = len(log)
            status = f(*args)
            results[call] = [status, " | ".join(m for _, m in log[k:])]
    null = {}  # references of the type's variables and a NULL value array: named first
    for name, _ in TYPES3:
        known = [v.valueReference for v in md.modelVariables if v.type == name]
        if not known:
            continue
        for verb in ("Get", "Set"):
            call = f"fmi3{verb}{name}"
            f = getattr(raw, call)
            f.restype = c_int
            k = len(log)
            status = f(c_void_p(s.s.component), (c_uint * 4)(*[known[0]] * 4), c_size_t(n),
                       c_void_p(None), c_size_t(n))
            null[call] = [status, " | ".join(m for _, m in log[k:])]
    outs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    after = s.status(s.s.getFloat64, outs[:1])
    return {"results": results, "null": null, "after": [after[0], after[1] and after[1][0]]}


def main(job):
    path = job["fmu"]
    md = read_model_description(path)
    unzip = extract(path, job.get("unzip"))
    log = []
    if job["job"] == "forge":
        return forge_job(job, Slave(path, unzip, md, "a", log, job.get("event_mode", False)),
                         log)
    return {"fresh": fresh_job, "pointers": pointers_job, "structure": structure_job,
            "resources": resources_job, "huge": huge_job}[job["job"]](job, path, unzip, md, log)


def _plain(x):
    """JSON for NaN and infinities as strings (the test reads them back)."""
    if isinstance(x, float) and not math.isfinite(x):
        return repr(x)
    if isinstance(x, dict):
        return {k: _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    return x


if __name__ == "__main__":
    with open(sys.argv[1]) as f:
        job = json.load(f, parse_constant=float)
    job["parameters"] = {int(k): v for k, v in job.get("parameters", {}).items()}
    job["inputs"] = [{int(k): v for k, v in row.items()} for row in job.get("inputs", [])]
    print(json.dumps(_plain(main(job))), flush=True)
