"""Volume control: the cracks' volume prescribed, their (uniform) face pressure the unknown.

    sol = nc.solve_volume(scene, volume=V)           # V: the volume between the faces (2D: per unit thickness)
    sol.options["volume_control"]                    # {"volume", "pressure", "solves", "method"}

The volume of a crack is V = int [u].nu over it (`crack_volume`; the body computes it: an
area per unit thickness in 2D, a volume in 3D). One uniform pressure p acts in every crack named (all of them by
default: one connected fluid). Without contact the response is linear, V(p) = V(0) +
p (V(p_ref) - V(0)) / p_ref, so two solves give p and a third the answer
("superposition"); where faces touch, contact makes V(p) piecewise linear (monotone: more
pressure never closes a face), and a bracketing regula falsi (Illinois) finds p
("search"). Every solve runs through one `ngcrack.core.pipeline.Pipeline`: the mesh is kept
and, in 2D, the assembled forms, the factorization and the Schur complement too, only the
load vector changing (a uniform pressure is an NGSolve Parameter of the assembled load); a 3D
body assembles its crack pressure with the forms, so each of its solves assembles again.
"""

from __future__ import annotations

import dataclasses
import math

from ..core.errors import InputError
from ..core.options import SolveOptions
from ..core.pipeline import Pipeline, SolveError
from ..core.scene import Scene
from ..core.solution import Solution
from ..core.solve import as_scene

#: relative volume tolerance of the pressure search (the superposition meets it to round-off)
VOLUME_RTOL = 1e-10
#: the most solves of the pressure search
MAX_SOLVES = 60
#: the first trial pressure is multiplied by WIDEN_FACTOR until the volume grows, at most
#: MAX_WIDEN times (a compression across the crack holds it closed below its own size)
WIDEN_FACTOR = 4.0
MAX_WIDEN = 30
#: the largest strain scale a prescribed volume may have, Sneddon's p / E' of the cracks in an
#: infinite body (`reference_pressure`): beyond it small-strain elasticity does not apply
MAX_STRAIN = 0.1


def crack_volume(sol, cracks=None) -> float:
    """The volume between the faces of the given cracks (all by default), as the body
    computes it: in 2D an area per unit thickness, the sum over crack edges of the
    mid-point normal jump times the edge length (exact for the P0 and P1 jumps of the
    default orders); in 3D the integral of the normal jump over the crack's faces."""
    if not isinstance(sol, Solution):
        raise InputError(f"sol = {type(sol).__name__}: must be a solution (what nc.solve returns), not "
                         f"{'a scene: solve it first' if isinstance(sol, Scene) else 'this'}")
    return sol.scene.body.crack_volume(sol, check_cracks(sol.scene, cracks))


def with_pressure(scene, cracks, p: float):
    """The scene with the uniform pressure p on the given cracks (all when None)."""
    idx = set(range(len(scene.cracks)) if cracks is None else cracks)
    if idx == set(range(len(scene.cracks))):
        return scene.with_(pressure=float(p))
    return scene.with_(cracks=tuple(dataclasses.replace(c, pressure=float(p)) if k in idx else c
                                    for k, c in enumerate(scene.cracks)))


def check_cracks(scene, cracks) -> list[int]:
    """The crack indices of `cracks` (None: every crack), refused by name if invalid."""
    n = len(scene.cracks)
    if n == 0:
        raise InputError(f"scene {scene.name!r}: has no crack; volume control needs one")
    if cracks is None:
        return list(range(n))
    if isinstance(cracks, int) and not isinstance(cracks, bool):
        cracks = [cracks]
    try:
        idx = [int(k) for k in cracks]
    except (TypeError, ValueError):
        raise InputError(f"cracks = {cracks!r}: must be None (every crack) or crack indices 0..{n - 1}") from None
    if not idx or any(k < 0 or k >= n for k in idx) or len(set(idx)) != len(idx):
        raise InputError(f"cracks = {cracks!r}: must be distinct crack indices 0..{n - 1}")
    return idx


def reference_pressure(scene, cracks, volume: float) -> float:
    """Sneddon's pressure for `volume` in the cracks alone in an infinite body (the body's
    `volume_compliance`: one straight crack of their total length in 2D, V = 2 pi p a^2 / E';
    pennies of their areas in 3D, V = 16 p a^3 / (3 E')): a scale for the first trial pressure."""
    return abs(volume) / scene.body.volume_compliance(scene, cracks)


