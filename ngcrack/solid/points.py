"""Point supports and point loads on a 3D body: ``[[point]]`` tables.

A point condition sits at ``at = [x, y, z]`` on a planar face of the body and acts on the
patch of diameter ``width`` centred there: a regular polygon of PATCH_SIDES sides inscribed in
the circle of that diameter (flat sides: the mesh's curving leaves the patch's elements
straight, so that a linear field stays in the mixed element's space there), which the mesher
imprints on the face as a face of its own labelled ``label`` (default ``point<k>``):

``force``   the total force ``value = [Fx, Fy, Fz]`` spread as a uniform traction over the
            patch (scaled to the meshed patch's area: the resultant is exact);
``pin``     the mean displacement of the patch is held at zero (three constraints): the
            patch's centre cannot move, the body may turn about it;
``roller``  the mean normal displacement of the patch is held at zero (one constraint),
            its tangential motion is free.

Pins and rollers hold means, not the patch itself, so their reactions are uniform tractions
over the patch: three pins not on one line with rollers make the 3-2-1 support that holds a
body with every load in equilibrium without constraining it (pin: 3, a roller on one
face: 2, on another: 1). The patch takes the point's condition in place of its face's.

Without ``width`` the patch is POINT_WIDTH_FRACTION of the scene's maxh (its default
when the scene gives none); it is meshed at PATCH_H_FRACTION of its width. Refused by field
before any meshing: an unknown key or type, a force without value or a support with one, a
point not on a face (or on a curved face), a patch that does not fit on its face at least
MIN_GAP_RTOL of the body's size from the face's edges, two patches overlapping, a label
taken by a face, and a [boundary.<label>] for a point's label.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..core.fields import SceneError, check_keys, positive, short
from .parts import perpendicular, vector3

#: the point condition types and whether each takes a value
POINT_TYPES: Mapping[str, bool] = {"force": True, "pin": False, "roller": False}
#: the default width (diameter) of a patch, as a fraction of the scene's maxh (as in 2D)
POINT_WIDTH_FRACTION = 0.5
#: the mesh size on a patch, as a fraction of its width
PATCH_H_FRACTION = 0.5
#: the sides of a patch's polygon
PATCH_SIDES = 8
#: a patch keeps this fraction of the body's size from its face's edges and from other patches
MIN_GAP_RTOL = 1e-3
#: the most point conditions of a scene
MAX_POINTS = 100
POINT_KEYS = ("at", "type", "value", "width", "label")


@dataclass(frozen=True, eq=False)
class PointCondition3:
    """A load or support on a patch of a face (module docstring), resolved against the body:
    `face` the label of the face it lies on, `normal` that face's unit normal (up to sign)."""

    at: np.ndarray
    type: str
    value: tuple[float, float, float] | None
    width: float
    label: str
    face: str
    normal: np.ndarray
    given_width: bool = True
    given_label: bool = True

    @property
    def area(self) -> float:
        """The patch's area: the regular PATCH_SIDES-gon inscribed in the circle of diameter width."""
        r = 0.5 * self.width
        return 0.5 * PATCH_SIDES * r * r * math.sin(2 * math.pi / PATCH_SIDES)

    def traction(self) -> tuple[float, float, float] | None:
        """The uniform traction of a force, value / area (None for a support)."""
        return None if self.value is None else tuple(float(v) / self.area for v in self.value)

    def directions(self) -> tuple[tuple[float, float, float], ...]:
        """The directions whose mean over the patch is held: e_x, e_y, e_z (pin), the normal (roller), none."""
        if self.type == "pin":
            return tuple(tuple(e) for e in np.eye(3).tolist())
        if self.type == "roller":
            return (tuple(float(c) for c in self.normal),)
        return ()

    def to_dict(self) -> dict[str, Any]:
        d: dict[str, Any] = {"at": self.at.tolist(), "type": self.type}
        if self.value is not None:
            d["value"] = list(self.value)
        if self.given_width:
            d["width"] = self.width
        if self.given_label:
            d["label"] = self.label
        return d


def points_from_list(raw: Any, domain, maxh: float, taken: Sequence[str]) -> tuple[PointCondition3, ...]:
    """The ``[[point]]`` list resolved on the domain (module docstring); `maxh` the scene's mesh size
    (or its default), `taken` the labels of the body's faces."""
    if isinstance(raw, (str, bytes, Mapping)) or not isinstance(raw, Sequence):
        raise SceneError(f"point = {short(raw)}: must be an array of tables ([[point]] with at, type and, for a "
                         f"force, value)")
    if len(raw) > MAX_POINTS:
        raise SceneError(f"point: {len(raw)} point conditions; at most {MAX_POINTS} are allowed")
    out: list[PointCondition3] = []
    gap = MIN_GAP_RTOL * domain.size
    for k, d in enumerate(raw):
        pc = _one(d, f"point[{k}]", domain, maxh, taken)
        fld = f"point[{k}]"
        for j, other in enumerate(out):
            if other.label == pc.label:
                raise SceneError(f"{fld}.label = {pc.label!r}: already the label of point[{j}]; give each point its own")
            if np.linalg.norm(other.at - pc.at) < 0.5 * (other.width + pc.width) + gap:
                raise SceneError(f"{fld}.at = {short(pc.at.tolist())}: its patch overlaps the patch of point[{j}] "
                                 f"(centres {np.linalg.norm(other.at - pc.at):.3g} apart, widths {pc.width:.3g} and "
                                 f"{other.width:.3g}); two point conditions may not overlap")
        out.append(pc)
    return tuple(out)


