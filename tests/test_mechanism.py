"""Mechanism.solve: scalar/array forms, the shortcuts for what a scene doesn't need
(each checked to skip the work and to give the full path's numbers), diagnostics and
bad input."""

from __future__ import annotations

import contextlib
import math
from unittest import mock

import numpy as np
import pytest

from conftest import IDS, VARIANTS
from linkage_fmu import SingularPositionError, friction, groups, kinetostatics, linalg, presets
from linkage_fmu.loads import wrenches
from linkage_fmu.pairs import Revolute

TH = np.linspace(0.05, 2 * np.pi, 25)


def test_scalar_gives_floats_and_arrays_broadcast(mech):
    s = mech.solve(0.7, 3.0, 1.0, 2.0)
    assert all(type(v) is float for v in s.values()) and s.valid is True
    a = mech.solve(TH[:, None], np.array([1.0, 2.0, 3.0]), 0.5, 2.0)
    assert a["cond"].shape == (25, 3) and a.valid.shape == (25, 3)
    assert a[mech.output_names[0]][7, 2] == pytest.approx(
        mech.solve(TH[7], 3.0, 0.5, 2.0)[mech.output_names[0]], rel=1e-13, abs=1e-12)


def _full_path(mech, theta, omega, alpha, load):
    """Reactions with everything computed: second-order kinematics, all wrench terms."""
    st = mech.kinematics(theta, order=2)
    W = wrenches(mech, st, omega, alpha, (load,), static=False)
    R, effort = kinetostatics.closed_form(mech, st, W)
    if mech.friction.joints:  # every mu 0: the outputs read a friction of 0 from R
        R = friction.unsolved(mech, st, R, effort, omega, static=False)
    return R, effort


def test_static_scene_skips_derivatives_and_matches_full_path(mech):
    spies = [mock.patch.object(cls, name, side_effect=AssertionError(f"{cls.__name__}.{name}"))
             for cls in (groups.RRR, groups.RRP, groups.RPP, groups.RPR)
             for name in ("first", "second")]
    # eta needs the first-order coefficients (which way the power flows)
    names = tuple(n for n in mech.output_names if n != "eta")
    if mech.effort_on_crank:  # otherwise the effort needs first-order coefficients
        with contextlib.ExitStack() as stack:
            for spy in spies:
                stack.enter_context(spy)
            fast = mech.solve(TH, 0.0, 0.0, 30.0, outputs=names)
    else:
        fast = mech.solve(TH, 0.0, 0.0, 30.0, outputs=names)
    R, effort = _full_path(mech, TH, 0.0, 0.0, 30.0)
    st = mech.kinematics(TH, order=2)
    full = {name: fn(R, effort, st) for name, fn in mech.output_functions if name in names}
    for name in names:
        np.testing.assert_allclose(fast[name], full[name], rtol=1e-13, atol=1e-12, err_msg=name)


def test_effort_only_skips_reactions_and_matches_full_path(mech):
    name = mech.effort.name
    with mock.patch.object(kinetostatics, "closed_form",
                           side_effect=AssertionError("closed_form")), \
         mock.patch.object(kinetostatics, "direct", side_effect=AssertionError("direct")):
        fast = mech.solve(TH, 7.0, -20.0, 30.0, outputs=(name,))
    full = mech.solve(TH, 7.0, -20.0, 30.0, method="direct")
    np.testing.assert_allclose(fast[name], full[name], rtol=1e-12, atol=1e-12)


def test_massless_and_weightless_bodies_add_no_terms():
    mech = presets.get("four_bar", m1=0.0, m2=0.0, J_S2=0.0, g=0.0)
    st = mech.kinematics(TH, order=2)
    W = wrenches(mech, st, 5.0, 1.0, (0.0,), static=False)
    assert W["1"] == [0.0, 0.0, 0.0] and W["2"] == [0.0, 0.0, 0.0]  # plain floats: nothing computed
    s = mech.solve(TH, 5.0, 1.0, 0.0)
    # massless coupler, two-force member: F12 + F32 = 0, so F32 = -F12 = F21
    np.testing.assert_allclose(s["F32x"], s["F21x"], atol=1e-12)
    np.testing.assert_allclose(s["F32y"], s["F21y"], atol=1e-12)


