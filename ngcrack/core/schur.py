"""Sparse direct solvers and the Schur complement of the condensed system on the crack.

Partition the condensed unknowns y of K y = F (see `hybrid.py`) into the crack normal
jumps c (m of them) and the rest r. The crack QP needs

    S = K_cc - K_cr K_rr^{-1} K_rc        (m x m, dense, SPD)
    b = F_c - K_cr x0,   x0 = K_rr^{-1} F_r

and the recovery of the rest for given jumps jn is y_r = x0 - K_rr^{-1} K_rc jn.

How S is formed (`method`):

- "factor": a partial factorization of the whole K with c ordered last. An LDL^T (or
  LU) factorization that stops before the last m pivots leaves S in the trailing block,
  so S costs about as much as the factorization of K_rr alone. With
  linear_solver="pardiso" this is MKL PARDISO's Schur-complement option (iparm[35] = 2,
  through ctypes); the same partial factorization then solves with K_rr (forward
  substitution, diagonal, the crack block set to zero, backward substitution). With
  "superlu", a first factorization of K_rr gives a fill-reducing order, the whole K is
  refactorized in that order with c appended (no pivoting), and S = L_cc U_cc; the first
  factorization is kept for the solves.
- "blocked": SCHUR_BLOCK columns of K_rc solved at once, S = K_cc - K_cr X.
- "columns": one solve per crack unknown (the reference the others are tested against).
- "auto": "factor" for pardiso and superlu on positive definite systems, else "blocked".

Measured on the project's 2-core machine (BENCHMARKS.md section 2), paper-2 with BDM at
1.06e6 unknowns in total (3.03e5 condensed, m = 296): factorization of K_rr alone 0.9 s
(pardiso), 3.2 s (cholespy), 2.6 s (ngsolve sparsecholesky), 3.7 s (superlu). S on top:
pardiso "factor" 1.8 s for factorization and S together (S costs nothing extra beyond
start-up noise), superlu "factor" 3.7 + 5.9 s, cholespy "blocked" 3.0 + 7.2 s,
pardiso "blocked" 2.3 + 13.9 s, superlu "blocked" about 3 + 11 s, ngsolve column by
column about 2.6 + 38 s. An active-set method on K that never forms S needs one
factorization per step (7 steps, 11.3 s on paper-2 with PEERS at 1.0e6 unknowns).
MKL PARDISO's Schur option needs a positive definite K: on the saddle-point systems of
the incompressible split (`definite=False`) it perturbs thousands of pivots and S is off
by 1e-4, so those systems take a pivoting LU and "blocked".

The sparse direct solver (`linear_solver`): "pardiso" (MKL PARDISO, where the `mkl`
package is installed: a dependency on x86-64), "superlu" (scipy), "cholespy" (CHOLMOD
through the cholespy package) or "ngsolve" (NGSolve's sparsecholesky / umfpack).
"auto" is pardiso where MKL loads, else superlu.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import glob
import os
import sys
import time
import warnings
import weakref
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from .csr import CSR, as_csr, to_scipy
from .errors import InputError

#: columns of K_rc solved at once when forming the Schur complement ("blocked")
SCHUR_BLOCK = 64
#: the sparse direct solvers; "auto" = pardiso where MKL loads, else superlu
LINEAR_SOLVERS = ("auto", "pardiso", "superlu", "cholespy", "ngsolve")
#: how the Schur complement is formed (module docstring)
SCHUR_METHODS = ("auto", "factor", "blocked", "columns")


class LinearSolverError(RuntimeError):
    """The sparse direct solver failed (singular or indefinite matrix, out of memory)."""


# --------------------------------------------------------------------------- MKL PARDISO


@lru_cache(maxsize=1)
def _mkl() -> ctypes.CDLL | None:
    """MKL's single dynamic library (the `mkl` package puts it in <prefix>/lib), or None."""
    for path in _mkl_candidates():
        try:
            lib = ctypes.CDLL(path)
            fn = lib.pardiso_64
        except (OSError, AttributeError):
            continue
        i64 = np.ctypeslib.ndpointer(np.int64, flags="C")
        f64 = np.ctypeslib.ndpointer(np.float64, flags="C")
        p = ctypes.POINTER(ctypes.c_int64)
        # pardiso_64(pt, maxfct, mnum, mtype, phase, n, a, ia, ja, perm, nrhs, iparm, msglvl, b, x, error)
        fn.argtypes = [i64, p, p, p, p, p, f64, i64, i64, i64, p, i64, p, f64, f64, p]
        fn.restype = None
        _sequential_if_one_thread(lib)
        return lib
    return None


