"""SIGTERM and SIGINT act at once in every stage, and an interrupted `grow` keeps its finished steps.

What is checked, and against what:
- netgen meshing a huge mesh (griffith at maxh 0.02: minutes of meshing) stops within a
  fraction of the time it had already run: the exit comes at most half as long after the
  signal as the signal came after the start (measured: 0.3 s after 8 s), exit code
  128 + signal, one line, no file;
- a main thread held in a C call that checks no flag (libc's system(), which waits for its
  child whatever the signals) is ended by the watcher after its grace period: exit code
  128 + 15, the command's line, the temporary files of outputs being written removed; a
  `grow` held so in a solve still writes the steps it finished;
- `grow` stopped after a step writes the finished steps (JSON and CSV, whole, marked
  "stopped": "interrupted: ...") and says so, also when the signal is swallowed by a library
  or comes back as another exception type (never lost, never "unexpected").
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

import pandas as pd
import pytest

from ngcrack.shell import cli

LINUX = sys.platform.startswith("linux")
GROW = ["grow", "inclined-compression", "--da", "0.2", "--maxh", "2", "--criterion", "mts"]


def _cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime + stime


def _wait(cond, timeout: float, step: float = 0.05) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if cond():
            return True
        time.sleep(step)
    return cond()


def _stop(proc) -> None:
    if proc.poll() is None:
        proc.kill()
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except OSError:
        pass
    proc.wait(timeout=30)


@pytest.mark.skipif(not LINUX, reason="reads the process's CPU time from /proc")
@pytest.mark.parametrize("sig", [signal.SIGTERM, pytest.param(signal.SIGINT, marks=pytest.mark.slow)],
                         ids=["SIGTERM", "SIGINT"])
def test_a_signal_stops_netgen_meshing_at_once(tmp_path, sig):
    cmd = [sys.executable, "-m", "ngcrack.shell.cli", "solve", "griffith", "--maxh", "0.02", "--max-dof", "1e30",
           "--json", "r.json"]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    start = time.monotonic()
    proc = subprocess.Popen(cmd, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            start_new_session=True)
    try:
        # the imports and checks take under 2 s of CPU; from then on netgen meshes (for minutes)
        assert _wait(lambda: proc.poll() is not None or _cpu_seconds(proc.pid) > 4, timeout=300)
        assert proc.poll() is None, proc.communicate()
        sent = time.monotonic()
        proc.send_signal(sig)
        proc.wait(timeout=300)
        latency = time.monotonic() - sent
    finally:
        _stop(proc)
    out, err = proc.communicate()
    assert proc.returncode == 128 + sig, err
    what = "terminated" if sig == signal.SIGTERM else "interrupted"
    assert err.splitlines() == [f"ngcrack: {what}; nothing was written"]
    assert latency <= 0.5 * (sent - start), (latency, sent - start)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not LINUX, reason="libc's system() through ctypes")
def test_a_long_c_call_is_ended_by_the_watcher(tmp_path):
    script = textwrap.dedent("""
        import ctypes, sys
        from pathlib import Path
        from ngcrack.shell.files import register_temporary
        from ngcrack.shell.interrupts import Interrupts

        tmp = Path(sys.argv[1]) / ".out.json.tmp"
        tmp.write_text("half")
        register_temporary(tmp)
        with Interrupts(lambda signum: f"ngcrack: stopped by {signum}; nothing was written"):
            print("ready", flush=True)
            ctypes.CDLL(None).system(b"sleep 60")  # waits for its child whatever the signals
        print("not reached", flush=True)
    """)
    proc = subprocess.Popen([sys.executable, "-c", script, str(tmp_path)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        assert proc.stdout.readline() == "ready\n"
        time.sleep(0.5)  # into system()
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=120)
        try:  # its `sleep 60` (same process group) outlives it: it did not wait for the C call
            os.killpg(proc.pid, 0)
            sleeping = True
        except ProcessLookupError:
            sleeping = False
    finally:
        _stop(proc)
    out, err = proc.communicate()
    assert proc.returncode == 128 + signal.SIGTERM
    assert err.splitlines() == ["ngcrack: stopped by 15; nothing was written"]
    assert "not reached" not in out
    assert sleeping  # the watcher ended the process inside system(), before its child's 60 s were over
    assert list(tmp_path.iterdir()) == []


def _grow_files(place: Path, steps_at_least: int, signame: str):
    data = json.loads((place / "g.json").read_text())
    assert data["stopped"].startswith(f"interrupted: {signame} after step ")
    n = len(data["steps"])
    assert n >= steps_at_least
    table = pd.read_csv(place / "g.csv")
    assert sorted(set(table["step"])) == list(range(n))  # the CSV holds exactly the JSON's steps
    assert [s["step"] for s in data["steps"]] == list(range(n))
    assert not [p.name for p in place.iterdir() if p.name.startswith(".")]  # no temporary file left
    return data


@pytest.mark.slow  # the default run has the grow held in a C call and the in-process cases below
@pytest.mark.skipif(not LINUX, reason="POSIX signals")
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_an_interrupted_grow_writes_its_finished_steps(tmp_path, sig):
    cmd = [sys.executable, "-m", "ngcrack.shell.cli", *GROW, "--steps", "30", "--json", "g.json", "--csv", "g.csv",
           "--gif", "g.gif"]
    proc = subprocess.Popen(cmd, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=dict(os.environ, OMP_NUM_THREADS="1"), start_new_session=True)
    try:
        for line in proc.stdout:
            if line.startswith("step 1:"):
                break
        proc.send_signal(sig)
        proc.wait(timeout=120)
    finally:
        _stop(proc)
    err = proc.stderr.read().splitlines()
    assert proc.returncode == 128 + sig, err
    what = "terminated" if sig == signal.SIGTERM else "interrupted"
    assert len(err) == 1 and err[0].startswith(f"ngcrack: {what}; wrote g.json and g.csv with the "), err
    assert "not written: g.gif" in err[0]
    _grow_files(tmp_path, 2, signal.Signals(sig).name)
    assert not (tmp_path / "g.gif").exists()


@pytest.mark.skipif(not LINUX, reason="libc's system() through ctypes")
def test_a_grow_held_in_a_long_c_call_still_writes_its_finished_steps(tmp_path):
    """The solve after step 1 (the step 2 -> 3 extension) never returns to Python (libc's system()):
    the watcher writes steps 0 and 1 itself."""
    script = textwrap.dedent(f"""
        import ctypes, sys
        from ngcrack.shell import cli
        from ngcrack.studies.growth import loop

        real, calls = loop.solve_step, []

        def solve_step(*args, **kwargs):
            calls.append(1)
            if len(calls) == 4:  # step 0's, then one a step: the 4th makes step 3, after "step 1" is printed
                ctypes.CDLL(None).system(b"sleep 60")
            return real(*args, **kwargs)

        loop.solve_step = solve_step
        sys.exit(cli.main({[*GROW, "--steps", "5", "--json", "g.json", "--csv", "g.csv"]!r}))
    """)
    proc = subprocess.Popen([sys.executable, "-c", script], cwd=tmp_path, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"),
                            start_new_session=True)
    try:
        for line in proc.stdout:
            if line.startswith("step 1:"):
                break
        time.sleep(0.5)  # into the next solve, in system()
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=120)
        try:  # its `sleep 60` (same process group) outlives it: it did not wait for the C call
            os.killpg(proc.pid, 0)
            sleeping = True
        except ProcessLookupError:
            sleeping = False
    finally:
        _stop(proc)
    err = proc.stderr.read().splitlines()
    assert proc.returncode == 128 + signal.SIGTERM, err
    assert err == ['ngcrack: terminated; wrote g.json and g.csv with the 2 finished steps, marked "stopped": '
                   '"interrupted: ..."'], err
    assert len(_grow_files(tmp_path, 2, "SIGTERM")["steps"]) == 2
    assert sleeping  # the watcher ended the process inside system(), before its child's 60 s were over


def _signal_in_step(monkeypatch, at_call: int, then):
    """Send SIGTERM to this process inside the loop's `at_call`-th tip evaluation; `then(exc)` decides
    what the library does with the KeyboardInterrupt (swallow it, or raise its own error)."""
    from ngcrack.studies.growth import loop

    real, calls = loop.tip_values, []

    def tip_values(*args, **kwargs):
        calls.append(1)
        if len(calls) == at_call:
            try:
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(5)  # the handler raises here
            except KeyboardInterrupt as exc:
                then(exc)
        return real(*args, **kwargs)

    monkeypatch.setattr(loop, "tip_values", tip_values)


def _swallow(exc):
    pass


def _as_foreign_error(exc):
    raise RuntimeError("ArgumentError: a callback raised KeyboardInterrupt") from exc


@pytest.mark.skipif(not LINUX, reason="POSIX signals")
@pytest.mark.parametrize("then, finished", [(_swallow, 2), (_as_foreign_error, 1)],
                         ids=["swallowed", "another-exception"])
def test_a_signal_in_grow_is_never_lost(tmp_path, monkeypatch, capsys, then, finished):
    """Step 1's tip evaluation gets the signal: swallowed, step 1 finishes and the run stops after it;
    turned into another error, the run stops with step 0."""
    monkeypatch.chdir(tmp_path)
    _signal_in_step(monkeypatch, 2, then)
    code = cli.main([*GROW, "--steps", "4", "--json", "g.json", "--csv", "g.csv"])
    out, err = capsys.readouterr()
    err = err.splitlines()
    assert code == 128 + signal.SIGTERM, err
    assert len(err) == 1 and err[0].startswith(f"ngcrack: terminated; wrote g.json and g.csv with the {finished} "
                                               "finished steps"), err
    data = _grow_files(tmp_path, finished, "SIGTERM")
    assert len(data["steps"]) == finished
    assert "wrote g.json" not in out  # the final outputs were not written as if complete
