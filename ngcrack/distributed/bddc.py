"""The preconditioners of the distributed CG: BDDC per rank subdomain, NGSolve's element-wise BDDC, direct.

"subdomains" (the default for TDNNS, subdomains.py): BDDC with each rank's part of the mesh
as one subdomain, exact local solves and a coarse space of three rigid-motion averages per
face between two ranks (3 coarse unknowns at two subdomains).

"bddc": NGSolve's "bddc" treats every element as a subdomain: the interface unknowns are
averaged, the local problems solved exactly, and the wirebasket unknowns form the coarse
problem, gathered and factorized on one rank ("masterinverse"). Its coarse space here
(marked WIREBASKET before assembly):

- every unknown of a normal-facet component (TDNNS's u_hat_n, all its orders);
- the lowest-order unknown of every facet in every other facet component (the
  tangential Nedelec dof of TDNNS's u);
- every unknown on the crack edges (the crack jumps act on one side's elements only,
  so an element's own matrix is singular in them).

Why the higher-order normal-facet unknowns must be coarse: an element's condensed matrix
has exactly the rigid motions as kernel, and with only the lowest-order unknowns fixed its
interface block is nonsingular (measured on one triangle), but the coarse matrix, the sum
of the elements' Schur complements on the lowest-order unknowns, is singular. Its kernel
is the coarse vectors that are a rigid motion's traces on every element: the lowest-order
tangential and normal unknowns of a rigid motion are its edge means, i.e. its values at the
edge mid points, so the kernel is the piecewise rigid motions continuous at the edge mid
points -- the Crouzeix-Raviart functions on which Korn's inequality fails (a space of
dimension 8, 16 and 32, the 3 rigid motions included, on unit squares of 6, 34 and 138
triangles; tests/test_bddc_coarse.py). A rotation's normal trace is linear along an edge (its slope
the rotation) and its tangential trace constant, so the first-order normal-facet unknown is
what ties the elements' rotations together: with it in the coarse space the kernel is
gone. At order 1 that leaves one unknown in four (the higher-order tangential one) to the
local solves: the coarse problem is three quarters of the condensed system, no smaller
choice from the element's unknowns works, and the element-wise method does not scale.

"direct": the condensed matrix gathered on rank 0 and factorized there (NGSolve's
"masterinverse"; exact, CG stops after a step or two).
"""

from __future__ import annotations

import ngsolve as ngs

#: how the element-wise coarse space is described in the results and BENCHMARKS
COARSE_SPACE = ("all normal-facet dofs, the lowest-order dof of every facet in the other facet components, "
                "all crack-edge dofs")


def mark_coarse_space(fes: ngs.FESpace, mesh: ngs.Mesh, crack_edges: set[int]) -> int:
    """Mark WIREBASKET the coarse space above on the coupling unknowns of `fes`; returns how many were marked
    (unknowns already WIREBASKET not counted)."""
    normal_facet = [isinstance(comp, ngs.NormalFacetFESpace) for comp in fes.components]
    marked = 0
    for e in mesh.edges:
        on_crack = e.nr in crack_edges
        for k, comp_dofs in enumerate(_per_component(fes, e)):
            for d in comp_dofs if on_crack or normal_facet[k] else comp_dofs[:1]:
                if fes.CouplingType(d) == ngs.COUPLING_TYPE.INTERFACE_DOF:
                    fes.SetCouplingType(d, ngs.COUPLING_TYPE.WIREBASKET_DOF)
                    marked += 1
    return marked


def _per_component(fes: ngs.FESpace, edge) -> list[list[int]]:
    """The compound space's dofs of `edge`, split by component (empty lists for components without)."""
    out = []
    for k, comp in enumerate(fes.components):
        rng = fes.Range(k)
        dofs = [rng.start + d for d in comp.GetDofNrs(ngs.NodeId(ngs.EDGE, edge.nr)) if d >= 0]
        out.append(dofs)
    return out


#: the preconditioners of the distributed CG (module docstring)
PRECONDITIONERS = ("subdomains", "bddc", "direct")
#: the distributed solve's, where `bddc_applies`; "direct" otherwise
DEFAULT = "subdomains"
#: the spaces of the elements that keep the direct preconditioner: bdm's vector facet space
#: breaks the coarse space above as the normal-facet one does (CG with BDDC stalls, 400
#: steps at griffith's default mesh), and for peers (vertex rotations in H1) BDDC's coarse
#: space is every unknown, i.e. the direct solve
NOT_BDDC_SPACES = (ngs.FacetFESpace, ngs.H1)


