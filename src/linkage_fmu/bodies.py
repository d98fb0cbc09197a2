"""The parts of a linkage that are not groups: the moving bodies' inertia, and where the
balancing effort acts."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

from . import numerics
from .errors import InputError
from .groups import LinkPoint
from .kernels.trace import Reason

_REAL = ("mass", "inertia", "along", "across", "distance", "angle")


@dataclass(frozen=True)
class Body:
    """A moving link: mass, moment of inertia about its centre of mass ``S``, and where
    ``S`` is in the link's own frame, measured from the link's point ``ref``: ``along``
    the link's direction and ``across`` to its left (counter-clockwise); or, with
    ``distance``, that far from ``ref`` in the direction ``angle`` counter-clockwise
    from the link's.

    Examples
    --------
    >>> Body("2", mass=2.0, inertia=0.02, ref="B", along=0.175).cg
    'S2'
    >>> Body("2", mass=-1.0, ref="B")
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError: mass of body '2' must be a finite number >= 0, got -1.0
    """

    name: str
    mass: float = 0.0
    inertia: float = 0.0
    ref: str = ""
    along: float = 0.0
    across: float = 0.0
    distance: float | None = None  # given: the centre of mass is placed by distance/angle
    angle: float = 0.0

    def __post_init__(self):
        traced = [a for a in _REAL if hasattr(getattr(self, a), "traced")]
        for attr in ("mass", "inertia"):
            v = getattr(self, attr)
            rule = f"{attr} of body {self.name!r} must be a finite number >= 0"
            if attr in traced:  # a parameter of a kernel: its parameter step checks it
                v >= 0.0  # noqa: B015 -- recorded as a check
                numerics.label(v, Reason("parameter", rule))
            elif not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise InputError(f"{rule}, got {v!r}")
        for attr in ("along", "across", "distance", "angle"):
            v = getattr(self, attr)
            if (v is None and attr == "distance") or attr in traced:
                continue  # traced: the builder checked that it is finite
            if not (isinstance(v, (int, float)) and math.isfinite(v)):
                raise InputError(f"{attr} of the centre of mass of body {self.name!r} must be "
                                 f"a finite number, got {v!r}")
        if not traced and self.distance is not None and (self.along or self.across):
            raise InputError(f"body {self.name!r}: give the centre of mass as along/across or "
                             "as distance/angle, not both")
        if not self.ref:
            raise InputError(f"body {self.name!r} needs the point 'ref' its centre of mass is "
                             "measured from")

    @functools.cached_property
    def offset(self) -> float:
        """Distance of the centre of mass from ``ref``."""
        if self.distance is not None:
            return abs(self.distance)
        return numerics.hypot(self.along, self.across)

    @functools.cached_property  # read for every body at every state
    def cg(self) -> str:
        """Name of the point at the centre of mass."""
        return self.ref if self.offset == 0.0 else f"S{self.name}"

    def cg_point(self) -> LinkPoint:
        """The centre of mass as a point fixed on the link."""
        if self.distance is not None:
            return LinkPoint(self.name, self.ref, self.cg, distance=self.distance,
                             angle=self.angle)
        return LinkPoint(self.name, self.ref, self.cg, self.along, self.across)


@dataclass(frozen=True)
class Effort:
    """The balancing effort: a moment on link ``body`` (``direction=None``), or a force
    on ``body`` at ``point`` along the unit vector ``direction`` (fixed in the frame) or
    along a link's direction (``direction`` its name: a cylinder's force along its
    barrel); a driver's reaction acts on ``base`` (a motor's base link, a cylinder's
    barrel; '' for a balancing effort, which the frame takes).

    Examples
    --------
    >>> Effort("Fb_P", "rod", "C", "barrel", "barrel").direction
    'barrel'
    """

    name: str
    body: str
    point: str = ""
    direction: tuple | str | None = None
    base: str = ""
