"""K_I near the free surface with the mesh refined locally where the front meets the surface.

    python benchmarks/surface_vertex.py --aspect 0.2 --depth 0.5 [--radius 3 --ratio 2 --front-h-per-a 6]
    python benchmarks/surface_vertex.py --aspect 1 --depth 0.8 --defaults [--radius 3 --ratio 2]

The plate of benchmarks/newman_raju.py (a = 0.6, thickness t = a / depth, half-width 5c; front_h = a/6, crack_h =
2 front_h, or `--defaults`: the scene without [mesh] sizes; TDNNS order 1) with, when `--ratio` > 1, the body's
mesh size at most front_h / ratio in the ball of
`--radius` front_h around each point where the crack's front meets the body's surface (netgen's local size
restrictions on a grid of points that fills the ball, as `solid.geometry.meshing_parameters` does for the near
ball). Prints one row per run: the tetrahedra, the mean edge of the tetrahedra touching those points (against
front_h), unknowns, CPU seconds of the solve (mesh included), peak memory, and the domain integral's K_I and the
opening's (`studies.newman_raju.front_opening_K_I`) at the stations up to 50 deg from the surface and at the
deepest point, against Newman and Raju's equation. One run a process (the peak is the process's).
"""

from __future__ import annotations

import argparse
import math
import resource
import time

import numpy as np


def surface_vertices(domain, crack, n: int = 4096) -> np.ndarray:
    """The points where the crack's outline crosses the body's surface (the ends of its fronts), by the sign of the
    outline's clearance between neighbouring samples, linearly interpolated."""
    from ngcrack.solid.surface import clearance

    p = crack.outline(n)
    d = clearance(domain, p)
    q, e = np.roll(p, -1, axis=0), np.roll(d, -1)
    k = np.flatnonzero((d > 0) != (e > 0))
    w = d[k] / np.where(d[k] != e[k], d[k] - e[k], 1.0)
    return p[k] + w[:, None] * (q[k] - p[k])


def ball_points(center, h: float, radius: float) -> np.ndarray:
    """Points h apart filling the ball of `radius` around `center`."""
    axis = np.arange(-radius, radius + 0.5 * h, h)
    grid = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    return np.asarray(center) + grid[np.linalg.norm(grid, axis=1) <= radius]


def vertex_parameters(original, radius_h: float, ratio: float):
    """`original` (`solid.geometry.meshing_parameters`) with the size restricted to front_h / ratio within radius_h
    front_h of every point where a front meets the surface."""

    def with_vertices(scene, sizes):
        mp = original(scene, sizes)
        h = sizes["front_h"] / ratio
        for c in scene.cracks:
            for v in surface_vertices(scene.domain, c):
                for p in ball_points(v, h, radius_h * sizes["front_h"]):
                    mp.RestrictH(float(p[0]), float(p[1]), float(p[2]), h)
        return mp

    return with_vertices


def vertex_edges(smesh) -> float:
    """The mean edge length of the tetrahedra touching the mesh vertices nearest the front's surface ends."""
    import ngsolve as ngs

    mesh = smesh.mesh
    pts = np.array([v.point for v in mesh.vertices])
    ends = [int(np.argmin(np.linalg.norm(pts - v, axis=1))) for c in smesh.scene.cracks
            for v in surface_vertices(smesh.scene.domain, c)]
    lengths = []
    for el in mesh.Elements(ngs.VOL):
        vs = [v.nr for v in el.vertices]
        if any(e in vs for e in ends):
            x = pts[vs]
            lengths += [np.linalg.norm(x[i] - x[j]) for i in range(4) for j in range(i + 1, 4)]
    return float(np.mean(lengths))


def run(aspect: float, depth: float, radius_h: float, ratio: float, per_a: float, defaults: bool = False,
        a: float = 0.6) -> None:
    import ngcrack as nc
    from benchmarks.newman_raju import default_scene, surface_scene
    from ngcrack.studies.newman_raju import front_opening_K_I, surface_crack_K

    if ratio > 1:  # for this process: `solid.geometry.make_mesh` calls the module's meshing_parameters
        from ngcrack.solid import geometry

        geometry.meshing_parameters = vertex_parameters(geometry.meshing_parameters, radius_h, ratio)
    c, t = a / aspect, a / depth
    scene = default_scene(aspect, depth, a) if defaults else surface_scene(aspect, depth, a, 1.0 / per_a)
    t0 = time.process_time()
    sol = nc.solve(scene, order=1)
    cpu = time.process_time() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    f = sol.fronts[0]
    phi = np.arctan2(np.maximum(t - f.points[:, 2], 0.0) / a, f.points[:, 0] / c)
    ref = surface_crack_K(1.0, a, c, t, 5.0 * c, phi)
    opening = front_opening_K_I(sol)
    ne = sol.smesh.mesh.ne
    hv = vertex_edges(sol.smesh) / sol.smesh.sizes["front_h"]
    label = f"{radius_h:g} front_h, front_h/{ratio:g}" if ratio > 1 else "none"
    fh = f"a/{a / sol.smesh.sizes['front_h']:.3g}" + (" (defaults)" if defaults else "")
    print(f"a/c {aspect:g}, a/t {depth:g}, front_h {fh}, vertex ball {label}: {ne:,} tets, edges at the ends "
          f"{hv:.2f} front_h, {sol.ndof['total']:,} unknowns, {cpu:.1f} CPU s, peak {peak:.0f} MB", flush=True)
    print("| phi (deg) | K domain integral | K opening | Newman-Raju |")
    print("|---|---|---|---|")
    deep = int(np.argmin(np.abs(f.points[:, 0])))
    for k in list(np.flatnonzero((phi > 1e-9) & (phi <= math.radians(50.0)))) + [deep]:
        print(f"| {math.degrees(phi[k]):.1f} | {f.K_I[k]:.4f} ({f.K_I[k] / ref[k] - 1:+.1%}) | "
              f"{opening[k]:.4f} ({opening[k] / ref[k] - 1:+.1%}) | {ref[k]:.4f} |", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--aspect", type=float, default=0.2, help="a/c")
    ap.add_argument("--depth", type=float, default=0.5, help="a/t")
    ap.add_argument("--radius", type=float, default=3.0, help="the ball's radius in front_h")
    ap.add_argument("--ratio", type=float, default=1.0, help="front_h over the size in the ball (1: no ball)")
    ap.add_argument("--front-h-per-a", type=float, default=6.0)
    ap.add_argument("--defaults", action="store_true", help="the scene without [mesh] sizes (the library's defaults)")
    args = ap.parse_args()
    run(args.aspect, args.depth, args.radius, args.ratio, args.front_h_per_a, args.defaults)


if __name__ == "__main__":
    main()
