"""The finite-body references of ngcrack.studies.references, reproduced with their convergence tables.

    NGCRACK_THREADS=1 python benchmarks/references.py [--quick] [--nu NU]

For `griffith` and `inclined-compression`: tdnns at order 3 and 2 on a sequence of meshes
refined together (level k: maxh = 1 / 2^k, crack_h = 0.05 / 2^k, tip_h = 0.005 / 5^k),
K at every tip and the profile's amplitude (its L2 projection on the closed form's shape,
relative to it); the values extrapolated Richardson-style from the last three order-3
levels (where their differences shrink at least twofold per level; else the finest value, the last
change its uncertainty); bdm beside them for comparison. The profile correction (a Legendre series
of
profile / shape, even for griffith, whose crack centre is on the symmetry line) is fitted
to the finest level's samples. Prints the tables (Markdown) and the data block of
ngcrack/studies/references.py, at nu = 0.3 (the scenes' own) and 0.4999 (or --nu NU only). About 3
minutes per Poisson ratio on one thread; --quick stops a level earlier.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

import ngcrack as nc
from ngcrack.studies.references import closed_form_shape

LEVELS = [(1.0 / 2**k, 0.05 / 2**k, 0.005 / 5**k) for k in range(4)]
#: levels per scene and element (order 3 reaches the finest)
DEPTH = {"griffith": 4, "inclined-compression": 3}
#: Poisson ratios (the scenes' own, and near incompressibility)
NUS = (0.3, 0.4999)
#: degree of the Legendre series of profile / shape
DEGREE = 8


def solve_level(name: str, element: str, order, level: int, nu: float):
    maxh, crack_h, tip_h = LEVELS[level]
    t0 = time.process_time()
    sol = nc.solve(nc.scenes.load(name).with_(nu=nu), element=element, order=order, maxh=maxh, crack_h=crack_h, tip_h=tip_h)
    return sol, time.process_time() - t0


def samples(sol):
    """(t = d / a, jump, shape, edge length) of the first crack's mid-point samples."""
    center, direction, a, factor, profile = closed_form_shape(sol.scene)
    p = sol.profiles[0]
    d = (p.x - center[0]) * direction[0] + (p.y - center[1]) * direction[1]
    shape = factor * np.sqrt(np.clip(a**2 - d**2, 0, None))
    jump = p.normal_jump if profile == "normal" else p.tangential_jump
    return d / a, jump, shape, sol.crack_mesh.cracks[0].length


def amplitude(sol) -> float:
    _, j, e, L = samples(sol)
    return float(np.sum(L * j * e) / np.sum(L * e * e))


def fit(sol, even: bool):
    """Legendre coefficients c of jump / shape (least squares in the L2 norm of the jump) and the
    fit's relative residual."""
    t, j, e, L = samples(sol)
    ks = [k for k in range(DEGREE + 1) if not (even and k % 2)]
    V = np.polynomial.legendre.legvander(t, DEGREE)[:, ks]
    w = np.sqrt(L)
    c_sub, *_ = np.linalg.lstsq(w[:, None] * e[:, None] * V, w * j, rcond=None)
    c = np.zeros(DEGREE + 1)
    c[ks] = c_sub
    resid = math.sqrt(np.sum(L * (j - e * (V @ c_sub)) ** 2) / np.sum(L * j * j))
    return c, resid


def fit_distance(c1, c2, even: bool) -> float:
    """Relative L2 distance of two fitted profiles shape * P(c) over the crack."""
    t = np.linspace(-1, 1, 4001)
    e = np.sqrt(1 - t**2)
    f1, f2 = (e * np.polynomial.legendre.legval(t, c) for c in (c1, c2))
    return float(math.sqrt(np.trapezoid((f1 - f2) ** 2, t) / np.trapezoid(f2**2, t)))


def richardson(q) -> tuple[float, float]:
    """(estimate, observed ratio of successive differences) from the last three values: the
    Richardson extrapolation when the ratio is at least 2 (the asymptotic range), else the last value."""
    q0, q1, q2 = q[-3:]
    d1, d2 = q1 - q0, q2 - q1
    rho = d1 / d2 if d2 else math.inf
    if not (rho >= 2.0) or not math.isfinite(rho):
        return q2, rho
    return q2 + d2 / (rho - 1), rho


def uncertainty(q, est: float, rho: float) -> float:
    """|last - estimate|, or the last change where the sequence is not in its asymptotic range."""
    return abs(q[-1] - est) if rho >= 2.0 and math.isfinite(rho) else abs(q[-1] - q[-2])


def round_up(x: float) -> float:
    if x <= 0:
        return 1e-7
    e = math.floor(math.log10(x))
    return math.ceil(x / 10**e) * 10**e