def _sequential_if_one_thread(lib: ctypes.CDLL) -> None:
    """MKL's sequential layer where the solves run on one thread (NGCRACK_THREADS or
    OMP_NUM_THREADS = 1) and MKL_THREADING_LAYER does not choose: the same factorization
    without starting OpenMP, which a small solve's first factorization notices. Decided once,
    when MKL loads."""
    from .parallel import thread_count

    if os.environ.get("MKL_THREADING_LAYER") is None and thread_count() == 1:
        with contextlib.suppress(AttributeError):
            lib.MKL_Set_Threading_Layer(ctypes.c_int(1))  # MKL_THREADING_SEQUENTIAL


def _mkl_candidates():
    """Paths to try for MKL's library: the environment's own first; the system's search
    (ctypes.util.find_library, which runs ldconfig and a compiler in subprocesses: about
    0.02 s) only when none of those loads."""
    for prefix in {sys.prefix, sys.base_prefix}:
        yield from sorted(glob.glob(os.path.join(prefix, "lib", "libmkl_rt.so*")))
        yield from sorted(glob.glob(os.path.join(prefix, "Library", "bin", "mkl_rt*.dll")))
    found = ctypes.util.find_library("mkl_rt")
    if found:
        yield found


def mkl_available() -> bool:
    """True where MKL PARDISO can be loaded (the `mkl` package is installed)."""
    return _mkl() is not None


def default_linear_solver() -> str:
    """What linear_solver="auto" means here: pardiso where MKL loads, else superlu."""
    return "pardiso" if mkl_available() else "superlu"


#: PARDISO error codes (the `error` argument) and what they mean here
_PARDISO_ERRORS = {
    -1: "input inconsistent",
    -2: "not enough memory",
    -3: "reordering problem",
    -4: "zero pivot (the matrix is singular or not positive definite: is every part of the body held?)",
    -5: "unclassified internal error",
    -6: "reordering failed",
    -7: "diagonal matrix is singular",
    -8: "32-bit integer overflow",
    -9: "not enough memory for out-of-core",
    -10: "error opening out-of-core files",
    -11: "read/write error with out-of-core files",
    -12: "wrong pardiso_64 / pardiso call",
}
#: PARDISO matrix types: real symmetric positive definite, real nonsymmetric, real symmetric indefinite
_SPD, _NONSYM, _SYMIND = 2, 11, -2


