"""Scene files: reading the TOML structure into a scene and writing it back.

The reader checks the document's shape (known keys, tables where tables belong) and
hands the fields to the scene's constructor, which validates their values; the writer
is a small TOML emitter for exactly the structure :func:`scene_to_dict` produces, so
that ``Scene.from_toml_string(scene.to_toml_string()) == scene``. The functions take
the scene class as an argument and import nothing of it: the scene type calls down
into this module, never the other way.
"""

from __future__ import annotations

import json
import math
import os
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ...core.fields import SceneError, check_keys, short, table
from ...core.scene import Scene, dimension_of

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib  # type: ignore[no-redef]

#: the top-level keys of a scene file
TOP_KEYS = ("name", "description", "domain", "crack", "hole", "point", "material", "load", "boundary",
            "mesh", "exact")
#: the keys of its [mesh] table
MESH_KEYS = ("maxh", "tip_h", "crack_h", "grading")


def scene_from_dict(cls, d: Mapping[str, Any], name: str | None = None):
    """A ``cls`` (the Scene type) from the TOML structure; ``name`` overrides ``d["name"]``."""
    if not isinstance(d, Mapping):
        raise SceneError(f"scene = {short(d)}: must be a table (the TOML document)")
    if dimension_of(d) == 3:  # a 3D body: its own kind (ngcrack.solid.scene)
        return Scene.from_dict(d, name)
    check_keys(d, TOP_KEYS, "")
    if name is None:
        if "name" not in d:
            raise SceneError("name: missing; give the scene a name (a non-empty string)")
        name = d["name"]
    domain = table(d, "domain", "domain")
    check_keys(domain, ("polygon", "labels"), "domain")
    if "polygon" not in domain:
        raise SceneError("domain.polygon: missing; give 3 or more vertices "
                         "[[x0, y0], [x1, y1], ...], counter-clockwise")
    cracks = d.get("crack", [])
    if isinstance(cracks, (Mapping, str, bytes)) or not isinstance(cracks, Sequence):
        raise SceneError(f"crack = {short(cracks)}: must be an array of tables "
                         f"([[crack]] with points = [[x, y], ...])")
    for i, c in enumerate(cracks):
        if not isinstance(c, Mapping):
            raise SceneError(f"crack[{i}] = {short(c)}: must be a table with key "
                             f"points ([[crack]] in TOML)")
    holes = d.get("hole", [])
    if isinstance(holes, (Mapping, str, bytes)) or not isinstance(holes, Sequence):
        raise SceneError(f"hole = {short(holes)}: must be an array of tables ([[hole]] with "
                         f"polygon = [[x, y], ...] or center = [x, y] and radius = r)")
    pts = d.get("point", [])
    if isinstance(pts, (Mapping, str, bytes)) or not isinstance(pts, Sequence):
        raise SceneError(f"point = {short(pts)}: must be an array of tables ([[point]] with at = [x, y], "
                         f"type = 'force' | 'pin' | 'roller' and, for a force, value = [Fx, Fy])")
    if "material" not in d:
        raise SceneError("material: missing; give a [material] table with E, nu and "
                         "optionally plane")
    load = table(d, "load", "load")
    check_keys(load, ("body_force",), "load")
    boundary = table(d, "boundary", "boundary")
    mesh = table(d, "mesh", "mesh")
    check_keys(mesh, MESH_KEYS, "mesh")
    return cls(
        name=name,
        description=d.get("description", ""),
        polygon=domain["polygon"],
        labels=domain.get("labels", ()),
        cracks=tuple(cracks),
        holes=tuple(holes),
        points=tuple(pts),
        material=d["material"],
        body_force=load.get("body_force"),
        boundary=boundary,
        maxh=mesh.get("maxh"),
        tip_h=mesh.get("tip_h"),
        crack_h=mesh.get("crack_h"),
        grading=mesh.get("grading"),
        exact=d.get("exact"),
    )


