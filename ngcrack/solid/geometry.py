"""Meshes of 3D scenes with netgen's OCC kernel: each crack a glued set of interior faces.

The body (a box or a cylinder) and each crack's plane face are glued (``Glue``): the
crack becomes a set of interior mesh faces with a tetrahedron on each side, named
``crack<i>`` as a boundary region, and its front an edge region ``front<i>``. Local sizes:
``crack_h`` on the crack face, ``front_h`` on its front edges, NEAR_H_FACTOR ``crack_h`` in
the ball of NEAR_RADIUS half sizes around each crack (netgen's local size restrictions,
`meshing_parameters`), ``maxh`` and ``grading`` elsewhere. The mesh is curved to second order (``mesh.Curve(2)``): on a disc meshed with
flat facets the crack's area is about 1% short; curved, it is exact to about 1e-6.

A :class:`SolidMesh` records per crack its surface elements, the mesh faces they are,
the tetrahedra on the + side (the side the crack normal points into) and on the - side,
and the front's edges and vertices: everything the element and the front's fracture
parameters need, so that neither looks at OCC again.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np

from ..core.errors import InputError
from .scene import Box, PlanarCrack, SolidScene
from .sizing import NEAR_H_FACTOR, NEAR_H_FLOOR_RTOL, NEAR_RADIUS  # noqa: F401  (this module's mesh choices)
from .surface import crosses, inside_measures, on_surface

#: the polynomial order of the curved geometry
CURVE_ORDER = 2
#: a crack whose meshed area is off the area of its part inside the body by more than this fraction was not meshed
#: (netgen gives up on a face it cannot mesh and goes on: a surface crack far shallower than front_h measured 20 times
#: its area; a meshed one is within 0.3% on the coarsest meshes, curved: 1e-6 on a disc)
MESHED_AREA_RTOL = 0.1
#: the body's mesh size near a crack (NEAR_H_FACTOR, NEAR_H_FLOOR_RTOL, NEAR_RADIUS): `solid.sizing`, which counts
#: its tetrahedra too


class MeshError(RuntimeError):
    """The mesher produced a mesh the solver cannot use (a crack face without two tetrahedra)."""


@dataclass
class CrackFaces:
    """One crack in the mesh (module docstring)."""

    index: int
    crack: PlanarCrack
    label: str
    front_label: str
    elements: np.ndarray  # surface element numbers
    faces: np.ndarray  # mesh face numbers
    plus: np.ndarray  # tetrahedron on the + side of each face
    minus: np.ndarray  # tetrahedron on the - side of each face
    front_edges: np.ndarray
    front_vertices: np.ndarray
    interior_edges: np.ndarray  # crack edges not on the front
    area: float = 0.0

    @property
    def normal(self) -> np.ndarray:
        return self.crack.normal


@dataclass
class SolidMesh:
    mesh: ngs.Mesh
    scene: SolidScene
    cracks: list[CrackFaces]
    sizes: dict
    timings: dict = field(default_factory=dict)
    dimension = 3

    @property
    def points(self) -> np.ndarray:
        return np.array([v.point for v in self.mesh.vertices])


def _occ_body(domain):
    from netgen import occ

    if hasattr(domain, "occ_shape"):  # a part read from a file (solid.parts.StepPart)
        return domain.occ_shape()
    if isinstance(domain, Box):
        body = occ.Box(occ.Pnt(*domain.lo), occ.Pnt(*domain.hi))
        for f in body.faces:
            c = np.array([f.center.x, f.center.y, f.center.z])
            for k, ax in enumerate("xyz"):
                if abs(c[k] - domain.lo[k]) < 1e-9 * domain.size:
                    f.name = ax + "min"
                elif abs(c[k] - domain.hi[k]) < 1e-9 * domain.size:
                    f.name = ax + "max"
        return body
    body = occ.Cylinder(occ.Pnt(*domain.base), occ.Dir(*domain.axis), domain.radius, domain.height)
    for f in body.faces:
        c = np.array([f.center.x, f.center.y, f.center.z])
        h = float(np.dot(c - domain.base, domain.axis))
        if abs(h) < 1e-6 * domain.height:
            f.name = "bottom"
        elif abs(h - domain.height) < 1e-6 * domain.height:
            f.name = "top"
        else:
            f.name = "side"
    return body


def _occ_crack(crack: PlanarCrack):
    from netgen import occ

    if crack.shape == "curve":
        from .curve import occ_curve_face

        return occ_curve_face(crack)
    if crack.shape == "polygon":
        pts = [occ.Pnt(*p) for p in crack.points]
        segs = [occ.Segment(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]
        return occ.Face(occ.Wire(segs))
    wp = occ.WorkPlane(occ.Axes(tuple(crack.center), n=occ.Dir(*crack.normal), h=occ.Dir(*crack.e_a)))
    if crack.shape == "disc":
        return wp.Circle(crack.radius).Face()
    a, b = crack.semi_axes
    if a >= b:
        return wp.Ellipse(a, b).Face()
    wp = occ.WorkPlane(occ.Axes(tuple(crack.center), n=occ.Dir(*crack.normal), h=occ.Dir(*crack.e_b)))
    return wp.Ellipse(b, a).Face()


def occ_geometry(scene: SolidScene, sizes: dict):
    """The scene's OCC geometry with its names and local sizes (`sizes`: scene.mesh_sizes): what
    `make_mesh` meshes, and what a subdomain of a distributed mesh is curved with."""
    from netgen import occ

    from .points import patch_faces

    parts = [_occ_body(scene.domain)] + patch_faces(scene.points)  # point supports' patches imprinted on faces
    for i, c in enumerate(scene.cracks):
        face = _occ_crack(c)
        reaches = crosses(scene.domain, c)
        if reaches:  # the crack is its part inside the body; its edges on the surface are its mouth
            face = face * parts[0]
        face.name = f"crack{i}"
        face.faces.maxh = sizes["crack_h"]
        for e in face.edges:
            if reaches and _on_surface(scene, e):
                e.name = f"mouth{i}"
                e.maxh = sizes["crack_h"]
            else:
                e.name = f"front{i}"
                e.maxh = sizes["front_h"]
        parts.append(face)
    return occ.OCCGeometry(occ.Glue(parts) if len(parts) > 1 else parts[0])


def _on_surface(scene: SolidScene, edge) -> bool:
    """Whether an OCC edge of a clipped crack lies on the body's surface (its ends and middle do)."""
    t0, t1 = edge.parameter_interval
    pts = [edge.Value(t) for t in (t0, 0.5 * (t0 + t1), t1)]
    return bool(on_surface(scene.domain, np.array([[p.x, p.y, p.z] for p in pts]), scene.size).all())


