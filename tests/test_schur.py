"""The Schur complement on the crack unknowns and the sparse direct solvers (schur.py).

What is checked, and against what:
- every way of forming S (partial factorization with pardiso and superlu, blocked
  multi-RHS solves with every backend) matches the column-by-column reference to 1e-10,
  and so do b, x0 and the recovered unknowns, on the paper's scenes;
- the saddle-point systems of the incompressible split take the blocked path;
- the factorizations solve a system to round-off, and a singular one is refused;
- "auto" picks pardiso where MKL loads and superlu where it does not;
- bad options are refused with a message that names the allowed values.

Run with `-s` to see the measured numbers (lines starting with "[schur]").
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
import scipy.sparse as sp

import ngcrack.scenes as scenes
from ngcrack.core import schur as schur_mod
from ngcrack.core.hybrid import condense, reduce_to_contact
from ngcrack.core.schur import Factorization, LinearSolverError, schur_complement
from ngcrack.core.solve import scene_loads
from ngcrack.planar import elements as _elements
from ngcrack.planar.geometry import make_mesh
from ngcrack.planar.materials import compliance

#: S, b, x0 of every path agree with the column-by-column reference to this (relative)
MATCH_RTOL = 1e-10
#: normwise backward error of a direct solve (PARDISO without refinement reaches 1e-13)
BACKWARD_TOL = 1e-11
PATHS = [("pardiso", "factor"), ("pardiso", "blocked"), ("superlu", "factor"), ("superlu", "blocked"),
         ("cholespy", "blocked"), ("ngsolve", "blocked")]
needs_mkl = pytest.mark.skipif(not schur_mod.mkl_available(), reason="MKL (the mkl package) is not installed")


def report(*args):
    print("[schur]", *args)


@functools.cache
def system(scene: str, element: str, maxh: float = 0.1, nu: float | None = None):
    sc = scenes.load(scene)
    if nu is not None:
        sc = sc.with_(nu=nu)
    loads = scene_loads(sc)
    cm = make_mesh(sc, maxh=maxh)
    mat = sc.material
    disc = _elements.build(element, cm, compliance(mat.E, mat.nu, mat.plane), loads)
    return condense(disc, loads)


@functools.cache
def reference(scene: str, element: str):
    sysm = system(scene, element)
    return schur_complement(sysm.K, sysm.F, sysm.rest, sysm.contact, linear_solver="superlu", method="columns")


def backward_error(K, x, f) -> float:
    """max |K x - f| / max (|K| |x| + |f|): the solve's own round-off, free of cancellation."""
    return float(np.abs(K @ x - f).max() / (abs(K) @ np.abs(x) + np.abs(f)).max())


def rel(a, b):
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


@pytest.mark.parametrize("scene", ["paper-1", "paper-2"])
@pytest.mark.parametrize("element", ["peers", "bdm"])
@pytest.mark.parametrize("solver, method", PATHS, ids=[f"{a}-{b}" for a, b in PATHS])
def test_schur_paths_match_columns(scene, element, solver, method):
    if solver == "pardiso" and not schur_mod.mkl_available():
        pytest.skip("MKL is not installed")
    sysm = system(scene, element)
    ref = reference(scene, element)
    got = schur_complement(sysm.K, sysm.F, sysm.rest, sysm.contact, linear_solver=solver, method=method)
    # b = F_c - K_cr x0 cancels (a closed crack has a small b): measure it on the scale of its terms
    b_scale = (abs(sysm.K[sysm.contact][:, sysm.rest]) @ np.abs(ref.x0)).max()
    K_rr = sysm.K[sysm.rest][:, sysm.rest]
    errs = {"S": rel(got.S, ref.S), "b": float(np.abs(got.b - ref.b).max() / b_scale),
            "x0 residual": backward_error(K_rr, got.x0, sysm.F[sysm.rest])}
    report(f"{scene} {element} {solver}/{method} (m={len(sysm.contact)}): {errs}")
    assert got.method == method
    assert max(errs["S"], errs["b"]) <= MATCH_RTOL
    assert errs["x0 residual"] <= BACKWARD_TOL
    assert np.array_equal(got.S, got.S.T)
    m = len(sysm.contact)
    if method == "factor":
        assert got.largest_dense == m * m  # no dense matrix larger than m x m
    # the factorization solves with K_rr (as the recovery needs)
    rhs = sysm.K[sysm.rest][:, sysm.contact] @ np.linspace(1.0, 2.0, m)
    assert backward_error(K_rr, got.factorization.solve(rhs), rhs) <= BACKWARD_TOL


