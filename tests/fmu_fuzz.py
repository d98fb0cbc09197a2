"""Fuzz an FMU through fmpy's raw FMI 2 functions and check every answer.

``generate`` writes a random sequence of FMI calls for one preset's FMU, good and bad,
and the answer each must get; ``fmu_raw_host.py`` runs them in a fresh process; ``check``
compares, with the direct solver (computed here, never in the host) as the reference for
every output read; ``check_counts`` that each kind of call came up, in proportion to the
steps. Used by ``tests/test_fmu_fuzz.py`` (2,000 steps per FMU) and as a script for
longer runs, with the same checks (``benchmarks/results/fuzz.md``: 10^4 steps per FMU,
both flavours)::

    python tests/fmu_fuzz.py DIST_DIR --steps 100000 [--seed 1]
    python tests/fmu_fuzz.py DIR_OF_DRIVE_FMUS --drive --steps 100000
    python tests/fmu_fuzz.py DIR_OF_DRIVE_FMUS --drive --energy --steps 10000
    python tests/fmu_fuzz.py DIST_DIR --memory 6 5000   # windows, cycles of FourBar.fmu
    python tests/fmu_fuzz.py DIR_OF_DRIVEN_FMUS --driven --steps 10000

``generate_driven`` does the same for the FMUs of the examples driven by several
actuators (``--driven``). ``generate_drive`` does the same for the drive FMUs (with
``preset``, random friction in half the episodes); ``generate_energy`` and
``check_energy`` hold the slider-crank's drive FMU with friction to its energy balance
over random-moment steps (``--energy``: that and the fuzz with friction, on
``SliderCrankDrive.fmu`` in DIR).
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import subprocess
import sys
import tempfile
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from fmpy import read_model_description

from linkage_fmu import presets

HOST = Path(__file__).with_name("fmu_raw_host.py")
OK, WARNING, DISCARD, ERROR, FATAL = range(5)
LAST_SUCCESSFUL_TIME, TERMINATED = 2, 3  # fmi2StatusKind
#: parameter perturbations per preset: a valid one and one that exitInitialization rejects
PERTURB = {
    "scotch_yoke": ({"l_AB": (0.05, 0.2), "m3": (1.0, 20.0)}, {"h2": -0.1}),
    "four_bar": ({"l_AB": (0.08, 0.3), "m2": (0.5, 4.0)}, {"l_BC": 0.0}),
    "six_bar": ({"l_OA": (0.1, 0.4), "rho": (1.0, 20.0)}, {"m4": -1.0}),
    "slider_crank": ({"e": (-0.1, 0.1), "m3": (0.1, 3.0)}, {"l_AB": -0.2}),
    "slotted_lever": ({"l_AB": (0.05, 0.6), "m3": (1.0, 10.0)}, {"J_S3": -1.0}),
    "crank_shaper": ({"l_DE": (0.2, 0.4), "m5": (5.0, 20.0)}, {"l_CD": 0.0}),
}
BAD_VALUES = (math.nan, math.inf, -math.inf, 1e300, 1e160)


#: preset -> its friction coefficients' parameters
FRICTION = {name: sorted(presets.preset(name).friction_parameters(("mu",)))
            for name in presets.names()}


def friction(preset: str, rng) -> dict:
    """Random friction in every pair of ``preset``: mu in [0, 0.3], pin radii in [0, 0.05]
    of the length scale, a random drive direction (self-locking states among them)."""
    d = presets.preset(preset)
    scale = presets.get(preset).length_scale
    params = {"drive": float(rng.choice((-1.0, 1.0)))}
    for spec in d.friction.values():
        params[spec["mu"]] = float(rng.uniform(0.0, 0.3))
        if "radius" in spec:
            params[spec["radius"]] = float(rng.uniform(0.0, 0.05) * scale)
    return params


@dataclass
class Plan:
    """The calls, and what each answer must be: ``checks[i]`` for op ``i``."""

    ops: list = field(default_factory=list)
    checks: dict = field(default_factory=dict)

    def add(self, op: list, check: tuple | None = None) -> None:
        """Append the call ``op``, and what its answer must be."""
        if check is not None:
            self.checks[len(self.ops)] = check
        self.ops.append(op)


def _variables(fmu: Path) -> dict:
    md = read_model_description(str(fmu))
    return {v.name: (v.valueReference, v.type, v.causality, v.variability)
            for v in md.modelVariables}


#: bytes a forged state's field may be given: the extremes of the u32 lengths and modes,
#: non-finite and huge doubles, zeros, invalid UTF-8
FORGED = ("ffffffff", "00000000", "01000000", "04000000", "7fffffff", "000000000000f87f",
          "000000000000f07f", "000000000000f0ff", "ffffffffffffefff", "0000000000000000",
          "ff", "00", "c0af", "80")


def _forged_bytes(rng) -> str:
    if rng.random() < 0.5:
        return str(rng.choice(FORGED))
    return bytes(rng.integers(0, 256, int(rng.integers(1, 9)), dtype=np.uint8)).hex()


def _bad_step(add, name: str, t: float, rng) -> None:
    """A doStep of a bad size or from a bad time: refused."""
    h, t0 = [(0.0, t), (-0.01, t), (math.nan, t), (0.01, math.nan), (math.inf, t)][
        int(rng.integers(5))]
    add([name, "doStep", t0, h], ("status", ERROR))


def _save(add, name: str, rng, saved: dict, u: list) -> None:
    """Save and serialize the instance's state in one of its three slots (a state is
    its instance's), the inputs ``u`` in force kept for the read after its restore."""
    slot = f"{name}:s{int(rng.integers(3))}"
    add([name, "getState", slot], ("status", OK))
    add([name, "serialize", slot, slot], ("status", OK))
    saved[slot] = list(u)


