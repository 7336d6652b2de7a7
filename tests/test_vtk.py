"""ParaView output (ngcrack.planar.vtk): the files read back with meshio hold the solution's values.

The body's file is compared, triangle by triangle and vertex by vertex, with the
solution's CoefficientFunctions evaluated at the same points of the same triangle
(NGSolve's MapToAllElements at the reference vertices: the fields of the mixed elements
are discontinuous, so a vertex belongs to each of its triangles separately). The crack
faces' file is compared with the crack profiles and the crack edges. Tolerances are
round-off (1e-12 relative to each field's largest value): the files are double precision.
"""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import ngcrack as nc
from ngcrack.planar.vtk import STATE_CODES, body_fields, save_vtk, write_collection

meshio = pytest.importorskip("meshio")
ngs = pytest.importorskip("ngsolve")

#: relative round-off tolerance of the values read back
RTOL = 1e-12
#: tdnns's rotation is a derivative of its H(curl) displacement of order 2: NGSolve's VTK
#: writer and a direct evaluation at the same points agree to 2e-10 of its largest value
#: (measured), not to round-off
RTOL_DERIVED = {("tdnns", "rotation"): 1e-9}


@pytest.fixture(scope="module")
def solutions():
    """A closed, sliding crack (inclined-compression) on a coarse mesh, for a weakly
    symmetric element (rotation multiplier) and tdnns (rotation from grad u)."""
    scene = nc.scenes.load("inclined-compression")
    return {el: nc.solve(scene, element=el, maxh=4.0) for el in ("bdm", "tdnns")}


def _reference_values(sol, cf) -> tuple[np.ndarray, np.ndarray]:
    """(points (ne, 3, 2), values (ne, 3, ncomp)) of `cf` at every triangle's vertices."""
    ir = ngs.IntegrationRule([(1.0, 0.0), (0.0, 1.0), (0.0, 0.0)], [1.0, 1.0, 1.0])
    mips = sol.mesh.MapToAllElements(ir, ngs.VOL)
    xy = np.asarray(ngs.CF((ngs.x, ngs.y))(mips)).reshape(sol.mesh.ne, 3, 2)
    vals = np.asarray(cf(mips)).reshape(sol.mesh.ne, 3, -1)
    return xy, vals


def _cell_order(sol, grid) -> tuple[np.ndarray, np.ndarray]:
    """(element of each cell, the cells' vertex coordinates (ncell, 3, 2))."""
    tri = grid.cells_dict["triangle"]
    pts = grid.points[tri][:, :, :2]
    cent = sol.crack_mesh.centroids
    elements = np.array([int(np.argmin(np.linalg.norm(cent - c, axis=1))) for c in pts.mean(axis=1)])
    return elements, pts


@pytest.mark.parametrize("element", ["bdm", "tdnns"])
def test_body_fields_read_back_at_every_vertex(solutions, element, tmp_path):
    sol = solutions[element]
    files = save_vtk(sol, tmp_path / "run")
    assert [f.name for f in files] == ["run.vtu", "run_cracks.vtu"]
    grid = meshio.read(files[0])
    fields = body_fields(sol)
    names = {"displacement", "stress", "sigma_xx", "sigma_yy", "sigma_xy", "sigma_nu", "von_mises",
             "rotation", "error_indicator"}
    assert names == set(fields) == set(grid.point_data)
    elements, pts = _cell_order(sol, grid)
    assert sorted(elements) == list(range(sol.mesh.ne))  # one cell per triangle
    tri = grid.cells_dict["triangle"]
    xy_ref = _reference_values(sol, ngs.CF((ngs.x, ngs.y)))[0][elements]
    # the same point of the same triangle: match each cell vertex to its reference vertex
    match = np.argmin(np.linalg.norm(pts[:, :, None, :] - xy_ref[:, None, :, :], axis=3), axis=2)
    assert np.all(np.sort(match, axis=1) == [0, 1, 2])
    for name, cf in fields.items():
        ref = _reference_values(sol, cf)[1][elements]
        ref = np.take_along_axis(ref, match[:, :, None], axis=1)
        got = np.asarray(grid.point_data[name])[tri].reshape(ref.shape)
        scale = max(np.abs(ref).max(), 1e-300)
        assert np.abs(got - ref).max() <= RTOL_DERIVED.get((element, name), RTOL) * scale, name


