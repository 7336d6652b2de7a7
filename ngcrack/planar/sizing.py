"""How big a solve will be, before meshing: triangles, unknowns, memory; the size guard.

A mistyped mesh size (maxh 1e-7 for 1e-2) would otherwise start netgen on 1e16
triangles. `check_size` estimates the request in microseconds from the scene's geometry
and refuses it (a ValueError, exit code 2 on the command line) when the estimated
unknowns exceed the ceiling `max_dof` or their memory exceeds what this process may
still allocate: the least of the machine's available memory, the address-space limit
(``ulimit -v``, RLIMIT_AS) and the cgroup's memory limit (`memory_limits`). The message
names the size that owes most of the triangles (maxh, crack_h or tip_h). A size below
``MIN_SIZE_RTOL`` (1e-6) of the body's diameter is refused even when the count is small
(`check_mesh_sizes`): netgen fails, hangs or crashes on such sizes (measured on griffith's
graded tip: 2e-8 of the diameter meshes in a second, 1e-8 fails, 4.5e-9 hangs, below
that the interpreter dies).

The triangle estimate. Netgen makes triangles of side about the local mesh size h(x),
so a region of area dA holds about TRIANGLES_PER_AREA dA / h^2 of them (4/sqrt(3) = 2.31
for equilateral triangles of side h; 2.25 fitted). The local size is maxh = H away from
the cracks; the crack segments ask for crack_h, the crack end points for tip_h, and netgen
lets the size grow linearly with the distance d from such a feature, h = h_f + g d (g the
grading), until it reaches H. Integrating 1 / h^2 in closed form:

    N = c [ A / H^2
            + 2 L ( (1/g)(1/h_c - 1/(h_c + g D)) - D / H^2 )                    (cracks)
            + sum_ends theta ( (1/g^2)(ln(s/h_0) + h_0/s - 1) - R^2 / (2 h_c'^2) ) ]  (ends)

with A the polygon's area, L the total crack length, h_c = min(crack_h, H), D = min((H -
h_c)/g, A/(2L)) the band's width (at most what fills the body), h_0 = tip_h, h_c' the
size the end's refinement grows into (h_c), R = min((h_c' - h_0)/g, sqrt(2A/theta)),
s = h_0 + g R, theta = 2 pi for an end inside the body and pi for one on its boundary.
Measured against netgen on 47 meshes of 9 scenes from 40 to 1.2e5 triangles (graded and
uniform; `benchmarks/size_estimate.py`, BENCHMARKS.md): estimate / netgen is 0.81-1.14
(median 0.98) from 1000 triangles up, and up to 1.41 on meshes of 40-200 triangles.

A hole adds the band along its edges like a crack's, on the body's side only, with
h_c its edge size (`Hole.edge_h`) and 2 L replaced by its perimeter. A scene that gives
no size at all gets `default_mesh_sizes` (from its shortest crack).

Unknowns per triangle (all unknowns, `ndof["total"]`, measured on paper-2 and griffith)
and peak memory per unknown (BENCHMARKS.md, section 1: 1.0-1.4 kB for the mixed elements
and 3.7-4.0 kB for the displacement baselines at 1e6 unknowns) are element constants.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..core.memory import (  # noqa: F401  (re-exported)
    DEFAULT_MAX_DOF,
    MEMORY_FRACTION,
    available_memory,
    check_max_dof,
    memory_limits,
)
from ..core.memory import (
    format_bytes as _bytes,
)
from .scene.types import MAX_SCALE, MIN_SIZE_RTOL

#: netgen triangles per unit area at mesh size h: TRIANGLES_PER_AREA / h^2 (fitted; 4/sqrt(3) = 2.31 equilateral)
TRIANGLES_PER_AREA = 2.25
#: unknowns (total, before condensation) per triangle, measured: {element: {order: value}}
UNKNOWNS_PER_TRIANGLE = {
    "peers": {None: 13.6},
    "bdm": {None: 21.2, 1: 21.2, 2: 42.0, 3: 70.0},
    "tdnns": {None: 19.2, 1: 19.2, 2: 37.3, 3: 60.4},
    "h1p1": {None: 1.1},
    "h1p2": {None: 4.2},
}
#: peak resident memory per unknown in bytes (BENCHMARKS.md: the largest measured at 1e6 unknowns)
BYTES_PER_UNKNOWN = {"peers": 1100, "bdm": 1400, "tdnns": 1450, "h1p1": 4000, "h1p2": 4000}
#: netgen's default growth rate of the mesh size: the grading of a scene that gives none
DEFAULT_GRADING = 0.3
#: default sizes of a scene that gives none (`default_mesh_sizes`): maxh a tenth of the
#: diameter; crack_h and tip_h the shortest crack's length over these
DEFAULT_MAXH_FRACTION = 0.1
DEFAULT_CRACK_DIVISOR = 40
DEFAULT_TIP_DIVISOR = 400
#: the grading of those default sizes (milder than netgen's 0.3: the lowest-order PEERS
#: stress needs the crack's perturbation resolved about a crack length around it)
DEFAULT_CRACK_GRADING = 0.2


@dataclass(frozen=True)
class SizeEstimate:
    """The estimated size of one solve: triangles, unknowns, peak memory in bytes."""

    triangles: float
    unknowns: float
    memory: float
    maxh: float
    culprit: str = "maxh"
    size: float | None = None

    def describe(self) -> str:
        return (f"about {self.triangles:.3g} triangles, {self.unknowns:.3g} unknowns and "
                f"{_bytes(self.memory)} of memory")


def default_mesh_sizes(scene) -> dict:
    """The mesh sizes a scene gets when neither it ([mesh]) nor the caller gives any size.

    maxh = DEFAULT_MAXH_FRACTION (1/10) of the body's diameter. With cracks, from the
    length L of the shortest crack: crack_h = L / DEFAULT_CRACK_DIVISOR (40) along every
    crack and tip_h = L / DEFAULT_TIP_DIVISOR (400) at every crack end, graded by netgen at
    the scene's grading (DEFAULT_CRACK_GRADING, 0.2, if it gives none); each crack then has
    at least 40 edges. Neither size goes below 10 MIN_SIZE_RTOL (1e-5) of the diameter.
    Returns {"maxh", "crack_h", "tip_h", "grading", "rule"} (crack_h, tip_h None without
    cracks; "rule" says in words where the sizes come from).
    """
    D = scene.diameter
    out = {"maxh": DEFAULT_MAXH_FRACTION * D, "crack_h": None, "tip_h": None,
           "grading": float(scene.grading or DEFAULT_GRADING),
           "rule": f"maxh = diameter / {1 / DEFAULT_MAXH_FRACTION:g}"}
    if scene.cracks and scene.grading is None:
        out["grading"] = DEFAULT_CRACK_GRADING
    if scene.cracks:
        L = min(c.length for c in scene.cracks)
        floor = 10 * MIN_SIZE_RTOL * D  # a crack far shorter than the body: netgen's limit
        out["tip_h"] = max(L / DEFAULT_TIP_DIVISOR, floor)
        out["crack_h"] = max(L / DEFAULT_CRACK_DIVISOR, out["tip_h"])
        out["rule"] += (f"; crack_h = L / {DEFAULT_CRACK_DIVISOR:g} and tip_h = L / {DEFAULT_TIP_DIVISOR:g}, "
                        f"L = {L:g} the shortest crack's length")
    return out


def sizes_given(scene, maxh=None, tip_h=None, crack_h=None) -> bool:
    """Whether the caller or the scene's [mesh] gives any of maxh, tip_h, crack_h."""
    return any(v is not None for v in (maxh, tip_h, crack_h, scene.maxh, scene.tip_h, scene.crack_h))


