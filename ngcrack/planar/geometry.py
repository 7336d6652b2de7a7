"""Netgen meshes in which every crack is a chain of interior mesh edges.

The body is meshed as one polygon (the smooth-domain formulation of the paper, section
2.1): a crack is a polyline of segments whose two sides belong to the same domain, so
the mesher places vertices on it and conforms to it, but the mesh stays connected
across it. A crack end point on the boundary is inserted as a vertex into the polygon
edge it lies on. Holes are inner boundaries (a circle meshed as a circle), their edges
carrying their labels. The crack segments carry the boundary names `crack_bc(k)`; the polygon
edges carry the scene's labels.

Everything downstream reads the crack through `CrackEdges`: the crack's mesh edges in
order along the crack, with their end points, mid points, arc length and unit normal.
"""

from __future__ import annotations

import re
import threading
import warnings
from contextlib import contextmanager
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
from netgen.geom2d import SplineGeometry
from netgen.libngpy import _meshing
from netgen.meshing import MeshingParameters

from ..core.csr import distinct
from ..core.errors import InputError
from .crack_sides import ON_EDGE_RTOL, crack_frame_cf, crack_side  # noqa: F401  (re-exported for the elements)
from .path_sizes import PathGrading, check_path_grading, grading_points, segment_sizes
from .scene import Scene
from .sizing import check_mesh_sizes, estimate_triangles, mesh_sizes

#: a triangle of lower quality 4 sqrt(3) area / (sum of squared sides) triggers a warning
MIN_QUALITY = 0.1
#: seconds netgen may take on one mesh before it is stopped and the meshing reported as
#: failed: MESH_TIME_BUDGET plus MESH_SECONDS_PER_TRIANGLE per estimated triangle (netgen
#: makes about 1e4 triangles a second here; a scene the checks admit meshes in seconds)
MESH_TIME_BUDGET = 60.0
MESH_SECONDS_PER_TRIANGLE = 2e-4
#: a circular hole is meshed as arcs of at most this many mesh sizes each
HOLE_ARC_SEGMENTS = 8


class MeshingError(InputError):
    """Netgen failed, or did not finish within its time budget; the message names the sizes."""


_budget_lock = threading.Lock()
_budget_users = 0


@contextmanager
def _netgen_budget(seconds: float):
    """Stop netgen (its terminate flag) if meshing inside this block takes longer than
    ``seconds``; yields a dict whose key "expired" says whether that happened. Netgen's
    flag is global: a mesh made at the same time in another thread is stopped too."""
    global _budget_users
    state = {"expired": False}

    def expire() -> None:
        state["expired"] = True
        _meshing._SetTerminate(True)

    timer = threading.Timer(seconds, expire)
    timer.daemon = True
    with _budget_lock:
        _budget_users += 1
    timer.start()
    try:
        yield state
    finally:
        timer.cancel()
        with _budget_lock:
            _budget_users -= 1
            if _budget_users == 0:
                _meshing._SetTerminate(False)


def crack_bc(k: int) -> str:
    """The boundary-condition name netgen gives to the segments of crack k."""
    return f"ngcrack_crack{k}"


def boundary_regex(labels) -> str:
    """A netgen/NGSolve region pattern matching exactly the given labels."""
    return "|".join(re.escape(lab) for lab in sorted(set(labels)))


def boundary_region(mesh: ngs.Mesh, labels) -> ngs.Region:
    """The boundary region made of exactly the given labels (names matched literally)."""
    return mesh.Boundaries(boundary_regex(labels))


