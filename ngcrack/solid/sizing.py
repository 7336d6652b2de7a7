"""How big a 3D solve will be, before meshing: tetrahedra, unknowns, memory; the 3D size guard.

A 3D request grows with the inverse cube of its mesh sizes: a penny at front_h = 0.005 was
still meshing after 180 s, larger ones ended "out of memory" after minutes. `check_size`
estimates the request in milliseconds from the body, the cracks and the sizes, and refuses
it with one line (an InputError, exit 2 on the command line) when the estimated unknowns
exceed the ceiling `max_dof` (default DEFAULT_MAX_DOF) or the estimated peak memory exceeds
what this process may still allocate (`ngcrack.core.memory`), as the 2D guard does
(`ngcrack.planar.sizing`).

The tetrahedron estimate. Netgen makes tetrahedra of edge about the local mesh size h(x),
so a region of volume dV holds about dV / h^3 of them times a constant. The size is maxh = H
away from the cracks; each crack's faces ask for crack_h = h_c, its front (the crack's edge)
for front_h = h_0, and h grows from them with the distance d at the rate g (grading), until
it reaches H; around each crack the body's size is at most h_n (`solid.geometry.NEAR_*`) in a ball
of radius R_n, from which it grows at the rate g too. Integrated, the four parts of the density are

    bulk   V / H^3                                                            (V the body's volume)
    faces  2 A [ (1/(2 g)) (1/h_c^2 - 1/s_c^2) - D / H_b^3 ],  s_c = h_c + g D, D = min((H_b - h_c)/g, V/(2A))
    front  L [ (2 pi / g^2) (1/(2 h_0) - 1/s_0 + h_0/(2 s_0^2)) - pi R^2 / H_b^3 ],
           s_0 = h_0 + g R, R = min((H_b - h_0)/g, sqrt(V/(pi L)))
    near   4/3 pi R_n^3 (1/h_n^3 - 1/H^3) + the shell where h = h_n + g (r - R_n) < H (trapezoidal rule)

(A a crack's area, L its front's length; the faces' band on both sides, the front's tube all
around it, each less what the near ball, of size H_b = h_n, or the bulk, H_b = H without one,
already counts), and the tetrahedra are TETS_PER_BULK, TETS_PER_FACES, TETS_PER_FRONT and
TETS_PER_NEAR times them (the bulk's fitted on the meshes before the near balls, the others to
the largest relative error on today's meshes). Measured against netgen on 18 meshes of 7 scenes
(the penny in boxes of side 20a and 6a and in a cylinder, the bent beam, the inclined penny, an
ellipse; front_h 0.05a to 0.5a, crack_h = 2 to 8 front_h, grading 0.2 to 0.5; 509 to 25,463
tetrahedra): estimate / netgen within ESTIMATE_SPREAD, 0.74 to 1.35 (BENCHMARKS.md, "3D memory,
the ellipse in 3 GB and the accuracy option"); the front's tube and the near ball owe most of the
tetrahedra of a penny. A surface crack's near ball (centred on the face it crosses) and front tube (cut by a
back face near a deep front) are integrated inside the body only (sampled), and its scene's parts are then
SURFACE_TETS times that: on 8 meshes of plates with surface cracks within the same spread.

The default sizes near faces (`ligament_caps`, used by `solid.scene.SolidScene.mesh_sizes`): front_h at most the
ligament between a front and a face it does not cross over LIGAMENT_ELEMENTS, maxh at most a thin body's
thickness there; and front_h at most the depth of a crack that crosses a face over DEPTH_ELEMENTS (`depth_cap`).

Unknowns per tetrahedron and peak memory per unknown are constants of the element and order
(UNKNOWNS_PER_TET, BYTES_PER_UNKNOWN above BASE_MEMORY: measured, the constants say where; for
TDNNS order 1 the bytes per unknown grow as the cube root of the unknowns, FILL_GROWS).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..core.memory import DEFAULT_MAX_DOF, MEMORY_FRACTION, available_memory, check_max_dof, memory_limits
from ..core.memory import format_bytes as _bytes
from .surface import clearance, crosses, depths_from_faces, face_distances, inside_measures, is_step, samples

#: tetrahedra per unit of each part of the density integral (module docstring), fitted on 19 netgen meshes
TETS_PER_BULK, TETS_PER_FACES, TETS_PER_FRONT = 10.05, 24.67, 4.46
#: ... and of the body's size near the cracks (`_near_ball`); the bulk's kept from the fit on 19 meshes, the three
#: others fitted on 18 of today's meshes (the body's size near the cracks included)
TETS_PER_NEAR = 7.41
#: estimate / netgen on those meshes lies in this range (the ellipse at front_h 0.1a, crack_h 0.2a at its low end:
#: netgen makes 21,706 tetrahedra there against 13,535 at crack_h 0.25a)
ESTIMATE_SPREAD = (0.74, 1.35)
#: unknowns (total, before condensation) per tetrahedron, by (element, order), measured on the penny (6,809
#: tetrahedra) and the bent beam (1,170): tdnns 48.6-48.9 and 115.0-115.7, h1p1 0.56-0.64, h1p2 4.2-4.5
UNKNOWNS_PER_TET = {("tdnns", 1): 49.0, ("tdnns", 2): 116.0, ("h1p1", 1): 0.64, ("h1p2", 2): 4.5}
#: peak resident memory per unknown in bytes, by (element, order), above BASE_MEMORY: tdnns the largest of the
#: penny solves of BENCHMARKS.md section 17 (closed faces, two active sets: 5.2 kB at order 1, 6.1 kB at order
#: 2), h1p2 measured at 59k and 131k unknowns (31 and 33 kB: the 3D fill of its sparse factorization); h1p1 as
#: h1p2 (its fill per unknown is smaller: an upper bound)
BYTES_PER_UNKNOWN = {("tdnns", 1): 3200, ("tdnns", 2): 6400, ("h1p1", 1): 33000, ("h1p2", 2): 33000}
#: the elements whose bytes per unknown above are at FILL_REFERENCE unknowns and grow as the cube root of the
#: unknowns (a nested-dissection factor of a 3D mesh: nnz(L) ~ n^(4/3)); TDNNS order 1 measured with the
#: symmetric form and one factorization with the crack unknowns last: 2.34 kB per unknown at 415,172 unknowns,
#: 2.6 kB at 557,303, 2.78 kB at 661,250 (BENCHMARKS, "3D memory, the ellipse in 3 GB
#: and the accuracy option")
FILL_GROWS = (("tdnns", 1),)
FILL_REFERENCE = 1e6
#: the memory of a 3D solve's process before its unknowns (the interpreter, NGSolve, the mesh): 0.4 GB measured
BASE_MEMORY = 0.4e9
#: the smallest mesh size netgen is asked for, as a fraction of the body's diameter (as in 2D)
MIN_SIZE_RTOL = 1e-6
#: the body's mesh size near a crack, in its crack_h: netgen's grading alone lets the size grow
#: from crack_h at the faces by `grading` per unit distance, and the body a crack radius off the
#: crack then stays too coarse for order 1 (K_I 0.9-1% low on average on the default penny;
#: BENCHMARKS section 21)
NEAR_H_FACTOR = 1.25
#: ... but not below this fraction of the crack's size: what the body needs there is the crack's
#: scale, not the front's (a finer crack_h would otherwise fill the ball: 18,234 tetrahedra at
#: front_h = 0.15a against 8,553 at 0.2a)
NEAR_H_FLOOR_RTOL = 0.25
#: ... in the ball around the crack's centre of this many times its half size (its radius for a disc)
NEAR_RADIUS = 2.0
#: points of the trapezoidal rule over the shell around a crack's near ball
SHELL_POINTS = 256

#: `accuracy` (the relative error of K asked for along the fronts) to mesh sizes: the worst front point's error of
#: the default sizes (front_h DEFAULT_FRONT_H_RTOL of the crack's size, crack_h twice that: the penny at 0.2a, 0.14%
#: of Sneddon with the front integral's closed-form disc, `solid.front.NEAR_DISC_H`), taken as the bound that holds at
#: every size measured from 0.3a to 0.1a (0.14-0.41%: the integral's bias moves by 0.1-0.4% with the disc's radius;
#: BENCHMARKS, "3D K tighter than 1%")...
ACCURACY_AT_DEFAULT = 0.005
#: ... at front_h this fraction of the crack's size (the 3D default, `solid.scene.DEFAULT_FRONT_H_RTOL`) ...
ACCURACY_FRONT_H_RTOL = 0.1
#: ... falls as front_h to this power (least squares over front_h = 0.5a-0.1a on the penny before the disc,
#: BENCHMARKS section 21; with it the worst point no longer falls with front_h below 0.3a: kept as a conservative
#: interpolation between the default sizes and the coarsest) ...
ACCURACY_RATE = 1.19
#: ... and front_h is never coarser than this fraction of the crack's size (0.3a on a penny: 0.32%)
ACCURACY_COARSEST_RTOL = 0.15
#: crack_h is this many times the front_h `accuracy` gives (as the defaults)
ACCURACY_CRACK_H_RATIO = 2.0


#: The default sizes of a crack whose front comes near a face it does not cross (a deep surface crack's back face, an
#: embedded crack near a face; `ligament_caps`). front_h is at most the ligament (the body between the front and that
#: face) over this many elements, and crack_h at most its default ratio to front_h times that: at a/t = 0.8 the
#: crack-sized default left the ligament 0.25a 0.75 to 1.5 elements thick and the deepest point's K moved by 5-6% when
#: refined to a/9-a/12 (the guide's advice, front_h <= (t - a)/3; BENCHMARKS, "Deep and slender surface cracks")
LIGAMENT_ELEMENTS = 3.0
#: ... but front_h not below this fraction of the crack's size (a quarter of the default front_h: the a/c = 0.6,
#: a/t = 0.8 plate's ligament / 3 exactly); thinner ligaments keep this size and the scene refuses a sliver thinner
#: than one front_h (`solid.surface.LIGAMENT_FRONT_H`), the size guard one that would not fit in memory
LIGAMENT_FLOOR_RTOL = 0.025
#: where the body through the front's point nearest that face, along the way to it (a plate's thickness at a surface
#: crack), is thinner than this many times the crack's size, the default maxh is at most ...
THIN_BODY_RTOL = 1.0
#: ... this many times that thickness: the far field at maxh = t instead of 4-7 t raised the deepest point's K of the
#: a/t = 0.8 plates by 1.8% and brought the domain integral and the opening's K within 0.4% of each other
MAXH_THICKNESS = 1.0
#: steps along the way back through the body measuring its thickness (then bisected LIGAMENT_BISECTIONS times)
THICKNESS_STEPS, LIGAMENT_BISECTIONS = 256, 40
#: outline samples measuring a front's ligament (at most `solid.surface.STEP_SAMPLES` on a STEP part)
LIGAMENT_SAMPLES = 512

#: The default sizes of a crack that crosses a face (a surface or corner crack; `depth_cap`): front_h is at most the
#: crack's depth (`crack_depth`) over this many elements (the built-in `surface-crack`'s a/6): the crack-sized default
#: (0.1 of the inside diameter, ~2c) gave a/1 to a/5 on a/c = 0.2-1, the deepest point's K -20.7% to +4.6% from the
#: published tables and the opening's up to 22% off the domain integral; at a/6 the domain integral is within 1.7% of
#: the tables on 14 plates (a/c 0.2-1, a/t 0.2-0.8), and a/8 moves it by 0.4% at most for 19-46% more unknowns
#: (BENCHMARKS, "Default sizes for surface cracks by depth")
DEPTH_ELEMENTS = 6.0
#: ... but front_h not below this fraction of the crack's size (its inside diameter, 2c on a semi-ellipse): a/6 on
#: a/c = 0.2, the most slender plate measured (2c = 10a; at a/t = 0.6 1.0M unknowns and 2.4 GB peak); a shallower,
#: longer crack keeps this size (its memory)
DEPTH_FLOOR_RTOL = 1.0 / 60.0

_LIGAMENTS: dict = {}


def ligament_thickness(domain, crack) -> tuple[float, float]:
    """(ligament, thickness) of the crack's front: the least distance from the front (the outline's points inside the
    body) to a face the crack does not cross, and the body's thickness through that point along the way to that face
    (the distance to the face plus the way back until the body ends: a plate's thickness at a surface crack's deepest
    point). (inf, inf) where every face is crossed or the outline lies outside."""
    return _front_measures(domain, crack)[:2]


def crack_depth(domain, crack) -> float:
    """The depth of a crack that crosses faces: its extent into the body from the faces it crosses, the least over
    those faces of the largest distance of the outline's points inside the body from that face (a semi-ellipse's a
    from the face it crosses, a corner crack's smaller extent, min(a, c), from its two faces). inf for a crack that
    crosses no face (embedded) or lies outside."""
    return _front_measures(domain, crack)[2]


def _front_measures(domain, crack) -> tuple[float, float, float]:
    """(ligament, thickness, depth), cached per (domain, crack)."""
    key = (id(domain), id(crack))
    hit = _LIGAMENTS.get(key)
    if hit is not None and hit[0] is domain and hit[1] is crack:
        return hit[2]
    out = _measure_front(domain, crack)
    if len(_LIGAMENTS) > 256:
        _LIGAMENTS.clear()
    _LIGAMENTS[key] = (domain, crack, out)
    return out


def _measure_front(domain, crack) -> tuple[float, float, float]:
    outline = crack.outline(samples(domain, LIGAMENT_SAMPLES))
    dist = face_distances(domain, outline)
    inside = clearance(domain, outline) > 0
    if not inside.any():
        return math.inf, math.inf, math.inf
    depth = min(depths_from_faces(dist, inside).values(), default=math.inf)
    ell, T = _ligament_thickness(domain, outline, dist, inside)
    return ell, T, depth


def _ligament_thickness(domain, outline, dist, inside) -> tuple[float, float]:
    rest = {k: d[inside] for k, d in dist.items() if d.min() >= 0}  # the faces the crack does not cross
    if not rest:
        return math.inf, math.inf
    face = min(rest, key=lambda k: rest[k].min())
    j = int(np.argmin(rest[face]))
    p, ell = outline[inside][j], float(rest[face][j])
    eps = 1e-6 * domain.size  # the way to the face: the gradient of the distance to it
    grad = np.array([(face_distances(domain, p + eps * e)[face][0] - face_distances(domain, p - eps * e)[face][0])
                     / (2 * eps) for e in np.eye(3)])
    if not np.linalg.norm(grad) > 0:
        return ell, math.inf
    back = grad / np.linalg.norm(grad)  # the distance grows away from the face
    s = np.linspace(0.0, domain.size, samples(domain, THICKNESS_STEPS) + 1)[1:]
    out = np.flatnonzero(clearance(domain, p + np.outer(s, back)) <= 0)
    if not len(out):
        return ell, math.inf
    hi = s[out[0]]
    lo = s[out[0] - 1] if out[0] > 0 else 0.0
    for _ in range(LIGAMENT_BISECTIONS):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if clearance(domain, p + mid * back)[0] > 0 else (lo, mid)
    return ell, ell + 0.5 * (lo + hi)


def ligament_caps(domain, cracks, crack_size: float) -> tuple[float, float]:
    """(front_h cap, maxh cap) of the default sizes near faces the fronts do not cross (LIGAMENT_ELEMENTS,
    LIGAMENT_FLOOR_RTOL, THIN_BODY_RTOL, MAXH_THICKNESS; `crack_size` the smallest crack's, as the defaults') and of
    cracks that cross faces (`depth_cap`), the smaller: inf where no front comes near a face, no crack crosses one
    and the body is not thin."""
    front, maxh = math.inf, math.inf
    for c in cracks:
        ell, T = ligament_thickness(domain, c)
        size = inside_measures(domain, c)[0]
        front = min(front, ell / LIGAMENT_ELEMENTS)
        if T < THIN_BODY_RTOL * size:
            maxh = min(maxh, MAXH_THICKNESS * T)
    front = max(front, LIGAMENT_FLOOR_RTOL * crack_size) if math.isfinite(front) else front
    return min(front, depth_cap(domain, cracks)), maxh


def depth_cap(domain, cracks) -> float:
    """The front_h cap of cracks that cross faces: the least over them of the depth (`crack_depth`) over
    DEPTH_ELEMENTS, each not below DEPTH_FLOOR_RTOL of that crack's size inside the body; inf without such a crack."""
    cap = math.inf
    for c in cracks:
        depth = crack_depth(domain, c)
        if math.isfinite(depth):
            cap = min(cap, max(depth / DEPTH_ELEMENTS, DEPTH_FLOOR_RTOL * inside_measures(domain, c)[0]))
    return cap