def _pardiso_arrays(K: CSR, upper: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """PARDISO's (a, ia, ja) of a canonical CSR matrix: its upper triangle (diagonal included) for the symmetric
    types, else all of it; int64 indices. Made in one pass with only short-lived temporaries (no row index of
    every entry is cached on K, no int32 copy of the triangle kept): what is alive during the factorization
    is the caller's K and these arrays."""
    counts = np.diff(K.indptr)
    if not upper:
        return (np.ascontiguousarray(K.data, dtype=np.float64), np.ascontiguousarray(K.indptr, dtype=np.int64),
                np.ascontiguousarray(K.indices, dtype=np.int64))
    rows = np.repeat(np.arange(K.shape[0], dtype=K.indices.dtype), counts)
    mask = K.indices >= rows
    kept = np.bincount(rows[mask], minlength=K.shape[0])
    del rows
    ia = np.zeros(K.shape[0] + 1, dtype=np.int64)
    np.cumsum(kept, out=ia[1:])
    a = np.ascontiguousarray(K.data[mask], dtype=np.float64)
    ja = K.indices[mask].astype(np.int64)
    return a, ia, ja


class _Pardiso:
    """One MKL PARDISO factorization (pardiso_64, zero-based CSR), optionally with S.

    `schur` lists unknowns kept out of the factorization: their Schur complement is
    returned densely (`self.S`) and the partial factor solves with the other block.
    """

    def __init__(self, K, mtype: int = _SPD, schur: np.ndarray | None = None):
        lib = _mkl()
        if lib is None:
            raise LinearSolverError("linear_solver = 'pardiso' needs MKL (pip install mkl)")
        self._fn = lib.pardiso_64
        K = as_csr(K).canonical()  # K (a CSR or scipy matrix): columns increasing in each row, no duplicates
        self.n = K.shape[0]
        self.mtype = mtype
        self.a, self.ia, self.ja = _pardiso_arrays(K, upper=mtype != _NONSYM)
        del K  # nothing of the caller's matrix is held beyond PARDISO's own arrays (the factorization's peak)
        self.pt = np.zeros(64, dtype=np.int64)
        self.iparm = np.zeros(64, dtype=np.int64)
        ip = self.iparm
        ip[0] = 1  # values below are supplied, the rest default (0)
        ip[1] = 2  # METIS nested dissection
        ip[7] = 2  # at most two steps of iterative refinement in phase 33
        ip[9] = 13 if mtype == _NONSYM else 8  # pivot perturbation 1e-13 / 1e-8
        ip[10] = 0 if mtype == _SPD else 1  # scaling (not for the definite matrix)
        ip[12] = 0 if mtype == _SPD else 1  # weighted matching (likewise)
        ip[17] = -1  # report the nonzeros of the factor
        ip[34] = 1  # zero-based indexing
        self.perm = np.zeros(self.n, dtype=np.int64)  # PARDISO may overwrite it
        self.rest = np.ones(self.n, dtype=bool)
        self.m = 0
        if schur is not None and len(schur):
            self.perm[np.asarray(schur)] = 1
            self.rest[np.asarray(schur)] = False
            ip[35] = 2  # Schur complement, and a partial factorization that solves with the rest
            self.m = len(schur)
        out = np.zeros(self.m * self.m if self.m else 1)
        self._call(12, np.zeros(1), out)
        self.S = out.reshape(self.m, self.m) if self.m else None
        weakref.finalize(self, _Pardiso._release, self._fn, self.pt, self.n)

    @staticmethod
    def _release(fn, pt, n):
        one = ctypes.c_int64(1)
        err = ctypes.c_int64(0)
        dummy_i = np.zeros(1, dtype=np.int64)
        dummy_f = np.zeros(1)
        fn(pt, ctypes.byref(one), ctypes.byref(one), ctypes.byref(ctypes.c_int64(_SPD)), ctypes.byref(ctypes.c_int64(-1)),
           ctypes.byref(ctypes.c_int64(n)), dummy_f, dummy_i, dummy_i, dummy_i, ctypes.byref(one),
           np.zeros(64, dtype=np.int64), ctypes.byref(ctypes.c_int64(0)), dummy_f, dummy_f, ctypes.byref(err))

    def _call(self, phase: int, b: np.ndarray, x: np.ndarray, nrhs: int = 1) -> None:
        one = ctypes.c_int64(1)
        err = ctypes.c_int64(0)
        self._fn(self.pt, ctypes.byref(one), ctypes.byref(one), ctypes.byref(ctypes.c_int64(self.mtype)),
                 ctypes.byref(ctypes.c_int64(phase)), ctypes.byref(ctypes.c_int64(self.n)), self.a, self.ia, self.ja,
                 self.perm, ctypes.byref(ctypes.c_int64(nrhs)), self.iparm, ctypes.byref(ctypes.c_int64(0)), b, x,
                 ctypes.byref(err))
        if err.value != 0:
            what = _PARDISO_ERRORS.get(int(err.value), "unknown error")
            raise LinearSolverError(f"MKL PARDISO phase {phase} failed with error {err.value}: {what}")

    def _phase(self, phase: int, b: np.ndarray) -> np.ndarray:
        """Apply one solve phase to a vector or to the columns of a matrix."""
        bt = np.ascontiguousarray(b.T if b.ndim == 2 else b, dtype=np.float64)
        x = np.zeros_like(bt)
        self._call(phase, bt, x, 1 if b.ndim == 1 else b.shape[1])
        return x.T if b.ndim == 2 else x

    def solve(self, b: np.ndarray) -> np.ndarray:
        """K^{-1} b (no Schur block), or K_rr^{-1} b_r on the non-Schur unknowns."""
        if not self.m:
            return self._phase(33, b)
        rest = self.rest
        full = np.zeros((self.n,) + b.shape[1:])
        full[rest] = b
        z = self._phase(332, self._phase(331, full))
        z[~rest] = 0.0  # the Schur unknowns held at zero
        return self._phase(333, z)[rest]


# --------------------------------------------------------------------------- factorizations


class Factorization:
    """A sparse direct factorization of a symmetric matrix with (multi-RHS) solves.

    backend: "pardiso" (MKL PARDISO), "superlu" (scipy's SuperLU), "cholespy" (CHOLMOD)
    or "ngsolve" (NGSolve's sparsecholesky); "auto" = `default_linear_solver()`.
    `definite=False` (a symmetric saddle point, e.g. the element pressures of the
    incompressible split) switches to pivoting LU: SuperLU with partial pivoting,
    PARDISO's nonsymmetric LU with matching, or UMFPACK through NGSolve; cholespy refuses.
    With `symmetric` too, PARDISO factorizes the symmetric indefinite matrix (Bunch-Kaufman
    pivoting, scaling and matching) from one triangle, about half the LU's memory; every
    diagonal entry must then be stored, zeros included (the other backends: as without).
    """

    BACKENDS = LINEAR_SOLVERS

    def __init__(self, K, backend: str = "auto", definite: bool = True, symmetric: bool = False):
        if backend not in self.BACKENDS:
            raise InputError(f"linear_solver = {backend!r}: allowed values are {', '.join(self.BACKENDS)}")
        if backend == "auto":
            backend = default_linear_solver()
        self.backend = backend
        self.n = K.shape[0]
        self.lu = None  # the SuperLU object, where there is one
        if self.n == 0:
            self._solve = lambda b: np.zeros_like(b)
            return
        if backend not in ("pardiso",):  # the other solvers take scipy's matrices
            import scipy.sparse as sp

            K = to_scipy(K)
        if backend == "superlu":
            import scipy.sparse.linalg as spla  # (with scipy.linalg: loaded only where used)

            if definite:
                lu = spla.splu(sp.csc_matrix(K), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                               options={"SymmetricMode": True})
            else:
                lu = spla.splu(sp.csc_matrix(K), permc_spec="COLAMD", diag_pivot_thresh=1.0)
            self.lu = lu
            self._solve = lu.solve
        elif backend == "pardiso":
            self._solve = _Pardiso(K, _SPD if definite else _SYMIND if symmetric else _NONSYM).solve
        elif backend == "cholespy":
            if not definite:
                raise InputError("linear_solver = 'cholespy' needs a positive definite matrix; use 'superlu' or 'pardiso'")
            from cholespy import CholeskySolverD, MatrixType

            coo = sp.coo_matrix(K)
            chol = CholeskySolverD(self.n, coo.row.astype(np.int32), coo.col.astype(np.int32),
                                   coo.data.astype(np.float64), MatrixType.COO)

            def solve(b):
                rhs = np.ascontiguousarray(b, dtype=np.float64)
                x = np.zeros_like(rhs)
                chol.solve(rhs, x)
                return x

            self._solve = solve
        else:
            import ngsolve as ngs

            coo = sp.coo_matrix(K)
            mat = ngs.la.SparseMatrixd.CreateFromCOO(coo.row.astype(np.int64), coo.col.astype(np.int64),
                                                     coo.data.astype(np.float64), self.n, self.n)
            inv = mat.Inverse(inverse="sparsecholesky" if definite else "umfpack")
            x = mat.CreateColVector()
            y = mat.CreateColVector()

            def solve(b):
                b2 = b.reshape(self.n, -1)
                out = np.empty_like(b2)
                for k in range(b2.shape[1]):
                    x.FV().NumPy()[:] = b2[:, k]
                    y.data = inv * x
                    out[:, k] = y.FV().NumPy()
                return out.reshape(b.shape)

            self._solve = solve

    def solve(self, b: np.ndarray) -> np.ndarray:
        """K^{-1} b for a vector or a matrix of right-hand sides."""
        return self._solve(np.asarray(b, dtype=float))


class _PartialFactorization(Factorization):
    """K_rr factorized as part of a factorization of the whole K with c last; `S` is its by-product."""

    def __init__(self, backend: str, solve, S: np.ndarray, n: int):
        self.backend = backend
        self.n = n
        self.lu = None
        self._solve = solve
        self.S = S


def _pardiso_schur(K: CSR, rest: np.ndarray, contact: np.ndarray) -> _PartialFactorization:
    """S from MKL PARDISO's partial factorization of K with the crack unknowns last."""
    p = _Pardiso(K, _SPD, schur=contact)
    # the partial factor solves in the original order of the unknowns, which is K_rr's
    # order only if `rest` is increasing (as CondensedSystem makes it)
    if np.any(np.diff(rest) <= 0):
        raise ValueError("schur = 'factor' with pardiso needs the rest unknowns in increasing order")
    return _PartialFactorization("pardiso", p.solve, np.array(p.S), len(rest))


def _superlu_schur(K, rest: np.ndarray, contact: np.ndarray, fac: Factorization) -> np.ndarray | None:
    """S = L_cc U_cc from SuperLU on K reordered as (K_rr's fill-reducing order, c); None if SuperLU pivoted."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    K = to_scipy(K)

    nr = len(rest)
    order = np.concatenate([rest[np.argsort(fac.lu.perm_c)], contact])
    Kp = sp.csc_matrix(K[order][:, order])
    lu = spla.splu(Kp, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    tail = np.arange(nr, K.shape[0])
    if not (np.array_equal(lu.perm_r[nr:], tail) and np.array_equal(lu.perm_c[nr:], tail)):
        return None
    L = sp.csc_matrix(lu.L)[:, nr:].tocsr()[nr:]
    U = sp.csc_matrix(lu.U)[:, nr:].tocsr()[nr:]
    return L.toarray() @ U.toarray()


# --------------------------------------------------------------------------- the Schur complement


@dataclass
class SchurData:
    """S, b, x0 and the factorization of K_rr (see the module docstring)."""

    S: np.ndarray
    b: np.ndarray
    x0: np.ndarray
    factorization: Factorization
    method: str
    largest_dense: int  # entries of the largest dense array built (S: m * m)
    timings: dict = field(default_factory=dict)


def resolve_method(method: str, linear_solver: str, definite: bool) -> tuple[str, str]:
    """The (linear_solver, method) that "auto" stands for, validated."""
    if linear_solver not in LINEAR_SOLVERS:
        raise InputError(f"linear_solver = {linear_solver!r}: allowed values are {', '.join(LINEAR_SOLVERS)}")
    if method not in SCHUR_METHODS:
        raise InputError(f"schur = {method!r}: allowed values are {', '.join(SCHUR_METHODS)}")
    solver = default_linear_solver() if linear_solver == "auto" else linear_solver
    if method == "auto":
        method = "factor" if definite and solver in ("pardiso", "superlu") else "blocked"
    if method == "factor" and solver not in ("pardiso", "superlu"):
        raise InputError(f"schur = 'factor' (a partial factorization) needs linear_solver = 'pardiso' or 'superlu', not {solver!r}")
    if method == "factor" and not definite:
        warnings.warn("schur = 'factor' needs a positive definite system; this one is a saddle point: using 'blocked'",
                      stacklevel=3)
        method = "blocked"
    return solver, method


def schur_complement(K, F: np.ndarray, rest: np.ndarray, contact: np.ndarray,
                     linear_solver: str = "auto", method: str = "auto", definite: bool = True) -> SchurData:
    """Factorize K_rr and form S and b on the unknowns `contact` (module docstring).

    K is a `csr.CSR` or a scipy.sparse matrix. Timings: "factorize" (for "factor" it
    includes S, which comes out of the same factorization), "solve" (x0 and b) and
    "schur" (the extra work for S).
    """
    K = as_csr(K)
    solver, method = resolve_method(method, linear_solver, definite)
    m = len(contact)
    t0 = time.perf_counter()
    S = None
    if m and method == "factor" and solver == "pardiso":
        fac = _pardiso_schur(K, rest, contact)
        S = fac.S
    else:
        fac = Factorization(K[rest][:, rest], backend=solver, definite=definite)
    t1 = time.perf_counter()
    x0 = fac.solve(F[rest])
    b = F[contact] - K[contact][:, rest] @ x0 if m else np.zeros(0)
    t2 = time.perf_counter()
    largest = m * m
    if m and S is None:
        import scipy.sparse as sp  # (a partial factorization without PARDISO, or blocked solves)

        K_cc = K[contact][:, contact].toarray()
        K_cr = K[contact][:, rest].to_scipy()
        if method == "factor":  # superlu
            S = _superlu_schur(K, rest, contact, fac)
            if S is None:
                warnings.warn("SuperLU pivoted in the partial factorization; forming S by blocked solves", stacklevel=2)
                method = "blocked"
        if S is None:
            K_rc = sp.csc_matrix(K[rest][:, contact].to_scipy())
            block = SCHUR_BLOCK if method == "blocked" else 1
            S = np.empty((m, m))
            for start in range(0, m, block):
                cols = slice(start, min(start + block, m))
                rhs = K_rc[:, cols].toarray()
                X = fac.solve(rhs if block > 1 else rhs[:, 0]).reshape(len(rest), -1)
                S[:, cols] = K_cc[:, cols] - K_cr @ X
            largest = max(largest, len(rest) * min(block, m))
    if m:
        S = 0.5 * (S + S.T)
    else:
        S = np.zeros((0, 0))
    t3 = time.perf_counter()
    return SchurData(S=S, b=b, x0=x0, factorization=fac, method=method, largest_dense=largest,
                     timings={"factorize": t1 - t0, "solve": t2 - t1, "schur": t3 - t2})