def test_displacement_and_stress_are_the_solutions(solutions, tmp_path):
    """The written arrays are sol.u and sol.sigma, not some other field: u at a vertex of
    a triangle equals sol.u at that triangle's centroid (P0 for bdm), the stress tensor's
    in-plane block is sol.sigma, sigma_zz follows plane strain."""
    sol = solutions["bdm"]
    grid = meshio.read(save_vtk(sol, tmp_path / "b")[0])
    elements, pts = _cell_order(sol, grid)
    tri = grid.cells_dict["triangle"]
    cent = pts.mean(axis=1)
    u = np.asarray(sol.u(sol.mesh(cent[:, 0], cent[:, 1])))
    disp = grid.point_data["displacement"][tri]  # (ncell, 3, 3)
    scale = np.abs(u).max()
    assert np.abs(disp[:, :, :2] - u[:, None, :]).max() <= 1e-12 * scale
    assert np.all(disp[:, :, 2] == 0.0)
    stress = grid.point_data["stress"].reshape(-1, 3, 3)
    nu = sol.scene.material.nu
    assert np.abs(stress[:, 2, 2] - nu * (stress[:, 0, 0] + stress[:, 1, 1])).max() <= 1e-12 * np.abs(stress).max()
    assert np.all(stress[:, 0, 2] == 0) and np.all(stress[:, 2, 0] == 0)
    # sigma_nu with the crack's normal, and von Mises of the symmetric part
    n = sol.crack_mesh.cracks[0].normal[0]
    s = 0.5 * (stress + np.transpose(stress, (0, 2, 1)))
    snu = np.einsum("i,kij,j->k", n, s[:, :2, :2], n)
    assert np.abs(grid.point_data["sigma_nu"].ravel() - snu).max() <= 1e-12 * np.abs(snu).max()
    dev = s - np.trace(s, axis1=1, axis2=2)[:, None, None] / 3 * np.eye(3)
    vm = np.sqrt(1.5 * np.einsum("kij,kij->k", dev, dev))
    assert np.abs(grid.point_data["von_mises"].ravel() - vm).max() <= 1e-12 * vm.max()
    # the error indicator is eta_T of the estimate, constant per triangle
    eta = grid.point_data["error_indicator"].ravel()[tri]
    assert np.abs(eta - sol.error_estimate.eta[elements][:, None]).max() <= 1e-12 * sol.error_estimate.eta.max()


def test_crack_faces_are_the_crack_profiles(solutions, tmp_path):
    sol = solutions["tdnns"]
    grid = meshio.read(save_vtk(sol, tmp_path / "c")[1])
    lines = grid.cells_dict["line"]
    crack = sol.crack_mesh.cracks[0]
    prof = sol.crack_profiles()[0]
    assert len(lines) == len(crack) == len(prof.s)
    ends = grid.points[lines][:, :, :2]
    assert np.abs(ends[:, 0] - crack.a).max() <= 1e-14 * sol.crack_mesh.diameter
    assert np.abs(ends[:, 1] - crack.b).max() <= 1e-14 * sol.crack_mesh.diameter
    data = {k: v[0] for k, v in grid.cell_data.items()}
    for name, ref in (("opening", prof.normal_jump), ("sliding", prof.tangential_jump),
                      ("normal_traction", prof.normal_stress), ("shear_traction", prof.shear_stress), ("s", prof.s)):
        assert np.array_equal(data[name], ref), name
    assert list(data["state"]) == [STATE_CODES[s] for s in prof.state]
    # a closed crack under compression: it slides everywhere, and presses
    assert set(prof.state) == {"slip"} and data["normal_traction"].max() < 0
    assert np.abs(data["normal"][:, :2] - crack.normal).max() == 0.0
    assert np.all(data["crack"] == 0)


