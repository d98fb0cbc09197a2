"""Design optimisation over the sweep engine: the values of some parameters, each within
bounds, that minimise a summary of :func:`~linkage_fmu.sweep.sweep` (``Mb_peak``,
``F21_peak``, ...) subject to constraints on the summaries (``"gamma_C_min_deg >= 40"``,
``"valid"``).

Every evaluation is a design of a sweep: a generation of differential evolution is one
sweep over its population, a grid is one sweep, and both can run on a Dask cluster as a
sweep does. A constraint is a summary's name, an operator among ``<=``, ``>=``, ``<``,
``>`` and a number (:func:`parse_constraint`; the text is parsed, never evaluated), or
``valid``: the design assembles at every angle and friction locks it at none.

Examples
--------
>>> from linkage_fmu.optimize import optimize
>>> vary = {"l_BC": (0.30, 0.45), "l_CD": (0.25, 0.40)}
>>> limits = ["gamma_C_min_deg >= 45", "valid"]
>>> coarse = optimize("four_bar", vary, "Mb_peak", limits, omega=10.0,
...                   method="grid", budget=16, polish=False)
>>> coarse.design, coarse.evaluations                 # the best of a 4 x 4 grid
({'l_BC': 0.4, 'l_CD': 0.3}, 16)
>>> best = optimize("four_bar", vary, "Mb_peak", limits, omega=10.0,
...                 method="grid", budget=16)         # and a polish from there
>>> # on the bound
>>> round(best.value, 3), round(float(best.summary["gamma_C_min_deg"]), 3)
(2.376, 45.0)
"""

from __future__ import annotations

import contextlib
import inspect
import math
import re
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from .drivers import one_crank
from .errors import InputError, InputTypeError, LinkageFmuError
from .presets import linkage
from .printing import number
from .sweep import STATES_PER_TASK, dask_client, sweep

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: the methods of :func:`optimize`
METHODS = ("differential_evolution", "grid")
#: the comparisons a constraint may make
OPERATORS = ("<=", ">=", "<", ">")
#: the penalised objective of a design that assembles but breaks a constraint is
#: INFEASIBLE * (1 + its violation): above every feasible objective smaller than this
INFEASIBLE = 1e20
#: the penalised objective of a design whose objective is not a number (its parameters
#: cannot be built, or it assembles at no angle): above every other
UNUSABLE = 1e40
#: the parameter kinds that take discrete values, which cannot be varied within bounds
_DISCRETE = ("branch", "choice", "sign")
#: a polish ends when its simplex is this small, as a fraction of each parameter's range
POLISH_XTOL = 1e-4
#: the polish's first simplex: steps of this fraction of each range from its start (DE)
POLISH_STEP = 0.05


class NoFeasibleDesignError(LinkageFmuError, ValueError):
    """No design evaluated met every constraint. ``result`` holds the search: its
    ``design`` is the one that broke them least (``feasible`` False), and its history."""

    def __init__(self, message: str, result: "OptimizationResult"):
        super().__init__(message)
        self.result = result


