"""Higher order and hp at the tips: error against unknowns and CPU time, and where the time goes.

Table 1 (`hp`): griffith and inclined-compression, bdm and tdnns of order 1-3, on the hp
meshes of ngcrack.planar.hp (`hp_mesh(scene, L)`: the coarse base mesh plus L geometric layers
of ratio 0.2 towards every tip) for L = 0, 1, ..., and, for comparison, on the scene's
own graded mesh ("own"). Errors are relative, against the finite plates' converged
answers (REFERENCES: order 3, 8 and 10 layers, base meshes maxh 1 and 0.5, bdm and tdnns
agreeing to the digits given): griffith K_I and the opening int_0^a [u].nu ds;
inclined-compression K_II at both tips (the larger error) and the sliding int [u].t ds;
"centre" is the opening at the crack's centre (griffith, s = 0) or the sliding at its
centre (inclined), from the jump polynomials (`hp.jump_at`).
"ratio" is the opening's (griffith) or sliding's (inclined) error over that of one
layer fewer. CPU s is the process time of meshing plus solving (tips and estimate
included), NGSolve on one thread (NGCRACK_THREADS=1 unless set).

Table 2 (`speed`): on griffith's own mesh and on a mesh of about 2e5 unknowns per
order, the solve's stages: assembly (the element's spaces and forms, NGSolve's static
condensation, the condensed system in scipy), the linear solve (factorization, solve,
recovery of the local unknowns), the crack's Schur complement and QP; asm/lin is the
ratio of the first two.

    python benchmarks/higher_order.py                 # both tables
    python benchmarks/higher_order.py hp --layers 0 1 2 3 4 --orders 3
    python benchmarks/higher_order.py speed

No number here is a test threshold.
"""

from __future__ import annotations

import argparse
import math
import os
import time

os.environ.setdefault("NGCRACK_THREADS", "1")  # one thread (process time = wall time), before ngcrack loads


from ngcrack import scenes
from ngcrack.core.solve import solve
from ngcrack.planar import hp

#: the finite plates' converged answers (see tests/test_hp.py for their uncertainty)
REFERENCES = {
    "griffith": {"K_I": 1.789047, "opening": 2.885691e-3, "centre": 1.009397 * 4 * 0.91e-3},
    "inclined-compression": {"K_II": (-0.7694174, -0.7698117), "sliding": -2.482696e-3, "centre": -1.580538e-3},
}


def errors(name: str, sol) -> dict:
    ref = REFERENCES[name]
    opening, sliding = hp.jump_integrals(sol)
    if name == "griffith":
        return {"K": abs(sol.tips[0].K_I / ref["K_I"] - 1), "jump": abs(opening / ref["opening"] - 1),
                "centre": abs(hp.jump_at(sol, 0.0)[0] / ref["centre"] - 1)}
    return {"K": max(abs(t.K_II / r - 1) for t, r in zip(sol.tips, ref["K_II"])),
            "jump": abs(sliding / ref["sliding"] - 1), "centre": abs(hp.jump_at(sol, 1.0)[1] / ref["centre"] - 1)}


def hp_table(names, elements, orders, layers, own: bool) -> list[dict]:
    rows = []
    print(f"{'scene':22s} {'element':8s} {'mesh':5s} {'unknowns':>9s} {'global':>7s} {'CPU s':>6s} "
          f"{'K err':>8s} {'open/slide err':>14s} {'ratio':>6s} {'centre err':>10s}")
    for name in names:
        scene = scenes.load(name)
        for element in elements:
            for order in orders:
                cases = (["own"] if own else []) + list(layers)
                previous = None
                for L in cases:
                    c0 = time.process_time()
                    cmesh = None if L == "own" else hp.hp_mesh(scene, L)
                    sol = solve(scene, element=element, order=order, crack_mesh=cmesh)
                    cpu = time.process_time() - c0
                    err = errors(name, sol)
                    ratio = err["jump"] / previous if previous and L != "own" else math.nan
                    previous = err["jump"] if L != "own" else previous
                    row = {"scene": name, "element": f"{element} {order}", "mesh": str(L),
                           "unknowns": sol.ndof["total"], "global": sol.ndof["global"], "cpu": cpu, **err,
                           "ratio": ratio}
                    rows.append(row)
                    print(f"{name:22s} {row['element']:8s} {row['mesh']:5s} {row['unknowns']:9d} {row['global']:7d} "
                          f"{cpu:6.2f} {err['K']:8.1e} {err['jump']:14.1e} {ratio:6.2f} {err['centre']:10.1e}", flush=True)
    return rows


#: griffith maxh (crack_h, tip_h from the scene) giving about 2e5 unknowns per order
SPEED_MAXH = {("bdm", 1): 0.2, ("bdm", 2): 0.3, ("bdm", 3): 0.4, ("tdnns", 1): 0.2, ("tdnns", 2): 0.3,
              ("tdnns", 3): 0.4}


def speed_table(elements, orders, repeats: int = 2) -> list[dict]:
    scene = scenes.load("griffith")
    rows = []
    print(f"{'element':8s} {'mesh':9s} {'unknowns':>9s} {'global':>7s} {'assemble':>8s} {'linear':>7s} "
          f"{'schur+qp':>8s} {'asm/lin':>7s}")
    for element in elements:
        for order in orders:
            for label, maxh in (("own", None), ("maxh " + str(SPEED_MAXH[(element, order)]), SPEED_MAXH[(element, order)])):
                best = None
                for _ in range(repeats):  # the machine is shared: keep the faster run
                    sol = solve(scene, element=element, order=order, maxh=maxh)
                    t = sol.timings
                    if best is None or t["assemble"] + t["linear"] < best["assemble"] + best["linear"]:
                        best = dict(t)
                row = {"element": f"{element} {order}", "mesh": label, "unknowns": sol.ndof["total"],
                       "global": sol.ndof["global"], "assemble": best["assemble"], "linear": best["linear"],
                       "crack": best["schur"] + best["qp"]}
                row["ratio"] = row["assemble"] / row["linear"]
                rows.append(row)
                print(f"{row['element']:8s} {label:9s} {row['unknowns']:9d} {row['global']:7d} {row['assemble']:8.2f} "
                      f"{row['linear']:7.2f} {row['crack']:8.3f} {row['ratio']:7.2f}", flush=True)
    return rows


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("table", nargs="*", default=["hp", "speed"], choices=["hp", "speed"])
    parser.add_argument("--scenes", nargs="+", default=["griffith", "inclined-compression"])
    parser.add_argument("--elements", nargs="+", default=["bdm", "tdnns"])
    parser.add_argument("--orders", nargs="+", type=int, default=[1, 2, 3])
    parser.add_argument("--layers", nargs="+", type=int, default=[0, 1, 2, 3, 4, 5, 6])
    parser.add_argument("--no-own", action="store_true", help="leave out the scene's own mesh")
    args = parser.parse_args(argv)
    if "hp" in args.table:
        hp_table(args.scenes, args.elements, args.orders, args.layers, own=not args.no_own)
    if "speed" in args.table:
        speed_table(args.elements, args.orders)


if __name__ == "__main__":
    main()
