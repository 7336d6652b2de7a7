"""Quote one run of benchmarks/getfem_peer.py in the documents: every number from that run's rows.

    python benchmarks/peer_quotes.py [benchmarks/figures/peer.json] [--check]

Reads the rows that getfem_peer.py saved beside its figure (peer.json: the rows, the load
average, the command, its start and end) and rewrites, from them alone:

- benchmarks/figures/peer.md: the run's full output (every row, every target);
- between marker comments, each on its own line, in README.md, the performance and elements
  guides and BENCHMARKS.md (`<!-- peer:KIND -->` ... `<!-- /peer:KIND -->`), KIND one of
  `run` (the date, the UTC times and the load average),
  `command` (the command that made the rows: BENCHMARKS only, the site's guides name no script),
  `table` (the judged targets: each code's cheapest run, both CPU columns, the ratios),
  `summary` (the ratios GetFEM / ngcrack per scene and quantity, as ranges over the judged targets).

Every file named must hold at least one marker pair, and every pair is rewritten, so the three
documents quote the same run exactly. --check: write nothing, exit 1 when a file would change.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

import getfem_peer as gp  # noqa: E402

#: the documents that quote the run, from the repository's root
DOCUMENTS = ["README.md", "docs/guide/performance.md", "docs/guide/elements.md", "BENCHMARKS.md"]
#: a marked region: <!-- peer:KIND --> ... <!-- /peer:KIND -->
MARKED = re.compile(r"(<!-- peer:(\w+) -->)(.*?)(<!-- /peer:\2 -->)", re.S)
#: the quantity names as the documents write them
QUANTITY = {("griffith", "K"): "K_I", ("griffith", "profile"): "opening",
            ("inclined-compression", "K"): "K_II", ("inclined-compression", "profile"): "sliding"}


def _getfem_label(r: dict) -> str:
    """'h=0.2 enrich=0.5a R=0.5a' -> 'h=0.2, radii 0.5a'."""
    h, enrich, _radius = r["options"].split()
    return f"{h}, radii {enrich.split('=')[1]}"


def _ngcrack_label(r: dict) -> str:
    return f"{r['code'][len('ngcrack '):]} {r['options']}"


def targets(rows: list[dict]) -> list[dict]:
    """The judged targets: per scene, quantity and target the cheapest GetFEM and ngcrack runs
    (in-process and whole process, by getfem_peer's rule) and their ratios."""
    fl = gp.floors(rows)
    out = []
    for name in gp.SCENES:
        sub = [r for r in rows if r["scene"] == name]
        for qty in ("K", "profile"):
            for tgt in gp.TARGETS:
                if tgt < gp.FLOOR_FACTOR * fl[(name, qty)]:
                    continue
                t = {"scene": name, "qty": qty, "target": tgt}
                for column in ("cpu", "cpu_whole"):
                    g, n = gp.cheapest(sub, "GetFEM", qty, tgt, column), gp.cheapest(sub, "ngcrack", qty, tgt, column)
                    t[column] = (g, n, g[column] / n[column] if g and n else None)
                out.append(t)
    return out


def _ratio(x: float | None) -> str:
    return f"{x:.1f}" if x is not None else ""


def _cell(r: dict | None, column: str, label) -> str:
    if r is None:
        return "not reached"
    return f"{r[column]:.2f}" + (f" ({label(r)})" if column == "cpu" else "")


def table(rows: list[dict]) -> str:
    n_ng = len({gp.family(r) for r in rows if not r["code"].startswith("GetFEM")})
    lines = [f"| scene | target | GetFEM, in-process s | ngcrack, in-process s (best of {n_ng}) | GetFEM / ngcrack | "
             "GetFEM, whole process s | ngcrack, whole process s | GetFEM / ngcrack |",
             "|---|---|---|---|---:|---:|---:|---:|"]
    for t in targets(rows):
        (g, n, ratio), (gw, nw, ratio_w) = t["cpu"], t["cpu_whole"]
        lines.append(f"| {t['scene']} | {QUANTITY[(t['scene'], t['qty'])]} within {100 * t['target']:g}% | "
                     f"{_cell(g, 'cpu', _getfem_label)} | {_cell(n, 'cpu', _ngcrack_label)} | {_ratio(ratio)} | "
                     f"{_cell(gw, 'cpu_whole', None)} | {_cell(nw, 'cpu_whole', None)} | {_ratio(ratio_w)} |")
    return "\n".join(lines)


def ranges(rows: list[dict]) -> dict[tuple[str, str, str], tuple[float, float] | None]:
    """(scene, qty, column) -> (least, largest) ratio GetFEM / ngcrack over the judged targets
    that both reach (as printed: one decimal)."""
    out: dict = {}
    for t in targets(rows):
        for column in ("cpu", "cpu_whole"):
            ratio = t[column][2]
            if ratio is None:
                continue
            key = (t["scene"], t["qty"], column)
            lo, hi = out.get(key, (ratio, ratio))
            out[key] = (min(lo, ratio), max(hi, ratio))
    return out


def _span(r) -> str:
    if r is None:
        return "not measured"
    lo, hi = (f"{x:.1f}" for x in r)
    return lo if lo == hi else f"{lo}-{hi}"


def summary(rows: list[dict]) -> str:
    rg = ranges(rows)
    judged: dict = {}
    for t in targets(rows):
        judged.setdefault((t["scene"], t["qty"]), []).append(t["target"])
    parts = []
    for column, what in (("cpu", "in-process"), ("cpu_whole", "as a whole process")):
        scenes = []
        for name in gp.SCENES:
            qs = ", ".join(f"{QUANTITY[(name, q)]} {_span(rg.get((name, q, column)))}" for q in ("K", "profile"))
            scenes.append(f"{name} {qs}")
        parts.append(f"{what} {'; '.join(scenes)}")
    within = "; ".join(f"{QUANTITY[key]} from {100 * max(ts):g}% to {100 * min(ts):g}%" for key, ts in judged.items())
    return ("GetFEM's CPU over ngcrack's to reach the same accuracy (above 1 where ngcrack is cheaper), "
            f"over the judged targets ({within}): " + "; ".join(parts) + ".")


def run_line(data: dict) -> str:
    run, load = data.get("run", {}), data["load"]
    when = f"{run['started']}-{run['ended']} UTC" if run else "time not recorded"
    return f"{when}, 1-minute load average {min(load):.1f}-{max(load):.1f} during the run"


def command_line(data: dict) -> str:
    return f"`{data['run']['command']}`" if data.get("run") else "(command not recorded)"


def full_output(data: dict) -> str:
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        gp.report(data["rows"], data["load"])
    return (f"Output of the quoted run, {command_line(data)} ({run_line(data)}; CPU s, one thread, cold, least over "
            "the passes)\n\n" + buf.getvalue())


def rewrite(text: str, data: dict) -> str:
    rows = data["rows"]
    content = {"run": run_line(data), "command": command_line(data), "table": table(rows), "summary": summary(rows)}

    def fill(m: re.Match) -> str:
        kind = m.group(2)
        if kind not in content:
            raise SystemExit(f"unknown marker <!-- peer:{kind} -->: one of {sorted(content)}")
        return f"{m.group(1)}\n{content[kind]}\n{m.group(4)}"

    return MARKED.sub(fill, text)


def main() -> None:
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    check = "--check" in sys.argv
    src = Path(args[0]) if args else HERE / "figures" / "peer.json"
    data = json.loads(src.read_text())
    outputs = {src.with_suffix(".md"): full_output(data)}
    for doc in DOCUMENTS:
        path = ROOT / doc
        text = path.read_text(encoding="utf-8")
        if not MARKED.search(text):
            raise SystemExit(f"{doc}: no <!-- peer:KIND --> marker pair")
        outputs[path] = rewrite(text, data)
    changed = [p for p, t in outputs.items() if not p.exists() or p.read_text(encoding="utf-8") != t]
    if check:
        print("\n".join(f"would change: {p.relative_to(ROOT) if p.is_relative_to(ROOT) else p}" for p in changed) or "up to date")
        sys.exit(1 if changed else 0)
    for p, t in outputs.items():  # every text made before any is written
        tmp = p.with_name(p.name + ".tmp")
        tmp.write_text(t, encoding="utf-8")
        tmp.replace(p)
    print(summary(data["rows"]))
    print("rewritten: " + ", ".join(str(p.relative_to(ROOT)) if p.is_relative_to(ROOT) else str(p) for p in outputs))


if __name__ == "__main__":
    main()
