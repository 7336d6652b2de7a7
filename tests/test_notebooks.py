"""Execute every notebook in a real Jupyter kernel (nbclient, ipykernel's python3) and fail on any error.

The notebooks are jupytext py:percent sources (notebooks/*.py); each is read with
jupytext, run with NGCRACK_QUICK=1 (small meshes) in a fresh temporary folder, and must
print its conclusion. Every notebook ends by asserting its conclusions in numbers (a rate,
an error band against a closed form, KKT residuals at round-off): those `assert` statements
are counted, and every cell holding one must have run. The fastest runs in the default
suite, the others are marked slow when they take long (see NOTEBOOKS); so are the paper's
and the stability study's, whose code the command line's quick runs hold in the default suite
(tests/test_cli.py, tests/test_stability.py).
"""

from __future__ import annotations

import ast
import time
from pathlib import Path

import pytest

jupytext = pytest.importorskip("jupytext")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

NOTEBOOK_DIR = Path(__file__).resolve().parent.parent / "notebooks"
#: (notebook, what its last cell must print, slow?)
NOTEBOOKS = [
    ("01-paper-reproduction.py", "paper-2, bdm: rates in dof", True),
    ("02-h-sweep.py", "Griffith opening, bdm: error", False),
    ("03-nu-sweep.py", "Mixed elements: every error grows by at most", False),
    ("04-error-vs-runtime.py", "the fastest solve is", False),
    ("05-contact-teaching.py", "Compression: the crack closes", False),
    ("06-stability.py", "Scaling laws hold to", True),
    ("07-fracture.py", "Compression with contact: |K_I| <=", False),
    ("09-explore.py", "Unilateral contact: closed over", False),
    ("08-friction.py", "Friction: the inclined crack slips below", False),
    ("10-adaptivity.py", "Adaptive bdm: sliding error", False),
    ("11-crack-growth.py", "Wing cracks: start at lambda within", True),
    ("12-penny.py", "Penny: K_I within", True),
    ("13-hydraulic-fracture.py", "KGD: l, p and w0 within", True),
    ("14-bending-and-holes.py", "Bending and holes: the reactions balance the load", True),
    ("15-fatigue-3d.py", "Elliptical fatigue crack: b/a rises", True),
    ("16-surface-fatigue.py", "Surface fatigue crack: a/c", True),
]

#: how many figures a notebook shows (a figure saved to a file must not switch the backend
#: and blank the ones after it: a missing figure fails here)
FIGURES = {"11-crack-growth.py": 4, "14-bending-and-holes.py": 3}


#: the fewest `assert` statements a notebook's conclusions may have
MIN_ASSERTIONS = 3


def test_every_notebook_is_listed():
    assert sorted(p.name for p in NOTEBOOK_DIR.glob("[0-9][0-9]-*.py")) == sorted(n for n, _, _ in NOTEBOOKS)


def _assertions(source: str) -> int:
    """The `assert` statements of a code cell (IPython's magics and shell lines left out)."""
    code = "\n".join(line for line in source.splitlines() if not line.lstrip().startswith(("%", "!")))
    return sum(isinstance(node, ast.Assert) for node in ast.walk(ast.parse(code)))


def test_every_notebook_asserts_its_conclusions():
    """Each notebook checks its conclusions in numbers, and the last of its code cells that
    asserts comes after the cell printing the conclusion (it checks what the reader was told)."""
    counts = {}
    for name, _, _ in NOTEBOOKS:
        cells = [c for c in jupytext.read(NOTEBOOK_DIR / name).cells if c.cell_type == "code"]
        per_cell = [_assertions(c.source) for c in cells]
        counts[name] = sum(per_cell)
        assert per_cell[-1] > 0 or per_cell[-2] > 0, f"{name}: its last cells assert nothing"
    print(f"[notebooks] {sum(counts.values())} assertions: {counts}")
    assert {n: k for n, k in counts.items() if k < MIN_ASSERTIONS} == {}


def _outputs(nb) -> str:
    text = []
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream":
                text.append(out.get("text", ""))
    return "".join(text)


@pytest.mark.parametrize("name, conclusion", [
    pytest.param(n, c, marks=[pytest.mark.slow] if slow else [], id=n) for n, c, slow in NOTEBOOKS])
def test_notebook_runs_clean(name, conclusion, tmp_path, monkeypatch):
    monkeypatch.setenv("NGCRACK_QUICK", "1")
    monkeypatch.setenv("MPLBACKEND", "module://matplotlib_inline.backend_inline")
    nb = jupytext.read(NOTEBOOK_DIR / name)
    t0 = time.perf_counter()
    client = nbclient.NotebookClient(nb, timeout=600, kernel_name="python3", allow_errors=False,
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()  # raises CellExecutionError on the first failing cell
    print(f"[notebooks] {name}: {time.perf_counter() - t0:.1f} s")
    last = nb.cells[-1]
    assert last.cell_type == "code"
    # the tutorials show no warning boxes (a warning that matters is said in a sentence)
    if name < "12":
        stderr = [o.get("text", "") for c in nb.cells for o in c.get("outputs", [])
                  if o.get("output_type") == "stream" and o.get("name") == "stderr"]
        assert stderr == [], stderr[:3]
    # every cell that asserts a conclusion ran (a failing assert raised above)
    asserting = [c for c in nb.cells if c.cell_type == "code" and _assertions(c.source)]
    assert len(asserting) >= 1 and all(c.get("execution_count") for c in asserting)
    print(f"[notebooks] {name}: {sum(_assertions(c.source) for c in asserting)} assertions held")
    text = _outputs(nb)
    assert conclusion in text, text[-2000:]
    # every plot cell produced an image
    images = sum(1 for c in nb.cells for o in c.get("outputs", []) if "image/png" in o.get("data", {}))
    assert images >= 1
    if name in FIGURES:
        assert images == FIGURES[name], f"{name}: {images} figures shown, {FIGURES[name]} expected"
