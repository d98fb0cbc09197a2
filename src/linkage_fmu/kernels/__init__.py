"""Kernels: each linkage traced once into straight-line code, one kernel per plan.

A plan is what a scene asks for: which outputs, and whether it is static (``omega =
alpha = 0``, no derivative kinematics); the loads present are the linkage's. The kernel
of a plan is the trace (:mod:`~linkage_fmu.kernels.trace`) of the closed-form formulas
for exactly that plan, as Python source (:mod:`~linkage_fmu.kernels.python_source`) and
C (:mod:`~linkage_fmu.kernels.c_source`, compiled by :mod:`~linkage_fmu.kernels.compiled`).
The real-valued parameters are arguments of a parameter step, run once per parameter
set; the work per state reads its values. A kernel is made on first use and kept by
the mechanism, so skipping work costs nothing at run time.

Examples
--------
>>> from linkage_fmu import presets
>>> mech = presets.get("four_bar")
>>> k = mech.kernel(("Mb", "F21x"))
>>> k.operations > 0, k(0.3, 10.0, 0.0, 0.0) == (mech.solve(0.3, 10.0, method="interpreted")["Mb"],
...                                               mech.solve(0.3, 10.0, method="interpreted")["F21x"])
(True, True)
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Callable

from ..numerics import SCALAR
from . import compiled
from .c_source import c_source
from .python_source import compile_source, python_source
from .trace import TRACE, Tape, program

#: one-state calls of a plan after which it is compiled (the first compilation of a
#: linkage's plan costs a fraction of a second; later ones, and other parameter sets of
#: the same linkage, load it from the cache)
HOT_CALLS = 1000
#: crank angles tried as the witness state of a trace, until one assembles
WITNESS_ANGLES = (0.3, 1.1, 2.3, 4.0, 5.5, 0.0, 3.0)


@dataclass
class Kernel:
    """The kernel of the plan ``outputs`` (static or not) of one linkage.

    Calling it with ``(theta, omega, alpha, *loads)`` (finite floats) returns the outputs
    as a tuple, or None where a guard fails (the state cannot be assembled, is
    singular, or takes a branch the trace did not): the interpreted formulas then
    decide. The linkage's real-valued parameters are arguments of the generated code
    (:attr:`parameters`), not constants in it: :attr:`frozen` holds what its parameter
    step computed from this linkage's values, and the same source serves every
    parameter set that passes the parameter step's checks.
    """

    outputs: tuple
    static: bool
    source: str
    prepare: Callable = field(repr=False)
    make: Callable = field(repr=False)
    frozen: tuple = ()
    parameters: tuple = ()  # parameter names, in the order of the parameter step's arguments
    operations: int = 0  # per state
    seconds: float = 0.0  # tracing and generation
    checked: tuple = ()  # positions of the outputs that must be finite (not diagnostics)
    index: dict = field(default_factory=dict)  # output name -> position in the tuple
    tape: Tape = field(default=None, repr=False)
    results: list = field(default_factory=list, repr=False)
    n_inputs: int = 0
    _array: object = field(default=False, repr=False)
    #: the Python kernel of a state, with :attr:`frozen` bound
    function: Callable = field(default=None, repr=False)
    #: what a one-state solve calls: the Python kernel, or once compiled, the C one
    call: Callable = field(default=None, repr=False)
    calls: int = 0

    def __post_init__(self):
        if self.function is None:
            self.function = self.make(*self.frozen)
        if self.call is None:
            self.call = self.function

    def __call__(self, *inputs):
        return self.call(*inputs)

    def count(self) -> None:
        """Count a one-state call; the :data:`HOT_CALLS`-th compiles the plan."""
        self.calls += 1
        if self.calls == HOT_CALLS:
            self.compile()

    @property
    def compiled(self) -> bool:
        """Whether one-state calls go to the compiled kernel, which takes any inputs
        and returns None unless they are finite floats and every checked output is
        finite."""
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
        return self.call is not self.function

    def c_source(self, array: bool = True, prefix: str = "linkage") -> str:
        """The kernel as C (:mod:`~linkage_fmu.kernels.c_source`), its functions named
        ``<prefix>_...``."""
        return c_source(self.tape, self.n_inputs, self.results,
                        tuple(f"p{k}" for k in range(len(self.parameters))), prefix, array)

    def array(self):
        """The compiled array kernel (:class:`~linkage_fmu.kernels.compiled.ArrayKernel`),
        built or loaded from the cache on first use; None without a C compiler."""
        if self._array is False:
            path = compiled.build(self.c_source())
            self._array = (None if path is None else compiled.ArrayKernel(
                path, "linkage", len(self.outputs), self.frozen))
        return self._array


def trace_kernel(mech, outputs: tuple, static: bool) -> Kernel:
    """Trace the closed-form formulas of ``mech`` for the plan ``(outputs, static)``.

    A linkage built from a description is traced with its real-valued parameters as
    inputs (built again from the description on traced numbers); one built in Python
    has them folded in as constants.
    """
    from ..spec.build import build

    t0 = time.perf_counter()
    names = [f"x{i}" for i in range(len(mech.input_names))]
    loads = [1.1 + 0.1 * k for k in range(len(mech.loads))]
    parameters = kernel_parameters(mech)
    last = None
    omega, alpha = (0.0, 0.0) if static else (1.3, 0.7)
    for theta in WITNESS_ANGLES:
        try:  # a witness must be solvable: the trace follows what the floats do there
            mech._compute(theta, omega, alpha, loads, SCALAR, "closed_form", outputs, static)
        except (ValueError, ZeroDivisionError) as err:
            last = err
            continue
        tape = Tape()
        syms = [tape.input(n, v) for n, v in zip(names, (theta, omega, alpha, *loads))]
        symbols = {name: tape.input(f"p{k}", mech.parameters[name], parameter=True)
                   for k, name in enumerate(parameters)}
        twin = build(mech.description, mech.parameters, symbols) if parameters else mech
        out, _ = twin._compute(syms[0], syms[1], syms[2], syms[3:], TRACE, "closed_form",
                               outputs, static)
        results = [out[n] for n in outputs]
        args = tuple(f"p{k}" for k in range(len(parameters)))
        source = python_source(tape, names, results, args)
        prepare, make = compile_source(source, label=f"kernel of {mech.name}")
        frozen = prepare(*(mech.parameters[name] for name in parameters))
        if frozen is None:
            raise RuntimeError(f"{mech.name}: the parameter step rejects the parameters it "
                               "was traced with")
        checked = tuple(i for i, n in enumerate(outputs) if n in mech.output_names)
        return Kernel(tuple(outputs), static, source, prepare, make, frozen, parameters,
                      len(program(tape, results).state), time.perf_counter() - t0,
                      checked, {name: i for i, name in enumerate(outputs)}, tape, results,
                      len(names))
    raise ValueError(f"{mech.name} cannot be assembled at any of the witness angles "
                     f"{WITNESS_ANGLES}: {last}")


def kernel_parameters(mech) -> tuple:
    """The parameters a kernel of ``mech`` takes as arguments: the real-valued ones of a
    linkage built from a description (a branch or a choice is structure)."""
    if mech.description is None:
        return ()
    return tuple(name for name, v in mech.parameters.items() if type(v) is float)


def finite(values) -> bool:
    """True when every value is finite (one sum: a finite sum of finite terms)."""
    return math.isfinite(sum(values)) or all(map(math.isfinite, values))
