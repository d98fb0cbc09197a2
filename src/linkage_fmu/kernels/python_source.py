"""Python source from a traced tape: the kernel that always works.

One assignment per live operation (a loop's body once, inside a ``for``), in the order
the formulas did them (so the results are bit-identical to the interpreted formulas on
floats), and an early return of the
guard's code (:attr:`Program.codes <linkage_fmu.kernels.trace.Program.codes>`) where a
guard does not hold. The work on the parameters alone is a separate function, run once
per parameter set; its values are closed over by the kernel of a state. The walk over
the tape is the C source's too (:class:`~linkage_fmu.kernels.printer.Printer`): this
module spells it in Python (:class:`PythonPrinter`).
"""

from __future__ import annotations

import math

from .printer import Printer, values
from .trace import Tape, operand, program, sign

_FUNCTIONS = ("sqrt", "cos", "sin", "tan", "asin", "acos", "atan", "atan2", "hypot",
              "radians", "degrees", "log")
_CALL = {**{f: f for f in _FUNCTIONS}, "abs": "abs", "max": "max", "min": "min",
         "sign": "sign"}
#: what the generated source calls: the very functions of the scalar formulas
def quotient(a: float, b: float) -> float:
    """``a / b`` as IEEE arithmetic (C) has it where ``b`` is zero: ``inf`` of the sign of
    the operands' product, or NaN for ``0 / 0`` and ``NaN / 0`` (Python raises).

    Examples
    --------
    >>> quotient(1.0, -0.0), quotient(0.0, 0.0), quotient(3.0, 2.0)
    (-inf, nan, 1.5)
    """
    if b:
        return a / b
    if a != a or a == 0.0:
        return math.nan
    return math.copysign(math.inf, a) * math.copysign(1.0, b)


NAMESPACE = {**{f: getattr(math, f) for f in _FUNCTIONS}, "inf": math.inf, "nan": math.nan,
             "sign": sign, "quotient": quotient}


def _literal(value: float) -> str:
    text = repr(value)
    return f"({text})" if text.startswith("-") else text


class PythonPrinter(Printer):
    """Python statements of a tape's operations: ``t<i> = ...``, a failed guard
    returns its code, a loop is a ``for`` over its runs; with ``ieee``, a division by
    anything but a nonzero constant gives IEEE arithmetic's inf or NaN where the divisor
    is zero (:func:`quotient`)."""

    def __init__(self, tape: Tape, guards: dict, codes: dict, bodies: dict | None = None,
                 ieee: bool = False):
        super().__init__(tape, guards, codes, bodies)
        self.ieee = ieee

    literal = staticmethod(_literal)

    def declare(self, i, node, expression, indent):
        return f"{indent}t{i} = {expression}"

    def guard(self, i, indent):
        return f"{indent}if {'not ' if self.guards[i] else ''}t{i}: return {self.codes[i]}"

    def divide(self, i, node, a):
        divisor = self.tape.nodes[node.args[1]]
        if self.ieee and not (divisor.op == "const" and divisor.value):
            return f"{a[0]} / {a[1]} if {a[1]} else quotient({a[0]}, {a[1]})"
        return f"{a[0]} / {a[1]}"

    def power(self, a):
        return f"{a[0]} ** {a[1]}"

    def select(self, a):
        return f"{a[1]} if {a[0]} else {a[2]}"

    def fails(self, a, holds):
        return f"1.0 if ({a[0]} or bool({a[1]}) != {holds}) else 0.0"

    def sign(self, a):
        return self.call("sign", a)

    def extremum(self, op, a):
        return self.call(op, a)

    def scaled(self, op, a):  # math.radians and math.degrees: the formulas' own
        return self.call(op, a)

    def call(self, op, a):
        return f"{_CALL[op]}({', '.join(a)})"

    def loop(self, L, indent):
        """A loop (:meth:`Tape.loop <linkage_fmu.kernels.trace.Tape.loop>`): its carried
        values, then ``for`` over its runs, the test after ``minimum`` of them."""
        inner = indent + "    "
        carries = [f"t{c}" for c in L.carries]
        news = [self.operand(n) for n in L.news]
        return [
            f"{indent}{_tuple(carries)} = {_tuple([self.operand(a) for a in L.inits])}",
            f"{indent}t{L.converged} = False",
            f"{indent}for _k{L.index} in range({L.maximum}):",
            *self.statements(self.bodies[L.index], inner),
            f"{inner}{_tuple(carries)} = {_tuple(news)}",
            f"{inner}if _k{L.index} >= {L.minimum - 1} and not {self.operand(L.again)}:",
            f"{inner}    t{L.converged} = True",
            f"{inner}    break",
            *(f"{indent}t{f} = t{c}" for f, c in zip(L.finals, L.carries)),
            *(f"{indent}{self.guard(i, '')}"
              for i in (*L.finals, L.converged) if i in self.guards),
        ]


