"""Python source from a traced tape: the kernel that always works.

One assignment per live operation (a loop's body once, inside a ``for``), in the order
the formulas did them (so the results are bit-identical to the interpreted formulas on
floats), and an early return of the
guard's code (:attr:`Program.codes <linkage_fmu.kernels.trace.Program.codes>`) where a
guard does not hold. The work on the parameters alone is a separate function, run once
per parameter set; its values are closed over by the kernel of a state.
"""

from __future__ import annotations

import math

from .trace import Sym, Tape, operand, program, sign

_INFIX = {"add": "+", "sub": "-", "mul": "*", "div": "/", "pow": "**", "lt": "<", "le": "<=",
          "gt": ">", "ge": ">=", "eq": "==", "ne": "!="}
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


def _statements(tape: Tape, nodes: list, guards: dict, codes: dict, indent: str,
                bodies: dict | None = None, ieee: bool = False) -> list:
    lines = []
    for i in nodes:
        node = tape.nodes[i]
        if node.op in ("final", "converged"):  # written by their loop
            continue
        if node.op == "loop":
            lines += _loop(tape, tape.loops[i], guards, codes, indent, bodies, ieee)
            continue
        args = [operand(tape, a, _literal) for a in node.args]
        if ieee and node.op == "div" and not (
                tape.nodes[node.args[1]].op == "const" and tape.nodes[node.args[1]].value):
            expr = f"{args[0]} / {args[1]} if {args[1]} else quotient({args[0]}, {args[1]})"
        elif node.op in _INFIX:
            expr = f"{args[0]} {_INFIX[node.op]} {args[1]}"
        elif node.op == "neg":
            expr = f"-{args[0]}"
        elif node.op == "extern":
            expr = f"{node.value}({', '.join(args)})"
        elif node.op == "select":
            expr = f"{args[1]} if {args[0]} else {args[2]}"
        elif node.op == "fails":  # a check inside a loop: its failure, kept
            expr = f"1.0 if ({args[0]} or bool({args[1]}) != {node.value}) else 0.0"
        else:
            expr = f"{_CALL[node.op]}({', '.join(args)})"
        lines.append(f"{indent}t{i} = {expr}")
        if i in guards:
            lines.append(f"{indent}if {'not ' if guards[i] else ''}t{i}: return {codes[i]}")
    return lines


def _loop(tape: Tape, L, guards: dict, codes: dict, indent: str, bodies: dict,
          ieee: bool = False) -> list:
    """A loop (:meth:`Tape.loop <linkage_fmu.kernels.trace.Tape.loop>`): its carried
    values, then ``for`` over its runs, the test after ``minimum`` of them."""
    inner = indent + "    "
    carries = [f"t{c}" for c in L.carries]
    news = [operand(tape, n, _literal) for n in L.news]
    return [
        f"{indent}{_tuple(carries)} = {_tuple([operand(tape, a, _literal) for a in L.inits])}",
        f"{indent}t{L.converged} = False",
        f"{indent}for _k{L.index} in range({L.maximum}):",
        *_statements(tape, bodies[L.index], guards, codes, inner, bodies, ieee),
        f"{inner}{_tuple(carries)} = {_tuple(news)}",
        f"{inner}if _k{L.index} >= {L.minimum - 1} and not "
        f"{operand(tape, L.again, _literal)}:",
        f"{inner}    t{L.converged} = True",
        f"{inner}    break",
        *(f"{indent}t{f} = t{c}" for f, c in zip(L.finals, L.carries)),
        *(f"{indent}if {'not ' if guards[i] else ''}t{i}: return {codes[i]}"
          for i in (*L.finals, L.converged) if i in guards),
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
    values = [operand(tape, r.index, _literal) if isinstance(r, Sym) else repr(float(r))
              for r in results]
    return "\n".join([
        f"def prepare({', '.join(parameters)}):",
        *_statements(tape, prog.prepare, prog.guards, codes, "    ", ieee=ieee),
        f"    return {_tuple(frozen)}",
        f"def make({', '.join(frozen)}):",
        f"    def kernel({', '.join(arguments)}):",
        *_statements(tape, prog.state, prog.guards, codes, "        ", prog.bodies, ieee),
        f"        return {_tuple(values)}",
        "    return kernel",
        "",
    ])


def compile_source(source: str, label: str = "kernel", externs: dict | None = None):
    """The functions ``prepare`` and ``make`` defined by the generated ``source`` (our
    own code, never a file's), which calls the functions ``externs`` (name -> function)
    besides :data:`NAMESPACE`."""
    namespace = {**NAMESPACE, **(externs or {})}
    exec(compile(source, f"<linkage_fmu {label}>", "exec"), namespace)
    return namespace["prepare"], namespace["make"]
