"""Element families: each module says which spaces it uses and builds its forms.

Every family returns a `Discretization` (see `base.py`): a compound NGSolve space whose
only non-local unknowns are the facet displacement trace u_hat, the crack jump
(normal part jn, tangential part jt) and, for PEERS, the continuous rotation. Its
bilinear form is assembled with static condensation; `hybrid.py` takes it from there.
"""

from __future__ import annotations

import math
import numbers

from ..errors import InputError
from . import bdm, h1, peers, tdnns
from .base import Discretization, ElementTraits, Loads

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
#: what the post-processing asks of each family (ElementTraits), known before anything is built
TRAITS = {"peers": peers.TRAITS, "bdm": bdm.TRAITS, "tdnns": tdnns.TRAITS, "h1p1": h1.TRAITS[1], "h1p2": h1.TRAITS[2]}


def check_element(name: str, order=None) -> int | None:
    """The one check of an element and its order: `name` one of ELEMENTS; `order` None
    (the family's default) or, for a family that has several (ORDERED), one of its ORDERS.
    Returns the order as an int (or None)."""
    if not isinstance(name, str) or name not in FAMILIES:
        raise InputError(f"element = {name!r}: allowed values are {', '.join(ELEMENTS)}")
    if order is None:
        return None
    if name not in ORDERED:
        raise InputError(f"order = {order!r}: element {name!r} has a fixed order; elements with an order: "
                         f"{', '.join(ORDERED)}")
    allowed = ORDERS[name]
    whole = isinstance(order, numbers.Real) and not isinstance(order, bool) and math.isfinite(float(order)) \
        and float(order).is_integer()
    if not whole or int(order) not in allowed:
        raise InputError(f"order = {order!r}: allowed values for {name} are {', '.join(map(str, allowed))} (or None "
                         f"for the element's default)")
    return int(order)


def build(name: str, crack_mesh, material, loads: Loads, order: int | None = None) -> Discretization:
    """Build the discretization of element family `name` (one of ELEMENTS).

    `order` selects the polynomial order where a family has several (bdm, tdnns); the
    families of fixed order (peers) accept only None (`check_element`).
    """
    order = check_element(name, order)
    if order is None:
        return FAMILIES[name](crack_mesh, material, loads)
    return FAMILIES[name](crack_mesh, material, loads, order=order)


__all__ = ["Discretization", "ElementTraits", "Loads", "ELEMENTS", "MIXED", "ORDERED", "ORDERS", "TRAITS", "build",
           "check_element"]