def generate(fmu: Path, preset: str, steps: int, seed: int) -> Plan:
    """Random calls to ``fmu`` totalling ``steps`` doStep calls, in episodes of 500 steps,
    each a fresh instance with its own parameters."""
    rng = np.random.default_rng(seed)
    v = _variables(fmu)
    outs = [vr for vr, t, c, _ in v.values() if c == "output"]
    out_names = [n for n, (vr, t, c, _) in v.items() if c == "output"]
    fixed_real = [vr for vr, t, c, var in v.values() if c == "parameter" and t == "Real"]
    n_vars = len(v)
    strings = [vr for vr, t, c, _ in v.values() if t == "String"]
    provides = read_model_description(str(fmu)).coSimulation.providesDirectionalDerivative
    valid, invalid = PERTURB[preset]
    defaults = {p.name: p.default for p in presets.preset(preset).parameter_specs()}
    plan = Plan()
    add = plan.add
    done = 0
    episode = 0

    while done < steps:
        name = f"e{episode}"
        episode += 1
        params = {k: float(rng.uniform(lo, hi)) for k, (lo, hi) in valid.items()}
        if rng.random() < 0.5:
            params.update(friction(preset, rng))
        add([name, "new", "M"], ("status", OK))
        add([name, "setup", 0.0, None], ("status", OK))
        add([name, "enter"], ("status", OK))
        if rng.random() < 0.2:  # an invalid set first: exit must fail, then be fixed
            for key, value in invalid.items():
                add([name, "setReal", [v[key][0]], [value]], ("status", OK))
            add([name, "getReal", outs], ("status", WARNING))  # NaN, and why
            add([name, "exit"], ("status", ERROR))
            add([name, "doStep", 0.0, 0.1], ("status", ERROR))
        for key, value in params.items():
            add([name, "setReal", [v[key][0]], [value]], ("status", OK))
        for key in invalid:  # back to a valid value where the perturbation has none
            if key not in params:
                add([name, "setReal", [v[key][0]], [defaults[key]]], ("status", OK))
        add([name, "exit"], ("status", OK))
        d = presets.preset(preset)
        u = [d.inputs["theta"], d.inputs["omega"], d.inputs["alpha"],
             d.loads[0]["start"]]  # the inputs' start values
        saved = {}
        t = 0.0
        for _ in range(min(500, steps - done)):
            r = rng.random()
            if r < 0.70:  # new inputs, sometimes not solvable, then a step and a read
                u = [float(rng.uniform(-7, 7)), float(rng.uniform(-30, 30)),
                     float(rng.uniform(-100, 100)), float(rng.uniform(-50, 50))]
                if rng.random() < 0.1:
                    u[int(rng.integers(4))] = float(rng.choice(BAD_VALUES))
                add([name, "setReal", [0, 1, 2, 3], u], ("set", list(u)))
                add([name, "doStep", t, 0.01], ("step", preset, params, list(u)))
                t += 0.01
                done += 1
                add([name, "getReal", outs], ("read", preset, params, list(u), out_names))
            elif r < 0.74:  # valid inputs mixed with an output or an unknown reference
                bad_vr = int(rng.choice([outs[0], n_vars + int(rng.integers(1, 100))]))
                add([name, "setReal", [0, bad_vr], [float(rng.uniform(-7, 7)), 1.0]],
                    ("status", ERROR))
                add([name, "doStep", t, 0.01], ("step", preset, params, list(u)))
                t += 0.01
                done += 1
                add([name, "getReal", outs], ("read", preset, params, list(u), out_names))
            elif r < 0.77:  # a fixed parameter after initialisation
                add([name, "setReal", [int(rng.choice(fixed_real))], [0.5]], ("status", ERROR))
            elif r < 0.80:  # wrong types, unknown references, strings that are not UTF-8
                choice = int(rng.integers(4))
                if choice == 0:
                    add([name, "setInteger", [int(rng.integers(0, n_vars + 50))], [2]],
                        ("status", ERROR))
                elif choice == 1:
                    add([name, "setString", [int(rng.choice(strings + [0]))],
                         [bytes(rng.integers(128, 256, 4).tolist()).hex()]], ("status", ERROR))
                elif choice == 2:
                    add([name, "getString", [n_vars + int(rng.integers(0, 9))]], ("status", ERROR))
                else:
                    add([name, "getReal", [0, n_vars + int(rng.integers(0, 9))]], ("status", ERROR))
            elif r < 0.83:  # bad step sizes and times
                _bad_step(add, name, t, rng)
            elif r < 0.88:  # save, serialize, restore (checked by the next read)
                _save(add, name, rng, saved, u)
            elif r < 0.91 and saved:
                slot = str(rng.choice(sorted(saved)))
                edit = [None, ["flip", int(rng.integers(0, 10_000)), int(rng.integers(1, 256))],
                        ["cut", -int(rng.integers(1, 100))],  # drop bytes
                        ["forge", int(rng.integers(0, 10_000)), _forged_bytes(rng)]][
                    int(rng.integers(4))]
                if edit and edit[0] == "forge":
                    # a valid CRC: refused, or a state this FMU could make; never more
                    add([name, "deserialize", slot, "d", edit], ("status in", (OK, ERROR)))
                    add([name, "getReal", outs], ("read", preset, params, list(u), out_names))
                    continue
                add([name, "deserialize", slot, "d", edit], ("status", OK if edit is None
                                                              else ERROR))
                if edit is None:
                    add([name, "setState", "d"], ("status", OK))
                    add([name, "freeState", "d"], ("status", OK))
                    u = list(saved[slot])
                    add([name, "getReal", outs], ("read", preset, params, list(u), out_names))
            elif r < 0.94:  # directional derivatives: of outputs along inputs, or refused
                unknowns = [int(u_) for u_ in rng.choice(outs, int(rng.integers(1, 4)))]
                knowns = [int(k_) for k_ in rng.choice(4, int(rng.integers(1, 4)))]
                seeds = [float(x) for x in rng.uniform(-2, 2, len(knowns))]
                kind = int(rng.integers(6))
                if kind == 0:  # J_red and dMb/dalpha, which equals it for an effort on the crank
                    unknowns, knowns, seeds = [v["J_red"][0], v["Mb"][0]], [2], [1.0]
                elif kind == 1:  # an input as the unknown
                    unknowns[0] = int(rng.integers(4))
                elif kind == 2:  # a parameter or an output as a known, or no variable
                    knowns[-1] = int(rng.choice([fixed_real[0], outs[0], n_vars + 3]))
                elif kind == 3:
                    seeds[0] = float(rng.choice(BAD_VALUES[:3]))
                add([name, "derivative", unknowns, knowns, seeds],
                    ("derivative", provides, kind, preset, params, list(u)))
            else:  # direct feedthrough: inputs read without a step; a value read is as set
                u = [float(rng.uniform(-7, 7)), float(rng.uniform(-30, 30)), 0.0,
                     float(rng.uniform(-50, 50))]
                add([name, "setReal", [0, 1, 2, 3], u], ("status", OK))
                add([name, "getReal", outs], ("read", preset, params, list(u), out_names))
                add([name, "getReal", [0, 1, 2, 3] + [v[k][0] for k in params]],
                    ("values", list(u) + list(params.values())))
        add([name, "terminate"], ("status", OK))
        add([name, "free"], ("status", OK))
    return plan