def _tuple(items: list) -> str:
    return f"({', '.join(items)}{',' if len(items) == 1 else ''})"


def python_source(tape: Tape, arguments: list[str], results: list,
                  parameters: tuple = (), ieee: bool = False) -> str:
    """Two functions: ``prepare(*parameters)``, the parameter step, returning the tuple
    of values the state step reads (or the code of the check of the parameters that
    fails, an int), and ``make(*those values)``, returning ``kernel(*arguments)``, which
    returns the tuple of ``results`` or the code of the guard that fails. With
    ``ieee``, a division by zero gives IEEE arithmetic's inf or NaN (:func:`quotient`)
    instead of raising.

    Examples
    --------
    >>> from linkage_fmu.kernels.trace import TRACE
    >>> tape = Tape()
    >>> x, L = tape.input("x", 4.0), tape.input("p0", 2.0, parameter=True)
    >>> if x < 0.0:
    ...     pass
    >>> print(python_source(tape, ["x"], [TRACE.sqrt(x) * (L * 3.0)], ("p0",)), end="")
    def prepare(p0):
        t6 = p0 * 3.0
        return (t6,)
    def make(t6):
        def kernel(x):
            t3 = x < 0.0
            if t3: return 1
            t4 = sqrt(x)
            t7 = t4 * t6
            return (t7,)
        return kernel
    """
    prog = program(tape, results)
    codes = prog.codes
    frozen = [operand(tape, i, _literal) for i in prog.frozen]
    outputs = values(tape, results, _literal)
    return "\n".join([
        f"def prepare({', '.join(parameters)}):",
        *PythonPrinter(tape, prog.guards, codes, ieee=ieee).statements(prog.prepare, "    "),
        f"    return {_tuple(frozen)}",
        f"def make({', '.join(frozen)}):",
        f"    def kernel({', '.join(arguments)}):",
        *PythonPrinter(tape, prog.guards, codes, prog.bodies, ieee).statements(prog.state,
                                                                               "        "),
        f"        return {_tuple(outputs)}",
        "    return kernel",
        "",
    ])


class RaisingPrinter(PythonPrinter):
    """A :class:`PythonPrinter` whose failed guard raises ``ValueError`` with its
    reason (a function file for a user's own use, not a kernel)."""

    def __init__(self, tape: Tape, guards: dict, codes: dict, reasons: dict,
                 bodies: dict | None = None):
        super().__init__(tape, guards, codes, bodies)
        self.reasons = reasons

    def guard(self, i, indent):
        test = f"{'not ' if self.guards[i] else ''}t{i}"
        return f"{indent}if {test}: raise ValueError({self.reasons[i]!r})"


def python_statements(tape: Tape, results: list, indent: str = "    ") -> tuple:
    """The statements computing ``results`` (Syms of ``tape``, or floats) from the
    tape's inputs, named as they are, the parameter step's first, a failed guard a
    ``ValueError`` with its reason; and the expression of each result.

    Examples
    --------
    >>> from linkage_fmu.kernels.trace import TRACE
    >>> tape = Tape()
    >>> x, L = tape.input("x", 4.0), tape.input("L", 2.0, parameter=True)
    >>> lines, out = python_statements(tape, [TRACE.sqrt(x) * (L * 3.0)])
    >>> print(*lines, sep=chr(10)); out
        t4 = L * 3.0
        t2 = sqrt(x)
        t5 = t2 * t4
    ['t5']
    """
    prog = program(tape, results)
    reasons = {i: tape.reason(i).text for i in prog.guards}
    printer = RaisingPrinter(tape, prog.guards, prog.codes, reasons, prog.bodies)
    lines = printer.statements(prog.prepare, indent) + printer.statements(prog.state, indent)
    return lines, values(tape, results, _literal)


def compile_source(source: str, label: str = "kernel", externs: dict | None = None):
    """The functions ``prepare`` and ``make`` defined by the generated ``source`` (our
    own code, never a file's), which calls the functions ``externs`` (name -> function)
    besides :data:`NAMESPACE`."""
    namespace = {**NAMESPACE, **(externs or {})}
    exec(compile(source, f"<linkage_fmu {label}>", "exec"), namespace)
    return namespace["prepare"], namespace["make"]
