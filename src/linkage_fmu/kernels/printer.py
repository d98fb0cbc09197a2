"""What the C and the Python source of a tape have in common: :class:`Printer`.

The walk over a list of the tape's operations (a loop's results are written by their
loop, a loop by :meth:`Printer.loop`), each operand as its source (an input's name, a
constant as the language writes it, or the variable ``t<i>`` of the operation that
computed it), the dispatch of an operation to its spelling, then the operation's guard.
A language is a subclass that spells each piece; one that misses a piece cannot be
made (:class:`abc.ABC`), so that no operation is printed by a default of the other
language.
"""

from __future__ import annotations

import abc

from .trace import SCALE, Node, Sym, Tape, operand

#: the operations written ``a <op> b`` in both languages (``pow`` is not: :meth:`power`)
INFIX = {"add": "+", "sub": "-", "mul": "*", "div": "/", "lt": "<", "le": "<=",
         "gt": ">", "ge": ">=", "eq": "==", "ne": "!="}


def values(tape: Tape, results: list, literal) -> list:
    """Each of the ``results`` (Syms of ``tape``, or floats) as the expression a kernel
    returns: a Sym as its operand (:func:`~linkage_fmu.kernels.trace.operand`), a float
    through ``literal``.

    Examples
    --------
    >>> tape = Tape()
    >>> x = tape.input("x0", 2.0)
    >>> values(tape, [x, x * 3.0, -1.5], repr)
    ['x0', 't2', '-1.5']
    """
    return [operand(tape, r.index, literal) if isinstance(r, Sym) else literal(float(r))
            for r in results]


class Printer(abc.ABC):
    """The statements of a tape's operations in one language.

    Parameters
    ----------
    tape : Tape
    guards : dict
        Operation -> whether the guard holds where its value is true
        (:attr:`Program.guards <linkage_fmu.kernels.trace.Program.guards>`).
    codes : dict
        Operation -> the code returned where its guard fails.
    bodies : dict, optional
        Loop node -> the operations of its body.

    Examples
    --------
    The pieces a language spells:

    >>> sorted(Printer.__abstractmethods__)  # doctest: +NORMALIZE_WHITESPACE
    ['call', 'declare', 'divide', 'extremum', 'fails', 'guard', 'literal', 'loop',
     'power', 'scaled', 'select', 'sign']
    >>> class Lisp(Printer):
    ...     def literal(value):
    ...         return repr(value)
    >>> Lisp(Tape(), {}, {})  # doctest: +IGNORE_EXCEPTION_DETAIL
    Traceback (most recent call last):
    TypeError: Can't instantiate abstract class Lisp with abstract methods call, ...
    """

    def __init__(self, tape: Tape, guards: dict, codes: dict, bodies: dict | None = None):
        self.tape, self.guards, self.codes, self.bodies = tape, guards, codes, bodies

    def operand(self, j: int) -> str:
        """Node ``j`` as an operand in this language."""
        return operand(self.tape, j, self.literal)

    def statements(self, nodes: list, indent: str) -> list:
        """The lines of the operations ``nodes``, each indented by ``indent``: a loop
        node is its loop, a loop's results are written by it, and each other operation
        is a declaration (:meth:`declare`), then its guard (:meth:`guard`) if it has
        one, then what follows it (:meth:`after`)."""
        lines = []
        for i in nodes:
            node = self.tape.nodes[i]
            if node.op in ("final", "converged"):  # written by their loop
                continue
            if node.op == "loop":
                lines += self.loop(self.tape.loops[i], indent)
                continue
            args = [self.operand(j) for j in node.args]
            lines.append(self.declare(i, node, self.expression(i, node, args), indent))
            if i in self.guards:
                lines.append(self.guard(i, indent))
            lines += self.after(i, indent)
        return lines

    def expression(self, i: int, node: Node, a: list) -> str:
        """Operation ``i`` (``node``) of the operands ``a`` as an expression."""
        op = node.op
        if op == "div":
            return self.divide(i, node, a)
        if op in INFIX:
            return f"{a[0]} {INFIX[op]} {a[1]}"
        if op == "neg":
            return f"-{a[0]}"
        if op == "pow":
            return self.power(a)
        if op == "extern":
            return f"{node.value}({', '.join(a)})"
        if op == "select":
            return self.select(a)
        if op == "fails":  # a check inside a loop: its failure, kept
            return self.fails(a, node.value)
        if op == "sign":
            return self.sign(a)
        if op in ("max", "min"):
            return self.extremum(op, a)
        if op in SCALE:
            return self.scaled(op, a)
        return self.call(op, a)

    def after(self, i: int, indent: str) -> list:
        """Lines that follow operation ``i`` and its guard: none."""
        return []

    @staticmethod
    @abc.abstractmethod
    def literal(value: float) -> str:
        """A constant, exact to the bit."""

    @abc.abstractmethod
    def declare(self, i: int, node: Node, expression: str, indent: str) -> str:
        """The statement giving operation ``i`` (``node``) the value ``expression``."""

    @abc.abstractmethod
    def guard(self, i: int, indent: str) -> str:
        """The statement that acts on the guard of operation ``i`` where it fails."""

    @abc.abstractmethod
    def loop(self, L, indent: str) -> list:
        """The lines of the loop ``L`` (:meth:`Tape.loop
        <linkage_fmu.kernels.trace.Tape.loop>`)."""

    @abc.abstractmethod
    def divide(self, i: int, node: Node, a: list) -> str:
        """``a[0] / a[1]``."""

    @abc.abstractmethod
    def power(self, a: list) -> str:
        """``a[0]`` to the power ``a[1]``."""

    @abc.abstractmethod
    def select(self, a: list) -> str:
        """``a[1]`` where the truth value ``a[0]`` holds, else ``a[2]``."""

    @abc.abstractmethod
    def fails(self, a: list, holds: bool) -> str:
        """1.0 where ``a[0]`` is nonzero (an earlier failure) or the truth of ``a[1]``
        is not ``holds``, else 0.0."""

    @abc.abstractmethod
    def sign(self, a: list) -> str:
        """The sign of ``a[0]`` (:func:`trace.sign <linkage_fmu.kernels.trace.sign>`)."""

    @abc.abstractmethod
    def extremum(self, op: str, a: list) -> str:
        """Python's ``max(a[0], a[1])`` (``op`` ``"max"``) or ``min``: ``a[1]`` only
        where it is greater (less)."""

    @abc.abstractmethod
    def scaled(self, op: str, a: list) -> str:
        """``a[0]`` converted by ``op`` (:data:`SCALE <linkage_fmu.kernels.trace.SCALE>`:
        radians, degrees)."""

    @abc.abstractmethod
    def call(self, op: str, a: list) -> str:
        """The elementary function ``op`` of ``a``."""