@functools.lru_cache(maxsize=16)
def _mechanism(preset: str, params: tuple):
    """The preset (or the description file) with an episode's parameters, built once
    per episode."""
    return presets.linkage(preset, **dict(params))


def generate_driven(fmu: Path, source: str, steps: int, seed: int) -> Plan:
    """Random calls to the FMU of a linkage driven by time (``source``, its description
    file) totalling ``steps`` doStep calls, in episodes of 500 steps: each driver's
    coordinate about its start (by 0.6 rad or 0.4 m, some states it cannot assemble
    at), speeds and accelerations, the loads, 10 % of the sets with a value not finite
    or huge; inputs mixed with an output's or an unknown reference, bad step sizes and
    times, FMU states saved, serialized, corrupted and restored, and (where the FMU
    provides them) the directional derivative of each effort by its own driver's
    acceleration, which is the mass matrix's diagonal entry ``M[k, k]`` there."""
    rng = np.random.default_rng(seed)
    v = _variables(fmu)
    mech = _mechanism(source, ())
    outs = [vr for vr, t, c, _ in v.values() if c == "output"]
    out_names = [n for n, (vr, t, c, _) in v.items() if c == "output"]
    inputs = [v[n][0] for n in mech.input_names]
    n_vars = len(v)
    provides = read_model_description(str(fmu)).coSimulation.providesDirectionalDerivative
    start = [float(mech.start[n]) for n in mech.input_names]
    spans = [(0.6 if d.kind == "angle" else 0.4, 2.0, 5.0) for d in mech.drivers]
    nominal = [2.0 * (ld.start or {"N": 100.0, "N.m": 10.0}.get(ld.unit, 1.0))
               for ld in mech.input_loads]
    plan = Plan()
    add = plan.add
    done = episode = 0

    def random_inputs():
        u = []
        for k, (dq, dv, da) in enumerate(spans):
            u += [start[3 * k] + float(rng.uniform(-dq, dq)), float(rng.uniform(-dv, dv)),
                  float(rng.uniform(-da, da))]
        return u + [float(rng.uniform(-a, a)) for a in nominal]

    while done < steps:
        name = f"e{episode}"
        episode += 1
        for op in ("new", "setup", "enter", "exit"):
            add([name, op, "M"] if op == "new" else [name, op, 0.0, None] if op == "setup"
                else [name, op], ("status", OK))
        u, saved, t = list(start), {}, 0.0
        for _ in range(min(500, steps - done)):
            r = rng.random()
            if r < 0.75:
                u = random_inputs()
                if rng.random() < 0.1:
                    u[int(rng.integers(len(u)))] = float(rng.choice(BAD_VALUES))
                add([name, "setReal", inputs, u], ("set", list(u)))
                add([name, "doStep", t, 0.01], ("step", source, {}, list(u)))
                t += 0.01
                done += 1
                add([name, "getReal", outs], ("read", source, {}, list(u), out_names))
            elif r < 0.79:
                bad_vr = int(rng.choice([outs[0], n_vars + int(rng.integers(1, 100))]))
                add([name, "setReal", [inputs[0], bad_vr], [start[0], 1.0]], ("status", ERROR))
            elif r < 0.83:
                _bad_step(add, name, t, rng)
            elif r < 0.88:
                _save(add, name, rng, saved, u)
            elif r < 0.91 and saved:
                slot = str(rng.choice(sorted(saved)))
                edit = [None, ["flip", int(rng.integers(0, 10_000)), int(rng.integers(1, 256))],
                        ["cut", -int(rng.integers(1, 100))]][int(rng.integers(3))]
                add([name, "deserialize", slot, "d", edit], ("status", OK if edit is None
                                                              else ERROR))
                if edit is None:
                    add([name, "setState", "d"], ("status", OK))
                    add([name, "freeState", "d"], ("status", OK))
                    u = list(saved[slot])
                    add([name, "getReal", outs], ("read", source, {}, list(u), out_names))
            elif r < 0.95:
                k = int(rng.integers(len(mech.drivers)))
                d = mech.drivers[k]
                add([name, "derivative", [v[d.effort][0]], [v[d.inputs[2]][0]], [1.0]],
                    ("mass", provides, source, list(u), k))
            else:  # direct feedthrough: a value read is as set
                u = random_inputs()
                add([name, "setReal", inputs, u], ("status", OK))
                add([name, "getReal", outs], ("read", source, {}, list(u), out_names))
                add([name, "getReal", inputs], ("values", list(u)))
        add([name, "terminate"], ("status", OK))
        add([name, "free"], ("status", OK))
    return plan


