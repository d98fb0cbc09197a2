"""Arithmetic expressions in description files, parsed safely.

An expression is a number, or text such as ``"rho * l_OA"`` or ``"-l_AS1 * sin(beta1)"``
over names (parameters, and in output expressions the joint reactions), the operators
``+ - * / **``, parentheses, the constant ``pi`` and the functions in :data:`FUNCTIONS`;
a number may carry a unit (``"240 mm"``, ``"800 kPa * pi * bore**2 / 4"``, see
:mod:`~linkage_fmu.units`), which is taken in SI. The text is parsed with
:mod:`ast` and only those node types are accepted; it is never passed to ``eval``.

Examples
--------
>>> e = Expression("rho * l_OA ** 2 / 12")
>>> e.names, e({"rho": 10.0, "l_OA": 0.15})
(('l_OA', 'rho'), 0.01875)
>>> Expression("__import__('os')")
Traceback (most recent call last):
...
linkage_fmu.errors.InputError:
'__import__' is not a function an expression may call; the functions are: abs, acos,
asin, atan, atan2, cos, degrees, hypot, max, min, radians, sign, sin, sqrt, tan
"""

from __future__ import annotations

import ast
import math
import operator
import re
from collections.abc import Callable, Mapping

from . import numerics, units
from .errors import InputError

#: functions an expression may call
#: (those of :mod:`~linkage_fmu.numerics`: on floats, or on traced parameters)
FUNCTIONS = numerics.FUNCTIONS
CONSTANTS = {"pi": math.pi}
_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
           ast.Div: operator.truediv, ast.Pow: operator.pow}
_UNARY = {ast.USub: operator.neg, ast.UAdd: operator.pos}
_SYMBOLS = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**",
            ast.USub: "-", ast.UAdd: "+"}
#: the operators an expression may use between two values, and as a sign
BINARY_OPERATORS = tuple(_SYMBOLS[op] for op in _BINARY)
SIGNS = tuple(_SYMBOLS[op] for op in _UNARY)


