"""Kinematic pairs: what each kind of pair transmits, and everything that follows from it.

A pair joins bodies ``a`` and ``b`` at ``point``; its reaction is the action of ``a`` on
``b``, two numbers whose meaning is the pair's kind:

* :class:`Revolute`: a pin, the force ``(Fx, Fy)`` at its point;
* :class:`Prismatic`: a slider in a guide, the force ``N`` along the guide's normal
  through its point and the couple ``M``.

Each kind owns its reaction components and their names, its columns and entries in the
equations of the moving links (``A x = b``), its friction law and how the friction acts,
and the force it exerts, for the outputs and the pictures. Code elsewhere asks a pair
what it does, never which kind it is: a new kind of pair (a cam contact, a gear mesh) is
a new subclass of :class:`Pair`, and :class:`Pair` refuses a subclass that leaves out
part of the contract.

Every method runs on floats, arrays over states, traced numbers or mpmath numbers; the
arithmetic of each is written once, in the order the kernels are traced in.
"""

from __future__ import annotations

import dataclasses
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .errors import InputTypeError

#: the magnitudes of a pin's reaction whose components :meth:`Revolute.friction_law`
#: squares as they are (2^-500 to 2^500, about 3e-151 to 3e+150: no square overflows
#: or falls below the normal doubles); beyond, it scales them by 2^-600 or 2^600 first
_SMALL, _HUGE = 2.0 ** -500, 2.0 ** 500
_SHRINK, _GROW = 2.0 ** -600, 2.0 ** 600


def _above(x, limit):
    """Whether ``x > limit``, as a value to pick with (:func:`_pick`), not a branch: a
    traced comparison, an array of bools, a bool."""
    tape = getattr(x, "tape", None) or getattr(limit, "tape", None)
    if tape is not None:
        return tape.compare("gt", x, limit)
    return np.greater(x, limit) if isinstance(x, np.ndarray) or isinstance(
        limit, np.ndarray) else x > limit


def _pick(condition, a, b):
    """``a`` where ``condition`` (of :func:`_above`) holds, else ``b``."""
    tape = getattr(condition, "tape", None)
    if tape is not None:
        return tape.select(condition, a, b)
    if isinstance(condition, np.ndarray):
        return np.where(condition, a, b)
    return a if condition else b

Vec = tuple  # (x, y) of floats or arrays


