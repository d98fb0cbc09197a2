"""matplotlib for the plots, imported only when one is drawn; the figure and axes to
draw in, the crank-angle axis, and names as drawn."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..errors import DependencyError

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

_INSTALL = ('linkage_fmu.plot needs matplotlib (>= 3.7): pip install "linkage_fmu[plot]" '
            "(or pip install matplotlib)")


def pyplot():
    """matplotlib.pyplot, or an ImportError that says how to install it."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as err:
        raise DependencyError(_INSTALL) from err
    return plt


def figure_axes(ax: "Axes | None", figsize=(8.0, 4.5)) -> tuple["Figure", "Axes"]:
    """``(figure, ax)``: the given axes' figure, or a new figure with one axes."""
    if ax is not None:
        return ax.figure, ax
    fig, ax = pyplot().subplots(figsize=figsize, layout="constrained")
    return fig, ax


def degree_axis(ax: "Axes", deg: np.ndarray) -> None:
    """The crank angle [deg] on the horizontal axis: its label, limits, ticks and grid."""
    ax.set_xlabel("crank angle θ [°]")
    lo, hi = float(np.min(deg)), float(np.max(deg))
    if hi > lo:
        ax.set_xlim(lo, hi)
        step = 45.0 if hi - lo <= 360.0 else 90.0
        ax.set_xticks(np.arange(math.ceil(lo / step) * step, hi + 1e-9, step))
    ax.grid(True, alpha=0.3)


def greek(name: str) -> str:
    """``name`` as drawn: a transmission angle ``gamma_<joint>`` with the letter γ."""
    return "γ" + name[5:] if name.startswith("gamma_") else name
