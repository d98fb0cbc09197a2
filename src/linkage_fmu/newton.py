"""Newton iterations written once for every kind of number.

The same steps run on floats (one state), numpy arrays (many states, each its own
iteration), mpmath numbers and traced numbers (:mod:`~linkage_fmu.kernels.trace`), where
an iteration is a loop of the kernel (:meth:`~linkage_fmu.kernels.trace.Tape.loop`):
its body holds no branch, its decisions are operations. The friction of the joints
(:mod:`~linkage_fmu.friction`) and the closure of a class III group
(:mod:`~linkage_fmu.groups.closure`) iterate with them, solving their linear systems
with :mod:`~linkage_fmu.linalg`.

Examples
--------
>>> from linkage_fmu.numerics import SCALAR
>>> def step(x, memory):  # Newton on x**2 = 2
...     return [(x[0] * x[0] - 2.0) / (2.0 * x[0])], None, memory
>>> round(iterate(SCALAR, [1.0], step, fail=None)[0], 15)
1.414213562373095
"""

from __future__ import annotations

import numpy as np

from .kernels.trace import Reason

#: Newton steps every path takes, the traced kernels' exactly (then they check them)
ITERATIONS = 5
#: steps at most, for a state the first ones do not settle
MAX_ITERATIONS = 60
#: converged: the last step is at most this fraction of the iterated values' size
TOLERANCE = 1e-13
#: the smallest positive double: ``x / max(|x|, TINY)`` is the sign of ``x``, 0 at 0
TINY = 5e-324


def tolerance(xp) -> float:
    """The relative size of a last step that ends an iteration: :data:`TOLERANCE`, or
    the namespace's own (``xp.eps()``, mpmath's at its precision).

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> tolerance(SCALAR)
    1e-13
    """
    eps = getattr(xp, "eps", None)
    return TOLERANCE if eps is None else eps()


def not_(xp, outcome):
    """``not outcome``, of a float comparison or elementwise of an array's.

    Examples
    --------
    >>> import numpy as np
    >>> from linkage_fmu.numerics import ARRAY, SCALAR
    >>> not_(SCALAR, 1.0 > 2.0), not_(ARRAY, np.array([1.0, 3.0]) > 2.0).tolist()
    (True, [True, False])
    """
    return (not outcome) if xp.scalar else ~outcome


def iterate(xp, x: list, step, fail, first=None, memory: tuple = (),
            minimum: int = ITERATIONS, maximum: int = MAX_ITERATIONS) -> list:
    """``x <- x - d`` with ``(d, det, memory) = step(x, memory)`` (``first`` instead for
    the first step, if given; ``memory``: what a step hands the next): ``minimum``
    steps (:data:`ITERATIONS`), then more (to ``maximum``, :data:`MAX_ITERATIONS`)
    while the last step exceeds :data:`TOLERANCE` of ``x``; ``det`` (or None) must stay
    > 0. On floats ``fail()`` raises where it does not converge or ``det <= 0``; on
    arrays, those states get NaN and ``fail(bad)`` is told which. (On traced numbers,
    the iterations are loops of the kernel: :func:`loop`.) A NaN passes both tests: a
    caller for whom it is a failure checks its result.

    Examples
    --------
    >>> import numpy as np
    >>> from linkage_fmu.numerics import ARRAY
    >>> def step(x, memory):
    ...     return [(x[0] * x[0] - np.array([4.0, 9.0])) / (2.0 * x[0])], None, memory
    >>> iterate(ARRAY, [np.array([1.0, 1.0])], step, fail=None, minimum=1)[0].tolist()
    [2.0, 3.0]
    """
    tol = tolerance(xp)
    done = det = None
    memory = tuple(memory)
    for k in range(maximum):
        d, det, memory = (first if k == 0 and first is not None else step)(x, memory)
        if done is None:
            x = [a - b for a, b in zip(x, d)]
        else:  # arrays: the states converged stay as they are
            x = [np.where(done, a, a - b) for a, b in zip(x, d)]
        if k + 1 < minimum:
            continue
        moved, size = sum(xp.abs(b) for b in d), sum(xp.abs(a) for a in x)
        # written so that NaN passes: a non-finite value is an overflow or a singular
        # position, which the solver's check of the outputs names; locking is finite
        converged = not_(xp, moved > tol * size)
        if xp.scalar:
            if converged:
                break
        else:
            done = converged if done is None else done | converged
            if done.all():
                break
    else:
        if xp.scalar:
            fail()
        else:
            fail(~done)
            x = [np.where(done, a, np.nan) for a in x]
    if det is not None:
        held = not_(xp, det <= 0.0)
        if xp.scalar:
            if not held:
                fail()
        elif not held.all():
            fail(~held)
            x = [np.where(held, a, np.nan) for a in x]
    return x


def tape_of(*values):
    """The tape of the first traced number among ``values``, or None.

    Examples
    --------
    >>> from linkage_fmu.kernels.trace import Tape
    >>> tape = Tape()
    >>> tape_of(1.0, tape.input("x", 2.0)) is tape, tape_of(1.0, 2.0)
    (True, None)
    """
    for v in values:
        tape = getattr(v, "tape", None)
        if tape is not None:
            return tape
    return None


