"""Varying loads in 3D: serial, MPI and the estimate (BENCHMARKS: "Varying loads in 3D").

A penny of radius a = 1 in a box of 6a (E = 1000, nu = 0.3, clamped at z = -3) under a
crack-face pressure given as a number, a table, or a Python callable, on one mesh
(`--front-h`, default 0.3a; order 1): per load, the CPU seconds of the scene's build (a
callable: its evaluation on the interpolation grid), of the solve (mesh shared, so the
first case carries the meshing) and of the Prager-Synge estimate; K_I against the closed
form (the penny's weight function: uniform 2 p0 sqrt(a/pi); p0 (r/a)^2: 2/3 of it; p0 x/a on
free faces: (4/3) p0 sqrt(a/pi) cos theta), and the estimate's crack and data terms. The
last row adds a quadratic traction g_z = x^2/4 on the top face (its data term).

    python benchmarks/varying_loads3d.py [--front-h 0.3] [--order 1]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from ngcrack.core.options import SolveOptions
from ngcrack.core.pipeline import Pipeline
from ngcrack.solid.scene import SolidScene
from ngcrack.solid.stages import SOLID

UNIFORM_K = 2.0 / math.sqrt(math.pi)  # 2 p0 sqrt(a / pi), p0 = a = 1


def penny(p, front_h: float, traction=None) -> dict:
    d = {"name": "penny", "domain": {"box": [[-3, -3, -3], [3, 3, 3]]},
         "crack": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0, "pressure": p}],
         "material": {"E": 1000.0, "nu": 0.3}, "boundary": {"zmin": {"type": "clamped"}},
         "mesh": {"maxh": 1.5, "crack_h": 2.0 * front_h, "front_h": front_h}}
    if traction is not None:
        d["boundary"]["zmax"] = {"type": "traction", "value": traction}
    return d


CASES = [  # name, pressure, crack model, the closed form K_I(points), traction
    ("uniform, number", 1.0, "contact", lambda pts: UNIFORM_K + 0 * pts[:, 0], None),
    ("uniform, callable", lambda x, y, z: 1.0, "contact", lambda pts: UNIFORM_K + 0 * pts[:, 0], None),
    ("p0 x/a, table, free faces", {"axis": [1, 0, 0], "table": [[-1, -1.0], [1, 1.0]]}, "free",
     lambda pts: 2.0 / 3.0 * UNIFORM_K * pts[:, 0] / np.linalg.norm(pts[:, :2], axis=1), None),
    ("p0 (r/a)^2, callable", lambda x, y, z: x * x + y * y, "contact", lambda pts: 2.0 / 3.0 * UNIFORM_K + 0 * pts[:, 0], None),
    ("p0 (r/a)^2 + g_z = x^2/4", lambda x, y, z: x * x + y * y, "contact", None, lambda x, y, z: (0.0, 0.0, 0.25 * x * x)),
]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--front-h", type=float, default=0.3)
    ap.add_argument("--order", type=int, default=1)
    args = ap.parse_args()
    pipeline = Pipeline()
    print(f"penny a = 1, front_h = {args.front_h}, order {args.order}")
    print("| load | build CPU s | solve CPU s | estimate CPU s | K_I error (of the uniform K) | eta | crack term / eta^2 | data |")
    print("|---|---|---|---|---|---|---|---|")
    for name, p, model, exact, traction in CASES:
        t0 = time.process_time()
        scene = SolidScene.from_dict(penny(p, args.front_h, traction))
        t1 = time.process_time()
        sol = SOLID.solve(pipeline, scene, SolveOptions(order=args.order, crack_model=model))
        t2 = time.process_time()
        est = sol.error_estimate
        t3 = time.process_time()
        (front,) = sol.fronts
        err = "-" if exact is None else f"{np.abs(front.K_I - exact(front.points)).max() / UNIFORM_K:.2%}"
        print(f"| {name} | {t1 - t0:.2f} | {t2 - t1:.1f} | {t3 - t2:.1f} | {err} | {est['total']:.4g} | "
              f"{est['contact'] / est['total'] ** 2:.1e} | {est['data']:.2g} |")


if __name__ == "__main__":
    main()
