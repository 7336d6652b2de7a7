"""The element families by name and their orders: what a solve's options may ask for.

Plain data and the one check of an element and its order (`check_element`), free of
any dimension: `ngcrack.core.options` validates a request with it before anything is built,
and the families' registry (`ngcrack.planar.elements.FAMILIES`) holds exactly these names.
"""

from __future__ import annotations

import math
import numbers

from .errors import InputError

#: every element family, by name
ELEMENTS = ("peers", "bdm", "tdnns", "h1p1", "h1p2")
#: the locking-free mixed elements (the baselines h1p1, h1p2 are displacement elements)
MIXED = ("peers", "bdm", "tdnns")
#: families that take an `order`, and the orders each has
ORDERS = {"bdm": (1, 2, 3), "tdnns": (1, 2, 3)}
ORDERED = tuple(ORDERS)
#: the displacement baselines' one order: asking for it is asking for the element's default
FIXED_ORDERS = {"h1p1": 1, "h1p2": 2}


def check_element(name: str, order=None) -> int | None:
    """The one check of an element and its order: `name` one of ELEMENTS; `order` None
    (the family's default) or, for a family that has several (ORDERED), one of its ORDERS.
    Returns the order as an int (or None)."""
    if not isinstance(name, str) or name not in ELEMENTS:
        raise InputError(f"element = {name!r}: allowed values are {', '.join(ELEMENTS)}")
    if order is None:
        return None
    if name not in ORDERED:
        if FIXED_ORDERS.get(name) == order and not isinstance(order, bool):
            return None
        raise InputError(f"order = {order!r}: element {name!r} has a fixed order; elements with an order: "
                         f"{', '.join(ORDERED)}")
    allowed = ORDERS[name]
    whole = isinstance(order, numbers.Real) and not isinstance(order, bool) and math.isfinite(float(order)) \
        and float(order).is_integer()
    if not whole or int(order) not in allowed:
        raise InputError(f"order = {order!r}: allowed values for {name} are {', '.join(map(str, allowed))} (or None "
                         f"for the element's default)")
    return int(order)
