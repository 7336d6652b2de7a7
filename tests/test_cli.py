"""Tests of the `ngcrack` command: solve, sweep and paper.

- bad input exits with code 2, prints one line naming the field and the allowed values,
  and leaves no output file;
- `solve --json` writes exactly the keys of its documented contract (README, "Command line");
- `sweep` writes its CSV, prints the table and rates, resumes without duplicating rows,
  runs with --jobs and --dask;
- `paper` writes every table and figure it announces (a small version by default; the
  real `--quick` run is marked slow).
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from ngcrack.shell.cli import main
from ngcrack.studies.sweeps import QUANTITIES, ROW_COLUMNS, read_results


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def files_in(path: Path) -> list[Path]:
    return sorted(p for p in path.rglob("*") if p.is_file())


# ----------------------------------------------------------------------- solve
SOLVE_BAD = [
    (["solve", "paper-2", "--nu", "0.7"], "nu"),
    (["solve", "no-such-scene"], "scene"),
    (["solve", "paper-2", "--element", "xyz"], "--element"),
    (["solve", "paper-2", "--maxh", "0.3", "--json", "{tmp}/missing/out.json"], "does not exist"),
    (["solve", "paper-2", "--maxh", "0.3", "--plot", "{tmp}/out.pdf"], ".png"),
    (["solve", "paper-2", "--maxh", "-1"], "maxh"),
]


@pytest.mark.parametrize("argv, field", SOLVE_BAD, ids=lambda v: " ".join(v) if isinstance(v, list) else v)
def test_solve_bad_input_exits_2_with_one_line_and_no_file(tmp_path, capsys, argv, field):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    if "--json" not in argv:  # an output that a wrong run might leave behind
        argv += ["--json", str(tmp_path / "out.json")]
    code, out, err = run(argv, capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ngcrack: error:") and field in lines[0], err
    assert files_in(tmp_path) == []


def test_solve_json_has_exactly_the_contract_keys(tmp_path, capsys):
    path = tmp_path / "r.json"
    code, out, err = run(["solve", "paper-2", "--element", "bdm", "--maxh", "0.3", "--json", path], capsys)
    assert code == 0, err
    d = json.loads(path.read_text())
    assert set(d) == {"scene", "element", "maxh", "nu", "E", "ndof", "time_s", "kkt", "kkt_sampled", "tips", "cracks",
                      "error_estimate"}
    assert set(d["error_estimate"]) == {"energy", "relative"}
    assert [(t["crack"], t["end"]) for t in d["tips"]] == [(0, "first"), (0, "last")]
    assert all(set(t) == {"crack", "end", "x", "y", "K_I", "K_II", "G", "T", "closed", "K_I_raw"} for t in d["tips"])
    assert "K_II" in out and "0,first" in out  # the tip table
    assert set(d["ndof"]) == {"total", "global", "contact"}
    assert set(d["time_s"]) == {"total", "mesh", "assemble", "linear", "contact"}
    assert set(d["kkt"]) == set(d["kkt_sampled"]) == {"max_penetration", "max_tension", "complementarity", "friction"}
    assert max(d["kkt"].values()) <= 1e-10
    assert len(d["cracks"]) == 1
    crack = d["cracks"][0]
    assert set(crack) == {"s", "x", "y", "normal_jump", "tangential_jump", "normal_stress", "shear_stress", "state"}
    assert len({len(v) for v in crack.values()}) == 1 and len(crack["s"]) == d["ndof"]["contact"] // 2
    assert (d["scene"], d["element"], d["maxh"], d["nu"], d["E"]) == ("paper-2", "bdm", 0.3, 0.49, 206900.0)
    assert isinstance(d["ndof"]["total"], int) and d["time_s"]["total"] > 0
    assert f"wrote {path}" in out


# ----------------------------------------------------------------------- sweep
SWEEP_BAD = [
    (["sweep", "paper-2", "--element", "xyz", "--maxh", "0.4"], "--element = 'xyz'"),
    (["sweep", "nope", "--element", "bdm", "--maxh", "0.4"], "scene = 'nope'"),
    (["sweep", "paper-2", "--element", "bdm", "--maxh", "0.4", "--nu", "0.7"], "nu"),
    (["sweep", "paper-2", "--element", "bdm", "--maxh", "0.4", "--friction", "0.2", "-1"], "friction"),
    (["sweep", "paper-2", "--element", "bdm", "--maxh", "0"], "--maxh"),
    (["sweep", "paper-2", "--element", "bdm", "--maxh", "0.4", "--jobs", "0"], "--jobs"),
    (["sweep", "paper-2", "--element", "bdm", "--maxh", "0.4", "--jobs", "2", "--dask", "tcp://x:1"], "--dask"),
    (["sweep", "paper-2", "--element", "bdm", "--maxh", "0.4", "--crack-model", "glued"], "--crack-model"),
    (["sweep", "paper-2", "--element", "bdm", "--maxh", "0.4", "--qp-solver", "magic"], "--qp-solver"),
    (["sweep", "paper-2", "--element", "bdm", "--maxh", "0.4", "0.3", "--reference-maxh", "0.35"], "reference_maxh"),
]


@pytest.mark.parametrize("argv, field", SWEEP_BAD, ids=lambda v: " ".join(v[4:]) if isinstance(v, list) else v)
def test_sweep_bad_input_exits_2_with_one_line_and_no_file(tmp_path, capsys, argv, field):
    code, out, err = run(argv + ["--out", tmp_path / "r.csv"], capsys)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ngcrack: error:") and field in lines[0], err
    assert files_in(tmp_path) == []


def test_sweep_output_must_be_a_csv_in_an_existing_folder(tmp_path, capsys):
    for out, field in ((tmp_path / "no" / "r.csv", "does not exist"), (tmp_path / "r.txt", ".csv")):
        code, _, err = run(["sweep", "paper-2", "--element", "bdm", "--maxh", "0.4", "--out", out], capsys)
        assert code == 2 and field in err
    assert files_in(tmp_path) == []


def test_sweep_writes_prints_and_resumes(tmp_path, capsys):
    out = tmp_path / "r.csv"
    argv = ["sweep", "paper-2", "--element", "peers", "bdm", "--maxh", "0.3", "0.25", "--nu", "0.3", "0.49",
            "--reference-maxh", "0.2", "--out", out, "--no-progress"]
    code, text, err = run(argv, capsys)
    assert code == 0, err
    df = read_results(out)
    tips = [f"{q}[0,{end}]" for end in ("first", "last") for q in ("K_I", "K_II", "G")]
    assert list(df.columns) == list(ROW_COLUMNS) + tips and len(df) == 8
    assert "fitted rates" in text and "(8 new rows, 8 in the file)" in text
    for q in QUANTITIES:
        assert f"err_{q}" in text
    before = out.read_bytes()
    code, text, _ = run(argv, capsys)
    assert code == 0 and "(0 new rows, 8 in the file)" in text and out.read_bytes() == before
    code, text, _ = run(argv[:6] + ["0.22"] + argv[6:], capsys)  # one more mesh size
    assert code == 0 and "(4 new rows, 12 in the file)" in text
    df = read_results(out)
    assert out.read_bytes().startswith(before)
    assert len(df) == len(df.drop_duplicates(["element", "maxh", "nu"])) == 12


def test_sweep_progress_bar_goes_to_stderr(tmp_path, capsys):
    code, out, err = run(["sweep", "paper-2", "--element", "bdm", "--maxh", "0.4", "--out", tmp_path / "r.csv"], capsys)
    assert code == 0
    assert "sweep paper-2: 1/1 runs" in err and "100%" in err
    assert "runs" not in out


def test_sweep_jobs_and_dask_from_the_command_line(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    common = ["sweep", "paper-2", "--element", "peers", "bdm", "--maxh", "0.3", "0.25", "--no-progress"]
    code, _, err = run(common + ["--out", tmp_path / "j.csv", "--jobs", "2"], capsys)
    assert code == 0, err
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        code, _, err = run(common + ["--out", tmp_path / "d.csv", "--dask", cluster.scheduler_address], capsys)
    assert code == 0, err
    a = read_results(tmp_path / "j.csv").sort_values(["element", "maxh"]).reset_index(drop=True)
    b = read_results(tmp_path / "d.csv").sort_values(["element", "maxh"]).reset_index(drop=True)
    cols = ["element", "maxh", "ndof_total"] + [f"err_{q}" for q in QUANTITIES]
    pd.testing.assert_frame_equal(a[cols], b[cols], rtol=1e-9)


def test_sweep_dask_unreachable_scheduler_is_a_usage_error(tmp_path, capsys, monkeypatch):
    pytest.importorskip("distributed")
    monkeypatch.setattr("ngcrack.studies.sweeps.executors.DASK_CONNECT_TIMEOUT", "2s")
    code, _, err = run(["sweep", "paper-2", "--element", "bdm", "--maxh", "0.4", "--out", tmp_path / "r.csv",
                        "--dask", "tcp://127.0.0.1:9", "--no-progress"], capsys)
    assert code == 2 and "cannot connect" in err
    assert files_in(tmp_path) == []


# ----------------------------------------------------------------------- paper
ANNOUNCED = re.compile(r"^wrote (.+)$", re.M)


def check_paper_output(out_dir: Path, text: str, elements: list[str], n_rows: int) -> list[Path]:
    """Every announced file exists and is what it claims; returns them."""
    from matplotlib.image import imread

    paths = [Path(p) for p in ANNOUNCED.findall(text)]
    kinds = {p.suffix for p in paths}
    assert kinds == {".csv", ".md", ".png"}
    assert sorted(paths) == sorted(p for p in files_in(out_dir) if p.suffix in kinds)
    names = {p.name for p in paths}
    for k, q in enumerate(QUANTITIES, start=1):
        assert {f"table{k}_{q}.csv", f"table{k}_{q}.md", f"time_{q}.png"} <= names
    for k, stem in enumerate(["paper-1_displacement", "paper-1_stress", "paper-2_displacement", "paper-2_stress",
                              "paper-1_sigma_nu", "paper-2_sigma_nu"], start=3):
        assert f"fig{k}_{stem}.png" in names
    for p in paths:
        assert p.stat().st_size > 0
        if p.suffix == ".png":
            img = imread(p)
            assert img.shape[0] > 400 and img.shape[1] > 600 and img.std() > 0.01, p  # a real picture
    for k, q in enumerate(QUANTITIES, start=1):
        t = pd.read_csv(out_dir / f"table{k}_{q}.csv")
        assert list(t.columns) == ["scene", "element", "maxh", "h", "dof", "error", "estimate", "rate_dof", "rate_h",
                                   "time_s", "cpu_s", "memory_mb"]
        assert len(t) == 2 * len(elements) * n_rows and set(t.element) == set(elements)
        assert (t.error > 0).all() and (t.time_s > 0).all() and (t.cpu_s > 0).all()
        md = (out_dir / f"table{k}_{q}.md").read_text()
        assert md.startswith(f"## Table {k}: {q}") and md.count("\n|") == len(t) + 2
    rates = pd.read_csv(out_dir / "rates.csv")
    assert len(rates) == 2 * len(elements) * len(QUANTITIES)
    return paths


def test_paper_small_writes_everything_it_announces(tmp_path, capsys):
    out = tmp_path / "paper"
    t0 = time.perf_counter()
    code, text, err = run(["paper", "--out", out, "--element", "peers", "bdm", "--maxh", "0.3", "0.25",
                           "--reference-maxh", "0.2", "--no-progress"], capsys)
    assert code == 0, err
    paths = check_paper_output(out, text, ["peers", "bdm"], 2)
    assert "paper-2: fitted rates in dof" in text
    with capsys.disabled():
        print(f"[cli] paper (small): {len(paths)} files in {time.perf_counter() - t0:.1f} s")
    # a second run resumes from the sweeps' CSVs and rewrites the same files
    code, text2, _ = run(["paper", "--out", out, "--element", "peers", "bdm", "--maxh", "0.3", "0.25",
                          "--reference-maxh", "0.2", "--no-progress"], capsys)
    assert code == 0 and ANNOUNCED.findall(text2) == ANNOUNCED.findall(text)


def test_paper_bad_output_folder(tmp_path, capsys):
    code, _, err = run(["paper", "--out", tmp_path / "a" / "b"], capsys)
    assert code == 2 and "does not exist" in err
    (tmp_path / "f").write_text("")
    code, _, err = run(["paper", "--out", tmp_path / "f"], capsys)
    assert code == 2 and "not a directory" in err


@pytest.mark.slow
def test_paper_quick_runs_in_time_and_writes_everything(tmp_path):
    """The README's main job, as a user runs it (a fresh process, the installed command)."""
    out = tmp_path / "quick"
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "ngcrack.shell.cli", "paper", "--quick", "--out", str(out)],
                          capture_output=True, text=True, timeout=600)
    elapsed = time.perf_counter() - t0
    assert proc.returncode == 0, proc.stderr
    from ngcrack.studies.paper import mixed_elements

    check_paper_output(out, proc.stdout, mixed_elements(), 3)
    print(f"[cli] paper --quick: {elapsed:.0f} s")  # (its time goes to BENCHMARKS, not into a threshold)