def _one(d: Any, fld: str, domain, maxh: float, taken: Sequence[str]) -> PointCondition3:
    if not isinstance(d, Mapping):
        raise SceneError(f"{fld} = {short(d)}: must be a table with keys {', '.join(POINT_KEYS)}")
    check_keys(d, POINT_KEYS, fld)
    for key in ("at", "type"):
        if key not in d:
            raise SceneError(f"{fld}.{key}: missing; a point needs at = [x, y, z] on a face and type = "
                             f"{' | '.join(POINT_TYPES)}")
    t = d["type"]
    if not isinstance(t, str) or t not in POINT_TYPES:
        raise SceneError(f"{fld}.type = {short(t)}: allowed types are {', '.join(POINT_TYPES)}")
    value = None
    if POINT_TYPES[t]:
        if "value" not in d:
            raise SceneError(f"{fld}.value: missing; type = {t!r} needs value = [Fx, Fy, Fz] (the total force)")
        value = tuple(vector3(d["value"], f"{fld}.value").tolist())
    elif "value" in d:
        raise SceneError(f"{fld}.value = {short(d['value'])}: type = {t!r} takes no value; remove it")
    at = vector3(d["at"], f"{fld}.at")
    given = "width" in d
    width = positive(d["width"], f"{fld}.width") if given else POINT_WIDTH_FRACTION * maxh
    label = d.get("label", None)
    given_label = label is not None
    if label is None:
        label = f"point{fld[len('point['):-1]}"
    elif not isinstance(label, str) or not label or not label.isidentifier():
        raise SceneError(f"{fld}.label = {short(label)}: must be a name (letters, digits, _)")
    if label in taken or re.fullmatch(r"(crack|front)\d+", label):
        raise SceneError(f"{fld}.label = {label!r}: already a label of the body (or the solver's own: crack<i>, "
                         f"front<i>); choose another")
    try:
        spot = domain.face_at(at)
    except SceneError as exc:
        raise SceneError(f"{fld}.{exc}") from None
    gap = MIN_GAP_RTOL * domain.size
    if width < gap:
        raise SceneError(f"{fld}.width = {width:.6g}: must be at least {gap:.3g} ({MIN_GAP_RTOL:g} of the body's size)")
    if spot.room <= gap:  # on the face's edge (or a corner): no width fits
        raise SceneError(f"{fld}.at = {short(at.tolist())}: on the edge of face {spot.label!r} ({spot.room:.3g} from "
                         f"it); a point sits inside a face, at least {gap:.3g} plus half its width from the face's edges")
    if 0.5 * width + gap > spot.room:
        raise SceneError(f"{fld}.width = {width:.6g}: the patch centred at {short(at.tolist())} does not fit on face "
                         f"{spot.label!r} (the face's edge is {spot.room:.3g} away); give a width below "
                         f"{max(2 * (spot.room - gap), 0.0):.3g} or move the point")
    return PointCondition3(at, t, value, float(width), label, spot.label, spot.normal,
                           given_width=given, given_label=given_label)


def rigid_rows(points: Sequence[PointCondition3]) -> list[np.ndarray]:
    """The rows a rigid motion u(p) = t + w x p = basis (t, w) must satisfy at the supports' centres."""
    rows = []
    for pc in points:
        basis = np.hstack([np.eye(3), np.array([np.cross(e, pc.at) for e in np.eye(3)]).T])
        for d in pc.directions():
            rows.append(np.asarray(d) @ basis)
    return rows


def held_directions(points: Sequence[PointCondition3]) -> dict[str, tuple]:
    """label -> the directions whose mean over the patch is held (pins and rollers)."""
    return {pc.label: pc.directions() for pc in points if pc.type != "force"}


def patch_faces(points: Sequence[PointCondition3]) -> list:
    """The patches as OCC polygons in their faces' planes, named by label, meshed at PATCH_H_FRACTION width:
    glued with the body, each becomes a face of its own."""
    from netgen import occ

    out = []
    for pc in points:
        e1 = perpendicular(pc.normal)
        e2 = np.cross(pc.normal, e1)
        phi = 2 * np.pi * np.arange(PATCH_SIDES) / PATCH_SIDES
        corners = [occ.Pnt(*(pc.at + 0.5 * pc.width * (math.cos(t) * e1 + math.sin(t) * e2))) for t in phi]
        disc = occ.Face(occ.Wire([occ.Segment(corners[i], corners[(i + 1) % PATCH_SIDES]) for i in range(PATCH_SIDES)]))
        disc.name = pc.label
        disc.faces.maxh = PATCH_H_FRACTION * pc.width
        for e in disc.edges:
            e.maxh = PATCH_H_FRACTION * pc.width
        out.append(disc)
    return out


def scaled(points: Sequence[PointCondition3], force: float) -> tuple[PointCondition3, ...]:
    """The points with their forces times `force`."""
    return tuple(replace(pc, value=None if pc.value is None else tuple(force * v for v in pc.value)) for pc in points)
