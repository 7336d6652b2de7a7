"""Radial (penny-shaped) hydraulic fracture in 3D, toughness-dominated, against Savitski-Detournay's K-vertex.

    python benchmarks/hydrofrac_radial.py [--steps N] [--figure OUT.png]
    python benchmarks/hydrofrac_radial.py --leakoff C_L [--steps N]
    python benchmarks/hydrofrac_radial.py --viscosity MU [--K-Ic K] [--steps N] [--crack-h H --front-h H] [--figure OUT.png]

The built-in penny's body (a box of side 20 R0, rollers on three faces through a corner, R0 = 1)
with E = 30 GPa, nu = 0.25, K_Ic = 1 MPa m^(1/2), Q0 = 1e-3 m^3/s, at its default mesh sizes
(crack_h 0.4 R, front_h 0.2 R: they scale with R), grown by da = 0.1 from R = 1. The table: per
step the radius, the pressure and the opening at the centre against the K-vertex at the step's
time (R = 0.8546 (E' Q0 t / K')^(2/5), p = K_Ic (pi / R)^(1/2) / 2, w0 = 8 p R / (pi E')), the
front's K_I spread and the step's CPU. Then the first step (R = 1) against the finite body's own
answer: the mesh halved at the crack (crack_h 0.2 R, front_h 0.1 R) and the box doubled.

With --viscosity the viscous model (lubrication on rings, the compliance from the 3D solve): per step
R, the pressure (the ring around r = R / 2 against the vertex's mean over it) and the centre's opening
against Savitski-Detournay's M-vertex (first order: R = 0.6976 (E' Q0^3 t^4 / mu')^(1/9); the zero-order
0.6955 beside it) and R against the K-vertex, the radial K = K' (t^2 / (mu'^5 Q0^3 E'^13))^(1/18), the
volume balance and the step's CPU; then the last step's profiles against the M-vertex's.
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


def viscous_run(args) -> None:
    """The viscous radial model against the M-vertex (and the K-vertex), per step (module docstring)."""
    from ngcrack.studies.hydrofrac.radial_viscous import M_GAMMA, m_opening, m_pressure, m_vertex_radial

    scene = body()
    Ep = e_prime_3d(scene)
    opts = {k: v for k, v in (("crack_h", args.crack_h), ("front_h", args.front_h)) if v is not None}
    t0 = time.process_time()
    res = nc.hydrofrac(scene, rate=Q0, K_Ic=args.K_Ic, da=0.1, steps=args.steps, viscosity=args.viscosity, **opts)
    total = time.process_time() - t0
    print(f"viscous radial, mu = {args.viscosity:g} Pa s, K_Ic = {args.K_Ic:g}, crack_h {opts.get('crack_h', 0.4):g}, "
          f"front_h {opts.get('front_h', 0.2):g} (x R): {res.stopped}; {total:.0f} s CPU in all\n")
    print("| step | t (s) | K | R (m) | R / R_M - 1 | R / R_M0 - 1 | R / R_K - 1 | p(R/2) err | w0 (mm) | w0 err | "
          "w0 / w0_K - 1 | balance | dofs | CPU (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for s in res.steps:
        ref = m_vertex_radial(s["time"], Ep, args.viscosity, Q0)
        R_k, _, w_k = k_vertex_radial(s["time"], Ep, args.K_Ic, Q0)
        R = s["half_length"]
        prof = s["profile"]
        edges = np.concatenate([[0.0], 0.5 * (np.asarray(prof["s"][1:]) + np.asarray(prof["s"][:-1])), [R]])
        k = int(np.searchsorted(edges, 0.5 * R)) - 1  # the ring around R / 2
        rho = np.linspace(edges[k], edges[k + 1], 201) / ref["R"]
        p_ref = np.trapezoid(m_pressure(rho) * rho, rho) / np.trapezoid(rho, rho) * ref["eps"] * Ep
        balance = s["volume"] / (Q0 * s["time"]) - 1
        print(f"| {s['step']} | {s['time']:.4f} | {s['K_m']:.3g} | {R:.2f} | {R / ref['R'] - 1:+.2%} | "
              f"{R / ref['R0'] - 1:+.2%} | {R / R_k - 1:+.2%} | {prof['pressure'][k] / p_ref - 1:+.2%} | "
              f"{s['opening_at_injection'] * 1e3:.5f} | {s['opening_at_injection'] / ref['w0'] - 1:+.2%} | "
              f"{s['opening_at_injection'] / w_k - 1:+.2%} | {balance:+.1e} | {s['ndof']} | {s['time_s']:.1f} |")
    s = res.steps[-1]
    ref = m_vertex_radial(s["time"], Ep, args.viscosity, Q0)
    print("\nthe last step's rings against the M-vertex at its time (rho = r / R_M):\n")
    print("| r (m) | opening (mm) | M-vertex (mm) | 3D opening at r (mm) | p (MPa) | M-vertex p (MPa) |")
    print("|---|---|---|---|---|---|")
    for r, w, w3, p in zip(s["profile"]["s"], s["profile"]["opening"], s["profile"]["opening_3d"], s["profile"]["pressure"]):
        rho = r / ref["R"]
        print(f"| {r:.3f} | {w * 1e3:.5f} | {float(m_opening(rho)) * ref['eps'] * ref['L'] * M_GAMMA * 1e3:.5f} | "
              f"{w3 * 1e3:.5f} | {p / 1e6:.4f} | {float(m_pressure(rho)) * ref['eps'] * Ep / 1e6:.4f} |")
    if args.figure:
        viscous_figure(res, Ep, args, args.figure)


def viscous_figure(res, Ep: float, args, path: str) -> None:
    """R against t with both vertices, and the last step's opening and pressure against the M-vertex's."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ngcrack.studies.hydrofrac.radial_viscous import M_GAMMA, m_opening, m_pressure, m_vertex_radial

    t = np.array([s["time"] for s in res.steps])
    tt = np.linspace(0.8 * t.min(), 1.1 * t.max(), 100)
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(12, 3.3), constrained_layout=True)
    a1.plot(tt, m_vertex_radial(tt, Ep, args.viscosity, Q0)["R"], "-", label="M-vertex (Savitski-Detournay)")
    a1.plot(tt, k_vertex_radial(tt, Ep, args.K_Ic, Q0)[0], "--", label="K-vertex")
    a1.plot(t, [s["radius"] for s in res.steps], "o", label="ngcrack (3D, viscous)")
    radii = [s["radius"] for s in res.steps]
    a1.set(xlabel="t (s)", ylabel="R (m)", ylim=(0.8 * min(radii), 1.2 * max(radii)))  # the K-vertex may lie above
    a1.legend(fontsize=8)
    s = res.steps[-1]
    ref = m_vertex_radial(s["time"], Ep, args.viscosity, Q0)
    rho = np.linspace(0.0, 1.0, 200)[1:-1]
    r = np.asarray(s["profile"]["s"])
    a2.plot(rho * ref["R"], m_opening(rho) * ref["eps"] * ref["L"] * M_GAMMA * 1e3, "-", label="M-vertex")
    a2.step(r, np.asarray(s["profile"]["opening"]) * 1e3, where="mid", label="rings' mean opening")
    a2.plot(r, np.asarray(s["profile"]["opening_3d"]) * 1e3, "o", ms=3, label="3D opening")
    a2.set(xlabel="r (m)", ylabel="opening (mm)", title=f"t = {s['time']:.3g} s", ylim=(0, None))
    a2.legend(fontsize=8)
    a3.plot(rho * ref["R"], m_pressure(rho) * ref["eps"] * Ep / 1e6, "-", label="M-vertex")
    a3.step(r, np.asarray(s["profile"]["pressure"]) / 1e6, where="mid", label="rings' pressure")
    top = float(np.max(s["profile"]["pressure"])) / 1e6
    a3.set(xlabel="r (m)", ylabel="p (MPa)", ylim=(-0.3 * top, 1.3 * top))
    a3.legend(fontsize=8)
    fig.savefig(path, dpi=110)
    print(f"\nwrote {path}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=5)
    ap.add_argument("--figure", default=None)
    ap.add_argument("--leakoff", type=float, default=None, metavar="C_L",
                    help="instead: a run with Carter's leak-off C_L against the storage-free radius")
    ap.add_argument("--viscosity", type=float, default=None, metavar="MU",
                    help="instead: the viscous model against the M-vertex (and the K-vertex)")
    ap.add_argument("--K-Ic", dest="K_Ic", type=float, default=1e4, help="the toughness of the --viscosity run")
    ap.add_argument("--crack-h", dest="crack_h", type=float, default=None)
    ap.add_argument("--front-h", dest="front_h", type=float, default=None)
    args = ap.parse_args()
    if args.viscosity is not None:
        return viscous_run(args)
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
