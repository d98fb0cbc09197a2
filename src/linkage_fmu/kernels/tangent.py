"""Forward mode as a transform of the tape: a tape that computes the derivatives too.

:func:`tangent_tape` replays a traced :class:`~linkage_fmu.kernels.trace.Tape` into a
new one in which each operation a result needs is followed by the operations of its
derivative along a direction ``dx`` of the inputs: the rules of calculus, written
operation for operation as the C kernels' forward mode writes them
(:mod:`~linkage_fmu.kernels.c_source`), so that any printer of a tape gives a kernel of
the derivatives, the Python one included, and its floats are the compiled tangent's
(the C is built with ``-ffp-contract=off``: the same operations in the same order give
the same floats). Derivatives known to be zero are left out, as the C leaves them out
(``0 * inf`` would be NaN, and a sum with a zero term can turn ``-0.0`` into ``0.0``).
A loop carries the derivatives of its carried values with them.

The parameters are not inputs of the derivatives' tape: the values the original
kernel's parameter step hands its state step (:attr:`Program.frozen
<linkage_fmu.kernels.trace.Program>`) are, as inputs ``q0, q1, ...``, so that the
derivatives' kernel runs from the original kernel's frozen values, whatever the
parameter set, and the parameter step's checks (passed by then) are not repeated.

Examples
--------
>>> from linkage_fmu.kernels.trace import TRACE, Tape
>>> tape = Tape()
>>> x = tape.input("x0", 3.0)
>>> k = tape.input("p0", 2.0, parameter=True)
>>> forward = tangent_tape(tape, [k * TRACE.sin(x)])
>>> forward.inputs, forward.parameters   # q0: the frozen value of the parameter p0
(('x0', 'dx0'), ('q0',))
>>> f = python_tangent(forward, (2.0,))
>>> y, dy = f([3.0], [1.0])        # d(2 sin x)/dx = 2 cos x
>>> dy == (2.0 * math.cos(3.0),)
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import InputError
from .trace import COMPARE, LOOP_OPS, SCALE, Loop, Node, Sym, Tape, live_nodes, program


def needed(tape: Tape, results: list) -> set:
    """The nodes whose derivatives the derivatives of ``results`` need: what they depend
    on, not through a comparison, a sign, a loop's convergence or a check's failure
    (piecewise constant), nor through a selection's condition; a loop's carried value
    through its initial and its new value.

    Examples
    --------
    >>> from linkage_fmu.kernels.trace import Tape
    >>> tape = Tape()
    >>> x, y = tape.input("x0", 1.0), tape.input("x1", 2.0)
    >>> z = tape.select(tape.compare("lt", x, y), x * x, y)
    >>> sorted(tape.nodes[i].op for i in needed(tape, [z]))
    ['input', 'input', 'mul', 'select']
    """
    carrier = {c: (L, k) for L in tape.loops.values() for k, c in enumerate(L.carries)}
    out: set = set()
    todo = [r.index for r in results if isinstance(r, Sym)]
    while todo:
        i = todo.pop()
        if i in out:
            continue
        out.add(i)
        node = tape.nodes[i]
        if node.op in ("sign", "converged", "fails") or node.op in COMPARE:
            continue  # piecewise constant: no derivative
        if node.op == "final":
            todo.append(tape.loops[node.args[0]].carries[node.value])
        elif node.op == "carry":
            L, k = carrier[i]
            todo += [L.inits[k], L.news[k]]
        elif node.op == "select":  # not through its condition
            todo.extend(node.args[1:])
        elif node.op != "loop":
            todo.extend(node.args)
    return out


@dataclass
class TangentTape:
    """A tape of the results and their derivatives (:func:`tangent_tape`).

    ``tape`` computes, from the inputs ``inputs`` (the original state inputs
    ``x0, x1, ...``, then their directions ``dx0, dx1, ...``) and the parameters
    ``parameters`` (``q0, q1, ...``: the original kernel's frozen values, in order),
    the original ``results`` (Syms of ``tape``, or floats) and their ``derivatives``
    (Syms of ``tape``, or 0.0 where a derivative is zero). ``codes``: the
    code of each of its guards (by position, from 1) in the original kernel's codes.
    Its witnesses are NaN but for the state inputs' (the new tape is printed, not
    traced on).
    """

    tape: Tape
    inputs: tuple
    parameters: tuple
    results: list
    derivatives: list
    codes: tuple = ()
    #: original node -> its node in ``tape`` (the nodes replayed)
    mapping: dict = field(default_factory=dict, repr=False)


class _DerivativeOf:
    """The derivative of an outside function (:meth:`Tape.extern
    <linkage_fmu.kernels.trace.Tape.extern>`) as an outside function of its own: named
    ``<name>_d``, calling the function's ``derivative`` (in C, its ``c_derivative``)."""

    def __init__(self, function):
        self.function = function
        self.name = f"{function.name}_d"

    def __call__(self, *args):
        return self.function.derivative(*args)

    def c_definition(self) -> str:
        return self.function.c_derivative()


