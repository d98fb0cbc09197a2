"""Tracing: the package's own formulas run once on a recording number type.

A :class:`Sym` is a node of a :class:`Tape`: every arithmetic operation and elementary
function applied to it appends one node (an identical operation on the same operands is
stored once), and carries its value at a *witness* state, so that the formulas' own
comparisons (``if value < 0.0`` in an assembly check, ``if a > 0.0`` before a division)
can take the branch the witness takes. Each such comparison is recorded as a *guard*:
the kernel checks it at run time, and a state where a guard fails (it cannot be
assembled, it is singular, it takes another branch) is handed back to the interpreted
formulas, which raise the exact error or compute the exceptional case. No formula is
written twice: the tape is what the formulas did.

A linkage's real-valued parameters are inputs of the tape too (``parameter=True``): what
depends on them alone is the parameter step of the generated code (:func:`program`),
run once per parameter set, and its order comparisons (a length > 0) are its checks. An
(in)equality of parameters alone is a shortcut of the formulas (skip the terms of a zero
mass) and takes the general branch, so that one kernel serves every parameter value.

Examples
--------
>>> tape = Tape()
>>> x = tape.input("x", 0.5)
>>> y = TRACE.sqrt(x * x + 1.0)
>>> bool(y > 1.0)   # the witness branch, recorded as a guard (1.0: the constant stored once)
True
>>> [node.op for node in tape.nodes]
['input', 'mul', 'const', 'add', 'sqrt', 'gt']
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace


@dataclass(frozen=True)
class Node:
    """One operation: ``op`` on the node indices ``args`` (a constant's value, an
    input's name in ``value``)."""

    op: str
    args: tuple = ()
    value: object = None


@dataclass(frozen=True)
class Reason:
    """Why a guard fails: ``kind`` is ``'assembly'`` (the state cannot be assembled),
    ``'singular'`` (the reactions are unbounded), ``'locking'`` (friction locks the
    linkage: no finite balancing effort), ``'parameter'`` (a check of the
    parameter step) or ``'branch'`` (the state takes a branch the trace did not), and
    ``what`` says which condition, without numbers.

    Examples
    --------
    >>> Reason("assembly", "the dyad B-C-D cannot close").text
    'the linkage cannot be assembled: the dyad B-C-D cannot close'
    """

    kind: str
    what: str = ""

    @property
    def text(self) -> str:
        """The reason as the FMUs log it, the same words in every flavour."""
        head = {"assembly": "the linkage cannot be assembled",
                "singular": "the linkage is at a singular position",
                "parameter": "the parameter set is invalid",
                "branch": "the state takes another branch than the kernel was traced on",
                "locking": "friction locks the linkage",
                "overflow": "the outputs overflow float64"}[self.kind]
        return f"{head}: {self.what}" if self.what else head


#: the reason of a guard nobody labelled, by the step it is in
UNLABELLED = {True: Reason("parameter", "a value computed from the parameters is out of range"),
              False: Reason("branch")}


class Tape:
    """The recorded operations, in order, with identical ones stored once."""

    def __init__(self):
        self.nodes: list[Node] = []
        self.witness: list[float] = []
        self.guards: list[tuple[int, bool]] = []  # (comparison node, outcome seen)
        self.labels: dict[int, Reason] = {}  # comparison node -> why it fails
        #: name -> an outside function a node calls (see :meth:`extern`)
        self.externs: dict = {}
        self.fixed: set = set()  # nodes of the parameters and constants alone
        self._index: dict = {}
        self._last = None  # the newest guard's node, None after an unrecorded comparison

    def _add(self, node: Node, witness: float, fixed: bool = False) -> "Sym":
        key = (node.op, node.args, _key(node.value))
        i = self._index.get(key)
        if i is None:
            i = self._index[key] = len(self.nodes)
            self.nodes.append(node)
            self.witness.append(witness)
            if fixed or (node.args and all(a in self.fixed for a in node.args)):
                self.fixed.add(i)
        return Sym(self, i)

    def input(self, name: str, witness: float, parameter: bool = False) -> "Sym":
        """An argument of the kernel (of its parameter step, with ``parameter``), with
        its witness value."""
        return self._add(Node("input", (), name), float(witness), parameter)

    def const(self, value: float) -> "Sym":
        return self._add(Node("const", (), float(value)), float(value), True)

    def apply(self, op: str, fn, *operands) -> "Sym":
        syms = [o if isinstance(o, Sym) else self.const(o) for o in operands]
        witness = fn(*(self.witness[s.index] for s in syms))
        return self._add(Node(op, tuple(s.index for s in syms)), witness)

    def extern(self, function, *operands) -> "Sym":
        """Record a call of ``function``, a function of floats the package defines (a
        table's spline), with a C identifier ``function.name`` and its C definition
        ``function.c_definition()`` for the generated code."""
        name = function.name
        if self.externs.setdefault(name, function) is not function:
            raise ValueError(f"two functions named {name!r} in one trace")
        syms = [o if isinstance(o, Sym) else self.const(o) for o in operands]
        witness = function(*(self.witness[s.index] for s in syms))
        return self._add(Node("extern", tuple(s.index for s in syms), name), witness)

    def guard(self, op: str, fn, a, b) -> bool:
        """Record the comparison ``a op b`` and return its outcome at the witness.

        An (in)equality of parameters alone is a shortcut of the formulas (``if
        body.mass:`` skips the terms of a zero mass): it takes the general branch
        (``!=`` true, ``==`` false) and is not recorded, so that one kernel serves every
        value of the parameters. An order comparison of parameters (``length > 0``) is
        a check of the parameter step."""
        node = self.apply(op, fn, a, b)
        if op in ("eq", "ne") and node.index in self.fixed:
            self._last = None
            return op == "ne"
        outcome = bool(self.witness[node.index])
        self.guards.append((node.index, outcome))
        self._last = node.index
        return outcome

    def label(self, reason: Reason) -> None:
        """Say why the comparison just recorded fails, unless it was said before (a
        guard recorded twice keeps its first reason)."""
        if self._last is not None:
            self.labels.setdefault(self._last, reason)

    def reason(self, index: int) -> Reason:
        """Why the guard at node ``index`` fails."""
        return self.labels.get(index) or UNLABELLED[index in self.fixed]


@dataclass
class Program:
    """What code generated from a tape computes, in the tape's order.

    ``prepare`` (once per parameter set): the live operations on the parameters alone,
    then its checks; ``frozen``: the values of the parameter step the state step reads;
    ``state`` (once per state): the other live operations; ``guards``: comparison node
    -> the outcome the witness took, for both steps, in the order they were recorded; a
    failed guard is reported by its code, its position in ``guards`` counted from 1.
    """

    prepare: list
    frozen: list
    state: list
    guards: dict

    @property
    def codes(self) -> dict:
        """Comparison node -> the code a failed guard returns (1, 2, ...)."""
        return {index: code for code, index in enumerate(self.guards, 1)}


def program(tape: Tape, results: list) -> Program:
    """The :class:`Program` of ``results`` (Syms or floats): the live nodes (the
    results', the guards' and what they depend on), split into the work on the
    parameters alone and the work per state."""
    todo = [r.index for r in results if isinstance(r, Sym)] + [g for g, _ in tape.guards]
    live = set()
    while todo:
        i = todo.pop()
        if i not in live:
            live.add(i)
            todo.extend(tape.nodes[i].args)
    guards = {}
    for index, outcome in tape.guards:
        guards.setdefault(index, outcome)
    fixed = tape.fixed
    order = sorted(live)
    state = [i for i in order if i not in fixed and tape.nodes[i].op != "input"]
    read = {a for i in state for a in tape.nodes[i].args}
    read.update(r.index for r in results if isinstance(r, Sym))
    frozen = [i for i in order if i in fixed and i in read and tape.nodes[i].op != "const"]
    prepare = [i for i in order if i in fixed and tape.nodes[i].op not in ("input", "const")]
    return Program(prepare, frozen, state, guards)


def operand(tape: Tape, i: int, literal) -> str:
    """Node ``i`` as an operand: an input's name, a constant through ``literal``, or
    the variable ``t<i>``."""
    node = tape.nodes[i]
    if node.op == "input":
        return node.value
    if node.op == "const":
        return literal(node.value)
    return f"t{i}"


def _key(value):
    # -0.0 and 0.0 are different constants; so are NaNs of one bit pattern only
    return (value, math.copysign(1.0, value)) if isinstance(value, float) else value


def _binary(op: str, fn, reverse: bool = False):
    if reverse:
        return lambda self, other: self.tape.apply(op, fn, other, self)
    return lambda self, other: self.tape.apply(op, fn, self, other)


def _compare(op: str, fn):
    return lambda self, other: self.tape.guard(op, fn, self, other)


class Sym:
    """A traced number: an index into its :class:`Tape`."""

    __slots__ = ("tape", "index")
    __array_priority__ = 1000  # numpy scalars defer to Sym's reflected operators

    def __init__(self, tape: Tape, index: int):
        self.tape, self.index = tape, index

    __add__ = _binary("add", lambda a, b: a + b)
    __radd__ = _binary("add", lambda a, b: a + b, reverse=True)
    __sub__ = _binary("sub", lambda a, b: a - b)
    __rsub__ = _binary("sub", lambda a, b: a - b, reverse=True)
    __mul__ = _binary("mul", lambda a, b: a * b)
    __rmul__ = _binary("mul", lambda a, b: a * b, reverse=True)
    __truediv__ = _binary("div", lambda a, b: a / b)
    __rtruediv__ = _binary("div", lambda a, b: a / b, reverse=True)
    __pow__ = _binary("pow", lambda a, b: a ** b)
    __rpow__ = _binary("pow", lambda a, b: a ** b, reverse=True)
    __lt__ = _compare("lt", lambda a, b: a < b)
    __le__ = _compare("le", lambda a, b: a <= b)
    __gt__ = _compare("gt", lambda a, b: a > b)
    __ge__ = _compare("ge", lambda a, b: a >= b)
    __eq__ = _compare("eq", lambda a, b: a == b)
    __ne__ = _compare("ne", lambda a, b: a != b)
    __hash__ = None

    def __neg__(self):
        return self.tape.apply("neg", lambda a: -a, self)

    def __pos__(self):
        return self

    def __abs__(self):
        return self.tape.apply("abs", abs, self)

    def __bool__(self):
        return self.tape.guard("ne", lambda a, b: a != b, self, 0.0)

    def traced(self, name: str, fn, *args) -> "Sym":
        """Record ``fn(*args)`` (a :mod:`math` function or ``min``/``max``) as ``name``."""
        if len(args) > 2:  # min/max of several: pairwise, as the builtins compare
            first = self.traced(name, fn, *args[:2])
            return first.traced(name, fn, first, *args[2:])
        return self.tape.apply(name, fn, *args)

    def __float__(self):
        # a formula that needs a plain float of a traced value (only error messages do,
        # and they are not traced: the guard before them hands the state back)
        raise TypeError("a traced value has no float value")


def _unary(op: str, fn):
    def apply(x):
        if isinstance(x, Sym):
            return x.tape.apply(op, fn, x)
        return fn(x)
    return apply


def sign(x: float) -> float:
    """-1.0, 0.0 or 1.0 as ``x`` is negative, zero or positive (0.0 for NaN): two
    comparisons, no branch, and a derivative of 0 in the kernels' tangent (where ``x``
    is exactly 0 too, where ``x / |x|`` would divide by 0)."""
    return float(x > 0.0) - float(x < 0.0)


def _atan2(y, x):
    tape = y.tape if isinstance(y, Sym) else x.tape if isinstance(x, Sym) else None
    if tape is None:
        return math.atan2(y, x)
    return tape.apply("atan2", math.atan2, y, x)


def _maximum(a, b):
    tape = a.tape if isinstance(a, Sym) else b.tape if isinstance(b, Sym) else None
    if tape is None:
        return max(a, b)
    return tape.apply("max", max, a, b)


def nan_where(z):
    """NaN where ``z`` is 1, 0 where it is 0 (``z`` one or the other), without a branch
    or a division (the kernels' Python raises on ``0 / 0``): ``z * 1e300 * 1e300``
    overflows to inf or stays 0, and ``inf - inf`` is NaN."""
    t = z * 1e300 * 1e300
    return t - t


#: evaluation mode of the formulas on traced numbers (see :mod:`linkage_fmu.numerics`)
TRACE = SimpleNamespace(scalar=True, sqrt=_unary("sqrt", math.sqrt), cos=_unary("cos", math.cos),
                        sin=_unary("sin", math.sin), atan2=_atan2, abs=_unary("abs", abs),
                        maximum=_maximum, sign=_unary("sign", sign), nan_where=nan_where)
