"""Point supports and the load-displacement record: what they cost beside a solve.

The built-in scene `three-point-bend` (a pin and a roller point, a force point) at three
mesh sizes, tdnns. For each: the solve with its point supports; the same body with the two
support segments clamped and on a roller edge instead (the same mesh: the segments are
labelled edges either way), so that the difference is the mean constraints' change of basis
(Z^T K Z in the condensed system); the tips' time (K_I, K_II, G and the T-stress, one
domain integral); and `load_point_values` (every point's force and mean displacement: the
reactions from the residual of the full form, one linear form per label and direction), which
growth computes at every step. Printed: a table of seconds (the medians of --repeat runs).

    OMP_NUM_THREADS=1 python benchmarks/points.py [--repeat 3]

No number here is a test threshold: the machine is shared and timings are noisy.
"""

from __future__ import annotations

import argparse
import statistics
import time


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--maxh", type=float, nargs="+", default=[0.25, 0.125, 0.0625])
    args = parser.parse_args(argv)

    import ngcrack as nc
    from ngcrack.planar.load_points import load_point_values

    bend = nc.scenes.load("three-point-bend")
    force = [pc for pc in bend.points if pc.type == "force"]
    edges = nc.Scene(name="three-point-bend-edges", polygon=bend.polygon, labels=bend.labels, cracks=bend.cracks,
                     material=bend.material, points=force, tip_h=bend.tip_h,
                     boundary={"support-left": {"type": "clamped"}, "support-right": {"type": "roller"}})
    rows = []
    for maxh in args.maxh:
        t = {"points": [], "edges": [], "tips": [], "record": [], "assemble_points": [], "assemble_edges": []}
        for _ in range(args.repeat):
            sol = nc.solve(bend, maxh=maxh)
            t["points"].append(sol.timings["total"])
            t["assemble_points"].append(sol.timings["assemble"])
            t["tips"].append(sol.timings["tips"])
            t0 = time.perf_counter()
            load_point_values(sol)
            t["record"].append(time.perf_counter() - t0)
            sol_e = nc.solve(edges, maxh=maxh)
            t["edges"].append(sol_e.timings["total"])
            t["assemble_edges"].append(sol_e.timings["assemble"])
        med = {k: statistics.median(v) for k, v in t.items()}
        rows.append((maxh, sol.ndof["total"], sol.ndof["global"], med))
    print("| maxh | unknowns (global) | solve, point supports | solve, clamped + roller edges "
          "| assemble + condense: points / edges | tips (K, G, T) | load_point_values |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    for maxh, n, g, m in rows:
        print(f"| {maxh:g} | {n} ({g}) | {m['points']:.3f} s | {m['edges']:.3f} s | {m['assemble_points']:.3f} / "
              f"{m['assemble_edges']:.3f} s | {m['tips']:.3f} s | {m['record']:.3f} s |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
