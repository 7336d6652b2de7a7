"""The Scene: one cracked 2D elastic body as plain, immutable, validated data.

A :class:`PlanarScene` holds the polygon and its edge labels, the cracks, the material, the
loads, the supports and the optional mesh sizes. It is validated completely when it is
built (``__post_init__``): the fields one by one (``fields``, ``types``), the polylines
against each other (``planar``), then the supports against rigid motion (``topology``),
so no invalid Scene can exist. Its geometric queries (tips, through cracks, edge
pieces, parts) are what the mesher and the solver read.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

if TYPE_CHECKING:
    import shapely

from ...core.fields import (
    FrozenMap,
    SceneError,
    check_keys,
    fmt,
    fmt_pt,
    pair,
    points,
    positive,
    short,
    unique,
)
from ...core.scene import Scene
from . import toml as _toml
from .holes import Hole, check_holes, check_not_on_holes, hole_ends
from .measures import (
    Point,
    diameter,
    dist,
    dot,
    point_segment_distance,
    signed_area,
    sub,
)
from .planar import (
    Walls,
    check_crack_in_domain,
    check_cracks_disjoint,
    check_gaps,
    check_polyline_simple,
)
from .points import (
    PointCondition,
    coerce_points,
    force_conditions,
    from_tractions,
    insert_points,
    strip_points,
    warn_held_mouths,
)
from .pressure import check_pressure
from .topology import Part, check_held, parts
from .types import (
    GEOMETRY_RTOL,
    MAX_BOUNDARY_POINTS,
    MAX_SCALE,
    MIN_SIZE_RTOL,
    RESERVED_LABEL_PREFIX,
    BoundaryCondition,
    Crack,
    Material,
    check_exact,
    check_load,
    crack_points,
    friction_coefficient,
)

__all__ = ["MAX_POLYGON_VERTICES", "PlanarScene", "Scene"]


#: The most vertices a polygon may have: validation is near-linear, netgen meshes a
#: circle of 1500 vertices in 1.6 s and one of 4000 in 7.4 s (measured).
MAX_POLYGON_VERTICES = 4000


def _check_name(name, description) -> None:
    """A non-empty name and a one-line description."""
    if not isinstance(name, str) or not name.strip():
        raise SceneError(f"name = {name!r}: must be a non-empty string")
    if not isinstance(description, str) or "\n" in description:
        raise SceneError(f"description = {short(description)}: must be a one-line string")


def _check_modulus(E: float) -> float:
    """Young's modulus within the range the solves hold in double precision."""
    if not 1.0 / MAX_SCALE <= E <= MAX_SCALE:
        raise SceneError(f"material.E = {fmt(E)}: must lie between {1.0 / MAX_SCALE:g} and "
                         f"{MAX_SCALE:g} (change the units)")
    return E


def _check_polygon(poly) -> float:
    """Refuse a polygon out of range, degenerate, self-intersecting or clockwise; its diameter."""
    for i, p in enumerate(poly):
        if max(abs(p[0]), abs(p[1])) > MAX_SCALE:
            raise SceneError(f"domain.polygon[{i}] = {fmt_pt(p)}: coordinates must lie "
                             f"within +-{MAX_SCALE:g}")
    diam = diameter(poly)
    if diam == 0.0:
        raise SceneError("domain.polygon: all vertices coincide; give 3 or more "
                         "distinct vertices, counter-clockwise")
    if diam < 1.0 / MAX_SCALE:
        raise SceneError(f"domain.polygon: the body is {fmt(diam)} across; its diameter "
                         f"must be at least {1.0 / MAX_SCALE:g}")
    tol = GEOMETRY_RTOL * diam
    check_polyline_simple(poly, "domain.polygon", tol, closed=True, what="edge")
    area = signed_area(poly)
    if area <= tol * diam:
        if area < -tol * diam:
            raise SceneError("domain.polygon: is clockwise; list the vertices "
                             "counter-clockwise")
        raise SceneError("domain.polygon: has zero area; give a simple polygon with "
                         "its vertices counter-clockwise")
    return diam


