"""Convergence rates of a sweep's rows: between consecutive meshes and fitted; a Markdown table.

Rates. With e the error, h the mesh's largest edge length and N = ndof_total:

    rate_h   = log(e_prev / e) / log(h_prev / h)        (e ~ h^rate_h)
    rate_dof = log(e_prev / e) / log(N / N_prev)         (e ~ N^-rate_dof)

In 2D N ~ h^-2, so rate_dof ~ rate_h / 2. The paper's rates (0.81, 0.65, 0.93, 0.78)
are least-squares slopes of log e against log dof: rate_dof in this convention (the
slopes of its Tables 1-4 are 0.82, 0.65, 0.94, 0.85).

Expected rates. The paper proves, in its energy-type norm (stress in L2 plus the
multiplier on the crack), h^(1/2) for PEERS and h^(3/4) for BDM; both come from the
regularity of the solution (u in H^(3/2 - eps) near the crack tips, the stress
singular like r^(-1/2)). For the L2 quantities here: the stress error is bounded by
that norm, and a r^(-1/2) singularity on a quasi-uniform mesh costs exactly h^(1/2) in
L2, so h^(1/2) is the asymptotic floor; the displacement is P0 per triangle, so its L2
error cannot beat h^1. On the meshes of a study (where the smooth part of the error still
dominates) the observed rate_h lie between these: see tests/test_study.py for the bands
and the measured values.

"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .quantities import RATE_QUANTITIES

#: columns `with_rates` adds to a sweep's DataFrame
RATE_COLUMNS = tuple(f"rate_{kind}_{q}" for q in RATE_QUANTITIES for kind in ("h", "dof"))


def _groups(df):
    cols = [c for c in ("scene", "element", "nu", "friction") if c in df.columns]
    return df.groupby(cols, sort=False, dropna=False)


def _adaptive(g) -> bool:
    """Whether a group's rows are adaptive runs (their maxh column holds tolerances)."""
    return "adapt" in g.columns and bool(g["adapt"].fillna(False).astype(bool).any())


def with_rates(df):
    """`df` plus rate_h_<q> and rate_dof_<q> between consecutive meshes of each (scene, element, nu).

    Rows are taken in order of decreasing h (adaptive rows: of increasing unknowns, and
    no rate in h, since adaptive refinement leaves the largest edge where it is); rows
    without a finite positive error (the reference) are skipped, and the first row of
    each group has no rate (NaN). Groups are (scene, element, nu, friction).
    """
    df = df.copy()
    for col in RATE_COLUMNS:
        df[col] = np.nan
    if df.empty:
        return df
    for _, g in _groups(df):
        adaptive = _adaptive(g)
        g = g.sort_values("ndof_total", kind="stable") if adaptive else g.sort_values("h", ascending=False, kind="stable")
        for q in RATE_QUANTITIES:
            e = g[f"err_{q}"].to_numpy(dtype=float)
            ok = np.isfinite(e) & (e > 0)
            idx = g.index[ok]
            e, h, n = e[ok], g["h"].to_numpy(float)[ok], g["ndof_total"].to_numpy(float)[ok]
            if len(e) < 2:
                continue
            de = np.log(e[:-1] / e[1:])
            with np.errstate(divide="ignore", invalid="ignore"):
                df.loc[idx[1:], f"rate_h_{q}"] = np.nan if adaptive else de / np.log(h[:-1] / h[1:])
                df.loc[idx[1:], f"rate_dof_{q}"] = de / np.log(n[1:] / n[:-1])
    return df


def fitted_rates(df, quantities: Sequence[str] = RATE_QUANTITIES):
    """Least-squares rates per (scene, element, nu, quantity): slopes of log e against log h and log dof.

    Columns: scene, element, nu, quantity, rate_h, rate_dof, points (rows used), h_min,
    ndof_max. Rows without a finite positive error are left out; a quantity with fewer
    than two such rows gives no line. Adaptive groups have no rate in h (NaN).
    """
    import pandas as pd

    out = []
    for keys, g in _groups(df):
        keys = dict(zip([c for c in ("scene", "element", "nu", "friction") if c in g.columns],
                        keys if isinstance(keys, tuple) else (keys,)))
        for q in quantities:
            col = f"err_{q}"
            if col not in g:
                continue
            e = g[col].to_numpy(float)
            ok = np.isfinite(e) & (e > 0)
            if ok.sum() < 2:
                continue
            le = np.log(e[ok])
            h, n = g["h"].to_numpy(float)[ok], g["ndof_total"].to_numpy(float)[ok]
            rate_h = math.nan if _adaptive(g) else float(np.polyfit(np.log(h), le, 1)[0])
            out.append({**keys, "quantity": q, "rate_h": rate_h,
                        "rate_dof": float(-np.polyfit(np.log(n), le, 1)[0]), "points": int(ok.sum()),
                        "h_min": float(h.min()), "ndof_max": int(n.max())})
    return pd.DataFrame(out, columns=["scene", "element", "nu", "friction", "quantity", "rate_h", "rate_dof", "points",
                                      "h_min", "ndof_max"])


def markdown_table(df, floatfmt: str = ".3g") -> str:
    """A GitHub-flavoured Markdown table of `df` (NaN shown as an empty cell)."""
    def cell(v):
        if isinstance(v, (float, np.floating)):
            return "" if not math.isfinite(v) else format(float(v), floatfmt)
        return str(v)

    cols = [str(c) for c in df.columns]
    lines = ["| " + " | ".join(cols) + " |",
             "|" + "|".join("---:" if df[c].dtype.kind in "fiu" else ":---" for c in df.columns) + "|"]
    for rec in df.itertuples(index=False):
        lines.append("| " + " | ".join(cell(v) for v in rec) + " |")
    return "\n".join(lines) + "\n"
