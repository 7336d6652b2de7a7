"""The statically condensed system and its Schur complement on the crack unknowns.

NGSolve condenses every element-local unknown (condense=True); what stays is the
facet trace u_hat, the crack jump (jn, jt) and, for PEERS, the rotation's vertex values.
The condensed form of the hybrid saddle point is negative definite on these global
unknowns; with the sign flipped, K x = F is symmetric positive definite once clamped
and roller edges hold every part of the body.

Boundary conditions on u_hat:
- clamped / displacement: the dofs are fixed (NGSolve Dirichlet dofs) and moved to
  the right-hand side;
- roller: u_hat . n = 0 by a change of basis per facet dof pair (ux, uy) -> the
  tangential coordinate only, x = T y, so K stays symmetric positive definite.

Partition the remaining unknowns into the crack normal jumps c (m of them) and the rest
r. With jn = 0, the rest solves K_rr x_r = F_r; the contact problem in jn alone is the
QP with S = K_cc - K_cr K_rr^{-1} K_rc and b = F_c - K_cr K_rr^{-1} F_r.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import ngsolve as ngs
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .elements import Discretization, Loads

#: columns of K_rc solved at once when forming the Schur complement
SCHUR_BLOCK = 64


def _bits(ba: ngs.BitArray) -> np.ndarray:
    return np.array(list(ba), dtype=bool)


def _to_scipy(mat) -> sp.csr_matrix:
    rows, cols, vals = mat.COO()
    n = mat.height
    return sp.csr_matrix((np.asarray(vals), (np.asarray(rows), np.asarray(cols))), shape=(n, n))


class Factorization:
    """A sparse direct factorization of a symmetric matrix with (multi-RHS) solves.

    backend "superlu" (scipy's SuperLU) is the default; "ngsolve" uses NGSolve's
    sparse Cholesky. `definite=False` (a symmetric saddle point, e.g. the element
    pressures of the incompressible split) switches to pivoting LU: SuperLU with
    partial pivoting, or UMFPACK through NGSolve.
    """

    BACKENDS = ("superlu", "ngsolve")

    def __init__(self, K: sp.spmatrix, backend: str = "superlu", definite: bool = True):
        if backend not in self.BACKENDS:
            raise ValueError(f"linear_solver = {backend!r}: allowed values are {', '.join(self.BACKENDS)}")
        self.backend = backend
        self.n = K.shape[0]
        if self.n == 0:
            self._solve = lambda b: np.zeros_like(b)
            return
        if backend == "superlu":
            if definite:
                lu = spla.splu(sp.csc_matrix(K), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                               options={"SymmetricMode": True})
            else:
                lu = spla.splu(sp.csc_matrix(K), permc_spec="COLAMD", diag_pivot_thresh=1.0)
            self._solve = lu.solve
        else:
            coo = sp.coo_matrix(K)
            mat = ngs.la.SparseMatrixd.CreateFromCOO(
                list(coo.row.astype(int)), list(coo.col.astype(int)), list(coo.data), self.n, self.n
            )
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


@dataclass
class CondensedSystem:
    """K y = F on the global unknowns y, with the crack normal jumps at `contact`.

    `to_global(y)` maps back to the condensed NGSolve unknowns (fixed values included);
    `expand(y)` returns the full NGSolve GridFunction (local unknowns recovered).
    """

    disc: Discretization
    K: sp.csr_matrix
    F: np.ndarray
    contact: np.ndarray  # positions of the jn unknowns in y
    rest: np.ndarray  # positions of all other unknowns in y
    _T: sp.csr_matrix
    _free: np.ndarray
    _fixed: np.ndarray
    _x_fixed: np.ndarray
    _fmod: ngs.BaseVector
    timings: dict = field(default_factory=dict)

    @property
    def n(self) -> int:
        return self.K.shape[0]

    def without_contact(self) -> "CondensedSystem":
        """The same system with the crack normal jumps treated as ordinary unknowns."""
        return CondensedSystem(
            disc=self.disc, K=self.K, F=self.F, contact=np.zeros(0, dtype=int), rest=np.arange(self.n),
            _T=self._T, _free=self._free, _fixed=self._fixed, _x_fixed=self._x_fixed, _fmod=self._fmod,
            timings=dict(self.timings),
        )

    def expand(self, y: np.ndarray) -> ngs.GridFunction:
        gf = ngs.GridFunction(self.disc.fes)
        vec = gf.vec.FV().NumPy()
        vec[:] = 0.0
        vec[self._free] = self._T @ y
        vec[self._fixed] = self._x_fixed
        a = self.disc.a
        gf.vec.data += a.harmonic_extension * gf.vec
        gf.vec.data += a.inner_solve * self._fmod
        return gf


#: normals whose cross product is below this count as parallel (one roller direction)
PARALLEL_TOL = 1e-9


def _merge_roller_pairs(pairs: list) -> list:
    """One entry per dof pair; a dof on two rollers with different normals gets None (fixed)."""
    merged: dict[tuple[int, int], np.ndarray | None] = {}
    for dx, dy, nrm in pairs:
        key = (dx, dy)
        if key not in merged:
            merged[key] = nrm
        elif merged[key] is not None and abs(merged[key][0] * nrm[1] - merged[key][1] * nrm[0]) > PARALLEL_TOL:
            merged[key] = None
    return [(dx, dy, nrm) for (dx, dy), nrm in merged.items()]


def condense(disc: Discretization, loads: Loads) -> CondensedSystem:
    """Build K, F on the global unknowns of an assembled discretization."""
    t0 = time.perf_counter()
    fes, a, f = disc.fes, disc.a, disc.f
    fmod = f.vec.CreateVector()
    fmod.data = f.vec
    fmod.data += a.harmonic_extension_trans * fmod
    A = _to_scipy(a.mat)
    coupling_free = _bits(fes.FreeDofs(True))
    fixed = ~_bits(fes.FreeDofs(False))
    free_idx = np.flatnonzero(coupling_free)
    fixed_idx = np.flatnonzero(fixed)
    # prescribed displacement values on the fixed dofs (clamped: zero)
    x_fixed = np.zeros(len(fixed_idx))
    if loads.displacement:
        gf = ngs.GridFunction(fes)
        disc.boundary_values(gf, loads)
        x_fixed = gf.vec.FV().NumPy()[fixed_idx].copy()
    # roller change of basis on the free global dofs (for elements whose displacement
    # unknowns on an edge are Cartesian components)
    pos = -np.ones(fes.ndof, dtype=int)
    pos[free_idx] = np.arange(len(free_idx))
    pairs = _merge_roller_pairs(disc.roller_pairs(loads.roller))
    rolled = np.zeros(len(free_idx), dtype=bool)
    for dx, dy, _ in pairs:
        rolled[pos[dx]] = rolled[pos[dy]] = True
    for d in disc.fixed_dofs:  # held at zero: no column
        rolled[pos[d]] = True
    pairs = [(dx, dy, nrm) for dx, dy, nrm in pairs if nrm is not None]
    keep = np.flatnonzero(~rolled)
    n_red = len(keep) + len(pairs)
    rows = np.concatenate([keep, [pos[dx] for dx, _, _ in pairs], [pos[dy] for _, dy, _ in pairs]]).astype(int)
    cols = np.concatenate([np.arange(len(keep)), len(keep) + np.arange(len(pairs)), len(keep) + np.arange(len(pairs))]).astype(int)
    vals = np.concatenate([np.ones(len(keep)), [-nrm[1] for *_, nrm in pairs], [nrm[0] for *_, nrm in pairs]])
    T = sp.csr_matrix((vals, (rows, cols)), shape=(len(free_idx), n_red))
    A_ff = A[free_idx][:, free_idx]
    A_fd = A[free_idx][:, fixed_idx]
    rhs = fmod.FV().NumPy()[free_idx] - A_fd @ x_fixed
    K = sp.csr_matrix(disc.sign * (T.T @ A_ff @ T))
    K.eliminate_zeros()
    F = disc.sign * (T.T @ rhs)
    contact = np.zeros(0, dtype=int)
    if disc.jn is not None:
        rng = fes.Range(disc.jn)
        jn_dofs = np.arange(rng.start, rng.stop)
        # jn dofs are never rolled: their position in y equals their position in `keep`
        where = {int(k): i for i, k in enumerate(keep)}
        contact = np.array([where[int(pos[d])] for d in jn_dofs], dtype=int)
    mask = np.ones(n_red, dtype=bool)
    mask[contact] = False
    return CondensedSystem(
        disc=disc,
        K=K,
        F=F,
        contact=contact,
        rest=np.flatnonzero(mask),
        _T=T,
        _free=free_idx,
        _fixed=fixed_idx,
        _x_fixed=x_fixed,
        _fmod=fmod,
        timings={"condense": time.perf_counter() - t0},
    )


@dataclass
class ContactReduction:
    """The crack QP data of a condensed system and the means to recover the rest.

    S (m x m, dense, SPD) and b as in the module docstring; `x0` is the rest's solution
    for jn = 0 (a bonded crack in the normal direction, free to slide).
    """

    S: np.ndarray
    b: np.ndarray
    x0: np.ndarray
    factorization: Factorization
    system: CondensedSystem
    timings: dict = field(default_factory=dict)

    def recover(self, jn: np.ndarray) -> np.ndarray:
        """The full global vector y for given crack normal jumps (one more solve)."""
        sysm = self.system
        y = np.zeros(sysm.n)
        y[sysm.contact] = jn
        if len(jn) and np.any(jn):
            K_rc = sysm.K[sysm.rest][:, sysm.contact]
            y[sysm.rest] = self.x0 - self.factorization.solve(K_rc @ jn)
        else:
            y[sysm.rest] = self.x0
        return y


def reduce_to_contact(system: CondensedSystem, linear_solver: str = "superlu", schur: bool = True) -> ContactReduction:
    """Factorize K_rr and form the Schur complement S on the crack normal jumps.

    With schur=False only K_rr is factorized and x0 solved (a bonded crack).
    """
    K, F = system.K, system.F
    r, c = system.rest, system.contact
    t0 = time.perf_counter()
    K_rr = K[r][:, r]
    fac = Factorization(K_rr, backend=linear_solver, definite=system.disc.definite)
    t1 = time.perf_counter()
    x0 = fac.solve(F[r])
    t2 = time.perf_counter()
    m = len(c) if schur else 0
    S = np.zeros((m, m))
    b = F[c].copy() if schur else np.zeros(0)
    if m:
        K_rc = sp.csc_matrix(K[r][:, c])
        K_cr = sp.csr_matrix(K[c][:, r])
        K_cc = K[c][:, c].toarray()
        for start in range(0, m, SCHUR_BLOCK):
            cols = slice(start, min(start + SCHUR_BLOCK, m))
            X = fac.solve(K_rc[:, cols].toarray())
            S[:, cols] = K_cc[:, cols] - K_cr @ X
        S = 0.5 * (S + S.T)
        b -= K_cr @ x0
    timings = {"factorize": t1 - t0, "solve": t2 - t1, "schur": time.perf_counter() - t2}
    return ContactReduction(S=S, b=b, x0=x0, factorization=fac, system=system, timings=timings)
