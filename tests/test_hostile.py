"""The command line against a hostile user: every bad input and every fault gets one clear line.

Each case of the table runs one subcommand (in this process, `cli.main`) in an empty
folder and checks: the exit code (2 bad input: an ngcrack.InputError; 3 anything else,
a system that cannot be solved or a fault of ngcrack), exactly one line on stderr that names the field or cause (a fragment of
it is asserted), and no file left behind (existing outputs untouched). The cases are
refused before any meshing, or solve a coarse mesh, so the file runs in well under a
minute. Signals and a killed process are tested in tests/test_study.py.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

import ngcrack as nc
from ngcrack.shell import cli

PAPER_2 = (Path(__file__).parents[1] / "ngcrack" / "scenes" / "paper-2.toml").read_text()
SCENES = {
    "typo.toml": PAPER_2.replace("[material]\nE =", "[material]\nYoung ="),
    "maxh-tiny.toml": PAPER_2.replace("maxh = 0.1", "maxh = 1e-300"),
    "maxh-huge.toml": PAPER_2.replace("maxh = 0.1", "maxh = 1e300"),
}


def _files(root: Path) -> set[str]:
    return {str(p.relative_to(root)) for p in root.rglob("*")}


def _readonly(path: Path) -> None:
    """Make `path` a folder this process cannot write in (root ignores the mode bits: immutable)."""
    path.mkdir()
    if os.geteuid() != 0:
        path.chmod(0o555)
        return
    if shutil.which("chattr") is None or subprocess.run(["chattr", "+i", str(path)], capture_output=True).returncode:
        pytest.skip("no way to make a read-only folder for root here (chattr +i)")


def _writable(path: Path) -> None:
    if path.exists():
        if os.geteuid() == 0:
            subprocess.run(["chattr", "-i", str(path)], capture_output=True)
        else:
            path.chmod(0o755)


@pytest.fixture
def place(tmp_path, monkeypatch):
    """An empty working folder with the scene files, an existing folder and a read-only folder."""
    monkeypatch.chdir(tmp_path)
    for name, text in SCENES.items():
        (tmp_path / name).write_text(text)
    (tmp_path / "adir").mkdir()
    (tmp_path / "adir.csv").mkdir()
    for name in ("v.vtu", "w_cracks.vtu", "s_0001_cracks.vtu", "p.pvd",  # output names taken by folders
                 "q_paper-2-tdnns-h0.4-nu0.49_cracks.vtu"):
        (tmp_path / name).mkdir()
    (tmp_path / "old.json").write_text('{"kept": true}')
    (tmp_path / "other.csv").write_text("a,b\n1,2\n")
    _readonly(tmp_path / "ro")
    yield tmp_path
    _writable(tmp_path / "ro")


def run(argv, capsys):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, [line for line in err.splitlines() if line.strip()]


MAXH = ["--maxh", "0.5"]
SWEEP = ["--out", "r.csv", "--no-progress"]
GROW = ["grow", "paper-2", "--da", "0.05", "--steps", "2"]

#: (argv, exit code, a fragment of the one line on stderr)
CASES = [
    # ------------------------------------------------------------------ solve
    (["solve", "nosuch"], 2, "scene = 'nosuch'"),
    (["solve", "paper-2", "--element", "foo"], 2, "--element = 'foo'"),
    (["solve", "paper-2", "--maxh", "abc"], 2, "--maxh: 'abc' is not a number"),
    (["solve", "paper-2", "--maxh", "1e-300"], 2, "--maxh = 1e-300"),
    (["solve", "paper-2", "--maxh", "1e300"], 2, "--maxh = 1e+300"),
    (["solve", "paper-2", "--maxh", "nan"], 2, "--maxh = nan"),
    (["solve", "paper-2", "--tip-h", "1e-300"], 2, "--tip-h = 1e-300"),
    (["solve", "paper-2", "--crack-h", "inf"], 2, "--crack-h = inf"),
    (["solve", "paper-2", "--max-dof", "2.5"], 2, "whole number"),
    (["solve", "paper-2", "--max-dof", "0"], 2, "--max-dof"),
    (["solve", "paper-2", "--nu", "0.7"], 2, "nu"),
    (["solve", "paper-2", "--crack-model", "foo"], 2, "--crack-model = 'foo': allowed values"),
    (["solve", "paper-2", "--qp-solver", "foo"], 2, "--qp-solver = 'foo': allowed values"),
    (["solve", "paper-2", "--adapt", "2"], 2, "adapt"),
    (["solve", "paper-2", "--json", "adir"], 2, "--json = 'adir': is a directory"),
    (["solve", "paper-2", "--json", "missing/r.json"], 2, "does not exist"),
    (["solve", "paper-2", "--json", "ro/r.json"], 2, "cannot write in the directory 'ro'"),
    (["solve", "paper-2", "--plot", "ro/r.png"], 2, "cannot write in the directory 'ro'"),
    (["solve", "paper-2", "--plot", "r.pdf"], 2, "must end in .png"),
    (["solve", "paper-2", "--friction", "0.5", "--crack-model", "free"], 2, "--friction = 0.5: friction acts only"),
    (["solve", "paper-2", "--friction", "0.5", "--crack-model", "bonded"], 2, "crack_model 'contact'"),
    (["solve", "paper-2", "--element", "tdnns", "--order", "9"], 2, "order = 9"),
    (["solve", "paper-2", "--element", "peers", "--order", "2"], 2, "fixed order"),
    (["solve", "paper-2", "--E", "-5"], 2, "material.E = -5"),
    (["solve", "paper-2", "--nu", "nan"], 2, "material.nu = nan"),
    (["solve", "paper-2", "--json", "r.json", "--plot", "adir"], 2, "--plot = 'adir': is a directory"),
    (["solve", "typo.toml"], 2, "Young"),
    (["solve", "maxh-tiny.toml"], 2, "maxh"),
    (["solve", "maxh-huge.toml"], 2, "maxh"),
    (["solve", "maxh-tiny.toml", "--maxh", "0.5", "--json", "r.json", "--plot", "missing/r.png"], 2,
     "--plot = 'missing/r.png': the directory 'missing' does not exist"),
    (["solve", "paper-2", "--E", "1e300", "--json", "r.json"] + MAXH, 2, "material.E = 1e+300"),
    (["solve", "paper-2", "--json", ""], 2, "--json = '': is empty"),
    (["solve", "paper-2", "--hp", "99999999999999999999"], 2, "--hp: '99999999999999999999': the number of layers"),
    (["solve", "no-crack", "--hp", "2", "--order", "2"], 2, "--hp = 2: scene 'no-crack' has no crack tip"),
    # ------------------------------------------- outputs: distinct, checked before the solve, one rule
    (["solve", "paper-2", "--json", "out.png", "--plot", "out.png"], 2, "--plot: 'out.png' is also the file of --json"),
    (["solve", "paper-2", "--json", "x.vtu", "--vtk", "x"], 2, "--vtk: 'x.vtu' is also the file of --json"),
    (["solve", "paper-2", "--json", "r.json", "--vtk", "ro/v"], 2, "--vtk = 'ro/v': cannot write in the directory 'ro'"),
    (["solve", "paper-2", "--json", "r.json", "--vtk", "v"], 2, "--vtk = 'v': v.vtu is a directory"),
    (["solve", "paper-2", "--json", "r.json", "--vtk", "w.vtu"], 2, "--vtk = 'w.vtu': w_cracks.vtu is a directory"),
    (["solve", "paper-2", "--json", "r.json", "--vtk", "missing/v"], 2,
     "--vtk = 'missing/v': the directory 'missing' does not exist"),
    (["solve", "paper-2", "--vtk", ""], 2, "--vtk = '': is empty"),
    (GROW + ["--json", "g.csv", "--csv", "g.csv"], 2, "--csv: 'g.csv' is also the file of --json"),
    (GROW + ["--json", "g.json", "--gif", "g.json"], 2, "--gif = 'g.json': must end in .gif"),
    (GROW + ["--json", "g.json", "--csv", "g.csv", "--png", "adir"], 2, "--png = 'adir': is a directory"),
    (GROW + ["--json", "t_0000.vtu", "--vtk", "t"], 2, "--vtk: 't_0000.vtu' is also the file of --json"),
    (GROW + ["--json", "g.json", "--vtk", "s"], 2, "--vtk = 's': s_0001_cracks.vtu is a directory"),
    (GROW + ["--json", "g.json", "--vtk", "p"], 2, "--vtk = 'p': p.pvd is a directory"),
    (GROW + ["--json", "g.json", "--vtk", "ro/g"], 2, "--vtk = 'ro/g': cannot write in the directory 'ro'"),
    (GROW + ["--json", "g.json", "--vtk", "missing/g"], 2, "the directory 'missing' does not exist"),
    (GROW + ["--json", ""], 2, "--json = '': is empty"),
    (["grow", "inclined-compression", "--da", "1e-6", "--steps", "2", "--maxh", "2", "--json", "g.json"], 2,
     "da = 1e-06: must be at least 0.1 of the mesh size at the crack tips"),
    (GROW + ["--json", "g.json", "--friction", "0.3", "--crack-model", "free"], 2, "--friction = 0.3: friction acts only"),
    (GROW + ["--json", "g.json", "--friction", "0.3", "--crack-model", "bonded"], 2, "crack_model 'contact'"),
    (GROW + ["--json", "old.json", "--at-hole", "0.5"], 2, "at_hole = 0.5: scene 'paper-2' has no hole"),
    (["sweep", "paper-2", "--maxh", "0.4", "--vtk", "p"] + SWEEP, 2, "--vtk = 'p': p.pvd is a directory"),
    (["sweep", "paper-2", "--maxh", "0.4", "--vtk", "ro/p"] + SWEEP, 2, "cannot write in the directory 'ro'"),
    (["sweep", "paper-2", "--maxh", "0.4", "--vtk", "q"] + SWEEP, 2,
     "vtk = 'q': 'q_paper-2-tdnns-h0.4-nu0.49_cracks.vtu' (the ParaView file of the run tdnns, maxh 0.4, nu 0.49) is a "
     "directory"),
    (["sweep", "paper-2", "--maxh", "0.4", "--vtk", "missing/p"] + SWEEP, 2, "the directory 'missing' does not exist"),
    # ------------------------------------------------------------------ sweep
    (["sweep", "paper-2", "--maxh", "0.4", "--out", "adir.csv", "--no-progress"], 2, "is a directory"),
    (["sweep", "paper-2", "--maxh", "0.4", "--out", "r.txt", "--no-progress"], 2, "must end in .csv"),
    (["sweep", "paper-2", "--maxh", "0.4", "--out", "ro/r.csv", "--no-progress"], 2, "cannot write"),
    (["sweep", "paper-2", "--maxh", "1e-300"] + SWEEP, 2, "--maxh = 1e-300"),
    (["sweep", "paper-2", "--maxh", "0.4", "--reference-maxh", "1e300"] + SWEEP, 2, "--reference-maxh"),
    (["sweep", "paper-2", "--maxh", "0.4", "--reference-maxh", "0.8"] + SWEEP, 2, "reference_maxh"),
    (["sweep", "paper-2", "--maxh", "0.4", "--element", "foo"] + SWEEP, 2, "--element = 'foo'"),
    (["sweep", "paper-2", "--maxh", "0.4", "--jobs", "0"] + SWEEP, 2, "--jobs"),
    (["sweep", "paper-2", "--maxh", "0.4", "--jobs", "2", "--dask", "tcp://x:1"] + SWEEP, 2, "--dask"),
    (["sweep", "paper-2", "--maxh", "0.4", "--nu", "0.6"] + SWEEP, 2, "nu"),
    (["sweep", "paper-2", "--maxh", "0.4", "--grading", "2"] + SWEEP, 2, "--grading"),
    (["sweep", "paper-2", "--maxh", "0.4", "--crack-model", "foo"] + SWEEP, 2, "--crack-model"),
    (["sweep", "paper-2", "--maxh", "0.4", "--max-dof", "10"] + SWEEP, 2, "max_dof"),
    (["sweep", "paper-2", "--maxh", "0.4", "--friction", "0", "0.5", "--crack-model", "bonded"] + SWEEP, 2,
     "--friction = 0.5: friction acts only"),
    (["sweep", "paper-2", "--adapt", "0.5", "--maxh", "0.4", "0.2"] + SWEEP, 2, "--maxh"),
    (["sweep", "paper-2"] + SWEEP, 2, "--maxh"),
    (["sweep", "nosuch", "--maxh", "0.4"] + SWEEP, 2, "scene = 'nosuch'"),
    (["sweep", "paper-2", "--adapt", "2"] + SWEEP, 2, "adapt = 2"),
    (["sweep", "paper-2", "--maxh", "0.4", "--reference-element", "foo"] + SWEEP, 2, "--reference-element = 'foo'"),
    (["sweep", "paper-2", "--maxh", "0.4", "--out", "other.csv", "--no-progress"], 2, "columns are not those"),
    (["sweep", "maxh-tiny.toml", "--adapt", "0.5"] + SWEEP, 2, "maxh"),
    # ------------------------------------------------------------------ paper
    (["paper", "--element", "foo", "--out", "p"], 2, "element = 'foo'"),
    (["paper", "--quick", "--maxh", "1e-7", "--out", "p"], 2, "maxh = 1e-07"),
    (["paper", "--element", "bdm", "--maxh", "0.3", "--reference-maxh", "0.8", "--out", "p"], 2,
     "reference_maxh = 0.8"),
    (["paper", "--quick", "--out", "ro/p"], 2, "cannot write"),
    (["paper", "--quick", "--out", "old.json"], 2, "not a directory"),
    (["paper", "--quick", "--jobs", "0", "--out", "p"], 2, "--jobs"),
    (["paper", "--out", "missing/p"], 2, "does not exist"),
    (["paper", "--quick", "--maxh", "abc"], 2, "'abc' is not a number"),
    # -------------------------------------------------------------- stability
    (["stability", "--quick", "--out", "ro/s"], 2, "cannot write"),
    (["stability", "--quick", "--out", "old.json"], 2, "not a directory"),
    (["stability", "--out", "missing/s"], 2, "does not exist"),
    # ------------------------------------------------------------ the parser
    ([], 2, "required"),
    (["nosuch"], 2, "invalid choice"),
    (["solve"], 2, "scene"),
]


def _id(case) -> str:
    argv = case.values[0] if hasattr(case, "values") else case[0]
    return " ".join(argv) or "(none)"


@pytest.mark.parametrize("argv, code, fragment", CASES, ids=[_id(c) for c in CASES])
def test_bad_input_gets_one_line_and_no_file(place, capsys, argv, code, fragment):
    before = _files(place)
    try:
        got, _, err = run(argv, capsys)
    except SystemExit as exc:  # argparse
        got, err = exc.code, [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert got == code, err
    assert len(err) == 1, err
    assert err[0].startswith("ngcrack"), err
    assert fragment in err[0], err
    assert "Traceback" not in err[0]
    assert _files(place) == before
    assert json.loads((place / "old.json").read_text()) == {"kept": True}


def _failing_solve(monkeypatch, exc: BaseException) -> None:
    import sys

    def broken(*args, **kwargs):
        raise exc

    monkeypatch.setattr(sys.modules["ngcrack.core.solve"], "solve", broken)


class NgException(Exception):
    """Stands for netgen's exception type (matched by name)."""


