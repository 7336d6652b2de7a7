"""Fatigue crack growth: the cycles of each step from the Paris law, da/dN = C (Delta K)^m.

Under a constant-amplitude cycle between R times and once the scene's load, the static
problem scales with the load (contact and friction under one proportional load: see
loop.py), so K_max is the K_eq of a tip at the scene's load and Delta K = (1 - R) K_max
for 0 <= R < 1; for R < 0 the compressive part of the cycle closes the crack and Delta
K = K_max. The loop advances the leading tip (the largest Delta K) by da per step (the
direction from the criterion as in quasi-static growth), and every other tip whose Delta K
lies above the threshold Delta K_th (`paris=(C, m, dK_th)`, default 0) by its own share of
the same cycles, da_i = da (Delta K_i / Delta K_max)^m (`Cycles.increments`); a share below
MIN_INCREMENT of da is kept and added to the tip's next one instead of remeshing for it.
The cycles the step takes are

    Delta N = integral over the step of ds / (C Delta K(s)^m),

with ln K interpolated in ln L (L the tip's crack length, s the tip's advance) through the
last three steps' (L, K) (two at the first step: a power law K ~ L^p), by Gauss-Legendre
quadrature: exact for a power law, and within 0.07% of the handbook life of a
centre-cracked strip from a/b = 0.2 to 0.6 in steps of 0.05 (`step_cycles` against the
integral of the handbook K, tests/test_growth_paths.py). The run stops when K_max reaches
K_Ic (fracture on the next cycle).
"""

from __future__ import annotations

import math

import numpy as np

from ...core.errors import InputError
from ...core.fields import is_finite

#: Gauss-Legendre points of the step's integral
GAUSS_POINTS = 6
#: a tip whose share of a step's cycles advances it by less than this fraction of da does not grow
#: in that step: its share is kept and added to its next one
MIN_INCREMENT = 0.1


def check_paris(paris, R) -> tuple[float, float, float] | None:
    """(C, m, dK_th) from `paris` (None: no fatigue), refusing bad input by name; R (the cycle's load ratio) only
    with paris."""
    if paris is None:
        if isinstance(R, bool) or not isinstance(R, (int, float, np.integer, np.floating)) or R != 0:
            raise InputError(f"R = {R!r}: the load ratio of a fatigue cycle acts only with paris = (C, m); give paris "
                             f"too, or remove R")
        return None


    ok = not isinstance(paris, (str, bytes)) and hasattr(paris, "__len__") and len(paris) in (2, 3)
    ok = ok and all(is_finite(v) and v > 0 for v in paris[:2]) and (len(paris) == 2 or (is_finite(paris[2]) and paris[2] >= 0))
    if not ok:
        raise InputError(f"paris = {paris!r}: must be a pair (C, m) of finite numbers > 0 (da/dN = C Delta_K^m), "
                         f"or a triple (C, m, dK_th) with a threshold dK_th >= 0 below which a tip does not grow, or None")
    if not (is_finite(R) and R < 1):
        raise InputError(f"R = {R!r}: must be a finite number < 1 (the load ratio K_min / K_max of the cycle)")
    return float(paris[0]), float(paris[1]), float(paris[2]) if len(paris) == 3 else 0.0


def delta_K(K_max: float, R: float) -> float:
    """The range of K over a cycle: (1 - R) K_max for R >= 0, K_max for R < 0 (the faces close
    under the compressive part)."""
    return (1.0 - max(float(R), 0.0)) * float(K_max)


def step_cycles(lengths, K_max, C: float, m: float, R: float = 0.0, advance: float | None = None) -> float:
    """The cycles of the last step of a tip: `lengths` and `K_max` the last two or three (crack
    length, K_max) of the tip (the step from the second-last to the last). `advance`: the tip's
    advance over the step (default the length's increase: one tip per crack). ln K is
    interpolated in ln L through the points given."""
    L = np.asarray(lengths, dtype=float)
    K = np.array([delta_K(k, R) for k in K_max])
    if len(L) not in (2, 3) or len(K) != len(L) or np.any(L <= 0) or np.any(K <= 0) or np.any(np.diff(L) <= 0):
        raise ValueError("step_cycles: 2 or 3 increasing crack lengths > 0 with K > 0")
    lam, lk = np.log(L), np.log(K)
    coef = np.polyfit(lam, lk, len(L) - 1)
    a, b = lam[-2], lam[-1]
    x, w = np.polynomial.legendre.leggauss(GAUSS_POINTS)
    t = 0.5 * (b - a) * x + 0.5 * (a + b)
    # dL = L d(ln L); ds = dL * advance / (L1 - L0)
    integral = 0.5 * (b - a) * float(np.dot(w, np.exp(t - m * np.polyval(coef, t)))) / C
    scale = 1.0 if advance is None else float(advance) / (L[-1] - L[-2])
    return integral * scale


