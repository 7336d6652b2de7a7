"""The size guard and the thin-part check (ngcrack.planar.sizing), before any meshing.

- the triangle estimate against netgen's meshes (graded and uniform, several scenes),
  the unknowns per triangle against the solves' counts;
- a request above the ceiling or the memory is refused with a message giving the
  estimate and the override (max_dof=, --max-dof), in solve, sweep and on the command
  line (exit code 2), and nothing is written;
- peers on a part one triangle thick (paper-1 at maxh 0.5: a displacement 30 times too
  large) is refused, naming maxh and the largest safe value; the safe value is safe.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
import warnings
from pathlib import Path

import ngsolve as ngs
import pytest

import ngcrack as nc
from ngcrack import scenes
from ngcrack.planar import sizing
from ngcrack.planar.geometry import make_mesh
from ngcrack.shell.cli import main
from ngcrack.studies.sweeps import sweep

ROOT = Path(__file__).resolve().parents[1]


def report(msg: str) -> None:
    sys.__stdout__.write(f"\n[sizing] {msg}\n")


# ------------------------------------------------------------------ the estimate
#: (scene, mesh options): uniform and graded meshes of 1e3 to 2e4 triangles
MESHES = [
    ("paper-1", dict(maxh=0.05)),
    ("paper-2", dict(maxh=0.1, tip_h=0.005)),
    ("kinked-crack", dict(maxh=0.05)),
    ("two-cracks", dict(maxh=0.05)),
    ("griffith", {}),
    ("griffith", dict(maxh=0.5, tip_h=0.01, crack_h=0.01, grading=0.5)),
    ("inclined-compression", {}),
    ("inclined-compression", dict(maxh=1.0, tip_h=0.001, crack_h=0.02)),
    ("tension-open", dict(maxh=0.05)),
]


def test_triangle_estimate_is_within_its_stated_accuracy():
    ratios = []
    for name, opts in MESHES:
        scene = scenes.load(name)
        actual = len(make_mesh(scene, **opts).triangles)
        est = sizing.estimate_triangles(scene, **opts)
        ratios.append(est / actual)
        assert actual >= 1000
    report("estimate / netgen's triangles: " + ", ".join(f"{r:.2f}" for r in ratios))
    assert 0.78 <= min(ratios) and max(ratios) <= 1.2


def test_unknowns_per_triangle_match_the_solves():
    scene = scenes.load("paper-2")
    for element, order in [("peers", None), ("bdm", None), ("tdnns", None), ("tdnns", 2), ("h1p1", None), ("h1p2", None)]:
        sol = nc.solve(scene, element=element, order=order, maxh=0.1)
        per = sol.ndof["total"] / len(sol.crack_mesh.triangles)
        assert per == pytest.approx(sizing.unknowns_per_triangle(element, order), rel=0.05), element


def test_the_estimate_takes_microseconds():
    scene = scenes.load("griffith")
    t0 = time.perf_counter()
    est = sizing.estimate_size(scene, "bdm", maxh=1e-7)
    report(f"griffith maxh 1e-7: {est.describe()} (estimated in {1e6 * (time.perf_counter() - t0):.0f} us)")
    assert est.triangles == pytest.approx(sizing.TRIANGLES_PER_AREA * 200 / 1e-14, rel=1e-6)


# ------------------------------------------------------------------ the guard
def test_cli_refuses_a_mistyped_maxh_within_seconds(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = tmp_path / "r.json"
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "ngcrack.shell.cli", "solve", "griffith", "--maxh", "1e-7", "--json", str(out)],
                          capture_output=True, text=True, env=env, timeout=300)
    report(f"ngcrack solve griffith --maxh 1e-7: exit {proc.returncode} after {time.perf_counter() - t0:.1f} s "
           f"(process start and imports included)")
    assert proc.returncode == 2
    for part in ("maxh = 1e-07", "triangles", "unknowns", "--max-dof", "max_dof="):
        assert part in proc.stderr, part
    assert not out.exists()


def test_max_dof_refuses_and_admits():
    scene = scenes.load("paper-2")
    with pytest.raises(ValueError, match=r"maxh = 0\.1: .*exceeds max_dof of 1000 unknowns.*--max-dof"):
        nc.solve(scene, element="bdm", maxh=0.1, max_dof=1000)
    sol = nc.solve(scene, element="bdm", maxh=0.1, max_dof=30_000)
    assert sol.ndof["total"] <= 30_000
    for bad in (0, -5, float("nan"), "many", True):
        with pytest.raises(ValueError, match="max_dof"):
            nc.solve(scene, element="bdm", maxh=0.1, max_dof=bad)


def test_memory_is_checked_unless_max_dof_is_given(monkeypatch):
    scene = scenes.load("paper-2")
    monkeypatch.setattr(sizing, "available_memory", lambda: 50e6)
    with pytest.raises(ValueError, match="50 MB available"):
        nc.solve(scene, element="bdm", maxh=0.05)
    est = sizing.check_size(scene, "bdm", maxh=0.05, max_dof=10**6)  # the caller takes the memory on
    assert est.memory > 0.8 * 50e6


def test_sweep_checks_every_case_before_any_run(tmp_path):
    out = tmp_path / "r.csv"
    with pytest.raises(ValueError, match="maxh = 0.001: sweep of 'paper-2', element 'bdm'"):
        sweep("paper-2", elements=["bdm"], maxh=[0.3, 0.001], out=out)
    assert not out.exists()
    with pytest.raises(ValueError, match="exceeds max_dof"):
        sweep("paper-2", elements=["bdm"], maxh=[0.3, 0.2], reference_maxh=0.05, max_dof=10_000, out=out)
    assert not out.exists()
    code = main(["sweep", "paper-2", "--element", "bdm", "--maxh", "0.3", "0.2", "--reference-maxh", "0.05",
                 "--max-dof", "1e4", "--out", str(out), "--no-progress"])
    assert code == 2 and not out.exists()


# ------------------------------------------------------------------ thin parts
def mean_u2(sol) -> float:
    """The mean vertical displacement (exact for P0 displacements: no sampling bias)."""
    return float(ngs.Integrate(sol.u[1], sol.mesh)) / 4.0


@pytest.fixture(scope="module")
def paper1_reference():
    return mean_u2(nc.solve(scenes.load("paper-1"), element="bdm", maxh=0.05))


def test_thinnest_part_of_the_paper_scenes():
    for name in ("paper-1", "paper-2"):
        thin = sizing.thinnest_part(scenes.load(name), maxh=0.5)
        assert thin.width == pytest.approx(0.5) and thin.across == pytest.approx(1.0)
    assert sizing.thinnest_part(scenes.load("no-crack"), maxh=0.1).across == pytest.approx(10.0)
    # an acute corner is not a thin part: a 30-degree wedge meshed at a tenth of its length
    wedge = scenes.load("no-crack").with_(polygon=[[0, 0], [1, 0], [1, 0.577]], labels=["bottom", "right", "left"])
    assert sizing.thinnest_part(wedge, maxh=0.1).across > 2.5
    nc.solve(wedge, element="peers", maxh=0.1)  # not refused


def test_peers_on_one_layer_is_refused_and_the_safe_value_is_safe(paper1_reference):
    scene = scenes.load("paper-1")
    with pytest.raises(ValueError, match=r"maxh = 0\.5: .*one triangle thick.*largest safe maxh here is about") as err:
        nc.solve(scene, element="peers", maxh=0.5)
    assert main(["solve", "paper-1", "--element", "peers", "--maxh", "0.5"]) == 2
    safe = float(str(err.value).split("largest safe maxh here is about ")[1].split(" ")[0])
    with warnings.catch_warnings():
        warnings.simplefilter("error", sizing.CoarseMeshWarning)
        sol = nc.solve(scene, element="peers", maxh=safe)
    ratio = mean_u2(sol) / paper1_reference
    report(f"paper-1 peers: refused at maxh 0.5; at the stated safe maxh {safe:g}: mean u2 {ratio:.3f} x the reference")
    assert 0.8 <= ratio <= 1.2
    # the other elements are stable on that mesh: bdm within 10%
    assert abs(mean_u2(nc.solve(scene, element="bdm", maxh=0.5)) / paper1_reference - 1) <= 0.1


def test_two_layers_of_peers_warn():
    with pytest.warns(sizing.CoarseMeshWarning, match=r"maxh = 0\.3: .*peers is known to be more than 20% off"):
        nc.solve(scenes.load("paper-1"), element="peers", maxh=0.3)
