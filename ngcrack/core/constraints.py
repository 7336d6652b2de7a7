"""The algebra of the crack constraints: the map G and its inverse, the scaled problem, KKT residuals.

G maps the crack unknowns j (a jump space's own basis) to the values that must be
non-negative, w = G j: the identity for P0 jumps, each edge's end-point values for P1
jumps; it is block diagonal (up to a permutation of its rows and columns) and
invertible. Both crack problems, the frictionless QP (contact.py) and the problem with
Coulomb friction (friction.py), are posed in w and Jacobi-scaled the same way
(`scaled_problem`); the KKT residuals of an answer are taken at the same constraint
points, with the contact forces computed from the solved system
(`discrete_contact_forces`, `kkt_at_constraints`).
"""

from __future__ import annotations

import weakref

import numpy as np

from .csr import CSR, as_csr, distinct


class ContactSolverError(RuntimeError):
    """The QP solver failed or returned an answer that violates the KKT conditions."""


#: The one rule for "the faces are closed" (they touch and may carry a normal traction),
#: used by the crack problem's point states, the profiles' states, the tips' face term,
#: growth and the explorer: at a point the normal jump [u].nu is at most CLOSED_RTOL times
#: its crack's largest jump |[u]| (the crack problem gives zeros up to round-off where the
#: faces touch). The same fraction says where a closed point sticks (|[u].t| below it) and
#: where a sample is compressed (sigma_n below -CLOSED_RTOL times the stress scale).
CLOSED_RTOL = 1e-8


def faces_closed(normal_jump, scale: float) -> np.ndarray:
    """Where the faces are closed: [u].nu <= CLOSED_RTOL * scale, `scale` the crack's
    largest |[u]| (an array of booleans like `normal_jump`; all closed if nothing moves)."""
    return np.asarray(normal_jump, dtype=float) <= CLOSED_RTOL * float(scale)


#: the largest scaled KKT residual an answer of the crack problem (Signorini or Coulomb) may have: above
#: it the solve refuses the answer (ContactSolverError); the native solvers reach round-off
#: (contact.KKT_TOL, 1e-9, counts as exact), an iterative cvxpy solver at its default tolerances 1e-8..1e-7
ACCEPT_KKT = 1e-6
#: the most crack unknowns whose dense Schur complement a solve forms (its m^2 doubles: 288 MB at 6000):
#: up to it the crack problem takes the dense strategy, above it the sparse active set on the
#: factorized system (`crack_problem.choose_strategy`; read when asked, so that a test may lower it)
SCHUR_MAX_M = 6000
#: G is inverted as a sparse matrix when at most this fraction of its entries is nonzero
G_SPARSE_FILL = 0.1


def _blocks(G: np.ndarray) -> tuple[int, np.ndarray, np.ndarray]:
    """The blocks of the dense G: the connected components of its pattern as a bipartite
    graph (rows and columns distinct nodes), their number and each row's and each column's
    component, numbered in the order of their smallest node (rows first). A block-diagonal G
    whose blocks are permuted (the tangential map of friction: a crack edge's constraint
    points against its own tangential unknowns, numbered apart) has its blocks found as well
    as one whose blocks sit on the diagonal. The smallest index is propagated along the
    pattern's entries with pointer jumping (scipy.sparse.csgraph, which loads scipy.linalg,
    is not needed)."""
    m = G.shape[0]
    row, col = np.nonzero(G)
    rows, cols = np.concatenate([row, col + m]), np.concatenate([col + m, row])
    label = np.arange(2 * m)
    while True:
        new = label.copy()
        np.minimum.at(new, rows, label[cols])
        new = new[new]
        if np.array_equal(new, label):
            break
        label = new
    roots, label = np.unique(label, return_inverse=True)
    return len(roots), label[:m], label[m:]


