"""Commands that are not distributed under `mpiexec -n 2` (issue 43, item 4): `ngcrack grow`, `ngcrack hydrofrac`
and `nc.grow` run once, on rank 0, print once and write once; the other rank ends at once after the same input
checks (`shell.cli_runs.runs_here`, `studies.growth.solves.on_rank_zero`).

Before, every rank ran the whole serial job and wrote the same files (each line printed twice). Asserted: every
line of stdout once, one note on stderr, the same numbers as the serial run, and a bad value refused in one line.
"""

from __future__ import annotations

import json
import textwrap

import pytest
from test_mpi import _run, pytestmark  # noqa: F401 -- mpiexec in a subprocess, skipped without mpi4py

import ngcrack as nc

NOTE = "ngcrack: note: this command is not distributed: rank 0 runs it alone, the other 1 rank(s) have nothing to do"


def _once(proc) -> list[str]:
    """stdout's lines, each asserted to be printed once; stderr holds the one note."""
    assert proc.returncode == 0, proc.stderr[-2000:]
    lines = proc.stdout.splitlines()
    assert len(lines) == len(set(lines)), proc.stdout
    assert [ln for ln in proc.stderr.splitlines() if ln.strip()] == [NOTE + " (run it without mpiexec)"], proc.stderr
    return lines


def test_grow_runs_once(tmp_path):
    out, csv = tmp_path / "g.json", tmp_path / "g.csv"
    args = ["griffith", "--da", "0.05", "--steps", "1", "--K-Ic", "2", "--criterion", "mts", "--maxh", "0.5"]
    lines = _once(_run(["-m", "ngcrack.shell.cli", "grow", *args, "--json", str(out), "--csv", str(csv)]))
    assert lines.count(f"wrote {out}") == 1 and lines.count(f"wrote {csv}") == 1
    assert sum(ln.startswith("griffith: 2 steps, stopped: ") for ln in lines) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.csv", "g.json"]
    data = json.loads(out.read_text())
    serial = nc.grow("griffith", 0.05, 1, K_Ic=2.0, criterion="mts", maxh=0.5, frames=False)
    assert [s["load_factor"] for s in data["steps"]] == pytest.approx([s["load_factor"] for s in serial.steps],
                                                                        rel=1e-10)


def test_grow_refuses_in_one_line(tmp_path):
    out = tmp_path / "g.json"
    proc = _run(["-m", "ngcrack.shell.cli", "grow", "griffith", "--da", "0.05", "--steps", "0", "--json", str(out)])
    assert proc.returncode == 2
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and "steps = 0" in lines[0], proc.stderr
    assert not out.exists()


def test_hydrofrac_runs_once(tmp_path):
    out = tmp_path / "h.json"
    lines = _once(_run(["-m", "ngcrack.shell.cli", "hydrofrac", "kgd", "--rate", "1e-4", "--K-Ic", "1e6", "--da",
                        "0.1", "--steps", "1", "--json", str(out)]))
    assert lines.count(f"wrote {out}") == 1
    assert len(json.loads(out.read_text())["steps"]) == 2


GROW = textwrap.dedent('''
    import json, sys
    from mpi4py import MPI
    import ngcrack as nc
    res = nc.grow("griffith", 0.05, 1, K_Ic=2.0, criterion="mts", maxh=0.5, frames=False)
    got = MPI.COMM_WORLD.gather(None if res is None else [s["load_factor"] for s in res.steps], root=0)
    if MPI.COMM_WORLD.rank == 0:
        json.dump(got, open(sys.argv[1], "w"))
''')


def test_nc_grow_runs_on_rank_zero(tmp_path):
    """nc.grow: the result on rank 0, None on rank 1 (as nc.solve's distributed solve)."""
    script, out = tmp_path / "grow.py", tmp_path / "out.json"
    script.write_text(GROW)
    proc = _run([str(script), str(out)])
    assert proc.returncode == 0, proc.stderr[-2000:]
    got = json.loads(out.read_text())
    assert got[1] is None and len(got[0]) == 2 and got[0][0] == pytest.approx(2.0 / 1.7893434723, rel=1e-3)


def test_an_interrupted_grow_writes_and_prints_once(tmp_path):
    """SIGINT to mpiexec after step 1: rank 0 writes the finished steps once and prints one interrupt line (every
    rank printed its own before); exit 128 + 2."""
    import signal
    import subprocess
    import sys

    from test_mpi import LIMIT_S, _env, _mpiexec

    out = tmp_path / "g.json"
    proc = subprocess.Popen([_mpiexec(), "-n", "2", sys.executable, "-m", "ngcrack.shell.cli", "grow", "griffith", "--da",
                             "0.05", "--steps", "40", "--maxh", "0.5", "--criterion", "mts", "--json", str(out)],
                            env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    for line in proc.stdout:
        if line.startswith("step 1:"):
            proc.send_signal(signal.SIGINT)
            break
    _, err = proc.communicate(timeout=LIMIT_S)
    assert proc.returncode == 128 + signal.SIGINT, err
    lines = [ln for ln in err.splitlines() if ln.startswith("ngcrack: interrupted")]
    assert len(lines) == 1 and str(out) in lines[0], err
    data = json.loads(out.read_text())
    assert data["stopped"].startswith("interrupted: SIGINT after step") and len(data["steps"]) >= 2
