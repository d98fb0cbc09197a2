"""Kernels: each linkage traced once into straight-line code, one kernel per plan.

A plan is what a scene asks for: which outputs, and whether it is static (``omega =
alpha = 0``, no derivative kinematics); the loads present are the linkage's. The kernel
of a plan is the trace (:mod:`~linkage_fmu.kernels.trace`) of the closed-form formulas
for exactly that plan, with the parameters folded in, as Python source
(:mod:`~linkage_fmu.kernels.python_source`). It is made on first use and kept by the
mechanism, so skipping work costs nothing at run time.

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

#: one-state calls of a plan after which it is compiled (parameters are folded into each
#: kernel, so compiling every plan on first use would compile every parameter set)
HOT_CALLS = 1000
#: crank angles tried as the witness state of a trace, until one assembles
WITNESS_ANGLES = (0.3, 1.1, 2.3, 4.0, 5.5, 0.0, 3.0)


@dataclass
class Kernel:
    """The compiled plan ``outputs`` (static or not) of one linkage.

    Calling it with ``(theta, omega, alpha, *loads)`` (finite floats) returns the outputs
    as a tuple, or None where a guard fails (the state cannot be assembled, is
    singular, or takes a branch the trace did not): the interpreted formulas then
    decide.
    """

    outputs: tuple
    static: bool
    source: str
    function: Callable = field(repr=False)
    operations: int = 0
    seconds: float = 0.0  # tracing and generation
    checked: tuple = ()  # positions of the outputs that must be finite (not diagnostics)
    index: dict = field(default_factory=dict)  # output name -> position in the tuple
    tape: Tape = field(default=None, repr=False)
    results: list = field(default_factory=list, repr=False)
    n_inputs: int = 0
    _array: object = field(default=False, repr=False)
    #: what a one-state solve calls: the Python kernel, or once compiled, the C one
    call: Callable = field(default=None, repr=False)
    calls: int = 0

    def __post_init__(self):
        if self.call is None:
            self.call = self.function

    def __call__(self, *inputs):
        return self.call(*inputs)

    def count(self) -> None:
        """Count a one-state call; the :data:`HOT_CALLS`-th compiles the plan."""
        self.calls += 1
        if self.calls == HOT_CALLS:
            self.compile()

    def compile(self) -> bool:
        """Make one-state calls use the compiled C kernel (built or loaded from the cache
        now); False, and the Python kernel stays, where there is no C compiler."""
        if self.call is self.function:
            source = c_source(self.tape, self.n_inputs, self.results, array=False)
            try:
                module = compiled.build_module(source, self.n_inputs, len(self.outputs))
            except compiled.CompilerError as err:  # keep the Python kernel, say why once
                compiled.warn_once(f"one-state kernels stay Python: {err}")
                module = None
            if module is not None:
                self.call = compiled.ScalarKernel(module, self.n_inputs, len(self.outputs))
        return self.call is not self.function

    def c_source(self) -> str:
        """The kernel as C (:mod:`~linkage_fmu.kernels.c_source`)."""
        return c_source(self.tape, self.n_inputs, self.results)

    def array(self):
        """The compiled array kernel (:class:`~linkage_fmu.kernels.compiled.ArrayKernel`),
        built or loaded from the cache on first use; None without a C compiler."""
        if self._array is False:
            path = compiled.build(self.c_source())
            self._array = (None if path is None else
                           compiled.ArrayKernel(path, "linkage", len(self.outputs)))
        return self._array


def trace_kernel(mech, outputs: tuple, static: bool) -> Kernel:
    """Trace the closed-form formulas of ``mech`` for the plan ``(outputs, static)``."""
    t0 = time.perf_counter()
    names = [f"x{i}" for i in range(len(mech.input_names))]
    loads = [1.1 + 0.1 * k for k in range(len(mech.loads))]
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
        out, _ = mech._compute(syms[0], syms[1], syms[2], syms[3:], TRACE, "closed_form",
                               outputs, static)
        results = [out[n] for n in outputs]
        source = python_source(tape, names, results)
        function = compile_source(source, label=f"kernel of {mech.name}")
        checked = tuple(i for i, n in enumerate(outputs) if n in mech.output_names)
        return Kernel(tuple(outputs), static, source, function,
                      len(program(tape, results)[0]), time.perf_counter() - t0, checked,
                      {name: i for i, name in enumerate(outputs)}, tape, results, len(names))
    raise ValueError(f"{mech.name} cannot be assembled at any of the witness angles "
                     f"{WITNESS_ANGLES}: {last}")


def finite(values) -> bool:
    """True when every value is finite (one sum: a finite sum of finite terms)."""
    return math.isfinite(sum(values)) or all(map(math.isfinite, values))