#: A crack crossing a face of a box or a cylinder (a surface crack): its near ball (centred on the face, half of it
#: outside) and its front's tube (cut by the faces near a deep front) are counted inside the body only, at
#: INSIDE_RADII radii (the ball's and the tube's) of INSIDE_DIRECTIONS directions on spheres (INSIDE_ANGLES angles
#: on circles around INSIDE_FRONT_POINTS points of the front) ...
INSIDE_RADII, INSIDE_DIRECTIONS, INSIDE_ANGLES, INSIDE_FRONT_POINTS = 200, 128, 24, 48
#: ... and such a scene's density integral is this many times its parts: fitted on 8 meshes of the plates of
#: `benchmarks/newman_raju.py` at their default sizes before and after the ligament rule (a/c 0.4-1, a/t 0.2-0.8,
#: 1,430 to 9,247 tetrahedra): estimate / netgen 0.75-1.34 with it (1.4-1.7 without it, 2.5-4 before the parts were
#: counted inside), the other meshes' unchanged (a STEP part's cracks are counted as a box's: OCC's distances are
#: too slow to sample)
SURFACE_TETS = 0.78


def _volume(domain) -> float:
    if hasattr(domain, "volume"):  # a STEP part (solid.parts.StepPart)
        return float(domain.volume)
    if hasattr(domain, "lo"):
        return float(np.prod(np.asarray(domain.hi) - np.asarray(domain.lo)))
    return float(math.pi * domain.radius ** 2 * domain.height)


