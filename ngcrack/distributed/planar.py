"""The distributed solve: parallel assembly, BDDC-preconditioned CG, the crack problem's
active set on the distributed crack unknowns, the gather to rank 0 (package docstring).

The crack problem is the serial one (contact.py): with w = G j the constraint values
(G per crack edge, `post.endpoint_map`), find j with w >= 0, lam >= 0, w lam = 0, the
forces lam = G^{-T} (K y - F)_c. Each step holds the active values at zero (a
projection of the crack edges' unknowns, krylov.py) and solves the rest by CG on the
sign-flipped (symmetric positive definite) system, preconditioned by BDDC (bddc.py); then
an active value leaves where its force is negative and an inactive one enters where it
penetrates. The iteration stops when no rank changes its active set. With Coulomb
friction the tangential values join it (stick and slip sets, friction.py).
"""

from __future__ import annotations

import time

import ngsolve as ngs
import numpy as np

from ..core.errors import InputError
from ..core.options import SolveOptions
from ..planar import elements as _elements
from ..planar.materials import compliance
from ..planar.post import endpoint_map
from .bddc import default_for, owned, preconditioner
from .friction import FrictionSets, friction_loop
from .gather import gather_to_rank0
from .krylov import Operator, condensed_rhs, held_rows, hold, pcg
from .mesh import MATCH_RTOL, TooFewElements, distribute
from .world import MPIUnavailable, require_mpi, run_on_ranks

#: active-set steps before the iteration is declared cycling
MAX_ACTIVE_SET_STEPS = 60
#: a force or a constraint value within this fraction of its largest magnitude counts as zero
#: when the active set is updated (round-off of the Krylov solve)
SIGN_RTOL = 1e-9


def check_supported(scene, o: SolveOptions) -> None:
    """What the distributed solve does not do yet, refused on every rank before any work."""
    if o.hp:
        raise InputError("hp: the distributed solve takes plain meshes only (hp = 0); run hp meshes without mpiexec")
    if getattr(scene, "points", ()):
        raise InputError("point: point supports and loads are not distributed yet; run this scene without mpiexec")
    if getattr(scene, "dim", 2) != 2:
        raise InputError("dim: the distributed solve handles 2D scenes; run 3D scenes without mpiexec")


def unsupported_discretization(disc, loads) -> str | None:
    """Why this rank's discretization cannot be solved distributed (None: it can)."""
    if disc.traits.gradient == "gradient":  # a displacement element: its crack constraints sit at vertices
        return (f"element: {disc.element!r} is not distributed (its crack constraints sit at vertices, shared "
                f"by edges); use one of {', '.join(sorted(_elements.MIXED))} under mpiexec")
    for _, _, nrm in disc.roller_pairs(loads.roller):
        if nrm is not None and abs(nrm[0]) > 1e-12 and abs(nrm[1]) > 1e-12:
            return (f"boundary: a roller edge not parallel to an axis is not distributed yet (normal {nrm[0]:.3g}, "
                    f"{nrm[1]:.3g}); run this scene without mpiexec")
    return None


def agree(comm, message: str | None) -> None:
    """Raise InputError on every rank if any rank has a `message` (so that all stop alike; collective)."""
    messages = [m for m in comm.allgather(message) if m]
    if messages:
        raise InputError(messages[0])


def free_mask(disc, loads) -> np.ndarray:
    """The condensed system's unknowns on this rank (coupling, not Dirichlet, not held):
    rollers whose normal is a coordinate axis hold that component (`unsupported_discretization`
    refuses the others first)."""
    fes = disc.fes
    free = np.array([bool(fes.FreeDofs(True)[d]) for d in range(fes.ndof)], dtype=bool)
    free[list(disc.fixed_dofs)] = False
    for dx, dy, nrm in disc.roller_pairs(loads.roller):
        if nrm is None:
            free[dx] = free[dy] = False
        elif abs(nrm[1]) < 1e-12:
            free[dx] = False
        elif abs(nrm[0]) < 1e-12:
            free[dy] = False
    return free


