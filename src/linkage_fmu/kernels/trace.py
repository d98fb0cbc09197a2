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

An iteration is a loop of the tape (:meth:`Tape.loop`): its body is recorded once, on
nodes that stand for the values it carries, and the generated code runs it until it
converges. Inside a body no formula may branch on what the carried values decide: its
decisions are operations (sign, abs, max, min, :meth:`Tape.select`) and its checks
(:meth:`Tape.check`) fail the state when the loop ends.

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
from collections.abc import Callable
from dataclasses import dataclass, field
from types import SimpleNamespace

from ..errors import InputError, InputTypeError, LinkageFmuError, Reason


@dataclass(frozen=True)
class Node:
    """One operation: ``op`` on the node indices ``args`` (a constant's value, an
    input's name in ``value``)."""

    op: str
    args: tuple = ()
    value: object = None


class TracingError(LinkageFmuError, RuntimeError):
    """The formulas did what a kernel cannot record: a branch on a value computed inside
    a loop's body, or a value of a loop's body read outside it. A fault of the formulas,
    not of a state or a parameter (no ValueError, which the solver takes for a state that
    cannot be traced)."""


#: the operations of a loop (:meth:`Tape.loop`): a loop-carried value inside its body,
#: the loop itself (its arguments: the carried values' initial values), a carried
#: value's last value, and whether the loop converged
LOOP_OPS = ("carry", "loop", "final", "converged")
#: the comparisons: their results are truth values (piecewise constant, no derivative)
COMPARE = frozenset({"lt", "le", "gt", "ge", "eq", "ne"})
#: CPython's math.radians and math.degrees: one multiplication by these
SCALE = {"radians": math.pi / 180.0, "degrees": 180.0 / math.pi}


@dataclass(eq=False)
class Loop:
    """A bounded iteration recorded on a tape (see :meth:`Tape.loop`): the nodes of its
    ``carries`` start at ``inits`` and take ``news`` after each run of the body (the
    nodes of this scope, ``nodes``, in order); it stops once it ran ``minimum`` times
    and ``again`` is false, or after ``maximum`` runs. ``index``: its loop node;
    ``finals``, ``converged``: the nodes of its results."""

    serial: int
    parent: "Loop | None"
    minimum: int
    maximum: int
    depth: int = 1
    carries: list = field(default_factory=list)
    inits: list = field(default_factory=list)
    news: list = field(default_factory=list)
    again: int = -1
    nodes: list = field(default_factory=list)
    index: int = -1
    finals: list = field(default_factory=list)
    converged: int = -1
    #: checks inside the body, kept as failure flags the loop carries
    pending: list = field(default_factory=list)


def _select(condition, a, b):
    return a if condition else b


