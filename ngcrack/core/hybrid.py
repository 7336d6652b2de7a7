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
  tangential coordinate only, x = T y, so K stays symmetric positive definite;
- pin and roller points (`Loads.held_mean`): the mean of u over a segment (or of u.n)
  held at zero by a second change of basis, y = Z z (`held_means.py`).

Partition the remaining unknowns into the crack normal jumps c (m of them) and the rest
r. With jn = 0, the rest solves K_rr x_r = F_r; the contact problem in jn alone is the
QP with S = K_cc - K_cr K_rr^{-1} K_rc and b = F_c - K_cr K_rr^{-1} F_r.

With friction (`condense(..., tangential=True)`) c holds the crack's tangential jump
unknowns too, after the normal ones: S and b are then the reduced problem in (jn, jt)
of `friction.py`. Without friction the tangential jumps stay in r (free sliding).
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np

from .csr import CSR
from .discretization import Discretization, Loads, refuse
from .parallel import task_manager
from .schur import SCHUR_BLOCK, Factorization, schur_complement  # noqa: F401  (re-exported)

#: entries of a constraint row below this fraction of its largest are round-off (not its support)
SUPPORT_RTOL = 1e-13
#: a pivot of the constraints' QR below this fraction of the largest: dependent constraints
RANK_RTOL = 1e-10


def _bits(ba: ngs.BitArray) -> np.ndarray:
    """The BitArray as a boolean array (NGSolve's projector sets the bits' entries, in C++)."""
    vec = ngs.BaseVector(len(ba))
    vals = vec.FV().NumPy()
    vals[:] = 1.0
    ngs.Projector(ba, True).Project(vec)
    return vals != 0.0


def _to_scipy(mat):
    """NGSolve's sparse matrix as scipy CSR on NGSolve's own arrays (imports scipy.sparse)."""
    return CSR.from_ngsolve(mat).to_scipy()


def _congruence(A, column: np.ndarray, coef: np.ndarray, n: int, sign: float) -> CSR:
    """sign T^T A T for a T with at most one entry per row, T[g, column[g]] = coef[g]
    (column -1: an empty row), in one pass over A's entries (no sparse products).

    Entries of T^T A T that sum three or more nonzero products (a roller whose normal is
    not along an axis) are summed by scipy, in its order, as before; an axis-aligned
    roller's coefficients are 1 and 0, and every other entry has at most two terms.
    """
    used = column >= 0
    if np.all(coef[used] == 1.0) and np.all(np.diff(column[used]) > 0):
        return _selection(A, column, used, n, sign)
    counts = np.diff(A.indptr)
    i, c_i = np.repeat(column, counts), np.repeat(sign * coef, counts)  # per entry, by its row
    j, c_j = column[A.indices], coef[A.indices]
    ok = (i >= 0) & (j >= 0)
    i, j = i[ok], j[ok]
    vals = A.data[ok] * (c_i[ok] * c_j[ok])
    K = CSR.from_triplets(vals, i, j, (n, n), drop_zeros=True)
    if K is None:
        import scipy.sparse as sp

        Ks = sp.csr_matrix((vals, (i, j)), shape=(n, n))
        Ks.sum_duplicates()
        Ks.eliminate_zeros()
        K = CSR.from_scipy(Ks)
    return K


def _selection(A, column: np.ndarray, used: np.ndarray, n: int, sign: float) -> CSR:
    """sign T^T A T where T only selects (coefficients 1, columns increasing with the rows: no roller pairs and no
    reordering): the rows and columns kept, zeros dropped, in one pass with few temporaries (the same matrix,
    bitwise, as the general congruence; a 3D system's condensation peaked at 0.5 GB above its result without it)."""
    rows = np.flatnonzero(used)
    sub = A[rows][:, rows]  # the kept rows, then the kept columns (in order: column is increasing on them)
    keep = sub.data != 0.0
    data = sign * sub.data[keep]
    indices = column[rows][sub.indices[keep]]
    kept = np.zeros(len(keep) + 1, dtype=np.int64)
    np.cumsum(keep, out=kept[1:])
    indptr = kept[sub.indptr].astype(np.int32 if n < 2**31 - 1 and len(data) < 2**31 - 1 else np.int64)
    return CSR(data, indices.astype(indptr.dtype), indptr, (n, n))


