"""Drive a native FMI 3.0 FourBar FMU through fmpy's FMU3Slave in this (fresh) process
and check what it answers (run by tests/test_native3.py): parameters set in
initialisation mode give the direct solver's outputs; every bad call is an error status
with a log naming it, and the instance keeps working; an unassemblable angle is a
discarded step (terminateSimulation true, lastSuccessfulTime the step's start, NaN
outputs read with a warning) and the next valid step is right; FMU states round-trip bit
for bit and a corrupted one is refused; a wrong instantiation token is refused; event
mode, where the importer uses it, asks for nothing. Prints one line per check; exits 1 if
any fails.

    python tests/fmu3_host.py FourBar.fmu
"""

from __future__ import annotations

import ctypes
import math
import shutil
import sys
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave, fmi3Float64, fmi3ValueReference

from linkage_fmu import presets

FAILED = []


def check(ok: bool, what: str) -> None:
    print(("PASS " if ok else "FAIL ") + what)
    if not ok:
        FAILED.append(what)


class Log:
    """Collects the FMU's log messages."""

    def __init__(self):
        self.messages = []

    def __call__(self, env, status, category, message):
        self.messages.append((status, category.decode(), message.decode()))


def status_of(call) -> int:
    try:
        call()
        return 0
    except FMICallException as e:
        return e.status


