"""NGSolve's BDDC preconditioner on the condensed facet system, and its coarse space.

NGSolve's "bddc" treats every element as a subdomain: the interface unknowns are
averaged, the local problems solved exactly, and the wirebasket unknowns form the coarse
problem, gathered and factorized on one rank ("masterinverse"). The coarse space chosen
here (marked WIREBASKET before assembly):

- every unknown of a normal-facet component (TDNNS's u_hat_n, all its orders): with
  the higher-order normal-facet unknowns left as interface unknowns NGSolve's BDDC is
  not a usable preconditioner (its spectrum spreads over 1e-3..1e16 and CG stalls,
  also on a symmetric positive definite form with the same spaces; measured in
  BENCHMARKS section 18);
- the lowest-order unknown of every facet in every other facet component (the
  tangential Nedelec dof of TDNNS's u): with the normal-facet unknowns they fix an
  element's rigid motions;
- every unknown on the crack edges (the crack jumps act on one side's elements only,
  so an element's own matrix is singular in them).

The interface space left to the local solves is the higher-order tangential trace. On
this space CG needs about 20 steps to 1e-8 at every mesh size measured (9k-59k unknowns),
but the coarse problem is about three quarters of the condensed system at order 1: it is
the part that does not shrink with the ranks.
"""

from __future__ import annotations

import ngsolve as ngs

#: how the coarse space is described in the results and BENCHMARKS
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


#: the preconditioners of the distributed CG: "bddc" (NGSolve's BDDC with the coarse space
#: above) and "direct" (the condensed matrix gathered on rank 0 and factorized there:
#: NGSolve's "masterinverse"; exact, CG stops after a step or two)
PRECONDITIONERS = ("bddc", "direct")
#: the distributed solve's, where `bddc_applies`; "direct" otherwise
DEFAULT = "bddc"
#: the spaces of the elements that keep the direct preconditioner: bdm's vector facet space
#: breaks the coarse space above as the normal-facet one does (CG with BDDC stalls, 400
#: steps at griffith's default mesh), and for peers (vertex rotations in H1) BDDC's coarse
#: space is every unknown, i.e. the direct solve
NOT_BDDC_SPACES = (ngs.FacetFESpace, ngs.H1)


def bddc_applies(fes: ngs.FESpace) -> bool:
    """Whether the coarse space above was measured to work on `fes` (TDNNS's HCurl and normal-facet traces)."""
    return not any(isinstance(comp, NOT_BDDC_SPACES) for comp in fes.components)


def default_for(disc) -> str:
    """The preconditioner the distributed solve uses for `disc`: DEFAULT where `bddc_applies`, else "direct"."""
    return DEFAULT if bddc_applies(disc.fes) else "direct"


def preconditioner(disc, kind: str = DEFAULT, free=None):
    """(operator, description): the preconditioner `kind` of the condensed matrix of `disc` (an approximate
    inverse of the matrix as assembled, of its sign: the Krylov solver flips both) on the unknowns `free` (a
    boolean mask; None: the space's coupling free dofs). The unknowns the space leaves free but `free` holds
    (bdm's and peers' roller components) are taken out of the space's free dofs first: without them the
    matrix is singular (the body's rigid motions)."""
    if free is not None:
        _hold(disc.fes, free)
    if kind == "bddc":
        crack_edges = {int(e) for c in disc.crack_mesh.cracks for e in c.edge}
        mark_coarse_space(disc.fes, disc.fes.mesh, crack_edges)
        pre = ngs.Preconditioner(disc.a, "bddc")
        disc.a.Assemble()  # BDDC collects the element matrices during assembly
        return pre.mat, f"bddc, coarse space: {COARSE_SPACE}"
    if kind == "direct":
        return disc.a.mat.Inverse(disc.fes.FreeDofs(True), inverse="masterinverse"), "direct (masterinverse on rank 0)"
    raise ValueError(f"preconditioner = {kind!r}: allowed values are {', '.join(PRECONDITIONERS)}")


def _hold(fes: ngs.FESpace, free) -> None:
    """Clear in the space's free dofs (both, and the coupling ones) every dof that `free` holds."""
    for bits in (fes.FreeDofs(), fes.FreeDofs(True)):
        for d in range(fes.ndof):
            if bits[d] and not free[d]:
                bits[d] = False
