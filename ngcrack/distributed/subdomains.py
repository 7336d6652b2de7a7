"""BDDC with one subdomain per rank: local factorizations and a coarse space of face rigid motions.

NGSolve's "bddc" (bddc.py) takes every element as a subdomain. For TDNNS its coarse space
must hold the higher-order normal-facet unknowns (their lowest-order unknowns alone make
the coarse matrix singular, bddc.py), about three quarters of the condensed system at
order 1 in 2D and 64-84% in 3D (with all edge unknowns). This preconditioner takes each
rank's part of the mesh as one subdomain instead (the balancing domain decomposition by
constraints of Dohrmann, on the whole condensed system), in 2D and 3D alike:

- the local matrix: the rank's unassembled part of the condensed matrix (NGSolve's
  ParallelMatrix.local_mat, the subdomain's Neumann matrix), times the sign that makes it
  positive semidefinite, on the free unknowns;
- interface: the unknowns a rank shares with others. A face is the set of interface
  unknowns shared with exactly one neighbour, split by the pieces of both sides where the
  crack cuts a rank's part (each piece has its own rigid motions). In 2D every facet
  unknown is shared by at most two subdomains (the subdomains' corners carry none); in 3D
  the HCurl edge unknowns of u on a subdomain edge (where three or more subdomains meet)
  are shared by more;
- primal constraints (the coarse space): per face, the face's values of the rigid
  motions (3 in 2D, 6 in 3D: the translations and the rotations; u interpolated,
  u_hat_n from the local matrix, the crack jumps zero), i.e. weighted averages of the
  face's unknowns, a mode dropped where it depends on those before it (Gram test). They
  fix each subdomain's rigid motions, so every local problem is nonsingular. The
  unknowns shared by three or more subdomains (`corners`): "primal" (the default) makes
  each its own coarse unknown, as BDDC's vertices are; "averages" treats each set of them
  shared by the same ranks as a face (rigid-motion averages over the subdomain edge).
  The coarse problem, at most 3 or 6 unknowns per face plus the primal edge unknowns, is
  assembled on every rank and factorized there (dense: small);
- the application, for a residual r: the interior correction (each rank's interior
  solve), the interface residual averaged by multiplicity, the coarse solve plus each
  rank's constrained Neumann solve, the weighted sum of the interface values over the
  ranks and the harmonic extension into each interior. Symmetric positive definite, so it
  preconditions CG (krylov.py); the condition number of BDDC grows like
  (1 + log(H/h))^2 in the subdomain size H/h.

Each rank factorizes two sparse matrices (its interior problem: Cholesky, or with held
values a saddle point; its constrained Neumann problem, a saddle point: MKL PARDISO's
symmetric indefinite factorization where MKL loads, else SuperLU's pivoting LU) and per CG step exchanges interface values
twice with its neighbours (by mpi4py: exchange.py) and reduces the coarse right-hand side once.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .exchange import Exchange

#: how the coarse space is described in the results and BENCHMARKS
COARSE_SPACE = ("per rank subdomain: the rigid motions' averages (3 in 2D, 6 in 3D) over each face shared with a "
                "neighbour (per pair of pieces where the crack cuts a subdomain), the unknowns shared by three or more "
                "subdomains primal")
#: how the unknowns shared by three or more subdomains enter the coarse space (module docstring)
CORNERS = ("primal", "averages")
#: pieces per rank are numbered below this (the code of a pair of pieces: lower + PIECE_BASE * higher)
PIECE_BASE = 1 << 16
#: a face's rigid mode is dropped where it is this close to the span of the modes before it (Gram determinant)
MODE_RTOL = 1e-6


def _lu(M: sp.csc_matrix, definite: bool = False):
    """A factorization of the symmetric saddle-point matrix M (ngcrack.core.schur.Factorization with definite=False:
    MKL PARDISO's symmetric indefinite factorization with matching where MKL loads, else SuperLU's pivoting LU);
    `.solve(b)`. With `definite` (M positive definite: an interior block without held rows) PARDISO's Cholesky.
    Either stores one triangle: about half the memory of PARDISO's LU."""
    from ..core.schur import Factorization

    if not definite:  # PARDISO's symmetric factorization wants every diagonal entry stored, zeros included
        C, d = M.tocoo(), np.arange(M.shape[0])
        M = sp.csr_matrix((np.concatenate([C.data, np.zeros(len(d))]), (np.concatenate([C.row, d]),
                                                                         np.concatenate([C.col, d]))), shape=M.shape)
    return Factorization(M, "auto", definite=definite, symmetric=True)


