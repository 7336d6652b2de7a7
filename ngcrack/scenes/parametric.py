"""Scene functions: scenes built from a few physical parameters (for studies and teaching).

Each function returns a validated :class:`~ngcrack.scene.Scene` and documents its
parameters, its supports and the closed form it carries in ``scene.exact``.
"""

from __future__ import annotations

import math

from ngcrack.scene import Scene


def inclined_crack(angle: float = 30.0, half_length: float = 1.0, load: float = -1.0,
                   plate: float = 10.0, E: float = 1000.0, nu: float = 0.3,
                   plane: str = "strain", center: tuple[float, float] = (0.0, 0.0),
                   maxh: float | None = None, tip_h: float | None = None,
                   name: str | None = None) -> Scene:
    """A straight crack at ``angle`` degrees in a square plate under uniaxial stress.

    The plate is [-L, L]^2 with L = ``plate`` * ``half_length``; the crack of half-length
    a = ``half_length`` is centred at ``center`` (in units of a), its tangent at ``angle``
    degrees from the x axis. The top edge carries the traction (0, ``load``): remote
    sigma_yy = load (negative: compression, the crack closes and slides; positive:
    tension, it opens). Rollers on the left and bottom edges hold the plate without
    disturbing the uniform state (u_x depends on x only, u_y on y only); the right edge
    is free. The closed forms for the infinite plate (``scene.exact``, kind
    ``inclined``): sigma_n = load cos^2(angle), tau = load sin(angle) cos(angle);
    K_I = max(sigma_n, 0) sqrt(pi a), K_II = tau sqrt(pi a) without friction. At
    L = 10 a the finite plate changes them by well under 1%.

    Mesh: ``maxh`` (default a) and ``tip_h`` (default a / 200) at the tips, graded like
    the ``griffith`` scene.
    """
    a = float(half_length)
    if not (isinstance(angle, (int, float)) and math.isfinite(angle) and -90.0 < angle < 90.0):
        raise ValueError(f"angle = {angle!r}: must be a number of degrees in (-90, 90)")
    if not (isinstance(plate, (int, float)) and plate > 1.5):
        raise ValueError(f"plate = {plate!r}: must be a number > 1.5 (the half width in crack half-lengths)")
    L = float(plate) * a
    cx, cy = (float(c) * a for c in center)
    b = math.radians(angle)
    d = (a * math.cos(b), a * math.sin(b))
    kind = "compression" if load < 0 else "tension"
    return Scene(
        name=name or f"inclined-{kind}",
        description=(f"crack of half-length {a:g} at {angle:g} degrees in a {2 * L:g} x {2 * L:g} plate "
                     f"under remote sigma_yy = {load:g}; closed forms for the infinite plate"),
        polygon=((-L, -L), (L, -L), (L, L), (-L, L)),
        labels=("bottom", "right", "top", "left"),
        cracks=({"points": [[cx - d[0], cy - d[1]], [cx + d[0], cy + d[1]]]},),
        material={"E": E, "nu": nu, "plane": plane},
        boundary={"bottom": {"type": "roller"}, "left": {"type": "roller"},
                  "top": {"type": "traction", "value": [0.0, float(load)]}},
        maxh=a if maxh is None else maxh,
        tip_h=a / 200 if tip_h is None else tip_h,
        crack_h=a / 20,
        grading=0.2,
        exact={"kind": "inclined", "a": a, "p": float(load), "angle": float(angle), "center": [cx, cy]},
    )


def inclined_closed_form(scene: Scene) -> dict[str, float]:
    """sigma_n, tau, K_I, K_II (frictionless) and E' of an ``inclined`` scene's closed form."""
    ex = scene.exact
    if ex is None or ex["kind"] != "inclined":
        raise ValueError(f"scene {scene.name!r}: has no closed form of kind 'inclined'")
    b = math.radians(ex["angle"])
    sn = ex["p"] * math.cos(b) ** 2
    tau = ex["p"] * math.sin(b) * math.cos(b)
    mat = scene.material
    E_prime = mat.E / (1 - mat.nu ** 2) if mat.plane == "strain" else mat.E
    root = math.sqrt(math.pi * ex["a"])
    return {"sigma_n": sn, "tau": tau, "K_I": max(sn, 0.0) * root, "K_II": tau * root, "E_prime": E_prime}