@pytest.mark.parametrize("exc, code, fragment", [
    ("SolveError", 3, "the condensed system is singular"),
    ("ContactSolverError", 3, "did not converge"),
    ("LinearSolverError", 3, "the factorization failed"),
    (MemoryError(), 3, "out of memory"),
    (NgException("thrown by allocate matrix"), 3, "out of memory"),
    (NgException("CalcLU: matrix singularin Assemble BilinearForm 'biform_from_py'"), 3,
     "the system is singular (netgen: CalcLU: matrix singular)"),
    (OverflowError("(34, 'Numerical result out of range')"), 3, "double precision"),
    ("InputError", 2, "maxh = -1: must be > 0"),
    ("PathError", 2, "cannot write"),
])
def test_errors_of_the_package_get_their_exit_code(place, capsys, monkeypatch, exc, code, fragment):
    from ngcrack.core.contact import ContactSolverError
    from ngcrack.core.schur import LinearSolverError
    from ngcrack.core.solve import SolveError
    from ngcrack.shell.files import PathError

    exc = {"SolveError": SolveError("bdm on 'x': the condensed system is singular\n(pivot 3)"),
           "InputError": nc.InputError("maxh = -1: must be > 0"),
           "PathError": PathError("out = 'x': cannot write in the directory '.'"),
           "ContactSolverError": ContactSolverError("qp_solver = 'pdas' did not converge in 50 iterations"),
           "LinearSolverError": LinearSolverError("the factorization failed")}.get(exc, exc)
    _failing_solve(monkeypatch, exc)
    before = _files(place)
    got, _, err = run(["solve", "paper-2", "--json", "r.json"], capsys)
    assert got == code and len(err) == 1, err
    assert fragment in err[0] and "--debug" not in err[0], err
    assert _files(place) == before


