"""Coulomb friction on 3D crack faces in the distributed solve: the serial law, Newton steps by CG.

The law is the serial one (`core.sparse_friction`): friction points q on the crack faces, their
slips s_q = B_q y (2-vectors in the crack's plane; B from `solid.friction_points`, made on
rank 0's serial system), the bound g_q = mu omega_q lam_f (lam_f the normal force of the
point's face), the friction force lam_t,q in the Coulomb cone, along the slip where the
point slips, and s_q = 0 where it sticks.

The unknowns B acts on (the crack's tangential jump unknowns, a few per crack face) are
few: every rank holds B over all of them (columns numbered as rank 0's), and a vector's
values there are reduced over the ranks (`CrackUnknowns`). Each step is one constrained
linear solve by CG (`krylov.pcg`, whatever the preconditioner):

- the contact points' normal values held at zero (the faces' projection, as without friction);
- the sticking points' slips held at zero: the projection onto B_S y = 0 over all ranks' crack
  unknowns (B_S's rows are redundant: an orthonormal basis of its row space is used);
- a slipping point's law linearised at its slip s0 (direction d, a primal Newton step on
  g |s|): lam_t = g d + N s, N = g / |s0| (I - d d'), a symmetric positive semidefinite
  2 x 2 block added to the operator (a point that has just started to slip takes N = 0: the
  force g d alone). At the answer s is along d, N s = 0: N sets the speed, not the answer.

After each step the sets are updated from the answer: a contact point leaves where its
force is negative, a gap point enters where it penetrates; g from the contact points'
forces; a sticking point slips where its friction force (of the multipliers of B_S that
balance the residual, the nearest the cone: `core.coulomb.cone_forces`) leaves the cone, along that force; a slipping point sticks
where its slip turns against d, and takes the direction of its slip otherwise. The steps
stop when no set changes, g has settled to BOUND_RTOL and the slip law holds to LAW_RTOL
(relative to the largest normal force): the outer loop is `core.coulomb.coulomb_loop`, the
serial solves' own. The decisions on the friction points are taken
on rank 0 and broadcast, so that every rank holds the same sets.

(The 2D fixed point of `friction.py`, the slip direction lagged, did not converge in 3D:
on the bent beam at mu = 1 slipping points reversed from step to step.)
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

import ngsolve as ngs
import numpy as np

from ..core.coulomb import STICK_RCOND, CoulombStep, cone_forces, coulomb_loop
from .friction import force_residual
from .krylov import _DEBUG, Operator, hold, pcg

#: the bound g must settle to this fraction of the largest normal force; it settles by about 0.15 per
#: step on the bent beam, to a floor of a few 1e-12 (it is read from a residual) until a step's CG needs
#: no step from the last answer: then the answer repeats and g moves by round-off
BOUND_RTOL = 1e-12
#: the slipping points' force must lie along their slip to this fraction of the largest normal force
LAW_RTOL = 1e-10
#: a friction force or a slip within this fraction of the largest counts as zero in the set updates
SIGN_RTOL = 1e-9
#: Newton steps before the iteration is declared not converging
MAX_STEPS = 100


@dataclass
class FrictionLayout:
    """Rank 0's friction points as every rank needs them: B over the crack's tangential unknowns, per point its
    face (numbered over all cracks as in `solid_mesh.crack_layout`), weight and coefficient, and per tangential
    unknown its mesh node (0: edge, 1: face), the node's centre and its place among the node's unknowns."""

    B: np.ndarray  # (2 q, nt)
    face: np.ndarray
    omega: np.ndarray
    mu: np.ndarray
    kind: np.ndarray  # (nt,)
    centre: np.ndarray  # (nt, 3)
    place: np.ndarray  # (nt,)


def _nodes(mesh, f: int):
    """A crack face's nodes that can carry tangential unknowns: its edges and itself, with their centres."""
    pts = lambda item: np.mean([mesh[v].point for v in item.vertices], axis=0)  # noqa: E731
    face = mesh[ngs.NodeId(ngs.FACE, int(f))]
    out = [(0, ngs.NodeId(ngs.EDGE, e.nr), pts(mesh[ngs.NodeId(ngs.EDGE, e.nr)])) for e in face.edges]
    return out + [(1, ngs.NodeId(ngs.FACE, int(f)), pts(face))]


