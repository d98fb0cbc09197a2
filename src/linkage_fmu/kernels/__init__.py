"""Kernels: formulas traced once into straight-line code and bounded loops, one kernel per
plan.

:func:`trace` runs a function of traced numbers (:mod:`~linkage_fmu.kernels.trace`)
once and turns what it did into Python source
(:mod:`~linkage_fmu.kernels.python_source`) and C (:mod:`~linkage_fmu.kernels.c_source`,
compiled by :mod:`~linkage_fmu.kernels.compiled`). The real-valued parameters are
arguments of a parameter step, run once per parameter set; the work per state reads its
values. This package knows nothing of linkages: the solver (:mod:`linkage_fmu.solver`)
says what to trace, and keeps the kernels.

Examples
--------
>>> k = trace(lambda x, p: [x[0] * p["a"] + 1.0], [2.0], {"a": 3.0}, ("y",), (0,))
>>> k(2.0), k.frozen
((7.0,), (3.0,))
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

from ..errors import ComputationError, InputError
from . import compiled
from .c_source import SUMMARY_HEAD, c_source
from .python_source import compile_source, python_source
from .tangent import TangentFunction, python_tangent, tangent_tape
from .trace import TRACE, Reason, Tape, program

__all__ = ["Kernel", "Reason", "TRACE", "trace"]


@dataclass
class Kernel:
    """The kernel of one plan: the traced function of ``n_inputs`` inputs and the
    parameters :attr:`parameters`.

    Calling it with the inputs (finite floats) returns the outputs as a tuple, or None
    where a guard fails (the state cannot be assembled, is singular, or takes a branch
    the trace did not). :attr:`call` is what the solver calls: the Python kernel, or once
    :meth:`compile` d, the C one; it returns the tuple, or the code of the failed guard
    (:attr:`reasons` says why), and the C one also None for inputs that are not finite
    floats and 0 for an output in :attr:`checked` that is not finite. The parameters are
    arguments of the generated code, not constants in it: :attr:`frozen` holds what its
    parameter step computed from the values it was traced with, and the same source
    serves every parameter set that passes the parameter step's checks.
    """

    outputs: tuple
    static: bool
    source: str
    make_prepare: Callable = field(repr=False)
    make: Callable = field(repr=False)
    frozen: tuple = ()
    parameters: tuple = ()  # parameter names, in the order of the parameter step's arguments
    operations: int = 0  # per state
    seconds: float = 0.0  # tracing and generation
    checked: tuple = ()  # positions of the outputs that must be finite (not eta)
    index: dict = field(default_factory=dict)  # output name -> position in the tuple
    #: code - 1 -> why that guard fails (the parameter step's checks and the state's)
    reasons: tuple = ()
    tape: Tape = field(default=None, repr=False)
    results: list = field(default_factory=list, repr=False)
    n_inputs: int = 0
    _array: object = field(default=False, repr=False)
    _summary_kernels: dict = field(default_factory=dict, repr=False)
    #: the Python kernel of a state, with :attr:`frozen` bound
    function: Callable = field(default=None, repr=False)
    #: what a one-state solve calls: the Python kernel, or once compiled, the C one
    call: Callable = field(default=None, repr=False)
    calls: int = 0  # one-state calls counted by the solver (which decides when to compile)
    _module: object = field(default=None, repr=False)  # the compiled one-state extension
    _python_tangent: object = field(default=None, repr=False)

    def __post_init__(self):
        if self.function is None:
            self.function = self.make(*self.frozen)
        if self.call is None:
            self.call = self.function

    def __call__(self, *inputs):
        r = self.call(*inputs)
        return r if type(r) is tuple else None

    def prepare(self, *parameters) -> tuple | None:
        """The parameter step's values for another parameter set (in the order of
        :attr:`parameters`), or None where one of its checks fails
        (:meth:`parameter_problem` says which)."""
        q = self.make_prepare(*parameters)
        return q if type(q) is tuple else None

    def parameter_problem(self, *parameters) -> str | None:
        """Why the parameter step refuses ``parameters``, or None if it takes them."""
        q = self.make_prepare(*parameters)
        return None if type(q) is tuple else self.reasons[q - 1].text

    @property
    def compiled(self) -> bool:
        """Whether one-state calls go to the compiled kernel."""
        return self.call is not self.function

    def compile(self) -> bool:
        """Make one-state calls use the compiled C kernel (built or loaded from the cache
        now); False, and the Python kernel stays, where there is no C compiler."""
        if self.call is self.function:
            try:
                module = compiled.build_module(self.c_source(array=False))
            except compiled.CompilerError as err:  # keep the Python kernel, say why once
                compiled.warn_once(f"one-state kernels stay Python: {err}")
                module = None
            if module is not None:
                self.call = compiled.scalar_kernel(module, self.frozen, self.checked)
                self._module = module
        return self.call is not self.function

    def instances(self, cls: type, slots: tuple, values: tuple) -> Callable | None:
        """The compiled one-state kernel (once :meth:`compile` d; None before) returning
        where it takes the state, instead of the outputs' tuple, an instance of ``cls``
        made without its ``__init__``: its slot ``slots[0]`` holds the outputs (the same
        floats, unboxed: a read-only sequence, see :func:`.compiled.scalar_kernel`),
        each following slot its value in ``values`` (saves building the caller's result
        in Python and boxing every output: a scalar solve's lean path). Elsewhere it
        returns what :attr:`call` does."""
        if self._module is None:
            return None
        return compiled.scalar_kernel(self._module, self.frozen, self.checked,
                                      (cls, slots, values))

    def c_source(self, array: bool = True, prefix: str = "linkage",
                 tangent: bool = False, settle: bool = False,
                 vary: int | None = None) -> str:
        """The kernel as C (:mod:`~linkage_fmu.kernels.c_source`), its functions named
        ``<prefix>_...``; with ``tangent``, its forward-mode derivatives too; with
        ``settle``, its loops stop as soon as they converge; with ``vary``, the state
        step in two too, the work that does not depend on input ``vary`` apart."""
        return c_source(self.tape, self.n_inputs, self.results,
                        tuple(f"p{k}" for k in range(len(self.parameters))), prefix, array,
                        tangent, settle=settle, vary=vary)

    def tangent(self):
        """The compiled forward-mode kernel
        (:class:`~linkage_fmu.kernels.compiled.TangentKernel`): ``tangent(x, dx)`` gives
        the outputs and their derivatives along the direction ``dx`` of the inputs, exact
        through the traced operations (what the native FMUs' directional derivatives
        compute); built or loaded from the cache; None without a C compiler.

        Examples
        --------
        >>> k = trace(lambda x, p: [x[0] * x[1] * p["a"]], [2.0, 5.0], {"a": 3.0}, ("y",))
        >>> y, dy = k.tangent()([2.0, 5.0], [1.0, 0.0])   # d(3 x0 x1)/dx0 = 3 x1
        >>> float(y[0]), float(dy[0])
        (30.0, 15.0)
        """
        path = compiled.build(self.c_source(array=False, tangent=True))
        return None if path is None else compiled.TangentKernel(
            path, "linkage", self.n_inputs, len(self.outputs), self.frozen)

    def python_tangent(self) -> TangentFunction:
        """The forward-mode kernel as Python
        (:class:`~linkage_fmu.kernels.tangent.TangentFunction`), which needs no C
        compiler: the tape's derivatives (:func:`~linkage_fmu.kernels.tangent.tangent_tape`)
        run from :attr:`frozen`, the same floats as :meth:`tangent`'s where both take
        the state; made on first use and kept.

        Examples
        --------
        >>> k = trace(lambda x, p: [x[0] * x[1] * p["a"]], [2.0, 5.0], {"a": 3.0}, ("y",))
        >>> k.python_tangent()([2.0, 5.0], [1.0, 0.0])   # d(3 x0 x1)/dx0 = 3 x1
        ((30.0,), (15.0,))
        """
        if self._python_tangent is None:
            self._python_tangent = python_tangent(tangent_tape(self.tape, self.results),
                                                  self.frozen)
        return self._python_tangent

    def summary(self, reductions: Sequence[tuple[str, tuple[str, ...]]]):
        """The compiled reductions over states
        (:class:`~linkage_fmu.kernels.compiled.SummaryKernel`) of the outputs named in
        ``reductions``, each ``(kind, names)`` with a kind of
        :data:`~linkage_fmu.kernels.c_source.SUMMARY_KINDS`: the C computes only the
        outputs they read (and every guard); built or loaded from the cache on first
        use; None without a C compiler. A row holds
        :data:`~linkage_fmu.kernels.c_source.SUMMARY_HEAD` (the parameter step's code,
        the states whose guards fail and the first of them, then those of them that
        friction locks, by the :attr:`reasons` of the guards they fail, and the first
        of them), then one value per reduction.

        Examples
        --------
        >>> import numpy as np
        >>> k = trace(lambda x, p: [x[0] * p["a"], x[0] - 1.0], [1.0], {"a": 3.0},
        ...           ("y", "z"))
        >>> s = k.summary([("peak", ("y",)), ("mean", ("z",))])
        >>> s([[3.0], [-2.0]], [np.array([1.0, 2.0, 4.0])], 3).tolist()  # SUMMARY_HEAD first
        ... # doctest: +NORMALIZE_WHITESPACE
        [[0.0, 0.0, -1.0, 0.0, -1.0, 12.0, 1.3333333333333333],
         [0.0, 0.0, -1.0, 0.0, -1.0, 8.0, 1.3333333333333333]]
        """
        key = tuple((kind, tuple(names)) for kind, names in reductions)
        if key not in self._summary_kernels:
            for _, names in key:
                for name in names:
                    if name not in self.index:
                        raise InputError(f"the kernel has no output {name!r}; its outputs "
                                         "are: " + ", ".join(self.outputs))
            used = list(dict.fromkeys(name for _, names in key for name in names))
            results = [self.results[self.index[name]] for name in used]
            spec = [(kind, tuple(used.index(name) for name in names)) for kind, names in key]
            source = c_source(self.tape, self.n_inputs, results,
                              tuple(f"p{k}" for k in range(len(self.parameters))), "linkage",
                              True, False, spec)
            path = compiled.build(source)
            self._summary_kernels[key] = None if path is None else compiled.SummaryKernel(
                path, "linkage", len(self.parameters), len(SUMMARY_HEAD) + len(key))
        return self._summary_kernels[key]

    def array(self):
        """The compiled array kernel (:class:`~linkage_fmu.kernels.compiled.ArrayKernel`),
        built or loaded from the cache on first use; None without a C compiler."""
        if self._array is False:
            path = compiled.build(self.c_source())
            self._array = (None if path is None else compiled.ArrayKernel(
                path, "linkage", len(self.outputs), self.frozen))
        return self._array


def trace(evaluate: Callable[[list, dict], list], inputs: Sequence[float],
          parameters: Mapping[str, float], outputs: tuple, checked: tuple = (),
          static: bool = False, label: str = "kernel") -> Kernel:
    """Trace ``evaluate(inputs, parameters)`` at the witness ``inputs`` into a kernel.

    Parameters
    ----------
    evaluate : callable
        Takes a list of traced inputs and a dict of traced parameters (name -> traced
        number) and returns the results (traced numbers or floats), one per name in
        ``outputs``. Its comparisons take the branch the witness values take, recorded
        as guards.
    inputs : sequence of float
        The witness state: it must be one ``evaluate`` solves on floats.
    parameters : mapping
        Parameter name -> value: the arguments of the parameter step, in this order.
    outputs : tuple of str
        Names of the results.
    checked : tuple of int
        Positions of the results that must be finite.
    static : bool
        Recorded on the kernel (a plan without derivative kinematics).
    label : str
        Names the kernel in tracebacks.

    Raises
    ------
    RuntimeError
        The parameter step refuses the values it was traced with.
    """
    t0 = time.perf_counter()
    tape = Tape()
    names = [f"x{i}" for i in range(len(inputs))]
    syms = [tape.input(n, v) for n, v in zip(names, inputs)]
    symbols = {name: tape.input(f"p{k}", value, parameter=True)
               for k, (name, value) in enumerate(parameters.items())}
    results = list(evaluate(syms, symbols))
    args = tuple(f"p{k}" for k in range(len(parameters)))
    source = python_source(tape, names, results, args)
    make_prepare, make = compile_source(source, label=label, externs=tape.externs)
    prog = program(tape, results)
    reasons = tuple(tape.reason(index) for index in prog.guards)
    frozen = make_prepare(*parameters.values())
    if type(frozen) is not tuple:
        raise ComputationError(f"{label}: the parameter step rejects the parameters it was traced "
                               f"with: {reasons[frozen - 1].text}")
    return Kernel(tuple(outputs), static, source, make_prepare, make, frozen,
                  tuple(parameters), prog.operations, time.perf_counter() - t0, tuple(checked),
                  {name: i for i, name in enumerate(outputs)}, reasons, tape, results,
                  len(names))
