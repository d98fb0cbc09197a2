"""Linear solves and determinants, each written once for the numbers it runs on.

- :func:`solve`, :func:`solve_signed`, :func:`solve_many`: Gaussian elimination with
  partial pivoting that takes no branch, on lists of numbers of any kind (floats, numpy
  arrays over states, mpmath numbers, traced numbers: inside a kernel's loop);
- :func:`solve_unpivoted` and :func:`determinant`: elimination without pivoting and the
  cofactor determinant of a small system near the identity; :func:`solve_adjugate`, the
  two at once by the adjugate (the friction's Newton step: one division);
- :func:`solve_batch`: numpy's LU over a batch of states, NaN for a singular one;
- :func:`solve_mpmath`: mpmath's LU of a system given by its nonzero entries.

The operations of each, and their order, are the floats of every path that uses it
(the traced kernels' too): a change here changes the results' last bits.

Examples
--------
>>> from linkage_fmu.numerics import SCALAR
>>> solve(SCALAR, [[0.0, 2.0], [4.0, 1.0]], [2.0, 9.0])[0]
[2.0, 1.0]
>>> solve_unpivoted([[1.0, 0.5], [0.25, 1.0]], [2.0, 2.25])
[1.0, 2.0]
"""

from __future__ import annotations

import numpy as np


def solve(xp, A: list, b: list) -> tuple[list, list]:
    """``A^-1 b`` by Gaussian elimination with partial pivoting, and the magnitudes of
    the pivots (the diagonal of ``U`` in ``PA = LU``): :func:`solve_many` of one
    right-hand side.

    Parameters
    ----------
    xp : namespace
        The kind of the numbers (:mod:`linkage_fmu.numerics`).
    A : list of lists
        The matrix, as rows.
    b : list
        The right-hand side.

    Returns
    -------
    tuple of list
        The solution and the pivots' magnitudes.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> x, pivots = solve(SCALAR, [[1e-20, 1.0], [1.0, 1.0]], [1.0, 2.0])
    >>> [round(v, 15) for v in x], pivots
    ([1.0, 1.0], [1.0, 1.0])
    """
    (x,), pivots = solve_many(xp, A, [b])
    return x, pivots


def solve_signed(xp, A: list, b: list) -> tuple[list, object]:
    """``A^-1 b`` (:func:`solve`) and the sign of ``det A``, -1.0 or 1.0 (0.0 where a
    pivot is 0 or NaN), from the pivots and the row swaps, without a branch.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> solve_signed(SCALAR, [[0.0, 2.0], [4.0, 1.0]], [2.0, 9.0])
    ([2.0, 1.0], -1.0)
    """
    (x,), _, sign = _eliminate(xp, A, [b], True)
    return x, sign


def solve_many(xp, A: list, B: list) -> tuple[list, list]:
    """``A^-1 b`` for each right-hand side ``b`` of ``B``, by Gaussian elimination with
    partial pivoting, and the magnitudes of the pivots.

    The pivoting takes no branch, so that it runs inside a kernel's loop: at column
    ``k`` each lower row in turn is swapped with row ``k`` where its entry is larger in
    magnitude, by blending the two rows with weights 0 and 1 (``w = max(sign(|a| -
    |p|), 0)``, exact): the largest entry of the column ends on the diagonal, as in
    LAPACK's partial pivoting, rows of equal magnitude left in place. ``A`` is a list of
    rows of numbers of ``xp`` (floats, arrays over states, mpmath, traced). A zero pivot
    divides by zero: ZeroDivisionError on floats and mpmath, inf or NaN on arrays and in
    kernels.

    Examples
    --------
    >>> from linkage_fmu.numerics import SCALAR
    >>> solve_many(SCALAR, [[0.0, 2.0], [4.0, 1.0]], [[1.0, 0.0], [0.0, 1.0]])[0]
    [[-0.125, 0.5], [0.25, 0.0]]
    """
    X, pivots, _ = _eliminate(xp, A, B, False)
    return X, pivots


