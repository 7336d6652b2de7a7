"""Forces and displacements at the loaded labels and the points of a solved scene.

For every point condition of the scene (``[[point]]``) and every boundary label loaded by
a traction, `load_point_values(sol)` gives

- ``force``: the total force on the body there, (Fx, Fy): the applied force of a force
  point or a traction label (the traction integrated over the label's edges), the
  reaction of a pin or roller point (from the residual of the solved system,
  `held_means.reactions`);
- ``displacement``: the mean displacement (ux, uy) over the point's segment or the
  label's edges, the value work-conjugate to a uniform traction there (for a force
  point: force . displacement is the work of the load).

`load_displacement(sol)` reduces each loaded label or force point to the pair of scalars a
test machine records: P = |F| and delta = F . u / |F| (the displacement along the force).
Under the scene's single proportional load the compliance C = delta / P does not depend
on the load level while the crack's contact set does not change.
"""

from __future__ import annotations

import math

from .held_means import reactions, segment_length, segment_mean
from .scene.points import held_directions


def _label_force(sol, label: str, value) -> tuple[float, float]:
    """The traction `value` (constant) integrated over the label's edges."""
    w = segment_length(sol.mesh, label)
    return (float(value[0]) * w, float(value[1]) * w)


def loaded_labels(scene) -> list[str]:
    """The labels that carry a load: the force points, then the traction labels with a nonzero value."""
    forces = [pc.label for pc in scene.points if pc.type == "force"]
    others = [lab for lab, bc in scene.boundary.items()
              if bc.type == "traction" and lab not in forces and any(v != 0.0 for v in bc.value)]
    return forces + sorted(others)


def load_point_values(sol) -> dict[str, dict]:
    """label -> {"type", "force": (Fx, Fy), "displacement": (ux, uy)} for every point and loaded label."""
    scene = sol.scene
    disc, gf = sol.disc, sol.gf
    held = held_directions(scene.polygon, scene.labels, scene.points)
    react = reactions(disc, gf, held)
    out: dict[str, dict] = {}
    for pc in scene.points:
        force = pc.value if pc.type == "force" else react[pc.label]
        out[pc.label] = {"type": pc.type, "force": (float(force[0]), float(force[1])),
                         "displacement": _mean(disc, gf, pc.label)}
    for lab in loaded_labels(scene):
        if lab not in out:
            out[lab] = {"type": "traction", "force": _label_force(sol, lab, scene.boundary[lab].value),
                        "displacement": _mean(disc, gf, lab)}
    return out


def _mean(disc, gf, label) -> tuple[float, float]:
    return (segment_mean(disc, gf, label, (1.0, 0.0)), segment_mean(disc, gf, label, (0.0, 1.0)))


def load_displacement(values: dict[str, dict]) -> dict[str, tuple[float, float]]:
    """label -> (P, delta): P = |F|, delta = F . u / |F|, for the loaded labels and force points."""
    out = {}
    for lab, v in values.items():
        if v["type"] not in ("force", "traction"):
            continue
        F, u = v["force"], v["displacement"]
        P = math.hypot(*F)
        out[lab] = (P, (F[0] * u[0] + F[1] * u[1]) / P if P > 0 else 0.0)
    return out