def friction_layout(pipe, scene, opts: dict, smesh):
    """Rank 0: (FrictionLayout, the serial FrictionPoints) from the serial system (`solid.friction_points`)."""
    from ..solid.friction_points import friction_points, positions_in_y

    disc, loads = pipe.discretization(scene, smesh, opts)
    system = pipe.system(disc, loads, False)
    points = friction_points(smesh, disc, system, [float(c.friction) for c in scene.cracks])
    ue = disc.fes.components[disc.tangential]
    offset = disc.fes.Range(disc.tangential).start
    cols, kind, centre, place = [], [], [], []
    seen = set()
    for c in smesh.cracks:
        for f in c.faces:
            for k, node, mid in _nodes(smesh.mesh, f):
                dofs = [d for d in ue.GetDofNrs(node) if d >= 0]
                if (k, node.nr) in seen or not dofs:
                    continue
                seen.add((k, node.nr))
                for i, d in enumerate(dofs):
                    cols.append(d)
                    kind.append(k)
                    centre.append(mid)
                    place.append(i)
    ypos = positions_in_y(system, offset + np.array(cols, dtype=int))
    B = points.B.tocsc()
    if np.any(ypos < 0) or B[:, np.setdiff1d(np.arange(B.shape[1]), ypos)].nnz:
        raise RuntimeError("friction: the friction points' slips reach unknowns that are not the crack's tangential ones")
    layout = FrictionLayout(B[:, ypos].toarray(), points.face, points.omega, points.mu, np.array(kind),
                            np.array(centre).reshape(-1, 3), np.array(place))
    return layout, points


def face_numbers(mesh, faces: list[int], centroids: np.ndarray, tol: float) -> np.ndarray:
    """The numbers over all cracks (rows of `centroids`, rank 0's order) of this rank's crack `faces`."""
    from scipy.spatial import cKDTree

    if not faces:
        return np.zeros(0, dtype=int)
    mine = np.array([_nodes(mesh, f)[-1][2] for f in faces])
    dist, idx = cKDTree(centroids).query(mine)
    if np.any(dist > tol):
        raise RuntimeError("friction: a crack face of a subdomain matches no crack face of the mesh")
    return np.asarray(idx, dtype=int)


class CrackUnknowns:
    """This rank's copies of the crack's tangential unknowns, numbered as rank 0's (`FrictionLayout`).

    `values(v)` gives every rank the global values of an NGSolve vector there (cumulated or distributed);
    `put(v, t)` writes them back and `add(v, t)` adds to them in the vector's own representation."""

    def __init__(self, comm, fes, component: int, mesh, faces: list[int], layout: FrictionLayout, tol: float):
        from scipy.spatial import cKDTree

        self.comm, self.nt = comm, len(layout.kind)
        space, offset = fes.components[component], fes.Range(component).start
        loc, gid = {}, {}
        trees = {k: cKDTree(layout.centre[layout.kind == k]) for k in (0, 1) if np.any(layout.kind == k)}
        index = {k: np.flatnonzero(layout.kind == k) for k in (0, 1)}
        for f in faces:
            for k, node, mid in _nodes(mesh, f):
                dofs = [d for d in space.GetDofNrs(node) if d >= 0]
                if not dofs:
                    continue
                dist, j = trees[k].query(mid, k=len(dofs)) if len(dofs) > 1 else trees[k].query(mid, k=[1])
                cand = index[k][np.atleast_1d(j)]
                if np.max(dist) > tol or len(cand) != len(dofs):
                    raise RuntimeError("friction: a crack unknown of a subdomain matches none of the mesh")
                for d, g in zip(dofs, sorted(cand, key=lambda g: layout.place[g])):
                    loc[offset + d], gid[offset + d] = True, g
        self.loc = np.array(sorted(loc), dtype=int)
        self.gid = np.array([gid[d] for d in self.loc], dtype=int)
        pd = fes.ParallelDofs()
        self.own = np.array([not any(p < comm.rank for p in pd.Dof2Proc(int(d))) for d in self.loc], dtype=bool)
        counted = np.zeros(self.nt)
        np.add.at(counted, self.gid[self.own], 1.0)
        if not np.all(comm.allreduce(counted) == 1.0):
            raise RuntimeError("friction: the crack's tangential unknowns are not shared consistently by the ranks")

    def values(self, vec: ngs.BaseVector) -> np.ndarray:
        vals = vec.FV().NumPy()
        out = np.zeros(self.nt)
        pick = self.own if vec.GetParallelStatus() == ngs.PARALLEL_STATUS.CUMULATED else np.ones(len(self.loc), bool)
        np.add.at(out, self.gid[pick], vals[self.loc[pick]])
        return self.comm.allreduce(out)

    def put(self, vec: ngs.BaseVector, t: np.ndarray) -> None:
        cumulated = vec.GetParallelStatus() == ngs.PARALLEL_STATUS.CUMULATED
        vec.FV().NumPy()[self.loc] = t[self.gid] if cumulated else np.where(self.own, t[self.gid], 0.0)

    def add(self, vec: ngs.BaseVector, t: np.ndarray) -> None:
        cumulated = vec.GetParallelStatus() == ngs.PARALLEL_STATUS.CUMULATED
        vec.FV().NumPy()[self.loc] += t[self.gid] if cumulated else np.where(self.own, t[self.gid], 0.0)


