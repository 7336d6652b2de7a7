"""The penny crack in 3D: accuracy along the front and cost per stage, against the mesh size.

The built-in scene `penny` (radius a = 1 in a block of side 20a, remote tension p = 1,
E = 1000, nu = 0.3) at several mesh sizes at the front (crack_h = 2 front_h, maxh = 5),
hybridized TDNNS of order 1 (and order 2 at the coarsest sizes with --order 2). Each
level runs in its own process so that its peak memory is its own. Per level:

- unknowns: total, condensed (global), crack (contact) unknowns;
- CPU seconds and peak resident memory after each stage: mesh, assemble (element
  forms, condensed), condense (the sparse system), contact (`core.sparse_contact.solve_contact`'s
  default: one sparse factorization and the active set on the crack's Schur complement; the
  split into the two: benchmarks/solid_cost.py), fronts (the interaction integral);
- the same penny with the load reversed: the contact stage closes every face (2 active
  sets), and its share of the solve's CPU;
- accuracy: the centre opening and K_I at every front point against Sneddon's closed
  forms (8 (1 - nu^2) p a / (pi E), 2 p sqrt(a / pi)), and against the finite body's
  own converged answer (Richardson extrapolation of the front-averaged K_I and the
  centre opening over the last three levels, with the observed rate).

    python benchmarks/penny.py                      # front_h = 0.2, 0.15, 0.1
    python benchmarks/penny.py --front-h 0.2 0.15 0.1 0.075 --out rows.json
    python benchmarks/penny.py --order 2 --front-h 0.3 0.2 0.15 --tension-only
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import time


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def run_level(front_h: float, order: int, reverse: bool) -> dict:
    """One level in this process: stages, CPU and peak memory, accuracy."""
    import numpy as np

    import ngcrack as nc
    from ngcrack.core.hybrid import condense
    from ngcrack.core.sparse_contact import solve_contact
    from ngcrack.solid.element import build
    from ngcrack.solid.front import front_parameters
    from ngcrack.solid.geometry import make_mesh
    from ngcrack.solid.output import SolidSolution
    from ngcrack.solid.solve import scene_loads

    scene = nc.scenes.load("penny")
    if reverse:
        d = scene.to_dict()
        d["boundary"]["zmax"]["value"] = [0.0, 0.0, -1.0]
        scene = nc.Scene.from_dict(d)
    row = {"front_h": front_h, "crack_h": 2 * front_h, "order": order, "load": "compression" if reverse else "tension"}
    cpu, rss = {}, {}
    t = time.process_time()
    smesh = make_mesh(scene, maxh=5.0, crack_h=2 * front_h, front_h=front_h)
    cpu["mesh"], rss["mesh"] = time.process_time() - t, _rss_mb()
    loads = scene_loads(scene)
    t = time.process_time()
    disc = build(smesh, scene.material.E, scene.material.nu, loads, order)
    cpu["assemble"], rss["assemble"] = time.process_time() - t, _rss_mb()
    t = time.process_time()
    system = condense(disc, loads)
    cpu["condense"], rss["condense"] = time.process_time() - t, _rss_mb()
    G = disc.constraint_map()
    t = time.process_time()
    result = solve_contact(system.K, system.F, system.contact, G)
    cpu["contact"], rss["contact"] = time.process_time() - t, _rss_mb()
    gf = system.expand(result.y)
    sol = SolidSolution(scene=scene, smesh=smesh, disc=disc, system=system, y=result.y, gf=gf, contact=result, G=G,
                        options={}, timings={})
    t = time.process_time()
    (front,) = front_parameters(sol)
    cpu["fronts"], rss["fronts"] = time.process_time() - t, _rss_mb()
    E, nu = scene.material.E, scene.material.nu
    w, pts = sol.normal_jumps(), disc.constraint_points
    r = np.linalg.norm(pts[:, :2], axis=1)
    i0 = int(np.argmin(r))
    row.update(tets=smesh.mesh.ne, ndof=sol.ndof, iterations=result.iterations, kkt=result.kkt, cpu=cpu, rss_mb=rss,
               centre_opening=float(w[i0] / math.sqrt(max(1 - r[i0] ** 2, 0.0))),
               sneddon_opening=8 * (1 - nu * nu) / (math.pi * E),
               K_I=front.K_I.tolist(), K_II=front.K_II.tolist(), K_III=front.K_III.tolist(), G=front.G.tolist(),
               K_I_scaled_to_J=front.scaled_to_J[:, 0].tolist(),
               sneddon_K=2.0 * math.sqrt(1.0 / math.pi), closed_fraction=sol.crack_summaries()[0]["closed_fraction"])
    return row


def _child(front_h: float, order: int, reverse: bool) -> dict:
    env = dict(os.environ, OMP_NUM_THREADS="1")
    out = subprocess.run([sys.executable, __file__, "--level", str(front_h), "--order", str(order)]
                         + (["--reverse"] if reverse else []), capture_output=True, text=True, env=env, check=False)
    if out.returncode:
        return {"front_h": front_h, "order": order, "error": out.stderr.strip().splitlines()[-1:]}
    return json.loads(out.stdout.strip().splitlines()[-1])


def richardson(h, v):
    """The limit and the rate from three values at sizes h (a geometric-like sequence)."""
    import numpy as np

    (h1, h2, h3), (v1, v2, v3) = h[-3:], v[-3:]
    d1, d2 = v1 - v2, v2 - v3
    if d1 == 0 or d2 == 0 or d1 * d2 < 0:
        return v3, float("nan")
    rate = math.log(abs(d1 / d2)) / math.log(h1 / h2) if h1 / h2 == h2 / h3 else \
        float(np.log(abs(d1 / d2)) / np.log(h1 / h2))
    return v3 - d2 / ((h2 / h3) ** rate - 1.0), rate


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--front-h", nargs="+", type=float, default=[0.2, 0.15, 0.1])
    p.add_argument("--order", type=int, default=1)
    p.add_argument("--out", help="write the rows as JSON")
    p.add_argument("--tension-only", action="store_true", help="skip the reversed load (accuracy only)")
    p.add_argument("--level", type=float, help=argparse.SUPPRESS)
    p.add_argument("--reverse", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.level is not None:
        print(json.dumps(run_level(args.level, args.order, args.reverse)))
        return 0
    import numpy as np

    rows = []
    for h in args.front_h:
        for reverse in (False,) if args.tension_only else (False, True):
            row = _child(h, args.order, reverse)
            rows.append(row)
            print(f"# done front_h {h} {'compression' if reverse else 'tension'}: "
                  f"{'error ' + str(row['error']) if 'error' in row else 'ok'}", flush=True)
    print(f"\nmachine: {os.cpu_count()} cores; load: {os.getloadavg()}; one thread (OMP_NUM_THREADS=1)")
    print("\ncost per stage (CPU s; peak resident MB after the stage), tension / compression")
    print(f"{'front_h':>7} {'load':>11} {'tets':>6} {'total':>8} {'global':>7} {'crack':>6} {'mesh':>6} {'assem':>6} "
          f"{'cond':>6} {'contact':>7} {'fronts':>6} {'steps':>5} {'share':>6} {'peak MB':>8}")
    for r in rows:
        if "error" in r:
            print(f"{r['front_h']:>7} failed: {r['error']}")
            continue
        c, n = r["cpu"], r["ndof"]
        solve = c["assemble"] + c["condense"] + c["contact"]
        print(f"{r['front_h']:>7} {r['load']:>11} {r['tets']:>6} {n['total']:>8} {n['global']:>7} {n['contact']:>6} "
              f"{c['mesh']:>6.1f} {c['assemble']:>6.1f} {c['condense']:>6.1f} {c['contact']:>7.1f} {c['fronts']:>6.1f} "
              f"{r['iterations']:>5} {c['contact'] / solve:>6.0%} {max(r['rss_mb'].values()):>8.0f}")
    ok = [r for r in rows if "error" not in r and r["load"] == "tension"]
    print("\naccuracy (tension): centre opening and K_I along the front")
    print(f"{'front_h':>7} {'w0/Sneddon':>10} {'K_I mean/S':>10} {'K_I min/S':>9} {'K_I max/S':>9} {'|K_II|/S':>8} "
          f"{'|K_III|/S':>9} {'G/G_S':>6} {'J-scaled K_I/S':>14}")
    for r in ok:
        K = np.array(r["K_I"]) / r["sneddon_K"]
        Gs = r["sneddon_K"] ** 2 * (1 - 0.09) / 1000.0
        print(f"{r['front_h']:>7} {r['centre_opening'] / r['sneddon_opening']:>10.4f} {K.mean():>10.4f} {K.min():>9.4f} "
              f"{K.max():>9.4f} {np.max(np.abs(r['K_II'])) / r['sneddon_K']:>8.4f} "
              f"{np.max(np.abs(r['K_III'])) / r['sneddon_K']:>9.4f} {np.mean(r['G']) / Gs:>6.4f} "
              f"{np.mean(r['K_I_scaled_to_J']) / r['sneddon_K']:>14.4f}")
    if len(ok) >= 3:
        hs = [r["front_h"] for r in ok]
        kl, kr = richardson(hs, [float(np.mean(r["K_I"])) for r in ok])
        wl, wr = richardson(hs, [r["centre_opening"] for r in ok])
        S = ok[0]["sneddon_K"]
        print(f"\nfinite body, extrapolated: front-mean K_I {kl / S:.4f} x Sneddon (rate {kr:.2f}); "
              f"centre opening {wl / ok[0]['sneddon_opening']:.4f} x Sneddon (rate {wr:.2f})")
        print("front point errors against the extrapolated K_I:")
        for r in ok:
            e = np.array(r["K_I"]) / kl - 1.0
            print(f"  front_h {r['front_h']}: max |error| {np.max(np.abs(e)):.2%}, mean {np.mean(e):+.2%}")
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