def _near_ball(crack, hc: float, H: float, g: float, V: float) -> tuple[float, float]:
    """(h_n, its part of the integral) of the body's size near `crack` (`solid.geometry.NEAR_*`): the ball of
    NEAR_RADIUS half sizes at h_n and the shell around it where h grows from h_n at the rate g up to H (both within
    the ball of the body's volume), less the bulk they replace; (H, 0) where there is none."""
    R = NEAR_RADIUS * 0.5 * crack.size
    hn = min(max(NEAR_H_FACTOR * hc, NEAR_H_FLOOR_RTOL * crack.size), H)
    if R <= 0 or hn >= H:
        return H, 0.0
    r_body = (3.0 * V / (4.0 * math.pi)) ** (1.0 / 3.0)
    Rb = min(R, r_body)
    part = 4.0 / 3.0 * math.pi * Rb ** 3 * (1.0 / hn ** 3 - 1.0 / H ** 3)
    r_end = min(R + (H - hn) / g, r_body)
    if r_end > Rb:
        r = np.linspace(Rb, r_end, SHELL_POINTS)
        f = 4.0 * math.pi * r ** 2 * (1.0 / (hn + g * (r - R)) ** 3 - 1.0 / H ** 3)
        part += float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(r)))
    return hn, part


def _fibonacci_sphere(n: int) -> np.ndarray:
    """n unit vectors spread evenly over the sphere."""
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    r, t = np.sqrt(1.0 - z * z), math.pi * (1.0 + math.sqrt(5.0)) * i
    return np.stack([r * np.cos(t), r * np.sin(t), z], axis=1)