class ActiveSet:
    """The active constraint values on this rank's crack edges and the projection that holds them at zero."""

    def __init__(self, G: np.ndarray, jn_dofs: np.ndarray, free: np.ndarray):
        self.G, self.jn, self.free = G, jn_dofs, free
        self.Ginv = np.linalg.inv(G) if len(G) else G
        self.active = np.zeros(len(G), dtype=bool)
        self.P = np.eye(len(G))

    def set(self, active: np.ndarray) -> None:
        self.active = active.copy()
        GA = self.G[active]
        self.P = np.eye(len(self.G))
        if len(GA):
            self.P -= GA.T @ np.linalg.solve(GA @ GA.T, GA)

    def project(self, vec: ngs.BaseVector) -> None:
        vals = vec.FV().NumPy()
        vals[~self.free] = 0.0
        if len(self.jn):
            vals[self.jn] = self.P @ vals[self.jn]

    def held(self):
        """The held values' rows over this rank's dofs (G's active rows on the crack unknowns), sparse."""
        return held_rows([(self.G[self.active], self.jn)], len(self.free))


def solve(scene, options: SolveOptions | None = None):
    """One solve over the ranks of MPI_COMM_WORLD; the Solution on rank 0, None on the others."""
    from ..core.pipeline import Pipeline
    from ..scenes import load

    comm = require_mpi()
    scene = load(scene) if isinstance(scene, str) else scene
    o = options if options is not None else SolveOptions()

    def check():
        Pipeline.check(scene, o)
        check_supported(scene, o)
        if comm.size < 2:
            raise MPIUnavailable("distributed solve: one MPI process; the serial solve is the one to use")

    # TooFewElements and InputError in the work are found alike on every rank (`agree`)
    return run_on_ranks(comm, check, lambda: _solve(comm, scene, o), alike=(TooFewElements, InputError))