def run_driven(fmu: Path, source: str, steps: int, seed: int) -> tuple[Counter, dict]:
    """:func:`generate_driven`, run in a fresh host process, :func:`check`."""
    plan = generate_driven(fmu, source, steps, seed)
    out = _host(fmu, plan)
    return check(plan, out["results"]), out


def _solvable(preset, params, u, names):
    """Reference outputs at ``u`` (closed form and direct must agree), or None where the
    inputs cannot be solved; and whether the state is too ill-conditioned to compare."""
    if not all(map(math.isfinite, u)):
        return None, False
    sol = _direct(preset, tuple(sorted(params.items())), tuple(u))
    if sol is None:
        return None, False
    values = [sol[n] for n in names]
    partial = _mechanism(preset, tuple(sorted(params.items()))).partial_outputs
    # eta is NaN where no power enters, at a state the FMU solves
    if not all(math.isfinite(v) for n, v in zip(names, values) if n not in partial):
        return None, False
    return values, sol["cond"] > 1e7


@functools.lru_cache(maxsize=64)
def _direct(preset: str, params: tuple, u: tuple):
    """The direct solver's solution at ``u`` (None where it raises), solved once for the
    step and the reads after it."""
    try:
        return _mechanism(preset, params).solve(*u, method="direct")
    except ValueError:
        return None


def check(plan: Plan, results: list) -> Counter:
    """Compare every answer with its check; return the tally of outcomes, raising
    ``AssertionError`` on the first wrong one.

    Both flavours answer alike (one framework): where the inputs cannot be solved the
    step is fmi2Discard and a read fmi2Warning with every output NaN; a value read is the
    value set."""
    tally = Counter()
    for i, (status, payload) in enumerate(results):
        assert status != FATAL, (i, plan.ops[i])
        tally[("status", status)] += 1
        c = plan.checks.get(i)
        if c is None:
            continue
        if c[0] == "status":
            assert status == c[1], (i, plan.ops[i], status, c[1])
        elif c[0] == "status in":
            assert status in c[1], (i, plan.ops[i], status, c[1])
            tally["forged state", status] += 1
        elif c[0] == "set":
            assert status == OK, (i, plan.ops[i], status)
        elif c[0] == "values":  # exactly as set, NaN too
            got = np.array([math.nan if y is None else y for y in payload])
            assert status == OK and np.array_equal(got, np.array(c[1]), equal_nan=True), (
                i, plan.ops[i], payload, c[1])
            tally["value read as set"] += 1
        elif c[0] == "step":
            _, preset, params, u = c
            names = list(_mechanism(preset, tuple(sorted(params.items()))).output_names)
            solvable = _solvable(preset, params, u, names)[0]
            assert status == (OK if solvable else DISCARD), (i, plan.ops[i], u, status)
        elif c[0] == "mass":  # dE_k/da_k, the mass matrix's diagonal entry
            _, provides, source, u, k = c
            if not provides:
                assert status == ERROR, (i, plan.ops[i], status)
                continue
            values = _solvable(source, {}, u, list(_mechanism(source, ()).output_names))[0]
            got = payload[0] if payload else None
            if values is None:
                assert status == WARNING and (got is None or math.isnan(got)), (i, u, status)
                tally["derivative nan"] += 1
                continue
            mech = _mechanism(source, ())
            q = tuple(u[3 * j] for j in range(len(mech.drivers)))
            want = float(mech.mass_matrix(q)[k, k])
            assert status == OK and abs(got - want) <= 1e-9 * abs(want), (i, u, got, want)
            tally["derivative"] += 1
        elif c[0] == "derivative":  # refused by an FMU without them, or a bad request
            _, provides, kind, preset, params, u = c
            if not provides or kind in (1, 2, 3):
                assert status == ERROR, (i, plan.ops[i], status)
                continue
            values = _solvable(preset, params, u, ["J_red"])[0]
            got = np.array([math.nan if y is None else y for y in payload])
            if values is None:
                assert status == WARNING and np.isnan(got).all(), (i, u, status, payload)
                tally["derivative nan"] += 1
            else:
                assert status == OK and np.isfinite(got).all(), (i, u, status, payload)
                if kind == 0 and not any(params.get(k, 0.0) for k in FRICTION[preset]):
                    # d(J_red, Mb)/dalpha; with friction Mb is not affine in alpha
                    assert got[0] == 0.0 and abs(got[1] - values[0]) <= 1e-12 * values[0], (
                        i, u, got, values)
                elif kind == 0:  # with friction: the central difference of the direct solver
                    h = 1e-4 * max(1.0, abs(u[2]))
                    ends = [_solvable(preset, params, [u[0], u[1], u[2] + t, *u[3:]], ["Mb"])[0]
                            for t in (h, -h)]
                    if None not in ends:
                        fd = (ends[0][0] - ends[1][0]) / (2 * h)
                        # truncation ~h**2, rounding ~eps |Mb| / h (a load of 1e160)
                        tol = 1e-6 * max(abs(fd), 1.0) + 1e-15 * max(map(abs, ends[0])) / h
                        assert got[0] == 0.0 and abs(got[1] - fd) <= tol, (i, u, got, fd)
                        tally["derivative with friction"] += 1
                tally["derivative"] += 1
        elif c[0] == "read":
            _, preset, params, u, names = c
            values, fragile = _solvable(preset, params, u, names)
            got = np.array([math.nan if y is None else y for y in payload])
            if values is None:
                assert np.isnan(got).all(), (i, u, payload)
                assert status == WARNING, (i, u, status)  # NaN always comes with a warning
                tally["nan read"] += 1
            elif fragile:
                tally["ill-conditioned, not compared"] += 1
            else:
                ref = np.array(values)
                # eta has no value where no power enters: a read of it warns, others are OK
                assert status == (WARNING if np.isnan(ref).any() else OK), (i, u, status)
                scale = np.maximum(np.abs(ref), 1e-3 * np.nanmax(np.abs(ref[:-1])))
                assert np.all((np.abs(got - ref) <= 1e-9 * scale)
                              | (np.isnan(got) & np.isnan(ref))), (
                    i, u, list(zip(names, got, ref)))
                tally["read equal to the direct solver"] += 1
                if any(params.get(k, 0.0) for k in FRICTION.get(preset, ())):
                    tally["read with friction"] += 1
    return tally


