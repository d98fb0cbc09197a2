"""C source from a traced tape: the same code (straight lines and loops), compiled.

Each operation is the same IEEE operation as in Python (the build keeps
``-ffp-contract=off`` and no fast-math) and the elementary functions are the C
library's, which Python's ``math`` module calls too: the results are the Python
kernel's. Two entry points: one state, and an array loop over states (threads with
OpenMP where the compiler has it) that marks the states whose guards fail. The
statements of the operations are :class:`CPrinter`'s, the C spelling of the walk over the
tape that the Python source shares (:class:`~linkage_fmu.kernels.printer.Printer`).
"""

from __future__ import annotations

import copy
import dataclasses

from ..errors import InputError
from .printer import Printer, values
from .tangent import needed as tangent_needed
from .trace import COMPARE, SCALE, Sym, Tape, operand, program

_CALL = {"sqrt": "sqrt", "cos": "cos", "sin": "sin", "tan": "tan", "asin": "asin",
         "acos": "acos", "atan": "atan", "atan2": "atan2", "hypot": "hypot", "abs": "fabs",
         "pow": "pow"}


def c_literal(value: float) -> str:
    """``value`` as a C double literal (``NAN``, ``INFINITY`` and negative numbers
    parenthesised), exact to the bit.

    Examples
    --------
    >>> c_literal(-0.1), c_literal(float("inf"))
    ('(-0.1)', 'INFINITY')
    """
    if value != value:
        return "NAN"
    if value in (float("inf"), float("-inf")):
        return "INFINITY" if value > 0 else "(-INFINITY)"
    text = repr(float(value))
    return f"({text})" if text.startswith("-") else text


#: the indent of a generated statement per level: one space (the six-bar's 20 structures
#: with friction are over 100,000 lines of one-state C, and the indent was a seventh of it)
INDENT = " "


class CPrinter(Printer):
    """C statements of a tape's operations: one declaration per operation (each
    assigned once: no ``const``, which only lengthens large kernels' source); a failed
    guard returns its code, or with ``simd`` marks the state (``bad``) and the
    computation goes on (NaNs, no traps), and the elementary functions are the vector
    ones (``lk_*``); with ``vectorise`` too, max and min pick by the bits (no branch to
    keep the loop scalar). With ``tangent``, each operation's derivative follows it.
    With ``peel`` (and ``simd``), a loop is its first runs, straight (:func:`_peeled`)."""

    def __init__(self, tape: Tape, guards: dict, codes: dict, bodies: dict | None = None,
                 simd: bool = False, vectorise: bool = False,
                 tangent: _Tangent | None = None, peel: bool = False):
        super().__init__(tape, guards, codes, bodies)
        self.simd, self.vectorise, self.tangent, self.peel = simd, vectorise, tangent, peel

    literal = staticmethod(c_literal)

    def declare(self, i, node, expression, indent):
        return f"{indent}{'int' if node.op in COMPARE else 'double'} t{i} = {expression};"

    def guard(self, i, indent):
        if self.simd:
            return f"{indent}bad |= {'!' if self.guards[i] else ''}t{i};"
        return f"{indent}if ({'!' if self.guards[i] else ''}t{i}) return {self.codes[i]};"

    def after(self, i, indent):
        return [] if self.tangent is None else self.tangent.line(i, indent)

    def loop(self, L, indent):
        if self.peel:
            return _peeled(self.tape, L, self.guards, self.codes, indent, self.bodies)
        return _loop(self.tape, L, self.guards, self.codes, indent, self.bodies, self.tangent)

    def divide(self, i, node, a):
        return f"{a[0]} / {a[1]}"

    def power(self, a):
        return self.call("pow", a)

    def select(self, a):
        return (f"lk_pick({a[0]} != 0, {a[1]}, {a[2]})" if self.vectorise
                else f"{a[0]} ? {a[1]} : {a[2]}")

    def fails(self, a, holds):
        return f"(double)(({a[0]} != 0.0) | ((({a[1]}) != 0) != {int(holds)}))"

    def sign(self, a):  # two comparisons, no branch
        return f"(double)(({a[0]} > 0.0) - ({a[0]} < 0.0))"

    def extremum(self, op, a):
        test = f"{a[1]} {'>' if op == 'max' else '<'} {a[0]}"
        return f"lk_pick({test}, {a[1]}, {a[0]})" if self.vectorise else \
            f"{test} ? {a[1]} : {a[0]}"

    def scaled(self, op, a):
        return f"{a[0]} * {c_literal(SCALE[op])}"

    def call(self, op, a):
        name = f"lk_{op}" if self.simd and op in _VECTOR else _CALL[op]
        return f"{name}({', '.join(a)})"


def _statements(tape: Tape, nodes: list, guards: dict, codes: dict, indent: str = INDENT,
                simd: bool = False, vectorise: bool = False, bodies: dict | None = None,
                tangent: _Tangent | None = None, peel: bool = False) -> list:
    """The C of the operations ``nodes`` (:class:`CPrinter`; ``bodies``: loop node ->
    its body's operations)."""
    return CPrinter(tape, guards, codes, bodies, simd, vectorise, tangent,
                    peel).statements(nodes, indent)


def _loop(tape: Tape, L, guards: dict, codes: dict, indent: str, bodies: dict,
          tangent: "_Tangent | None") -> list:
    """A loop (:meth:`Tape.loop <linkage_fmu.kernels.trace.Tape.loop>`): its carried
    values (and their derivatives) as variables, ``for`` over its runs, the new values
    assigned together, the test after ``minimum`` runs; then its results."""
    inner = indent + INDENT
    k = f"k{L.index}"
    carried = [c for c in L.carries if tangent is not None and tangent.carried(c)]
    lines = [
        *(f"{indent}double t{c} = {operand(tape, a, c_literal)};"
          for c, a in zip(L.carries, L.inits)),
        *(f"{indent}double d{c} = {tangent.of(a) or '0.0'};"
          for c, a in zip(L.carries, L.inits) if c in carried),
        f"{indent}int t{L.converged} = 0;",
        f"{indent}for (int {k} = 0; {k} < {L.maximum}; {k}++) {{",
        *_statements(tape, bodies[L.index], guards, codes, inner, bodies=bodies,
                     tangent=tangent),
        *(f"{inner}double u{c} = {operand(tape, n, c_literal)};"
          for c, n in zip(L.carries, L.news)),
        *(f"{inner}double du{c} = {tangent.of(n) or '0.0'};"
          for c, n in zip(L.carries, L.news) if c in carried),
        *(f"{inner}t{c} = u{c};" for c in L.carries),
        *(f"{inner}d{c} = du{c};" for c in carried),
        f"{inner}if ({k} + 1 >= {L.minimum} && !({operand(tape, L.again, c_literal)})) {{",
        f"{inner}    t{L.converged} = 1;",
        f"{inner}    break;",
        f"{inner}}}",
        f"{indent}}}",
        *(f"{indent}double t{f} = t{c};" for f, c in zip(L.finals, L.carries)),
        *(f"{indent}double d{f} = d{c};" for f, c in zip(L.finals, L.carries)
          if c in carried),
        *(f"{indent}(void)t{n};" for n in (*L.finals, L.converged)),
        *(f"{indent}(void)d{f};" for f, c in zip(L.finals, L.carries) if c in carried),
        *(f"{indent}if ({'!' if guards[i] else ''}t{i}) return {codes[i]};"
          for i in (*L.finals, L.converged) if i in guards),
    ]
    if tangent is not None:
        tangent.zero.update(f for f, c in zip(L.finals, L.carries) if c not in carried)
    return lines