class SubdomainError(RuntimeError):
    """A subdomain's constrained local problem is singular (its rigid motions not fixed by its faces)."""


def rigid_motions(dim: int) -> list:
    """The rigid motions as CoefficientFunctions: in 2D (1, 0), (0, 1), (-y, x); in 3D the three translations and
    the rotations about the x, y and z axes."""
    x, y, z = ngs.x, ngs.y, ngs.z
    if dim == 2:
        return [ngs.CF((1, 0)), ngs.CF((0, 1)), ngs.CF((-y, x))]
    return [ngs.CF((1, 0, 0)), ngs.CF((0, 1, 0)), ngs.CF((0, 0, 1)),
            ngs.CF((0, -z, y)), ngs.CF((z, 0, -x)), ngs.CF((-y, x, 0))]


def rigid_modes(fes: ngs.FESpace, K: sp.csr_matrix, normal_facet: bool = True) -> np.ndarray:
    """(ndof, modes): the values of the rigid motions (`rigid_motions`: 3 in 2D, 6 in 3D) in the unknowns of `fes`:
    its first HCurl component (u) interpolated, its first normal-facet component (u_hat_n) from the rows of the
    local matrix `K` (all of the space's unknowns) that it tests (K r = 0 for a rigid motion r: u_hat_n =
    -K_nn^-1 K_nu u), every other component zero. Local: u's unknowns are the L2 projection onto this rank's
    elements, exact (the space holds the rigid motions), so the ranks sharing an unknown find the same value.
    NGSolve's interpolation (GridFunction.Set) would sum over the ranks through NGSolve's own exchange, not
    reliable on a rank with two or more neighbours (exchange.py)."""
    comps = list(fes.components)
    k_u = next(k for k, c in enumerate(comps) if isinstance(c, ngs.HCurl))
    k_n = next(k for k, c in enumerate(comps) if isinstance(c, ngs.NormalFacetFESpace))
    motions = rigid_motions(fes.mesh.dim)
    out = np.zeros((fes.ndof, len(motions)))
    ru, rn = fes.Range(k_u), fes.Range(k_n)
    u_dofs, n_dofs = np.arange(ru.start, ru.stop), np.arange(rn.start, rn.stop)
    if len(u_dofs):
        out[u_dofs] = _local_projection(comps[k_u], motions)
    if not len(n_dofs) or not normal_facet:  # (a rank without faces needs none)
        return out
    K_nn = K[n_dofs][:, n_dofs].tocsc()
    out[n_dofs] = -spla.splu(K_nn).solve(np.asarray(K[n_dofs][:, u_dofs] @ out[u_dofs]))
    return out


def _local_projection(space: ngs.FESpace, fields) -> np.ndarray:
    """(ndof, len(fields)): the L2 projections of `fields` onto `space` over this rank's elements alone (the local
    mass matrix and right-hand sides, no exchange with other ranks)."""
    u, v = space.TnT()
    m = ngs.BilinearForm(space)
    m += u * v * ngs.dx
    m.Assemble()
    rows, cols, vals = getattr(m.mat, "local_mat", m.mat).COO()
    M = sp.csc_matrix((np.asarray(vals), (np.asarray(rows), np.asarray(cols))), shape=(space.ndof, space.ndof))
    b = np.zeros((space.ndof, len(fields)))
    for j, cf in enumerate(fields):
        f = ngs.LinearForm(space)
        f += cf * v * ngs.dx
        f.Assemble()
        b[:, j] = f.vec.FV().NumPy()  # this rank's elements' integrals (the distributed vector's local part)
    from ..core.schur import Factorization

    # a mass matrix: positive definite (PARDISO's Cholesky; SuperLU's LU took minutes and gigabytes on a
    # subdomain of millions of unknowns)
    return Factorization(M, "auto", definite=True).solve(b)


