"""Semi-elliptical surface cracks in plates in tension against Newman and Raju's equation.

    python benchmarks/newman_raju.py [--quick] [--order K]

For each (a/c, a/t): a plate of thickness t, half-width b = 5c and half-length 2b, one end clamped and
the other pulled (S = 1), the crack an ellipse centred on the face zmax; mesh front_h = a/6, crack_h = a/3
(the built-in scene `surface-crack`'s sizes), front_h at most a third of the ligament t - a. Prints per front point phi (from the surface), K_I ours,
Newman-Raju's (ngcrack.studies.newman_raju), the error, the unknowns and the CPU time of the solve; the
surface points (phi = 0, 90 deg at the deepest point) carry the value a bump half-width inside.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from ngcrack.solid.scene import SolidScene
from ngcrack.studies.newman_raju import surface_crack_K

CASES = [(0.6, 0.4), (0.2, 0.2), (0.2, 0.5), (0.4, 0.6), (1.0, 0.2), (1.0, 0.5), (1.0, 0.8), (0.6, 0.8)]
QUICK = [(0.6, 0.4), (1.0, 0.2)]
#: front_h is at most this fraction of the ligament below the front (deep cracks: a/t = 0.8)
LIGAMENT_FRONTS = 3.0


def surface_scene(a_over_c: float, a_over_t: float, a: float = 0.6, front_h_per_a: float = 1 / 6) -> SolidScene:
    """A plate with a semi-elliptical surface crack of depth a (the benchmark's geometry); front_h a/6, at most
    LIGAMENT_FRONTS of the ligament t - a below the front (the domain integral's tube spans at most 0.8 of it)."""
    c, t = a / a_over_c, a / a_over_t
    front_h = min(front_h_per_a * a, (t - a) / LIGAMENT_FRONTS)
    b = 5.0 * c
    d = {"name": f"nr-{a_over_c:g}-{a_over_t:g}", "domain": {"box": [[-b, -2 * b, 0.0], [b, 2 * b, t]]},
         "crack": [{"shape": "ellipse", "center": [0.0, 0.0, t], "normal": [0.0, 1.0, 0.0],
                    "semi_axes": [max(a, c), min(a, c)] if c >= a else [a, c],
                    "major_axis": [1.0, 0.0, 0.0] if c >= a else [0.0, 0.0, 1.0]}],
         "material": {"E": 1000.0, "nu": 0.3},
         "boundary": {"ymin": {"type": "clamped"}, "ymax": {"type": "traction", "value": [0.0, 1.0, 0.0]}},
         "mesh": {"front_h": front_h, "crack_h": 2 * front_h}}
    return SolidScene.from_dict(d)


def run(a_over_c: float, a_over_t: float, order: int = 1, a: float = 0.6):
    """(phi, K ours, K Newman-Raju, ndof, seconds) at the front points of one case."""
    import ngcrack as nc

    scene = surface_scene(a_over_c, a_over_t, a)
    t0 = time.process_time()
    sol = nc.solve(scene, order=order)
    cpu = time.process_time() - t0
    c, t = a / a_over_c, a / a_over_t
    f = sol.fronts[0]
    depth = np.maximum(t - f.points[:, 2], 0.0)
    phi = np.arctan2(depth / a, f.points[:, 0] / c)  # the parametric angle from the surface (0 to pi)
    ref = surface_crack_K(1.0, a, c, t, 5.0 * c, phi)
    return phi, np.asarray(f.K_I), ref, sol.ndof["total"], cpu


def plot(out: str, order: int = 1) -> None:
    """K_I along the front of the built-in scene's crack (a/c = 0.6, a/t = 0.4) against Newman-Raju's."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    phi, K, _, ndof, _ = run(*CASES[0], order)
    fine = np.linspace(0.0, math.pi, 181)
    a, (r, s) = 0.6, CASES[0]
    fig, ax = plt.subplots(figsize=(6, 3.6))
    ax.plot(np.degrees(fine), surface_crack_K(1.0, a, a / r, a / s, 5.0 * a / r, fine), "k-", label="Newman-Raju (1981)")
    ax.plot(np.degrees(phi[1:-1]), K[1:-1], "o", label=f"ngcrack, order {order} ({ndof} unknowns)")
    ax.plot(np.degrees(phi[[0, -1]]), K[[0, -1]], "s", mfc="none", label="surface points (value a bump inside)")
    ax.set_xlabel("parametric angle phi (deg; 90 = deepest point)")
    ax.set_ylabel("K_I / (S sqrt(m))")
    ax.set_title("semi-elliptical surface crack, a/c = 0.6, a/t = 0.4")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="two cases only")
    ap.add_argument("--order", type=int, default=1)
    ap.add_argument("--plot", metavar="OUT.png", help="only draw K_I along the front of the first case against Newman-Raju's")
    args = ap.parse_args()
    if args.plot:
        plot(args.plot, args.order)
        return
    print("| a/c | a/t | phi (deg) | K ours | K Newman-Raju | error | unknowns | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    for r, s in QUICK if args.quick else CASES:
        phi, K, ref, ndof, cpu = run(r, s, args.order)
        half = phi <= 0.5 * math.pi + 1e-9  # one half of the symmetric front
        for p, k, kr in zip(phi[half], K[half], ref[half]):
            print(f"| {r:g} | {s:g} | {math.degrees(p):5.1f} | {k:.4f} | {kr:.4f} | {k / kr - 1:+.2%} | {ndof} | {cpu:.1f} |")
        deep = int(np.argmin(np.abs(phi - 0.5 * math.pi)))
        inner = (phi > 0.1) & (phi < math.pi - 0.1)
        print(f"| {r:g} | {s:g} | deepest | {K[deep]:.4f} | {ref[deep]:.4f} | {K[deep] / ref[deep] - 1:+.2%} | "
              f"max inside {np.max(np.abs(K[inner] / ref[inner] - 1)):.2%} | |", flush=True)


if __name__ == "__main__":
    main()