def _peeled(tape: Tape, L, guards: dict, codes: dict, indent: str, bodies: dict) -> list:
    """A loop as its first :func:`peeled_runs` runs, straight in a vector loop over
    states (the runs every state takes: no test between them, the carried values in
    registers, not arrays): each run a block of the body's operations (its inner loops
    peeled too). ``more`` is set where the loop would run again after them: that state's
    values are not the loop's, and its caller recomputes it (the one-state function)."""
    inner = indent + "    "
    runs = peeled_runs(L)
    lines = [f"{indent}double t{c} = {operand(tape, a, c_literal)};"
             for c, a in zip(L.carries, L.inits)]
    for run in range(runs):
        lines += [
            f"{indent}{{",
            *_statements(tape, bodies[L.index], guards, codes, inner, simd=True,
                         vectorise=True, bodies=bodies, peel=True),
            *(f"{inner}double u{c} = {operand(tape, n, c_literal)};"
              for c, n in zip(L.carries, L.news)),
            (f"{inner}more |= ({operand(tape, L.again, c_literal)}) != 0;"
             if run == runs - 1 else f"{inner}(void)({operand(tape, L.again, c_literal)});"),
            *(f"{inner}t{c} = u{c};" for c in L.carries),
            f"{indent}}}",
        ]
    lines += [
        *(f"{indent}double t{f} = t{c};" for f, c in zip(L.finals, L.carries)),
        f"{indent}const int t{L.converged} = 1; /* where not, more */",
        *(f"{indent}(void)t{n};" for n in (*L.finals, L.converged)),
        *(f"{indent}bad |= {'!' if guards[i] else ''}(t{i} != 0);"
          for i in (*L.finals, L.converged) if i in guards),
    ]
    return lines


def peeled_runs(L) -> int:
    """The runs of the loop ``L`` every state takes (its test comes after them): its
    minimum, and at least one."""
    return max(L.minimum, 1)


def peeled_operations(tape: Tape, prog) -> int | None:
    """The operations per state of the state step with every loop peeled
    (:func:`_peeled`), or None where a loop has no minimum (the effort's secant loop:
    its runs are phases that every state goes through, so a state never stops after
    its first run, and peeling it only adds work)."""
    def count(nodes):
        total = 0
        for i in nodes:
            if tape.nodes[i].op != "loop":
                total += 1
                continue
            L = tape.loops[i]
            inner = count(prog.bodies[i])
            if L.minimum < 1 or inner is None:
                return None
            total += peeled_runs(L) * (inner + len(L.news))
        return total
    return count(prog.state)


class _Tangent:
    """Forward mode: the derivative ``d<i>`` of each operation along the direction
    ``dx`` of the inputs (the parameters' is zero: they are not inputs here), by the
    rules of calculus applied to the operation the tape holds; only for the operations
    a result's derivative needs (not those only a guard reads). A loop carries the
    derivatives of its carried values with them."""

    def __init__(self, tape: Tape, prog, results: list):
        self.tape = tape
        zero = {i for i, n in enumerate(tape.nodes) if n.op == "const" or i in tape.fixed}
        needed = tangent_needed(tape, results)
        zero.update(i for i in range(len(tape.nodes)) if i not in needed)
        self.zero, self.needed = zero, needed

    def carried(self, c: int) -> bool:
        return c in self.needed and c not in self.zero

    def of(self, j: int) -> str | None:
        """The derivative of operand ``j`` as C text, None where it is zero."""
        node = self.tape.nodes[j]
        if j in self.zero:
            return None
        return f"d{node.value}" if node.op == "input" else f"d{j}"

    def line(self, i: int, indent: str) -> list:
        """The declaration of the derivative of operation ``i`` (none where it is 0)."""
        tape, node = self.tape, self.tape.nodes[i]
        if node.op in COMPARE or i in self.zero or node.op == "fails":
            self.zero.add(i)
            return []
        e = _derivative(tape, i, self.of)
        if e is None:
            self.zero.add(i)
            return []
        return [f"{indent}double d{i} = w ? {e} : 0.0;"]


def _derivative(tape: Tape, i: int, d) -> str | None:
    """The derivative of operation ``i`` as C text (``d``: an operand's), None if 0."""
    def times(a, b):
        return None if a is None or b is None else f"{a} * {b}"

    def plus(a, b, minus=False):
        if b is None:
            return a
        if a is None:
            return f"-({b})" if minus else b
        return f"{a} {'-' if minus else '+'} ({b})" if minus else f"{a} + {b}"

    node = tape.nodes[i]
    a = [operand(tape, j, c_literal) for j in node.args]
    da = [d(j) for j in node.args]
    t, op = f"t{i}", node.op
    if op == "add":
        e = plus(da[0], da[1])
    elif op == "sub":
        e = plus(da[0], da[1], minus=True)
    elif op == "mul":
        e = plus(times(da[0], a[1]), times(a[0], da[1]))
    elif op == "div":
        e = None if da[0] is None and da[1] is None else \
            f"({plus(da[0], times(t, da[1]), minus=True)}) / {a[1]}"
    elif op == "neg":
        e = None if da[0] is None else f"-{da[0]}"
    elif op == "sqrt":
        e = None if da[0] is None else f"{da[0]} / (2.0 * {t})"
    elif op == "sin":
        e = times(f"cos({a[0]})", da[0])
    elif op == "cos":
        e = None if da[0] is None else f"-sin({a[0]}) * {da[0]}"
    elif op == "tan":
        e = times(f"(1.0 + {t} * {t})", da[0])
    elif op in ("asin", "acos"):
        e = None if da[0] is None else (
            f"{'-' if op == 'acos' else ''}{da[0]} / sqrt(1.0 - {a[0]} * {a[0]})")
    elif op == "atan":
        e = None if da[0] is None else f"{da[0]} / (1.0 + {a[0]} * {a[0]})"
    elif op == "atan2":  # atan2(y, x)
        num = plus(times(a[1], da[0]), times(a[0], da[1]), minus=True)
        e = None if num is None else f"({num}) / ({a[1]} * {a[1]} + {a[0]} * {a[0]})"
    elif op == "hypot":
        num = plus(times(a[0], da[0]), times(a[1], da[1]))
        e = None if num is None else f"({num}) / {t}"
    elif op == "abs":
        e = None if da[0] is None else f"({a[0]} < 0.0 ? -{da[0]} : {da[0]})"
    elif op == "pow":
        parts = [None if da[0] is None else f"{a[1]} * pow({a[0]}, {a[1]} - 1.0) * {da[0]}",
                 None if da[1] is None else f"{t} * log({a[0]}) * {da[1]}"]
        e = plus(*parts)
    elif op == "sign":  # piecewise constant
        e = None
    elif op in ("max", "min"):  # the operand Python's max/min returns
        pick = ">" if op == "max" else "<"
        e = None if da[0] is None and da[1] is None else \
            f"({a[1]} {pick} {a[0]} ? {da[1] or '0.0'} : {da[0] or '0.0'})"
    elif op in SCALE:
        e = times(da[0], c_literal(SCALE[op]))
    elif op == "select":
        e = None if da[1] is None and da[2] is None else \
            f"({a[0]} ? {da[1] or '0.0'} : {da[2] or '0.0'})"
    elif op == "extern":
        if len(a) != 1:
            raise InputError(f"no derivative of the outside function {node.value} of "
                             f"{len(a)} arguments")
        e = times(f"{node.value}_d({a[0]})", da[0])
    else:
        raise InputError(f"no derivative rule for the operation {op!r}")
    return e


