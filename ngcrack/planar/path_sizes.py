"""Mesh sizes along a crack graded with the distance from the crack ends (`path_grading`).

A grown crack path is long, and most of it lies far from the tips where K is computed:
meshed at crack_h all along, the unknowns of a growth run's solves grow with the path
(the README's teaching scene: 53k at its first step, 135k after 50 steps of da = 0.1).
With `path_grading` = r, a crack segment at distance d from the nearest crack end (a tip,
or an end on the boundary or on a hole: `grading_points`) asks netgen for the size

    h = min(crack_h + r d, PATH_H_CAP crack_h, maxh),

d the Euclidean distance from the segment to that end (a mesh-size field like netgen's own
grading, which lets h grow by about `grading` per unit length away from a feature). Near
the ends the crack keeps crack_h, and the tips keep their tip_h grading. Segments that lie
on one of the polylines `PathGrading.fine` keep crack_h wherever they are.

Measured on the teaching scene's grown paths (BENCHMARKS 13: the scenes of a run meshed at
crack_h, solved again graded): with rate 0.1, K_I moves by at most 0.17% and K_II by at
most 0.73% of K_I (0.3 degrees of kink at the measured dK_II/dtheta of 1.5 K_I); the
unknowns at step 50 are 77k instead of 135k. Most of the change in K comes from the
initial crack, closed and sliding under friction, which drives the wings: kept at crack_h
(`fine` = the scene's cracks before the run) K moves by at most 0.15% and 0.16%, at 93k
unknowns and about a fifth more CPU.

Netgen puts a vertex at every point of a crack's polyline, so a path of segments of length
da is meshed no coarser than da, whatever h asks. `path_grading=None` (the default of a
solve) leaves the mesh as it was; growth grades with GROWTH_PATH_GRADING
(ngcrack.studies.growth.checks) unless told otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError

#: the coarsest size a crack segment asks for, in units of crack_h (and at most maxh)
PATH_H_CAP = 4.0
#: the largest grading rate accepted (h may grow by at most its own length per unit of distance)
MAX_PATH_GRADING = 1.0


@dataclass(frozen=True)
class PathGrading:
    """How the crack's mesh size grows from crack_h: `rate` per unit distance from the nearest
    tip; the polylines `fine` ((x, y) points each) are kept at crack_h."""

    rate: float
    fine: tuple = ()


def check_path_grading(value) -> PathGrading | None:
    """None, a rate (a number in (0, MAX_PATH_GRADING]) or a PathGrading, as a PathGrading (the
    error names the field)."""
    if value is None:
        return None
    rate, fine = (value.rate, value.fine) if isinstance(value, PathGrading) else (value, ())
    ok = isinstance(rate, (int, float)) and not isinstance(rate, bool)
    if not ok or not math.isfinite(float(rate)) or not 0.0 < float(rate) <= MAX_PATH_GRADING:
        raise InputError(f"path_grading = {value!r}: must be None (crack_h all along the cracks) or a number in "
                         f"(0, {MAX_PATH_GRADING:g}]: how fast the crack's mesh size grows with the distance from "
                         "the nearest crack end")
    try:
        fine = tuple(tuple((float(x), float(y)) for x, y in line) for line in fine)
    except (TypeError, ValueError) as exc:
        raise InputError(f"path_grading.fine = {fine!r}: must be polylines of (x, y) points") from exc
    return PathGrading(float(rate), fine)


def grading_points(cracks) -> np.ndarray:
    """The points the crack's size grades from (k, 2): every crack end, the tips and the ends on
    the boundary or on a hole (a crack joined to a hole makes a corner of the body there)."""
    return np.reshape([p for pts in cracks for p in (pts[0], pts[-1])], (-1, 2)).astype(float)


def segment_tip_distance(tips: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The distance from each segment [a_i, b_i] to the nearest of the points `tips` (k, 2);
    infinite without tips."""
    a, b = np.asarray(a, dtype=float).reshape(-1, 2), np.asarray(b, dtype=float).reshape(-1, 2)
    tips = np.asarray(tips, dtype=float).reshape(-1, 2)
    if not len(tips):
        return np.full(len(a), np.inf)
    ab = b - a
    L2 = np.einsum("ij,ij->i", ab, ab)
    rel = tips[None, :, :] - a[:, None, :]  # (segment, tip, 2)
    t = np.clip(np.einsum("ikj,ij->ik", rel, ab) / np.where(L2 > 0, L2, 1.0)[:, None], 0.0, 1.0)
    nearest = a[:, None, :] + t[:, :, None] * ab[:, None, :]
    return np.min(np.linalg.norm(tips[None, :, :] - nearest, axis=2), axis=1)


def _point_segment_distance(x: np.ndarray, p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The distance from each point x_i (n, 2) to the segment [p, q]."""
    pq = q - p
    L2 = float(pq @ pq)
    t = np.clip((x - p) @ pq / L2, 0.0, 1.0) if L2 > 0 else np.zeros(len(x))
    return np.linalg.norm(x - (p + t[:, None] * pq), axis=1)


def on_polylines(lines, a: np.ndarray, b: np.ndarray, tol: float) -> np.ndarray:
    """Whether each segment [a_i, b_i] lies on one segment of the polylines `lines` (both its
    end points within tol of it)."""
    a, b = np.asarray(a, dtype=float).reshape(-1, 2), np.asarray(b, dtype=float).reshape(-1, 2)
    out = np.zeros(len(a), dtype=bool)
    for line in lines:
        pts = np.asarray(line, dtype=float).reshape(-1, 2)
        for p, q in zip(pts[:-1], pts[1:]):
            out |= (_point_segment_distance(a, p, q) <= tol) & (_point_segment_distance(b, p, q) <= tol)
    return out


def segment_sizes(tips: np.ndarray, a: np.ndarray, b: np.ndarray, crack_h: float, grading: PathGrading | None,
                  maxh: float, fine=(), tol: float = 0.0) -> np.ndarray:
    """The size each crack segment [a_i, b_i] asks for: crack_h + rate d, d its distance from
    the nearest crack end, at most PATH_H_CAP crack_h and maxh (and at least crack_h); crack_h
    without grading, without a tip, and on the polylines `fine` (within tol; the caller's
    coordinates, like a and b)."""
    a = np.asarray(a, dtype=float).reshape(-1, 2)
    h = np.full(len(a), float(crack_h))
    if grading is None or not len(np.asarray(tips).reshape(-1, 2)):
        return h
    cap = min(PATH_H_CAP * float(crack_h), float(maxh))
    h = np.maximum(h, np.minimum(crack_h + grading.rate * segment_tip_distance(tips, a, b), cap))
    if len(fine):
        h[on_polylines(fine, a, b, tol)] = crack_h
    return h