def test_unexpected_error_is_one_line_and_debug_gives_the_traceback(place, capsys, monkeypatch):
    _failing_solve(monkeypatch, KeyError("a bug"))
    code, _, err = run(["solve", "paper-2", "--json", "r.json"], capsys)
    assert code == 3 and len(err) == 1, err
    assert "unexpected KeyError in ngcrack solve" in err[0] and "report it" in err[0], err
    assert "run with --debug for the traceback" in err[0]
    code, _, err = run(["solve", "paper-2", "--json", "r.json", "--debug"], capsys)
    assert code == 3 and err[0].startswith("Traceback") and "KeyError" in err[-2], err
    assert err[-1].startswith("ngcrack: error: unexpected KeyError")
    assert not (place / "r.json").exists()


def test_a_library_fault_is_not_called_bad_input(place, capsys, monkeypatch):
    """A plain ValueError from numpy inside a solve (a broadcasting error: a fault of the
    library, not of the input) exits with 3 and asks for a report, not with 2."""
    import numpy as np

    def broken(*args, **kwargs):
        return np.zeros(3) + np.zeros(4)  # ValueError: operands could not be broadcast together

    import sys

    monkeypatch.setattr(sys.modules["ngcrack.core.solve"], "solve", broken)
    code, _, err = run(["solve", "paper-2", "--json", "r.json"], capsys)
    assert code == 3 and len(err) == 1, err
    assert "unexpected ValueError in ngcrack solve" in err[0] and "broadcast" in err[0] and "report it" in err[0], err
    assert not (place / "r.json").exists()


