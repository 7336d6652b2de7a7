"""3D elements side by side: hybridized TDNNS against the displacement baselines h1p1/h1p2.

Prints two tables (one thread; the machine's load printed first):

1. a cube clamped at x = 0 under gravity: the tip displacement u_z(1, 0.5, 0.5) of each
   element at nu = 0.3 and 0.4999, over the reference (TDNNS order 2 on the finer mesh);
2. the penny crack (a = 1 in a block of side 20a, tension p = 1, E = 1000): the centre
   opening (mean over rho < 0.3a) and K_I (least and largest over the front) over
   Sneddon's, for nu = 0.3 and 0.4999, with the unknowns and the CPU seconds of the solve;
   and the same penny with the load as a pressure on the faces (no remote load).

Usage: OMP_NUM_THREADS=1 python benchmarks/solid_elements.py [--quick] [--penny]
(--quick: the coarse meshes only; --penny: the penny table only).
"""

from __future__ import annotations

import copy
import math
import os
import sys
import time

import numpy as np

import ngcrack as nc
from ngcrack.solid.geometry import make_mesh
from ngcrack.solid.scene import SolidScene

CUBE = {"name": "cube", "domain": {"box": [[0, 0, 0], [1, 1, 1]]}, "material": {"E": 1.0, "nu": 0.3},
        "load": {"body_force": [0, 0, -1e-3]}, "boundary": {"xmin": {"type": "clamped"}}}
PENNY = {"name": "penny", "domain": {"box": [[-10.0, -10.0, -10.0], [10.0, 10.0, 10.0]]},
         "crack": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0}],
         "material": {"E": 1000.0, "nu": 0.3},
         "boundary": {"xmin": {"type": "roller"}, "ymin": {"type": "roller"}, "zmin": {"type": "roller"},
                      "zmax": {"type": "traction", "value": [0.0, 0.0, 1.0]}}}
ELEMENTS = (("tdnns", 1), ("tdnns", 2), ("h1p1", 1), ("h1p2", 2))
#: on the penny, TDNNS order 2 is left out (5 GB at front_h = 0.2a: benchmarks/penny.py measures it)
PENNY_ELEMENTS = (("tdnns", 1), ("h1p1", 1), ("h1p2", 2))


def cube_table(sizes) -> None:
    tip = {}
    for maxh in sizes:
        d = dict(CUBE, mesh={"maxh": maxh})
        s = SolidScene.from_dict(d)
        sm = make_mesh(s)
        for nu in (0.3, 0.4999):
            for el, k in ELEMENTS:
                tip[maxh, nu, el, k] = nc.solve(s.with_(nu=nu), crack_mesh=sm, element=el, order=k).u(sm.mesh(1, .5, .5))[2]
    fine = min(sizes)
    print("\nclamped cube, u_z at the tip over TDNNS order 2 at maxh", fine)
    print(f"{'maxh':>5} {'nu':>7} " + " ".join(f"{name(el, k):>8}" for el, k in ELEMENTS))
    for maxh in sizes:
        for nu in (0.3, 0.4999):
            ref = tip[fine, nu, "tdnns", 2]
            print(f"{maxh:5.2f} {nu:7.4f} " + " ".join(f"{tip[maxh, nu, el, k] / ref:8.4f}" for el, k in ELEMENTS))


def name(el: str, k: int) -> str:
    return el + str(k) if el == "tdnns" else el


def penny_row(scene, sm, el, k, nu) -> str:
    t = time.process_time()
    sol = nc.solve(scene, crack_mesh=sm, element=el, order=k)
    cpu = time.process_time() - t
    E = scene.material.E
    w, pts = sol.normal_jumps(), sol.disc.constraint_points
    rho = np.linalg.norm(pts[:, :2], axis=1)
    c = rho < 0.3
    sneddon = 8 * (1 - nu * nu) / (math.pi * E) * np.sqrt(1 - rho[c] ** 2)
    K = sol.fronts[0].K_I / (2 / math.sqrt(math.pi))
    return (f"{name(el, k):>7} {sol.ndof['total']:>8} {np.mean(w[c] / sneddon):8.4f} {K.min():8.4f} {K.max():8.4f} "
            f"{max(sol.kkt.values()):8.1e} {cpu:7.1f}")


def penny_table(front_hs) -> None:
    print("\npenny (a = 1, block 20a): centre opening (mean, rho < 0.3) and K_I (min, max) over Sneddon")
    for front_h in front_hs:
        mesh = {"maxh": 5.0, "crack_h": 2 * front_h, "front_h": front_h}
        base = SolidScene.from_dict(dict(PENNY, mesh=mesh))
        sm = make_mesh(base)
        for nu in (0.3, 0.4999):
            print(f"front_h {front_h}a, nu = {nu}, remote tension")
            print(f"{'element':>7} {'unknowns':>8} {'opening':>8} {'K_I min':>8} {'K_I max':>8} {'KKT':>8} {'cpu s':>7}")
            for el, k in PENNY_ELEMENTS:
                print(penny_row(base.with_(nu=nu), sm, el, k, nu), flush=True)
        d = copy.deepcopy(dict(PENNY, mesh=mesh))
        del d["boundary"]["zmax"]
        d["crack"][0]["pressure"] = 1.0
        print(f"front_h {front_h}a, nu = 0.3, pressure 1 on the faces, no remote load")
        for el, k in PENNY_ELEMENTS:
            print(penny_row(SolidScene.from_dict(d), sm, el, k, 0.3), flush=True)


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    print("load average:", os.getloadavg(), "threads:", os.environ.get("OMP_NUM_THREADS"))
    if "--penny" not in sys.argv:
        cube_table((0.3,) if quick else (0.3, 0.15))
    penny_table((0.2,) if quick else (0.2, 0.15))