def dof_pieces(fes: ngs.FESpace, mesh: ngs.Mesh, crack_facets: set[int]) -> np.ndarray:
    """Per dof of `fes`, the connected piece of this rank's elements its node belongs to (elements joined across
    facets -- edges in 2D, faces in 3D -- that are not crack facets: a crack can cut a subdomain in two, each with
    its own rigid motions); 0 for dofs on no edge or face. A node of elements of several pieces (an edge on the
    crack in 3D) takes its first element's piece."""
    from scipy.sparse.csgraph import connected_components

    facets = mesh.faces if mesh.dim == 3 else mesh.edges
    rows, cols = [], []
    for f in facets:
        els = [el.nr for el in f.elements]
        if f.nr not in crack_facets and len(els) == 2:
            rows.append(els[0])
            cols.append(els[1])
    out = np.zeros(fes.ndof, dtype=int)
    if not mesh.ne:
        return out
    _, label = connected_components(sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(mesh.ne, mesh.ne)),
                                    directed=False)
    kinds = ((ngs.EDGE, mesh.edges), (ngs.FACE, mesh.faces)) if mesh.dim == 3 else ((ngs.EDGE, mesh.edges),)
    for ntype, nodes in kinds:
        for node in nodes:
            els = [el.nr for el in node.elements]
            if els:
                dofs = [d for d in fes.GetDofNrs(ngs.NodeId(ntype, node.nr)) if d >= 0]
                out[dofs] = label[els[0]]
    return out


def _face_modes(R: np.ndarray) -> list[int]:
    """The modes kept on a face with mode values R (rows: the face's unknowns): each in turn unless it is (nearly)
    in the span of those kept; from the Gram matrix, so that both sides of the face keep the same ones."""
    gram = R.T @ R
    keep: list[int] = []
    scale = max(float(np.max(np.diag(gram))), 1e-300)
    for j in range(R.shape[1]):
        trial = keep + [j]
        sub = gram[np.ix_(trial, trial)] / scale
        if np.linalg.det(sub) > MODE_RTOL * max(np.linalg.det(gram[np.ix_(keep, keep)] / scale), 1e-300 if keep else 1.0):
            keep = trial
    return keep