#: the elementary functions with vector versions in glibc's libmvec
_VECTOR = ("sin", "cos", "atan2")
#: the array kernel's options (-D): LK_SIMD (the blocked loop), LK_MVEC_SINCOS and
#: LK_MVEC_ATAN2 (sin/cos from libmvec, glibc >= 2.22; atan2, glibc >= 2.35), LK_TARGETS
_SIMD_HEAD = """\
#if defined(LK_SIMD) && LK_SIMD
/* Blocks of LK_BLOCK states, each one `omp simd` loop over the straight-line code.
 * math.h declares the vector versions of sin, cos and atan2 only under __FAST_MATH__:
 * the lk_* names are simd-declared aliases of them (from libmvec), or small functions
 * of which GCC makes vector versions itself (a libm call per lane). Flags per state
 * are int: a char makes GCC process 32 states per iteration and spill. */
#ifndef LK_BLOCK
#define LK_BLOCK 256
#endif
#if !defined(LK_CLONES) && defined(__x86_64__) && defined(__GLIBC__)
#ifndef LK_TARGETS
#define LK_TARGETS "default", "arch=x86-64-v3", "arch=x86-64-v4"
#endif
#define LK_CLONES __attribute__((target_clones(LK_TARGETS)))
#endif
#ifndef LK_CLONES
#define LK_CLONES
#endif
"""
#: c ? b : a by the bits, without a branch: GCC 12 if-converts no loop that calls a
#: vector function (a branch there keeps the whole loop scalar), nor some conditional sums
_PICK = """\
static inline double lk_pick(int c, double b, double a) {
    union { double d; unsigned long long u; } x, y;
    const unsigned long long mask = 0ULL - (unsigned long long)(c != 0);
    x.d = b;
    y.d = a;
    x.u = (x.u & mask) | (y.u & ~mask);
    return x.d;
}
"""
#: a state step of more operations than this is not vectorised: GCC 12's loop vectoriser
#: grows faster than the loop (the four-bar with friction, 1407 operations: 0.5 -> 2.2 s;
#: the six-bar's off-crank drivers with friction, 13,156: 5.5 -> 66 s), for a loop that
#: runs about ten times faster (six-bar with friction, 2463 operations: 460 -> 44 ns)
VECTOR_OPERATIONS = 4000
_VECTOR_DECLARATIONS = {
    "sin": ("LK_MVEC_SINCOS", "double lk_sin(double)", "sin", "(double v) { return sin(v); }"),
    "cos": ("LK_MVEC_SINCOS", "double lk_cos(double)", "cos", "(double v) { return cos(v); }"),
    "atan2": ("LK_MVEC_ATAN2", "double lk_atan2(double, double)", "atan2",
              "(double v, double w) { return atan2(v, w); }"),
}


def _marked(n_out: int) -> list:
    """The end of a block of states: ``ok`` from the states' ``badb`` flags, and NaN in
    the outputs of the failed states only."""
    return [
        "    for (size_t j = 0; j < m; j++) {",
        "        ok[j] = (unsigned char)(badb[j] == 0);",
        "        anybad |= badb[j];",
        "    }",
        "    if (anybad) /* NaN the outputs of the failed states only */",
        "        for (size_t j = 0; j < m; j++)",
        "            if (badb[j]) {",
        *(f"                y{k}[j] = NAN;" for k in range(n_out)),
        "            }",
        "}",
    ]


def _array_source(tape: Tape, prog, prefix: str, n_inputs: int, results: list,
                  frozen: list) -> list:
    n_out = len(results)
    xs = ", ".join(f"const double *restrict xb{k}" for k in range(n_inputs))
    ys = ", ".join(f"double *restrict y{k}" for k in range(n_out))
    outputs = values(tape, results, c_literal)
    vectorise = prog.operations <= VECTOR_OPERATIONS
    used = {tape.nodes[i].op for body in (prog.state, *prog.bodies.values()) for i in body}
    used &= set(_VECTOR)
    declarations = []
    for op in _VECTOR:
        if op in used:
            macro, signature, symbol, body = _VECTOR_DECLARATIONS[op]
            declarations += [
                "#pragma omp declare simd notinbranch",
                f"#if defined({macro}) && {macro}",
                f'extern {signature} __asm__("{symbol}");',
                "#else",
                f"static __attribute__((noinline)) double lk_{op}{body}",
                "#endif",
            ]
    peeled = peeled_operations(tape, prog) if prog.bodies and vectorise else None
    if peeled is not None and peeled <= VECTOR_OPERATIONS:  # the loops' first runs, straight
        block = [*_looped_block(tape, prog, prefix, n_inputs, results, frozen, xs, ys,
                                "looped"),
                 *_peeled_block(tape, prog, prefix, n_inputs, outputs, frozen, xs, ys)]
    elif prog.bodies and vectorise:  # loops run on the block, each lane until it converges
        block = _looped_block(tape, prog, prefix, n_inputs, results, frozen, xs, ys)
    elif prog.bodies:  # loops: each state runs its own iterations, one after the other
        block = [
            "__attribute__((noinline))",
            f"static void {prefix}_block(size_t m, const double *restrict q"
            + (f", {xs}" if xs else "") + (f", {ys}" if ys else "")
            + ", unsigned char *restrict ok) {",
            "    for (size_t j = 0; j < m; j++) {",
            f"        double xi[{max(n_inputs, 1)}], yi[{max(n_out, 1)}];",
            *(f"        xi[{k}] = xb{k}[j];" for k in range(n_inputs)),
            f"        const int good = {prefix}_one(q, xi, yi) == 0;",
            "        ok[j] = (unsigned char)good;",
            *(f"        y{k}[j] = good ? yi[{k}] : NAN;" for k in range(n_out)),
            "    }",
            "}",
            "",
        ]
        declarations = []
    else:
        block = None
    block = block or [
        "LK_CLONES __attribute__((noinline))",
        f"static void {prefix}_block(size_t m, const double *restrict q"
        + (f", {xs}" if xs else "") + (f", {ys}" if ys else "")
        + ", unsigned char *restrict ok) {",
        "    int badb[LK_BLOCK], anybad = 0;",
        "    (void)q;",
        "#pragma omp simd" if vectorise else
        f"    /* {prog.operations} operations per state: not vectorised (see VECTOR_OPERATIONS) */",
        "    for (size_t j = 0; j < m; j++) {",
        "        int bad = 0;",
        *(f"        const double {name} = q[{k}];" for k, name in enumerate(frozen)),
        *(f"        const double x{k} = xb{k}[j];" for k in range(n_inputs)),
        *(f"        (void)x{k};" for k in range(n_inputs)),
        *_statements(tape, prog.state, prog.guards, prog.codes, "        ", simd=True,
                     vectorise=vectorise),
        *(f"        y{k}[j] = {v};" for k, v in enumerate(outputs)),
        "        badb[j] = bad;",
        "    }",
        *_marked(n_out),
        "",
    ]
    signature = [f"void {prefix}_array(size_t n, const double *q, const double *const *x,",
                 "                    const size_t *step, double *const *y, unsigned char *ok) {"]
    blocked = [
        *signature,
        "    const size_t nb = (n + LK_BLOCK - 1) / LK_BLOCK;",
        "#pragma omp parallel for schedule(static) if (n > 8192)",
        "    for (size_t b = 0; b < nb; b++) {",
        "        const size_t i0 = b * LK_BLOCK, m = n - i0 < LK_BLOCK ? n - i0 : LK_BLOCK;",
        f"        double xbuf[{max(n_inputs, 1)}][LK_BLOCK];",
        f"        const double *xb[{max(n_inputs, 1)}];",
        f"        for (int k = 0; k < {n_inputs}; k++) {{",
        "            const double *xk = x[k];",
        "            const size_t s = step[k];",
        "            if (s == 1) {",
        "                xb[k] = xk + i0;",
        "            } else {",
        "                for (size_t j = 0; j < m; j++) xbuf[k][j] = xk[(i0 + j) * s];",
        "                xb[k] = xbuf[k];",
        "            }",
        "        }",
        f"        {prefix}_block(m, q"
        + "".join(f", xb[{k}]" for k in range(n_inputs))
        + "".join(f", y[{k}] + i0" for k in range(n_out)) + ", ok + i0);",
        "    }",
        "}",
    ]
    plain = [
        *signature,
        "#pragma omp parallel for schedule(static) if (n > 8192)",
        "    for (size_t i = 0; i < n; i++) {",
        f"        double xi[{max(n_inputs, 1)}], yi[{max(n_out, 1)}];",
        f"        for (int k = 0; k < {n_inputs}; k++) xi[k] = x[k][i * step[k]];",
        f"        const int good = {prefix}_one(q, xi, yi) == 0;",
        "        ok[i] = (unsigned char)good;",
        f"        for (int k = 0; k < {n_out}; k++) y[k][i] = good ? yi[k] : NAN;",
        "    }",
        "}",
    ]
    return [_PICK, _SIMD_HEAD, *declarations, "", *block, *blocked,
            "#else /* one state after the other, through the one-state function */",
            *plain, "#endif", ""]