class Expression:
    """A parsed expression; calling it with a mapping of names to numbers evaluates it.

    Raises ``ValueError`` at construction for text that is not such an expression,
    and at evaluation for a name that is not given.
    """

    def __init__(self, source: str | int | float):
        if isinstance(source, bool) or not isinstance(source, (str, int, float)):
            raise InputError(f"expected a number or an expression, got {source!r}")
        self.source = source
        #: the numbers with units in the text (pint quantities), in order
        self.quantities: list = []
        if isinstance(source, (int, float)):
            if not math.isfinite(source):
                raise InputError(f"{source!r} is not a finite number")
            self._tree = ast.Constant(float(source))
        else:
            text = source.strip()
            if units.has_units(text):
                text, self.quantities = units.substitute(text)
            try:
                self._tree = ast.parse(text, mode="eval").body
            except SyntaxError as err:
                raise InputError(f"{source!r} is not an expression: {err.msg}") from None
        #: the SI value of each quantity, by its name in the parsed text
        self._si = {f"__q{k}__": units.si(q) for k, q in enumerate(self.quantities)}
        names: set = set()
        self._check(self._tree, names)
        self.names = tuple(sorted(names))

    def in_si(self) -> str | float:
        """The expression with each number that carries a unit replaced by its value in
        SI (the source itself when none does): to combine it with plain numbers.

        Examples
        --------
        >>> Expression("l_AB + 120 mm").in_si()
        'l_AB + 0.12'
        >>> Expression(0.5).in_si()
        0.5
        """
        if not self.quantities:
            return self.source
        text = ast.unparse(self._tree)
        for name, value in self._si.items():
            text = re.sub(rf"\b{name}\b", repr(value), text)
        return text

    @property
    def has_units(self) -> bool:
        """Whether a number of the expression carries a unit."""
        return bool(self.quantities)

    def measure(self, units_of: Mapping[str, tuple]):
        """The expression over pint quantities: each name as ``units_of[name]``, a
        ``(value, unit)`` pair (the package's unit names, see
        :data:`~linkage_fmu.units.PINT`). What it measures checks its units.

        Examples
        --------
        >>> q = Expression("800 kPa * pi * bore**2 / 4").measure({"bore": (0.086, "m")})
        >>> f"{q.to('N'):.1f~}"
        '4647.0 N'
        """
        import numpy as np

        ureg = units.registry()
        values = {name: ureg.Quantity(value, units.PINT.get(unit, unit))
                  for name, (value, unit) in units_of.items()}
        values.update({f"__q{k}__": q for k, q in enumerate(self.quantities)})
        functions = {"sqrt": np.sqrt, "sin": np.sin, "cos": np.cos, "tan": np.tan,
                     "asin": np.arcsin, "acos": np.arccos, "atan": np.arctan,
                     "atan2": np.arctan2, "hypot": np.hypot, "abs": abs, "min": min,
                     "max": max, "radians": np.radians, "degrees": np.degrees}
        return self._eval(self._tree, values, functions)

    def _check(self, node, names: set) -> None:
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
                raise InputError(f"{node.value!r} in {self.source!r} is not a number")
        elif isinstance(node, ast.Name):
            if node.id in FUNCTIONS:
                raise InputError(f"{node.id!r} in {self.source!r} is a function: call it")
            if node.id not in CONSTANTS and node.id not in self._si:
                names.add(node.id)
        elif isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            self._check(node.left, names)
            self._check(node.right, names)
        elif isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
            self._check(node.operand, names)
        elif isinstance(node, ast.Call):
            if not isinstance(node.func, ast.Name) or node.func.id not in FUNCTIONS:
                called = node.func.id if isinstance(node.func, ast.Name) else ast.unparse(node.func)
                raise InputError(f"{called!r} is not a function an expression may call; the "
                                 f"functions are: {', '.join(sorted(FUNCTIONS))}")
            if node.keywords:
                raise InputError(f"keyword arguments are not allowed: {self.source!r}")
            for arg in node.args:
                self._check(arg, names)
        else:
            raise InputError(f"{ast.unparse(node)!r} in {self.source!r} is not allowed in an "
                             "expression (numbers, names, + - * / **, parentheses and "
                             "function calls only)")

    def __call__(self, values: Mapping[str, float], functions: Mapping | None = None) -> float:
        """The value over ``values`` (name -> number: floats, arrays, traced or mpmath
        numbers, with ``functions`` of that kind; default :data:`FUNCTIONS`)."""
        return self._eval(self._tree, values, functions or FUNCTIONS)

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
            target = (CONSTANTS.get(node.id) if node.id in CONSTANTS else
                      self._si[node.id] if node.id in self._si else resolve(node.id))
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

    def _eval(self, node, values, functions):
        if isinstance(node, ast.Constant):
            return float(node.value)
        if isinstance(node, ast.Name):
            if node.id in CONSTANTS:
                return CONSTANTS[node.id]
            try:
                return values[node.id] if node.id in values else self._si[node.id]
            except KeyError:
                raise InputError(f"unknown name {node.id!r} in {self.source!r}") from None
        if isinstance(node, ast.BinOp):
            return _BINARY[type(node.op)](self._eval(node.left, values, functions),
                                          self._eval(node.right, values, functions))
        if isinstance(node, ast.UnaryOp):
            return _UNARY[type(node.op)](self._eval(node.operand, values, functions))
        return functions[node.func.id](*(self._eval(a, values, functions) for a in node.args))

    def __repr__(self) -> str:
        return f"Expression({self.source!r})"


def evaluate(source, unit: str, where: str, values: Mapping | None = None,
             units_of: Mapping | None = None) -> float:
    """The value of ``source`` (a number, or the text of an expression, with units or
    not) over ``values`` (name -> number), in SI; an expression with units must measure
    what ``unit`` does, its names measured by ``units_of`` (name -> (value, unit)).
    A ValueError names ``where`` and says why.

    Examples
    --------
    >>> evaluate("pi / 2", "rad", "gamma")
    1.5707963267948966
    >>> evaluate("120 mm + 2 * l_OA", "m", "l_AB", {"l_OA": 0.015}, {"l_OA": (0.015, "m")})
    0.15
    >>> evaluate("4 kN", "N.m", "T")
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError: T = '4 kN' must be a moment (N.m), but it is a force (N)
    """
    try:
        expr = Expression(source)
        x = expr(values or {})
    except (ValueError, ZeroDivisionError, OverflowError, TypeError) as err:
        raise InputError(f"{where} = {source!r}: {err}") from None
    if expr.has_units:
        check_units(expr, unit, where, units_of or {})
    return x


def check_units(expr: Expression, unit: str, where: str, units_of: Mapping) -> None:
    """A ValueError naming ``where`` unless ``expr``, its names measured by ``units_of``
    (name -> (value, unit)), measures what ``unit`` does, its units agreeing."""
    try:
        measured = expr.measure(units_of)
    except (TypeError, ValueError, ArithmeticError, AttributeError) as err:  # 1 m + 1 s
        raise InputError(f"{where} = {expr.source!r}: its units do not agree: {err}") from None
    units.check(measured, unit, where, expr.source)
