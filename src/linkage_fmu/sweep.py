"""Design sweeps: many parameter sets of one linkage, a revolution each, summarised.

A sweep solves every design (a row of parameter values) at every crank angle with the
linkage's compiled kernel: its parameters are arguments of the kernel (see
:mod:`~linkage_fmu.kernels`), so one compilation serves every design of a structure
(a value of each branch and choice parameter). The summaries are computed in the C as
the states are solved (:meth:`Kernel.summary <linkage_fmu.kernels.Kernel.summary>`:
only the outputs they read, no state's outputs kept), the designs split between
threads; ``fused=False`` keeps every output of every state of a chunk of designs (the
array kernel) and summarises them with numpy, the reference. Designs go in chunks, each
one task solving thousands of states: in this process, or on a Dask cluster
(``pip install "linkage_fmu[sweep]"``) for more cores or machines than this one.
Where there is no C compiler, each design is built and solved on numpy, after one
warning: the same table, to rounding, tens of times slower (the four-bar's 22 designs
over 360 angles: 0.31 s, against 0.005 s with the compiled kernels).

Each design's row holds its parameter values and:

- ``valid``: the parameter set is valid and the linkage assembles at every angle,
  friction locking it at none;
- ``problem``: why a parameter set is invalid ('' otherwise);
- ``unassembled`` and ``first_unassembled_deg``: how many angles cannot be assembled
  (or are singular), and the first of them in degrees (NaN if none);
- ``locked`` and ``first_locked_deg``: how many angles friction locks (they assemble,
  and no finite balancing effort moves the linkage there: a state whose ``sol.status``
  is :data:`~linkage_fmu.solver.LOCKED`), and the first of them in degrees (NaN if
  none); 0 without friction;
- ``<effort>_peak`` and ``<effort>_rms``: the balancing effort's largest magnitude and
  root mean square over the angles that assemble;
- ``<force>_peak``: each pin force's largest magnitude (``F21_peak`` from ``F21x``,
  ``F21y``; ``shake_peak``, the shaking force's, from ``shake_x``, ``shake_y``), and the
  largest magnitude of every other output (``<name>_peak``: ``shake_M_peak``, ...);
- with friction in the joints (:mod:`~linkage_fmu.friction`): ``P_loss_peak`` (above)
  and ``P_loss_mean``, the power friction dissipates, its largest value and its mean
  over the angles that assemble, and ``eta_min``, the instantaneous efficiency's
  smallest value (over the angles where power enters the linkage: ``eta`` is NaN
  where none does);
- ``gamma_<joint>_min_deg``: each transmission angle's minimum distance from a toggle,
  ``min(gamma, 180 - gamma)`` in degrees.

Examples
--------
>>> import numpy as np
>>> from linkage_fmu.sweep import grid, sweep
>>> designs = grid(l_AB=[0.08, 0.10, 0.12], l_BC=[0.30, 0.35])
>>> table = sweep("four_bar", designs, omega=10.0)
>>> len(table), bool(table["valid"].all()), table["Mb_peak"].idxmax()
(6, True, 4)
"""

from __future__ import annotations

import contextlib
import functools
import itertools
import math
import warnings
from collections.abc import Iterator, Mapping, Sequence

import numpy as np
import pandas as pd

from .ccompiler import find_compiler
from .descriptions import Description
from .drivers import one_crank
from .errors import DependencyError, InputError, InputTypeError
from .kernels.c_source import SUMMARY_HEAD
from .parameters import resolve
from .presets import linkage

#: states a task solves at least (Dask's per-task overhead is 0.2 to 1 ms)
STATES_PER_TASK = 50_000
#: threads solving the designs of a task in this process
THREADS = 2


def grid(**axes: Sequence) -> pd.DataFrame:
    """Every combination of the values of each parameter, one design per row.

    Examples
    --------
    >>> grid(l_AB=[0.1, 0.2], m2=[1.0, 2.0, 3.0]).shape
    (6, 2)
    """
    names = list(axes)
    rows = list(itertools.product(*(list(axes[n]) for n in names)))
    return pd.DataFrame(rows, columns=names)


