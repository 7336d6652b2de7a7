"""A 3D scene (ngcrack.solid) solved over the ranks of MPI_COMM_WORLD.

The 2D distributed solve's stages (`distributed.planar`) on the 3D element:

- mesh: rank 0 meshes the scene serially (the mesh a serial solve gets) and keeps it;
  netgen distributes a copy; every rank curves its subdomain with the scene's geometry
  and finds its crack faces and interior crack edges again (`solid_mesh`);
- system: every rank builds the hybridized TDNNS element (`solid.element.build`) on its
  subdomain, the face tractions and crack pressures that vary in space as the serial
  solve's CoefficientFunctions (`solid.loads.coefficients`), and assembles the condensed
  facet system in parallel; the crack's constraint map G is made on rank 0's serial mesh and its per-face blocks placed on each rank;
- crack problem: the active-set steps of the 2D solve (`solve.normal_loop`), each step a
  projected CG with the active constraint values of a crack face held at zero by a
  projection on that face's unknowns (`FaceActiveSet`); preconditioner: BDDC with one
  subdomain per rank ("subdomains", subdomains.py: the 6 rigid motions' averages per
  shared face as coarse space, the held constraint values kept in the local solves), or
  NGSolve's element-wise BDDC with the coarse space of `coarse_space` ("bddc", 64-84% of
  the system); the condensed matrix factorized on rank 0 ("direct": asked for);
- gather: the condensed unknowns go to rank 0 by node coordinates; rank 0 assembles the
  serial system (no factorization), recovers the element-local unknowns and runs the
  serial post-processing (KKT residuals from the serial system's residual, the fronts'
  K_I, K_II, K_III, G, the error estimate): one SolidSolution on rank 0, written once.

With Coulomb friction the crack problem's steps are those of `solid_friction` (the serial
law at the friction points, Newton steps by the same projected CG). Not distributed yet
(refused by name before any work): the displacement baselines h1p1 / h1p2 (their
constraints sit at vertices), point supports, and above 3 ranks a prescribed displacement (NGSolve interpolates
it through its own exchange, exchange.py).
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp

from ..core.errors import InputError
from .krylov import Operator, condensed_rhs, held_rows
from .solid_mesh import TooFewTetrahedra, check_ranks, crack_layout, distribute, gather_to_rank0, local_solid_mesh, scatter_into

#: the 3D preconditioners of the distributed CG: BDDC per rank subdomain (subdomains.py), NGSolve's
#: element-wise BDDC with `coarse_space`, or the condensed matrix gathered and factorized on rank 0
#: ("direct": NGSolve's masterinverse)
PRECONDITIONERS = ("subdomains", "bddc", "direct")
def default_preconditioner(size: int) -> str:
    """The preconditioner a distributed 3D solve over `size` ranks uses unless told: BDDC per rank subdomain at any
    number of ranks (its exchanges go through mpi4py, exchange.py)."""
    return "subdomains"


class SplitCrackFace(ValueError):
    """A crack face's two tetrahedra sit on two ranks (not handled yet; found alike on every rank)."""


#: the most ranks at which a prescribed displacement is interpolated on the distributed mesh: NGSolve's
#: GridFunction.Set sums through NGSolve's own exchange, which is wrong from 3 subdomains on with MPICH
#: (exchange.py); at 2 and 3 ranks each subdomain has at most one neighbour
MAX_RANKS_DISPLACEMENT = 3


def check_supported(scene, opts: dict, size: int = 2) -> None:
    """What the distributed 3D solve over `size` ranks does not do, refused on every rank before any work."""
    if opts["element"] != "tdnns":
        raise InputError(f"element = {opts['element']!r}: a distributed 3D solve takes element = 'tdnns' (the "
                         "displacement baselines' crack constraints sit at vertices); run it without mpiexec")
    if getattr(scene, "points", ()):  # (solid.points)
        raise InputError("point[0]: point supports are solved serially only; run the scene without mpiexec")
    shifted = [label for label, bc in scene.boundary.items() if bc.type == "displacement"]
    if shifted and size > MAX_RANKS_DISPLACEMENT:
        raise InputError(f"boundary[{shifted[0]!r}].type = 'displacement': a prescribed displacement in 3D is "
                         f"distributed on at most {MAX_RANKS_DISPLACEMENT} ranks (mpiexec -n {size} asked); run it "
                         f"with -n 2 or 3 or without mpiexec, or clamp the face")


