"""What `import ngcrack`, `ngcrack --help` and a solve load: sets of modules, not times.

`import ngcrack` imports its public names on first use (PEP 562), so the package alone
loads nothing but itself; the command line's parser loads no numerics; a plain 2D solve
loads NGSolve and numpy but none of the optional parts (pandas, widgets, cvxpy, meshio,
dask, jupytext, matplotlib), nor scipy.sparse (its condensed system is `ngcrack.core.csr`,
numpy alone) nor shapely (the scene's planar checks). benchmarks/startup.py prints the
times.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

import ngcrack as nc
from ngcrack.shell.cli_errors import EXIT_INPUT, classify
from ngcrack.shell.extras import EXTRAS, missing_extra, require

#: what no solve needs: the extras and the heavy packages of plots and other QP solvers
NOT_FOR_A_SOLVE = {"pandas", "tqdm", "ipywidgets", "IPython", "jupytext", "meshio", "dask", "distributed",
                   "matplotlib", "cvxpy", "clarabel", "cholespy"}


def _loaded(code: str) -> set[str]:
    """The modules that `code` adds to a bare interpreter's."""
    probe = "import json, sys; before = set(sys.modules); {code}; print(json.dumps(sorted(set(sys.modules) - before)))"
    out = subprocess.run([sys.executable, "-c", probe.format(code=code)], capture_output=True, text=True, check=True)
    return set(json.loads(out.stdout.splitlines()[-1]))


def _top(modules: set[str]) -> set[str]:
    return {m.split(".")[0] for m in modules}


def test_import_ngcrack_loads_only_the_package():
    loaded = _loaded("import ngcrack")
    assert {m for m in loaded if m.startswith("ngcrack")} == {"ngcrack"}
    assert not _top(loaded) & (NOT_FOR_A_SOLVE | {"ngsolve", "netgen", "numpy", "scipy", "shapely"})


def test_the_command_line_parser_loads_no_numerics():
    loaded = _loaded("from ngcrack.shell.cli import build_parser; build_parser().format_help()")
    assert not _top(loaded) & (NOT_FOR_A_SOLVE | {"ngsolve", "netgen", "numpy", "scipy", "shapely"})
    grown = {m for m in loaded if m.startswith("ngcrack.studies.growth.") and m != "ngcrack.studies.growth.criteria"}
    assert not grown - {"ngcrack.studies.growth.cli"}


def test_a_solve_loads_no_optional_part():
    loaded = _loaded("import ngcrack as nc; sol = nc.solve('griffith', maxh=4, tip_h=0.05, crack_h=0.2); sol.tips; "
                     "sol.crack_profiles(); sol.error_estimate")
    assert {"ngsolve", "numpy"} <= _top(loaded)
    assert not _top(loaded) & NOT_FOR_A_SOLVE
    assert not {"ngcrack.shell.explorer", "ngcrack.studies.sweeps", "ngcrack.studies.growth", "ngcrack.studies.paper",
                "ngcrack.planar.plots"} & loaded
    # scipy.sparse costs 0.08-0.11 s of CPU at import (scipy 1.17 builds an array-API copy
    # of numpy, loading numpy.f2py and numpy.testing), scipy.linalg loads its own BLAS: only
    # friction, point supports, superlu, large dense QPs and the 3D paths need scipy
    assert not {"scipy", "shapely"} & _top(loaded)
    assert not {m for m in loaded if m.startswith(("numpy.f2py", "numpy.testing"))}


def test_a_plain_griffith_solve_loads_neither_scipy_sparse_nor_shapely():
    """What the command-line user's cheapest griffith run loads (the peer benchmark's first
    mesh): scipy.sparse and shapely cost 0.09-0.13 s of CPU at import together, as much as
    the solve; numpy.ma (0.02 s, loaded by np.unique) is not needed either."""
    loaded = _loaded("import ngcrack as nc; nc.solve('griffith', maxh=4, crack_h=0.5, tip_h=0.005, grading=0.5, "
                     "order=2)")
    assert not {"scipy", "shapely"} & _top(loaded)
    assert not {"numpy.ma", "numpy.f2py", "numpy.testing", "numpy.random"} & loaded


def test_the_solve_command_loads_no_sweeps(tmp_path):
    out = tmp_path / "g.json"
    loaded = _loaded("from ngcrack.shell.cli import main; main(['solve', 'griffith', '--maxh', '4', '--tip-h', '0.05', "
                     f"'--crack-h', '0.2', '--json', {str(out)!r}])")
    assert out.exists()
    assert not {m for m in loaded if m.startswith(("ngcrack.studies.sweeps", "multiprocessing", "concurrent.futures.process"))}
    assert not _top(loaded) & NOT_FOR_A_SOLVE


def test_every_public_name_resolves():
    for name in nc.__all__:
        assert getattr(nc, name) is not None
    assert set(nc.__all__) <= set(dir(nc))
    assert nc.tips.__name__ == "ngcrack.planar.tips"  # a submodule, on first use
    with pytest.raises(AttributeError, match="no attribute 'no_such_name'"):
        nc.no_such_name  # noqa: B018


def test_a_function_stays_the_function_after_its_module_is_imported():
    code = ("import ngcrack as nc, ngcrack.core.pipeline; import ngcrack.core.solve; from ngcrack import solve; "
            "import ngcrack.studies.hydrofrac.cli; "
            "print(callable(nc.solve) and nc.solve is solve and nc.solve.__module__ == 'ngcrack.core.solve' "
            "and callable(nc.hydrofrac) and nc.hydrofrac.__module__ == 'ngcrack.studies.hydrofrac.loop')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "True"


@pytest.mark.parametrize("package", sorted(EXTRAS))
def test_a_missing_optional_package_names_its_extra(package):
    exc = ModuleNotFoundError(f"No module named '{package}'", name=package)
    assert f"ngcrack[{EXTRAS[package]}]" in missing_extra(exc)
    wrapped = RuntimeError("sweep failed")
    wrapped.__cause__ = exc
    code, text = classify(wrapped)
    assert code == EXIT_INPUT and f"pip install 'ngcrack[{EXTRAS[package]}]'" in text


def test_other_missing_modules_are_not_an_extra():
    assert missing_extra(ModuleNotFoundError("No module named 'nothere'", name="nothere")) is None
    assert missing_extra(ValueError("x")) is None


def test_require_refuses_a_missing_package_before_any_work(monkeypatch):
    require("numpy", "a solve")  # installed: nothing happens
    monkeypatch.setitem(EXTRAS, "ngcrack_no_such_package", "vtk")
    with pytest.raises(ModuleNotFoundError) as info:
        require("ngcrack_no_such_package", "--vtk")
    assert info.value.name == "ngcrack_no_such_package"
    code, text = classify(info.value)
    assert code == EXIT_INPUT and "pip install 'ngcrack[vtk]'" in text
