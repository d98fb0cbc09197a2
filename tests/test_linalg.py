"""The linear solves of linkage_fmu.linalg against references: numpy.linalg.solve and
numpy.linalg.det (LAPACK's LU) for floats, mpmath.lu_solve at 50 digits for mpmath."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

from linkage_fmu import linalg
from linkage_fmu.numerics import ARRAY, SCALAR

RNG = np.random.default_rng(38)


def well_conditioned(n: int) -> np.ndarray:
    """A random ``n`` by ``n`` matrix with a condition number below 1e3 (an orthogonal
    matrix times a diagonal of singular values in [1, 10], rows scrambled)."""
    q, _ = np.linalg.qr(RNG.standard_normal((n, n)))
    return q * RNG.uniform(1.0, 10.0, n)


@pytest.mark.parametrize("n", [1, 2, 3, 6, 9])
def test_the_pivoted_solve_is_numpys(n):
    """Reference: numpy.linalg.solve. Tolerance: 1e-12 relative (cond < 1e3 times a few
    eps of rounding, with room); the sign of det A is numpy.linalg.det's exactly."""
    A, b = well_conditioned(n), RNG.standard_normal(n)
    x, pivots = linalg.solve(SCALAR, A.tolist(), b.tolist())
    np.testing.assert_allclose(x, np.linalg.solve(A, b), rtol=1e-12, atol=1e-12)
    x, sign = linalg.solve_signed(SCALAR, A.tolist(), b.tolist())
    assert sign == np.sign(np.linalg.det(A))
    # partial pivoting: |det A| is the product of the pivots' magnitudes
    assert np.prod(pivots) == pytest.approx(abs(np.linalg.det(A)), rel=1e-12)


def test_the_pivoted_solve_pivots_where_unpivoted_elimination_fails():
    """A zero in the top-left corner: the pivoted solve swaps rows, the unpivoted one
    divides by zero (floats: ZeroDivisionError)."""
    A, b = [[0.0, 2.0], [4.0, 1.0]], [2.0, 9.0]
    assert linalg.solve(SCALAR, A, b)[0] == [2.0, 1.0]
    with pytest.raises(ZeroDivisionError):
        linalg.solve_unpivoted(A, b)


def test_the_pivoted_solve_over_states_is_each_states():
    """Arrays over states solve each state as floats do, to the bit (the same operations
    elementwise), inverse columns included (solve_many against numpy.linalg.inv, 1e-12)."""
    As = [well_conditioned(4) for _ in range(5)]
    bs = [RNG.standard_normal(4) for _ in range(5)]
    A = [[np.array([M[r][c] for M in As]) for c in range(4)] for r in range(4)]
    b = [np.array([v[r] for v in bs]) for r in range(4)]
    x, _ = linalg.solve(ARRAY, A, b)
    for s in range(5):
        one, _ = linalg.solve(SCALAR, As[s].tolist(), bs[s].tolist())
        assert [float(v[s]) for v in x] == one
    unit = [[1.0 if r == c else 0.0 for r in range(4)] for c in range(4)]
    columns, _ = linalg.solve_many(SCALAR, As[0].tolist(), unit)
    np.testing.assert_allclose(np.array(columns).T, np.linalg.inv(As[0]), rtol=1e-12,
                               atol=1e-12)


@pytest.mark.parametrize("n", [1, 2, 3])
def test_the_unpivoted_solve_and_determinant_near_the_identity(n):
    """Reference: numpy.linalg.solve and numpy.linalg.det, on the identity plus terms of
    at most 0.3 (as the friction's Newton step has). Tolerance: 1e-14 relative."""
    J = np.eye(n) + RNG.uniform(-0.3, 0.3, (n, n))
    g = RNG.standard_normal(n)
    np.testing.assert_allclose(linalg.solve_unpivoted(J.tolist(), g.tolist()),
                               np.linalg.solve(J, g), rtol=1e-14, atol=1e-14)
    assert linalg.determinant(J.tolist()) == pytest.approx(np.linalg.det(J), rel=1e-14)


def test_the_determinant_of_a_singular_matrix_is_zero():
    assert linalg.determinant([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]]) == 0.0


def test_the_batch_solve_is_numpys_with_nan_for_a_singular_state():
    """Reference: numpy.linalg.solve of each state alone (1e-15 relative); an exactly
    singular state is all NaN, the others solved as alone."""
    A = np.array([well_conditioned(3), [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]],
                  well_conditioned(3)])
    b = RNG.standard_normal((3, 3))
    x = linalg.solve_batch(A, b)
    assert x.shape == (3, 3)
    assert np.isnan(x[1]).all()
    for s in (0, 2):
        np.testing.assert_allclose(x[s], np.linalg.solve(A[s], b[s]), rtol=1e-15)
    regular = A[[0, 2]]
    np.testing.assert_array_equal(linalg.solve_batch(regular, b[[0, 2]]),
                                  np.linalg.solve(regular, b[[0, 2], :, None])[..., 0])


def test_the_mpmath_solve_is_mpmaths_at_its_precision():
    """Reference: mpmath.lu_solve of the dense matrix at 50 digits, exactly (the same
    LU); and the solution solves the system to 1e-45."""
    A = well_conditioned(4)
    b = RNG.standard_normal(4)
    entries = [(r, c, A[r, c]) for r in range(4) for c in range(4) if A[r, c] != 0.0]
    with mpmath.workdps(50):
        x = linalg.solve_mpmath(4, entries, list(enumerate(b)))
        ref = mpmath.lu_solve(mpmath.matrix(A.tolist()), mpmath.matrix(b.tolist()))
        assert x == ref
        residual = mpmath.matrix(A.tolist()) * x - mpmath.matrix(b.tolist())
        assert mpmath.norm(residual, 1) < mpmath.mpf("1e-45")


def test_the_mpmath_solve_of_a_singular_system_raises():
    with pytest.raises(ZeroDivisionError):
        linalg.solve_mpmath(2, [(0, 0, 1.0), (0, 1, 2.0), (1, 0, 2.0), (1, 1, 4.0)],
                            [(0, 1.0), (1, 1.0)])