def _peeled_block(tape: Tape, prog, prefix: str, n_inputs: int, outputs: list,
                  frozen: list, xs: str, ys: str) -> list:
    """``<prefix>_block`` of a kernel whose loops all have a minimum: one vector loop
    over the block's states, straight, each loop its first runs (:func:`_peeled`: the
    runs every state takes before the loop's test, as many as the one-state function
    runs before it tests); the states whose loops would run on are then gathered and
    run by ``<prefix>_looped`` (:func:`_looped_block`: each state's loops until it
    converges). Friction's Newton loops settle in their minimum runs almost everywhere
    (every state of the slider-crank's benchmark), so almost every state is one pass of
    straight vector code: no arrays between vector loops, no lanes waiting for others.
    Where they do not (large friction: most states run on), the first :data:`PROBE`
    states tell, and the whole block runs the looped loops. Either way a state's values
    are the looped loops' (the same operations and vector functions: bit for bit on the
    benchmark's states, large friction's too)."""
    n_out = len(outputs)
    return [
        "#ifndef LK_PROBE",
        f"#define LK_PROBE {PROBE}",
        "#endif",
        "LK_CLONES __attribute__((noinline))",
        f"static void {prefix}_block(size_t m, const double *restrict q"
        + (f", {xs}" if xs else "") + (f", {ys}" if ys else "")
        + ", unsigned char *restrict ok) {",
        "    int badb[LK_BLOCK], moreb[LK_BLOCK], anybad = 0, anymore = 0;",
        "    size_t lo = 0, hi = m < LK_PROBE ? m : LK_PROBE, ran = 0, on = 0;",
        "    (void)q;",
        "    while (lo < m) {",
        "#pragma omp simd",
        "    for (size_t j = lo; j < hi; j++) {",
        "        int bad = 0, more = 0;",
        *(f"        const double {name} = q[{k}];" for k, name in enumerate(frozen)),
        *(f"        const double x{k} = xb{k}[j];" for k in range(n_inputs)),
        *(f"        (void)x{k};" for k in range(n_inputs)),
        *_statements(tape, prog.state, prog.guards, prog.codes, "        ", simd=True,
                     vectorise=True, bodies=prog.bodies, peel=True),
        *(f"        y{k}[j] = {v};" for k, v in enumerate(outputs)),
        "        badb[j] = bad;",
        "        moreb[j] = more;",
        "    }",
        "        for (size_t j = lo; j < hi; j++)",
        "            on += (size_t)moreb[j];",
        "        ran = hi;",
        "        if (hi < m && 4 * on > ran) { /* many of the first run on: all loop */",
        "            ran = 0;",
        "            break;",
        "        }",
        "        lo = hi;",
        "        hi = m;",
        "    }",
        "    if (ran < m) { /* the block, each state's loops until it converges */",
        "        unsigned char okr[LK_BLOCK];",
        f"        {prefix}_looped(m - ran, q" + "".join(f", xb{k} + ran" for k in range(n_inputs))
        + "".join(f", y{k} + ran" for k in range(n_out)) + ", okr);",
        "        for (size_t j = ran; j < m; j++)",
        "            badb[j] = !okr[j - ran];",
        "    }",
        "    for (size_t j = 0; j < ran; j++)",
        "        anymore |= moreb[j];",
        "    if (anymore) { /* loops that run on: gathered, each until it converges */",
        f"        double xg[{max(n_inputs, 1)}][LK_BLOCK + 8], "
        f"yg[{max(n_out, 1)}][LK_BLOCK + 8];",
        "        unsigned char okg[LK_BLOCK + 8];",
        "        size_t at[LK_BLOCK], g = 0;",
        "        for (size_t j = 0; j < ran; j++)",
        "            if (moreb[j]) {",
        *(f"                xg[{k}][g] = xb{k}[j];" for k in range(n_inputs)),
        "                at[g++] = j;",
        "            }",
        "        /* whole vectors (copies of the last state): no lanes of scalar code */",
        "        const size_t g8 = (g + 7) / 8 * 8;",
        "        for (size_t i = g; i < g8; i++) {",
        *(f"            xg[{k}][i] = xg[{k}][g - 1];" for k in range(n_inputs)),
        "        }",
        f"        {prefix}_looped(g8, q" + "".join(f", xg[{k}]" for k in range(n_inputs))
        + "".join(f", yg[{k}]" for k in range(n_out)) + ", okg);",
        "        for (size_t i = 0; i < g; i++) {",
        "            const size_t j = at[i];",
        "            badb[j] = !okg[i];",
        *(f"            y{k}[j] = yg[{k}][i];" for k in range(n_out)),
        "        }",
        "    }",
        *_marked(n_out),
        "",
    ]


#: the states of a block (:func:`_peeled_block`) whose loops' first runs tell whether the
#: others' are worth running straight: where more than a quarter of them run on, the
#: rest of the block runs the looped loops
PROBE = 16


#: lanes of a kernel with loops run together (its values that cross from one vector loop
#: to another are kept in arrays of this length: they stay in the CPU caches)
LOOP_LANES = 32


