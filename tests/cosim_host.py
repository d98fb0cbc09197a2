"""Runs FMUs in libcosim (the Open Simulation Platform's co-simulation engine, through
libcosimpy) in a fresh process (started by ``test_libcosim.py``, never imported).

Usage: ``python cosim_host.py JOB.json`` prints one JSON line: a list with one result per
FMU of the job. Each FMU of the job runs in an execution of its own (a fixed-step
algorithm, step ``h_ns`` nanoseconds) with an override manipulator that sets the inputs
and a last value observer that reads the outputs. For each row ``k`` of ``inputs``:

1. the manipulator overrides every input with row ``k``'s values;
2. ``execution.step()`` applies the overrides to the FMU and calls its doStep from
   ``t_k`` to ``t_k + h``;
3. the observer's values, read now (time ``t_k + h``), are the outputs the FMU computed
   from row ``k``'s inputs.

So a result's ``outputs[k]`` pairs with ``inputs[k]``; ``ok[k]`` is what ``step()`` said,
``errors[k]`` libcosim's message if it failed, ``time_ns[k]`` and ``states[k]`` the
execution's time and state after it (0 stopped, 1 running, 2 error). With ``until`` (one
target time in ns per row), each row's inputs are set and ``simulate_until`` runs to the
row's target instead of one step. An FMU libcosim cannot load gives
``error`` (libcosim's message) and nothing else. This process never imports linkage_fmu,
so each FMU runs what it bundles.
"""

import json
import sys

from libcosimpy._internal import get_last_error_message
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
from libcosimpy.CosimManipulator import CosimManipulator
from libcosimpy.CosimObserver import CosimObserver
from libcosimpy.CosimSlave import CosimLocalSlave

INPUT, OUTPUT = 0, 2  # libcosim's variable causalities


def run(job: dict) -> dict:
    execution = CosimExecution.from_step_size(job["h_ns"])
    slave = CosimLocalSlave(fmu_path=job["fmu"], instance_name="linkage")
    if not slave.ptr():
        # adding the null slave would crash the process: say what libcosim said
        return {"error": get_last_error_message()}
    index = execution.add_local_slave(slave)
    variables = execution.slave_variables(index)
    refs = {v.name.decode(): v.reference for v in variables}
    outputs = [v.name.decode() for v in variables if v.causality == OUTPUT]
    inputs = [v.name.decode() for v in variables if v.causality == INPUT]
    if inputs != job["input_names"]:
        return {"error": f"the FMU's inputs are {inputs}, the job's {job['input_names']}"}
    manipulator = CosimManipulator.create_override()
    execution.add_manipulator(manipulator)
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    in_refs, out_refs = [refs[n] for n in inputs], [refs[n] for n in outputs]
    result = {"names": outputs, "ok": [], "time_ns": [], "outputs": [], "errors": [],
              "states": []}
    for row, until in zip(job["inputs"], job.get("until") or [None] * len(job["inputs"])):
        manipulator.slave_real_values(index, in_refs, row)
        ok = execution.step() if until is None else execution.simulate_until(until)
        result["states"].append(execution.status().state)
        result["ok"].append(ok)
        result["errors"].append("" if ok else get_last_error_message().strip())
        result["time_ns"].append(execution.status().current_time)
        result["outputs"].append(observer.last_real_values(index, out_refs))
    return result


def main(jobs: list) -> list:
    log_output_level(CosimLogLevel.ERROR)
    return [run(job) for job in jobs]


if __name__ == "__main__":
    with open(sys.argv[1]) as f:
        print(json.dumps(main(json.load(f))), flush=True)