def solve_volume(scene, volume: float, *, cracks=None, options: SolveOptions | None = None,
                 pipeline: Pipeline | None = None, rtol: float = VOLUME_RTOL, **changes):
    """Solve `scene` with the uniform face pressure that gives the cracks the volume `volume`.

    `cracks`: the indices of the cracks that share the pressure and whose volumes add up
    (None: all); the scene's own pressures on them are replaced. The scene's other loads
    stay (an in-situ stress). `options`/`changes` as for `nc.solve`; `pipeline`: one to
    reuse (a fresh one by default). Returns the Solution at that pressure, with
    ``sol.options["volume_control"]`` = {"volume", "pressure", "solves", "method"}.
    Raises SolveError where no pressure reaches the volume (a bonded crack, say).
    """
    scene = as_scene(scene)
    if isinstance(volume, bool) or not isinstance(volume, (int, float)) or not math.isfinite(volume):
        raise InputError(f"volume = {volume!r}: must be a finite number (the volume between the faces; 2D: per unit thickness)")
    if not (isinstance(rtol, float) and 0 < rtol < 1):
        raise InputError(f"rtol = {rtol!r}: must be a number in (0, 1)")
    idx = check_cracks(scene, cracks)
    opts = SolveOptions.of(options, **changes)
    opts.check_for(scene)
    if opts.crack_model == "bonded":
        raise InputError("crack_model = 'bonded': a bonded crack holds no volume; allowed values here are contact, free")
    if volume < 0 and opts.crack_model == "contact":
        raise InputError(f"volume = {volume!r}: must be >= 0 with contact (the faces cannot overlap; "
                         "crack_model='free' lets them)")
    strain = reference_pressure(scene, idx, volume) / scene.body.effective_modulus(scene)
    if strain > MAX_STRAIN:
        raise InputError(f"volume = {volume!r}: the strain scale p / E' of Sneddon's pressure for it would be {strain:.3g}; "
                         f"at most {MAX_STRAIN:g} keeps the strains small")
    pipe = pipeline if pipeline is not None else Pipeline()
    solves = 0

    def run(p):
        nonlocal solves
        solves += 1
        sol = scene.body.solve(pipe, with_pressure(scene, idx, p), opts)
        return sol, crack_volume(sol, idx)

    p_ref = reference_pressure(scene, idx, volume) or 1.0 / scene.body.volume_compliance(scene, idx)
    sol0, v0 = run(0.0)
    for _ in range(MAX_WIDEN):  # a pressure that opens the crack (an in-situ compression may hold it closed)
        sol1, v1 = run(p_ref)
        if v1 > v0:
            break
        p_ref *= WIDEN_FACTOR
    else:
        raise SolveError(f"scene {scene.name!r}: the crack volume does not grow with the pressure "
                         f"(V = {v0:.4g} at p = 0, {v1:.4g} at p = {p_ref:.4g}); no pressure gives volume {volume:.4g}")
    p = p_ref * (volume - v0) / (v1 - v0)
    sol, v = run(p)
    method = "superposition"
    tol = rtol * (abs(volume) or (v1 - v0))
    if abs(v - volume) > tol:
        method = "search"
        sol, p = _search(run, volume, tol, (0.0, v0, sol0), (p_ref, v1, sol1), (p, v, sol))
    sol.options["volume_control"] = {"volume": float(volume), "pressure": float(p), "solves": solves, "method": method}
    return sol


def _search(run, volume, tol, *tried):
    """Illinois regula falsi on the monotone V(p) from the tried (p, V, sol): it starts from the superposition's
    guess, so it needs fewer solves than scipy's brentq from the same bracket (4-8 against 10-11: BENCHMARKS.md,
    the one path's section)."""
    lo = max((t for t in tried if t[1] <= volume), key=lambda t: t[0], default=None)
    hi = min((t for t in tried if t[1] >= volume), key=lambda t: t[0], default=None)
    n = 0
    while lo is None or hi is None:  # widen the bracket
        n += 1
        if n > MAX_SOLVES:
            raise SolveError(f"volume {volume:.4g}: no bracketing pressure found in {MAX_SOLVES} solves")
        ref = max(abs(t[0]) for t in tried) or 1.0
        p = (hi[0] - 2 * ref) if lo is None else (lo[0] + 2 * ref)
        sol, v = run(p)
        t = (p, v, sol)
        tried = tried + (t,)
        if v <= volume:
            lo = t if lo is None or p > lo[0] else lo
        if v >= volume:
            hi = t if hi is None or p < hi[0] else hi
    side = 0
    fl, fh = lo[1] - volume, hi[1] - volume
    best = min((lo, hi), key=lambda t: abs(t[1] - volume))
    for _ in range(MAX_SOLVES):
        if abs(best[1] - volume) <= tol:
            return best[2], best[0]
        p = hi[0] if fh == fl else (lo[0] * fh - hi[0] * fl) / (fh - fl)
        sol, v = run(p)
        f = v - volume
        best = min((best, (p, v, sol)), key=lambda t: abs(t[1] - volume))
        if f <= 0:
            lo, fl = (p, v, sol), f
            if side == -1:
                fh *= 0.5
            side = -1
        else:
            hi, fh = (p, v, sol), f
            if side == 1:
                fl *= 0.5
            side = 1
    if abs(best[1] - volume) <= 1e3 * tol:
        return best[2], best[0]
    raise SolveError(f"volume {volume:.4g}: the pressure search did not converge in {MAX_SOLVES} solves "
                     f"(closest volume {best[1]:.6g})")