def _inside_fraction(domain, points: np.ndarray) -> np.ndarray:
    """The fraction inside the body of each row of `points` (radii x samples x 3)."""
    m, n, _ = points.shape
    return (clearance(domain, points.reshape(-1, 3)) > 0).reshape(m, n).mean(axis=1)


def _near_ball_inside(domain, crack, hc: float, H: float, g: float) -> tuple[float, float]:
    """`_near_ball` of a surface crack counted inside the body: the integral of 1/h^3 - 1/H^3 over the ball and its
    shell times the fraction of each sphere around the crack's centre inside the body."""
    R = NEAR_RADIUS * 0.5 * crack.size
    hn = min(max(NEAR_H_FACTOR * hc, NEAR_H_FLOOR_RTOL * crack.size), H)
    if R <= 0 or hn >= H:
        return H, 0.0
    r = np.linspace(0.0, R + (H - hn) / g, INSIDE_RADII)
    h = np.where(r < R, hn, hn + g * (r - R))
    inside = _inside_fraction(domain, crack.center + r[:, None, None] * _fibonacci_sphere(INSIDE_DIRECTIONS)[None])
    f = 4.0 * math.pi * r ** 2 * inside * (1.0 / h ** 3 - 1.0 / H ** 3)
    return hn, float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(r)))