def _looped_block(tape: Tape, prog, prefix: str, n_inputs: int, results: list,
                  frozen: list, xs: str, ys: str, name: str = "block") -> list:
    """``<prefix>_block`` of a kernel with loops: its straight parts are vector loops
    over the lanes (states) of a piece of the block, and each loop of the kernel runs
    on the piece's lanes until every one has converged (a converged lane keeps its
    values: the values of each lane are the one-state function's). What one vector loop
    computes and another reads crosses in an array per value. Its sin, cos and atan2
    are libmvec's where the build says so (``LK_MVEC_*``), as in the kernels without
    loops: then within a few ulp of the one-state function's, else bit for bit."""
    nodes = tape.nodes
    frozen_at = {name: k for k, name in enumerate(frozen)}
    home = {}  # node -> the vector loop it is computed in

    def split(order):
        out, run = [], []
        for i in order:
            if nodes[i].op == "loop":
                if run:
                    out.append(("straight", run))
                    run = []
                L = tape.loops[i]
                for c in L.carries:
                    home[c] = ("carry", i)
                for f in (*L.finals, L.converged):
                    home[f] = ("loop", i)
                out.append(("loop", i, split(prog.bodies[i])))
            elif nodes[i].op not in ("final", "converged"):
                run.append(i)
        if run:
            out.append(("straight", run))
        for item in out:
            if item[0] == "straight":
                for i in item[1]:
                    home[i] = id(item)
        return out

    tree = split(prog.state)

    def variable(i):
        return nodes[i].op not in ("input", "const") and operand(tape, i, c_literal) \
            not in frozen_at

    crossing = set()  # computed in one vector loop, read in another
    for body in (prog.state, *prog.bodies.values()):
        for i in body:
            if nodes[i].op in ("loop", "final", "converged"):  # their loops read for them
                continue
            for a in nodes[i].args:
                if variable(a) and home.get(a) != home.get(i):
                    crossing.add(a)
    for L in (tape.loops[i] for i in prog.bodies):
        crossing.update(a for a in (*L.news, L.again, *L.inits) if variable(a))
        crossing.update((*L.carries, L.converged))
    crossing.update(r.index for r in results if isinstance(r, Sym) and variable(r.index))
    alias = {}
    for L in (tape.loops[i] for i in prog.bodies):
        alias.update(zip(L.finals, L.carries))
    arrays = sorted(i for i in crossing if i not in alias)
    slot = {i: k for k, i in enumerate(arrays)}
    acts = {i: len(arrays) + k for k, i in enumerate(sorted(prog.bodies))}

    def array(i):
        return f"a{alias.get(i, i)}"

    def loads(operands, indent, skip=()):
        lines, seen = [], set()
        for a in operands:
            node = nodes[a]
            if a in seen or a in skip or node.op == "const":
                continue
            seen.add(a)
            name = operand(tape, a, c_literal)
            if name in frozen_at:
                lines.append(f"{indent}const double {name} = q[{frozen_at[name]}];")
            elif node.op == "input":
                lines.append(f"{indent}const double {name} = xb{name[1:]}[j];")
            elif a in crossing:
                lines.append(f"{indent}const double {name} = {array(a)}[j];")
        return lines

    def lanes(body, indent, clause=""):
        return [f"{indent}#pragma omp simd{clause}", f"{indent}for (size_t j = 0; j < m; j++) {{",
                *body, f"{indent}}}"]

    def emit(tree, indent, active):
        lines = []
        for item in tree:
            if item[0] == "straight":
                run, inner = item[1], indent + "    "
                mine = set(run)
                guarded = any(i in prog.guards for i in run)
                body = loads([a for i in run for a in nodes[i].args], inner, mine)
                body += [f"{inner}int bad = badb[j];"] if guarded else []
                body += _statements(tape, run, prog.guards, prog.codes, inner, simd=True,
                                    vectorise=True)
                body += [f"{inner}{array(i)}[j] = t{i};" for i in run if i in crossing]
                body += [f"{inner}badb[j] = bad;"] if guarded else []
                lines += lanes(body, indent)
                continue
            index, sub = item[1], item[2]
            L, inner = tape.loops[index], indent + "    "
            act, k = f"act{index}", f"k{index}"
            start = active and f"{active}[j]" or "(double)(badb[j] == 0)"
            lines += [f"{indent}/* the loop of node {index}: {L.minimum} to {L.maximum} runs */"]
            lines += lanes([*loads(L.inits, inner),
                            *(f"{inner}{array(c)}[j] = {operand(tape, a, c_literal)};"
                              for c, a in zip(L.carries, L.inits)),
                            f"{inner}{array(L.converged)}[j] = 0.0;",
                            f"{inner}{act}[j] = {start};"], indent)
            lines += [f"{indent}for (int {k} = 0; {k} < {L.maximum}; {k}++) {{"]
            lines += emit(sub, inner, act)
            deep = inner + "    "
            update = [*loads([*L.news, L.again], deep),
                      f"{deep}const int on = {act}[j] != 0.0;",
                      f"{deep}const int stop = {k} + 1 >= {L.minimum} && "
                      f"!({operand(tape, L.again, c_literal)});",
                      *(f"{deep}{array(c)}[j] = lk_pick(on, {operand(tape, n, c_literal)}, "
                        f"{array(c)}[j]);" for c, n in zip(L.carries, L.news)),
                      f"{deep}{array(L.converged)}[j] = lk_pick(on && stop, 1.0, "
                      f"{array(L.converged)}[j]);",
                      f"{deep}{act}[j] = (double)(on && !stop);",
                      f"{deep}any |= on && !stop;"]
            lines += [f"{inner}int any = 0;", *lanes(update, inner, " reduction(|:any)"),
                      f"{inner}if (!any) break;", f"{indent}}}"]
            checked = [i for i in (*L.finals, L.converged) if i in prog.guards]
            if checked:
                lines += lanes([*(f"{inner}badb[j] |= {'!' if prog.guards[i] else ''}"
                                  f"({array(i)}[j] != 0.0);" for i in checked)], indent)
        return lines

    outputs = values(tape, results, c_literal)
    ends = loads([r.index for r in results if isinstance(r, Sym)], "        ")
    ends += [f"        y{k}[j0 + j] = {v};" for k, v in enumerate(outputs)]
    total = len(arrays) + len(acts)
    inputs = "".join(f", const double *restrict xs{k}" for k in range(n_inputs))
    return [
        "LK_CLONES __attribute__((noinline))",
        f"static void {prefix}_{name}(size_t n, const double *restrict q{inputs}"
        + (f", {ys}" if ys else "") + ", unsigned char *restrict ok) {",
        f"    double buf[{max(total, 1)}][{LOOP_LANES}];",
        *(f"    double *const {array(i)} = buf[{slot[i]}];" for i in arrays),
        *(f"    double *const act{i} = buf[{acts[i]}];" for i in acts),
        f"    for (size_t j0 = 0; j0 < n; j0 += {LOOP_LANES}) {{",
        f"    const size_t m = n - j0 < {LOOP_LANES} ? n - j0 : {LOOP_LANES};",
        f"    int badb[{LOOP_LANES}] = {{0}};",
        *(f"    const double *restrict xb{k} = xs{k} + j0;" for k in range(n_inputs)),
        *(f"    (void)xb{k};" for k in range(n_inputs)),  # an input no lane reads
        *emit(tree, "    ", None),
        "    #pragma omp simd",
        "    for (size_t j = 0; j < m; j++) {",
        *ends,
        "        ok[j0 + j] = (unsigned char)(badb[j] == 0);",
        "    }",
        "    for (size_t j = 0; j < m; j++)",
        "        if (badb[j]) {",
        *(f"            y{k}[j0 + j] = NAN;" for k in range(len(results))),
        "        }",
        "    }",
        "}",
        "",
    ]


#: the reductions of a summary (:func:`c_source`): kind -> the outputs it reads
SUMMARY_KINDS = {"peak": 1, "peak_pair": 2, "rms": 1, "mean": 1, "min": 1, "toggle_deg": 1}
#: the values a summary's row starts with, before one value per reduction
SUMMARY_HEAD = ("code", "failed", "first_failed", "locked", "first_locked")


def _simd(clauses: str, indent: str) -> list:
    """An ``omp simd`` loop with reductions (lanes kept apart, sums reassociated), where
    the build has OpenMP."""
    return ["#if defined(_OPENMP)", f"#pragma omp simd {clauses}", "#endif"]