def check_counts(tally: Counter, steps: int, derivatives: bool) -> None:
    """Assert that a :func:`run` of ``steps`` steps made each kind of call, in proportion
    to ``steps`` (the share of each kind is :func:`generate`'s): reads compared with the
    direct solver, with friction, values read back, bad calls refused, discarded steps and
    NaN reads, forged states refused and taken, and (``derivatives``: the native FMUs)
    directional derivatives, finite and NaN."""
    assert tally["read equal to the direct solver"] > steps // 2
    assert tally["read with friction"] > steps // 5  # half the episodes have friction
    assert tally["value read as set"] > steps // 20
    assert tally[("status", ERROR)] > steps // 10  # the bad calls were made and refused
    assert tally[("status", DISCARD)] > steps // 100
    assert tally[("status", WARNING)] > steps // 100
    assert tally[("status", OK)] > steps
    assert tally[("forged state", ERROR)] > steps // 1000
    assert tally[("forged state", OK)] > steps // 1000
    if derivatives:
        assert tally["derivative"] > steps // 100
        assert tally["derivative nan"] >= steps // 2000


def generate_drive(fmu: Path, steps: int, seed: int, preset: str | None = None) -> Plan:
    """Random calls to a drive FMU (``linkage-fmu build --native --drive``) totalling
    ``steps`` doStep calls, in episodes of up to 300 steps, each a fresh instance with
    its own start values and tolerance: moments good, huge and not finite, steps of any
    size and bad ones, states and parameters set as variables, FMU states saved,
    serialized, corrupted and restored, directional derivatives (the drive has none),
    last successful times. An episode ends at a step Discarded at the assembly limit.
    With ``preset`` (the linkage's), half the episodes have random friction in every
    pair (:func:`friction`), a fifth start at rest, whose first moments lie mostly
    inside the friction band there (the direct solver's static Mb with drive -1 and +1),
    and a third of the moments are small (within 1 N.m of 0)."""
    rng = np.random.default_rng(seed)
    v = _variables(fmu)
    outs = [vr for vr, t, c, _ in v.values() if c == "output"]
    names = [n for n, (vr, t, c, _) in v.items() if c == "output"]
    n_vars = len(v)
    plan = Plan()
    add = plan.add
    done = episode = 0

    while done < steps:
        name = f"e{episode}"
        episode += 1
        add([name, "new", "M"], ("status", OK))
        add([name, "setup", 0.0, None], ("status", OK))
        entered = rng.random() < 0.2
        if entered:  # a tolerance out of range: exitInitialization refuses it, then fixed
            bad = float(rng.choice([0.0, -1e-8, 1e-300, 1e-15, 0.5, math.nan, math.inf]))
            add([name, "setReal", [v["tolerance"][0]], [bad]], ("status", OK))
            add([name, "enter"], ("status", OK))
            add([name, "exit"], ("status", ERROR))
            add([name, "doStep", 0.0, 0.01], ("status", ERROR))
        start = {"theta0": float(rng.uniform(-1.0, 1.0)), "omega0": float(rng.uniform(-20, 20)),
                 "tolerance": float(10.0 ** rng.uniform(-12, -3))}
        if preset is not None:
            if rng.random() < 0.5:
                start.update(friction(preset, rng))
            if rng.random() < 0.2:  # from rest: the friction band decides
                start["omega0"] = 0.0
        add([name, "setReal", [v[k][0] for k in start], list(start.values())], ("status", OK))
        if not entered:
            add([name, "enter"], ("status", OK))
        add([name, "exit"], ("status", OK))
        t, tau, saved = 0.0, 0.0, {}  # slot -> the moment in force when it was saved
        band = None
        if preset is not None and start["omega0"] == 0.0:  # the band at rest (load at start)
            from linkage_fmu.presets import linkage

            params = {k: x for k, x in start.items() if k not in ("theta0", "omega0",
                                                                   "tolerance", "drive")}
            band = [float(linkage(preset, drive=d, **params).solve(
                start["theta0"], 0.0, 0.0, method="direct", outputs=("Mb",))["Mb"])
                for d in (-1.0, 1.0)]
        for _ in range(min(300, steps - done)):
            r = rng.random()
            if r < 0.62:  # a moment, a step, a read
                tau = float(rng.uniform(-20, 20))
                if preset is not None and rng.random() < 0.3:
                    tau = float(rng.uniform(-1.0, 1.0))
                if band is not None:  # from rest: the first moments inside the band
                    tau = float(rng.uniform(*band)) if rng.random() < 0.9 else tau
                    band = band if rng.random() < 0.8 else None
                if rng.random() < 0.08:
                    tau = float(rng.choice(BAD_VALUES))
                h = float(10.0 ** rng.uniform(-4, -1.3))
                add([name, "setReal", [v["tau"][0]], [tau]], ("status", OK))
                add([name, "doStep", t, h], ("drive step", tau))
                add([name, "getReal", outs], ("drive read", tau, names))
                add([name, "realStatus", LAST_SUCCESSFUL_TIME], ("status in", (OK,)))
                done += 1
                if math.isfinite(tau):  # a moment not finite discards at the step's start
                    t += h
            elif r < 0.70:  # bad steps: refused, nothing changes
                h, t0 = [(0.0, t), (-0.01, t), (math.nan, t), (0.01, math.nan), (math.inf, t)][
                    int(rng.integers(5))]
                add([name, "doStep", t0, h], ("status", ERROR))
            elif r < 0.75:  # a state, an output, a fixed parameter or no variable set
                vr = int(rng.choice([v["theta"][0], v["omega"][0], outs[-1], v["theta0"][0],
                                     n_vars + 7]))
                add([name, "setReal", [vr], [0.5]], ("status", ERROR))
            elif r < 0.83:  # save and serialize
                slot = f"{name}:s{int(rng.integers(2))}"
                add([name, "getState", slot], ("status", OK))
                add([name, "serialize", slot, slot], ("status", OK))
                saved[slot] = tau
            elif r < 0.90 and saved:  # restore, whole or corrupted
                slot = sorted(saved)[int(rng.integers(len(saved)))]
                edit = [None, ["flip", int(rng.integers(0, 10_000)), int(rng.integers(1, 256))],
                        ["cut", -int(rng.integers(1, 100))]][int(rng.integers(3))]
                add([name, "deserialize", slot, "d", edit], ("status", OK if edit is None
                                                              else ERROR))
                if edit is None:
                    add([name, "setState", "d"], ("status", OK))
                    add([name, "freeState", "d"], ("status", OK))
                    add([name, "getReal", outs], ("drive read", saved[slot], names))
                    break  # its time is the saved one's: a fresh episode goes on
            elif r < 0.93:
                add([name, "derivative", [outs[0]], [v["tau"][0]], [1.0]], ("status", ERROR))
            else:
                add([name, "getReal", outs], ("drive read", tau, names))
        add([name, "terminate"], ("status in", (OK, ERROR)))
        add([name, "free"], ("status", OK))
    return plan


