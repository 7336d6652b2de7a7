"""Element families: each module says which spaces it uses and builds its forms.

Every family returns a `Discretization` (see `base.py`): a compound NGSolve space whose
only non-local unknowns are the facet displacement trace u_hat, the crack jump
(normal part jn, tangential part jt) and, for PEERS, the continuous rotation. Its
bilinear form is assembled with static condensation; `hybrid.py` takes it from there.
"""

from __future__ import annotations

from .base import Discretization, Loads
from . import bdm, peers

FAMILIES = {"peers": peers.build, "bdm": bdm.build}
ELEMENTS = tuple(FAMILIES)


def build(name: str, crack_mesh, material, loads: Loads, **options) -> Discretization:
    """Build the discretization of element family `name` (one of ELEMENTS)."""
    try:
        family = FAMILIES[name]
    except KeyError:
        raise ValueError(f"element = {name!r}: allowed values are {', '.join(ELEMENTS)}") from None
    return family(crack_mesh, material, loads, **options)


__all__ = ["Discretization", "Loads", "ELEMENTS", "build"]