def mesh_sizes(scene, maxh=None, tip_h=None, crack_h=None, grading=None) -> tuple[float, float | None, float | None, float]:
    """(maxh, tip_h, crack_h, grading) as `geometry.make_mesh` resolves them: the arguments
    over the scene's [mesh]; where neither gives any size, `default_mesh_sizes`."""
    if not sizes_given(scene, maxh, tip_h, crack_h):
        d = default_mesh_sizes(scene)
        g = grading if grading is not None else d["grading"]
        return float(d["maxh"]), d["tip_h"], d["crack_h"], float(g)
    g = grading if grading is not None else (scene.grading or DEFAULT_GRADING)
    H = maxh if maxh is not None else (scene.maxh if scene.maxh is not None else DEFAULT_MAXH_FRACTION * scene.diameter)
    tip = tip_h if tip_h is not None else scene.tip_h
    ch = crack_h if crack_h is not None else scene.crack_h
    return float(H), tip, ch, float(g)


def describe_mesh_sizes(scene, maxh=None, tip_h=None, crack_h=None, grading=None) -> str:
    """One line: the sizes a solve will mesh with and where they come from (for the CLI)."""
    H, tip, ch, g = mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    parts = [f"maxh {H:.4g}"] + [f"{k} {v:.4g}" for k, v in (("crack_h", ch), ("tip_h", tip)) if v is not None]
    parts.append(f"grading {g:g}")
    where = ("the scene has no [mesh] sizes: " + default_mesh_sizes(scene)["rule"]
             if not sizes_given(scene, maxh, tip_h, crack_h) else "given")
    return f"mesh sizes: {', '.join(parts)} ({where})"


