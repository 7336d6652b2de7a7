"""How coarse a mesh each element survives: the measurements behind ngcrack.planar.sizing's
thin-part check (MIN_ACROSS_REFUSE, MIN_ACROSS_WARN).

Bodies whose thin parts bend: a plain cantilever (0,4) x (0,t), clamped on the left,
under its weight, for t = 0.5 and 0.25; paper-1 (two halves 0.5 thick); paper-2 (bands
0.5 thick above and below the crack). For every element and mesh size: the number of
mesh sizes across the thinnest part (sizing.thinnest_part), the triangles, and the mean
vertical displacement (the integral of u2 over the body, exact for P0 displacements: no
sampling bias) over that of a fine reference (h1p2 on the cantilevers, bdm on the paper
scenes, maxh = t / 25). The check itself is switched off here so that every mesh runs.

    python benchmarks/coarse_meshes.py           # every element, 9 mesh sizes per body
    python benchmarks/coarse_meshes.py --quick   # peers and bdm only
"""

from __future__ import annotations

import argparse
import sys
import warnings

import ngsolve as ngs

import ngcrack as nc
from ngcrack import scenes
from ngcrack.planar import sizing
from ngcrack.planar.scene import Scene

ELEMENTS = [("peers", None), ("bdm", None), ("tdnns", 1), ("tdnns", 2), ("tdnns", 3), ("h1p1", None), ("h1p2", None)]
#: mesh sizes as fractions of the thickness t: t / h = 0.8 ... 8
FRACTIONS = (1.25, 1.0, 0.8, 0.6, 0.5, 0.4, 0.34, 0.25, 0.125)


def cantilever(t: float) -> Scene:
    return Scene.from_dict({
        "name": f"cantilever-t{t:g}",
        "domain": {"polygon": [[0, 0], [4, 0], [4, t], [0, t]], "labels": ["bottom", "right", "top", "left"]},
        "material": {"E": 206900.0, "nu": 0.29, "plane": "strain"}, "load": {"body_force": [0.0, -1.0]},
        "boundary": {"left": {"type": "clamped"}}})


def mean_u2(sol) -> float:
    return float(ngs.Integrate(sol.u[1], sol.mesh))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    elements = ELEMENTS[:2] if args.quick else ELEMENTS
    warnings.simplefilter("ignore")
    sizing.MIN_ACROSS_REFUSE.clear()  # measure every mesh
    bodies = [(cantilever(0.5), 0.5, "h1p2"), (cantilever(0.25), 0.25, "h1p2"),
              (scenes.load("paper-1"), 0.5, "bdm"), (scenes.load("paper-2"), 0.5, "bdm")]
    print(f"{'body':16s} {'maxh':>6s} {'across':>6s} {'tri':>5s}  " + " ".join(
        f"{e + (str(o) if o else ''):>7s}" for e, o in elements))
    for scene, t, ref_el in bodies:
        ref = mean_u2(nc.solve(scene, element=ref_el, maxh=t / 25))
        for f in FRACTIONS:
            h = f * t
            across = sizing.thinnest_part(scene, maxh=h).across
            cells, ntri = [], 0
            for e, o in elements:
                try:
                    sol = nc.solve(scene, element=e, maxh=h, order=o)
                    ntri = len(sol.crack_mesh.triangles)
                    cells.append(f"{mean_u2(sol) / ref:7.3f}")
                except Exception as exc:  # noqa: BLE001 -- a singular system is a result here
                    cells.append(f"{'sing.' if 'singular' in str(exc) else 'err':>7s}")
            print(f"{scene.name:16s} {h:6.3f} {across:6.2f} {ntri:5d}  " + " ".join(cells), flush=True)
    print("\nentries: mean u2 / reference (1 = exact; > 1 too soft, < 1 too stiff); sing.: singular system")
    return 0


if __name__ == "__main__":
    sys.exit(main())