def _tube_inside(domain, crack, h0: float, Hb: float, g: float) -> float:
    """The front tube's integral per unit length (module docstring) counted inside the body: on circles around
    points of the front's part inside, normal to it, the fraction inside times 1/h^3 - 1/Hb^3, h = h0 + g r."""
    out = crack.outline(4 * INSIDE_FRONT_POINTS)
    tangent = np.roll(out, -1, axis=0) - np.roll(out, 1, axis=0)
    keep = clearance(domain, out) > 0
    P, T = out[keep][::4], tangent[keep][::4]
    if not len(P):
        return 0.0
    T = T / np.linalg.norm(T, axis=1)[:, None]
    e2 = np.cross(T, crack.normal)
    th = np.linspace(0.0, 2.0 * math.pi, INSIDE_ANGLES, endpoint=False)
    around = (np.cos(th)[None, :, None] * crack.normal[None, None] + np.sin(th)[None, :, None] * e2[:, None]).reshape(-1, 3)
    r = np.linspace(0.0, (Hb - h0) / g, INSIDE_RADII)
    inside = _inside_fraction(domain, np.repeat(P, INSIDE_ANGLES, axis=0)[None] + r[:, None, None] * around[None])
    f = 2.0 * math.pi * r * inside * (1.0 / (h0 + g * r) ** 3 - 1.0 / Hb ** 3)
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(r)))