def test_four_bar_transmission_angle_is_law_of_cosines():
    mech = presets.get("four_bar")
    s = mech.solve(TH, outputs=("gamma_C",))
    bd2 = (0.1 * np.cos(TH) - 0.4) ** 2 + (0.1 * np.sin(TH)) ** 2
    gamma = np.arccos((0.35 ** 2 + 0.30 ** 2 - bd2) / (2 * 0.35 * 0.30))
    np.testing.assert_allclose(s["gamma_C"], gamma, rtol=1e-12)


def test_condition_estimate_grows_towards_a_toggle():
    """With l_AB + l_AD = l_BC + l_CD - margin, B, C and D are nearly collinear at
    theta = pi; the estimate grows like 1/margin, as 1/sin(gamma)**2 does."""
    conds = []
    for margin in (1e-2, 1e-4, 1e-6):
        mech = presets.get("four_bar", l_AB=0.1, l_BC=0.35, l_CD=0.3, l_AD=0.55 - margin)
        conds.append(mech.solve(math.pi, 10.0)["cond"])
    assert conds[0] < conds[1] < conds[2]
    assert conds[2] / conds[0] == pytest.approx(1e4, rel=0.1)


def test_toggle_is_reported_not_hidden():
    """Four-bar with B, C, D collinear at theta = pi (0.125 + 0.5 = 0.375 + 0.25): the
    reactions blow up and the condition estimate says so (>= 1/eps)."""
    mech = presets.get("four_bar", l_AB=0.125, l_BC=0.375, l_CD=0.25, l_AD=0.5)
    sol = mech.solve(np.array([math.pi, 1.0]), 10.0)
    assert sol["cond"][0] >= 1 / np.finfo(float).eps and sol["cond"][1] < 100


def test_exactly_singular_scalar_state_raises_with_angle():
    """Slider-crank whose rod is exactly perpendicular to the guide at theta = pi/2
    (offset e = l_OA - l_AB): the dyad's equations have a zero determinant."""
    mech = presets.get("slider_crank", l_OA=0.25, l_AB=0.5, e=-0.25)
    for method in ("closed_form", "direct"):
        with pytest.raises(SingularPositionError, match=r"theta = 1\.5708 rad .*gamma_B = 0 rad"):
            mech.solve(math.pi / 2, 0.0, load=10.0, method=method)
    assert np.isinf(mech.solve(np.array([math.pi / 2]), outputs=("cond",))["cond"][0])


@pytest.mark.parametrize("kwargs, error, pattern", [
    ({"theta": math.nan}, ValueError, "theta must be a finite number, got nan"),
    ({"omega": math.inf}, ValueError, "omega must be a finite number, got inf"),
    ({"load": "1 m"}, ValueError,
     r"load = '1 m' must be a moment \(N.m\), but it is a length \(m\)"),
    ({"load": "fast"}, ValueError, "load = 'fast': unknown name 'fast'"),
    ({"omega": [1.0, "2 rpm"]}, TypeError, "omega must be an array of real numbers"),
    ({"alpha": np.array([0.0, np.nan])}, ValueError, r"alpha must be finite: entry \(1,\) is nan"),
    ({"method": "lu"}, ValueError, "method must be one of"),
    ({"outputs": ("Mb", "M_b")}, ValueError, "has no output 'M_b'"),
])
def test_bad_solve_input_is_named(kwargs, error, pattern):
    args = {"theta": 0.3, "omega": 1.0, "alpha": 0.0, "load": 0.0, **kwargs}
    with pytest.raises(error, match=pattern):
        presets.get("four_bar").solve(**args)


