"""Traced kernels: bit-identical to the interpreted closed form for every preset and plan,
equal to the direct solver, the same assembly mask, the same errors, and only the work
each plan needs."""

from __future__ import annotations

import importlib
import math
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st_

from conftest import IDS, VARIANTS
from linkage_fmu import AssemblyError, SingularPositionError, numerics, presets
from linkage_fmu.kernels import TRACE, trace
from linkage_fmu.kernels.c_source import SUMMARY_HEAD
from linkage_fmu.kernels.trace import Reason, TracingError

STATES = st_.tuples(
    st_.floats(0.0, 2 * math.pi),
    st_.floats(-60.0, 60.0),
    st_.floats(-500.0, 500.0),
    st_.floats(-200.0, 200.0),
)


def plans(mech) -> list[tuple]:
    """All outputs; the effort alone; the diagnostics alone; a few forces."""
    names = mech.output_names
    return [None, (mech.effort.name,), tuple(mech.diagnostic_names), names[:3] + ("cond",)]


def _bits(x: float):
    """``x`` as ``==`` compares it, every NaN one value."""
    return "nan" if math.isnan(x) else x


@pytest.mark.parametrize("variant", VARIANTS, ids=IDS)
@settings(max_examples=25, deadline=None, derandomize=True)
@given(state=STATES)
def test_kernels_are_the_interpreted_formulas_bit_for_bit(variant, state):
    """For every plan, static (omega = alpha = 0) or not: the kernel's outputs are the
    interpreted closed form's, bit for bit (the same operations in the same order), and
    equal the direct solver to 1e-13 max(1, cond/100) of the largest output."""
    mech = presets.get(variant[0], **variant[1])
    for at in (state, (state[0], 0.0, 0.0, state[3])):
        for outputs in plans(mech):
            try:
                ref = mech.solve(*at, method="interpreted", outputs=outputs)
            except (AssemblyError, SingularPositionError):
                with pytest.raises((AssemblyError, SingularPositionError)):
                    mech.solve(*at, outputs=outputs)
                continue
            got = mech.solve(*at, outputs=outputs)
            # the same floats, NaN as NaN (eta where no power enters)
            assert {n: _bits(v) for n, v in got.items()} == {
                n: _bits(v) for n, v in ref.items()}, outputs
            direct = mech.solve(*at, method="direct", outputs=outputs)
            forces = [n for n in got if n in mech.output_names and not math.isnan(ref[n])]
            if forces:
                scale = max(abs(ref[n]) for n in forces)
                tol = 1e-13 * max(1.0, ref["cond"] / 100 if "cond" in ref else
                                  mech.solve(*at, outputs=("cond",))["cond"] / 100)
                for n in forces:
                    assert abs(got[n] - direct[n]) <= tol * scale, n


def test_the_assembly_mask_and_errors_are_the_interpreted_ones():
    """A four-bar whose crank cannot turn fully: over 3601 angles the kernel gives up
    (None) exactly where the interpreted positions raise AssemblyError, and solve raises
    the same error with the same message; everywhere else the outputs are identical."""
    mech = presets.get("four_bar", l_AB=0.3)
    kernel = mech.kernel()
    positions = mech.kernel(())
    failed = 0
    for theta in np.linspace(0.0, 2 * math.pi, 3601):
        theta = float(theta)
        try:
            mech.kinematics(theta, order=0)
            assembles = True
        except AssemblyError as err:
            assembles, message = False, str(err)
        assert (positions(theta, 10.0, 0.0, 1.0) is not None) == assembles
        assert (kernel(theta, 10.0, 0.0, 1.0) is not None) == assembles
        if assembles:
            assert mech.solve(theta, 10.0, 0.0, 1.0) == mech.solve(theta, 10.0, 0.0, 1.0,
                                                                   method="interpreted")
        else:
            failed += 1
            with pytest.raises(AssemblyError) as info:
                mech.solve(theta, 10.0, 0.0, 1.0)
            assert str(info.value) == message
    assert 0 < failed < 3601


def test_a_singular_state_raises_as_the_interpreted_path_does():
    mech = presets.get("slider_crank", l_OA=0.25, l_AB=0.5, e=-0.25)
    with pytest.raises(SingularPositionError, match=r"theta = 1\.5708 rad"):
        mech.solve(math.pi / 2, 0.0, load=10.0)


def test_a_plan_computes_only_what_it_needs():
    """Fewer operations for the effort alone than for every reaction, and for a static
    scene than a moving one (no derivative kinematics, no inertia)."""
    mech = presets.get("four_bar")
    full = mech.kernel()
    effort = mech.kernel(("Mb",))
    static = mech.kernel(static=True)
    positions = mech.kernel(())
    assert positions.operations < static.operations < full.operations
    assert effort.operations < full.operations
    body = static.source.split("def kernel(", 1)[1].split("\n", 1)[1]
    assert "cos(x0)" in full.source and "x1" not in body and "x2" not in body  # no omega, alpha


