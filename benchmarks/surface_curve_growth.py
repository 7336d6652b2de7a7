"""A surface crack grown with a free front shape (a curve) against the same crack grown as a fitted ellipse.

The plate of the built-in `surface-crack` scene (thickness t = 1.5, half-width b = 5, remote tension S = 1)
with a semicircular surface crack of radius `--a0` (or, with `--corner`, a quarter-circular corner crack
on the edge of the faces xmin and zmax) grows under Paris's law (C = 1e-3, m `--m`) by `--steps` steps
of `--da` twice: as the ellipse (the default: the ellipse with the same centre and axes fitted to the
advanced points, ngcrack.studies.growth.surface3d) and as a curve through ELLIPSE_CURVE_POINTS points of
the same circle (the new crack the spline through the advanced points completed beyond the faces,
ngcrack.studies.growth.surface_curve), on the same mesh sizes (front_h `--front-h`, crack_h twice that).

Printed per step: the depth a and half-length c of both runs and the curve's against the ellipse's, the
cycles of both, and the front's smoothness: the largest turning of the curve's front between neighbouring
chords of FRONT_SAMPLES points equally spaced in arc length, `kink` the largest jump of that turning from
the mean of its neighbours' over the median turning (a smooth front's is small, a corner's of order 1),
and the curvature range max/min along the front. The CPU seconds of each run (process time; the machine is shared).

    python benchmarks/surface_curve_growth.py --a0 0.5 --steps 4 --m 3
    python benchmarks/surface_curve_growth.py --corner --a0 0.5 --steps 3

Also `--k-only`: K along the front of the built-in `surface-crack` (a/c = 0.6) as the ellipse, as curves
through 24, 32 and 48 points of it, and as the ellipse moved by 1e-3 (another mesh of the same crack:
the mesh-to-mesh spread), at `--front-h`; with `--corner` the same ellipse centred on the edge of the
faces xmin and zmax (a corner crack; moved by 1e-3 along z).

No number here is a test threshold.
"""

from __future__ import annotations

import argparse
import copy
import os
import time

import numpy as np

T, B = 1.5, 5.0
#: front points equally spaced in arc length at which the smoothness is measured
FRONT_SAMPLES = 257


def turning(points: np.ndarray) -> np.ndarray:
    """The angles (radians) between neighbouring chords of a polyline."""
    d = np.diff(points, axis=0)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return np.arccos(np.clip(np.sum(d[1:] * d[:-1], axis=1), -1.0, 1.0))


def plate(front_h: float, crack: dict) -> dict:
    import ngcrack as nc

    d = copy.deepcopy(nc.scenes.load("surface-crack").to_dict())
    d["mesh"] = {"front_h": front_h, "crack_h": 2 * front_h, "maxh": 1.5}
    d["crack"] = [crack]
    return d


def k_only(front_h: float, corner: bool) -> None:
    import ngcrack as nc
    from ngcrack.solid.scene import SolidScene
    from ngcrack.studies.growth.surface_curve import curve_of_ellipse

    d = plate(front_h, {})
    base = copy.deepcopy(nc.scenes.load("surface-crack").to_dict()["crack"][0])
    if corner:
        base["center"] = [-B, 0.0, T]
    ellipse = SolidScene.from_dict({**d, "crack": [base]}).cracks[0]
    moved = [c + 1e-3 * (k == 2) for k, c in enumerate(base["center"])] if corner else [1e-3, 0.0, T]
    cases = [("ellipse", base), ("ellipse moved 1e-3", {**base, "center": moved})]
    cases += [(f"curve, {n} points", curve_of_ellipse(ellipse, n)) for n in (24, 32, 48)]
    ref = None
    where = "on the edge of xmin and zmax (a corner crack)" if corner else "(a/c = 0.6)"
    print(f"K_I along the front of surface-crack's ellipse {where}, front_h {front_h}; against the ellipse's")
    print(f"{'crack':>20} {'points':>6} {'max dev':>8} {'mean dev':>8} {'cpu s':>6}")
    for name, crack in cases:
        t0 = time.process_time()
        f = nc.solve(SolidScene.from_dict({**d, "crack": [crack]})).fronts[0]
        cpu = time.process_time() - t0
        if ref is None:
            ref = f.K_I
        dev = np.abs(f.K_I / ref - 1) if len(f.K_I) == len(ref) else np.full(1, np.nan)
        print(f"{name:>20} {len(f.K_I):>6} {dev.max():>8.4f} {dev.mean():>8.4f} {cpu:>6.1f}", flush=True)


