"""3D scenes: a box or a cylinder holding planar cracks, as plain validated data.

A scene is 3D when its ``[domain]`` is (``box`` or ``cylinder``); ``Scene.from_toml``
hands such a document to :meth:`SolidScene.from_dict`. Like the 2D scene, a
:class:`SolidScene` is immutable and validated completely when it is built, before any
meshing: every bad field raises :class:`ngcrack.SceneError` naming the field and what is
allowed.

Domain
    ``box = [[x0, y0, z0], [x1, y1, z1]]``: faces ``xmin xmax ymin ymax zmin zmax``.
    ``cylinder = {center, axis, radius, height}``: ``center`` is the centre of the
    cylinder (mid-height on the axis); faces ``bottom`` (at center - height/2 axis),
    ``top`` and ``side``.
Cracks (``[[crack]]``), each a plane set strictly inside the body:
    ``shape = "disc"`` with ``center``, ``normal``, ``radius``;
    ``shape = "ellipse"`` with ``center``, ``normal``, ``semi_axes = [a, b]`` and
    ``major_axis`` (projected into the crack plane; the semi-axis a lies along it);
    ``shape = "polygon"`` with ``points`` (3 or more, in one plane, a simple polygon; the
    normal follows the right-hand rule of the point order). ``friction`` >= 0;
    ``pressure`` (a number, default 0): a uniform pressure on both faces, pushing them apart.
    The normal nu points into the ``+`` face; the jump is [u] = u+ - u-.
Cracks stay apart from each other and from the boundary (a clearance of
``CLEARANCE_RTOL`` times the crack's size); a crack reaching a face is a later step.
Boundary conditions by face label: ``clamped``, ``displacement`` (value = [ux, uy, uz]),
``roller`` (u.n = 0) or ``traction`` (value = [gx, gy, gz]); unnamed faces are free.
The supports must hold every rigid motion (checked on points of the faces).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..core.fields import MIN_SIZE_RTOL, SceneError, check_keys, check_scale, finite, is_number, positive, short, table
from ..core.scene import Scene

DOMAIN_KINDS = ("box", "cylinder")
SHAPES = ("disc", "ellipse", "polygon")
BOX_FACES = ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")
CYLINDER_FACES = ("bottom", "top", "side")
BOUNDARY_TYPES = ("clamped", "displacement", "roller", "traction")
TOP_KEYS = ("name", "description", "domain", "crack", "material", "load", "boundary", "mesh")
MESH_KEYS = ("maxh", "crack_h", "front_h", "grading")
#: a crack must keep this fraction of its size (diameter) away from the boundary and other cracks
CLEARANCE_RTOL = 0.05
#: points of a polygon crack off their plane by more than this fraction of its size are refused
PLANARITY_RTOL = 1e-6
#: default mesh sizes, as fractions: maxh of the body's size, crack_h and front_h of the crack's size
DEFAULT_MAXH_RTOL, DEFAULT_CRACK_H_RTOL, DEFAULT_FRONT_H_RTOL = 0.25, 0.2, 0.1
DEFAULT_GRADING = 0.3


def vector3(v: Any, fld: str, unit: bool = False) -> np.ndarray:
    """Three finite numbers [x, y, z] (a nonzero direction, normalised, with `unit`)."""
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if (isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) != 3
            or not all(is_number(c) and math.isfinite(float(c)) for c in v)):
        raise SceneError(f"{fld} = {short(v)}: must be a list of 3 finite numbers [x, y, z]")
    x = np.array([float(c) for c in v])
    if unit:
        n = np.linalg.norm(x)
        if n == 0.0:
            raise SceneError(f"{fld} = {short(v)}: must be a nonzero direction")
        x = x / n
    return x


def perpendicular(n: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to the unit vector n."""
    a = np.eye(3)[int(np.argmin(np.abs(n)))]
    e = a - np.dot(a, n) * n
    return e / np.linalg.norm(e)


