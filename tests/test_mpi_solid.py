"""A 3D penny solved under `mpiexec -n 3` against the serial 3D solve, and its bad setups.

The scene: a penny crack across a clamped beam bent by a shear load at its free end, so
that the crack's upper half opens and its lower half closes (a mixed active set, found in
several active-set steps). The numbers asserted, against the serial sparse active set on
the same mesh in the same run: K_I, K_II, K_III along the front to 1e-8 of their
largest value, the normal jumps at every constraint point to 1e-8, the same active set,
KKT residuals at the Krylov tolerance; CG with BDDC per rank subdomain within 45 steps per
active set (36 measured) with a coarse problem below 1% of the system (6 unknowns: the
rigid motions of the one face between the two subdomains). Three ranks, because rank 0
holds no elements: at two the one subdomain's local solve is the direct solve. Bad
setups: a mesh too small for the ranks and an element that is not distributed give one
line, no hang.
"""

from __future__ import annotations

import json
import textwrap

import numpy as np
import pytest
from test_mpi import _run, pytestmark  # noqa: F401  (the mpi4py skip)

from ngcrack.scenes.coarse3d import bent_penny

BEAM = bent_penny()

COMPARE = textwrap.dedent('''
    import json, sys
    import numpy as np
    import ngcrack as nc
    from ngcrack.solid.scene import SolidScene
    from ngcrack.solid.solve import solve_solid
    scene = SolidScene.from_dict(json.loads(open(sys.argv[2]).read()))
    order = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    sol = nc.solve(scene, order=order)  # under mpiexec: the distributed 3D solve (None on ranks > 0)
    if sol is not None:
        ser = solve_solid(scene, order=order)  # the serial solve on the same mesh
        K = lambda s: np.array([[f.K_I, f.K_II, f.K_III] for f in s.fronts]).tolist()
        out = dict(K=K(sol), K_serial=K(ser), jumps=sol.normal_jumps().tolist(), jumps_serial=ser.normal_jumps().tolist(),
                   active=sol.contact.active.tolist(), active_serial=ser.contact.active.tolist(), kkt=sol.kkt,
                   info=sol.distributed, record=sol.to_json_dict()["distributed"])
        json.dump(out, open(sys.argv[1], "w"))
''')


@pytest.fixture(scope="module")
def compared(tmp_path_factory):
    d = tmp_path_factory.mktemp("mpi3d")
    (d / "compare.py").write_text(COMPARE)
    (d / "scene.json").write_text(json.dumps(BEAM))
    proc = _run([str(d / "compare.py"), str(d / "out.json"), str(d / "scene.json")], n=3)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads((d / "out.json").read_text())


def test_distributed_3d_penny_equals_serial(compared):
    r = compared
    K, Ks = np.array(r["K"]), np.array(r["K_serial"])
    assert np.max(np.abs(K - Ks)) <= 1e-8 * np.max(np.abs(Ks))
    w, ws = np.array(r["jumps"]), np.array(r["jumps_serial"])
    assert np.max(np.abs(w - ws)) <= 1e-8 * np.max(np.abs(ws))
    assert r["active"] == r["active_serial"]
    # a mixed active set: the bent beam closes the crack's lower half and opens its upper half
    assert 0.3 < np.mean(r["active"]) < 0.7 and r["info"]["active_set_steps"] >= 3
    assert max(r["kkt"].values()) <= 1e-10  # at the Krylov tolerance (1e-12) times the system's condition


def test_distributed_3d_runs_subdomain_bddc_with_a_small_coarse_space(compared):
    info = compared["info"]
    assert info["ranks"] == 3 and info["subdomains"] == 2 and info["preconditioner"].startswith("bddc per rank")
    assert 0 < info["coarse_unknowns"] <= 0.01 * info["global_dofs"]  # the element-wise BDDC's: 84%
    assert max(info["cg_steps"]) <= 45
    assert compared["record"] == info  # the JSON record carries the ranks, steps and memory


def test_3d_mesh_too_small_for_the_ranks_is_one_line(tmp_path):
    """Three ranks for a mesh of a few hundred tetrahedra: rank 0 reports one line, the others leave, no hang."""
    small = dict(BEAM, mesh={"maxh": 8.0, "crack_h": 2.0, "front_h": 1.0})
    path = tmp_path / "small.json"
    path.write_text(json.dumps(small))
    code = textwrap.dedent(f'''
        import json, sys
        from ngcrack.shell.cli import main
        from ngcrack.solid.scene import SolidScene
        text = SolidScene.from_dict(json.load(open({str(path)!r}))).to_toml_string()
        open({str(tmp_path / "small.toml")!r}, "w").write(text)
        sys.exit(main(["solve", {str(tmp_path / "small.toml")!r}]))
    ''')
    script = tmp_path / "small.py"
    script.write_text(code)
    proc = _run([str(script)], n=3)
    assert proc.returncode != 0
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "fewer than 500 per worker rank" in lines[0], proc.stderr


def test_3d_displacement_element_is_one_line():
    """h1p1 in 3D is not distributed: refused alike on every rank before meshing, one line from rank 0."""
    proc = _run(["-m", "ngcrack.shell.cli", "solve", "penny", "--element", "h1p1"])
    assert proc.returncode != 0
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "element = 'h1p1': a distributed 3D solve takes element = 'tdnns'" in lines[0], \
        proc.stderr