def test_kernel_sources_are_straight_line_python():
    """One assignment per operation, a guard per comparison, no loops or calls into the
    package: the kernel stands alone."""
    kernel = presets.get("crank_shaper").kernel()
    source = kernel.source
    assert "for " not in source and "while " not in source and "linkage_fmu" not in source
    # the lever's and the rod's assembly checks, each returning its code
    checks = [code for code, r in enumerate(kernel.reasons, 1) if r.kind == "assembly"]
    assert [kernel.reasons[c - 1].what for c in checks] == [
        "the lever's direction is undefined: B coincides with C", "D is farther from the guide "
        "of E than DE"]
    assert all(f": return {code}\n" in source for code in checks)


def test_the_c_and_python_printers_walk_the_tape_alike():
    """One walk over the tape (kernels/printer.py) for both languages: each live
    operation is one statement of its variable ``t<i>`` in each, in the same order, its
    guard right after it; a printer that misses a language's piece cannot be made."""
    from linkage_fmu.kernels.c_source import CPrinter
    from linkage_fmu.kernels.printer import Printer
    from linkage_fmu.kernels.python_source import PythonPrinter
    from linkage_fmu.kernels.trace import program

    kernel = presets.get("crank_shaper").kernel()
    prog = program(kernel.tape, kernel.results)
    c = CPrinter(kernel.tape, prog.guards, prog.codes).statements(prog.state, "")
    py = PythonPrinter(kernel.tape, prog.guards, prog.codes).statements(prog.state, "")
    assert len(c) == len(py) == len(prog.state) + len(prog.guards.keys() & set(prog.state))
    for a, b in zip(c, py):
        if b.startswith("if "):
            assert a.startswith("if (") and a.endswith(f"return {b.split()[-1]};")
        else:
            assert a.split(" = ")[0].split()[-1] == b.split(" = ")[0]
    assert issubclass(CPrinter, Printer) and issubclass(PythonPrinter, Printer)

    class Partial(Printer):
        def literal(value):
            return repr(value)

    with pytest.raises(TypeError, match="abstract"):
        Partial(kernel.tape, prog.guards, prog.codes)


@pytest.mark.parametrize("friction, vectorise", [(False, True), (True, True), (True, False)])
def test_the_compiled_array_kernel_is_the_python_kernel_to_a_few_ulp(monkeypatch, friction,
                                                                     vectorise):
    """The C array kernel (same operations, IEEE arithmetic, vector loops whose sin, cos
    and atan2 come from glibc's libmvec, within a few ulp of the C library's functions
    that Python's math module calls) hands back exactly the states the Python kernel
    does, and its values agree to 1e-13 max(1, cond/100) of the largest output; with
    friction too (its iterations are loops, run on blocks of states until each state
    converged), and where the kernel is too large to vectorise (its loop scalar, max and
    min by a branch)."""
    if not vectorise:  # the module (the package's c_source is its function)
        source = importlib.import_module("linkage_fmu.kernels.c_source")
        monkeypatch.setattr(source, "VECTOR_OPERATIONS", 0)
    mu = {"mu_A": 0.1, "r_A": 0.02, "mu_guide": 0.15, "mu_E": 0.1, "r_E": 0.02}
    mech = presets.get("crank_shaper", branch=-1, **(mu if friction else {}))
    kernel = mech.kernel()
    assert ("#pragma omp simd\n    for" in kernel.c_source(array=True)) == vectorise
    array = kernel.array()
    if array is None:
        pytest.skip("no C compiler")
    rng = np.random.default_rng(5)
    states = rng.uniform([0, -30, -100, -2000], [2 * np.pi, 30, 100, 2000], size=(3000, 4))
    values, ok = array([states[:, k].copy() for k in range(4)], len(states))
    cond = kernel.index["cond"]
    checked = 0
    for i, state in enumerate(states):
        r = kernel(*state)
        assert ok[i] == (r is not None)
        if r is not None:
            scale = max(abs(r[j]) for j in kernel.checked)
            tol = 1e-13 * max(1.0, r[cond] / 100) * scale
            assert all(abs(v[i] - r[j]) <= tol for j, v in enumerate(values)
                       if j in kernel.checked)
            checked += 1
    assert checked > len(states) // 2


@pytest.mark.parametrize("variant", VARIANTS, ids=IDS)
def test_arrays_through_the_compiled_kernel_match_the_interpreted_arrays(variant):
    """Over 20,000 random states: the same mask of valid states, NaN in the same places,
    values within 1e-13 max(1, cond/100) of the largest output (numpy's vector cos and
    sin differ from the C library's in the last bit)."""
    mech = presets.get(variant[0], **variant[1])
    rng = np.random.default_rng(11)
    th, om, al, ld = (rng.uniform(lo, hi, 20_000) for lo, hi in
                      ((0, 2 * np.pi), (-30, 30), (-100, 100), (-50, 50)))
    a = mech.solve(th, om, al, ld)
    b = mech.solve(th, om, al, ld, method="interpreted")
    np.testing.assert_array_equal(a.valid, b.valid)
    v = b.valid
    scale = np.max([np.abs(b[n][v]) for n in mech.output_names], axis=0)
    tol = 1e-13 * np.maximum(1.0, b["cond"][v] / 100) * scale
    for n in mech.output_names + mech.diagnostic_names:
        np.testing.assert_array_equal(np.isnan(a[n]), np.isnan(b[n]))
        if n in mech.output_names:
            assert np.all(np.abs(a[n][v] - b[n][v]) <= tol), n


