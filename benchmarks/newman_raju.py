"""Semi-elliptical surface cracks in plates in tension against Newman and Raju's equation.

    python benchmarks/newman_raju.py [--quick] [--order K]
    python benchmarks/newman_raju.py --deep      # the deepest point of deep cracks by mesh, order and extraction
    python benchmarks/newman_raju.py --slender   # the points near the surface of a slender crack by mesh
    python benchmarks/newman_raju.py --defaults [--before] [--cases 0.6,0.4 ...]  # the deepest point at the default sizes

For each (a/c, a/t): a plate of thickness t, half-width b = 5c and half-length 2b, one end clamped and
the other pulled (S = 1; the pulled end is free, so the bending of the cracked section is the one
Newman and Raju's plate under uniform stress on both ends has), the crack an ellipse centred on the
face zmax; mesh front_h = a/6, crack_h = a/3 (the built-in scene `surface-crack`'s sizes; on a/t = 0.8
the ligament t - a below the front is 1.5 front_h). Prints per front point phi (the ellipse's parametric
angle from the surface, Newman and Raju's), K_I ours, Newman-Raju's (ngcrack.studies.newman_raju, with
their finite-width factor for c/b = 0.2), the error, the unknowns and the CPU time of the solve; the
surface points (phi = 0, 90 deg at the deepest point) carry the value a bump half-width inside.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from ngcrack.solid.scene import SolidScene
from ngcrack.studies.newman_raju import corner_crack_K, opening_K_I, surface_crack_K

CASES = [(0.6, 0.4), (0.2, 0.2), (0.2, 0.5), (0.4, 0.6), (1.0, 0.2), (1.0, 0.5), (1.0, 0.8), (0.6, 0.8)]
QUICK = [(0.6, 0.4), (1.0, 0.2)]


def surface_scene(a_over_c: float, a_over_t: float, a: float = 0.6, front_h_per_a: float = 1 / 6,
                  crack_h_per_front_h: float = 2.0) -> SolidScene:
    """A plate with a semi-elliptical surface crack of depth a (the benchmark's geometry), front_h = a/6 and
    crack_h = 2 front_h by default."""
    c, t = a / a_over_c, a / a_over_t
    front_h = front_h_per_a * a
    b = 5.0 * c
    d = {"name": f"nr-{a_over_c:g}-{a_over_t:g}", "domain": {"box": [[-b, -2 * b, 0.0], [b, 2 * b, t]]},
         "crack": [{"shape": "ellipse", "center": [0.0, 0.0, t], "normal": [0.0, 1.0, 0.0],
                    "semi_axes": [max(a, c), min(a, c)] if c >= a else [a, c],
                    "major_axis": [1.0, 0.0, 0.0] if c >= a else [0.0, 0.0, 1.0]}],
         "material": {"E": 1000.0, "nu": 0.3},
         "boundary": {"ymin": {"type": "clamped"}, "ymax": {"type": "traction", "value": [0.0, 1.0, 0.0]}},
         "mesh": {"front_h": front_h, "crack_h": crack_h_per_front_h * front_h}}
    return SolidScene.from_dict(d)


def run(a_over_c: float, a_over_t: float, order: int = 1, a: float = 0.6, corner: bool = False):
    """(phi, K ours, K Newman-Raju, ndof, seconds) at the front points of one case (`corner`: the crack centred
    on the plate's edge x = -b instead, a quarter-elliptical corner crack in a plate of width 2b)."""
    import ngcrack as nc

    scene = surface_scene(a_over_c, a_over_t, a)
    c, t = a / a_over_c, a / a_over_t
    x0 = -5.0 * c if corner else 0.0
    if corner:
        d = scene.to_dict()
        d["crack"][0]["center"] = [x0, 0.0, t]
        scene = SolidScene.from_dict(d)
    t0 = time.process_time()
    sol = nc.solve(scene, order=order)
    cpu = time.process_time() - t0
    f = sol.fronts[0]
    depth = np.maximum(t - f.points[:, 2], 0.0)
    phi = np.arctan2(depth / a, (f.points[:, 0] - x0) / c)  # the parametric angle from the surface (0 to pi)
    ref = corner_crack_K(1.0, a, c, t, 10.0 * c, phi) if corner else surface_crack_K(1.0, a, c, t, 5.0 * c, phi)
    return phi, np.asarray(f.K_I), ref, sol.ndof["total"], cpu


#: the deepest point's study (`deep_study`): (a/c, a/t, element, order, front_h / a, crack_h / front_h); TDNNS (the
#: default, mixed) and the displacement element h1p2 bracket the answer from either side; the controls a/c = 1,
#: a/t = 0.8 (the same ligament, 0.25 a) and the built-in a/c = 0.6, a/t = 0.4 last
DEEP = [(0.6, 0.8, "tdnns", 1, 1 / 6, 2.0), (0.6, 0.8, "tdnns", 1, 1 / 9, 2.0), (0.6, 0.8, "tdnns", 1, 1 / 12, 2.0),
        (0.6, 0.8, "tdnns", 2, 1 / 6, 2.0), (0.6, 0.8, "tdnns", 2, 1 / 6, 1.0),
        (0.6, 0.8, "h1p2", None, 1 / 6, 2.0), (0.6, 0.8, "h1p2", None, 1 / 9, 2.0), (1.0, 0.8, "tdnns", 1, 1 / 6, 2.0),
        (1.0, 0.8, "tdnns", 2, 1 / 6, 2.0), (1.0, 0.8, "h1p2", None, 1 / 9, 2.0), (0.6, 0.4, "tdnns", 2, 1 / 6, 2.0),
        (0.6, 0.4, "h1p2", None, 1 / 9, 2.0)]
#: the slender crack's study (`slender_study`): a/c = 0.2, a/t = 0.5, order 1 (or --order), these front_h / a
SLENDER = [1 / 6, 1 / 8]


def deep_study(a: float = 0.6, element: str | None = None, aspect: float | None = None) -> None:
    """The deepest point by the domain integral (the reported K_I) and by the opening behind it
    (`ngcrack.studies.newman_raju.opening_K_I`), against Newman-Raju's equation, by mesh, order and element
    (`element`, `aspect`: only that element's, that a/c's rows)."""
    import ngcrack as nc

    print("| a/c | a/t | element | front_h | crack_h | unknowns | K domain integral | K opening | Newman-Raju | CPU s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r, s, elem, order, fh, ch in DEEP:
        if (element and elem != element) or (aspect is not None and abs(r - aspect) > 1e-9):
            continue
        scene = surface_scene(r, s, a, fh, ch)
        c, t = a / r, a / s
        t0 = time.process_time()
        sol = nc.solve(scene, element=elem, order=order, max_dof=3_000_000)
        cpu = time.process_time() - t0
        f = sol.fronts[0]
        k = int(np.argmin(np.abs(f.points[:, 0])))  # the deepest point (x = 0)
        ref = float(surface_crack_K(1.0, a, c, t, 5.0 * c, 0.5 * math.pi))
        K = float(f.K_I[k])
        Ko = opening_K_I(sol, f.points[k], [0.0, 0.0, 1.0], a)
        name = elem if order is None else f"{elem} {order}"
        print(f"| {r:g} | {s:g} | {name} | a/{1 / fh:.0f} | {ch:g} front_h | {sol.ndof['total']:,} | "
              f"{K:.4f} ({K / ref - 1:+.2%}) | {Ko:.4f} ({Ko / ref - 1:+.2%}) | {ref:.4f} | {cpu:.1f} |", flush=True)


#: the default sizes' study (`defaults_study`): (a/c, a/t) of plates whose scene sets no [mesh] sizes (the first four
#: the ones `--defaults` runs unless --cases), and the converged deepest-point K_I of the deep ones (BENCHMARKS, "Deep
#: and slender surface cracks": 1.33 +- 0.03 and 0.95-0.96)
DEFAULTS = [(0.6, 0.4), (0.4, 0.6), (0.2, 0.5), (1.0, 0.2), (0.6, 0.8), (1.0, 0.8), (0.2, 0.2), (0.4, 0.4), (0.6, 0.6),
            (1.0, 0.4), (1.0, 0.6), (0.2, 0.4), (0.4, 0.2), (0.6, 0.2), (0.4, 0.8), (0.2, 0.6), (0.2, 0.8)]
CONVERGED = {(0.6, 0.8): 1.33, (1.0, 0.8): 0.955}


def default_scene(a_over_c: float, a_over_t: float, a: float = 0.6, before: bool = False) -> SolidScene:
    """The benchmark's plate without [mesh] sizes (the library's defaults); `before`: with the defaults of before the
    depth rule set explicitly (the crack-sized ones with the ligament's caps: `mesh_sizes` without the depth cap)."""
    from unittest import mock

    from ngcrack.solid import sizing

    d = surface_scene(a_over_c, a_over_t, a).to_dict()
    d.pop("mesh")
    if before:
        with mock.patch.object(sizing, "depth_cap", lambda domain, cracks: math.inf):
            scene = SolidScene.from_dict(d)
            z = scene.mesh_sizes()
        d["mesh"] = {k: z[k] for k in ("maxh", "crack_h", "front_h")}
    return SolidScene.from_dict(d)


def default_case(a_over_c: float, a_over_t: float, before: bool = False, a: float = 0.6) -> dict:
    """One plate at the default sizes: the sizes, the estimate and netgen's tetrahedra, the unknowns, the deepest
    point's K by both extractions, CPU seconds and the peak resident memory (run in its own process)."""
    import resource

    import ngcrack as nc
    from ngcrack.solid.sizing import estimate_size

    c, t = a / a_over_c, a / a_over_t
    try:
        scene = default_scene(a_over_c, a_over_t, a, before)
    except ValueError as e:
        return {"refused": str(e)}
    sizes, est = scene.mesh_sizes(), estimate_size(scene)
    t0 = time.process_time()
    sol = nc.solve(scene, max_dof=3_000_000)
    cpu = time.process_time() - t0
    f = sol.fronts[0]
    k = int(np.argmin(np.abs(f.points[:, 0])))
    return {"sizes": sizes, "est_tets": est.tets, "est_memory": est.memory, "tets": sol.smesh.mesh.ne,
            "ndof": sol.ndof["total"], "K": float(f.K_I[k]), "Ko": opening_K_I(sol, f.points[k], [0.0, 0.0, 1.0], a),
            "Ks": 0.5 * float(f.K_I[0] + f.K_I[-1]), "nr_s": float(surface_crack_K(1.0, a, c, t, 5.0 * c, 0.0)),
            "nr": float(surface_crack_K(1.0, a, c, t, 5.0 * c, 0.5 * math.pi)), "cpu": cpu,
            "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def _published(a_over_c: float, a_over_t: float, a: float = 0.6, point: str = "deepest") -> float | None:
    """The mean of Shiratori's and ASME XI's K at the deepest (or surface) point of the plate
    (`studies.newman_raju.published_K`; the tables' own where only one covers the case), None where neither does."""
    from ngcrack.studies.newman_raju import published_K

    c, t = a / a_over_c, a / a_over_t
    ks = []
    for source in ("shiratori", "asme"):
        try:
            ks.append(published_K(source, point, 1.0, a, c, t, 5.0 * c))
        except ValueError:
            pass
    return float(np.mean(ks)) if ks else None


def defaults_study(before: bool = False, cases=None, a: float = 0.6) -> None:
    """The deepest point of the DEFAULTS plates (`cases`, else the first four) at the library's default sizes
    (`before`: without the depth rule), one process each (its peak memory), against the published tables
    (`_published`), our converged K and Newman-Raju's equation."""
    import json
    import subprocess
    import sys

    print("| a/c | a/t | maxh | crack_h | front_h | tets (estimate / netgen) | unknowns | K domain integral | K opening | "
          "published (errors) | converged (errors) | Newman-Raju (errors) | CPU s | peak MB (estimate) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    surface = []
    for r, s in cases or DEFAULTS[:4]:
        code = (f"import json, benchmarks.newman_raju as m; print('@@' + json.dumps(m.default_case({r}, {s}, {before})))")
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        line = next((x for x in out.stdout.splitlines() if x.startswith("@@")), None)
        if line is None:
            print(f"| {r:g} | {s:g} | failed: {out.stderr.strip().splitlines()[-1:]} |", flush=True)
            continue
        d = json.loads(line[2:])
        if "refused" in d:
            print(f"| {r:g} | {s:g} | refused: {d['refused']} |", flush=True)
            continue
        z, conv, pub = d["sizes"], CONVERGED.get((r, s)), _published(r, s, a)

        def versus(ref, d=d):
            return "" if ref is None else f"{ref:.4f} ({d['K'] / ref - 1:+.1%}, {d['Ko'] / ref - 1:+.1%})"

        print(f"| {r:g} | {s:g} | {z['maxh']:.3g} | a/{a / z['crack_h']:.3g} | a/{a / z['front_h']:.3g} | {d['tets']:,} "
              f"({d['est_tets'] / d['tets']:.2f}) | {d['ndof']:,} | {d['K']:.4f} | {d['Ko']:.4f} | {versus(pub)} | "
              f"{versus(conv)} | {versus(d['nr'])} | {d['cpu']:.1f} | {d['peak_mb']:.0f} ({d['est_memory'] / 2 ** 20:.0f}) |",
              flush=True)
        pub_s = _published(r, s, a, "surface")
        surface.append(f"| {r:g} | {s:g} | {d['Ks']:.4f} | " + ("" if pub_s is None else f"{pub_s:.4f} ({d['Ks'] / pub_s - 1:+.1%})")
                       + f" | {d['nr_s']:.4f} ({d['Ks'] / d['nr_s'] - 1:+.1%}) |")
    print("\nThe surface points (the mean of the two; the value a bump half-width inside, `solid.surface.SURFACE_INSET`):\n")
    print("| a/c | a/t | K surface points | published (error) | Newman-Raju (error) |")
    print("|---|---|---|---|---|")
    print("\n".join(surface))


def slender_study(a: float = 0.6, order: int = 1) -> None:
    """K_I at the points up to 45 deg from the surface of a/c = 0.2, a/t = 0.5 against Newman-Raju's, by front_h, and
    at the deepest point against the published tables (`--order 2`: 1.0M and 1.4M unknowns, 4.8 and 7.4 GB)."""
    import ngcrack as nc

    r, s = 0.2, 0.5
    c, t = a / r, a / s
    tables = _published(r, s, a)
    print(f"order {order}; the deepest point's published K (Shiratori's and ASME's mean): {tables:.4f}")
    print("| front_h | phi (deg) | K ours | Newman-Raju | error | unknowns | CPU s |")
    print("|---|---|---|---|---|---|---|")
    for fh in SLENDER:
        t0 = time.process_time()
        sol = nc.solve(surface_scene(r, s, a, fh), order=order, max_dof=6_000_000)
        cpu = time.process_time() - t0
        f = sol.fronts[0]
        phi = np.arctan2(np.maximum(t - f.points[:, 2], 0.0) / a, f.points[:, 0] / c)
        ref = surface_crack_K(1.0, a, c, t, 5.0 * c, phi)
        deepest = int(np.argmin(np.abs(phi - 0.5 * math.pi)))
        print(f"| a/{1 / fh:.0f} | deepest {math.degrees(phi[deepest]):.1f} | {f.K_I[deepest]:.4f} | tables {tables:.4f} | "
              f"{f.K_I[deepest] / tables - 1:+.2%} | | |")
        for k in np.flatnonzero((phi > 1e-9) & (phi <= 0.25 * math.pi + 1e-9)):
            print(f"| a/{1 / fh:.0f} | {math.degrees(phi[k]):.1f} | {f.K_I[k]:.4f} | {ref[k]:.4f} | {f.K_I[k] / ref[k] - 1:+.2%} | "
                  f"{sol.ndof['total']:,} | {cpu:.1f} |", flush=True)


def plot(out: str, order: int = 1) -> None:
    """K_I along the front of the built-in scene's crack (a/c = 0.6, a/t = 0.4) against Newman-Raju's."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    phi, K, _, ndof, _ = run(*CASES[0], order)
    fine = np.linspace(0.0, math.pi, 181)
    a, (r, s) = 0.6, CASES[0]
    fig, ax = plt.subplots(figsize=(6, 3.6))
    nr = surface_crack_K(1.0, a, a / r, a / s, 5.0 * a / r, fine)
    ax.plot(np.degrees(fine), nr, "k-", label="Newman-Raju (1981)")
    ax.fill_between(np.degrees(fine), 0.95 * nr, 1.05 * nr, color="0.85", label="their stated accuracy, 5%")
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
    ap.add_argument("--deep", action="store_true", help="the deepest point of deep cracks by mesh, order and extraction")
    ap.add_argument("--element", help="with --deep: only this element's rows (tdnns or h1p2)")
    ap.add_argument("--aspect", type=float, help="with --deep: only the rows of this a/c")
    ap.add_argument("--defaults", action="store_true", help="the deepest point at the library's default sizes")
    ap.add_argument("--before", action="store_true", help="with --defaults: the defaults of before the depth rule")
    ap.add_argument("--cases", nargs="+", metavar="A/C,A/T", help="with --defaults: these plates (e.g. 0.6,0.4 1,0.2)")
    ap.add_argument("--slender", action="store_true", help="the points near the surface of a/c = 0.2 by mesh")
    ap.add_argument("--plot", metavar="OUT.png", help="only draw K_I along the front of the first case against Newman-Raju's")
    args = ap.parse_args()
    if args.plot:
        plot(args.plot, args.order)
        return
    if args.defaults:
        cases = [tuple(float(x) for x in case.split(",")) for case in args.cases] if args.cases else None
        defaults_study(args.before, cases)
        return
    if args.deep or args.slender:
        deep_study(element=args.element, aspect=args.aspect) if args.deep else slender_study(order=args.order)
        return
    print("| a/c | a/t | phi (deg) | K ours | K Newman-Raju | error | unknowns | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    summary = []
    cases = [(r, s, False) for r, s in (QUICK if args.quick else CASES)] + ([] if args.quick else [(0.6, 0.4, True)])
    for r, s, corner in cases:
        phi, K, ref, ndof, cpu = run(r, s, args.order, corner=corner)
        half = phi <= 0.5 * math.pi + 1e-9 if not corner else np.ones(len(phi), dtype=bool)
        for p, k, kr in zip(phi[half], K[half], ref[half]):
            print(f"| {r:g}{' corner' if corner else ''} | {s:g} | {math.degrees(p):5.1f} | {k:.4f} | {kr:.4f} | "
                  f"{k / kr - 1:+.2%} | {ndof} | {cpu:.1f} |", flush=True)
        err = K / ref - 1
        inner = np.arange(1, len(phi) - 1)  # the points off the surface
        deep = int(np.argmin(np.abs(phi - 0.5 * math.pi))) if not corner else None
        from45 = inner[(phi[inner] >= math.pi / 4) & (phi[inner] <= 3 * math.pi / 4)]
        summary.append(f"| {r:g}{' corner' if corner else ''} | {s:g} | "
                       f"{'' if deep is None else f'{err[deep]:+.2%}'} | {err[inner][np.argmax(np.abs(err[inner]))]:+.2%} | "
                       f"{err[from45][np.argmax(np.abs(err[from45]))]:+.2%} | {err[0]:+.2%}, {err[-1]:+.2%} | {ndof} | {cpu:.1f} |")
    print("\n| a/c | a/t | deepest | worst off the surface | worst, phi 45-135 deg | surface points | unknowns | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(summary))

if __name__ == "__main__":
    main()