@dataclass(frozen=True, slots=True)
class Pair(ABC):
    """A kinematic pair between bodies ``a`` and ``b`` at ``point``; its reaction is the
    action of ``a`` on ``b``.

    A subclass states its reaction's ``components`` (two names, as the outputs
    ``<component>_<pair>`` of a description's expressions read them), the
    ``friction_prefix`` and ``friction_unit`` of its friction output, and implements every
    abstract method; one that does not is refused when it is defined (a kind meant to be
    subclassed further says ``class HigherPair(Pair, abstract=True)``).

    Examples
    --------
    >>> class Half(Pair):
    ...     components = ("Fx", "Fy")
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputTypeError:
    pair kind Half leaves out friction_prefix, friction_unit, column_scale, ...
    """

    name: str
    point: str
    a: str
    b: str

    #: the names of the reaction's two components
    components: ClassVar[tuple[str, str]]
    #: the friction output is ``<friction_prefix>_<pair>``, in ``friction_unit``
    friction_prefix: ClassVar[str]
    friction_unit: ClassVar[str]
    #: whether a picture draws the pair as a pin at its point
    draws_pin: ClassVar[bool] = False

    _CLASS_FACTS: ClassVar[tuple[str, ...]] = ("components", "friction_prefix",
                                               "friction_unit")

    def __init_subclass__(cls, abstract: bool = False):
        # a kind that is missing part of the contract fails here, where it is defined,
        # not at the first state that needs the missing part (no super(): the slotted
        # dataclass is a copy of the class the zero-argument form would name)
        if abstract:
            return
        missing = [f for f in cls._CLASS_FACTS if not hasattr(cls, f)]
        missing += [n for n, v in vars(Pair).items()
                    if getattr(getattr(cls, n, None), "__isabstractmethod__", False)]
        if missing:
            shown = ", ".join(missing[:3]) + (", ..." if len(missing) > 3 else "")
            raise InputTypeError(f"pair kind {cls.__name__} leaves out {shown}")

    def between(self, a: str) -> Pair:
        """The same pair with body ``a`` named (a description's placeholder resolved)."""
        return dataclasses.replace(self, a=a)

    # -- the equations of the moving links ----------------------------------------------
    @abstractmethod
    def column_scale(self, length_scale):
        """The factor of the reaction's second component over its column of ``A x = b``
        (the columns are scaled so that every entry of ``A`` is of order one)."""

    @abstractmethod
    def entries(self, st, row: int, col: int, sign: float, arm: Vec) -> list:
        """The pair's entries ``(row, column, value)`` of ``A`` in the three equations of
        a body starting at ``row`` (forces x, y, moment about the centre of mass over the
        length scale), its reaction in columns ``col`` and ``col + 1``: ``sign`` +1 for
        body ``b``, -1 for body ``a``; ``arm`` the pair's point from the body's centre of
        mass, over the length scale."""

    @abstractmethod
    def reaction(self, st, first, second) -> tuple:
        """The action of ``a`` on ``b`` of the components ``first``, ``second`` (numbers
        or symbols) as ``(fx, fy, m)``: a force at the pair's point and a couple."""

    # -- friction ----------------------------------------------------------------------
    @abstractmethod
    def friction_rule(self, radius, length) -> str:
        """What is wrong with the friction values ``radius`` and ``length`` (None where
        not given) for this pair, or '' where they fit."""

    @abstractmethod
    def friction_law(self, xp, mu, radius, length, s, reaction, tiny: float) -> tuple:
        """The friction for the ``reaction`` and the motion sign ``s``, and its
        derivatives by the reaction's two components."""

    @abstractmethod
    def friction_formula(self, xp, mu, radius, length, s, first, second):
        """The friction of :meth:`friction_law` written plainly, for the equations shown
        (:mod:`linkage_fmu.free_body`): of the reaction's components ``first``,
        ``second`` (symbols or numbers; ``xp.sqrt``, and ``abs``)."""

    @abstractmethod
    def relative_motion(self, st, omega: Callable, velocity: Callable):
        """First-order coefficient of the motion friction opposes: of ``b`` relative to
        ``a``; ``omega(body)`` and ``velocity(body, point)`` give the bodies'."""

    @abstractmethod
    def apply_friction(self, st, f, couple: Callable, force: Callable) -> None:
        """Add the friction ``f`` (on ``b``; its opposite on ``a``) through
        ``couple(body, moment)`` or ``force(body, point, fx, fy)``."""

    @abstractmethod
    def friction_description(self) -> str:
        """The friction output's description."""

    # -- the force it transmits ----------------------------------------------------------
    @abstractmethod
    def force_output(self, axis: int, sign: float, rubs: bool) -> Callable:
        """``fn(R, E, st)``: component ``axis`` (0: x, 1: y) of the force of ``a`` on
        ``b`` times ``sign``; ``rubs``: the pair has friction (``R.friction``)."""

    @abstractmethod
    def magnitude_output(self) -> Callable:
        """``fn(R, E, st)``: the magnitude of the force the pair transmits."""

    @abstractmethod
    def action(self, R, st, sign: float, rubs: bool) -> tuple:
        """``(fx, fy, point, couple)``: the action of ``a`` on ``b`` times ``sign``, its
        friction included where it ``rubs``."""

    def guide(self, st) -> Vec | None:
        """The direction of a guide fixed in the frame that a picture draws, or None."""
        return None