def _density_parts(scene, maxh=None, tip_h=None, crack_h=None, grading=None) -> dict[str, float]:
    """The closed form of the module docstring, term by term: the triangles (before the
    factor TRIANGLES_PER_AREA) owed to maxh (the body), crack_h (the band along the
    cracks) and tip_h (the graded ends). Safe for sizes down to 1e-300 (no overflow)."""
    H, tip, ch, g = mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    A = scene.area
    L = sum(c.length for c in scene.cracks)
    r = math.sqrt(A) / H
    parts = {"maxh": r * r, "crack_h": 0.0, "tip_h": 0.0}
    for k, hole in enumerate(scene.holes):
        hh = min(hole.edge_h, H)
        if hh < H:  # the band of refinement inside the body along the hole's edges (one side)
            P = math.pi * hole.size
            D = min((H - hh) / g, A / P)
            parts[f"hole[{k}].maxh"] = P * ((1 / hh - 1 / (hh + g * D)) / g - D / H * (1 / H))
    hc = min(H, ch) if ch else H
    if L and hc < H:  # the band of refinement along the cracks
        D = min((H - hc) / g, A / (2 * L))
        parts["crack_h"] = 2 * L * ((1 / hc - 1 / (hc + g * D)) / g - D / H * (1 / H))
    if tip and tip < hc:  # the graded refinement at every crack end
        for i in range(len(scene.cracks)):
            for on_boundary in scene.crack_end_on_boundary(i):
                theta = math.pi if on_boundary else 2 * math.pi
                R = min((hc - tip) / g, math.sqrt(2 * A / theta))
                s = tip + g * R
                parts["tip_h"] += theta * ((math.log(s / tip) + tip / s - 1) / g**2 - (R / hc) ** 2 / 2)
    return parts


def estimate_triangles(scene, maxh=None, tip_h=None, crack_h=None, grading=None) -> float:
    """The number of triangles netgen will make (the closed form of the module docstring)."""
    return TRIANGLES_PER_AREA * sum(_density_parts(scene, maxh, tip_h, crack_h, grading).values())


def unknowns_per_triangle(element: str, order: int | None = None) -> float:
    per = UNKNOWNS_PER_TRIANGLE[element]
    return per.get(order, per[None])


def estimate_size(scene, element: str, maxh=None, tip_h=None, crack_h=None, grading=None,
             order: int | None = None) -> SizeEstimate:
    """Estimated triangles, unknowns and peak memory of `solve(scene, element, ...)`.

    ``culprit`` names the size that owes the most triangles (maxh, crack_h or tip_h) and
    ``size`` its value, for messages."""
    H, tip, ch, _ = mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    parts = _density_parts(scene, maxh, tip_h, crack_h, grading)
    tri = TRIANGLES_PER_AREA * sum(parts.values())
    dof = tri * unknowns_per_triangle(element, order)
    culprit = max(parts, key=parts.get)
    size = {"maxh": H, "crack_h": ch, "tip_h": tip}.get(culprit)
    if size is None:  # a hole's edges
        size = scene.holes[int(culprit[5:culprit.index("]")])].edge_h
    return SizeEstimate(triangles=tri, unknowns=dof, memory=dof * BYTES_PER_UNKNOWN[element], maxh=H,
                        culprit=culprit, size=size)


