"""The faces a surface crack's front ends on, for its growth (surface3d.py, surface_curve.py): their normals,
the direction an end point moves along its face, the body's thickness along a direction, and what a crack's
new shape keeps of it."""

from __future__ import annotations

import numpy as np

#: the step of the central differences that give a face's normal, a fraction of the body's size
NORMAL_STEP_RTOL = 1e-6


def face_normal(domain, p: np.ndarray, size: float) -> np.ndarray:
    """The outward unit normal of the face nearest to the point p."""
    from ngcrack.solid.surface import face_distances

    dist = face_distances(domain, p[None])
    key = min(dist, key=lambda k: abs(dist[k][0]))
    h = NORMAL_STEP_RTOL * size
    grad = np.array([(face_distances(domain, (p + h * e)[None])[key][0] - face_distances(domain, (p - h * e)[None])[key][0])
                     / (2 * h) for e in np.eye(3)])
    return -grad / np.linalg.norm(grad)  # the distance grows inwards


def along_faces(domain, crack, p: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The directions d of the front's points p with the first and last (its ends on the surface) projected into their
    faces and the crack's plane, so that the ends move along the surface."""
    d = np.array(d, dtype=float)
    for k in (0, len(p) - 1):
        nf = face_normal(domain, p[k], crack.size)
        t = d[k] - np.dot(d[k], nf) * nf
        t -= np.dot(t, crack.normal) * crack.normal
        d[k] = t / np.linalg.norm(t)
    return d


def thickness(domain, p: np.ndarray, inward: np.ndarray, size: float) -> float:
    """The body's thickness from the surface point p along the inward direction (bisection to where it leaves)."""
    lo, hi = 0.0, 4.0 * size
    while hi - lo > 1e-6 * size:
        mid = 0.5 * (lo + hi)
        if float(domain.clearance((p + (mid + 1e-9 * size) * inward)[None])[0]) > 0 or mid < 1e-9 * size:
            lo = mid
        else:
            hi = mid
    return lo


def domain_size(domain) -> float:
    """The body's diameter (its bounding box's), the scale of a probe."""
    if hasattr(domain, "lo"):
        return float(np.linalg.norm(np.asarray(domain.hi) - np.asarray(domain.lo)))
    return float(np.hypot(2 * domain.radius, domain.height))


def carried(crack) -> dict:
    """What a crack's new shape keeps of it (a grown or re-characterised crack's scene dictionary): its friction and its
    pressure (a number, a table or a callable: a field in space, solid.loads), where it has them."""
    return {k: v for k, v in (("friction", crack.friction), ("pressure", crack.pressure)) if v}