@pytest.mark.parametrize("preset, params, error, pattern", [
    ("four_bar", {"l_AB": -0.1}, ValueError, r"l_AB must be > 0 \(crank length AB\), got -0.1"),
    ("four_bar", {"m2": -1}, ValueError, "m2 must be >= 0"),
    ("four_bar", {"l_BC": math.nan}, ValueError, "l_BC must be a finite number"),
    ("four_bar", {"branch": 0}, ValueError, "branch must be"),
    ("four_bar", {"lAB": 0.1}, TypeError, "four_bar has no parameter 'lAB'"),
    ("six_bar", {"driver": "BC"}, ValueError, "driver must be one of 'OA', 'AB', 'O1B', 'KD', 'D'"),
    ("scotch_yoke", {"g": -9.81}, ValueError, "g must be >= 0"),
    ("slider_crank", {"J2": "x"}, ValueError, "J2 = 'x': unknown name 'x'"),
    ("slider_crank", {"J2": "4 kg"}, ValueError, r"J2 = '4 kg' must be a moment of inertia"),
    ("pendulum", {}, ValueError, "no preset 'pendulum'"),
])
def test_bad_parameters_are_named(preset, params, error, pattern):
    with pytest.raises(error, match=pattern):
        presets.get(preset, **params)


def test_table_is_a_dataframe_with_one_column_per_output():
    mech = presets.get("slider_crank")
    df = mech.table(TH, omega=10.0, load=100.0)
    assert list(df.columns) == list(mech.output_names + mech.diagnostic_names)
    assert df.index.name == "theta" and len(df) == len(TH)
    np.testing.assert_allclose(df["Mb"], mech.solve(TH, 10.0, 0.0, 100.0)["Mb"], rtol=0)


def test_a_table_holds_no_negative_zero():
    """The slider-crank without friction at 90 and 180 deg: its friction outputs (Mf_O,
    Mf_A, Mf_B, Ff_guide, P_loss) come out of the solve as -0.0 (mu = 0 times a
    negative), which pandas printed as -0.0. The table holds 0.0 there, and every
    other value as the solve gives it, bit for bit."""
    mech = presets.get("slider_crank")
    theta = np.radians([0.0, 90.0, 180.0])
    sol = mech.solve(theta)
    friction = ["Mf_O", "Mf_A", "Mf_B", "Ff_guide", "P_loss"]
    assert all(math.copysign(1.0, v) < 0 for k in friction for v in sol[k][1:])  # the case
    df = mech.table(theta)
    assert not np.signbit(df.to_numpy()[df.to_numpy() == 0.0]).any()
    assert "-0.0" not in df.to_string().split()
    for k in df.columns:
        np.testing.assert_array_equal(df[k].to_numpy(), sol[k])  # equal: -0.0 == 0.0
        ok = sol[k] != 0.0
        assert (np.signbit(df[k].to_numpy()[ok]) == np.signbit(sol[k][ok])).all()


@pytest.mark.parametrize("inputs", [dict(omega=1e160), dict(omega=-1e200, alpha=1e300)])
def test_inputs_that_overflow_are_an_error_not_a_silent_inf(mech, inputs):
    """Finite inputs too large for float64 arithmetic: an OverflowInputError naming the
    inputs, for both methods (they used to come back as inf or NaN, silently)."""
    from linkage_fmu import OverflowInputError

    for method in ("closed_form", "direct"):
        with pytest.raises(OverflowInputError, match="overflow float64 at theta = 0.3"):
            mech.solve(0.3, **inputs, method=method)


def test_an_overflow_names_the_load_values_of_the_state():
    """The overflow error lists every input as given, loads by name included, and a
    load over the cycle at its value at that state (2 kN/m * x_B at theta = 0: 2000 *
    (l_OA + l_AB) = 500 N)."""
    from linkage_fmu import OverflowInputError

    mech = presets.linkage("examples/coupler_four_bar.toml")
    with pytest.raises(OverflowInputError, match=r"theta = 0.3, omega = 1e\+160, alpha = 0.0, "
                                                 r"F_P = 80.0, T4 = 4021.0: "):
        mech.solve(0.3, omega=1e160, T4=4021.0)
    d = presets.preset("slider_crank").copy()
    d.load("F_spring", body="3", kind="force", at="B", direction=[-1, 0],
           value="2 kN/m * x_B")
    with pytest.raises(OverflowInputError, match=r"load = 7.0, F_spring = 500.0 \(over the "
                                                 r"cycle\)"):
        d.build().solve(0.0, 1e160, 0.0, 7.0)



def _outcome(call):
    """What a call gives: the solution's type, valid, names and its floats' bits (NaN
    included), or the error's type and message."""
    try:
        sol = call()
    except Exception as err:  # noqa: BLE001  (the error is the outcome compared)
        return type(err), str(err)
    return (type(sol), np.asarray(sol.valid).tobytes(), tuple(sol),
            np.asarray(list(sol.values()), dtype=np.float64).tobytes())


