"""3D point supports, loads that vary and a STEP part: the checks against exact fields and closed forms.

    python benchmarks/solid_supports.py

Prints one table: the relative L2 error of the stress against the exact field for a box
2 x 1 x 1 in tension and in bending held by 3-2-1 point supports (the largest reaction for the
tension case), the penny (a = 1, box 6a, front_h = 0.3a) under a uniform pressure and under
p = 1 + x / a (the largest error of K_I along the front against Sneddon's and against
2 sqrt(a / pi) + (4/3) sqrt(a / pi) cos(theta), in units of the uniform case's K_I), and the STEP
example (examples/plate-hole.toml, written by plate_hole_step.py): K_I along its front over the
penny's in Kirsch's stress at the crack's centre. CPU seconds per solve, one thread.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import ngsolve as ngs
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))


def main() -> None:
    import test_solid_loads as tl
    import test_solid_points as tp
    from plate_hole_step import SCENE, write_step

    import ngcrack as nc
    from ngcrack.solid.point_means import point_values
    from ngcrack.solid.scene import SolidScene

    rows = []
    tension = ngs.CF((1, 0, 0, 0, 0, 0, 0, 0, 0), dims=(3, 3))
    bending = ngs.CF((-ngs.z, 0, 0, 0, 0, 0, 0, 0, 0), dims=(3, 3))
    for case, scene, exact in (("tension, 3-2-1 points", SolidScene.from_dict(tp._box()), tension),
                               ("bending (table), 3-2-1 points", SolidScene.from_dict(tl._bent(*tl.TABLES)), bending)):
        for element, order in (("tdnns", 1), ("tdnns", 2), ("h1p2", None)):
            t0 = time.process_time()
            sol = nc.solve(scene, element=element, order=order)
            react = max(np.abs(v["force"]).max() for v in point_values(sol).values())
            rows.append((case, f"{element} {order or ''}".strip(), sol.ndof["total"],
                         f"stress {tp._stress_error(sol, exact):.1e}, reaction {react:.1e}", time.process_time() - t0))
    unit = 2.0 * math.sqrt(1.0 / math.pi)
    for name, p, p1 in (("penny, uniform pressure", 1.0, 0.0),
                        ("penny, p = 1 + x/a (table)", {"axis": [1, 0, 0], "table": [[-1, 0.0], [1, 2.0]]}, 1.0),
                        ("penny, p = 1 + x/a (callable)", lambda x, y, z: 1.0 + x, 1.0)):
        t0 = time.process_time()
        sol = nc.solve(SolidScene.from_dict(tl._penny(p)))
        (front,) = sol.fronts
        cos = front.points[:, 0] / np.linalg.norm(front.points[:, :2], axis=1)
        err = np.abs(front.K_I - unit - 4.0 / 3.0 * p1 * math.sqrt(1.0 / math.pi) * cos).max() / unit
        rows.append((name, "tdnns 1", sol.ndof["total"], f"K_I {100 * err:.2f}%", time.process_time() - t0))
    write_step()
    scene = nc.Scene.from_toml(SCENE)
    t0 = time.process_time()
    sol = nc.solve(scene)
    a, y = scene.cracks[0].radius, scene.cracks[0].center[1] / 0.5
    ref = 2 * (1.0 + 0.5 / y**2 + 1.5 / y**4) * math.sqrt(a / math.pi)
    rows.append(("STEP plate with a hole, 3-2-1 points", "tdnns 1", sol.ndof["total"],
                 f"K_I / ref {sol.fronts[0].K_I.min() / ref:.3f}-{sol.fronts[0].K_I.max() / ref:.3f}", time.process_time() - t0))
    print("| case | element | unknowns | error | CPU s |")
    print("|---|---|---|---|---|")
    for case, element, n, err, cpu in rows:
        print(f"| {case} | {element} | {n:,} | {err} | {cpu:.1f} |")


if __name__ == "__main__":
    main()
