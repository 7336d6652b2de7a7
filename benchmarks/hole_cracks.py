"""Cracks at a hole in a STEP plate: a through crack against Bowie, corner cracks against Newman-Raju.

    python benchmarks/hole_cracks.py            # writes examples/hole-plate.step
    python benchmarks/hole_cracks.py --solve [--plot OUT.png]   # ... and solves examples/hole-through-crack.toml
                                        # and examples/hole-corner-cracks.toml, printing K_I along the fronts

The plate (written with netgen.occ, faces named ``left`` (x = -W), ``right``, ``front`` (y = -W),
``back``, ``bottom`` (z = 0), ``top`` (z = t) and ``hole``) is 2W x 2W x t with W = 12 r, t = r, and a
hole of radius r = 1 through its thickness at the origin; it is clamped at x = -W and pulled along x
(S = 1) at x = W. The cracks lie in the plane x = 0, through the hole's axis, where the hole raises the
stress to three times S:

- a through crack of length a = r/2 from the bore (a rectangle crossing the bore, the top and the
  bottom face; its front the straight side at y = r + a). Reference: Bowie's plane solution for one
  crack at a hole in an infinite plate, K = S sqrt(pi a) F(a/r), F(0.5) = 1.73
  (``ngcrack.studies.newman_raju.bowie_F``);
- two symmetric quarter-circular corner cracks of radius a = c = r/2 (a/t = 0.5, c/r = 0.5) at the
  top face's edge of the bore (ellipses centred on that edge: their parts inside the plate are the
  cracks). Reference: Newman and Raju's equation for two corner cracks at a hole
  (``ngcrack.studies.newman_raju.hole_corner_cracks_K``), phi from the plate's face (0) to the bore (90 deg).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
STEP = ROOT / "examples" / "hole-plate.step"
THROUGH = ROOT / "examples" / "hole-through-crack.toml"
CORNER = ROOT / "examples" / "hole-corner-cracks.toml"
#: the hole's radius, the plate's half-width and its thickness
RADIUS, HALF_WIDTH, THICKNESS = 1.0, 12.0, 1.0


def write_step(path: Path = STEP, r: float = RADIUS, w: float = HALF_WIDTH, t: float = THICKNESS) -> Path:
    """The plate with its hole, faces named, written as STEP."""
    from netgen import occ

    part = occ.Box(occ.Pnt(-w, -w, 0.0), occ.Pnt(w, w, t)) - occ.Cylinder(occ.Pnt(0, 0, -t), occ.Dir(0, 0, 1), r, 3 * t)
    names = {(-w, 0): "left", (w, 0): "right", (-w, 1): "front", (w, 1): "back", (0.0, 2): "bottom", (t, 2): "top"}
    for f in part.faces:
        c = (f.center.x, f.center.y, f.center.z)
        f.name = next((n for (v, k), n in names.items() if abs(c[k] - v) < 1e-9), "hole")
    path.parent.mkdir(parents=True, exist_ok=True)
    part.WriteStep(str(path))
    return path


def solve(scene_path: Path, order: int = 1):
    """(solution, CPU seconds) of one of the example scenes."""
    import ngcrack as nc

    scene = nc.Scene.from_toml(scene_path)
    t0 = time.process_time()
    sol = nc.solve(scene, order=order)
    return sol, time.process_time() - t0


def through_rows(sol, a: float = 0.5 * RADIUS) -> list[tuple[float, float, float]]:
    """(z / t, K_I, K_I / Bowie's) along the through crack's front."""
    from ngcrack.studies.newman_raju import bowie_F

    ref = math.sqrt(math.pi * a) * bowie_F(a / RADIUS)
    f = sol.fronts[0]
    order = np.argsort(f.points[:, 2])
    return [(float(f.points[k, 2] / THICKNESS), float(f.K_I[k]), float(f.K_I[k] / ref)) for k in order]


def corner_rows(sol, a: float = 0.5 * RADIUS) -> list[tuple[int, float, float, float]]:
    """(crack, phi in degrees from the plate's face, K_I, K_I / Newman-Raju's) along both corner cracks' fronts."""
    from ngcrack.studies.newman_raju import hole_corner_cracks_K

    rows = []
    for i, f in enumerate(sol.fronts):
        radial = np.abs(f.points[:, 1]) - RADIUS  # along the face, away from the bore
        depth = THICKNESS - f.points[:, 2]  # along the bore, into the plate
        phi = np.arctan2(depth / a, radial / a)
        ref = hole_corner_cracks_K(1.0, a, a, THICKNESS, RADIUS, HALF_WIDTH, phi)
        for k in np.argsort(phi):
            rows.append((i, float(np.degrees(phi[k])), float(f.K_I[k]), float(f.K_I[k] / ref[k])))
    return rows


def plot(out: str, rows: list, bowie_rows: list) -> None:
    """K_I along the corner cracks' fronts against Newman-Raju's (with their stated 5%), and the through crack's
    along the thickness against Bowie's plane value."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ngcrack.studies.newman_raju import STATED_ACCURACY, bowie_F, hole_corner_cracks_K

    a = 0.5 * RADIUS
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(9, 3.6))
    fine = np.linspace(0.0, 0.5 * math.pi, 91)
    ref = hole_corner_cracks_K(1.0, a, a, THICKNESS, RADIUS, HALF_WIDTH, fine)
    ax.plot(np.degrees(fine), ref, "k-", label="Newman-Raju, two corner cracks at a hole")
    ax.fill_between(np.degrees(fine), (1 - STATED_ACCURACY) * ref, (1 + STATED_ACCURACY) * ref, color="0.85",
                    label="their stated accuracy, 5%")
    for i, mark in ((0, "o"), (1, "x")):
        pts = [(p, k) for j, p, k, _ in rows if j == i]
        inner = [(p, k) for p, k in pts if 0.5 < p < 89.5]
        ends = [(p, k) for p, k in pts if not 0.5 < p < 89.5]
        ax.plot(*zip(*inner), mark, label=f"ngcrack, crack {i}")
        ax.plot(*zip(*ends), "s", mfc="none", color="C2", label="surface points (value inside)" if i == 0 else None)
    ax.set_xlabel("phi (deg): 0 on the plate's face, 90 on the bore")
    ax.set_ylabel("K_I / (S sqrt(m))")
    ax.set_title("corner cracks a = c = r/2, a/t = 0.5", fontsize=10)
    ax.legend(fontsize=7)
    z, k = zip(*[(zz, kk) for zz, kk, _ in bowie_rows])
    bx.plot(z, k, "o-", label="ngcrack")
    bx.axhline(math.sqrt(math.pi * a) * float(bowie_F(a / RADIUS)), color="k", label="Bowie (plane), F(0.5) = 1.73")
    bx.set_xlabel("z / t")
    bx.set_ylabel("K_I / (S sqrt(m))")
    bx.set_title("through crack a = r/2", fontsize=10)
    bx.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--solve", action="store_true", help="solve both example scenes and print K_I along the fronts")
    ap.add_argument("--order", type=int, default=1)
    ap.add_argument("--plot", metavar="OUT.png", help="with --solve: also draw K_I along the fronts against the references")
    args = ap.parse_args()
    print(f"wrote {write_step()}")
    if not args.solve:
        return
    sol, cpu = solve(THROUGH, args.order)
    bowie_rows = through_rows(sol)
    print(f"\nthrough crack a = r/2: {sol.ndof['total']:,} unknowns, {cpu:.1f} CPU s")
    print("| z / t | K_I | K_I / Bowie |\n|---|---|---|")
    for z, k, ratio in bowie_rows:
        print(f"| {z:.3f} | {k:.4f} | {ratio:.4f} |")
    sol, cpu = solve(CORNER, args.order)
    rows = corner_rows(sol)
    print(f"\ntwo corner cracks a = c = r/2: {sol.ndof['total']:,} unknowns, {cpu:.1f} CPU s")
    print("| crack | phi (deg) | K_I | K_I / Newman-Raju |\n|---|---|---|---|")
    for i, p, k, ratio in rows:
        print(f"| {i} | {p:.1f} | {k:.4f} | {ratio:.4f} |")
    if args.plot:
        plot(args.plot, rows, bowie_rows)


if __name__ == "__main__":
    main()
