"""An embedded crack that grows near a face breaks through it: re-characterised as a surface crack.

When a grown embedded front comes near a face, the ligament of body between the front and the face
is thin, highly stressed and breaks through in a few cycles: the engineering codes do not follow
it, they re-characterise the flaw. The rule here is the flaw-to-surface proximity rule of the ASME
Boiler and Pressure Vessel Code, Section XI, IWA-3300 (also JSME S NA1's): an embedded flaw of
half-height a (its containment rectangle's half extent across the face, measured in the crack's
plane) whose ligament S to the face is below PROXIMITY_FACTOR a is a surface flaw of depth

    a' = 2 a + S,

the ligament counted in the crack (BS 7910's Annex E and API 579 re-characterise the same way with
factors of their own). The grown front is tested after every step; a front that comes within the
scene's clearance of a face (fronts3d.CLEARANCE_RTOL of its size), or crosses it, in a step longer
than the ligament is re-characterised too.

The new crack is the ellipse the surface stepper grows (surface3d.py), the codes' re-characterised
flaw: in the old crack's plane, its depth semi-axis a' = 2a + S along the in-plane direction e_d
towards the face and its half-length on the surface the embedded flaw's half-length c (its
containment rectangle's, along e_l = normal x e_d), centred on the face where the line through the
rectangle's mid-length at its deepest level meets it. The ellipse is the codes' idealisation of the
broken-through crack (the embedded crack and the ligament it broke): it need not contain the whole
grown front (a penny's sides at mid-depth lie just outside it; the ellipse of depth a' that contains
them depends on the front's curvature at its deepest point, 0.69 or 0.98 for the same penny on two
meshes, where the codes' c is the same). The front of any shape (disc, ellipse or the curve of a
grown front) becomes an ellipse, the codes' idealisation (a curve crossing the faces grows too,
surface_curve.py, but the re-characterised flaw is the codes' ellipse).

What stops the run instead, by name: a crack nearly parallel to the face it nears (its plane within
PARALLEL_SINE of the face's: a delamination, not a surface crack), a front whose deepest point is
outside the body, and a re-characterised crack the scene refuses (the sliver it leaves to the back
face thinner than the mesh resolves, another face crossed, another crack met): the reason names the
rule and the scene's words.

Cycles (fatigue): the step in which the front nears the face is counted as every step of the
embedded crack (its leading point's advance, K at the grown front extrapolated from the last steps
as a power of the crack's size); the break-through itself takes none (the codes' assumption: the
thin ligament goes in a few cycles), and the surface crack's steps count from its first solve on.
"""

from __future__ import annotations

import math

import numpy as np

#: ASME Section XI IWA-3300's proximity factor: an embedded flaw whose ligament to the face is below this
#: fraction of its half-height is a surface flaw
PROXIMITY_FACTOR = 0.4
#: a crack whose plane makes an angle below asin(PARALLEL_SINE) with the face it nears is not re-characterised
PARALLEL_SINE = 0.2
#: outline points of the grown front measured for the re-characterisation
OUTLINE_POINTS = 512
#: bisection steps locating the face along the depth direction (to 2^-60 of the search length)
FACE_BISECTIONS = 60
#: the step of the central differences of a face's distance (its normal), a fraction of the crack's size
NORMAL_STEP_RTOL = 1e-6


def _face_distance(domain, key: str, p: np.ndarray) -> np.ndarray:
    from ngcrack.solid.surface import face_distances

    return face_distances(domain, np.atleast_2d(p))[key]


def nearest_face(domain, points: np.ndarray) -> tuple[str, float, int]:
    """(the face the points come nearest to, their least signed distance to it (negative: beyond it), the index of
    the nearest point)."""
    from ngcrack.solid.surface import face_distances

    dist = face_distances(domain, points)
    key = min(dist, key=lambda k: float(np.min(dist[k])))
    return key, float(np.min(dist[key])), int(np.argmin(dist[key]))


def _inward_normal(domain, key: str, p: np.ndarray, size: float) -> np.ndarray:
    h = NORMAL_STEP_RTOL * size
    g = np.array([(_face_distance(domain, key, p + h * e)[0] - _face_distance(domain, key, p - h * e)[0]) / (2 * h)
                  for e in np.eye(3)])
    return g / np.linalg.norm(g)