def check_mesh_sizes(scene, maxh=None, tip_h=None, crack_h=None, grading=None) -> None:
    """Refuse a mesh size (given or the scene's) netgen cannot mesh: not a finite number
    > 0 (numpy numbers are numbers), or below MIN_SIZE_RTOL or above MAX_SCALE times the
    body's diameter. The ValueError names the field (maxh, tip_h, crack_h, grading)."""
    for name, value in (("maxh", maxh), ("tip_h", tip_h), ("crack_h", crack_h), ("grading", grading)):
        if value is None:
            continue
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)) \
                or not math.isfinite(float(value)) or not float(value) > 0:
            raise InputError(f"{name} = {value!r}: must be a finite number > 0")
    if grading is not None and float(grading) > 1.0:
        raise InputError(f"grading = {grading!r}: must lie in (0, 1] (netgen's default is 0.3)")
    H, tip, ch, _ = mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    D = scene.diameter
    for name, value in (("maxh", H), ("crack_h", ch), ("tip_h", tip)):
        if value is None:
            continue
        if {"maxh": maxh, "crack_h": crack_h, "tip_h": tip_h}[name] is not None:
            fld = name
        elif getattr(scene, name) is not None:
            fld = f"{name} (the scene's [mesh] {name})"
        else:
            fld = f"{name} (the default: {default_mesh_sizes(scene)['rule']})"
        if value < MIN_SIZE_RTOL * D:
            raise InputError(
                f"{fld} = {float(value):g}: below the smallest mesh size netgen meshes reliably, "
                f"{MIN_SIZE_RTOL:g} of the body's diameter {D:g} (= {MIN_SIZE_RTOL * D:g}; smaller sizes "
                f"make netgen fail, hang or crash, measured); give {name} >= {MIN_SIZE_RTOL * D:.3g}")
        if value > MAX_SCALE * D:
            raise InputError(f"{fld} = {float(value):g}: above {MAX_SCALE:g} times the body's diameter "
                              f"{D:g}; give a size at most the diameter")


def check_size(scene, element: str, maxh=None, tip_h=None, crack_h=None, grading=None, order=None,
               max_dof=None, what: str | None = None) -> SizeEstimate:
    """Refuse a solve whose estimated unknowns exceed the ceiling or the process's memory,
    or whose mesh sizes netgen cannot mesh (`check_mesh_sizes`).

    max_dof None: the ceiling is DEFAULT_MAX_DOF and the estimated peak memory must fit
    in MEMORY_FRACTION of the memory this process may still allocate (the least of the
    machine's, the address-space limit's and the cgroup's: `memory_limits`). An explicit
    max_dof replaces both (the caller takes the memory on). Raises ValueError naming the
    size that owes the most triangles (maxh, crack_h or tip_h), the estimate and the
    override; returns the estimate otherwise.
    """
    check_max_dof(max_dof)
    for name, value in (("maxh", maxh), ("tip_h", tip_h), ("crack_h", crack_h), ("grading", grading)):
        if value is not None and (isinstance(value, (bool, np.bool_))
                                  or not isinstance(value, (int, float, np.integer, np.floating))
                                  or not math.isfinite(float(value)) or not float(value) > 0):
            raise InputError(f"{name} = {value!r}: must be a finite number > 0")
    est = estimate_size(scene, element, maxh, tip_h, crack_h, grading, order)
    if not math.isfinite(est.unknowns):
        check_mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    ceiling = DEFAULT_MAX_DOF if max_dof is None else max_dof
    case = what or f"scene {scene.name!r}, element {element!r}"
    others = ", ".join(k for k in ("maxh", "crack_h", "tip_h") if k != est.culprit)
    how = (f"use a larger {est.culprit} (it owes most of the triangles; or a larger {others}), or raise "
           f"the limit with max_dof=N in Python or --max-dof N on the command line")
    head = f"{est.culprit} = {est.size:g}"
    if est.unknowns > ceiling:
        limit = "the default ceiling" if max_dof is None else "max_dof"
        raise InputError(f"{head}: {case} would need {est.describe()}; that exceeds {limit} of "
                          f"{int(ceiling)} unknowns; {how}")
    check_mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    if max_dof is None:
        avail = available_memory()
        if avail is not None:
            kind = next((k for k, v in memory_limits().items() if v == avail), "machine")
            if est.memory > MEMORY_FRACTION * avail:
                where = {"machine": "this machine has",
                         "address space": "this process's address-space limit (ulimit -v) leaves",
                         "cgroup": "this process's cgroup memory limit leaves"}[kind]
                raise InputError(f"{head}: {case} would need {est.describe()}; {where} "
                                  f"{_bytes(avail)} available; {how} (at your own risk)")
    return est