@dataclass
class CondensedSystem:
    """K y = F on the global unknowns y, with the crack normal jumps at `contact`.

    `to_global(y)` maps back to the condensed NGSolve unknowns (fixed values included);
    `expand(y)` returns the full NGSolve GridFunction (local unknowns recovered).
    K and the change of basis T are held as `csr.CSR` (`K_csr`, `_T_csr`: numpy alone,
    what the 2D solve path uses); `K` and `_T` are the same matrices as scipy.sparse CSR
    on the same arrays, made on first use (for the paths that need scipy).
    """

    disc: Discretization
    K_csr: CSR
    F: np.ndarray
    contact: np.ndarray  # positions of the jn unknowns in y
    rest: np.ndarray  # positions of all other unknowns in y
    _T_csr: CSR
    _free: np.ndarray
    _fixed: np.ndarray
    _x_fixed: np.ndarray
    _fmod: ngs.BaseVector
    timings: dict = field(default_factory=dict)
    #: with tangential unknowns in `contact`: how many of its leading entries are jn, and
    #: the tangential component's dofs (numbered within that component) that follow them
    n_normal: int | None = None
    tangential_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))

    @property
    def n(self) -> int:
        """The number of global unknowns (after condensation)."""
        return self.K_csr.shape[0]

    @property
    def K(self):
        """K as a scipy.sparse CSR matrix (on K_csr's arrays; imports scipy.sparse)."""
        return self.K_csr.to_scipy()

    @property
    def _T(self):
        """The change of basis T as a scipy.sparse CSR matrix (imports scipy.sparse)."""
        return self._T_csr.to_scipy()

    def without_contact(self) -> CondensedSystem:
        """The same system with the crack normal jumps treated as ordinary unknowns."""
        return CondensedSystem(
            disc=self.disc, K_csr=self.K_csr, F=self.F, contact=np.zeros(0, dtype=int), rest=np.arange(self.n),
            _T_csr=self._T_csr, _free=self._free, _fixed=self._fixed, _x_fixed=self._x_fixed, _fmod=self._fmod,
            timings=dict(self.timings),
        )

    def with_load(self, loads: Loads) -> CondensedSystem:
        """The same K with F rebuilt from `disc.f` as assembled now (a new load, same matrix).

        F = sign T^T (f_free + (E^T f)_free - A_fd x_fixed), as in `condense`, with E the
        harmonic extension and x_fixed the prescribed displacements of `loads` (A_fd is
        re-read from the assembled matrix only where some are nonzero). Nothing is
        re-assembled or re-factorized: the caller re-assembles `disc.f` first.
        """
        disc, a = self.disc, self.disc.a
        fmod = disc.f.vec.CreateVector()
        fmod.data = disc.f.vec
        fmod.data += a.harmonic_extension_trans * fmod
        rhs = fmod.FV().NumPy()[self._free].copy()
        x_fixed = np.zeros(len(self._fixed))
        if loads.displacement:
            gf = ngs.GridFunction(disc.fes)
            disc.boundary_values(gf, loads)
            x_fixed = gf.vec.FV().NumPy()[self._fixed].copy()
            if np.any(x_fixed):
                rhs -= CSR.from_ngsolve(a.mat)[self._free][:, self._fixed] @ x_fixed
        return dataclasses.replace(self, F=disc.sign * (self._T_csr.T @ rhs), _x_fixed=x_fixed, _fmod=fmod,
                                   timings=dict(self.timings))

    def expand(self, y: np.ndarray) -> ngs.GridFunction:
        """The GridFunction of the global solution `y`, its local unknowns recovered by static condensation."""
        gf = ngs.GridFunction(self.disc.fes)
        vec = gf.vec.FV().NumPy()
        vec[:] = 0.0
        vec[self._free] = self._T_csr @ y
        vec[self._fixed] = self._x_fixed
        a = self.disc.a
        with task_manager():
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


