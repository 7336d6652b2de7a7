"""The scene's loads as the explorer varies them: scaled by the load factor and turned.

`scaled_loads` gives the scene with every load vector multiplied by the load factor and
turned by the load angle. (The pipeline holds the loads as NGSolve Parameters, so that a
new load re-assembles only the load vector: `ngcrack.core.pipeline.ParameterLoads`.)
"""

from __future__ import annotations

import math

from ...planar.scene import Scene


def _rotate(v, degrees: float, factor: float) -> tuple[float, float]:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return (factor * (c * v[0] - s * v[1]), factor * (s * v[0] + c * v[1]))


def scaled_loads(scene: Scene, load: float = 1.0, load_angle: float = 0.0) -> Scene:
    """The scene with every load vector (tractions, prescribed displacements, body force)
    multiplied by ``load`` and turned by ``load_angle`` degrees (counter-clockwise)."""
    if load == 1.0 and load_angle == 0.0:
        return scene
    boundary = {}
    for label, bc in scene.boundary.items():
        if bc.type in ("traction", "displacement"):
            boundary[label] = {"type": bc.type, "value": list(_rotate(bc.value, load_angle, load))}
        else:
            boundary[label] = bc
    body = None if scene.body_force is None else _rotate(scene.body_force, load_angle, load)
    return scene.with_(boundary=boundary, body_force=body)