def _sparse_inverse(dense: np.ndarray) -> CSR | np.ndarray:
    """The inverse of a G that is block diagonal up to a permutation of its rows and columns
    (blocks = the components of `_blocks`), given as a dense array (which costs no more
    memory than the dense m x m Schur complement): a block G[R, C] gives G^{-1}[C, R].

    Blocks of equal size are inverted together (numpy's batched inverse). A component with
    fewer rows than columns (G singular) goes to the dense inverse, which raises numpy's
    LinAlgError.
    """
    m = dense.shape[0]
    n_blocks, row_label, col_label = _blocks(dense)
    r_order, c_order = np.argsort(row_label, kind="stable"), np.argsort(col_label, kind="stable")
    r_bounds = np.searchsorted(row_label[r_order], np.arange(n_blocks + 1))
    c_bounds = np.searchsorted(col_label[c_order], np.arange(n_blocks + 1))
    sizes = np.diff(r_bounds)
    if not np.array_equal(sizes, np.diff(c_bounds)):
        return np.linalg.inv(dense)
    rows, cols, vals = [], [], []
    for b in distinct(sizes):
        ks = np.flatnonzero(sizes == b)
        R = np.stack([r_order[r_bounds[k]:r_bounds[k + 1]] for k in ks])  # (blocks, b)
        C = np.stack([c_order[c_bounds[k]:c_bounds[k + 1]] for k in ks])
        inv = np.linalg.inv(dense[R[:, :, None], C[:, None, :]])
        rows.append(np.repeat(C, b, axis=1).ravel())
        cols.append(np.tile(R, (1, b)).ravel())
        vals.append(inv.ravel())
    return CSR.from_triplets(np.concatenate(vals), np.concatenate(rows), np.concatenate(cols), (m, m))


#: the last G inverted (a weak reference) and its inverse: one solve maps through the
#: same G twice (the QP and the contact forces); the entry is dropped when G is
_LAST_INVERSE: list = [None]  # one (weak reference to G, G^{-1}) pair, replaced as a whole


def _forget_inverse(ref) -> None:
    """Drop the cached pair of the G that `ref` referred to (not a newer one)."""
    entry = _LAST_INVERSE[0]
    if entry is not None and entry[0] is ref:
        _LAST_INVERSE[0] = None


def _inverse_map(G, m: int):
    """G^{-1}: None for G = None or the identity, sparse where G is (block diagonal), else dense."""
    if G is None:
        return None
    entry = _LAST_INVERSE[0]  # read once: another thread may replace it meanwhile
    if entry is not None and entry[0]() is G:
        return entry[1]
    inv = _compute_inverse_map(G, m)
    try:
        ref = weakref.ref(G)
    except TypeError:  # an object without weak references: no caching
        return inv
    _LAST_INVERSE[0] = (ref, inv)
    weakref.finalize(G, _forget_inverse, ref)
    return inv


def _compute_inverse_map(G, m: int):
    if hasattr(G, "tocsr") and not isinstance(G, np.ndarray):  # a sparse G (scipy or CSR)
        dense = as_csr(G).canonical().toarray()
    else:
        G = np.asarray(G, dtype=float)
        if G.shape != (m, m):
            raise ValueError(f"G: a square matrix of size {m} (the number of crack unknowns) was expected, got {G.shape}")
        if np.count_nonzero(G) == m and np.all(np.diag(G) == 1.0):  # the identity
            return None
        dense = G
    if np.count_nonzero(dense) > G_SPARSE_FILL * m * m:
        return np.linalg.inv(dense)
    return _sparse_inverse(dense)


