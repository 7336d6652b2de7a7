"""The one-path redesign, before and after: the same solves in two checkouts, answers and CPU seconds.

    python benchmarks/one_path.py --before /path/to/old/checkout [--after .] [--repeat 3]

Each case runs `nc.solve` (the public API both checkouts share) in a fresh process with the
checkout first on PYTHONPATH, interleaving the two checkouts, `--repeat` times each; the table
gives the minimum CPU seconds of the solve (the process's CPU time around `nc.solve`, imports
excluded), the ratio after / before, and the largest relative difference of K (tips in 2D, the
front's points in 3D) and of the unknowns between the two answers. Cases: griffith and
inclined-compression at their default meshes, the penny at a coarse front (front_h 0.3, crack_h
0.6), and griffith over `mpiexec -n 2` (the distributed solve; wall seconds of the whole run).
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import shutil
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]

CHILD = """
import json, time, numpy as np, ngcrack as nc
t0 = time.process_time()
sol = nc.solve({scene!r}, **{options!r})
cpu = time.process_time() - t0
print("FROM", nc.__file__)
if sol is not None:
    fronts = getattr(sol, "fronts", None)  # (a 2D solution of the former path has its tips only)
    K = [float(k) for f in fronts for k in np.atleast_1d(f.K_I)] if fronts else [float(t.K_I) for t in sol.tips]
    print("RESULT", json.dumps({{"cpu": cpu, "K": K, "ndof": int(sol.ndof["total"])}}))
"""

CASES = {
    "griffith": ("griffith", {}),
    "inclined-compression": ("inclined-compression", {}),
    "penny (front_h 0.3)": ("penny", {"front_h": 0.3, "crack_h": 0.6}),
    "griffith, mpiexec -n 2": ("griffith", {}),
}


def run(checkout: pathlib.Path, scene: str, options: dict, ranks: int) -> dict:
    env = {**os.environ, "PYTHONPATH": str(checkout), "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    cmd = [sys.executable, "-c", CHILD.format(scene=scene, options=options)]
    if ranks > 1:
        cmd = [shutil.which("mpiexec") or "mpiexec", "-n", str(ranks), *cmd]
    import time

    t0 = time.perf_counter()
    # run in the checkout itself: `python -c` puts the working folder first on sys.path, before PYTHONPATH
    out = subprocess.run(cmd, env=env, cwd=checkout, capture_output=True, text=True, timeout=1800)
    wall = time.perf_counter() - t0
    line = next((x for x in out.stdout.splitlines() if x.startswith("RESULT")), None)
    if line is None:
        raise RuntimeError(f"{checkout}: {scene} failed:\n{out.stderr[-2000:]}")
    result = json.loads(line[len("RESULT"):])
    where = next((x for x in out.stdout.splitlines() if x.startswith("FROM")), "")
    if str(checkout) not in where:
        raise RuntimeError(f"{checkout}: ngcrack was imported from elsewhere ({where})")
    result["wall"] = wall
    return result


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--before", required=True, type=lambda v: pathlib.Path(v).resolve())
    p.add_argument("--after", default=ROOT, type=lambda v: pathlib.Path(v).resolve())
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--cases", nargs="+", default=list(CASES))
    args = p.parse_args()
    print("| case | unknowns | CPU s before | CPU s after | after / before | K rel. diff |")
    print("|---|---:|---:|---:|---:|---:|")
    for name in args.cases:
        scene, options = CASES[name]
        ranks = 2 if "mpiexec" in name else 1
        runs = {"before": [], "after": []}
        for _ in range(args.repeat):
            for which in ("before", "after"):
                runs[which].append(run(getattr(args, which), scene, options, ranks))
        key = "wall" if ranks > 1 else "cpu"
        b, a = (min(r[key] for r in runs[w]) for w in ("before", "after"))
        Kb, Ka = runs["before"][0]["K"], runs["after"][0]["K"]
        scale = max((abs(k) for k in Kb), default=1.0) or 1.0
        dK = max((abs(x - y) for x, y in zip(Kb, Ka)), default=float("nan")) / scale if len(Kb) == len(Ka) else float("nan")
        nd = runs["after"][0]["ndof"]
        same = "" if nd == runs["before"][0]["ndof"] else f" (before {runs['before'][0]['ndof']})"
        unit = " (wall)" if ranks > 1 else ""
        print(f"| {name}{unit} | {nd}{same} | {b:.2f} | {a:.2f} | {a / b:.2f} | {dK:.1e} |", flush=True)


if __name__ == "__main__":
    main()
