"""The GetFEM peer comparison's bookkeeping (benchmarks/getfem_peer.py, benchmarks/peer_quotes.py),
without GetFEM: the target table's selection rule and the documents' quotes of one run.

- a family (one configuration on its mesh ladder) reaches a target at a mesh only when that
  mesh and every finer mesh of the family stay within it: an error that dips below the target
  and rises above it on the next finer mesh does not count;
- the quotes: every document named holds marker pairs, rewriting fills them and leaves every
  other line alone, and once a run made by the current script is saved (its rows carry the
  command and the times), every document quotes exactly that run.
"""

from __future__ import annotations

import importlib
import json
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def pq():
    env = dict(os.environ)
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        yield importlib.import_module("peer_quotes")
    finally:
        sys.path.remove(str(ROOT / "benchmarks"))
        os.environ.clear()  # getfem_peer sets its children's thread counts at import
        os.environ.update(env)


def _row(code, options, level, K, profile, cpu, scene="griffith"):
    return {"scene": scene, "code": code, "options": options, "level": level, "unknowns": 1000 * (level + 1),
            "cpu": cpu, "cpu_whole": cpu + 0.2, "K": K, "profile": profile, "profile_mid": None}


def test_a_target_counts_only_where_every_finer_mesh_stays_within_it(pq):
    gp = pq.gp
    rows = [_row("GetFEM P2 XFEM", f"h={h} enrich=0.5a R=0.5a", i, K, 1e-3, cpu)
            for i, (h, K, cpu) in enumerate([(0.4, 1e-2, 0.1), (0.2, 2e-3, 0.2), (0.1, 4e-3, 0.4), (0.05, 1e-3, 0.8)])]
    # 3e-3: the h = 0.2 run dips below it, h = 0.1 rises above: only h = 0.05 counts
    assert gp.cheapest(rows, "GetFEM", "K", 3e-3, "cpu")["options"].startswith("h=0.05")
    assert gp.cheapest(rows, "GetFEM", "K", 5e-3, "cpu")["options"].startswith("h=0.2")
    assert gp.cheapest(rows, "GetFEM", "K", 5e-4, "cpu") is None
    # another family's finer meshes do not judge this one
    other = [_row("GetFEM P2 XFEM", "h=0.4 enrich=0.2a R=0.2a", 0, 2e-3, 1e-3, 0.05),
             _row("GetFEM P2 XFEM", "h=0.2 enrich=0.2a R=0.2a", 1, 9e-3, 1e-3, 0.1)]
    assert gp.family(other[0]) != gp.family(rows[0])
    assert gp.cheapest(rows + other, "GetFEM", "K", 3e-3, "cpu")["options"].startswith("h=0.05")
    ng = [_row("ngcrack tdnns", f"order=2 maxh={m} crack_h=0.1 tip_h=0.01", i, K, 1e-3, cpu)
          for i, (m, K, cpu) in enumerate([(4, 2e-3, 0.1), (2, 1e-3, 0.2)])]
    assert gp.family(ng[0]) == gp.family(ng[1]) == "ngcrack tdnns order=2"
    assert gp.cheapest(ng, "ngcrack", "K", 3e-3, "cpu")["cpu"] == 0.1


def test_rewriting_fills_the_markers_and_nothing_else(pq):
    # errors far below every target (the references' floor then their stated uncertainty): every target judged
    rows = [_row("GetFEM P2 XFEM", "h=0.2 enrich=0.5a R=0.5a", 0, 1e-7, 1e-7, 0.3),
            _row("ngcrack tdnns", "order=2 maxh=4 crack_h=0.1 tip_h=0.01", 0, 1e-7, 1e-7, 0.1)]
    rows = [dict(r, scene=s) for s in pq.gp.SCENES for r in rows]
    data = {"load": [0.2, 0.4], "run": {"command": "python benchmarks/getfem_peer.py --quick", "started": "2026-12-03 07:00",
                                        "ended": "07:05"}, "rows": rows}
    text = "before\n<!-- peer:summary -->\nold\n<!-- /peer:summary -->\nbetween 3.2-8.0\n<!-- peer:run -->\nx\n<!-- /peer:run -->\nafter\n"
    out = pq.rewrite(text, data)
    assert out.startswith("before\n<!-- peer:summary -->\nGetFEM's CPU over ngcrack's")
    assert "\nbetween 3.2-8.0\n" in out and out.endswith("<!-- /peer:run -->\nafter\n")
    assert "2026-12-03 07:00-07:05 UTC, 1-minute load average 0.2-0.4" in out
    # GetFEM 0.3 s against ngcrack's 0.1 s at every judged target: the ratio 3.0, whole 0.5 / 0.3
    assert "griffith K_I 3.0, opening 3.0" in out and "griffith K_I 1.7, opening 1.7" in out
    assert "over the judged targets (K_I from 1% to 0.001%; opening from 1% to " in out
    assert pq.rewrite(out, data) == out
    for doc in pq.DOCUMENTS:
        assert pq.MARKED.search((ROOT / doc).read_text(encoding="utf-8")), doc


def test_the_documents_quote_the_saved_run(pq):
    saved = ROOT / "benchmarks" / "figures" / "peer.json"
    data = json.loads(saved.read_text())
    if "run" not in data:
        pytest.skip("the saved rows predate the fair peer (no command and times): the re-measured run is pending")
    for doc in pq.DOCUMENTS:
        text = (ROOT / doc).read_text(encoding="utf-8")
        assert pq.rewrite(text, data) == text, f"{doc} does not quote {saved.name}: run benchmarks/peer_quotes.py"
