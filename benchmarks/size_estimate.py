"""The size guard's triangle estimate (ngcrack.planar.sizing) against netgen's meshes.

For every built-in scene on uniform and graded meshes (its own [mesh] values, maxh
halved and quartered, and a few tip_h / crack_h / grading variants), print netgen's
triangles, the estimate and their ratio, the estimate's time and netgen's; then the
ratio's range overall and from 1000 triangles up. Also `ngcrack solve griffith --maxh
1e-7` as a user runs it: exit code and wall time (process start included).

    python benchmarks/size_estimate.py            # up to about 3e5 triangles
    python benchmarks/size_estimate.py --quick    # up to about 3e4
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

from ngcrack import scenes
from ngcrack.planar import sizing
from ngcrack.planar.geometry import make_mesh

CASES = [
    ("paper-1", [dict(maxh=h) for h in (0.4, 0.2, 0.1, 0.05, 0.025, 0.0125)]),
    ("paper-2", [dict(maxh=h) for h in (0.4, 0.2, 0.1, 0.05, 0.025, 0.0125)]
     + [dict(maxh=0.1, tip_h=0.005), dict(maxh=0.2, tip_h=0.002, crack_h=0.02, grading=0.3),
        dict(maxh=0.1, grading=0.6)]),
    ("kinked-crack", [dict(maxh=h) for h in (0.2, 0.05, 0.0125)] + [dict(maxh=0.1, tip_h=0.005)]),
    ("two-cracks", [dict(maxh=h) for h in (0.2, 0.05, 0.0125)]),
    ("no-crack", [dict(maxh=h) for h in (0.2, 0.05, 0.0125)]),
    ("tension-open", [dict(maxh=h) for h in (0.2, 0.05, 0.0125)]),
    ("uniaxial-compression", [dict(maxh=h) for h in (0.2, 0.05, 0.0125)]),
    ("griffith", [dict(maxh=h) for h in (4.0, 1.0, 0.5, 0.25, 0.1)]
     + [dict(maxh=1.0, tip_h=0.02, crack_h=0.1, grading=0.3), dict(maxh=1.0, tip_h=0.001, crack_h=0.02),
        dict(maxh=0.5, tip_h=0.01, crack_h=0.01, grading=0.5), dict(maxh=1.0, crack_h=0.005, tip_h=0.0005)]),
    ("inclined-compression", [dict(maxh=h) for h in (4.0, 1.0, 0.5, 0.25, 0.1)]
     + [dict(maxh=1.0, tip_h=0.001, crack_h=0.02), dict(maxh=0.5, tip_h=0.01, crack_h=0.01, grading=0.5)]),
]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="skip meshes estimated above 3e4 triangles")
    args = ap.parse_args(argv)
    limit = 3e4 if args.quick else 3e5
    warnings.simplefilter("ignore")
    rows = []
    print(f"{'scene':22s} {'mesh options':46s} {'netgen':>8s} {'estimate':>9s} {'ratio':>6s} {'est [us]':>8s} {'mesh [s]':>8s}")
    for name, variants in CASES:
        scene = scenes.load(name)
        for opts in variants:
            t0 = time.perf_counter()
            est = sizing.estimate_triangles(scene, **opts)
            t_est = time.perf_counter() - t0
            if est > limit:
                continue
            t0 = time.perf_counter()
            n = len(make_mesh(scene, **opts).triangles)
            t_mesh = time.perf_counter() - t0
            rows.append((n, est / n))
            text = ", ".join(f"{k} {v:g}" for k, v in opts.items())
            print(f"{name:22s} {text:46s} {n:8d} {est:9.0f} {est / n:6.2f} {1e6 * t_est:8.0f} {t_mesh:8.2f}", flush=True)
    n, r = np.array(rows).T
    big = r[n >= 1000]
    print(f"\n{len(r)} meshes, {int(n.min())} to {int(n.max())} triangles: estimate / netgen {r.min():.2f} .. {r.max():.2f}; "
          f"from 1000 triangles up ({len(big)} meshes): {big.min():.2f} .. {big.max():.2f}, "
          f"median {np.median(big):.2f}")
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[1]))
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "ngcrack.shell.cli", "solve", "griffith", "--maxh", "1e-7"],
                          capture_output=True, text=True, env=env)
    print(f"\nngcrack solve griffith --maxh 1e-7: exit code {proc.returncode} after {time.perf_counter() - t0:.2f} s "
          f"(process start and imports included)\n  {proc.stderr.strip()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
