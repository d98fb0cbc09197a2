"""An optimisation's convergence: the best feasible objective over the generations
(:func:`convergence`)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..printing import number
from .figures import figure_axes

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


# the result's type is named, not imported: linkage_fmu.optimize imports this module
def convergence(result: "OptimizationResult", ax: "Axes | None" = None) -> "Figure":  # noqa: F821
    """The best feasible value of the objective of ``result``
    (:func:`~linkage_fmu.optimize.optimize`) against the generation: a step line over
    the global search (a grid is one generation) and a point for the polish, one
    generation after it.

    Parameters
    ----------
    result : OptimizationResult
        Its ``history`` is drawn.
    ax : matplotlib Axes, optional
        Where to draw; a new figure if None.

    Returns
    -------
    Figure
        Lines (gid): ``"best"`` (the best feasible objective after each generation of
        the global search; none before the first feasible design) and ``"polish"`` (one
        point, after the polish, if there was one); a marker ``"optimum"``, the value
        returned, at the last generation.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> from linkage_fmu.optimize import optimize
    >>> res = optimize("four_bar", {"l_AB": (0.05, 0.15)}, "Mb_peak", ["valid"],
    ...                omega=10.0, maxiter=3, seed=0)
    >>> fig = res.plot()
    >>> [line.get_gid() for line in fig.axes[0].lines]
    ['best', 'polish', 'optimum']
    """
    history = result.history
    fig, ax = figure_axes(ax)
    search = history[history["stage"] == "global"]
    polish = history[history["stage"] == "polish"]
    generation = search["generation"].to_numpy(dtype=np.float64)
    best = search["best"].to_numpy(dtype=np.float64)
    name = result.objective.lstrip("-")
    ax.plot(generation, best, drawstyle="steps-post", color="C0", lw=1.6, marker=".",
            label=f"best feasible {name}, {result.method.replace('_', ' ')}", gid="best")
    if len(polish):
        g = float(polish["generation"].iloc[-1])
        ax.plot([generation[-1], g], [best[-1], float(polish["best"].iloc[-1])], color="C1",
                lw=1.2, ls="--", marker="o", markevery=[1], label="after the polish (Nelder-Mead)",
                gid="polish")
    last = float(history["generation"].iloc[-1])
    ax.plot([last], [result.value], "*", color="C3", ms=12,
            label=f"optimum {name} = {number(result.value, 6)}", gid="optimum")
    ax.set_xlabel("generation" + (" (the last: the polish)" if len(polish) else ""))
    ax.set_ylabel(name)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=9)
    subject = ", ".join(map(str, result.constraints)) or "no constraint"
    what = "maximise" if result.objective.startswith("-") else "minimise"
    ax.set_title(f"{what} {name} subject to {subject}\n{result.evaluations} evaluations, "
                 f"{number(result.seconds, 3)} s",
                 fontsize=10)
    return fig