class FaceActiveSet:
    """The active constraint values of this rank's crack faces and the projection holding them at zero.

    G is block diagonal, one p x p block per crack face (rows: the face's constraint points,
    placed on the face's jn unknowns); the projection acts face by face."""

    def __init__(self, faces: list[np.ndarray], blocks: list[np.ndarray], n: int, jn_dofs: np.ndarray,
                 free: np.ndarray):
        self.faces, self.blocks = faces, blocks
        self.jn, self.free = jn_dofs, free
        self.G = self._matrix(blocks, n)
        self.Ginv = self._matrix([np.linalg.inv(b) for b in blocks], n)
        self.active = np.zeros(n, dtype=bool)
        self.P = sp.identity(n, format="csr")
        self.n = n

    def _matrix(self, blocks, n: int) -> sp.csr_matrix:
        if not blocks:
            return sp.csr_matrix((n, n))
        rows = np.concatenate([np.repeat(d, len(d)) for d in self.faces])
        cols = np.concatenate([np.tile(d, len(d)) for d in self.faces])
        return sp.csr_matrix((np.concatenate([b.ravel() for b in blocks]), (rows, cols)), shape=(n, n))

    def set(self, active: np.ndarray) -> None:
        self.active = active.copy()
        rows, cols, vals = [np.arange(self.n)], [np.arange(self.n)], [np.ones(self.n)]
        for d, b in zip(self.faces, self.blocks):
            on = active[d]
            if not on.any():
                continue
            GA = b[on]
            Q = GA.T @ np.linalg.solve(GA @ GA.T, GA)
            rows.append(np.repeat(d, len(d)))
            cols.append(np.tile(d, len(d)))
            vals.append(-Q.ravel())
        self.P = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                               shape=(self.n, self.n))

    def project(self, vec: ngs.BaseVector) -> None:
        vals = vec.FV().NumPy()
        vals[~self.free] = 0.0
        if len(self.jn):
            vals[self.jn] = self.P @ vals[self.jn]

    def held(self) -> sp.csr_matrix:
        """The held values' rows over this rank's dofs (each face's active rows of its block), sparse."""
        return held_rows([(b[self.active[d]], self.jn[d]) for d, b in zip(self.faces, self.blocks)
                          if self.active[d].any()], len(self.free))


def solve_scene(scene, options=None):
    """`nc.solve` / `ngcrack solve` of a 3D scene under mpiexec: `options` a SolveOptions, checked for the 3D
    body by `nc.solve` before any work; the SolidSolution on rank 0, None elsewhere."""
    from ..core.options import SolveOptions
    from ..solid.solve import solid_options
    from ..solid.stages import check_request
    from .world import refuse

    options = options if options is not None else SolveOptions()
    opts = solid_options(options, scene)
    try:  # alike on every rank, before any work: rank 0 reports, the others leave quietly
        check_request(scene, opts, options.max_dof)
    except ValueError as exc:
        refuse(str(exc))
    return solve(scene, opts, options.preconditioner)


def solve(scene, opts: dict, preconditioner_kind: str | None = None):
    """The distributed 3D solve (module docstring): the SolidSolution on rank 0, None on the others.
    `opts`: the checked options of `solid.solve.check_options` with the mesh sizes."""
    from .world import require_mpi, run_on_ranks

    comm = require_mpi()
    kind = preconditioner_kind or default_preconditioner(comm.size)

    def check():
        check_supported(scene, opts, comm.size)
        if kind not in PRECONDITIONERS:
            raise InputError(f"preconditioner = {kind!r}: allowed values are {', '.join(PRECONDITIONERS)}")

    # a too coarse mesh or a split crack face is found alike on every rank
    return run_on_ranks(comm, check, lambda: _solve(comm, scene, opts, kind), alike=(TooFewTetrahedra, SplitCrackFace))


@dataclass
class LocalSystem:
    """This rank's part of a distributed 3D solve before its crack problem (`local_system`)."""

    pipe: object  # rank 0's Pipeline (None elsewhere)
    smesh: object  # rank 0's serial SolidMesh (None elsewhere)
    mesh: ngs.Mesh  # this rank's subdomain
    lsm: object  # its SolidMesh
    placed: list  # per crack: (local crack faces, their blocks of G)
    loads: object
    disc: object  # the TDNNS discretization on the subdomain, assembled
    layout: list = None  # per crack: solid_mesh.CrackLayout (every rank)
    friction: object = None  # with Coulomb friction: solid_friction.FrictionLayout (every rank)
    points: object = None  # and rank 0's serial FrictionPoints (None elsewhere)