def _eliminate(xp, A: list, B: list, signed: bool) -> tuple[list, list, object]:
    """:func:`solve_many`'s elimination; with ``signed``, also the sign of ``det A``
    (each swap taken, ``w = 1``, turns it; then the pivots' signs), else None."""
    n = len(A)
    A = [list(row) for row in A]
    B = [list(b) for b in B]
    pivots = []
    turned = 1.0
    for k in range(n):
        for i in range(k + 1, n):
            w = xp.maximum(xp.sign(xp.abs(A[i][k]) - xp.abs(A[k][k])), 0.0)
            v = 1.0 - w
            if signed:
                turned = turned * (1.0 - 2.0 * w)
            for c in range(k, n):
                A[k][c], A[i][c] = w * A[i][c] + v * A[k][c], w * A[k][c] + v * A[i][c]
            for b in B:
                b[k], b[i] = w * b[i] + v * b[k], w * b[k] + v * b[i]
        p = A[k][k]
        pivots.append(xp.abs(p))
        for i in range(k + 1, n):
            r = A[i][k] / p
            for c in range(k + 1, n):
                A[i][c] = A[i][c] - r * A[k][c]
            for b in B:
                b[i] = b[i] - r * b[k]
    X = []
    for b in B:
        x = [0.0] * n
        for i in reversed(range(n)):
            v = b[i]
            for c in range(i + 1, n):
                v = v - A[i][c] * x[c]
            x[i] = v / A[i][i]
        X.append(x)
    if not signed:
        return X, pivots, None
    sign = turned
    for k in range(n):
        sign = sign * xp.sign(A[k][k])
    return X, pivots, sign


def solve_unpivoted(J: list, g: list) -> list:
    """``J^-1 g`` for a small system near the identity, by Gaussian elimination without
    pivoting.

    The friction's Newton step (:func:`linkage_fmu.friction.solve_group`) solves ``J d =
    g`` with ``J = I - D K``: the identity less the friction law's derivatives ``D`` by
    the reactions times the reactions' responses ``K`` to unit friction values. ``J``
    is the identity at zero friction and its diagonal stays near 1 until the friction
    locks the group, which is where its :func:`determinant` (computed with each step)
    falls to zero: a state whose last determinant is not positive is self-locking,
    whatever the solve gave (:func:`linkage_fmu.newton.iterate`). So no row needs to be
    swapped, and without pivoting the step is the fewest operations, none of them a
    comparison, the same in the Python kernel and in a traced kernel's loop. Only the
    arithmetic operators are used: ``J`` and ``g`` may hold numbers of any kind.

    Parameters
    ----------
    J : list of lists
        The matrix, as rows (up to three: the friction values of one group).
    g : list
        The right-hand side.

    Returns
    -------
    list
        The solution. A zero pivot divides by zero (ZeroDivisionError on floats).

    Examples
    --------
    >>> solve_unpivoted([[1.0, 0.5], [0.25, 1.0]], [2.0, 2.25])
    [1.0, 2.0]
    """
    n = len(g)
    J = [list(row) for row in J]
    g = list(g)
    for k in range(n):
        for i in range(k + 1, n):
            r = J[i][k] / J[k][k]
            for c in range(k + 1, n):
                J[i][c] = J[i][c] - r * J[k][c]
            g[i] = g[i] - r * g[k]
    x = [0.0] * n
    for i in reversed(range(n)):
        v = g[i]
        for c in range(i + 1, n):
            v = v - J[i][c] * x[c]
        x[i] = v / J[i][i]
    return x


def determinant(J: list):
    """``det J`` of a small matrix by cofactor expansion along the first row: products
    and sums only, no division and no comparison (a traced kernel's loop runs it as
    it is; :func:`solve_unpivoted`'s system is at most 3 by 3).

    Examples
    --------
    >>> determinant([[2.0]]), determinant([[1.0, 2.0], [3.0, 4.0]])
    (2.0, -2.0)
    >>> determinant([[2.0, 0.0, 1.0], [1.0, 3.0, 0.0], [0.0, 1.0, 4.0]])
    25.0
    """
    n = len(J)
    if n == 1:
        return J[0][0]
    if n == 2:
        return J[0][0] * J[1][1] - J[0][1] * J[1][0]
    return sum(J[0][c] * determinant([row[:c] + row[c + 1:] for row in J[1:]]) * (-1.0) ** c
               for c in range(n))


