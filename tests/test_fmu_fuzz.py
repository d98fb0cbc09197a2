"""10^4 fuzzed steps per FMU, both FMI 2.0 flavours, through fmpy's raw FMI 2 functions
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
cannot be solved, the pythonfmu FMUs' refused with fmi2Error."""

from __future__ import annotations

import pytest

from linkage_fmu import presets

from fmu_fuzz import DISCARD, ERROR, OK, WARNING, run

STEPS = 10_000


@pytest.mark.parametrize("preset", presets.names())
def test_fuzz(fmu2, preset):
    tally, _ = run(fmu2, preset, STEPS, seed=sum(map(ord, preset)))
    assert tally["read equal to the direct solver"] > STEPS // 2
    assert tally["read with friction"] > STEPS // 5  # half the episodes have friction
    assert tally["value read as set"] > STEPS // 20
    assert tally[("status", ERROR)] > STEPS // 10  # the bad calls were made and refused
    assert tally[("status", DISCARD)] > 100 and tally[("status", WARNING)] > 100
    assert tally[("status", OK)] > STEPS
    assert tally[("forged state", ERROR)] > 10 and tally[("forged state", OK)] > 10
    if fmu2.name.startswith("native"):  # the flavour with directional derivatives
        assert tally["derivative"] > STEPS // 100 and tally["derivative nan"] > 5
