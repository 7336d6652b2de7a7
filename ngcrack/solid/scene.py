"""3D scenes: a box or a cylinder holding planar cracks, as plain validated data.

A scene is 3D when its ``[domain]`` is (``box``, ``cylinder`` or ``step``); ``Scene.from_toml``
hands such a document to :meth:`SolidScene.from_dict`. Like the 2D scene, a
:class:`SolidScene` is immutable and validated completely when it is built, before any
meshing: every bad field raises :class:`ngcrack.SceneError` naming the field and what is
allowed.

Domain (`solid.parts`)
    ``box = [[x0, y0, z0], [x1, y1, z1]]``: faces ``xmin xmax ymin ymax zmin zmax``.
    ``cylinder = {center, axis, radius, height}``: ``center`` is the centre of the
    cylinder (mid-height on the axis); faces ``bottom`` (at center - height/2 axis),
    ``top`` and ``side``. ``step = "part.step"``: a solid from a STEP file, faces by the
    file's names or ``face<i>``.
Cracks (``[[crack]]``), each a plane set inside the body or crossing its free faces:
    ``shape = "disc"`` with ``center``, ``normal``, ``radius``;
    ``shape = "ellipse"`` with ``center``, ``normal``, ``semi_axes = [a, b]`` and ``major_axis`` (projected into the plane);
    ``shape = "polygon"`` with ``points`` (3 or more, in one plane, a simple polygon; the
    normal follows the right-hand rule of the point order; ``"curve"``: a spline through them). ``friction`` >= 0;
    ``pressure`` (a number, default 0): a uniform pressure on both faces, pushing them apart;
    or a table along an in-plane axis or a callable p(x, y, z) (`solid.loads`).
    The normal nu points into the ``+`` face; the jump is [u] = u+ - u-.
Cracks stay apart from each other and from the faces (a clearance of ``CLEARANCE_RTOL`` times the
crack's size), or cross free faces by as much: the crack is then its part inside the body, its
front the part of its outline inside (``ngcrack.solid.surface``): a semi-elliptical surface crack
is an ellipse centred on a face, a corner crack a quarter of one centred on an edge.
Boundary conditions by face label: ``clamped``, ``displacement`` (value = [ux, uy, uz]),
``roller`` (u.n = 0) or ``traction`` (value = [gx, gy, gz], or a table along an axis or a
callable g(x, y, z): `solid.loads`); unnamed faces are free. Point supports and loads
(``[[point]]``: `solid.points`) on patches of planar faces. The supports must hold every rigid
motion (checked on points of the faces and at the point supports).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..core.fields import MIN_SIZE_RTOL, SceneError, check_keys, check_scale, finite, positive, short, table
from ..core.scene import Scene
from . import curve
from .loads import VaryingField, is_varying, pressure_field, traction_field
from .parts import (  # noqa: F401  (re-exported: the domains' names)
    BOX_FACES,
    CYLINDER_FACES,
    DOMAIN_KINDS,
    Box,
    Cylinder,
    StepPart,
    domain_from_dict,
    domain_labels,
    perpendicular,
    vector3,
)
from .points import PointCondition3, held_directions, points_from_list, rigid_rows  # noqa: F401
from .sizing import ligament_caps
from .surface import face_problem, inside_measures

SHAPES = ("disc", "ellipse", "polygon", "curve")
BOUNDARY_TYPES = ("clamped", "displacement", "roller", "traction")
TOP_KEYS = ("name", "description", "domain", "crack", "material", "load", "boundary", "mesh", "point")
MESH_KEYS = ("maxh", "crack_h", "front_h", "grading")
#: a crack must keep this fraction of its size (diameter) away from the boundary and other cracks
CLEARANCE_RTOL = 0.05
#: points of a polygon crack off their plane by more than this fraction of its size are refused
PLANARITY_RTOL = 1e-6
#: default mesh sizes, as fractions: maxh of the body's size, crack_h and front_h of the crack's size
DEFAULT_MAXH_RTOL, DEFAULT_CRACK_H_RTOL, DEFAULT_FRONT_H_RTOL = 0.25, 0.2, 0.1
#: ... and maxh at most this many times the smallest crack's size: at a quarter of its block's diameter (8.7a) the
#: penny's K_I was 0.7% low on average and 1.05% at its worst front point, at 5a 0.33% and 0.71% (BENCHMARKS)
DEFAULT_MAXH_CRACK_RTOL = 2.5
DEFAULT_GRADING = 0.3


# ------------------------------------------------------------------------------------- cracks
@dataclass(frozen=True, eq=False)
class PlanarCrack:
    """One planar crack: its shape, plane frame (e_a, e_b, normal) and outline.

    For a disc, e_a is an arbitrary in-plane unit vector; for an ellipse the major axis;
    for a polygon the direction from its first point to its second.
    """

    shape: str
    center: np.ndarray
    normal: np.ndarray
    e_a: np.ndarray
    semi_axes: tuple[float, float] = (0.0, 0.0)
    points: np.ndarray | None = None
    friction: float = 0.0
    pressure: float = 0.0  # uniform pressure on both faces (pushing them apart)

    @property
    def e_b(self) -> np.ndarray:
        return np.cross(self.normal, self.e_a)

    @property
    def radius(self) -> float:
        return self.semi_axes[0]

    def outline(self, n: int = 64) -> np.ndarray:
        """Points on the crack front (n per curve; a polygon's vertices and n points per side)."""
        if self.shape == "curve":  # a periodic spline through the points (ngcrack.solid.curve)
            return curve.curve_outline(self, n)
        if self.shape == "polygon":
            p = self.points
            q = np.roll(p, -1, axis=0)
            t = np.linspace(0.0, 1.0, max(n // len(p), 2), endpoint=False)
            return np.concatenate([p[i] + np.outer(t, q[i] - p[i]) for i in range(len(p))])
        phi = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
        a, b = self.semi_axes
        return self.center + np.outer(a * np.cos(phi), self.e_a) + np.outer(b * np.sin(phi), self.e_b)

    def fill(self, n: int = 12) -> np.ndarray:
        """Points covering the crack (its outline shrunk towards the centre, n rings)."""
        out = self.outline(4 * n)
        c = self.center
        return np.concatenate([c + s * (out - c) for s in np.linspace(0.0, 1.0, n)])

    @property
    def size(self) -> float:
        """The crack's diameter (largest distance between two outline points)."""
        p = self.outline(64)
        return float(np.max(np.linalg.norm(p[:, None] - p[None], axis=-1)))

    @property
    def area(self) -> float:
        if self.shape in ("polygon", "curve"):
            p = (self.points if self.shape == "polygon" else self.outline(curve.AREA_POINTS)) - self.center
            return float(0.5 * abs(np.dot(np.sum(np.cross(p, np.roll(p, -1, axis=0)), axis=0), self.normal)))
        return float(math.pi * self.semi_axes[0] * self.semi_axes[1])

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"shape": self.shape}
        if self.shape in ("polygon", "curve"):
            d["points"] = self.points.tolist()
        else:
            d.update(center=self.center.tolist(), normal=self.normal.tolist())
            if self.shape == "disc":
                d["radius"] = self.radius
            else:
                d.update(semi_axes=list(self.semi_axes), major_axis=self.e_a.tolist())
        if self.friction:
            d["friction"] = self.friction
        if is_varying(self.pressure):
            d["pressure"] = self.pressure.to_toml("crack.pressure")
        elif self.pressure:
            d["pressure"] = self.pressure
        return d


CRACK_KEYS = {"disc": ("shape", "center", "normal", "radius", "friction", "pressure"),
              "ellipse": ("shape", "center", "normal", "semi_axes", "major_axis", "friction", "pressure"),
              "polygon": ("shape", "points", "friction", "pressure"), "curve": ("shape", "points", "friction", "pressure")}
#: the crack keys that may be left out
OPTIONAL_CRACK_KEYS = ("friction", "pressure")


def crack_from_dict(c: Any, i: int) -> PlanarCrack:
    fld = f"crack[{i}]"
    if not isinstance(c, Mapping):
        raise SceneError(f"{fld} = {short(c)}: must be a table ([[crack]] with shape = {' | '.join(SHAPES)})")
    shape = c.get("shape")
    if shape not in SHAPES:
        raise SceneError(f"{fld}.shape = {short(shape)}: allowed values are {', '.join(SHAPES)}")
    check_keys(c, CRACK_KEYS[shape], fld)
    needed = [k for k in CRACK_KEYS[shape][1:] if k not in OPTIONAL_CRACK_KEYS]
    for key in needed:
        if key not in c:
            raise SceneError(f"{fld}.{key}: missing; a {shape} crack needs {', '.join(needed)}")
    mu = finite(c.get("friction", 0.0), f"{fld}.friction", "a finite number >= 0")
    if mu < 0:
        raise SceneError(f"{fld}.friction = {mu!r}: must be a finite number >= 0")
    p = c.get("pressure", 0.0)
    crack = _crack_shape(c, shape, fld, mu)
    if isinstance(p, (Mapping, VaryingField)) or callable(p):  # a pressure varying over the crack (solid.loads)
        return dataclasses.replace(crack, pressure=pressure_field(p, f"{fld}.pressure", crack))  # a callable's grid on this crack
    if isinstance(p, bool) or not isinstance(p, (int, float)) or not math.isfinite(p):
        raise SceneError(f"{fld}.pressure = {short(p)}: must be a finite number (a uniform pressure on the faces), "
                         "a table {axis, table = [[s, p], ...]} or in Python a callable p(x, y, z)")
    return dataclasses.replace(crack, pressure=float(p))


def _crack_shape(c: Mapping, shape: str, fld: str, mu: float) -> PlanarCrack:
    if shape == "polygon":
        return _polygon(c["points"], fld, mu)
    if shape == "curve":  # a closed spline outline (ngcrack.solid.curve)
        return PlanarCrack("curve", **curve.curve_frame(c["points"], fld), friction=mu)
    center = vector3(c["center"], f"{fld}.center")
    normal = vector3(c["normal"], f"{fld}.normal", unit=True)
    if shape == "disc":
        r = positive(c["radius"], f"{fld}.radius")
        return PlanarCrack("disc", center, normal, perpendicular(normal), (r, r), friction=mu)
    ax = c["semi_axes"]
    if isinstance(ax, (str, bytes)) or not isinstance(ax, Sequence) or len(ax) != 2:
        raise SceneError(f"{fld}.semi_axes = {short(ax)}: must be [a, b], two numbers > 0")
    a, b = positive(ax[0], f"{fld}.semi_axes[0]"), positive(ax[1], f"{fld}.semi_axes[1]")
    major = vector3(c["major_axis"], f"{fld}.major_axis", unit=True)
    e_a = major - np.dot(major, normal) * normal
    if np.linalg.norm(e_a) < 1e-6:
        raise SceneError(f"{fld}.major_axis = {short(c['major_axis'])}: must not be parallel to the normal")
    return PlanarCrack("ellipse", center, normal, e_a / np.linalg.norm(e_a), (a, b), friction=mu)


def _polygon(v: Any, fld: str, mu: float) -> PlanarCrack:
    if isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) < 3:
        raise SceneError(f"{fld}.points = {short(v)}: must be 3 or more points [[x, y, z], ...] in one plane")
    p = np.array([vector3(q, f"{fld}.points[{k}]") for k, q in enumerate(v)])
    center = p.mean(axis=0)
    newell = np.sum(np.cross(p - center, np.roll(p, -1, axis=0) - center), axis=0)
    size = float(np.max(np.linalg.norm(p[:, None] - p[None], axis=-1)))
    if np.linalg.norm(newell) <= 1e-12 * size * size:
        raise SceneError(f"{fld}.points: the polygon has no area (points on one line)")
    normal = newell / np.linalg.norm(newell)
    off = np.abs((p - center) @ normal)
    if off.max() > PLANARITY_RTOL * size:
        raise SceneError(f"{fld}.points[{int(off.argmax())}]: {off.max():.3g} off the polygon's plane; "
                         f"a crack must be planar")
    e_a = (p[1] - p[0]) / np.linalg.norm(p[1] - p[0])
    e_b = np.cross(normal, e_a)
    uv = np.column_stack([(p - center) @ e_a, (p - center) @ e_b])
    import shapely

    ring = shapely.Polygon(uv)
    if not ring.is_valid or len(set(map(tuple, uv.round(12)))) < len(uv):
        raise SceneError(f"{fld}.points: the polygon must be simple (no crossing sides, no repeated point)")
    return PlanarCrack("polygon", center, normal, e_a, points=p, friction=mu)


# ----------------------------------------------------------------------------- other tables
@dataclass(frozen=True)
class Material3:
    """Isotropic material of a 3D body: E > 0, nu in (-1, 1/2)."""

    E: float
    nu: float

    @classmethod
    def from_dict(cls, d: Any) -> Material3:
        if not isinstance(d, Mapping):
            raise SceneError(f"material = {short(d)}: must be a table with keys E, nu")
        check_keys(d, ("E", "nu"), "material")
        for key in ("E", "nu"):
            if key not in d:
                raise SceneError(f"material.{key}: missing; give E > 0 and nu in (-1, 1/2)")
        E = positive(d["E"], "material.E")
        nu = finite(d["nu"], "material.nu", "a number in (-1, 1/2)")
        if not -1.0 < nu < 0.5:
            raise SceneError(f"material.nu = {nu!r}: must lie in (-1, 1/2) in 3D (nu = 1/2 exactly is not "
                             f"supported in 3D yet: use 0.4999, which does not lock)")
        return cls(E, nu)


@dataclass(frozen=True)
class Condition3:
    """A face's condition; a traction's `value` a constant [gx, gy, gz] or a VaryingField (solid.loads)."""

    type: str
    value: tuple[float, float, float] | VaryingField | None = None

    @classmethod
    def from_dict(cls, d: Any, fld: str, domain=None) -> Condition3:
        if not isinstance(d, Mapping):
            raise SceneError(f"{fld} = {short(d)}: must be a table with keys type, value")
        check_keys(d, ("type", "value"), fld)
        t = d.get("type")
        if t not in BOUNDARY_TYPES:
            raise SceneError(f"{fld}.type = {short(t)}: allowed values are {', '.join(BOUNDARY_TYPES)}")
        if t in ("clamped", "roller"):
            if "value" in d:
                raise SceneError(f"{fld}.value: a {t} face takes no value; remove it")
            return cls(t)
        if "value" not in d:
            raise SceneError(f"{fld}.value: missing; a {t} face needs value = [x, y, z]")
        v = d["value"]
        if t == "traction" and (isinstance(v, (Mapping, VaryingField)) or callable(v)):
            return cls(t, v if is_varying(v) else traction_field(v, f"{fld}.value", domain))
        return cls(t, tuple(vector3(v, f"{fld}.value").tolist()))

    @property
    def varying(self) -> bool:
        return is_varying(self.value)

    def to_dict(self, fld: str = "boundary") -> dict[str, Any]:
        if self.value is None:
            return {"type": self.type}
        return {"type": self.type, "value": self.value.to_toml(f"{fld}.value") if self.varying else list(self.value)}


# -------------------------------------------------------------------------------- the scene
@dataclass(frozen=True, eq=False)
class SolidScene(Scene, dimension=3):
    """A cracked 3D elastic body (module docstring). Build with :meth:`from_dict`."""

    body_module: ClassVar[str] = "ngcrack.solid.stages"

    name: str
    description: str
    domain: Box | Cylinder | StepPart
    cracks: tuple[PlanarCrack, ...]
    material: Material3
    boundary: dict  # label -> Condition3 of constant value (a force point's patch: its traction)
    body_force: tuple[float, float, float] | None = None
    maxh: float | None = None
    crack_h: float | None = None
    front_h: float | None = None
    grading: float | None = None
    points: tuple[PointCondition3, ...] = ()
    #: label -> Condition3 of a traction varying over the face (solid.loads), kept out of `boundary`
    tractions: dict = dataclasses.field(default_factory=dict)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any], name: str | None = None) -> SolidScene:
        check_keys(d, TOP_KEYS, "")
        name = d.get("name") if name is None else name
        if not isinstance(name, str) or not name:
            raise SceneError(f"name = {short(name)}: give the scene a name (a non-empty string)")
        description = d.get("description", "")
        if not isinstance(description, str):
            raise SceneError(f"description = {short(description)}: must be a string")
        domain = domain_from_dict(table(d, "domain", "domain"))
        raw = d.get("crack", [])
        if isinstance(raw, (Mapping, str, bytes)) or not isinstance(raw, Sequence):
            raise SceneError(f"crack = {short(raw)}: must be an array of tables ([[crack]])")
        cracks = tuple(crack_from_dict(c, i) for i, c in enumerate(raw))
        if "material" not in d:
            raise SceneError("material: missing; give a [material] table with E and nu")
        material = Material3.from_dict(d["material"])
        load = table(d, "load", "load")
        check_keys(load, ("body_force",), "load")
        body = None if "body_force" not in load else tuple(vector3(load["body_force"], "load.body_force").tolist())
        mesh = table(d, "mesh", "mesh")
        check_keys(mesh, MESH_KEYS, "mesh")
        sizes = {k: (None if k not in mesh else positive(mesh[k], f"mesh.{k}")) for k in MESH_KEYS}
        if sizes["grading"] is not None and not 0 < sizes["grading"] <= 1:
            raise SceneError(f"mesh.grading = {sizes['grading']!r}: must lie in (0, 1]")
        labels = domain_labels(domain)
        points = points_from_list(d.get("point", []), domain, sizes["maxh"] or DEFAULT_MAXH_RTOL * domain.size, labels)
        boundary, tractions = {}, {}
        for label, cond in table(d, "boundary", "boundary").items():
            if label in {pc.label for pc in points}:
                raise SceneError(f"boundary.{label}: the patch of a point takes its condition from [[point]]; remove "
                                 f"[boundary.{label}]")
            if label not in labels:
                kind = "STEP part" if isinstance(domain, StepPart) else type(domain).__name__.lower()
                raise SceneError(f"boundary.{label}: no such face; the faces of the {kind} are {', '.join(labels)}")
            c = Condition3.from_dict(cond, f"boundary.{label}", domain)
            (tractions if c.varying else boundary)[label] = c
        if isinstance(domain, StepPart):
            domain.check_rollers(boundary)
        for k, pc in enumerate(points):  # a patch keeps its face's traction, a force adds its own
            face = boundary.get(pc.face) or tractions.get(pc.face)
            if face is not None and face.type != "traction":
                raise SceneError(f"point[{k}].at = {short(pc.at.tolist())}: on face {pc.face!r}, which is {face.type}; "
                                 f"a point sits on a free or loaded face")
            if face is not None and face.varying:
                if pc.type == "force":
                    raise SceneError(f"point[{k}]: a force on face {pc.face!r}, whose traction varies; put the force "
                                     f"on a face with a constant traction or none")
                tractions[pc.label] = face
            elif pc.type == "force" or face is not None:
                g = np.add(pc.traction() or (0.0, 0.0, 0.0), face.value if face is not None else (0.0, 0.0, 0.0))
                boundary[pc.label] = Condition3("traction", tuple(float(c) for c in g))
        scene = cls(name, description, domain, cracks, material, boundary, body, **sizes, points=points,
                    tractions=tractions)
        scene.check()
        return scene

    def check(self) -> None:
        """Scales double precision holds, the cracks inside the body and apart; the supports holding every
        rigid motion."""
        self._check_scales()
        for i, c in enumerate(self.cracks):
            problem = face_problem(self.domain, c, CLEARANCE_RTOL, self.boundary, lambda: self.mesh_sizes()["front_h"])
            if problem:  # inside every face by the clearance, or across free ones by as much (ngcrack.solid.surface)
                raise SceneError(f"crack[{i}]: {problem}")
        for i, ci in enumerate(self.cracks):
            for j in range(i):
                cj = self.cracks[j]
                pi, pj = ci.fill(), cj.fill()
                dist = np.min(np.linalg.norm(pi[:, None] - pj[None], axis=-1))
                gap = CLEARANCE_RTOL * max(ci.size, cj.size)
                if dist < gap:
                    raise SceneError(f"crack[{i}]: touches or comes too close to crack[{j}] (distance {dist:.3g}, "
                                     f"at least {gap:.3g} needed); cracks must stay apart")
        self._check_held()

    def _check_scales(self) -> None:
        """E, every load as a strain and every crack's size over the body's within MAX_SCALE, and each crack
        larger than the smallest mesh size netgen meshes (MIN_SIZE_RTOL of the body's diameter)."""
        E, d = self.material.E, self.size
        check_scale(E, 1.0, "material.E", "E")
        for label, cond in {**self.boundary, **self.tractions}.items():
            if cond.value is not None:
                if cond.varying:
                    check_scale(cond.value.largest(), 1.0 / E, f"boundary.{label}.value", "a traction over E")
                    continue
                to_strain = 1.0 / E if cond.type == "traction" else 1.0 / d
                check_scale(cond.value, to_strain, f"boundary.{label}.value", "a traction over E" if
                            cond.type == "traction" else "a displacement over the diameter")
        if self.body_force is not None:
            check_scale(self.body_force, d / E, "load.body_force", "a body force times the diameter over E")
        for i, c in enumerate(self.cracks):
            if c.pressure:
                check_scale(c.pressure.largest() if is_varying(c.pressure) else c.pressure, 1.0 / E, f"crack[{i}].pressure", "a pressure over E")
            smallest = min((a for a in c.semi_axes if a > 0), default=c.size)
            if smallest < MIN_SIZE_RTOL * d:
                raise SceneError(f"crack[{i}]: its smallest size {smallest:.3g} is below {MIN_SIZE_RTOL:g} of the body's "
                                 f"diameter {d:.3g}, the smallest length netgen meshes; give a larger crack")

    def _check_held(self) -> None:
        """The supports (faces and point supports) hold every rigid motion: rank 6 of their rows at points of
        the faces and at the points' centres (solid.points.rigid_rows)."""
        rows = rigid_rows(self.points)
        faces = self.domain.face_points()
        for label, cond in self.boundary.items():
            if label not in faces:  # a force point's patch
                continue
            pts, normals = faces[label]
            for p, n in zip(pts, normals):
                # a rigid motion u(p) = t + w x p = basis @ (t, w); column 3 + l is e_l x p
                basis = np.hstack([np.eye(3), np.array([np.cross(e, p) for e in np.eye(3)]).T])
                if cond.type in ("clamped", "displacement"):
                    rows.extend(basis)
                elif cond.type == "roller":
                    rows.append(n @ basis)
        rank = np.linalg.matrix_rank(np.array(rows)) if rows else 0
        if rank < 6:
            raise SceneError(f"boundary: the supports leave {6 - rank} rigid motion(s) free; clamp a face, put "
                             f"rollers on faces or pins and rollers at points ([[point]]) that hold every translation "
                             f"and rotation (labels: {', '.join(domain_labels(self.domain))})")

    # ------------------------------------------------------------------ sizes and changes
    @property
    def size(self) -> float:
        """The body's diameter (the largest distance between two of its points)."""
        return self.domain.size

    @property
    def diameter(self) -> float:
        """The body's diameter, as a planar scene's `diameter` (`size`)."""
        return self.domain.size

    def mesh_sizes(self, maxh=None, crack_h=None, front_h=None, grading=None) -> dict[str, float]:
        """maxh, crack_h, front_h, grading: the arguments, else the scene's, else the defaults.

        The defaults know the faces a front comes near without crossing them (`sizing.ligament_caps`): on a scene
        whose [mesh] sets none of maxh, crack_h and front_h, front_h is at most the ligament over
        `sizing.LIGAMENT_ELEMENTS` (not below `sizing.LIGAMENT_FLOOR_RTOL` of the crack's size) and crack_h
        its default ratio to front_h times that, unless the call gives crack_h or front_h; and where the body is
        thinner than the crack (a plate), maxh is at most `sizing.MAXH_THICKNESS` times its thickness there, unless
        the call gives maxh. Cracks far from the faces keep the crack-sized defaults exactly."""
        crack = min((inside_measures(self.domain, c)[0] for c in self.cracks), default=self.size)  # the parts inside
        front_cap = maxh_cap = math.inf
        if self.maxh is None and self.crack_h is None and self.front_h is None and self.cracks:
            front_cap, maxh_cap = ligament_caps(self.domain, self.cracks, crack)
            if crack_h or front_h:  # the call sets the crack's sizes: they keep their meaning
                front_cap = math.inf
        maxh = maxh or self.maxh or min(DEFAULT_MAXH_RTOL * self.size, DEFAULT_MAXH_CRACK_RTOL * crack, maxh_cap)
        ratio = DEFAULT_CRACK_H_RTOL / DEFAULT_FRONT_H_RTOL
        crack_h = crack_h or self.crack_h or min(DEFAULT_CRACK_H_RTOL * crack, maxh, ratio * front_cap)
        front_h = front_h or self.front_h or min(DEFAULT_FRONT_H_RTOL * crack, crack_h, front_cap)
        return {"maxh": float(maxh), "crack_h": float(crack_h), "front_h": float(front_h),
                "grading": float(grading or self.grading or DEFAULT_GRADING)}

    def with_(self, **changes: Any) -> SolidScene:
        """The scene with E, nu, friction or pressure (every crack), its cracks or a mesh size changed, validated again."""
        d = self.to_dict()
        for key, value in changes.items():
            if key in ("E", "nu"):
                d["material"][key] = value
            elif key in ("friction", "pressure"):
                for c in d.get("crack", []):
                    c[key] = value
            elif key in MESH_KEYS:
                d.setdefault("mesh", {})[key] = value
            elif key == "name":
                d["name"] = value
            elif key == "cracks":
                d["crack"] = [c.to_dict() for c in value]
            else:
                raise SceneError(f"{key}: not a field a 3D scene changes; allowed: E, nu, friction, pressure, cracks, name, "
                                 f"{', '.join(MESH_KEYS)}")
        return SolidScene.from_dict(d)

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"name": self.name}
        if self.description:
            d["description"] = self.description
        d["domain"] = self.domain.to_dict()
        if self.cracks:
            d["crack"] = [c.to_dict() for c in self.cracks]
        d["material"] = {"E": self.material.E, "nu": self.material.nu}
        if self.body_force is not None:
            d["load"] = {"body_force": list(self.body_force)}
        own = {pc.label for pc in self.points}
        d["boundary"] = {k: v.to_dict(f"boundary.{k}") for k, v in {**self.boundary, **self.tractions}.items()
                         if k not in own}
        if self.points:
            d["point"] = [pc.to_dict() for pc in self.points]
        mesh = {k: getattr(self, k) for k in MESH_KEYS if getattr(self, k) is not None}
        if mesh:
            d["mesh"] = mesh
        return d

    def to_toml_string(self) -> str:
        """The scene as TOML text; ``Scene.from_toml_string`` of it gives an equal scene."""
        from ..planar.scene.toml import dump_toml
        from .loads import check_writable

        d = self.to_dict()
        check_writable(d)
        return dump_toml(d)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, SolidScene) and self.to_dict() == other.to_dict()

    def __hash__(self) -> int:
        import json

        return hash(json.dumps(self.to_dict(), sort_keys=True, default=id))

    def replace(self, **fields) -> SolidScene:
        """The scene with some fields replaced (objects or their TOML tables), validated again as a new scene is."""
        names = [f.name for f in dataclasses.fields(self)]
        d = self.to_dict()
        for key, value in fields.items():
            if key not in names:
                raise SceneError(f"{key}: not a field of a 3D scene; its fields are {', '.join(names)}")
            if key in MESH_KEYS:
                d.setdefault("mesh", {})[key] = value
            elif key == "body_force":
                d["load"] = {} if value is None else {"body_force": _plain(value)}
            elif key in ("boundary", "tractions"):  # one TOML table of both (a force point's patch: its own)
                own = {pc.label for pc in self.points}
                other = self.tractions if key == "boundary" else self.boundary
                d["boundary"] = {**{k: c.to_dict(f"boundary.{k}") for k, c in other.items() if k not in own},
                                 **{k: v for k, v in _plain(value).items() if k not in own}}
            else:
                d[TOML_KEYS.get(key, key)] = _plain(value)
        return SolidScene.from_dict({k: v for k, v in d.items() if v is not None})


#: a scene field's key in the TOML document, where they differ
TOML_KEYS = {"cracks": "crack", "points": "point"}


def _plain(value: Any) -> Any:
    """A scene's field as TOML data: its parts' tables (to_dict), lists and plain values."""
    if hasattr(value, "to_dict"):
        return value.to_dict()
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return dataclasses.asdict(value)
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value