def _check_labels(labels, n: int) -> tuple[str, ...]:
    """One non-empty, unreserved label per edge (e0, e1, ... where none are given)."""
    if labels is None or (isinstance(labels, Sequence) and len(labels) == 0):
        labels = tuple(f"e{i}" for i in range(n))
    if isinstance(labels, (str, bytes)) or not isinstance(labels, Sequence):
        raise SceneError(f"domain.labels = {short(labels)}: must be a list of "
                         f"{n} strings, one per edge")
    if len(labels) != n:
        raise SceneError(f"domain.labels: {len(labels)} labels for {n} edges; give "
                         f"one label per edge (edge i runs from vertex i to vertex "
                         f"i+1)")
    for i, lab in enumerate(labels):
        if not isinstance(lab, str) or not lab:
            raise SceneError(f"domain.labels[{i}] = {lab!r}: must be a non-empty "
                             f"string")
        if lab.startswith(RESERVED_LABEL_PREFIX):
            raise SceneError(f"domain.labels[{i}] = {lab!r}: labels starting with "
                             f"{RESERVED_LABEL_PREFIX!r} are reserved (the mesher names the "
                             f"crack faces so); choose another label")
    return tuple(labels)


def _check_mesh_values(scene, diam: float) -> dict[str, float]:
    """The [mesh] values given (maxh, tip_h, crack_h within range of the diameter; grading
    in (0, 1]), checked and as floats."""
    out = {}
    for key in ("maxh", "tip_h", "crack_h"):
        if getattr(scene, key) is not None:
            h = positive(getattr(scene, key), f"mesh.{key}")
            if not MIN_SIZE_RTOL * diam <= h <= MAX_SCALE * diam:
                raise SceneError(
                    f"mesh.{key} = {fmt(h)}: must lie between {MIN_SIZE_RTOL:g} and "
                    f"{MAX_SCALE:g} times the body's diameter {fmt(diam)} (netgen fails, hangs "
                    f"or crashes on smaller sizes, measured)")
            out[key] = h
    if scene.grading is not None:
        g = positive(scene.grading, "mesh.grading")
        if g > 1.0:
            raise SceneError(f"mesh.grading = {fmt(g)}: must lie in (0, 1] (netgen's "
                             f"default is 0.3)")
        out["grading"] = g
    return out


def _with_on_every_crack(cracks, key: str, value) -> tuple:
    """`cracks` (Crack objects, their tables or bare point lists) with field `key` set to
    `value` on every one (`Scene.with_`'s friction and pressure)."""
    if isinstance(cracks, (str, bytes, Mapping)) or not isinstance(cracks, Sequence):
        raise SceneError(f"crack = {short(cracks)}: must be a list of cracks")
    return tuple(dataclasses.replace(c, **{key: value}) if isinstance(c, Crack)
                 else {**c, key: value} if isinstance(c, Mapping) else {"points": c, key: value}
                 for c in cracks)


