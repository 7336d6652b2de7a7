"""Finite cracked strips with handbook stress intensity factors (Tada, Paris, Irwin).

Reference: H. Tada, P. C. Paris, G. R. Irwin, *The Stress Analysis of Cracks Handbook*,
3rd ed., ASME Press, 2000. Both strips are long (height 2 H, H = `height` widths) and
loaded by a uniform tension p on their ends; the handbook's values are for the infinitely
long strip, which the strips here approach to well under 0.5% (Saint-Venant: the ends'
disturbances decay over about one width).

- `centre_cracked_strip`: width 2b, a central crack of length 2a normal to the load
  (handbook page 2.1, after Feddersen; accurate to 0.1% for any a/b):

      K_I = p sqrt(pi a) (1 - 0.025 (a/b)^2 + 0.06 (a/b)^4) sqrt(sec(pi a / (2 b)))

- `edge_cracked_strip`: width b, an edge crack of length a normal to the load, the ends
  free to rotate (handbook page 2.10; accurate to 0.5% for any a/b):

      K_I = p sqrt(pi a) sqrt(2b / (pi a) tan(pi a / (2b)))
            (0.752 + 2.02 (a/b) + 0.37 (1 - sin(pi a / (2b)))^3) / cos(pi a / (2b))
"""

from __future__ import annotations

import math

from ngcrack.planar.scene import Scene

from ..core.errors import InputError

#: half length of the clamped anchor of the edge-cracked strip, in widths: the loads are
#: self-equilibrated, so the anchor only removes the rigid motions (its reaction is the
#: load missing on it, 2 ANCHOR p b, spread by Saint-Venant near the far end)
ANCHOR = 0.02


def _ratio(a_over_b: float, low: float, high: float) -> float:
    if isinstance(a_over_b, bool) or not isinstance(a_over_b, (int, float)) or not (low < a_over_b < high):
        raise InputError(f"a_over_b = {a_over_b!r}: must be a number in ({low:g}, {high:g})")
    return float(a_over_b)


def _mesh(a: float, b: float, maxh, tip_h, crack_h) -> dict:
    return {"maxh": b / 2 if maxh is None else maxh, "tip_h": a / 200 if tip_h is None else tip_h,
            "crack_h": min(a, b - a) / 20 if crack_h is None else crack_h, "grading": 0.2}


def centre_cracked_strip(a_over_b: float = 0.4, b: float = 1.0, height: float = 3.0, load: float = 1.0,
                         E: float = 1000.0, nu: float = 0.3, plane: str = "strain", maxh: float | None = None,
                         tip_h: float | None = None, crack_h: float | None = None) -> Scene:
    """The centre-cracked strip (width 2b, crack 2a, ends |y| = H = height * b under tension `load`).

    Modelled by symmetry like the `griffith` scene: the right half [0, b] x [-H, H] with
    rollers on the symmetry line x = 0 (split at the crack's centre), the half crack
    (0, 0)-(a, 0), traction (0, load) on the top, a roller on the bottom (the strip's
    mid plane y = 0 would be one by symmetry; its far end stays straight). One tip, at
    (a, 0). Closed form: `centre_cracked_K`.
    """
    lam = _ratio(a_over_b, 0.0, 0.95)
    a, H = lam * b, height * b
    return Scene(
        name=f"centre-cracked-strip-{lam:g}",
        description=f"centre-cracked strip, a/b = {lam:g}, half width {b:g}, height {2 * H:g}, tension {load:g} "
                    f"(Tada-Paris-Irwin)",
        polygon=((0.0, -H), (b, -H), (b, H), (0.0, H), (0.0, 0.0)),
        labels=("bottom", "right", "top", "sym-upper", "sym-lower"),
        cracks=({"points": [[0.0, 0.0], [a, 0.0]]},),
        material={"E": E, "nu": nu, "plane": plane},
        boundary={"bottom": {"type": "roller"}, "sym-upper": {"type": "roller"}, "sym-lower": {"type": "roller"},
                  "top": {"type": "traction", "value": [0.0, float(load)]}},
        **_mesh(a, b, maxh, tip_h, crack_h),
    )


def edge_cracked_strip(a_over_b: float = 0.3, b: float = 1.0, height: float = 3.0, load: float = 1.0,
                       E: float = 1000.0, nu: float = 0.3, plane: str = "strain", maxh: float | None = None,
                       tip_h: float | None = None, crack_h: float | None = None) -> Scene:
    """The single-edge-cracked strip (width b, edge crack a, ends |y| = H under tension `load`).

    The whole strip [0, b] x [-H, H], the crack (0, 0)-(a, 0) from the left edge, traction
    (0, +-load) on both ends (so the ends rotate freely, as in the handbook), held by a
    short clamped anchor in the middle of the bottom end (ANCHOR). One tip, at (a, 0).
    Closed form: `edge_cracked_K`.
    """
    lam = _ratio(a_over_b, 0.0, 0.9)
    a, H = lam * b, height * b
    d = ANCHOR * b
    down = {"type": "traction", "value": [0.0, -float(load)]}
    return Scene(
        name=f"edge-cracked-strip-{lam:g}",
        description=f"single-edge-cracked strip, a/b = {lam:g}, width {b:g}, height {2 * H:g}, tension {load:g} "
                    f"(Tada-Paris-Irwin)",
        polygon=((0.0, -H), (0.5 * b - d, -H), (0.5 * b + d, -H), (b, -H), (b, H), (0.0, H)),
        labels=("bottom-left", "anchor", "bottom-right", "right", "top", "left"),
        cracks=({"points": [[0.0, 0.0], [a, 0.0]]},),
        material={"E": E, "nu": nu, "plane": plane},
        boundary={"bottom-left": down, "bottom-right": down, "anchor": {"type": "clamped"},
                  "top": {"type": "traction", "value": [0.0, float(load)]}},
        **_mesh(a, b, maxh, tip_h, crack_h),
    )


def centre_cracked_K(a_over_b: float, b: float = 1.0, load: float = 1.0) -> float:
    """Tada-Paris-Irwin (p. 2.1): K_I = p sqrt(pi a) (1 - 0.025 l^2 + 0.06 l^4) sqrt(sec(pi l / 2)), l = a/b."""
    lam = _ratio(a_over_b, 0.0, 1.0)
    return load * math.sqrt(math.pi * lam * b) * (1 - 0.025 * lam**2 + 0.06 * lam**4) / math.sqrt(math.cos(0.5 * math.pi * lam))


def edge_cracked_K(a_over_b: float, b: float = 1.0, load: float = 1.0) -> float:
    """Tada-Paris-Irwin (p. 2.10), ends free to rotate:
    K_I = p sqrt(pi a) sqrt(2 / (pi l) tan(pi l / 2)) (0.752 + 2.02 l + 0.37 (1 - sin(pi l / 2))^3) / cos(pi l / 2)."""
    lam = _ratio(a_over_b, 0.0, 1.0)
    x = 0.5 * math.pi * lam
    F = math.sqrt(math.tan(x) / x) * (0.752 + 2.02 * lam + 0.37 * (1 - math.sin(x)) ** 3) / math.cos(x)
    return load * math.sqrt(math.pi * lam * b) * F
