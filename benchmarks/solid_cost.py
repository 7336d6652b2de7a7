"""What the 3D penny costs against the size at its front, and how K_I's error falls with it.

The built-in scene `penny` (radius a = 1 in a block of side 20a, remote tension p = 1,
E = 1000, nu = 0.3, hybridized TDNNS) at several sizes at the front (crack_h = 2 front_h,
maxh = 5; `--front-h`), each in its own process on one thread so that its CPU seconds and
peak memory are its own. Per size:

- unknowns: total (before the static condensation), condensed, crack (the contact unknowns);
- CPU seconds per stage (time.process_time): mesh, assemble, condense, factorize (the one
  sparse factorization with the crack unknowns last, which leaves their Schur complement:
  the linear solve of the body), contact (the active set on the crack unknowns, the
  recovery of the rest and the certificate), fronts (the interaction integral), and the
  error estimate with `--estimate`; the contact stage's share of the solve;
- the peak resident memory of the process;
- K_I at every front point against Sneddon's 2 p sqrt(a / pi): the worst and the mean error.

At the end, the rates of the worst and of the mean error against the front size (least
squares of log |error| on log front_h over the sizes run).

`--levers` chooses what of this round's changes the run uses, one row of the lever table
of BENCHMARKS section 20 each: "none" (the mesh of netgen's grading alone, the bump of
3 front_h, one sparse factorization per active set), "contact" (the active set on the
Schur complement), "mesh" (that and the body's size near the crack, geometry.NEAR_*),
"all" (that and the front integral over the front's reach: the bump along the front at
least 1.6 of it, front.BUMP_REACH, and the tube at 0.8 of it whatever front_h,
front.CLOSED_TUBE_REACH: the defaults).

    python benchmarks/solid_cost.py                                  # front_h = 0.3, 0.2, 0.15; all levers
    python benchmarks/solid_cost.py --front-h 0.2 --levers none contact mesh all
    python benchmarks/solid_cost.py --front-h 0.2 --load -1           # every face closed: two active sets
    python benchmarks/solid_cost.py --accuracy 0.02 0.01 0.005         # the sizes `accuracy=` asks for
    python benchmarks/solid_cost.py --scene ellipse --front-h 0.09 --crack-h-ratio 2.78   # Irwin's ellipse, b/a = 0.5

`--integral before`: the front integral without its closed-form disc next to the front and with the Gauss rule of
order 6 (front.NEAR_DISC_H = 0, front.QUADRATURE_ORDER = 6): the "before" column of BENCHMARKS, "3D K tighter than 1%".

`--scene ellipse`: an elliptical crack of semi-axes a = 1 and b = 0.5 in the same block, K_I against Irwin's
p sqrt(pi b) / E(k) (sin^2 phi + (b/a)^2 cos^2 phi)^(1/4). `--accuracy`: each value's front_h and crack_h
(`ngcrack.solid.sizing.accuracy_sizes`), the requested accuracy beside the error obtained. Every row also
prints the size guard's estimate (`ngcrack.solid.sizing.estimate_size`: tetrahedra and peak memory) beside
the measured ones.
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

LEVERS = ("none", "contact", "mesh", "all")


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def scene_of(kind: str, load: float = 1.0):
    """The built-in penny, or the ellipse b/a = 0.5 in its block, under the traction `load` on the top face."""
    import ngcrack as nc

    d = nc.scenes.load("penny").to_dict()
    d["boundary"]["zmax"]["value"] = [0.0, 0.0, float(load)]
    if kind == "ellipse":
        d["name"] = "ellipse"
        d["crack"] = [{"shape": "ellipse", "center": [0, 0, 0], "normal": [0, 0, 1], "semi_axes": [1.0, 0.5],
                       "major_axis": [1, 0, 0]}]
    return nc.Scene.from_dict(d)


def reference_K_I(kind: str, front, load: float):
    """Sneddon's K_I along the penny's front, Irwin's along the ellipse's (module docstring)."""
    import numpy as np

    if kind == "penny":
        return np.full(len(front.K_I), 2.0 * abs(load) * math.sqrt(1.0 / math.pi))
    from scipy.special import ellipe

    a, b = 1.0, 0.5
    return abs(load) * math.sqrt(math.pi * b) / ellipe(1 - b * b / (a * a)) * (
        np.sin(front.angle) ** 2 + (b / a) ** 2 * np.cos(front.angle) ** 2) ** 0.25


def run_level(front_h: float, order: int, levers: str, load: float, estimate: bool, kind: str = "penny",
              ratio: float = 2.0, integral: str = "now") -> dict:
    """One size in this process: the stages timed one by one (module docstring)."""
    import numpy as np

    from ngcrack.core import schur
    from ngcrack.core.hybrid import condense
    from ngcrack.core.sparse_contact import solve_contact
    from ngcrack.solid import front as front_module
    from ngcrack.solid import geometry
    from ngcrack.solid.element import build
    from ngcrack.solid.output import SolidSolution
    from ngcrack.solid.solve import scene_loads

    if levers in ("none", "contact"):
        geometry.NEAR_RADIUS = 0.0
    if levers != "all":
        front_module.BUMP_REACH = front_module.CLOSED_TUBE_REACH = 0.0
    if integral == "before":
        from ngcrack.core.quadrature import DOMAIN_INTEGRAL_ORDER

        front_module.NEAR_DISC_H, front_module.QUADRATURE_ORDER = 0.0, DOMAIN_INTEGRAL_ORDER
    factorize = [0.0]
    original = schur.schur_complement

    def timed(*args, **kwargs):
        t = time.process_time()
        out = original(*args, **kwargs)
        factorize[0] += time.process_time() - t
        return out

    schur.schur_complement = timed
    from ngcrack.solid.sizing import estimate_size

    scene = scene_of(kind, load)
    guard = estimate_size(scene, "tdnns", order, maxh=5.0, crack_h=ratio * front_h, front_h=front_h)
    cpu = {}
    t = time.process_time()
    smesh = geometry.make_mesh(scene, maxh=5.0, crack_h=ratio * front_h, front_h=front_h)
    cpu["mesh"] = time.process_time() - t
    loads = scene_loads(scene)
    t = time.process_time()
    disc = build(smesh, scene.material.E, scene.material.nu, loads, order)
    cpu["assemble"] = time.process_time() - t
    t = time.process_time()
    system = condense(disc, loads)
    cpu["condense"] = time.process_time() - t
    G = disc.constraint_map()
    t = time.process_time()
    result = solve_contact(system.K, system.F, system.contact, G, method="sparse" if levers == "none" else "schur")
    total = time.process_time() - t
    if result.method == "schur":
        cpu["factorize"], cpu["contact"] = factorize[0], total - factorize[0]
    else:  # one factorization per active set: all of it is the contact stage's
        cpu["factorize"], cpu["contact"] = 0.0, total
    gf = system.expand(result.y)
    sol = SolidSolution(scene=scene, smesh=smesh, disc=disc, system=system, y=result.y, gf=gf, contact=result, G=G,
                        options={}, timings={})
    t = time.process_time()
    (front,) = front_module.front_parameters(sol)
    cpu["fronts"] = time.process_time() - t
    if estimate:
        from ngcrack.solid.estimate import prager_synge

        t = time.process_time()
        prager_synge(sol, loads)
        cpu["estimate"] = time.process_time() - t
    err = front.K_I / reference_K_I(kind, front, load) - 1.0
    return {"front_h": front_h, "crack_h": ratio * front_h, "order": order, "levers": levers, "load": load,
            "scene": kind, "tets": smesh.mesh.ne, "ndof": sol.ndof, "cpu": cpu, "peak_mb": _peak_mb(),
            "active_sets": result.iterations, "kkt": max(result.kkt.values()), "K_I_worst": float(np.max(np.abs(err))),
            "K_I_mean": float(np.mean(err)), "points": len(err), "guard_tets": guard.tets,
            "guard_mb": guard.memory / 1e6}


def _child(front_h: float, order: int, levers: str, load: float, estimate: bool, kind: str = "penny",
           ratio: float = 2.0, integral: str = "now") -> dict:
    env = dict(os.environ, OMP_NUM_THREADS="1", NGCRACK_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    cmd = [sys.executable, __file__, "--level", str(front_h), "--order", str(order), "--levers", levers,
           "--load", str(load), "--scene", kind, "--crack-h-ratio", str(ratio), "--integral", integral] + (["--estimate"] if estimate else [])
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    if out.returncode:
        return {"front_h": front_h, "levers": levers, "error": out.stderr.strip().splitlines()[-1:]}
    return json.loads(out.stdout.strip().splitlines()[-1])


def rate(hs, errors) -> float:
    """The slope of log |error| against log h (least squares); nan with fewer than two sizes."""
    import numpy as np

    if len(hs) < 2:
        return float("nan")
    return float(np.polyfit(np.log(hs), np.log(np.abs(errors)), 1)[0])


def report(rows: list[dict]) -> None:
    print(f"\nmachine: {os.cpu_count()} cores; load: {os.getloadavg()}; one thread")
    print("CPU s per stage; unknowns total / condensed / crack; K_I errors against Sneddon (penny) or Irwin (ellipse) over the "
          "front points; guard: the size guard's estimate")
    head = (f"{'levers':>7} {'accuracy':>8} {'front_h':>7} {'crack_h':>7} {'tets':>6} {'guard':>6} {'total':>8} {'cond.':>7} "
            f"{'crack':>5} {'mesh':>5} {'assem':>5} "
            f"{'cond':>5} {'factor':>6} {'contact':>7} {'fronts':>6} {'est':>5} {'solve':>6} {'share':>5} {'sets':>4} "
            f"{'peak MB':>7} {'guard MB':>8} {'worst':>6} {'mean':>7}")
    print(head)
    for r in rows:
        if "error" in r:
            print(f"{r['levers']:>7} {r['front_h']:>7} failed: {r['error']}")
            continue
        c, n = r["cpu"], r["ndof"]
        solve = sum(c.values())
        acc = f"{r['accuracy']:.3g}" if r.get("accuracy") else "-"
        print(f"{r['levers']:>7} {acc:>8} {r['front_h']:>7.4g} {r['crack_h']:>7.4g} {r['tets']:>6} {r['guard_tets']:>6.0f} "
              f"{n['total']:>8} {n['global']:>7} {n['contact']:>5} "
              f"{c['mesh']:>5.1f} {c['assemble']:>5.1f} {c['condense']:>5.1f} {c['factorize']:>6.1f} {c['contact']:>7.1f} "
              f"{c['fronts']:>6.1f} {c.get('estimate', float('nan')):>5.1f} {solve:>6.1f} {c['contact'] / solve:>5.0%} "
              f"{r['active_sets']:>4} {r['peak_mb']:>7.0f} {r['guard_mb']:>8.0f} {r['K_I_worst']:>6.2%} {r['K_I_mean']:>+7.2%}")
    for levers in dict.fromkeys(r["levers"] for r in rows):
        ok = [r for r in rows if r["levers"] == levers and "error" not in r]
        if len(ok) >= 2:
            hs = [r["front_h"] for r in ok]
            print(f"{levers}: rate of the worst error {rate(hs, [r['K_I_worst'] for r in ok]):.2f}, of the mean error "
                  f"{rate(hs, [r['K_I_mean'] for r in ok]):.2f} (log |error| against log front_h)")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--front-h", nargs="+", type=float, default=[0.3, 0.2, 0.15])
    p.add_argument("--order", type=int, default=1)
    p.add_argument("--levers", nargs="+", choices=LEVERS, default=["all"])
    p.add_argument("--load", type=float, default=1.0, help="the traction on the top face (-1: every face closes)")
    p.add_argument("--estimate", action="store_true", help="time the error estimate too")
    p.add_argument("--scene", choices=("penny", "ellipse"), default="penny", help="the penny or the ellipse b/a = 0.5")
    p.add_argument("--crack-h-ratio", dest="ratio", type=float, default=2.0, help="crack_h / front_h (default 2)")
    p.add_argument("--accuracy", nargs="+", type=float,
                   help="run the sizes these accuracies ask for (sizing.accuracy_sizes) instead of --front-h")
    p.add_argument("--integral", choices=("now", "before"), default="now",
                   help="the front integral as it is, or without its closed-form disc and with the rule of order 6")
    p.add_argument("--out", help="write the rows as JSON")
    p.add_argument("--level", type=float, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.level is not None:
        print(json.dumps(run_level(args.level, args.order, args.levers[0], args.load, args.estimate, args.scene,
                                   args.ratio, args.integral)))
        return 0
    rows = []
    if args.accuracy:
        from ngcrack.solid.sizing import ACCURACY_CRACK_H_RATIO, accuracy_sizes

        for a in args.accuracy:
            h = accuracy_sizes(scene_of(args.scene), a)["front_h"]
            row = _child(h, args.order, "all", args.load, args.estimate, args.scene, ACCURACY_CRACK_H_RATIO, args.integral)
            rows.append({**row, "accuracy": a})
            print(f"# done accuracy {a}: front_h {h:.4g}", flush=True)
    for levers in args.levers if not args.accuracy else ():
        for h in args.front_h:
            rows.append(_child(h, args.order, levers, args.load, args.estimate, args.scene, args.ratio, args.integral))
            print(f"# done {levers} front_h {h}", flush=True)
    report(rows)
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
