"""The inputs of a linkage: their names, units and start values, and the values of a
call, positional, by name or as text with a unit, in the order the formulas take them.

An :class:`InputTable` is built once per linkage from its drivers
(:mod:`~linkage_fmu.drivers`) and its loads; the solver reads a call's values through
it, and :meth:`Mechanism.solve <linkage_fmu.mechanism.Mechanism.solve>`'s lean path its
loads (:meth:`InputTable.lean_loads`).

Examples
--------
>>> from linkage_fmu import presets
>>> table = presets.get("four_bar").input_table
>>> table.names, table.units["omega"]
(('theta', 'omega', 'alpha', 'load'), 'rad/s')
>>> table.values(alpha=2.0, named={"load": 3.0})
([10.0, 2.0, 3.0], ())
"""

from __future__ import annotations

from collections.abc import Sequence
from types import MappingProxyType

import numpy as np

from .drivers import Driver, input_names, input_units
from .errors import InputError, InputTypeError
from .expressions import evaluate

#: the types the lean path takes besides floats, as floats (:func:`floats`)
CONVERTED = frozenset((int, np.float64))
#: the types of a driver's speed and acceleration it takes (not bool: the general path
#: refuses it)
LEAN = CONVERTED | {float}


def floats(values: tuple) -> list | None:
    """``values`` with each int or numpy float64 as a float (as the general path takes
    them), or None where an int does not fit a float (the general path says why).

    Examples
    --------
    >>> floats((1, 2.5)), floats((10**400,))
    ([1.0, 2.5], None)
    """
    try:
        return [float(v) if type(v) in CONVERTED else v for v in values]
    except OverflowError:
        return None