def density_parts(scene, maxh=None, crack_h=None, front_h=None, grading=None) -> dict[str, float]:
    """The bulk's, the crack faces', the fronts' and the near balls' parts of the integral of 1 / h^3 (module
    docstring): each crack's faces and front grade into its near ball's size, which grades into maxh; a surface
    crack's near ball and tube counted inside the body, and the scene's parts then times SURFACE_TETS."""
    s = scene.mesh_sizes(maxh, crack_h, front_h, grading)
    H, g = s["maxh"], s["grading"]
    hc = min(s["crack_h"], H)
    h0 = min(s["front_h"], hc)
    V = _volume(scene.domain)
    parts = {"maxh": V / H ** 3, "crack_h": 0.0, "front_h": 0.0, "near": 0.0}
    surface = False
    for c in scene.cracks:
        _, A, L = inside_measures(scene.domain, c)  # a surface crack: its part inside the body
        clip = not is_step(scene.domain) and crosses(scene.domain, c)
        surface |= clip
        Hb, near = _near_ball_inside(scene.domain, c, hc, H, g) if clip else _near_ball(c, hc, H, g, V)
        parts["near"] += near
        if A > 0 and hc < Hb:
            D = min((Hb - hc) / g, V / (2.0 * A))
            sc = hc + g * D
            parts["crack_h"] += max(2.0 * A * ((1.0 / (2.0 * g)) * (1.0 / hc ** 2 - 1.0 / sc ** 2) - D / Hb ** 3), 0.0)
        if L > 0 and h0 < Hb and clip:
            parts["front_h"] += L * _tube_inside(scene.domain, c, h0, Hb, g)
        elif L > 0 and h0 < Hb:
            R = min((Hb - h0) / g, math.sqrt(V / (math.pi * L)))
            s0 = h0 + g * R
            tube = (2.0 * math.pi / g ** 2) * (0.5 / h0 - 1.0 / s0 + 0.5 * h0 / s0 ** 2)
            parts["front_h"] += max(L * (tube - math.pi * R ** 2 / Hb ** 3), 0.0)
    return {k: SURFACE_TETS * v for k, v in parts.items()} if surface else parts