def _reduction(i: int, kind: str, y: list) -> tuple[list, list, list]:
    """The declarations, the reduction of one block of states and the final value of
    summary ``i`` of ``kind`` over the block's results ``y`` (NaN where a state's guards
    fail: NaN values are skipped)."""
    ind = "            "
    loop = f"{ind}    for (size_t j = 0; j < m; j++) {{"
    if kind in ("peak", "peak_pair"):
        # a peak starts below every magnitude (a NaN never compares greater)
        init = [f"        double a{i} = -1.0;"]
        if kind == "peak":
            block = [f"{ind}{{", f"{ind}    double b = -1.0;", *_simd("reduction(max:b)", ind),
                     loop, f"{ind}        const double v = fabs({y[0]});",
                     f"{ind}        b = v > b ? v : b;", f"{ind}    }}"]
        else:  # the largest x^2 + y^2, its root; hypot itself where that is not exact
            block = [f"{ind}{{", f"{ind}    double b = -1.0, c = 0.0;",
                     *_simd("reduction(max:b) reduction(+:c)", ind), loop,
                     f"{ind}        const double v = {y[0]} * {y[0]} + {y[1]} * {y[1]};",
                     f"{ind}        b = v > b ? v : b;",
                     f"{ind}        c += v != v ? 1.0 : 0.0;", f"{ind}    }}",
                     f"{ind}    /* over- or underflow, or a NaN beside an infinity */",
                     f"{ind}    if (c != (double)nbad || !(b < 1e300)"
                     f" || (b > 0.0 && b < 1e-290)) {{",
                     f"{ind}        b = -1.0;",
                     f"{ind}        for (size_t j = 0; j < m; j++) {{",
                     f"{ind}            const double v = hypot({y[0]}, {y[1]});",
                     f"{ind}            if (v > b) b = v;",
                     f"{ind}        }}",
                     f"{ind}    }} else if (b >= 0.0) {{",
                     f"{ind}        b = sqrt(b);",
                     f"{ind}    }}"]
        block += [f"{ind}    if (b > a{i}) a{i} = b;", f"{ind}}}"]
        final = [f"        sd[{len(SUMMARY_HEAD) + i}] = a{i} < 0.0 ? NAN : a{i};"]
    elif kind in ("rms", "mean"):
        init = [f"        double a{i} = 0.0, c{i} = 0.0;"]
        block = [f"{ind}{{", f"{ind}    double b = 0.0, c = 0.0;",
                 *_simd("reduction(+:b, c)", ind), loop,
                 f"{ind}        const double v = {y[0]};",
                 f"{ind}        const double w = {'v * v' if kind == 'rms' else 'v'};",
                 f"{ind}        b += lk_pick(v == v, w, 0.0);",
                 f"{ind}        c += lk_pick(v == v, 1.0, 0.0);",
                 f"{ind}    }}", f"{ind}    a{i} += b;", f"{ind}    c{i} += c;", f"{ind}}}"]
        mean = f"a{i} / c{i}"
        final = [f"        sd[{len(SUMMARY_HEAD) + i}] = c{i} > 0.0 ? "
                 f"{f'sqrt({mean})' if kind == 'rms' else mean} : NAN;"]
    else:
        if kind == "min":
            value = [f"const double v = {y[0]};"]
        else:  # min(g, 180 - g) of the angle in degrees g (numpy's np.degrees)
            value = [f"const double g = {y[0]} * {c_literal(SCALE['degrees'])};",
                     "const double h = 180.0 - g;", "const double v = h < g ? h : g;"]
        init = [f"        double a{i} = INFINITY, c{i} = 0.0;"]
        block = [f"{ind}{{", f"{ind}    double b = INFINITY, c = 0.0;",
                 *_simd("reduction(min:b) reduction(+:c)", ind), loop,
                 *(f"{ind}        {line}" for line in value),
                 f"{ind}        b = v < b ? v : b;", f"{ind}        c += v == v ? 1.0 : 0.0;",
                 f"{ind}    }}", f"{ind}    if (b < a{i}) a{i} = b;", f"{ind}    c{i} += c;",
                 f"{ind}}}"]
        final = [f"        sd[{len(SUMMARY_HEAD) + i}] = c{i} > 0.0 ? a{i} : NAN;"]
    return init, block, final


def _summary_source(prefix: str, n_inputs: int, n_out: int, summary: list,
                    locking: list) -> list:
    """``<prefix>_summary``: the array kernel's blocks of states, one parameter set after
    the other, each block reduced as it comes (its results stay in buffers of the
    block's size); a state whose guards fail is counted as locked where the first guard
    it fails (the one-state function's code) is one of the codes ``locking``."""
    upper = prefix.upper()
    head = len(SUMMARY_HEAD)
    width = head + len(summary)
    if locking:  # the code of a failed state, from the one-state function
        which = [
            "                int locks = 0;",
            "                {",
            f"                    double xi[{max(n_inputs, 1)}], yi[{max(n_out, 1)}];",
            f"                    for (int k = 0; k < {n_inputs}; k++) xi[k] = xb[k][j];",
            f"                    switch ({prefix}_one(q, xi, yi)) {{",
            "                    " + " ".join(f"case {c}:" for c in sorted(locking))
            + " locks = 1; break;",
            "                    default: break;",
            "                    }",
            "                }",
        ]
    else:
        which = ["                const int locks = 0; /* no guard of friction's */"]
    init, update, final = [], [], []
    for i, (kind, args) in enumerate(summary):
        if kind not in SUMMARY_KINDS or len(args) != SUMMARY_KINDS[kind]:
            raise InputError(f"summary {i}: {kind!r} of {len(args)} outputs is not one of "
                             + ", ".join(f"{k} ({n})" for k, n in SUMMARY_KINDS.items()))
        for k in args:
            if not 0 <= k < n_out:
                raise InputError(f"summary {i}: output {k} is not one of the {n_out} results")
        a, b, c = _reduction(i, kind, [f"yb[{k}][j]" for k in args])
        init += a
        update += b
        final += c
    ys = "".join(f", yb[{k}]" for k in range(n_out))
    return [
        "#ifndef LK_BLOCK",
        "#define LK_BLOCK 256",
        "#endif",
        "#ifndef LK_CLONES",
        "#define LK_CLONES",
        "#endif",
        f"static void {prefix}_states(size_t m, const double *q, const double *const *xb,",
        "                           double (*yb)[LK_BLOCK], unsigned char *ok) {",
        "#if defined(LK_SIMD) && LK_SIMD",
        f"    {prefix}_block(m, q" + "".join(f", xb[{k}]" for k in range(n_inputs))
        + ys + ", ok);",
        "#else",
        "    for (size_t j = 0; j < m; j++) {",
        f"        double xi[{max(n_inputs, 1)}], yi[{max(n_out, 1)}];",
        f"        for (int k = 0; k < {n_inputs}; k++) xi[k] = xb[k][j];",
        f"        const int good = {prefix}_one(q, xi, yi) == 0;",
        "        ok[j] = (unsigned char)good;",
        f"        for (int k = 0; k < {n_out}; k++) yb[k][j] = good ? yi[k] : NAN;",
        "    }",
        "#endif",
        "    (void)xb; (void)yb;",
        "}",
        "",
        "LK_CLONES __attribute__((noinline))",
        f"static void {prefix}_reduce(const double *q, size_t n, const double *const *x,",
        "                           const size_t *step, double *sd) {",
        "    size_t bad = 0, first = 0, locked = 0, first_locked = 0;",
        *init,
        "    for (size_t i0 = 0; i0 < n; i0 += LK_BLOCK) {",
        "        const size_t m = n - i0 < LK_BLOCK ? n - i0 : LK_BLOCK;",
        f"        double xbuf[{max(n_inputs, 1)}][LK_BLOCK], yb[{max(n_out, 1)}][LK_BLOCK];",
        "        unsigned char ok[LK_BLOCK];",
        f"        const double *xb[{max(n_inputs, 1)}];",
        f"        for (int k = 0; k < {n_inputs}; k++) {{",
        "            if (step[k] == 1) {",
        "                xb[k] = x[k] + i0;",
        "            } else {",
        "                for (size_t j = 0; j < m; j++) xbuf[k][j] = x[k][(i0 + j) * step[k]];",
        "                xb[k] = xbuf[k];",
        "            }",
        "        }",
        f"        {prefix}_states(m, q, xb, yb, ok);",
        "        size_t nbad = 0;",
        "        for (size_t j = 0; j < m; j++) nbad += !ok[j];",
        "        if (nbad)",
        "            for (size_t j = 0; j < m; j++) {",
        "                if (ok[j]) continue;",
        *which,
        "                if (locks) {",
        "                    if (!locked) first_locked = i0 + j;",
        "                    locked++;",
        "                } else {",
        "                    if (!bad) first = i0 + j;",
        "                    bad++;",
        "                }",
        "            }",
        "        if (nbad < m) { /* the outputs of the failed states are NaN, skipped */",
        *update,
        "        }",
        "    }",
        "    sd[0] = 0.0; sd[1] = (double)bad; sd[2] = bad ? (double)first : -1.0;",
        "    sd[3] = (double)locked; sd[4] = locked ? (double)first_locked : -1.0;",
        *(line[4:] for line in final),
        "}",
        "",
        f"void {prefix}_summary(size_t nd, const double *p, size_t n, const double *const *x,",
        "                      const size_t *step, double *s, int threads) {",
        "#if defined(_OPENMP) /* the array kernel's team: no second set of threads */",
        "#pragma omp parallel for schedule(dynamic, 4) num_threads(threads) if (threads > 1)",
        "#endif",
        "    for (size_t d = 0; d < nd; d++) {",
        f"        double *sd = s + d * {width};",
        f"        double q[{upper}_N_Q + 1];",
        f"        int code = {prefix}_prepare(p + d * {upper}_N_P, q);",
        f"        for (int k = 0; k < {upper}_N_Q && code == 0; k++)",
        "            if (!isfinite(q[k])) code = -1;",
        "        if (code != 0) {",
        "            sd[0] = (double)code; sd[1] = (double)n; sd[2] = -1.0;",
        "            sd[3] = 0.0; sd[4] = -1.0;",
        f"            for (int k = {head}; k < {width}; k++) sd[k] = NAN;",
        "            continue;",
        "        }",
        f"        {prefix}_reduce(q, n, x, step, sd);",
        "    }",
        "    (void)p; (void)threads;",
        "}",
        "",
    ]