def test_without_a_compiler_arrays_use_numpy_after_one_warning(monkeypatch, tmp_path):
    from linkage_fmu.kernels import compiled

    monkeypatch.setenv("CC", "no-such-compiler")
    monkeypatch.setenv("LINKAGE_FMU_CACHE", str(tmp_path))
    compiled._no_compiler_warning.cache_clear()
    mech = presets.get("four_bar")
    th = np.linspace(0.0, 2 * np.pi, 50)
    with pytest.warns(RuntimeWarning, match="no C compiler found"):
        a = mech.solve(th, 10.0)
    assert mech.kernel().array() is None and not list(tmp_path.iterdir())
    b = mech.solve(th, 10.0, method="interpreted")
    assert all(np.array_equal(a[n], b[n]) for n in a)


def test_a_hot_plan_is_compiled_and_gives_the_same_floats():
    """After HOT_CALLS one-state solves the plan calls its compiled C kernel (an
    extension module); on 2,000 random states, including unassemblable ones, it gives
    the Python kernel's floats exactly and hands back the same states."""
    from linkage_fmu.solver import HOT_CALLS

    mech = presets.get("four_bar", l_AB=0.3)
    kernel = mech.kernel()
    for i in range(HOT_CALLS):
        mech.solve(0.4 + 1e-4 * i, 10.0, 0.0, 1.0)
    if not kernel.compiled:
        pytest.skip("no C compiler")
    rng = np.random.default_rng(9)
    states = rng.uniform([0, -30, -100, -50], [2 * np.pi, 30, 100, 50], size=(2000, 4))
    handed_back = 0
    for state in states:
        state = [float(v) for v in state]
        python, c = kernel.function(*state), kernel.call(*state)
        handed_back += type(python) is not tuple
        assert c == python  # the same floats, or the same guard's code
    assert 0 < handed_back < len(states)
    assert kernel.call(0.4, 10.0, 0.0, float("nan")) is None  # the C kernel checks inputs
    assert kernel.call(0.4, 10.0, 0, 1.0) is None  # not a float: the caller converts


def test_parameters_are_arguments_of_one_kernel_source():
    """The real-valued parameters enter the parameter step, not the code: two parameter
    sets of a linkage generate the same Python and C source, even where one has zeros
    the formulas skip (no gravity; a crank inertia and offset centre of mass where the
    defaults have none), and each kernel gives its own linkage's interpreted floats
    exactly. A branch (structure) is part of the code."""
    a = presets.get("four_bar")
    b = presets.get("four_bar", l_AB=0.12, m2=3.0, g=0.0, J1=0.001, l_AS1=0.05, beta1=0.3)
    ka, kb = a.kernel(), b.kernel()
    assert ka.source == kb.source and ka.c_source() == kb.c_source()
    assert ka.frozen != kb.frozen
    # the friction's parameters are constants while every mu is 0 (friction not solved)
    assert ka.parameters == tuple(k for k, v in a.parameters.items()
                                  if k != "branch" and not k.startswith(("mu_", "r_", "drive")))
    for mech, k in ((a, ka), (b, kb)):
        ref = mech.solve(0.7, 5.0, 1.0, 2.0, method="interpreted")
        assert k(0.7, 5.0, 1.0, 2.0) == tuple(ref[n] for n in k.outputs)
    assert presets.get("four_bar", branch=-1).kernel().source != ka.source
    # the parameter step checks what the linkage was built to check: a length must be > 0
    values = dict(zip(ka.parameters, (a.parameters[n] for n in ka.parameters)), l_BC=-0.35)
    assert ka.prepare(*values.values()) is None


def test_without_a_compiler_a_plan_stays_python(monkeypatch, tmp_path):
    from linkage_fmu.kernels import compiled

    monkeypatch.setenv("CC", "no-such-compiler")
    monkeypatch.setenv("LINKAGE_FMU_CACHE", str(tmp_path))
    compiled._no_compiler_warning.cache_clear()
    kernel = presets.get("slider_crank", e=0.01).kernel()
    with pytest.warns(RuntimeWarning, match="no C compiler found"):
        assert kernel.compile() is False
    assert kernel.call is kernel.function


def test_a_narrow_range_is_a_witness_and_no_range_is_said_once():
    """A slider-crank whose rod is so short that it assembles only within 0.003 rad of
    0.7 and pi - 0.7 misses every fixed witness angle: its kernel is traced in the
    middle of a range where it assembles, and gives the interpreted formulas' numbers.
    One that assembles nowhere has no kernel: kernel() says so once; the next call
    raises the same error without tracing again, and solve stays interpreted."""
    mech = presets.get("slider_crank", l_OA=1.0, l_AB=0.002, e=math.sin(0.7))
    k = mech.kernel()
    ref = mech.solve(0.7, 5.0, 0.0, 1.0, method="interpreted")
    assert k(0.7, 5.0, 0.0, 1.0) == pytest.approx(tuple(ref.values()), rel=1e-12)
    never = presets.get("slider_crank", l_OA=1.0, l_AB=0.002, e=1.5)
    with pytest.raises(ValueError, match="cannot be assembled at any crank angle"):
        never.kernel()
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match="at any crank angle"):
        never.kernel()
    assert time.perf_counter() - t0 < 1e-3
    with pytest.raises(AssemblyError):
        never.solve(0.7)