class SubdomainBDDC:
    """The preconditioner of the module docstring on `fes`'s free unknowns `free` (a boolean mask per local dof)
    for K = sign * A (A a ParallelMatrix, assembled): apply(r, out) sets out = C r, C an approximate inverse of K."""

    def __init__(self, comm, A, fes: ngs.FESpace, free: np.ndarray, sign: float, pieces: np.ndarray | None = None,
                 corners: str = "primal"):
        if corners not in CORNERS:
            raise ValueError(f"corners = {corners!r}: allowed values are {', '.join(CORNERS)}")
        self.comm, self.A = comm, A
        n = self.n = fes.ndof
        self.exchange = Exchange.of_space(fes, comm)
        self.idx = np.flatnonzero(free[:n]) if n else np.zeros(0, dtype=int)
        pd = fes.ParallelDofs()
        neighbours = [tuple(sorted(int(p) for p in pd.Dof2Proc(int(d)))) for d in self.idx]
        shared = np.array([len(p) > 0 for p in neighbours], dtype=bool)
        self.gamma, self.inner = np.flatnonzero(shared), np.flatnonzero(~shared)
        self.weight = 1.0 / (1.0 + np.array([len(neighbours[i]) for i in self.gamma], dtype=float))
        if n:
            rows, cols, vals = A.local_mat.COO()
            K_all = sp.csr_matrix((sign * np.asarray(vals), (np.asarray(rows), np.asarray(cols))), shape=(n, n))
            del rows, cols, vals  # (the triplets' copies: not kept while the local problems are factorized)
        else:
            K_all = sp.csr_matrix((0, 0))
        K = K_all[self.idx][:, self.idx].tocsr()
        self.K = K
        # faces: the interface unknowns shared with one set of ranks, keyed by all of them (this one included)
        # and by the pieces (`dof_pieces`) on both sides, so that every piece's rigid motions are fixed; with
        # corners = "primal" an unknown shared by three or more ranks is a coarse unknown of its own
        code = self._piece_codes(A, pieces if pieces is not None else np.zeros(n, dtype=int), neighbours)
        corner = np.array([corners == "primal" and len(neighbours[i]) > 1 for i in self.gamma], dtype=bool)
        faces: dict[tuple, list[int]] = {}
        for i in self.gamma[~corner]:
            faces.setdefault((tuple(sorted((comm.rank,) + neighbours[i])), int(code[i])), []).append(int(i))
        keys = sorted({k for part in comm.allgather(sorted(faces)) for k in part})
        self.faces = len(keys)
        modes = rigid_modes(fes, K_all, normal_facet=bool(faces))[self.idx]
        del K_all
        m = modes.shape[1]
        # primal constraints: rows of C (one per kept mode of each face, one per corner unknown), their global numbers
        crow, ccol, cval, self.primal = [], [], [], []
        for key, dofs in faces.items():
            R = modes[dofs]
            for j in _face_modes(R):
                crow += [len(self.primal)] * len(dofs)
                ccol += dofs
                cval += list(R[:, j] / np.linalg.norm(R[:, j]))  # the same scale on every face
                self.primal.append(m * keys.index(key) + j)
        corner_ids, n_corners = self._corner_numbers(A, self.gamma[corner], neighbours)
        for i, g in zip(self.gamma[corner], corner_ids):
            crow.append(len(self.primal))
            ccol.append(int(i))
            cval.append(1.0)
            self.primal.append(m * len(keys) + g)
        self.corners = n_corners
        nc = len(self.primal)
        self.C = sp.csr_matrix((cval, (crow, ccol)), shape=(nc, len(self.idx)))
        self.n0 = m * len(keys) + n_corners
        self._held = None
        self._factorize(sp.csr_matrix((0, len(self.idx))))
        self._coarse()

    def _corner_numbers(self, A, positions: np.ndarray, neighbours: list) -> tuple[np.ndarray, int]:
        """(global numbers of the free unknowns `positions`, their count over all ranks): the lowest rank sharing an
        unknown numbers it, the sum over the sharing ranks tells the others (collective)."""
        mine = np.array([all(self.comm.rank < p for p in neighbours[i]) for i in positions], dtype=bool)
        count = int(np.count_nonzero(mine))
        start = int(self.comm.exscan(count) or 0)
        total = int(self.comm.allreduce(count))
        if not total:
            return np.zeros(0, dtype=int), 0
        vals = np.zeros(self.n)
        vals[self.idx[positions[mine]]] = 1.0 + start + np.arange(count)
        self.exchange.add_shared(vals)
        return np.rint(vals[self.idx[positions]]).astype(int) - 1, total

    def _piece_codes(self, A, pieces: np.ndarray, neighbours: list) -> np.ndarray:
        """Per free dof, one number for the pair (piece on the lower rank, piece on the higher rank) of an interface
        dof, the same on both ranks (the sum over the ranks sharing a dof)."""
        vals = np.zeros(self.n)
        lower = np.array([all(self.comm.rank < p for p in nb) for nb in neighbours], dtype=bool)
        p = pieces[self.idx].astype(float) + 1.0
        vals[self.idx] = np.where(lower, p, p * PIECE_BASE)
        self.exchange.add_shared(vals)
        return np.rint(vals[self.idx]).astype(np.int64)

    def hold(self, rows: sp.spmatrix) -> None:
        """Keep the values `rows` @ y (rows over this rank's dofs; a crack edge's constraint rows, the same on every
        rank that shares the edge) at zero in every local solve: the preconditioner of the constrained problem,
        whose answers satisfy the constraints. Refactorizes where the rows changed on some rank (collective)."""
        B = sp.csr_matrix(rows)[:, self.idx] if len(self.idx) else sp.csr_matrix((0, 0))
        B = B[np.flatnonzero(np.diff(B.indptr))] if B.shape[0] else B  # rows on held dofs only: none
        key = (B.shape, B.indptr.tobytes(), B.indices.tobytes(), B.data.tobytes())
        if not self.comm.allreduce(int(key != self._held)):
            return
        self._held = key
        self._factorize(B.tocsr())
        self._coarse()

    def _factorize(self, B: sp.csr_matrix) -> None:
        """The interior and constrained Neumann problems, with the held rows B (free-dof columns) as constraints;
        the coarse basis Phi (the constrained Neumann problem's answers to a unit primal value each)."""
        K, I, G, nc = self.K, self.inner, self.gamma, len(self.primal)
        n = len(self.idx)
        inner_row = np.zeros(B.shape[0], dtype=bool)
        if B.shape[0]:
            on_gamma = np.zeros(n, dtype=bool)
            on_gamma[G] = True
            inner_row = np.array([not np.any(on_gamma[B.indices[B.indptr[k]:B.indptr[k + 1]]])
                                  for k in range(B.shape[0])], dtype=bool)
        B_I = B[np.flatnonzero(inner_row)][:, I]
        self.n_held_inner = B_I.shape[0]
        if not len(I):
            self.K_II = None
        elif B_I.shape[0]:
            self.K_II = _lu(sp.bmat([[K[I][:, I], B_I.T], [B_I, None]], format="csc"))
        else:  # nothing held: the interior matrix is positive definite
            self.K_II = _lu(K[I][:, I].tocsc(), definite=True)
        self.K_IG = K[I][:, G].tocsr()
        self.K_GI = K[G][:, I].tocsr()
        if not n or not len(G):  # no interface: the interior solve is the whole local solve
            self.saddle, self.phi, self.n_rows = None, np.zeros((n, 0)), 0
            return
        D = sp.vstack([self.C, B]).tocsr()
        self.n_rows = D.shape[0]
        try:
            self.saddle = _lu(sp.bmat([[K, D.T], [D, None]], format="csc"))
        except RuntimeError as exc:  # the factorization found it exactly singular
            raise SubdomainError(f"rank {self.comm.rank}: the constrained local problem is singular ({exc})") from exc
        rhs = np.zeros((n + self.n_rows, nc))
        rhs[n:n + nc] = np.eye(nc)
        self.phi = self.saddle.solve(rhs)[:n] if nc else np.zeros((n, 0))
        if not np.all(np.isfinite(self.phi)):
            raise SubdomainError(f"rank {self.comm.rank}: the constrained local problem is singular")

    def _solve_inner(self, rhs: np.ndarray) -> np.ndarray:
        """K_II^-1 rhs on the interior unknowns (the held interior rows kept at zero)."""
        if self.K_II is None:
            return np.zeros(0)
        return self.K_II.solve(np.concatenate([rhs, np.zeros(self.n_held_inner)]))[:len(self.inner)]

    def _coarse(self) -> None:
        """The coarse matrix sum_s Phi_s^T K_s Phi_s, reduced on every rank and factorized there."""
        n0 = self.n0
        A0 = np.zeros((n0, n0))
        if len(self.primal):
            p = np.asarray(self.primal)
            A0[np.ix_(p, p)] = self.phi.T @ (self.K @ self.phi)
        A0 = self.comm.allreduce(A0)
        used = np.flatnonzero(np.diag(A0) != 0.0)  # modes dropped on every face: no row
        self.used = used
        self.coarse_size = len(used)
        self.A0 = sla.cho_factor(A0[np.ix_(used, used)]) if len(used) else None

    def _sum_over_ranks(self, values: np.ndarray, positions: np.ndarray, work=None) -> np.ndarray:
        """The sum over the ranks sharing them of every rank's `values` at the free unknowns `positions`."""
        arr = np.zeros(self.n)
        arr[self.idx[positions]] = values
        self.exchange.add_shared(arr)
        return arr[self.idx[positions]]

    def apply(self, r: ngs.BaseVector, out: ngs.BaseVector) -> None:
        rv = np.array(r.FV().NumPy(), dtype=float)
        if r.GetParallelStatus() == ngs.PARALLEL_STATUS.DISTRIBUTED:
            self.exchange.add_shared(rv)  # the residual's consistent values
        rv = rv[self.idx]
        I, G = self.inner, self.gamma
        w_I = self._solve_inner(rv[I])
        r_G = rv[G] - self._sum_over_ranks(self.K_GI @ w_I, G)
        b = np.zeros(len(self.idx))
        b[G] = self.weight * r_G
        g = np.zeros(self.n0)
        if len(self.primal):
            np.add.at(g, np.asarray(self.primal), self.phi.T @ b)
        g = self.comm.allreduce(g)
        u0 = np.zeros(self.n0)
        if self.A0 is not None:
            u0[self.used] = sla.cho_solve(self.A0, g[self.used])
        u = np.zeros(len(self.idx))
        if self.saddle is not None:
            u = self.phi @ u0[np.asarray(self.primal, dtype=int)] if len(self.primal) else u
            rhs = np.concatenate([b, np.zeros(self.n_rows)])
            u = u + self.saddle.solve(rhs)[:len(self.idx)]
        u_G = self._sum_over_ranks(self.weight * u[G], G)
        u_I = w_I - self._solve_inner(self.K_IG @ u_G)
        out.SetParallelStatus(ngs.PARALLEL_STATUS.CUMULATED)
        vals = out.FV().NumPy()
        vals[:] = 0.0
        vals[self.idx[I]] = u_I
        vals[self.idx[G]] = u_G
