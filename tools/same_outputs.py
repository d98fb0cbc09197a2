"""Same outputs, bit for bit: record what ``linkage_fmu`` computes, and compare two records.

A refactor whose acceptance criterion is "the outputs are bit-identical to the commit
before it" needs a record of that commit's outputs and a bitwise comparison. ``dump``
evaluates a fixed, seeded set of cases through the public API only, so that it runs
unchanged before and after the refactor, and stores every output array in one ``.npz``;
``compare`` compares two such files value by value on the bits of the float64.

Commands
--------
``python tools/same_outputs.py dump OUT.npz [--fmus] [--states N] [--fmu-states N]``
    Evaluate the cases below and write them to ``OUT.npz``. The package is whatever
    ``import linkage_fmu`` finds: set ``PYTHONPATH=<checkout>/src`` to choose the
    checkout (the file records ``linkage_fmu.__file__`` and its git commit under
    ``meta|...``). Compiled kernels go to ``$LINKAGE_FMU_CACHE``.
``python tools/same_outputs.py compare A.npz B.npz [--show N]``
    Compare key by key; print per-group counts and the first ``N`` differences; exit 1
    if any value differs (or a key is missing or changed shape), else 0.

Cases
-----
All inputs are drawn from ``numpy.random.default_rng([2026, crc32(case label)])``: each
case has its own stream, so the inputs of one case do not depend on which others run.
Every input array is stored too (keys with method ``inputs``), so that ``compare`` also
proves both files evaluated the same states.

* Linkages: the 15 variants of ``tests/conftest.py`` (``VARIANTS``, copied here as of
  the baseline), ``four_bar`` with ``l_AB=0.3`` (assembles only over part of a
  revolution), every preset with friction in every pair (``FRICTION``) and every
  example file, ``examples/joints/`` too (through ``linkage_fmu.load``).
* Methods ``closed_form``, ``interpreted``, ``direct``; plans (``outputs=``) ``all``
  (None), ``effort`` (the balancing effort alone), ``subset`` (the first two outputs),
  ``diagnostics``; motions ``moving`` (omega in [-30, 30], alpha in [-100, 100], loads
  in [-500, 500]) and ``static`` (omega = alpha = 0).
* ``scalar``: ``--states`` states solved one at a time with Python floats on a fresh
  mechanism (so one-state closed-form calls stay in the Python kernel); a state that
  raises has NaN outputs and its exception class name under ``...|!error`` ('' where it
  solved): ``ValueError`` and ``ArithmeticError`` (cannot be assembled, singular,
  overflow), and any other exception too (at the baseline, ``KeyError`` for six_bar
  drivers other than OA, interpreted, subset plan, static: a bug, recorded as behaviour).
* ``scalar_compiled`` (closed_form): the same states after
  ``mech.kernel(outputs, static).compile()``: the compiled one-state kernel of each plan.
* ``scalar_hot`` (closed_form, all outputs): 2,100 one-state calls on a fresh mechanism:
  the first 1000 through the Python kernel, the rest compiled (``HOT_CALLS``), with the
  fast path of ``outputs=None``.
* ``special`` and ``special_array``: theta in {0, pi/2, pi, 3pi/2} (moving and static),
  overflowing inputs (omega = 1e160, ...), all zeros, -0.0, 2pi, negative and large
  angles; one at a time, then as one array.
* ``array``: 4,096 states in one call, with ``sol.valid`` under ``...|!valid``.
* ``big``: 100,000 states, closed_form, all outputs, moving, for ``four_bar``,
  ``slider_crank`` and ``six_bar`` (driver OA): the threaded compiled array kernel.
* ``--fmus``: the pythonfmu FMU (run with ``method`` ``closed_form`` and ``direct``), the
  native FMI 2.0 and the native FMI 3.0 FMU of every preset, each built into a temporary
  folder and driven in a fresh process that never imports ``linkage_fmu`` (the pythonfmu
  FMU runs the copy it bundles, which is checked): instantiate, set up, initialise, then
  ``--fmu-states`` seeded steps (set every input, doStep, read every output in one
  call), recording the values and each call's status. The default 1200 steps take the
  pythonfmu FMU's closed form past its 1000th call, where it compiles.

Keys
----
``linkage|parameters|method|plan|motion|kind|name``, e.g.
``four_bar|branch=-1,beta2=0.4,...|closed_form|all|moving|scalar|Mb``; ``name`` is an
output, ``!error`` or ``!valid``. Inputs: method ``inputs``, plan ``-``, ``name`` an
input name. FMUs: ``fmu|flavour|preset|name`` with ``name`` an output, ``!status``
(per step: set, doStep, get, and FMI 3.0's terminateSimulation, -1 where none) or
``!setup`` (setup, enter, exit, terminate), and ``fmu|flavour|preset|@inputs``.
``meta|...``: where and when the file was made (not compared).

Comparison
----------
Float arrays are compared on their bits (``view(uint64)``): NaN payloads too, and -0.0
differs from 0.0. States where one side is NaN and the other is not are counted apart
(and are differences). FMU outputs are compared only where both sides are finite: at an
unsolvable state the statuses (and which outputs are NaN) may legitimately change, so
those and status differences are reported, not counted as failures.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Iterator

import numpy as np

# linkage_fmu is imported inside the functions of ``dump`` only: the FMU host (the hidden
# ``fmu-host`` command, run in a fresh process) must never import it.

SEED = 2026
ROOT = Path(__file__).resolve().parents[1]
#: tests/conftest.py VARIANTS at the baseline: every preset and every six-bar driver
VARIANTS: list[tuple[str, dict]] = [
    ("scotch_yoke", {}),
    ("scotch_yoke", {"m1": 1.5, "J1": 0.01, "J3": 0.2, "g": 9.81}),
    ("four_bar", {}),
    ("four_bar", {"branch": -1, "beta2": 0.4, "beta3": -0.3, "l_AS1": 0.03, "J1": 0.001}),
    ("slider_crank", {}),
    ("slider_crank", {"e": 0.02, "gamma": 0.7, "m1": 0.5, "J1": 1e-3, "l_OS1": 0.02}),
    ("six_bar", {"driver": "OA"}),
    ("six_bar", {"driver": "AB"}),
    ("six_bar", {"driver": "O1B"}),
    ("six_bar", {"driver": "KD"}),
    ("six_bar", {"driver": "D"}),
    ("slotted_lever", {}),
    ("slotted_lever", {"l_AB": 0.55, "l_AC": 0.25, "l_CS3": -0.1}),
    ("crank_shaper", {}),
    ("crank_shaper", {"branch": -1, "l_AB": 0.2, "h_E": 0.35, "g": 0.0}),
]
#: every linkage of the record: the variants, a crank too long to turn, the example file
#: every preset with friction in every pair (pins of radius 0.01 m)
FRICTION: list[tuple[str, dict]] = [
    ("scotch_yoke", {"mu_A": 0.1, "r_A": 0.01, "mu_B": 0.1, "r_B": 0.01, "mu_slot": 0.08,
                     "mu_guide": 0.12}),
    ("four_bar", {"mu_A": 0.1, "r_A": 0.01, "mu_B": 0.1, "r_B": 0.01, "mu_C": 0.1,
                  "r_C": 0.01, "mu_D": 0.1, "r_D": 0.01}),
    ("slider_crank", {"mu_O": 0.1, "r_O": 0.01, "mu_A": 0.1, "r_A": 0.01, "mu_B": 0.1,
                      "r_B": 0.01, "mu_guide": 0.1}),
    ("six_bar", {"driver": "OA", "mu_O": 0.1, "r_O": 0.01, "mu_A": 0.1, "r_A": 0.01,
                 "mu_B": 0.1, "r_B": 0.01, "mu_O1": 0.1, "r_O1": 0.01, "mu_K": 0.1,
                 "r_K": 0.01, "mu_D": 0.1, "r_D": 0.01, "mu_guide": 0.1}),
    ("slotted_lever", {"mu_A": 0.1, "r_A": 0.01, "mu_B": 0.1, "r_B": 0.01, "mu_slot": 0.1,
                       "mu_C": 0.1, "r_C": 0.01}),
    ("crank_shaper", {"mu_A": 0.1, "r_A": 0.01, "mu_B": 0.1, "r_B": 0.01, "mu_slot": 0.1,
                      "mu_C": 0.1, "r_C": 0.01, "mu_D": 0.1, "r_D": 0.01, "mu_E": 0.1,
                      "r_E": 0.01, "mu_guide": 0.1}),
]
#: every example file (the joints-and-links form of each preset among them)
EXAMPLES: list[tuple[str, dict]] = [
    (str(path), {}) for path in sorted(ROOT.glob("examples/*.toml"))
    + sorted(ROOT.glob("examples/joints/*.toml"))]
#: every linkage of the record: the variants, a crank too long to turn, friction, the
#: example files
LINKAGES: list[tuple[str, dict]] = (VARIANTS + [("four_bar", {"l_AB": 0.3})] + FRICTION
                                    + EXAMPLES)
METHODS = ("closed_form", "interpreted", "direct")
PLANS = ("all", "effort", "subset", "diagnostics")
MOTIONS = ("moving", "static")
ARRAY_STATES = 4096
BIG_STATES = 100_000
BIG_LINKAGES: list[tuple[str, dict]] = [("four_bar", {}), ("slider_crank", {}),
                                        ("six_bar", {"driver": "OA"})]
HOT_STATES = 2100
FMU_FLAVOURS = ("pythonfmu", "pythonfmu_direct", "fmi2", "fmi3")
FMU_STEP = 1e-3
#: differences listed by ``compare``
SHOW_DEFAULT = 10


# -- inputs ---------------------------------------------------------------------------
def rng_for(*labels: str) -> np.random.Generator:
    """The generator of one case: seeded with 2026 and the case's label."""
    return np.random.default_rng([SEED, zlib.crc32("|".join(labels).encode())])