def _lean(mech) -> bool:
    """Compile the one-state kernels of every output (static and moving) and let a solve
    of each take them: True once both lean paths are live (False: no C compiler)."""
    from linkage_fmu.solver import WITNESS_ANGLES

    for static in (False, True):
        if not mech.solver.kernel(None, static).compile():
            return False
        for theta in WITNESS_ANGLES:
            if mech.solver.hot[not static] is not None:
                break
            with contextlib.suppress(ValueError):
                mech.solve(theta, *(0.0, 0.0) if static else (1.3, 0.7))
    return None not in mech.solver.hot


def _friction(name: str, base: dict, rng) -> dict:
    """``base`` with a random mu in [0, 0.6] on every pair (enough for some states to
    lock) and pin radii up to 0.05 of the length scale."""
    mech = presets.get(name, **base)
    params = dict(base)
    for jf in mech.friction.joints:
        j = jf.joint.name
        params[next(k for k in mech.parameters if k.startswith("mu") and k.endswith(f"_{j}"))] = \
            float(rng.uniform(0.0, 0.6))
        if isinstance(jf.joint, Revolute):
            params[f"r_{j}"] = float(rng.uniform(0.0, 0.05) * mech.length_scale)
    return params


def _compare_lean(mech, calls, monkeypatch) -> tuple[list, int]:
    """Each ``(args, kwargs)`` of ``calls`` through Mechanism.solve and through the
    general path (Solver.solve asked for every output by a tuple of their names: the
    kernel's tuple, else the interpreted formulas): the same outcome (:func:`_outcome`).
    Returns the outcomes and how many solutions of plain floats needed the general
    path."""
    from linkage_fmu.solver import Solution, Solver

    everything = tuple(mech.output_names + mech.diagnostic_names)
    general = Solver.solve.__get__(mech.solver)
    fallbacks = []

    def spy(*args, **kwargs):
        fallbacks.append(args)
        return general(*args, **kwargs)

    monkeypatch.setattr(mech.solver, "solve", spy)
    outcomes, missed = [], 0
    for args, kwargs in calls:
        before = len(fallbacks)
        got = _outcome(lambda: mech.solve(*args, **kwargs))  # noqa: B023
        ref = _outcome(lambda: general(*args, outputs=everything, **kwargs))  # noqa: B023
        assert got == ref, (args, kwargs, got[:2], ref[:2])
        outcomes.append(got[0])
        plain = all(type(v) is float for v in args + tuple(kwargs.values()))
        missed += got[0] is Solution and plain and len(fallbacks) > before
    return outcomes, missed


@pytest.mark.parametrize("friction_on", [False, True], ids=["no friction", "friction"])
@pytest.mark.parametrize("variant", VARIANTS, ids=IDS)
def test_the_lean_scalar_path_gives_the_general_paths_outcome_bit_for_bit(variant, friction_on,
                                                                         monkeypatch):
    """Mechanism.solve's lean path (plain numbers, every output, the hot compiled kernel)
    against the general path, over 120 random states in six call forms (positional,
    keywords, a load by name, inputs left at their start values, ints and numpy floats)
    and bad inputs: the same type, valid, names and float bits, or the same error and
    message, with friction (mu up to 0.6) and without. Every solved state of plain
    floats is served without the general path."""
    from linkage_fmu.solver import Solution

    name, base = variant
    rng = np.random.default_rng(3)
    mech = presets.get(name, **(_friction(name, base, rng) if friction_on else base))
    if not _lean(mech):
        pytest.skip("no C compiler: solve has no lean path")
    loads = [ld.name for ld in mech.input_loads]
    calls = []
    for k in range(120):
        th = float(rng.uniform(0.0, 2 * np.pi))
        w, a = (0.0, 0.0) if k % 5 == 0 else (float(rng.uniform(-30.0, 30.0)),
                                              float(rng.uniform(-100.0, 100.0)))
        ld = [float(rng.uniform(-50.0, 50.0)) for _ in loads]
        calls += [((th, w, a, *ld), {}),
                  ((th,), {"omega": w, "alpha": a, **dict(zip(loads, ld))}),
                  ((th,), {"omega": w}),
                  ((th, w, a), {}),
                  ((np.float64(th), int(w), int(a), *map(int, ld)), {}),
                  ((th, w), {"alpha": a, **dict(zip(loads[:1], ld[:1]))})]
    calls += [((math.nan,), {"omega": 1.0}), ((0.3,), {"omega": math.inf}),
              ((0.3,), {"omega": True}), ((0.3, 1.0, 0.0, *[1.0] * len(loads)), {"load": 2.0}),
              ((0.3,), {"omega": 1.0, "no_such_load": 1.0}), ((0.3,), {"omega": 10 ** 400}),
              ((0.3, 1.0, 0.0, *[1.0] * (len(loads) + 1)), {}),
              (("30 deg",), {"omega": "5 rpm"}), ((np.array([0.3, 0.4]),), {"omega": 1.0})]
    outcomes, missed = _compare_lean(mech, calls, monkeypatch)
    assert outcomes.count(Solution) > 100 and missed == 0


