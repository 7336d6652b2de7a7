"""ngcrack side by side with an XFEM peer (GetFEM): error against CPU time on two closed-form scenes.

    python benchmarks/getfem_peer.py [--quick] [--out benchmarks/figures/peer.png] [--replot]

Needs Debian's python3-getfem for the system Python (/usr/bin/python3; `apt-get install
python3-getfem`); it is not a dependency of ngcrack nor of its tests. The peer runs
benchmarks/getfem_xfem.py in its own process (P2 XFEM with Heaviside and crack-tip
enrichment, K by an interaction integral, crack faces traction free or in unilateral
contact by penalty; see that file); ngcrack runs in this process. Both single-threaded
(NGCRACK_THREADS = OMP_NUM_THREADS = 1), interleaved mesh by mesh, CPU seconds of the
whole solve (mesh, assembly, solve, K and the profile; not the interpreter's start).

Scenes: `griffith` (K_I and the opening) and `inclined-compression` (K_II and the
sliding, crack faces in frictionless contact). Errors against the finite-body references
(ngcrack.references, reproduced by benchmarks/references.py): K, max over the tips of
|K - K_ref| / |K_ref|; profile, relative L2 error of the opening (sliding) along the
crack (ngcrack: edge mid points weighted by the edge lengths; GetFEM: its quadrature on
the level set). Prints one table and the cheapest run of each code per accuracy target;
writes the figure (error against CPU time) and the rows (peer.json beside it; --replot
redraws both from it). Expect +-30% on CPU times (shared machine). The references come
from tdnns solves: errors below their uncertainty (the figure's dotted lines) are not
resolved, least of all tdnns's own.

ngcrack's runs are data (RUNS): add an entry (e.g. {"element": "tdnns", "order": 3,
"hp": 4}) to put a new option in the table and the figure; keys nc.solve does not accept,
and options it refuses (bdm's higher orders before they exist), are skipped with a note.
"""

from __future__ import annotations

import os