@dataclass(frozen=True, kw_only=True)
class PlanarScene(Scene, dimension=2):
    """A cracked 2D elastic body: polygon, cracks, material, loads, supports, mesh sizes.

    Fields (all validated on construction; lists and tables are accepted and stored as
    tuples, :class:`Crack`, :class:`Material`, :class:`BoundaryCondition`):

    ``name``; ``polygon`` the vertices, counter-clockwise; ``labels`` one per edge
    (edge i runs from vertex i to vertex i+1; default ``e0, e1, ...``); ``cracks``;
    ``holes`` (:class:`Hole`: polygons or circles inside the body, their edges labelled);
    ``material``; ``body_force`` f = (fx, fy) or None; ``boundary`` label -> condition
    (unnamed edges are traction-free); ``maxh`` global mesh size, ``crack_h`` size along
    the cracks, ``grading`` how fast sizes grow (netgen, 0.3 default) and ``tip_h`` local
    size at crack tips (None: the solver decides); ``description`` one line;
    ``exact`` closed-form metadata (see :data:`EXACT_KINDS`) or None; ``points``
    loads and supports at points of the outer boundary (:class:`PointCondition`, the
    ``[[point]]`` tables): their segments are inserted into ``polygon`` and ``labels``, a
    force is stored as a traction on its label in ``boundary`` (``points.py``).
    """

    body_module: ClassVar[str] = "ngcrack.planar.stages"

    name: str
    polygon: tuple[tuple[float, float], ...]
    material: Material
    labels: tuple[str, ...] = ()
    cracks: tuple[Crack, ...] = ()
    holes: tuple[Hole, ...] = ()
    body_force: tuple[float, float] | None = None
    boundary: Mapping[str, BoundaryCondition] = field(default_factory=FrozenMap)
    maxh: float | None = None
    tip_h: float | None = None
    crack_h: float | None = None
    grading: float | None = None
    description: str = ""
    exact: Mapping[str, Any] | None = None
    points: tuple[PointCondition, ...] = ()

    # ---------------------------------------------------------------- validation
    def __post_init__(self) -> None:
        set_ = functools.partial(object.__setattr__, self)
        _check_name(self.name, self.description)

        # domain.polygon
        poly = points(self.polygon, "domain.polygon", 3,
                      "a list of 3 or more vertices [[x0, y0], [x1, y1], ...], "
                      "counter-clockwise", MAX_POLYGON_VERTICES)
        set_("polygon", poly)
        diam = _check_polygon(poly)
        self.__dict__["diameter"] = diam  # the cached property, computed once
        tol = GEOMETRY_RTOL * diam

        # domain.labels
        set_("labels", _check_labels(self.labels, len(poly)))
        labels = self.labels

        # material, load, mesh
        set_("material", Material.from_dict(self.material))
        if self.body_force is not None:
            set_("body_force", pair(self.body_force, "load.body_force",
                                    "a list of 2 finite numbers [fx, fy]"))
        E = _check_modulus(self.material.E)
        if self.body_force is not None:
            check_load(self.body_force, diam / E, "load.body_force", "a body force times the "
                        "diameter over E")
        for key, value in _check_mesh_values(self, diam).items():
            set_(key, value)

        # points: their segments inserted into the polygon, forces as tractions
        pconds = coerce_points(self.points, self.maxh, diam)
        if pconds:
            poly, labels = insert_points(poly, self.labels, pconds, (), diam, tol)
            set_("polygon", poly)
            set_("labels", labels)
        set_("points", pconds)

        # cracks
        raw = self.cracks
        if isinstance(raw, (str, bytes, Mapping)) or not isinstance(raw, Sequence):
            raise SceneError(f"crack = {short(raw)}: must be a list of cracks "
                             f"([[crack]] tables with points = [[x, y], ...] and "
                             f"optionally friction = mu)")
        outer = Walls([(poly, self.labels, "domain.polygon")])
        holes = check_holes(self.holes, outer, diam, tol)
        set_("holes", holes)
        for k, pc in enumerate(pconds):
            if any(pc.label in h.labels for h in holes):
                raise SceneError(f"point[{k}].label = {pc.label!r}: already the label of a hole's edge; choose "
                                 f"another label")
        parsed = []
        for i, c in enumerate(raw):
            fld = f"crack[{i}]"
            pts_raw = c.points if isinstance(c, Crack) else c
            mu = c.friction if isinstance(c, Crack) else 0.0
            pressure = c.pressure if isinstance(c, Crack) else None
            if isinstance(pts_raw, Mapping):
                check_keys(pts_raw, ("points", "friction", "pressure"), fld)
                if "points" not in pts_raw:
                    raise SceneError(f"{fld}.points: missing; give a polyline "
                                     f"[[x0, y0], [x1, y1], ...]")
                mu = friction_coefficient(pts_raw.get("friction", 0.0), f"{fld}.friction")
                pressure = check_pressure(pts_raw.get("pressure"), f"{fld}.pressure")
                pts_raw = pts_raw["points"]
            parsed.append((c, crack_points(pts_raw, fld, tol), mu, pressure))
        through = hole_ends(holes, [p for _, pts, _, _ in parsed for p in (pts[0], pts[-1])], tol)
        walls = Walls([(poly, self.labels, "domain.polygon")]
                      + [(h.loop(through=through[k]), h.edge_labels(through=through[k]), f"hole[{k}]")
                         for k, h in enumerate(holes)])
        self.__dict__["_walls"] = outer  # the cache of the outer boundary (on_boundary)
        cracks = []
        for i, (c, pts, mu, pressure) in enumerate(parsed):
            fld = f"crack[{i}]"
            check_crack_in_domain(walls, pts, fld, tol)
            check_not_on_holes(holes, pts, fld, tol)
            if not isinstance(c, Crack):
                try:
                    c = Crack(pts, mu, pressure)
                except SceneError as exc:  # the pressure's checks, under this crack's name
                    raise SceneError(str(exc).replace("crack.pressure", f"{fld}.pressure")) from None
            check_crack_pressure(c.pressure, E, diam, f"{fld}.pressure")
            cracks.append(c)
        warn_held_mouths(pconds, [c.points for c in cracks], tol)
        total = (len(poly) + sum(len(h.polygon) for h in holes if not h.is_circle)
                 + 2 * sum(len(c.points) for c in cracks))
        if total > MAX_BOUNDARY_POINTS:
            raise SceneError(f"crack: {total} boundary points (polygon vertices plus twice the crack "
                             f"points); at most {MAX_BOUNDARY_POINTS} are allowed (a documented "
                             f"ceiling that keeps meshing within seconds); simplify the polylines")
        check_cracks_disjoint([c.points for c in cracks], tol)
        check_gaps(walls, [c.points for c in cracks], diam, tol)
        set_("cracks", tuple(cracks))

        # boundary
        bnd = self.boundary
        if not isinstance(bnd, Mapping):
            raise SceneError(f"boundary = {short(bnd)}: must be a table of "
                             f"[boundary.<label>] tables")
        allowed = self.boundary_labels
        conds = force_conditions(pconds, bnd)
        for k, pc in enumerate(pconds):  # a point force, as the traction on its segment over E
            if pc.type == "force":
                check_load(pc.value, 1.0 / (E * pc.width), f"point[{k}].value", "the force over its width and E")
        for lab, cond in bnd.items():
            if lab in conds:
                continue
            if lab not in allowed:
                raise SceneError(f"boundary.{lab}: unknown edge label; allowed labels: "
                                 f"{', '.join(allowed)}")
            bc = conds[lab] = BoundaryCondition.from_dict(cond, f"boundary.{lab}")
            if bc.type == "traction":
                check_load(bc.value, 1.0 / E, f"boundary.{lab}.value", "a traction over E")
            elif bc.type == "displacement":
                check_load(bc.value, 1.0 / diam, f"boundary.{lab}.value",
                            "a displacement over the diameter")
        set_("boundary", FrozenMap(conds))

        # exact
        if self.exact is not None:
            set_("exact", check_exact(self.exact))

        self.check_held()

    def __getstate__(self) -> dict[str, Any]:
        """The fields only: the caches (diameter, walls, parts) are rebuilt on demand, so a
        pickled scene (sent to a sweep's worker) stays small."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}

    # ---------------------------------------------------------------- geometry
    @property
    def boundary_labels(self) -> list[str]:
        """The distinct labels of the domain's edges and of the holes' edges, in order."""
        return unique(list(self.labels) + [lab for h in self.holes for lab in h.labels])

    def region(self) -> shapely.Polygon:
        """The body as a shapely Polygon: the domain with the holes cut out (a circle as
        its inscribed polygon of CIRCLE_SEGMENTS sides). Cracks are not part of it."""
        import shapely

        return shapely.Polygon(self.polygon, [h.loop() for h in self.holes])

    @property
    def area(self) -> float:
        """The body's area: the polygon's less the holes' (a circle's exactly)."""
        return signed_area(self.polygon) - sum(h.area for h in self.holes)

    def hole_pieces(self, circle_segments: int | None = None) -> list[tuple[str, Point, Point]]:
        """The holes' edges ``(label, p, q)`` oriented with the body on their left (so
        clockwise around each hole); a circle as its inscribed polygon of
        ``circle_segments`` sides (default CIRCLE_SEGMENTS)."""
        out = []
        for h in self.holes:
            loop, labels = h.loop(circle_segments), h.edge_labels(circle_segments)
            n = len(loop)
            out += [(labels[i], loop[(i + 1) % n], loop[i]) for i in range(n)]
        return out

    @functools.cached_property
    def diameter(self) -> float:
        """Largest distance between two polygon vertices (computed once)."""
        return diameter(self.polygon)

    @property
    def tol(self) -> float:
        """Absolute geometric tolerance, ``GEOMETRY_RTOL * diameter``."""
        return GEOMETRY_RTOL * self.diameter

    def edges(self) -> list[tuple[str, Point, Point]]:
        """The polygon edges ``(label, p, q)``, edge i from vertex i to vertex i+1."""
        n = len(self.polygon)
        return [(self.labels[i], self.polygon[i], self.polygon[(i + 1) % n])
                for i in range(n)]

    @functools.cached_property
    def _walls(self) -> Walls:
        """The outer polygon's edges, indexed (holes are not in it)."""
        return Walls([(self.polygon, self.labels, "domain.polygon")])

    def on_boundary(self, x: Sequence[float]) -> bool:
        """True if ``x`` lies on the outer polygon's boundary (within :attr:`tol`); a hole's
        edges do not count (see :meth:`on_hole`)."""
        return bool(self._walls.distance(np.array([[float(x[0]), float(x[1])]]))[0] <= self.tol)

    def on_hole(self, x: Sequence[float]) -> int | None:
        """The index of the hole whose edge ``x`` lies on (within :attr:`tol`), else None."""
        return next((k for k, h in enumerate(self.holes) if h.edge_distance(x) <= self.tol), None)

    def crack_end_on_boundary(self, i: int) -> tuple[bool, bool]:
        """Whether the first and the last point of crack ``i`` lie on the boundary: the outer
        polygon's or a hole's edge (a crack that joins a hole there)."""
        pts = self.cracks[i].points
        return tuple(self.on_boundary(p) or self.on_hole(p) is not None for p in (pts[0], pts[-1]))

    def hole_joins(self) -> list[tuple[int, int, int]]:
        """The crack ends on a hole's edge, as ``(crack, end index 0 or -1, hole)``."""
        out = []
        for i, c in enumerate(self.cracks):
            for k in (0, -1):
                h = self.on_hole(c.points[k])
                if h is not None:
                    out.append((i, k, h))
        return out

    def tip_points(self) -> list[tuple[int, Point]]:
        """Crack end points strictly inside the domain, as ``(crack index, point)``."""
        out = []
        for i, c in enumerate(self.cracks):
            for k, on in zip((0, -1), self.crack_end_on_boundary(i)):
                if not on:
                    out.append((i, c.points[k]))
        return out

    def through_cracks(self) -> list[int]:
        """Indices of the cracks with both ends on the outer boundary (they cut a part in two)."""
        return [i for i, c in enumerate(self.cracks) if self.on_boundary(c.points[0]) and self.on_boundary(c.points[-1])]

    def edge_pieces(self) -> list[tuple[str, Point, Point]]:
        """The polygon edges split at every crack end point lying on them, as
        ``(label, p, q)`` in counter-clockwise order."""
        tol = self.tol
        ends = [c.points[k] for i, c in enumerate(self.cracks)
                for k, on in zip((0, -1), self.crack_end_on_boundary(i)) if on]
        out = []
        for lab, p, q in self.edges():
            d = sub(q, p)
            cuts = sorted(dot(sub(x, p), d) / dot(d, d) for x in ends
                          if point_segment_distance(x, p, q) <= tol
                          and dist(x, p) > tol and dist(x, q) > tol)
            pts = [p] + [(p[0] + t * d[0], p[1] + t * d[1]) for t in cuts] + [q]
            out += [(lab, pts[k], pts[k + 1]) for k in range(len(pts) - 1)]
        return out

    def parts(self) -> tuple[Part, ...]:
        """The connected pieces of the body after the through cracks cut it."""
        return self._parts

    @functools.cached_property
    def _parts(self) -> tuple[Part, ...]:
        return parts(self)

    def check_held(self) -> None:
        """Refuse a scene in which some part can move rigidly (see :func:`topology.check_held`)."""
        check_held(self)

    # ---------------------------------------------------------------- I/O
    @classmethod
    def from_dict(cls, d: Mapping[str, Any], name: str | None = None) -> Scene:
        """Build from the TOML structure (a dict as ``tomllib`` returns it).

        ``name``, if given, overrides ``d["name"]``; one of the two is required.
        """
        return _toml.scene_from_dict(cls, d, name)

    @classmethod
    def from_toml_string(cls, text: str, name: str | None = None,
                         source: str = "scene") -> Scene:
        """Parse TOML text; ``name`` as in :meth:`from_dict`; ``source`` names the text
        in the message of a TOML syntax error."""
        return cls.from_dict(_toml.parse_toml(text, source), name=name)

    @classmethod
    def from_toml(cls, path: str | Path) -> Scene:
        """Read a scene file; without a ``name`` key the file's stem is the name."""
        return _toml.scene_from_file(cls, path)

    def to_dict(self) -> dict[str, Any]:
        """The TOML structure (plain dicts, lists, floats, strings); inverse of
        :meth:`from_dict`. Empty optional sections are left out."""
        return _toml.scene_to_dict(self)

    def to_toml_string(self) -> str:
        """The scene as TOML text; ``Scene.from_toml_string`` of it gives an equal scene."""
        return _toml.dump_toml(self.to_dict())

    # ---------------------------------------------------------------- new scenes
    def with_(self, **changes: Any) -> Scene:
        """A new, validated scene with some fields replaced.

        Accepts any field (``name``, ``polygon``, ``labels``, ``cracks``, ``holes``, ``material``,
        ``body_force``, ``boundary``, ``maxh``, ``tip_h``, ``description``, ``exact``, ``points``)
        and the material's ``E``, ``nu``, ``plane``. ``boundary`` replaces the whole
        mapping (label -> BoundaryCondition or {"type": ..., "value": ...}); a traction it gives
        on a force point's label sets that point's force (value = traction times width).
        New ``points`` replace the old ones, their segments and forces.
        ``friction`` sets the Coulomb coefficient of every crack, ``pressure`` the face
        pressure of every crack (``ngcrack.planar.scene.pressure``).
        """
        names = [f.name for f in dataclasses.fields(self)]
        mat_keys = ("E", "nu", "plane")
        for key, check in (("friction", friction_coefficient), ("pressure", check_pressure)):
            if key in changes:
                changes["cracks"] = _with_on_every_crack(changes.get("cracks", self.cracks), key,
                                                         check(changes.pop(key), key))
        unknown = [k for k in changes if k not in names and k not in mat_keys]
        if unknown:
            allowed = ", ".join(names + list(mat_keys))
            raise SceneError(f"with_: unknown field{'s' if len(unknown) > 1 else ''} "
                             f"{', '.join(unknown)}; allowed: {allowed}")
        if self.points and "points" in changes:
            # new points: the old ones' segments and forces leave the polygon and the boundary
            if "polygon" not in changes and "labels" not in changes:
                changes["polygon"], changes["labels"] = strip_points(self.polygon, self.labels, self.points)
            if "boundary" not in changes:
                forces = {pc.label for pc in self.points if pc.type == "force"}
                changes["boundary"] = {k: v for k, v in self.boundary.items() if k not in forces}
        elif self.points and isinstance(changes.get("boundary"), Mapping):
            # a new boundary mapping carries the forces of the points (a scaled or turned load)
            changes["points"] = from_tractions(self.points, changes["boundary"])
        mat = {k: changes.pop(k) for k in mat_keys if k in changes}
        if mat:
            base = Material.from_dict(changes.get("material", self.material))
            changes["material"] = dataclasses.replace(base, **mat)
        return dataclasses.replace(self, **changes)

    def scaled(self, E: float = 1.0, load: float = 1.0, size: float = 1.0) -> Scene:
        """The scene with E, all loads and all lengths multiplied by the given factors.

        Lengths (polygon, cracks, mesh sizes) scale by ``size``, E by ``E``, tractions by
        ``load``, body forces by ``load / size`` (so that stresses scale with ``load``)
        and prescribed displacements by ``load * size / E``: the displacements of the
        scaled scene are those of this one times ``load * size / E``. Each crack keeps
        its friction coefficient, its pressure scales by ``load`` (a table's arc lengths by
        ``size``); the ``[exact]`` metadata is kept as it is.
        """
        for v, fld in ((E, "E"), (load, "load"), (size, "size")):
            positive(v, f"scaled.{fld}")
        factor = {"traction": load, "displacement": load * size / E}
        boundary = {k: b.scaled(factor[b.type]) if b.type in factor else b
                    for k, b in self.boundary.items()}
        bf = tuple(v * load / size for v in self.body_force) if self.body_force else None
        forces = {pc.label for pc in self.points if pc.type == "force"}
        boundary = {k: b for k, b in boundary.items() if k not in forces}
        return self.with_(
            points=tuple(pc.scaled(size, load * size) for pc in self.points),
            E=self.material.E * E,
            polygon=tuple((x * size, y * size) for x, y in self.polygon),
            cracks=tuple(c.scaled(size, load) for c in self.cracks),
            holes=tuple(h.scaled(size) for h in self.holes),
            body_force=bf, boundary=boundary,
            **{k: getattr(self, k) * size for k in ("maxh", "tip_h", "crack_h") if getattr(self, k)},
        )


def check_crack_pressure(p, E: float, diam: float, fld: str) -> None:
    """Refuse a crack pressure whose nonzero values leave the range of the scene's loads
    (as strains p / E, and in size, between 1/MAX_SCALE and MAX_SCALE)."""
    if p is None:
        return
    vals = [p] if isinstance(p, float) else [v for _, v in p] if isinstance(p, tuple) else []
    for v in vals:
        if v != 0.0 and not (1.0 / MAX_SCALE <= abs(v) / E <= MAX_SCALE and 1.0 / MAX_SCALE <= abs(v) <= MAX_SCALE):
            raise SceneError(f"{fld} = {short(p)}: out of range ({fmt(v)}, as a strain p / E "
                             f"{abs(v) / E:.3g}); each nonzero value must lie, in size and over E, "
                             f"between {1.0 / MAX_SCALE:g} and {MAX_SCALE:g} (change the units)")