def test_the_lean_scalar_path_raises_as_the_general_path_where_a_state_has_no_outputs(
        monkeypatch):
    """States without outputs through the lean path: the four-bar whose crank cannot
    turn (l_AB = 0.3: AssemblyError), and the massless slider-crank of
    test_friction.py with mu = 0.6 in its guide, whose piston locks where it moves out
    against the load at theta in (pi, 3 pi / 2) (SelfLockingError), moving and at
    rest: the same errors and messages as the general path."""
    from linkage_fmu import AssemblyError, SelfLockingError

    rng = np.random.default_rng(8)
    four_bar = presets.get("four_bar", l_AB=0.3)
    locking = presets.get("slider_crank", m1=0.0, J1=0.0, m2=0.0, J2=0.0, m3=0.0, g=0.0,
                          l_OA=0.18, l_AB=0.2, mu_guide=0.6)
    for mech in (four_bar, locking):
        if not _lean(mech):
            pytest.skip("no C compiler: solve has no lean path")
    th = rng.uniform(0.0, 2 * np.pi, 200)
    out, _ = _compare_lean(four_bar, [((float(t), 10.0), {"load": 1.0}) for t in th],
                           monkeypatch)
    assert 20 < out.count(AssemblyError) < 180
    th = rng.uniform(np.pi, 1.5 * np.pi, 200)
    out, _ = _compare_lean(locking, [((float(t),), {"omega": 5.0, "load": 250.0}) for t in th]
                           + [((float(t), 0.0, 0.0, 250.0), {}) for t in th], monkeypatch)
    assert out.count(SelfLockingError) > 20


def test_without_a_compiler_scalar_solves_past_hot_take_the_python_kernel(monkeypatch,
                                                                         tmp_path):
    """No C compiler: the plan stays Python after HOT_CALLS one-state solves (one
    warning), solve has no lean path and goes on giving the interpreted formulas'
    floats (reference: method="interpreted", exact) in every call form."""
    import warnings

    from linkage_fmu.kernels import compiled
    from linkage_fmu.solver import HOT_CALLS

    monkeypatch.setenv("CC", "no-such-compiler")
    monkeypatch.setenv("LINKAGE_FMU_CACHE", str(tmp_path))
    compiled._no_compiler_warning.cache_clear()
    mech = presets.get("four_bar")
    th = np.linspace(0.1, 6.2, HOT_CALLS + 20)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # said once, tested in test_kernels
        for t in th[:HOT_CALLS]:
            mech.solve(float(t), omega=10.0, alpha=1.0, load=2.0)
    assert mech.solver.hot == [None, None] and not mech.kernel().compiled
    for t in th[HOT_CALLS:]:
        ref = mech.solve(float(t), 10.0, 1.0, 2.0, method="interpreted")
        for sol in (mech.solve(float(t), omega=10.0, alpha=1.0, load=2.0),
                    mech.solve(float(t), 10, 1, 2), mech.solve(float(t), 10.0, 1.0, 2.0)):
            assert dict(sol) == dict(ref)


