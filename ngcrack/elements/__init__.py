"""Element families: each module says which spaces it uses and builds its forms.

Every family returns a `Discretization` (see `base.py`): a compound NGSolve space whose
only non-local unknowns are the facet displacement trace u_hat, the crack jump
(normal part jn, tangential part jt) and, for PEERS, the continuous rotation. Its
bilinear form is assembled with static condensation; `hybrid.py` takes it from there.
"""

from __future__ import annotations

from ..errors import InputError
from . import bdm, h1, peers, tdnns
from .base import Discretization, Loads

FAMILIES = {
    "peers": peers.build,
    "bdm": bdm.build,
    "tdnns": tdnns.build,
    "h1p1": lambda *args: h1.build(*args, order=1),
    "h1p2": lambda *args: h1.build(*args, order=2),
}
#: the locking-free mixed elements (the baselines h1p1, h1p2 are displacement elements)
MIXED = ("peers", "bdm", "tdnns")
ELEMENTS = tuple(FAMILIES)
#: families that take an `order`, and the orders each has
ORDERS = {"bdm": bdm.ORDERS, "tdnns": tdnns.ORDERS}
ORDERED = tuple(ORDERS)


def build(name: str, crack_mesh, material, loads: Loads, order: int | None = None) -> Discretization:
    """Build the discretization of element family `name` (one of ELEMENTS).

    `order` selects the polynomial order where a family has several (bdm, tdnns); the
    families of fixed order (peers) accept only None.
    """
    try:
        family = FAMILIES[name]
    except KeyError:
        raise InputError(f"element = {name!r}: allowed values are {', '.join(ELEMENTS)}") from None
    if order is None:
        return family(crack_mesh, material, loads)
    if name not in ORDERED:
        raise InputError(f"order = {order!r}: element {name!r} has a fixed order; elements with an order: {', '.join(ORDERED)}")
    return family(crack_mesh, material, loads, order=order)


__all__ = ["Discretization", "Loads", "ELEMENTS", "MIXED", "ORDERED", "ORDERS", "build"]
