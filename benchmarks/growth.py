"""Crack growth: the cost of a growth step against a fresh solve, and the total CPU of a run.

The README's teaching scene: `inclined-compression` (the plate [-10, 10]^2, a crack of
half-length 1 at 30 degrees, remote compression sigma_yy = -1, its mesh maxh 1, tip_h
0.005, crack_h 0.05) with friction 0.3 on the crack; wing cracks grow from both tips,
da = 0.1, K_Ic = 2, PLS, the default element, growth's default path grading (the grown
path coarser with the distance from the tips, `ngcrack.planar.path_sizes`). Printed per step:
ndof, the solves that made it (more than one: PLS trials), its wall-clock seconds split
into meshing, assembly, linear solves, the crack problem and post-processing (the tips' K
and the error estimate); every `--every` steps a fresh solve of the same step's scene
timed alone; then the solves per step and the run's CPU seconds (process time: the
machine is shared, wall-clock times vary with its load, printed with `uptime`).

    python benchmarks/growth.py                        # 50 steps, PLS (the default)
    python benchmarks/growth.py --steps 20 --criterion mts
    python benchmarks/growth.py --path-grading none    # the whole path meshed at crack_h
    python benchmarks/growth.py --compare              # also the run with the path at crack_h, compared
    python benchmarks/growth.py --crack-h 0.1          # also the run with crack_h 0.1 everywhere, compared

With --compare (or --crack-h H) a second run is made and the two are compared step by
step: CPU, solves, unknowns, seconds by part, the largest differences of the tips' kinks,
K_II and load factors over the steps both runs made, and the final tips' positions.

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
    parser.add_argument("--path-grading", default=None,
                        help="the path's grading rate, or none: crack_h all along (default: growth's)")
    parser.add_argument("--compare", action="store_true", help="also run with the path at crack_h and compare")
    args = parser.parse_args(argv)
    grading = {} if args.path_grading is None else {
        "path_grading": None if args.path_grading.lower() == "none" else float(args.path_grading)}

    import ngcrack as nc
    from ngcrack.core.solve import solve
    from ngcrack.studies.growth.solves import growth_solve_options

    print(f"load average before: {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")
    scene = nc.scenes.load("inclined-compression").with_(friction=args.friction)
    c0, t0 = time.process_time(), time.perf_counter()
    res = nc.grow(scene, da=0.1, steps=args.steps, K_Ic=2.0, criterion=args.criterion, frames=False, **grading)
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
            solve(res.scenes[n], **growth_solve_options(scene, grading))  # growth's own options
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
        compare(nc, scene, res, cpu, args, f"crack_h {args.crack_h:g}", crack_h=args.crack_h, **grading)
    if args.compare:
        other = compare(nc, scene, res, cpu, args, "path at crack_h", path_grading=None)
        same_scenes(nc, other, args.every // 2 or 1)
    return 0


def compare(nc, scene, res, cpu, args, what: str, **options) -> None:
    """The same run with `options` (`what`): its CPU, solves, unknowns and seconds by part, and how
    far its path's numbers are from the first run's, step by step (tips matched by crack and end)."""
    c0 = time.process_time()
    other = nc.grow(scene, da=0.1, steps=args.steps, K_Ic=2.0, criterion=args.criterion, frames=False, **options)
    cpu2 = time.process_time() - c0
    a, b = res.table, other.table
    keys = ["step", "crack", "end"]
    both = a.merge(b, on=keys, suffixes=("", "_b"))
    both = both[both.step <= min(a.step.max(), b.step.max())]
    scale = float(np.abs(a.K_II).max())
    lf = (both.load_factor_b / both.load_factor - 1).abs()
    parts = ["mesh_s", "assembly_s", "linear_s", "crack_s", "post_s"]
    print(f"\n| run | steps | solves | CPU s | unknowns, first to last step | {' | '.join(p[:-2] for p in parts)} |\n"
          + "|---" * (5 + len(parts)) + "|")
    for name, r, c in (("this run", res, cpu), (what, other, cpu2)):
        t = r.table.groupby("step").first()
        print(f"| {name} | {len(r.steps) - 1} | {int(t.solves.sum())} | {c:.1f} | {int(t.ndof.iloc[0])} to "
              f"{int(t.ndof.iloc[-1])} | " + " | ".join(f"{t[p].sum():.1f}" for p in parts) + " |")
    kinks = both[both.kink_deg.notna() & both.kink_deg_b.notna()]
    dk = (kinks.kink_deg_b - kinks.kink_deg).abs()
    last = both[both.step == both.step.max()]
    tips = np.hypot(last.x - last.x_b, last.y - last.y_b)
    print(f"over steps 0-{int(both.step.max())}: kink differs by at most {dk.max():.2f} degrees (mean {dk.mean():.2f}; "
          f"grown tips), K_II by {np.abs(both.K_II_b - both.K_II).max() / scale:.2e} of the largest |K_II|, the step's "
          f"load factor by at most {lf.max():.2e} (mean {lf.mean():.2e}, relative); the last step's tips "
          f"{tips.max():.2e} apart; stopped: {other.stopped}")
    return other


def same_scenes(nc, uniform, every: int) -> None:
    """Every `every`-th grown scene of the run with the path at crack_h, solved again with growth's
    path grading: how far K moves on the same geometry (no path divergence), and the unknowns."""
    from ngcrack.studies.growth.checks import GROWTH_PATH_GRADING

    print(f"\nthe same grown scenes (every {every}-th step of the run with the path at crack_h), graded "
          f"(path_grading {GROWTH_PATH_GRADING:g}): |dK_I| / K, |dK_II| / K, K = max(|K_I|, |K_II|) (largest over the tips)")
    print("| step | unknowns at crack_h | graded | dK_I / K | dK_II / K |\n|---|---|---|---|---|")
    worst = [0.0, 0.0]
    for n in range(0, len(uniform.scenes), every):
        fine = nc.solve(uniform.scenes[n])
        coarse = nc.solve(uniform.scenes[n], path_grading=GROWTH_PATH_GRADING)
        scale = [max(abs(s.K_I), abs(s.K_II)) for s in fine.tips]  # K_I, or K_II where the tip is closed
        d1 = max(abs(t.K_I - s.K_I) / k for s, t, k in zip(fine.tips, coarse.tips, scale))
        d2 = max(abs(t.K_II - s.K_II) / k for s, t, k in zip(fine.tips, coarse.tips, scale))
        worst = [max(worst[0], d1), max(worst[1], d2)]
        print(f"| {n} | {fine.ndof['total']} | {coarse.ndof['total']} | {d1:.1e} | {d2:.1e} |")
    print(f"largest: dK_I / K {worst[0]:.1e}, dK_II / K {worst[1]:.1e}")


if __name__ == "__main__":
    raise SystemExit(main())