@dataclass(frozen=True)
class CrackEdges:
    """The mesh edges of one crack, ordered from its first point to its last.

    Arrays have one row per edge: `a`, `b` (end points, a before b along the crack),
    `mid`, `s_mid` (arc length of the mid point from the crack's first point),
    `normal` (nu, the tangent turned by +90 degrees), `tangent`, `length` and
    `edge` (NGSolve edge numbers), `bnd` (the crack's boundary element numbers).
    """

    index: int
    a: np.ndarray
    b: np.ndarray
    va: np.ndarray
    vb: np.ndarray
    edge: np.ndarray
    bnd: np.ndarray
    segment: np.ndarray
    s_mid: np.ndarray
    normal: np.ndarray
    tangent: np.ndarray

    @property
    def mid(self) -> np.ndarray:
        return 0.5 * (self.a + self.b)

    @property
    def length(self) -> np.ndarray:
        return np.linalg.norm(self.b - self.a, axis=1)

    def __len__(self) -> int:
        return len(self.edge)

    def vertices(self) -> np.ndarray:
        """The mesh vertex numbers along the crack, first to last (len + 1 of them)."""
        return np.concatenate([self.va[:1], self.vb]) if len(self) else np.zeros(0, dtype=int)


@dataclass(frozen=True)
class CrackMesh:
    """An NGSolve mesh of a scene plus the ordered crack edges."""

    mesh: ngs.Mesh
    points: np.ndarray  # (nv, 2) vertex coordinates
    triangles: np.ndarray  # (ne, 3) vertex numbers, in NGSolve's element order
    cracks: tuple[CrackEdges, ...]
    polylines: tuple[np.ndarray, ...]
    tip_vertices: frozenset[int]  # mesh vertex numbers of the crack tips (crack ends inside the body)
    diameter: float
    maxh: float
    tip_h: float | None
    quality: float
    crack_h: float | None = None
    grading: float | None = None

    @property
    def centroids(self) -> np.ndarray:
        """(ne, 2) triangle centroids."""
        return self.points[self.triangles].mean(axis=1)

    @property
    def crack_region(self) -> ngs.Region:
        if not self.cracks:
            return self.mesh.Boundaries("")
        return self.mesh.Boundaries("|".join(crack_bc(c.index) for c in self.cracks))


def _param_on_edge(p, q, x, tol) -> float | None:
    """The parameter t in (0, 1) of x on the segment p-q, or None if x is not on it."""
    d = q - p
    t = float(np.dot(x - p, d) / np.dot(d, d))
    if t <= 0.0 or t >= 1.0:
        return None
    if np.linalg.norm(p + t * d - x) > tol:
        return None
    return t


def normalizing_frame(scene: Scene) -> tuple[np.ndarray, float]:
    """(center, diameter) of the polygon: netgen meshes (x - center) / diameter."""
    poly = np.asarray(scene.polygon, dtype=float)
    return 0.5 * (poly.min(axis=0) + poly.max(axis=0)), scene.diameter


def graded_polyline(pts: np.ndarray, tip_h: float, target_h: float, grading: float) -> np.ndarray:
    """The polyline with points added near both ends: spacing tip_h, tip_h r, tip_h r^2, ...

    r = 1 + grading (netgen lets sizes grow by about `grading` per unit length; a
    faster boundary grading makes slivers); the spacing stops growing at target_h, and the points stay in
    the first (last) half of the first (last) segment. Netgen divides a crack segment by
    its own size and would otherwise ignore the size asked for at its end points.
    """
    ratio = 1.0 + grading

    def offsets(length: float) -> list[float]:
        out, d, h = [], 0.0, tip_h
        while h < target_h and d + h < 0.5 * length:
            d += h
            out.append(d)
            h *= ratio
        return out

    pts = [np.asarray(p, dtype=float) for p in pts]
    first_t = (pts[1] - pts[0]) / np.linalg.norm(pts[1] - pts[0])
    last_t = (pts[-1] - pts[-2]) / np.linalg.norm(pts[-1] - pts[-2])
    head = [pts[0] + d * first_t for d in offsets(np.linalg.norm(pts[1] - pts[0]))]
    tail = [pts[-1] - d * last_t for d in offsets(np.linalg.norm(pts[-1] - pts[-2]))][::-1]
    if len(pts) == 2:  # one segment: both ends share it, each keeps to its own half
        return np.array([pts[0], *head, *tail, pts[1]])
    return np.array([pts[0], *head, *pts[1:-1], *tail, pts[-1]])


