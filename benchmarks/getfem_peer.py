"""ngcrack side by side with an XFEM peer (GetFEM): error against CPU time on two closed-form scenes.

    python benchmarks/getfem_peer.py [--quick] [--passes 2] [--out benchmarks/figures/peer.png] [--replot]
                                     [--levels N] [--peer-levels N]

The quoted run: `benchmarks/peer_quotes.py` then writes its tables into BENCHMARKS.md, the
performance guide, the README and benchmarks/figures/peer.md (see that file).

--quick: ngcrack's first three meshes of each ladder (GetFEM's whole ladder either way).
--levels N, --peer-levels N: ngcrack's first N meshes, GetFEM's first N h (a trial of the
script, e.g. `--levels 2 --peer-levels 3 --passes 1 --out /tmp/peer.png`; not for quoting).

Needs Debian's python3-getfem for the system Python (/usr/bin/python3; `apt-get install
python3-getfem`); it is not a dependency of ngcrack nor of its tests. Both codes run cold,
each case in its own fresh process (GetFEM: benchmarks/getfem_xfem.py under the system
Python; ngcrack: this file with --child under this Python, its bytecode cached as an
installed package has it), one thread (NGCRACK_THREADS = OMP_NUM_THREADS = 1), GetFEM and
ngcrack interleaved mesh by mesh, PASSES passes; each case keeps its least CPU over the
passes. Two CPU columns:

- in-process: from after the imports (`import getfem`; `import ngcrack` and the names a
  solve uses) to the answer: the mesh, assembly, solve, K at the tips (and ngcrack's
  profiles, KKT and error estimate, which a solve computes);
- whole process: the child's CPU (user + system, the interpreter's start and the imports
  included), less the CPU it spent measuring its own errors: what a command-line user pays.

Scenes: `griffith` (K_I and the opening) and `inclined-compression` (K_II and the sliding,
crack faces in frictionless contact). Errors against the same finite-body references
(ngcrack.studies.references) for both codes: K, max over the tips of |K - K_ref| / |K_ref|;
profile, the true relative L2 error of the opening (sliding) along the crack, by
quadrature for both (GetFEM: its quadrature on the level set; ngcrack: the jump
(n.nu)(u.Other() - u) of the displacement sol.u on the crack edges, NGSolve's element-
boundary quadrature). The mid-point profile error that ngcrack reports is printed beside it.

GetFEM's runs: the mesh ladder from coarse (h = 0.4, 0.2, 0.1, ...), each h with three
enrichment and integral radii (0.2 a, 0.5 a and 1 a, a the crack's half length); its contact
is the augmented Lagrangian with a P0 multiplier on the cut elements, its K the interaction
integral with GetFEM's crack functions (see getfem_xfem.py). ngcrack's runs are data (RUNS x
MESHES). A family is one configuration on its mesh ladder (GetFEM: one radius; ngcrack: one
set of options); a family reaches a target at its cheapest mesh whose error and the errors of
all its finer meshes stay below the target (an error that dips below the target on one mesh
and rises above it on the next does not count). Each code's cell in the target table is its
best family there. A target is
judged only where it is at least 3x the references' own floor: the larger of their
stated uncertainty and their disagreement with GetFEM's best run (the two codes are
independent); finer targets are printed as "not judged". The 1-minute load average is
printed with the tables (the machine may be shared: CPU times then vary by +-30%).

ngcrack's runs are data (RUNS): add an entry (e.g. {"element": "tdnns", "order": 3,
"hp": 4}) to put a new option in the table and the figure; keys nc.solve does not accept,
and options it refuses, are skipped with a note.
"""

from __future__ import annotations

import os

