"""Crack growth: the cost of a growth step against a fresh solve, and the total CPU of a run.

The README's teaching scene: `inclined-compression` (the plate [-10, 10]^2, a crack of
half-length 1 at 30 degrees, remote compression sigma_yy = -1, its mesh maxh 1, tip_h
0.005) with friction 0.3 on the crack; wing cracks grow from both tips, da = 0.1,
K_Ic = 2, PLS, the default element. Printed per step: ndof, the solves that made it
(more than one: PLS trials), its wall-clock seconds split into meshing, assembly, linear
solves, the crack problem and post-processing (the tips' K and the error estimate);
every `--every` steps a fresh solve of the same step's scene timed alone; then the solves
per step and the run's CPU seconds (process time: the machine is shared, wall-clock
times vary with its load, printed with `uptime`).

    python benchmarks/growth.py                 # 50 steps, PLS (the default)
    python benchmarks/growth.py --steps 20 --criterion mts
    python benchmarks/growth.py --crack-h 0.1     # the path meshed at 0.1 (the scene's: 0.05), compared

With --crack-h H the same run is repeated with crack_h = H for every solve and the two are
compared step by step: CPU, unknowns, and the largest differences of the tips' kinks,
K_II and load factors over the steps both runs made.

No number here is a test threshold.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--criterion", default="pls")
    parser.add_argument("--every", type=int, default=10, help="time a fresh solve of every N-th step's scene")
    parser.add_argument("--friction", type=float, default=0.3)
    parser.add_argument("--crack-h", type=float, default=None, help="also run with this crack_h and compare")
    args = parser.parse_args(argv)

    import ngcrack as nc
    from ngcrack.solve import solve

    print(f"load average before: {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")
    scene = nc.scenes.load("inclined-compression").with_(friction=args.friction)
    c0, t0 = time.process_time(), time.perf_counter()
    res = nc.grow(scene, da=0.1, steps=args.steps, K_Ic=2.0, criterion=args.criterion, frames=False)
    cpu, total = time.process_time() - c0, time.perf_counter() - t0
    df = res.table.groupby("step").first()
    print(f"{scene.name}, friction {args.friction:g}, {args.criterion}, da 0.1, K_Ic 2: {len(res.steps)} steps, "
          f"CPU {cpu:.1f} s, wall {total:.1f} s; stopped: {res.stopped}")
    parts = ["mesh_s", "assembly_s", "linear_s", "crack_s", "post_s"]
    print(f"{'step':>4} {'ndof':>7} {'solves':>6} {'step s':>7} " + " ".join(f"{p:>10}" for p in parts)
          + f" {'fresh s':>8} {'per solve/fresh':>15}")
    ratios = []
    for n, row in df.iterrows():
        fresh = ""
        if n % args.every == 0 or n == df.index[-1]:
            t1 = time.perf_counter()
            solve(res.scenes[n])
            f = time.perf_counter() - t1
            ratios.append(row.time_s / row.solves / f)
            fresh = f"{f:8.2f} {ratios[-1]:15.2f}"
        print(f"{n:>4} {row.ndof:>7} {row.solves:>6} {row.time_s:>7.2f} " + " ".join(f"{row[p]:>10.2f}" for p in parts)
              + f" {fresh}")
    solves = df.solves.to_numpy()
    print(f"solves per step: mean {solves[1:].mean():.2f} (steps after the first), max {solves.max()}; "
          f"{solves.sum()} solves in all")
    print("seconds per part, summed: " + ", ".join(f"{p[:-2]} {df[p].sum():.1f}" for p in parts))
    print(f"per solve / fresh solve: median {np.median(ratios):.2f}")
    print(f"CPU for {len(res.steps) - 1} steps: {cpu:.1f} s; wall {total:.1f} s")
    print(f"load average after: {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")
    if args.crack_h is not None:
        compare(nc, scene, res, cpu, args)
    return 0


def compare(nc, scene, res, cpu, args) -> None:
    """The same run with crack_h = args.crack_h: its CPU and unknowns, and how far its path's
    numbers are from the first run's, step by step (tips matched by crack and end)."""
    c0 = time.process_time()
    other = nc.grow(scene, da=0.1, steps=args.steps, K_Ic=2.0, criterion=args.criterion, frames=False,
                    crack_h=args.crack_h)
    cpu2 = time.process_time() - c0
    a, b = res.table, other.table
    keys = ["step", "crack", "end"]
    both = a.merge(b, on=keys, suffixes=("", "_h"))
    both = both[both.step <= min(a.step.max(), b.step.max())]
    scale = float(np.abs(a.K_II).max())
    lf = (both.load_factor_h / both.load_factor - 1).abs()
    print("\n| crack_h | steps | solves | CPU s | unknowns, first to last step |\n|---|---|---|---|---|")
    for h, r, c in ((scene.crack_h, res, cpu), (args.crack_h, other, cpu2)):
        t = r.table.groupby("step").first()
        print(f"| {h:g} | {len(r.steps) - 1} | {int(t.solves.sum())} | {c:.1f} | {int(t.ndof.iloc[0])} to {int(t.ndof.iloc[-1])} |")
    print(f"over steps 0-{int(both.step.max())}: kink differs by at most {np.abs(both.kink_deg_h - both.kink_deg).max():.2f} "
          f"degrees (grown tips), K_II by {np.abs(both.K_II_h - both.K_II).max() / scale:.2e} of the largest |K_II|, "
          f"the step's load factor by {lf.max():.2e} (relative); stopped: {other.stopped}")


if __name__ == "__main__":
    raise SystemExit(main())