#: The fewest mesh segments on an edge whose displacement is held (clamped or prescribed):
#: a constant facet trace on a single segment fixes a rotation about its mid point only
#: through round-off (measured: a unit square clamped on one bottom edge 1e-4 long, peers's
#: condensed system singular to working precision with one segment, equilibrium within 0.2%
#: with two).
SUPPORT_SEGMENTS_MIN = 2


def _holds_displacement(scene: Scene, label: str) -> bool:
    """Whether the boundary condition of edge label `label` prescribes both displacement components."""
    bc = scene.boundary.get(label)
    return bc is not None and bc.type in ("clamped", "displacement")


def build_geometry(scene: Scene, tip_h: float | None = None, crack_h: float | None = None,
                   frame: tuple[np.ndarray, float] | None = None, maxh: float | None = None,
                   grading: float = 0.3, path_grading: PathGrading | None = None) -> SplineGeometry:
    """A netgen 2D spline geometry: the polygon, its labels, and the cracks as slits.

    tip_h is the mesh size at crack end points (the crack is graded from there, see
    `graded_polyline`), crack_h the size along crack segments; with `path_grading` (a
    path_sizes.PathGrading) a segment asks for more the farther it lies from the
    nearest crack end (`path_sizes.segment_sizes`). With `frame` =
    (center, scale) the geometry and sizes are given to netgen in the coordinates
    (x - center) / scale.
    """
    center, scale = frame if frame is not None else (np.zeros(2), 1.0)
    maxh_hint = (maxh / scale) if maxh else 1.0
    grading_hint = grading
    tip_h = tip_h / scale if tip_h else tip_h
    crack_h = crack_h / scale if crack_h else crack_h
    scene_points = lambda pts: (np.asarray(pts, dtype=float) - center) / scale  # noqa: E731
    poly = scene_points(scene.polygon)
    tol = ON_EDGE_RTOL * scene.diameter / scale
    n = len(poly)
    # crack points that sit on the boundary are inserted into the polygon edges
    inserted: list[list[tuple[float, np.ndarray]]] = [[] for _ in range(n)]
    cracks = [scene_points(crack.points) for crack in scene.cracks]
    for pts in cracks:
        for x in (pts[0], pts[-1]):
            if np.min(np.linalg.norm(poly - x, axis=1)) <= tol:
                continue  # a polygon vertex already
            for i in range(n):
                t = _param_on_edge(poly[i], poly[(i + 1) % n], x, tol)
                if t is not None:
                    inserted[i].append((t, x))
    geo = SplineGeometry()
    # points already given to netgen, hashed on a grid of cells of side tol: a point
    # within tol of an earlier one is that point (a lookup in the 9 cells around it)
    point_ids: dict[tuple[int, int], list[tuple[np.ndarray, int]]] = {}

    def point(x: np.ndarray, h: float | None = None) -> int:
        cx, cy = int(np.floor(x[0] / tol)), int(np.floor(x[1] / tol))
        for key in ((cx + i, cy + j) for i in (-1, 0, 1) for j in (-1, 0, 1)):
            for y, pid in point_ids.get(key, ()):
                if np.linalg.norm(y - x) <= tol:
                    return pid
        pid = geo.AppendPoint(float(x[0]), float(x[1]), maxh=h if h else 1e99)
        point_ids.setdefault((cx, cy), []).append((x, pid))
        return pid

    ends = np.array([x for pts in cracks for x in (pts[0], pts[-1])]).reshape(-1, 2)

    def h_of(x):
        at_end = len(ends) and np.min(np.linalg.norm(ends - x, axis=1)) <= tol
        return tip_h if (tip_h and at_end) else None

    # crack end points first so that they carry the tip mesh size
    for x in ends:
        point(x, h_of(x))
    for i in range(n):
        chain = [poly[i]] + [x for _, x in sorted(inserted[i], key=lambda tx: tx[0])]
        chain.append(poly[(i + 1) % n])
        held = _holds_displacement(scene, scene.labels[i])
        for p, q in zip(chain[:-1], chain[1:]):
            # a supporting edge meshed by one segment fixes the rotation of a constant facet
            # trace (peers) only through round-off: give it two segments at least
            h = {"maxh": float(np.linalg.norm(q - p)) / SUPPORT_SEGMENTS_MIN} if held else {}
            geo.Append(["line", point(p, h_of(p)), point(q, h_of(q))], leftdomain=1, rightdomain=0, bc=scene.labels[i], **h)
    joins = scene.hole_joins()
    for k, hole in enumerate(scene.holes):
        on = [cracks[i][e] for i, e, h in joins if h == k]
        _append_hole(geo, point, hole, center, scale, on, tol)
    ends_h = grading_points(cracks) if path_grading else np.zeros((0, 2))
    fine = [scene_points(line) for line in path_grading.fine] if path_grading else []
    for k, pts in enumerate(cracks):
        if tip_h:
            pts = graded_polyline(pts, tip_h, crack_h or maxh_hint, grading_hint)
        sizes = segment_sizes(ends_h, pts[:-1], pts[1:], crack_h, path_grading, maxh_hint, fine, tol) if crack_h else None
        for i, (p, q) in enumerate(zip(pts[:-1], pts[1:])):
            geo.Append(["line", point(p, h_of(p)), point(q, h_of(q))], leftdomain=1, rightdomain=1, bc=crack_bc(k),
                       maxh=float(sizes[i]) if crack_h else 1e99)
    return geo