# ------------------------------------------------------------------ thin parts
#: below this many mesh sizes across its thinnest part, an element is refused (it is
#: unstable there: singular, or an answer off by a factor), measured (README "Coarse meshes")
MIN_ACROSS_REFUSE = {"peers": 1.6}
#: below this many mesh sizes across, an element's answer is known to be more than
#: COARSE_ERROR off (measured on a plain cantilever and on paper-1 and paper-2): a warning
MIN_ACROSS_WARN = {"peers": 2.9, "tdnns": 1.6, "h1p1": 4.0}
#: the error level that defines "safe" for MIN_ACROSS_WARN (mean deflection, relative)
COARSE_ERROR = 0.2
#: elements and orders the tables above apply to (tdnns order 2 and 3 are safe on one layer)
_ORDERED_SAFE = {("tdnns", 2), ("tdnns", 3)}
#: sample points per boundary piece and crack face, in the middle MIDDLE of its length;
#: a piece counts by the median of its samples (a thin stretch, not a corner's wedge)
SAMPLES_PER_PIECE = 9
MIDDLE = (0.25, 0.75)
#: quadrature points along a ray for the number of mesh sizes across
RAY_POINTS = 8
#: pieces of a circular hole sampled for the thinnest part
HOLE_PIECES = 16
#: at most this many pieces (boundary pieces and crack faces) cast rays: of more, every
#: k-th (a polygon of 4000 short edges is measured in seconds, not minutes)
MAX_RAY_PIECES = 600


class CoarseMeshWarning(UserWarning):
    """The mesh is so coarse across a thin part that the element's answer is known to be poor."""


@dataclass(frozen=True)
class ThinPart:
    """The thinnest place of the body: `across` mesh sizes over a width `width` at `point`,
    measured along `normal` from a boundary or crack-face point."""

    across: float
    width: float
    point: tuple[float, float]
    normal: tuple[float, float]


def local_size(scene, points: np.ndarray, maxh=None, tip_h=None, crack_h=None, grading=None) -> np.ndarray:
    """The mesh size netgen aims at at `points` (N, 2): min(H, h_f + g d_f) over the crack
    segments (h_f = crack_h) and the crack ends (h_f = tip_h), as in `estimate_triangles`."""
    H, tip, ch, g = mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    h = np.full(len(points), H)
    for hole in scene.holes:
        if hole.edge_h < H:
            loop = np.asarray(hole.loop(HOLE_PIECES), dtype=float)
            h = np.minimum(h, hole.edge_h + g * _polyline_distance(points, np.vstack([loop, loop[:1]])))
    for crack in scene.cracks:
        if ch and ch < H:
            h = np.minimum(h, ch + g * _polyline_distance(points, np.asarray(crack.points, dtype=float)))
        if tip:
            for end in (crack.points[0], crack.points[-1]):
                h = np.minimum(h, tip + g * np.linalg.norm(points - np.asarray(end), axis=1))
    return h