def draw_states(rng: np.random.Generator, n: int, n_loads: int, static: bool) -> np.ndarray:
    """``n`` states as rows ``(theta, omega, alpha, *loads)``: theta in [0, 2 pi), omega
    in [-30, 30], alpha in [-100, 100] (both 0 if ``static``), loads in [-500, 500]."""
    theta = rng.uniform(0.0, 2.0 * math.pi, n)
    omega = rng.uniform(-30.0, 30.0, n)
    alpha = rng.uniform(-100.0, 100.0, n)
    loads = rng.uniform(-500.0, 500.0, (n, n_loads))
    if static:
        omega[:] = 0.0
        alpha[:] = 0.0
    return np.column_stack([theta, omega, alpha, loads])


def special_states(n_loads: int) -> np.ndarray:
    """Toggle-prone angles, overflowing inputs, zeros and odd angles, as rows."""
    rows = []
    for theta in (0.0, 0.5 * math.pi, math.pi, 1.5 * math.pi):
        rows.append((theta, 10.0, -20.0, 100.0))
        rows.append((theta, 0.0, 0.0, 100.0))
    rows += [
        (1.0, 1e160, 0.0, 0.0),     # omega**2 overflows
        (1.0, 1e160, 1.0, 100.0),
        (1.0, 0.0, 1e300, 100.0),   # alpha huge
        (1.0, 1.0, 0.0, 1e300),     # load huge
        (1.0, 0.0, 0.0, 0.0),       # nothing moves, nothing loads
        (-0.0, 0.0, 0.0, 0.0),
        (2.0 * math.pi, 10.0, 0.0, 100.0),
        (-1.0, 10.0, 5.0, -100.0),
        (100.0, 3.0, 2.0, 50.0),
        (1e6, 3.0, 2.0, 50.0),
    ]
    return np.array([(t, w, a) + (load,) * n_loads for t, w, a, load in rows])


