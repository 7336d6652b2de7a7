"""The input checks of a growth run (grow's arguments), made before any work.

Each names the field and the values it allows (an InputError).
"""

from __future__ import annotations

import math

import numpy as np

from ...core.errors import InputError
from ...core.fields import is_number
from .criteria import check_criterion, check_r_c
from .fatigue import check_paris
from .holes import check_at_hole

#: the most steps a growth run may take
MAX_STEPS = 1000
#: da may be at most this fraction of the body's diameter
MAX_DA_FRACTION = 0.1
#: da must be at least this fraction of the mesh size at the tips: a shorter segment is below
#: what the mesh resolves (da = 1e-6 on a tip mesh of 5e-3 was taken for a cut-through)
MIN_DA_TIP_FRACTION = 0.1
#: the crack's mesh size along a growth run's path grows from crack_h at this rate with the distance from
#: the nearest crack end (`ngcrack.planar.path_sizes`, where its effect on K is measured; `path_grading=None` meshes
#: the whole path at crack_h, `path_sizes.PathGrading(rate, fine)` keeps the polylines `fine` at crack_h)
GROWTH_PATH_GRADING = 0.1
#: solve options grow sets itself
_RESERVED = ("warm_start", "crack_mesh", "loads")


def check_growth_options(scene, da, steps, K_Ic, criterion, solve_options) -> None:
    """Refuse bad input before any work, naming the field and what is allowed."""
    from ngcrack.planar.tips import tip_labels

    check_criterion(criterion)
    check_growth_solve_options(scene, solve_options)

    if K_Ic is not None and not (is_number(K_Ic) and math.isfinite(K_Ic) and K_Ic > 0):
        raise InputError(f"K_Ic = {K_Ic!r}: must be a finite number > 0 (the fracture toughness), or None")
    limit = MAX_DA_FRACTION * scene.diameter
    if not (is_number(da) and math.isfinite(da) and 0 < da <= limit):
        raise InputError(f"da = {da!r}: must be a number in (0, {limit:.4g}] (at most {MAX_DA_FRACTION:g} of the "
                          f"body's diameter {scene.diameter:.4g})")
    shortest = min_da(scene, solve_options)
    if da < shortest:
        raise InputError(f"da = {da!r}: must be at least {MIN_DA_TIP_FRACTION:g} of the mesh size at the crack tips "
                         f"({shortest / MIN_DA_TIP_FRACTION:.4g}), i.e. >= {shortest:.4g}: a shorter segment is not "
                         f"resolved by the mesh; give a larger da or a smaller tip_h")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or not 1 <= steps <= MAX_STEPS:
        raise InputError(f"steps = {steps!r}: must be a whole number in [1, {MAX_STEPS}]")
    bad = [k for k in _RESERVED if k in solve_options]
    if bad:
        raise InputError(f"{bad[0]}: grow sets it for every step itself; give the scene and the mesh options only")
    if not tip_labels(scene):
        raise InputError(f"scene {scene.name!r}: has no crack tip inside the body (every crack end lies on the "
                          f"boundary or on another crack), so no crack can grow")


def min_da(scene, solve_options) -> float:
    """The shortest segment a step may add: MIN_DA_TIP_FRACTION of the mesh size at the tips (tip_h,
    else crack_h, else maxh, as the mesh resolves them from the options and the scene)."""
    from ngcrack.planar.sizing import mesh_sizes

    sizes = {k: solve_options.get(k) for k in ("maxh", "tip_h", "crack_h", "grading")}
    try:
        maxh, tip_h, crack_h, _ = mesh_sizes(scene, **sizes)
    except (TypeError, ValueError):  # a bad size is refused, naming it, by the solve options' check
        return 0.0
    h = next(v for v in (tip_h, crack_h, maxh) if v is not None)
    return MIN_DA_TIP_FRACTION * float(h)


def check_growth_solve_options(scene, solve_options) -> None:
    """What a solve alone accepts but growth cannot use: friction on cracks that have no contact."""
    model = solve_options.get("crack_model") or "contact"
    if model != "contact":
        mu = max((float(getattr(c, "friction", 0.0) or 0.0) for c in scene.cracks), default=0.0)
        if mu:
            raise InputError(f"crack_model = {model!r}: the scene's cracks have friction {mu:g}, which acts only "
                             f"with crack_model 'contact' (free and bonded cracks have no contact); drop the friction "
                             f"(scene.with_(friction=0)) or use crack_model 'contact'")


def check_flag(value, name: str, what: str) -> bool:
    """A switch of grow: True or False (a string such as 'yes' is refused, not read as true)."""
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{name} = {value!r}: must be True or False ({what})")
    return bool(value)


def check_grow_call(scene, da, steps, K_Ic, criterion, together, progress, r_c, paris, R, at_hole, solve_options,
                    estimate=False, frames=True):
    """grow's input checks, in order, before any work: (the scene, r_c, the Paris law or None, the hole crack)."""
    from ngcrack.core.solve import as_scene
    from ngcrack.planar.scene import Scene

    if not isinstance(scene, (Scene, str)):
        raise InputError(f"scene = {scene!r}: must be a Scene (nc.Scene.from_toml, nc.scenes.load) or the name of a "
                         f"built-in scene")
    scene = as_scene(scene)
    if progress is not None and not callable(progress):
        raise InputError(f"progress = {progress!r}: must be None or a callable, called as progress(step, result) "
                         f"after every step")
    check_growth_options(scene, da, steps, K_Ic, criterion, solve_options)
    r_c = check_r_c(r_c, criterion)
    fatigue = check_paris(paris, R)
    hole_crack = check_at_hole(at_hole, scene)
    if isinstance(together, bool) or not (isinstance(together, (int, float)) and 0 <= together < 1):
        raise InputError(f"together = {together!r}: must be a number in [0, 1)")
    check_flag(estimate, "estimate", "compute every step's error estimate")
    check_flag(frames, "frames", "keep every step's deformed body for the animation")
    return scene, r_c, fatigue, hole_crack