def tangent_tape(tape: Tape, results: list) -> TangentTape:
    """The tape of ``results`` (of ``tape``, Syms or floats) and of their derivatives
    along the direction ``dx`` of the state inputs (``x0, x1, ...``; the parameters'
    direction is zero), forward mode written as the compiled kernels' (see the module's
    text); only the derivatives the results' need are computed.

    Parameters
    ----------
    tape : Tape
        A traced tape (:func:`linkage_fmu.kernels.trace`): its state inputs are named
        ``x0, x1, ...`` and its parameters ``p0, p1, ...``.
    results : list
        The results of the kernel (Syms of ``tape``, or floats).

    Returns
    -------
    TangentTape
        The new tape, its inputs and parameters, and the results and derivatives on it.

    Raises
    ------
    ValueError
        An operation without a derivative rule (an outside function of more than one
        argument, or one without a ``derivative``).

    Examples
    --------
    >>> from linkage_fmu.kernels.trace import TRACE, Tape
    >>> tape = Tape()
    >>> x, y = tape.input("x0", 0.5), tape.input("x1", 2.0)
    >>> t = tangent_tape(tape, [x * y + TRACE.sin(x)])
    >>> t.inputs
    ('x0', 'x1', 'dx0', 'dx1')
    >>> [t.tape.nodes[s.index].op for s in (*t.results, *t.derivatives)]   # d: a sum
    ['add', 'add']
    """
    prog = program(tape, results)
    live = live_nodes(tape, results)
    frozen = {i: k for k, i in enumerate(prog.frozen)}
    need = needed(tape, results)
    new = Tape()
    new.externs = dict(tape.externs)
    m: dict = {}  # original node -> new node
    d: dict = {}  # original node -> its derivative's new node (absent: zero)
    loops: dict = {}  # original Loop -> new Loop
    dcarry: dict = {}  # new carry -> the new carry of its derivative

    def chain(scope) -> list:
        out = []
        while scope is not None:
            out.append(loops[scope])
            scope = scope.parent
        return out[::-1]

    def add(op: str, *args, value=None, scope: object = False) -> int:
        node = Node(op, tuple(args), value)
        return new.record(node, math.nan, fn=None, scope=scope).index

    def const(value: float) -> int:
        return new.const(value).index

    for i, node in enumerate(tape.nodes):
        op, scope = node.op, tape.scopes[i]
        if i not in live and op != "input":
            continue
        if i in tape.fixed:
            if op == "const":
                m[i] = const(node.value)
            elif i in frozen:  # the original's frozen value: an input of the new tape
                m[i] = new.input(f"q{frozen[i]}", math.nan, parameter=True).index
            continue  # the parameter step's own work: done by the original kernel
        if op == "carry" and scope not in loops:  # the loop's first: the loop begins
            parent = loops[scope.parent] if scope.parent is not None else None
            loops[scope] = Loop(scope.serial, parent, scope.minimum, scope.maximum,
                                scope.depth)
        new._open = chain(scope)
        where = loops[scope] if scope is not None else None
        if op == "input":
            m[i] = new.input(node.value, tape.witness[i]).index
            if i in need:
                d[i] = new.input(f"d{node.value}", math.nan).index
            continue
        if op == "carry":
            NL = where
            m[i] = add("carry", value=(NL.serial, len(NL.carries)), scope=NL)
            NL.carries.append(m[i])
            if i in need:
                d[i] = add("carry", value=(NL.serial, len(NL.carries)), scope=NL)
                NL.carries.append(d[i])
                dcarry[m[i]] = d[i]
            continue
        if op == "loop":
            L = tape.loops[i]
            NL = loops[L]
            new._open = chain(L.parent)
            inits, news = {}, {}
            for c, a, n in zip(L.carries, L.inits, L.news):
                inits[m[c]], news[m[c]] = m[a], m[n]
                if m[c] in dcarry:
                    dc = dcarry[m[c]]
                    inits[dc] = d.get(a, None)
                    news[dc] = d.get(n, None)
            for c in NL.carries:
                for table in (inits, news):
                    if table[c] is None:
                        table[c] = const(0.0)
            NL.inits = [inits[c] for c in NL.carries]
            NL.news = [news[c] for c in NL.carries]
            NL.again = m[L.again]
            NL.index = m[i] = add("loop", *NL.inits, value=NL.serial, scope=where)
            NL.finals = [None] * len(NL.carries)
            new.loops[NL.index] = NL
            new._serial = max(new._serial, NL.serial)
            continue
        if op == "final":
            L = tape.loops[node.args[0]]
            NL = loops[L]
            c = m[L.carries[node.value]]
            k = NL.carries.index(c)
            m[i] = add("final", NL.index, value=k, scope=where)
            NL.finals[k] = m[i]
            if c in dcarry:
                k = NL.carries.index(dcarry[c])
                d[i] = NL.finals[k] = add("final", NL.index, value=k, scope=where)
            continue
        if op == "converged":
            NL = loops[tape.loops[node.args[0]]]
            m[i] = NL.converged = add("converged", NL.index, scope=where)
            continue
        m[i] = add(op, *(m[a] for a in node.args), value=node.value, scope=where)
        if op == "extern":
            new.functions[m[i]] = tape.functions[i]
        if i in need and op not in COMPARE and op not in ("fails", "sign"):
            e = _derivative(new, op, node, m[i], [m[a] for a in node.args],
                            [d.get(a) for a in node.args])
            if e is not None:
                d[i] = e
    new._open = []
    codes = prog.codes
    for g, outcome in tape.guards:
        if g not in tape.fixed:
            new.guards.append((m[g], outcome))
    for g, reason in tape.labels.items():
        if g in m and g not in tape.fixed:
            new.labels[m[g]] = reason
    order = list(dict.fromkeys(g for g, _ in tape.guards if g not in tape.fixed))
    names = tuple(tape.nodes[i].value for i in range(len(tape.nodes))
                  if tape.nodes[i].op == "input" and i not in tape.fixed)
    out = [Sym(new, m[r.index]) if isinstance(r, Sym) else r for r in results]
    derivatives = [Sym(new, d[r.index]) if isinstance(r, Sym) and r.index in d else 0.0
                   for r in results]
    return TangentTape(new, (*names, *(f"d{n}" for n in names)),
                       tuple(f"q{k}" for k in range(len(prog.frozen))), out, derivatives,
                       tuple(codes[g] for g in order), m)