def sweep(source, designs: pd.DataFrame | Mapping[str, Sequence], theta=None,
          omega: float | None = None, alpha: float | None = None, *loads: float, scheduler=None,
          states_per_task: int = STATES_PER_TASK, progress: bool = False,
          fused: bool = True, threads: int | None = None,
          **named_loads: float) -> pd.DataFrame:
    """Summaries of the linkage ``source`` (preset, description file, Description or a
    Mechanism built from one) at each design over the crank angles ``theta``.

    Parameters
    ----------
    source
        The linkage; its parameter values are the defaults of every design.
    designs : DataFrame or mapping of equal-length sequences
        One design per row, one column per parameter swept (see :func:`grid`).
    theta : array_like, optional
        Crank angles [rad]; default 360 over a revolution.
    omega, alpha, *loads, **named_loads : float
        The same speed, acceleration and loads for every design and angle; one not
        given takes its start value (:attr:`~linkage_fmu.Mechanism.start`). A load over
        the cycle is computed at each angle unless given by name.
    scheduler : None, "local", a Dask ``Client`` or a scheduler address
        None solves in this process; "local" starts a local Dask cluster (one worker
        per core); a Client or an address (``tcp://host:8786``) uses that cluster.
    states_per_task : int
        Designs per task: this many states, rounded up to whole designs (in this
        process without a progress bar, the summaries computed in the C take every
        design in one task: they keep no state's outputs).
    progress : bool
        A progress bar (tqdm) while the chunks are solved in this process.
    fused : bool
        Compute the summaries in the C as the states are solved (default); False keeps
        every output of every state of a chunk and summarises them with numpy (the
        reference: the same table, to rounding).
    threads : int, optional
        Threads solving each task's designs with ``fused``: default :data:`THREADS`
        in this process, 1 on Dask (its workers are the parallelism).

    Returns
    -------
    DataFrame
        One row per design, in the order given (see the module's notes for the
        columns).

    Raises
    ------
    TypeError, ValueError
        A column that is not a parameter of the linkage, no angle, an angle or load that
        is not finite, a number of threads that is not a positive integer: naming it. An
        invalid parameter value is not an error: its design's row says why
        (``problem``).
    """
    if threads is None:
        threads = THREADS if scheduler is None else 1
    if isinstance(threads, bool) or not isinstance(threads, int) or threads < 1:
        raise InputError(f"threads must be a positive integer, got {threads!r}")
    mech = linkage(source)
    one_crank(mech, "a sweep over crank angles")
    designs = pd.DataFrame(designs).reset_index(drop=True)
    specs = {p.name: p for p in mech.description.parameter_specs()}
    for name in designs.columns:
        if name not in specs:
            raise InputTypeError(f"{mech.name} has no parameter {name!r}; its parameters are: "
                                 + ", ".join(specs))
    theta = np.linspace(0.0, 2.0 * math.pi, 360, endpoint=False) if theta is None else theta
    theta = np.asarray(theta, dtype=np.float64).reshape(-1)
    if not theta.size:
        raise InputError("theta must hold at least one crank angle: a design's summaries "
                         "are over its angles")
    values, given = mech.inputs(omega, alpha, loads, named_loads)
    inputs = [theta] + [np.full(1, float(v)) for v in values]
    for name, a in zip(mech.input_names + given, inputs):
        if not np.isfinite(a).all():
            raise InputError(f"{name} must be finite")
    text = mech.description.with_defaults(mech.parameters).to_toml()
    per = max(1, -(-states_per_task // max(theta.size, 1)))
    if fused and scheduler is None and not progress:
        per = max(len(designs), 1)
    chunks = [designs.iloc[i:i + per] for i in range(0, len(designs), per)] or [designs]
    args = [(text, {name: chunk[name].to_numpy() for name in chunk.columns}, inputs, given,
             fused, threads) for chunk in chunks]
    if scheduler is None:
        parts = []
        iterator = args
        if progress:
            from tqdm import tqdm

            iterator = tqdm(args, desc=f"{mech.name}: designs", unit="chunk")
        for a in iterator:
            parts.append(solve_chunk(*a))
    else:
        parts = _on_dask(scheduler, args)
    table = pd.concat(parts, ignore_index=True)
    _overflowing(table, (f"{mech.effort.name}_peak", f"{mech.effort.name}_rms"))
    return pd.concat([designs, table], axis=1)


#: why a design that assembles at every angle has no finite balancing effort
OVERFLOW = "the outputs overflow float64: a parameter is too large in magnitude"


def _overflowing(table: pd.DataFrame, summaries: tuple) -> None:
    """Mark invalid, saying why, the designs called valid whose balancing effort's
    ``summaries`` (peak and rms) are not finite: their arithmetic overflows
    (``J2 = 1e308``), where a valid row used to hold NaN or inf and no reason."""
    if "valid" not in table:  # no designs
        return
    bad = table["valid"].to_numpy(bool, copy=True)
    finite = np.ones(bad.size, bool)
    for name in summaries:
        if name in table:
            finite &= np.isfinite(table[name].to_numpy(float))
    bad &= ~finite
    if bad.any():
        table.loc[bad, "valid"] = False
        table.loc[bad, "problem"] = OVERFLOW


def _on_dask(scheduler, args: list) -> list:
    with dask_client(scheduler) as client:
        futures = client.map(lambda a: solve_chunk(*a), args, pure=False)
        return client.gather(futures)


@contextlib.contextmanager
def dask_client(scheduler) -> Iterator:
    """The Dask client of ``scheduler`` for the duration of a ``with`` block, so that
    many sweeps share one cluster: "local" starts a local cluster (one worker process
    per core), an address (``tcp://host:8786``) connects to that scheduler, a
    ``Client`` is used as it is. What is started here is closed at the end of the block;
    a given ``Client`` is left open.

    Raises
    ------
    ImportError
        dask.distributed is not installed, saying how to install it.
    """
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise DependencyError('a sweep on Dask needs dask.distributed: pip install '
                              '"linkage_fmu[sweep]"') from None
    if isinstance(scheduler, Client):
        yield scheduler
        return
    cluster = None
    if scheduler == "local":
        cluster = LocalCluster(threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
    else:
        client = Client(scheduler)
    try:
        yield client
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


@functools.lru_cache(maxsize=16)
def _layout(text: str) -> tuple:
    """The parameters of the linkage described by ``text`` (name -> spec), their values
    there, the structural ones (branch and choice), and the friction coefficients
    (friction with every mu 0 is structure too: its parameters are then no kernel
    arguments, and a design with a mu not 0 needs a kernel that solves the friction)."""
    d = Description.from_toml(text, "<sweep>")
    specs = {p.name: p for p in d.parameter_specs()}
    base = resolve(tuple(specs.values()), {}, d.name)
    structural = tuple(p.name for p in specs.values() if p.kind in ("branch", "choice"))
    return specs, base, structural, tuple(sorted(d.friction_parameters(("mu",))))


def _validated(spec, values) -> tuple[list | np.ndarray, list]:
    """Each value of one parameter's column checked by ``spec``, each distinct value
    once: the checked values (an array where they are floats, NaN where refused), and
    why each is refused ('' where it is not)."""
    a = values if isinstance(values, np.ndarray) else None
    if a is not None and a.dtype == np.float64 and a.ndim == 1:
        # distinct by the bits: -0.0 is 0.0 to np.unique, not to every formula
        bits, first, inverse = np.unique(a.view(np.int64), return_index=True,
                                         return_inverse=True)
        out, why = np.empty(bits.size), []
        for u, f in enumerate(first):
            try:
                out[u], reason = spec.validate(float(a[f])), ""
            except (TypeError, ValueError) as err:
                out[u], reason = math.nan, str(err)
            why.append(reason)
        return out[inverse], [why[u] for u in inverse] if any(why) else [""] * a.size
    seen: dict = {}
    out, problems = [], []
    for v in (a.tolist() if a is not None else values):  # Python's numbers, not numpy's
        try:
            key = (type(v), v, math.copysign(1.0, v) if type(v) is float else 0.0)
            hit = seen.get(key)
        except TypeError:  # unhashable: checked as it is (and refused)
            key, hit = None, None
        if hit is None:
            try:
                hit = (spec.validate(v), "")
            except (TypeError, ValueError) as err:
                hit = (None, str(err))
            if key is not None:
                seen[key] = hit
        out.append(hit[0])
        problems.append(hit[1])
    return out, problems


def solve_chunk(text: str, columns: Mapping[str, list], inputs: list,
                over_cycle: tuple = (), fused: bool = True, threads: int = 1) -> pd.DataFrame:
    """The summaries of the designs ``columns`` (parameter -> values) of the linkage
    described by ``text`` (a description file's text, its defaults the base
    parameters), at the flat ``inputs`` (theta, omega, alpha, the input loads, then the
    loads over the cycle named in ``over_cycle``; arrays of the angles' length or of one):
    one task of :func:`sweep` (``fused`` and ``threads`` as there)."""
    specs, base, structural, frictional = _layout(text)
    names = list(columns)
    n = len(next(iter(columns.values()))) if columns else 1
    checked, problems = {}, [""] * n
    for k in names:  # a design's problem is that of its first column refused
        checked[k], refused = _validated(specs[k], columns[k])
        problems = [p or r for p, r in zip(problems, refused)]
    if fused and find_compiler() is not None:  # without one: numpy's summaries, below
        return _fused_chunk(text, n, checked, problems, base, structural, frictional, inputs,
                            over_cycle, threads)
    checked = {k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in checked.items()}
    rows = [(None, problem) if problem else
            ({**base, **{k: checked[k][i] for k in names}}, "")
            for i, problem in enumerate(problems)]
    results: list[dict] = [None] * n
    groups: dict[tuple, list[int]] = {}
    for i, (params, problem) in enumerate(rows):
        if params is None:
            results[i] = {"valid": False, "problem": problem}
        else:
            key = tuple(params[k] for k in structural)
            groups.setdefault((key, any(params[k] != 0.0 for k in frictional)), []).append(i)
    theta = inputs[0]
    for (key, friction), members in groups.items():
        mech, kernel, array = _structure(text, tuple(zip(structural, key)), over_cycle,
                                         friction)
        outputs = kernel.outputs
        block = np.full((len(outputs), len(members), theta.size), np.nan)
        valid = np.zeros((len(members), theta.size), dtype=bool)
        locked = np.zeros((len(members), theta.size), dtype=bool)
        problems = [""] * len(members)
        for j, i in enumerate(members):
            params = rows[i][0]
            try:
                frozen = kernel.prepare(*(params[k] for k in kernel.parameters))
            except (OverflowError, ZeroDivisionError):  # the C gets inf or NaN there
                frozen = None
            if frozen is None or not np.isfinite(frozen).all():
                problems[j] = _UNBUILT
                continue
            if array is None:  # no C compiler: the design's own linkage, on numpy
                valid[j], locked[j] = _on_numpy(text, params, friction, mech, kernel.outputs,
                                                inputs, over_cycle, block[:, j])
                continue
            _, valid[j] = array(inputs, theta.size, block[:, j], frozen)
            locked[j] = _locked(kernel, frozen, inputs, ~valid[j])
        summary = _summaries(mech, outputs, block, valid, locked, theta, problems)
        for j, row in enumerate(summary.to_dict("records")):
            results[members[j]] = row
    return pd.DataFrame(results)


def _fused_chunk(text: str, n: int, checked: dict, problems: list, base: dict,
                 structural: tuple, frictional: tuple, inputs: list, over_cycle: tuple,
                 threads: int) -> pd.DataFrame:
    """:func:`solve_chunk` with the summaries computed in the C: the ``n`` designs'
    checked values ``checked`` (parameter -> values) and ``problems``."""
    theta = inputs[0]
    degrees = np.degrees(theta)

    rubbing = np.full(n, any(base[k] != 0.0 for k in frictional if k not in checked))
    for k in frictional:
        if k in checked:
            rubbing |= np.array([v != 0.0 for v in checked[k]], dtype=bool)
    swept = [k for k in structural if k in checked]
    fixed = tuple(base[k] for k in structural)
    keys = zip(*(checked[k] for k in swept)) if swept else None
    groups: dict[tuple, list[int]] = {}
    for i, (problem, f) in enumerate(zip(problems, rubbing.tolist())):
        if keys is not None:
            row = dict(zip(swept, next(keys)))
        if not problem:
            key = fixed if keys is None else tuple(row.get(k, base[k]) for k in structural)
            groups.setdefault((key, f), []).append(i)
    invalid = [i for i, p in enumerate(problems) if p]
    parts = []  # (rows, columns: name -> values)
    if invalid:
        parts.append((invalid, {"valid": [False] * len(invalid),
                                "problem": [problems[i] for i in invalid]}))
    for (key, friction), members in groups.items():
        mech, kernel, _ = _structure(text, tuple(zip(structural, key)), over_cycle, friction)
        names, reductions = _reductions(mech, kernel.outputs)
        summary = kernel.summary(reductions)
        params = np.empty((len(members), len(kernel.parameters)))
        for c, k in enumerate(kernel.parameters):
            params[:, c] = np.asarray(checked[k])[members] if k in checked else base[k]
        s = summary(params, inputs, theta.size, threads)
        bad = s[:, 0] != 0.0
        count, first, locked, first_locked = (s[:, k].astype(np.int64) for k in range(1, 5))
        table = {"valid": ~bad & (count == 0) & (locked == 0),
                 "problem": [_UNBUILT if b else "" for b in bad], "unassembled": count,
                 "first_unassembled_deg": np.where(first >= 0, degrees[first], np.nan),
                 "locked": locked,
                 "first_locked_deg": np.where(first_locked >= 0, degrees[first_locked],
                                              np.nan)}
        for k, name in enumerate(names):
            table[name] = s[:, len(SUMMARY_HEAD) + k]
        parts.append((members, table))
    # the columns in the order the rows first give them, as a table of row dicts would
    parts.sort(key=lambda part: part[0][0])
    order = list(dict.fromkeys(name for _, table in parts for name in table))
    columns = {}
    for name in order:
        having = [(rows, t[name]) for rows, t in parts if name in t]
        if len(having) == 1 and len(having[0][0]) == n:
            columns[name] = having[0][1]
            continue
        column = np.full(n, np.nan, dtype=object)  # NaN where a row has no such column
        for rows, values in having:
            column[rows] = list(values)
        columns[name] = column.tolist()
    return pd.DataFrame(columns, index=range(n))


#: why a design's parameter set is refused by the kernel's parameter step
_UNBUILT = ("the parameter set cannot be built (a computed length is not positive, or a "
            "value is not finite)")


def _reductions(mech, outputs: tuple) -> tuple[list, list]:
    """The summary columns of a structure (the names :func:`_summaries` gives them, in
    its order) and the reductions computing them (:meth:`Kernel.summary
    <linkage_fmu.kernels.Kernel.summary>`)."""
    index = set(outputs)
    effort = mech.effort.name
    pairs = [name[:-1] for name in mech.output_names
             if name.endswith("x") and name[:-1] + "y" in index]
    paired = {p + a for p in pairs for a in "xy"}
    columns = {f"{effort}_peak": ("peak", (effort,)), f"{effort}_rms": ("rms", (effort,))}
    for p in pairs:
        columns[f"{p.rstrip('_')}_peak"] = ("peak_pair", (p + "x", p + "y"))
    for name in mech.output_names:
        if name not in paired and name != effort:
            columns[f"{name}_peak"] = ("peak", (name,))
    if "P_loss" in index:
        columns["P_loss_mean"] = ("mean", ("P_loss",))
        columns["eta_min"] = ("min", ("eta",))
    for name in mech.diagnostic_names:
        if name.startswith("gamma_"):
            columns[f"{name}_min_deg"] = ("toggle_deg", (name,))
    return list(columns), list(columns.values())


@functools.lru_cache(maxsize=64)
def _structure(text: str, structure: tuple, given: tuple = (), friction: bool = False):
    """The mechanism, kernel (all outputs, moving; the loads over the cycle ``given``
    as inputs) and array kernel of one structure of a linkage (its friction solved, and
    its parameters kernel arguments, with ``friction``); kept per process, so a worker
    traces and loads each once."""
    d = Description.from_toml(text, "<sweep>")
    mech = (d.fmu_build if friction else d.build)(**dict(structure))
    kernel = mech.solver.kernel(None, False, given)
    array = kernel.array()  # None without a C compiler (after one warning)
    assert kernel.parameters == mech.kernel_parameters
    return mech, kernel, array


def _on_numpy(text: str, params: dict, friction: bool, mech, outputs: tuple, inputs: list,
              over_cycle: tuple, out: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One design's outputs at the flat ``inputs`` of :func:`solve_chunk` by the linkage
    built with its parameters ``params`` and solved on numpy (the path where there is
    no C compiler), written into ``out`` (one row per output of ``outputs``): whether
    each state is solved, and whether friction locks it."""
    from .solver import LOCKED, SOLVED

    d = Description.from_toml(text, "<sweep>")
    design = (d.fmu_build if friction else d.build)(**params)
    values = [float(a[0]) if a.size == 1 else a for a in map(np.asarray, inputs)]
    names = [ld.name for ld in mech.input_loads] + list(over_cycle)
    sol = design.solve(*values[:3], **dict(zip(names, values[3:])))
    for k, name in enumerate(outputs):
        out[k] = sol[name]
    status = np.asarray(sol.status).reshape(-1)
    return status == SOLVED, status == LOCKED


def _locked(kernel, frozen, inputs: list, failed: np.ndarray) -> np.ndarray:
    """Which of the states ``failed`` (whose guards fail in the array kernel) friction
    locks: the first guard the kernel's one-state function (with the parameter step's
    values ``frozen``) fails there is one whose reason is ``'locking'``."""
    out = np.zeros(failed.size, dtype=bool)
    if not any(r.kind == "locking" for r in kernel.reasons):
        return out
    one = kernel.make(*frozen)
    for i in np.flatnonzero(failed):
        state = [float(a[i] if a.size > 1 else a[0]) for a in inputs]
        try:
            code = one(*state)
        except (ArithmeticError, ValueError):  # the Python kernel meets the failure itself
            continue
        out[i] = type(code) is int and code > 0 and kernel.reasons[code - 1].kind == "locking"
    return out


def _summaries(mech, outputs: tuple, block: np.ndarray, valid: np.ndarray,
               locked: np.ndarray, theta: np.ndarray, problems: list) -> pd.DataFrame:
    """The summaries of the designs of one structure, all at once: ``block[k, j, i]`` is
    output ``k`` of design ``j`` at angle ``i`` (NaN where it has none), ``valid[j, i]``
    whether it has outputs, ``locked[j, i]`` whether friction locks it (:func:`_locked`),
    ``problems[j]`` why design ``j`` is invalid."""
    index = {name: k for k, name in enumerate(outputs)}
    effort = mech.effort.name
    pairs = [name[:-1] for name in mech.output_names
             if name.endswith("x") and name[:-1] + "y" in index]
    paired = {p + a for p in pairs for a in "xy"}
    bad = np.array([bool(p) for p in problems])
    ok = valid & ~bad[:, None]
    locked = locked & ~bad[:, None]
    unassembled = ~ok & ~locked
    degrees = np.degrees(theta)
    table = {"valid": ok.all(axis=1), "problem": problems,
             "unassembled": np.where(bad, theta.size, unassembled.sum(axis=1)),
             "first_unassembled_deg": np.where(bad | ~unassembled.any(axis=1), np.nan,
                                               degrees[np.argmax(unassembled, axis=1)]),
             "locked": locked.sum(axis=1),
             "first_locked_deg": np.where(locked.any(axis=1),
                                          degrees[np.argmax(locked, axis=1)], np.nan)}
    with warnings.catch_warnings(), np.errstate(invalid="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows: NaN summaries
        e = np.where(ok, block[index[effort]], np.nan)
        table[f"{effort}_peak"] = np.nanmax(np.abs(e), axis=1)
        table[f"{effort}_rms"] = np.sqrt(np.nanmean(e * e, axis=1))
        for p in pairs:
            size = np.hypot(block[index[p + "x"]], block[index[p + "y"]])
            table[f"{p.rstrip('_')}_peak"] = np.nanmax(np.where(ok, size, np.nan), axis=1)
        for name in mech.output_names:
            if name not in paired and name != effort:
                table[f"{name}_peak"] = np.nanmax(np.where(ok, np.abs(block[index[name]]),
                                                           np.nan), axis=1)
        if "P_loss" in index:
            loss = np.where(ok, block[index["P_loss"]], np.nan)
            table["P_loss_mean"] = np.nanmean(loss, axis=1)
            table["eta_min"] = np.nanmin(np.where(ok, block[index["eta"]], np.nan), axis=1)
        for name in mech.diagnostic_names:
            if name.startswith("gamma_"):
                gamma = np.degrees(np.where(ok, block[index[name]], np.nan))
                table[f"{name}_min_deg"] = np.nanmin(np.minimum(gamma, 180.0 - gamma), axis=1)
    return pd.DataFrame(table)