@dataclass(frozen=True, slots=True)
class Revolute(Pair):
    """A pin: it transmits the force ``(Fx, Fy)`` of ``a`` on ``b`` at its point.

    Examples
    --------
    >>> pin = Revolute("B", "B", "2", "3")
    >>> pin.components, pin.friction_unit, pin.friction_rule(0.01, None)
    (('Fx', 'Fy'), 'N.m', '')
    >>> pin.friction_rule(None, 0.1)
    'a revolute pair has a mu and a radius (no length)'
    """

    components = ("Fx", "Fy")
    friction_prefix = "Mf"
    friction_unit = "N.m"
    draws_pin = True

    def column_scale(self, length_scale):
        return 1.0

    def entries(self, st, row, col, sign, arm):
        ax, ay = arm
        return [(row, col, sign), (row + 2, col, -sign * ay),
                (row + 1, col + 1, sign), (row + 2, col + 1, sign * ax)]

    def reaction(self, st, first, second):
        return first, second, 0

    def friction_rule(self, radius, length):
        if length is not None or radius is None:
            return "a revolute pair has a mu and a radius (no length)"
        return ""

    def friction_law(self, xp, mu, radius, length, s, reaction, tiny):
        a, b = reaction
        # |R| = sqrt(a^2 + b^2) with one square root and one reciprocal: the components
        # are scaled by a power of two (exact) only where a square would overflow (a
        # reaction over 1e150: with mu = 0, inf * 0 would be NaN) or lose its digits to
        # underflow, chosen without a branch (as a kernel's loop decides). The
        # derivatives are the unit vector's, 0 for R = 0 (where the root is 0 and its
        # reciprocal finite).
        big = xp.maximum(xp.abs(a), xp.abs(b))
        down, up = _above(big, _HUGE), _above(_SMALL, big)
        scale = _pick(down, _SHRINK, _pick(up, _GROW, 1.0))
        p, q = a * scale, b * scale
        root = xp.sqrt(p * p + q * q)
        k = -mu * radius * s
        inv = 1.0 / xp.maximum(root, _SMALL)
        size = root * _pick(down, _GROW, _pick(up, _SHRINK, 1.0))
        return k * size, k * (p * inv), k * (q * inv)

    def friction_formula(self, xp, mu, radius, length, s, first, second):
        return -mu * radius * s * xp.sqrt(first * first + second * second)

    def relative_motion(self, st, omega, velocity):
        return omega(self.b) - omega(self.a)

    def apply_friction(self, st, f, couple, force):
        for body, v in ((self.b, f), (self.a, -f)):
            couple(body, v)

    def friction_description(self):
        return (f"friction moment in the pin {self.name} of link {self.a} on link {self.b}, "
                f"counter-clockwise positive (it opposes the rotation of link {self.b} "
                f"relative to link {self.a}); link {self.b} acts on link {self.a} with its "
                "opposite")

    def force_output(self, axis, sign, rubs):
        return lambda R, E, st, name=self.name: sign * R[name][axis]

    def magnitude_output(self):
        def magnitude(R, E, st, name=self.name):
            a, b = R[name]
            return st.xp.sqrt(a * a + b * b)

        return magnitude

    def action(self, R, st, sign, rubs):
        name = self.name
        return (sign * R[name][0], sign * R[name][1], self.point,
                sign * R.friction[name] if rubs else 0.0)