def bddc_applies(fes: ngs.FESpace) -> bool:
    """Whether both BDDC variants were measured to work on `fes` (TDNNS's HCurl and normal-facet traces; the
    subdomain variant interpolates the rigid motions into these two)."""
    comps = list(fes.components)
    return (not any(isinstance(c, NOT_BDDC_SPACES) for c in comps) and any(isinstance(c, ngs.HCurl) for c in comps)
            and any(isinstance(c, ngs.NormalFacetFESpace) for c in comps))


class ElementwiseBDDCUnsafe(RuntimeError):
    """NGSolve's element-wise BDDC asked for where NGSolve's own exchanges are not reliable (exchange.py)."""


def require_ngsolve_exchange(fes: ngs.FESpace, comm=None) -> None:
    """Raise ElementwiseBDDCUnsafe where NGSolve's own exchange is not reliable for `fes` (exchange.py): NGSolve's
    element-wise BDDC cumulates through it in every application (collective)."""
    from .exchange import ngsolve_exchange_safe

    if comm is None:
        from mpi4py import MPI

        comm = MPI.COMM_WORLD
    if not ngsolve_exchange_safe(fes, comm):
        raise ElementwiseBDDCUnsafe(
            "preconditioner = 'bddc': NGSolve's element-wise BDDC sums over the ranks through NGSolve's own exchange, "
            "which MPICH's 4-byte request handles break on a rank with two or more neighbours (from mpiexec -n 4); "
            "use 'subdomains' or 'direct', or run mpi4py on Open MPI")


def default_for(disc, size: int = 1) -> str:
    """The preconditioner the distributed solve over `size` ranks uses for `disc`: DEFAULT where `bddc_applies`,
    else "direct". (The subdomain BDDC exchanges by mpi4py, exchange.py, so it holds at any number of ranks.)"""
    return DEFAULT if bddc_applies(disc.fes) else "direct"


def preconditioner(disc, kind: str = DEFAULT, free=None, comm=None):
    """(operator, description): the preconditioner `kind` of the condensed matrix of `disc` on the unknowns `free`
    (a boolean mask; None: the space's coupling free dofs): for "bddc" and "direct" an approximate inverse of
    the matrix as assembled, of its sign (the Krylov solver flips both), for "subdomains" one of the
    sign-flipped matrix with an `apply` method (`comm`: the ranks; None: MPI's world). The unknowns the space
    leaves free but `free` holds (bdm's and peers' roller components) are taken out of the space's free dofs
    first: without them the matrix is singular (the body's rigid motions)."""
    if kind not in PRECONDITIONERS:
        raise ValueError(f"preconditioner = {kind!r}: allowed values are {', '.join(PRECONDITIONERS)}")
    if free is not None:
        _hold(disc.fes, free)
    if kind == "subdomains":
        return subdomain_preconditioner(disc, comm)
    if kind == "bddc":
        require_ngsolve_exchange(disc.fes, comm)
        crack_edges = {int(e) for c in disc.crack_mesh.cracks for e in c.edge}
        mark_coarse_space(disc.fes, disc.fes.mesh, crack_edges)
        pre = ngs.Preconditioner(disc.a, "bddc")
        disc.a.Assemble()  # BDDC collects the element matrices during assembly
        return pre.mat, f"bddc element-wise, coarse space: {COARSE_SPACE}"
    return disc.a.mat.Inverse(disc.fes.FreeDofs(True), inverse="masterinverse"), "direct (masterinverse on rank 0)"


def crack_facets(disc) -> set[int]:
    """The crack's facets of this rank's mesh: its edges in 2D, its faces in 3D."""
    if disc.fes.mesh.dim == 3:
        return {int(f) for c in disc.crack_mesh.cracks for f in c.faces}
    return {int(e) for c in disc.crack_mesh.cracks for e in c.edge}