def accuracy_sizes(scene, accuracy: float) -> dict[str, float]:
    """The front_h and crack_h that give K within `accuracy` (relative, at the worst front point) along the fronts
    of `scene` by the measured rate: front_h = ACCURACY_FRONT_H_RTOL d (accuracy / ACCURACY_AT_DEFAULT)^(1 /
    ACCURACY_RATE), d the smallest crack's size, at most ACCURACY_COARSEST_RTOL d; crack_h = ACCURACY_CRACK_H_RATIO
    front_h. Smaller for a smaller accuracy (monotone); the scene's own front_h and crack_h are not used.

    The rate was measured on a penny far from the faces: near a face a front does not cross, front_h is moreover at
    most the default's cap (`ligament_caps`: a third of the ligament, not below LIGAMENT_FLOOR_RTOL of the crack's
    size), whatever the accuracy; maxh, which `accuracy` does not set, takes its default (with its cap at a thin
    body's thickness when the scene sets no sizes)."""
    d = min((c.size for c in scene.cracks), default=scene.size)
    h = ACCURACY_FRONT_H_RTOL * d * (float(accuracy) / ACCURACY_AT_DEFAULT) ** (1.0 / ACCURACY_RATE)
    h = min(h, ACCURACY_COARSEST_RTOL * d)
    if scene.cracks:
        inside = min(inside_measures(scene.domain, c)[0] for c in scene.cracks)
        h = min(h, ligament_caps(scene.domain, scene.cracks, inside)[0])
    return {"front_h": h, "crack_h": ACCURACY_CRACK_H_RATIO * h}


def estimate_tets(scene, maxh=None, crack_h=None, front_h=None, grading=None) -> float:
    """The estimated tetrahedra of netgen's mesh of `scene` at these sizes (the scene's where None)."""
    return sum(_weighted(density_parts(scene, maxh, crack_h, front_h, grading)).values())


def _weighted(parts: dict[str, float]) -> dict[str, float]:
    """The tetrahedra of each part of the density integral."""
    return {"maxh": TETS_PER_BULK * parts["maxh"], "crack_h": TETS_PER_FACES * parts["crack_h"],
            "front_h": TETS_PER_FRONT * parts["front_h"], "near": TETS_PER_NEAR * parts["near"]}


def peak_memory(unknowns: float, element: str = "tdnns", order: int = 1) -> float:
    """The estimated peak resident memory in bytes of a 3D solve with `unknowns` (module docstring)."""
    per = BYTES_PER_UNKNOWN[(element, order)]
    if (element, order) in FILL_GROWS:  # the factor's fill per unknown grows as the cube root of the unknowns
        per *= (unknowns / FILL_REFERENCE) ** (1.0 / 3.0)
    return BASE_MEMORY + unknowns * per


@dataclass(frozen=True)
class SolidSizeEstimate:
    """The estimated size of one 3D solve: tetrahedra, unknowns, peak memory in bytes, and the mesh size that owes
    most of the tetrahedra (`culprit`, its value `size`)."""

    tets: float
    unknowns: float
    memory: float
    culprit: str
    size: float

    def describe(self) -> str:
        return f"about {self.tets:.3g} tetrahedra, {self.unknowns:.3g} unknowns and {_bytes(self.memory)} of memory"


def estimate_size(scene, element: str = "tdnns", order: int | None = None, maxh=None, crack_h=None, front_h=None,
                  grading=None) -> SolidSizeEstimate:
    """Estimated tetrahedra, unknowns and peak memory of a 3D solve of `scene` (module docstring)."""
    order = order or (2 if element == "h1p2" else 1)
    weighted = _weighted(density_parts(scene, maxh, crack_h, front_h, grading))
    tets = sum(weighted.values())
    unknowns = tets * UNKNOWNS_PER_TET[(element, order)]
    weighted["crack_h"] += weighted.pop("near")  # the body's size near a crack follows its crack_h
    culprit = max(weighted, key=weighted.get)
    size = scene.mesh_sizes(maxh, crack_h, front_h, grading)[culprit]
    return SolidSizeEstimate(tets=tets, unknowns=unknowns, memory=peak_memory(unknowns, element, order),
                             culprit=culprit, size=size)


