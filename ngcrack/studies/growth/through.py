"""A surface or corner crack that grows near the back face breaks through it: re-characterised as a through crack.

When the deepest point of a grown surface crack (its mouth on the front face of a plate) comes near
the back face, the ligament between them is thin and goes in a few cycles; the engineering codes do
not follow it but re-characterise the crack as a through crack. The rule here is NASGRO's transition
criterion for a surface (or corner) crack: the crack becomes a through crack once its depth a
reaches TRANSITION_DEPTH = 0.95 of the thickness t (the ligament t - a below 0.05 t); and, since the
mesh resolves no thinner ligament (the scene's sliver rule, ngcrack.solid.surface.LIGAMENT_FRONT_H),
once the ligament falls below THROUGH_FRONT_H front_h of the mesh, or the front crosses the back face
in the step. (BS 7910 and API 579 have re-characterisation rules of their own for a flaw penetrating
the wall; the depth fraction is NASGRO's.)

The new crack (the codes' idealisation): in the old crack's plane a region from the front face to the
back face, its fronts straight lines from face to face:

- a surface crack (its mouth on one face): a through crack of two fronts, of length 2c on the front
  face (the grown crack's mouth, centred on it) and 2c_b on the back face, c_b from the grown crack's
  area A inside the body (the trapezoid keeps it: t (c + c_b) = A, a semi-ellipse's pi a c / 2);
- a corner crack (its mouth on two faces meeting at a right angle): a through crack of one front, of
  length c along the front face from the side face and c_b along the back face, t (c + c_b) / 2 = A.

The area rule is the one choice of the back-face length here (the codes differ on it: some keep c,
some the area); at a = 0.95 t it gives c_b = 0.49 c for a semi-ellipse, the front leaning as the
grown crack's does. The region is written as a polygon crossing both faces (and a corner crack's
side face) by THROUGH_MARGIN of the thickness or more (the scene's clearance rule): its two sides
(or one) inside the body are the fronts, which the solver takes as a polygon's clipped sides.

Refused by name (the run stops): faces that are not parallel planes (the front and back faces of a
plate) or a corner whose side face is not at a right angle; a mouth the outline does not cross as a
surface or corner crack's; a back-face length below MIN_BACK_FRACTION of c (the ligament rule fired
while the crack was still shallow: a coarse mesh; give a smaller front_h).

Cycles (fatigue): the step that brought the surface crack near the back face is counted as its steps
are (K at the grown crack extrapolated as a power of its size, as for a break-through); the
transition itself takes none (the codes' assumption), and the run stops after the through crack's
solve: its K along both fronts is the last step's, and `stopped` says that the through crack formed
and that its growth is not supported yet.
"""

from __future__ import annotations

import math

import numpy as np

from .faces3d import carried

#: NASGRO's transition: a surface or corner crack whose depth reaches this fraction of the thickness becomes a through crack
TRANSITION_DEPTH = 0.95
#: ... or whose ligament to the back face is below this many front_h of the mesh (the scene refuses a sliver
#: thinner than ngcrack.solid.surface.LIGAMENT_FRONT_H front_h; the margin catches the grown crack before that)
THROUGH_FRONT_H = 1.5
#: the polygon crosses the front and back faces (and a corner crack's side face) by this fraction of the thickness,
#: more where the scene's clearance asks for it
THROUGH_MARGIN = 0.3
#: a back-face half-length below this fraction of the front face's is refused (the transition came too early)
MIN_BACK_FRACTION = 0.1
#: outline points of the grown crack measured for the transition (ngcrack.solid.surface.STEP_SAMPLES on a STEP part)
OUTLINE_POINTS = 2048
#: faces are parallel (the front and back faces), or at a right angle (a corner), to within this sine or cosine
PARALLEL_TOL = 1e-6
#: the crack's clearance rule (ngcrack.solid.scene.CLEARANCE_RTOL), which the polygon's crossings must exceed
CLEARANCE_RTOL = 0.05


def _inward(domain, key: str, p: np.ndarray, size: float) -> np.ndarray:
    from .breakthrough import _inward_normal

    return _inward_normal(domain, key, p, size)


