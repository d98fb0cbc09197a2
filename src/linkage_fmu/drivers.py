"""The drivers of a linkage: which pair each one drives, its inputs and its effort.

A :class:`Driver` is data: the pair it moves, its kind (an angle or a travel), the
names and units of its coordinate, speed and acceleration inputs, and the name of the
effort output it needs. The mechanism holds a tuple of them (``mech.drivers``), from
which its inputs are named and its mobility checked; nothing else names a driver's
inputs.

Examples
--------
>>> crank = Driver.named("A", "angle", "Mb")
>>> crank.inputs, crank.units, crank.effort
(('theta', 'omega', 'alpha'), ('rad', 'rad/s', 'rad/s2'), 'Mb')
>>> Driver.named("C", "travel", "Fb_C", alone=False).inputs
('s_C', 'v_C', 'a_C')
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from .errors import InputError
from .units import MOTION_UNITS

#: kind -> the names of its coordinate, speed and acceleration (a linkage's one crank
#: takes them as they are; a linkage driven by time, by several drivers, a motor between
#: two links or a cylinder, adds each driver's pair: ``theta_A``, ``s_P``) and their units
KINDS: dict[str, tuple[tuple[str, str, str], tuple[str, str, str]]] = {
    "angle": (tuple(MOTION_UNITS), tuple(MOTION_UNITS.values())),
    "travel": (("s", "v", "a"), ("m", "m/s", "m/s2")),
}
#: kind -> what its coordinate, speed and acceleration are, in words
MEANINGS: dict[str, tuple[str, str, str]] = {
    "angle": ("angle of the driven link (from +x, or from its first link's direction for "
              "a motor), counter-clockwise", "angular speed", "angular acceleration"),
    "travel": ("travel from the drawn length, > 0 extending", "speed of travel",
               "acceleration of travel"),
}
#: kind -> the name of its effort: a moment for an angle (``Mb``, ``Mb_A``: on the
#: driver's second link), a force for a travel (``Fb_P``: on a cylinder's rod, > 0
#: pushing its pins apart)
EFFORTS: dict[str, str] = {"angle": "Mb", "travel": "Fb"}


@dataclass(frozen=True)
class Driver:
    """A driver: the pair ``name`` it drives, its ``kind`` (a key of :data:`KINDS`),
    its coordinate, speed and acceleration ``inputs`` with their ``units``, and the name
    of its ``effort`` output (the moment or force it applies).

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> (crank,) = presets.get("slider_crank").drivers
    >>> crank.name, crank.kind, crank.inputs, crank.effort
    ('O', 'angle', ('theta', 'omega', 'alpha'), 'Mb')
    """

    name: str
    kind: str
    inputs: tuple[str, str, str]
    units: tuple[str, str, str]
    effort: str

    #: the kinds a driver may be
    kinds: ClassVar[tuple[str, ...]] = tuple(KINDS)

    @classmethod
    def named(cls, pair: str, kind: str, effort: str | None, alone: bool = True) -> Driver:
        """The driver of ``pair`` with its inputs named: a linkage's only driver
        (``alone``) takes its kind's names as they are (``theta``, ``omega``,
        ``alpha``), one of several adds its pair's (``theta_A``); an ``effort`` None
        is named likewise (``Mb``, ``Mb_A``, ``Fb_P``: :data:`EFFORTS`).

        Raises
        ------
        ValueError
            A kind that is none of :data:`KINDS`.

        Examples
        --------
        >>> Driver.named("A", "angle", "Mb_A", alone=False).inputs
        ('theta_A', 'omega_A', 'alpha_A')
        >>> Driver.named("P", "travel", None, alone=False).effort
        'Fb_P'
        >>> Driver.named("A", "rotary", "Mb")
        Traceback (most recent call last):
        ...
        linkage_fmu.errors.InputError: the driver of A: a driver's kind is one of angle,
        travel, not 'rotary'
        """
        if kind not in KINDS:
            raise InputError(f"the driver of {pair}: a driver's kind is one of "
                             f"{', '.join(KINDS)}, not {kind!r}")
        names, units = KINDS[kind]
        inputs = names if alone else tuple(f"{n}_{pair}" for n in names)
        if effort is None:
            effort = EFFORTS[kind] if alone else f"{EFFORTS[kind]}_{pair}"
        return cls(pair, kind, inputs, units, effort)

    def meaning(self, k: int) -> str:
        """What its input ``k`` (0 the coordinate, 1 the speed, 2 the acceleration) is.

        Examples
        --------
        >>> Driver.named("P", "travel", None, alone=False).meaning(0)
        'travel from the drawn length, > 0 extending, of the driver at P'
        """
        return f"{MEANINGS[self.kind][k]}, of the driver at {self.name}"


def input_names(drivers: tuple[Driver, ...]) -> tuple[str, ...]:
    """The drivers' inputs in a linkage's order: each driver's coordinate, speed and
    acceleration, driver by driver.

    Examples
    --------
    >>> input_names((Driver.named("A", "angle", "Mb"),))
    ('theta', 'omega', 'alpha')
    """
    return tuple(n for d in drivers for n in d.inputs)


def input_units(drivers: tuple[Driver, ...]) -> dict[str, str]:
    """Input name -> unit, for the drivers' inputs.

    Examples
    --------
    >>> input_units((Driver.named("C", "travel", "Fb"),))
    {'s': 'm', 'v': 'm/s', 'a': 'm/s2'}
    """
    return {n: u for d in drivers for n, u in zip(d.inputs, d.units)}


def one_crank(mech, job: str) -> None:
    """Refuse, saying why, a ``job`` that takes a linkage driven by one crank on the
    frame for the linkage ``mech`` driven by time (several drivers, a motor, a
    cylinder), which its ``solve`` serves.

    Examples
    --------
    >>> from linkage_fmu import presets
    >>> one_crank(presets.get("four_bar"), "the reduced inertia")
    """
    if mech.rates:
        drivers = ", ".join(d.inputs[0] for d in mech.drivers)
        raise InputError(f"{mech.name} is driven by time ({drivers}): {job} takes a linkage "
                         "driven by one crank on the frame, so far; solve (its kernels, its "
                         "FMUs), mass_matrix and simulate take this one")
