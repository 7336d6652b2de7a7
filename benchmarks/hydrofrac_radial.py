"""Radial (penny-shaped) hydraulic fracture in 3D, toughness-dominated, against Savitski-Detournay's K-vertex.

    python benchmarks/hydrofrac_radial.py [--steps N] [--figure OUT.png]
    python benchmarks/hydrofrac_radial.py --leakoff C_L [--steps N]

The built-in penny's body (a box of side 20 R0, rollers on three faces through a corner, R0 = 1)
with E = 30 GPa, nu = 0.25, K_Ic = 1 MPa m^(1/2), Q0 = 1e-3 m^3/s, at its default mesh sizes
(crack_h 0.4 R, front_h 0.2 R: they scale with R), grown by da = 0.1 from R = 1. The table: per
step the radius, the pressure and the opening at the centre against the K-vertex at the step's
time (R = 0.8546 (E' Q0 t / K')^(2/5), p = K_Ic (pi / R)^(1/2) / 2, w0 = 8 p R / (pi E')), the
front's K_I spread and the step's CPU. Then the first step (R = 1) against the finite body's own
answer: the mesh halved at the crack (crack_h 0.2 R, front_h 0.1 R) and the box doubled.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import ngcrack as nc
from ngcrack.solid.scene import SolidScene
from ngcrack.studies.hydrofrac.radial import e_prime_3d, k_vertex_radial

E, NU, Q0, K_IC = 30e9, 0.25, 1e-3, 1e6


def body(half: float = 10.0) -> SolidScene:
    d = nc.scenes.load("penny").to_dict()
    d["boundary"].pop("zmax")  # the fluid alone loads the body
    d["material"] = {"E": E, "nu": NU}
    d["domain"]["box"] = [[-half] * 3, [half] * 3]
    d.pop("mesh")  # the 3D defaults: crack_h 0.2 and front_h 0.1 of the crack's diameter
    d["mesh"] = {"maxh": 5.0}
    return SolidScene.from_dict(d)


def errors(s: dict, Ep: float) -> tuple:
    R, p, w0 = k_vertex_radial(s["time"], Ep, K_IC, Q0)
    return s["half_length"] / R - 1, s["pressure"] / p - 1, s["opening_at_injection"] / w0 - 1


def leakoff_run(steps: int, C_L: float) -> None:
    """The same body and mesh with leak-off: per step the efficiency and R against the storage-free radius."""
    from ngcrack.studies.hydrofrac.radial import carter_radius

    scene = body()
    res = nc.hydrofrac(scene, rate=Q0, K_Ic=K_IC, da=0.1, steps=steps, leakoff=C_L)
    print(f"leak-off C_L = {C_L:g}: {res.stopped}\n")
    print("| step | t (s) | R (m) | efficiency | storage-free R (m) | R / storage-free R | balance | CPU (s) |")
    print("|---|---|---|---|---|---|---|---|")
    for s in res.steps:
        Rc = carter_radius(s["time"], Q0, C_L)
        balance = (s["volume"] + s["leaked"]) / (Q0 * s["time"]) - 1  # stored + leaked = injected
        print(f"| {s['step']} | {s['time']:.4f} | {s['half_length']:.2f} | {s['efficiency']:.3f} | {Rc:.3f} | "
              f"{s['half_length'] / Rc:.3f} | {balance:+.1e} | {s['time_s']:.1f} |")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=5)
    ap.add_argument("--figure", default=None)
    ap.add_argument("--leakoff", type=float, default=None, metavar="C_L",
                    help="instead: a run with Carter's leak-off C_L against the storage-free radius")
    args = ap.parse_args()
    if args.leakoff is not None:
        return leakoff_run(args.steps, args.leakoff)
    scene = body()
    Ep = e_prime_3d(scene)
    t0 = time.process_time()
    res = nc.hydrofrac(scene, rate=Q0, K_Ic=K_IC, da=0.1, steps=args.steps)
    total = time.process_time() - t0
    print(f"default penny mesh, box 20 R0, da = 0.1 R0: {res.stopped}; {total:.0f} s CPU in all\n")
    print("| step | t (s) | R (m) | R err | p (MPa) | p err | w0 (mm) | w0 err | K_I spread | dofs | CPU (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for s in res.steps:
        eR, ep, ew = errors(s, Ep)
        print(f"| {s['step']} | {s['time']:.4f} | {s['half_length']:.2f} | {eR:+.2%} | {s['pressure'] / 1e6:.4f} | {ep:+.2%} | "
              f"{s['opening_at_injection'] * 1e3:.5f} | {ew:+.2%} | {s['front']['spread']:.2%} | {s['ndof']} | "
              f"{s['time_s']:.1f} |")
    # the first step against the finite body's own answer: finer at the crack, then a larger box
    print("\nR = 1 (step 0) on other meshes and bodies:\n")
    print("| body | crack_h, front_h | R err | p err | w0 err | CPU (s) |")
    print("|---|---|---|---|---|---|")
    for label, sc, opts in [("box 20 R0", scene, {}), ("box 20 R0", scene, {"crack_h": 0.2, "front_h": 0.1}),
                            ("box 40 R0", body(20.0), {"maxh": 10.0})]:
        r = nc.hydrofrac(sc, rate=Q0, K_Ic=K_IC, da=0.1, steps=1, time=1e-12, **opts)
        s = r.steps[0]
        eR, ep, ew = errors(s, Ep)
        sizes = f"{opts.get('crack_h', 0.4):g} R, {opts.get('front_h', 0.2):g} R"
        print(f"| {label} | {sizes} | {eR:+.2%} | {ep:+.2%} | {ew:+.2%} | {s['time_s']:.1f} |")
    if args.figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        t = np.array([s["time"] for s in res.steps])
        tt = np.linspace(0.5 * t.min(), 1.1 * t.max(), 100)
        R, p, _ = k_vertex_radial(tt, Ep, K_IC, Q0)
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(8, 3.2), constrained_layout=True)
        a1.plot(tt, R, "-", label="K-vertex (Savitski-Detournay)")
        a1.plot(t, [s["half_length"] for s in res.steps], "o", label="ngcrack (3D, tdnns)")
        a1.set(xlabel="t (s)", ylabel="R (m)")
        a1.legend(fontsize=8)
        a2.plot(tt, p / 1e6, "-")
        a2.plot(t, [s["pressure"] / 1e6 for s in res.steps], "o")
        a2.set(xlabel="t (s)", ylabel="p (MPa)")
        fig.savefig(args.figure, dpi=110)
        print(f"\nwrote {args.figure}")


if __name__ == "__main__":
    main()
