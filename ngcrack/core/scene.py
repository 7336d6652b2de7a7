"""The scene of either dimension: what every stage may ask of a cracked body, whatever its dimension.

`Scene` is the type of every scene: the planar (2D) one (`ngcrack.planar.scene.PlanarScene`)
and the solid (3D) one (`ngcrack.solid.scene.SolidScene`) are its kinds, and only they know
their dimension (`scene.dimension`, 2 or 3) and their body (`scene.body`: the meshing, the
element forms, the crack-face loads and the post-processing the pipeline asks of it).

`Scene(...)` with the fields of a planar scene makes a planar one (the everyday 2D use:
``nc.Scene(name=..., polygon=..., material=...)``); `Scene.from_toml`, `from_toml_string`
and `from_dict` read a scene of either dimension (a ``[domain]`` that is a box, a cylinder
or a STEP part is 3D).
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any, ClassVar

__all__ = ["KINDS", "SOLID_DOMAINS", "Scene", "dimension_of"]

#: the module of each kind by dimension, imported by name when first needed (so that this
#: module imports neither body); the planar kind is the one `Scene(...)` makes from fields
#: and reads scene files with (it hands a 3D one back to `Scene.from_dict`)
KINDS = {2: "ngcrack.planar.scene.body", 3: "ngcrack.solid.scene"}
#: the ``[domain]`` keys of a 3D body
SOLID_DOMAINS = ("box", "cylinder", "step")


def dimension_of(d: Any) -> int:
    """The dimension of a scene's TOML structure: 3 where its ``[domain]`` is a box, a cylinder or a STEP part."""
    dom = d.get("domain") if isinstance(d, Mapping) else None
    return 3 if isinstance(dom, Mapping) and any(k in dom for k in SOLID_DOMAINS) else 2


class Scene:
    """A cracked elastic body of either dimension (module docstring).

    Every kind has `name`, `description`, `cracks`, `material`, `boundary`, `body_force`
    and the mesh sizes of its dimension, `with_(**changes)`, `to_dict()` and
    `to_toml_string()`; `dimension` and `body` say what the kind is.
    """

    #: 2 (planar) or 3 (solid): set by each kind
    dimension: ClassVar[int] = 0
    #: the kinds by dimension, as their modules register them (`class PlanarScene(Scene, dimension=2)`)
    _kinds: ClassVar[dict[int, type]] = {}

    def __init_subclass__(cls, dimension: int | None = None, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if dimension is not None:
            cls.dimension = dimension
            Scene._kinds[dimension] = cls

    def __new__(cls, *args: Any, **kwargs: Any):
        if cls is Scene:  # fields of a planar scene: the planar kind
            cls = kind(2)
        return object.__new__(cls)

    #: the module whose ``BODY`` the stages ask for the mesh, the element forms, the loads and the
    #: post-processing (set by each kind: ngcrack.planar.stages, ngcrack.solid.stages)
    body_module: ClassVar[str] = ""

    @property
    def body(self):
        """What the stages ask of this scene's body (mesh, element forms, loads, post-processing)."""
        return importlib.import_module(self.body_module).BODY

    @classmethod
    def from_dict(cls, d: Any, name: str | None = None) -> Scene:
        """A scene of either dimension from the TOML structure (a dict as ``tomllib`` returns it)."""
        return kind(dimension_of(d)).from_dict(d, name)

    @classmethod
    def from_toml_string(cls, text: str, name: str | None = None, source: str = "scene") -> Scene:
        """A scene of either dimension from TOML text; ``source`` names the text in a syntax error."""
        return kind(2).from_toml_string(text, name=name, source=source)

    @classmethod
    def from_toml(cls, path: str | Path) -> Scene:
        """A scene of either dimension from a scene file (without a ``name`` key the file's stem)."""
        return kind(2).from_toml(path)


def kind(dimension: int) -> type:
    """The Scene kind of a dimension (its module imported on first use)."""
    if dimension not in Scene._kinds:
        importlib.import_module(KINDS[dimension])  # the module registers its kind
    return Scene._kinds[dimension]
