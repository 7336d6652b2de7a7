"""Which element when: error against CPU time of every element on two scenes with finite-body references.

    python benchmarks/element_choice.py [--nu 0.3 0.4999] [--levels 2]

For `griffith` (K_I and the opening) and `inclined-compression` (K_II and the sliding of
the closed crack under compression), at each Poisson ratio (default 0.3 and 0.4999) and on
`--levels` meshes (the scene's default mesh, then maxh and crack_h halved and tip_h / 5
per level) and a strongly graded one (GRADED: maxh 2, crack_h 0.2, tip_h 5e-4, grading
0.5): every element (tdnns also at orders 2 and 3), its unknowns, the CPU seconds
of the whole solve on one thread, and its errors against the finite plate's converged
answer (ngcrack.studies.references: K, max over the tips of |K - K_ref| / |K_ref|; profile,
relative L2 error over the crack edges' mid points weighted by their lengths), the
infinite plate's closed-form opening error beside them. Prints Markdown tables.
Expect +-30% on CPU times (shared machine).
"""

from __future__ import annotations

import os

for _v in ("NGCRACK_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import sys
import time

import ngcrack as nc
from ngcrack import references
from ngcrack.planar.elements import ELEMENTS

RUNS = [(el, None) for el in ELEMENTS] + [("tdnns", 2), ("tdnns", 3)]
SCENES = ("griffith", "inclined-compression")


#: a strongly graded mesh: coarse far field, fine tips, fast growth between (benchmarks/getfem_peer.py)
GRADED = {"maxh": 2.0, "crack_h": 0.2, "tip_h": 5e-4, "grading": 0.5}


def mesh(scene, level) -> dict:
    if level == "graded":
        return dict(GRADED)
    return {"maxh": scene.maxh / 2**level, "crack_h": scene.crack_h / 2**level, "tip_h": scene.tip_h / 5**level}


def measure(name: str, element: str, order, nu: float, level: int) -> dict:
    scene = nc.scenes.load(name).with_(nu=nu)
    t0 = time.process_time()
    sol = nc.solve(scene, element=element, order=order, **mesh(nc.scenes.load(name), level))
    cpu = time.process_time() - t0
    e = references.errors(sol, references.reference(name, nu))
    return {"cpu": cpu, "ndof": sol.ndof["total"], **e}


def main() -> None:
    nus = [float(v) for v in sys.argv[sys.argv.index("--nu") + 1:] if not v.startswith("--")] if "--nu" in sys.argv \
        else [0.3, 0.4999]
    levels = int(sys.argv[sys.argv.index("--levels") + 1]) if "--levels" in sys.argv else 2
    for nu in nus:
        print(f"\n### nu = {nu:g}\n")
        print("| element | mesh | griffith: unknowns | CPU s | K_I error | opening error | opening vs closed form "
              "| inclined: unknowns | CPU s | K_II error | sliding error | sliding vs closed form |")
        print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for element, order in RUNS:
            for level in [*range(levels), "graded"]:
                try:
                    g, i = (measure(name, element, order, nu, level) for name in SCENES)
                except ValueError as exc:  # e.g. an h1 baseline refusing a Poisson ratio
                    print(f"| {element} | level {level} | refused: {exc} |")
                    break
                label = element + (f" order {order}" if order else "")
                print(f"| {label} | {'default' if level == 0 else level if level == 'graded' else f'level {level}'} | {g['ndof']} | {g['cpu']:.2f} | "
                      f"{g['K']:.1e} | {g['profile']:.1e} | {100 * g['profile_closed_form']:.2f}% | "
                      f"{i['ndof']} | {i['cpu']:.2f} | {i['K']:.1e} | {i['profile']:.1e} | "
                      f"{100 * i['profile_closed_form']:.2f}% |", flush=True)


if __name__ == "__main__":
    main()
