"""3D growth of planar cracks: a penny and an ellipse under Paris fatigue, their shapes and cycles per step.

The coarse penny (`ngcrack.scenes.coarse3d.coarse_penny`: radius a = 1 in a box of side 20a, tension
sigma = 1 normal to it, maxh 5, crack_h 0.4, front_h 0.2) or an ellipse of semi-axes 1 and `--aspect`
in the same box (crack_h 0.3, front_h 0.15) grows under Paris's law da/dN = C Delta_K^m (C = 1e-3, m
`--m`, R = 0) by `--steps` steps of `--da`. Printed per step: the crack's equivalent radius sqrt(A/pi),
the spread of its front's distance from the centre (max - min over the mean), its aspect ratio b/a
(the extents along the two axes), the largest K_eq, the cumulative cycles, the closed form of Paris's
law with Sneddon's K = 2 sigma sqrt(a/pi) at the equivalent radius and their ratio (for the ellipse the
closed form is the penny's, only a scale), the largest |kink_deg| and the CPU seconds of the step
(process time; the machine is shared: `uptime` printed).

    python benchmarks/grow3d.py                       # the penny, 4 steps of 0.1
    python benchmarks/grow3d.py --da 0.05 --steps 8   # the same growth in steps half as long
    python benchmarks/grow3d.py --case ellipse --aspect 0.6 --steps 3

No number here is a test threshold.
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np


def sneddon_cycles(a, a0, C, m):
    k = C * (2.0 / math.sqrt(math.pi)) ** m
    return (a ** (1 - m / 2) - a0 ** (1 - m / 2)) / ((1 - m / 2) * k)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", choices=("penny", "ellipse"), default="penny")
    parser.add_argument("--da", type=float, default=0.1)
    parser.add_argument("--steps", type=int, default=4)
    parser.add_argument("--m", type=float, default=3.0)
    parser.add_argument("--aspect", type=float, default=0.6)
    parser.add_argument("--png", help="write the fronts over the steps here")
    args = parser.parse_args(argv)

    import ngcrack as nc
    from ngcrack.scenes.coarse3d import coarse_penny

    d = coarse_penny()
    if args.case == "ellipse":
        d["crack"] = [{"shape": "ellipse", "center": [0, 0, 0], "normal": [0, 0, 1], "semi_axes": [1.0, args.aspect],
                       "major_axis": [1, 0, 0]}]
        d["mesh"] = {"maxh": 5.0, "crack_h": 0.3, "front_h": 0.15}
    scene = nc.Scene.from_dict(d)
    C, m = 1e-3, args.m
    print(f"{os.uname().nodename}: {os.cpu_count()} cores; load {os.getloadavg()[0]:.1f}")
    clock = [time.process_time()]
    cpu = []

    def progress(n, result):
        now = time.process_time()
        cpu.append(now - clock[0])
        clock[0] = now

    res = nc.grow(scene, da=args.da, steps=args.steps, paris=(C, m), progress=progress)
    a0 = math.sqrt(scene.cracks[0].area / math.pi)
    print(f"\n{args.case}: da {args.da:g}, {args.steps} steps, m {m:g}; stopped: {res.stopped}\n")
    print("| step | sqrt(A/pi) | radius spread | b/a | max K_eq | cycles | closed form | ratio | max abs kink deg | CPU s |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for k, (s, st) in enumerate(zip(res.scenes, res.steps)):
        p = s.cracks[0].outline(512) - s.cracks[0].center
        r = np.linalg.norm(p, axis=1)
        a = math.sqrt(s.cracks[0].area / math.pi)
        closed = sneddon_cycles(a, a0, C, m)
        (f,) = st["fronts"]
        ratio = f"{st['cycles'] / closed:.4f}" if k else "-"
        print(f"| {k} | {a:.4f} | {(r.max() - r.min()) / r.mean():.4f} | {np.ptp(p[:, 1]) / np.ptp(p[:, 0]):.4f} | "
              f"{max(f['K_eq']):.4f} | {st['cycles']:.2f} | {closed:.2f} | {ratio} | "
              f"{max(abs(x) for x in f['kink_deg']):.2f} | {cpu[k]:.1f} |")
    print(f"\nunknowns at the last step: {res.steps[-1]['ndof']}; CPU per step (solve and growth): "
          f"{np.mean(cpu[1:]) if len(cpu) > 1 else cpu[0]:.1f} s")
    if args.png:
        res.plot(args.png)
        print(f"wrote {args.png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
