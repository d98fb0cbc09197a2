"""Straight-line Python source from a traced tape: the kernel that always works.

One assignment per live operation, in the order the formulas did them (so the results
are bit-identical to the interpreted formulas on floats), and an early ``return None``
where a guard does not hold.
"""

from __future__ import annotations

import math

from .trace import Sym, Tape, operand, program

_INFIX = {"add": "+", "sub": "-", "mul": "*", "div": "/", "pow": "**", "lt": "<", "le": "<=",
          "gt": ">", "ge": ">=", "eq": "==", "ne": "!="}
_CALL = {"sqrt": "sqrt", "cos": "cos", "sin": "sin", "atan2": "atan2", "abs": "abs",
         "max": "max"}
#: what the generated source calls: the very functions of the scalar formulas
NAMESPACE = {"sqrt": math.sqrt, "cos": math.cos, "sin": math.sin, "atan2": math.atan2,
             "inf": math.inf, "nan": math.nan}


def _literal(value: float) -> str:
    text = repr(value)
    return f"({text})" if text.startswith("-") else text


def python_source(tape: Tape, arguments: list[str], results: list, name: str = "kernel") -> str:
    """A function ``name(*arguments)`` returning the tuple of ``results``, or None when a
    guard fails.

    Examples
    --------
    >>> from linkage_fmu.kernels.trace import TRACE
    >>> tape = Tape()
    >>> x = tape.input("x", 4.0)
    >>> if x < 0.0:
    ...     pass
    >>> print(python_source(tape, ["x"], [TRACE.sqrt(x) * 2.0]), end="")
    def kernel(x):
        t2 = x < 0.0
        if t2: return None
        t3 = sqrt(x)
        t5 = t3 * 2.0
        return (t5,)
    """
    live, guards = program(tape, results)

    def ref(i: int) -> str:
        return operand(tape, i, _literal)

    lines = [f"def {name}({', '.join(arguments)}):"]
    for i, node in enumerate(tape.nodes):
        if i not in live or node.op in ("input", "const"):
            continue
        args = [ref(a) for a in node.args]
        if node.op in _INFIX:
            expr = f"{args[0]} {_INFIX[node.op]} {args[1]}"
        elif node.op == "neg":
            expr = f"-{args[0]}"
        else:
            expr = f"{_CALL[node.op]}({', '.join(args)})"
        lines.append(f"    t{i} = {expr}")
        if i in guards:
            lines.append(f"    if {'not ' if guards[i] else ''}t{i}: return None")
    values = [ref(r.index) if isinstance(r, Sym) else repr(float(r)) for r in results]
    lines.append(f"    return ({', '.join(values)}{',' if len(values) == 1 else ''})")
    return "\n".join(lines) + "\n"


def compile_source(source: str, name: str = "kernel", label: str = "kernel"):
    """The function defined by the generated ``source`` (our own code, never a file's)."""
    namespace = dict(NAMESPACE)
    exec(compile(source, f"<linkage_fmu {label}>", "exec"), namespace)
    return namespace[name]