class InputTable:
    """The inputs of the linkage ``name``: its ``drivers``' coordinates, speeds and
    accelerations, then each load of ``loads`` that is an input (not computed over the
    cycle), with their units and ``start`` values (input name -> value; default 0, a
    load's own ``start``).

    Attributes
    ----------
    names : tuple of str
        The inputs, in the order a call takes them positionally.
    units : dict
        Input name -> unit, the loads over the cycle included.
    input_loads, computed_loads : tuple of Load
        The loads that are inputs, and those computed over the cycle.
    """

    def __init__(self, name: str, drivers: Sequence[Driver], loads: Sequence,
                 start: dict | None = None):
        self.name = name
        self.input_loads = tuple(ld for ld in loads if not ld.computed)
        self.computed_loads = tuple(ld for ld in loads if ld.computed)
        self.motion = input_names(tuple(drivers))
        self.names = self.motion + tuple(ld.name for ld in self.input_loads)
        self.units = {**input_units(tuple(drivers)), **{ld.name: ld.unit for ld in loads}}
        #: input name -> start value, for reading only (:attr:`start` is its read-only
        #: view; a view is not held, so that a linkage deep-copies)
        self.defaults = {**dict.fromkeys(self.motion, 0.0),
                         **{ld.name: ld.start for ld in loads}, **(start or {})}
        #: the input loads by name -> position, their start values, and the name of a
        #: linkage's one load (None for none or several): the lean path's
        self.position = {ld.name: k for k, ld in enumerate(self.input_loads)}
        self.n_loads = len(self.input_loads)
        self.start_loads = tuple(self.defaults[ld.name] for ld in self.input_loads)
        self.one_load = self.input_loads[0].name if len(self.input_loads) == 1 else None

    @property
    def start(self) -> MappingProxyType:
        """Input name -> the value it takes where none is given (read-only)."""
        return MappingProxyType(self.defaults)

    def values(self, omega=None, alpha=None, loads: Sequence = (),
               named: dict | None = None) -> tuple[list, tuple]:
        """``[omega, alpha, *input loads, *given computed loads]`` from the values given
        (the input loads positionally in :attr:`input_loads` order, or by name; a load
        over the cycle by name to override it), each input not given taking its start
        value, text (a number with a unit, an expression: ``"1800 rpm"``, ``"2 * pi *
        30 rad/s"``) taken in SI (:func:`~.expressions.evaluate`); and the names of the
        computed loads given.

        Raises
        ------
        TypeError
            Too many loads, an unknown name, or a load given twice.
        """
        if not named and len(loads) == len(self.input_loads) and omega is not None and \
                alpha is not None:
            out, given = [omega, alpha, *loads], ()
        else:
            out, given = self._named(omega, alpha, loads, named or {})
        for k, value in enumerate(out):
            if isinstance(value, str):  # a number with a unit, an expression
                name = (self.names[1:] + given)[k]
                out[k] = evaluate(value, self.units[name], name)
        return out, given

    def _named(self, omega, alpha, loads: Sequence, named: dict) -> tuple[list, tuple]:
        names = [load.name for load in self.input_loads]
        if len(loads) > len(names):
            raise InputTypeError(f"{self.name} has {len(names)} input load(s) "
                                 f"({', '.join(names)}), got {len(loads)} positional load "
                                 "values")
        values = dict(zip(names, loads))
        known = {load.name for load in self.input_loads + self.computed_loads}
        for key, value in named.items():
            if key not in known:
                raise InputTypeError(f"{self.name} has no input {key!r}; its inputs are: "
                                     + ", ".join(self.names + tuple(
                                         ld.name for ld in self.computed_loads)))
            if key in values:
                raise InputTypeError(f"load {key} is given twice")
            values[key] = value
        given = tuple(ld.name for ld in self.computed_loads if ld.name in values)
        speed, acceleration = self.motion[1], self.motion[2]
        return [self.defaults[speed] if omega is None else omega,
                self.defaults[acceleration] if alpha is None else alpha,
                *(values.get(n, self.defaults[n]) for n in names),
                *(values[n] for n in given)], given

    def every(self, positional: Sequence, named: dict) -> tuple[list, tuple]:
        """Every input of a linkage driven by time, in :attr:`names` order (then the
        computed loads given), from ``positional`` values in that order (None: not given)
        and ``named`` ones: each driver's coordinate is required, every other input not
        given takes its start value; text is taken in SI.

        Raises
        ------
        TypeError
            Too many values, an unknown name, or an input given twice.
        ValueError
            A driver's coordinate not given.

        Examples
        --------
        >>> from linkage_fmu.drivers import Driver
        >>> table = InputTable("arm", (Driver.named("P", "travel", None, False),), ())
        >>> table.every(("20 mm",), {"v_P": 0.1})
        ([0.02, 0.1, 0.0], ())
        """
        if len(positional) > len(self.names):
            raise InputTypeError(f"{self.name} has {len(self.names)} inputs "
                                 f"({', '.join(self.names)}), got {len(positional)} "
                                 "positional values")
        values = {n: v for n, v in zip(self.names, positional) if v is not None}
        computed = {ld.name for ld in self.computed_loads}
        for key, value in named.items():
            if key not in self.names and key not in computed:
                raise InputTypeError(f"{self.name} has no input {key!r}; its inputs are: "
                                     + ", ".join(self.names))
            if key in values:
                raise InputTypeError(f"input {key} is given twice")
            values[key] = value
        missing = [n for n in self.motion[0::3] if n not in values]
        if missing:
            raise InputError(f"{self.name}: give each driver's coordinate; missing: "
                             + ", ".join(missing))
        given = tuple(ld.name for ld in self.computed_loads if ld.name in values)
        out = [values.get(n, self.defaults[n]) for n in self.names + given]
        for k, value in enumerate(out):
            if isinstance(value, str):
                name = (self.names + given)[k]
                out[k] = evaluate(value, self.units[name], name)
        return out, given

    def lean_loads(self, loads: tuple, named: dict) -> tuple | list | None:
        """The input loads of the lean path from those given positionally (``loads``)
        and by name (``named``), each not given at its start value; None where the
        general path must decide (too many, unknown names, twice given, a load over the
        cycle given).

        Examples
        --------
        >>> import linkage_fmu
        >>> table = linkage_fmu.load("examples/coupler_four_bar.toml").input_table
        >>> table.lean_loads((80.0,), {"T4": 120.0}), table.lean_loads((), {"x": 1.0})
        ([80.0, 120.0], None)
        """
        position = self.position
        if not named and len(loads) == len(position):
            return loads
        if not named and not loads:
            return self.start_loads
        if not loads and len(named) == len(position):  # each by name
            x = []
            for name in position:
                value = named.get(name)
                if value is None:
                    return None
                x.append(value)
            return x
        if len(loads) > len(position):
            return None
        x = list(loads) + list(self.start_loads[len(loads):])
        for name, value in named.items():
            k = position.get(name)
            if k is None or k < len(loads):
                return None
            x[k] = value
        return x
