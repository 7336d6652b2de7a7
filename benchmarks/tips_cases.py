"""K_I, K_II errors per element on the checks with known answers, at the scenes' default meshes.

    python benchmarks/tips_cases.py [--elements bdm tdnns ...] [--out cases.csv]

Cases: the inclined crack (30 degrees) under tension and, closed and frictionless, under
compression (closed forms for the infinite plate, `nc.scenes.inclined_closed_form`), the
centre-cracked strip (a/b = 0.2 ... 0.8) and the single-edge-cracked strip (a/b = 0.1 ...
0.7) against Tada, Paris and Irwin (`nc.scenes.handbook`). Errors are relative to
|p| sqrt(pi a) for the inclined crack (K_I is zero under compression) and to the handbook
K_I for the strips; the worse of the two tips is reported. Also: the solve's total time
and the share the tips' domain integrals take of it.
"""

from __future__ import annotations

import argparse
import math

import pandas as pd

import ngcrack as nc
from ngcrack.scenes import handbook
from ngcrack.studies import sweeps


def cases():
    for load in (1.0, -1.0):
        scene = nc.scenes.inclined_crack(angle=30.0, load=load)
        ex = nc.scenes.inclined_closed_form(scene)
        yield f"inclined 30deg, p={load:+g}", scene, ex["K_I"], ex["K_II"], abs(load) * math.sqrt(math.pi)
    for lam in (0.2, 0.4, 0.6, 0.8):
        K = handbook.centre_cracked_K(lam)
        yield f"centre strip a/b={lam:g}", handbook.centre_cracked_strip(lam), K, 0.0, K
    for lam in (0.1, 0.3, 0.5, 0.7):
        K = handbook.edge_cracked_K(lam)
        yield f"edge strip a/b={lam:g}", handbook.edge_cracked_strip(lam), K, 0.0, K


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--elements", nargs="+", default=list(nc.ELEMENTS))
    p.add_argument("--out", default=None)
    args = p.parse_args()
    rows = []
    for case, scene, K_I, K_II, scale in cases():
        for el in args.elements:
            sol = nc.solve(scene, element=el)
            rows.append({"case": case, "element": el, "ndof": sol.ndof["total"],
                         "err_K_I": max(abs(t.K_I - K_I) for t in sol.tips) / scale,
                         "err_K_II": max(abs(t.K_II - K_II) for t in sol.tips) / scale,
                         "time_total": sol.timings["total"], "tips_share": sol.timings["tips"] / sol.timings["total"]})
            print(rows[-1], flush=True)
    df = pd.DataFrame(rows)
    print(sweeps.markdown_table(df, floatfmt=".3g"))
    print(sweeps.markdown_table(df.pivot_table(index="case", columns="element", values="err_K_I", sort=False)
                               .reset_index(), floatfmt=".2%"))
    if args.out:
        df.to_csv(args.out, index=False)


if __name__ == "__main__":
    main()