def near_points(crack: PlanarCrack, h: float, radius: float) -> np.ndarray:
    """Points h apart filling the ball of `radius` around the crack's centre."""
    axis = np.arange(-radius, radius + 0.5 * h, h)
    grid = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    return crack.center + grid[np.linalg.norm(grid, axis=1) <= radius]


def meshing_parameters(scene: SolidScene, sizes: dict):
    """netgen's meshing parameters: maxh and grading, and the body's size near every crack
    (NEAR_H_FACTOR crack_h, at least NEAR_H_FLOOR_RTOL of its size, in the ball of NEAR_RADIUS half
    sizes around it) as local restrictions."""
    from netgen.meshing import MeshingParameters

    mp = MeshingParameters(maxh=sizes["maxh"], grading=sizes["grading"])
    for c in scene.cracks:
        h = min(max(NEAR_H_FACTOR * sizes["crack_h"], NEAR_H_FLOOR_RTOL * c.size), sizes["maxh"])
        if NEAR_RADIUS > 0:
            for p in near_points(c, h, NEAR_RADIUS * 0.5 * c.size):
                mp.RestrictH(float(p[0]), float(p[1]), float(p[2]), h)
    return mp


def make_mesh(scene: SolidScene, maxh=None, crack_h=None, front_h=None, grading=None,
              curve: int = CURVE_ORDER) -> SolidMesh:
    """Mesh the scene (sizes: the arguments, else the scene's [mesh], else the defaults)."""

    sizes = scene.mesh_sizes(maxh, crack_h, front_h, grading)
    t0 = time.perf_counter()
    ngmesh = occ_geometry(scene, sizes).GenerateMesh(mp=meshing_parameters(scene, sizes))
    mesh = ngs.Mesh(ngmesh)
    if curve:
        mesh.Curve(curve)
    t1 = time.perf_counter()
    cracks = [_crack_faces(mesh, i, c) for i, c in enumerate(scene.cracks)]
    for cf in cracks:
        check_meshed_area(scene, cf, sizes)
    return SolidMesh(mesh, scene, cracks, sizes, {"mesh": t1 - t0, "topology": time.perf_counter() - t1})


