"""The fluid pressure at which a crack propagates: the root of K(p) - K_Ic over the solves of a loop.

K (the most loaded tip's K_eq in 2D, the front's mean K_I in 3D) is affine in the fluid
pressure p while the contact state does not change, and monotone where contact makes it
piecewise affine. Each evaluation is a solve, so the search spends as few as it can: the
secant through the last two states (exact where K is affine), kept inside the bracket of the
states on either side of K_Ic, a regula falsi on that bracket where the secant leaves it, and
its half every few solves as a safeguard. The planar loop (`loop.propagation`) and the radial
one (`radial.propagation_radial`) share it.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from ...core.pipeline import SolveError

#: every this many solves the bracket's half is taken instead (the safeguard of the regula falsi)
BISECT_EVERY = 4
#: the first trial pressure grows by this factor until it drives the tips (a compression may hold them shut)
WIDEN_FACTOR = 4.0


def pressure_at_propagation(run: Callable, p_ref: float, K_Ic: float, rtol: float, max_solves: int, what: str):
    """(solution, pressure, solves) at which `run(p)` -> (p, K(p) - K_Ic, solution) is zero to rtol K_Ic.

    `p_ref`: a first trial pressure (Sneddon's at propagation); `what`: the driven part's name in the
    errors ("the tips of crack 0", "the front of crack 0"). SolveError where no pressure drives it, where
    it propagates without fluid pressure, or where max_solves do not reach the tolerance (the closest
    state within 1000 times it is taken)."""
    tried = []

    def evaluate(p):
        tried.append(run(p))
        return tried[-1]

    _, g0, _ = evaluate(0.0)
    if g0 >= 0:
        raise SolveError(f"{what}: at propagation without fluid pressure (K - K_Ic = {g0:.4g} >= 0)")
    p = p_ref
    for _ in range(max_solves):
        _, g1, _ = evaluate(p)
        if g1 > g0:
            break
        p *= WIDEN_FACTOR
    else:
        raise SolveError(f"the pressure does not drive {what} (up to p = {p:.4g})")
    while len(tried) < max_solves:
        last = tried[-1]
        if abs(last[1]) <= rtol * K_Ic:
            return last[2], last[0], len(tried)
        lo = max((t for t in tried if t[1] < 0), key=lambda t: t[0])
        his = [t for t in tried if t[1] > 0]
        hi = min(his, key=lambda t: t[0]) if his else None
        a, b = sorted(tried[-2:], key=lambda t: t[0])
        p = b[0] - b[1] * (b[0] - a[0]) / (b[1] - a[1]) if b[1] != a[1] else math.nan  # the secant of the last two
        if hi is None:
            p = p if math.isfinite(p) and p > lo[0] else 2.0 * max(t[0] for t in tried)
        elif not (math.isfinite(p) and lo[0] < p < hi[0]) or len(tried) % BISECT_EVERY == 0:
            p = (lo[0] * hi[1] - hi[0] * lo[1]) / (hi[1] - lo[1])  # regula falsi on the bracket
            if not lo[0] < p < hi[0] or len(tried) % BISECT_EVERY == 0:
                p = 0.5 * (lo[0] + hi[0])
        evaluate(p)
    best = min(tried, key=lambda t: abs(t[1]))
    if abs(best[1]) <= 1e3 * rtol * K_Ic:
        return best[2], best[0], len(tried)
    raise SolveError(f"the pressure at propagation was not found in {max_solves} solves (K - K_Ic = {best[1]:.3g})")