def test_the_kernel_cache_keeps_the_most_recently_used(monkeypatch, tmp_path):
    """Beyond CACHE_FILES compiled kernels, the least recently used are removed: five
    plans compiled with room for three leave the last three, and a kernel used again
    counts as recent."""
    from linkage_fmu.kernels import compiled

    if compiled.find_compiler() is None:
        pytest.skip("no C compiler")
    monkeypatch.setenv("LINKAGE_FMU_CACHE", str(tmp_path))
    monkeypatch.setattr(compiled, "CACHE_FILES", 3)
    yoke = presets.get("scotch_yoke")
    plans = [None, ("Mb",), ("Mb", "F12x"), ("F23y",), ()]
    sources = [yoke.kernel(plan).c_source() for plan in plans]
    paths = []
    for k, source in enumerate(sources):
        paths.append(compiled.build(source))
        if k == 2:
            time.sleep(0.05)
            compiled.build(sources[0])  # used again: now the most recent
        time.sleep(0.05)
    left = set(tmp_path.glob("kernel-*.so"))
    assert left == {paths[0], paths[3], paths[4]}


def _reduced(kernel, outputs, rows, x) -> np.ndarray:
    """numpy's NaN-skipping reductions over the array kernel's outputs, design by design,
    in the layout of ``Kernel.summary`` (code, failed states, first failed, locked
    states, first locked, values: this kernel has no guard of friction's)."""
    out = []
    for row in rows:
        q = kernel.prepare(*row)
        if q is None or not np.isfinite(q).all():
            out.append([None, x.size, -1, 0, -1] + [math.nan] * 6)
            continue
        ys, ok = kernel.array()([x], x.size, None, q)
        u, v, w = (np.where(ok, ys[kernel.index[n]], np.nan) for n in outputs)
        g = np.degrees(u)
        with np.errstate(invalid="ignore", over="ignore"):
            out.append([0.0, int((~ok).sum()), int(np.argmin(ok)) if (~ok).any() else -1,
                        0, -1, np.nanmax(np.abs(u)), np.nanmax(np.hypot(u, v)),
                        np.sqrt(np.nanmean(u * u)), np.nanmean(w), np.nanmin(w),
                        np.nanmin(np.minimum(g, 180.0 - g))])
    return out


def test_summary_reductions_equal_numpy_over_the_array_kernel():
    """``Kernel.summary`` against numpy's nanmax, hypot, nanmean and nanmin over the
    array kernel's outputs (NaN where a guard fails), to 1e-12 relative: states past a
    guard (x > 5) counted and the first one found; an output NaN at states that pass
    (x > 1.79: inf - inf) skipped; x^2 + y^2 overflowing (1e200) left to hypot; a
    parameter set the parameter step refuses (a <= 0) and one whose values are not
    finite (a = inf) reported with NaN summaries; threads give the same rows."""

    def f(x, p):
        if x[0] > 5.0:  # a guard: the witness takes the other way
            pass
        if p["a"] > 0.0:  # a check of the parameter step
            pass
        u = p["a"] * TRACE.sin(3.0 * x[0]) + 0.2
        t = x[0] * p["big"]
        return [u, p["b"] * TRACE.cos(x[0]), (t - t) + x[0] - 1.0]

    k = trace(f, [1.0], {"a": 2.0, "b": 1.0, "big": 1e308}, ("u", "v", "w"))
    summary = k.summary([("peak", ("u",)), ("peak_pair", ("u", "v")), ("rms", ("u",)),
                         ("mean", ("w",)), ("min", ("w",)), ("toggle_deg", ("u",))])
    if summary is None:
        pytest.skip("no C compiler")
    x = np.linspace(0.0, 6.0, 1001)
    rows = [[2.0, 1.0, 1e308], [0.5, 1e200, 1e308], [1.0, 3.0, 1.0], [-1.0, 1.0, 1e308],
            [math.inf, 1.0, 1e308]]
    got = summary(rows, [x], x.size)
    want = _reduced(k, ("u", "v", "w"), rows, x)
    assert got[3, 0] > 0 and got[4, 0] == -1.0  # refused by a check; values not finite
    for g, w in zip(got, want):
        if w[0] is not None:
            assert g[0] == 0.0
        assert g[1] == w[1] and g[2] == w[2] and g[3] == w[3] and g[4] == w[4]
        assert len(g) == len(w)
        for a, b in zip(g[5:], w[5:]):
            assert (math.isnan(a) and math.isnan(b)) or abs(a - b) <= 1e-12 * abs(b), (g, w)
    assert got[0, 1] == 167 and got[0, 2] == 834  # x = 5.004 .. 6 (0.006 apart) fail
    assert not math.isnan(got[0, 8]) and 1e200 <= got[1, 6] < math.inf  # NaN skipped; hypot
    np.testing.assert_array_equal(summary(rows, [x], x.size, threads=2), got)