class Cycles:
    """The cycle count of a fatigue run: each tip's (crack length, K_max, position) at the steps
    it grew from, and the cumulative cycles (0 at step 0)."""

    def __init__(self, C: float, m: float, dK_th: float = 0.0, R: float = 0.0):
        self.C, self.m, self.dK_th, self.R = C, m, dK_th, R
        self.total = 0.0
        self.history: dict[str, list] = {}
        #: tip -> its share of the cycles so far that it has not grown by yet (below MIN_INCREMENT da)
        self.owed: dict[str, float] = {}
        self._pending: dict[str, float] = {}

    def increments(self, active: list[dict], da: float) -> list[dict]:
        """The tips of `active` (their values, K_eq the K_max) that grow this step, each with its
        advance `v["da"]`: the leading tip (the largest Delta K) da, every other tip above the
        threshold da (Delta K_i / Delta K_max)^m plus what it is owed; a tip whose advance would be
        below MIN_INCREMENT da waits (its share is owed once the step is taken: `growing`)."""
        driven = [v for v in active if delta_K(v["K_eq"], self.R) > self.dK_th and v["K_eq"] > 0]
        self._pending = {}
        if not driven:
            return []
        top = max(delta_K(v["K_eq"], self.R) for v in driven)
        out = []
        for v in driven:
            inc = da * (delta_K(v["K_eq"], self.R) / top) ** self.m + self.owed.get(v["label"], 0.0)
            if inc >= MIN_INCREMENT * da:
                v["da"] = min(inc, da)
                out.append(v)
            else:
                self._pending[v["label"]] = inc
        return out

    @staticmethod
    def _state(scene, v) -> tuple:
        return (float(scene.cracks[v["crack"]].length), float(v["K_eq"]), float(v["x"]), float(v["y"]))

    def grown(self, scene, values, labels) -> float:
        """A new step after the tips `labels` grew: add the cycles of that growth (the leading
        tip's, which advanced by da; the others' shares of the same cycles) to the total."""
        dn = []
        for v in values:
            h = self.history.get(v["label"])
            if v["label"] not in labels or not h:
                continue
            state = self._state(scene, v)
            L0, K0, x0, y0 = h[-1]
            advance = math.hypot(state[2] - x0, state[3] - y0)
            if state[1] <= 0 or K0 <= 0 or state[0] <= L0 or advance <= 0:
                h.clear()
                continue
            h.append(state)
            pts = h[-3:]
            dn.append((advance, step_cycles([p[0] for p in pts], [p[1] for p in pts], self.C, self.m, self.R, advance)))
        if dn:
            self.total += max(dn)[1]
        return self.total

    def growing(self, scene, values, labels) -> None:
        """Before the tips `labels` grow: their present state starts or continues their history;
        what the tips that wait this step are owed (`increments`) is kept."""
        for lab in labels:
            self.owed.pop(lab, None)
        self.owed.update(self._pending)
        self._pending = {}
        for v in values:
            if v["label"] not in labels:
                continue
            state = self._state(scene, v)
            h = self.history.setdefault(v["label"], [])
            if not h or h[-1] != state:
                h[:] = [state]

    @staticmethod
    def fracture(values, K_Ic) -> str:
        """The stop reason where some tip's K_max has reached K_Ic, else ""."""
        if K_Ic is None or not values:
            return ""
        top = max(values, key=lambda v: v["K_eq"])
        if top["K_eq"] < K_Ic:
            return ""
        return (f"fracture: K_max = {top['K_eq']:.4g} at tip {top['label']} reached K_Ic = {K_Ic:.4g} "
                "(the crack runs on the next cycle)")
