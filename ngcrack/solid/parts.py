"""The bodies of 3D scenes: a box, a cylinder or a part read from a STEP file.

``[domain]`` holds exactly one of

``box = [[x0, y0, z0], [x1, y1, z1]]``
    faces ``xmin xmax ymin ymax zmin zmax``;
``cylinder = {center, axis, radius, height}``
    ``center`` the centre of the cylinder (mid-height on the axis); faces ``bottom`` (at
    center - height/2 axis), ``top`` and ``side``;
``step = "part.step"``
    one solid read from a STEP file with OpenCascade (netgen.occ); a relative path is taken
    from the scene file's folder. Its faces are labelled by the names the file gives them
    and, where a face has none, ``face<i>`` (i its index in the file's face order, from 0;
    several faces may share a name: a condition on it holds on all). A missing or unreadable file, a file
    without exactly one solid, a face name that, read as a regular expression (as the mesh's regions are
    found), names another face or not itself (``a|b``, ``f(1)``), or a label that names no face is refused by name
    (``domain.step``, ``boundary.<label>``) before any meshing.

Each kind answers what the scene's checks ask of a body: its size, the clearance of points
from its boundary (negative outside), points and normals on each face (the rigid-motion
check of the supports) and, for a point support, the planar face a point lies on with its
normal and the room around the point on that face (`face_at`).

For a STEP part the clearance is OpenCascade's distance from each point to the solid
(outside) and to its nearest face (inside): exact for the part as the file describes it,
except that OCC counts a point within about 1e-3 of a face as outside; `face_distances` gives
the distance to each label's faces (negative, at a point outside, for the label nearest to it),
which is how a crack crossing a part's free faces (a corner crack at a hole) is checked and
where its front's ligament is measured (``ngcrack.solid.surface``).
"""

from __future__ import annotations

import math
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..core.fields import SceneError, check_keys, is_number, positive, short

DOMAIN_KINDS = ("box", "cylinder", "step")
BOX_FACES = ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")
CYLINDER_FACES = ("bottom", "top", "side")
#: a point is on a face when it is this fraction of the body's size from it, at most
ON_FACE_RTOL = 1e-6
#: points per edge of a STEP face used by the rigid-motion check
EDGE_SAMPLES = 5
#: a STEP face is planar when its normals at sample parameters agree to this
PLANAR_TOL = 1e-9


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


@dataclass(frozen=True)
class FaceSpot:
    """Where a point sits on a body: the face's label, its unit normal (up to sign) and the
    distance from the point to the face's boundary in the face (how wide a patch fits)."""

    label: str
    normal: np.ndarray
    room: float


def _not_on_face(at: np.ndarray, dist: float, label: str) -> SceneError:
    return SceneError(f"at = {short(at.tolist())}: not on the body's boundary (it is {dist:.3g} from the nearest "
                      f"face, {label!r}); a point sits on a face")


# ------------------------------------------------------------------------------------ box
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

    def face_at(self, at: np.ndarray) -> FaceSpot:
        """The face the point lies on (FaceSpot), or a SceneError."""
        best = None
        for k, ax in enumerate("xyz"):
            for side, val in (("min", self.lo[k]), ("max", self.hi[k])):
                d = abs(at[k] - val)
                others = [m for m in range(3) if m != k]
                outside = max(max(self.lo[m] - at[m], at[m] - self.hi[m], 0.0) for m in others)
                d = math.hypot(d, outside)
                if best is None or d < best[0]:
                    room = min(min(at[m] - self.lo[m], self.hi[m] - at[m]) for m in others)
                    best = (d, ax + side, np.eye(3)[k], room)
        if best[0] > ON_FACE_RTOL * self.size:
            raise _not_on_face(at, best[0], best[1])
        return FaceSpot(best[1], best[2], float(best[3]))

    def to_dict(self) -> dict[str, Any]:
        return {"box": [self.lo.tolist(), self.hi.tolist()]}


# ------------------------------------------------------------------------------- cylinder
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

    def face_at(self, at: np.ndarray) -> FaceSpot:
        """The end face the point lies on (the side is curved: refused by name)."""
        d = at - self.center
        h = float(d @ self.axis)
        r = float(np.linalg.norm(d - h * self.axis))
        ends = abs(abs(h) - 0.5 * self.height)
        tol = ON_FACE_RTOL * self.size
        if abs(r - self.radius) <= tol and abs(h) <= 0.5 * self.height + tol and ends > tol:
            raise SceneError(f"at = {short(at.tolist())}: on the cylinder's side, a curved face; point supports and "
                             f"loads sit on planar faces (top, bottom)")
        dist = math.hypot(ends, max(r - self.radius, 0.0))
        label = "top" if h > 0 else "bottom"
        if dist > tol:
            raise _not_on_face(at, dist, label)
        return FaceSpot(label, self.axis.copy(), self.radius - r)

    def to_dict(self) -> dict[str, Any]:
        return {"cylinder": {"center": self.center.tolist(), "axis": self.axis.tolist(),
                             "radius": self.radius, "height": self.height}}