def _derivative(tape: Tape, op: str, node: Node, t: int, a: list, da: list) -> int | None:
    """The derivative of the operation ``op`` (its node ``t`` of ``tape``, on the
    operands ``a``) from its operands' derivatives ``da`` (None where zero), as new
    nodes of ``tape``: the C kernels' expressions (``c_source._derivative``), operation
    for operation; None where it is zero."""
    def mul(x, y):
        return add("mul", x, y)

    def add(o, *args, value=None):
        return tape.record(Node(o, tuple(args), value), math.nan).index

    def const(value):
        return tape.const(value).index

    def times(x, y):
        return None if x is None or y is None else mul(x, y)

    def plus(x, y, minus=False):
        if y is None:
            return x
        if x is None:
            return add("neg", y) if minus else y
        return add("sub" if minus else "add", x, y)

    if op == "add":
        return plus(da[0], da[1])
    if op == "sub":
        return plus(da[0], da[1], minus=True)
    if op == "mul":
        return plus(times(da[0], a[1]), times(a[0], da[1]))
    if op == "div":
        if da[0] is None and da[1] is None:
            return None
        return add("div", plus(da[0], times(t, da[1]), minus=True), a[1])
    if op == "neg":
        return None if da[0] is None else add("neg", da[0])
    if op == "sqrt":
        return None if da[0] is None else add("div", da[0], mul(const(2.0), t))
    if op == "sin":
        return times(add("cos", a[0]), da[0])
    if op == "cos":
        return None if da[0] is None else mul(add("neg", add("sin", a[0])), da[0])
    if op == "tan":
        return times(add("add", const(1.0), mul(t, t)), da[0])
    if op in ("asin", "acos"):
        if da[0] is None:
            return None
        root = add("sqrt", add("sub", const(1.0), mul(a[0], a[0])))
        return add("div", add("neg", da[0]) if op == "acos" else da[0], root)
    if op == "atan":
        return None if da[0] is None else add("div", da[0],
                                              add("add", const(1.0), mul(a[0], a[0])))
    if op == "atan2":  # atan2(y, x)
        num = plus(times(a[1], da[0]), times(a[0], da[1]), minus=True)
        return None if num is None else add("div", num, add("add", mul(a[1], a[1]),
                                                             mul(a[0], a[0])))
    if op == "hypot":
        num = plus(times(a[0], da[0]), times(a[1], da[1]))
        return None if num is None else add("div", num, t)
    if op == "abs":
        return None if da[0] is None else add(
            "select", add("lt", a[0], const(0.0)), add("neg", da[0]), da[0])
    if op == "pow":
        parts = [None if da[0] is None else
                 mul(mul(a[1], add("pow", a[0], add("sub", a[1], const(1.0)))), da[0]),
                 None if da[1] is None else mul(mul(t, add("log", a[0])), da[1])]
        return plus(*parts)
    if op in ("max", "min"):  # the operand Python's max/min returns
        if da[0] is None and da[1] is None:
            return None
        zero = const(0.0)
        return add("select", add("gt" if op == "max" else "lt", a[1], a[0]),
                   zero if da[1] is None else da[1], zero if da[0] is None else da[0])
    if op in SCALE:
        return times(da[0], const(SCALE[op]))
    if op == "select":
        if da[1] is None and da[2] is None:
            return None
        zero = const(0.0)
        return add("select", a[0], zero if da[1] is None else da[1],
                   zero if da[2] is None else da[2])
    if op == "extern":
        function = tape.externs[node.value]
        if len(a) != 1 or not hasattr(function, "derivative"):
            raise InputError(f"no derivative of the outside function {node.value} of "
                             f"{len(a)} arguments")
        if da[0] is None:
            return None
        derivative = _DerivativeOf(function)
        tape.externs.setdefault(derivative.name, derivative)
        i = add("extern", a[0], value=derivative.name)
        tape.functions[i] = derivative
        return mul(i, da[0])
    if op in LOOP_OPS:
        return None
    raise InputError(f"no derivative rule for the operation {op!r}")


