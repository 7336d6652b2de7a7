"""The crack QP solvers on the same (S, b, G): time, steps and KKT residuals; warm starts.

    python benchmarks/qp_solvers.py                  # real scenes and random SPD instances
    python benchmarks/qp_solvers.py --quick
    python benchmarks/qp_solvers.py sweep            # warm starts across a maxh and a nu sweep

The QPs come from real scenes (hybrid.condense + reduce_to_contact, as solve() builds
them, with G the element's constraint map) and from random SPD instances with a known
solution (eigenvalues 1..cond, a third of the indices active). Each solver runs on the
same data; "raw KKT" is the scaled KKT residual of the solver's own answer, "KKT" the
one after the active-set polish (solve_qp's default), "err" the largest difference of
w = G j from pdas's answer, relative to its size. No number here is a test threshold.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings

import numpy as np

#: (label, solver, options)
SOLVERS = [
    ("pdas", "pdas", {}),
    ("uzawa", "uzawa", {"max_iter": 20_000}),
    ("uzawa-acc", "uzawa", {"accelerate": True, "max_iter": 20_000}),
    ("clarabel", "clarabel", {}),
    ("osqp", "osqp", {}),
    ("scs", "scs", {}),
]
#: real scenes: (scene, element, maxh, crack_h)
SCENES = [
    ("paper-1", "peers", 0.05, None), ("paper-1", "bdm", 0.05, None),
    ("paper-2", "peers", 0.025, None), ("paper-2", "bdm", 0.025, None),
    ("paper-1", "bdm", 0.0125, None),
    ("griffith", "peers", 0.4, 0.002), ("griffith", "bdm", 0.4, 0.002),
    ("griffith", "bdm", 0.4, 0.001),
]
RANDOM = [(200, 1e4), (1000, 1e6), (2000, 1e8)]


def scene_qp(scene: str, element: str, maxh: float, crack_h):
    import ngcrack.scenes as scenes
    from ngcrack.core.hybrid import condense, reduce_to_contact
    from ngcrack.core.solve import scene_loads
    from ngcrack.planar import elements as E
    from ngcrack.planar.geometry import make_mesh
    from ngcrack.planar.materials import compliance

    sc = scenes.load(scene)
    loads = scene_loads(sc)
    cm = make_mesh(sc, maxh=maxh, crack_h=crack_h)
    mat = sc.material
    disc = E.build(element, cm, compliance(mat.E, mat.nu, mat.plane), loads)
    red = reduce_to_contact(condense(disc, loads))
    G = disc.constraint_map()
    return red.S, red.b, G


def random_qp(m: int, cond: float, seed: int = 0):
    rng = np.random.default_rng(seed)
    Q, _ = np.linalg.qr(rng.standard_normal((m, m)))
    S = (Q * np.logspace(0.0, np.log10(cond), m)) @ Q.T
    S = 0.5 * (S + S.T)
    v = np.where(rng.random(m) < 1 / 3, 0.0, rng.uniform(0.5, 2.0, m))
    Sv = S @ v
    mu = np.where(v == 0, rng.uniform(0.5, 2.0, m) * np.abs(Sv).max(), 0.0)
    return S, Sv - mu, None


def run_all(label: str, S, b, G) -> list[str]:
    from ngcrack.core.contact import ContactSolverError, solve_qp

    m = len(b)
    cond = np.linalg.cond(S)
    rows = []
    ref = None
    for name, solver, options in SOLVERS:
        t0 = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = solve_qp(S, b, G=G, solver=solver, solver_options=options)
        except ContactSolverError as exc:
            rows.append(f"{label:28s} {m:5d} {cond:8.1e} {name:10s} failed: {str(exc)[:80]}")
            continue
        t = time.perf_counter() - t0
        ref = r.w if ref is None else ref
        err = np.abs(r.w - ref).max() / max(np.abs(ref).max(), 1e-300)
        rows.append(f"{label:28s} {m:5d} {cond:8.1e} {name:10s} {t:8.3f} {r.iterations:6d} "
                    f"{max(r.raw_kkt.values()):9.1e} {max(r.kkt.values()):9.1e} {err:8.1e} {len(r.active):5d}")
    return rows


HEAD = (f"{'QP':28s} {'m':>5s} {'cond(S)':>8s} {'solver':10s} {'time [s]':>8s} {'steps':>6s} "
        f"{'raw KKT':>9s} {'KKT':>9s} {'err':>8s} {'act':>5s}")


def main_solvers(args) -> None:
    print(HEAD)
    print("-" * len(HEAD))
    cases = SCENES[:4] if args.quick else SCENES
    for scene, element, maxh, crack_h in cases:
        S, b, G = scene_qp(scene, element, maxh, crack_h)
        label = f"{scene} {element} h={maxh:g}" + (f" ch={crack_h:g}" if crack_h else "")
        for line in run_all(label, S, b, G):
            print(line, flush=True)
    for m, cond in (RANDOM[:1] if args.quick else RANDOM):
        S, b, G = random_qp(m, cond)
        for line in run_all("random SPD", S, b, G):
            print(line, flush=True)


def main_sweep(args) -> None:
    """Warm starts: pdas steps and QP time, cold against warm, along a maxh and a nu sweep."""
    import ngcrack.scenes as scenes
    from ngcrack.core.solve import solve

    print(f"{'sweep':34s} {'m':>5s} {'steps cold':>10s} {'steps warm':>10s} {'qp cold [s]':>11s} "
          f"{'qp warm [s]':>11s} {'total cold':>10s} {'total warm':>10s} {'|dj|':>8s}")
    sweeps = [("paper-1", "bdm", "maxh", [0.2, 0.1, 0.05, 0.025, 0.0125]),
              ("paper-1", "peers", "maxh", [0.2, 0.1, 0.05, 0.025, 0.0125]),
              ("paper-1", "bdm", "nu", [0.2, 0.3, 0.4, 0.45, 0.49, 0.499]),
              ("griffith", "bdm", "crack_h", [0.02, 0.01, 0.005, 0.0025])]
    for scene, element, what, values in sweeps:
        prev = None
        for val in values:
            sc = scenes.load(scene)
            kw = {"maxh": 0.025} if what == "nu" else {}
            if what == "nu":
                sc = sc.with_(nu=val)
            else:
                kw[what] = val
            cold = solve(sc, element, **kw)
            warm = solve(sc, element, warm_start=prev, **kw) if prev is not None else cold
            dj = np.abs(warm.qp.j - cold.qp.j).max() / max(np.abs(cold.qp.j).max(), 1e-300)
            print(f"{scene + ' ' + element + ' ' + what + '=' + format(val, 'g'):34s} {len(cold.qp.w):5d} "
                  f"{cold.qp.iterations:10d} {warm.qp.iterations:10d} {cold.qp.time_s:11.4f} {warm.qp.time_s:11.4f} "
                  f"{cold.timings['total']:10.2f} {warm.timings['total']:10.2f} {dj:8.1e}", flush=True)
            prev = cold


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="cmd")
    sub.add_parser("sweep", help="warm starts across a maxh and a nu sweep")
    p.add_argument("--quick", action="store_true")
    args = p.parse_args()
    if args.cmd == "sweep":
        main_sweep(args)
    else:
        main_solvers(args)


if __name__ == "__main__":
    sys.exit(main())