def test_cli_vtk_matches_its_json(tmp_path):
    from ngcrack.shell.cli import main

    out, js = tmp_path / "out" / "open", tmp_path / "r.json"
    assert main(["solve", "tension-open", "--maxh", "0.5", "--vtk", str(out)]) == 2  # a missing folder, as --json
    assert not out.parent.exists()
    out.parent.mkdir()
    assert main(["solve", "tension-open", "--maxh", "0.5", "--json", str(js), "--vtk", str(out)]) == 0
    result = json.loads(js.read_text())
    grid = meshio.read(tmp_path / "out" / "open_cracks.vtu")
    opening = grid.cell_data["opening"][0]
    assert np.allclose(opening, result["cracks"][0]["normal_jump"], rtol=1e-15, atol=0)
    assert opening.min() > 0  # tension: the crack is open everywhere
    assert (tmp_path / "out" / "open.vtu").is_file()


def test_scene_without_crack_writes_the_body_only(tmp_path):
    sol = nc.solve(nc.scenes.load("no-crack"), element="bdm", maxh=0.5)
    files = save_vtk(sol, tmp_path / "plain.vtu")  # the suffix is dropped, then added back
    assert [f.name for f in files] == ["plain.vtu"]
    grid = meshio.read(files[0])
    assert "sigma_nu" not in grid.point_data
    # traction (1, 0) on the right of a clamped unit square: the mean of sigma_xx over the right half is near 1
    assert 0.8 < np.mean(grid.point_data["sigma_xx"]) < 1.2


@pytest.mark.parametrize("path, field", [("", "path"), (".", "path"), ("dir/", "path")])
def test_bad_paths_are_refused_before_any_work(solutions, tmp_path, monkeypatch, path, field):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match=field):
        save_vtk(solutions["bdm"], path)
    with pytest.raises(ValueError, match="subdivision"):
        save_vtk(solutions["bdm"], "ok", subdivision=-1)
    assert list(tmp_path.iterdir()) == []  # nothing written, no temporary folder left


def test_collection_lists_every_part_relative_to_itself(solutions, tmp_path):
    parts = [save_vtk(solutions[el], tmp_path / "runs" / el) for el in ("bdm", "tdnns")]
    pvd = write_collection(parts, [0.0, 0.5], tmp_path / "all")
    assert pvd.name == "all.pvd"
    rows = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    assert [(float(r.get("timestep")), int(r.get("part"))) for r in rows] == [(0.0, 0), (0.0, 1), (0.5, 0), (0.5, 1)]
    for r in rows:
        assert (tmp_path / r.get("file")).is_file() and not Path(r.get("file")).is_absolute()
    with pytest.raises(ValueError, match="times"):
        write_collection(parts, [0.0], tmp_path / "bad")
    with pytest.raises(ValueError, match="times"):
        write_collection(parts, [0.0, math.nan], tmp_path / "bad")
    assert not (tmp_path / "bad.pvd").exists()


def test_series_writes_one_file_per_step_and_their_collection(solutions, tmp_path):
    from ngcrack.planar.vtk import save_series

    sols = [solutions["bdm"], solutions["tdnns"]]
    pvd = save_series(sols, [1, 2.5], tmp_path / "steps" / "run")
    assert pvd == tmp_path / "steps" / "run.pvd"
    rows = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    assert [r.get("file") for r in rows] == ["run_0000.vtu", "run_0000_cracks.vtu", "run_0001.vtu",
                                             "run_0001_cracks.vtu"]
    assert [float(r.get("timestep")) for r in rows] == [1.0, 1.0, 2.5, 2.5]
    # each step's file holds that step's solution
    for k, sol in enumerate(sols):
        grid = meshio.read(tmp_path / "steps" / f"run_{k:04d}_cracks.vtu")
        assert np.array_equal(grid.cell_data["sliding"][0], sol.crack_profiles()[0].tangential_jump)
    with pytest.raises(ValueError, match="times"):
        save_series(sols, [0.0], tmp_path / "bad" / "run")
    assert not (tmp_path / "bad").exists()