def _solve(comm, scene, o: SolveOptions):
    from ..core.pipeline import ParameterLoads, Pipeline

    rank = comm.rank
    timings: dict[str, float] = {}
    t_start = t0 = time.perf_counter()
    pipe = Pipeline() if rank == 0 else None
    serial_mesh = pipe.mesh(scene, o) if rank == 0 else None
    timings["mesh"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    blocks = constraint_blocks(pipe, scene, o, serial_mesh) if rank == 0 else None
    # what rank 0's serial discretization cannot do distributed, told to every rank before any other work
    agree(comm, blocks if isinstance(blocks, str) else None)
    timings["blocks"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    cmesh = distribute(serial_mesh, scene, comm)
    timings["distribute"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    loads = ParameterLoads(scene).loads
    mat = scene.material
    disc = _elements.build(o.element, cmesh, compliance(mat.E, mat.nu, mat.plane), loads, order=o.order)
    free = free_mask(disc, loads)
    timings["assemble"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    pre, coarse = preconditioner(disc, default_for(disc, comm.size), free, comm)
    timings["preconditioner"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    fes, a = disc.fes, disc.a
    rhs, x = condensed_rhs(disc, loads, free, prescribed_values(comm, pipe, scene, o, serial_mesh, cmesh, disc, loads))
    x_fixed = x.CreateVector()
    x_fixed.data = x
    x[:] = 0.0
    timings["assemble"] += time.perf_counter() - t0

    t0 = time.perf_counter()
    op = Operator(A=a.mat, C=pre, sign=disc.sign)
    has_crack = disc.jn is not None and o.crack_model != "free"
    tangential = has_crack and o.tangential_for(scene)
    jn_dofs, jt_dofs = _dofs(fes, disc.jn if has_crack else None), _dofs(fes, tangential_component(disc) if
                                                                         tangential else None)
    G, Gt, mu = local_constraint_maps(comm, disc, cmesh, blocks if has_crack else [], scene, tangential)
    slip = np.zeros(len(G))
    if tangential:
        sets = FrictionSets(G, Gt, mu, jn_dofs, jt_dofs, free)
        steps, cg_steps = friction_loop(comm, op, rhs, x, sets, SIGN_RTOL)
        active, slip = sets.contact, sets.sign
    else:
        aset = ActiveSet(G, jn_dofs, free)
        if has_crack and o.crack_model == "bonded":
            aset.set(np.ones(len(G), dtype=bool))
            hold(op, aset)
        steps, cg_steps = normal_loop(comm, op, rhs, x, aset, iterate=has_crack and o.crack_model == "contact")
        active = aset.active
    op.cumulate(x)
    timings["solve"] = time.perf_counter() - t0
    timings["cg"] = op.seconds  # the rest of "solve": the active-set (and friction) updates and their reductions
    info = {"ranks": comm.size, "subdomains": comm.size - 1, "active_set_steps": steps, "cg_steps": cg_steps,
            "cg_steps_1e-8": [r.get(1e-8) for r in op.reached], "preconditioner": coarse, "krylov": "cg",
            "global_dofs": int(comm.allreduce(int(np.count_nonzero(free & owned(fes))))),
            "memory_mb": _memory_per_rank(comm)}
    t0 = time.perf_counter()
    gathered = gather_to_rank0(comm, cmesh, fes, x, active, jn_dofs)
    codes = np.zeros(fes.ndof)
    codes[jn_dofs] = slip  # the slip direction per constraint point (points are numbered like jn's dofs)
    slips = gather_to_rank0(comm, cmesh, fes, codes, active, jn_dofs)
    timings["gather"] = time.perf_counter() - t0
    if rank != 0:
        return None
    from .assemble0 import solution_on_rank0

    return solution_on_rank0(pipe, scene, o, serial_mesh, gathered, timings, info, t_start,
                             slips if tangential else None)


def normal_loop(comm, op, rhs, x, aset: ActiveSet, iterate: bool) -> tuple[int, list[int]]:
    """The frictionless active-set steps (module docstring); returns (steps, CG steps per step)."""
    steps, cg_steps = 0, []
    residual = x.CreateVector()
    jn_dofs, G = aset.jn, aset.G
    while True:
        steps += 1
        cg_steps.append(pcg(op, rhs, x, aset.project))
        if not iterate:
            return steps, cg_steps
        op.cumulate(x)
        op.apply(x, residual)
        residual.data -= rhs  # K y - F: the crack faces' forces on the crack rows
        op.cumulate(residual)
        w = G @ x.FV().NumPy()[jn_dofs]
        lam = aset.Ginv.T @ residual.FV().NumPy()[jn_dofs]
        w_max = comm.allreduce(float(np.max(np.abs(w), initial=0.0)), op=_max())
        lam_max = comm.allreduce(float(np.max(np.abs(lam), initial=0.0)), op=_max())
        active = np.where(aset.active, lam > -SIGN_RTOL * lam_max, w < -SIGN_RTOL * w_max)
        changed = comm.allreduce(int(np.count_nonzero(active != aset.active)))
        if changed == 0:
            return steps, cg_steps
        if steps >= MAX_ACTIVE_SET_STEPS:
            raise RuntimeError(f"crack problem: the active set still changed after {steps} steps")
        aset.set(active)
        hold(op, aset)


def tangential_component(disc) -> int:
    """The compound component whose crack dofs carry the tangential jump (jt, or TDNNS's u_e)."""
    return disc.jt if disc.jt is not None else disc.tangential


def _dofs(fes, component: int | None) -> np.ndarray:
    if component is None:
        return np.zeros(0, dtype=int)
    rng = fes.Range(component)
    return np.arange(rng.start, rng.stop)


def prescribed_values(comm, pipe, scene, o: SolveOptions, serial_mesh, cmesh, disc, loads) -> np.ndarray | None:
    """The prescribed displacements' values per local dof (None without any): interpolated on rank 0's serial
    discretization and matched to this rank's nodes by position (collective). NGSolve's interpolation on the
    distributed mesh would sum through NGSolve's own exchange, which fails from 4 ranks with MPICH (exchange.py)."""
    from .gather import local_values, serial_node_values

    if not loads.displacement:
        return None
    serial = None
    if comm.rank == 0:
        sdisc, sloads = pipe.discretization(scene, serial_mesh, o)
        gD = ngs.GridFunction(sdisc.fes)
        sdisc.boundary_values(gD, sloads)
        serial = serial_node_values(serial_mesh.mesh, sdisc.fes, gD.vec.FV().NumPy())
    serial = comm.bcast(serial, root=0)
    return local_values(serial, cmesh.mesh, disc.fes, MATCH_RTOL * scene.diameter)


def constraint_blocks(pipe, scene, o: SolveOptions, serial_mesh) -> list | str:
    """Rank 0: per crack edge (mid point, block of G, block of Gt or None, crack index), or why the
    discretization cannot be distributed (`unsupported_discretization`).

    G (post.endpoint_map) and, with friction, Gt (the element's tangential_point_map) are
    computed on the serial mesh (moments over the crack edges, point evaluation); their
    blocks go to the ranks, which place them on their own crack edges (the same dofs in
    the same order).
    """

    disc, loads = pipe.discretization(scene, serial_mesh, o)
    why = unsupported_discretization(disc, loads)
    if why is not None:
        return why
    if disc.jn is None:
        return []
    space = disc.fes.components[disc.jn]
    G = endpoint_map(space, serial_mesh, disc.facet_order)
    tangential = o.tangential_for(scene)
    Gt = disc.tangential_point_map(serial_mesh, G) if tangential else None
    space_t = disc.fes.components[tangential_component(disc)] if tangential else None
    out = []
    for k, crack in enumerate(serial_mesh.cracks):
        for e, mid in zip(crack.edge, crack.mid):
            node = ngs.NodeId(ngs.EDGE, int(e))
            dofs = list(space.GetDofNrs(node))
            block_t = Gt[np.ix_(dofs, list(space_t.GetDofNrs(node)))] if tangential else None
            out.append((np.asarray(mid, float), G[np.ix_(dofs, dofs)], block_t, k))
    return out


def local_constraint_maps(comm, disc, cmesh, blocks: list | None, scene, tangential: bool):
    """(G, Gt, mu per point) on this rank's crack unknowns from rank 0's blocks, matched by the edges' mid points
    (Gt and mu empty without friction); collective."""
    blocks = comm.bcast(blocks, root=0)
    n = disc.fes.components[disc.jn].ndof if disc.jn is not None and blocks else 0
    G, Gt, mu = np.zeros((n, n)), np.zeros((n, n) if tangential else (0, 0)), np.zeros(n if tangential else 0)
    if not n:
        return G, Gt, mu
    space = disc.fes.components[disc.jn]
    space_t = disc.fes.components[tangential_component(disc)] if tangential else None
    friction = [float(c.friction) for c in scene.cracks]
    mids = np.array([b[0] for b in blocks])
    for crack in cmesh.cracks:
        for e, mid in zip(crack.edge, crack.mid):
            dist = np.linalg.norm(mids - mid, axis=1)
            k = int(np.argmin(dist))
            if dist[k] > MATCH_RTOL * scene.diameter:
                raise RuntimeError("crack problem: a crack edge of a subdomain matches no crack edge of the mesh")
            node = ngs.NodeId(ngs.EDGE, int(e))
            dofs = list(space.GetDofNrs(node))
            G[np.ix_(dofs, dofs)] = blocks[k][1]
            if tangential:
                if space_t.ndof != n:
                    raise RuntimeError("crack problem with friction: the tangential and normal unknowns differ in number")
                Gt[np.ix_(dofs, list(space_t.GetDofNrs(node)))] = blocks[k][2]
                mu[dofs] = friction[blocks[k][3]]
    return G, Gt, mu


def _max():
    from mpi4py import MPI

    return MPI.MAX


#: the dofs this rank counts (bddc.owned; the name other modules of the package import)
_owned = owned


def _memory_per_rank(comm) -> list[float]:
    """Peak resident memory of every rank, in MB (Linux: ru_maxrss in kB)."""
    import resource

    return comm.allgather(round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, 1))
