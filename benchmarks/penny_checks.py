"""Two published penny checks in 3D: code_aster's SSLV134 and a closed penny inclined to compression.

sslv134
    code_aster's validation case SSLV134: a penny crack of radius a = 2 m in a large body
    under remote tension sigma = 1 MPa normal to it, E = 2e5 MPa, nu = 0.3, in Pa and m
    (E = 2e11 Pa, sigma = 1e6 Pa). Reference: K_I = 1.596e6 Pa sqrt(m) and G = 11.586 J/m^2
    along the front; Sneddon's 2 sigma sqrt(a / pi) = 1.5958e6 Pa sqrt(m) beside it. The
    body is a box of side 20a = 40 m (rollers on xmin, ymin, zmin; the tension on zmax).
inclined
    A penny of radius a = 1 in a box of side 20a, its normal at `beta` (default 45 deg) to
    a uniaxial compression p = 1 along z (E = 1000, nu = 0.3), frictionless: the faces
    close and carry the normal stress p cos^2(beta); the shear tau = p sin(beta) cos(beta)
    slides them as on a free penny in that shear (Kassir and Sih): K_I = 0 and
    K_II = 4 tau sqrt(a/pi) / (2 - nu) (s . e1), K_III = (1 - nu) 4 tau sqrt(a/pi) / (2 - nu) (s . e3),
    s the shear direction in the crack plane, e1 and e3 the front's frame at the point.
    Reported: the K of the solve (where the faces are closed, the interaction integral's
    own values) and the same mode mix scaled to G = J (J is exact on frictionless faces).

Each case runs in its own process (its CPU seconds and peak memory its own), one thread.

    python benchmarks/penny_checks.py                          # both, order 2, front_h = 0.2a
    python benchmarks/penny_checks.py --case inclined --order 1 --front-h 0.2
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

#: code_aster SSLV134 (Pa, m)
SSLV134 = {"a": 2.0, "sigma": 1.0e6, "E": 2.0e11, "nu": 0.3, "K_I": 1.596e6, "G": 11.586}


def sslv134_scene(front_h_over_a: float = 0.2, units: str = "Pa") -> dict:
    """The scene in Pa and m, or in MPa and m (units = "MPa": K in MPa sqrt(m), G in MPa m = 1e6 J/m^2)."""
    a, scale = SSLV134["a"], (1e-6 if units == "MPa" else 1.0)
    side = 20.0 * a
    return {
        "name": "sslv134",
        "description": "code_aster SSLV134: penny crack a = 2 m under remote tension 1 MPa (Pa, m)",
        "domain": {"box": [[-side / 2] * 3, [side / 2] * 3]},
        "crack": [{"shape": "disc", "center": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0], "radius": a}],
        "material": {"E": SSLV134["E"] * scale, "nu": SSLV134["nu"]},
        "boundary": {"xmin": {"type": "roller"}, "ymin": {"type": "roller"}, "zmin": {"type": "roller"},
                     "zmax": {"type": "traction", "value": [0.0, 0.0, SSLV134["sigma"] * scale]}},
        "mesh": {"maxh": 2.5 * a, "crack_h": 2 * front_h_over_a * a, "front_h": front_h_over_a * a},
    }


def inclined_scene(front_h: float = 0.2, beta_deg: float = 45.0) -> dict:
    b = math.radians(beta_deg)
    return {
        "name": "inclined-penny",
        "description": "closed frictionless penny inclined to a uniaxial compression",
        "domain": {"box": [[-10.0] * 3, [10.0] * 3]},
        "crack": [{"shape": "disc", "center": [0.0, 0.0, 0.0], "normal": [math.sin(b), 0.0, math.cos(b)],
                   "radius": 1.0}],
        "material": {"E": 1000.0, "nu": 0.3},
        "boundary": {"xmin": {"type": "roller"}, "ymin": {"type": "roller"}, "zmin": {"type": "roller"},
                     "zmax": {"type": "traction", "value": [0.0, 0.0, -1.0]}},
        "mesh": {"maxh": 5.0, "crack_h": 2 * front_h, "front_h": front_h},
    }


def kassir_sih(front, beta_deg: float, nu: float, p: float = 1.0, a: float = 1.0):
    """K_II and K_III of a free penny in the resolved shear, at the front's points (module docstring)."""
    import numpy as np

    from ngcrack.solid.front import FrontGeometry

    b = math.radians(beta_deg)
    tau = p * math.sin(b) * math.cos(b)
    s = np.array([math.cos(b), 0.0, -math.sin(b)])  # the shear direction in the crack plane
    geom = FrontGeometry(front.crack_obj)
    e1, _, e3 = geom.frame(front.angle)
    k = 4.0 * tau * math.sqrt(a / math.pi) / (2.0 - nu)
    return k * (e1 @ s), (1.0 - nu) * k * (e3 @ s), k


