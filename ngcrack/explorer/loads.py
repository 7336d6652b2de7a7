"""The scene's loads as the explorer varies them: scaled and turned, and as NGSolve Parameters.

`scaled_loads` gives the scene with every load vector multiplied by the load factor and
turned by the load angle; `ParameterLoads` holds the scene's loads as Parameters, so that
an assembled linear form follows a new load without re-assembly of the matrix;
`load_structure` is what the assembled forms depend on besides the load values.
"""

from __future__ import annotations

import math

import ngsolve as ngs

from ..elements import Loads
from ..scene import Scene


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


class ParameterLoads:
    """The scene's loads as NGSolve Parameters: the assembled linear form follows their values.

    Every traction, displacement and body-force vector of the scene gets two Parameters
    (zero ones too, so a load scaled to zero keeps the same form); `set(scene)` copies a
    scene's values in (the scene must have the same loaded labels: see `structure`).
    """

    def __init__(self, scene: Scene):
        self.structure = load_structure(scene)
        self.params: dict[tuple[str, str], tuple[ngs.Parameter, ngs.Parameter]] = {}
        traction, displacement, clamped, roller = {}, {}, set(), set()
        for label, bc in scene.boundary.items():
            if bc.type == "clamped":
                clamped.add(label)
            elif bc.type == "roller":
                roller.add(label)
            else:
                p = (ngs.Parameter(0.0), ngs.Parameter(0.0))
                self.params[(bc.type, label)] = p
                (traction if bc.type == "traction" else displacement)[label] = ngs.CF(p)
        body = None
        if scene.body_force is not None:
            p = (ngs.Parameter(0.0), ngs.Parameter(0.0))
            self.params[("body", "")] = p
            body = ngs.CF(p)
        self.loads = Loads(body_force=body, traction=traction, displacement=displacement,
                           clamped=frozenset(clamped), roller=frozenset(roller))
        self.set(scene)

    def set(self, scene: Scene) -> None:
        for (kind, label), (px, py) in self.params.items():
            value = scene.body_force if kind == "body" else scene.boundary[label].value
            px.Set(float(value[0]))
            py.Set(float(value[1]))


def load_structure(scene: Scene) -> tuple:
    """What the assembled forms depend on besides the load values: the supports and
    which labels carry loads."""
    return (tuple(sorted((lab, bc.type) for lab, bc in scene.boundary.items())), scene.body_force is not None)