# -- the linkages ---------------------------------------------------------------------
def linkage_label(source: str, parameters: dict) -> str:
    """``name|parameters`` of a linkage in the keys."""
    name = (Path(source).resolve().relative_to(ROOT).with_suffix("").as_posix()
            if source.endswith(".toml") else source)
    params = ",".join(f"{k}={v}" for k, v in parameters.items()) or "defaults"
    return f"{name}|{params}"


def build(source: str, parameters: dict):
    """A fresh Mechanism (no kernel traced, no call counted) of a preset or a file."""
    import linkage_fmu
    from linkage_fmu import presets

    if source.endswith(".toml"):
        return linkage_fmu.load(source, **parameters)
    return presets.get(source, **parameters)


def plan_outputs(mech, plan: str) -> tuple | None:
    """The ``outputs=`` argument of a plan."""
    if plan == "all":
        return None
    if plan == "effort":
        return (mech.effort.name,)
    if plan == "subset":
        return tuple(mech.output_names[:2])
    if plan == "diagnostics":
        return tuple(mech.diagnostic_names)
    raise ValueError(f"unknown plan {plan!r}")


def plan_names(mech, outputs: tuple | None) -> tuple:
    """The names a plan answers."""
    return tuple(mech.output_names) + tuple(mech.diagnostic_names) if outputs is None \
        else outputs


# -- solving --------------------------------------------------------------------------
@dataclass
class Record:
    """The arrays of a dump, by key, and what was done."""

    arrays: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)

    def put(self, key: str, value: Any) -> None:
        if key in self.arrays:
            raise KeyError(f"key recorded twice: {key}")
        self.arrays[key] = np.asarray(value)

    def put_inputs(self, prefix: str, names: Iterable[str], states: np.ndarray) -> None:
        for i, name in enumerate(names):
            self.put(f"{prefix}|{name}", states[:, i].copy())


def solve_one_by_one(mech, states: np.ndarray, method: str, outputs: tuple | None,
                     names: tuple) -> tuple[np.ndarray, np.ndarray]:
    """Each state through ``solve`` with Python floats (loads positional): the outputs
    (rows of NaN where it raised) and the exception class names ('' where it solved)."""
    values = np.full((len(states), len(names)), np.nan)
    errors = [""] * len(states)
    for i, row in enumerate(states.tolist()):  # Python floats
        try:
            sol = mech.solve(*row, method=method, outputs=outputs)
        except Exception as err:  # ValueError, ArithmeticError; any other is kept too
            errors[i] = type(err).__name__
            continue
        values[i] = [sol[n] for n in names]
    return values, np.array(errors, dtype=str)


def put_scalar_case(rec: Record, prefix: str, names: tuple, values: np.ndarray,
                    errors: np.ndarray) -> None:
    for j, name in enumerate(names):
        rec.put(f"{prefix}|{name}", values[:, j].copy())
    rec.put(f"{prefix}|!error", errors)


