"""Execute every notebook in a real Jupyter kernel (nbclient, ipykernel's python3) and fail on any error.

The notebooks are jupytext py:percent sources (notebooks/*.py); each is read with
jupytext, run with NGCRACK_QUICK=1 (small meshes) in a fresh temporary folder, and must
print its conclusion. The fastest runs in the default suite, the others are marked slow
when they take long (see NOTEBOOKS).
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest

jupytext = pytest.importorskip("jupytext")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")

NOTEBOOK_DIR = Path(__file__).resolve().parent.parent / "notebooks"
#: (notebook, what its last cell must print, slow?)
NOTEBOOKS = [
    ("01-paper-reproduction.py", "paper-2, bdm: rates in dof", False),
    ("02-h-sweep.py", "Griffith opening, bdm: error", False),
    ("03-nu-sweep.py", "Mixed elements: every error grows by at most", False),
    ("04-error-vs-runtime.py", "the fastest solve is", False),
    ("05-contact-teaching.py", "Compression: the crack closes", False),
    ("06-stability.py", "Scaling laws hold to", False),
    ("07-fracture.py", "Compression with contact: |K_I| <=", False),
    ("09-explore.py", "Unilateral contact: closed over", False),
    ("08-friction.py", "Friction: the inclined crack slips below", False),
    ("10-adaptivity.py", "Adaptive bdm: sliding error", False),
    ("11-crack-growth.py", "Wing cracks: start at lambda within", False),
    ("12-penny.py", "Penny: K_I within", True),
    ("13-hydraulic-fracture.py", "KGD: l, p and w0 within", False),
    ("14-bending-and-holes.py", "Bending and holes: the reactions balance the load", False),
]

#: how many figures a notebook shows (a figure saved to a file must not switch the backend
#: and blank the ones after it: a missing figure fails here)
FIGURES = {"11-crack-growth.py": 4, "14-bending-and-holes.py": 3}


def test_every_notebook_is_listed():
    assert sorted(p.name for p in NOTEBOOK_DIR.glob("[0-9][0-9]-*.py")) == sorted(n for n, _, _ in NOTEBOOKS)


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
    text = _outputs(nb)
    assert conclusion in text, text[-2000:]
    # every plot cell produced an image
    images = sum(1 for c in nb.cells for o in c.get("outputs", []) if "image/png" in o.get("data", {}))
    assert images >= 1
    if name in FIGURES:
        assert images == FIGURES[name], f"{name}: {images} figures shown, {FIGURES[name]} expected"