def test_a_lean_solution_is_a_mapping_of_floats_like_any_other():
    """The lean path's Solution (its outputs kept unboxed) against the general path's for
    the same state (reference: Solver.solve asked for every output by name): the same
    names, floats (type float, equal bits), repr and valid; it copies, deep-copies and
    pickles to an equal Solution; and it compares equal to the dict of its items."""
    import copy
    import pickle

    from linkage_fmu.solver import Solution

    mech = presets.get("slider_crank")
    if not _lean(mech):
        pytest.skip("no C compiler: solve has no lean path")
    sol = mech.solve(0.7, omega=12.0, alpha=-3.0, load=40.0)
    ref = mech.solver.solve(0.7, 12.0, -3.0, 40.0,
                            outputs=tuple(mech.output_names + mech.diagnostic_names))
    assert type(sol) is Solution and sol.valid is True and len(sol) == len(ref)
    assert list(sol) == list(ref) and repr(sol) == repr(ref)
    assert all(type(v) is float for v in sol.values())
    assert np.array_equal(np.array(list(sol.values())), np.array(list(ref.values())))
    for twin in (copy.copy(sol), copy.deepcopy(sol), pickle.loads(pickle.dumps(sol))):
        assert type(twin) is Solution and twin == sol == dict(ref.items())


def test_a_parameter_whose_arithmetic_overflows_is_the_librarys_error():
    """The four-bar with l_CD = 1e308: (l_BC + l_CD)**2 overflows Python's float (an
    OverflowError, where C and numpy give inf). Every method raises the library's
    OverflowInputError, a ValueError naming the overflow and the parameter; an array
    solve marks every state OVERFLOW with NaN outputs; the FMUs' call gives the reason."""
    from linkage_fmu import OverflowInputError
    from linkage_fmu.solver import METHODS, OVERFLOW

    mech = presets.get("four_bar", l_CD=1e308)
    for method in METHODS:
        with pytest.raises(OverflowInputError, match=r"overflows float64 at theta = 0.5, "
                           r"omega = 10.0.*parameter l_CD = 1e\+308") as err:
            mech.solve(0.5, omega=10.0, method=method)
        assert isinstance(err.value, ValueError)
        sol = mech.solve(np.array([0.5, 2.0]), omega=10.0, method=method)
        assert not sol.valid.any() and np.isnan(sol["Mb"]).all()
        assert sol.status.tolist() == [OVERFLOW, OVERFLOW]
        assert sol.problems[OVERFLOW].reason.kind == "overflow"
        assert mech.solver.attempt([0.5, 10.0, 0.0, 0.0], None, method).text == \
            "the outputs overflow float64: an input or a parameter is too large in magnitude"


def test_a_singular_matrix_in_the_direct_method_is_the_librarys_error():
    """The slider-crank with l_AB = 1e308 by the direct method (where
    numpy.linalg.LinAlgError escaped): the library's SingularPositionError for every
    method, saying what both FMU flavours log. A LinAlgError from inside the direct
    method (an exactly singular Jacobian of the friction's Newton steps: mocked here, as
    no coefficient of friction up to the largest taken makes one) is the library's
    error too, not numpy's; and the batched solve gives NaN for an exactly singular
    state, the others as numpy solves them alone (1e-15)."""
    from linkage_fmu.solver import METHODS, STATE_ERRORS

    mech = presets.get("slider_crank", l_AB=1e308)
    for method in METHODS:
        with pytest.raises(SingularPositionError) as err:
            mech.solve(0.5, omega=10.0, method=method)
        assert err.value.reason.text == ("the linkage is at a singular position: the dyad at "
                                         "B is at a toggle")
    rubbing = presets.get("slider_crank", mu_guide=0.1)
    with mock.patch.object(friction.linalg, "solve_batch",
                           side_effect=np.linalg.LinAlgError("Singular matrix")):
        with pytest.raises(STATE_ERRORS):
            rubbing.solve(0.5, omega=10.0, method="direct")
    A = np.array([[[2.0, 1.0], [1.0, 3.0]], [[1.0, 2.0], [2.0, 4.0]]])
    b = np.array([[1.0, 2.0], [1.0, 1.0]])
    x = linalg.solve_batch(A, b)
    np.testing.assert_allclose(x[0], np.linalg.solve(A[0], b[0]), rtol=1e-15)
    assert np.isnan(x[1]).all()


