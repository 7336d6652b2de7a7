"""ngcrack.core.csr gives bitwise scipy.sparse's results on the same arrays.

The condensed system of a 2D solve is held as `csr.CSR` (numpy alone) so that a small
solve does not import scipy.sparse; its answers must not change by a bit. Each
operation the solve path uses is compared here with scipy's, entry by entry and bit by
bit (array_equal, not a tolerance): the triplet form with duplicates, row and column
selection, the upper triangle, the diagonal, abs, the dense copy and the products
A @ x, A.T @ x, A @ X and A.T @ X.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from ngcrack.core.csr import CSR, as_csr, to_scipy


def _same(A: CSR, B) -> bool:
    B = B.tocsr()
    return (A.shape == B.shape and np.array_equal(A.indptr, B.indptr) and np.array_equal(A.indices, B.indices)
            and np.array_equal(A.data, B.data))


def _random(n: int, m: int, density: float, seed: int) -> sp.csr_matrix:
    A = sp.random(n, m, density=density, random_state=seed, format="csr")
    A.data = np.random.default_rng(seed).normal(size=A.nnz) * 10.0 ** np.random.default_rng(seed + 1).integers(-8, 8, A.nnz)
    return A


@pytest.mark.parametrize("seed", range(4))
def test_triplets_with_at_most_two_nonzero_duplicates_equal_scipy_bitwise(seed):
    rng = np.random.default_rng(seed)
    n, k = 30, 600
    rows, cols = rng.integers(0, n, k), rng.integers(0, n, k)
    vals = rng.normal(size=k)
    # a duplicate (row, col) gets at most two nonzero values; the others zeros
    seen: dict = {}
    for t, key in enumerate(zip(rows.tolist(), cols.tolist())):
        seen[key] = seen.get(key, 0) + 1
        if seen[key] > 2:
            vals[t] = 0.0 if t % 2 else -0.0
    ref = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    ref.sum_duplicates()
    assert _same(CSR.from_triplets(vals, rows, cols, (n, n)), ref)
    ref.eliminate_zeros()
    assert _same(CSR.from_triplets(vals, rows, cols, (n, n), drop_zeros=True), ref)


def test_three_nonzero_duplicates_are_left_to_scipy():
    assert CSR.from_triplets([1.0, 1e-16, -1.0], [0, 0, 0], [1, 1, 1], (2, 2)) is None


@pytest.mark.parametrize("seed", range(4))
def test_selection_triangle_diagonal_and_products_equal_scipy_bitwise(seed):
    rng = np.random.default_rng(seed)
    S = _random(80, 70, 0.2, seed)
    A = CSR.from_scipy(S)
    rows = np.sort(rng.choice(80, 50, replace=False))
    cols = np.sort(rng.choice(70, 40, replace=False))
    assert _same(A[rows], S[rows])
    assert _same(A[rows][:, cols], S[rows][:, cols])
    assert _same(A[:, cols], S[:, cols])
    assert _same(A[rows[::-1]], S[rows[::-1]])
    Q = _random(60, 60, 0.2, seed + 10)
    assert _same(CSR.from_scipy(Q).triu(), sp.triu(Q, format="csr"))
    assert np.array_equal(CSR.from_scipy(Q).diagonal(), Q.diagonal())
    assert _same(abs(A), abs(S))
    assert np.array_equal(A.toarray(), S.toarray())
    x, y = rng.normal(size=70), rng.normal(size=80)
    X, Y = rng.normal(size=(70, 5)), rng.normal(size=(80, 7))
    assert np.array_equal(A @ x, S @ x)
    assert np.array_equal(A.T @ y, S.T @ y)
    assert np.array_equal(A @ X, S @ X)
    assert np.array_equal(A.T @ Y, S.T @ Y)


def test_to_scipy_is_made_once_on_the_same_arrays():
    S = _random(20, 20, 0.3, 7)
    A = CSR.from_scipy(S)
    assert A.to_scipy() is A.to_scipy() and _same(A, A.to_scipy())
    assert to_scipy(S) is S and as_csr(A) is A
    with pytest.raises(TypeError, match="sparse matrix"):
        as_csr(np.eye(2))


def test_canonical_sorts_and_sums_an_unsorted_matrix():
    A = CSR([1.0, 2.0, 3.0, 4.0], [2, 0, 2, 1], [0, 3, 4], (2, 3))
    ref = sp.csr_matrix(([1.0, 2.0, 3.0, 4.0], [2, 0, 2, 1], [0, 3, 4]), shape=(2, 3))
    ref.sum_duplicates()
    assert _same(A.canonical(), ref)
    C = A.canonical()
    assert C.canonical() is C