# -------------------------------------------------------------------------------- STEP
@dataclass(frozen=True, eq=False)
class StepPart:
    """A solid read from a STEP file (module docstring); `labels` every face's label in the
    file's face order (its name, else ``face<i>``)."""

    path: str
    labels: tuple[str, ...]
    _shape: Any = field(repr=False, compare=False)

    @property
    def size(self) -> float:
        lo, hi = self.bounds
        return float(np.linalg.norm(hi - lo))

    @property
    def volume(self) -> float:
        return float(self._shape.mass)

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = self._shape.bounding_box
        return np.array([lo.x, lo.y, lo.z]), np.array([hi.x, hi.y, hi.z])

    def aliases(self) -> dict[str, list[int]]:
        """label -> the indices of the faces carrying it."""
        out: dict[str, list[int]] = {}
        for i, lab in enumerate(self.labels):
            out.setdefault(lab, []).append(i)
        return out

    def occ_shape(self):
        """A fresh copy of the solid with every face named by its label (what the mesher glues)."""
        from netgen import occ

        shape = _read_step(self.path, "domain.step")
        for f, lab in zip(shape.faces, self.labels):
            f.name = lab
        return shape if isinstance(shape, occ.Solid) else shape.solids[0]

    def clearance(self, p: np.ndarray) -> np.ndarray:
        """OCC's distance of each point to the part's faces, negative outside the solid."""
        from netgen import occ

        faces = list(self._shape.faces)
        out = np.empty(len(p))
        for k, q in enumerate(np.asarray(p, dtype=float)):
            v = occ.Vertex(occ.Pnt(*q))
            outside = self._shape.Distance(v)
            out[k] = -outside if outside > 0 else min(f.Distance(v) for f in faces)
        return out

    def face_distances(self, p: np.ndarray) -> dict[str, np.ndarray]:
        """Per label, the distance of each point to its faces, negative at a point outside the solid for the label
        nearest to it (the face it crossed): the box's signed face distances (``solid.surface.face_distances``)."""
        from netgen import occ

        faces = list(self._shape.faces)
        labels = list(self.aliases().items())
        out = np.empty((len(labels), len(p)))
        for k, q in enumerate(np.asarray(p, dtype=float)):
            v = occ.Vertex(occ.Pnt(*q))
            d = [f.Distance(v) for f in faces]
            out[:, k] = [min(d[i] for i in idx) for _, idx in labels]
            outside = self._shape.Distance(v)
            if outside > 0:
                j = int(np.argmin(out[:, k]))
                out[j, k] = -max(outside, out[j, k])
        return {lab: out[j] for j, (lab, _) in enumerate(labels)}

    def face_points(self) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Per label, points on its faces' edges (EDGE_SAMPLES per edge) and the faces' normals there (a
        curved face's normals are NaN: a roller there is refused before, `check_rollers`)."""
        out: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        faces = list(self._shape.faces)
        for lab, idx in self.aliases().items():
            pts, nrm = [], []
            for i in idx:
                n = self._plane_normal(faces[i])
                for e in faces[i].edges:
                    t0, t1 = e.parameter_interval
                    for t in np.linspace(t0, t1, EDGE_SAMPLES):
                        q = e.Value(float(t))
                        pts.append([q.x, q.y, q.z])
                        nrm.append(n if n is not None else np.full(3, np.nan))
            out[lab] = (np.array(pts), np.array(nrm))
        return out

    @staticmethod
    def _plane_normal(face) -> np.ndarray | None:
        """The unit normal of a planar face (up to sign), None for a curved one."""
        surf, normals = face.surf, []
        for u, w in ((0.0, 0.0), (0.37, 0.61), (1.3, -0.7), (-2.1, 1.9)):
            _, du, dw = surf.D1(u, w)  # the surface's normal there: du x dw
            normals.append(np.cross([du.x, du.y, du.z], [dw.x, dw.y, dw.z]))
        normals = np.array(normals) / np.linalg.norm(normals, axis=1)[:, None]
        return normals[0] if np.abs(np.abs(normals @ normals[0]) - 1.0).max() <= PLANAR_TOL else None

    def check_rollers(self, boundary: Mapping[str, Any]) -> None:
        """Refuse a roller on a curved face of the part (its normal varies: not supported yet)."""
        faces = list(self._shape.faces)
        for lab, cond in boundary.items():
            if cond.type == "roller" and any(self._plane_normal(faces[i]) is None for i in self.aliases().get(lab, [])):
                raise SceneError(f"boundary.{lab}.type = 'roller': a roller on a curved face of a STEP part is not "
                                 f"supported; clamp it, or hold the part by rollers on planar faces or point supports")

    def face_at(self, at: np.ndarray) -> FaceSpot:
        """The planar face the point lies on, its normal and the distance to its edges."""
        from netgen import occ

        v = occ.Vertex(occ.Pnt(*at))
        faces = list(self._shape.faces)
        dist = [f.Distance(v) for f in faces]
        i = int(np.argmin(dist))
        if dist[i] > ON_FACE_RTOL * self.size:
            raise _not_on_face(at, dist[i], self.labels[i])
        normal = self._plane_normal(faces[i])
        if normal is None:
            raise SceneError(f"at = {short(at.tolist())}: on face {self.labels[i]!r} (face{i}), which is curved; "
                             f"point supports and loads sit on planar faces")
        room = min((e.Distance(v) for e in faces[i].edges), default=0.0)
        return FaceSpot(self.labels[i], normal, float(room))

    def to_dict(self) -> dict[str, Any]:
        return {"step": self.path}


def _read_step(path: str, fld: str):
    """The shape of a STEP file, or a SceneError naming `fld`."""
    from netgen import occ

    if os.path.isdir(path):
        raise SceneError(f"{fld} = {path!r}: is a directory; give the path of a STEP file")
    if not os.path.isfile(path):
        raise SceneError(f"{fld} = {path!r}: no such file (a relative path is taken from the scene file's folder)")
    try:
        geo = occ.OCCGeometry(path)
        shape = geo.shape
    except Exception as exc:  # OCC's reader: any failure is an unreadable file
        raise SceneError(f"{fld} = {path!r}: cannot be read as a STEP file ({type(exc).__name__}: {exc})") from None
    if shape is None or len(shape.faces) == 0:
        raise SceneError(f"{fld} = {path!r}: holds no faces; give a STEP file with one solid")
    return shape


def step_part(path: Any, fld: str = "domain.step") -> StepPart:
    """The STEP part at `path` (module docstring), checked by name."""
    if not isinstance(path, (str, os.PathLike)) or not str(path):
        raise SceneError(f"{fld} = {short(path)}: must be the path of a STEP file (a string)")
    path = os.path.abspath(os.fspath(path))
    shape = _read_step(path, fld)
    solids = list(shape.solids)
    if len(solids) != 1:
        raise SceneError(f"{fld} = {path!r}: holds {len(solids)} solids; give a STEP file with exactly one")
    solid = solids[0]
    labels = tuple(f.name if f.name else f"face{i}" for i, f in enumerate(solid.faces))
    for i, lab in enumerate(labels):
        if re.fullmatch(r"(crack|front|point)\d+", lab):
            raise SceneError(f"{fld}: face {i} is named {lab!r}; the names crack<i>, front<i> and point<k> are the "
                             f"solver's own; rename the face in the file")
    for i, lab in enumerate(labels):  # the mesh's regions are found by pattern: 'a|b' would also be faces a and b
        try:
            named = sorted({m for m in labels if re.fullmatch(lab, m)})
        except re.error:
            named = []
        if named != [lab]:
            raise SceneError(f"{fld}: face {i} is named {lab!r}, which the mesh reads as a pattern (a regular "
                             f"expression) naming {', '.join(repr(m) for m in named) or 'no face'}; rename the face in "
                             f"the file (letters, digits, _, - and spaces are safe)")
    return StepPart(path, labels, solid)


def domain_from_dict(d: Mapping[str, Any]) -> Box | Cylinder | StepPart:
    check_keys(d, DOMAIN_KINDS, "domain")
    kinds = [k for k in DOMAIN_KINDS if k in d]
    if len(kinds) != 1:
        raise SceneError(f"domain: give exactly one of {', '.join(DOMAIN_KINDS)} (found {len(kinds)})")
    if kinds[0] == "step":
        return step_part(d["step"])
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


def domain_labels(domain) -> tuple[str, ...]:
    """Every label a boundary condition may name on the domain (each once)."""
    if isinstance(domain, StepPart):
        return tuple(domain.aliases())
    return tuple(domain.labels)
