"""The fast assembly gives the same discrete system as the plain one (issue 14).

The crack terms are assembled on the crack's triangles only, the PEERS bubbles live in a
4-shape cubic element and the condensed matrix is formed in one pass: each is checked
here against the straightforward form (crack indicator in every element boundary, the
full cubic element) to round-off. Also: the sweep's mesh cache and the thread count.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
import pytest
import scipy.sparse as sp

import ngcrack as nc
import ngcrack.scenes as scenes
from ngcrack.core.hybrid import _congruence, _to_scipy, condense
from ngcrack.core.parallel import THREADS_ENV, task_manager, thread_count
from ngcrack.core.solve import scene_loads
from ngcrack.planar.elements import base, bdm, peers
from ngcrack.planar.geometry import crack_frame_cf, make_mesh
from ngcrack.planar.materials import compliance

#: relative agreement of two assemblies of the same form (summation order differs)
ROUND_OFF = 1e-13


def _matrix(a: ngs.BilinearForm) -> sp.csr_matrix:
    return sp.csr_matrix(_to_scipy(a.mat), copy=True)


def _rel(A, B) -> float:
    return float(abs(A - B).max() / abs(B).max())


@pytest.fixture(scope="module")
def griffith():
    sc = scenes.load("griffith")
    return sc, make_mesh(sc, maxh=0.5, crack_h=0.05)


def test_crack_elements_are_the_crack_edges_neighbours(griffith):
    _, cm = griffith
    els = base.crack_elements(cm)
    n_edges = sum(len(c) for c in cm.cracks)
    # an interior crack edge has a triangle on each side; the crack here has no edge on the boundary
    assert els.NumSet() == 2 * n_edges


def test_crack_terms_on_crack_triangles_equal_indicator_everywhere(griffith):
    """The hybrid BDM form with chi in every element boundary equals the localized one."""
    sc, cm = griffith
    mat = sc.material
    C = compliance(mat.E, mat.nu, mat.plane)
    disc = bdm.build(cm, C, scene_loads(sc))
    fes = disc.fes
    (s1, s2, u, r, ux, uy, jn, jt), (q1, q2, v, eta, mx, my, kn, kt) = fes.TnT()
    sig, tau = base.stress_matrix(s1, s2), base.stress_matrix(q1, q2)
    n = ngs.specialcf.normal(2)
    nu, t = crack_frame_cf(cm)
    chi = ngs.IfPos(n * nu - 0.5, 1.0, 0.0)
    a = ngs.BilinearForm(fes, condense=True)
    a += (ngs.InnerProduct(C.apply(sig), tau) + ngs.CF((ngs.div(q1), ngs.div(q2))) * u
          + ngs.CF((ngs.div(s1), ngs.div(s2))) * v + base.skew(tau) * r + base.skew(sig) * eta) * ngs.dx
    a += -((tau * n) * (ngs.CF((ux, uy)) - chi * (jn * nu + jt * t))
           + (sig * n) * (ngs.CF((mx, my)) - chi * (kn * nu + kt * t))) * ngs.dx(
               element_boundary=True, bonus_intorder=base.CRACK_BONUS_INTORDER)
    a.Assemble()
    assert _rel(_matrix(disc.a), _matrix(a)) < ROUND_OFF


def test_peers_bubble_space_is_the_cubic_bubble(griffith):
    """curl(b_T) from the 4-shape element has the same Gram matrix as from the full cubic element."""
    _, cm = griffith
    mesh = cm.mesh
    full = ngs.H1(mesh, order=3)
    interior = ngs.BitArray(full.ndof)
    interior.Clear()
    for el in mesh.Elements(ngs.VOL):
        for d in full.GetDofNrs(ngs.NodeId(ngs.FACE, el.nr)):
            interior[d] = True
    spaces = (ngs.Compress(full, active_dofs=interior), peers.cubic_bubbles(mesh))
    assert spaces[0].ndof == spaces[1].ndof == mesh.ne

    def gram(space):
        b, c = space.TnT()
        a = ngs.BilinearForm(space)
        a += ngs.grad(b) * ngs.grad(c) * ngs.dx
        a.Assemble()
        per_element = [space.GetDofNrs(ngs.NodeId(ngs.FACE, el.nr))[0] for el in mesh.Elements(ngs.VOL)]
        return _to_scipy(a.mat).diagonal()[per_element]

    g_full, g_small = gram(spaces[0]), gram(spaces[1])
    assert np.max(np.abs(g_full - g_small) / g_full) < ROUND_OFF


def test_congruence_equals_sparse_products():
    rng = np.random.default_rng(3)
    n = 40
    A = sp.random(n, n, density=0.3, random_state=4, format="csr")
    A = sp.csr_matrix(A + A.T)
    column = rng.integers(-1, 25, size=n)
    coef = rng.normal(size=n)
    T = sp.csr_matrix((coef[column >= 0], (np.flatnonzero(column >= 0), column[column >= 0])), shape=(n, 25))
    K = _congruence(A, column, coef, 25, -1.0).to_scipy()
    ref = -(T.T @ A @ T)
    assert _rel(K, ref) < ROUND_OFF
    assert K.has_canonical_format


def test_condense_reproduces_the_condensed_form(griffith):
    """K of `condense` is sign T^T A T of NGSolve's condensed matrix (rollers included)."""
    sc, cm = griffith
    from ngcrack.planar import elements

    loads = scene_loads(sc)
    assert loads.roller  # griffith holds its symmetry lines on rollers
    disc = elements.build("bdm", cm, compliance(sc.material.E, sc.material.nu, sc.material.plane), loads)
    system = condense(disc, loads)
    A = _to_scipy(disc.a.mat)
    A_ff = A[system._free][:, system._free]
    ref = disc.sign * (system._T.T @ A_ff @ system._T)
    assert _rel(system.K, ref) < ROUND_OFF