def condense(disc: Discretization, loads: Loads, tangential: bool = False) -> CondensedSystem:
    """Build K, F on the global unknowns of an assembled discretization.

    `tangential`: put the crack's tangential jump unknowns into `contact` after the
    normal ones (a crack with friction); those held at zero (a crack node on a roller)
    stay out.
    """
    t0 = time.perf_counter()
    fes, a, f = disc.fes, disc.a, disc.f
    fmod = f.vec.CreateVector()
    fmod.data = f.vec
    with task_manager():
        fmod.data += a.harmonic_extension_trans * fmod
    A = CSR.from_ngsolve(a.mat)
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
    T = CSR.from_triplets(vals, rows, cols, (len(free_idx), n_red))  # one entry per row: never None
    # T has at most one entry per row: the column and coefficient of each NGSolve dof
    column = np.full(fes.ndof, -1, dtype=np.int64)
    coef = np.zeros(fes.ndof)
    column[free_idx[rows]], coef[free_idx[rows]] = cols, vals
    rhs = fmod.FV().NumPy().copy()
    if np.any(x_fixed):
        x_full = np.zeros(fes.ndof)
        x_full[fixed_idx] = x_fixed
        rhs -= A @ x_full
    K = _congruence(A, column, coef, n_red, disc.sign)
    used = column >= 0
    F = np.bincount(column[used], weights=disc.sign * coef[used] * rhs[used], minlength=n_red)
    contact = np.zeros(0, dtype=int)
    if disc.jn is not None:
        rng = fes.Range(disc.jn)
        jn_dofs = np.arange(rng.start, rng.stop)
        # jn dofs are never rolled: their position in y equals their position in `keep`
        contact = np.searchsorted(keep, pos[jn_dofs])  # keep is sorted
    n_normal, t_dofs = None, np.zeros(0, dtype=int)
    if tangential and disc.jn is not None:
        comp = disc.jt if disc.jt is not None else disc.tangential
        if comp is None:
            raise refuse("tangential", True, "False", f"element {disc.element!r} has no tangential jump unknowns "
                         "(friction needs them)")
        rng = fes.Range(comp)
        p = pos[np.arange(rng.start, rng.stop)]
        at = np.searchsorted(keep, p)
        kept = (p >= 0) & (at < len(keep)) & (keep[np.minimum(at, len(keep) - 1)] == p)
        t_dofs = np.flatnonzero(kept)
        n_normal = len(contact)
        contact = np.concatenate([contact, at[kept]]).astype(int)
        if np.any(np.diff(contact) <= 0):  # the Schur complement's order is the order of `contact`
            raise AssertionError("crack unknowns out of order")
    if loads.held_mean:  # pin and roller points: their mean constraints eliminated (held_means.py)
        B, names = disc.held_mean_rows(loads.held_mean, T, free_idx)
        held = eliminate(B, names, contact)
        Z = held.Z
        K = CSR.from_scipy(Z.T @ K.to_scipy() @ Z)
        F = Z.T @ F
        T = CSR.from_scipy(T.to_scipy() @ Z)
        contact = held.position[contact]
        n_red = Z.shape[1]
    mask = np.ones(n_red, dtype=bool)
    mask[contact] = False
    return CondensedSystem(
        disc=disc,
        K_csr=K,
        F=F,
        contact=contact,
        rest=np.flatnonzero(mask),
        _T_csr=T,
        _free=free_idx,
        _fixed=fixed_idx,
        _x_fixed=x_fixed,
        _fmod=fmod,
        timings={"condense": time.perf_counter() - t0},
        n_normal=n_normal,
        tangential_dofs=t_dofs,
    )


@dataclass
class ContactReduction:
    """The crack QP data of a condensed system and the means to recover the rest.

    S (m x m, dense, SPD) and b as in the module docstring; `x0` is the rest's solution
    for jn = 0 (a bonded crack in the normal direction, free to slide). `method` says
    how S was formed and `largest_dense` counts the entries of the largest dense array
    built on the way (m * m unless S came from blocked solves); see `schur.py`.
    """

    S: np.ndarray
    b: np.ndarray
    x0: np.ndarray
    factorization: Factorization
    system: CondensedSystem
    timings: dict = field(default_factory=dict)
    method: str = "none"
    largest_dense: int = 0
    _K_rc: CSR | None = field(default=None, repr=False)  # K[rest][:, contact], sliced once

    def coupling(self) -> CSR:
        """K_rc = K[rest][:, contact], sliced on first use and kept (shared by `with_load`)."""
        if self._K_rc is None:
            sysm = self.system
            self._K_rc = sysm.K_csr[sysm.rest][:, sysm.contact]
        return self._K_rc

    def with_load(self, system: CondensedSystem) -> ContactReduction:
        """The reduction of `system` (same K, new F) from this one's factorization and S.

        One solve: x0 = K_rr^{-1} F_r and b = F_c - K_cr x0; S, the factorization and
        the method are shared. Timings: "factorize" and "schur" 0 (reused), "solve".
        """
        if system.K_csr is not self.system.K_csr or not np.array_equal(system.contact, self.system.contact):
            raise ValueError("with_load: the system has another matrix or other crack unknowns; use reduce_to_contact")
        t0 = time.perf_counter()
        x0 = self.factorization.solve(system.F[system.rest])
        m = len(self.b)  # 0 where only K_rr was factorized (no crack, or no QP)
        b = system.F[system.contact] - self.coupling().T @ x0 if m else np.zeros(0)  # K symmetric: K_cr = K_rc^T
        return dataclasses.replace(self, b=b, x0=x0, system=system, _K_rc=self._K_rc,
                                   timings={"factorize": 0.0, "solve": time.perf_counter() - t0, "schur": 0.0})

    def recover(self, jn: np.ndarray) -> np.ndarray:
        """The full global vector y for given crack unknowns (one more solve).

        `jn` holds the values of the unknowns at `system.contact`: the normal jumps and,
        with friction, the tangential ones after them. Empty means zero (a bonded crack,
        or no crack).
        """
        sysm = self.system
        jn = np.asarray(jn, dtype=float)
        y = np.zeros(sysm.n)
        if jn.size and np.any(jn):
            y[sysm.contact] = jn
            y[sysm.rest] = self.x0 - self.factorization.solve(self.coupling() @ jn)
        else:
            y[sysm.rest] = self.x0
        return y