def scaled_problem(S: np.ndarray, b: np.ndarray, Ginv) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The problem in w = G j, Jacobi-scaled: (S_s, b_s, D) with S_w = G^{-T} S G^{-1},
    b_w = G^{-T} b, D = diag(S_w)^{-1/2}, S_s = D S_w D (symmetrised) and b_s = D b_w.

    Ginv None means G = I. With a sparse (block-diagonal) Ginv this is O(m^2) work.
    Raises ContactSolverError where S_w has a diagonal entry <= 0 (a part of the body
    is not held).
    """
    if Ginv is None:
        S_w, b_w = S, b
    else:
        S_w = (Ginv.T @ (Ginv.T @ S).T).T
        b_w = Ginv.T @ b
    diag = np.diag(S_w)
    if np.any(diag <= 0.0):
        raise ContactSolverError("the crack Schur complement is not positive definite: a part of the body is not held")
    D = 1.0 / np.sqrt(diag)
    S_s = D[:, None] * S_w * D[None, :]
    return 0.5 * (S_s + S_s.T), D * b_w, D


# ----------------------------------------------------------------------------- KKT residuals

#: the keys of `kkt` and `kkt_sampled` (the `solve --json` contract)
KKT_KEYS = ("max_penetration", "max_tension", "complementarity", "friction")
#: a largest jump or force below this fraction of the body's own scale counts as zero
#: (the residuals are then taken relative to that body scale)
KKT_ZERO_RTOL = 1e-8


def discrete_contact_forces(K, F: np.ndarray, y: np.ndarray, contact: np.ndarray, G) -> tuple[np.ndarray, np.ndarray]:
    """The discrete contact forces lam at the QP's constraint points, and their rounding bound.

    With y the recovered global vector, the rows of K y = F that belong to the crack
    normal jumps j are the only ones not imposed: their residual is what the crack
    faces exert, r = (K y - F)_c = S j - b. The forces on the constrained values
    w = G j are lam = G^{-T} r (for a frictionless contact answer: lam >= 0, the QP's
    multipliers, i.e. minus the normal traction integrated against each constraint
    point's basis function; force per unit thickness). Computed from the system itself,
    not taken from the QP solver, so they certify its answer.

    In double precision r cannot be known better than its rounding-error bound
    gamma_n (|K| |y| + |F|), gamma_n = n u / (1 - n u) (u the unit round-off, n the
    nonzeros of the row plus one): y itself is only known to u |y|. Returned as
    `bound` = |G^{-T}| times that, per constraint point.
    """
    contact = np.asarray(contact, dtype=int)
    sparse = not isinstance(K, np.ndarray)
    K_c = as_csr(K)[contact] if sparse else K[contact]
    r = np.asarray(K_c @ y - F[contact])
    n = np.diff(K_c.indptr) + 1 if sparse else np.full(len(r), K_c.shape[1] + 1)
    u = np.finfo(float).eps / 2
    gamma = n * u / (1.0 - n * u)
    bound = gamma * (np.asarray(abs(K_c) @ np.abs(y)) + np.abs(F[contact]))
    if G is None or not len(r):
        return r, bound
    Ginv = _inverse_map(G, len(r))
    if Ginv is None:
        return r, bound
    return np.asarray(Ginv.T @ r).ravel(), np.asarray(abs(Ginv).T @ bound).ravel()


def kkt_at_constraints(w: np.ndarray, lam: np.ndarray, jump_max: float, jump_scale: float = 0.0,
                       force_scale: float = 0.0, friction: float = 0.0, lam_bound=0.0) -> dict:
    """Relative residuals of the discrete Signorini conditions at the constraint points.

    w >= 0 (constrained values: normal jumps), lam >= 0 (contact forces), w lam = 0.
    With W = `jump_max` (the largest jump on the crack) and L = max lam:
    max_penetration = max(0, -min w) / W, max_tension = max(0, -min lam) / L,
    complementarity = max |w lam| / (W L). A force within its rounding-error bound
    `lam_bound` (`discrete_contact_forces`) is indistinguishable from zero in double
    precision and counts as zero: lam is moved towards zero by that bound first
    (measured on paper-2, where L is 1e-4 of the body's force scale: the raw figures
    are 1e-11 to 1.3e-10, at that bound). Where W (or L) is zero up to round-off
    (below KKT_ZERO_RTOL times `jump_scale`, or `force_scale`: the body's own
    displacement and force scales), that scale is used instead, or 1 (absolute) if it
    is zero too. `friction`: the discrete Coulomb residual relative to L, computed by
    the caller (0 without friction). No constraint point: all zero.
    """
    w = np.asarray(w, dtype=float)
    lam = np.asarray(lam, dtype=float)
    if not len(w):
        return dict.fromkeys(KKT_KEYS, 0.0)
    lam = np.sign(lam) * np.maximum(np.abs(lam) - np.asarray(lam_bound, dtype=float), 0.0)

    def scale(value: float, body: float) -> float:
        return value if value > KKT_ZERO_RTOL * body and value > 0.0 else (body or 1.0)

    W = scale(float(jump_max), jump_scale)
    L = scale(float(np.max(lam)), force_scale)
    return {
        "max_penetration": float(max(0.0, -w.min()) / W),
        "max_tension": float(max(0.0, -lam.min()) / L),
        "complementarity": float(np.max(np.abs(w * lam)) / (W * L)),
        "friction": float(friction),
    }