def test_summary_counts_the_states_friction_locks_apart():
    """A kernel with a guard of another kind (x > 5: the branch the witness did not
    take) recorded before one labelled 'locking' (x < 3): the states failing only the
    second are counted as locked, those failing the first (whatever the second does)
    as failed, each with the first of them. Reference: the one-state function's code at
    every state, mapped through ``Kernel.reasons``; exact."""

    def f(x, p):
        if x[0] > 5.0:
            pass
        if x[0] * p["a"] < 3.0:
            numerics.label(x[0] * p["a"], Reason("locking", "test"))
        return [x[0] * p["a"]]

    k = trace(f, [1.0], {"a": 1.0}, ("y",))
    assert [r.kind for r in k.reasons] == ["branch", "locking"]
    summary = k.summary([("peak", ("y",))])
    if summary is None:
        pytest.skip("no C compiler")
    x = np.linspace(0.0, 6.0, 601)
    for a in (1.0, 0.5):
        codes = np.array([k.make(*k.prepare(a))(v) for v in x], dtype=object)
        kinds = np.array(["" if type(c) is tuple else k.reasons[c - 1].kind for c in codes])
        locked, failed = kinds == "locking", kinds == "branch"
        row = summary([[a]], [x], x.size)[0]
        assert row[1:5].tolist() == [failed.sum(), np.argmax(failed) if failed.any() else -1,
                                     locked.sum(), np.argmax(locked) if locked.any() else -1]
        assert row[5] == np.max(np.where(kinds == "", x * a, 0.0))
    assert summary([[1.0]], [x], x.size)[0, 3] == 201  # 3 <= x <= 5, 0.01 apart


def test_summary_refuses_what_it_cannot_reduce():
    k = trace(lambda x, p: [x[0] * p["a"]], [1.0], {"a": 2.0}, ("y",))
    with pytest.raises(ValueError, match="no output 'z'"):
        k.summary([("peak", ("z",))])
    with pytest.raises(ValueError, match="'median' of 1 outputs is not one of"):
        k.summary([("median", ("y",))])
    summary = k.summary([("peak", ("y",))])
    if summary is None:
        pytest.skip("no C compiler")
    with pytest.raises(ValueError, match=r"parameters must have shape \(sets, 1\)"):
        summary([[1.0, 2.0]], [np.zeros(3)], 3)
    with pytest.raises(ValueError, match="input 0 has 2 values, not 1 or 3"):
        summary([[1.0]], [np.zeros(2)], 3)
    with pytest.raises(ValueError, match="threads must be a positive integer"):
        summary([[1.0]], [np.zeros(3)], 3, threads=0)


def test_array_kernel_writes_the_rows_of_one_block():
    """The array kernel into the rows of one 2-D block (as a sweep's numpy path passes a
    design's slice of its block): the same floats, bit for bit, as into a list of arrays;
    a block of another shape or with overlapping rows is refused, naming ``out``."""
    mech = presets.get("four_bar")
    k = mech.kernel()
    array = k.array()
    if array is None:
        pytest.skip("no C compiler")
    theta = np.linspace(0.0, 2 * np.pi, 50)
    inputs = [theta, np.full(1, 10.0), np.full(1, 1.0), np.full(1, 3.0)]
    listed, ok = array(inputs, theta.size)
    block = np.full((len(k.outputs), 3, theta.size), -1.0)
    rows, ok2 = array(inputs, theta.size, block[:, 1])
    assert rows.shape == (len(k.outputs), theta.size) and np.array_equal(ok, ok2)
    np.testing.assert_array_equal(block[:, 1], np.array(listed))
    assert (block[:, [0, 2]] == -1.0).all()  # its neighbours untouched
    with pytest.raises(ValueError, match="out must be a float64 array of shape"):
        array(inputs, theta.size, np.empty((len(k.outputs), theta.size + 1)))
    with pytest.raises(ValueError, match="out must be a float64 array of shape"):
        array(inputs, theta.size, np.lib.stride_tricks.as_strided(
            np.empty(theta.size + len(k.outputs)), (len(k.outputs), theta.size), (8, 8)))


# -- loops ------------------------------------------------------------------------------------
def _newton_sqrt(x, p, maximum=60, minimum=1):
    """sqrt(a) by Newton from a (a loop of the kernel), the runs it took, scaled by p."""
    a = x[0]
    tape = a.tape

    def body(carried):
        y, runs = carried
        z = 0.5 * (y + a / y)
        return [z, runs + 1.0], tape.compare("gt", abs(z - y), 1e-15 * z)

    (root, runs), converged = tape.loop([a, 0.0], body, minimum, maximum)
    tape.check(converged, True, Reason("locking", "Newton did not converge"))
    return [root * p["s"], runs]


def _reference_sqrt(a, minimum=1):
    """The same Newton iteration, written here on floats: the root and the runs."""
    y, runs = a, 0
    while True:
        z = 0.5 * (y + a / y)
        runs += 1
        more = abs(z - y) > 1e-15 * z
        y = z
        if runs >= minimum and not more:
            return y, runs