class TangentFunction:
    """The derivatives' kernel of a :class:`TangentTape` as Python (generated by
    :mod:`~linkage_fmu.kernels.python_source`, see :func:`python_tangent`): calling it
    with the state inputs ``x`` and a direction ``dx`` returns ``(y, dy)``, tuples of
    the outputs and of their derivatives along ``dx`` (the compiled
    :class:`~linkage_fmu.kernels.compiled.TangentKernel`'s floats), or the code of the
    guard that fails (the original kernel's code)."""

    def __init__(self, function, n_inputs: int, n_outputs: int, codes: tuple, source: str):
        self.function, self.n_inputs, self.n_outputs = function, n_inputs, n_outputs
        self.codes, self.source = codes, source

    def __call__(self, x, dx) -> tuple | int:
        x, dx = [float(v) for v in x], [float(v) for v in dx]
        if len(x) != self.n_inputs or len(dx) != self.n_inputs:
            raise InputError(f"x and dx must have {self.n_inputs} values each, got "
                             f"{len(x)} and {len(dx)}")
        r = self.function(*x, *dx)
        if type(r) is not tuple:
            return self.codes[r - 1]
        n = self.n_outputs
        return r[:n], r[n:]


def python_tangent(forward: TangentTape, frozen: tuple, label: str = "tangent"
                   ) -> TangentFunction:
    """The Python kernel of the derivatives' tape ``forward`` (:func:`tangent_tape`),
    run from the original kernel's ``frozen`` values (its parameter step's, for the
    parameter set it serves); ``label`` names it in tracebacks.

    Divisions by zero give what IEEE arithmetic gives (the compiled kernels' inf or
    NaN), not an exception: a derivative there that a selection discards (the friction
    law's at a zero reaction) does not fail the whole state. Other operations raise
    where Python's do (``math.sqrt`` of a negative number, ...).

    Examples
    --------
    >>> from linkage_fmu.kernels.trace import Tape
    >>> tape = Tape()
    >>> x, a = tape.input("x0", 2.0), tape.input("p0", 3.0, parameter=True)
    >>> f = python_tangent(tangent_tape(tape, [x * x * a]), (3.0,))
    >>> f([2.0], [1.0])       # 3 x**2 and its derivative 6 x
    ((12.0,), (12.0,))
    """
    from .python_source import compile_source, python_source

    outputs = [*forward.results, *forward.derivatives]
    source = python_source(forward.tape, list(forward.inputs), outputs, forward.parameters,
                           ieee=True)
    prepare, make = compile_source(source, label=label, externs=forward.tape.externs)
    q = prepare(*frozen)
    return TangentFunction(make(*q), len(forward.inputs) // 2, len(forward.results),
                           forward.codes, source)
