"""Hydraulic fracture: GEOS's KGD validation cases with GEOS's inputs, beside GEOS's published results.

GEOS's documentation (advanced examples, validation studies, hydraulic fracture) runs two KGD cases
on a 200 m x 50 m half-domain (the fracture's symmetry plane), clamped on its faces, a 1 m initial
half-length, 0.5 m elements along the fracture plane, E = 30 GPa, nu = 0.25, Q0 = 1e-4 m^2/s
(SourceFlux scale 5e-2 kg/s on the half-wing, density 1000), to t = 100 s:

    viscosity-dominated   mu = 1e-3 Pa s, K_Ic = 1e4 Pa m^(1/2)   (K_m = 0.0127)
    toughness-dominated   mu = 1e-6 Pa s, K_Ic = 1e6 Pa m^(1/2)   (K_m = 7.14)

and publishes the inlet pressure, inlet aperture and half-length every 2 s (their
`model-results.txt`, GEOS-DEV/GEOS src/docs/sphinx/advancedExamples/validationStudies/
hydraulicFracture/kgd{Viscosity,Toughness}Dominated/; the half-length moves in steps of their 0.5 m
elements). GEOS_RESULTS below holds their rows at 10, 20, 50 and 100 s.

ngcrack runs the same inputs on its `kgd` scene (a 2 m crack in a clamped 400 m square, tips meshed
at 0.05 m, the crack at 0.1 m; tdnns) with the viscous fluid, da per tip and step as given, to 100 s;
printed at those times (interpolated between steps): l, w0, p of ngcrack and GEOS, and the vertex
(M: Adachi-Detournay; K: the uniform-pressure closed form) and the transition reference (`transition.py`).

GEOS's third KGD case validates against an experiment (Rubin 1983, as GEOS's documentation gives it):
a PMMA block 2 x 152.5 mm long, 96 mm across the fracture, traction-free, plane strain (55 mm high,
rollers top and bottom), E = 3.28 GPa, nu = 0.367 (bulk 4.110 GPa, shear 1.200 GPa), K_Ic =
1.2 MPa m^(1/2), mu = 97.7 Pa s, Q0 = 73.2e-9 m^3/s over the 55 mm (1.331e-6 m^2/s), an initial
half-length of 3 mm, to 100 s; compared at the wellbore (the injection point), the pressure gages at
15 mm and 41 mm, the aperture 28.5 mm from the well, and the half-length. ngcrack models the block in
2D with the same faces free, a pin and a roller holding its rigid motions (statically determinate:
no reaction under the fluid's self-equilibrated load), tips meshed at 0.3 mm, the crack at 0.6 mm,
da = 3 mm. GEOS_EXPERIMENT holds GEOS's model_results.txt and the experiment's points at a few times
(GEOS's time axis: the experiment's clock less its 3.7 s start).

    OMP_NUM_THREADS=1 python benchmarks/hydrofrac_geos.py [--case viscosity toughness experiment] [--da 0.25]

No number here is a test threshold: the machine is shared and timings are noisy.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

Q0 = 1e-4
#: case -> (mu, K_Ic)
CASES = {"viscosity": (1e-3, 1e4), "toughness": (1e-6, 1e6), "experiment": (97.7, 1.2e6)}
#: GEOS's published results (model-results.txt): time [s] -> (inlet pressure [Pa], inlet aperture [m], half-length [m])
GEOS_RESULTS = {
    "viscosity": {10: (6.512e5, 2.220e-4, 3.5), 20: (4.790e5, 2.698e-4, 5.5), 50: (3.425e5, 3.564e-4, 10.5),
                  100: (2.782e5, 4.475e-4, 16.0)},
    "toughness": {10: (2.411e5, 1.409e-4, 5.0), 20: (2.051e5, 1.830e-4, 7.5), 50: (1.550e5, 2.478e-4, 13.5),
                  100: (1.307e5, 3.137e-4, 21.0)},
}

#: the experiment-based case: GEOS's results (model_results.txt), GEOS time [s] -> (wellbore pressure, gage 58
#: (15 mm), gage 57 (41 mm) [Pa], aperture at 28.5 mm [m], half-length [m] = fractured area / 55 mm)
GEOS_EXPERIMENT = {10: (3.981e6, 3.188e6, 6.454e5, 1.493e-4, 0.002307 / 0.055),
                   20: (2.272e6, 1.987e6, 1.130e6, 2.666e-4, 0.003418 / 0.055),
                   40: (1.299e6, 1.207e6, 9.894e5, 4.299e-4, 0.004718 / 0.055),
                   60: (8.396e5, 7.921e5, 6.877e5, 5.530e-4, 0.005766 / 0.055),
                   100: (3.547e5, 3.333e5, 2.905e5, 7.443e-4, 0.007339 / 0.055)}
#: Rubin's (1983) measurements as GEOS's documentation gives them, on GEOS's time axis (experiment - 3.7 s):
#: time -> (wellbore pressure, gage 58, gage 57 [Pa], aperture at 28.5 mm [m], half-length [m])
RUBIN = {t - 3.7: (pb * 1e6, p58 * 1e6, p57 * 1e6, w * 1e-6, length * 1e-3) for t, pb, p58, p57, w, length in (
    (11.9, 5.43, 4.145, 0.362, 69, 30), (19.25, 3.23, 2.827, 0.412, 185, 50), (30.35, 2.03, 1.894, 1.396, 294, 70),
    (46.15, 1.39, 1.345, 1.153, 420, 90), (61.50, 1.07, 1.050, 0.942, 514, 105), (68.90, 0.97, 0.949, 0.861, 552, 112))}
#: the block (half-length along the fracture, half-width across it) [m], the initial half-length, the gages [m]
BLOCK, L0, GAGES = (0.1525, 0.048), 0.003, (0.015, 0.041, 0.0285)
EXPERIMENT_Q0 = 2 * 3.66e-5 / 1000 / 0.055


def rubin_block():
    """GEOS's experiment-based KGD in 2D: the PMMA block, free faces, a pin and a roller."""
    import ngcrack as nc

    a, b = BLOCK
    K, G = 4.110276e9, 1.19971e9
    return nc.Scene(name="kgd-rubin", polygon=[[-a, -b], [a, -b], [a, b], [-a, b]], labels=["bottom", "right", "top", "left"],
                    cracks=[{"points": [[-L0, 0.0], [L0, 0.0]]}],
                    material={"E": 9 * K * G / (3 * K + G), "nu": (3 * K - 2 * G) / (2 * (3 * K + G)), "plane": "strain"},
                    boundary={}, points=[nc.PointCondition(at=(0.0, b), type="pin", width=0.004),
                                         nc.PointCondition(at=(a, 0.0), type="roller", width=0.004)])