@pytest.mark.parametrize("name, parameter", [("scotch_yoke", "J3"), ("slotted_lever", "J2")])
def test_a_non_finite_diagnostic_is_no_solution(name, parameter):
    """ScotchYoke with J3 = 1e308 gave dJ_red = NaN, SlottedLever with J2 = 1e308
    dJ_red = -inf, as a valid solution: every output counts, diagnostics included
    (only eta may be NaN at a solved state, where no power enters). Both are the
    overflow error for every method, at rest too, and OVERFLOW over arrays."""
    from linkage_fmu import OverflowInputError
    from linkage_fmu.solver import METHODS, OVERFLOW

    mech = presets.get(name, **{parameter: 1e308})
    for method in METHODS:
        for omega in (0.0, 10.0):
            with pytest.raises(OverflowInputError, match=rf"parameter {parameter} = 1e\+308"):
                mech.solve(0.5, omega=omega, method=method)
        sol = mech.solve(np.array([0.5, 2.0]), omega=10.0, method=method)
        assert sol.status.tolist() == [OVERFLOW, OVERFLOW]


def test_an_integer_past_float64_is_named():
    """An int too large for a float64 (10**400) as an input, in an array or as a
    parameter raised Python's bare OverflowError; it is a ValueError naming it."""
    mech = presets.get("four_bar")
    for call, name in ((lambda: mech.solve(10 ** 400, omega=10.0), "theta"),
                       (lambda: mech.solve(0.3, omega=10 ** 400), "omega"),
                       (lambda: mech.solve([0.1, 10 ** 400], omega=10.0), "theta"),
                       (lambda: presets.get("four_bar", l_CD=10 ** 400), "l_CD")):
        with pytest.raises(ValueError, match=rf"{name} must be (a )?finite.*past float64's range"):
            call()


def test_start_values_cannot_go_stale():
    """The lean path keeps the input loads' start values: ``start`` is read-only, neither
    assigned nor changed in place, and a linkage still deep-copies (a read-only mapping
    held in it made deepcopy fail). Reference: the copy's Mb equals the original's."""
    import copy

    mech = presets.get("scotch_yoke")
    with pytest.raises(AttributeError):
        mech.start = {**mech.start, "load": 0.0}
    with pytest.raises(TypeError):
        mech.start["load"] = 0.0
    twin = copy.deepcopy(mech)
    assert twin.solve(0.3, omega=10.0)["Mb"] == mech.solve(0.3, omega=10.0)["Mb"]
    assert twin.start == mech.start


def test_a_second_driver_refuses_a_balancing_effort_with_the_reason():
    """A second crank makes the linkage one driven by time, each driver with its own
    effort: a balancing effort given besides is refused, naming the drivers and it."""
    from linkage_fmu import Mechanism
    from linkage_fmu.errors import LinkageError
    from linkage_fmu.groups import Crank

    m = presets.get("four_bar")
    with pytest.raises(LinkageError, match=r"four_bar: it is driven by time \(Crank at A, "
                                           r"Crank at D\): each driver applies its own "
                                           r"effort \(Mb_<j>, Fb_<j>\), so it takes no "
                                           "balancing effort 'Mb'"):
        Mechanism("four_bar", m.frame, m.frame_points, (*m.groups, Crank("9", "D", "Z", 0.1)),
                  m.bodies, m.effort, [], [], 0.0)
    assert [d.name for d in m.drivers] == ["A"] and m.drivers[0].effort == "Mb"


def test_a_linkage_driven_by_one_crank_without_its_effort_is_refused():
    from linkage_fmu.errors import LinkageError
    from linkage_fmu.groups import RRR, Crank
    from linkage_fmu.mechanism import Body, Mechanism

    with pytest.raises(LinkageError, match="four: it is driven by one crank: give its "
                                           "balancing effort"):
        Mechanism("four", "0", {"A": (0.0, 0.0), "D": (0.4, 0.0)},
                  [Crank("1", "A", "B", 0.1), RRR("2", "3", "B", "C", "D", 0.35, 0.3, 1)],
                  [Body("1", 1.0, 0.01, "A"), Body("2", 1.0, 0.01, "B"),
                   Body("3", 1.0, 0.01, "D")], None, [], [], 9.81)