def test_a_loop_is_newton_for_sqrt_in_python_c_arrays_summaries_and_tangent():
    """Reference: math.sqrt (1 ulp), the iteration written on floats in the test (its
    root bit for bit, its count of runs exactly: 1 to over 20 by state), and the
    derivative 1 / (2 sqrt(a)) (1e-12 relative) through the carried derivatives. The
    Python kernel, the C one-state, the C array and summary kernels and the tangent
    agree; the runs respect the minimum; too few runs fail with the check's reason."""
    k = trace(_newton_sqrt, [2.0], {"s": 1.0}, ("root", "runs"))
    assert "for _k" in k.source
    a = np.array([1.0, 2.0, 0.25, 7.5, 1e-6, 3e5, 1e12, 4e-9])
    runs = []
    for v in a.tolist():
        root, n = k(v)
        want, m = _reference_sqrt(v)
        assert root == want and n == m and abs(root - math.sqrt(v)) <= 2.3e-16 * root
        runs.append(n)
    assert min(runs) <= 2 and max(runs) >= 20
    if k.compile():
        assert all(k.call(v) == k.function(v) for v in a.tolist())
    array = k.array()
    if array is not None:
        (roots, counts), ok = array([a.copy()], a.size)
        assert ok.all() and roots.tolist() == [k(v)[0] for v in a.tolist()]
        assert counts.tolist() == runs
        s = k.summary([("peak", ("runs",))])
        assert s([[1.0]], [a.copy()], a.size)[0][len(SUMMARY_HEAD)] == max(runs)
    tangent, python = k.tangent(), k.python_tangent()
    for v in a.tolist():
        y, dy = python([v], [1.0])
        assert y[0] == k(v)[0]
        assert abs(dy[0] - 0.5 / math.sqrt(v)) <= 1e-12 * 0.5 / math.sqrt(v)
        if tangent is not None:
            c, dc = tangent([v], [1.0])
            assert (list(c), list(dc)) == (list(y), list(dy))
    k5 = trace(lambda x, p: _newton_sqrt(x, p, minimum=5), [2.0], {"s": 1.0}, ("r", "n"))
    assert k5(1.0) == (1.0, 5.0) and k5(1e12)[1] == _reference_sqrt(1e12, 5)[1]
    k3 = trace(lambda x, p: _newton_sqrt(x, p, maximum=3), [1.0], {"s": 1.0}, ("r", "n"))
    assert k3(1.0) == (1.0, 1.0) and k3(1e12) is None
    assert k3.call(1e12) == 1 and k3.reasons[0].what == "Newton did not converge"


def test_a_settled_loop_stops_once_converged_in_c(tmp_path):
    """Reference: the Newton iteration for sqrt written on floats in the test, with its
    test from the first run (its root bit for bit, its runs exactly) and math.sqrt (1
    ulp). The C of a loop of minimum 5 with ``settle`` stops as soon as it converges
    (1 run at a = 1, where the plain C takes 5); without it, the minimum holds."""
    import ctypes

    from linkage_fmu.ccompiler import CompilerError, compile_shared

    k5 = trace(lambda x, p: _newton_sqrt(x, p, minimum=5), [2.0], {"s": 1.0}, ("r", "n"))
    libraries = {}
    for settle in (False, True):
        source = tmp_path / f"settle{int(settle)}.c"
        source.write_text(k5.c_source(array=False, prefix="k", settle=settle))
        try:
            libraries[settle] = ctypes.CDLL(str(compile_shared(
                [source], tmp_path / f"settle{int(settle)}.so",
                flags=("-O2", "-ffp-contract=off"))))
        except CompilerError:
            pytest.skip("no C compiler")
    for v in (1.0, 2.0, 0.25, 7.5, 1e-6, 1e12):
        for settle, lib in libraries.items():
            q, y = (ctypes.c_double * 64)(), (ctypes.c_double * 2)()
            assert lib.k_prepare((ctypes.c_double * 1)(1.0), q) == 0
            assert lib.k_one(q, (ctypes.c_double * 1)(v), y) == 0
            root, runs = _reference_sqrt(v, 1 if settle else 5)
            assert y[0] == root and y[1] == runs
            assert abs(y[0] - math.sqrt(v)) <= 2.3e-16 * y[0]
    q, y = (ctypes.c_double * 64)(), (ctypes.c_double * 2)()
    libraries[True].k_prepare((ctypes.c_double * 1)(1.0), q)
    libraries[True].k_one(q, (ctypes.c_double * 1)(1.0), y)
    assert (y[0], y[1]) == (1.0, 1.0)


def test_nested_loops_and_checks_inside_a_body():
    """Reference: the fixed point of x = sqrt(x + a), (1 + sqrt(1 + 4 a)) / 2 (1e-15
    relative), each square root a Newton loop inside the outer loop; a check inside the
    outer body (the inner loop's convergence) fails the state where it fails in any run,
    with its reason, in Python and C."""
    def fixed_point(x, p, inner=60):
        a = x[0]
        tape = a.tape

        def root(v):
            def body(c):
                z = 0.5 * (c[0] + v / c[0])
                return [z], tape.compare("gt", abs(z - c[0]), 1e-15 * z)
            (r,), converged = tape.loop([v], body, 1, inner)
            tape.check(converged, True, Reason("locking", "the square root"))
            return r

        def outer(c):
            z = root(c[0] + a)
            return [z], tape.compare("gt", abs(z - c[0]), 1e-15 * z)

        (x,), converged = tape.loop([a], outer, 1, 200)
        tape.check(converged, True, Reason("locking", "the fixed point"))
        return [x * p["s"]]

    k = trace(fixed_point, [2.0], {"s": 1.0}, ("x",))
    assert k.source.count("for _k") == 2
    compiled = trace(fixed_point, [2.0], {"s": 1.0}, ("x",))
    if not compiled.compile():
        pytest.skip("no C compiler")
    for a in (2.0, 0.3, 40.0, 1e6):
        want = (1.0 + math.sqrt(1.0 + 4.0 * a)) / 2.0
        assert abs(k(a)[0] - want) <= 1e-15 * want and compiled.call(a) == k(a)
    short = trace(lambda x, p: fixed_point(x, p, inner=8), [0.5], {"s": 1.0}, ("x",))
    short.compile()
    assert short(0.5) is not None and short(1e6) is None
    assert short.reasons[short.call(1e6) - 1].what == "the square root"