def solve_arrays(mech, states: np.ndarray, method: str, outputs: tuple | None,
                 static: bool) -> Any:
    """All states in one call: arrays of theta and of each load; omega and alpha arrays,
    or the floats 0.0 if ``static``."""
    columns = [states[:, i].copy() for i in range(states.shape[1])]
    if static:
        columns[1] = columns[2] = 0.0
    return mech.solve(*columns, method=method, outputs=outputs)


def put_array_case(rec: Record, prefix: str, mech, states: np.ndarray, method: str,
                   outputs: tuple | None, static: bool) -> None:
    names = plan_names(mech, outputs)
    try:
        sol = solve_arrays(mech, states, method, outputs, static)
    except Exception as err:  # recorded, so that a change shows
        rec.put(f"{prefix}|!error", np.array([type(err).__name__]))
        return
    for name in names:
        rec.put(f"{prefix}|{name}", np.asarray(sol[name], dtype=float))
    rec.put(f"{prefix}|!valid", np.asarray(sol.valid, dtype=bool))
    rec.put(f"{prefix}|!error", np.array([""]))


@contextlib.contextmanager
def timed(rec: Record, label: str) -> Iterator[None]:
    """Add the seconds spent in the ``with`` block to ``rec.timings[label]``."""
    t0 = time.perf_counter()
    try:
        yield
    finally:
        rec.timings[label] = rec.timings.get(label, 0.0) + time.perf_counter() - t0


def linkage_inputs(rec: Record, label: str, inputs: tuple, n_states: int) -> dict:
    """The inputs of a linkage's cases, recorded; (kind, motion) -> states."""
    n_loads = len(inputs) - 3
    special = special_states(n_loads)
    states = {("special", "mixed"): special, ("special_array", "mixed"): special}
    for motion in MOTIONS:
        static = motion == "static"
        for kind, n in (("scalar", n_states), ("array", ARRAY_STATES),
                        ("scalar_hot", HOT_STATES)):
            states[kind, motion] = draw_states(rng_for(label, motion, kind), n, n_loads, static)
    for (kind, motion), rows in states.items():
        rec.put_inputs(f"{label}|inputs|-|{motion}|{kind}", inputs, rows)
    return states


def dump_plan(rec: Record, source: str, parameters: dict, method: str, plan: str,
              states: dict) -> None:
    """One method and plan of a linkage: scalar (and compiled scalar), array and special
    cases, each on a fresh mechanism."""
    label = linkage_label(source, parameters)
    for motion in MOTIONS:
        static = motion == "static"
        prefix = f"{label}|{method}|{plan}|{motion}"
        mech = build(source, parameters)  # fresh: its kernels count calls from zero
        outputs = plan_outputs(mech, plan)
        names = plan_names(mech, outputs)
        with timed(rec, f"scalar {method}"):
            put_scalar_case(rec, f"{prefix}|scalar", names, *solve_one_by_one(
                mech, states["scalar", motion], method, outputs, names))
        if method == "closed_form":
            with timed(rec, "scalar_compiled closed_form"):
                mech = build(source, parameters)
                mech.kernel(outputs, static).compile()
                put_scalar_case(rec, f"{prefix}|scalar_compiled", names, *solve_one_by_one(
                    mech, states["scalar", motion], method, outputs, names))
        with timed(rec, f"array {method}"):
            put_array_case(rec, f"{prefix}|array", build(source, parameters),
                           states["array", motion], method, outputs, static)
    prefix = f"{label}|{method}|{plan}|mixed"
    with timed(rec, f"special {method}"):
        mech = build(source, parameters)
        outputs = plan_outputs(mech, plan)
        names = plan_names(mech, outputs)
        put_scalar_case(rec, f"{prefix}|special", names, *solve_one_by_one(
            mech, states["special", "mixed"], method, outputs, names))
        put_array_case(rec, f"{prefix}|special_array", build(source, parameters),
                       states["special_array", "mixed"], method, outputs, False)


def dump_linkage(rec: Record, source: str, parameters: dict, n_states: int) -> None:
    """Every method x plan x motion of one linkage, and the hot one-state runs."""
    label = linkage_label(source, parameters)
    states = linkage_inputs(rec, label, tuple(build(source, parameters).input_names), n_states)
    for method in METHODS:
        for plan in PLANS:
            dump_plan(rec, source, parameters, method, plan, states)
    # many one-state calls: the Python kernel, then (from the 1001st) the compiled one
    with timed(rec, "scalar_hot closed_form"):
        for motion in MOTIONS:
            mech = build(source, parameters)
            names = plan_names(mech, None)
            put_scalar_case(rec, f"{label}|closed_form|all|{motion}|scalar_hot", names,
                            *solve_one_by_one(mech, states["scalar_hot", motion],
                                              "closed_form", None, names))


def dump_big(rec: Record) -> None:
    """100,000 states in one closed-form call: the compiled array kernel on threads."""
    for source, parameters in BIG_LINKAGES:
        label = linkage_label(source, parameters)
        mech = build(source, parameters)
        states = draw_states(rng_for(label, "moving", "big"), BIG_STATES,
                             len(mech.input_names) - 3, False)
        rec.put_inputs(f"{label}|inputs|-|moving|big", mech.input_names, states)
        put_array_case(rec, f"{label}|closed_form|all|moving|big", mech, states, "closed_form",
                       None, False)