def experiment(args) -> None:
    """The experiment-based case against GEOS's results and Rubin's measurements."""
    import ngcrack as nc

    mu, K_Ic = CASES["experiment"]
    cpu0 = time.process_time()
    run = nc.hydrofrac(rubin_block(), rate=EXPERIMENT_Q0, K_Ic=K_Ic, da=args.da_experiment, time=args.end, viscosity=mu,
                       maxh=0.01, tip_h=0.0003, crack_h=0.0006)
    cpu = time.process_time() - cpu0
    t = np.array([s["time"] for s in run.steps])
    print(f"\nexperiment-based (Rubin 1983): K_m = {run.K_m:.3g}, {len(run.steps) - 1} steps ({run.stopped}); CPU {cpu:.0f} s")

    def at(step, x, key):  # the profile's value x from the injection point (NaN beyond the tip)
        s = np.asarray(step["profile"]["s"])
        s0 = 0.5 * (s[0] + s[-1])
        return float(np.interp(s0 + x, s, step["profile"][key], left=np.nan, right=np.nan))

    print("| t [s] | well p: ngcrack, GEOS, exp. [MPa] | gage 15 mm | gage 41 mm | w at 28.5 mm [um] | l [mm] |")
    print("|---|---|---|---|---|---|")
    for when in sorted(set(GEOS_EXPERIMENT) | set(RUBIN)):
        if not t[0] <= when <= t[-1]:
            continue
        i = min(max(int(np.searchsorted(t, when)), 1), len(t) - 1)  # the steps i - 1 and i bracket `when`
        f = (when - t[i - 1]) / (t[i] - t[i - 1])

        def values(step):
            return np.array([step["pressure"], at(step, GAGES[0], "pressure"), at(step, GAGES[1], "pressure"),
                             at(step, GAGES[2], "opening"), step["half_length"]])

        ours = (1 - f) * values(run.steps[i - 1]) + f * values(run.steps[i])  # linear in time between the steps
        geos, rubin = GEOS_EXPERIMENT.get(when), RUBIN.get(when)
        cols = []
        for k, scale in enumerate((1e-6, 1e-6, 1e-6, 1e6, 1e3)):
            vals = [f"{ours[k] * scale:.3g}", "-" if geos is None else f"{geos[k] * scale:.3g}",
                    "-" if rubin is None else f"{rubin[k] * scale:.3g}"]
            cols.append(", ".join(vals))
        print(f"| {when:.4g} | " + " | ".join(cols) + " |", flush=True)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", nargs="+", choices=sorted(CASES), default=["viscosity", "toughness"])
    parser.add_argument("--da", type=float, default=0.25)
    parser.add_argument("--da-experiment", type=float, default=0.003)
    parser.add_argument("--end", type=float, default=100.0, help="end time [s]")
    args = parser.parse_args(argv)
    if "experiment" in args.case:
        experiment(args)

    import ngcrack as nc
    from ngcrack.studies.hydrofrac.flow import k_vertex, m_vertex
    from ngcrack.studies.hydrofrac.transition import kgd_transition

    scene = nc.scenes.load("kgd")
    e_prime = scene.material.E / (1 - scene.material.nu ** 2)
    for case in [c for c in args.case if c != "experiment"]:
        mu, K_Ic = CASES[case]
        cpu0 = time.process_time()
        run = nc.hydrofrac(scene, rate=Q0, K_Ic=K_Ic, da=args.da, time=args.end, viscosity=mu)
        cpu = time.process_time() - cpu0
        t = np.array([s["time"] for s in run.steps])
        print(f"\n{case}-dominated: K_m = {run.K_m:.3g}, {len(run.steps) - 1} steps of da = {args.da} ({run.stopped}); "
              f"CPU {cpu:.0f} s, {cpu / len(run.steps):.2f} s per step")
        print("| t [s] | l: ngcrack, GEOS, vertex, transition [m] | w0: ngcrack, GEOS, vertex, transition [um] | "
              "p: ngcrack, GEOS, K-vertex (toughness case) [MPa] |")
        print("|---|---|---|---|")
        for when, (pg, wg, lg) in GEOS_RESULTS[case].items():
            if not t[0] <= when <= t[-1]:
                continue
            l, w, p = (float(np.interp(when, t, [s[k] for s in run.steps]))
                       for k in ("half_length", "opening_at_injection", "pressure"))
            lm, wm = m_vertex(when, e_prime, mu, Q0)
            lk, pk, wk = k_vertex(when, e_prime, K_Ic, Q0)
            lv, wv = (lm, wm) if case == "viscosity" else (lk, wk)
            lt, wt = kgd_transition(when, e_prime, K_Ic, mu, Q0)
            print(f"| {when} | {l:.2f}, {lg:.1f}, {lv:.2f}, {lt:.2f} | {w * 1e6:.1f}, {wg * 1e6:.1f}, {wv * 1e6:.1f}, "
                  f"{wt * 1e6:.1f} | {p / 1e6:.4f}, {pg / 1e6:.4f}, {pk / 1e6 if case == 'toughness' else math.nan:.4f} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
