"""2,000 fuzzed steps per FMU, both FMI 2.0 flavours, through fmpy's raw FMI 2 functions
(``fmu_fuzz.py``): NaN, infinite and overflowing inputs, unassemblable angles, invalid
parameter sets, outputs and unknown references set, fixed parameters set after
initialisation, wrong types, strings that are not UTF-8, bad step sizes, state round
trips, friction in every pair in half the episodes (self-locking states
among them), directional derivatives (good requests and bad ones: an input as the unknown, a
parameter or an output as the known, a seed that is not finite), corrupted states, and
forged states (bytes written into a serialized state and its
CRC-32 made valid again: each refused, or taken as a state the FMU could have made, and the
instance reads on unchanged). Every answer is checked: no Fatal and no crash, each bad
call fmi2Error, each read after a bad call equal to the direct solver at the inputs in
force (1e-9 relative) or NaN with fmi2Warning where they cannot be solved (the step
then fmi2Discard), each value read equal to the value set; the native FMUs' derivatives
finite (dMb/dalpha equal to J_red to 1e-12), or NaN with fmi2Warning where the inputs
cannot be solved, the pythonfmu FMUs' refused with fmi2Error.

Each kind of call is counted, and the counts asserted in proportion to the steps (the
share of each kind is the generator's): at 2,000 steps per FMU every kind the fuzz has
found a fault with still comes up, dozens to thousands of times per FMU (forged states
5 to 14 times of each answer, unsolvable derivatives at least once). The long runs,
10^5 steps per FMU, are ``python tests/fmu_fuzz.py DIST --steps 100000``; their figures
are in ``benchmarks/results/fuzz.md``."""

from __future__ import annotations

import pytest

from fmu_fuzz import check_counts, run
from linkage_fmu import presets

STEPS = 2_000


@pytest.mark.slow
@pytest.mark.parametrize("preset", presets.names())
def test_fuzz(fmu2, preset):
    tally, _ = run(fmu2, preset, STEPS, seed=sum(map(ord, preset)))
    check_counts(tally, STEPS, derivatives=fmu2.name.startswith("native"))


EXAMPLES = __import__("pathlib").Path(__file__).resolve().parents[1] / "examples"
DRIVEN_STEPS = 1_000


@pytest.mark.slow
@pytest.mark.parametrize("flavour", ["native", "pythonfmu"])
@pytest.mark.parametrize("name", ["five_bar", "dump_body", "excavator"])
def test_fuzz_of_a_linkage_driven_by_time(name, flavour, tmp_path):
    """The FMUs of the examples driven by several actuators, from a clean host: no
    Fatal, every read equal to the direct solver, a step discarded exactly where the
    direct solver has no solution, bad calls refused, and (native) each effort's
    derivative by its driver's acceleration the mass matrix's diagonal entry."""
    import fmu_cache
    from fmu_fuzz import DISCARD, ERROR, FATAL, run_driven

    build = fmu_cache.build_native_fmu if flavour == "native" else fmu_cache.build_fmu
    source = str(EXAMPLES / f"{name}.toml")
    tally, _ = run_driven(build(source, tmp_path), source, DRIVEN_STEPS,
                          seed=sum(map(ord, name)))
    assert tally[("status", FATAL)] == 0
    assert tally["read equal to the direct solver"] > DRIVEN_STEPS // 2
    assert tally[("status", ERROR)] > DRIVEN_STEPS // 20
    assert tally[("status", DISCARD)] > DRIVEN_STEPS // 100
    if flavour == "native":
        assert tally["derivative"] > DRIVEN_STEPS // 100