# -- FMUs -----------------------------------------------------------------------------
def fmu_states(preset: str, n: int, n_loads: int) -> np.ndarray:
    """The steps of a preset's FMUs: random states, every tenth static, special angles
    first, one overflowing speed; all finite."""
    states = draw_states(rng_for("fmu", preset), n, n_loads, False)
    states[::10, 1:3] = 0.0
    for i, theta in enumerate((0.0, 0.5 * math.pi, math.pi, 1.5 * math.pi)):
        states[1 + i, 0] = theta
    states[7, 1] = 1e160  # overflow: unsolvable once
    return states


def build_fmus(preset: str, folder: Path) -> dict[str, Path]:
    """The three FMUs of a preset, in sub-folders of ``folder``; flavour -> path."""
    from linkage_fmu.fmi import build_fmu, build_native_fmu

    python = build_fmu(preset, folder / "pythonfmu")
    return {"pythonfmu": python, "pythonfmu_direct": python,
            "fmi2": build_native_fmu(preset, folder / "fmi2", 2),
            "fmi3": build_native_fmu(preset, folder / "fmi3", 3)}


def host_environment() -> dict:
    """The FMU host's environment: no PYTHONPATH, so nothing points it at a checkout."""
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)
    return env


def run_fmu_host(fmu: Path, flavour: str, input_names: tuple, states: np.ndarray,
                 folder: Path) -> dict:
    """Drive one FMU in a fresh process (``fmu-host``); its result arrays."""
    job = folder / f"{fmu.stem}-{flavour}.json"
    result = folder / f"{fmu.stem}-{flavour}.npz"
    job.write_text(json.dumps({
        "fmu": str(fmu), "fmi": 3 if flavour == "fmi3" else 2,
        "method": "direct" if flavour == "pythonfmu_direct" else None,
        "bundled": flavour.startswith("pythonfmu"), "inputs": list(input_names),
        "states": states.tolist(), "out": str(result)}))
    run = subprocess.run([sys.executable, str(Path(__file__).resolve()), "fmu-host", str(job)],
                         env=host_environment(), cwd=folder, capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError(f"FMU host for {fmu} ({flavour}) failed:\n{run.stdout}\n{run.stderr}")
    with np.load(result, allow_pickle=False) as data:
        return {k: data[k] for k in data.files}


def dump_fmus(rec: Record, n_states: int) -> None:
    """Build and drive the FMUs of every preset (see the module docstring)."""
    from linkage_fmu import presets

    with tempfile.TemporaryDirectory(prefix="same_outputs_fmus_") as tmp:
        for preset in presets.names():
            folder = Path(tmp) / preset
            with timed(rec, "fmu build"):
                fmus = build_fmus(preset, folder)
            input_names = tuple(presets.get(preset).input_names)
            states = fmu_states(preset, n_states, len(input_names) - 3)
            for flavour in FMU_FLAVOURS:
                with timed(rec, f"fmu run {flavour}"):
                    out = run_fmu_host(fmus[flavour], flavour, input_names, states, folder)
                prefix = f"fmu|{flavour}|{preset}"
                rec.put(f"{prefix}|@inputs", states)
                for j, name in enumerate(out["outputs"].tolist()):
                    rec.put(f"{prefix}|{name}", out["values"][:, j].copy())
                rec.put(f"{prefix}|!status", out["status"])
                rec.put(f"{prefix}|!setup", out["setup"])
                if flavour.startswith("pythonfmu"):
                    rec.put(f"meta|fmu|{flavour}|{preset}|package", out["package"])


def host_fmi2(md, unzip: str, job: dict, in_vr: list, out_vr: list) -> tuple:
    """Steps of an FMI 2.0 FMU through fmpy's raw functions; (values, status, setup)."""
    from ctypes import c_char_p, c_double, c_uint

    from fmpy import calloc, free
    from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE,
                           fmi2CallbackFreeMemoryTYPE, fmi2CallbackFunctions,
                           fmi2CallbackLoggerTYPE)

    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzip,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="same")
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = fmi2CallbackLoggerTYPE(lambda *args: None)
    callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    fmu.instantiate(callbacks=callbacks, loggingOn=False)
    fn, c = fmu._functions, fmu.component
    setup = [fn["fmi2SetupExperiment"](c, 0, 0.0, 0.0, 0, 0.0),
             fn["fmi2EnterInitializationMode"](c)]
    if job["method"]:
        vr = (c_uint * 1)(job["method_vr"])
        setup.append(fn["fmi2SetString"](c, vr, 1, (c_char_p * 1)(job["method"].encode())))
    else:
        setup.append(-1)
    setup.append(fn["fmi2ExitInitializationMode"](c))
    vin, vout = (c_uint * len(in_vr))(*in_vr), (c_uint * len(out_vr))(*out_vr)
    u, y = (c_double * len(in_vr))(), (c_double * len(out_vr))()
    states = job["states"]
    values = np.empty((len(states), len(out_vr)))
    status = np.full((len(states), 4), -1, dtype=np.int64)
    t = 0.0
    for i, row in enumerate(states):
        u[:] = row
        status[i, 0] = fn["fmi2SetReal"](c, vin, len(in_vr), u)
        status[i, 1] = fn["fmi2DoStep"](c, t, FMU_STEP, 1)
        status[i, 2] = fn["fmi2GetReal"](c, vout, len(out_vr), y)
        values[i] = y[:]
        t += FMU_STEP
    setup.append(fn["fmi2Terminate"](c))
    fn["fmi2FreeInstance"](c)
    return values, status, np.array(setup, dtype=np.int64)


