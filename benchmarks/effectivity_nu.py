"""The error estimate's effectivity as nu -> 1/2, every mixed element.

    python benchmarks/effectivity_nu.py [--quick]

Effectivity = eta / ||sigma_ref - sigma_h||_A (the stress error in the compliance norm,
at the quadrature points of the reference mesh), on griffith and inclined-compression in
plane strain at nu = 0.3, 0.45, 0.49, 0.499, 0.4999:
  * coarse: the scene with maxh 4, crack_h 0.4, tip_h 0.04 (the test's meshes,
    tests/test_readable.py);
  * reference: the same element on maxh 1, crack_h 0.05, tip_h 0.005.
Two estimates from the same solve: "robust" is `sol.error_estimate` (the volumetric
strain residual weighted by min(lambda + mu, 2.5 mu), ngcrack/planar/estimate.py); "plain" is
the Prager-Synge estimate with the full weight lambda + mu (the same reconstructed w),
rebuilt from the estimate's terms. --quick: nu = 0.3 and 0.4999 only. Accuracy only: no timing is claimed.
"""

from __future__ import annotations

import argparse
import math
import warnings

import ngcrack as nc
from ngcrack.planar.estimate import VOLUMETRIC_WEIGHT, energy_error_against
from ngcrack.planar.materials import lame_parameters

SCENES = ("griffith", "inclined-compression")
ELEMENTS = ("bdm", "peers", "tdnns")
NUS = (0.3, 0.45, 0.49, 0.499, 0.4999)
COARSE = {"maxh": 4.0, "crack_h": 0.4, "tip_h": 0.04}
FINE = {"maxh": 1.0, "crack_h": 0.05, "tip_h": 0.005}


def effectivities(name: str, element: str, nu: float) -> tuple[float, float]:
    """(robust, plain) effectivity of one scene, element and nu."""
    scene = nc.scenes.load(name).with_(nu=nu)
    sol = nc.solve(scene, element=element, **COARSE)
    err = energy_error_against(sol, nc.solve(scene, element=element, **FINE))
    est = sol.error_estimate
    lam, mu = lame_parameters(scene.material.E, nu, scene.material.plane)
    kappa = min(lam + mu, VOLUMETRIC_WEIGHT * mu)
    t = est.terms
    plain2 = t["deviatoric"] + t["volumetric"] * (lam + mu) / kappa + t["contact"] + t["oscillation"]
    return est.energy / err, math.sqrt(plain2) / err


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="nu = 0.3 and 0.4999 only")
    args = parser.parse_args()
    nus = (NUS[0], NUS[-1]) if args.quick else NUS
    warnings.simplefilter("ignore")  # coarse meshes on purpose
    head = " | ".join(f"nu {nu}" for nu in nus)
    print(f"| scene | element | estimate | {head} |")
    print("|---|---|---|" + "---|" * len(nus))
    for name in SCENES:
        for element in ELEMENTS:
            rows = [effectivities(name, element, nu) for nu in nus]
            for k, label in enumerate(("robust", "plain")):
                print(f"| {name} | {element} | {label} | " + " | ".join(f"{r[k]:.2f}" for r in rows) + " |", flush=True)


if __name__ == "__main__":
    main()