def run_case(case: str, order: int, front_h: float, beta: float, units: str = "Pa") -> dict:
    import numpy as np

    import ngcrack as nc
    from ngcrack.solid.scene import SolidScene

    t = time.process_time()
    if case == "sslv134":
        scene = SolidScene.from_dict(sslv134_scene(front_h, units))
    else:
        scene = SolidScene.from_dict(inclined_scene(front_h, beta))
    sol = nc.solve(scene, order=order)
    cpu = time.process_time() - t
    (front,) = sol.fronts
    E, nu = scene.material.E, scene.material.nu
    row = {"case": case, "order": order, "front_h_over_a": front_h, "tets": sol.smesh.mesh.ne, "ndof": sol.ndof,
           "cpu_s": cpu, "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
           "kkt": sol.kkt, "active_sets": sol.contact.iterations, "closed": front.closed.tolist(),
           "K_I": front.K_I.tolist(), "K_II": front.K_II.tolist(), "K_III": front.K_III.tolist(),
           "G": front.G.tolist(), "scaled_to_J": front.scaled_to_J.tolist(), "angle": front.angle.tolist(),
           "closed_fraction": sol.crack_summaries()[0]["closed_fraction"], "units": units}
    if case == "sslv134" and units == "MPa":  # back to Pa sqrt(m) and J/m^2
        for key, f in (("K_I", 1e6), ("K_II", 1e6), ("K_III", 1e6), ("G", 1e6)):
            row[key] = (np.array(row[key]) * f).tolist()
        row["scaled_to_J"] = (np.array(row["scaled_to_J"]) * 1e6).tolist()
    if case == "inclined":
        front.crack_obj = scene.cracks[0]
        k2, k3, kmax = kassir_sih(front, beta, nu)
        mu, e_prime = E / (2 * (1 + nu)), E / (1 - nu * nu)
        JK = front.K_II ** 2 / e_prime + front.K_III ** 2 / (2 * mu)
        scale = np.sqrt(np.maximum(front.G, 0.0) / np.where(JK > 0, JK, 1.0))
        row.update(beta=beta, ref_K_II=k2.tolist(), ref_K_III=k3.tolist(), ref_max=kmax,
                   K_II_J=(scale * front.K_II).tolist(), K_III_J=(scale * front.K_III).tolist(),
                   ref_G=float(np.mean(k2 ** 2 / e_prime + k3 ** 2 / (2 * mu))))
    return row


def _child(case: str, order: int, front_h: float, beta: float, units: str) -> dict:
    env = dict(os.environ, OMP_NUM_THREADS="1")
    out = subprocess.run([sys.executable, __file__, "--child", case, "--order", str(order), "--front-h", str(front_h),
                          "--beta", str(beta), "--units", units], capture_output=True, text=True, env=env, check=False)
    if out.returncode:
        return {"case": case, "order": order, "front_h_over_a": front_h, "error": out.stderr.strip().splitlines()[-1:]}
    return json.loads(out.stdout.strip().splitlines()[-1])


