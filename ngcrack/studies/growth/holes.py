"""Cracks that reach a hole, and the new crack that leaves it (`grow(..., at_hole=...)`).

A tip whose next segment reaches a hole joins it (paths.extend_tip): the crack ends on the
hole's edge, that end is no tip any more, and the ligament between the tip and the hole is
cut. What then is the user's choice:

- `at_hole="stop"` (the default): the crack ends there, the reason in `result.frozen`; the
  other tips grow on, and the run stops when none is left or none can grow. Where the
  joined cracks cut the body in pieces, the run ends "cut through".
- `at_hole=L0` (a length): the crack goes on through the hole, as the experiments on
  drilled beams show: a new crack of length L0 starts on the hole's edge, radially, at the
  point of the edge with the largest hoop stress of the step's solution, away from the
  arriving tip (points of the edge within ARRIVAL_SECTOR of the direction to it are left
  out: the arriving tip's own field is largest there). The hoop stress is sampled SAMPLES
  times around the hole, at SAMPLE_OFFSET of its radius into the body. Circular holes only.

The closest approach of every crack to every hole is reported in `result.holes` either way.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from ...core.errors import InputError
from ...core.fields import is_finite
from ...planar.scene import SceneError

#: a tip's frozen reason when it stopped at a hole (paths.extend_tip)
HOLE_REASON = re.compile(r"reached hole\[(\d+)\]")
#: the hoop stress is sampled at this many points around the hole
SAMPLES = 360
#: ... this fraction of the hole's radius into the body
SAMPLE_OFFSET = 0.02
#: edge points within this angle (radians) of the direction from the hole's centre to the
#: arriving tip are not candidates for the new crack
ARRIVAL_SECTOR = math.radians(60.0)


def check_at_hole(at_hole, scene) -> float | None:
    """The new crack's length for `at_hole` (None for "stop"), refusing bad input by name."""
    if isinstance(at_hole, str) and at_hole == "stop":
        return None
    ok = is_finite(at_hole)
    if not ok or not 0 < at_hole <= 0.25 * scene.diameter:
        raise InputError(f"at_hole = {at_hole!r}: must be \"stop\" (a tip that reaches a hole stops there) or the "
                         f"length of the new crack that leaves the hole, a number in (0, {0.25 * scene.diameter:.4g}]")
    if not scene.holes:
        raise InputError(f"at_hole = {at_hole!r}: scene {scene.name!r} has no hole, so no tip can reach one; remove "
                         f"at_hole (--at-hole)")
    return float(at_hole)


def hoop_stress(sol, hole, n: int = SAMPLES) -> tuple[np.ndarray, np.ndarray]:
    """(angles, sigma_tt) around a circular hole of `sol`'s scene, SAMPLE_OFFSET of its radius into the body."""
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    c, r = np.asarray(hole.center, dtype=float), float(hole.radius) * (1.0 + SAMPLE_OFFSET)
    x, y = c[0] + r * np.cos(phi), c[1] + r * np.sin(phi)
    s = np.asarray(sol.sigma(sol.mesh(x, y))).reshape(n, -1)
    sxx, sxy, syy = s[:, 0], s[:, 1], s[:, -1]
    t = np.column_stack([-np.sin(phi), np.cos(phi)])
    return phi, t[:, 0] ** 2 * sxx + 2 * t[:, 0] * t[:, 1] * sxy + t[:, 1] ** 2 * syy


def new_crack(scene, sol, hole_index: int, tip_xy, length: float, friction: float = 0.0):
    """The crack that leaves hole `hole_index` at its largest hoop stress away from the arriving tip
    at `tip_xy`: a Crack, or the reason (a string) where there is none."""
    from ngcrack.planar.scene import Crack

    hole = scene.holes[hole_index]
    if not hole.is_circle:
        return f"hole[{hole_index}] is a polygon: a new crack leaves circular holes only"
    phi, hoop = hoop_stress(sol, hole)
    c = np.asarray(hole.center, dtype=float)
    arrive = math.atan2(tip_xy[1] - c[1], tip_xy[0] - c[0])
    away = np.abs(np.angle(np.exp(1j * (phi - arrive)))) > ARRIVAL_SECTOR
    if not np.any(away & (hoop > 0)):
        return f"no tension on the edge of hole[{hole_index}] away from the arriving tip: no new crack leaves it"
    k = int(np.argmax(np.where(away, hoop, -np.inf)))
    d = np.array([math.cos(phi[k]), math.sin(phi[k])])
    start = c + hole.radius * d  # on the edge: the new crack starts at the hole
    return Crack(((float(start[0]), float(start[1])), tuple(map(float, start + length * d))), friction)


@dataclass
class Left:
    """What `leave_holes` did: the scene with the new cracks (None: none) and the events."""

    scene: object = None
    events: list = field(default_factory=list)


def leave_holes(scene, sol, values, frozen, passed: set, length: float) -> Left:
    """For every tip that has just stopped at a hole no crack has left yet: a new crack of `length`
    leaving that hole (holes.new_crack) added to `scene`."""
    out = Left()
    cracks = list(scene.cracks)
    for v in values:
        lab = v["label"]
        m = HOLE_REASON.search(frozen.get(lab, ""))
        if m is None or lab in passed:
            continue
        passed.add(lab)
        i = int(m.group(1))
        if ("hole", i) in passed:
            continue
        passed.add(("hole", i))
        c = new_crack(scene, sol, i, (v["x"], v["y"]), length, scene.cracks[v["crack"]].friction)
        if isinstance(c, str):
            out.events.append((lab, c))
            continue
        cracks.append(c)
        (x0, y0), (x1, y1) = c.points
        out.events.append((lab, f"crack {len(cracks) - 1} leaves hole[{i}] from ({x0:.4g}, {y0:.4g}) to "
                                f"({x1:.4g}, {y1:.4g}), where its hoop stress is largest"))
    if len(cracks) > len(scene.cracks):
        try:
            out.scene = scene.with_(cracks=cracks)
        except SceneError as exc:
            out.events.append(("", f"the new crack makes no valid scene ({exc})"))
    return out