def local_system(comm, scene, opts: dict, timings: dict) -> LocalSystem:
    """Mesh on rank 0, distribute, find the cracks again and assemble on every rank (module docstring), the stages'
    seconds into `timings` (collective)."""
    from ..core.pipeline import Pipeline
    from ..solid.element import build
    from ..solid.geometry import CURVE_ORDER
    from ..solid.loads import coefficients
    from ..solid.solve import scene_loads
    from .solid_friction import friction_layout

    rank = comm.rank
    t0 = time.perf_counter()
    sizes = scene.mesh_sizes(*(opts.get(k) for k in ("maxh", "crack_h", "front_h", "grading")))
    pipe = Pipeline() if rank == 0 else None
    smesh = pipe.mesh(scene, opts) if rank == 0 else None
    ne = comm.bcast(smesh.mesh.ne if rank == 0 else None, root=0)
    check_ranks(ne, comm.size)
    layout = comm.bcast(crack_layout(smesh, opts["order"]) if rank == 0 else None, root=0)
    frictional = opts["crack_model"] == "contact" and any(float(c.friction) > 0 for c in scene.cracks)
    friction, points = friction_layout(pipe, scene, opts, smesh) if frictional and rank == 0 else (None, None)
    friction = comm.bcast(friction, root=0)
    timings["mesh"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    mesh = distribute(smesh, scene, comm, sizes, CURVE_ORDER)
    lsm, placed = local_solid_mesh(mesh, scene, layout, sizes)
    # crack faces whose two tetrahedra sit on two ranks: netgen's partition kept every crack face's two
    # tetrahedra together at 2-6 ranks on every mesh measured; the other case is not verified, so refused
    shared = int(comm.allreduce(sum(len(f) for f, _ in placed)) - sum(len(c.centroids) for c in layout))
    if shared:
        raise SplitCrackFace(f"mpiexec -n {comm.size}: {shared} crack faces have their two tetrahedra on two ranks, "
                             "which the distributed 3D solve does not handle yet; use another number of ranks")
    timings["distribute"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    loads = scene_loads(scene)
    pressure, traction = coefficients(scene, loads.traction)  # loads varying in space as CoefficientFunctions
    loads = dataclasses.replace(loads, traction=traction)
    disc = build(lsm, scene.material.E, scene.material.nu, loads, opts["order"],
                 pressure if any(p is not None for p in pressure) else None, constraints=False)
    timings["assemble"] = time.perf_counter() - t0
    return LocalSystem(pipe, smesh, mesh, lsm, placed, loads, disc, layout, friction, points)


def _solve(comm, scene, opts: dict, kind: str):
    from .mesh import MATCH_RTOL
    from .planar import SIGN_RTOL, _memory_per_rank, _owned, normal_loop
    from .solid_friction import CrackUnknowns, face_numbers, friction_loop

    rank = comm.rank
    timings: dict[str, float] = {}
    t_start = time.perf_counter()
    loc = local_system(comm, scene, opts, timings)
    pipe, smesh, mesh, lsm, placed, loads, disc = (loc.pipe, loc.smesh, loc.mesh, loc.lsm, loc.placed, loc.loads,
                                                   loc.disc)
    fes, a = disc.fes, disc.a
    free = np.array(list(fes.FreeDofs(True)), dtype=bool)
    t0 = time.perf_counter()
    pre, described = make_preconditioner(disc, lsm, kind, comm)
    timings["preconditioner"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    rhs, x = condensed_rhs(disc, loads, free)
    x[:] = 0.0
    timings["assemble"] += time.perf_counter() - t0

    t0 = time.perf_counter()
    has_crack = disc.jn is not None
    jn_dofs = np.arange(fes.Range(disc.jn).start, fes.Range(disc.jn).stop) if has_crack else np.zeros(0, int)
    jn_space = fes.components[disc.jn] if has_crack else None
    faces, blocks = [], []
    for local_faces, bl in placed:
        for f_nr, b in zip(local_faces, bl):
            faces.append(np.array(jn_space.GetDofNrs(ngs.NodeId(ngs.FACE, int(f_nr))), dtype=int))
            blocks.append(b)
    aset = FaceActiveSet(faces, blocks, len(jn_dofs), jn_dofs, free)
    op = Operator(A=a.mat, C=pre, sign=disc.sign)
    state = None
    if loc.friction is not None and has_crack:
        local_faces = [int(f) for fs, _ in placed for f in fs]
        tol = MATCH_RTOL * scene.size
        crack = CrackUnknowns(comm, fes, disc.tangential, lsm.mesh, local_faces, loc.friction, tol)
        gid = face_numbers(lsm.mesh, local_faces, np.concatenate([c.centroids for c in loc.layout]), tol)
        steps, cg_steps, state = friction_loop(comm, op, rhs, x, aset, crack, loc.friction, gid, SIGN_RTOL)
    else:
        steps, cg_steps = normal_loop(comm, op, rhs, x, aset, iterate=has_crack and opts["crack_model"] == "contact")
    op.cumulate(x)
    timings["solve"] = time.perf_counter() - t0
    timings["cg"] = op.seconds  # the rest of "solve": the active-set updates and their reductions
    info = {"ranks": comm.size, "subdomains": comm.size - 1, "active_set_steps": steps, "cg_steps": cg_steps,
            "cg_steps_1e-8": [r.get(1e-8) for r in op.reached],
            "preconditioner": described, "krylov": "cg", "coarse_unknowns": getattr(pre, "coarse_size", None),
            "global_dofs": int(comm.allreduce(int(np.count_nonzero(free & _owned(fes))))),
            "memory_mb": _memory_per_rank(comm)}
    t0 = time.perf_counter()
    flags = np.zeros(fes.ndof, dtype=bool)
    flags[jn_dofs] = aset.active
    gathered = gather_to_rank0(comm, mesh, fes, x.FV().NumPy(), flags)
    timings["gather"] = time.perf_counter() - t0
    if rank != 0:
        return None
    from .solid_rank0 import solution_on_rank0

    return solution_on_rank0(pipe, scene, opts, smesh, gathered, timings, info, t_start,
                             (loc.points, state) if state is not None else None)


#: the coarse space of the 3D BDDC, as stated in the results
COARSE_SPACE = ("all normal-facet dofs, all edge dofs, the lowest-order face dof of the other facet components, "
                "all crack dofs")


def coarse_space(fes: ngs.FESpace, mesh: ngs.Mesh, crack_faces: set[int], crack_edges: set[int]) -> int:
    """Mark WIREBASKET the 3D coarse space (COARSE_SPACE) on the coupling unknowns of `fes`; returns how many.

    Measured on the coarse penny (21k unknowns, CG to 1e-8): with the 2D choice (normal-facet
    dofs, the lowest-order dof of the others) CG took 142 steps; all edge dofs added, 35."""
    normal_facet = [isinstance(comp, ngs.NormalFacetFESpace) for comp in fes.components]
    starts = np.array([fes.Range(k).start for k in range(len(fes.components))])
    interface, wirebasket = ngs.COUPLING_TYPE.INTERFACE_DOF, ngs.COUPLING_TYPE.WIREBASKET_DOF
    marked = 0
    for ntype, items, crack in ((ngs.EDGE, mesh.edges, crack_edges), (ngs.FACE, mesh.faces, crack_faces)):
        everything = ntype == ngs.EDGE
        for item in items:
            on_crack = item.nr in crack
            seen = set()
            for d in fes.GetDofNrs(ngs.NodeId(ntype, item.nr)):
                if d < 0:
                    continue
                k = int(np.searchsorted(starts, d, side="right")) - 1
                first = k not in seen
                seen.add(k)
                if (everything or on_crack or normal_facet[k] or first) and fes.CouplingType(d) == interface:
                    fes.SetCouplingType(d, wirebasket)
                    marked += 1
    return marked


def make_preconditioner(disc, lsm, kind: str, comm):
    if kind == "subdomains":
        from .bddc import subdomain_preconditioner

        return subdomain_preconditioner(disc, comm)
    if kind == "direct":
        return disc.a.mat.Inverse(disc.fes.FreeDofs(True), inverse="masterinverse"), "direct (masterinverse on rank 0)"
    from .bddc import require_ngsolve_exchange

    require_ngsolve_exchange(disc.fes, comm)  # NGSolve's BDDC cumulates through NGSolve's own exchange
    faces = {int(f) for c in lsm.cracks for f in c.faces}
    edges = {int(e.nr) for c in lsm.cracks for f in c.faces for e in lsm.mesh[ngs.NodeId(ngs.FACE, int(f))].edges}
    edges |= {int(e) for c in lsm.cracks for e in c.interior_edges}
    coarse_space(disc.fes, lsm.mesh, faces, edges)
    pre = ngs.Preconditioner(disc.a, "bddc")
    disc.a.Assemble()  # BDDC collects the element matrices during assembly
    return pre.mat, f"bddc, coarse space: {COARSE_SPACE}"


__all__ = ["FaceActiveSet", "check_supported", "coarse_space", "scatter_into", "solve"]
