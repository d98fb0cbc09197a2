"""The pythonfmu FMU's Python slave, called as the framework's backend calls it.

The slave runs in this process here, without pythonfmu's wrapper: ``set_real`` of every
parameter and ``exit_initialization_mode`` (a prepare), then ``set_real`` of every input
and ``get_real`` of every output (an evaluation). The FMUs themselves are tested through
the framework in test_fmu.py and test_fmu_protocol.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from pythonfmu.enums import Fmi2Status

from linkage_fmu import SelfLockingError, presets
from linkage_fmu.ccompiler import find_compiler
from linkage_fmu.fmi.slave import PACKAGE, LinkageSlave, fingerprint
from linkage_fmu.fmi.variables import variables
from linkage_fmu.solver import HOT_CALLS, LOCKED

#: relative tolerance against the direct solver (the pythonfmu FMU's check in build_fmu.py)
RTOL = 1e-9


def make_slave(tmp_path, name: str, **parameters):
    """A prepared slave of the preset ``name`` with ``parameters``, its input and output
    value references, and its linkage (built in this process, for the references)."""
    d = presets.preset(name)
    (tmp_path / "linkage.toml").write_text(d.to_toml(), encoding="utf-8")

    class Slave(LinkageSlave):
        DESCRIPTION = "linkage.toml"
        FINGERPRINT = fingerprint(PACKAGE)

    slave = Slave(instance_name="test", resources=str(tmp_path))
    mech = presets.get(name, **parameters)
    table = variables(mech)
    for kind, setter in (("Real", slave.set_real), ("Integer", slave.set_integer),
                         ("String", slave.set_string)):
        vrs = [vr for vr, v in enumerate(table) if v.causality == "parameter" and v.type == kind]
        setter(vrs, [parameters.get(table[vr].name, table[vr].start) for vr in vrs])
    slave.exit_initialization_mode()
    inputs = [vr for vr, v in enumerate(table) if v.causality == "input"]
    outputs = [vr for vr, v in enumerate(table) if v.causality == "output"]
    names = [table[vr].name for vr in outputs]
    return slave, inputs, outputs, names, mech


def reference(mech, names, state) -> list[float]:
    sol = mech.solver.solve(*state, method="direct")
    return [float(sol[n]) for n in names]


def assert_close(got, expected, state):
    for g, e in zip(got, expected, strict=True):
        assert math.isclose(g, e, rel_tol=RTOL, abs_tol=RTOL * max(map(abs, expected))), state


@pytest.mark.skipif(find_compiler() is None, reason="no C compiler for the compiled kernels")
def test_outputs_against_direct_solver(tmp_path):
    """Every output of the four-bar, read after each change of the inputs over more
    evaluations than the solver takes to compile its kernels (so the later ones are the
    compiled kernel's), moving and static states: equal to the direct solver's (the
    assembled LU) within 1e-9 relative."""
    slave, inputs, outputs, names, mech = make_slave(tmp_path, "four_bar")
    n = HOT_CALLS + 100
    for i in range(n):
        for state in ([2 * math.pi * i / n, 10.0, 3.0, 5.0], [2 * math.pi * i / n, 0.0, 0.0, -2.0]):
            slave.set_real(inputs, list(state))
            got = slave.get_real(outputs)
            if i % 50 == 0 or i == n - 1:
                assert_close(got, reference(mech, names, state), state)
    assert not slave.log_queue, [m.msg for m in slave.log_queue]
    # the later reads were the compiled kernels' (moving and static), not the solver's
    assert None not in slave._hot


def test_outputs_after_a_setter_alone(tmp_path):
    """One input set by itself (not the whole input list), then every output, and a
    subset in another order: the direct solver's outputs at the inputs in force (1e-9)."""
    slave, inputs, outputs, names, mech = make_slave(tmp_path, "slider_crank")
    slave.set_real(inputs, [0.4, 10.0, 0.0, 5.0])
    slave.get_real(outputs)
    slave.set_real([inputs[0]], [1.3])
    state = [1.3, 10.0, 0.0, 5.0]
    expected = reference(mech, names, state)
    assert_close(slave.get_real(outputs), expected, state)
    picked = [outputs[-1], outputs[0], outputs[2]]
    assert_close(slave.get_real(picked), [expected[-1], expected[0], expected[2]], state)


@pytest.mark.skipif(find_compiler() is None, reason="no C compiler for the compiled kernels")
def test_state_without_outputs_is_nan_with_its_reason(tmp_path):
    """The four-bar with l_AB = 0.3 cannot close at theta = 3.1: NaN for every output and
    a Discard with the solver's reason (Solver.attempt's words), before and after the
    kernel is compiled; the next state that closes reads the direct solver's outputs
    (1e-9), never the NaN of the one before."""
    slave, inputs, outputs, names, mech = make_slave(tmp_path, "four_bar", l_AB=0.3)
    why = mech.solver.attempt([3.1, 10.0, 0.0, 0.0]).text
    assert why == "the linkage cannot be assembled: the dyad B-C-D cannot close"
    for i in range(HOT_CALLS + 10):
        if i in (0, HOT_CALLS + 5):
            slave.set_real(inputs, [3.1, 10.0, 0.0, 0.0])
            assert all(math.isnan(y) for y in slave.get_real(outputs))
            last = slave.log_queue[-1]
            assert (last.status, last.msg) == (Fmi2Status.discard, why)
        state = [0.2 + 1e-4 * i, 10.0, 0.0, 1.0]
        slave.set_real(inputs, list(state))
        got = slave.get_real(outputs)
        if i in (0, HOT_CALLS + 5):
            assert_close(got, reference(mech, names, state), state)
    assert len(slave.log_queue) == 2


def test_a_self_locked_state_is_nan_with_the_libraries_words(tmp_path):
    """The massless slider-crank with guide friction mu 0.6 (test_friction's hand-derived
    case) locks at theta = 4.45 driven at omega = 5 against a 250 N load: NaN for every
    output and a Discard saying SelfLockingError's reason, the words of the array
    solve's problem and of the kernel's guard (Kernel.reasons); the next state reads the
    direct solver's outputs (1e-9), eta among them."""
    params = dict(m1=0.0, J1=0.0, m2=0.0, J2=0.0, m3=0.0, g=0.0, l_OA=0.18, l_AB=0.2,
                  mu_guide=0.6)
    slave, inputs, outputs, names, mech = make_slave(tmp_path, "slider_crank", **params)
    locked = [4.45, 5.0, 0.0, 250.0]
    with pytest.raises(SelfLockingError) as caught:
        mech.solve(*locked)
    why = caught.value.reason
    assert why.text == ("friction locks the linkage: friction at A, B, guide locks the group "
                        "of link 2")
    assert mech.solve(np.array([locked[0]]), *locked[1:]).problems[LOCKED].reason == why
    k = mech.solver.kernel()
    code = k.call(*locked)
    assert type(code) is int and k.reasons[code - 1] == why
    slave.set_real(inputs, locked)
    assert all(math.isnan(y) for y in slave.get_real(outputs))
    last = slave.log_queue[-1]
    assert (last.status, last.msg) == (Fmi2Status.discard, why.text)
    state = [1.0, 5.0, 0.0, 250.0]
    slave.set_real(inputs, state)
    got = slave.get_real(outputs)
    assert_close(got, reference(mech, names, state), state)
    assert 0.0 < got[names.index("eta")] < 1.0
