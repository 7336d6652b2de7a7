"""Surface cracks against published tables: our recorded K_I beside the tables and Newman and Raju's equation.

    python benchmarks/surface_references.py

No solve is run: ngcrack's values are the ones recorded in BENCHMARKS.md, section "Deep and slender
surface cracks" (`python benchmarks/newman_raju.py --deep` and `--slender` on the 2-core machine; the
plates of that section: a = 0.6, thickness t = a / (a/t), half-width b = 5c, one end clamped and the
other pulled, S = 1). The references are the published influence coefficients F0 of uniform stress at
the deepest point and at the surface (`ngcrack.studies.newman_raju.PUBLISHED_F0`: Shiratori's, and
ASME Section XI Appendix A's, both for wide plates), made K for that plate by `published_K` (Newman and
Raju's finite-width factor f_w), and Newman and Raju's equation (`surface_crack_K`, the same plate).
Prints Markdown tables with the differences in percent.
"""

from __future__ import annotations

import math

from ngcrack.studies.newman_raju import PUBLISHED_F0, published_F, published_K, surface_crack_F, surface_crack_K

#: the crack depth of the recorded runs (S = 1 and b = 5c throughout)
DEPTH = 0.6
#: the plate's half-width in crack half-lengths
WIDTH_IN_C = 5.0

#: the deepest point's K_I recorded in BENCHMARKS.md, section "Deep and slender surface cracks":
#: (a/c, a/t, element and mesh, K by the domain integral, K by the opening behind the front)
RECORDED_DEEPEST = [
    (0.6, 0.8, "TDNNS 1, a/12, maxh = t", 1.3272, 1.3326),
    (0.6, 0.8, "TDNNS 1, a/12", 1.3039, 1.3443),
    (0.6, 0.8, "TDNNS 2, a/9", 1.3141, 1.3657),
    (0.6, 0.8, "h1p2, a/9", 1.3071, None),
    (1.0, 0.8, "TDNNS 1, a/12, maxh = t", 0.9502, 0.9600),
    (1.0, 0.8, "TDNNS 1, a/12", 0.9521, 0.9611),
    (1.0, 0.8, "TDNNS 2, a/9", 0.9523, 0.9824),
    (0.4, 0.6, "TDNNS 2, a/6", 1.6126, 1.6446),
    (0.4, 0.6, "TDNNS 1, a/9", 1.5889, 1.5741),
    (0.6, 0.4, "TDNNS 2, a/6", 1.2452, 1.2561),
]

#: the section's summary of the converged deepest point: (a/c, a/t, K_I, its spread) - 1.33 +- 0.03 at
#: a/c = 0.6, a/t = 0.8; 0.944-0.982 over both extractions and orders on a/c = 1, a/t = 0.8; the two order-2
#: extractions on a/c = 0.4, a/t = 0.6 (1.6126, 1.6446) and a/c = 0.6, a/t = 0.4 (1.2452, 1.2561)
CONVERGED_DEEPEST = [
    (0.6, 0.8, 1.33, 0.03),
    (1.0, 0.8, 0.963, 0.019),
    (0.4, 0.6, 1.629, 0.016),
    (0.6, 0.4, 1.251, 0.006),
]

#: the slender crack (a/c = 0.2, a/t = 0.5) near the surface, TDNNS 1 at front_h = a/8, recorded in the same
#: section: (phi in degrees, K_I ours)
RECORDED_SLENDER = [(16.8, 1.1425), (23.9, 1.3040), (29.7, 1.4259), (34.7, 1.4813), (39.2, 1.5586), (43.3, 1.6216)]
SLENDER = (0.2, 0.5)


def plate(a_over_c: float, a_over_t: float) -> dict:
    """The recorded runs' plate for a crack of depth DEPTH: a, c, t, b and S = 1."""
    c = DEPTH / a_over_c
    return {"S": 1.0, "a": DEPTH, "c": c, "t": DEPTH / a_over_t, "b": WIDTH_IN_C * c}


def equation_K(a_over_c: float, a_over_t: float, phi: float) -> float:
    """Newman and Raju's equation on the recorded runs' plate at the parametric angle phi."""
    return float(surface_crack_K(phi=phi, **plate(a_over_c, a_over_t)))


