"""The distributed solve under `mpiexec -n 2` against the serial one, and its bad setups.

Each test starts mpiexec in a subprocess. The numbers asserted: with CG preconditioned by
BDDC, the stress intensity factors and crack profiles equal the serial direct solve's to
1e-8 (relative; griffith, inclined-compression, and inclined-compression with Coulomb
friction slipping and sticking), the same open/stick/slip states, the
same active set, KKT residuals at round-off; a failing rank stops the others (no hang);
MPI missing and a mesh too small for the ranks give one line.
"""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
import textwrap

import numpy as np
import pytest

pytestmark = pytest.mark.skipif(importlib.util.find_spec("mpi4py") is None,
                                reason="mpi4py is not installed (pip install 'ngcrack[mpi]')")

#: wall-clock limit of one mpiexec run: a hang fails the test instead of stalling the suite
LIMIT_S = 240


def _mpiexec() -> str:
    exe = shutil.which("mpiexec") or os.path.join(os.path.dirname(sys.executable), "mpiexec")
    if not os.path.exists(exe):
        pytest.skip("mpiexec is not on the PATH (the mpich wheel of the [mpi] extra provides it)")
    return exe


def _env() -> dict:
    env = dict(os.environ, OMP_NUM_THREADS="1")
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _run(args: list[str], n: int = 2, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([_mpiexec(), "-n", str(n), sys.executable, *args], env=_env(), capture_output=True,
                          text=True, timeout=LIMIT_S, **kw)


COMPARE = textwrap.dedent('''
    import json, sys
    import numpy as np
    import ngcrack as nc
    out = {}
    cases = {"griffith": nc.scenes.load("griffith"), "inclined-compression": nc.scenes.load("inclined-compression")}
    # Coulomb friction: every closed point slips (mu 0.3) or sticks (mu 0.7 > tan 30 deg)
    cases.update({f"friction-{mu}": nc.scenes.load("inclined-compression").with_(friction=mu) for mu in (0.3, 0.7)})
    cases["open-friction"] = nc.scenes.load("griffith").with_(friction=0.3)  # friction on a crack that opens
    options = {"peers": nc.SolveOptions(element="peers")}  # rollers on facet unknowns, the direct preconditioner
    cases["peers"] = cases["inclined-compression"]
    # a prescribed displacement (interpolated on rank 0's serial mesh and sent to the ranks)
    from ngcrack.planar.scene.types import BoundaryCondition
    g = cases["griffith"]
    cases["displacement"] = g.with_(boundary=dict(g.boundary, top=BoundaryCondition(type="displacement",
                                                                                     value=(0.002, 0.01))))
    for name in sys.argv[2:]:
        scene, o = cases[name], options.get(name, nc.SolveOptions())
        sol = nc.solve(scene, options=o)  # the user's path, several solves in one process
        if sol is None:
            continue
        ser = nc.Pipeline().run(scene, o)  # the serial direct path
        K = [[t.K_I, t.K_II] for t in sol.tips]
        Ks = [[t.K_I, t.K_II] for t in ser.tips]
        jump = lambda s: np.concatenate([np.r_[p.normal_jump, p.tangential_jump] for p in s.profiles])
        scale = float(np.max(np.abs(jump(ser)))) or 1.0
        states = lambda s: [str(x) for x in (s.qp.point_states() if hasattr(s.qp, "point_states") else [])]
        out[name] = dict(K=K, K_serial=Ks, profile_error=float(np.max(np.abs(jump(sol) - jump(ser)))) / scale,
                         active=[int(i) for i in sol.qp.active], active_serial=[int(i) for i in ser.qp.active],
                         states=states(sol), states_serial=states(ser), kkt=sol.kkt, kkt_serial=ser.kkt,
                         info=sol.options["distributed"])
    if out:
        json.dump(out, open(sys.argv[1], "w"))
''')


def _compare(d, names: list[str]) -> dict:
    script, out = d / "compare.py", d / "out.json"
    script.write_text(COMPARE)
    proc = _run([str(script), str(out), *names])
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(out.read_text())


@pytest.fixture(scope="module")
def compared(tmp_path_factory):
    return _compare(tmp_path_factory.mktemp("mpi"), ["griffith", "inclined-compression", "friction-0.3", "peers",
                                                      "displacement", "open-friction"])


@pytest.mark.parametrize("name", ["griffith", "inclined-compression", "friction-0.3", "peers", "displacement",
                                  "open-friction"])
def test_distributed_equals_serial(compared, name):
    _equals_serial(compared, name)


@pytest.mark.parametrize("name", ["friction-0.3", "open-friction"])
def test_friction_kkt_is_the_serial_one(compared, name):
    """The Coulomb law's residual of the distributed answer, computed as the serial one (no contact force off the
    contact set): within 1e-8 of the serial residual, on slipping faces and on an open crack with friction (where
    the Krylov solve's round-off off the contact set once set the force scale: 1.13)."""
    r = compared[name]
    assert abs(r["kkt"]["friction"] - r["kkt_serial"]["friction"]) <= 1e-8
    assert r["kkt_serial"]["friction"] <= 1e-12


@pytest.mark.slow
def test_friction_sticks(tmp_path, compared):
    """mu 0.7 (> tan 30 deg, the crack's inclination): every point sticks, K about 0, as in the serial solve."""
    r = _compare(tmp_path, ["friction-0.7"])
    r["inclined-compression"] = compared["inclined-compression"]
    _equals_serial(r, "friction-0.7")
    assert set(r["friction-0.7"]["states"]) == {"stick"}


@pytest.mark.slow
def test_four_ranks_with_bddc(tmp_path):
    """mpiexec -n 4 (three subdomains: a rank with two neighbours, where NGSolve's own exchange fails with MPICH,
    distributed/exchange.py): BDDC per rank subdomain gives the serial answer, open and closed crack, Coulomb
    friction and a prescribed displacement, each CG solve under 40 steps to 1e-12."""
    script, out = tmp_path / "compare.py", tmp_path / "out.json"
    script.write_text(COMPARE)
    names = ["griffith", "inclined-compression", "friction-0.3", "displacement"]
    proc = _run([str(script), str(out), *names], n=4)
    assert proc.returncode == 0, proc.stderr[-2000:]
    r = json.loads(out.read_text())
    for name in names:
        _equals_serial(r, name, ranks=4)
        assert "coarse unknowns" in r[name]["info"]["preconditioner"]
        assert max(r[name]["info"]["cg_steps"]) <= 40


def _equals_serial(compared, name, ranks: int = 2):
    r = compared[name]
    K, Ks = np.array(r["K"]), np.array(r["K_serial"])
    # relative to the frictionless closed crack's |K| where friction holds every point (K about 0)
    K_scale = max(np.max(np.abs(Ks)), np.max(np.abs(compared["inclined-compression"]["K_serial"])))
    assert np.max(np.abs(K - Ks)) <= 1e-8 * K_scale
    assert r["profile_error"] <= 1e-8
    assert r["active"] == r["active_serial"]
    assert r["states"] == r["states_serial"]  # open / stick / slip at every constraint point
    kkt = dict(r["kkt"])
    assert kkt.pop("friction") <= 1e-9  # the Coulomb law: to the Krylov tolerance
    assert max(kkt.values()) <= 1e-12
    assert r["info"]["ranks"] == ranks
    # the Krylov solves are preconditioned by BDDC (tdnns), peers keeps the direct preconditioner
    assert r["info"]["preconditioner"].startswith("direct" if name == "peers" else "bddc")


def test_friction_slips(compared):
    """mu 0.3 (< tan 30 deg): every closed point slips, found by the fixed point on mu lam_n."""
    assert set(compared["friction-0.3"]["states"]) == {"slip"}
    assert compared["friction-0.3"]["info"]["active_set_steps"] >= 3  # the fixed point on mu lam_n


def test_bddc_steps(compared):
    """BDDC per rank subdomain at -n 2 (one subdomain: its local solve is exact): CG to 1e-12 in at most 2 steps
    on the open crack, no coarse problem; the closed crack's second active set (110 values held at zero by the
    projection) needs more, still bounded."""
    assert compared["griffith"]["info"]["cg_steps"][0] <= 2
    assert "(0 coarse unknowns)" in compared["griffith"]["info"]["preconditioner"]
    # the held values are constraints of the local solve too: still exact, 2 steps (76 with the projection alone)
    assert max(compared["inclined-compression"]["info"]["cg_steps"]) <= 3
    assert max(compared["friction-0.3"]["info"]["cg_steps"]) <= 3


THREE = textwrap.dedent('''
    import json, sys
    from mpi4py import MPI
    import ngcrack as nc
    from ngcrack.planar import elements
    from ngcrack.distributed import solve as distributed_solve
    from ngcrack.distributed.bddc import unconstrained_steps
    from ngcrack.distributed.mesh import distribute
    from ngcrack.planar.materials import compliance
    from ngcrack.core.pipeline import ParameterLoads, Pipeline
    comm = MPI.COMM_WORLD
    scene = nc.scenes.load("griffith")
    o = nc.SolveOptions(maxh=2 * scene.maxh, tip_h=2 * scene.tip_h, crack_h=2 * scene.crack_h)  # about 2.6k unknowns
    out = {}
    for kind in ("subdomains", "bddc"):
        serial = Pipeline().mesh(scene, o) if comm.rank == 0 else None
        cmesh = distribute(serial, scene, comm)
        mat = scene.material
        disc = elements.build("tdnns", cmesh, compliance(mat.E, mat.nu, mat.plane), ParameterLoads(scene).loads)
        out[kind] = unconstrained_steps(disc, kind, comm=comm)
    closed = nc.scenes.load("inclined-compression")
    o = nc.SolveOptions(maxh=2 * closed.maxh, tip_h=2 * closed.tip_h, crack_h=2 * closed.crack_h)
    sol = distributed_solve(closed, o)
    if comm.rank == 0:
        ser = nc.Pipeline().run(closed, o)
        out["closed"] = dict(info=sol.options["distributed"], K=[[t.K_I, t.K_II] for t in sol.tips],
                             K_serial=[[t.K_I, t.K_II] for t in ser.tips], active=len(sol.qp.active),
                             active_serial=len(ser.qp.active))
        json.dump(out, open(sys.argv[1], "w"))
''')


def test_subdomain_bddc_two_subdomains(tmp_path):
    """-n 3 (two subdomains): BDDC per rank subdomain has 3 or 6 coarse unknowns (the rigid motions' averages over
    the face, split where the crack cuts a rank's part) where NGSolve's element-wise BDDC, in the same run, has three quarters of the system; it needs
    fewer CG steps than the element-wise one and its answer equals the direct solve's; the closed crack's
    distributed solve equals the serial one."""
    script, out = tmp_path / "three.py", tmp_path / "three.json"
    script.write_text(THREE)
    proc = _run([str(script), str(out)], n=3)
    assert proc.returncode == 0, proc.stderr[-2000:]
    r = json.loads(out.read_text())
    sub, el = r["subdomains"], r["bddc"]
    # 3 per face between the two ranks; a face is split where the crack cuts a rank's part in two pieces
    assert sub["coarse"] in (3, 6)
    assert el["coarse"] >= 0.7 * el["unknowns"]
    assert sub["steps"][1] <= el["steps"][1] <= 30  # to 1e-8
    assert sub["difference"] <= 1e-7 and el["difference"] <= 1e-7
    # the closed crack: its held values are constraints of the local solves, each active set under 30 CG steps
    closed = r["closed"]
    assert closed["info"]["active_set_steps"] >= 2 and max(closed["info"]["cg_steps"]) <= 30
    assert closed["active"] == closed["active_serial"] > 0
    K, Ks = np.array(closed["K"]), np.array(closed["K_serial"])
    assert np.max(np.abs(K - Ks)) <= 1e-8 * np.max(np.abs(Ks))


def test_closed_crack_needs_an_active_set(compared):
    """inclined-compression closes: the active set is every constraint point, found in a few steps."""
    r = compared["inclined-compression"]
    assert len(r["active"]) > 0 and r["info"]["active_set_steps"] >= 2
    assert compared["griffith"]["active"] == []


def test_cli_writes_json_once(tmp_path):
    out = tmp_path / "g.json"
    proc = _run(["-m", "ngcrack.shell.cli", "solve", "griffith", "--json", str(out)])
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.count("wrote ") == 1  # rank 0 alone prints and writes
    result = json.loads(out.read_text())
    assert result["tips"][0]["K_I"] == pytest.approx(1.7893434723332, rel=1e-8)  # the serial solve's value
    # the JSON and the printed summary say how the solve ran: 2 ranks, 1 subdomain, the CG steps
    dist = result["distributed"]
    assert (dist["ranks"], dist["subdomains"], dist["active_set_steps"]) == (2, 1, 1)
    assert len(dist["cg_steps"]) == 1 and 1 <= dist["cg_steps"][0] <= 3  # one subdomain: its local solve is exact
    assert f"distributed over 2 ranks (1 subdomains), preconditioner bddc per rank subdomain: 1 active-set steps, " \
           f"{dist['cg_steps'][0]} CG steps" in proc.stdout


FAIL = textwrap.dedent('''
    from mpi4py import MPI
    import ngcrack.distributed.planar as ds
    if MPI.COMM_WORLD.rank == 1:
        def broken(*args, **kw):
            raise RuntimeError("injected failure")
        ds.local_constraint_maps = broken
    ds.solve("griffith")
''')


def test_failing_rank_stops_all(tmp_path):
    script = tmp_path / "fail.py"
    script.write_text(FAIL)
    proc = _run([str(script)])  # a hang would exceed LIMIT_S
    assert proc.returncode != 0
    assert "failed on rank 1: RuntimeError: injected failure" in proc.stderr


def test_mesh_too_small_for_the_ranks():
    from ngcrack.distributed.mesh import MIN_ELEMENTS_PER_RANK, TooFewElements, check_ranks

    check_ranks(MIN_ELEMENTS_PER_RANK, 2)
    with pytest.raises(TooFewElements, match="fewer than 50 per worker rank"):
        check_ranks(3 * MIN_ELEMENTS_PER_RANK - 1, 4)


def test_mpi_missing_is_one_line():
    code = ("import sys; sys.modules['mpi4py'] = None; from ngcrack.shell.cli import main; "
            "sys.exit(main(['solve', 'griffith']))")
    proc = subprocess.run([sys.executable, "-c", code], env=dict(_env(), PMI_SIZE="2"), capture_output=True,
                          text=True, timeout=LIMIT_S)
    assert proc.returncode != 0
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "ngcrack[mpi]" in lines[0], proc.stderr


def test_unsupported_element_is_one_line():
    """A displacement element is refused alike on every rank: one line from rank 0, no abort."""
    proc = _run(["-m", "ngcrack.shell.cli", "solve", "griffith", "--element", "h1p1"])
    assert proc.returncode != 0
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "'h1p1' is not distributed" in lines[0], proc.stderr


@pytest.mark.parametrize("args", [["griffith", "--maxh", "-1"], ["penny", "--maxh", "-1"],
                                  ["griffith", "--order", "abc"]])
def test_bad_option_is_one_line(args, tmp_path):
    """An option every rank refuses alike (the checks, the parser): one line from rank 0, exit 2, nothing written."""
    out = tmp_path / "out.json"
    proc = _run(["-m", "ngcrack.shell.cli", "solve", *args, "--json", str(out)])
    assert proc.returncode == 2
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and ("maxh" in lines[0] or "--order" in lines[0]), proc.stderr
    assert not out.exists()