# ------------------------------------------------------------------------------------ domains
@dataclass(frozen=True, eq=False)
class Box:
    lo: np.ndarray
    hi: np.ndarray
    labels = BOX_FACES

    @property
    def size(self) -> float:
        return float(np.linalg.norm(self.hi - self.lo))

    def clearance(self, p: np.ndarray) -> np.ndarray:
        """The distance of each point (rows of p) to the box's boundary, negative outside."""
        return np.minimum((p - self.lo).min(axis=1), (self.hi - p).min(axis=1))

    def face_points(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """(points on each face, its outward normal), for the rigid-motion check."""
        out = {}
        t = np.linspace(0.0, 1.0, 3)
        for k, ax in enumerate("xyz"):
            i, j = [m for m in range(3) if m != k]
            for side, val in (("min", self.lo[k]), ("max", self.hi[k])):
                pts = []
                for s in t:
                    for r in t:
                        p = np.zeros(3)
                        p[k] = val
                        p[i] = self.lo[i] + s * (self.hi[i] - self.lo[i])
                        p[j] = self.lo[j] + r * (self.hi[j] - self.lo[j])
                        pts.append(p)
                n = np.zeros(3)
                n[k] = -1.0 if side == "min" else 1.0
                out[ax + side] = (np.array(pts), np.tile(n, (len(pts), 1)))
        return out

    def to_dict(self) -> dict[str, Any]:
        return {"box": [self.lo.tolist(), self.hi.tolist()]}


@dataclass(frozen=True, eq=False)
class Cylinder:
    center: np.ndarray
    axis: np.ndarray
    radius: float
    height: float
    labels = CYLINDER_FACES

    @property
    def size(self) -> float:
        return float(math.hypot(2 * self.radius, self.height))

    @property
    def base(self) -> np.ndarray:
        return self.center - 0.5 * self.height * self.axis

    def clearance(self, p: np.ndarray) -> np.ndarray:
        d = p - self.center
        h = d @ self.axis
        r = np.linalg.norm(d - np.outer(h, self.axis), axis=1)
        return np.minimum(self.radius - r, 0.5 * self.height - np.abs(h))

    def face_points(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        e1 = perpendicular(self.axis)
        e2 = np.cross(self.axis, e1)
        phi = np.linspace(0.0, 2 * np.pi, 8, endpoint=False)
        ring = np.outer(np.cos(phi), e1) + np.outer(np.sin(phi), e2)
        half = 0.5 * self.height * self.axis
        out = {}
        for label, sign in (("bottom", -1.0), ("top", 1.0)):
            pts = self.center + sign * half + 0.5 * self.radius * ring
            out[label] = (pts, np.tile(sign * self.axis, (len(pts), 1)))
        side = np.concatenate([self.center + self.radius * ring + s * half for s in (-0.5, 0.5)])
        out["side"] = (side, np.concatenate([ring, ring]))
        return out

    def to_dict(self) -> dict[str, Any]:
        return {"cylinder": {"center": self.center.tolist(), "axis": self.axis.tolist(),
                             "radius": self.radius, "height": self.height}}


def domain_from_dict(d: Mapping[str, Any]) -> Box | Cylinder:
    check_keys(d, ("box", "cylinder", "step"), "domain")
    if "step" in d:
        raise SceneError("domain.step: STEP geometries are not supported yet (a later step); use box or cylinder")
    kinds = [k for k in DOMAIN_KINDS if k in d]
    if len(kinds) != 1:
        raise SceneError(f"domain: give exactly one of {', '.join(DOMAIN_KINDS)} (found {len(kinds)})")
    if kinds[0] == "box":
        v = d["box"]
        if isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) != 2:
            raise SceneError(f"domain.box = {short(v)}: must be two corners [[x0, y0, z0], [x1, y1, z1]]")
        lo, hi = vector3(v[0], "domain.box[0]"), vector3(v[1], "domain.box[1]")
        if not np.all(hi > lo):
            raise SceneError(f"domain.box = {short(v)}: the second corner must exceed the first in x, y and z")
        return Box(lo, hi)
    c = d["cylinder"]
    if not isinstance(c, Mapping):
        raise SceneError(f"domain.cylinder = {short(c)}: must be a table with keys center, axis, radius, height")
    check_keys(c, ("center", "axis", "radius", "height"), "domain.cylinder")
    for key in ("center", "axis", "radius", "height"):
        if key not in c:
            raise SceneError(f"domain.cylinder.{key}: missing; give center, axis, radius and height")
    return Cylinder(vector3(c["center"], "domain.cylinder.center"), vector3(c["axis"], "domain.cylinder.axis", unit=True),
                    positive(c["radius"], "domain.cylinder.radius"), positive(c["height"], "domain.cylinder.height"))


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
        if self.shape == "polygon":
            p = self.points - self.center
            return float(0.5 * abs(np.dot(np.sum(np.cross(p, np.roll(p, -1, axis=0)), axis=0), self.normal)))
        return float(math.pi * self.semi_axes[0] * self.semi_axes[1])

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"shape": self.shape}
        if self.shape == "polygon":
            d["points"] = self.points.tolist()
        else:
            d.update(center=self.center.tolist(), normal=self.normal.tolist())
            if self.shape == "disc":
                d["radius"] = self.radius
            else:
                d.update(semi_axes=list(self.semi_axes), major_axis=self.e_a.tolist())
        if self.friction:
            d["friction"] = self.friction
        if self.pressure:
            d["pressure"] = self.pressure
        return d