def test_a_loop_refuses_branches_inside_and_its_values_outside():
    """A formula that branches on a value of a loop's body, or reads one after the loop,
    is a TracingError naming what it did."""
    def branching(x, p):
        tape = x[0].tape

        def body(c):
            z = c[0] * 0.5
            if z > 1.0:  # a branch: refused
                z = z - 1.0
            return [z], tape.compare("gt", z, 1.0)
        return tape.loop([x[0]], body, 1, 10)[0]

    with pytest.raises(TracingError, match="branches .gt. on a value computed inside"):
        trace(branching, [3.0], {}, ("y",))
    kept = []

    def leaking(x, p):
        tape = x[0].tape

        def body(c):
            kept.append(c[0] * 2.0)
            return [kept[-1]], tape.compare("lt", kept[-1], 100.0)
        tape.loop([x[0]], body, 1, 10)
        return [kept[-1] + 1.0]

    with pytest.raises(TracingError, match="read outside it"):
        trace(leaking, [3.0], {}, ("y",))


def test_an_array_kernel_with_loops_is_the_one_state_kernel():
    """Reference: the Python kernel of one state (the interpreted formulas' floats).
    Tolerance: the same states refused, values within 1e-13 max(1, cond/100) of the
    largest output (libmvec's sin, cos and atan2 are within a few ulp of the C
    library's). The six-bar driven at KD with friction (a secant loop holding the
    groups' Newton loops) over 500 random states, run on blocks by the compiled array
    kernel, each state's loops until it converged."""
    mu = {n: 0.2 for n in presets.get("six_bar").parameters if n.startswith("mu_")}
    mu.update({n: 0.01 for n in presets.get("six_bar").parameters if n.startswith("r_")})
    kernel = presets.get("six_bar", driver="KD", **mu).kernel()
    array = kernel.array()
    if array is None:
        pytest.skip("no C compiler")
    rng = np.random.default_rng(8)
    states = rng.uniform([0, -30, -100, -300], [2 * np.pi, 30, 100, 300], size=(500, 4))
    values, ok = array([states[:, k].copy() for k in range(4)], len(states))
    cond, refused = kernel.index["cond"], 0
    for i, state in enumerate(states.tolist()):
        r = kernel.function(*state)
        assert ok[i] == (type(r) is tuple)
        if type(r) is tuple:
            tol = 1e-13 * max(1.0, r[cond] / 100) * max(abs(r[j]) for j in kernel.checked)
            assert all(abs(v[i] - r[j]) <= tol for j, v in enumerate(values)
                       if j in kernel.checked), i
        else:
            refused += 1
    assert refused < 50


def test_a_kernel_split_at_an_input_is_the_one_state_kernel(tmp_path):
    """Reference: the direct solver's Mb and J_red with friction (1e-12 relative), and
    the one-state C kernel bit for bit. The slider-crank's kernel of Mb and J_red with
    friction in every pair, split at alpha (input 2): its fix once per (theta, omega,
    load), then vary at several alpha, gives the one-state kernel's outputs and codes."""
    import ctypes

    from linkage_fmu.ccompiler import CompilerError, compile_shared

    mech = presets.linkage("slider_crank", mu_O=0.15, r_O=0.02, mu_A=0.15, r_A=0.02,
                           mu_B=0.2, r_B=0.015, mu_guide=0.15)
    k = mech.kernel(("Mb", "J_red"))
    source = tmp_path / "split.c"
    source.write_text(k.c_source(array=False, prefix="k", vary=2))
    try:
        lib = ctypes.CDLL(str(compile_shared([source], tmp_path / "split.so",
                                             flags=("-O2", "-ffp-contract=off"))))
    except CompilerError:
        pytest.skip("no C compiler")
    D = ctypes.c_double
    p = (D * len(k.parameters))(*[float(mech.parameters[n]) for n in k.parameters])
    q = (D * 512)()
    assert lib.k_prepare(p, q) == 0
    rng = np.random.default_rng(29)
    checked = 0
    for theta, omega in zip(rng.uniform(-math.pi, math.pi, 12), rng.uniform(-9.0, 9.0, 12)):
        x = (D * 4)(theta, omega, 0.0, 20.0)
        f = (D * 512)()
        fixed = lib.k_fix(q, x, f)
        for alpha in (-300.0, -1.0, 0.0, 2.5, 58.7):
            x[2] = alpha
            one, split = (D * 2)(), (D * 2)()
            code = lib.k_one(q, x, one)
            assert (fixed or lib.k_vary(q, f, x, split)) == code
            if code:
                continue
            assert list(split) == list(one)
            s = mech.solve(theta, omega, alpha, load=20.0, outputs=("Mb", "J_red"))
            assert abs(one[0] - s["Mb"]) <= 1e-12 * (1.0 + abs(s["Mb"]))
            assert abs(one[1] - s["J_red"]) <= 1e-12 * s["J_red"]
            checked += 1
    assert checked >= 40