@dataclass(frozen=True)
class Constraint:
    """A constraint on a design's summaries: ``name op value`` (``op`` one of
    :data:`OPERATORS`), or, with ``op`` None, the design is ``valid`` (assembles at every
    angle, and friction locks it at none).

    Examples
    --------
    >>> c = Constraint("gamma_C_min_deg", ">=", 40.0)
    >>> table = pd.DataFrame({"gamma_C_min_deg": [39.0, 40.0, np.nan]})
    >>> str(c), c.satisfied(table).tolist()
    ('gamma_C_min_deg >= 40', [False, True, False])
    """

    name: str
    op: str | None = None
    value: float | None = None

    def __str__(self) -> str:
        return self.name if self.op is None else f"{self.name} {self.op} {number(self.value, 12)}"

    def satisfied(self, table: pd.DataFrame) -> np.ndarray:
        """Whether each row of the sweep ``table`` meets the constraint (a NaN summary
        does not)."""
        if self.op is None:
            return table[self.name].to_numpy(dtype=bool)
        x = table[self.name].to_numpy(dtype=np.float64)
        with np.errstate(invalid="ignore"):
            return {"<=": x <= self.value, ">=": x >= self.value, "<": x < self.value,
                    ">": x > self.value}[self.op]

    def violation(self, table: pd.DataFrame, angles: int) -> np.ndarray:
        """How far each row of the sweep ``table`` is from meeting the constraint, >= 0:
        the distance past the bound relative to the bound (absolute for a bound 0), 1
        for a NaN summary; for ``valid``, the fraction of the ``angles`` at which the
        design does not assemble or friction locks it."""
        if self.op is None:
            return (table["unassembled"].to_numpy(dtype=np.float64)
                    + table["locked"].to_numpy(dtype=np.float64)) / angles
        x = table[self.name].to_numpy(dtype=np.float64)
        scale = abs(self.value) if self.value != 0.0 else 1.0
        beyond = (x - self.value if self.op in ("<=", "<") else self.value - x) / scale
        return np.where(np.isnan(x), 1.0, np.maximum(beyond, 0.0))


_CONSTRAINT = re.compile(r"\s*([A-Za-z_]\w*)\s*(<=|>=|<|>)\s*([^\s<>=]+)\s*")


def parse_constraint(spec: str | Constraint | tuple) -> Constraint:
    """A constraint from text ``"NAME OP VALUE"`` (``OP`` one of ``<=``, ``>=``, ``<``,
    ``>``; ``VALUE`` a finite number in the summary's unit, as the sweep gives it) or
    ``"valid"``, from a tuple ``(name, op, value)``, or a :class:`Constraint` as it is.
    The text is matched, never evaluated.

    Raises
    ------
    ValueError
        Text of another form, another operator, a value that is not a finite number:
        naming the constraint.

    Examples
    --------
    >>> parse_constraint("gamma_C_min_deg >= 40")
    Constraint(name='gamma_C_min_deg', op='>=', value=40.0)
    >>> parse_constraint(" valid ")
    Constraint(name='valid', op=None, value=None)
    >>> str(parse_constraint("eta_min >= 0.85"))
    'eta_min >= 0.85'
    >>> str(parse_constraint("Mb_mean <= -0.0"))
    'Mb_mean <= 0'
    >>> parse_constraint("F21_peak == 500")
    Traceback (most recent call last):
    ...
    linkage_fmu.errors.InputError:
    constraint 'F21_peak == 500': expected NAME OP VALUE with OP one of
    <=, >=, <, > (as in 'gamma_C_min_deg >= 40'), or 'valid'
    """
    if isinstance(spec, Constraint):
        return spec
    if isinstance(spec, tuple):
        if len(spec) != 3 or spec[1] not in OPERATORS or not isinstance(spec[0], str):
            raise InputError(f"constraint {spec!r}: expected (name, op, value) with op one "
                             f"of {', '.join(OPERATORS)}")
        name, op, text = spec
    elif isinstance(spec, str):
        if spec.strip() == "valid":
            return Constraint("valid")
        found = _CONSTRAINT.fullmatch(spec)
        if found is None:
            raise InputError(f"constraint {spec!r}: expected NAME OP VALUE with OP one of "
                             f"{', '.join(OPERATORS)} (as in 'gamma_C_min_deg >= 40'), or "
                             "'valid'")
        name, op, text = found.groups()
    else:
        raise InputTypeError(f"constraint {spec!r}: expected text such as 'gamma_C_min_deg >= 40', "
                             "'valid', or a tuple (name, op, value)")
    try:
        value = float(text)
    except (TypeError, ValueError):
        value = math.nan
    if isinstance(text, bool) or not math.isfinite(value):
        raise InputError(f"constraint {spec!r}: the value {text!r} is not a finite number")
    return Constraint(name, op, value)