def host_fmi3(md, unzip: str, job: dict, in_vr: list, out_vr: list) -> tuple:
    """Steps of an FMI 3.0 FMU through fmpy's raw functions; (values, status, setup)."""
    from ctypes import byref, c_bool, c_double

    from fmpy.fmi3 import FMU3Slave, fmi3Float64, fmi3ValueReference

    fmu = FMU3Slave(guid=md.guid, unzipDirectory=unzip,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="same")
    fmu.instantiate(loggingOn=False, logMessage=lambda *args: None)
    fn, c = fmu._functions, fmu.component
    setup = [-1, fn["fmi3EnterInitializationMode"](c, False, 0.0, 0.0, False, 0.0), -1,
             fn["fmi3ExitInitializationMode"](c)]
    n_in, n_out = len(in_vr), len(out_vr)
    vin, vout = (fmi3ValueReference * n_in)(*in_vr), (fmi3ValueReference * n_out)(*out_vr)
    u, y = (fmi3Float64 * n_in)(), (fmi3Float64 * n_out)()
    event, term, early, last = c_bool(), c_bool(), c_bool(), c_double()
    states = job["states"]
    values = np.empty((len(states), n_out))
    status = np.full((len(states), 4), -1, dtype=np.int64)
    t = 0.0
    for i, row in enumerate(states):
        u[:] = row
        status[i, 0] = fn["fmi3SetFloat64"](c, vin, n_in, u, n_in)
        status[i, 1] = fn["fmi3DoStep"](c, t, FMU_STEP, True, byref(event), byref(term),
                                        byref(early), byref(last))
        status[i, 2] = fn["fmi3GetFloat64"](c, vout, n_out, y, n_out)
        status[i, 3] = int(term.value)
        values[i] = y[:]
        t += FMU_STEP
    setup.append(fn["fmi3Terminate"](c))
    fn["fmi3FreeInstance"](c)
    return values, status, np.array(setup, dtype=np.int64)


def fmu_host(job_path: str) -> None:
    """Run in a fresh process: drive one FMU as the job says and write the result npz.
    Never imports linkage_fmu (a pythonfmu FMU must run the copy it bundles)."""
    if "linkage_fmu" in sys.modules:
        raise RuntimeError("the FMU host imported linkage_fmu")
    from fmpy import extract, read_model_description

    job = json.loads(Path(job_path).read_text())
    md = read_model_description(job["fmu"])
    vr = {v.name: v.valueReference for v in md.modelVariables}
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    job["method_vr"] = vr.get("method")
    unzip = extract(job["fmu"])
    runner = host_fmi3 if job["fmi"] == 3 else host_fmi2
    values, status, setup = runner(md, unzip, job, [vr[n] for n in job["inputs"]],
                                   [vr[n] for n in outputs])
    package = ""
    if job["bundled"]:  # the FMU ran the linkage_fmu it bundles, not a checkout's
        module = sys.modules.get("linkage_fmu")
        package = getattr(module, "__file__", "") or ""
        if not Path(package).resolve().is_relative_to(Path(unzip).resolve()):
            raise RuntimeError(f"the pythonfmu FMU ran linkage_fmu from {package!r}, "
                               f"not from the copy it bundles in {unzip}")
        package = str(Path(package).resolve().relative_to(Path(unzip).resolve()))
    np.savez(job["out"], values=values, status=status, setup=setup,
             outputs=np.array(outputs, dtype=str), package=np.array(package))


# -- dump -----------------------------------------------------------------------------
def package_meta() -> dict[str, str]:
    """Which linkage_fmu was imported: its file and the git commit of its checkout."""
    import linkage_fmu

    folder = Path(linkage_fmu.__file__).resolve().parent

    def git(*args: str) -> str:
        run = subprocess.run(["git", "-C", str(folder), *args], capture_output=True, text=True)
        return run.stdout.strip() if run.returncode == 0 else "?"

    return {"package": str(linkage_fmu.__file__), "commit": git("rev-parse", "HEAD"),
            "dirty": git("status", "--porcelain", "--", "."),
            "cache": os.environ.get("LINKAGE_FMU_CACHE", "")}