@pytest.mark.slow
def test_two_ranks_one_subdomain_equal_serial(tmp_path):
    """mpiexec -n 2: one subdomain (rank 0 holds none), its local solve exact: CG in one step, the same answer."""
    (tmp_path / "compare.py").write_text(COMPARE)
    (tmp_path / "scene.json").write_text(json.dumps(BEAM))
    proc = _run([str(tmp_path / "compare.py"), str(tmp_path / "out.json"), str(tmp_path / "scene.json")], n=2)
    assert proc.returncode == 0, proc.stderr[-2000:]
    r = json.loads((tmp_path / "out.json").read_text())
    assert r["info"]["subdomains"] == 1 and r["info"]["coarse_unknowns"] == 0 and max(r["info"]["cg_steps"]) <= 2
    test_distributed_3d_penny_equals_serial(r)


@pytest.mark.slow
def test_cli_writes_the_3d_json_once(tmp_path):
    """`mpiexec -n 2 ngcrack solve scene.toml --json out.json`: rank 0 alone writes and prints; the serial K."""
    from ngcrack.solid.scene import SolidScene
    from ngcrack.solid.solve import solve_solid

    scene = SolidScene.from_dict(BEAM)
    path, out = tmp_path / "bent.toml", tmp_path / "bent.json"
    path.write_text(scene.to_toml_string())
    proc = _run(["-m", "ngcrack.shell.cli", "solve", str(path), "--json", str(out)])
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.count("wrote ") == 1 and proc.stdout.count("(3D)") == 1
    record = json.loads(out.read_text())
    assert record["distributed"]["ranks"] == 2
    front = record["fronts"][0]
    serial = solve_solid(scene).fronts[0]
    K = np.array([front["K_I"], front["K_II"], front["K_III"]])
    Ks = np.array([serial.K_I, serial.K_II, serial.K_III])
    assert np.max(np.abs(K - Ks)) <= 1e-8 * np.max(np.abs(Ks))


@pytest.mark.slow
def test_order_2_with_a_crack_face_pressure_equals_serial(tmp_path):
    """Order 2 (6 Bernstein constraints per face) and a uniform pressure on the crack's faces, mpiexec -n 3: the
    serial answer, CG within 45 steps per active set (the element-wise BDDC took 62-94 at order 2)."""
    beam = json.loads(json.dumps(BEAM))
    beam["crack"][0]["pressure"] = 0.5
    (tmp_path / "compare.py").write_text(COMPARE)
    (tmp_path / "scene.json").write_text(json.dumps(beam))
    proc = _run([str(tmp_path / "compare.py"), str(tmp_path / "out.json"), str(tmp_path / "scene.json"), "2"], n=3)
    assert proc.returncode == 0, proc.stderr[-2000:]
    r = json.loads((tmp_path / "out.json").read_text())
    assert len(r["active"]) % 6 == 0  # six constraint points per crack face
    assert max(r["info"]["cg_steps"]) <= 45
    test_distributed_3d_penny_equals_serial(r)


@pytest.mark.slow
def test_four_ranks_three_subdomains_with_primal_edges_equal_serial(tmp_path):
    """mpiexec -n 4: three subdomains, whose shared edges' unknowns are coarse unknowns of their own; the serial
    answer, CG within 60 steps per active set, the coarse problem still below 2% of the system (the beam meshed
    with maxh 0.7: 500 tetrahedra per worker at least)."""
    (tmp_path / "compare.py").write_text(COMPARE)
    (tmp_path / "scene.json").write_text(json.dumps(dict(BEAM, mesh={"maxh": 0.7, "crack_h": 0.8, "front_h": 0.5})))
    proc = _run([str(tmp_path / "compare.py"), str(tmp_path / "out.json"), str(tmp_path / "scene.json")], n=4)
    assert proc.returncode == 0, proc.stderr[-2000:]
    r = json.loads((tmp_path / "out.json").read_text())
    info = r["info"]
    assert info["subdomains"] == 3 and info["preconditioner"].startswith("bddc per rank")
    assert 6 < info["coarse_unknowns"] <= 0.02 * info["global_dofs"] and max(info["cg_steps"]) <= 60
    test_distributed_3d_penny_equals_serial(r)


def test_3d_prescribed_displacement_above_three_ranks_is_refused():
    """NGSolve's interpolation of a prescribed displacement sums through its own exchange, wrong from 3 subdomains
    on with MPICH: refused by name above 3 ranks, before any mesh; clamped faces and 2-3 ranks pass."""
    from ngcrack.core.errors import InputError
    from ngcrack.distributed.solid import check_supported
    from ngcrack.solid.scene import SolidScene

    opts = {"element": "tdnns"}
    clamped = SolidScene.from_dict(bent_penny())
    moved = bent_penny()
    moved["boundary"]["xmin"] = {"type": "displacement", "value": [0.0, 0.0, 0.01]}
    moved = SolidScene.from_dict(moved)
    for size in (2, 3, 4, 6):
        check_supported(clamped, opts, size)
    for size in (2, 3):
        check_supported(moved, opts, size)
    for size in (4, 6):
        with pytest.raises(InputError, match=r"boundary\['xmin'\]\.type = 'displacement'.* at most 3 ranks"):
            check_supported(moved, opts, size)
