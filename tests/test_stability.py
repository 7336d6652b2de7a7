"""Stiff and extreme cases: locking, nu -> 1/2, scaling laws, extreme geometry, failure paths."""

from __future__ import annotations

import functools

import ngsolve as ngs
import numpy as np
import pytest

import ngcrack.scenes as scenes
from ngcrack.core.contact import ContactSolverError
from ngcrack.core.solve import SolveError, solve
from ngcrack.planar.elements import MIXED, Loads
from ngcrack.planar.scene import SceneError
from ngcrack.studies import stability

NEAR_HALF = (0.49, 0.4999, 0.49999, 0.5 - 1e-8, 0.5)


@functools.cache
def mms(element: str, nu: float) -> dict:
    return stability.manufactured_errors(element, nu, maxh=0.2)


@pytest.mark.parametrize("element", MIXED)
def test_mixed_elements_are_flat_up_to_one_half(element):
    """Errors for nu in [0.49, 1/2] (1/2 included) stay within 10% of each other."""
    for key in ("error_u", "error_sigma"):
        errs = [mms(element, nu)[key] for nu in NEAR_HALF]
        print(f"{element} {key}: {[f'{e:.4e}' for e in errs]}")
        assert max(errs) <= 1.10 * min(errs)
        assert max(errs) <= 1.25 * mms(element, 0.3)[key]


def test_displacement_baselines_lock():
    """h1p1 locks (error grows by more than 3x from nu = 0.3 to 0.49999), h1p2 degrades (> 2x)."""
    growth = {el: mms(el, 0.49999)["error_u"] / mms(el, 0.3)["error_u"] for el in ("h1p1", "h1p2")}
    print(f"error growth nu 0.3 -> 0.49999: {growth}")
    assert growth["h1p1"] > 3.0
    assert growth["h1p2"] > 2.0
    for el in MIXED:
        assert mms(el, 0.49999)["error_u"] <= 1.25 * mms(el, 0.3)["error_u"]


@pytest.mark.parametrize("element", ["h1p1", "h1p2"])
def test_baselines_refuse_one_half(element):
    with pytest.raises(ValueError, match="material.nu = 0.5"):
        solve(scenes.load("paper-2").with_(nu=0.5), element=element)


@pytest.mark.parametrize("element", ["peers", "bdm"])
def test_griffith_and_paper_2_flat_in_nu(element):
    """Griffith opening error and paper-2 against bdm (h/2): flat as nu -> 1/2, 1/2 included."""
    mesh = dict(maxh=2.0, crack_h=0.1, tip_h=0.01)
    g = [stability.griffith_error(element, nu, **mesh)["error_opening"] for nu in (0.49, 0.4999, 0.5)]
    print(f"griffith {element}: {g}")
    assert max(g) <= 1.10 * min(g)
    p = [stability.paper2_errors(element, nu, 0.2)["error_sigma"] for nu in (0.49, 0.4999, 0.5)]
    print(f"paper-2 {element}: {p}")
    assert max(p) <= 1.10 * min(p)


def test_one_half_equals_the_limit():
    """nu = 1/2 exactly gives the limit of nu -> 1/2 (incompressible split), every mixed element."""
    for element in MIXED:
        a = solve(scenes.load("paper-1").with_(nu=0.5), element=element)
        b = solve(scenes.load("paper-1").with_(nu=0.5 - 1e-9), element=element)
        ja, jb = a.profiles[0].normal_jump, b.profiles[0].normal_jump
        assert np.max(np.abs(ja - jb)) <= 1e-6 * np.max(np.abs(jb))
        assert not a.disc.definite  # the element pressures are global unknowns


def test_one_half_without_traction_edge_is_refused():
    scene = scenes.load("paper-2").with_(nu=0.5)
    held = {lab: scenes.load("paper-2").boundary["left"] for lab in scene.labels}
    with pytest.raises(ValueError, match="pressure is undetermined"):
        solve(scene.with_(boundary=held))


@pytest.fixture(scope="module")
def scale_rows():
    return stability.scale_table()


def test_scaling_laws_hold_to_1e_8(scale_rows):
    """Jumps scale with load * size / E, stresses with load: E 1e-3..1e12, loads 1e-9..1e9, sizes 1e-3..1e3."""
    print(scale_rows[["element", "scaled", "factor", "jump_law_deviation", "stress_law_deviation"]].to_string())
    assert scale_rows["E"].min() <= 1e-3 and scale_rows["E"].max() >= 1e12
    assert scale_rows["diameter"].max() / scale_rows["diameter"].min() >= 1e6 * 0.99
    assert scale_rows["jump_law_deviation"].max() <= 1e-8
    assert scale_rows["stress_law_deviation"].max() <= 1e-8


def test_kkt_and_conditioning_across_scales(scale_rows):
    assert scale_rows["kkt_max_penetration"].max() <= 1e-6
    assert scale_rows["kkt_max_tension"].max() <= 1e-6
    assert scale_rows["qp_kkt"].max() <= 1e-9
    # the Jacobi-scaled condition numbers do not depend on E, load or size
    for _element, g in scale_rows.groupby("element"):
        for col in ("cond_K", "cond_S"):
            assert np.all(np.isfinite(g[col]))
            assert g[col].max() <= 2.0 * g[col].min()  # the estimator is randomized


def test_extreme_geometry():
    """A 1:100 strip (exact uniform stress, crack closed) and a tip graded to 1e-4 maxh."""
    df = stability.extreme_table(elements=("peers", "bdm"))
    print(df.to_string())
    strip = df[df["case"].str.startswith("strip")]
    assert strip["error"].max() <= 1e-8
    assert strip["max_jump"].max() <= 1e-12
    tip = df[df["case"].str.startswith("griffith")]
    assert tip["kkt"].max() <= 1e-6
    assert tip["error"].max() <= 0.05


# ------------------------------------------------------------------------ failure paths


def test_non_finite_data_is_refused():
    scene = scenes.load("no-crack")
    nan_load = Loads(body_force=ngs.CF((float("nan"), 0.0)), clamped=frozenset({"left"}))
    with pytest.raises(SolveError, match="non-finite"):
        solve(scene, loads=nan_load)
    with pytest.raises(SceneError, match="material.E"):
        scene.with_(E=float("inf"))


def test_singular_system_is_refused():
    """Supports that hold nothing: refused before any solve, naming the part not held."""
    with pytest.raises(SceneError, match="held by nothing"):
        solve(scenes.load("paper-2"), loads=Loads(body_force=ngs.CF((1.0, 0.0))))


def test_qp_solver_failure_names_the_solver(monkeypatch):
    """A QP solver returning garbage is caught by the KKT check and named."""
    import ngcrack.core.contact as contact

    def broken(S, b, *args, **kwargs):
        return np.full(len(b), np.nan)

    monkeypatch.setattr(contact, "_pdas", lambda S, b, active=None, **kw: (np.full(len(b), np.nan), 1, True))
    with pytest.raises(ContactSolverError, match="pdas"):
        solve(scenes.load("paper-1"), element="bdm", maxh=0.2, qp_solver="pdas")


def test_quick_report_writes_every_file(tmp_path):
    files = stability.run(quick=True, out=tmp_path)
    for name, path in files.items():
        assert path.exists() and path.stat().st_size > 0, name
    locking = (tmp_path / "locking.csv").read_text()
    assert "h1p1" in locking and "tdnns" in locking