for _v in ("NGCRACK_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
    os.environ[_v] = "1"

import json
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import ngcrack as nc
from ngcrack import references
from ngcrack import tips as nctips

HERE = Path(__file__).resolve().parent
PEER = HERE / "getfem_xfem.py"
SYSTEM_PYTHON = "/usr/bin/python3"
SCENES = {"griffith": "free", "inclined-compression": "contact"}
#: ngcrack's mesh ladder: (maxh, crack_h, tip_h), from coarse to fine
#: "scene": the scenes' grading (0.2); "graded": strong grading towards the tips (0.5: the mesh
#: grows fast away from them), a coarse far field and a fine tip (the efficient path at order 3)
MESHES = {
    "scene": [(2.0, 0.1, 0.01, None), (1.0, 0.05, 0.005, None), (0.5, 0.025, 0.001, None), (0.25, 0.0125, 0.0002, None)],
    "graded": [(2.0, 0.2, 0.002, 0.5), (2.0, 0.2, 0.0005, 0.5), (2.0, 0.1, 0.0001, 0.5), (2.0, 0.05, 0.00005, 0.5)],
}
#: GetFEM's ladder: the mesh size h around the crack (graded outside)
GETFEM_H = [0.1, 0.07, 0.05, 0.035, 0.025]
#: the finest h per scene: on inclined-compression at h = 0.025 GetFEM's MUMPS stops with error -9
#: (workspace, ICNTL(14), which its Python interface does not set)
FINEST = {"griffith": 0.025, "inclined-compression": 0.035}
#: ngcrack's options (any of nc.SolveOptions; "mesh": "graded" for the strongly graded ladder)
RUNS = [
    {"element": "bdm"},
    {"element": "tdnns", "order": 1},
    {"element": "tdnns", "order": 2},
    {"element": "tdnns", "order": 3},
    {"element": "tdnns", "order": 2, "mesh": "graded"},
    {"element": "tdnns", "order": 3, "mesh": "graded"},
    {"element": "bdm", "order": 2},
    {"element": "bdm", "order": 3},
    {"element": "tdnns", "order": 3, "hp": 4},
    {"element": "bdm", "order": 3, "hp": 4},
]
#: a run is skipped once its previous mesh had more unknowns than this / 3 (memory, time)
MAX_UNKNOWNS = 1.6e6
#: accuracy targets (quantity, relative error)
#: (the tightest stay above the references' uncertainties: griffith K_I 2e-6, opening 3e-6;
#: inclined-compression K_II 8e-6, sliding 4e-5)
TARGETS = {"griffith": [("K", 1e-4), ("K", 1e-5), ("profile", 3e-4), ("profile", 1e-4), ("profile", 3e-5)],
           "inclined-compression": [("profile", 1e-3), ("profile", 3e-4), ("profile", 1e-4), ("K", 1e-4),
                                    ("K", 2e-5)]}


def options_label(run: dict) -> str:
    label = " ".join(f"{k}={v}" for k, v in run.items() if k not in ("element", "mesh")) or "order=1"
    return label + (" graded" if run.get("mesh") == "graded" else "")


def _option_names() -> set[str]:
    import dataclasses

    return {f.name for f in dataclasses.fields(nc.SolveOptions)}


def accepted(run: dict) -> bool:
    return all(k in _option_names() for k in run if k != "mesh")


def peer_problem(scene, ref, h: float, faces: str) -> dict:
    """The JSON problem of getfem_xfem.py for a rectangular scene with one straight crack."""
    poly = np.asarray(scene.polygon, float)
    (x0, y0), (x1, y1) = poly.min(axis=0), poly.max(axis=0)
    boundary = {}
    for i, (p, q) in enumerate(zip(poly, np.roll(poly, -1, axis=0))):
        side = ("left" if p[0] == q[0] == x0 else "right" if p[0] == q[0] == x1 else
                "bottom" if p[1] == q[1] == y0 else "top" if p[1] == q[1] == y1 else None)
        if side is None:
            raise ValueError(f"scene {scene.name!r}: edge {i} is not on its bounding box (rectangles only)")
        bc = scene.boundary.get(scene.labels[i])
        bc = {"type": "free"} if bc is None else {"type": bc.type, **({"value": list(bc.value)} if bc.value else {})}
        if bc["type"] == "free":
            continue
        if boundary.get(side, bc) != bc:
            raise ValueError(f"scene {scene.name!r}: side {side} carries two conditions")
        boundary[side] = bc
    if len(scene.cracks) != 1 or len(scene.cracks[0].points) != 2:
        raise ValueError(f"scene {scene.name!r}: one straight crack only")
    pts = np.asarray(scene.cracks[0].points, float)
    tips = []
    for label in nctips.tip_labels(scene):
        end = label.split(",")[1]
        p, prev = (pts[0], pts[1]) if end == "first" else (pts[-1], pts[-2])
        e = (p - prev) / np.linalg.norm(p - prev)
        tips.append([float(p[0]), float(p[1]), float(e[0]), float(e[1])])
    return {"box": [[float(x0), float(y0)], [float(x1), float(y1)]], "crack": pts.tolist(), "h": h,
            "E": scene.material.E, "nu": scene.material.nu, "tips": tips, "faces": faces, "boundary": boundary,
            "reference": {"center": list(ref.center), "a": ref.half_length, "factor": ref.shape_factor,
                          "coefficients": list(ref.coefficients), "profile": ref.profile}}


def run_peer(name: str, h: float) -> dict:
    scene, ref = nc.scenes.load(name), references.reference(name)
    prob = peer_problem(scene, ref, h, SCENES[name])
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)
    out = subprocess.run([SYSTEM_PYTHON, str(PEER), json.dumps(prob)], capture_output=True, text=True, env=env, check=False,
                         timeout=600)
    if out.returncode:
        raise RuntimeError(f"getfem_xfem.py failed on {name}, h = {h}:\n{out.stderr[-2000:]}")
    res = json.loads(out.stdout.strip().splitlines()[-1])
    labels = nctips.tip_labels(scene)
    err_K = max(abs(t[ref.mode] - ref.K(lab)) / abs(ref.K(lab)) for lab, t in zip(labels, res["tips"]))
    return {"scene": name, "code": "GetFEM P2 XFEM", "options": f"h={h:g}", "unknowns": res["unknowns"],
            "cpu": res["cpu"], "K": err_K, "profile": res["profile_error"],
            "profile_closed_form": res["profile_error_closed_form"], "note": res.get("penetration"),
            "linear_solver": res.get("linear_solver"), "phases": res.get("phases")}