@dataclass
class SlipOperator(Operator):
    """K + B_L' N B_L (module docstring): `crack` the tangential unknowns, `B` over them, N per point (q, 2, 2)."""

    crack: CrackUnknowns | None = None
    B: np.ndarray | None = None
    N: np.ndarray | None = None

    def apply(self, x: ngs.BaseVector, out: ngs.BaseVector) -> None:
        super().apply(x, out)
        if self.N is not None and np.any(self.N):
            s = (self.B @ self.crack.values(x)).reshape(-1, 2)
            self.crack.add(out, self.B.T @ np.einsum("qij,qj->qi", self.N, s).ravel())


@dataclass
class PointState:
    """The friction points' sets (the same on every rank): stick, the slipping points' direction d and slip
    size |s0| (0: no linearisation yet), the bound g, the sticking points' forces and the projection's basis."""

    stick: np.ndarray
    d: np.ndarray
    size: np.ndarray
    g: np.ndarray
    lam_t: np.ndarray
    basis: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))

    @property
    def slip(self) -> np.ndarray:
        return (self.g > 0) & ~self.stick

    def N(self) -> np.ndarray:
        lin = self.slip & (self.size > 0)
        out = np.zeros((len(self.g), 2, 2))
        out[lin] = (self.g[lin] / self.size[lin])[:, None, None] * (np.eye(2) - self.d[lin, :, None] * self.d[lin, None, :])
        return out


def _update(state: PointState, B: np.ndarray, s: np.ndarray, r_t: np.ndarray, g: np.ndarray,
            lam_max: float) -> tuple[PointState, int, float]:
    """Rank 0: the next sets from the step's slips `s`, tangential residual `r_t` (the sticking points' forces
    balance it) and bound `g` (module docstring); returns (state, set changes, slip law residual)."""
    q = len(g)
    lam_t = np.zeros((q, 2))
    rows = np.flatnonzero(np.repeat(state.stick, 2))
    if len(rows):
        lam_t[state.stick] = cone_forces(B[rows].T, r_t, g[state.stick])  # of the balancing forces, the nearest the cone
    lam_t[state.slip] = state.g[state.slip, None] * state.d[state.slip] + np.einsum(
        "qij,qj->qi", state.N()[state.slip], s[state.slip])
    norm_t, norm_s = np.linalg.norm(lam_t, axis=1), np.linalg.norm(s, axis=1)
    slipping = state.slip & (norm_s > 0)
    law = np.linalg.norm(lam_t[slipping] - state.g[slipping, None] * s[slipping] / norm_s[slipping, None], axis=1)
    on = g > 0
    turned = np.sum(s * state.d, axis=1) <= SIGN_RTOL * max(float(norm_s.max(initial=0.0)), 1e-300) * norm_s
    stick = np.where(state.stick, norm_t <= g + SIGN_RTOL * lam_max, state.slip & turned) & on
    starts = state.stick & ~stick & on
    d = np.where(starts[:, None], lam_t / np.maximum(norm_t, 1e-300)[:, None], s / np.maximum(norm_s, 1e-300)[:, None])
    size = np.where(starts, 0.0, norm_s)
    slip = on & ~stick
    d[~slip], size[~slip] = 0.0, 0.0
    changed = int(np.count_nonzero(stick != state.stick) + np.count_nonzero(on != (state.g > 0)))
    new = PointState(stick, d, size, g, lam_t)
    rows = np.flatnonzero(np.repeat(stick, 2))
    if len(rows):
        _, sv, vt = np.linalg.svd(B[rows], full_matrices=False)
        new.basis = vt[sv > STICK_RCOND * sv[0]]
    else:
        new.basis = np.zeros((0, B.shape[1]))
    return new, changed, float(law.max(initial=0.0)) / max(lam_max, 1e-300)


