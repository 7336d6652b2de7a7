"""Why NGSolve's element-wise BDDC needs TDNNS's higher-order normal-facet unknowns in its coarse space.

Serial, on small unit squares (the hybrid TDNNS form of ngcrack.planar.elements.tdnns without a
crack). The numbers asserted: an element's condensed matrix has exactly the rigid motions
as kernel and its block on the higher-order (interface) unknowns is nonsingular, yet the
coarse matrix on the lowest-order unknowns is singular: its kernel holds the piecewise
rigid motions continuous at the edge mid points (Crouzeix-Raviart's failure of Korn's
inequality), many more than the 3 rigid motions; with that coarse space the preconditioned
spectrum spreads over 1e10 and more, with the normal-facet unknowns coarse it lies in [1, 10].
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
import pytest
from netgen.geom2d import unit_square

from ngcrack.planar.elements.tdnns import tdnns_terms
from ngcrack.planar.materials import compliance


def _tdnns(mesh: ngs.Mesh, dirichlet: str = "", only=None) -> tuple[ngs.FESpace, ngs.BilinearForm]:
    """The hybrid TDNNS form (order 1) on `mesh`, on the elements `only` (a BitArray; None: all)."""
    fes = ngs.FESpace([ngs.HDivDiv(mesh, order=1, discontinuous=True, plus=True),
                       ngs.HCurl(mesh, order=2, type1=True, dirichlet=dirichlet),
                       ngs.NormalFacetFESpace(mesh, order=1, dirichlet=dirichlet)])
    trial, test = fes.TrialFunction(), fes.TestFunction()
    comp = compliance(1.0, 0.3, "strain")
    volume, boundary = tdnns_terms(comp.apply(trial[0]), trial[0], test[0], trial, test, ngs.specialcf.normal(2))
    a = ngs.BilinearForm(fes, condense=True)
    a += volume * ngs.dx(definedonelements=only)
    a += boundary * ngs.dx(element_boundary=True, definedonelements=only)
    return fes, a


def _dense(fes, mat, dofs=None) -> tuple[np.ndarray, list[int]]:
    free = fes.FreeDofs(True)
    idx = [d for d in (range(fes.ndof) if dofs is None else dofs) if d >= 0 and free[d]]
    return mat.ToDense().NumPy()[np.ix_(idx, idx)], idx


def test_one_element_kernel_is_the_rigid_motions():
    """One triangle's condensed matrix (12 facet unknowns, sign flipped): kernel 3, interface block nonsingular."""
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=0.5))
    el = next(iter(mesh.Elements(ngs.VOL)))
    only = ngs.BitArray(mesh.ne)
    only.Clear()
    only[el.nr] = True
    fes, a = _tdnns(mesh, only=only)
    a.Assemble()
    M, idx = _dense(fes, a.mat, fes.GetDofNrs(el))
    M = -M
    ev = np.linalg.eigvalsh(M)
    assert len(idx) == 12
    assert np.sum(ev < 1e-10 * ev[-1]) == 3  # the rigid motions, no more
    inner = [k for k, d in enumerate(idx) if fes.CouplingType(d) == ngs.COUPLING_TYPE.INTERFACE_DOF]
    assert len(inner) == 6  # the higher-order tangential and normal unknowns
    assert np.min(np.linalg.eigvalsh(M[np.ix_(inner, inner)])) > 1e-3 * ev[-1]  # nonsingular


@pytest.mark.parametrize("maxh, expected", [(0.5, 8), (0.25, 16)])
def test_piecewise_rigid_motions_continuous_at_mid_points(maxh, expected):
    """The kernel of the coarse matrix on the lowest-order unknowns (edge means = mid-point values of rigid
    motions): piecewise rigid motions (a - w y, b + w x) per triangle, equal at every inner edge's mid point."""
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=maxh))
    rows = []
    for e in mesh.edges:
        els = [el.nr for el in mesh[e].elements]
        if len(els) != 2:
            continue
        m = np.mean([mesh[v].point for v in mesh[e].vertices], axis=0)
        for comp in range(2):
            r = np.zeros(3 * mesh.ne)
            for s, el in zip((1.0, -1.0), els):
                r[3 * el + comp] += s
                r[3 * el + 2] += s * (-m[1] if comp == 0 else m[0])
            rows.append(r)
    sv = np.linalg.svd(np.array(rows), compute_uv=False)
    nullity = 3 * mesh.ne - int(np.sum(sv > 1e-10 * sv[0]))
    assert nullity == expected  # the 3 rigid motions included: 5 and 13 more


def _spectrum(coarse_normal_facet: bool) -> np.ndarray:
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=0.25))
    fes, a = _tdnns(mesh, dirichlet="left")
    if coarse_normal_facet:
        rng = fes.Range(2)
        for d in range(rng.start, rng.stop):
            if fes.CouplingType(d) == ngs.COUPLING_TYPE.INTERFACE_DOF:
                fes.SetCouplingType(d, ngs.COUPLING_TYPE.WIREBASKET_DOF)
    pre = ngs.Preconditioner(a, "bddc")
    a.Assemble()
    A, idx = _dense(fes, a.mat)
    C = np.zeros_like(A)
    v, w = a.mat.CreateColVector(), a.mat.CreateColVector()
    for j, d in enumerate(idx):
        v[:] = 0.0
        v[d] = 1.0
        w.data = pre.mat * v
        C[:, j] = w.FV().NumPy()[idx]
    return np.sort(np.linalg.eigvals(C @ A).real)


def test_element_bddc_spectrum():
    assert np.max(np.abs(_spectrum(False))) > 1e10  # the singular coarse matrix
    ev = _spectrum(True)
    assert ev[0] >= 1.0 - 1e-8 and ev[-1] <= 10.0