def solve_adjugate(J: list, g: list) -> tuple[list, object]:
    """``J^-1 g`` and ``det J`` of a small system near the identity (as
    :func:`solve_unpivoted` solves, up to three unknowns): the adjugate times ``g``,
    times the one reciprocal of the :func:`determinant` (the same floats as it), where
    elimination divides once per row and once per pivot. Its minors are the
    determinant's own (a traced kernel computes each once). One unknown: ``g / J``;
    more than three: :func:`solve_unpivoted` and :func:`determinant`. Only the
    arithmetic operators: numbers of any kind. A zero determinant divides by zero
    (ZeroDivisionError on floats).

    Examples
    --------
    >>> solve_adjugate([[1.0, 0.5], [0.25, 1.0]], [2.0, 2.25])
    ([1.0, 2.0], 0.875)
    """
    n = len(g)
    if n == 1:
        return [g[0] / J[0][0]], J[0][0]
    if n > 3:
        return solve_unpivoted(J, g), determinant(J)
    det = determinant(J)
    inv = 1.0 / det

    def minor(r, c):  # of the entry (r, c): as determinant() expands it
        return determinant([row[:c] + row[c + 1:] for k, row in enumerate(J) if k != r])

    x = []
    for i in range(n):  # (adj J)[i][j] = (-1)^(i+j) minor(j, i): the sum of (-1)^j, then (-1)^i
        v = None
        for j in range(n):
            term = minor(j, i) * g[j]
            v = term if v is None else v - term if j % 2 else v + term
        x.append((-v if i % 2 else v) * inv)
    return x, det


def solve_batch(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``A[s]^-1 b[s]`` for every state ``s`` by numpy's LU (LAPACK's, partial pivoting);
    a singular state gives NaN instead of failing the batch.

    Parameters
    ----------
    A : ndarray, shape (states, n, n)
    b : ndarray, shape (states, n)

    Returns
    -------
    ndarray, shape (states, n)
        The solutions; all NaN for a state whose ``A`` numpy finds exactly singular.

    Examples
    --------
    >>> A = np.array([[[2.0, 0.0], [0.0, 4.0]], [[1.0, 2.0], [2.0, 4.0]]])
    >>> solve_batch(A, np.array([[2.0, 2.0], [1.0, 1.0]])).tolist()
    [[1.0, 0.5], [nan, nan]]
    """
    try:
        return np.linalg.solve(A, b[..., None])[..., 0]
    except np.linalg.LinAlgError:
        x = np.full(b.shape, np.nan)
        for i in range(A.shape[0]):
            try:
                x[i] = np.linalg.solve(A[i], b[i])
            except np.linalg.LinAlgError:
                pass
        return x


def solve_mpmath(n: int, a: list, b: list):
    """Solve the ``n`` equations given as nonzero entries ``a`` (row, column, value) and
    right-hand side ``b`` (row, value) by mpmath's LU with partial pivoting, at mpmath's
    working precision (mpmath is imported on the first call).

    Returns
    -------
    mpmath.matrix
        The solution, ``n`` by 1. An exactly singular system raises ZeroDivisionError.

    Examples
    --------
    >>> x = solve_mpmath(2, [(0, 0, 2.0), (0, 1, 1.0), (1, 1, 4.0)], [(0, 3.0), (1, 4.0)])
    >>> [float(v) for v in x]
    [1.0, 1.0]
    """
    import mpmath

    A, B = mpmath.zeros(n, n), mpmath.zeros(n, 1)
    for r, c, v in a:
        A[r, c] = v
    for r, v in b:
        B[r] = v
    return mpmath.lu_solve(A, B)
