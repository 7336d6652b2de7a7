"""Built-in scenes: the TOML files in this package, loaded by name.

``paper-1`` and ``paper-2`` are the two examples of Belhachmi et al. as ngcrack reads
them (README, "The paper's scenes"); ``griffith`` has a closed-form crack opening; ``kirsch`` is
a plate with a circular hole (stress concentration 3) and ``hole-crack`` a crack beside a hole;
the others are small checks (a crack that stays closed, one that never closes, no crack, a polyline
crack, two cracks). Each file starts with comments that say what it models and why its
supports are what they are. The scene functions of ``SCENE_FUNCTIONS`` (parametric.py)
build teaching scenes from a few parameters; ``nc.explore`` turns them into sliders.
"""

from __future__ import annotations

import functools
from importlib import resources
from pathlib import Path

from ngcrack.planar.scene import Scene, SceneError

#: the names of parametric.py, imported on first use (PEP 562): loading a built-in scene
#: needs neither the scene functions nor the handbook strips (handbook.py)
_PARAMETRIC = ("SCENE_FUNCTIONS", "Parameter", "SceneFunction", "cracked_beam", "griffith_plate",
               "inclined_closed_form", "inclined_crack", "scene_function")


def __getattr__(name: str):
    if name in _PARAMETRIC:
        from ngcrack.scenes import parametric

        return getattr(parametric, name)
    if name in ("parametric", "handbook"):  # (finite cracked strips with handbook K, Tada-Paris-Irwin)
        import importlib

        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["names", "load", "describe", "paper_example", "resolve", "inclined_crack", "inclined_closed_form",
           "griffith_plate", "cracked_beam", "SCENE_FUNCTIONS", "SceneFunction", "Parameter", "scene_function"]

_SUFFIX = ".toml"


def names() -> list[str]:
    """Names of the built-in scenes, sorted."""
    return sorted(f.name[: -len(_SUFFIX)] for f in resources.files(__name__).iterdir()
                  if f.name.endswith(_SUFFIX))


@functools.cache
def load(name: str) -> Scene:
    """The built-in scene ``name`` (scenes are immutable, so the result is shared)."""
    if name not in names():
        raise SceneError(f"scene = {name!r}: unknown built-in scene; built-in scenes: "
                         f"{', '.join(names())}")
    text = resources.files(__name__).joinpath(name + _SUFFIX).read_text(encoding="utf-8")
    return Scene.from_toml_string(text, source=f"built-in scene {name!r}")


def describe() -> list[tuple[str, str]]:
    """``(name, one-line description)`` of every built-in scene, sorted by name."""
    return [(n, load(n).description) for n in names()]


def paper_example(k: int) -> Scene:
    """Example ``k`` (1 or 2) of the paper: ``paper-1`` or ``paper-2``."""
    if k not in (1, 2) or isinstance(k, bool):
        raise SceneError(f"paper_example: k = {k!r}; allowed values are 1, 2")
    return load(f"paper-{k}")


def resolve(name_or_path: str | Path) -> Scene:
    """A built-in scene by name, or a scene file by path (what the CLI's SCENE means)."""
    if isinstance(name_or_path, str) and name_or_path in names():
        return load(name_or_path)
    path = Path(name_or_path)
    if path.is_file():
        return Scene.from_toml(path)
    raise SceneError(f"scene = {str(name_or_path)!r}: neither a built-in scene nor an "
                     f"existing .toml file; built-in scenes: {', '.join(names())}")