#: what a user's first solves compile: the slider-crank with friction in its guide (its
#: kernels have loops), over a revolution at rest (the static plan reads neither omega
#: nor alpha: its array C declared a pointer to each that no lane read, and gcc warned
#: "unused variable" on stderr) and moving, at one state (hot: the extension module),
#: its directional derivatives and a sweep's summaries
FIRST_USE = """
import numpy as np
from linkage_fmu import presets
from linkage_fmu.solver import HOT_CALLS

mech = presets.get("slider_crank", mu_guide=0.1, mu_A=0.05, r_A=0.01)
theta = np.linspace(0.0, 2.0 * np.pi, 360)
assert np.asarray(mech.solve(theta, 0.0, 0.0, 50.0).valid).all()
assert np.asarray(mech.solve(theta, 10.0, 0.0, 50.0).valid).all()
for k in range(HOT_CALLS + 10):
    mech.solve(0.1 * k, 10.0, 0.0, 50.0)
kernel = mech.kernel()
assert kernel.compiled and kernel.tangent() is not None
assert kernel.summary([("peak", ("Mb",))]) is not None
"""


def test_first_use_with_an_empty_kernel_cache_prints_nothing(tmp_path):
    """With an empty kernel cache (LINKAGE_FMU_CACHE a new folder) a process compiles
    its kernels on first use and says nothing: its stderr is empty, and the cache holds
    the five libraries it compiled (two array kernels, at rest and moving; the one-state
    module, tangent, summary). It runs with logging at INFO, where a successful
    compile's output goes (not shown by default: tests/test_ccompiler.py), so an empty
    stderr also says that the generated C compiles without a warning, rather than
    having its warnings hidden."""
    import subprocess
    import sys

    from linkage_fmu.ccompiler import find_compiler

    if find_compiler() is None:
        pytest.skip("no C compiler")
    cache = tmp_path / "cache"
    head = "import logging; logging.basicConfig(level=logging.INFO)\n"
    run = subprocess.run([sys.executable, "-c", head + FIRST_USE], capture_output=True,
                         text=True, timeout=600,
                         env={**__import__("os").environ, "LINKAGE_FMU_CACHE": str(cache)})
    assert run.returncode == 0, run.stderr
    assert run.stderr == "" and run.stdout == ""
    assert len(list(cache.glob("kernel-*.so"))) == 4
    assert len(list(cache.glob("_linkage_kernel_*"))) == 1


def _every_rule(x, p):
    """One traced operation of each derivative rule, on the state inputs and a
    parameter: their values and derivatives by each input."""
    a, b, c = x
    k = p["k"]
    r = [a + b, a - b * k, a * b, a / (b + 2.0), -a, TRACE.sqrt(b * b + 1.0),
         TRACE.sin(a), TRACE.cos(b), math.tan(0.0) + TRACE.abs(c - a), TRACE.sign(a) * b,
         TRACE.maximum(a, b), TRACE.atan2(a, b), a ** k]
    t = a.tape
    r += [t.select(t.compare("lt", a, b), a * c, b), a.traced("min", min, a, c),
          a.traced("radians", math.radians, c),
          a.traced("degrees", math.degrees, b), a.traced("tan", math.tan, c * 0.1),
          a.traced("asin", math.asin, a * 0.1), a.traced("acos", math.acos, b * 0.1),
          a.traced("atan", math.atan, c), (b + 3.0) ** c]
    return r


def test_the_python_tangent_is_the_compiled_tangent_to_the_bit():
    """The tape transform's forward mode, printed as Python (Kernel.python_tangent),
    against the compiled forward mode (Kernel.tangent): the same floats, values and
    derivatives, along random directions, for each derivative rule (a kernel of one
    operation each), through the friction's loops (the crank-shaper's kernel of every
    output, with friction in two pairs) and through a table's spline (an outside
    function: the engine example); and the same failed guards."""
    import linkage_fmu

    rules = trace(_every_rule, [0.3, 0.7, 1.1], {"k": 1.5},
                  tuple(f"r{i}" for i in range(22)))
    mu = {"mu_A": 0.1, "r_A": 0.02, "mu_guide": 0.15}
    kernels = [(rules, [(0.0, 1.0)] * 3), (presets.get("crank_shaper", **mu).kernel(),
               [(0, 2 * np.pi), (-30, 30), (-300, 300), (-100, 100)]),
               (linkage_fmu.load("examples/engine.toml").kernel(), None)]
    rng = np.random.default_rng(7)
    for k, box in kernels:
        compiled = k.tangent()
        if compiled is None:
            pytest.skip("no C compiler")
        python, n = k.python_tangent(), k.n_inputs
        box = box or [(-10.0, 10.0), (-30.0, 30.0), (-300.0, 300.0)] + [(-5.0, 5.0)] * (n - 3)
        taken = 0
        for _ in range(300):
            x = [float(rng.uniform(lo, hi)) for lo, hi in box]
            dx = rng.normal(size=n)
            c, p = compiled(x, dx), python(x, dx)
            if type(c) is not tuple:
                assert p == c, x
                continue
            taken += 1
            assert [_bits(v) for v in c[0]] == [_bits(v) for v in p[0]], x
            assert [_bits(v) for v in c[1]] == [_bits(v) for v in p[1]], x
        assert taken > 100
