"""Ranges of crank angles: where a linkage assembles, and runs of angles in words.

A linkage whose crank cannot turn a full revolution (a Grashof rocker-rocker, a crank
too long for its coupler) assembles over one or more ranges of the crank angle; the
build, the FMU check and the table command say which.

Examples
--------
>>> from linkage_fmu import presets
>>> text(assembles(presets.get("four_bar", l_AB=0.3)))
'0 to 135.95 and 224.05 to 360 deg'
>>> text(assembles(presets.get("four_bar")))
'0 to 360 deg'
"""

from __future__ import annotations

import math

import numpy as np

from .errors import AssemblyError
from .printing import number

#: samples of a revolution before the ends of each range are refined
SAMPLES = 3600


def runs(values: np.ndarray, ok: np.ndarray) -> list[tuple[float, float]]:
    """``(first, last)`` of ``values`` over each run of consecutive ``ok``.

    Examples
    --------
    >>> runs(np.arange(6.0), np.array([1, 1, 0, 1, 1, 1], bool))
    [(0.0, 1.0), (3.0, 5.0)]
    """
    ok = np.asarray(ok, dtype=bool)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.view(np.int8), [0]])))
    return [(float(values[a]), float(values[b - 1])) for a, b in zip(edges[::2], edges[1::2])]


def text(ranges: list[tuple[float, float]], unit: str = "deg", digits: int = 5) -> str:
    """The ranges in words, ``'0 to 135.95 and 224.05 to 360 deg'``; ``'none'`` for
    no range, one angle alone as itself.

    Examples
    --------
    >>> text([(-0.0, 135.9500001), (224.05, 360.0)]), text([(90.0, 90.0)]), text([])
    ('0 to 135.95 and 224.05 to 360 deg', '90 deg', 'none')
    """
    if not ranges:
        return "none"
    parts = [number(a, digits) if a == b else f"{number(a, digits)} to {number(b, digits)}"
             for a, b in ranges]
    return (", ".join(parts[:-1]) + " and " + parts[-1] if len(parts) > 1 else parts[0]) + \
        f" {unit}"


def assembles(mech, samples: int = SAMPLES) -> list[tuple[float, float]]:
    """The ranges of the crank angle over ``[0, 360]`` deg where ``mech`` assembles,
    each end found to 1e-9 rad by bisection between the samples.

    A range that ends between two samples is found; one shorter than a sample step
    (360 / ``samples`` deg) may be missed.
    """
    theta = np.linspace(0.0, 2.0 * math.pi, samples + 1)
    st = mech.kinematics(theta, order=0)
    ok = np.ones(theta.size, bool) if st.invalid is None else ~st.invalid
    out = []
    for a, b in runs(np.arange(theta.size, dtype=float), ok):
        i, j = int(a), int(b)
        lo = theta[i] if i == 0 else _edge(mech, theta[i - 1], theta[i])
        hi = theta[j] if j == theta.size - 1 else _edge(mech, theta[j + 1], theta[j])
        out.append((math.degrees(lo), math.degrees(hi)))
    return out


def _edge(mech, bad: float, good: float) -> float:
    """The angle between ``bad`` (does not assemble) and ``good`` (does) where it starts
    to, to 1e-9 rad."""
    while abs(good - bad) > 1e-9:
        mid = 0.5 * (bad + good)
        try:
            mech.kinematics(mid, order=0)
            good = mid
        except AssemblyError:
            bad = mid
    return good