def run(crack: dict, front_h: float, da: float, steps: int, m: float):
    import ngcrack as nc
    from ngcrack.solid.scene import SolidScene

    t0 = time.process_time()
    res = nc.grow(SolidScene.from_dict(plate(front_h, crack)), da=da, steps=steps, paris=(1e-3, m))
    return res, time.process_time() - t0


def smoothness(scene) -> tuple[float, float, float]:
    """(the largest turning between neighbouring chords of the front, the kink: the largest jump of the turning
    from the mean of its two neighbours' over the median turning (a smooth front's is small, a corner's of order
    1), the range max/min of the curvature) of a curve crossing the faces."""
    from ngcrack.studies.growth.surface_curve import front_points

    p = front_points(scene.domain, scene.cracks[0], FRONT_SAMPLES)
    t = turning(p)
    around = 0.5 * (np.r_[t[1], t[:-1]] + np.r_[t[1:], t[-2]])
    ds = np.linalg.norm(np.diff(p, axis=0), axis=1)
    kappa = t / (0.5 * (ds[1:] + ds[:-1]))
    return float(t.max()), float(np.max(np.abs(t - around)) / np.median(t)), float(kappa.max() / kappa.min())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--a0", type=float, default=0.5)
    ap.add_argument("--da", type=float, default=0.1)
    ap.add_argument("--steps", type=int, default=4)
    ap.add_argument("--m", type=float, default=3.0)
    ap.add_argument("--front-h", type=float, default=0.15)
    ap.add_argument("--corner", action="store_true")
    ap.add_argument("--k-only", action="store_true")
    args = ap.parse_args()
    print(f"machine: {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    if args.k_only:
        k_only(args.front_h, args.corner)
        return
    from ngcrack.solid.scene import SolidScene
    from ngcrack.studies.growth.surface_curve import curve_of_ellipse

    a0 = args.a0
    centre = [-B, 0.0, T] if args.corner else [0.0, 0.0, T]
    ellipse = {"shape": "ellipse", "center": centre, "normal": [0.0, 1.0, 0.0], "semi_axes": [a0, a0],
               "major_axis": [1.0, 0.0, 0.0]}
    curve = curve_of_ellipse(SolidScene.from_dict(plate(args.front_h, ellipse)).cracks[0])
    res_e, cpu_e = run(ellipse, args.front_h, args.da, args.steps, args.m)
    res_c, cpu_c = run(curve, args.front_h, args.da, args.steps, args.m)
    ac_e, ac_c = res_e.depth_and_length(), res_c.depth_and_length()
    N_e, N_c = res_e.cycles(), res_c.cycles()
    kind = "quarter-circular corner" if args.corner else "semicircular surface"
    print(f"a {kind} crack a0 = {a0}, Paris m = {args.m}, da = {args.da}, front_h = {args.front_h}; "
          f"ellipse fit {cpu_e:.0f} s, curve {cpu_c:.0f} s CPU")
    print(f"stopped: ellipse {res_e.stopped!r}; curve {res_c.stopped!r}")
    print(f"{'step':>4} {'a ell':>7} {'a crv':>7} {'a/a':>7} {'c ell':>7} {'c crv':>7} {'c/c':>7} {'N ell':>8} {'N crv':>8}"
          f" {'turn max':>8} {'kink':>6} {'k range':>7}")
    for n in range(min(len(ac_e), len(ac_c))):
        t_max, kink, k_range = smoothness(res_c.scenes[n])
        print(f"{n:>4} {ac_e[n, 0]:>7.4f} {ac_c[n, 0]:>7.4f} {ac_c[n, 0] / ac_e[n, 0]:>7.4f} {ac_e[n, 1]:>7.4f} "
              f"{ac_c[n, 1]:>7.4f} {ac_c[n, 1] / ac_e[n, 1]:>7.4f} {N_e[n]:>8.2f} {N_c[n]:>8.2f} {t_max:>8.5f} "
              f"{kink:>6.4f} {k_range:>7.3f}")


if __name__ == "__main__":
    main()
