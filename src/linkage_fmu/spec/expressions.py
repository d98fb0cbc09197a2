"""Arithmetic expressions in description files, parsed safely.

An expression is a number, or text such as ``"rho * l_OA"`` or ``"-l_AS1 * sin(beta1)"``
over names (parameters, and in output expressions the joint reactions), the operators
``+ - * / **``, parentheses, the constant ``pi`` and the functions in :data:`FUNCTIONS`.
The text is parsed with :mod:`ast` and only those node types are accepted; it is never
passed to ``eval``.

Examples
--------
>>> e = Expression("rho * l_OA ** 2 / 12")
>>> e.names, e({"rho": 10.0, "l_OA": 0.15})
(('l_OA', 'rho'), 0.01875)
>>> Expression("__import__('os')")
Traceback (most recent call last):
...
ValueError: '__import__' is not a function an expression may call; the functions are: abs, acos, asin, atan, atan2, cos, degrees, hypot, max, min, radians, sin, sqrt, tan
"""

from __future__ import annotations

import ast
import math
import operator
from typing import Callable, Mapping

from .. import numerics

#: functions an expression may call
#: (those of :mod:`~linkage_fmu.numerics`: on floats, or on traced parameters)
FUNCTIONS = {
    "sqrt": numerics.sqrt, "sin": numerics.sin, "cos": numerics.cos, "tan": numerics.tan,
    "asin": numerics.asin, "acos": numerics.acos, "atan": numerics.atan,
    "atan2": numerics.atan2, "hypot": numerics.hypot, "radians": numerics.radians,
    "degrees": numerics.degrees, "abs": abs, "min": numerics.minimum, "max": numerics.maximum,
}
CONSTANTS = {"pi": math.pi}
_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
           ast.Div: operator.truediv, ast.Pow: operator.pow}
_UNARY = {ast.USub: operator.neg, ast.UAdd: operator.pos}


class Expression:
    """A parsed expression; calling it with a mapping of names to numbers evaluates it.

    Raises ``ValueError`` at construction for text that is not such an expression,
    and at evaluation for a name that is not given.
    """

    def __init__(self, source: str | int | float):
        if isinstance(source, bool) or not isinstance(source, (str, int, float)):
            raise ValueError(f"expected a number or an expression, got {source!r}")
        self.source = source
        if isinstance(source, (int, float)):
            if not math.isfinite(source):
                raise ValueError(f"{source!r} is not a finite number")
            self._tree = ast.Constant(float(source))
        else:
            try:
                self._tree = ast.parse(source.strip(), mode="eval").body
            except SyntaxError as err:
                raise ValueError(f"{source!r} is not an expression: {err.msg}") from None
        names: set = set()
        self._check(self._tree, names)
        self.names = tuple(sorted(names))

    def _check(self, node, names: set) -> None:
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
                raise ValueError(f"{node.value!r} in {self.source!r} is not a number")
        elif isinstance(node, ast.Name):
            if node.id in FUNCTIONS:
                raise ValueError(f"{node.id!r} in {self.source!r} is a function: call it")
            if node.id not in CONSTANTS:
                names.add(node.id)
        elif isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            self._check(node.left, names)
            self._check(node.right, names)
        elif isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
            self._check(node.operand, names)
        elif isinstance(node, ast.Call):
            if not isinstance(node.func, ast.Name) or node.func.id not in FUNCTIONS:
                called = node.func.id if isinstance(node.func, ast.Name) else ast.unparse(node.func)
                raise ValueError(f"{called!r} is not a function an expression may call; the "
                                 f"functions are: {', '.join(sorted(FUNCTIONS))}")
            if node.keywords:
                raise ValueError(f"keyword arguments are not allowed: {self.source!r}")
            for arg in node.args:
                self._check(arg, names)
        else:
            raise ValueError(f"{ast.unparse(node)!r} in {self.source!r} is not allowed in an "
                             "expression (numbers, names, + - * / **, parentheses and "
                             "function calls only)")

    def __call__(self, values: Mapping[str, float]) -> float:
        return self._eval(self._tree, values)

    def bind(self, resolve) -> "Callable":
        """A function of ``*args`` that evaluates the expression, each name bound once
        by ``resolve(name)`` to a number or to a function of ``*args``: a tree of
        closures, so no mapping is built per call.

        Examples
        --------
        >>> f = Expression("-0.5 * N - M / h").bind(
        ...     lambda n: {"h": 2.0}.get(n) or (lambda R: R[0] if n == "N" else R[1]))
        >>> f((4.0, 6.0))
        -5.0
        """
        return self._bind(self._tree, resolve)

    def _bind(self, node, resolve):
        if isinstance(node, ast.Constant):
            value = float(node.value)
            return lambda *args: value
        if isinstance(node, ast.Name):
            target = CONSTANTS[node.id] if node.id in CONSTANTS else resolve(node.id)
            if callable(target):
                return target
            return lambda *args: target
        if isinstance(node, ast.BinOp):
            op, a, b = _BINARY[type(node.op)], self._bind(node.left, resolve), self._bind(
                node.right, resolve)
            return lambda *args: op(a(*args), b(*args))
        if isinstance(node, ast.UnaryOp):
            op, a = _UNARY[type(node.op)], self._bind(node.operand, resolve)
            return lambda *args: op(a(*args))
        fn, parts = FUNCTIONS[node.func.id], [self._bind(a, resolve) for a in node.args]
        return lambda *args: fn(*(p(*args) for p in parts))

    def _eval(self, node, values):
        if isinstance(node, ast.Constant):
            return float(node.value)
        if isinstance(node, ast.Name):
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            try:
                return values[node.id]
            except KeyError:
                raise ValueError(f"unknown name {node.id!r} in {self.source!r}") from None
        if isinstance(node, ast.BinOp):
            return _BINARY[type(node.op)](self._eval(node.left, values),
                                          self._eval(node.right, values))
        if isinstance(node, ast.UnaryOp):
            return _UNARY[type(node.op)](self._eval(node.operand, values))
        return FUNCTIONS[node.func.id](*(self._eval(a, values) for a in node.args))

    def __repr__(self) -> str:
        return f"Expression({self.source!r})"