def check_drive(plan: Plan, results: list) -> Counter:
    """Compare every answer of a :func:`generate_drive` run with its check: no Fatal;
    a step OK, or Discard (at the assembly limit, or at its start for a moment that is
    not finite); after it the reads OK with finite outputs and ``Mb`` equal to ``tau``
    (1e-12 of the larger of ``tau`` and ``J_red alpha``), or NaN with a Warning where the
    moment is not finite. After a
    Discard at the limit an episode's later steps are not compared (they start from
    another time)."""
    tally = Counter()
    stopped = set()  # instances discarded at the limit
    for i, (status, payload) in enumerate(results):
        assert status != FATAL, (i, plan.ops[i])
        tally[("status", status)] += 1
        c = plan.checks.get(i)
        name = plan.ops[i][0]
        if c is None:
            continue
        if name in stopped and c[0] != "status":
            continue
        if c[0] == "status":
            assert status == c[1] or name in stopped, (i, plan.ops[i], status, c[1])
        elif c[0] == "status in":
            assert status in c[1], (i, plan.ops[i], status, c[1])
        elif c[0] == "drive step":
            tau = c[1]
            if not math.isfinite(tau):
                assert status == DISCARD, (i, plan.ops[i], status)
                tally["discard: moment not finite"] += 1
            else:
                assert status in (OK, DISCARD), (i, plan.ops[i], status)
                if status == DISCARD:  # the assembly limit, or a moment so large the
                    stopped.add(name)    # substep falls below the time's resolution
                    tally["discard in the step"] += 1
        elif c[0] == "drive read":
            tau, names = c[1], c[2]
            got = np.array([math.nan if y is None else y for y in payload])
            if not math.isfinite(tau):
                assert status == WARNING, (i, status)
                tally["nan read"] += 1
                continue
            assert status == OK and np.isfinite(got).all(), (i, status, payload)
            if got[names.index("omega")] == 0.0 and got[names.index("alpha")] == 0.0:
                # held by friction, the linkage takes tau all the same (exactly); at
                # rest without friction, tau is Mb(alpha = 0) to rounding
                Mb = got[names.index("Mb")]
                assert abs(Mb - tau) <= 1e-12 * max(1.0, abs(tau)), (i, Mb, tau)
                tally["stuck"] += 1
                continue
            # Mb = J_red alpha + Mb(alpha = 0): near a toggle both terms are large and
            # cancel, so the scale of the comparison is the larger of them
            Mb = got[names.index("Mb")]
            inertial = got[names.index("J_red")] * got[names.index("alpha")]
            assert abs(Mb - tau) <= 1e-12 * max(1.0, abs(tau), abs(inertial)), (i, Mb, tau)
            tally["Mb equal to tau"] += 1
    return tally


def run_drive(fmu: Path, steps: int, seed: int,
              preset: str | None = None) -> tuple[Counter, dict]:
    """:func:`generate_drive` on the drive FMU ``fmu`` (of ``preset``: with friction), run
    in a fresh host process, :func:`check_drive`."""
    plan = generate_drive(fmu, steps, seed, preset)
    out = _host(fmu, plan)
    return check_drive(plan, out["results"]), out


#: the energy run's linkage, parameters and load: the slider-crank with friction in every
#: pair, a flywheel on the crank, and 20 N on the piston
ENERGY_PRESET = "slider_crank"
ENERGY_PARAMETERS = dict(mu_O=0.15, r_O=0.02, mu_A=0.15, r_A=0.02, mu_B=0.2, r_B=0.015,
                         mu_guide=0.15, J1=0.02)
ENERGY_LOAD = 20.0
#: the outputs each read of the energy run takes
ENERGY_OUTPUTS = ("theta", "omega", "J_red", "P_loss")


