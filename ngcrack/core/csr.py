"""A compressed sparse row matrix on numpy alone, for the condensed system of a small solve.

`import scipy.sparse` costs a small solve about as much CPU as the solve itself (scipy
builds an array-API copy of numpy at import, which loads numpy.f2py, numpy.testing and
numpy.random; measured in BENCHMARKS.md, the start-up section). The 2D solve path needs only a few operations on
the condensed matrix K and the change of basis T, and `CSR` gives exactly those on
numpy arrays (NGSolve's own CSR arrays without a copy where possible):

- row selection `A[rows]`, column selection `A[:, cols]` (distinct columns), the upper
  triangle, the diagonal, `abs`, a dense copy;
- products with a vector or a dense matrix, `A @ x` and `A.T @ x`.

Every product sums each entry's contribution in the order the entries are stored,
starting from zero, as scipy's sparse kernels do (np.bincount and np.add.at accumulate
in order): the results are bitwise those of scipy.sparse on the same arrays, which
tests/test_csr.py checks. `to_scipy()` gives the scipy matrix on the same arrays for
the paths that need scipy (other linear solvers, sparse-sparse products, 3D); it is
the only place that imports scipy.sparse.
"""

from __future__ import annotations

import numpy as np


class CSR:
    """A (rows x cols) sparse matrix in CSR form: `data`, `indices`, `indptr` as scipy has them."""

    __slots__ = ("data", "indices", "indptr", "shape", "_row_ids", "_scipy")

    def __init__(self, data, indices, indptr, shape: tuple[int, int]):
        self.data = np.asarray(data, dtype=float)
        self.indices = _signed(indices)
        self.indptr = _signed(indptr)
        self.shape = (int(shape[0]), int(shape[1]))
        self._row_ids = None
        self._scipy = None

    # ------------------------------------------------------------------ construction

    @classmethod
    def from_ngsolve(cls, mat) -> CSR:
        """NGSolve's sparse matrix on its own arrays (no copy of the values: valid while
        `mat` lives and is not reassembled)."""
        vals, cols, first = mat.CSR()
        return cls(np.asarray(vals), np.asarray(cols), np.asarray(first), (mat.height, mat.width))

    @classmethod
    def from_scipy(cls, A) -> CSR:
        """A scipy sparse matrix (any format) on its CSR arrays."""
        A = A.tocsr()
        return cls(A.data, A.indices, A.indptr, A.shape)

    @classmethod
    def from_triplets(cls, vals, rows, cols, shape: tuple[int, int], drop_zeros: bool = False) -> CSR | None:
        """The matrix of (row, col, value) triplets, columns sorted within each row and
        duplicates summed (as scipy's coo -> csr), explicit zeros dropped on request.

        Returns None where some (row, col) has three or more nonzero values: their sum
        then depends on the order of addition, and scipy's order (an unstable sort) is
        not reproduced here (the caller uses scipy instead). With at most two nonzero
        values (and any zeros) every order gives the same sum.
        """
        vals = np.asarray(vals, dtype=float)
        rows, cols = np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64)
        if drop_zeros:  # a zero changes no sum: dropped first, so the entries are sorted less often
            nz = vals != 0.0
            rows, cols, vals = rows[nz], cols[nz], vals[nz]
        key = rows * shape[1] + cols
        if not np.all(key[1:] > key[:-1]):  # not already sorted without duplicates
            order = np.argsort(key, kind="stable")
            rows, cols, vals, key = rows[order], cols[order], vals[order], key[order]
            new = np.ones(len(key), dtype=bool)
            new[1:] = key[1:] != key[:-1]
            if not new.all():
                group = np.cumsum(new) - 1
                if np.bincount(group, weights=(vals != 0.0)).max(initial=0) >= 3:
                    return None
                vals = np.bincount(group, weights=vals)
                rows, cols = rows[new], cols[new]
                if drop_zeros:  # sums that cancel
                    nz = vals != 0.0
                    rows, cols, vals = rows[nz], cols[nz], vals[nz]
        indptr = np.zeros(shape[0] + 1, dtype=np.int32 if max(shape) < 2**31 - 1 and len(vals) < 2**31 - 1 else np.int64)
        np.cumsum(np.bincount(rows, minlength=shape[0]), out=indptr[1:])
        return cls(vals, cols.astype(indptr.dtype), indptr, shape)

    def to_scipy(self):
        """The scipy CSR matrix on the same arrays (imports scipy.sparse; made once, the
        same object on every call)."""
        if self._scipy is None:
            import scipy.sparse as sp

            self._scipy = sp.csr_matrix((self.data, self.indices, self.indptr), shape=self.shape, copy=False)
        return self._scipy

    def tocsr(self) -> CSR:
        return self

    # ------------------------------------------------------------------ structure

    @property
    def nnz(self) -> int:
        return len(self.data)

    @property
    def row_ids(self) -> np.ndarray:
        """The row of every stored entry."""
        if self._row_ids is None:
            self._row_ids = np.repeat(np.arange(self.shape[0]), np.diff(self.indptr))
        return self._row_ids

    @property
    def T(self) -> TransposedCSR:
        return TransposedCSR(self)

    def _entries(self, mask: np.ndarray, indices: np.ndarray, shape: tuple[int, int]) -> CSR:
        """The entries where `mask` holds, with new column `indices` (in storage order)."""
        counts = np.bincount(self.row_ids[mask], minlength=self.shape[0])
        indptr = np.zeros(self.shape[0] + 1, dtype=self.indptr.dtype)
        np.cumsum(counts, out=indptr[1:])
        return CSR(self.data[mask], indices.astype(self.indices.dtype, copy=False), indptr, shape)

    def _rows(self, rows) -> CSR:
        if isinstance(rows, slice):
            rows = np.arange(self.shape[0])[rows]
        rows = np.asarray(rows)
        if rows.dtype == bool:
            rows = np.flatnonzero(rows)
        rows = np.where(rows < 0, rows + self.shape[0], rows)
        start, stop = self.indptr[rows], self.indptr[rows + 1]
        counts = stop - start
        indptr = np.zeros(len(rows) + 1, dtype=self.indptr.dtype)
        np.cumsum(counts, out=indptr[1:])
        take = np.repeat(start - indptr[:-1], counts) + np.arange(indptr[-1])
        return CSR(self.data[take], self.indices[take], indptr, (len(rows), self.shape[1]))

    def _cols(self, cols) -> CSR:
        if isinstance(cols, slice):
            if cols == slice(None):
                return self
            cols = np.arange(self.shape[1])[cols]
        cols = np.asarray(cols)
        if cols.dtype == bool:
            cols = np.flatnonzero(cols)
        cols = np.where(cols < 0, cols + self.shape[1], cols)
        new = np.full(self.shape[1], -1, dtype=np.int64)
        new[cols] = np.arange(len(cols))
        if np.count_nonzero(new >= 0) != len(cols):
            raise ValueError("CSR: a column selection must not repeat a column")
        at = new[self.indices]
        mask = at >= 0
        return self._entries(mask, at[mask], (self.shape[0], len(cols)))

    def __getitem__(self, key) -> CSR:
        if isinstance(key, tuple):
            rows, cols = key
            out = self if (isinstance(rows, slice) and rows == slice(None)) else self._rows(rows)
            return out._cols(cols)
        return self._rows(key)

    def triu(self) -> CSR:
        """The upper triangle (diagonal included)."""
        mask = self.indices >= self.row_ids
        return self._entries(mask, self.indices[mask], self.shape)

    def canonical(self) -> CSR:
        """This matrix with its columns increasing within each row and no duplicates
        (itself where that already holds, as for every matrix of the condensed system)."""
        step = np.diff(self.indices.astype(np.int64))
        first = np.zeros(len(self.indices), dtype=bool)
        first[self.indptr[:-1][np.diff(self.indptr) > 0]] = True
        if len(step) == 0 or np.all((step > 0) | first[1:]):
            return self
        out = CSR.from_triplets(self.data, self.row_ids, self.indices, self.shape)
        if out is None:
            return CSR.from_scipy(self.to_scipy().tocoo().tocsr())
        return out

    def diagonal(self) -> np.ndarray:
        on = self.indices == self.row_ids
        n = min(self.shape)
        return np.bincount(self.row_ids[on], weights=self.data[on], minlength=n)[:n]

    def __abs__(self) -> CSR:
        return CSR(np.abs(self.data), self.indices, self.indptr, self.shape)

    def toarray(self) -> np.ndarray:
        out = np.zeros(self.shape)
        np.add.at(out, (self.row_ids, self.indices), self.data)
        return out

    # ------------------------------------------------------------------ products

    def __matmul__(self, x):
        return _product(self.data, self.row_ids, self.indices, self.shape[0], x)


