"""Fatigue growth of a semi-elliptical surface crack: its a/c against a/t and its cycles, against Newman-Raju.

The plate of the built-in `surface-crack` scene (thickness t = 1.5, half-width b = 5, length 20, remote
tension S = 1, one end clamped) with a surface crack of depth `--a0` and aspect ratio `--ratio` (a/c)
grows under Paris's law da/dN = C Delta_K^m (C = 1e-3, m `--m`, R = 0) by `--steps` steps of `--da`
(`nc.grow`, the crack refitted as a semi-ellipse at each step: ngcrack.studies.growth.surface3d), on a
mesh of front_h `--front-h` and crack_h twice that.

The reference (`--reference` prints it alone, in a second): Newman and Raju's K at the deepest point
and at the surface point taken 5% of the front's length in (the growth's convention), integrated
with the same Paris law (ngcrack.studies.growth.newman_raju_growth.trajectory); beside it the same
at the surface point itself (fraction 0), and the rule of a step of the growth fed their K
(`rule_trajectory`, da 0.05): the error of the fitted-ellipse rule apart from that of the computed K.

Printed per step of the run: a/t, a/c, the reference's a/c at the same depth and their ratio, the
cycles and the reference's, K at the deepest point against Newman-Raju's, and the CPU seconds of the
step (process time; the machine is shared: its load is printed).

    python benchmarks/surface_growth.py --reference
    python benchmarks/surface_growth.py --ratio 0.4 --a0 0.3 --steps 5
    python benchmarks/surface_growth.py --ratio 1.2 --a0 0.45 --steps 4 --front-h 0.075

No number here is a test threshold.
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import time
from pathlib import Path

import numpy as np

T, B = 1.5, 5.0


def reference_table(m: float) -> None:
    import ngcrack as nc
    from ngcrack.solid.scene import SolidScene
    from ngcrack.studies.growth.newman_raju_growth import rule_trajectory, trajectory

    marks = np.array([0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8])
    print(f"Newman-Raju integrated (m = {m:g}): a/c at a/t = " + ", ".join(f"{x:g}" for x in marks))
    for ratio in (0.4, 1.2):
        a0, c0 = 0.3, 0.3 / ratio
        for label, frac in (("5% in (the growth's)", None), ("at the surface", 0.0)):
            tr = trajectory(a0, c0, 1.2, T, B, 1e-3, m, fraction=frac)
            row = np.interp(marks * T, tr["a"], tr["a"] / tr["c"])
            print(f"  from {ratio:g}, K_C {label:22s}: " + "  ".join(f"{v:.3f}" for v in row))
        d = copy.deepcopy(nc.scenes.load("surface-crack").to_dict())
        d["crack"][0]["semi_axes"] = [c0, a0]
        rule = rule_trajectory(SolidScene.from_dict(d), 0.05, 18, m)
        row = np.interp(marks[marks * T <= rule["a"][-1]] * T, rule["a"], rule["a"] / rule["c"])
        print(f"  from {ratio:g}, the rule fed their K (da 0.05): " + "  ".join(f"{v:.3f}" for v in row))


def rule_orders(m: float) -> None:
    """The rule of a step fed Newman and Raju's K, one solve a step (K at the step's start) against Heun's
    predictor-corrector (the mean of the advances on the crack and on the predicted one): the largest |a/c / the
    reference's - 1| from a/t 0.2 to 0.6, at da = 0.1, 0.05, 0.025, from a/c = 0.4 and 1.2."""
    import ngcrack as nc
    from ngcrack.solid.scene import SolidScene
    from ngcrack.studies.growth.newman_raju_growth import rule_trajectory, trajectory

    print(f"the rule of a step fed Newman-Raju's K (m = {m:g}): max |a/c error| over a/t 0.2-0.6")
    for ratio in (0.4, 1.2):
        a0, c0 = 0.3, 0.3 / ratio
        d = copy.deepcopy(nc.scenes.load("surface-crack").to_dict())
        d["crack"][0]["semi_axes"] = [c0, a0]
        ref = trajectory(a0, c0, 1.2, T, B, 1e-3, m)
        for heun in (False, True):
            errs = []
            for da in (0.1, 0.05, 0.025):
                r = rule_trajectory(SolidScene.from_dict(d), da, int(round(0.6 / da)), m, heun=heun)
                want = np.interp(r["a"], ref["a"], ref["a"] / ref["c"])
                errs.append(float(np.max(np.abs(r["a"] / r["c"] / want - 1))))
            print(f"  from {ratio:g}, {'Heun' if heun else 'one solve':9s}: " + "  ".join(f"{e:.4f}" for e in errs))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ratio", type=float, default=0.4, help="the initial a/c")
    parser.add_argument("--a0", type=float, default=0.3, help="the initial depth a")
    parser.add_argument("--da", type=float, default=0.1)
    parser.add_argument("--steps", type=int, default=4)
    parser.add_argument("--m", type=float, default=3.0)
    parser.add_argument("--front-h", type=float, default=0.1)
    parser.add_argument("--corner", action="store_true", help="a quarter-elliptical corner crack on the edge of the "
                        "plate's face and its side (against Newman and Raju's corner-crack equation)")
    parser.add_argument("--reference", action="store_true", help="print the reference table only")
    parser.add_argument("--corrector", action="store_true", help="Heun's predictor-corrector step (two solves a step)")
    parser.add_argument("--orders", action="store_true", help="print the rule's errors, one solve a step against "
                        "Heun's, at da 0.1, 0.05, 0.025, and stop")
    parser.add_argument("--png", help="write the fronts over the steps here")
    parser.add_argument("--save", help="add the run's depths, lengths and cycles to this JSON file (a list of runs)")
    parser.add_argument("--figure", nargs=2, metavar=("PNG", "RUNS"), help="draw a/c against a/t of the runs saved "
                        "in RUNS (--save) over the reference trajectories, and stop")
    args = parser.parse_args(argv)
    if args.figure:
        figure(*args.figure, args.m)
        return 0
    if args.orders:
        rule_orders(args.m)
        return 0
    print(f"{os.uname().nodename}: {os.cpu_count()} cores; load {os.getloadavg()[0]:.1f}")
    reference_table(args.m)
    if args.reference:
        return 0

    import ngcrack as nc
    from ngcrack.studies.growth.newman_raju_growth import surface_K_any, trajectory

    C, m = 1e-3, args.m
    a0, c0 = args.a0, args.a0 / args.ratio
    d = copy.deepcopy(nc.scenes.load("surface-crack").to_dict())
    d["crack"][0]["semi_axes"] = [c0, a0]
    d["mesh"] = {"front_h": args.front_h, "crack_h": 2 * args.front_h}
    if args.corner:
        d["crack"][0]["center"] = [-B, 0.0, T]  # on the edge of the face z = t and the side x = -b
        return corner_run(d, args, a0, c0)
    clock, cpu = [time.process_time()], []

    def progress(n, result):
        now = time.process_time()
        cpu.append(now - clock[0])
        clock[0] = now

    r = nc.grow(nc.Scene.from_dict(d), da=args.da, steps=args.steps, paris=(C, m), progress=progress,
                corrector=args.corrector)
    ac = r.depth_and_length()
    ref = trajectory(a0, c0, max(ac[-1, 0], a0 + 1e-9) + 1e-6, T, B, C, m)
    N = r.cycles()
    print(f"\nfrom a/c = {args.ratio:g}, a/t = {a0 / T:.3g}: da {args.da:g}, front_h {args.front_h:g}"
          f"{', Heun' if args.corrector else ''}; {r.stopped}")
    print(f"{'step':>4} {'a/t':>6} {'a/c':>6} {'ref':>6} {'ratio':>6} {'cycles':>9} {'ref N':>9} {'N/ref':>6} "
          f"{'K_A':>6} {'K_A NR':>6} {'K_A/NR':>6} {'ndof':>8} {'cpu s':>6}")
    for k, (a, c) in enumerate(ac):
        step = r.steps[k]
        K = np.asarray(step["fronts"][0]["K_I"])
        K_A = float(K[len(K) // 2])
        K_nr = float(surface_K_any(1.0, a, c, T, B, 0.5 * np.pi))
        want = float(np.interp(a, ref["a"], ref["a"] / ref["c"]))
        N_ref = float(np.interp(a, ref["a"], ref["N"]))
        print(f"{k:4d} {a / T:6.3f} {a / c:6.3f} {want:6.3f} {a / c / want:6.3f} {N[k]:9.4g} {N_ref:9.4g} "
              f"{(N[k] / N_ref if N_ref else 1.0):6.3f} {K_A:6.3f} {K_nr:6.3f} {K_A / K_nr:6.3f} {step['ndof']:8d} "
              f"{cpu[k]:6.1f}")
    if args.png:
        r.plot(args.png)
        print(f"wrote {args.png}")
    if args.save:
        runs = json.loads(Path(args.save).read_text()) if Path(args.save).exists() else []
        runs.append({"ratio": args.ratio, "a": ac[:, 0].tolist(), "c": ac[:, 1].tolist(), "N": N.tolist(),
                     "front_h": args.front_h, "da": args.da})
        Path(args.save).write_text(json.dumps(runs))
    return 0


def corner_run(d: dict, args, a0: float, c0: float) -> int:
    """The corner crack's run: a/c and the cycles against the corner-crack reference, K at the 5% points of both
    ends (both on a face) against Newman and Raju's there."""
    import ngcrack as nc
    from ngcrack.studies.growth.newman_raju_growth import phi_in_from_surface, trajectory
    from ngcrack.studies.newman_raju import corner_crack_K

    C, m, width = 1e-3, args.m, 2 * B
    clock, cpu = [time.process_time()], []

    def progress(n, result):
        now = time.process_time()
        cpu.append(now - clock[0])
        clock[0] = now

    r = nc.grow(nc.Scene.from_dict(d), da=args.da, steps=args.steps, paris=(C, m), progress=progress)
    ac = r.depth_and_length()
    ref = trajectory(a0, c0, max(ac[-1, 0], a0 + 1e-9) + 1e-6, T, width, C, m, corner=True)
    N = r.cycles()
    print(f"\ncorner crack from a/c = {args.ratio:g}, a/t = {a0 / T:.3g}: da {args.da:g}, front_h {args.front_h:g}; "
          f"{r.stopped}")
    print(f"{'step':>4} {'a/t':>6} {'a/c':>6} {'ref':>6} {'ratio':>6} {'cycles':>9} {'ref N':>9} {'N/ref':>6} "
          f"{'K_C':>6} {'NR':>6} {'K_A':>6} {'NR':>6} {'ndof':>8} {'cpu s':>6}")
    for k, (a, c) in enumerate(ac):
        step = r.steps[k]
        drive = step["fronts"][0]["K_drive"]  # from the end on the face z = t (C) to the end on the side (A)
        nr_c = float(corner_crack_K(1.0, a, c, T, width, phi_in_from_surface(a, c, 0.05, quarter=True)))
        nr_a = float(corner_crack_K(1.0, a, c, T, width, 0.5 * np.pi - phi_in_from_surface(c, a, 0.05, quarter=True)))
        want = float(np.interp(a, ref["a"], ref["a"] / ref["c"]))
        N_ref = float(np.interp(a, ref["a"], ref["N"]))
        print(f"{k:4d} {a / T:6.3f} {a / c:6.3f} {want:6.3f} {a / c / want:6.3f} {N[k]:9.4g} {N_ref:9.4g} "
              f"{(N[k] / N_ref if N_ref else 1.0):6.3f} {drive[0]:6.3f} {nr_c:6.3f} {drive[-1]:6.3f} {nr_a:6.3f} "
              f"{step['ndof']:8d} {cpu[k]:6.1f}")
    if args.png:
        r.plot(args.png)
        print(f"wrote {args.png}")
    return 0


def figure(png: str, runs_file: str, m: float) -> None:
    """a/c against a/t: the reference trajectories from a/c = 0.4 and 1.2 (and from each run's start), the runs."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ngcrack.studies.growth.newman_raju_growth import trajectory

    runs = json.loads(Path(runs_file).read_text())
    fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
    for ratio in (0.4, 1.2):
        tr = trajectory(0.3, 0.3 / ratio, 1.2, T, B, 1e-3, m)
        ax.plot(tr["a"] / T, tr["a"] / tr["c"], "--", color="0.5", lw=1,
                label="Newman-Raju from a/t = 0.2, a/c = 0.4 and 1.2" if ratio == 0.4 else None)
    for run in runs:
        a, c = np.array(run["a"]), np.array(run["c"])
        tr = trajectory(a[0], c[0], 1.2, T, B, 1e-3, m)
        line, = ax.plot(tr["a"] / T, tr["a"] / tr["c"], "-", lw=1.2, label=f"Newman-Raju from a/c = {run['ratio']:g}")
        ax.plot(a / T, a / c, "o", color=line.get_color(), label=f"nc.grow (front_h {run['front_h']:g}, da {run['da']:g})")
    ax.set_xlabel("a/t")
    ax.set_ylabel("a/c")
    ax.set_title(f"Surface crack under Paris fatigue (m = {m:g}): a/c against a/t")
    ax.legend(fontsize=7)
    fig.savefig(png, dpi=130)
    print(f"wrote {png}")


if __name__ == "__main__":
    raise SystemExit(main())