def check_meshed_area(scene: SolidScene, cf, sizes: dict) -> None:
    """Refuse, naming the crack, a mesh whose crack faces do not cover the crack's part inside the body (within
    MESHED_AREA_RTOL): netgen went on past a face it could not mesh, and every number after would be wrong."""
    area = inside_measures(scene.domain, cf.crack)[1]
    if abs(cf.area - area) > MESHED_AREA_RTOL * area:
        raise InputError(f"crack[{cf.index}]: the mesher did not mesh it (its faces' area {cf.area:.3g}, its part inside "
                         f"the body {area:.3g}): a crack part this small or thin is not resolved at front_h "
                         f"{sizes['front_h']:.3g}; give a smaller mesh.front_h and crack_h, or a larger crack")


def _crack_faces(mesh: ngs.Mesh, i: int, crack: PlanarCrack) -> CrackFaces:
    label, front = f"crack{i}", f"front{i}"
    pts = np.array([v.point for v in mesh.vertices])
    els, faces, plus, minus = [], [], [], []
    crack_edges: set[int] = set()
    for el in mesh.Elements(ngs.BND):
        if el.mat != label:
            continue
        f = el.faces[0].nr
        tets = mesh[el.faces[0]].elements
        if len(tets) != 2:
            raise MeshError(f"crack[{i}]: a crack face with {len(tets)} tetrahedra (two expected); the OCC glue failed")
        fv = {v.nr for v in el.vertices}
        side = []
        for t in tets:
            opp = [v.nr for v in mesh[t].vertices if v.nr not in fv][0]
            side.append(np.dot(pts[opp] - crack.center, crack.normal))
        if side[0] * side[1] >= 0:
            raise MeshError(f"crack[{i}]: the two tetrahedra of a crack face lie on one side of it")
        p, m = (tets[0].nr, tets[1].nr) if side[0] > 0 else (tets[1].nr, tets[0].nr)
        els.append(el.nr)
        faces.append(f)
        plus.append(p)
        minus.append(m)
        crack_edges.update(e.nr for e in el.edges)
    if not els:
        raise MeshError(f"crack[{i}]: no crack faces in the mesh; the OCC glue failed")
    f_edges, f_verts = set(), set()
    for el in mesh.Elements(ngs.BBND):
        if el.mat == front:
            f_edges.update(e.nr for e in el.edges)
            f_verts.update(v.nr for v in el.vertices)
    area = ngs.Integrate(ngs.CF(1.0), mesh, definedon=mesh.Boundaries(label))
    return CrackFaces(i, crack, label, front, np.array(els), np.array(faces), np.array(plus), np.array(minus),
                      np.array(sorted(f_edges)), np.array(sorted(f_verts)),
                      np.array(sorted(crack_edges - f_edges)), float(area))
