"""Solving a linkage: plans, methods, the kernels and when to compile them, arrays in
blocks, and why a state has no outputs.

A :class:`Plan` is what a call asks for: which outputs, a static scene or not, which
method. A :class:`Solver` (one per :class:`~linkage_fmu.mechanism.Mechanism`, its
``solver``) serves every call with the cheapest path that gives the plan's exact floats:

* one state of finite floats: the plan's traced kernel (Python, then, once the plan has
  served :data:`HOT_CALLS` calls, C); the interpreted formulas where the kernel does not
  take the state;
* many states: the compiled array kernel over all of them, the interpreted formulas for
  the states it hands back, in blocks that stay in the CPU caches;
* ``method="interpreted"`` or ``"direct"``: :func:`~linkage_fmu.evaluation.evaluate`
  on floats or arrays.

A state without outputs has a reason (:class:`~linkage_fmu.kernels.trace.Reason`):
scalars raise the library's error, which carries it; arrays give NaN and a status per
state (:attr:`ArraySolution.status`, :attr:`ArraySolution.problems`);
:meth:`Solver.attempt` answers either for one state without raising (the FMU's call).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import NamedTuple

import numpy as np

from . import diagnostics, evaluation, ranges
from .drivers import one_crank
from .errors import (
    AssemblyError,
    InputError,
    InputTypeError,
    OverflowInputError,
    SelfLockingError,
    SingularPositionError,
)
from .expressions import evaluate
from .kernels import TRACE, Kernel, trace
from .kernels.trace import Reason
from .numerics import ARRAY, SCALAR, finite_array, finite_float

#: closed_form: the traced kernel (scalars) or the group formulas (arrays); direct: the
#: assembled linear system (the reference); interpreted: the group formulas step by step
METHODS = ("closed_form", "direct", "interpreted")
#: one-state calls of a plan after which it is compiled (the first compilation of a
#: linkage's plan costs a fraction of a second; later ones, and other parameter sets of
#: the same linkage, load it from the cache)
HOT_CALLS = 1000
#: crank angles tried as the witness state of a trace, until one assembles
WITNESS_ANGLES = (0.3, 1.1, 2.3, 4.0, 5.5, 0.0, 3.0)
#: states per block of an array solve: its temporaries stay in the CPU caches
CHUNK = 8192
#: the status of a state in an array solve
SOLVED, UNASSEMBLED, SINGULAR, OVERFLOW, LOCKED = 0, 1, 2, 3, 4
STATUS_NAMES = {SOLVED: "solved", UNASSEMBLED: "cannot be assembled", SINGULAR: "singular",
                OVERFLOW: "overflow", LOCKED: "self-locking"}
#: the errors of a state without outputs
STATE_ERRORS = (AssemblyError, SingularPositionError, OverflowInputError, SelfLockingError)


class Plan(NamedTuple):
    """What a call asks for: the ``outputs`` (validated names), whether the scene is
    ``static``, the ``method``, and what they need: the balancing ``effort``, the
    ``reactions``, the ``diagnostics``; ``checked``: the outputs that must be finite,
    diagnostics included (not those that may be NaN at a solved state: ``eta`` where no
    power enters);
    ``given``: the loads over the cycle given as inputs (after the input loads)."""

    outputs: tuple
    static: bool
    method: str
    effort: bool
    reactions: bool
    diagnostics: bool
    checked: tuple
    given: tuple = ()


class Solution(Mapping):
    """Outputs of :meth:`Solver.solve`: name -> float (scalar inputs) or ndarray.

    Attributes
    ----------
    valid : bool or ndarray of bool
        Which states have outputs: they can be assembled and friction does not lock
        them (always True for scalar inputs, which raise
        :class:`~linkage_fmu.AssemblyError` or
        :class:`~linkage_fmu.SelfLockingError` instead).
    """

    __slots__ = ("_values", "_index", "valid")
    #: a scalar solution is solved (a state that is not raises)
    status = SOLVED
    problems: dict = {}

    def __init__(self, values, valid, index: dict | None = None):
        # a dict, or a sequence of floats (a tuple; the outputs a compiled kernel keeps
        # unboxed: Solver.hot) with the name -> position map its kernel shares
        if index is None:
            index = {name: i for i, name in enumerate(values)}
            values = tuple(values.values())
        self._values, self._index, self.valid = values, index, valid

    def __getitem__(self, name: str):
        return self._values[self._index[name]]

    def __iter__(self):
        return iter(self._index)

    def __len__(self) -> int:
        return len(self._index)

    def __eq__(self, other):
        return dict(self) == dict(other) if isinstance(other, Mapping) else NotImplemented

    def __repr__(self) -> str:
        body = ", ".join(f"{k}={v!r}" for k, v in self.items())
        return f"Solution({body})"


class Problem(NamedTuple):
    """States of an array solve without outputs, of one status: the ``reason`` (as the
    FMUs say it), the library's ``message`` at the ``first`` of them (flat index), and
    how many there are (``count``)."""

    reason: Reason
    message: str
    first: int
    count: int


class ArraySolution(Solution):
    """A :class:`Solution` over arrays of states, which also says why a state has no
    outputs: :attr:`status` and :attr:`problems`, worked out when first asked for."""

    __slots__ = ("_classify", "_status", "_problems")

    def __init__(self, values, valid, classify):
        super().__init__(values, valid)
        self._classify, self._status, self._problems = classify, None, None

    @property
    def status(self) -> np.ndarray:
        """Per state: :data:`SOLVED`, :data:`UNASSEMBLED`, :data:`SINGULAR` (the outputs
        are unbounded), :data:`OVERFLOW` (an input too large) or :data:`LOCKED` (friction
        locks it), as int8."""
        if self._status is None:
            self._status, self._problems = self._classify(self)
        return self._status

    @property
    def problems(self) -> dict[int, Problem]:
        """Status -> :class:`Problem`, for each status other than :data:`SOLVED` that
        some state has."""
        if self._problems is None:
            self._status, self._problems = self._classify(self)
        return self._problems


class _NoKernel:
    """The kernel of a plan that could not be traced (no witness state): every state is
    interpreted. ``error`` says why."""

    compiled = False
    checked = ()
    index: dict = {}
    calls = HOT_CALLS  # never counted, never compiled

    def __init__(self, error: ValueError):
        self.error = error

    @staticmethod
    def call(*inputs):
        return None

    @staticmethod
    def array():
        return None


def frame(sol: Solution, theta):
    """The array solution ``sol`` at the angles ``theta`` as a pandas DataFrame, one column
    per output, indexed by ``theta`` (broadcast to the solution's shape); a negative
    zero (a friction output without friction, ``-mu * |F|`` with ``mu = 0``) as 0, so
    that a table printed shows no ``-0.0``."""
    import pandas as pd

    index = pd.Index(np.broadcast_to(theta, np.shape(next(iter(sol.values())))).ravel(),
                     name="theta")
    # x + 0.0 is x for every x but -0.0, which it makes 0.0
    return pd.DataFrame({k: np.ravel(v) + 0.0 for k, v in sol.items()}, index=index)


def finite(values) -> bool:
    """True when every value is finite (one sum: a finite sum of finite terms)."""
    return math.isfinite(sum(values)) or all(map(math.isfinite, values))


class Solver:
    """Solves the linkage ``mech``: plans, kernels and methods (see the module notes)."""

    def __init__(self, mech):
        self.mech = mech
        self._all = mech.output_names + mech.diagnostic_names  # one object: fast keys
        self._plans: dict = {}  # (outputs, static, method) -> Plan
        self._valid: set = {self._all}  # output tuples validated before
        self._kernels: dict = {}  # (outputs, static) -> Kernel, or _NoKernel
        #: [static, moving]: the compiled one-state kernel of every output, once it is
        #: hot (None before), as ``hot(theta, omega, alpha, *loads)``: a
        #: :class:`Solution` where the kernel takes the state (what :meth:`solve` returns
        #: for it), else what :attr:`Kernel.call <linkage_fmu.kernels.Kernel.call>`
        #: returns (:meth:`solve` decides)
        self.hot: list = [None, None]

    # -- plans ------------------------------------------------------------------
    def wanted(self, outputs: Iterable[str] | None) -> tuple:
        """``outputs`` as a tuple of the linkage's output names (default: all of them and
        the diagnostics); an unknown name is a ValueError naming it."""
        if outputs is None:
            return self._all
        if type(outputs) is tuple and outputs in self._valid:
            return outputs
        wanted = (outputs,) if isinstance(outputs, str) else tuple(outputs)
        for name in wanted:
            if name not in self._all:
                raise InputError(f"{self.mech.name} has no output {name!r}; its outputs are: "
                                 + ", ".join(self._all))
        self._valid.add(wanted)
        return wanted

    def plan(self, outputs: tuple, static: bool, method: str, given: tuple = ()) -> Plan:
        """The :class:`Plan` of the validated ``outputs`` (:meth:`wanted`)."""
        key = (outputs, static, method, given)
        plan = self._plans.get(key)
        if plan is None:
            mech = self.mech
            diag, efforts = set(mech.diagnostic_names), mech.effort_outputs
            effort = any(n in efforts for n in outputs)
            plan = self._plans[key] = Plan(
                outputs, static, method, effort,
                any(n not in diag and n not in efforts for n in outputs) or (
                    effort and mech.friction.active),  # the effort needs the reactions
                bool(diag.intersection(outputs)),
                tuple(n for n in outputs if n in mech.output_info
                      and n not in mech.partial_outputs), given)
        return plan

    # -- kernels ----------------------------------------------------------------
    def kernel(self, outputs: Iterable[str] | None = None, static: bool = False,
               given: tuple = ()) -> Kernel:
        """The traced kernel of the plan ``(outputs, static)``, made on first use and kept.

        ``kernel(theta, omega, alpha, *loads)`` returns the outputs as a tuple of floats,
        or None at a state it does not take (see :class:`~linkage_fmu.kernels.Kernel`);
        ``loads`` are the input loads, then the loads over the cycle named in ``given``.

        Raises
        ------
        ValueError
            The linkage assembles at none of the :data:`WITNESS_ANGLES`: there is no
            state to trace the formulas at (asked again, at once, without tracing).
        """
        wanted = self.wanted(outputs)
        key = (wanted, static, given)
        k = self._kernels.get(key)
        if k is None:
            try:
                k = self._kernels[key] = self._trace(wanted, static, given)
            except ValueError as err:
                self._kernels[key] = _NoKernel(err)
                raise
        if isinstance(k, _NoKernel):  # traced before, without a witness: say so at once
            raise k.error
        return k

    def _kernel_or_none(self, wanted: tuple, static: bool, given: tuple = ()):
        try:
            return self.kernel(wanted, static, given)
        except ValueError:  # no witness state: this plan stays interpreted
            return self._kernels[(wanted, static, given)]

    def _trace(self, wanted: tuple, static: bool, given: tuple) -> Kernel:
        """Trace the closed-form formulas of the plan at the first witness angle where
        the linkage assembles (the trace follows what the floats do there); failing
        those, the middle of each range where it does."""
        mech = self.mech
        plan = self.plan(wanted, static, "closed_form", given)
        loads = [1.1 + 0.1 * k for k in range(len(mech.input_loads) + len(given))]
        omega, alpha = (0.0, 0.0) if static else (1.3, 0.7)
        last = None

        def witnesses():
            if mech.rates:  # where the drivers start (a drawn linkage: where drawn)
                yield [v for d in mech.drivers
                       for v in (float(mech.start[d.inputs[0]]), omega, alpha)]
                return
            for theta in WITNESS_ANGLES:
                yield [theta, omega, alpha]
            try:
                found = ranges.assembles(mech)  # a linkage that turns part of a revolution
            except OverflowError:  # its parameters overflow: no state to trace
                found = ()
            for a, b in found:
                yield [math.radians(0.5 * (a + b)), omega, alpha]

        for state in witnesses():
            try:  # a witness must be solvable
                evaluation.evaluate(mech, plan, *evaluation.split(mech, state + loads), SCALAR)
            except (ValueError, ArithmeticError, np.linalg.LinAlgError) as err:
                last = err  # an overflow at these parameters: no witness here either
                continue
            parameters = {n: mech.parameters[n] for n in mech.kernel_parameters}

            def outputs(x: list, symbols: dict) -> list:
                twin = mech.rebuild(symbols) if symbols else mech
                out, _ = evaluation.evaluate(twin, plan, *evaluation.split(twin, x), TRACE)
                return [out[n] for n in wanted]

            checked = tuple(i for i, n in enumerate(wanted) if n in plan.checked)
            return trace(outputs, (*state, *loads), parameters, wanted, checked,
                         static, f"kernel of {mech.name}")
        where = "where its drivers start" if mech.rates else "at any crank angle"
        raise InputError(f"{mech.name} cannot be assembled {where}: {last}")

    def _count(self, k) -> None:
        """A one-state call of the kernel ``k``: the :data:`HOT_CALLS`-th compiles it."""
        k.calls += 1
        if k.calls == HOT_CALLS:
            k.compile()

    # -- solving ----------------------------------------------------------------
    def solve(self, theta, omega=None, alpha=None, *loads, method: str = "closed_form",
              outputs: Iterable[str] | None = None, **named_loads) -> Solution:
        """Joint reactions, balancing effort and diagnostics at one or many states:
        every call :meth:`Mechanism.solve <linkage_fmu.mechanism.Mechanism.solve>`'s
        fast path does not serve.

        Parameters
        ----------
        theta : float, str or array_like
            Crank angle [rad]; one angle may be text with a unit (``"30 deg"``).
        omega, alpha : float, str or array_like, optional
            Crank speed [rad/s] and acceleration [rad/s2] (``"1800 rpm"``); default the
            start values (the linkage's ``start``).
        *loads : float, str or array_like
            Each input load's magnitude [N or N.m], in the linkage's ``input_names`` order.
        method : {'closed_form', 'direct', 'interpreted'}
            ``closed_form`` (default): group by group from the last group back to the
            crank, one state by its compiled kernel; ``direct``: the assembled linear
            system of the whole linkage (the reference); ``interpreted``: the closed
            form's formulas step by step (a second reference).
        outputs : iterable of str, optional
            The names wanted, of the linkage's ``output_names`` and ``diagnostic_names``
            (default all); asking for the balancing effort alone skips the reactions.
        **named_loads : float, str or array_like
            The input loads by name (a preset's one load is ``load``), or a load given
            over the cycle by name, which replaces what it computes. A load not given
            takes its start value.

        Returns
        -------
        Solution
            Output name -> value, the outputs then the diagnostics: floats for one
            state; for arrays an :class:`~linkage_fmu.solver.ArraySolution` of the
            inputs' broadcast shape, NaN at a state without outputs, whose ``valid``
            and ``status`` say which and why.

        Raises
        ------
        AssemblyError
            One state the linkage cannot be assembled at.
        SingularPositionError
            One state at which the equations are singular (a toggle, a dead centre).
        SelfLockingError
            One state that friction locks: no finite effort moves the linkage.
        OverflowInputError
            One state of finite inputs whose outputs overflow.
        ValueError
            An unknown method or output, an input that is not a finite number (or an
            unknown unit), or inputs that do not broadcast to one shape.
        TypeError
            An unknown input name, a load given twice, or too many loads.

        Examples
        --------
        The scotch yoke worked example's state, given as text with units:

        >>> from linkage_fmu import presets
        >>> solver = presets.get("scotch_yoke").solver
        >>> sol = solver.solve("60 deg", "10 rad/s", load="0.4 kN")
        >>> round(sol["Mb"], 4), round(sol["F23y"], 4)
        (15.6699, 313.3975)
        """
        mech = self.mech
        if method not in METHODS:
            raise InputError(f"method must be one of {METHODS}, got {method!r}")
        wanted = self.wanted(outputs)
        if mech.rates:  # every input positionally or by name
            args, given = mech.input_table.every((theta, omega, alpha, *loads), named_loads)
            args = tuple(args)
        else:
            if theta is None:
                raise InputTypeError(f"{mech.name}: solve takes the crank angle theta")
            values, given = mech.input_table.values(omega, alpha, loads, named_loads)
            if isinstance(theta, str):  # a number with a unit, an expression
                theta = evaluate(theta, "rad", "theta")
            args = (theta, *values)
        names = mech.input_names + given
        if all(type(a) is float for a in args) and math.isfinite(sum(args)):
            return self._one(args, method, wanted, given)  # finite floats: FMU steps
        if all(np.ndim(a) == 0 for a in args):
            values = [finite_float(n, a.item() if isinstance(a, np.ndarray) else a)
                      for n, a in zip(names, args)]
            return self._one(values, method, wanted, given)
        arrays_given = [finite_array(n, a) for n, a in zip(names, args)]
        try:
            arrays = np.broadcast_arrays(*arrays_given)
        except ValueError:
            raise InputError(", ".join(names) + " must broadcast to one shape, got "
                             + ", ".join(str(np.shape(a)) for a in arrays_given)) from None
        shape = arrays[0].shape
        flat = [a.reshape(-1) for a in arrays]  # views where possible: no scalar copied n times
        n = flat[0].size
        out = None
        try:
            if method == "closed_form" and n:
                out = self._compiled_arrays(arrays_given, flat, n, wanted, given)
                method = "interpreted"  # without a C compiler: numpy
            if out is None:
                out = {name: np.empty(n) for name in wanted}
                valid = np.empty(n, dtype=bool)
                self._interpreted_arrays(flat, method, wanted, out, valid, slice(0, n), given)
            else:
                out, valid = out
        except OverflowError:  # Python floats (the parameters') raise where numpy gives inf
            out = {name: np.full(n, np.nan) for name in wanted}
            valid = np.zeros(n, dtype=bool)

            def classify(sol: ArraySolution):
                return self._overflowed(sol, flat, wanted, given)
        else:
            def classify(sol: ArraySolution):
                return self._classify(sol, flat, method, wanted, given)

        return ArraySolution({k: v.reshape(shape) for k, v in out.items()},
                             valid.reshape(shape), classify)

    def table(self, theta, omega=None, alpha=None, *loads, method: str = "closed_form",
              outputs: Iterable[str] | None = None, **named_loads):
        """:meth:`solve` over the crank angles ``theta`` as a pandas DataFrame, one
        column per output.

        Parameters
        ----------
        theta : float or array_like
            Crank angle(s) [rad], the table's index (named ``theta``).
        omega, alpha, *loads, method, outputs, **named_loads
            As for :meth:`solve`; each broadcasts against ``theta``.

        Returns
        -------
        pandas.DataFrame
            One row per angle, one column per output wanted (the outputs, then the
            diagnostics); a row the linkage has no outputs at (it cannot be assembled
            there, a singular or locked position) is NaN.

        Raises
        ------
        ValueError, TypeError
            As :meth:`solve` for the inputs; a state without outputs raises nothing
            (its row is NaN).

        Examples
        --------
        >>> import numpy as np
        >>> from linkage_fmu import presets
        >>> yoke = presets.get("scotch_yoke")
        >>> df = yoke.table(np.radians([0.0, 60.0]), omega=10.0, load=400.0,
        ...                 outputs=["Mb", "F23y"])
        >>> df.round(4)
                      Mb      F23y
        theta
        0.000000  40.0000  400.0000
        1.047198  15.6699  313.3975

        A crank too long to turn a revolution: the rows it cannot reach are NaN.

        >>> rocker = presets.get("four_bar", l_AB=0.3)
        >>> rocker.table([0.0, 3.0], omega=10.0, outputs=["Mb"])["Mb"].isna().tolist()
        [False, True]
        """
        one_crank(self.mech, "a table over crank angles")
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        return frame(self.solve(theta, omega, alpha, *loads, method=method, outputs=outputs,
                                **named_loads), theta)

    # -- one state ------------------------------------------------------------------
    def _one(self, values, method: str, wanted: tuple, given: tuple = ()) -> Solution:
        """One state of finite floats: the kernel's tuple, or the interpreted formulas."""
        if method == "closed_form":
            r, k = self._kernel_call(values, wanted, given)
            if wanted is self._all and k.compiled and not self.mech.rates and \
                    self.hot[values[1] != 0.0 or values[2] != 0.0] is None:
                self.hot[values[1] != 0.0 or values[2] != 0.0] = k.instances(
                    Solution, ("_values", "_index", "valid"), (k.index, True))
            if type(r) is tuple and (math.isfinite(sum(r)) or finite([r[i] for i in k.checked])):
                return Solution(r, True, k.index)
            # the interpreted formulas decide: they raise the exact error, or compute
            # the state the trace did not take
            method = "interpreted"
        return Solution(self._interpreted_one(values, method, wanted, given), True)

    def _kernel_call(self, values, wanted: tuple, given: tuple = ()):
        """The plan's kernel at one state: its answer (a tuple, a guard's code, or None)
        and the kernel."""
        static = evaluation.still(self.mech, values) if self.mech.rates else \
            values[1] == 0.0 and values[2] == 0.0
        k = self._kernels.get((wanted, static, given)) or self._kernel_or_none(
            wanted, static, given)
        try:
            r = k.call(*values)
        except (ArithmeticError, ValueError):  # a division by zero, math range error
            r = None
        if k.calls < HOT_CALLS:
            self._count(k)
        return r, k

    def _interpreted_one(self, values, method: str, wanted: tuple, given: tuple = ()) -> dict:
        """One state of finite floats ``(theta, omega, alpha, *loads)`` by the formulas;
        raises the error of a state without outputs."""
        mech = self.mech
        static = evaluation.still(mech, values) if mech.rates else \
            values[1] == 0.0 and values[2] == 0.0
        plan = self.plan(wanted, static, method, given)
        try:
            out, _ = evaluation.evaluate(mech, plan, *evaluation.split(mech, values), SCALAR)
            # one finite sum: every term is finite (a sum that overflows is checked term
            # by term); a non-finite output means singular or overflowing
            if math.isfinite(sum(out[n] for n in plan.checked)) or \
                    all(math.isfinite(out[n]) for n in plan.checked):
                return {n: float(out[n]) for n in wanted}
        except (ZeroDivisionError, OverflowError, np.linalg.LinAlgError):
            pass  # Python's float arithmetic raises what C's gives as inf or NaN
        raise self._unbounded(values, given)

    def _unbounded(self, values, given: tuple = ()) -> ValueError:
        """The error of a state that assembles but whose outputs are not finite: an
        overflow if the position is well conditioned, else a singular position."""
        mech = self.mech
        theta, speeds, accelerations, _ = evaluation.split(mech, values)
        rates = tuple(zip(speeds, accelerations)) if mech.rates else None
        inputs = ", ".join(f"{n} = {v!r}" for n, v in zip(mech.input_names + given, values))
        try:
            st = evaluation.kinematics(mech, theta, 0 if mech.effort_on_crank else 1, SCALAR,
                                       rates)
        except OverflowError:  # the position itself overflows
            return OverflowInputError(mech.name, f"the arithmetic overflows float64 at "
                                      f"{inputs}: {_largest(mech, values, given)}")
        try:  # a finite condition: the position is fine, the inputs overflow
            cond = diagnostics.values(mech, st)["cond"]
        except (ZeroDivisionError, OverflowError):
            cond = math.inf
        if math.isfinite(cond):
            inputs += "".join(f", {ld.name} = {float(ld.at_state(st))!r} (over the cycle)"
                              for ld in mech.computed_loads if ld.name not in given)
            return OverflowInputError(mech.name, f"the outputs overflow float64 at {inputs}: "
                                      f"{_largest(mech, values, given)}")
        return SingularPositionError(mech.name, evaluation.state_words(mech, theta),
                                     diagnostics.singular_detail(mech, st),
                                     diagnostics.singular_what(mech, st))

    def attempt(self, values: list, outputs: Iterable[str] | None = None,
                method: str = "closed_form") -> tuple | Reason:
        """One state of finite floats ``(theta, omega, alpha, *loads)``: the outputs as a
        tuple (in the order of ``outputs``, default all), or the
        :class:`~linkage_fmu.kernels.trace.Reason` the state has none. Never raises for
        a state; one kernel call where the kernel decides (the FMU's step).

        Examples
        --------
        >>> from linkage_fmu import presets
        >>> solver = presets.get("four_bar", l_AB=0.3).solver
        >>> solver.attempt([3.1, 10.0, 0.0, 0.0]).text
        'the linkage cannot be assembled: the dyad B-C-D cannot close'
        """
        wanted = self.wanted(outputs)
        if method == "closed_form":
            r, k = self._kernel_call(values, wanted)
            if type(r) is tuple and (math.isfinite(sum(r)) or finite([r[i] for i in k.checked])):
                return r
            if type(r) is int and r > 0 and \
                    k.reasons[r - 1].kind in ("assembly", "singular", "locking"):
                return k.reasons[r - 1]
            method = "interpreted"  # the formulas decide what the kernel does not
        try:
            out = self._interpreted_one(values, method, wanted)
        except STATE_ERRORS as err:
            return err.reason
        return tuple(out[n] for n in wanted)

    # -- arrays -----------------------------------------------------------------
    def _interpreted_arrays(self, flat, method, wanted, out, valid, rows, given=()) -> None:
        """The formulas on numpy arrays over the states ``rows`` of ``flat`` (a slice,
        or an index array), in blocks that stay in the CPU caches (the formulas make
        many temporaries per state); results into ``out`` and ``valid``."""
        if isinstance(rows, slice):
            parts = (slice(i, min(i + CHUNK, rows.stop))
                     for i in range(rows.start, rows.stop, CHUNK))
        else:
            parts = (rows[i:i + CHUNK] for i in range(0, rows.size, CHUNK))
        with np.errstate(divide="ignore", invalid="ignore"):
            for part in parts:
                state = [a[part] for a in flat]
                plan = self.plan(wanted, evaluation.still(self.mech, state), method, given)
                values, st = evaluation.evaluate(self.mech, plan,
                                                 *evaluation.split(self.mech, state), ARRAY)
                valid[part] = _solved(st)
                for name in wanted:
                    out[name][part] = values[name]

    def _compiled_arrays(self, arrays, flat, n, wanted, given=()):
        """The compiled kernel of the plan over every state, the interpreted formulas for
        the states it hands back: ``(outputs, valid)``; None without a compiled kernel."""
        static = evaluation.still(self.mech, flat)
        k = self._kernels.get((wanted, static, given)) or self._kernel_or_none(
            wanted, static, given)
        array = k.array()
        if array is None:
            return None
        # one value, or the whole flat array: a broadcast scalar is never copied n times
        inputs = [g.reshape(1) if g.size == 1 else f for g, f in zip(arrays, flat)]
        values, valid = array(inputs, n)
        out = dict(zip(wanted, values))
        back = np.flatnonzero(~valid)
        if back.size:  # cannot be assembled, singular, or another branch: the formulas decide
            self._interpreted_arrays(flat, "interpreted", wanted, out, valid, back, given)
        return out, valid

    def _classify(self, sol: ArraySolution, flat, method, wanted, given=()) -> tuple:
        """The status of every state of ``sol`` and a :class:`Problem` per status."""
        valid = np.asarray(sol.valid).reshape(-1)
        status = np.where(valid, SOLVED, UNASSEMBLED).astype(np.int8)
        rows = np.flatnonzero(~valid)
        if rows.size and self.mech.friction.active:  # not valid: unassembled, or locked
            status[rows[self._locked([a[rows] for a in flat], wanted, given)]] = LOCKED
        checked = self.plan(wanted, False, method, given).checked
        bad = np.zeros(valid.size, dtype=bool)
        for name in checked:
            bad |= ~np.isfinite(np.asarray(sol[name]).reshape(-1))
        rows = np.flatnonzero(bad & valid)
        if rows.size:
            out = {"cond": np.empty(rows.size)}
            self._interpreted_arrays([a[rows] for a in flat], "interpreted", ("cond",), out,
                                     np.empty(rows.size, bool), slice(0, rows.size), given)
            status[rows] = np.where(np.isfinite(out["cond"]), OVERFLOW, SINGULAR)
        problems = {}
        for code in (UNASSEMBLED, SINGULAR, OVERFLOW, LOCKED):
            where = np.flatnonzero(status == code)
            if where.size:
                i = int(where[0])
                error = self._error_at([float(a[i]) for a in flat], wanted, given)
                reason = error.reason if error is not None else Reason("branch")
                problems[code] = Problem(reason, str(error or reason.text), i, int(where.size))
        return status.reshape(np.shape(sol.valid)), problems

    def _error_at(self, state: list, wanted, given=()) -> Exception | None:
        """The error a failed array state raises when solved alone, None if it solves."""
        try:
            self._interpreted_one(state, "interpreted", wanted, given)
        except STATE_ERRORS as err:
            return err
        return None

    def _overflowed(self, sol: ArraySolution, flat, wanted, given=()) -> tuple:
        """Every state of ``sol`` overflows: what its parameters compute overflows
        float64 (a Python float raises OverflowError where arrays would give inf)."""
        error = self._error_at([float(a[0]) for a in flat], wanted, given)
        reason = error.reason if error is not None else Reason("overflow")
        n = int(np.size(sol.valid))
        status = np.full(np.shape(sol.valid), OVERFLOW, dtype=np.int8)
        return status, {OVERFLOW: Problem(reason, str(error or reason.text), 0, n)}

    def _locked(self, flat, wanted, given=()) -> np.ndarray:
        """Which of the states ``flat`` friction locks (the formulas on arrays): those
        that assemble and whose friction has no solution."""
        with np.errstate(all="ignore"):
            plan = self.plan(wanted, False, "interpreted", given)
            _, st = evaluation.evaluate(self.mech, plan, *evaluation.split(self.mech, flat), ARRAY)
        locked = np.zeros(flat[0].size, bool) if st.locked is None else st.locked.copy()
        if st.invalid is not None:
            locked &= ~st.invalid
        return locked


def _largest(mech, values, given: tuple = ()) -> str:
    """Which input or parameter is too large, for a message: the largest in magnitude.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> _largest(presets.get("four_bar", l_CD=1e308), [0.5, 10.0, 0.0, 0.0])
    'an input or a parameter is too large in magnitude (the largest: parameter l_CD = 1e+308)'
    """
    named = [(f"input {n}", v) for n, v in zip(mech.input_names + given, values)]
    named += [(f"parameter {n}", v) for n, v in mech.parameters.items() if type(v) is float]
    name, value = max(named, key=lambda nv: abs(nv[1]))
    return f"an input or a parameter is too large in magnitude (the largest: {name} = {value!r})"


def _solved(st) -> np.ndarray | bool:
    """Which states of the array solve ``st`` have outputs: they assemble, and friction
    does not lock them (a locked state has none, as an unassembled one)."""
    bad = st.invalid
    if st.locked is not None:
        bad = st.locked if bad is None else bad | st.locked
    return True if bad is None else ~bad