def reduce_to_contact(system: CondensedSystem, linear_solver: str = "auto", schur: bool | str = True) -> ContactReduction:
    """Factorize K_rr and form the Schur complement S on the crack normal jumps.

    `linear_solver` is one of `schur.LINEAR_SOLVERS` ("auto": MKL PARDISO where it
    loads, else SuperLU). `schur` is False (only K_rr is factorized and x0 solved: a
    bonded crack), True (= "auto") or a method of `schur.SCHUR_METHODS`: "factor"
    (partial factorization), "blocked" or "columns".
    """
    if schur is False:
        method, m_contact = "auto", np.zeros(0, dtype=int)
    else:
        method, m_contact = ("auto" if schur is True else schur), system.contact
    data = schur_complement(system.K_csr, system.F, system.rest, m_contact, linear_solver=linear_solver,
                            method=method if len(m_contact) else "blocked" if method == "factor" else method,
                            definite=system.disc.definite)
    if schur is False or not len(m_contact):
        data.method = "none"
    return ContactReduction(S=data.S, b=data.b, x0=data.x0, factorization=data.factorization, system=system,
                            timings=data.timings, method=data.method, largest_dense=data.largest_dense)


@dataclass
class MeanConstraints:
    """y = Z z: `Z` (n x (n - k)), `position` the new index of every old unknown (-1: a pivot)."""

    Z: object  # a scipy.sparse CSR matrix
    position: np.ndarray
    rows: list  # (label, direction) of each constraint


def eliminate(B: np.ndarray, names: list, protected: np.ndarray) -> MeanConstraints:
    """The change of basis that satisfies B y = 0; `protected` unknowns (the crack's) are never pivots."""
    k, n = B.shape
    scale = np.abs(B).max(axis=1, keepdims=True)
    support = np.flatnonzero((np.abs(B) > SUPPORT_RTOL * scale).any(axis=0))
    candidates = np.setdiff1d(support, protected)
    if len(candidates) < k:
        raise ValueError(f"point supports: {k} mean constraints on {len(candidates)} unknowns; a pin or roller "
                         f"segment has too few boundary unknowns (widen it or refine the mesh there)")
    Bs = B[:, candidates]
    import scipy.linalg as sla  # (loaded by a scene with pin or roller points only)

    _, R, perm = sla.qr(Bs, mode="economic", pivoting=True)
    diag = np.abs(np.diag(R))
    if diag[-1] <= RANK_RTOL * diag[0]:
        raise ValueError(f"point supports: the mean constraints of {sorted({lab for lab, _ in names})} are "
                         f"dependent (two supports on one segment?)")
    pivots = np.sort(candidates[perm[:k]])
    others = np.setdiff1d(support, pivots)
    coef = -np.linalg.solve(B[:, pivots], B[:, others])  # y_P = coef y_others
    position = np.full(n, -1, dtype=np.int64)
    kept = np.setdiff1d(np.arange(n), pivots)
    position[kept] = np.arange(len(kept))
    r = np.concatenate([kept, np.repeat(pivots, len(others))])
    c = np.concatenate([np.arange(len(kept)), np.tile(position[others], k)])
    v = np.concatenate([np.ones(len(kept)), coef.ravel()])
    import scipy.sparse as sp

    Z = sp.csr_matrix((v, (r, c)), shape=(n, len(kept)))
    return MeanConstraints(Z=Z, position=position, rows=names)