for _v in ("NGCRACK_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
    os.environ[_v] = "1"

import json
import math
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
PEER = HERE / "getfem_xfem.py"
SYSTEM_PYTHON = "/usr/bin/python3"
SCENES = {"griffith": "free", "inclined-compression": "contact"}
#: ngcrack's mesh ladder: (maxh, crack_h, tip_h, grading), from coarse to fine
#: "scene": the scenes' grading (0.2); "graded": strong grading towards the tips (0.5: the mesh
#: grows fast away from them), a coarse far field and a fine tip (the efficient path at order 3)
MESHES = {
    "scene": [(4.0, 0.2, 0.02, None), (2.0, 0.1, 0.01, None), (1.0, 0.05, 0.005, None), (0.5, 0.025, 0.001, None)],
    "graded": [(4.0, 0.5, 0.005, 0.5), (2.0, 0.2, 0.002, 0.5), (2.0, 0.2, 0.0005, 0.5), (2.0, 0.1, 0.0001, 0.5)],
}
#: GetFEM's ladder: the mesh size h around the crack (graded outside), from coarse
GETFEM_H = [0.4, 0.2, 0.1, 0.07, 0.05, 0.035, 0.025]
#: GetFEM's configurations per h: the tip enrichment's radius and the interaction integral's
#: radius, relative to the crack's half length a (0.2 a: GetFEM's cheapest on the inclined crack)
GETFEM_RADII = [{"enrich": 0.2, "radius": 0.2}, {"enrich": 0.5, "radius": 0.5}, {"enrich": 1.0, "radius": 1.0}]
#: the finest h per scene: on inclined-compression at h = 0.025 GetFEM's MUMPS stops with error -9
#: (workspace, ICNTL(14), which its Python interface does not set)
FINEST = {"griffith": 0.025, "inclined-compression": 0.035}
#: ngcrack's options (any of nc.SolveOptions; "mesh": "graded" for the strongly graded ladder)
RUNS = [
    {"element": "tdnns"},
    {"element": "tdnns", "order": 2},
    {"element": "tdnns", "order": 3},
    {"element": "tdnns", "order": 2, "mesh": "graded"},
    {"element": "tdnns", "order": 3, "mesh": "graded"},
    {"element": "bdm", "order": 3},
    {"element": "tdnns", "order": 2, "hp": 3},
    {"element": "tdnns", "order": 3, "hp": 4},
    {"element": "bdm", "order": 3, "hp": 4},
]
#: a run is skipped once its previous mesh had more unknowns than this / 3 (memory, time)
MAX_UNKNOWNS = 1.2e6
#: accuracy targets (relative errors) for both quantities of both scenes; each is judged only
#: where it is at least FLOOR_FACTOR times the references' floor (`floors`)
TARGETS = [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6]
FLOOR_FACTOR = 3.0
#: the children's environment: no PYTHONDONTWRITEBYTECODE (bytecode cached, as installed)
CHILD_ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
CHILD_ENV["PYTHONPYCACHEPREFIX"] = os.path.join(tempfile.gettempdir(), "ngcrack-peer-pycache")


def options_label(run: dict) -> str:
    label = " ".join(f"{k}={v}" for k, v in run.items() if k not in ("element", "mesh")) or "order=1"
    return label + (" graded" if run.get("mesh") == "graded" else "")


def _option_names() -> set[str]:
    import dataclasses

    import ngcrack as nc

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
    from ngcrack.planar import tips as nctips

    tips = []
    for label in nctips.tip_labels(scene):
        end = label.split(",")[1]
        p, prev = (pts[0], pts[1]) if end == "first" else (pts[-1], pts[-2])
        e = (p - prev) / np.linalg.norm(p - prev)
        tips.append([float(p[0]), float(p[1]), float(e[0]), float(e[1])])
    return {"box": [[float(x0), float(y0)], [float(x1), float(y1)]], "crack": pts.tolist(), "h": h,
            "E": scene.material.E, "nu": scene.material.nu, "tips": tips, "faces": faces, "boundary": boundary,
            "a": ref.half_length,
            "reference": {"center": list(ref.center), "a": ref.half_length, "factor": ref.shape_factor,
                          "coefficients": list(ref.coefficients), "profile": ref.profile}}


def child_cpu(args: list[str], env: dict) -> tuple[float, subprocess.CompletedProcess]:
    """(CPU seconds of the child process, its result)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        out = subprocess.run(args, capture_output=True, text=True, env=env, check=False, timeout=900)
    except subprocess.TimeoutExpired:  # (a loaded machine): the case fails, the run goes on
        out = subprocess.CompletedProcess(args, -9, "", "timed out after 900 s")
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), out


def run_peer(name: str, h: float, radii: dict) -> dict:
    import ngcrack as nc
    from ngcrack import references

    scene, ref = nc.scenes.load(name), references.reference(name)
    prob = peer_problem(scene, ref, h, SCENES[name]) | radii
    env = dict(CHILD_ENV)
    env.pop("PYTHONPATH", None)
    env.pop("PYTHONPYCACHEPREFIX", None)  # the system's own bytecode
    whole, out = child_cpu([SYSTEM_PYTHON, str(PEER), json.dumps(prob)], env)
    if out.returncode:
        raise RuntimeError(f"getfem_xfem.py failed on {name}, h = {h}:\n{out.stderr[-2000:]}")
    res = json.loads(out.stdout.strip().splitlines()[-1])
    labels = nc.tips.tip_labels(scene)
    err_K = max(abs(t[ref.mode] - ref.K(lab)) / abs(ref.K(lab)) for lab, t in zip(labels, res["tips"]))
    return {"scene": name, "code": "GetFEM P2 XFEM", "options": f"h={h:g} enrich={radii['enrich']:g}a R={radii['radius']:g}a",
            "level": GETFEM_H.index(h), "iterations": res.get("iterations"), "unknowns": res["unknowns"], "cpu": res["cpu"],
            "cpu_whole": whole - res["cpu_errors"], "K": err_K,
            "profile": res["profile_error"], "profile_mid": None, "profile_closed_form": res["profile_error_closed_form"],
            "note": res.get("penetration"), "phases": res.get("phases")}


def profile_error_l2(sol, ref) -> float:
    """The true relative L2 error of the first crack's profile (opening or sliding) against
    the reference: the jump of sol.u across the crack edges, (n.nu)(u.Other() - u) with n
    the element's outer normal, integrated by NGSolve's element-boundary quadrature (every
    crack edge seen from both sides: the factor 2 cancels in the ratio)."""
    import ngsolve as ngs

    crack = sol.crack_mesh.cracks[0]
    nu, t = crack.normal[0], crack.tangent[0]
    c, a = np.asarray(ref.center, float), ref.half_length
    d = ref.direction[0] * (ngs.x - c[0]) + ref.direction[1] * (ngs.y - c[1])
    off = nu[0] * (ngs.x - c[0]) + nu[1] * (ngs.y - c[1])
    n = ngs.specialcf.normal(2)
    jump = (n[0] * nu[0] + n[1] * nu[1]) * (sol.u.Other() - sol.u)
    along = ngs.CF(tuple(nu)) if ref.profile == "normal" else ngs.CF(tuple(t))
    j = jump * along
    poly = np.polynomial.legendre.leg2poly(np.asarray(ref.coefficients, float))
    tt = d / a
    series = ngs.CF(float(poly[-1]))
    for coef in reversed(poly[:-1]):
        series = series * tt + float(coef)
    exact = ref.shape_factor * ngs.sqrt(ngs.IfPos(a * a - d * d, a * a - d * d, 0.0)) * series
    on = ngs.IfPos(1e-9 * a - ngs.sqrt(off * off), ngs.IfPos(a - ngs.sqrt(d * d), 1.0, 0.0), 0.0)
    order = 2 * (sol.options.get("order") or 2) + 8
    dx = ngs.dx(element_boundary=True, bonus_intorder=order)
    num = ngs.Integrate(on * (j - exact) ** 2 * dx, sol.mesh)
    den = ngs.Integrate(on * exact**2 * dx, sol.mesh)
    return float(math.sqrt(num / den))


def child(spec: dict) -> None:
    """One cold ngcrack case in this fresh process: prints one JSON line."""
    import ngcrack as nc
    from ngcrack import references

    solve = nc.solve  # the modules a solve uses (their import is the whole process's, not the solve's)
    t0 = time.process_time()
    scene = nc.scenes.load(spec["scene"])
    sol = solve(scene, **spec["options"])
    cpu = time.process_time() - t0
    ref = references.reference(spec["scene"])
    e = references.errors(sol, ref)
    l2 = profile_error_l2(sol, ref)
    cpu_errors = time.process_time() - t0 - cpu
    print(json.dumps({"unknowns": sol.ndof["total"], "cpu": cpu, "cpu_errors": cpu_errors, "K": e["K"], "profile": l2,
                      "profile_mid": e["profile"], "profile_closed_form": e["profile_closed_form"]}))


def run_ngcrack(name: str, run: dict, level: int) -> dict:
    run = dict(run)
    maxh, crack_h, tip_h, grading = MESHES[run.pop("mesh", "scene")][level]
    label = options_label(run) + (" graded" if grading else "")
    options = {"maxh": maxh, "crack_h": crack_h, "tip_h": tip_h, "grading": grading, **run}
    whole, out = child_cpu([sys.executable, str(Path(__file__)), "--child", json.dumps({"scene": name, "options": options})],
                           CHILD_ENV)
    if out.returncode:
        raise ValueError(out.stderr.strip().splitlines()[-1] if out.stderr.strip() else f"exit {out.returncode}")
    res = json.loads(out.stdout.strip().splitlines()[-1])
    mesh = f"maxh={maxh:g} crack_h={crack_h:g} tip_h={tip_h:g}" + (f" grading={grading:g}" if grading else "")
    return {"scene": name, "code": f"ngcrack {run['element']}", "options": f"{label} {mesh}", "level": level, "unknowns": res["unknowns"],
            "cpu": res["cpu"], "cpu_whole": whole - res["cpu_errors"], "K": res["K"], "profile": res["profile"],
            "profile_mid": res["profile_mid"], "profile_closed_form": res["profile_closed_form"], "note": None}


def check_peer() -> None:
    if not Path(SYSTEM_PYTHON).exists():
        sys.exit(f"{SYSTEM_PYTHON} not found: the peer needs the system Python with python3-getfem")
    probe = subprocess.run([SYSTEM_PYTHON, "-c", "import getfem"], capture_output=True, text=True, check=False)
    if probe.returncode:
        sys.exit("GetFEM is not importable by /usr/bin/python3: apt-get install -y python3-getfem")


def merge(rows: list[dict]) -> list[dict]:
    """One row per case: the least in-process and the least whole-process CPU over the passes."""
    out: dict[tuple, dict] = {}
    for r in rows:
        key = (r["scene"], r["code"], r["options"])
        if key not in out:
            out[key] = dict(r, passes=1)
        else:
            best = out[key]
            best["cpu"], best["cpu_whole"] = min(best["cpu"], r["cpu"]), min(best["cpu_whole"], r["cpu_whole"])
            best["passes"] += 1
    return list(out.values())


def main() -> None:
    if "--child" in sys.argv:
        child(json.loads(sys.argv[sys.argv.index("--child") + 1]))
        return
    quick = "--quick" in sys.argv
    passes = int(sys.argv[sys.argv.index("--passes") + 1]) if "--passes" in sys.argv else 2
    out = Path(sys.argv[sys.argv.index("--out") + 1]) if "--out" in sys.argv else HERE / "figures" / "peer.png"
    if "--replot" in sys.argv:  # the tables and figure again from the saved rows, no solving
        data = json.loads(out.with_suffix(".json").read_text())
        report(data["rows"], data["load"])
        figure(data["rows"], out)
        return
    check_peer()
    runs = [r for r in RUNS if accepted(r)]
    for r in RUNS:
        if r not in runs:
            unknown = sorted(set(r) - _option_names() - {"mesh"})
            print(f"(skipped: nc.solve does not accept {unknown} for {r})", file=sys.stderr)
    levels = 3 if quick else len(MESHES["scene"])
    peer_h = GETFEM_H  # (also with --quick: GetFEM's finest runs set the references' floor)
    if "--levels" in sys.argv:
        levels = int(sys.argv[sys.argv.index("--levels") + 1])
    if "--peer-levels" in sys.argv:
        peer_h = GETFEM_H[:int(sys.argv[sys.argv.index("--peer-levels") + 1])]
    load = [os.getloadavg()[0]]
    started = time.strftime("%Y-%m-%d %H:%M", time.gmtime())
    command = "python benchmarks/getfem_peer.py " + " ".join(sys.argv[1:])
    # one uncounted ngcrack child: writes the bytecode, as an installed package has it
    run_ngcrack("griffith", {"element": "tdnns"}, 0)
    rows, last = [], {}
    for p in range(passes):
        steps = max(levels, len(peer_h))
        for i in range(steps):
            for name in SCENES:
                if i < len(peer_h) and peer_h[i] >= FINEST[name]:
                    for radii in GETFEM_RADII:
                        try:
                            rows.append(run_peer(name, peer_h[i], radii))
                            print(f"  [{p + 1}] {name} GetFEM {rows[-1]['options']}: {rows[-1]['unknowns']} unknowns, "
                                  f"{rows[-1]['cpu']:.2f} s ({rows[-1]['cpu_whole']:.2f} s whole)", file=sys.stderr)
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
                        print(f"  [{p + 1}] {name} {rows[-1]['code']} {rows[-1]['options']}: {rows[-1]['unknowns']} unknowns, "
                              f"{rows[-1]['cpu']:.2f} s ({rows[-1]['cpu_whole']:.2f} s whole)", file=sys.stderr)
            load.append(os.getloadavg()[0])
            save(merge(rows), load, out, {"command": command, "started": started, "ended": time.strftime("%H:%M", time.gmtime())})
    rows = merge(rows)
    report(rows, load)
    figure(rows, out)


def save(rows, load, out: Path, run: dict) -> None:
    """The rows so far, as JSON beside the figure (a long run's partial results survive; the
    command, its start and end in UTC: benchmarks/peer_quotes.py quotes them)."""
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".json.tmp")
    tmp.write_text(json.dumps({"load": load, "run": run, "rows": rows}, indent=1))
    tmp.replace(out.with_suffix(".json"))


def report(rows, load) -> None:
    print(f"1-minute load average during the run: {min(load):.1f} to {max(load):.1f}")
    print_table(rows)
    print_targets(rows)


def _quantity(name: str, qty: str) -> str:
    if qty == "K":
        return "K_I" if name == "griffith" else "K_II"
    return "opening" if name == "griffith" else "sliding"


def floors(rows) -> dict[tuple[str, str], float]:
    """(scene, "K" | "profile") -> the references' floor: the larger of their stated
    uncertainty and their disagreement with GetFEM's best run (an independent code)."""
    from ngcrack import references

    out = {}
    for name in SCENES:
        ref = references.reference(name)
        stated = {"K": ref.K_uncertainty / abs(ref.K(next(iter(ref.tips)))), "profile": ref.profile_uncertainty}
        for qty in ("K", "profile"):
            peer = [r[qty] for r in rows if r["scene"] == name and r["code"].startswith("GetFEM")]
            out[(name, qty)] = max(stated[qty], min(peer) if peer else 0.0)
    return out


def print_table(rows) -> None:
    from ngcrack import references

    fl = floors(rows)
    for name in SCENES:
        ref = references.reference(name)
        prof = _quantity(name, "profile")
        print(f"\n### {name}: errors against the finite-body reference (floor: {ref.mode} {fl[(name, 'K')]:.0e}, "
              f"{prof} {fl[(name, 'profile')]:.0e})\n")
        print(f"| code | options | unknowns | CPU s in-process | CPU s whole process | {ref.mode} error | {prof} error (L2) | "
              f"{prof} error (mid points) |")
        print("|---|---|---:|---:|---:|---:|---:|---:|")
        for r in sorted((r for r in rows if r["scene"] == name), key=lambda r: (r["code"], r["options"], r["cpu"])):
            mid = f"{r['profile_mid']:.1e}" if r.get("profile_mid") is not None else ""
            print(f"| {r['code']} | {r['options']} | {r['unknowns']} | {r['cpu']:.2f} | {r['cpu_whole']:.2f} | {r['K']:.1e} | "
                  f"{r['profile']:.1e} | {mid} |")


def family(r) -> str:
    """One configuration on its mesh ladder: GetFEM with its radii, ngcrack with its options but the mesh."""
    if r["code"].startswith("GetFEM"):
        return r["code"] + " " + r["options"].split(" ", 1)[1]
    return r["code"] + " " + r["options"].split(" maxh")[0]


def _fineness(r) -> tuple:
    """A row's place on its family's ladder (rows saved before the ladder level was: by unknowns)."""
    return (r.get("level", -1), r["unknowns"])


def reaching(rows, qty: str, target: float) -> list[dict]:
    """The rows that reach `target` for their family: the row's error and the errors of every
    finer mesh of its family (same scene) are at most the target."""
    out = []
    for r in rows:
        kin = [o for o in rows if o["scene"] == r["scene"] and family(o) == family(r) and _fineness(o) >= _fineness(r)]
        if all(o[qty] <= target for o in kin):
            out.append(r)
    return out


def cheapest(rows, side: str, qty: str, target: float, column: str):
    pool = [r for r in reaching(rows, qty, target) if r["code"].startswith("GetFEM") == (side == "GetFEM")]
    return min(pool, key=lambda r: r[column]) if pool else None


def print_targets(rows) -> None:
    """Per accuracy target: the cheapest GetFEM run and the cheapest ngcrack run reaching it."""
    fl = floors(rows)
    n_ng = len({family(r) for r in rows if not r["code"].startswith("GetFEM")})
    n_gf = len({family(r) for r in rows if r["code"].startswith("GetFEM")})
    print(f"\n### cheapest run per accuracy target (CPU seconds, one thread, cold; ngcrack's column is the best of "
          f"{n_ng} configurations, GetFEM's of {n_gf} radii, each on its mesh ladder; a run counts where it and every "
          f"finer mesh of its family stay within the target)\n")
    print("| scene | target | GetFEM in-process | ngcrack in-process | GetFEM / ngcrack in-process | GetFEM whole | "
          "ngcrack whole | GetFEM / ngcrack whole |")
    print("|---|---|---|---|---:|---:|---:|---:|")
    for name in SCENES:
        sub = [r for r in rows if r["scene"] == name]
        for qty in ("K", "profile"):
            for tgt in TARGETS:
                what = f"{_quantity(name, qty)} within {100 * tgt:g}%"
                if tgt < FLOOR_FACTOR * fl[(name, qty)]:
                    print(f"| {name} | {what} | not judged: below {FLOOR_FACTOR:g}x the references' floor "
                          f"({fl[(name, qty)]:.0e}) | | | | | |")
                    continue
                cells, ratios = [], []
                for column in ("cpu", "cpu_whole"):
                    g, n = cheapest(sub, "GetFEM", qty, tgt, column), cheapest(sub, "ngcrack", qty, tgt, column)
                    gc = "not reached" if g is None else f"{g[column]:.2f}" + (f" ({g['options']})" if column == "cpu" else "")
                    nc_ = "not reached" if n is None else (f"{n[column]:.2f}" + (f" ({n['code'][8:]} {n['options']})"
                                                                                 if column == "cpu" else ""))
                    cells += [gc, nc_]
                    ratios.append(f"{g[column] / n[column]:.1f}" if g and n else "")
                print(f"| {name} | {what} | {cells[0]} | {cells[1]} | {ratios[0]} | {cells[2]} | {cells[3]} | {ratios[1]} |")


def figure(rows, out: Path) -> None:
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ngcrack import references

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
                gf_styles = {"0.2a": ":", "0.5a": "--", "1a": "-"}
                style = (dict(color="k", lw=2.0, marker="s", ls=gf_styles.get(label.rsplit("=", 1)[-1], "-"))
                         if label.startswith("GetFEM") else
                     dict(marker="^", ls="--") if label.endswith("graded") else dict(marker="o"))
                ax.loglog([r["cpu"] for r in rs], [max(r[qty], 1e-8) for r in rs], label=label, **style)
            ax.axhline(floors(rows)[(name, qty)], color="grey", ls=":", lw=1)
            ax.set_title(f"{name}: {title} error (finite-body reference)")
            ax.set_xlabel("CPU s in-process, cold (one thread)")
            ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_ylabel("relative error")
            ax.grid(True, which="both", alpha=0.3)
            if i == 0 and j == 0:
                ax.legend(fontsize=8)
    fig.suptitle("ngcrack and GetFEM's tip-enriched P2 XFEM: error against CPU time\n"
                 "(dotted: the references' floor; errors below it are not resolved)")
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"\nfigure: {out}")


if __name__ == "__main__":
    main()