def _depends_on(tape: Tape, name: str) -> set:
    """The nodes of ``tape`` that depend on its input ``name``: through their arguments,
    and a loop through anything in its body (a loop node and its results stand for the
    whole loop)."""
    body: dict = {}
    for i, scope in enumerate(tape.scopes):
        if scope is not None:
            body.setdefault(scope.index, []).append(i)
    out: set = set()
    for i, node in enumerate(tape.nodes):
        if node.op == "input":
            if node.value == name:
                out.add(i)
            continue
        if any(a in out for a in node.args):
            out.add(i)
        elif node.op == "loop":
            L = tape.loops[i]
            if any(j in out for j in (*body.get(i, ()), *L.news, L.again)):
                out.add(i)
    return out


def _split_source(tape: Tape, prog, prefix: str, frozen: list, results: list,
                  n_inputs: int, vary: int) -> list:
    """``<prefix>_fix(q, x, f)`` and ``<prefix>_vary(q, f, x, y)``: ``<prefix>_one``
    in two, the work that does not depend on input ``vary`` (into ``f``, its values
    the rest reads) and the rest, so that a caller varying that input alone runs the
    first once; each returns 0 or the code of a guard that fails in it."""
    moving = _depends_on(tape, f"x{vary}")
    fixed = [i for i in prog.state if i not in moving]
    rest = [i for i in prog.state if i in moving]
    read = {a for i in rest for a in tape.nodes[i].args}
    for index, body in prog.bodies.items():
        if index in moving or tape.scopes[index] is not None:
            L = tape.loops[index]
            read.update(a for i in body for a in tape.nodes[i].args)
            read.update([*L.news, L.again])
    read.update(r.index for r in results if isinstance(r, Sym))
    crossing = [i for i in fixed if i in read and tape.nodes[i].op not in ("const", "input")]
    crossing += [i for i in fixed if i in read and tape.nodes[i].op == "final"
                 and i not in crossing]
    outputs = values(tape, results, c_literal)
    loads = [f"    const double {name} = q[{k}]; (void){name};" for k, name in enumerate(frozen)]
    inputs = [f"    const double x{k} = x[{k}]; (void)x{k};" for k in range(n_inputs)]
    return [
        f"#define {prefix.upper()}_N_F {max(len(crossing), 1)}",
        f"int {prefix}_fix(const double *q, const double *x, double *f) {{",
        *loads, *(line for k, line in enumerate(inputs) if k != vary),
        *_statements(tape, fixed, prog.guards, prog.codes, bodies=prog.bodies),
        *(f"    f[{k}] = t{i};" for k, i in enumerate(crossing)),
        "    (void)q; (void)x; (void)f;",
        "    return 0;",
        "}",
        "",
        f"int {prefix}_vary(const double *q, const double *f, const double *x, double *y) {{",
        *loads, *inputs,
        *(f"    const double t{i} = f[{k}]; (void)t{i};" for k, i in enumerate(crossing)),
        *_statements(tape, rest, prog.guards, prog.codes, bodies=prog.bodies),
        *(f"    y[{k}] = {v};" for k, v in enumerate(outputs)),
        "    (void)q; (void)f; (void)x; (void)y;",
        "    return 0;",
        "}",
        "",
    ]


