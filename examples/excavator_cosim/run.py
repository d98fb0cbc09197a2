"""The excavator arm's FMU in libcosim: a digging cycle of its three cylinders, given as
tables, and the forces the cylinders must give, against the library.

    python examples/excavator_cosim/run.py [--step 0.01] [--out dist/excavator_cosim]

Builds the native FMI 2.0 FMU of ``examples/excavator.toml`` and runs it in libcosim (the
Open Simulation Platform's engine, through ``libcosimpy``), in a process of its own that
never imports ``linkage_fmu`` (this script, run again with ``--host``). The cycle is
:func:`cycle`: the bucket curls in while the stick pulls in, then the boom lifts, each
travel a smooth ramp (its speed and acceleration its derivatives), with 15 kN on the
bucket's teeth while it digs. Before each step libcosim's override manipulator sets the
row's nine inputs and the load; its last value observer reads the FMU's outputs after
the step (the FMU is direct feedthrough: the outputs of the row's inputs). Every output
is compared with ``Mechanism.solve`` at the same rows; the run prints the largest
difference (relative to the largest output of its unit), each cylinder's range of force
and the pressure its push needs on the bore side and its pull on the rod side
(:data:`BORES`).
It exits with status 1 where the difference exceeds 1e-12, 2 where libcosim is missing.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SOURCE = ROOT / "examples" / "excavator.toml"
#: each cylinder's bore and rod diameters, m (a 20 t machine's, about)
BORES = {"cyl1": (0.14, 0.10), "cyl2": (0.15, 0.105), "cyl3": (0.13, 0.09)}
#: the cycle: per cylinder, (start, end) of its travel [m] and (t0, t1) of its ramp [s]
CYCLE = {"cyl1": ((0.0, 0.25), (4.0, 6.0)), "cyl2": ((0.0, -0.3), (1.0, 4.0)),
         "cyl3": ((0.0, 0.3), (0.5, 3.0))}
DURATION, DIG = 6.0, (0.5, 4.0)  # s: the cycle, and while the teeth dig (F_T on)


def ramp(t: np.ndarray, a: float, b: float, t0: float, t1: float) -> tuple:
    """``a`` to ``b`` between ``t0`` and ``t1``, as ``(1 - cos)/2``: the travel, speed and
    acceleration."""
    u = np.clip((t - t0) / (t1 - t0), 0.0, 1.0)
    inside = (t > t0) & (t < t1)
    w = math.pi / (t1 - t0)
    s = a + (b - a) * 0.5 * (1.0 - np.cos(math.pi * u))
    v = np.where(inside, (b - a) * 0.5 * w * np.sin(math.pi * u), 0.0)
    acc = np.where(inside, (b - a) * 0.5 * w * w * np.cos(math.pi * u), 0.0)
    return s, v, acc


def cycle(step: float) -> dict:
    """The inputs at ``t = 0, step, ...`` up to :data:`DURATION`, by name."""
    t = np.arange(0.0, DURATION + step / 2, step)
    rows = {"time": t}
    for name, ((a, b), (t0, t1)) in CYCLE.items():
        rows[f"s_{name}"], rows[f"v_{name}"], rows[f"a_{name}"] = ramp(t, a, b, t0, t1)
    rows["F_T"] = np.where((t >= DIG[0]) & (t <= DIG[1]), 15000.0, 0.0)
    return rows


def host(job: Path) -> None:
    """Run the FMU of ``job`` in libcosim, one step per row; print one JSON line."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    spec = json.loads(job.read_text())
    execution = CosimExecution.from_step_size(spec["h_ns"])
    index = execution.add_local_slave(CosimLocalSlave(fmu_path=spec["fmu"],
                                                      instance_name="excavator"))
    variables = execution.slave_variables(index)
    refs = {v.name.decode(): v.reference for v in variables}
    outputs = [v.name.decode() for v in variables if v.causality == 2]
    manipulator = CosimManipulator.create_override()
    execution.add_manipulator(manipulator)
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    inputs = [refs[n] for n in spec["names"]]
    got = []
    for row in spec["rows"]:
        manipulator.slave_real_values(index, inputs, row)
        if not execution.step():
            raise SystemExit(f"libcosim: the step at row {len(got)} failed")
        got.append(observer.last_real_values(index, [refs[n] for n in outputs]))
    print(json.dumps({"names": outputs, "values": got}), flush=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--step", type=float, default=0.01, help="communication step, s")
    parser.add_argument("--out", type=Path, default=ROOT / "dist" / "excavator_cosim")
    parser.add_argument("--host", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.host:
        host(args.host)
        return 0
    try:
        import libcosimpy  # noqa: F401
    except ImportError:
        print("run.py: libcosimpy is not installed (pip install libcosimpy)", file=sys.stderr)
        return 2
    import linkage_fmu
    from linkage_fmu.fmi import build_native_fmu
    from linkage_fmu.fmi.check import compare

    fmu = build_native_fmu(SOURCE, args.out)
    mech = linkage_fmu.load(SOURCE)
    rows = cycle(args.step)
    names = list(mech.input_names)
    job = args.out / "job.json"
    job.write_text(json.dumps({"fmu": str(fmu.resolve()), "h_ns": round(args.step * 1e9),
                               "names": names,
                               "rows": np.column_stack([rows[n] for n in names]).tolist()}))
    run = subprocess.run([sys.executable, __file__, "--host", str(job)], cwd=args.out,
                         capture_output=True, text=True)
    if run.returncode != 0:
        print(f"run.py: libcosim's run failed: {run.stderr[-2000:]}", file=sys.stderr)
        return 1
    result = json.loads(next(line for line in reversed(run.stdout.splitlines())
                             if line.startswith('{"names"')))
    got = {n: np.array(v) for n, v in zip(result["names"], np.array(result["values"]).T)}
    want = mech.solve(**{n: rows[n] for n in names})
    outputs = list(mech.output_names + mech.diagnostic_names)
    err, where = compare(got, want, outputs, {n: mech.output_info[n][0] for n in outputs})
    print(f"{fmu.name} in libcosim, {len(rows['time'])} steps of {args.step:g} s: every "
          f"output within {err:.2g} ({where or 'every output'}) of Mechanism.solve, relative "
          "to the largest output of its unit")
    for name, (bore, rod) in BORES.items():
        force = got[f"Fb_{name}"]
        low, high = float(force.min()), float(force.max())
        full, annulus = math.pi * bore ** 2 / 4, math.pi * (bore ** 2 - rod ** 2) / 4
        needs = ([f"{high / full / 1e5:.0f} bar on the bore side to push"] if high > 0 else
                 []) + ([f"{-low / annulus / 1e5:.0f} bar on the rod side to pull"]
                        if low < 0 else [])
        print(f"  {name}: Fb_{name} from {low / 1e3:.1f} to {high / 1e3:.1f} kN: "
              f"{', '.join(needs)}")
    return 0 if err <= 1e-12 else 1


if __name__ == "__main__":
    sys.exit(main())
