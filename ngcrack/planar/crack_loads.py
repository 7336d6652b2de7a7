"""The crack-face pressure as an NGSolve CoefficientFunction on a crack's edges.

A crack's pressure (``ngcrack.planar.scene.pressure``: a number, a table [[s, p], ...] or a
callable of the arc length s from the crack's first point) becomes a CoefficientFunction
that the elements integrate over the crack's own edges (``elements.base.load_vector``):

- uniform: an ``ngs.Parameter``, so that a new value re-assembles the load vector only
  (the factorization and the Schur complement are kept: volume control and hydraulic
  fracture change the pressure every solve);
- table: the piecewise linear interpolant of the rows in s (NGSolve's order-2 BSpline,
  a repeated s a jump), s the arc length of the point along the crack's polyline,
  held constant beyond the table's first and last s;
- callable: sampled at CALLABLE_SAMPLES evenly spaced arc lengths and at the polyline's
  points, then as a table (documented: a callable is resolved to 1/CALLABLE_SAMPLES of
  the crack's length).
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from .crack_sides import ON_CRACK_FACTOR, ON_EDGE_RTOL, segment_cf
from .scene.pressure import pressure_values

#: arc lengths at which a callable pressure is sampled along its crack (evenly spaced)
CALLABLE_SAMPLES = 2048


def arclength_cf(polyline: np.ndarray, diameter: float) -> ngs.CoefficientFunction:
    """s, the arc length from the polyline's first point, on its segments (0 away from them)."""
    tol = ON_EDGE_RTOL * diameter * ON_CRACK_FACTOR
    s = ngs.CF(0.0)
    s0 = 0.0
    for p, q in zip(polyline[:-1], polyline[1:]):
        L, _, along, on = segment_cf(p, q, tol)
        s = s + on * (s0 + along)
        s0 += L
    return s


def table_cf(table, s: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """The piecewise linear interpolant of rows (s_i, p_i) at the CoefficientFunction s."""
    rows = np.asarray(table, dtype=float)
    ss, pp = rows[:, 0], rows[:, 1]
    lo, hi = float(ss[0]), float(ss[-1])
    clamped = ngs.IfPos(s - hi, hi, ngs.IfPos(lo - s, lo, s))
    knots = [lo] + [float(v) for v in ss] + [hi]
    return ngs.BSpline(2, knots, [float(v) for v in pp])(clamped)


def pressure_cf(pressure, polyline: np.ndarray, diameter: float,
                parameter: ngs.Parameter | None = None) -> ngs.CoefficientFunction:
    """The CoefficientFunction of a crack's pressure on its edges (see the module docstring).

    `parameter`: the Parameter holding a uniform pressure's value (made if None).
    """
    if isinstance(pressure, float):
        if parameter is None:
            parameter = ngs.Parameter(pressure)
        return ngs.CF(parameter)
    pts = np.asarray(polyline, dtype=float)
    s_pts = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
    if callable(pressure):
        s = np.union1d(np.linspace(0.0, s_pts[-1], CALLABLE_SAMPLES + 1), s_pts)
        pressure = tuple(zip(s.tolist(), pressure_values(pressure, s).tolist()))
    return table_cf(pressure, arclength_cf(pts, diameter))
