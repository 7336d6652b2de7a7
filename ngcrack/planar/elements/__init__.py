"""Element families: each module says which spaces it uses and builds its forms.

Every family returns a `Discretization` (see `base.py`): a compound NGSolve space whose
only non-local unknowns are the facet displacement trace u_hat, the crack jump
(normal part jn, tangential part jt) and, for PEERS, the continuous rotation. Its
bilinear form is assembled with static condensation; `hybrid.py` takes it from there.
"""

from __future__ import annotations

from ...core.element_names import ELEMENTS, MIXED, ORDERED, ORDERS, check_element
from . import bdm, h1, peers, tdnns
from .base import Discretization, ElementTraits, Loads

FAMILIES = {
    "peers": peers.build,
    "bdm": bdm.build,
    "tdnns": tdnns.build,
    "h1p1": lambda *args: h1.build(*args, order=1),
    "h1p2": lambda *args: h1.build(*args, order=2),
}
if tuple(FAMILIES) != ELEMENTS:
    raise ImportError("ngcrack.planar.elements: the families' registry differs from ngcrack.core.element_names.ELEMENTS")
#: what the post-processing asks of each family (ElementTraits), known before anything is built
TRAITS = {"peers": peers.TRAITS, "bdm": bdm.TRAITS, "tdnns": tdnns.TRAITS, "h1p1": h1.TRAITS[1], "h1p2": h1.TRAITS[2]}


def check_material(name: str, material) -> None:
    """Refuse, before any meshing, a material that element `name` cannot solve (ElementTraits.check_material)."""
    TRAITS[name].check_material(name, material, [e for e in ELEMENTS if TRAITS[e].incompressible])


def build(name: str, crack_mesh, material, loads: Loads, order: int | None = None) -> Discretization:
    """Build the discretization of element family `name` (one of ELEMENTS).

    `order` selects the polynomial order where a family has several (bdm, tdnns); the
    families of fixed order (peers) accept only None (`check_element`).
    """
    order = check_element(name, order)
    if order is None:
        return FAMILIES[name](crack_mesh, material, loads)
    return FAMILIES[name](crack_mesh, material, loads, order=order)


__all__ = ["Discretization", "ElementTraits", "Loads", "ELEMENTS", "MIXED", "ORDERED", "ORDERS", "TRAITS", "build", "check_material",
           "check_element"]