def _fails(outcome: bool):
    return lambda before, value: 1.0 if (before or bool(value) != outcome) else 0.0


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
        self.scopes: list = []  # per node: the Loop whose body it is in, None outside
        self.functions: list = []  # per node: the function of floats it computes
        self.loops: dict = {}  # loop node -> its Loop
        self._open: list = []  # the loops whose bodies are being recorded, outermost first
        self._serial = 0

    def _visible(self, scope) -> bool:
        return scope is None or scope in self._open

    def record(self, node: Node, witness: float, fixed: bool = False, fn=None,
               scope: object = False) -> "Sym":
        """The Sym of ``node``: the one already on the tape (the same operation of the
        same operands), or ``node`` appended with its ``witness`` value, the function
        ``fn`` that computes it, in ``scope`` (the loop whose body it is in; by default
        its operands' innermost), ``fixed`` (computed from the parameters alone) if so
        or if its operands all are."""
        # a * b and b * a stay two nodes: where both are NaNs of two signs, x86 gives
        # the first's
        key = (node.op, node.args, _key(node.value))
        i = self._index.get(key)
        if i is not None:
            if not self._visible(self.scopes[i]):
                raise TracingError(f"a value computed inside a loop's body is read outside "
                                   f"it (operation {node.op})")
            return Sym(self, i)
        if scope is False:  # the innermost loop any operand is in
            scope = None
            for a in node.args:
                inner = self.scopes[a]
                if not self._visible(inner):
                    raise TracingError("a value computed inside a loop's body is read "
                                       f"outside it (by the operation {node.op})")
                if inner is not None and (scope is None or inner.depth > scope.depth):
                    scope = inner
        i = self._index[key] = len(self.nodes)
        self.nodes.append(node)
        self.witness.append(witness)
        self.scopes.append(scope)
        self.functions.append(fn)
        if scope is not None:
            scope.nodes.append(i)
        if node.op not in LOOP_OPS and \
                (fixed or (node.args and all(a in self.fixed for a in node.args))):
            self.fixed.add(i)
        return Sym(self, i)

    def _sym(self, value) -> "Sym":
        return value if isinstance(value, Sym) else self.const(value)

    def input(self, name: str, witness: float, parameter: bool = False) -> "Sym":
        """An argument of the kernel (of its parameter step, with ``parameter``), with
        its witness value."""
        return self.record(Node("input", (), name), float(witness), parameter)

    def const(self, value: float) -> "Sym":
        return self.record(Node("const", (), float(value)), float(value), True)

    def apply(self, op: str, fn, *operands) -> "Sym":
        syms = [o if isinstance(o, Sym) else self.const(o) for o in operands]
        same = self._identity(op, [s.index for s in syms])
        if same is not None:
            return Sym(self, same)
        witness = fn(*(self.witness[s.index] for s in syms))
        return self.record(Node(op, tuple(s.index for s in syms)), witness, fn=fn)

    def _constant(self, i: int, value: float) -> bool:
        """Whether node ``i`` is the constant ``value``, its zero's sign too."""
        node = self.nodes[i]
        return node.op == "const" and _key(node.value) == _key(value)

    def _identity(self, op: str, args: list) -> int | None:
        """The operand an operation gives back bit for bit, whatever its value, or None:
        ``x * 1.0``, ``1.0 * x``, ``x / 1.0``, ``x - 0.0``, ``x + -0.0``, ``-0.0 + x``,
        ``-(-x)`` (IEEE arithmetic: exact, the sign of a zero, inf and NaN kept; a
        compiler may not drop them under strict IEEE, so the tape does). Not ``x + 0.0``,
        whose ``-0.0 + 0.0`` is ``0.0`` (the sign of a zero is the branch of an
        ``atan2``), nor ``0.0 * x`` (NaN where ``x`` is inf or NaN), nor ``0.0 - x``
        (``0.0`` where ``x`` is ``0.0``, not ``-0.0``)."""
        if op == "mul":
            if self._constant(args[1], 1.0):
                return args[0]
            if self._constant(args[0], 1.0):
                return args[1]
        elif op == "div":
            if self._constant(args[1], 1.0):
                return args[0]
        elif op == "sub":
            if self._constant(args[1], 0.0):
                return args[0]
        elif op == "add":
            if self._constant(args[1], -0.0):
                return args[0]
            if self._constant(args[0], -0.0):
                return args[1]
        elif op == "neg":
            inner = self.nodes[args[0]]
            if inner.op == "neg":
                return inner.args[0]
        return None

    def compare(self, op: str, a, b) -> "Sym":
        """The comparison ``a op b`` (``op`` one of lt, le, gt, ge, eq, ne) as a value
        (true or false at run time), not a branch: what a loop's body decides with
        (:meth:`loop`), or what :meth:`check` checks."""
        return self.apply(op, _COMPARISONS[op], a, b)

    def extern(self, function, *operands) -> "Sym":
        """Record a call of ``function``, a function of floats the package defines (a
        table's spline), with a C identifier ``function.name`` and its C definition
        ``function.c_definition()`` for the generated code."""
        name = function.name
        if self.externs.setdefault(name, function) is not function:
            raise InputError(f"two functions named {name!r} in one trace")
        syms = [o if isinstance(o, Sym) else self.const(o) for o in operands]
        witness = function(*(self.witness[s.index] for s in syms))
        return self.record(Node("extern", tuple(s.index for s in syms), name), witness,
                         fn=function)

    def guard(self, op: str, fn, a, b) -> bool:
        """Record the comparison ``a op b`` and return its outcome at the witness.

        An (in)equality of parameters alone is a shortcut of the formulas (``if
        body.mass:`` skips the terms of a zero mass): it takes the general branch
        (``!=`` true, ``==`` false) and is not recorded, so that one kernel serves every
        value of the parameters. An order comparison of parameters (``length > 0``) is
        a check of the parameter step."""
        node = self.apply(op, fn, a, b)
        if self.scopes[node.index] is not None:
            raise TracingError(
                f"a formula branches ({op}) on a value computed inside a loop's body: a "
                "decision inside a loop must be an operation (sign, abs, max, min) or a "
                "comparison of Tape.compare")
        if op in ("eq", "ne") and node.index in self.fixed:
            self._last = None
            return op == "ne"
        outcome = bool(self.witness[node.index])
        self.guards.append((node.index, outcome))
        self._last = node.index
        return outcome

    def select(self, condition, a, b) -> "Sym":
        """``a`` where ``condition`` (a value: a :meth:`compare`, or a number, true where
        it is not 0) holds, else ``b``: a decision taken at run time, not a branch."""
        return self.apply("select", _select, condition, a, b)

    def check(self, value: "Sym", outcome: bool, reason: Reason) -> bool:
        """Require ``value`` (a comparison, or a failure flag) to be ``outcome`` at run
        time, failing with ``reason``: a guard, or inside a loop's body (``value`` depends
        on its carried values), a flag the loop carries and checks when it ends (a state
        fails if the check failed in any run of the body). Returns whether the witness
        passes it (True inside a body)."""
        value = self._sym(value)
        scope = self.scopes[value.index]
        if scope is not None:
            scope.pending.append((value.index, bool(outcome), reason))
            return True
        self.guards.append((value.index, bool(outcome)))
        self.labels.setdefault(value.index, reason)
        return bool(self.witness[value.index]) == bool(outcome)

    def loop(self, init: list, body: Callable, minimum: int, maximum: int) -> tuple:
        """A bounded iteration: ``body(carried)`` (a list of traced values) returns the
        next carried values and ``again`` (a :meth:`compare`), optionally a third item,
        values of the run to hand out of the loop (its last run's, after the carried
        ones in what the loop returns), and runs at least
        ``minimum`` times, then until ``again`` is false, at most ``maximum`` times, from
        the carried values ``init``. The body is recorded once, on nodes that stand for
        the carried values; what it computes from values outside alone is computed
        before the loop. Inside it, no formula may branch on what depends on the carried
        values (:class:`TracingError`); :meth:`check` s there fail the state when the
        loop ends. Returns the last carried values and whether ``again`` ended the loop
        (a value, for :meth:`check`); their witnesses are the iteration's on the
        witness state.

        Examples
        --------
        >>> tape = Tape()
        >>> a = tape.input("a", 2.0)
        >>> def newton(c):
        ...     x = c[0]
        ...     y = 0.5 * (x + a / x)
        ...     return [y], tape.compare("ne", y, x)
        >>> (root,), converged = tape.loop([a], newton, 1, 20)
        >>> tape.witness[root.index], bool(tape.witness[converged.index])
        (1.414213562373095, True)
        """
        if not 0 <= minimum <= maximum or maximum < 1:
            raise InputError(f"a loop runs between minimum and maximum times, "
                             f"0 <= {minimum} <= {maximum}, at least once")
        inits = [self._sym(v) for v in init]
        for s in inits:
            if not self._visible(self.scopes[s.index]):
                raise TracingError("a loop starts from a value computed inside another "
                                   "loop's body, outside it")
        parent = self._open[-1] if self._open else None
        self._serial += 1
        L = Loop(self._serial, parent, int(minimum), int(maximum),
                 1 if parent is None else parent.depth + 1)
        self._open.append(L)
        try:
            carries = [self.record(Node("carry", (), (L.serial, k)), self.witness[s.index],
                                 scope=L) for k, s in enumerate(inits)]
            new, again, *last = body(list(carries))
            new = [self._sym(v) for v in new]
            if len(new) != len(carries):
                raise TracingError(f"a loop's body returns {len(new)} values for "
                                   f"{len(carries)} carried ones")
            again = self._sym(again)
            for value in (last[0] if last else ()):  # carried out, not read by the body
                carries.append(self.record(Node("carry", (), (L.serial, len(carries))), 0.0,
                                         scope=L))
                inits.append(self.const(0.0))
                new.append(self._sym(value))
            flags = []
            for value, outcome, reason in L.pending:  # checks of the body: failure flags
                k = len(carries)
                flag = self.record(Node("carry", (), (L.serial, k)), 0.0, scope=L)
                carries.append(flag)
                inits.append(self.const(0.0))
                fn = _fails(outcome)
                new.append(self.record(Node("fails", (flag.index, value), outcome),
                                     fn(0.0, self.witness[value]), fn=fn))
                flags.append(reason)
        finally:
            self._open.pop()
        L.carries = [s.index for s in carries]
        L.inits = [s.index for s in inits]
        L.news = [s.index for s in new]
        L.again = again.index
        loop = self.record(Node("loop", tuple(L.inits), L.serial), 0.0, scope=parent)
        L.index = loop.index
        self.loops[L.index] = L
        env = {}
        values, converged = self._run(L, env)
        finals = [self.record(Node("final", (L.index,), k), v, scope=parent)
                  for k, v in enumerate(values)]
        flag = self.record(Node("converged", (L.index,)), bool(converged), scope=parent)
        L.finals, L.converged = [s.index for s in finals], flag.index
        n = len(finals) - len(flags)
        for final, reason in zip(finals[n:], flags):
            self.check(final, False, reason)
        return finals[:n], flag

    def _run(self, L: Loop, env: dict) -> tuple:
        """The loop's iterations on the witness values (``env``: values of the nodes of
        the loops being run, by node), as the generated code runs them."""
        witness = self.witness

        def value(i):
            return env[i] if i in env else witness[i]

        values = [value(i) for i in L.inits]
        for k in range(L.maximum):
            env.update(zip(L.carries, values))
            for i in L.nodes:
                node = self.nodes[i]
                if node.op == "loop":
                    inner = self.loops[i]
                    finals, converged = self._run(inner, env)
                    env.update(zip(inner.finals, finals))
                    env[inner.converged] = converged
                elif node.op not in LOOP_OPS:
                    try:
                        env[i] = self.functions[i](*(value(a) for a in node.args))
                    except (ArithmeticError, ValueError):  # C gives inf or NaN there
                        env[i] = math.nan
            values = [value(i) for i in L.news]
            if k + 1 >= L.minimum and not value(L.again):
                return values, True
        return values, False

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
    ``state`` (once per state): the other live operations outside loops (a loop node
    stands for its whole loop); ``bodies``: loop node -> the live operations of its
    body, in order (carried values excluded); ``guards``: comparison node -> the outcome
    the witness took, for both steps, in the order they were recorded; a failed guard is
    reported by its code, its position in ``guards`` counted from 1.
    """

    prepare: list
    frozen: list
    state: list
    guards: dict
    bodies: dict = field(default_factory=dict)

    @property
    def codes(self) -> dict:
        """Comparison node -> the code a failed guard returns (1, 2, ...)."""
        return {index: code for code, index in enumerate(self.guards, 1)}

    @property
    def operations(self) -> int:
        """The operations of the state step as written (a loop's body once)."""
        return len(self.state) + sum(len(b) for b in self.bodies.values())


def program(tape: Tape, results: list) -> Program:
    """The :class:`Program` of ``results`` (Syms or floats): the live nodes (the
    results', the guards' and what they depend on), split into the work on the
    parameters alone and the work per state, the loops' bodies apart."""
    live = live_nodes(tape, results)
    guards = {}
    for index, outcome in tape.guards:
        guards.setdefault(index, outcome)
    fixed = tape.fixed
    order = sorted(live)
    state, bodies = [], {}
    for i in order:
        op, scope = tape.nodes[i].op, tape.scopes[i]
        if i in fixed or op in ("input", "carry"):
            continue
        if scope is None:
            state.append(i)
        else:
            bodies.setdefault(scope.index, []).append(i)
    for L in tape.loops.values():
        if L.index in live:
            bodies.setdefault(L.index, [])
    read = {a for i in state for a in tape.nodes[i].args}
    for index, body in bodies.items():
        L = tape.loops[index]
        read.update(a for i in body for a in tape.nodes[i].args)
        read.update([*L.news, L.again])
    read.update(r.index for r in results if isinstance(r, Sym))
    frozen = [i for i in order if i in fixed and i in read and tape.nodes[i].op != "const"]
    prepare = [i for i in order if i in fixed and tape.nodes[i].op not in ("input", "const")]
    return Program(prepare, frozen, state, guards, bodies)


def live_nodes(tape: Tape, results: list) -> set:
    """The nodes code generated from ``tape`` computes for ``results`` (Syms or
    floats): the results', the guards' and what they depend on (a loop's body, its
    carried values and its test included)."""
    todo = [r.index for r in results if isinstance(r, Sym)] + [g for g, _ in tape.guards]
    live = set()
    while todo:
        i = todo.pop()
        if i not in live:
            live.add(i)
            todo.extend(tape.nodes[i].args)
            if tape.nodes[i].op == "loop":
                L = tape.loops[i]
                todo.extend([*L.news, L.again, *L.carries])
    return live


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


_COMPARISONS = {"lt": lambda a, b: a < b, "le": lambda a, b: a <= b,
                "gt": lambda a, b: a > b, "ge": lambda a, b: a >= b,
                "eq": lambda a, b: a == b, "ne": lambda a, b: a != b}


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
        raise InputTypeError("a traced value has no float value")


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