def friction_loop(comm, op: Operator, rhs, x, aset, crack: CrackUnknowns, layout: FrictionLayout,
                  face_gid: np.ndarray, sign_rtol: float):
    """The Newton steps of the module docstring on the frictionless solve's `aset` (`solid.FaceActiveSet`) with
    `face_gid` its faces' numbers over all cracks; returns (steps, CG steps per step, the last PointState,
    cumulated `x`)."""
    from mpi4py import MPI

    q = len(layout.face)
    B = layout.B
    state = PointState(np.zeros(q, bool), np.zeros((q, 2)), np.zeros(q), np.zeros(q), np.zeros((q, 2)),
                       np.zeros((0, crack.nt)))
    rhs_c = rhs.CreateVector()
    rhs_c.data = rhs
    op.cumulate(rhs_c)
    # the same operator, its exchange, CG records and clock shared, with the slipping points' blocks added
    slip_op = SlipOperator(**{f.name: getattr(op, f.name) for f in fields(op)}, crack=crack, B=B)
    load, residual = rhs_c.CreateVector(), rhs_c.CreateVector()

    def project(vec):
        aset.project(vec)
        if len(state.basis):
            t = crack.values(vec)
            crack.put(vec, t - state.basis.T @ (state.basis @ t))

    cg_steps, pending = [], []
    nfaces = int(max(np.max(layout.face, initial=-1), np.max(face_gid, initial=-1)) + 1)
    nfaces = comm.allreduce(nfaces, op=MPI.MAX)

    def step(g_used: np.ndarray) -> CoulombStep:
        """One Newton step with the sets of the last one (held on entry), then the next sets (rank 0's)."""
        nonlocal state
        if pending:  # the last step's sets, now that the loop goes on
            active, new = pending.pop()
            if active is not None:
                aset.set(active)
                hold(op, aset)
            state = new
        load.data = rhs_c
        crack.add(load, -(B.T @ (state.g[:, None] * state.d * state.slip[:, None]).ravel()))
        slip_op.N = state.N()
        cg_steps.append(pcg(slip_op, load, x, project))
        op.seconds = slip_op.seconds
        force_residual(op, x, rhs_c, residual)
        xv, rv = x.FV().NumPy(), residual.FV().NumPy()
        w = aset.G @ xv[aset.jn]
        lam = aset.Ginv.T @ rv[aset.jn]
        w_max = comm.allreduce(float(np.max(np.abs(w), initial=0.0)), op=MPI.MAX)
        lam_max = comm.allreduce(float(np.max(np.abs(lam), initial=0.0)), op=MPI.MAX)
        active = np.where(aset.active, lam > -sign_rtol * lam_max, w < -sign_rtol * w_max)
        changed = comm.allreduce(int(np.count_nonzero(active != aset.active)))
        face_force = np.zeros(nfaces)
        for i, dofs in enumerate(aset.faces):
            face_force[face_gid[i]] = np.sum(np.where(active[dofs], lam[dofs], 0.0))
        face_force = comm.allreduce(face_force)
        g = layout.mu * layout.omega * np.maximum(face_force, 0.0)[layout.face]
        t = crack.values(x)
        s = (B @ t).reshape(q, 2)
        r_t = crack.values(residual) + B.T @ (
            state.g[:, None] * state.d * state.slip[:, None] + np.einsum("qij,qj->qi", slip_op.N, s)).ravel()
        if comm.rank == 0:  # decided on one rank: every rank holds the same sets
            new, changed_t, law = _update(state, B, s, r_t, g, lam_max)
        else:
            new, changed_t, law = None, 0, 0.0
        new, changed_t, law = comm.bcast((new, changed_t, law), root=0)
        g = new.g  # rank 0's bound: the loop's test is then the same on every rank
        if _DEBUG and comm.rank == 0:
            print(f"friction step {len(cg_steps)}: CG {cg_steps[-1]}, set changes {changed} + {changed_t}, slip law "
                  f"{law:.1e}", flush=True)
        state.lam_t = new.lam_t  # the forces of this step (kept if the loop stops here)
        pending.append((active if changed else None, new))
        return CoulombStep(g, max(lam_max, 1e-300), changed + changed_t, law)

    run = coulomb_loop(step, state.g, max_steps=MAX_STEPS, bound_rtol=BOUND_RTOL, law_rtol=LAW_RTOL,
                       what="the crack problem with friction", unit="steps")
    return run.steps, cg_steps, state