def _polyline_distance(points: np.ndarray, line: np.ndarray) -> np.ndarray:
    """The distance of each point to the polyline (GEOS's numbers: shapely's on many pairs)."""
    from .scene.measures import point_segment_distances
    from .scene.planar import BRUTE_FORCE_PAIRS

    points = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(points) * (len(line) - 1) > BRUTE_FORCE_PAIRS:
        import shapely

        return shapely.distance(shapely.points(points), shapely.LineString(line))
    rows = max(1, BRUTE_FORCE_PAIRS // max(len(line) - 1, 1))
    return np.concatenate([point_segment_distances(points[i:i + rows, None], line[None, :-1], line[None, 1:]).min(axis=1)
                           for i in range(0, len(points), rows)] or [np.zeros(0)])


def _rays_hitting(X0: np.ndarray, X1: np.ndarray, A: np.ndarray, B: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The pairs (ray i, wall segment j) where the segment X0[i]-X1[i] meets A[j]-B[j]."""
    from .scene.measures import segment_distances
    from .scene.planar import BRUTE_FORCE_PAIRS

    if len(X0) * len(A) > BRUTE_FORCE_PAIRS:  # shapely's spatial index
        import shapely

        rays = shapely.linestrings(np.stack([X0, X1], axis=1))
        return shapely.STRtree(shapely.linestrings(np.stack([A, B], axis=1))).query(rays, predicate="intersects")
    rows = max(1, BRUTE_FORCE_PAIRS // max(len(A), 1))
    hits = [np.nonzero(segment_distances(X0[i:i + rows, None], X1[i:i + rows, None], A[None], B[None]) == 0.0)
            for i in range(0, len(X0), rows)]
    return (np.concatenate([r + i * rows for i, (r, _) in enumerate(hits)]).astype(int),
            np.concatenate([c for _, c in hits]).astype(int))


def thinnest_part(scene, maxh=None, tip_h=None, crack_h=None, grading=None) -> ThinPart | None:
    """Where the body is fewest mesh sizes across, before meshing.

    From sample points on every boundary piece and on both faces of every crack segment,
    a ray goes into the body along the inward normal to the next boundary or crack; the
    number of mesh sizes across is the integral of 1/h (`local_size`) along it. Each piece
    counts by the median over its samples in the middle half of its length (so the wedge
    at an acute corner is not a thin part); the least over the pieces is returned. A
    one-layer strip is about 1.15 across (a layer of triangles of side h is 0.87 h high).
    The rays are cast together (through shapely's STRtree of the walls where there are
    many); of more than MAX_RAY_PIECES pieces, every k-th casts rays.
    """
    holes = scene.holes
    chains = [list(scene.polygon) + [scene.polygon[0]]]
    chains += [list(h.loop(HOLE_PIECES)) + [h.loop(HOLE_PIECES)[0]] for h in holes]
    chains += [list(c.points) for c in scene.cracks]
    A = np.concatenate([np.asarray(c[:-1], float) for c in chains])  # wall segments a-b
    B = np.concatenate([np.asarray(c[1:], float) for c in chains])
    starts = []  # (point, direction along the piece, inward normal)
    pieces = list(scene.edge_pieces()) + (scene.hole_pieces(HOLE_PIECES) if holes else [])
    for _, p, q in pieces:
        d = np.subtract(q, p)
        starts.append((np.asarray(p, float), d, np.array([-d[1], d[0]]) / np.linalg.norm(d)))
    for crack in scene.cracks:
        for (p, q), nu in zip(crack.segments, crack.normals()):
            for sign in (1.0, -1.0):
                starts.append((np.asarray(p, float), np.subtract(q, p), sign * np.asarray(nu)))
    if not starts:
        return None
    stride = -(-len(starts) // MAX_RAY_PIECES)  # many short pieces: every stride-th of them
    starts = starts[::stride]
    reach = 2.0 * scene.diameter
    ts = np.linspace(*MIDDLE, SAMPLES_PER_PIECE)
    P0 = np.array([p for p, _, _ in starts])
    D = np.array([d for _, d, _ in starts])
    Nn = np.array([n for _, _, n in starts])
    # every ray, piece by piece: from x = p + t d along the inward normal, to the first wall hit
    X = (P0[:, None, :] + ts[None, :, None] * D[:, None, :]).reshape(-1, 2)
    N = np.repeat(Nn, len(ts), axis=0)
    ray_i, seg_j = _rays_hitting(X + 1e-9 * reach * N, X + reach * N, A, B)
    width = np.full(len(X), np.inf)
    if len(ray_i):
        e = B[seg_j] - A[seg_j]
        denom = N[ray_i, 0] * e[:, 1] - N[ray_i, 1] * e[:, 0]
        rel = A[seg_j] - X[ray_i]
        with np.errstate(divide="ignore", invalid="ignore"):
            dist_hit = np.where(np.abs(denom) > 0, (rel[:, 0] * e[:, 1] - rel[:, 1] * e[:, 0]) / denom, np.inf)
        # a wall along the ray (parallel): the nearer of its end points ahead
        along = np.minimum(*(np.where(v > 0, v, np.inf) for v in
                             (np.einsum("ij,ij->i", A[seg_j] - X[ray_i], N[ray_i]),
                              np.einsum("ij,ij->i", B[seg_j] - X[ray_i], N[ray_i]))))
        dist_hit = np.where(np.abs(denom) > 0, dist_hit, along)
        np.minimum.at(width, ray_i, np.where(dist_hit > 0, dist_hit, np.inf))
    hit = np.isfinite(width)
    s = (np.arange(RAY_POINTS) + 0.5) / RAY_POINTS
    w = np.where(hit, width, 0.0)
    pts = (X[:, None, :] + (s[None, :, None] * w[:, None, None]) * N[:, None, :]).reshape(-1, 2)
    h = local_size(scene, pts, maxh, tip_h, crack_h, grading).reshape(len(X), RAY_POINTS)
    across = np.sum(w[:, None] / RAY_POINTS / h, axis=1)
    best = None
    for k in range(len(starts)):
        rows = [r for r in range(k * len(ts), (k + 1) * len(ts)) if hit[r]]
        if not rows:
            continue
        # the piece's median: a part is thin along a stretch, not at a corner's wedge
        r = sorted(rows, key=lambda r: across[r])[(len(rows) - 1) // 2]
        if best is None or across[r] < best.across:
            n = N[r]
            best = ThinPart(float(across[r]), float(width[r]), (float(X[r, 0]), float(X[r, 1])),
                            (float(n[0]), float(n[1])))
    return best


def check_thin_parts(scene, element: str, maxh=None, tip_h=None, crack_h=None, grading=None, order=None,
                     what: str | None = None) -> ThinPart | None:
    """Refuse (ValueError) or warn (CoarseMeshWarning) where the body's thinnest part is too
    few mesh sizes across for `element` (MIN_ACROSS_REFUSE, MIN_ACROSS_WARN)."""
    import warnings

    if (element, order) in _ORDERED_SAFE or (element not in MIN_ACROSS_REFUSE and element not in MIN_ACROSS_WARN):
        return None
    thin = thinnest_part(scene, maxh, tip_h, crack_h, grading)
    if thin is None:
        return None
    H = mesh_sizes(scene, maxh, tip_h, crack_h, grading)[0]
    case = what or f"scene {scene.name!r}, element {element!r}"
    where = (f"the body is {thin.width:.3g} thick at ({thin.point[0]:.3g}, {thin.point[1]:.3g}), "
             f"{thin.across:.2g} mesh sizes across")
    refuse, warn = MIN_ACROSS_REFUSE.get(element), MIN_ACROSS_WARN.get(element)
    if refuse is not None and thin.across < refuse:
        raise InputError(
            f"maxh = {H:g}: {case}: {where}; {element} is unstable on a part one triangle thick (singular, or "
            f"displacements 3 to 40 times too large, measured); the largest safe maxh here is about "
            f"{H * thin.across / warn:.3g} ({warn:g} mesh sizes across; {H * thin.across / refuse:.3g} is the "
            f"stability limit), or use element 'bdm'")
    if warn is not None and thin.across < warn:
        warnings.warn(
            f"maxh = {H:g}: {case}: {where}; {element} is known to be more than {COARSE_ERROR:.0%} off on "
            f"such meshes (measured); maxh at most {H * thin.across / warn:.3g} gives {warn:g} mesh sizes across",
            CoarseMeshWarning, stacklevel=4)
    return thin


def check_request(scene, element: str, maxh=None, tip_h=None, crack_h=None, grading=None, order=None,
                  max_dof=None, what: str | None = None) -> tuple[SizeEstimate, ThinPart | None]:
    """Everything `solve` checks before meshing: `check_size`, then `check_thin_parts`."""
    est = check_size(scene, element, maxh, tip_h, crack_h, grading, order, max_dof, what)
    return est, check_thin_parts(scene, element, maxh, tip_h, crack_h, grading, order, what)