def check_mesh_sizes(scene, maxh=None, crack_h=None, front_h=None, grading=None) -> None:
    """Refuse sizes netgen cannot mesh, by name: not a finite number > 0, grading above 1 (netgen gives up and spins:
    grading 5 took 83 s CPU without an answer), a size below MIN_SIZE_RTOL of the body's diameter."""
    given = {"maxh": maxh, "crack_h": crack_h, "front_h": front_h, "grading": grading}
    for name, value in given.items():
        if value is not None and (isinstance(value, (bool, np.bool_))
                                  or not isinstance(value, (int, float, np.integer, np.floating))
                                  or not math.isfinite(float(value)) or not float(value) > 0):
            raise InputError(f"{name} = {value!r}: must be a finite number > 0")
    sizes = scene.mesh_sizes(maxh, crack_h, front_h, grading)
    if sizes["grading"] > 1.0:
        where = "" if grading is not None else " (the scene's [mesh] grading)"
        raise InputError(f"grading = {sizes['grading']:g}{where}: must lie in (0, 1] (netgen's default is 0.3; "
                         f"above 1 netgen gives up meshing)")
    D = scene.size
    for name in ("maxh", "crack_h", "front_h"):
        if sizes[name] < MIN_SIZE_RTOL * D:
            where = "" if given[name] is not None else " (the scene's or the default)"
            raise InputError(f"{name} = {sizes[name]:g}{where}: below the smallest mesh size netgen meshes, "
                             f"{MIN_SIZE_RTOL:g} of the body's diameter {D:g}; give {name} >= {MIN_SIZE_RTOL * D:.3g}")


def check_size(scene, element: str = "tdnns", order: int | None = None, maxh=None, crack_h=None, front_h=None,
               grading=None, max_dof=None) -> SolidSizeEstimate:
    """Refuse a 3D solve, with one line before any meshing, whose mesh sizes netgen cannot mesh
    (`check_mesh_sizes`), whose estimated unknowns exceed the ceiling (max_dof, default DEFAULT_MAX_DOF) or, with
    max_dof None, whose estimated peak memory exceeds MEMORY_FRACTION of what this process may still allocate. The
    line names the size that owes most of the tetrahedra, the estimate and the override; the estimate otherwise."""
    check_max_dof(max_dof)
    check_mesh_sizes(scene, maxh, crack_h, front_h, grading)
    est = estimate_size(scene, element, order, maxh, crack_h, front_h, grading)
    others = " or ".join(k for k in ("maxh", "crack_h", "front_h") if k != est.culprit)
    how = (f"use a larger {est.culprit} (it owes most of the tetrahedra; or a larger {others}), or raise the limit "
           f"with max_dof=N in Python or --max-dof N on the command line")
    case = f"{est.culprit} = {est.size:g}: scene {scene.name!r}, element {element!r}"
    ceiling = DEFAULT_MAX_DOF if max_dof is None else max_dof
    if est.unknowns > ceiling:
        limit = "the default ceiling" if max_dof is None else "max_dof"
        raise InputError(f"{case} would need {est.describe()}; that exceeds {limit} of {int(ceiling)} unknowns; {how}")
    if max_dof is None:
        avail = available_memory()
        if avail is not None and est.memory > MEMORY_FRACTION * avail:
            kind = next((k for k, v in memory_limits().items() if v == avail), "machine")
            where = {"machine": "this machine has", "address space": "this process's address-space limit leaves",
                     "cgroup": "this process's cgroup memory limit leaves"}.get(kind, "this process has")
            raise InputError(f"{case} would need {est.describe()}; {where} {_bytes(avail)} available; {how} (at "
                             f"your own risk)")
    return est
