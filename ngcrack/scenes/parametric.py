"""Scene functions: scenes built from a few physical parameters (for studies and teaching).

Each function returns a validated :class:`~ngcrack.planar.scene.Scene` and documents its
parameters, its supports and the closed form it carries in ``scene.exact``.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ngcrack.planar.scene import Scene

from ..core.errors import InputError


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
        raise InputError(f"angle = {angle!r}: must be a number of degrees in (-90, 90)")
    if not (isinstance(plate, (int, float)) and plate > 1.5):
        raise InputError(f"plate = {plate!r}: must be a number > 1.5 (the half width in crack half-lengths)")
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
        raise InputError(f"scene {scene.name!r}: has no closed form of kind 'inclined'")
    b = math.radians(ex["angle"])
    sn = ex["p"] * math.cos(b) ** 2
    tau = ex["p"] * math.sin(b) * math.cos(b)
    mat = scene.material
    E_prime = mat.E / (1 - mat.nu ** 2) if mat.plane == "strain" else mat.E
    root = math.sqrt(math.pi * ex["a"])
    return {"sigma_n": sn, "tau": tau, "K_I": max(sn, 0.0) * root, "K_II": tau * root, "E_prime": E_prime}


def griffith_plate(half_length: float = 1.0, load: float = 1.0, plate: float = 10.0,
                   E: float = 1000.0, nu: float = 0.3, plane: str = "strain",
                   center: tuple[float, float] = (0.0, 0.0), maxh: float | None = None,
                   tip_h: float | None = None, name: str | None = None) -> Scene:
    """Griffith's crack: a horizontal crack of half-length a in a square plate under remote tension.

    The whole plate [-L, L]^2, L = ``plate`` * a, the crack centred at ``center`` (in
    units of a), the top edge loaded by (0, ``load``), rollers on the left and bottom
    edges (they hold the plate without disturbing the uniform state; see
    :func:`inclined_crack`, of which this is the case angle = 0). Closed form
    (``scene.exact``, kind ``griffith``) for the infinite plate in plane strain: the crack
    opens as [u].nu = 4 p (1 - nu^2) / E sqrt(a^2 - s^2) under tension p = ``load`` > 0;
    K_I = p sqrt(pi a). Under compression it stays closed and carries sigma_n = p.
    """
    scene = inclined_crack(angle=0.0, half_length=half_length, load=load, plate=plate, E=E, nu=nu,
                           plane=plane, center=center, maxh=maxh, tip_h=tip_h)
    a = float(half_length)
    cx, cy = (float(c) * a for c in center)
    return scene.with_(
        name=name or "griffith-plate",
        description=(f"Griffith crack of half-length {a:g} in a {2 * plate * a:g} x {2 * plate * a:g} plate "
                     f"under remote sigma_yy = {load:g}; closed-form opening"),
        exact={"kind": "griffith", "a": a, "p": float(load), "center": [cx, cy]},
    )


def cracked_beam(center_x: float = 2.0, center_y: float = 0.5, half_length: float = 1.0,
                 angle: float = 0.0, length: float = 4.0, height: float = 1.0,
                 load: float = 1.0, E: float = 206900.0, nu: float = 0.29,
                 plane: str = "strain", maxh: float | None = None, tip_h: float | None = None,
                 name: str | None = None) -> Scene:
    """A beam clamped at both ends, bent by its own weight, with an interior crack.

    The paper's second example made parametric: the beam (0, ``length``) x (0, ``height``),
    clamped on the left and right edges, under the body force (0, -``load``); a straight
    crack of half-length ``half_length`` centred at (``center_x``, ``center_y``), its
    tangent at ``angle`` degrees from the x axis. Where the crack lies in the beam's
    shear zone it stays closed and slides; above the neutral axis near a clamp it opens.
    A crack that leaves the body is refused (SceneError naming the crack's points).
    """
    if not (isinstance(angle, (int, float)) and math.isfinite(angle) and -90.0 < angle < 90.0):
        raise InputError(f"angle = {angle!r}: must be a number of degrees in (-90, 90)")
    b = math.radians(angle)
    d = (half_length * math.cos(b), half_length * math.sin(b))
    W, H = float(length), float(height)
    return Scene(
        name=name or "cracked-beam",
        description=(f"beam {W:g} x {H:g} clamped at both ends under its weight {load:g}, crack of half-length "
                     f"{half_length:g} at {angle:g} degrees centred at ({center_x:g}, {center_y:g})"),
        polygon=((0.0, 0.0), (W, 0.0), (W, H), (0.0, H)),
        labels=("bottom", "right", "top", "left"),
        cracks=({"points": [[center_x - d[0], center_y - d[1]], [center_x + d[0], center_y + d[1]]]},),
        material={"E": E, "nu": nu, "plane": plane},
        body_force=(0.0, -float(load)),
        boundary={"left": {"type": "clamped"}, "right": {"type": "clamped"}},
        maxh=H / 8 if maxh is None else maxh,
        tip_h=H / 100 if tip_h is None else tip_h,
        crack_h=H / 30,
        grading=0.3,
    )


# --------------------------------------------------------------------------- registry


@dataclass(frozen=True)
class Parameter:
    """One parameter of a scene function as a slider shows it.

    ``kind``: "geometry" (a change remeshes), "load" or "material" (kept on the mesh);
    ``low``/``high``/``step`` the slider's range (the function may accept more).
    """

    name: str
    default: float
    low: float
    high: float
    step: float
    kind: str
    doc: str


@dataclass(frozen=True)
class SceneFunction:
    """A scene function of the registry: its name, the function and its parameters."""

    name: str
    function: Callable[..., Scene]
    parameters: tuple[Parameter, ...]
    summary: str

    def __call__(self, **params: Any) -> Scene:
        known = {p.name for p in self.parameters} | set(inspect.signature(self.function).parameters)
        unknown = sorted(set(params) - known)
        if unknown:
            raise InputError(f"{self.name}: unknown parameter{'s' if len(unknown) > 1 else ''} "
                              f"{', '.join(unknown)}; allowed: {', '.join(p.name for p in self.parameters)}")
        return self.function(**params)

    def geometry(self) -> tuple[Parameter, ...]:
        """The parameters whose change remeshes."""
        return tuple(p for p in self.parameters if p.kind == "geometry")

    def signature(self) -> str:
        """``name(p=default [low, high], ...)`` for listings."""
        return f"{self.name}(" + ", ".join(f"{p.name}={p.default:g} [{p.low:g}, {p.high:g}]"
                                           for p in self.parameters) + ")"


def _p(name, default, low, high, step, kind, doc):
    return Parameter(name, float(default), float(low), float(high), float(step), kind, doc)


#: half width of the teaching plates (absolute units: the crack's size and position change
#: inside a plate that stays put), and their mesh: maxh, the crack tips' and the crack's size
TEACHING_PLATE = 5.0
TEACHING_MESH = {"maxh": 1.0, "tip_h": 0.02}


def _teaching_half_length(half_length: float) -> float:
    if not (isinstance(half_length, (int, float)) and 0 < half_length < TEACHING_PLATE):
        raise InputError(f"half_length = {half_length!r}: must lie in (0, {TEACHING_PLATE:g})")
    return float(half_length)


def teaching_inclined(angle: float = 30.0, half_length: float = 1.0, center_x: float = 0.0,
                      center_y: float = 0.0, load: float = -1.0, E: float = 1000.0, nu: float = 0.3,
                      plane: str = "strain", maxh: float | None = None, tip_h: float | None = None,
                      name: str | None = None) -> Scene:
    """:func:`inclined_crack` in the fixed plate [-5, 5]^2, crack centre in absolute units,
    mesh TEACHING_MESH unless given."""
    a = _teaching_half_length(half_length)
    return inclined_crack(angle=angle, half_length=a, load=load, plate=TEACHING_PLATE / a, E=E, nu=nu, plane=plane,
                          center=(center_x / a, center_y / a), name=name,
                          maxh=TEACHING_MESH["maxh"] if maxh is None else maxh,
                          tip_h=TEACHING_MESH["tip_h"] if tip_h is None else tip_h)


def teaching_griffith(half_length: float = 1.0, center_x: float = 0.0, center_y: float = 0.0,
                      load: float = 1.0, E: float = 1000.0, nu: float = 0.3, plane: str = "strain",
                      maxh: float | None = None, tip_h: float | None = None, name: str | None = None) -> Scene:
    """:func:`griffith_plate` in the fixed plate [-5, 5]^2, crack centre in absolute units,
    mesh TEACHING_MESH unless given."""
    a = _teaching_half_length(half_length)
    return griffith_plate(half_length=a, load=load, plate=TEACHING_PLATE / a, E=E, nu=nu, plane=plane,
                          center=(center_x / a, center_y / a), name=name,
                          maxh=TEACHING_MESH["maxh"] if maxh is None else maxh,
                          tip_h=TEACHING_MESH["tip_h"] if tip_h is None else tip_h)


_POSITION = (_p("center_x", 0, -4, 4, 0.25, "geometry", "x of the crack centre"),
             _p("center_y", 0, -4, 4, 0.25, "geometry", "y of the crack centre"))

#: the teaching scene functions by name (``ngcrack scenes`` lists them; ``nc.explore`` shows
#: their geometry parameters as sliders)
SCENE_FUNCTIONS: dict[str, SceneFunction] = {
    "inclined-crack": SceneFunction(
        "inclined-crack", teaching_inclined,
        (_p("angle", 30, -80, 80, 5, "geometry", "crack angle from the x axis, degrees"),
         _p("half_length", 1, 0.25, 2.5, 0.25, "geometry", "crack half-length a"),
         *_POSITION,
         _p("load", -1, -2, 2, 0.1, "load", "remote sigma_yy on the top edge (negative: compression)")),
        "straight crack in the plate [-5, 5]^2 under uniaxial stress; closes and slides under compression"),
    "griffith-plate": SceneFunction(
        "griffith-plate", teaching_griffith,
        (_p("half_length", 1, 0.25, 2.5, 0.25, "geometry", "crack half-length a"),
         *_POSITION,
         _p("load", 1, -2, 2, 0.1, "load", "remote sigma_yy (positive: tension, the crack opens)")),
        "Griffith's horizontal crack in the plate [-5, 5]^2 under remote tension; closed-form opening"),
    "cracked-beam": SceneFunction(
        "cracked-beam", cracked_beam,
        (_p("center_x", 2, 0, 4, 0.1, "geometry", "x of the crack centre"),
         _p("center_y", 0.5, 0, 1, 0.05, "geometry", "y of the crack centre"),
         _p("half_length", 1, 0.1, 1.8, 0.1, "geometry", "crack half-length"),
         _p("angle", 0, -80, 80, 5, "geometry", "crack angle from the x axis, degrees"),
         _p("load", 1, -2, 2, 0.1, "load", "weight per unit area (body force (0, -load))")),
        "beam (0,4)x(0,1) clamped at both ends under its weight with an interior crack (the paper's example 2, parametric)"),
}


def scene_function(name: str) -> SceneFunction:
    """The registered scene function ``name`` (ValueError listing the names otherwise)."""
    try:
        return SCENE_FUNCTIONS[name]
    except KeyError:
        raise InputError(f"scene function = {name!r}: allowed values are {', '.join(SCENE_FUNCTIONS)}") from None