def _mouth_crossings(domain, p: np.ndarray, mouth: str, others: list[str]) -> np.ndarray:
    """The points where the closed outline p crosses face `mouth` on the body's surface (the mouth's ends)."""
    from ngcrack.solid.surface import face_distances

    dist = face_distances(domain, p)
    dm, dn = dist[mouth], np.roll(dist[mouth], -1)
    out = []
    for j in np.flatnonzero((dm > 0) != (dn > 0)):
        w = dm[j] / (dm[j] - dn[j])
        x = p[j] + w * (p[(j + 1) % len(p)] - p[j])
        if all(float(face_distances(domain, x[None])[k][0]) >= 0 for k in others):
            out.append(x)
    return np.array(out)


def through_crack(domain, old, grown, i: int, front_h: float) -> tuple[dict | None, dict | None, str]:
    """The grown surface crack `grown` (crack[i], grown from `old`) near the back face: (None, None, "") if it stays a
    surface crack (module docstring's rule); else (the through crack's scene dictionary, what happened (the event's
    numbers), "") or (None, None, why it cannot)."""
    from ngcrack.solid.surface import face_distances, inside_measures, samples

    from .fronts3d import equivalent_radius

    n_out = samples(domain, OUTLINE_POINTS)  # (a STEP part's distances are OCC's, a few ms a point: fewer there)
    q_old = old.outline(n_out)
    crossed = [k for k, d in face_distances(domain, q_old).items() if d.min() < 0]
    if len(crossed) not in (1, 2):
        return None, None, ""
    p = grown.outline(n_out)
    inside = domain.clearance(p) > 0
    if not inside.any():
        return None, None, ""
    size = float(grown.size)
    dist = face_distances(domain, p[inside])
    back = min((k for k in dist if k not in crossed), key=lambda k: float(dist[k].min()))
    deep = int(np.argmin(dist[back]))
    S = float(dist[back][deep])
    n = np.asarray(grown.normal, dtype=float)
    g = _inward(domain, back, p[inside][deep], size)
    e_d = -(g - np.dot(g, n) * n)
    cos = float(np.linalg.norm(e_d))  # the ligament along e_d is S / cos
    e_d /= max(cos, 1e-300)
    e_l = np.cross(n, e_d)
    normals = {k: _inward(domain, k, p[inside][deep], size) for k in crossed}
    mouth = max(crossed, key=lambda k: float(np.dot(normals[k], e_d)))
    side = [k for k in crossed if k != mouth]
    gm = normals[mouth] - np.dot(normals[mouth], n) * n
    if abs(float(np.dot(gm / np.linalg.norm(gm), e_d)) - 1.0) > PARALLEL_TOL:
        return None, None, ""  # not a plate's front and back faces: the surface crack's own rules apply
    X = _mouth_crossings(domain, p, mouth, [k for k in dist if k != mouth])
    if len(X) != (2 if not side else 1):
        return None, None, ""
    t = float(face_distances(domain, X[:1])[back][0]) / cos  # the thickness along e_d
    ligament = min(S, float(face_distances(domain, p)[back].min())) / cos  # negative: the front crossed the back face
    a = t - ligament
    need = max((1.0 - TRANSITION_DEPTH) * t, THROUGH_FRONT_H * front_h)
    if ligament >= need:
        return None, None, ""
    if ligament <= 0:
        rule = f"its front crossed the back face {back} in the step"
    elif ligament < (1.0 - TRANSITION_DEPTH) * t:
        rule = f"its depth {a:.4g} reached {TRANSITION_DEPTH:g} of the thickness {t:.4g} (NASGRO's transition)"
    else:
        rule = (f"its ligament to the back face {back}, {ligament:.3g}, below {THROUGH_FRONT_H:g} front_h = "
                f"{THROUGH_FRONT_H * front_h:.3g} (the thinnest the mesh resolves)")
    area = float(inside_measures(domain, grown)[1])
    O = X[0]
    lx = (X - O) @ e_l
    if side:  # a corner crack: l measured from the side face into the body
        gs = normals[side[0]] - np.dot(normals[side[0]], n) * n
        if abs(float(np.dot(gs / np.linalg.norm(gs), e_d))) > PARALLEL_TOL:
            return None, None, (f"boundary: crack[{i}] nears the back face {back} ({rule}), but its side face "
                                f"{side[0]} is not at a right angle to the front face: it is not re-characterised as a "
                                f"through crack")
        sgn = 1.0 if float(np.dot(gs, e_l)) > 0 else -1.0
        e_l = sgn * e_l
        c = float(face_distances(domain, O[None])[side[0]][0]) / float(np.linalg.norm(gs))
        c_b = 2.0 * area / t - c
        l0 = -c  # the side face
    else:
        c = 0.5 * float(lx.max() - lx.min())
        c_b = area / t - c
        O = O + 0.5 * float(lx.max() + lx.min()) * e_l  # the mouth's middle
    if not c_b >= MIN_BACK_FRACTION * c:
        return None, None, (f"boundary: crack[{i}] nears the back face {back} ({rule}), but at depth {a:.3g} of the "
                            f"thickness {t:.3g} the through crack of its area would be {max(c_b, 0):.3g} long on the "
                            f"back face, below {MIN_BACK_FRACTION:g} of its {c:.3g} on the front face: give a smaller "
                            f"front_h (the transition comes at 0.95 of the thickness)")
    m = THROUGH_MARGIN * t
    for _ in range(20):

        def h(dd):  # the front's half-length (a corner crack's length from the side face) at depth dd
            return c + (c_b - c) * dd / t

        if side:
            uv = [(-m, l0 - m), (-m, l0 + h(-m)), (t + m, l0 + h(t + m)), (t + m, l0 - m)]
        else:
            uv = [(-m, -h(-m)), (-m, h(-m)), (t + m, h(t + m)), (t + m, -h(t + m))]
        pts = np.array([O + dd * e_d + ll * e_l for dd, ll in uv])
        extent = float(np.max(np.linalg.norm(pts[:, None] - pts[None], axis=-1)))
        if m / max(cos, 1e-300) > 2 * CLEARANCE_RTOL * extent and (not side or m > 2 * CLEARANCE_RTOL * extent):
            break
        m *= 1.5
    newell = np.cross(pts[1] - pts[0], pts[2] - pts[0])
    if float(np.dot(newell, n)) < 0:
        pts = pts[::-1]
    d = {"shape": "polygon", "points": pts.tolist(), **carried(grown)}
    kind = "corner" if side else "surface"
    info = {"crack": i, "event": "through", "face": back, "ligament": ligament, "half_height": a, "half_length": c,
            "depth": t, "surface_half_length": c, "back_half_length": c_b, "embedded_size": equivalent_radius(grown),
            "what": (f"through: crack[{i}] (a {kind} crack) broke through the back face {back}: {rule}; re-characterised "
                     f"as a through crack {'of length' if side else 'of half-length'} {c:.4g} on the front face "
                     f"{mouth} and {c_b:.4g} on the back face (the grown crack's area {area:.4g} kept)")}
    return d, info, ""


def stop_reason(info: dict) -> str:
    """The run's stop after the through crack's solve (module docstring)."""
    return (f"through: crack[{info['crack']}] became a through crack at the back face {info['face']} (its K along the "
            f"fronts from face to face is this step's); the growth of a through crack is not supported yet")


def through_values(front, nu: float) -> dict:
    """A through crack's front values (fronts3d.point_values, K_drive the unsmoothed K_eq: its fronts are straight
    polygon sides, not a closed front's periodic curve)."""
    from .fronts3d import point_values

    v = point_values(front, nu)
    v["K_drive"] = np.maximum(v["K_eq"], 0.0)
    return v


def trapezoid_back_half_length(a: float, c: float, t: float, corner: bool = False) -> float:
    """The back-face half-length (a corner crack's length) of the through crack with the area of a semi-elliptical
    (quarter-elliptical) crack of depth a and half-length c in a plate of thickness t (module docstring)."""
    area = 0.25 * math.pi * a * c * (1 if corner else 2)
    return (2.0 if corner else 1.0) * area / t - c
