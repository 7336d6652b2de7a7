"""Whether a friction coefficient applies: friction acts only with crack_model "contact".

Light on purpose (numpy and the errors only): `ngcrack solve` checks its --friction with
these before a solve without loading the sweeps (ngcrack.studies.sweeps re-exports them).
"""

from __future__ import annotations

import warnings

import numpy as np

from .errors import InputError


def scene_friction(scene) -> float:
    """The scene's Coulomb coefficient for the `friction` column: its cracks' largest (0 without a crack)."""
    return max((float(c.friction) for c in scene.cracks), default=0.0)


def check_friction_applies(friction, crack_model: str | None, field: str = "friction") -> None:
    """Refuse a friction coefficient asked for with a crack model that has none (free, bonded)."""
    values = [friction] if isinstance(friction, (int, float, np.floating, np.integer)) else list(friction or [])
    given = [float(f) for f in values if isinstance(f, (int, float, np.floating, np.integer)) and f != 0]
    if given and (crack_model or "contact") != "contact":
        raise InputError(f"{field} = {given[0]:g}: friction acts only with crack_model = 'contact' (free and "
                          f"bonded cracks have no contact, so no friction); drop {field} or use crack_model "
                          f"'contact'")


def warn_friction_not_applied(scene, crack_model: str | None) -> None:
    """Warn that a scene's own friction plays no part under crack_model free or bonded."""
    mu = scene_friction(scene)
    if mu and (crack_model or "contact") != "contact":
        warnings.warn(f"scene {scene.name!r}: its cracks' friction ({mu:g}) is not applied with crack_model = "
                      f"{crack_model!r} (a sweep's rows record friction 0)", UserWarning, stacklevel=3)
