"""NGSolve's BDDC preconditioner on the condensed facet system, and its coarse space.

NGSolve's "bddc" treats every element as a subdomain: the interface (facet) unknowns
are averaged, the local problems solved exactly, and the wirebasket unknowns form the
coarse problem, gathered and factorized on one rank. The hybrid elements have no
vertex unknowns in 2D, so the default wirebasket would be empty; the coarse space
chosen here is the lowest-order part of the facet trace unknowns (each facet's first
dof of every facet component: an element's rigid motions are fixed by them) and every
unknown on the crack edges (the crack jumps act on one side's elements only, so an
element's own matrix is singular in them), marked WIREBASKET before assembly.
"""

from __future__ import annotations

import ngsolve as ngs

#: how the coarse space is described in the results and BENCHMARKS
COARSE_SPACE = "lowest-order facet trace dofs (one per facet and facet component) and all crack-edge dofs"


def mark_coarse_space(fes: ngs.FESpace, mesh: ngs.Mesh, crack_edges: set[int]) -> int:
    """Mark WIREBASKET the first dof of every facet in every coupling component and every
    dof of the crack edges; returns how many were marked."""
    marked = 0
    for e in mesh.edges:
        on_crack = e.nr in crack_edges
        for comp_dofs in _per_component(fes, e):
            for d in comp_dofs if on_crack else comp_dofs[:1]:
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


#: the preconditioners of the distributed CG: "direct" (the condensed matrix gathered on rank 0
#: and factorized there: NGSolve's "masterinverse"; exact, CG stops after a step or two) and
#: "bddc" (NGSolve's BDDC with the coarse space above)
PRECONDITIONERS = ("direct", "bddc")
#: the distributed solve's: CG needs a symmetric positive definite preconditioner, and BDDC
#: on this negative definite condensed system is not one (its v.Cv has the wrong sign and
#: CG diverges); with GMRES it converges in about 40 steps (benchmarks/mpi_scaling.py), but a
#: GMRES projected onto the active set is not written yet (BENCHMARKS.md, section 18)
DEFAULT = "direct"


def preconditioner(disc, kind: str = DEFAULT):
    """(operator, description): the preconditioner `kind` of the condensed matrix of `disc`."""
    if kind == "bddc":
        crack_edges = {int(e) for c in disc.crack_mesh.cracks for e in c.edge}
        mark_coarse_space(disc.fes, disc.fes.mesh, crack_edges)
        pre = ngs.Preconditioner(disc.a, "bddc")
        disc.a.Assemble()  # BDDC collects the element matrices during assembly
        return pre.mat, f"bddc, coarse space: {COARSE_SPACE}"
    if kind == "direct":
        return disc.a.mat.Inverse(disc.fes.FreeDofs(True), inverse="masterinverse"), "direct (masterinverse on rank 0)"
    raise ValueError(f"preconditioner = {kind!r}: allowed values are {', '.join(PRECONDITIONERS)}")