def test_a_target_that_is_a_directory_is_named_and_nothing_is_written(solutions, tmp_path):
    (tmp_path / "r_cracks.vtu").mkdir()
    with pytest.raises(nc.InputError, match=r"r_cracks.vtu' is a directory"):
        save_vtk(solutions["bdm"], tmp_path / "r")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r_cracks.vtu"]  # neither file, no temporary folder


def test_a_reused_series_leaves_no_stale_step_file(solutions, tmp_path):
    """A second series on the same path (a shorter run) removes the first one's step files, and only those."""
    from ngcrack.planar.vtk import SeriesWriter

    sol = next(iter(solutions.values()))
    first = SeriesWriter(tmp_path / "run")
    for k in range(3):
        first.add(sol, k)
    for other in ("run_extra.vtu", "other_0001.vtu", "run_0001.txt"):
        (tmp_path / other).write_text("not ours")
    second = SeriesWriter(tmp_path / "run")
    second.add(sol, 0)
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == ["other_0001.vtu", "run.pvd", "run_0000.vtu", "run_0000_cracks.vtu", "run_0001.txt",
                    "run_extra.vtu"]
    rows = ET.parse(second.collection).getroot().find("Collection").findall("DataSet")
    assert [r.get("file") for r in rows] == ["run_0000.vtu", "run_0000_cracks.vtu"]


def test_growth_writes_one_file_per_step_through_its_progress_callback(tmp_path):
    """nc.grow(..., progress=SeriesWriter(path)): one body and one crack file per step, the
    collection listing them at the step numbers, each crack file the crack of its step
    (one more segment per step) with that step's opening."""
    from ngcrack.planar.vtk import SeriesWriter

    writer = SeriesWriter(tmp_path / "growth" / "run")
    scene = nc.scenes.inclined_crack(angle=45, load=1)
    res = nc.grow(scene, da=0.5, steps=1, K_Ic=2.0, criterion="mts", element="bdm", maxh=1.0, frames=False,
                  progress=writer)
    assert writer.times == [0.0, 1.0]
    rows = ET.parse(writer.collection).getroot().find("Collection").findall("DataSet")
    assert [r.get("file") for r in rows] == ["run_0000.vtu", "run_0000_cracks.vtu", "run_0001.vtu", "run_0001_cracks.vtu"]
    grids = [meshio.read(tmp_path / "growth" / f"run_{k:04d}_cracks.vtu") for k in range(2)]
    for k, grid in enumerate(grids):
        opening = np.concatenate([c for c in grid.cell_data["opening"]])
        assert np.array_equal(opening, np.concatenate([p.normal_jump for p in res.profiles[k]]))
    # the grown crack reaches further: its end points lie beyond the first step's
    ext = [np.abs(g.points[:, :2]).max() for g in grids]
    assert ext[1] > ext[0] + 0.4
    assert res.table["grew"].any()


def test_sweep_writes_one_file_pair_per_run_and_their_collection(tmp_path):
    """sweep(vtk=OUT): each run's crack file holds that run's crack profile (its largest
    opening is the row's max_opening to round-off), and OUT.pvd lists every run."""
    out = tmp_path / "runs"
    df = nc.sweep("paper-2", elements=["bdm"], maxh=[0.5, 0.35], vtk=out)
    pvd = ET.parse(str(out) + ".pvd").getroot()
    names = [d.get("file") for d in pvd.iter("DataSet")]
    assert len(names) == 2 * len(df)
    for row in df.itertuples():
        stem = f"runs_paper-2-bdm-h{row.maxh:g}-nu{row.nu:g}"
        assert f"{stem}.vtu" in names and f"{stem}_cracks.vtu" in names
        cracks = meshio.read(tmp_path / f"{stem}_cracks.vtu")
        assert abs(float(np.max(cracks.cell_data["opening"][0])) - row.max_opening) <= 1e-12 * abs(row.max_opening)