def _append_hole(geo: SplineGeometry, point, hole, center: np.ndarray, scale: float, on=(), tol: float = 0.0) -> None:
    """The hole's boundary, clockwise so that the body lies on its left (as on the outer
    polygon, counter-clockwise): the boundary elements' outward normal is then their
    tangent turned by -90 degrees everywhere. A circle is a ring of rational quadratic
    splines (netgen's spline3: exact arcs), one per HOLE_ARC_SEGMENTS mesh sizes of its
    perimeter; their points carry the hole's mesh size, so that netgen refines inside the
    body next to the hole too, not only along its edges. The crack ends `on` the hole (in
    netgen's frame) are points of its boundary: a circle's arcs end there too (an arc end
    within a quarter arc of one gives way to it), a polygon's edge is split there."""
    h = hole.edge_h / scale
    if hole.is_circle:
        c = (np.asarray(hole.center, dtype=float) - center) / scale
        r = hole.radius / scale
        n = 4 * max(1, int(np.ceil(2 * np.pi * r / (HOLE_ARC_SEGMENTS * h) / 4)))
        step = 2 * np.pi / n
        fixed = [float(np.arctan2(x[1] - c[1], x[0] - c[0]) % (2 * np.pi)) for x in on]
        gap = lambda a, b: abs((a - b + np.pi) % (2 * np.pi) - np.pi)  # noqa: E731
        angles = sorted([k * step for k in range(n) if all(gap(k * step, a) > step / 4 for a in fixed)] + fixed,
                        key=lambda a: (-a) % (2 * np.pi))  # clockwise from angle 0
        xy = {a: x for a, x in zip(fixed, on)}
        ends = [point(xy[a] if a in xy else c + r * np.array([np.cos(a), np.sin(a)]), h) for a in angles]
        m = len(angles)
        half = [0.5 * ((angles[k] - angles[(k + 1) % m]) % (2 * np.pi)) for k in range(m)]  # clockwise arcs
        ctrl = [point(c + r / np.cos(half[k]) * np.array([np.cos(angles[k] - half[k]), np.sin(angles[k] - half[k])]), h)
                for k in range(m)]  # the control point: where the end tangents meet
        for k in range(m):
            geo.Append(["spline3", ends[k], ctrl[k], ends[(k + 1) % m]], leftdomain=1, rightdomain=0,
                       bc=hole.labels[0], maxh=h)
        return
    pts = (np.asarray(hole.polygon, dtype=float) - center) / scale
    n = len(pts)
    for i in range(n):  # edge i (vertex i to i+1) traversed backwards, split at the crack ends on it
        cuts = [(t, x) for x in on if (t := _param_on_edge(pts[(i + 1) % n], pts[i], x, tol)) is not None]
        chain = [pts[(i + 1) % n]] + [x for _, x in sorted(cuts, key=lambda tx: tx[0])] + [pts[i]]
        for p, q in zip(chain[:-1], chain[1:]):
            geo.Append(["line", point(p, h), point(q, h)], leftdomain=1, rightdomain=0, bc=hole.labels[i], maxh=h)


