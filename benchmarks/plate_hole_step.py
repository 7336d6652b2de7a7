"""The STEP example: a plate with a hole written with netgen.occ, and its scene solved.

    python benchmarks/plate_hole_step.py            # writes examples/plate-hole.step
    python benchmarks/plate_hole_step.py --solve    # ... and solves examples/plate-hole.toml

The plate is 8 x 4 x 1 (x from -4 to 4, y from -2 to 2, z from -0.5 to 0.5) with a hole of
radius 0.5 through its thickness at the origin; its faces are named in the file: ``left``
(x = -4), ``right`` (x = 4), ``hole``, ``top`` (z = 0.5), ``bottom``, ``front`` (y = -2) and
``back``. The scene (examples/plate-hole.toml) pulls the plate along x by tractions on its
ends, holds it by 3-2-1 point supports (which do not constrain it) and puts a penny crack of
radius 0.2 in the plane x = 0 just above the hole (its nearest point 0.2 from it). With --solve
the script prints K_I along the front over a rough reference: the penny's 2 s sqrt(a / pi) in the
stress s that Kirsch's plane solution gives at the crack's centre (1.30 times the remote one at
y = 1.8 hole radii), which the hole's gradient over the crack and the plate's thickness modify.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
STEP = ROOT / "examples" / "plate-hole.step"
SCENE = ROOT / "examples" / "plate-hole.toml"
#: the plate's half sizes and the hole's radius
HALF = (4.0, 2.0, 0.5)
HOLE_RADIUS = 0.5


def write_step(path: Path = STEP) -> Path:
    """The plate with its hole, faces named, written as STEP."""
    from netgen import occ

    hx, hy, hz = HALF
    part = occ.Box(occ.Pnt(-hx, -hy, -hz), occ.Pnt(hx, hy, hz)) - occ.Cylinder(
        occ.Pnt(0, 0, -2 * hz), occ.Dir(0, 0, 1), HOLE_RADIUS, 4 * hz)
    names = {(-hx, 0): "left", (hx, 0): "right", (-hy, 1): "front", (hy, 1): "back", (-hz, 2): "bottom", (hz, 2): "top"}
    for f in part.faces:
        c = (f.center.x, f.center.y, f.center.z)
        f.name = next((n for (v, k), n in names.items() if abs(c[k] - v) < 1e-9), "hole")
    path.parent.mkdir(parents=True, exist_ok=True)
    part.WriteStep(str(path))
    return path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--solve", action="store_true", help="solve examples/plate-hole.toml and print K_I along the front")
    args = ap.parse_args()
    print(f"wrote {write_step()}")
    if not args.solve:
        return
    import numpy as np

    import ngcrack as nc

    scene = nc.Scene.from_toml(SCENE)
    t0 = time.process_time()
    sol = nc.solve(scene)
    (front,) = sol.fronts
    a, y = scene.cracks[0].radius, scene.cracks[0].center[1] / HOLE_RADIUS
    kirsch = 1.0 + 0.5 / y**2 + 1.5 / y**4  # sigma_xx / sigma on the line x = 0 beside a hole in tension along x
    ref = 2 * kirsch * math.sqrt(a / math.pi)
    print("| unknowns | K_I min / ref | K_I max / ref | CPU s |")
    print("|---|---|---|---|")
    print(f"| {sol.ndof['total']:,} | {np.min(front.K_I) / ref:.3f} | {np.max(front.K_I) / ref:.3f} | "
          f"{time.process_time() - t0:.1f} |")


if __name__ == "__main__":
    main()