CRACK_KEYS = {"disc": ("shape", "center", "normal", "radius", "friction", "pressure"),
              "ellipse": ("shape", "center", "normal", "semi_axes", "major_axis", "friction", "pressure"),
              "polygon": ("shape", "points", "friction", "pressure")}
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
    if isinstance(p, bool) or not isinstance(p, (int, float)) or not math.isfinite(p):
        raise SceneError(f"{fld}.pressure = {short(p)}: must be a finite number (a uniform pressure on the faces; "
                         "tables and functions of position are 2D only)")
    return dataclasses.replace(_crack_shape(c, shape, fld, mu), pressure=float(p))


def _crack_shape(c: Mapping, shape: str, fld: str, mu: float) -> PlanarCrack:
    if shape == "polygon":
        return _polygon(c["points"], fld, mu)
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
    type: str
    value: tuple[float, float, float] | None = None

    @classmethod
    def from_dict(cls, d: Any, fld: str) -> Condition3:
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
        return cls(t, tuple(vector3(d["value"], f"{fld}.value").tolist()))

    def to_dict(self) -> dict[str, Any]:
        return {"type": self.type} if self.value is None else {"type": self.type, "value": list(self.value)}


# -------------------------------------------------------------------------------- the scene
@dataclass(frozen=True, eq=False)
class SolidScene(Scene, dimension=3):
    """A cracked 3D elastic body (module docstring). Build with :meth:`from_dict`."""

    body_module: ClassVar[str] = "ngcrack.solid.stages"

    name: str
    description: str
    domain: Box | Cylinder
    cracks: tuple[PlanarCrack, ...]
    material: Material3
    boundary: dict
    body_force: tuple[float, float, float] | None = None
    maxh: float | None = None
    crack_h: float | None = None
    front_h: float | None = None
    grading: float | None = None

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
        boundary = {}
        for label, cond in table(d, "boundary", "boundary").items():
            if label not in domain.labels:
                raise SceneError(f"boundary.{label}: no such face; the faces of a {type(domain).__name__.lower()} "
                                 f"are {', '.join(domain.labels)}")
            boundary[label] = Condition3.from_dict(cond, f"boundary.{label}")
        mesh = table(d, "mesh", "mesh")
        check_keys(mesh, MESH_KEYS, "mesh")
        sizes = {k: (None if k not in mesh else positive(mesh[k], f"mesh.{k}")) for k in MESH_KEYS}
        if sizes["grading"] is not None and not 0 < sizes["grading"] <= 1:
            raise SceneError(f"mesh.grading = {sizes['grading']!r}: must lie in (0, 1]")
        scene = cls(name, description, domain, cracks, material, boundary, body, **sizes)
        scene.check()
        return scene

    def check(self) -> None:
        """Scales double precision holds, the cracks inside the body and apart; the supports holding every
        rigid motion."""
        self._check_scales()
        for i, c in enumerate(self.cracks):
            gap = CLEARANCE_RTOL * c.size
            clear = self.domain.clearance(c.outline(256))
            if clear.min() < gap:
                where = "reaches or crosses the boundary" if clear.min() <= 0 else "comes too close to the boundary"
                raise SceneError(f"crack[{i}]: {where} (clearance {clear.min():.3g}, at least {gap:.3g} needed); "
                                 f"cracks reaching a face are not supported yet (a later step)")
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
        for label, cond in self.boundary.items():
            if cond.value is not None:
                to_strain = 1.0 / E if cond.type == "traction" else 1.0 / d
                check_scale(cond.value, to_strain, f"boundary.{label}.value", "a traction over E" if
                            cond.type == "traction" else "a displacement over the diameter")
        if self.body_force is not None:
            check_scale(self.body_force, d / E, "load.body_force", "a body force times the diameter over E")
        for i, c in enumerate(self.cracks):
            if c.pressure:
                check_scale(c.pressure, 1.0 / E, f"crack[{i}].pressure", "a pressure over E")
            smallest = min((a for a in c.semi_axes if a > 0), default=c.size)
            if smallest < MIN_SIZE_RTOL * d:
                raise SceneError(f"crack[{i}]: its smallest size {smallest:.3g} is below {MIN_SIZE_RTOL:g} of the body's "
                                 f"diameter {d:.3g}, the smallest length netgen meshes; give a larger crack")

    def _check_held(self) -> None:
        rows = []
        faces = self.domain.face_points()
        for label, cond in self.boundary.items():
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
            raise SceneError(f"boundary: the supports leave {6 - rank} rigid motion(s) free; clamp a face or put "
                             f"rollers on faces that hold every translation and rotation (labels: "
                             f"{', '.join(self.domain.labels)})")

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
        """maxh, crack_h, front_h, grading: the arguments, else the scene's, else the defaults."""
        crack = min((c.size for c in self.cracks), default=self.size)
        maxh = maxh or self.maxh or DEFAULT_MAXH_RTOL * self.size
        crack_h = crack_h or self.crack_h or min(DEFAULT_CRACK_H_RTOL * crack, maxh)
        front_h = front_h or self.front_h or min(DEFAULT_FRONT_H_RTOL * crack, crack_h)
        return {"maxh": float(maxh), "crack_h": float(crack_h), "front_h": float(front_h),
                "grading": float(grading or self.grading or DEFAULT_GRADING)}

    def with_(self, **changes: Any) -> SolidScene:
        """The scene with E, nu, friction or pressure (every crack) or a mesh size changed, validated again."""
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
            else:
                raise SceneError(f"{key}: not a field a 3D scene changes; allowed: E, nu, friction, pressure, name, "
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
        d["boundary"] = {k: v.to_dict() for k, v in self.boundary.items()}
        mesh = {k: getattr(self, k) for k in MESH_KEYS if getattr(self, k) is not None}
        if mesh:
            d["mesh"] = mesh
        return d

    def to_toml_string(self) -> str:
        """The scene as TOML text; ``Scene.from_toml_string`` of it gives an equal scene."""
        from ..planar.scene.toml import dump_toml

        return dump_toml(self.to_dict())

    def __eq__(self, other: object) -> bool:
        return isinstance(other, SolidScene) and self.to_dict() == other.to_dict()

    def __hash__(self) -> int:
        import json

        return hash(json.dumps(self.to_dict(), sort_keys=True))

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