def _crack_edges(mesh: ngs.Mesh, scene: Scene, k: int, verts: np.ndarray | None = None) -> CrackEdges:
    """The ordered crack edges of crack k; `verts` are the mesh's vertex coordinates."""
    crack = scene.cracks[k]
    pts = np.asarray(crack.points, dtype=float)
    seg_t = pts[1:] - pts[:-1]
    seg_len = np.linalg.norm(seg_t, axis=1)
    seg_t = seg_t / seg_len[:, None]
    seg_s0 = np.concatenate([[0.0], np.cumsum(seg_len)[:-1]])
    name = crack_bc(k)
    if verts is None:
        verts = np.array([v.point for v in mesh.vertices])
    rows = []
    for el in mesh.Elements(ngs.BND):
        if el.mat != name:
            continue
        na, nb = (v.nr for v in el.vertices)
        va, vb = verts[na], verts[nb]
        mid = 0.5 * (va + vb)
        # which crack segment holds this edge: the nearest one to its mid point
        rel = mid - pts[:-1]
        t = np.clip(np.einsum("ij,ij->i", rel, seg_t), 0.0, seg_len)
        dist = np.linalg.norm(pts[:-1] + t[:, None] * seg_t - mid, axis=1)
        j = int(np.argmin(dist))
        if np.dot(vb - va, seg_t[j]) < 0:
            va, vb, na, nb = vb, va, nb, na
        s_mid = seg_s0[j] + float(np.dot(mid - pts[j], seg_t[j]))
        rows.append((s_mid, va, vb, el.edges[0].nr, j, na, nb, el.nr))
    rows.sort(key=lambda r: r[0])
    tangent = np.array([seg_t[r[4]] for r in rows]).reshape(-1, 2)
    normal = np.column_stack([-tangent[:, 1], tangent[:, 0]])
    return CrackEdges(
        index=k,
        a=np.array([r[1] for r in rows]).reshape(-1, 2),
        b=np.array([r[2] for r in rows]).reshape(-1, 2),
        va=np.array([r[5] for r in rows], dtype=int),
        vb=np.array([r[6] for r in rows], dtype=int),
        edge=np.array([r[3] for r in rows], dtype=int),
        bnd=np.array([r[7] for r in rows], dtype=int),
        segment=np.array([r[4] for r in rows], dtype=int),
        s_mid=np.array([r[0] for r in rows]),
        normal=normal,
        tangent=tangent,
    )


def mesh_quality(P: np.ndarray, T: np.ndarray) -> float:
    """The smallest triangle quality 4 sqrt(3) area / (a^2 + b^2 + c^2) (1 = equilateral)."""
    d1, d2 = P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]
    area = 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    sides = sum(np.sum((P[T[:, i]] - P[T[:, (i + 1) % 3]]) ** 2, axis=1) for i in range(3))
    return float(np.min(4.0 * np.sqrt(3.0) * area / sides))


def make_mesh(scene: Scene, maxh: float | None = None, tip_h: float | None = None,
              crack_h: float | None = None, grading: float | None = None,
              path_grading: PathGrading | float | None = None) -> CrackMesh:
    """Mesh the scene with netgen; the arguments override the scene's [mesh] values, and
    where neither gives a size the defaults of `sizing.default_mesh_sizes` apply (maxh a
    tenth of the diameter; crack_h and tip_h from the shortest crack, graded).
    `path_grading`: the crack's size grows with the distance from the nearest crack end
    (`ngcrack.planar.path_sizes`; None: crack_h all along).

    Warns if netgen produced a triangle of quality below MIN_QUALITY (a strong grading
    can do that); such a triangle spoils the accuracy nearby. Every call meshes: the
    reuse of a mesh is the mesh stage's of `ngcrack.core.pipeline.Pipeline`.
    """
    check_mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    maxh, tip_h, crack_h, grading = mesh_sizes(scene, maxh, tip_h, crack_h, grading)
    return _make_mesh(scene, maxh, tip_h, crack_h, grading, check_path_grading(path_grading))