def test_solve_order_is_passed_and_checked(tmp_path):
    """--order reaches tdnns; an element of fixed order refuses it with exit code 2 and no file."""
    from ngcrack.shell.cli import main

    out = tmp_path / "t.json"
    assert main(["solve", "paper-2", "--element", "tdnns", "--order", "2", "--maxh", "0.2", "--json", str(out)]) == 0
    data = json.loads(out.read_text())
    assert data["element"] == "tdnns" and data["kkt"]["max_penetration"] <= 1e-6
    bad = tmp_path / "u.json"
    assert main(["solve", "paper-2", "--element", "peers", "--order", "2", "--json", str(bad)]) == 2
    assert not bad.exists()


def test_stability_refuses_a_missing_folder(tmp_path, capsys):
    from ngcrack.shell.cli import main

    assert main(["stability", "--quick", "--out", str(tmp_path / "no" / "such")]) == 2
    assert "--out" in capsys.readouterr().err


def test_help_texts_stand_alone():
    """No help text sends the reader to a file a user of the package does not have."""
    import pydoc

    import ngcrack
    from ngcrack.shell.cli import build_parser

    parser = build_parser()
    texts = {"ngcrack": parser.format_help()}
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, p in sub.choices.items():
        texts[name] = p.format_help()
    for mod in ("ngcrack", "ngcrack.core.solve", "ngcrack.core.contact", "ngcrack.planar.post", "ngcrack.shell.cli", "ngcrack.planar.scene",
                "ngcrack.scenes", "ngcrack.studies.sweeps"):
        texts[mod] = pydoc.render_doc(__import__(mod, fromlist=["_"]), renderer=pydoc.plaintext)
    texts["solve()"] = ngcrack.core.solve.__doc__
    for name, text in texts.items():
        for other in ("DESIGN" + ".md", "STYLE" + ".md"):
            assert other not in text, f"{name}: help refers to {other}"
    assert "tdnns (default)" in texts["solve"]
    assert "README" in texts["solve"]


def test_solve_and_sweep_default_to_tdnns(tmp_path, capsys):
    code, out, err = run(["solve", "paper-2", "--maxh", "0.4", "--json", tmp_path / "r.json"], capsys)
    assert code == 0, err
    assert json.loads((tmp_path / "r.json").read_text())["element"] == "tdnns"
    assert "KKT at the constraint points" in out and "at the edge mid points" in out
    code, out, err = run(["sweep", "paper-2", "--maxh", "0.4", "--out", tmp_path / "s.csv", "--no-progress"], capsys)
    assert code == 0, err
    assert set(read_results(tmp_path / "s.csv")["element"]) == {"tdnns"}