def run(name: str, depth: int, nu: float) -> dict:
    even = name == "griffith"
    rows, series = [], {}
    for element, order in (("tdnns", 3), ("tdnns", 2), ("bdm", None)):
        levels = range({3: depth, 2: min(depth, 3)}.get(order, depth - 1) if element == "tdnns" else depth - 1)
        for k in levels:
            sol, cpu = solve_level(name, element, order, k, nu)
            tips = {t.label: (t.K_I, t.K_II) for t in sol.tips}
            rec = {"element": element, "order": order or 1, "level": k, "unknowns": sol.ndof["total"], "cpu": cpu,
                   "tips": tips, "amplitude": amplitude(sol), "sol": sol if (order == 3 and k >= depth - 2) else None}
            rows.append(rec)
            series.setdefault((element, order), []).append(rec)
            print(f"  {name} nu={nu:g} {element} order {order or 1} level {k}: {rec['unknowns']} unknowns, {cpu:.1f} s", file=sys.stderr)
    mode = "K_I" if name == "griffith" else "K_II"
    labels = list(rows[0]["tips"])
    out = {"rows": rows, "mode": mode}
    # extrapolations
    est = {}
    for key in (("tdnns", 3), ("tdnns", 2)):
        s = series[key]
        est[key] = {"amplitude": richardson([r["amplitude"] for r in s])}
        for lab in labels:
            for m, i in (("K_I", 0), ("K_II", 1)):
                est[key][(lab, m)] = richardson([r["tips"][lab][i] for r in s])
    fine = series[("tdnns", 3)]

    def values(recs, q):
        return [r["amplitude"] if q == "amplitude" else r["tips"][q[0]][0 if q[1] == "K_I" else 1] for r in recs]

    unc = {}
    for q in est[("tdnns", 3)]:
        v3, rho3 = est[("tdnns", 3)][q]
        v2, _ = est[("tdnns", 2)][q]
        unc[q] = max(uncertainty(values(fine, q), v3, rho3), abs(v3 - v2))
    out["estimate"], out["uncertainty"] = est[("tdnns", 3)], unc
    c_fine, resid = fit(fine[-1]["sol"], even)
    c_prev, _ = fit(fine[-2]["sol"], even)
    rho = est[("tdnns", 3)]["amplitude"][1]
    c_est = c_fine + (c_fine - c_prev) / (rho - 1) if rho >= 2.0 and math.isfinite(rho) else c_fine
    out["coefficients"], out["fit_residual"] = c_est, resid
    out["fit_change"] = fit_distance(c_prev, c_fine, even)
    out["fit_uncertainty"] = (fit_distance(c_est, c_fine, even) if c_est is not c_fine else out["fit_change"]) + resid
    out["labels"] = labels
    return out


def table(name: str, res: dict, nu: float) -> None:
    mode = res["mode"]
    i = 0 if mode == "K_I" else 1
    labels = res["labels"]
    cf = closed_form_shape(nc.scenes.load(name))
    ex = nc.scenes.load(name).exact
    if name == "griffith":
        K_cf = ex["p"] * math.sqrt(math.pi * ex["a"])
    else:
        K_cf = nc.scenes.inclined_closed_form(nc.scenes.load(name))["K_II"]
    print(f"\n### {name}, nu = {nu:g}: {mode} / closed form, amplitude of the {cf[4]} profile / closed form\n")
    head = " | ".join(f"{mode}[{lab}]" for lab in labels)
    print(f"| element | order | level | unknowns | CPU s | {head} | amplitude |")
    print("|---|---:|---:|---:|---:|" + "---:|" * len(labels) + "---:|")
    for r in res["rows"]:
        ks = " | ".join(f"{r['tips'][lab][i] / K_cf:.6f}" for lab in labels)
        print(f"| {r['element']} | {r['order']} | {r['level']} | {r['unknowns']} | {r['cpu']:.1f} | {ks} | {r['amplitude']:.6f} |")
    est, unc = res["estimate"], res["uncertainty"]
    ks = " | ".join(f"{est[(lab, mode)][0] / K_cf:.6f} +- {unc[(lab, mode)] / abs(K_cf):.0e} (ratio {est[(lab, mode)][1]:.1f})"
                    for lab in labels)
    a, rho = est["amplitude"]
    print(f"| extrapolated | 3 | | | | {ks} | {a:.6f} +- {unc['amplitude']:.0e} (ratio {rho:.1f}) |")
    print(f"\nprofile fit: residual {res['fit_residual']:.1e}, change from the previous level {res['fit_change']:.1e}, "
          f"uncertainty of the extrapolated fit {res['fit_uncertainty']:.1e}")


def data_block(name: str, res: dict, nu: float) -> None:
    est, unc = res["estimate"], res["uncertainty"]
    tips = {lab: (round(float(est[(lab, "K_I")][0]), 7), round(float(est[(lab, "K_II")][0]), 7)) for lab in res["labels"]}
    Ku = round_up(max(unc[(lab, m)] for lab in res["labels"] for m in ("K_I", "K_II")))
    if name == "inclined-compression":  # closed and frictionless: K_I = 0 exactly (contact); the samples' noise
        Ku_I = max(abs(est[(lab, "K_I")][0]) for lab in res["labels"])
        tips = {lab: (0.0, v[1]) for lab, v in tips.items()}
        Ku = round_up(max(unc[(lab, "K_II")] for lab in res["labels"]))
        print(f"# K_I: 0 by contact; the extrapolated values are at most {Ku_I:.1e}")
    pu = round_up(res["fit_uncertainty"])
    coeffs = tuple(round(float(c), 7) for c in res["coefficients"])
    rows = res["rows"]
    finest = max(r["unknowns"] for r in rows if r["order"] == 3)
    print(f'    ("{name}", {nu!r}): dict(\n        tips={tips!r},\n        K_uncertainty={Ku:.0e},\n        mode="{res["mode"]}",\n'
          f'        amplitude={est["amplitude"][0]:.7f},\n        amplitude_uncertainty={round_up(unc["amplitude"]):.0e},\n'
          f'        coefficients={coeffs!r},\n        profile_uncertainty={pu:.0e},\n        unknowns={finest},\n    ),')


def main() -> None:
    quick = "--quick" in sys.argv
    nus = [float(sys.argv[sys.argv.index("--nu") + 1])] if "--nu" in sys.argv else list(NUS)
    results = {}
    for nu in nus:
        for name, depth in DEPTH.items():
            results[(name, nu)] = run(name, depth - 1 if quick else depth, nu)
            table(name, results[(name, nu)], nu)
    print("\n# data block for ngcrack/studies/references.py")
    for (name, nu), res in results.items():
        data_block(name, res, nu)


if __name__ == "__main__":
    main()
