"""SIGTERM and SIGINT at each stage of a 3D solve, a hydrofrac and an mpiexec run: a quick exit, old outputs kept.

Each case runs the `ngcrack` command in a child process whose stage function (meshing,
assembly, condensation, the crack problem, the fronts' K, the estimate, the writing of
the outputs) first leaves a marker file and then waits: the test sends the signal while
the command is in that stage, as a user's Ctrl-C or a batch system's SIGTERM would come.
The pause only makes the stage long enough to be hit; the function itself is unchanged.
What must hold (against the files written before the run, the "old outputs"):

- the exit code is 128 + the signal's number and stderr is one line (under mpiexec: one
  line in all, from rank 0) saying what was written;
- the process ends within EXIT_WITHIN_S of the signal (the pause would last PAUSE_S);
- the old outputs are intact byte for byte and no temporary file is left, unless the
  signal came while the new outputs were being moved into place: then every output is
  the new run's, whole (a JSON that parses, the VTK files of the same run), and the line
  says they were written.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

LINUX = sys.platform.startswith("linux")
pytestmark = pytest.mark.skipif(not LINUX, reason="POSIX signals")

#: how long a paused stage would wait; the run must end long before that
PAUSE_S = 60.0
#: the pause while the outputs are renamed into place (a real rename takes microseconds; a signal then waits for it)
COMMIT_PAUSE_S = 2.0
#: the exit must come within this many seconds of the signal (the watcher's grace is 1 s; a loaded machine adds some)
EXIT_WITHIN_S = 10.0
#: how long a child may take to reach its stage
REACH_S = 240.0

#: a small 3D scene (about 3 s): a penny in a block clamped below, pulled above
SMALL_3D = textwrap.dedent("""
    name = "small-penny"
    [domain]
    box = [[-2.0, -2.0, -2.0], [2.0, 2.0, 2.0]]
    [[crack]]
    shape = "disc"
    center = [0.0, 0.0, 0.0]
    normal = [0.0, 0.0, 1.0]
    radius = 1.0
    [material]
    E = 1000.0
    nu = 0.3
    [boundary.zmin]
    type = "clamped"
    [boundary.zmax]
    type = "traction"
    value = [0.0, 0.0, 1.0]
    [mesh]
    maxh = 1.0
    front_h = 0.4
""")

#: the child: pause in one stage (on rank 0), then run the command as `ngcrack` does
CHILD = textwrap.dedent('''
    import functools, importlib, os, sys, time
    from pathlib import Path

    stage, marker, pause = os.environ["STAGE"], Path(os.environ["MARKER"]), float(os.environ["PAUSE_S"])
    module, owner, name, when = os.environ["HOOK"].split(":")

    def rank0():
        from ngcrack.distributed.world import world_rank
        return world_rank() == 0

    def wait():
        if rank0() and not marker.exists():
            marker.write_text(stage)
            time.sleep(pause)

    target = importlib.import_module(module)
    holder = getattr(target, owner) if owner else target
    if name == "replace":  # the outputs being moved into place: pause after the first one
        real = os.replace
        class _Os:
            def __getattr__(self, attr):
                return getattr(os, attr)
            def replace(self, a, b):
                real(a, b)
                wait()
        holder.os = _Os()
    else:
        f = getattr(holder, name)
        @functools.wraps(f)
        def paused(*args, **kwargs):
            if when == "before":
                wait()
                return f(*args, **kwargs)
            out = f(*args, **kwargs)
            wait()
            return out
        setattr(holder, name, paused)

    from ngcrack.shell.cli import main
    sys.exit(main(sys.argv[1:]))
''')

#: stage -> the function paused (module:class:name:before|after)
STAGES_3D = {
    "mesh": "ngcrack.core.pipeline:Pipeline:mesh:before",
    "assemble": "ngcrack.core.pipeline:Pipeline:discretization:before",
    "condense": "ngcrack.core.pipeline:Pipeline:system:before",
    "contact": "ngcrack.core.pipeline:Pipeline:system:after",
    "fronts": "ngcrack.solid.front::front_parameters:before",
    "estimate": "ngcrack.solid.estimate::prager_synge:before",
    "write": "ngcrack.shell.files:Staged:write:after",
    "commit": "ngcrack.shell.files::replace:after",
}


def _old_outputs(place: Path, names) -> dict:
    """Files standing in for an earlier run's outputs: {name: bytes}."""
    old = {}
    for name in names:
        (place / name).write_bytes(f"an earlier run's {name}\n".encode())
        old[name] = (place / name).read_bytes()
    return old