def report(rows) -> None:
    import numpy as np

    print(f"machine: {os.cpu_count()} cores; load: {os.getloadavg()}; one thread (OMP_NUM_THREADS=1)")
    for r in rows:
        if "error" in r:
            print(f"{r['case']} order {r['order']} front_h {r['front_h_over_a']}a failed: {r['error']}")
            continue
        units = f" ({r['units']} and m)" if r["case"] == "sslv134" else ""
        print(f"\n{r['case']}{units}: order {r['order']}, front_h {r['front_h_over_a']}a, {r['tets']} tets, "
              f"{r['ndof']['global']} condensed unknowns, {r['ndof']['contact']} crack unknowns, "
              f"{r['active_sets']} active sets, {r['cpu_s']:.1f} s CPU, peak {r['peak_mb']:.0f} MB, "
              f"max KKT {max(r['kkt'].values()):.1e}, closed fraction {r['closed_fraction']:.3f}")
        K_I, G = np.array(r["K_I"]), np.array(r["G"])
        if r["case"] == "sslv134":
            sneddon = 2 * SSLV134["sigma"] * math.sqrt(SSLV134["a"] / math.pi)
            Ki = np.array(r["scaled_to_J"])[:, 0]
            print(f"  K_I/ref   min {K_I.min() / SSLV134['K_I']:.4f} mean {K_I.mean() / SSLV134['K_I']:.4f} "
                  f"max {K_I.max() / SSLV134['K_I']:.4f}   (ref 1.596e6; mean K_I {K_I.mean():.4e})")
            print(f"  K_I/Sneddon min {K_I.min() / sneddon:.4f} mean {K_I.mean() / sneddon:.4f} "
                  f"max {K_I.max() / sneddon:.4f}   (Sneddon {sneddon:.4e})")
            print(f"  G/ref     min {G.min() / SSLV134['G']:.4f} mean {G.mean() / SSLV134['G']:.4f} "
                  f"max {G.max() / SSLV134['G']:.4f}   (ref 11.586; mean G {G.mean():.4f})")
            print(f"  K_I scaled to G = J / ref mean {Ki.mean() / SSLV134['K_I']:.4f}; "
                  f"max |K_II|, |K_III| / K_I: {np.max(np.abs(r['K_II'])) / K_I.mean():.4f}, "
                  f"{np.max(np.abs(r['K_III'])) / K_I.mean():.4f}")
        else:
            k = r["ref_max"]
            e2 = (np.array(r["K_II"]) - r["ref_K_II"]) / k
            e3 = (np.array(r["K_III"]) - r["ref_K_III"]) / k
            e2j = (np.array(r["K_II_J"]) - r["ref_K_II"]) / k
            e3j = (np.array(r["K_III_J"]) - r["ref_K_III"]) / k
            print(f"  front points {len(K_I)}, closed {int(np.sum(r['closed']))}, max |K_I| {np.max(np.abs(K_I)):.3g}")
            print(f"  reported K:      max|K_II - KS|/KS_max {np.max(np.abs(e2)):.2%}   max|K_III - KS|/KS_max "
                  f"{np.max(np.abs(e3)):.2%}   max|K_II|/KS_max {np.max(np.abs(r['K_II'])) / k:.4f}  "
                  f"max|K_III|/KS_III_max {np.max(np.abs(r['K_III'])) / ((1 - 0.3) * k):.4f}")
            print(f"  scaled to G = J: max|K_II - KS|/KS_max {np.max(np.abs(e2j)):.2%}   max|K_III - KS|/KS_max "
                  f"{np.max(np.abs(e3j)):.2%}   max|K_II|/KS_max {np.max(np.abs(r['K_II_J'])) / k:.4f}  "
                  f"max|K_III|/KS_III_max {np.max(np.abs(r['K_III_J'])) / ((1 - 0.3) * k):.4f}")
            print(f"  mean G / Kassir-Sih G: {np.mean(G) / r['ref_G']:.4f}")
            print(f"  {'angle':>6} {'K_II/KS':>8} {'KS_II':>8} {'K_III/KS':>8} {'KS_III':>8}")
            for i in range(0, len(K_I), max(1, len(K_I) // 8)):
                print(f"  {math.degrees(r['angle'][i]):6.1f} {r['K_II'][i] / k:8.4f} {r['ref_K_II'][i] / k:8.4f} "
                      f"{r['K_III'][i] / k:8.4f} {r['ref_K_III'][i] / k:8.4f}")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--case", nargs="+", default=["sslv134", "inclined"], choices=["sslv134", "inclined"])
    p.add_argument("--order", type=int, default=2)
    p.add_argument("--front-h", type=float, default=0.2, help="front_h over the crack radius")
    p.add_argument("--beta", type=float, default=45.0, help="inclined: the normal's angle to the load, degrees")
    p.add_argument("--units", default="Pa", choices=["Pa", "MPa"], help="sslv134: Pa and m, or MPa and m")
    p.add_argument("--out", help="write the rows as JSON")
    p.add_argument("--child", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.child:
        print(json.dumps(run_case(args.child, args.order, args.front_h, args.beta, args.units)))
        return 0
    rows = [_child(c, args.order, args.front_h, args.beta, args.units) for c in args.case]
    report(rows)
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