def loop(tape, xp, x: list, det, memory: tuple, step, fail, reason: Reason,
         minimum: int, maximum: int) -> list:
    """:func:`iterate`'s steps on traced numbers as a loop of the kernel
    (:meth:`~linkage_fmu.kernels.trace.Tape.loop`) carrying ``x``, ``det`` (None: the
    steps have none) and ``memory``, with its test after ``minimum`` steps, at most
    ``maximum``; then its checks, labelled ``reason``: that it converged, and that the
    last ``det`` > 0 (both written so that NaN passes, as on floats)."""
    tol = tolerance(xp)
    n, m = len(x), 0 if det is None else 1

    def body(carried):
        x, memory = carried[:n], tuple(carried[n + m:])
        d, det, memory = step(x, memory)
        x = [a - b for a, b in zip(x, d)]
        moved, size = sum(xp.abs(b) for b in d), sum(xp.abs(a) for a in x)
        return [*x, *([det] if m else []), *memory], tape.compare("gt", moved, tol * size)

    carried, converged = tape.loop([*x, *([det] if m else []), *memory], body,
                                   minimum, maximum)
    if not tape.check(converged, True, reason):
        fail()
    if m and not tape.check(tape.compare("le", carried[n], 0.0), False, reason):
        fail()
    return carried[:n]


def compare(xp, op: str, a, b):
    """``a op b`` (``op`` one of lt, le, gt, ge) as a value a loop's body decides with:
    a bool on floats, an array of them on arrays, :meth:`Tape.compare
    <linkage_fmu.kernels.trace.Tape.compare>` on traced numbers (no branch).

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> compare(SCALAR, "lt", 1.0, 2.0)
    True
    """
    tape = tape_of(a, b)
    if tape is not None:
        return tape.compare(op, a, b)
    return _ORDER[op](a, b)


def both(xp, a, b):
    """``a and b`` of two :func:`compare` values, without a branch.

    Examples
    --------
    >>> import numpy as np
    >>> from linkage_fmu.numerics import ARRAY
    >>> both(ARRAY, np.array([True, True]), np.array([True, False])).tolist()
    [True, False]
    """
    tape = tape_of(a, b)
    if tape is not None:
        return tape.apply("min", min, a, b)
    return a & b


def either(xp, a, b):
    """``a or b`` of two :func:`compare` values, without a branch.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> either(SCALAR, False, True)
    True
    """
    tape = tape_of(a, b)
    if tape is not None:
        return tape.apply("max", max, a, b)
    return a | b


def select(xp, condition, a, b):
    """``a`` where ``condition`` (a :func:`compare` value) holds, else ``b``: element by
    element on arrays, a decision of the kernel on traced numbers (no branch).

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> select(SCALAR, compare(SCALAR, "gt", 3.0, 2.0), "yes", "no")
    'yes'
    """
    tape = tape_of(condition, a, b)
    if tape is not None:
        return tape.select(condition, a, b)
    if xp.scalar:
        return a if condition else b
    return np.where(condition, a, b)


def repeat(xp, carried: list, body, minimum: int, maximum: int,
           tape=None) -> tuple[list, object]:
    """``carried <- body(carried)[0]`` (``body`` returns the next values and ``again``, a
    :func:`compare` value) at least ``minimum`` times, then while ``again``, at most
    ``maximum`` times; returns the last values and whether ``again`` ended it (per state
    on arrays, whose ended states keep their values; a value of the kernel on traced
    numbers: one loop, :meth:`Tape.loop <linkage_fmu.kernels.trace.Tape.loop>`, on
    ``tape`` or that of the carried values). The body decides with :func:`compare`,
    :func:`both` and :func:`select` only, so that it does the same on every kind of
    number.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> def halve(c):                       # halve until below 1
    ...     x = 0.5 * c[0]
    ...     return [x], compare(SCALAR, "ge", x, 1.0)
    >>> repeat(SCALAR, [10.0], halve, 1, 60)
    ([0.625], True)
    >>> repeat(SCALAR, [1e30], halve, 1, 3)
    ([1.25e+29], False)
    """
    tape = tape or tape_of(*carried)
    if tape is not None:
        return tape.loop(list(carried), body, minimum, maximum)
    if xp.scalar:
        for k in range(maximum):
            carried, again = body(carried)
            if k + 1 >= minimum and not again:
                return carried, True
        return carried, False
    done = None
    for k in range(maximum):
        new, again = body(carried)
        carried = new if done is None else [np.where(done, a, b) for a, b in zip(carried, new)]
        if k + 1 >= minimum:
            ended = ~np.asarray(again, bool)
            done = ended if done is None else done | ended
            if done.all():
                break
    if done is None:
        done = np.zeros(np.shape(carried[0]), bool)
    return carried, done


_ORDER = {"lt": lambda a, b: a < b, "le": lambda a, b: a <= b, "gt": lambda a, b: a > b,
          "ge": lambda a, b: a >= b}


def inverse(xp, x):
    """``1 / x``, and 0 for ``x = 0`` (no comparison: :func:`~.kernels.trace.sign`).

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> inverse(SCALAR, 4.0), inverse(SCALAR, 0.0)
    (0.25, 0.0)
    """
    return xp.sign(x) / xp.maximum(xp.abs(x), TINY)