def test_a_failing_plot_leaves_no_json_and_the_old_one_untouched(place, capsys, monkeypatch):
    import ngcrack.planar.plots

    def broken(sol, path):
        Path(path).write_text("half a figure")
        raise RuntimeError("the figure broke")

    monkeypatch.setattr(ngcrack.planar.plots, "plot_solution", broken)
    before = _files(place)
    code, _, err = run(["solve", "paper-2", *MAXH, "--element", "bdm", "--json", "old.json", "--plot", "r.png"], capsys)
    assert code == 3 and len(err) == 1 and "the figure broke" in err[0], err
    assert _files(place) == before
    assert json.loads((place / "old.json").read_text()) == {"kept": True}
    # without the failure both are written, the JSON replacing the old one
    monkeypatch.undo()
    monkeypatch.chdir(place)
    code, out, err = run(["solve", "paper-2", *MAXH, "--json", "old.json", "--plot", "r.png"], capsys)
    assert code == 0, err
    assert json.loads((place / "old.json").read_text())["scene"] == "paper-2"
    assert (place / "r.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert _files(place) == before | {"r.png"}


def test_the_installed_command_prints_one_line_too(tmp_path):
    """The real entry point, in its own process: the same one line, nothing on stdout but netgen's own."""
    import sys

    for argv, code, fragment in [(["solve", "paper-2", "--maxh", "1e-300"], 2, "--maxh = 1e-300"),
                                 (["sweep", "paper-2", "--maxh", "0.4", "--out", "adir"], 2, "must end in .csv")]:
        proc = subprocess.run([sys.executable, "-m", "ngcrack.shell.cli", *argv], cwd=tmp_path, capture_output=True,
                              text=True, timeout=120)
        err = proc.stderr.splitlines()
        assert proc.returncode == code and len(err) == 1 and fragment in err[0], proc.stderr
        assert list(tmp_path.iterdir()) == []


def test_a_closed_pipe_ends_quietly(tmp_path):
    """`ngcrack scenes | head -1`: the reader goes away; no traceback, the shell's code for SIGPIPE."""
    import sys

    proc = subprocess.Popen([sys.executable, "-m", "ngcrack.shell.cli", "scenes"], cwd=tmp_path, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    proc.stdout.close()
    assert proc.wait(timeout=120) == 141
    assert proc.stderr.read() == b""


def test_every_error_of_the_input_is_an_input_error():
    """The family the command line maps to exit 2: the scene's, the paths', the meshes',
    the command line's and the explorer's errors, and the option checks."""
    from ngcrack.planar.geometry import MeshingError
    from ngcrack.shell.cli import UsageError
    from ngcrack.shell.explorer.widget import ArgumentError
    from ngcrack.shell.files import PathError

    for cls in (nc.SceneError, PathError, MeshingError, UsageError, ArgumentError):
        assert issubclass(cls, nc.InputError) and issubclass(cls, ValueError), cls
    for bad in ({"element": "foo"}, {"maxh": -1.0}, {"qp_solver": "foo"}, {"friction_method": "foo"}):
        with pytest.raises(nc.InputError):
            nc.SolveOptions.of(**bad)


def test_a_point_force_beyond_double_precision_is_refused_when_the_scene_is_read():
    import ngcrack as nc

    d = nc.scenes.load("three-point-bend").to_dict()
    d["point"][-1]["value"] = [0.0, -1e300]
    with pytest.raises(nc.SceneError, match=r"point\[2\]\.value = \[0, -1e\+300\]: out of range"):
        nc.Scene.from_dict(d)
