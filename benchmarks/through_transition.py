"""A surface crack grown to the back face of a plate: the through crack it becomes, and its K against the closed form.

    python benchmarks/through_transition.py            # the straight through crack at two meshes, then the growth

The plate is the built-in `surface-crack` scene's (10 wide, 20 long, t = 1.5 thick, E = 1000, nu = 0.3, pulled
by S = 1 at y = 10, clamped at y = -10), the crack in the plane y = 0.

1. A straight through crack of half-length c = 1.2 (a rectangle crossing the front and back faces, as
   studies/growth/through.py writes it when the back-face length equals the front face's): K_I at the
   mid-thickness points of its two fronts against the through crack in a plate of width 2b under tension,
   K = S sqrt(pi c) sec(pi c / 2b)^(1/2) (Feddersen's width correction), at two meshes.
2. The growth: a semi-elliptical crack a = 1.1, c = 1.5 grown by Paris's law (da = 0.1) until it becomes a
   through crack (through.py's rule); the event's numbers, the cycles and K_I at the trapezoid's
   mid-thickness points against the closed form at its mean half-length (c + c_b) / 2 (informative: the
   closed form is a straight crack's).
"""

from __future__ import annotations

import copy
import math
import sys
import time

import numpy as np

import ngcrack as nc

T, B, C = 1.5, 5.0, 1.2  # the plate's thickness and half-width, the through crack's half-length
MESHES = ((0.15, 0.3), (0.1, 0.2))  # (front_h, crack_h)


def closed_form(c: float, S: float = 1.0, b: float = B) -> float:
    """A through crack of length 2c in a plate of width 2b under the tension S: S sqrt(pi c) sec(pi c / 2b)^(1/2)."""
    return S * math.sqrt(math.pi * c / math.cos(math.pi * c / (2 * b)))


def plate(mesh) -> dict:
    d = copy.deepcopy(nc.scenes.load("surface-crack").to_dict())
    d["mesh"] = {"front_h": mesh[0], "crack_h": mesh[1]}
    return d


def mid_thickness(front) -> list[float]:
    """K_I at the point nearest to mid-thickness on each front (x < 0 and x > 0)."""
    P, K = np.asarray(front.points if hasattr(front, "points") else front["points"]), np.asarray(
        front.K_I if hasattr(front, "K_I") else front["K_I"])
    return [float(K[int(np.argmin(np.abs(P[:, 2] - 0.5 * T) + 99 * (np.sign(P[:, 0]) != side)))]) for side in (-1, 1)]


def straight(mesh):
    d = plate(mesh)
    m = 0.3 * T
    d["crack"] = [{"shape": "polygon", "points": [[-C, 0.0, -m], [C, 0.0, -m], [C, 0.0, T + m], [-C, 0.0, T + m]]}]
    t0 = time.process_time()
    sol = nc.solve(nc.Scene.from_dict(d))
    return mid_thickness(sol.fronts[0]), int(sol.ndof["total"]), time.process_time() - t0


def growth():
    d = plate(MESHES[0])
    d["crack"][0]["semi_axes"] = [1.5, 1.1]
    t0 = time.process_time()
    r = nc.grow(nc.Scene.from_dict(d), da=0.1, steps=8, paris=(1e-3, 3.0))
    return r, time.process_time() - t0


def main() -> None:
    K0 = closed_form(C)
    print(f"1. straight through crack, c = {C}, t = {T}, b = {B}: closed form K = {K0:.4f}")
    print("| front_h | crack_h | ndof | K_I mid-thickness (x<0, x>0) | / closed form | CPU s |")
    print("|---|---|---|---|---|---|")
    for mesh in MESHES:
        K, ndof, cpu = straight(mesh)
        print(f"| {mesh[0]} | {mesh[1]} | {ndof} | {K[0]:.4f}, {K[1]:.4f} | {K[0] / K0:.4f}, {K[1] / K0:.4f} | {cpu:.0f} |")
    sys.stdout.flush()
    r, cpu = growth()
    print("\n2. growth of a = 1.1, c = 1.5 (front_h 0.15) to the transition")
    print(r.summary())
    print("stopped:", r.stopped)
    e = r.transitions[-1]
    cm = 0.5 * (e["surface_half_length"] + e["back_half_length"])
    K = mid_thickness(r.steps[-1]["fronts"][0])
    print(f"event at step {e['step']}: a = {e['half_height']:.4f}, ligament {e['ligament']:.4f}, c = "
          f"{e['surface_half_length']:.4f}, c_b = {e['back_half_length']:.4f}; cycles at the through crack "
          f"{r.cycles()[-1]:.4g} (before: {r.cycles()[-2]:.4g})")
    print(f"trapezoid K_I mid-thickness {K[0]:.4f}, {K[1]:.4f}; closed form at (c + c_b)/2 = {cm:.4f}: "
          f"{closed_form(cm):.4f} (ratio {K[0] / closed_form(cm):.4f}, {K[1] / closed_form(cm):.4f}); CPU {cpu:.0f} s")


if __name__ == "__main__":
    main()