def dump(out: Path, fmus: bool, n_states: int, n_fmu_states: int) -> None:
    """Evaluate every case and write them to ``out``."""
    t0 = time.perf_counter()
    meta = package_meta()
    print(f"linkage_fmu from {meta['package']} (commit {meta['commit']}"
          f"{', with uncommitted changes' if meta['dirty'] else ''})", flush=True)
    rec = Record()
    for source, parameters in LINKAGES:
        if build(source, parameters).rates:  # driven by time: tests/test_actuated.py
            print(f"  {linkage_label(source, parameters)}: driven by time, not recorded",
                  flush=True)
            continue
        t1 = time.perf_counter()
        dump_linkage(rec, source, parameters, n_states)
        print(f"  {linkage_label(source, parameters)}: {time.perf_counter() - t1:.1f} s",
              flush=True)
    with timed(rec, "big closed_form"):
        dump_big(rec)
    if fmus:
        dump_fmus(rec, n_fmu_states)
    seconds = time.perf_counter() - t0
    for key, value in {**meta, "argv": " ".join(sys.argv), "seconds": f"{seconds:.1f}",
                       "timings": json.dumps({k: round(v, 2) for k, v in rec.timings.items()})
                       }.items():
        rec.put(f"meta|{key}", np.array(value))
    out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(out, **rec.arrays)
    n_values = sum(a.size for k, a in rec.arrays.items() if not k.startswith("meta|"))
    print(f"{out}: {len(rec.arrays)} keys, {n_values} values, {seconds:.1f} s")
    for label, s in sorted(rec.timings.items(), key=lambda kv: -kv[1]):
        print(f"  {label:30s} {s:8.1f} s")


# -- compare --------------------------------------------------------------------------
@dataclass
class Counts:
    """Comparison counts of one group of keys."""

    keys: int = 0
    values: int = 0
    identical: int = 0
    differing: int = 0
    nan_one_side: int = 0  # among differing (library) or apart from the values (FMUs)
    missing_in_a: int = 0
    missing_in_b: int = 0
    shape_changed: int = 0
    status_differing: int = 0  # FMU call statuses: reported, not failures

    def failed(self) -> bool:
        return bool(self.differing or self.missing_in_a or self.missing_in_b or
                    self.shape_changed)


def group_of(key: str) -> str:
    """The group a key is counted in: method/kind, fmu/flavour, inputs."""
    parts = key.split("|")
    if parts[0] == "fmu":
        return "inputs" if parts[3] == "@inputs" else f"fmu/{parts[1]}"
    if parts[2] == "inputs":
        return "inputs"
    return f"{parts[2]}/{parts[5]}"


def is_fmu_value(key: str) -> bool:
    parts = key.split("|")
    return parts[0] == "fmu" and not parts[3].startswith(("!", "@"))


def is_status(key: str) -> bool:
    return key.startswith("fmu|") and key.split("|")[3] in ("!status", "!setup")


def text(value: Any) -> str:
    """A value for a difference report: a float with its bits."""
    if isinstance(value, (float, np.floating)):
        return f"{float(value)!r} (0x{np.float64(value).view(np.uint64):016x})"
    return repr(value.item() if isinstance(value, np.generic) else value)


def differences(a: np.ndarray, b: np.ndarray, fmu: bool) -> tuple[np.ndarray, np.ndarray,
                                                                    np.ndarray]:
    """Flat boolean arrays: which values differ, which are compared at all, and which are
    NaN on one side only."""
    a, b = a.reshape(-1), b.reshape(-1)
    everywhere = np.ones(a.shape, bool)
    if a.dtype.kind == "f" and b.dtype.kind == "f":
        a64, b64 = a.astype(np.float64), b.astype(np.float64)
        nan_one_side = np.isnan(a64) != np.isnan(b64)
        differ = a64.view(np.uint64) != b64.view(np.uint64)
        if fmu:  # only where both are finite; the rest is a matter of statuses
            compared = np.isfinite(a64) & np.isfinite(b64)
            return differ & compared, compared, nan_one_side
        return differ, everywhere, nan_one_side
    if a.dtype.kind != b.dtype.kind:
        return everywhere, everywhere, ~everywhere
    return a != b, everywhere, ~everywhere


def locate(key: str, shape: tuple, flat_index: int) -> str:
    """``key[i, j]`` of a flat index into an array of ``shape``."""
    return f"{key}[{', '.join(str(i) for i in np.unravel_index(flat_index, shape))}]"