def c_source(tape: Tape, n_inputs: int, results: list, parameters: tuple = (),
             prefix: str = "linkage", array: bool = True, tangent: bool = False,
             summary: list | None = None, settle: bool = False,
             vary: int | None = None) -> str:
    """C functions of the traced ``results``:

    - ``int <prefix>_prepare(const double *p, double *q)``: the parameter step, from the
      parameters ``p`` (in the order of ``parameters``) to the values ``q`` the state
      step reads; 0, or the code of the check of the parameters that fails;
    - ``int <prefix>_one(const double *q, const double *x, double *y)``: one state; 0 if
      it passed every guard, else the code of the guard that failed (the codes are
      :attr:`Program.codes <linkage_fmu.kernels.trace.Program.codes>`);
    - with ``array``, ``void <prefix>_array(n, q, x, step, y, ok)`` over ``n`` states:
      input ``k`` of state ``i`` is ``x[k][i * step[k]]`` (step 0 broadcasts one
      value), output ``k`` goes to ``y[k][i]`` (no output array may overlap another or
      an input), ``ok[i]`` is 0 where a guard fails (outputs NaN there). Compiled with
      ``-DLK_SIMD=1`` it runs blocks of states as vector loops (threads with OpenMP);
      ``-DLK_MVEC_SINCOS=1`` and ``-DLK_MVEC_ATAN2=1`` take sin, cos and atan2 from
      glibc's libmvec (within a few ulp of the scalar ones; without them every value
      is the one-state function's, bit for bit).

    - with ``tangent``, ``int <prefix>_tangent(q, x, dx, y, dy)``: one state as
      ``<prefix>_one``, and ``dy``, the derivatives of the outputs along the direction
      ``dx`` of the inputs (forward mode through the same operations: exact, up to
      rounding), or the code of the guard that fails.

    - with ``summary`` (and ``array``), a list of ``(kind, positions)`` of the results,
      ``void <prefix>_summary(nd, p, n, x, step, s, threads)``: for each of ``nd``
      parameter sets (split between ``threads`` OpenMP threads where built with it)
      (row ``d`` of ``p``, ``<PREFIX>_N_P`` values each), the parameter step, then the
      ``n`` states (``x`` and ``step`` as in the array function) in blocks, each
      reduced as it comes into row ``d`` of ``s`` (``5 + len(summary)`` values,
      :data:`SUMMARY_HEAD` first): the parameter step's code (-1 where it passes but a
      value it computes is not finite), the number of states whose guards fail, other
      than friction's, and the first of them (-1 if none; after a parameter step that
      fails: ``n`` and -1, and the rest NaN), the number of states friction locks (the
      first guard they fail is one whose reason is ``'locking'``) and the first of them
      (-1 if none), then
      one value per entry over the states that pass, NaN values skipped (NaN if none is
      left), of the kinds in :data:`SUMMARY_KINDS`: ``peak`` (largest magnitude),
      ``peak_pair`` (largest ``hypot`` of two results), ``rms`` (root mean square),
      ``mean``, ``min``, and ``toggle_deg`` (smallest ``min(d, 180 - d)`` of the
      result ``d`` in degrees: a transmission angle's distance from a toggle).

    ``<PREFIX>_N_P``, ``_N_Q``, ``_N_X`` and ``_N_Y`` give the lengths of the four.

    With ``settle``, each loop tests whether to go on from its first run (a ``minimum``
    above 1 taken as 1): it stops as soon as it converges, its values then within
    rounding of those after its ``minimum`` runs rather than equal to them, for a caller
    that needs them converged, not the same floats as the library's (the drive FMU's
    kernel of its motion, an iteration's residual).

    With ``vary`` (an input's position), ``<prefix>_fix(q, x, f)`` and
    ``<prefix>_vary(q, f, x, y)`` too: ``<prefix>_one`` in two, the work that does not
    depend on input ``vary`` once into ``f`` (``<PREFIX>_N_F`` values), then the rest,
    as often as that input alone changes; their outputs are ``<prefix>_one``'s.
    """
    if settle:
        tape = copy.copy(tape)
        tape.loops = {i: dataclasses.replace(L, minimum=min(L.minimum, 1))
                      for i, L in tape.loops.items()}
    prog = program(tape, results)
    inner = [i for body in prog.bodies.values() for i in body]
    inner += [a for L in map(tape.loops.get, prog.bodies) for a in (*L.news, L.again)]
    used = {tape.nodes[i].value for i in (*prog.prepare, *prog.state, *prog.frozen, *inner)
            if tape.nodes[i].op == "input"}
    used.update(tape.nodes[a].value for i in (*prog.prepare, *prog.state, *inner)
                for a in tape.nodes[i].args if tape.nodes[a].op == "input")
    frozen = [operand(tape, i, c_literal) for i in prog.frozen]
    n_out, upper = len(results), prefix.upper()
    # an outside function once per translation unit, whatever kernels share it
    externs = [f"#ifndef LK_DEFINED_{name}\n#define LK_DEFINED_{name}\n{f.c_definition()}\n#endif"
               for name, f in tape.externs.items()]
    if tangent:  # and their derivatives
        externs += [f"#ifndef LK_DEFINED_{name}_d\n#define LK_DEFINED_{name}_d\n"
                    f"{f.c_derivative()}\n#endif" for name, f in tape.externs.items()]
    head = [
        "/* generated by linkage_fmu.kernels.c_source: do not edit */",
        "#include <math.h>",
        "#include <stddef.h>",
        "",
        *externs,
        f"#define {upper}_N_P {len(parameters)}",
        f"#define {upper}_N_Q {len(frozen)}",
        f"#define {upper}_N_X {n_inputs}",
        f"#define {upper}_N_Y {n_out}",
        "",
        f"int {prefix}_prepare(const double *p, double *q) {{",
        *(f"    const double {name} = p[{k}];" for k, name in enumerate(parameters)
          if name in used),
        *_statements(tape, prog.prepare, prog.guards, prog.codes),
        *(f"    q[{k}] = {name};" for k, name in enumerate(frozen)),
        "    (void)p; (void)q;",
        "    return 0;",
        "}",
        "",
    ]
    outputs = values(tape, results, c_literal)
    if not tangent:
        head += [
            f"int {prefix}_one(const double *q, const double *x, double *y) {{",
            *(f"    const double {name} = q[{k}];" for k, name in enumerate(frozen)),
            *(f"    const double x{k} = x[{k}];" for k in range(n_inputs) if f"x{k}" in used),
            *_statements(tape, prog.state, prog.guards, prog.codes, bodies=prog.bodies),
            *(f"    y[{k}] = {v};" for k, v in enumerate(outputs)),
            "    (void)q; (void)x; (void)y;",
            "    return 0;",
            "}",
            "",
        ]
    else:  # one function with its derivatives (where w), inlined in the two entry points
        forward = _Tangent(tape, prog, results)
        statements = _statements(tape, prog.state, prog.guards, prog.codes,
                                 bodies=prog.bodies, tangent=forward)

        def d(r):
            return (forward.of(r.index) or "0.0") if isinstance(r, Sym) else "0.0"

        head += [
            "#ifndef LK_INLINE",
            "#if defined(_MSC_VER)",
            "#define LK_INLINE static __forceinline",
            "#else",
            "#define LK_INLINE static inline __attribute__((always_inline))",
            "#endif",
            "#endif",
            f"LK_INLINE int {prefix}_eval(const double *q, const double *x, const double *dx, "
            "double *y, double *dy, const int w) {",
            *(f"    const double {name} = q[{k}];" for k, name in enumerate(frozen)),
            *(f"    const double x{k} = x[{k}], dx{k} = w ? dx[{k}] : 0.0;"
              for k in range(n_inputs) if f"x{k}" in used),
            *statements,
            *(f"    y[{k}] = {v};" for k, v in enumerate(outputs)),
            "    if (w) {",
            *(f"        dy[{k}] = {d(r)};" for k, r in enumerate(results)),
            "    }",
            "    (void)q; (void)x; (void)dx; (void)y; (void)dy;",
            "    return 0;",
            "}",
            "",
            f"int {prefix}_one(const double *q, const double *x, double *y) {{",
            f"    return {prefix}_eval(q, x, NULL, y, NULL, 0);",
            "}",
            "",
            f"int {prefix}_tangent(const double *q, const double *x, const double *dx, "
            "double *y, double *dy) {",
            f"    return {prefix}_eval(q, x, dx, y, dy, 1);",
            "}",
            "",
        ]
    if vary is not None:
        head += _split_source(tape, prog, prefix, frozen, results, n_inputs, vary)
    if not array:
        return "\n".join(head)
    locking = [code for index, code in prog.codes.items()
               if tape.reason(index).kind == "locking"]
    tail = [] if summary is None else _summary_source(prefix, n_inputs, n_out, list(summary),
                                                      locking)
    return "\n".join([*head, *_array_source(tape, prog, prefix, n_inputs, results, frozen),
                      *tail])