@dataclass(frozen=True, eq=False)
class OptimizationResult:
    """The best design an optimisation found (:func:`optimize`).

    Attributes
    ----------
    design : dict
        The varied parameters' values.
    summary : Series
        The design's row of the sweep: its parameters and every summary.
    objective : str
        The summary minimised (``-name``: maximised), and ``value``, its value.
    constraints : tuple of Constraint
        What the design meets (``feasible``), or, when no design met them all (see
        :class:`NoFeasibleDesignError`), the design that broke them least.
    method : str
        ``"differential_evolution"`` or ``"grid"``.
    evaluations : int
        Designs solved over the revolution (each a row of a sweep), the polish's included.
    seconds : float
        Wall time of the optimisation.
    history : DataFrame
        One row per sweep of the global search (``stage`` "global"; for
        differential evolution, generation 0 is the initial population) and one for the
        polish (``stage`` "polish"): ``generation``, ``evaluations`` so far,
        ``feasible`` designs in that step, and ``best``, the best feasible value of
        the objective so far (NaN before there is one).
    """

    design: dict
    summary: pd.Series
    objective: str
    value: float
    constraints: tuple
    method: str
    evaluations: int
    seconds: float
    history: pd.DataFrame
    feasible: bool = True

    def __str__(self) -> str:
        name = self.objective.lstrip("-")
        what = "maximise" if self.objective.startswith("-") else "minimise"
        head = (f"{what} {name} subject to {', '.join(map(str, self.constraints)) or 'nothing'}"
                f" ({self.method}, {self.evaluations} evaluations, {number(self.seconds, 3)} s)")
        lines = [head, ("best design:" if self.feasible else
                        "no design meets every constraint; the one that breaks them least:")]
        lines += [f"  {k} = {number(v, 10)}" for k, v in self.design.items()]
        lines.append("its summaries:")
        for k, v in self.summary.items():
            if k not in self.design and k != "problem":
                lines.append(f"  {k} = {number(v, 10)}" if isinstance(v, (float, np.floating))
                             else f"  {k} = {v}")
        return "\n".join(lines)

    def plot(self, ax: "Axes | None" = None) -> "Figure":
        """The best feasible objective over the generations
        (:func:`linkage_fmu.plot.convergence`)."""
        from .plot.convergence import convergence

        return convergence(self, ax=ax)