def run_ngcrack(name: str, run: dict, level: int) -> dict:
    run = dict(run)
    maxh, crack_h, tip_h, grading = MESHES[run.pop("mesh", "scene")][level]
    label = options_label(run) + (" graded" if grading else "")
    scene = nc.scenes.load(name)
    t0 = time.process_time()
    sol = nc.solve(scene, maxh=maxh, crack_h=crack_h, tip_h=tip_h, grading=grading, **run)
    cpu = time.process_time() - t0
    e = references.errors(sol)
    mesh = f"maxh={maxh:g} crack_h={crack_h:g} tip_h={tip_h:g}" + (f" grading={grading:g}" if grading else "")
    return {"scene": name, "code": f"ngcrack {run['element']}", "options": f"{label} {mesh}", "unknowns": sol.ndof["total"], "cpu": cpu, "K": e["K"],
            "profile": e["profile"], "profile_closed_form": e["profile_closed_form"], "note": None}


def check_peer() -> None:
    if not Path(SYSTEM_PYTHON).exists():
        sys.exit(f"{SYSTEM_PYTHON} not found: the peer needs the system Python with python3-getfem")
    probe = subprocess.run([SYSTEM_PYTHON, "-c", "import getfem"], capture_output=True, text=True, check=False)
    if probe.returncode:
        sys.exit("GetFEM is not importable by /usr/bin/python3: apt-get install -y python3-getfem")


def main() -> None:
    quick = "--quick" in sys.argv
    out = Path(sys.argv[sys.argv.index("--out") + 1]) if "--out" in sys.argv else HERE / "figures" / "peer.png"
    if "--replot" in sys.argv:  # the table and figure again from the saved rows, no solving
        rows = json.loads(out.with_suffix(".json").read_text())
        print_table(rows)
        print_targets(rows)
        figure(rows, out)
        return
    check_peer()
    runs = [r for r in RUNS if accepted(r)]
    for r in RUNS:
        if r not in runs:
            unknown = sorted(set(r) - _option_names() - {"mesh"})
            print(f"(skipped: nc.solve does not accept {unknown} for {r})", file=sys.stderr)
    levels = 3 if quick else len(MESHES["scene"])
    peer_h = GETFEM_H[:4] if quick else GETFEM_H
    nc.solve(nc.scenes.load("griffith"), maxh=4.0)  # warm-up: imports and first-call costs
    rows, last = [], {}
    steps = max(levels, len(peer_h))
    for i in range(steps):
        for name in SCENES:
            if i < len(peer_h) and peer_h[i] >= FINEST[name]:
                try:
                    rows.append(run_peer(name, peer_h[i]))
                    print(f"  {name} GetFEM h={peer_h[i]}: {rows[-1]['unknowns']} unknowns, {rows[-1]['cpu']:.2f} s",
                          file=sys.stderr)
                except RuntimeError as exc:
                    print(f"  (GetFEM failed on {name}, h = {peer_h[i]}: {str(exc)[-300:]})", file=sys.stderr)
            if i < levels:
                for r in runs:
                    key = (name, json.dumps(r, sort_keys=True))
                    if last.get(key, 0) * 3 > MAX_UNKNOWNS:
                        continue
                    try:
                        rows.append(run_ngcrack(name, r, i))
                    except ValueError as exc:  # an option this version refuses (e.g. an order of an element)
                        print(f"  (skipped {r}: {exc})", file=sys.stderr)
                        last[key] = math.inf
                        continue
                    last[key] = rows[-1]["unknowns"]
                    print(f"  {name} {rows[-1]['code']} {rows[-1]['options']}: {rows[-1]['unknowns']} unknowns, "
                          f"{rows[-1]['cpu']:.2f} s", file=sys.stderr)
        save(rows, out)
    print_table(rows)
    print_targets(rows)
    figure(rows, out)


def save(rows, out: Path) -> None:
    """The rows so far, as JSON beside the figure (a long run's partial results survive)."""
    out.parent.mkdir(parents=True, exist_ok=True)
    out.with_suffix(".json").write_text(json.dumps([{k: v for k, v in r.items() if k != "key"} for r in rows], indent=1))