def _run_to_stage(prefix: list, args: list, place: Path, stage: str, hook: str, sig: int):
    """Start `prefix child args` in `place` paused at `stage`, signal it there; (returncode, stderr, seconds to exit)."""
    child = place.parent / f"child-{stage}.py"
    child.write_text(CHILD)
    marker = place.parent / f"reached-{stage}"
    env = dict(os.environ, OMP_NUM_THREADS="1", STAGE=stage, MARKER=str(marker), HOOK=hook,
               PAUSE_S=str(COMMIT_PAUSE_S if stage == "commit" else PAUSE_S))
    root = Path(__file__).resolve().parents[1]
    env["PYTHONPATH"] = str(root) + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.Popen([*prefix, str(child), *args],
                            cwd=place, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        deadline = time.monotonic() + REACH_S
        while not marker.exists() and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert marker.exists(), (stage, proc.poll(), proc.communicate(timeout=30) if proc.poll() is not None else "")
        time.sleep(0.2)  # into the pause
        sent = time.monotonic()
        proc.send_signal(sig)
        proc.wait(timeout=PAUSE_S)
        took = time.monotonic() - sent
    finally:
        if proc.poll() is None:
            proc.kill()
        try:
            os.killpg(proc.pid, signal.SIGKILL)  # nothing of the run may outlive it: checked below
            orphans = True
        except ProcessLookupError:
            orphans = False
        proc.wait(timeout=30)
    _, err = proc.communicate()
    assert not orphans, f"processes of the run outlived it ({stage})"
    return proc.returncode, err, took


def _check_outputs(place: Path, old: dict, committed: bool) -> None:
    left = sorted(p.name for p in place.iterdir() if p.name.startswith("."))
    assert left == [], left  # no temporary file or staging folder
    now = {p.name: p.read_bytes() for p in place.iterdir()}
    if not committed:
        assert now == old  # every old output intact, nothing new
        return
    assert set(now) == set(old)
    assert all(now[n] != old[n] for n in old)  # every output is the new run's: none old, none half
    data = json.loads(now["out.json"])
    assert data["fronts"] and all(v == v for v in data["fronts"][0]["K_I"])  # whole, and no NaN


#: the stages of the default run (about 5 s each); the others and SIGINT are in the slow run
DEFAULT_3D = ("mesh", "contact", "commit")
SIG = [signal.SIGTERM, pytest.param(signal.SIGINT, marks=pytest.mark.slow)]
SIG_IDS = ["SIGTERM", "SIGINT"]


@pytest.mark.parametrize("sig", SIG, ids=SIG_IDS)
@pytest.mark.parametrize("stage", [s if s in DEFAULT_3D else pytest.param(s, marks=pytest.mark.slow) for s in STAGES_3D])
def test_a_3d_solve_stops_at_each_stage_and_keeps_the_old_outputs(tmp_path, stage, sig):
    place = tmp_path / "run"
    place.mkdir()
    (tmp_path / "small.toml").write_text(SMALL_3D)
    old = _old_outputs(place, ["out.json", "v.vtu", "v_cracks.vtu"])
    args = ["solve", str(tmp_path / "small.toml"), "--order", "1", "--json", "out.json", "--vtk", "v"]
    code, err, took = _run_to_stage([sys.executable], args, place, stage, STAGES_3D[stage], sig)
    what = "terminated" if sig == signal.SIGTERM else "interrupted"
    assert code == 128 + sig, err
    lines = err.splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"ngcrack: {what}"), err
    committed = stage == "commit"
    assert ("nothing was written" in lines[0]) != committed, lines[0]
    assert took < EXIT_WITHIN_S + (COMMIT_PAUSE_S if committed else 0.0), took
    _check_outputs(place, old, committed)


HYDROFRAC = ["hydrofrac", "kgd", "--rate", "1e-4", "--K-Ic", "1e6", "--da", "0.5", "--steps", "3", "--maxh", "8",
             "--json", "out.json"]
STAGES_HYDROFRAC = {
    "first mesh": "ngcrack.core.pipeline:Pipeline:mesh:before",
    "first crack problem": "ngcrack.core.pipeline:Pipeline:system:after",
    "write": "ngcrack.shell.files:Staged:write:after",
}


@pytest.mark.parametrize("stage", [s if s == "first crack problem" else pytest.param(s, marks=pytest.mark.slow)
                                   for s in STAGES_HYDROFRAC])
def test_a_hydrofrac_stops_at_each_stage(tmp_path, stage):
    place = tmp_path / "run"
    place.mkdir()
    old = _old_outputs(place, ["out.json"])
    code, err, took = _run_to_stage([sys.executable], HYDROFRAC, place, stage.replace(" ", "-"), STAGES_HYDROFRAC[stage],
                                    signal.SIGTERM)
    assert code == 128 + signal.SIGTERM, err
    assert len(err.splitlines()) == 1 and err.startswith("ngcrack: terminated"), err
    assert took < EXIT_WITHIN_S, took
    if stage == "write":  # the finished steps are being written when the signal comes: those are kept, whole
        data = json.loads((place / "out.json").read_text())
        assert data["stopped"].startswith("interrupted") or len(data["steps"]) >= 1
        assert not [p for p in place.iterdir() if p.name.startswith(".")]
    else:
        _check_outputs(place, old, committed=False)


STAGES_MPI = {
    "mesh": "ngcrack.solid.geometry::make_mesh:before",
    "fronts": "ngcrack.solid.front::front_parameters:before",
    "write": "ngcrack.shell.files:Staged:write:after",
}


@pytest.mark.slow
@pytest.mark.parametrize("stage", list(STAGES_MPI))
def test_an_mpiexec_solve_stops_at_each_stage(tmp_path, stage):
    from test_mpi import _mpiexec

    place = tmp_path / "run"
    place.mkdir()
    (tmp_path / "small.toml").write_text(SMALL_3D)
    old = _old_outputs(place, ["out.json"])
    args = ["solve", str(tmp_path / "small.toml"), "--order", "1", "--json", "out.json"]
    code, err, took = _run_to_stage([_mpiexec(), "-n", "2", sys.executable], args, place, stage, STAGES_MPI[stage],
                                    signal.SIGINT)
    assert code == 128 + signal.SIGINT, err
    lines = [ln for ln in err.splitlines() if ln.startswith("ngcrack:")]
    assert len(lines) == 1 and lines[0].startswith("ngcrack: interrupted"), err
    assert took < EXIT_WITHIN_S, took
    _check_outputs(place, old, committed=False)
