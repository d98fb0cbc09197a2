"""GNU Octave and MATLAB statements from a traced tape: the parameter step and the state
step as one function body, a failed guard an ``error`` with its reason.

The language's own spellings: ``~=`` for ``!=``, ``^`` for a power, ``&&``/``||``,
``deg2rad``-free scaling (``x * (pi / 180)``, Python's ``math.radians``), and a choice
of two values (``select``, Python's ``max``/``min``) by a local function ``pick`` that
the file defines (:data:`PICK`).
"""

from __future__ import annotations

from .printer import INFIX, Printer, values
from .trace import SCALE, Tape, program

#: the local function a file with the statements must define
PICK = ["function r = pick(c, a, b)",
        "  % a where c holds, else b (Python's a if c else b)",
        "  if c", "    r = a;", "  else", "    r = b;", "  end", "end"]

_CALL = {"sqrt": "sqrt", "cos": "cos", "sin": "sin", "tan": "tan", "asin": "asin",
         "acos": "acos", "atan": "atan", "atan2": "atan2", "hypot": "hypot", "log": "log",
         "abs": "abs"}


def _literal(value: float) -> str:
    if value != value:
        return "NaN"
    if value in (float("inf"), float("-inf")):
        return "Inf" if value > 0 else "(-Inf)"
    text = repr(float(value))
    return f"({text})" if text.startswith("-") else text


class OctavePrinter(Printer):
    """Octave/MATLAB statements of a tape's operations (``t<i> = ...;``); a failed guard
    raises ``error('linkage_fmu:state', reason)``, its reason's text."""

    def __init__(self, tape: Tape, guards: dict, codes: dict, reasons: dict,
                 bodies: dict | None = None):
        super().__init__(tape, guards, codes, bodies)
        self.reasons = reasons

    literal = staticmethod(_literal)

    def expression(self, i, node, a):
        if node.op == "ne":
            return f"{a[0]} ~= {a[1]}"
        if node.op == "extern":
            raise NotImplementedError(f"{node.value}: no Octave spelling")
        return super().expression(i, node, a)

    def declare(self, i, node, expression, indent):
        return f"{indent}t{i} = {expression};"

    def guard(self, i, indent):
        text = self.reasons[i].replace("'", "''")
        test = f"~t{i}" if self.guards[i] else f"t{i}"
        return f"{indent}if {test}, error('linkage_fmu:state', '%s', '{text}'); end"

    def divide(self, i, node, a):
        return f"{a[0]} / {a[1]}"

    def power(self, a):
        return f"{a[0]} ^ {a[1]}"

    def select(self, a):
        return f"pick({a[0]}, {a[1]}, {a[2]})"

    def fails(self, a, holds):
        return f"double(({a[0]} ~= 0) || (logical({a[1]}) ~= {str(bool(holds)).lower()}))"

    def sign(self, a):
        return f"double({a[0]} > 0) - double({a[0]} < 0)"

    def extremum(self, op, a):
        return f"pick({a[1]} {'>' if op == 'max' else '<'} {a[0]}, {a[1]}, {a[0]})"

    def scaled(self, op, a):
        return f"{a[0]} * {_literal(SCALE[op])}"

    def call(self, op, a):
        return f"{_CALL[op]}({', '.join(a)})"

    def loop(self, L, indent):
        inner = indent + "  "
        carries = [f"t{c}" for c in L.carries]
        news = [self.operand(n) for n in L.news]
        k = f"k{L.index}"
        return [
            *(f"{indent}{c} = {self.operand(a)};" for c, a in zip(carries, L.inits)),
            f"{indent}t{L.converged} = false;",
            f"{indent}for {k} = 1:{L.maximum}",
            *self.statements(self.bodies[L.index], inner),
            f"{inner}[{', '.join(carries)}] = deal({', '.join(news)});",
            f"{inner}if {k} >= {L.minimum} && ~{self.operand(L.again)}",
            f"{inner}  t{L.converged} = true;",
            f"{inner}  break;",
            f"{inner}end",
            f"{indent}end",
            *(f"{indent}t{f} = t{c};" for f, c in zip(L.finals, L.carries)),
            *(self.guard(i, indent) for i in (*L.finals, L.converged) if i in self.guards),
        ]


def octave_statements(tape: Tape, results: list, indent: str = "  ") -> tuple:
    """The statements computing ``results`` (Syms of ``tape``, or floats) from the
    tape's inputs, named as they are, the parameter step's first, and the expression of
    each result.

    Examples
    --------
    >>> from linkage_fmu.kernels.trace import TRACE
    >>> tape = Tape()
    >>> x, L = tape.input("x", 4.0), tape.input("L", 2.0, parameter=True)
    >>> lines, out = octave_statements(tape, [TRACE.sqrt(x) * (L * 3.0)])
    >>> print(*lines, sep=chr(10)); out
      t4 = L * 3.0;
      t2 = sqrt(x);
      t5 = t2 * t4;
    ['t5']
    """
    prog = program(tape, results)
    reasons = {i: tape.reason(i).text for i in prog.guards}
    printer = OctavePrinter(tape, prog.guards, prog.codes, reasons, prog.bodies)
    lines = printer.statements(prog.prepare, indent) + printer.statements(prog.state, indent)
    return lines, values(tape, results, _literal)


__all__ = ["INFIX", "OctavePrinter", "PICK", "octave_statements"]
