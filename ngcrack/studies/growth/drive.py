"""Which tips a load drives: K_eq against the noise of the computed K, measured on the load's own scale.

A lone crack that no load opens or shears (the three-point bend with the force reversed: the
faces pressed together, K_II = 0 by symmetry) has a computed K_eq that is the discretization's
noise, 1e-5 to 1e-2 of the load's scale depending on the element and the mesh. A load factor
K_Ic / K_eq from it is meaningless (the load scaled by 1e4 and more), and the kink of that
noise is random (+-88 degrees). Comparing a tip with the run's other tips cannot see this
when it is the only one, so each tip is compared with the load's scale at its crack:

    K_load = sigma_rms sqrt(pi L),   sigma_rms = sqrt(integral of sigma : sigma / area),

L the tip's crack length and sigma_rms the root mean square of the step's stress over the
body (mesh-independent: the tip's singular field is square integrable). A tip is driven
where its K_eq exceeds K_load times the larger of DRIVE_NOISE_FLOOR and DRIVE_NOISE_PER_ESTIMATE
times the solve's relative error estimate (computed only for a tip below
DRIVE_NOISE_PER_ESTIMATE K_load, where it decides).

Measured (K_eq / K_load at the noise; benchmarks in the comments of the constants): the
reversed three-point bend and the uniaxially compressed closed crack, elements tdnns, bdm,
peers, h1p1, h1p2 at three meshes each: at most 1.5e-2, and at most 5.0e-2 of the relative
error estimate; the driven tips of the built-in scenes (griffith, three-point-bend,
inclined-compression with friction 0.3, two-cracks, hole-crack): at least 0.17.
"""

from __future__ import annotations

import math

#: a tip's K_eq at or below this fraction of its load scale sigma_rms sqrt(pi L) is noise, however fine the
#: mesh (measured: 1.3e-4 at most with tdnns; the extraction of K alone leaves 2e-5 on an exact solution)
DRIVE_NOISE_FLOOR = 1e-3
#: ... or below this times the solve's relative error estimate (measured noise: at most 0.050 of the estimate,
#: h1p1 at maxh 1 on the reversed three-point bend; 0.021 with peers, 0.015 with bdm, 0.004 with tdnns and h1p2)
DRIVE_NOISE_PER_ESTIMATE = 0.2


def stress_rms(sol) -> float:
    """sqrt(integral of sigma : sigma over the body / its area): the step's stress scale (0 without stress)."""
    import ngsolve as ngs

    area = float(ngs.Integrate(ngs.CoefficientFunction(1.0), sol.mesh))
    if not area > 0:
        return 0.0
    square = float(ngs.Integrate(ngs.InnerProduct(sol.sigma, sol.sigma), sol.mesh))
    return math.sqrt(max(square, 0.0) / area)


def _estimate(sol) -> float | None:
    """The solve's relative error estimate (computed now if pending), None where it has none."""
    est = sol.error_estimate
    rel = None if est is None else float(est.relative)
    return rel if rel is not None and math.isfinite(rel) else None


def noise_reasons(sol, scene, values: list[dict]) -> dict:
    """tip label -> why the tip has no driving force, for the tips of `values` (tip_values) whose K_eq is
    at the noise level of the computed K (module docstring); the others are driven. The error estimate is
    computed only where a tip lies between the floor and DRIVE_NOISE_PER_ESTIMATE of its load scale."""
    out: dict = {}
    rms = stress_rms(sol) if values else 0.0
    estimate: list = []  # the estimate once computed (at most once per step)
    for v in values:
        K_load = rms * math.sqrt(math.pi * float(scene.cracks[v["crack"]].length))
        K_eq = float(v["K_eq"])
        rtol = DRIVE_NOISE_FLOOR
        if DRIVE_NOISE_FLOOR * K_load < K_eq <= DRIVE_NOISE_PER_ESTIMATE * K_load:
            if not estimate:
                estimate.append(_estimate(sol))
            if estimate[0] is not None:
                rtol = max(rtol, DRIVE_NOISE_PER_ESTIMATE * min(estimate[0], 1.0))
        if K_eq <= rtol * K_load:
            out[v["label"]] = (f"tip {v['label']}: no driving force: K_eq = {K_eq:.3g} is within the noise of the "
                               f"computed K ({rtol:.2g} of the load's scale sigma_rms sqrt(pi L) = {K_load:.4g}); "
                               f"the load neither opens nor shears the crack there")
    return out
