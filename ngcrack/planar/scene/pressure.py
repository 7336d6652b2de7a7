"""Crack-face pressure: a load p(s) on both faces of a crack, pushing them apart.

``[[crack]] pressure = p`` (uniform), ``pressure = [[s0, p0], [s1, p1], ...]`` (piecewise
linear in the arc length s from the crack's first point; the s values non-decreasing,
a repeated s a jump of p there; held constant beyond the first and last s) or, in
Python, a callable ``p(s)`` of the arc length returning a finite number. p > 0 pushes
the faces apart (the traction on each face is -p n, n the face's outward normal):
its virtual work is the integral of p [v].nu over the crack. p < 0 (suction) is
allowed. With unilateral contact the faces close where the net normal traction is
compressive; the contact pressure there is what the constraint adds to p.

This module checks a pressure field (by name, before any meshing) and evaluates it at
arc lengths (numpy); the NGSolve CoefficientFunction of a pressure lives with the mesh
(``ngcrack.planar.crack_loads``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ...core.fields import SceneError, is_number, pressure_kind, short  # noqa: F401  (re-exported)

__all__ = ["MAX_TABLE_POINTS", "Pressure", "check_pressure", "pressure_kind", "pressure_values",
           "pressure_to_toml"]

#: the most [s, p] rows a pressure table may have
MAX_TABLE_POINTS = 10000
#: points at which a callable pressure is probed when the scene is built (evenly along the crack)
PROBE_POINTS = 5

#: a crack's pressure: None (no load), a number, a table ((s, p), ...) or a callable of s
Pressure = None | float | tuple[tuple[float, float], ...] | Callable[[float], float]

WHAT = ("a finite number (uniform), a table [[s, p], ...] of 2 or more rows with s >= 0 "
        "non-decreasing (piecewise linear in the arc length s from the crack's first point), "
        "or in Python a callable p(s)")


def check_pressure(v: Any, fld: str, length: float | None = None) -> Pressure:
    """Coerce and check a crack's pressure field ``fld``; a callable is probed along
    ``length`` (the crack's arc length) when given. Raises SceneError naming ``fld``."""
    if v is None:
        return None
    if is_number(v):
        x = float(v)
        if not math.isfinite(x):
            raise SceneError(f"{fld} = {v!r}: must be {WHAT}")
        return x
    if callable(v):
        if length is not None:
            for s in np.linspace(0.0, length, PROBE_POINTS):
                try:
                    p = v(float(s))
                except Exception as exc:  # the user's function: report its failure by field
                    raise SceneError(f"{fld}: the callable failed at s = {s:.6g} ({type(exc).__name__}: "
                                     f"{exc}); it must return a finite number for every s in "
                                     f"[0, {length:.6g}]") from None
                if not is_number(p) or not math.isfinite(float(p)):
                    raise SceneError(f"{fld}: the callable returned {short(p)} at s = {s:.6g}; it must "
                                     f"return a finite number for every s in [0, {length:.6g}]")
        return v
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) < 2:
        raise SceneError(f"{fld} = {short(v)}: must be {WHAT}")
    if len(v) > MAX_TABLE_POINTS:
        raise SceneError(f"{fld}: {len(v)} rows; at most {MAX_TABLE_POINTS} are allowed")
    rows = []
    for i, row in enumerate(v):
        if isinstance(row, np.ndarray):
            row = row.tolist()
        if (isinstance(row, (str, bytes)) or not isinstance(row, Sequence) or len(row) != 2
                or not all(is_number(c) and math.isfinite(float(c)) for c in row)):
            raise SceneError(f"{fld}[{i}] = {short(row)}: must be a row [s, p] of 2 finite numbers")
        s, p = float(row[0]), float(row[1])
        if s < 0:
            raise SceneError(f"{fld}[{i}] = [{s:g}, {p:g}]: s must be >= 0 (the arc length from the "
                             f"crack's first point)")
        if rows and s < rows[-1][0]:
            raise SceneError(f"{fld}[{i}]: s = {s:g} is below the previous row's {rows[-1][0]:g}; the "
                             f"s values must be non-decreasing")
        rows.append((s, p))
    if rows[-1][0] == rows[0][0]:
        raise SceneError(f"{fld}: every row has s = {rows[0][0]:g}; give at least two distinct s")
    return tuple(rows)


def pressure_values(p: Pressure, s: Any) -> np.ndarray:
    """p at the arc lengths ``s`` (array); zeros for None. A table is interpolated
    linearly (constant beyond its ends; at a repeated s, the value after the jump)."""
    s = np.asarray(s, dtype=float)
    if p is None:
        return np.zeros_like(s)
    if isinstance(p, float):
        return np.full_like(s, p)
    if isinstance(p, tuple):
        table = np.asarray(p)
        ss, pp = table[:, 0], table[:, 1]
        # right-continuous at jumps: the last row of each repeated s wins
        out = np.interp(s, ss, pp)
        idx = np.searchsorted(ss, s, side="right") - 1
        at = (idx >= 0) & (idx < len(ss)) & np.isclose(s, ss[np.clip(idx, 0, len(ss) - 1)], rtol=0, atol=0)
        out[at] = pp[idx[at]]
        return out
    return np.array([float(p(float(x))) for x in s.ravel()]).reshape(s.shape)


def pressure_to_toml(p: Pressure, fld: str) -> Any:
    """The TOML value of a pressure (a callable has none: refused by name)."""
    if isinstance(p, tuple):
        return [list(r) for r in p]
    if callable(p):
        raise SceneError(f"{fld}: a Python callable cannot be written to a scene file; give a number "
                         f"or a table [[s, p], ...]")
    return p