def _warn_quality(scene: Scene, quality: float, maxh: float, grading: float, stacklevel: int) -> None:
    """Warn (at `stacklevel`: make_mesh's caller) about a triangle of quality below MIN_QUALITY."""
    if quality < MIN_QUALITY:
        warnings.warn(f"scene {scene.name!r}: netgen made a triangle of quality {quality:.3f} (maxh={maxh:g}, "
                      f"grading={grading:g}); a milder grading or another maxh gives a better mesh", stacklevel=stacklevel)


def _make_mesh(scene: Scene, maxh: float, tip_h, crack_h, grading: float,
               path_grading: PathGrading | None = None) -> CrackMesh:
    # netgen meshes the scene scaled to unit diameter, and the vertices are mapped back:
    # a scaled scene gets the same mesh, scaled (up to round-off)
    center, scale = normalizing_frame(scene)
    geo = build_geometry(scene, tip_h=tip_h, crack_h=crack_h, frame=(center, scale), maxh=maxh, grading=grading,
                         path_grading=path_grading)
    budget = MESH_TIME_BUDGET + MESH_SECONDS_PER_TRIANGLE * estimate_triangles(scene, maxh, tip_h, crack_h, grading)
    sizes = f"maxh={maxh:g}, tip_h={tip_h}, crack_h={crack_h}, grading={grading:g}"
    with _netgen_budget(budget) as state:
        try:
            ngmesh = geo.GenerateMesh(mp=MeshingParameters(maxh=maxh / scale, grading=grading))
        except Exception as exc:  # netgen reports failures as its own exception type
            if state["expired"]:
                raise MeshingError(
                    f"mesh: netgen did not finish meshing scene {scene.name!r} with {sizes} within "
                    f"{budget:.0f} s and was stopped; try a larger maxh, tip_h or crack_h, a milder "
                    f"grading (larger, up to 1) or fewer polygon vertices and crack points") from exc
            raise MeshingError(
                f"mesh: netgen could not mesh scene {scene.name!r} with {sizes} ({exc}); try another "
                f"maxh, a milder grading (larger, up to 1) or a larger crack_h/tip_h"
            ) from exc
    coords = ngmesh.Coordinates()
    coords[:] = coords * scale + center
    points = np.array(coords[:, :2], dtype=float)
    triangles = np.asarray(ngmesh.Elements2D().NumPy()["nodes"][:, :3], dtype=int) - 1  # netgen counts from 1
    mesh = ngs.Mesh(ngmesh)
    quality = mesh_quality(points, triangles)
    _warn_quality(scene, quality, maxh, grading, stacklevel=4)
    cracks = tuple(_crack_edges(mesh, scene, k, points) for k in range(len(scene.cracks)))
    bnd_vertices = {v.nr for el in mesh.Elements(ngs.BND) if not el.mat.startswith("ngcrack_crack") for v in el.vertices}
    tips = frozenset(
        int(v) for c in cracks if len(c) for v in (c.va[0], c.vb[-1]) if int(v) not in bnd_vertices
    )
    return CrackMesh(
        mesh=mesh,
        points=points,
        triangles=triangles,
        cracks=cracks,
        tip_vertices=tips,
        polylines=tuple(np.asarray(c.points, float) for c in scene.cracks),
        diameter=scene.diameter,
        maxh=float(maxh),
        tip_h=tip_h,
        quality=quality,
        crack_h=crack_h,
        grading=float(grading),
    )