class TransposedCSR:
    """The transpose of a CSR matrix, for products (`A.T @ x`)."""

    __slots__ = ("A",)

    def __init__(self, A: CSR):
        self.A = A

    @property
    def shape(self) -> tuple[int, int]:
        return self.A.shape[::-1]

    def __matmul__(self, x):
        A = self.A
        return _product(A.data, A.indices, A.row_ids, A.shape[1], x)


def _signed(index) -> np.ndarray:
    """An index array as signed integers (NGSolve's CSR arrays are unsigned)."""
    index = np.asarray(index)
    return index if index.dtype.kind == "i" else index.astype(np.int64)


def _product(data: np.ndarray, out_index: np.ndarray, in_index: np.ndarray, n_out: int, x):
    """sum over stored entries k of data[k] x[in_index[k]] into row out_index[k], in storage order."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        return np.bincount(out_index, weights=data * x[in_index], minlength=n_out)
    out = np.zeros((n_out,) + x.shape[1:])
    np.add.at(out, out_index, data[:, None] * x[in_index])
    return out


def distinct(a) -> np.ndarray:
    """The sorted distinct values of `a`: np.unique(a) without its test for a masked array,
    which imports numpy.ma on first use (BENCHMARKS.md, the start-up section)."""
    s = np.sort(np.asarray(a).ravel())
    keep = np.ones(len(s), dtype=bool)
    keep[1:] = s[1:] != s[:-1]
    return s[keep]


def as_csr(A) -> CSR:
    """A CSR matrix of `A` (a CSR or a scipy sparse matrix)."""
    if isinstance(A, CSR):
        return A
    if hasattr(A, "tocsr"):
        return CSR.from_scipy(A)
    raise TypeError(f"a sparse matrix (ngcrack.core.csr.CSR or scipy.sparse) was expected, got {type(A).__name__}")


def to_scipy(A):
    """The scipy CSR matrix of `A` (a CSR on the same arrays, a scipy matrix as it is)."""
    return A.to_scipy() if isinstance(A, CSR) else A