def slave_checks(fmu: Path) -> None:
    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    out_vr = [vr[n] for n in outputs]
    tmp = extract(str(fmu))
    log = Log()
    try:
        s = FMU3Slave(guid=md.guid, unzipDirectory=tmp,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="a")
        s.instantiate(logMessage=log, loggingOn=True)
        s.setDebugLogging(True, ["logAll"])
        # parameters set in initialisation mode
        s.enterInitializationMode(startTime=0.0, stopTime=1.0)
        s.setFloat64([vr["l_AB"]], [0.12])
        s.setInt32([vr["branch"]], [-1])
        check(s.getString([vr["method"]]) == ["closed_form"], "slave: getString(method)")
        s.exitInitializationMode()
        mech = presets.get("four_bar", l_AB=0.12, branch=-1)
        rng = np.random.default_rng(1)
        t, h = 0.0, 0.01
        worst = 0.0
        for _ in range(50):
            x = {"theta": rng.uniform(0, 2 * math.pi), "omega": rng.uniform(-5, 5),
                 "alpha": rng.uniform(-50, 50), "load": rng.uniform(-20, 20)}
            s.setFloat64([vr[n] for n in x], list(x.values()))
            ev, term, early, last = s.doStep(t, h)
            assert not ev and not term and not early and last == t + h, (ev, term, early, last)
            t += h
            y = s.getFloat64(out_vr)
            ref = mech.solve(x["theta"], x["omega"], x["alpha"], x["load"], method="direct")
            for n, value in zip(outputs, y):
                r = float(np.asarray(ref[n]))
                worst = max(worst, abs(value - r) / max(1.0, abs(r)))
        check(worst <= 1e-12, f"slave: l_AB=0.12 branch=-1, 50 random steps vs direct, worst "
              f"rel error {worst:.3g}")
        check(s.getFloat64([vr["time"]]) == [t] and
              s.getFloat64([out_vr[0], vr["time"], vr["theta"]])[1] == t,
              f"slave: the independent variable 'time' reads {t} (alone and within a list)")
        check(s.getInt32([vr["branch"]]) == [-1], "slave: getInt32(branch) = -1")

        # bad calls: an error status, a log naming the call, the instance still works
        def bad(what, call, expect=3, contains=None):
            n = len(log.messages)
            st = status_of(call)
            msg = log.messages[-1][2] if len(log.messages) > n else ""
            check(st == expect and (contains is None or contains in msg),
                  f"slave: {what} -> status {st}, log: {msg!r}")

        bad("unknown value reference", lambda: s.getFloat64([9999]), contains="9999")
        bad("set an output", lambda: s.setFloat64([out_vr[0]], [1.0]), contains="output")
        bad("setFloat64 of a fixed parameter after init", lambda: s.setFloat64([vr["l_AB"]], [0.1]),
            contains="fixed parameter")
        bad("set the independent variable", lambda: s.setFloat64([vr["time"]], [1.0]),
            contains="independent")
        bad("wrong type (getInt32 of a Float64)", lambda: s.getInt32([vr["theta"]]),
            contains="is a Float64, not a Int32")
        bad("type without variables (getFloat32)", lambda: s.getFloat32([vr["theta"]]),
            contains="not a Float32")
        bad("getUInt64", lambda: s.getUInt64([vr["branch"]]), contains="is a Int32")
        bad("getBoolean of a String", lambda: s.getBoolean([vr["method"]]),
            contains="is a String, not a Boolean")
        bad("nValues != nValueReferences", lambda: s.fmi3GetFloat64(
            s.component, (fmi3ValueReference * 2)(0, 1), 2, (fmi3Float64 * 3)(), 3),
            contains="nValues = 3")
        bad("setString method after init", lambda: s.setString([vr["method"]], ["direct"]),
            contains="fixed parameter")
        bad("doStep with h = 0", lambda: s.doStep(t, 0.0), contains="communicationStepSize")
        bad("enterInitializationMode in step mode", lambda: s.enterInitializationMode(),
            contains="not allowed in state StepMode")
        bad("enterEventMode without eventModeUsed", lambda: s.enterEventMode(),
            contains="eventModeUsed = false")
        bad("getDirectionalDerivative of an input (native: no output; pythonfmu: none)",
            lambda: s.getDirectionalDerivative([vr["theta"]], [vr["theta"]], [1.0]),
            contains="fmi3GetDirectionalDerivative: ")
        bad("updateDiscreteStates in step mode", lambda: s.updateDiscreteStates(),
            contains="not allowed in state StepMode")
        bad("setDebugLogging unknown category", lambda: s.setDebugLogging(True, ["nope"]),
            contains="unknown log category")
        x0 = {"theta": 1.0, "omega": 2.0, "alpha": 3.0, "load": 4.0}
        s.setFloat64([vr[n] for n in x0], list(x0.values()))
        ev, term, early, last = s.doStep(t, h)
        t += h
        check(not term and last == t, "slave: a valid step after the bad calls works")
        s.terminate()
        bad("doStep after terminate", lambda: s.doStep(t, h), contains="Terminated")
        check(len(s.getFloat64(out_vr)) == len(out_vr), "slave: getFloat64 in Terminated")
        s.reset()
        check(status_of(lambda: s.getFloat64([0])) == 3,
              "slave: after reset, getFloat64 is not allowed in Instantiated")
        s.freeInstance()

        # unassemblable angle: discard, NaN outputs, terminateSimulation; then a valid step
        log.messages.clear()
        s = FMU3Slave(guid=md.guid, unzipDirectory=tmp,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="b")
        s.instantiate(logMessage=log, loggingOn=True)
        s.enterInitializationMode()
        bad("setString method=direct in init", lambda: s.setString([vr["method"]], ["direct"]),
            contains="method must be one of 'closed_form', got 'direct'")
        bad("setInt32 branch=2 in init", lambda: s.setInt32([vr["branch"]], [2]),
            contains="branch must be +1 or -1")
        bad("setString invalid UTF-8", lambda: s.fmi3SetString(
            s.component, (fmi3ValueReference * 1)(vr["method"]), 1,
            (ctypes.c_char_p * 1)(b"\xff"), 1), contains="not valid UTF-8")
        s.setFloat64([vr["l_AB"]], [0.3])
        s.exitInitializationMode()
        s.setFloat64([vr["theta"]], [math.pi])
        res = {}

        def step():
            res["r"] = s.fmi3DoStep(s.component, 0.0, 0.1, True, ctypes.byref(ev_),
                                    ctypes.byref(term_), ctypes.byref(early_),
                                    ctypes.byref(last_))
        ev_, term_, early_, last_ = (ctypes.c_bool(), ctypes.c_bool(), ctypes.c_bool(),
                                     ctypes.c_double(-1.0))
        st = status_of(step)
        msg = log.messages[-1] if log.messages else None
        check(st == 2 and term_.value and not ev_.value and not early_.value and
              last_.value == 0.0, f"slave: l_AB=0.3, theta=pi: doStep status {st}, "
              f"terminateSimulation {term_.value}, lastSuccessfulTime {last_.value}, "
              f"log {msg}")
        n_out = len(out_vr)
        values = (fmi3Float64 * n_out)()
        st_get = s.fmi3GetFloat64(s.component, (fmi3ValueReference * n_out)(*out_vr), n_out,
                                  values, n_out)
        check(st_get == 1 and all(math.isnan(v) for v in values),
              f"slave: outputs after the discard are NaN, getFloat64 status {st_get} (Warning)")
        s.setFloat64([vr["theta"]], [0.5])
        ev, term, early, last = s.doStep(0.0, 0.1)
        y = s.getFloat64(out_vr)
        m3 = presets.get("four_bar", l_AB=0.3)
        # the inputs other than theta are the start values
        x_start = {v.name: float(v.start) for v in md.modelVariables if v.causality == "input"}
        ref = m3.solve(0.5, x_start["omega"], x_start["alpha"], x_start["load"],
                       method="direct")
        err = max(abs(a - float(np.asarray(ref[n]))) / max(1.0, abs(float(np.asarray(ref[n]))))
                  for n, a in zip(outputs, y))
        check(not term and last == 0.1 and err <= 1e-12,
              f"slave: the next valid step works (terminate {term}, last {last}, error {err:.3g})")

        # FMU state: get / set / serialize / deserialize, bit-exact
        state = s.getFMUState()
        y0 = s.getFloat64(out_vr + [vr["time"]])
        s.setFloat64([vr["theta"]], [0.6])
        s.doStep(0.1, 0.1)
        y1 = s.getFloat64(out_vr + [vr["time"]])
        s.setFMUState(state)
        y0b = s.getFloat64(out_vr + [vr["time"]])
        check(np.array_equal(np.array(y0).view(np.uint64), np.array(y0b).view(np.uint64))
              and y1 != y0, "slave: getFMUState/setFMUState round trip bit-exact (time too)")
        blob = s.serializeFMUState(state)
        s.freeFMUState(state)
        s.setFloat64([vr["theta"]], [0.4])
        s.doStep(0.1, 0.1)
        state2 = s.deserializeFMUState(blob)
        s.setFMUState(state2)
        y0c = s.getFloat64(out_vr + [vr["time"]])
        blob2 = s.serializeFMUState(state2)
        check(np.array_equal(np.array(y0).view(np.uint64), np.array(y0c).view(np.uint64))
              and blob == blob2, f"slave: serialize/deserialize round trip bit-exact "
              f"({len(blob)} bytes, re-serialized identical)")
        corrupt = bytearray(blob)
        corrupt[len(corrupt) // 2] ^= 1
        bad("deserialize a corrupted state",
            lambda: s.deserializeFMUState(bytes(corrupt)), contains="checksum")
        s.freeFMUState(state2)
        s.terminate()
        s.freeInstance()

        # instantiation: wrong token, event mode, model exchange
        s = FMU3Slave(guid="{not-the-token}", unzipDirectory=tmp,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="c")
        try:
            s.instantiate(logMessage=log)
            ok = False
        except Exception:
            ok = "does not match" in log.messages[-1][2]
        check(ok, f"slave: a wrong instantiation token is refused ({log.messages[-1][2]!r})")
        s = FMU3Slave(guid=md.guid, unzipDirectory=tmp,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="d")
        s.instantiate(logMessage=log, eventModeUsed=True)
        s.enterInitializationMode()
        s.exitInitializationMode()  # into event mode
        bad("doStep in event mode", lambda: s.doStep(0.0, 0.1), contains="EventMode")
        flags = s.updateDiscreteStates()
        s.enterStepMode()
        ev, term, early, last = s.doStep(0.0, 0.1)
        s.enterEventMode()
        s.setFloat64([vr["theta"]], [0.5])
        y = s.getFloat64(out_vr)
        s.updateDiscreteStates()
        s.enterStepMode()
        s.doStep(0.1, 0.1)
        ref = presets.get("four_bar").solve(0.5, x_start["omega"], x_start["alpha"],
                                            x_start["load"], method="direct")
        err = max(abs(a - float(np.asarray(ref[n]))) / max(1.0, abs(float(np.asarray(ref[n]))))
                  for n, a in zip(outputs, y))
        check(not any(flags[:5]) and not ev and not term and last == 0.1 and err <= 1e-12,
              f"slave: eventModeUsed=true instantiates; event mode asks for nothing "
              f"({flags}), steps go on, outputs read in event mode (error {err:.3g})")
        s.terminate()
        s.freeInstance()
        s.freeLibrary()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    slave_checks(Path(sys.argv[1]))
    print(f"{len(FAILED)} failed" if FAILED else "all passed")
    sys.exit(1 if FAILED else 0)