def element_points(crack_mesh: CrackMesh, lam: np.ndarray) -> np.ndarray | None:
    """NGSolve mesh points at barycentric coordinates `lam` (k, 3) in every triangle, in
    element order (k per triangle), without a point search: the reference coordinates
    of a triangle are its barycentric coordinates of vertices 0 and 1, in the vertex
    order of `CrackMesh.triangles`. The layout is checked against the point search on a
    few triangles; None where it differs (then search the points instead)."""
    lam = np.asarray(lam, float).reshape(-1, 3)
    P, T = crack_mesh.points, crack_mesh.triangles
    ne, nk = len(T), len(lam)
    if ne == 0:
        return None
    probe = distinct(np.r_[0, ne - 1, np.linspace(0, ne - 1, 7).astype(int)])
    pts = np.einsum("kv,evd->ekd", lam, P[T[probe]]).reshape(-1, 2)
    found = crack_mesh.mesh(pts[:, 0], pts[:, 1])
    mips = np.zeros(ne * nk, dtype=found.dtype)
    mips["x"] = np.tile(lam[:, 0], ne)
    mips["y"] = np.tile(lam[:, 1], ne)
    mips["meshptr"] = found["meshptr"][0]
    mips["VorB"] = found["VorB"][0]
    mips["nr"] = np.repeat(np.arange(ne, dtype=np.int32), nk)
    mips["facetnr"] = found["facetnr"][0]
    mine = mips[(probe[:, None] * nk + np.arange(nk)[None, :]).ravel()]
    if not (np.array_equal(mine["nr"], found["nr"]) and np.allclose(mine["x"], found["x"], atol=1e-9)
            and np.allclose(mine["y"], found["y"], atol=1e-9)):
        return None
    return mips


# ------------------------------------------------------------ refined meshes (adaptivity)

def crack_mesh_of(mesh: ngs.Mesh, scene: Scene, maxh: float, tip_h: float | None) -> CrackMesh:
    """Re-identify the cracks of `scene` on an existing mesh (e.g. after netgen's refinement).

    Bisection keeps every crack segment a chain of boundary segments named crack_bc(k)
    and every crack end point a vertex, so the crack edges, their order along the crack
    and the interior tips are read back from the mesh exactly as `make_mesh` does.
    """
    ngmesh = mesh.ngmesh
    points = np.array(ngmesh.Coordinates()[:, :2], dtype=float)
    triangles = np.asarray(ngmesh.Elements2D().NumPy()["nodes"][:, :3], dtype=int) - 1
    cracks = tuple(_crack_edges(mesh, scene, k) for k in range(len(scene.cracks)))
    bnd_vertices = {v.nr for el in mesh.Elements(ngs.BND) if not el.mat.startswith("ngcrack_crack") for v in el.vertices}
    tips = frozenset(int(v) for c in cracks if len(c) for v in (c.va[0], c.vb[-1]) if int(v) not in bnd_vertices)
    return CrackMesh(mesh=mesh, points=points, triangles=triangles, cracks=cracks, tip_vertices=tips,
                     polylines=tuple(np.asarray(c.points, float) for c in scene.cracks),
                     diameter=scene.diameter, maxh=float(maxh), tip_h=tip_h,
                     quality=mesh_quality(points, triangles))


def refine_crack_mesh(crack_mesh: CrackMesh, scene: Scene, marked: np.ndarray) -> CrackMesh:
    """A copy of the mesh with the marked triangles bisected by netgen (plus the closure
    netgen adds for conformity), its cracks re-identified. The input mesh is unchanged.

    Crack and polygon edges are straight, so the new boundary points are the edges' mid
    points (netgen's geometry is detached first): the crack stays a chain of mesh
    edges and the tips stay vertices.
    """
    ngmesh = crack_mesh.mesh.ngmesh.Copy()
    # netgen would project the new boundary points onto the spline geometry, which
    # make_mesh built in normalized coordinates; without it they are the mid points
    ngmesh.SetGeometry(None)
    mesh = ngs.Mesh(ngmesh)
    for el in mesh.Elements(ngs.VOL):
        mesh.SetRefinementFlag(el, bool(marked[el.nr]))
    for el in mesh.Elements(ngs.BND):
        mesh.SetRefinementFlag(el, False)
    mesh.Refine()
    # a fresh mesh of the refined elements: NGSolve keeps the bisected parent edges of a
    # refined mesh in its topology (unused dofs of facet spaces), a copy does not
    mesh = ngs.Mesh(mesh.ngmesh.Copy())
    return crack_mesh_of(mesh, scene, crack_mesh.maxh, crack_mesh.tip_h)