def compare(path_a: Path, path_b: Path, show: int) -> int:
    """Compare two dumps bitwise; print the counts and the first differences; 1 if any
    value differs (or a key is missing or changed shape), else 0."""
    with np.load(path_a, allow_pickle=False) as fa, np.load(path_b, allow_pickle=False) as fb:
        a = {k: fa[k] for k in fa.files}
        b = {k: fb[k] for k in fb.files}
    for name, data in (("A", a), ("B", b)):
        meta = {k[5:]: str(v) for k, v in data.items() if k.startswith("meta|") and
                k[5:] in ("package", "commit", "seconds")}
        print(f"{name}: {meta}")
    groups: dict[str, Counts] = {}
    shown: list[str] = []  # failures
    noted: list[str] = []  # FMU statuses and FMU outputs NaN on one side: not failures
    for key in sorted(k for k in set(a) | set(b) if not k.startswith("meta|")):
        c = groups.setdefault(group_of(key), Counts())
        if key not in a or key not in b:
            if key not in a:
                c.missing_in_a += 1
            else:
                c.missing_in_b += 1
            shown.append(f"{key}: only in {'B' if key not in a else 'A'}")
            continue
        va, vb = a[key], b[key]
        c.keys += 1
        if va.shape != vb.shape:
            c.shape_changed += 1
            shown.append(f"{key}: shape {va.shape} in A, {vb.shape} in B")
            continue
        fmu = is_fmu_value(key)
        differ, compared, nan_one_side = differences(va, vb, fmu)
        if is_status(key):
            c.status_differing += int(np.count_nonzero(differ))
            noted += [f"{locate(key, va.shape, i)}: status A {text(va.flat[i])}, "
                      f"B {text(vb.flat[i])}" for i in np.flatnonzero(differ)[:show]]
            continue
        c.values += int(np.count_nonzero(compared))
        n = int(np.count_nonzero(differ))
        c.differing += n
        c.identical += int(np.count_nonzero(compared)) - n
        c.nan_one_side += int(np.count_nonzero(nan_one_side))
        shown += [f"{locate(key, va.shape, i)}: A {text(va.flat[i])}, B {text(vb.flat[i])}"
                  for i in np.flatnonzero(differ)[:show]]
        if fmu:
            noted += [f"{locate(key, va.shape, i)}: NaN on one side: A {text(va.flat[i])}, "
                      f"B {text(vb.flat[i])}" for i in np.flatnonzero(nan_one_side)[:show]]
    print_counts(groups)
    if shown:
        print(f"\nfirst differences ({min(show, len(shown))} of {len(shown)} listed):")
        print("\n".join("  " + s for s in shown[:show]))
    if noted:
        print(f"\nFMU statuses and FMU outputs NaN on one side (not failures; "
              f"{min(show, len(noted))} of {len(noted)} listed):")
        print("\n".join("  " + s for s in noted[:show]))
    failed = any(c.failed() for c in groups.values())
    print("\nDIFFERENT" if failed else "\nbit-identical (every compared value)")
    return 1 if failed else 0


def print_counts(groups: dict[str, Counts]) -> None:
    """One line per group, then the totals."""
    head = (f"{'group':28s} {'keys':>6s} {'values':>11s} {'identical':>11s} "
            f"{'differing':>9s} {'NaN 1-side':>10s} {'miss A':>6s} {'miss B':>6s} "
            f"{'shape':>5s} {'status':>6s}")
    print(head)
    print("-" * len(head))
    total = Counts()
    for name in sorted(groups):
        c = groups[name]
        print(f"{name:28s} {c.keys:6d} {c.values:11d} {c.identical:11d} {c.differing:9d} "
              f"{c.nan_one_side:10d} {c.missing_in_a:6d} {c.missing_in_b:6d} "
              f"{c.shape_changed:5d} {c.status_differing:6d}")
        for attr in vars(total):
            setattr(total, attr, getattr(total, attr) + getattr(c, attr))
    print("-" * len(head))
    c = total
    print(f"{'total':28s} {c.keys:6d} {c.values:11d} {c.identical:11d} {c.differing:9d} "
          f"{c.nan_one_side:10d} {c.missing_in_a:6d} {c.missing_in_b:6d} "
          f"{c.shape_changed:5d} {c.status_differing:6d}")
    print("(NaN 1-side: states NaN on one side only; for fmu/* groups these are not among "
          "the values compared, which are those finite on both sides; status: FMU call "
          "statuses that differ, reported, not failures)")


# -- command line ---------------------------------------------------------------------
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("dump", help="evaluate the cases and write them to an npz")
    p.add_argument("out", type=Path)
    p.add_argument("--fmus", action="store_true", help="build and drive the preset FMUs too")
    p.add_argument("--states", type=int, default=300, help="one-state solves per case")
    p.add_argument("--fmu-states", type=int, default=1200, help="steps per FMU")
    p = sub.add_parser("compare", help="compare two dumps bitwise; exit 1 if any differs")
    p.add_argument("a", type=Path)
    p.add_argument("b", type=Path)
    p.add_argument("--show", type=int, default=SHOW_DEFAULT, help="differences printed")
    p = sub.add_parser("fmu-host", help=argparse.SUPPRESS)
    p.add_argument("job")
    args = parser.parse_args(argv)
    if args.command == "dump":
        if args.fmu_states < 8:
            parser.error("--fmu-states must be at least 8 (special steps come first)")
        dump(args.out, args.fmus, args.states, args.fmu_states)
        return 0
    if args.command == "compare":
        return compare(args.a, args.b, args.show)
    fmu_host(args.job)
    return 0


if __name__ == "__main__":
    sys.exit(main())