@dataclass(frozen=True, slots=True)
class Prismatic(Pair):
    """A slider in a guide: it transmits the force ``N`` of ``a`` on ``b`` along the
    guide's ``normal`` through its point, and a couple ``M``. The normal is a unit
    vector ``(nx, ny)`` fixed in the frame, or the name of the link whose left normal it
    is (a guide on a moving link).

    Examples
    --------
    >>> slider = Prismatic("P", "C", "1", "4", (0.0, 1.0))
    >>> slider.components, slider.friction_unit, slider.guide(None)
    (('N', 'M'), 'N', (0.0, 1.0))
    >>> slider.friction_rule(0.01, None)
    'a prismatic pair has a mu and optionally a length (no radius)'
    """

    normal: Vec | str = (0.0, 1.0)

    components = ("N", "M")
    friction_prefix = "Ff"
    friction_unit = "N"

    def normal_at(self, st) -> Vec:
        """The unit normal at the state ``st``."""
        if isinstance(self.normal, str):
            t = st.u[self.normal]
            return -t[1], t[0]
        return self.normal

    def tangent(self, st) -> Vec:
        """The sliding direction: the one whose left normal is the normal."""
        nx, ny = self.normal_at(st)
        return ny, -nx

    def column_scale(self, length_scale):
        return length_scale

    def entries(self, st, row, col, sign, arm):
        ax, ay = arm
        nx, ny = self.normal_at(st)
        return [(row, col, sign * nx), (row + 1, col, sign * ny),
                (row + 2, col, sign * (ax * ny - ay * nx)), (row + 2, col + 1, sign)]

    def reaction(self, st, first, second):
        nx, ny = self.normal_at(st)
        return first * nx, first * ny, second

    def friction_rule(self, radius, length):
        if radius is not None:
            return "a prismatic pair has a mu and optionally a length (no radius)"
        return ""

    def friction_law(self, xp, mu, radius, length, s, reaction, tiny):
        a, b = reaction
        k = -mu * s
        if length is None:
            return k * xp.abs(a), k * xp.sign(a), 0.0 * a
        n1, n2 = 0.5 * a - b / length, 0.5 * a + b / length
        s1, s2 = xp.sign(n1), xp.sign(n2)
        return k * (xp.abs(n1) + xp.abs(n2)), k * 0.5 * (s1 + s2), k * (s2 - s1) / length

    def friction_formula(self, xp, mu, radius, length, s, first, second):
        if length is None:
            return -mu * s * abs(first)
        return -mu * s * (abs(first / 2 - second / length) + abs(first / 2 + second / length))

    def relative_motion(self, st, omega, velocity):
        (ax, ay), (bx, by) = velocity(self.a, self.point), velocity(self.b, self.point)
        tx, ty = self.tangent(st)
        return (bx - ax) * tx + (by - ay) * ty

    def apply_friction(self, st, f, couple, force):
        tx, ty = self.tangent(st)
        force(self.b, self.point, f * tx, f * ty)
        force(self.a, self.point, -f * tx, -f * ty)

    def friction_description(self):
        along = (f"the direction of link {self.normal}" if isinstance(self.normal, str) else
                 "the pair's sliding direction t = (n_y, -n_x), its normal n turned 90 deg "
                 "clockwise")
        return (f"friction force in the prismatic pair {self.name} of link {self.a} on link "
                f"{self.b}, positive along {along} (it opposes the sliding of link {self.b} "
                f"on link {self.a}); link {self.b} acts on link {self.a} with its opposite")

    def force_output(self, axis, sign, rubs):
        i = axis
        if rubs:  # the normal force and the friction along the pair

            def force(R, E, st, name=self.name):
                nx, ny = self.normal_at(st)
                return sign * (R[name][0] * (nx, ny)[i] + R.friction[name] * (ny, -nx)[i])

            return force
        if isinstance(self.normal, str):  # a guide on a moving link
            return lambda R, E, st, name=self.name: sign * self.normal_at(st)[i] * R[name][0]
        k = sign * self.normal[i]
        return lambda R, E, st, name=self.name: k * R[name][0]

    def magnitude_output(self):
        return lambda R, E, st, name=self.name: st.xp.abs(R[name][0])  # the normal force

    def action(self, R, st, sign, rubs):
        name = self.name
        nx, ny = self.normal_at(st)
        n = sign * R[name][0]
        fx, fy = n * nx, n * ny
        if rubs:
            f = sign * R.friction[name]
            fx, fy = fx + f * ny, fy - f * nx
        return fx, fy, self.point, sign * R[name][1]

    def guide(self, st):
        return None if isinstance(self.normal, str) else self.normal