def generate_energy(fmu: Path, steps: int, seed: int, h: float = 1e-3) -> Plan:
    """One instance of the slider-crank's drive FMU (:data:`ENERGY_PARAMETERS`, load
    :data:`ENERGY_LOAD`, tolerance 1e-12) stepped ``steps`` times by ``h`` from rest
    under a random moment, each held over 1 to 100 steps, uniform in [-2, 2] N.m (the
    crank sticks, breaks away, turns both ways, stops); each step taken in two halves,
    the outputs read at its start (the new moment in force), middle and end."""
    rng = np.random.default_rng(seed)
    v = _variables(fmu)
    vrs = [v[n][0] for n in ENERGY_OUTPUTS]
    plan = Plan()
    start = {**ENERGY_PARAMETERS, "load": ENERGY_LOAD, "theta0": 0.3, "omega0": 0.0,
             "tolerance": 1e-12}
    for op in (["E", "new", "M"], ["E", "setup", 0.0, None],
               ["E", "setReal", [v[k][0] for k in start], list(start.values())],
               ["E", "enter"], ["E", "exit"]):
        plan.add(op, ("status", OK))
    tau, held = 0.0, 0
    for k in range(steps):
        if held == 0:
            tau, held = float(rng.uniform(-2.0, 2.0)), int(rng.integers(1, 101))
        held -= 1
        plan.add(["E", "setReal", [v["tau"][0]], [tau]], ("status", OK))
        plan.add(["E", "getReal", vrs], ("energy", "start", tau))
        plan.add(["E", "doStep", k * h, 0.5 * h], ("status", OK))
        plan.add(["E", "getReal", vrs], ("energy", "middle", tau))
        plan.add(["E", "doStep", (k + 0.5) * h, 0.5 * h], ("status", OK))
        plan.add(["E", "getReal", vrs], ("energy", "end", tau))
    plan.add(["E", "free"], ("status", OK))
    return plan


def check_energy(plan: Plan, results: list, h: float = 1e-3) -> dict:
    """The energy balance of a :func:`generate_energy` run: the work of the moment (tau
    times the turn over each step), minus the friction's loss (``P_loss`` by the
    trapezoidal rule over each step), plus the work of the load on the piston and of
    gravity (from the linkage's kinematics at each step's ends), against the change of
    the kinetic energy ``J_red omega**2 / 2``; every status as it must be (no Fatal).
    The loss is integrated by Simpson's rule over each step (start, middle, end): its
    error falls as h**4, but for the steps in which the crank stops (P_loss has a kink
    there)."""
    from linkage_fmu.presets import linkage

    for i, (status, _) in enumerate(results):
        assert status != FATAL, (i, plan.ops[i])
        c = plan.checks.get(i)
        if c is not None and c[0] == "status":
            assert status == c[1], (i, plan.ops[i], status)
        elif c is not None:
            assert status == OK, (i, plan.ops[i], status, results[i])
    reads = [(plan.checks[i][1], plan.checks[i][2], np.array(payload, dtype=float))
             for i, (_, payload) in enumerate(results)
             if i in plan.checks and plan.checks[i][0] == "energy"]
    start = np.array([r for kind, _, r in reads if kind == "start"])
    middle = np.array([r for kind, _, r in reads if kind == "middle"])
    end = np.array([r for kind, _, r in reads if kind == "end"])
    tau = np.array([t for kind, t, _ in reads if kind == "start"])
    theta0, theta1 = start[:, 0], end[:, 0]
    work = np.sum(tau * (theta1 - theta0))
    loss = np.sum(h / 6.0 * (start[:, 3] + 4.0 * middle[:, 3] + end[:, 3]))
    mech = linkage(ENERGY_PRESET, **ENERGY_PARAMETERS)
    ends = np.append(theta0[:1], theta1)
    st = mech.kinematics(ends, order=0)
    potential = mech.g * sum(b.mass * st.p[b.cg][1] for b in mech.bodies)
    load = -ENERGY_LOAD * (st.p["B"][0][-1] - st.p["B"][0][0])  # 20 N along -x on B
    kinetic = 0.5 * np.append(start[:1, 2], end[:, 2]) * np.append(start[:1, 1], end[:, 1]) ** 2
    balance = work - loss + load - (potential[-1] - potential[0]) - (kinetic[-1] - kinetic[0])
    scale = np.sum(np.abs(tau * (theta1 - theta0)))
    return {"work": float(work), "loss": float(loss), "load": float(load),
            "kinetic": float(kinetic[-1] - kinetic[0]), "balance": float(balance),
            "relative": float(abs(balance) / scale), "scale": float(scale),
            "stuck steps": int(np.sum((theta1 == theta0) & (end[:, 1] == 0.0))),
            "reversals": int(np.sum(np.diff(np.sign(end[:, 1][end[:, 1] != 0.0])) != 0))}


def run_energy(fmu: Path, steps: int, seed: int) -> dict:
    """:func:`generate_energy` on the slider-crank's drive FMU ``fmu``, run in a fresh host
    process, :func:`check_energy`."""
    plan = generate_energy(fmu, steps, seed)
    return check_energy(plan, _host(fmu, plan)["results"])


def _host(fmu: Path, plan: Plan, keep_log: int = 20) -> dict:
    """The host's output of ``plan``'s calls to ``fmu``, from a fresh process."""
    with tempfile.TemporaryDirectory(prefix="linkage_fmu_fuzz_") as cwd:
        job = Path(cwd) / "job.json"
        job.write_text(json.dumps({"fmus": {"M": str(fmu)}, "ops": plan.ops,
                                   "keep_log": keep_log}))
        proc = subprocess.run([sys.executable, str(HOST), str(job)], cwd=cwd,
                              capture_output=True, text=True)
    assert proc.returncode == 0, f"host died ({proc.returncode}): {proc.stderr[-3000:]}"
    return json.loads(proc.stdout.splitlines()[-1])


def memory(fmu: Path, windows: int, cycles: int, warm: int = 500) -> list[int]:
    """Resident memory (KiB) of a fresh host process after ``warm`` cycles of the FourBar
    FMU ``fmu`` and after each of ``windows`` windows of ``cycles`` more; a cycle:
    instantiate, initialise with another ``l_AB``, step, read, free. Every answer must be
    OK (asserted). ``tests/test_fmu_protocol.py`` runs it small; ``--memory`` long."""
    l_ab = _variables(fmu)["l_AB"][0]
    plan = Plan()
    plan.add(["M", "cycles", "M", warm, l_ab])
    plan.add(["M", "rss"])
    for _ in range(windows):
        plan.add(["M", "cycles", "M", cycles, l_ab])
        plan.add(["M", "rss"])
    results = _host(fmu, plan, keep_log=5)["results"]
    for counts, n in zip(results[0::2], [warm] + [cycles] * windows):
        assert counts[1]["counts"][OK] == 7 * n == sum(counts[1]["counts"]), counts
    return [value for _, value in results[1::2]]