@needs_mkl
@pytest.mark.parametrize("element", ["peers", "bdm"])
def test_recovery_matches_reference(element):
    sysm = system("paper-1", element)
    jn = np.abs(np.sin(np.arange(len(sysm.contact))))  # some jumps
    ref = reduce_to_contact(sysm, linear_solver="superlu", schur="columns").recover(jn)
    got = reduce_to_contact(sysm, linear_solver="pardiso", schur="factor")
    assert got.method == "factor" and got.factorization.backend == "pardiso"
    assert rel(got.recover(jn), ref) <= MATCH_RTOL
    # an empty jn means jn = 0 (bonded): the rest is x0
    y0 = got.recover(np.zeros(0))
    assert np.array_equal(y0[sysm.rest], got.x0) and not np.any(y0[sysm.contact])


def test_bonded_reduction_has_no_schur():
    sysm = system("paper-2", "peers")
    red = reduce_to_contact(sysm, schur=False)
    assert red.S.shape == (0, 0) and red.b.shape == (0,) and red.method == "none"
    assert red.recover(np.zeros(0)).shape == (sysm.n,)


def test_saddle_point_takes_blocked_path():
    """nu = 1/2: the element pressures stay global and K is indefinite; S by pivoting LU."""
    sysm = system("paper-2", "bdm", maxh=0.2, nu=0.5)
    assert not sysm.disc.definite
    ref = schur_complement(sysm.K, sysm.F, sysm.rest, sysm.contact, linear_solver="superlu", method="columns",
                           definite=False)
    for solver in ("superlu",) + (("pardiso",) if schur_mod.mkl_available() else ()):
        got = schur_complement(sysm.K, sysm.F, sysm.rest, sysm.contact, linear_solver=solver, method="auto",
                               definite=False)
        assert got.method == "blocked"
        errs = (rel(got.S, ref.S), rel(got.b, ref.b))
        report(f"paper-2 bdm nu=0.5 {solver}/blocked: S, b rel diff {errs}")
        # b sits at the round-off level of this nearly singular saddle point: K perturbed by
        # one ulp per entry moves pardiso's b against superlu's by 5e-9 to 6e-8
        assert max(errs) <= 1e-7
    with pytest.warns(UserWarning, match="positive definite"):
        got = schur_complement(sysm.K, sysm.F, sysm.rest, sysm.contact, linear_solver="superlu", method="factor",
                               definite=False)
    assert got.method == "blocked"


def _laplacian(n: int) -> sp.csr_matrix:
    main = 2.0 * np.ones(n)
    off = -np.ones(n - 1)
    return sp.diags([off, main, off], [-1, 0, 1], format="csr")


@pytest.mark.parametrize("backend", ["superlu", "cholespy", "ngsolve", "pardiso"])
def test_factorization_solves(backend):
    if backend == "pardiso" and not schur_mod.mkl_available():
        pytest.skip("MKL is not installed")
    K = _laplacian(200) + sp.eye(200) * 1e-3
    b = np.cos(np.arange(200.0))
    B = np.column_stack([b, 2 * b, np.ones(200)])
    fac = Factorization(K, backend=backend)
    assert rel(K @ fac.solve(b), b) <= 1e-12
    assert rel(K @ fac.solve(B), B) <= 1e-12


@needs_mkl
def test_pardiso_refuses_a_singular_matrix():
    K = sp.csr_matrix(np.array([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 1.0]]))
    with pytest.raises(LinearSolverError, match="PARDISO"):
        Factorization(K, backend="pardiso").solve(np.ones(3))


def test_auto_follows_mkl(monkeypatch):
    monkeypatch.setattr(schur_mod, "_mkl", lambda: None)
    assert schur_mod.default_linear_solver() == "superlu"
    assert schur_mod.resolve_method("auto", "auto", True) == ("superlu", "factor")
    assert schur_mod.resolve_method("auto", "cholespy", True) == ("cholespy", "blocked")
    with pytest.raises(LinearSolverError, match="mkl"):
        Factorization(_laplacian(5), backend="pardiso")


@pytest.mark.parametrize("kwargs, fragments", [
    (dict(linear_solver="lu"), ("linear_solver", "pardiso", "superlu", "cholespy")),
    (dict(method="exact"), ("schur", "factor", "blocked", "columns")),
    (dict(linear_solver="cholespy", method="factor"), ("factor", "pardiso", "superlu")),
])
def test_bad_options(kwargs, fragments):
    sysm = system("paper-2", "peers")
    with pytest.raises(ValueError) as info:
        schur_complement(sysm.K, sysm.F, sysm.rest, sysm.contact, **kwargs)
    for frag in fragments:
        assert frag in str(info.value)
