"""Crack growth: the cost of a growth step against a fresh solve, and the total for 50 steps.

The teaching scene `inclined-crack` (nc.scenes.SCENE_FUNCTIONS: the plate [-5, 5]^2, a
crack of half-length 1 at 45 degrees, remote compression sigma_yy = -1, its mesh maxh 1,
tip_h 0.02) with friction 0.3 on the crack: wing cracks grow from both tips, da = 0.1,
K_Ic = 1, bdm. For every step: the step's time (its solves: remesh, assembly, the crack
problem, K at the tips; more than one solve where PLS tried several angles) and, every
`--every` steps, a fresh solve of the same step's scene timed alone. Printed: a table of
per-step cost against the fresh solve, the solves per step, and the totals.

    python benchmarks/growth.py                 # 50 steps, PLS (the default)
    python benchmarks/growth.py --steps 10 --criterion mts

No number here is a test threshold: the machine is shared and timings are noisy.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--criterion", default="pls")
    parser.add_argument("--every", type=int, default=10, help="time a fresh solve of every N-th step's scene")
    parser.add_argument("--friction", type=float, default=0.3)
    args = parser.parse_args(argv)

    import ngcrack as nc
    from ngcrack.solve import solve

    scene = nc.scenes.SCENE_FUNCTIONS["inclined-crack"](angle=45.0, load=-1.0).with_(friction=args.friction)
    t0 = time.perf_counter()
    res = nc.grow(scene, da=0.1, steps=args.steps, K_Ic=1.0, criterion=args.criterion, frames=False)
    total = time.perf_counter() - t0
    df = res.table.groupby("step").first()
    print(f"{scene.name}, friction {args.friction:g}, {args.criterion}, da 0.1: {len(res.steps)} steps in {total:.1f} s "
          f"({total / len(res.steps):.2f} s per step); stopped: {res.stopped}")
    print(f"{'step':>4} {'ndof':>7} {'solves':>6} {'step s':>7} {'fresh s':>8} {'step/fresh':>10} {'per solve/fresh':>15}")
    ratios = []
    for n, row in df.iterrows():
        fresh = ""
        if n % args.every == 0 or n == df.index[-1]:
            t1 = time.perf_counter()
            solve(res.scenes[n])
            f = time.perf_counter() - t1
            ratios.append((row.time_s / f, row.time_s / row.solves / f))
            fresh = f"{f:8.2f} {ratios[-1][0]:10.2f} {ratios[-1][1]:15.2f}"
        print(f"{n:>4} {row.ndof:>7} {row.solves:>6} {row.time_s:>7.2f} {fresh}")
    solves = df.solves.to_numpy()
    print(f"solves per step: mean {solves[1:].mean():.2f} (steps after the first), max {solves.max()}")
    r = np.array(ratios)
    print(f"step / fresh solve: median {np.median(r[:, 0]):.2f}; per solve / fresh solve: median {np.median(r[:, 1]):.2f}")
    print(f"total for {len(res.steps)} steps: {total:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