def test_a_sweep_worker_runs_through_one_pipeline_sharing_each_mesh():
    """The runs of a sweep's worker go through its one Pipeline: another element or
    Poisson ratio at the same size meshes nothing, another size meshes once; only the
    mesh is kept between runs (the assembly and the factorization are released)."""
    from ngcrack.studies.sweeps.cases import Case, run_case, worker_pipeline

    sc = scenes.load("paper-1")
    pipeline = worker_pipeline()
    assert worker_pipeline() is pipeline
    before = dict(pipeline.counts)
    setup = {"reference_element": "", "reference_maxh": 0.25, "crack_model": "contact", "qp_solver": "pdas",
             "adapt": False}
    rows = [run_case(Case(sc, el, h, nu, {}, setup=setup))[0] for el, h, nu in
            [("bdm", 0.25, 0.3), ("tdnns", 0.25, 0.3), ("bdm", 0.25, 0.45), ("bdm", 0.3, 0.3)]]
    assert pipeline.counts["mesh"] - before["mesh"] == 2
    assert pipeline.counts["assemble"] - before["assemble"] == 4  # nothing after the mesh is kept
    assert pipeline._disc is None and not pipeline._reductions
    assert rows[0]["n_elements"] == rows[1]["n_elements"] == rows[2]["n_elements"] != rows[3]["n_elements"]
    assert make_mesh(sc, maxh=0.3) is not pipeline.mesh(sc, nc.SolveOptions.of(maxh=0.3))  # outside: a fresh mesh


def test_thread_count(monkeypatch):
    monkeypatch.setenv(THREADS_ENV, "1")
    assert thread_count() == 1
    monkeypatch.delenv(THREADS_ENV)
    monkeypatch.setenv("OMP_NUM_THREADS", "3")
    assert thread_count() == 3
    monkeypatch.setenv("OMP_NUM_THREADS", "x")
    assert thread_count() >= 1
    with task_manager():
        with task_manager():  # re-entrant
            pass