def reference_K(source: str, point: str, a_over_c: float, a_over_t: float) -> float:
    """A published table's K_I on the recorded runs' plate (`published_K`)."""
    return published_K(source, point, **plate(a_over_c, a_over_t))


def percent(value: float, reference: float) -> str:
    return f"{100.0 * (value / reference - 1.0):+.1f}%"


def deepest_table() -> list[str]:
    lines = ["| a/c | a/t | Shiratori | ASME XI App. A | Newman-Raju eq. | ours (element, mesh) | K domain integral | K opening |",
             "|---|---|---|---|---|---|---|---|"]
    for ac, at, run, k_di, k_op in RECORDED_DEEPEST:
        ref = reference_K("shiratori", "deepest", ac, at)
        asme = reference_K("asme", "deepest", ac, at)
        eq = equation_K(ac, at, 0.5 * math.pi)
        opening = f"{k_op:.4f} ({percent(k_op, ref)})" if k_op is not None else "-"
        lines.append(f"| {ac} | {at} | {ref:.4f} | {asme:.4f} ({percent(asme, ref)}) | {eq:.4f} ({percent(eq, ref)}) | {run} | "
                     f"{k_di:.4f} ({percent(k_di, ref)}) | {opening} |")
    return lines


def converged_table() -> list[str]:
    lines = ["| a/c | a/t | ours (converged) | Shiratori | ASME | Newman-Raju eq. | ours vs Shiratori | eq. vs Shiratori |",
             "|---|---|---|---|---|---|---|---|"]
    for ac, at, k, spread in CONVERGED_DEEPEST:
        ref = reference_K("shiratori", "deepest", ac, at)
        asme = reference_K("asme", "deepest", ac, at)
        eq = equation_K(ac, at, 0.5 * math.pi)
        lines.append(f"| {ac} | {at} | {k:.3f} +- {spread:.3f} | {ref:.4f} | {asme:.4f} | {eq:.4f} | {percent(k, ref)} | {percent(eq, ref)} |")
    return lines


def equation_vs_tables() -> list[str]:
    """Newman and Raju's F (wide plate) against each table at the common grid points, in percent."""
    lines = ["| point | a/t | " + " | ".join(f"a/c = {ac}" for ac in (0.2, 0.4, 0.6, 1.0)) + " |", "|---|---|---|---|---|---|"]
    for point, phi in (("deepest", 0.5 * math.pi), ("surface", 0.0)):
        for at in (0.2, 0.4, 0.6, 0.8):
            cells = []
            for ac in (0.2, 0.4, 0.6, 1.0):
                f_eq = float(surface_crack_F(ac, at, 0.0, phi))
                cells.append(" / ".join(percent(f_eq, published_F(src, point, ac, at)) for src in PUBLISHED_F0))
            lines.append(f"| {point} | {at} | " + " | ".join(cells) + " |")
    return lines


def slender_table() -> list[str]:
    ac, at = SLENDER
    lines = ["| phi (deg) | K ours | Newman-Raju eq. | ours vs eq. | published |", "|---|---|---|---|---|"]
    for point, phi in (("surface", 0.0), ("deepest", 90.0)):
        eq = equation_K(ac, at, math.radians(phi))
        refs = ", ".join(f"{src} {reference_K(src, point, ac, at):.4f} (eq. {percent(eq, reference_K(src, point, ac, at))})"
                         for src in PUBLISHED_F0)
        lines.append(f"| {phi:.0f} ({point}) | - | {eq:.4f} | - | {refs} |")
    for phi, k in RECORDED_SLENDER:
        eq = equation_K(ac, at, math.radians(phi))
        lines.append(f"| {phi} | {k:.4f} | {eq:.4f} | {percent(k, eq)} | none found |")
    return lines


def main() -> None:
    print("Deepest point, every recorded run (percent against Shiratori's K on the same plate):\n")
    print("\n".join(deepest_table()))
    print("\nDeepest point, the converged values of the section:\n")
    print("\n".join(converged_table()))
    print("\nNewman-Raju's F against the tables (wide plate), eq./Shiratori - 1 and eq./ASME - 1:\n")
    print("\n".join(equation_vs_tables()))
    print(f"\nSlender crack a/c = {SLENDER[0]}, a/t = {SLENDER[1]}, TDNNS 1 at front_h = a/8:\n")
    print("\n".join(slender_table()))


if __name__ == "__main__":
    main()
