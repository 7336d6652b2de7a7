"""How big a solve will be, before meshing: triangles, unknowns, memory; the size guard.

A mistyped mesh size (maxh 1e-7 for 1e-2) would otherwise start netgen on 1e16
triangles. `check_size` estimates the request in microseconds from the scene's geometry
and refuses it (a ValueError, exit code 2 on the command line) when the estimated
unknowns exceed the ceiling `max_dof` or their memory exceeds what the machine has.

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

Unknowns per triangle (all unknowns, `ndof["total"]`, measured on paper-2 and griffith)
and peak memory per unknown (BENCHMARKS.md, section 1: 1.0-1.4 kB for the mixed elements
and 3.7-4.0 kB for the displacement baselines at 1e6 unknowns) are element constants.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from .scene.measures import polygon_area as _polygon_area

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
#: the default ceiling on the estimated unknowns of one solve (about 7 GB for the mixed elements);
#: `max_dof=` / `--max-dof` replaces it
DEFAULT_MAX_DOF = 5_000_000
#: fraction of the machine's available memory a solve may plan to use
MEMORY_FRACTION = 0.8
#: netgen's default growth rate of the mesh size (geometry.DEFAULT_GRADING)
DEFAULT_GRADING = 0.3


@dataclass(frozen=True)
class SizeEstimate:
    """The estimated size of one solve: triangles, unknowns, peak memory in bytes."""

    triangles: float
    unknowns: float
    memory: float
    maxh: float

    def describe(self) -> str:
        return (f"about {self.triangles:.3g} triangles, {self.unknowns:.3g} unknowns and "
                f"{_bytes(self.memory)} of memory")


def _bytes(n: float) -> str:
    if n >= 1e15:
        return f"{n:.2g} bytes"
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n / 1e3:.3g} kB"


def mesh_sizes(scene, maxh=None, tip_h=None, crack_h=None, grading=None) -> tuple[float, float | None, float | None, float]:
    """(maxh, tip_h, crack_h, grading) as `geometry.make_mesh` resolves them (arguments over the scene's)."""
    H = maxh if maxh is not None else (scene.maxh if scene.maxh is not None else 0.1 * scene.diameter)
    tip = tip_h if tip_h is not None else scene.tip_h
    ch = crack_h if crack_h is not None else scene.crack_h
    g = grading if grading is not None else (scene.grading or DEFAULT_GRADING)
    return float(H), tip, ch, float(g)


def estimate_triangles(scene, maxh=None, tip_h=None, crack_h=None, grading=None) -> float:
    """The number of triangles netgen will make (the closed form of the module docstring)."""
    H, tip, ch, g = mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    A = _polygon_area(np.asarray(scene.polygon, dtype=float))
    L = sum(c.length for c in scene.cracks)
    density = A / H**2
    hc = min(H, ch) if ch else H
    if L and hc < H:  # the band of refinement along the cracks
        D = min((H - hc) / g, A / (2 * L))
        density += 2 * L * ((1 / hc - 1 / (hc + g * D)) / g - D / H**2)
    if tip and tip < hc:  # the graded refinement at every crack end
        for i in range(len(scene.cracks)):
            for on_boundary in scene.crack_end_on_boundary(i):
                theta = math.pi if on_boundary else 2 * math.pi
                R = min((hc - tip) / g, math.sqrt(2 * A / theta))
                s = tip + g * R
                density += theta * ((math.log(s / tip) + tip / s - 1) / g**2 - R**2 / (2 * hc**2))
    return TRIANGLES_PER_AREA * density


def unknowns_per_triangle(element: str, order: int | None = None) -> float:
    per = UNKNOWNS_PER_TRIANGLE[element]
    return per.get(order, per[None])


def estimate(scene, element: str, maxh=None, tip_h=None, crack_h=None, grading=None,
             order: int | None = None) -> SizeEstimate:
    """Estimated triangles, unknowns and peak memory of `solve(scene, element, ...)`."""
    H = mesh_sizes(scene, maxh, tip_h, crack_h, grading)[0]
    tri = estimate_triangles(scene, maxh, tip_h, crack_h, grading)
    dof = tri * unknowns_per_triangle(element, order)
    return SizeEstimate(triangles=tri, unknowns=dof, memory=dof * BYTES_PER_UNKNOWN[element], maxh=H)


def available_memory() -> float | None:
    """The memory the machine can still give (Linux MemAvailable, else free pages), or None."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None


def check_max_dof(max_dof) -> None:
    """max_dof must be None or a positive integer."""
    if max_dof is None:
        return
    if isinstance(max_dof, bool) or not isinstance(max_dof, (int, np.integer, float)) or not max_dof >= 1 \
            or not math.isfinite(max_dof):
        raise ValueError(f"max_dof = {max_dof!r}: must be None (the default ceiling, {DEFAULT_MAX_DOF:,}) or a "
                         f"number of unknowns >= 1".replace(",", " "))


def check_size(scene, element: str, maxh=None, tip_h=None, crack_h=None, grading=None, order=None,
               max_dof=None, what: str | None = None) -> SizeEstimate:
    """Refuse a solve whose estimated unknowns exceed the ceiling or the machine's memory.

    max_dof None: the ceiling is DEFAULT_MAX_DOF and the estimated peak memory must fit
    in MEMORY_FRACTION of the available memory. An explicit max_dof replaces both (the
    caller takes the memory on). Raises ValueError naming maxh, the estimate and the
    override; returns the estimate otherwise.
    """
    check_max_dof(max_dof)
    est = estimate(scene, element, maxh, tip_h, crack_h, grading, order)
    ceiling = DEFAULT_MAX_DOF if max_dof is None else max_dof
    case = what or f"scene {scene.name!r}, element {element!r}"
    how = ("use a larger maxh (or tip_h, crack_h), or raise the limit with max_dof=N in Python or "
           "--max-dof N on the command line")
    if est.unknowns > ceiling:
        limit = "the default ceiling" if max_dof is None else "max_dof"
        raise ValueError(f"maxh = {est.maxh:g}: {case} would need {est.describe()}; that exceeds {limit} of "
                         f"{int(ceiling)} unknowns; {how}")
    avail = available_memory() if max_dof is None else None
    if avail is not None and est.memory > MEMORY_FRACTION * avail:
        raise ValueError(f"maxh = {est.maxh:g}: {case} would need {est.describe()}; this machine has "
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
    import shapely

    H, tip, ch, g = mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    h = np.full(len(points), H)
    pts = shapely.points(points)
    for crack in scene.cracks:
        if ch and ch < H:
            h = np.minimum(h, ch + g * shapely.distance(pts, shapely.LineString(crack.points)))
        if tip:
            for end in (crack.points[0], crack.points[-1]):
                h = np.minimum(h, tip + g * np.linalg.norm(points - np.asarray(end), axis=1))
    return h


def thinnest_part(scene, maxh=None, tip_h=None, crack_h=None, grading=None) -> ThinPart | None:
    """Where the body is fewest mesh sizes across, before meshing.

    From sample points on every boundary piece and on both faces of every crack segment,
    a ray goes into the body along the inward normal to the next boundary or crack; the
    number of mesh sizes across is the integral of 1/h (`local_size`) along it. Each piece
    counts by the median over its samples in the middle half of its length (so the wedge
    at an acute corner is not a thin part); the least over the pieces is returned. A
    one-layer strip is about 1.15 across (a layer of triangles of side h is 0.87 h high).
    """
    import shapely

    lines = [shapely.LineString(list(scene.polygon) + [scene.polygon[0]])]
    lines += [shapely.LineString(c.points) for c in scene.cracks]
    walls = shapely.MultiLineString(lines)
    starts = []  # (point, inward normal)
    for _, p, q in scene.edge_pieces():
        d = np.subtract(q, p)
        starts.append((np.asarray(p, float), d, np.array([-d[1], d[0]]) / np.linalg.norm(d)))
    for crack in scene.cracks:
        for (p, q), nu in zip(crack.segments, crack.normals()):
            for sign in (1.0, -1.0):
                starts.append((np.asarray(p, float), np.subtract(q, p), sign * np.asarray(nu)))
    reach = 2.0 * scene.diameter
    best = None
    ts = np.linspace(*MIDDLE, SAMPLES_PER_PIECE)
    for p, d, n in starts:
        samples = []
        for t in ts:
            x = p + t * d
            ray = shapely.LineString([x + 1e-9 * reach * n, x + reach * n])
            hit = ray.intersection(walls)
            if hit.is_empty:
                continue
            width = shapely.Point(x).distance(hit)
            s = (np.arange(RAY_POINTS) + 0.5) / RAY_POINTS * width
            h = local_size(scene, x + s[:, None] * n, maxh, tip_h, crack_h, grading)
            samples.append((float(np.sum(width / RAY_POINTS / h)), float(width), x))
        if not samples:
            continue
        # the piece's median: a part is thin along a stretch, not at a corner's wedge
        across, width, x = sorted(samples, key=lambda a: a[0])[(len(samples) - 1) // 2]
        if best is None or across < best.across:
            best = ThinPart(across, width, (float(x[0]), float(x[1])), (float(n[0]), float(n[1])))
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
        raise ValueError(
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