def recharacterise(domain, crack, i: int, clearance_rtol: float) -> tuple[dict | None, dict | None, str]:
    """The grown embedded crack `crack` (crack[i]) near a face: (None, None, "") if it stays embedded (its ligament
    at least PROXIMITY_FACTOR of its half-height and the scene's clearance); else (the surface crack's scene
    dictionary, what happened (the event's numbers), "") or (None, None, why it cannot) (module docstring)."""
    p = crack.outline(OUTLINE_POINTS)
    size = float(np.max(np.linalg.norm(p[:, None] - p[None], axis=-1)))
    key, S, k = nearest_face(domain, p)
    n = np.asarray(crack.normal, dtype=float)
    g = _inward_normal(domain, key, p[k], size)
    towards = -(g - np.dot(g, n) * n)  # the in-plane direction towards the face
    sine = float(np.linalg.norm(towards))
    e_d = towards / max(sine, 1e-300)
    c0 = p.mean(axis=0)
    u, w = (p - c0) @ e_d, (p - c0) @ np.cross(n, e_d)
    a = 0.5 * float(u.max() - u.min())
    c = 0.5 * float(w.max() - w.min())
    if S >= PROXIMITY_FACTOR * a and S >= clearance_rtol * size:
        return None, None, ""
    if S <= 0:
        rule = f"its front crossed face {key} in the step"
    elif S < PROXIMITY_FACTOR * a:
        rule = f"its ligament to face {key}, {S:.3g}, below {PROXIMITY_FACTOR:g} of its half-height {a:.3g} (ASME XI's proximity rule)"
    else:
        rule = f"its ligament to face {key}, {S:.3g}, within the scene's clearance {clearance_rtol:g} of its size {size:.3g}"
    if sine < PARALLEL_SINE:
        return None, None, (f"boundary: crack[{i}] nears face {key}, {rule}, but lies nearly parallel to it (the sine "
                            f"of the angle {sine:.3g} < {PARALLEL_SINE:g}): it is not re-characterised as a surface "
                            f"crack")
    deep = int(np.argmin(u))
    q = c0 + 0.5 * (w.max() + w.min()) * np.cross(n, e_d) + u[deep] * e_d  # the containment's mid-length, deepest
    if float(_face_distance(domain, key, q)[0]) <= 0:
        q = p[deep]
    if float(_face_distance(domain, key, q)[0]) <= 0:
        return None, None, f"boundary: crack[{i}] has crossed face {key} wholly; it is not re-characterised"
    lo, hi = 0.0, 2.0 * (u.max() - u.min()) + abs(S) + size  # along e_d from the deepest point to the face
    if float(_face_distance(domain, key, q + hi * e_d)[0]) > 0:
        return None, None, f"boundary: crack[{i}]'s depth direction does not meet face {key}; it is not re-characterised"
    for _ in range(FACE_BISECTIONS):
        mid = 0.5 * (lo + hi)
        if float(_face_distance(domain, key, q + mid * e_d)[0]) > 0:
            lo = mid
        else:
            hi = mid
    depth = 0.5 * (lo + hi)  # 2 a + S (the ligament measured along e_d)
    centre = q + depth * e_d
    half = c  # the codes': the embedded flaw's half-length
    e_l = np.cross(n, e_d)
    from .surface3d import carried

    d = {"shape": "ellipse", "center": centre.tolist(), "normal": n.tolist(), "semi_axes": [half, depth],
         "major_axis": (e_l / np.linalg.norm(e_l)).tolist(), **carried(crack)}
    info = {"crack": i, "event": "surface", "face": key, "ligament": S, "half_height": a, "half_length": c,
            "depth": depth, "surface_half_length": half, "embedded_size": math.sqrt(float(crack.area) / math.pi),
            "what": (f"surface: crack[{i}] broke through face {key}: {rule}; re-characterised as a surface crack of depth "
                     f"{depth:.4g} (2a + S) and half-length {half:.4g} on the face")}
    return d, info, ""