def print_table(rows) -> None:
    for name in SCENES:
        ref = references.reference(name)
        prof = "opening" if ref.profile == "normal" else "sliding"
        print(f"\n### {name}: errors against the finite-body reference ({ref.mode} +- "
              f"{ref.K_uncertainty / abs(ref.K(next(iter(ref.tips)))):.0e}, {prof} +- {ref.profile_uncertainty:.0e})\n")
        print(f"| code | options | unknowns | CPU s | {ref.mode} error | {prof} error | {prof} vs closed form |")
        print("|---|---|---:|---:|---:|---:|---:|")
        for r in sorted((r for r in rows if r["scene"] == name), key=lambda r: (r["code"], r["options"], r["cpu"])):
            print(f"| {r['code']} | {r['options']} | {r['unknowns']} | {r['cpu']:.2f} | {r['K']:.1e} | "
                  f"{r['profile']:.1e} | {100 * r['profile_closed_form']:.2f}% |")


def family(r) -> str:
    """GetFEM, or ngcrack with its options but the mesh."""
    return r["code"] if r["code"].startswith("GetFEM") else r["code"] + " " + r["options"].split(" maxh")[0]


def print_targets(rows) -> None:
    """Per accuracy target: the cheapest GetFEM run and the cheapest ngcrack run reaching it."""
    print("\n### cheapest run per accuracy target (CPU seconds, one thread)\n")
    print("| scene | target | GetFEM P2 XFEM | ngcrack, best | GetFEM / ngcrack CPU |")
    print("|---|---|---|---|---:|")
    for name, targets in TARGETS.items():
        sub = [r for r in rows if r["scene"] == name]
        for qty, tgt in targets:
            what = "K_I" if name == "griffith" else "K_II"
            what = what if qty == "K" else ("opening" if name == "griffith" else "sliding")
            best = {}
            for r in sub:
                side = "GetFEM" if r["code"].startswith("GetFEM") else "ngcrack"
                if r[qty] <= tgt and (side not in best or r["cpu"] < best[side]["cpu"]):
                    best[side] = r
            cells = []
            for side in ("GetFEM", "ngcrack"):
                r = best.get(side)
                cells.append("not reached" if r is None else
                             f"{r['cpu']:.2f} s, {r['unknowns']} unknowns ({'' if side == 'GetFEM' else r['code'][8:] + ' '}"
                             f"{r['options']})")
            ratio = (f"{best['GetFEM']['cpu'] / best['ngcrack']['cpu']:.1f}" if len(best) == 2 else "")
            print(f"| {name} | {what} within {100 * tgt:g}% | {cells[0]} | {cells[1]} | {ratio} |")


def figure(rows, out: Path) -> None:
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))
    for i, name in enumerate(SCENES):
        ref = references.reference(name)
        for j, (qty, title) in enumerate((("K", ref.mode), ("profile", "opening" if ref.profile == "normal" else "sliding"))):
            ax = axes[i, j]
            groups = {}
            for r in rows:
                if r["scene"] == name:
                    groups.setdefault(family(r), []).append(r)
            for label, rs in groups.items():
                rs = sorted(rs, key=lambda r: r["cpu"])
                style = (dict(color="k", lw=2.2, marker="s") if label.startswith("GetFEM") else
                     dict(marker="^", ls="--") if label.endswith("graded") else dict(marker="o"))
                ax.loglog([r["cpu"] for r in rs], [max(r[qty], 1e-8) for r in rs], label=label, **style)
            unc = ref.K_uncertainty / abs(ref.K(next(iter(ref.tips)))) if qty == "K" else ref.profile_uncertainty
            ax.axhline(unc, color="grey", ls=":", lw=1)
            ax.set_title(f"{name}: {title} error (finite-body reference)")
            ax.set_xlabel("CPU s (one thread)")
            ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_ylabel("relative error")
            ax.grid(True, which="both", alpha=0.3)
            if i == 0 and j == 0:
                ax.legend(fontsize=8)
    fig.suptitle("ngcrack and GetFEM's tip-enriched P2 XFEM: error against CPU time\n"
                 "(dotted: the reference's uncertainty; errors below it are not resolved)")
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"\nfigure: {out}")


if __name__ == "__main__":
    main()