def subdomain_preconditioner(disc, comm=None, corners: str = "primal"):
    """(SubdomainBDDC, description) on the space's coupling free dofs of `disc` (2D or 3D; subdomains.py)."""
    import numpy as np

    from .subdomains import COARSE_SPACE as SUBDOMAIN_SPACE
    from .subdomains import SubdomainBDDC, dof_pieces

    if comm is None:
        from mpi4py import MPI

        comm = MPI.COMM_WORLD
    fes = disc.fes
    mask = np.array([bool(fes.FreeDofs(True)[d]) for d in range(fes.ndof)], dtype=bool)
    pieces = dof_pieces(fes, fes.mesh, crack_facets(disc))
    pre = SubdomainBDDC(comm, disc.a.mat, fes, mask, disc.sign, pieces, corners)
    return pre, f"bddc {SUBDOMAIN_SPACE} ({pre.coarse_size} coarse unknowns)"


def _hold(fes: ngs.FESpace, free) -> None:
    """Clear in the space's free dofs (both, and the coupling ones) every dof that `free` holds."""
    for bits in (fes.FreeDofs(), fes.FreeDofs(True)):
        for d in range(fes.ndof):
            if bits[d] and not free[d]:
                bits[d] = False


def unconstrained_steps(disc, kind: str, tols=(1e-6, 1e-8), comm=None, made=None, exact: bool = True) -> dict:
    """CG steps with the preconditioner `kind` on the sign-flipped condensed system of `disc` without crack
    constraints (the space's free dofs), to each preconditioned relative residual of `tols`, and their seconds;
    the coarse problem's global size; the last answer's largest relative difference to the direct solve (with
    `exact`; None without: the direct solve is the expensive part at large sizes) (collective; for
    BENCHMARKS 18 and the tests); the global unknowns. `made`: the preconditioner already made for `disc`
    (as `preconditioner` returns it; the 3D element-wise one is made by distributed.solid)."""
    import numpy as np

    from .krylov import Operator, pcg

    if comm is None:
        from mpi4py import MPI

        comm = MPI.COMM_WORLD
    fes = disc.fes
    pre, _ = made if made is not None else preconditioner(disc, kind, comm=comm)
    free = np.array([bool(fes.FreeDofs(True)[d]) for d in range(fes.ndof)], dtype=bool)
    if kind == "subdomains":
        coarse = pre.coarse_size
    else:
        wb = np.array([fes.CouplingType(d) == ngs.COUPLING_TYPE.WIREBASKET_DOF for d in range(fes.ndof)], dtype=bool)
        coarse = int(comm.allreduce(int(np.count_nonzero(free & wb & owned(fes)))))
    f = disc.f.vec.CreateVector()
    f.data = disc.f.vec
    f.data += disc.a.harmonic_extension_trans * f
    f.data *= disc.sign

    def project(v):
        v.FV().NumPy()[~free] = 0.0

    project(f)
    op = Operator(A=disc.a.mat, C=pre, sign=disc.sign)
    steps, seconds, x = [], [], f.CreateVector()
    for tol in tols:
        x[:] = 0.0
        before = op.seconds
        steps.append(pcg(op, f, x, project, tol=tol))
        seconds.append(op.seconds - before)
    unknowns = int(comm.allreduce(int(np.count_nonzero(free & owned(fes)))))
    out = {"steps": steps, "coarse": coarse, "unknowns": unknowns, "seconds": op.seconds, "seconds_each": seconds}
    if not exact:
        return dict(out, difference=None)
    exact = f.CreateVector()
    # cumulated before: the inverse cumulates its output first, by NGSolve's exchange (exchange.py)
    exact.SetParallelStatus(ngs.PARALLEL_STATUS.CUMULATED)
    disc.a.mat.Inverse(fes.FreeDofs(True), inverse="masterinverse").Mult(f, exact)
    exact.data *= disc.sign
    op.cumulate(x)
    op.cumulate(exact)
    diff = x.CreateVector()
    diff.data = x - exact
    return dict(out, difference=ngs.Norm(diff) / max(ngs.Norm(exact), 1e-300))


def owned(fes: ngs.FESpace):
    """The dofs this rank counts (the lowest rank sharing a dof counts it), a boolean mask."""
    import numpy as np
    from mpi4py import MPI

    pd = fes.ParallelDofs()
    own = np.ones(fes.ndof, dtype=bool)
    if pd is None:
        return own
    rank = MPI.COMM_WORLD.rank
    for d in range(fes.ndof):
        procs = pd.Dof2Proc(d)
        if len(procs) and min(procs) < rank:
            own[d] = False
    return own