def parse_toml(text: str, source: str) -> dict[str, Any]:
    """The TOML document as a dict; a syntax error is a SceneError naming ``source``."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise SceneError(f"{source}: not valid TOML: {err}") from err


def scene_from_file(cls, path: str | Path):
    """Read a scene file; without a ``name`` key the file's stem is the name."""
    if not isinstance(path, (str, os.PathLike)):
        raise SceneError(f"path = {path!r}: expected the name of a scene file (str or os.PathLike)")
    path = Path(path)
    if path.is_dir():
        raise SceneError(f"scene file {str(path)!r}: is a directory; give a .toml file")
    if not path.is_file():
        raise SceneError(f"scene file {str(path)!r}: does not exist")
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(f"scene file {str(path)!r}: is not a UTF-8 text file (byte {exc.start}); give a TOML scene "
                         f"file") from None
    except OSError as exc:
        raise SceneError(f"scene file {str(path)!r}: cannot be read ({exc.strerror or exc})") from None
    d = parse_toml(text, str(path))
    dom = d.get("domain")
    if isinstance(dom, dict) and isinstance(dom.get("step"), str) and not os.path.isabs(dom["step"]):
        dom["step"] = str(path.parent / dom["step"])  # a 3D part's file, relative to the scene file
    return scene_from_dict(cls, d, name=None if "name" in d else path.stem)


def scene_to_dict(scene) -> dict[str, Any]:
    """The TOML structure of a scene (plain dicts, lists, floats, strings)."""
    d: dict[str, Any] = {"name": scene.name}
    if scene.description:
        d["description"] = scene.description
    poly, labels = scene.polygon, scene.labels
    if scene.points:  # the polygon as written: without the points' segments
        from .points import strip_points

        poly, labels = strip_points(poly, labels, scene.points)
    d["domain"] = {"polygon": [list(p) for p in poly], "labels": list(labels)}
    if scene.cracks:
        d["crack"] = [c.to_dict() for c in scene.cracks]
    if scene.holes:
        d["hole"] = [h.to_dict() for h in scene.holes]
    d["material"] = scene.material.to_dict()
    if scene.body_force is not None:
        d["load"] = {"body_force": list(scene.body_force)}
    if scene.points:
        d["point"] = [pc.to_dict() for pc in scene.points]
    forces = {pc.label for pc in scene.points if pc.type == "force"}
    boundary = {lab: bc.to_dict() for lab, bc in scene.boundary.items() if lab not in forces}
    if boundary:
        d["boundary"] = boundary
    mesh = {k: getattr(scene, k) for k in MESH_KEYS if getattr(scene, k) is not None}
    if mesh:
        d["mesh"] = mesh
    if scene.exact is not None:
        d["exact"] = {k: list(v) if isinstance(v, tuple) else v for k, v in scene.exact.items()}
    return d


# --------------------------------------------------------------------------------------
# a small TOML writer for the scene structure
# --------------------------------------------------------------------------------------

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _toml_key(k: str) -> str:
    return k if _BARE_KEY.match(k) else _toml_value(k)


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise SceneError(f"cannot write {v!r} to TOML")  # excluded by validation
        return repr(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, Mapping) for x in v)


def dump_toml(d: Mapping[str, Any]) -> str:
    """TOML text of a structure of tables, arrays of tables and plain values."""
    lines: list[str] = []

    def scalars(t: Mapping[str, Any]) -> None:
        for k, v in t.items():
            if not isinstance(v, Mapping) and not _is_table_array(v):
                lines.append(f"{_toml_key(k)} = {_toml_value(v)}")

    def tables(path: list[str], t: Mapping[str, Any]) -> None:
        for k, v in t.items():
            sub = path + [_toml_key(k)]
            if isinstance(v, Mapping):
                has_scalars = any(not isinstance(x, Mapping) and not _is_table_array(x)
                                  for x in v.values())
                if has_scalars or not v:
                    lines.extend(["", f"[{'.'.join(sub)}]"])
                    scalars(v)
                tables(sub, v)
            elif _is_table_array(v):
                for item in v:
                    lines.extend(["", f"[[{'.'.join(sub)}]]"])
                    scalars(item)
                    tables(sub, item)

    scalars(d)
    tables([], d)
    return "\n".join(lines) + "\n"