def run(dist: Path, preset: str, steps: int, seed: int) -> tuple[Counter, dict]:
    """Generate, run in a fresh host process, check. Returns the tally and host output."""
    fmu = Path(dist) / f"{presets.preset(preset).model}.fmu"
    plan = generate(fmu, preset, steps, seed)
    out = _host(fmu, plan)
    return check(plan, out["results"]), out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dist", type=Path, help="folder with the built FMUs")
    parser.add_argument("--steps", type=int, default=100_000, help="doStep calls per FMU")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--drive", action="store_true",
                        help="DIST holds drive FMUs (linkage-fmu build --native --drive): "
                             "fuzz each")
    parser.add_argument("--energy", action="store_true",
                        help="with --drive: the energy balance of SliderCrankDrive.fmu with "
                             "friction over STEPS random-moment steps, and the fuzz with "
                             "friction")
    parser.add_argument("--driven", action="store_true",
                        help="DIST holds the FMUs of the examples driven by time "
                             "(FiveBar, DumpBody, Excavator): fuzz each")
    parser.add_argument("--memory", type=int, nargs=2, metavar=("WINDOWS", "CYCLES"),
                        help="the resident memory of a host over WINDOWS windows of CYCLES "
                             "instantiate/free cycles of FourBar.fmu in DIST, after 500")
    args = parser.parse_args(argv)
    if args.memory:
        windows, cycles = args.memory
        start = time.perf_counter()
        rss = memory(Path(args.dist) / "FourBar.fmu", windows, cycles)
        print(f"FourBar.fmu: resident memory {' -> '.join(map(str, rss))} KiB after 500 and "
              f"{windows} x {cycles} instantiate/free cycles (window growth "
              f"{', '.join(f'{b - a:+d}' for a, b in zip(rss, rss[1:]))} KiB); "
              f"{time.perf_counter() - start:.0f} s")
        return 0
    if args.driven:
        examples = Path(__file__).resolve().parents[1] / "examples"
        for name in ("five_bar", "dump_body", "excavator"):
            source = examples / f"{name}.toml"
            fmu = Path(args.dist) / f"{presets.linkage(str(source)).description.model}.fmu"
            start = time.perf_counter()
            tally, out = run_driven(fmu, str(source), args.steps, args.seed)
            statuses = "/".join(str(tally[("status", k)]) for k in range(5))
            print(f"{fmu.name}: {sum(tally[('status', k)] for k in range(5))} calls, "
                  f"statuses OK/Warning/Discard/Error/Fatal = {statuses}; "
                  f"{tally['read equal to the direct solver']} reads equal to the direct "
                  f"solver, {tally['derivative']} derivatives equal to M[k, k], "
                  f"{tally['derivative nan']} NaN; {time.perf_counter() - start:.0f} s",
                  flush=True)
        return 0
    if args.drive and args.energy:
        fmu = Path(args.dist) / "SliderCrankDrive.fmu"
        tally, out = run_drive(fmu, args.steps, args.seed, ENERGY_PRESET)
        statuses = {s: tally[("status", s)] for s in range(5)}
        print(f"{fmu.name} with friction: statuses OK/Warning/Discard/Error/Fatal = "
              f"{'/'.join(map(str, statuses.values()))}; {tally['Mb equal to tau']} reads with "
              f"Mb equal to tau, {tally['stuck']} stuck, {tally['discard in the step']} "
              f"steps discarded inside", flush=True)
        energy = run_energy(fmu, args.steps, args.seed)
        print(f"{fmu.name} energy over {args.steps} steps: {energy}")
        return 0
    if args.drive:
        for fmu in sorted(Path(args.dist).glob("*Drive.fmu")):
            tally, out = run_drive(fmu, args.steps, args.seed)
            statuses = {s: tally[("status", s)] for s in range(5)}
            print(f"{fmu.name}: {sum(statuses.values())} calls, statuses "
                  f"OK/Warning/Discard/Error/Fatal = {'/'.join(map(str, statuses.values()))}; "
                  f"{tally['Mb equal to tau']} reads with Mb equal to tau, "
                  f"{tally['discard in the step']} steps discarded inside, "
                  f"{tally['nan read']} NaN reads; peak memory {out['peak_kib'] / 1024:.0f} MiB",
                  flush=True)
        return 0
    for preset in presets.names():
        start = time.perf_counter()
        tally, out = run(args.dist, preset, args.steps, args.seed)
        fmu = Path(args.dist) / f"{presets.preset(preset).model}.fmu"
        check_counts(tally, args.steps, read_model_description(
            str(fmu)).coSimulation.providesDirectionalDerivative)
        statuses = {s: tally[("status", s)] for s in range(5)}
        print(f"{presets.preset(preset).model}: {sum(statuses.values())} calls, statuses "
              f"OK/Warning/Discard/Error/Fatal = {'/'.join(map(str, statuses.values()))}; "
              f"{tally['read equal to the direct solver']} reads equal to the direct solver, "
              f"{tally['nan read']} NaN reads, {tally['ill-conditioned, not compared']} "
              f"ill-conditioned, {tally['read with friction']} reads with friction, "
              f"{tally['forged state', ERROR]}/{tally['forged state', OK]} forged states "
              f"refused/taken, {tally['derivative']} derivatives ({tally['derivative nan']} "
              f"NaN); peak memory {out['peak_kib'] / 1024:.0f} MiB; "
              f"{time.perf_counter() - start:.0f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