def optimize(source, vary: Mapping[str, tuple], minimize: str,
             subject_to: Sequence = (), *, theta=None, omega: float | None = None,
             alpha: float | None = None, loads: Sequence[float] = (),
             method: str = "differential_evolution", budget: int | None = None,
             maxiter: int = 100, popsize: int = 15, tol: float = 0.0,
             seed: int | None = None, polish: bool = True, scheduler=None,
             progress: bool = False, **named_loads: float) -> OptimizationResult:
    """The design of the linkage ``source`` within the bounds ``vary`` that minimises the
    sweep's summary ``minimize`` subject to the constraints ``subject_to``.

    Infeasible designs are handled by a penalty, not by scipy's ``NonlinearConstraint``:
    a design that meets every constraint scores its objective; one that assembles but
    breaks a constraint scores ``INFEASIBLE * (1 + v)``, ``v`` the sum of its relative
    violations (:meth:`Constraint.violation`), above any feasible design and lower the
    nearer it is to feasible; one whose objective is not a number (invalid parameters, or
    no angle assembles) scores ``UNUSABLE``, worst. So a generation is still one sweep
    (scipy evaluates a ``NonlinearConstraint`` per member, apart from the vectorised
    objective), and the same function serves the grid and the polish (Nelder-Mead, which
    takes no constraints; scipy's constrained polish, trust-constr, needs gradients the
    peak summaries do not have). The design returned is the best feasible one among all
    evaluated, so it meets every constraint.

    Parameters
    ----------
    source
        The linkage: a preset, a description file, a Description or a Mechanism (its
        parameter values are the fixed ones).
    vary : mapping of name to (lo, hi)
        The parameters varied and their bounds, ``lo < hi``, both valid values of the
        parameter (numbers in SI, or text with a unit: ``("50 mm", "150 mm")``).
    minimize : str
        A summary column of the sweep (``"Mb_peak"``, ``"F21_peak"``, ...); ``"-name"``
        maximises it (``"-eta_min"``).
    subject_to : sequence of str, tuple or Constraint
        Constraints (:func:`parse_constraint`): ``"gamma_C_min_deg >= 40"``, ``"valid"``.
        Without ``valid``, a design that assembles over part of the revolution is
        judged on the summaries of the angles where it does.
    theta, omega, alpha, loads, **named_loads
        The states of every design, as :func:`~linkage_fmu.sweep.sweep` takes them
        (``loads`` the loads by position after ``alpha``).
    method : {"differential_evolution", "grid"}
        ``scipy.optimize.differential_evolution`` (``vectorized=True``,
        ``updating="deferred"``: a generation is one sweep over its population), or a
        grid of ``budget`` designs at most, every combination of evenly spaced values of
        each parameter, bounds included.
    budget : int, optional
        The global search's evaluations at most. Default: differential evolution's with
        ``maxiter`` generations, ``max(5, popsize * len(vary)) * (maxiter + 1)``; for
        differential evolution it caps the generations at ``budget // population - 1``.
    maxiter, popsize, tol
        Differential evolution's generations after the first at most, population per
        parameter, and relative tolerance of convergence (as scipy takes them). The
        default tol, 0, runs every generation: with scipy's default, 0.01, the search
        may stop at a local optimum (the four-bar over four lengths,
        ``benchmarks/optimize_timing.py``, stopped in one of two basins depending on
        the seed, after a quarter of the evaluations).
    seed : int, optional
        The random generator's seed: with it, the same result every run.
    polish : bool
        Refine the best feasible design with a bounded Nelder-Mead on the penalised
        objective (a simplex of :data:`POLISH_STEP` of each range for differential
        evolution, of the grid's spacing for a grid, until it is :data:`POLISH_XTOL` of
        each range, or ``200 * len(vary)`` evaluations), design by design in this process.
    scheduler : None, "local", a Dask Client or an address
        Where the sweeps of the global search run (as :func:`~linkage_fmu.sweep.sweep`);
        one cluster serves every generation.
    progress : bool
        A progress bar (tqdm) over the generations (for a grid: the sweep's).

    Returns
    -------
    OptimizationResult

    Raises
    ------
    TypeError
        A parameter the linkage does not have, naming it and the linkage's parameters.
    ValueError
        Bounds with ``lo >= hi``, or outside the parameter's valid values; a parameter
        that takes discrete values; an objective or constraint that is not a summary of
        the sweep, naming them and the summaries; an unknown method; a budget smaller
        than a population (or than two values per parameter for a grid); a negative
        tol.
    NoFeasibleDesignError
        No design evaluated meets every constraint; its ``result`` holds the search.

    Examples
    --------
    >>> res = optimize("four_bar", {"l_AB": (0.05, 0.15)}, "Mb_peak",
    ...                ["gamma_C_min_deg >= 40"], omega=10.0, maxiter=5, seed=1)
    >>> res.history.columns.tolist()
    ['generation', 'stage', 'evaluations', 'feasible', 'best']
    >>> res.history["stage"].tolist()[-2:]
    ['global', 'polish']
    """
    start = time.perf_counter()
    mech = linkage(source)
    one_crank(mech, "an optimisation over crank angles")
    names, lo, hi = _bounds(mech, vary)
    if method not in METHODS:
        raise InputError(f"method {method!r}: expected one of {', '.join(METHODS)}")
    sign, objective = (-1.0, minimize[1:]) if minimize.startswith("-") else (1.0, minimize)
    constraints = tuple(parse_constraint(c) for c in subject_to)
    if isinstance(popsize, bool) or not isinstance(popsize, int) or popsize < 1:
        raise InputError(f"popsize must be an integer >= 1, got {popsize!r}")
    if isinstance(maxiter, bool) or not isinstance(maxiter, int) or maxiter < 0:
        raise InputError(f"maxiter must be an integer >= 0, got {maxiter!r}")
    if not (isinstance(tol, (int, float)) and not isinstance(tol, bool) and tol >= 0):
        raise InputError(f"tol must be a number >= 0, got {tol!r}")
    population = max(5, popsize * len(names))
    if budget is None:
        budget = population * (maxiter + 1)
    elif isinstance(budget, bool) or not isinstance(budget, (int, np.integer)) or budget < 1:
        raise InputError(f"budget must be an integer >= 1, got {budget!r}")
    theta = (np.linspace(0.0, 2.0 * math.pi, 360, endpoint=False) if theta is None
             else np.asarray(theta, dtype=np.float64).reshape(-1))
    states = dict(omega=omega, alpha=alpha, loads=tuple(loads), named_loads=named_loads)
    _check_names(mech, names, lo, hi, objective, minimize, constraints, theta, states)

    with _scheduled(scheduler) as (client, workers):
        def run(x: np.ndarray, where=client) -> pd.DataFrame:
            designs = pd.DataFrame(x, columns=names)
            per_task = STATES_PER_TASK if where is None else min(
                STATES_PER_TASK, -(-len(designs) // workers) * theta.size)
            return sweep(mech, designs, theta, states["omega"], states["alpha"],
                         *states["loads"], scheduler=where, states_per_task=per_task,
                         progress=progress and method == "grid" and where is None,
                         **states["named_loads"])

        search = _Search(run, names, lo, hi, objective, sign, constraints, theta.size)
        if method == "grid":
            axes = _grid_axes(lo, hi, budget)
            search.step(np.array(np.meshgrid(*axes, indexing="ij")).reshape(
                len(names), -1).T)
            step = np.array([1.0 / (a.size - 1) for a in axes])
        else:
            _evolve(search, population, budget, maxiter, popsize, tol, seed, progress)
            step = np.full(len(names), POLISH_STEP)
    if polish and search.best is not None:
        search.run = lambda x: run(x, where=None)  # one design at a time: no cluster trip
        _polish(search, step)
    return search.result(minimize, method, time.perf_counter() - start)


def _bounds(mech, vary: Mapping[str, tuple]) -> tuple[list, np.ndarray, np.ndarray]:
    """The names varied and their bounds in SI, checked."""
    specs = {p.name: p for p in mech.description.parameter_specs()}
    if not isinstance(vary, Mapping) or not vary:
        raise InputError(f"vary must map one or more parameters to bounds (lo, hi), got "
                         f"{vary!r}")
    lo, hi = [], []
    for name, bounds in vary.items():
        if name not in specs:
            raise InputTypeError(f"vary: {mech.name} has no parameter {name!r}; its parameters "
                                 "are: " + ", ".join(specs))
        spec = specs[name]
        if spec.kind in _DISCRETE:
            raise InputError(f"vary: {name} is a {spec.kind} parameter (its values are "
                             "discrete), which cannot be varied within bounds")
        if isinstance(bounds, (str, bytes)) or not hasattr(bounds, "__len__") or \
                len(bounds) != 2:
            raise InputError(f"vary: {name} needs bounds (lo, hi), got {bounds!r}")
        try:
            a, b = (spec.validate(v) for v in bounds)
        except (TypeError, ValueError) as err:
            raise InputError(f"vary: the bounds {tuple(bounds)!r} of {name} are not both "
                             f"valid values of it: {err}") from None
        if not a < b:
            raise InputError(f"vary: {name} needs lo < hi, got lo = {a!r}, hi = {b!r}")
        lo.append(a)
        hi.append(b)
    return list(vary), np.array(lo), np.array(hi)


def _check_names(mech, names, lo, hi, objective, minimize, constraints, theta,
                 states) -> None:
    """The objective and every constraint name summaries of the sweep: the columns of a
    sweep at one angle of the bounds' middle and of the linkage's own values (which
    also checks the states)."""
    designs = pd.DataFrame([(lo + hi) / 2.0, [mech.parameters[n] for n in names]],
                           columns=names)
    table = sweep(mech, designs, theta[:1], states["omega"], states["alpha"],
                  *states["loads"], **states["named_loads"])
    summaries = [c for c in table.columns if c not in names and c != "problem"]
    numbers = [c for c in summaries if c != "valid"]
    if objective not in numbers:
        raise InputError(f"minimize {minimize!r}: {objective!r} is not a numeric summary of "
                         f"the sweep of {mech.name}; they are: {', '.join(numbers)}")
    for c in constraints:
        allowed = ["valid"] if c.op is None else numbers
        if c.name not in allowed:
            raise InputError(f"constraint '{c}': {c.name!r} is not a summary of the sweep of "
                             f"{mech.name} to compare; they are: valid, {', '.join(numbers)}")


@contextlib.contextmanager
def _scheduled(scheduler) -> Iterator[tuple]:
    """``with _scheduled(scheduler) as (client, workers)``: None and 1 in this process,
    else the Dask client (one for the whole optimisation) and its number of workers."""
    if scheduler is None:
        yield None, 1
        return
    with dask_client(scheduler) as client:
        yield client, max(1, len(client.scheduler_info().get("workers", {})))


class _Search:
    """The evaluations of one optimisation: the penalised objective of designs (through
    ``run``, a sweep), the best feasible design so far, the least infeasible one, the
    count and the history."""

    def __init__(self, run: Callable, names: list, lo: np.ndarray, hi: np.ndarray,
                 objective: str, sign: float, constraints: tuple, angles: int):
        self.run, self.names, self.lo, self.hi = run, names, lo, hi
        self.objective, self.sign, self.constraints = objective, sign, constraints
        self.angles = angles
        self.count, self.rows = 0, []
        self.best: pd.Series | None = None  # the best feasible design's row
        self.best_value = math.inf  # its objective, times sign
        self.closest: pd.Series | None = None  # the lowest penalised one's, while none is
        self.closest_energy = math.inf
        self.on_step: Callable | None = None

    def design(self, u: np.ndarray) -> np.ndarray:
        """The parameter values at ``u`` in [0, 1]**n (rows): lo at 0, hi at 1, exactly."""
        u = np.clip(u, 0.0, 1.0)
        return np.clip(self.lo * (1.0 - u) + self.hi * u, self.lo, self.hi)

    def penalised(self, table: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
        """The penalised objective of each row of a sweep, and whether it is feasible."""
        f = self.sign * table[self.objective].to_numpy(dtype=np.float64)
        met = np.ones(len(table), dtype=bool)
        violation = np.zeros(len(table))
        for c in self.constraints:
            met &= c.satisfied(table)
            violation += c.violation(table, self.angles)
        usable = np.isfinite(f) & (table["problem"].to_numpy(dtype=object) == "")
        energy = np.where(met, f, INFEASIBLE * (1.0 + violation))
        return np.where(usable, energy, UNUSABLE), usable & met

    def evaluate(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The penalised objective of the designs ``x`` (one per row, in SI), one sweep,
        and whether each is feasible."""
        table = self.run(x)
        energy, feasible = self.penalised(table)
        self.count += len(table)
        if feasible.any():
            i = int(np.argmin(np.where(feasible, energy, np.inf)))
            if energy[i] < self.best_value:
                self.best_value, self.best = float(energy[i]), table.iloc[i].copy()
        i = int(np.argmin(energy))
        if energy[i] < self.closest_energy:
            self.closest_energy, self.closest = float(energy[i]), table.iloc[i].copy()
        return energy, feasible

    def step(self, x: np.ndarray) -> np.ndarray:
        """:meth:`evaluate` as a step of the global search: a row of the history."""
        energy, feasible = self.evaluate(x)
        self.record("global", int(feasible.sum()))
        if self.on_step is not None:
            self.on_step()
        return energy

    def record(self, stage: str, feasible: int) -> None:
        """A row of the history: the evaluations so far and the best feasible value."""
        self.rows.append({"generation": len(self.rows), "stage": stage,
                          "evaluations": self.count, "feasible": feasible,
                          "best": self.sign * self.best_value if self.best is not None
                          else math.nan})

    def result(self, minimize: str, method: str, seconds: float) -> OptimizationResult:
        feasible = self.best is not None
        row = self.best if feasible else self.closest
        res = OptimizationResult(
            design={n: float(row[n]) for n in self.names}, summary=row,
            objective=minimize, value=float(row[self.objective]),
            constraints=self.constraints, method=method, evaluations=self.count,
            seconds=seconds, history=pd.DataFrame(self.rows), feasible=feasible)
        if not feasible:
            broken = [str(c) for c in self.constraints
                      if not c.satisfied(pd.DataFrame([row]))[0]]
            why = (f"breaks {', '.join(broken)}" if broken else
                   f"meets them, but its {self.objective} is not a number")
            raise NoFeasibleDesignError(
                f"no design of the {self.count} evaluated meets every constraint; the "
                f"closest, {res.design}, {why}", res)
        return res


def _grid_axes(lo: np.ndarray, hi: np.ndarray, budget: int) -> list[np.ndarray]:
    """Evenly spaced values of each parameter, bounds included, as many as the budget
    allows: ``k`` or ``k + 1`` per parameter, their product at most ``budget``."""
    n = lo.size
    k = max(1, int(round(budget ** (1.0 / n))))
    while k ** n > budget:
        k -= 1
    while (k + 1) ** n <= budget:
        k += 1
    if k < 2:
        raise InputError(f"budget {budget} is too small for a grid of {n} parameters: it "
                         f"needs two values of each, {2 ** n} designs")
    counts = [k] * n
    for i in range(n):
        if math.prod(counts) // k * (k + 1) <= budget:
            counts[i] = k + 1
    return [np.linspace(a, b, c) for a, b, c in zip(lo, hi, counts)]


def _evolve(search: _Search, population: int, budget: int, maxiter: int, popsize: int,
            tol: float, seed, progress: bool) -> None:
    """Differential evolution over [0, 1]**n, a generation one sweep."""
    from scipy.optimize import differential_evolution

    generations = min(maxiter, budget // population - 1)
    if generations < 0:
        raise InputError(f"budget {budget} is less than one population of differential "
                         f"evolution ({population} = max(5, popsize * {len(search.names)}))")
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=generations + 1, desc="generations (at most)", unit="gen")
        search.on_step = lambda: (bar.update(), bar.set_postfix(best=search.rows[-1]["best"]))
    # scipy >= 1.15 names the seed rng (seed= warns there); earlier ones know only seed
    key = "rng" if "rng" in inspect.signature(differential_evolution).parameters else "seed"
    try:
        differential_evolution(
            lambda u: search.step(search.design(u.T)),
            [(0.0, 1.0)] * len(search.names), maxiter=generations, popsize=popsize,
            tol=tol, polish=False, vectorized=True, updating="deferred",
            init="latinhypercube", **{key: seed})
    finally:
        search.on_step = None
        if bar is not None:
            bar.total = bar.n  # converged before the last generation: the bar ends full
            bar.refresh()
            bar.close()


def _polish(search: _Search, step: np.ndarray) -> None:
    """A bounded Nelder-Mead from the best feasible design, a simplex of ``step`` (a
    fraction of each range) along each parameter, towards the middle at a bound."""
    from scipy.optimize import minimize

    n = len(search.names)
    start = ((search.best[search.names].to_numpy(dtype=np.float64) - search.lo)
             / (search.hi - search.lo))
    simplex = np.repeat(start[None, :], n + 1, axis=0)
    for i in range(n):
        simplex[i + 1, i] += step[i] if start[i] + step[i] <= 1.0 else -step[i]
    feasible = [0]

    def f(u: np.ndarray) -> float:
        energy, met = search.evaluate(search.design(u[None, :]))
        feasible[0] += int(met[0])
        return float(energy[0])

    minimize(f, start, method="Nelder-Mead", bounds=[(0.0, 1.0)] * n,
             options={"initial_simplex": simplex, "xatol": POLISH_XTOL, "fatol": math.inf,
                      "maxfev": 200 * n})
    search.record("polish", feasible[0])
