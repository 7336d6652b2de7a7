"""Faults during long work: a sweep's process killed or terminated, runs that fail, files that rot.

What is checked, and against what:
- SIGTERM or SIGKILL of the main process of `ngcrack sweep --jobs 2` leaves no process of
  its session behind (the workers die with their parent, and with them the resource
  tracker), within a few seconds; the CSV holds complete, distinct rows;
- a sweep that fails or is interrupted before any run finishes leaves no file (never a
  header alone), and one that fails later leaves the rows before untouched;
- a corrupted CSV (a garbled cell, a lost cell, a duplicated row, a cell "nan") is refused
  naming the file, the row and the column, by the reader and by a resumed sweep;
- scene names become file names only sanitised: `../../escaped` and `my/scene` write
  their reference cache inside the output folder.
- a worker of `sweep --jobs 2` killed by SIGTERM ends the sweep with exit code 3 and one line
  saying so (not an unexpected BrokenProcessPool), the finished rows kept;
- under an address-space limit the libraries alone exceed (ulimit -v 500000), a solve
  exits with 3 and one line saying "out of memory" (OpenBLAS aborted or looped before);
(The resume after SIGKILL of a serial sweep is in tests/test_study.py.)
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from dataclasses import replace
from pathlib import Path

import pytest

from ngcrack import scenes
from ngcrack.shell import cli
from ngcrack.studies.sweeps import read_results, sweep

LINUX = sys.platform.startswith("linux")


def _session(sid: int) -> list[int]:
    """The processes of session `sid` (Linux /proc)."""
    pids = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            stat = Path(f"/proc/{entry}/stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2:].split()  # after "pid (comm) "
        if fields[0] != "Z" and int(fields[3]) == sid:  # state, ppid, pgrp, session
            pids.append(int(entry))
    return pids


def _wait(cond, timeout: float, step: float = 0.1) -> bool:
    deadline = time.time() + timeout
    while time.time() < deadline:
        if cond():
            return True
        time.sleep(step)
    return cond()


GRID = ["--element", "bdm", "--maxh", "0.2", "0.15", "0.12", "0.1", "0.08", "0.07", "0.06"]


@pytest.mark.skipif(not LINUX, reason="reads the process table from /proc")
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
def test_a_killed_parallel_sweep_leaves_no_worker(tmp_path, sig):
    out = tmp_path / "r.csv"
    cmd = [sys.executable, "-m", "ngcrack.shell.cli", "sweep", "paper-2", *GRID, "--jobs", "2", "--out", str(out),
           "--no-progress"]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=tmp_path,
                            start_new_session=True, text=True)
    try:
        # both workers started, and (SIGTERM) a row written: the workers are busy with the next runs
        assert _wait(lambda: len(_session(proc.pid)) >= 3 and (sig == signal.SIGKILL or (
            out.exists() and out.read_text().count("\n") >= 2)), timeout=120), "the sweep did not get going"
        assert proc.poll() is None, "the sweep finished before it could be stopped"
        workers = [p for p in _session(proc.pid) if p != proc.pid]
        proc.send_signal(sig)
        proc.wait(timeout=60)
        gone = _wait(lambda: not _session(proc.pid), timeout=15)
        left = _session(proc.pid)
        assert gone, f"left behind: {[Path(f'/proc/{p}/cmdline').read_bytes()[:80] for p in left]}"
    finally:
        if proc.poll() is None:
            proc.kill()
        for p in _session(proc.pid):
            os.kill(p, signal.SIGKILL)
        proc.wait(timeout=30)
    err = proc.stderr.read()
    if sig == signal.SIGTERM:
        assert proc.returncode == 128 + signal.SIGTERM, err
        assert "ngcrack: terminated; finished runs are saved" in err
        assert "Traceback" not in err
    else:
        assert proc.returncode == -signal.SIGKILL
    assert len(workers) >= 2
    if out.exists():  # complete, distinct rows only
        rows = read_results(out)
        assert 0 < len(rows) < 7 and rows["maxh"].is_unique


def test_a_failed_or_interrupted_sweep_leaves_no_header_alone(tmp_path, monkeypatch):
    import ngcrack.studies.sweeps.plan as plan

    out = tmp_path / "r.csv"

    def failing(case):
        raise RuntimeError("the run broke")

    monkeypatch.setattr(plan, "run_case", failing)
    with pytest.raises(plan.SweepError, match="the run broke"):
        sweep("paper-2", maxh=[0.4, 0.3], out=out)
    assert not out.exists()

    def interrupted(case):
        raise KeyboardInterrupt

    monkeypatch.setattr(plan, "run_case", interrupted)
    with pytest.raises(KeyboardInterrupt):
        sweep("paper-2", maxh=[0.4, 0.3], out=out)
    assert not out.exists()
    monkeypatch.undo()
    # the first two runs finish (the reference first), the third fails: those two rows stay
    sweep("paper-2", maxh=[0.4, 0.3], out=out)
    before = out.read_bytes()
    real = plan.run_case

    def third_fails(case):
        if case.maxh == 0.35:
            raise RuntimeError("the run broke")
        return real(case)

    monkeypatch.setattr(plan, "run_case", third_fails)
    with pytest.raises(plan.SweepError, match="maxh=0.35"):
        sweep("paper-2", maxh=[0.4, 0.35, 0.3], out=out)
    assert out.read_bytes() == before
    # and on the command line: one line, exit 3 (not the input: an unexpected error of a run), the file untouched
    code = cli.main(["sweep", "paper-2", "--maxh", "0.4", "0.35", "0.3", "--out", str(out), "--no-progress"])
    assert code == 3 and out.read_bytes() == before


@pytest.fixture(scope="module")
def results(tmp_path_factory) -> tuple[Path, str]:
    out = tmp_path_factory.mktemp("csv") / "r.csv"
    sweep("paper-2", maxh=[0.4, 0.3, 0.25], out=out)
    return out, out.read_text()


def _corrupt(text: str, row: int, column: str, value: str) -> str:
    import csv
    import io

    lines = list(csv.reader(io.StringIO(text)))
    lines[row][lines[0].index(column)] = value
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerows(lines)
    return buf.getvalue()


@pytest.mark.parametrize("how, message", [
    ("cell", "row 2 (line 3), column 'err_u1': 'abc' is not a finite number"),
    ("nan", "row 1 (line 2), column 'time_total': 'nan' is not a finite number"),
    ("int", "row 3 (line 4), column 'ndof_total': '12.5' is not an integer"),
    ("bool", "row 1 (line 2), column 'reference': 'yes' is not True or False"),
    ("short", "row 2 (line 3) has"),
    ("duplicate", "rows 1 and 4 (lines 2 and 5) are the same run"),
    ("edited-nu", "row 2 (line 3) was changed after the sweep wrote it (scene = paper-2, element = tdnns, "
                  "maxh = 0.3, nu = 0.3,"),
])
def test_a_corrupted_csv_is_refused_naming_file_row_and_column(results, tmp_path, capsys, how, message):
    good, text = results
    bad = tmp_path / "bad.csv"
    lines = text.splitlines(keepends=True)
    corrupted = {
        "cell": lambda: _corrupt(text, 2, "err_u1", "abc"),
        "nan": lambda: _corrupt(text, 1, "time_total", "nan"),
        "int": lambda: _corrupt(text, 3, "ndof_total", "12.5"),
        "bool": lambda: _corrupt(text, 1, "reference", "yes"),
        "short": lambda: "".join(lines[:2] + [lines[2].rsplit(",", 1)[0] + "\n"] + lines[3:]),
        "duplicate": lambda: text + lines[1],
        "edited-nu": lambda: _corrupt(text, 2, "nu", "0.3"),  # would pass for a run at nu = 0.3
    }[how]()
    bad.write_text(corrupted)
    with pytest.raises(ValueError) as info:
        read_results(bad)
    assert str(bad) in str(info.value) and message in str(info.value)
    assert len(read_results(good)) == 3  # the good file reads
    # a resumed sweep refuses it too, on one line, and leaves it as it was
    code = cli.main(["sweep", "paper-2", "--maxh", "0.4", "0.3", "0.25", "--out", str(bad), "--no-progress"])
    err = capsys.readouterr().err.splitlines()
    assert code == 2 and len(err) == 1 and message in err[0], err
    assert bad.read_text() == corrupted


@pytest.mark.parametrize("name", ["../../escaped", "my/scene", "/abs/olute", ".hidden"])
def test_scene_names_stay_inside_the_output_folder(tmp_path, name):
    work = tmp_path / "a" / "b"
    work.mkdir(parents=True)
    scene = replace(scenes.load("paper-2"), name=name)
    df = sweep(scene, maxh=[0.4], reference_maxh=0.3, out=work / "r.csv")
    assert list(df["scene"]) == [name]
    inside = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*") if p.is_file())
    assert all(p.startswith("a/b/r.csv") for p in inside), inside
    (cache,) = (work / "r.csv.refs").iterdir()
    assert not cache.name.startswith(".") and "/" not in cache.name
    # resumed: the cache is found again, nothing new is computed
    again = sweep(scene, maxh=[0.4], reference_maxh=0.3, out=work / "r.csv")
    assert len(again) == 1 and list((work / "r.csv.refs").iterdir()) == [cache]


@pytest.mark.skipif(not LINUX, reason="reads the process table from /proc")
def test_a_killed_sweep_worker_ends_the_sweep_with_one_line(tmp_path):
    out = tmp_path / "r.csv"
    cmd = [sys.executable, "-m", "ngcrack.shell.cli", "sweep", "paper-2", *GRID, "--jobs", "2", "--out", str(out),
           "--no-progress"]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=tmp_path,
                            start_new_session=True, text=True)
    try:
        assert _wait(lambda: len(_session(proc.pid)) >= 3, timeout=120), "the workers did not start"
        time.sleep(1.0)  # the workers have their runs
        worker = max(p for p in _session(proc.pid) if p != proc.pid)
        os.kill(worker, signal.SIGTERM)
        proc.wait(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
        for p in _session(proc.pid):
            os.kill(p, signal.SIGKILL)
        proc.wait(timeout=30)
    err = proc.stderr.read().splitlines()
    assert proc.returncode == 3, err
    assert len(err) == 1 and "a worker process of the sweep ended abruptly" in err[0], err
    assert "unexpected" not in err[0] and "BrokenProcessPool" not in err[0]
    if out.exists():
        assert read_results(out)["maxh"].is_unique


@pytest.mark.skipif(not LINUX, reason="RLIMIT_AS")
def test_an_address_space_limit_is_reported_as_out_of_memory(tmp_path):
    import resource

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (500000 * 1024, resource.RLIM_INFINITY))

    proc = subprocess.run([sys.executable, "-m", "ngcrack.shell.cli", "solve", "paper-2", "--maxh", "0.3", "--json",
                           "r.json"], cwd=tmp_path, capture_output=True, text=True, timeout=120, preexec_fn=limit)
    err = proc.stderr.splitlines()
    assert proc.returncode == 3, proc.stderr
    assert len(err) == 1 and err[0].startswith("ngcrack: error: out of memory: the address-space limit (ulimit -v) "
                                               "is 488 MB"), err
    assert list(tmp_path.iterdir()) == []
