"""What each control of the explorer accepts, what it is called, and the one-line refusal.

A control is numeric (a `Range`: low, high, step, linear or logarithmic slider) or a
choice (a tuple of allowed values). `Explorer` checks every value, passed to
`nc.explore` or set later, against them: a value out of range is refused with one line
naming the control and the allowed range (never clamped), and is not kept. The ranges of
E and of the mesh size follow the scene (decades around the starting E; mesh sizes whose
estimated unknowns stay below `MAX_UNKNOWNS`, so that a typed 0 cannot start a solve of
half a million unknowns); the geometry parameters come with their scene function.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real
from typing import Any

import numpy as np

from ...core.errors import InputError

#: significant digits of a refused value in the messages (-2.0001 is not shown as -2, its bound)
VALUE_DIGITS = 12

#: the names the widget shows (the keyword is what `nc.explore` and `update` take)
LABELS = {
    "load": "load factor", "load_angle": "load angle", "E": "Young's modulus", "nu": "Poisson's ratio",
    "friction": "friction coefficient", "pressure": "crack pressure",
    "maxh": "mesh size", "element": "element", "crack_model": "crack model", "field": "stress shown",
    "scales": "scales", "magnification": "magnification",
    "angle": "crack angle", "half_length": "crack half length", "center_x": "crack centre x",
    "center_y": "crack centre y",
}

#: one line of help per control (tooltips and the help line under the controls)
HELP = {
    "load": "every load of the scene times this factor: 1 = as the scene gives it, -1 = reversed, 0 = unloaded",
    "load_angle": "degrees, counter-clockwise: turns every load vector of the scene",
    "E": "Young's modulus, in the scene's stress units (the stresses of a load do not depend on it)",
    "nu": "Poisson's ratio (1/2: incompressible, only for the mixed elements)",
    "friction": "Coulomb friction coefficient of the crack faces",
    "pressure": "a uniform pressure on every crack's faces, pushing them apart (stress units; negative: suction)",
    "maxh": "largest triangle size (finer: more unknowns, slower)",
    "magnification": "displacements drawn times this factor (0: automatic, the largest displacement 8% of the body)",
}

#: what each crack model means, shown where it is chosen
CRACK_MODEL_HELP = {
    "contact": "contact: the faces may open but never pass through each other (Signorini)",
    "free": "free: traction-free faces, no contact condition: under compression they pass through each other",
    "bonded": "bonded: the faces are glued (no opening, no sliding), as if there were no crack; under compression "
              "contact closes the crack too, so the two look alike unless the faces slide",
}

#: the scales of the figure: held while only the load, load angle, friction or crack model
#: change ("auto"), held always, or fitted to every frame
SCALES = {"auto": "hold for load changes", "hold": "hold always", "fit": "fit every frame"}
#: the crack models as their menu shows them
CRACK_MODEL_LABELS = {"contact": "contact (Signorini)", "free": "free (no contact)", "bonded": "bonded (faces glued)"}

#: the finest mesh size offered gives at most this many unknowns (sizing.py's estimate)
MAX_UNKNOWNS = 2.0e5
#: decades of E around the starting value
E_DECADES = 2.0


class ControlRefused(InputError):
    """A control's value refused: the technical line (the keyword, the value, what it allows)
    as the message, and `sentence`, the same in plain words for a student."""

    def __init__(self, message: str, control: str, sentence: str):
        super().__init__(message)
        self.control = control
        self.sentence = sentence


def _plain(name: str) -> str:
    return LABELS.get(name, name.replace("_", " "))


@dataclass(frozen=True)
class Range:
    """The allowed values of a numeric control: low <= value <= high (a log slider if `log`)."""

    low: float
    high: float
    step: float
    log: bool = False

    def check(self, name: str, value: Any) -> float:
        """`value` as a float, or ValueError naming the control and the allowed range."""
        label = _label(name)
        if isinstance(value, (bool, np.bool_)):  # True is not the number 1 here
            raise ControlRefused(f"{label} = {value!r}: a number from {self.low:.4g} to {self.high:.4g}", name,
                                 f"The {_plain(name)} must be a number: type one from {self.low:.4g} to "
                                 f"{self.high:.4g}.")
        if not isinstance(value, Real):
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise ControlRefused(f"{label} = {value!r}: a number from {self.low:.4g} to {self.high:.4g}", name,
                                     f"The {_plain(name)} must be a number: type one from {self.low:.4g} to "
                                     f"{self.high:.4g}.") from None
        value = float(value)
        if not math.isfinite(value) or not self.low <= value <= self.high:
            raise ControlRefused(f"{label} = {value:.{VALUE_DIGITS}g} refused: allowed from {self.low:.4g} to {self.high:.4g}",
                                 name, f"The {_plain(name)} {value:.{VALUE_DIGITS}g} is out of range: choose a value from "
                                       f"{self.low:.4g} to {self.high:.4g}.")
        return value


def _label(name: str) -> str:
    shown = LABELS.get(name)
    return name if shown is None or shown == name else f"{name} ({shown})"


def check_choice(name: str, value: Any, allowed) -> Any:
    """`value` if it is one of `allowed`, else ValueError naming the control and the allowed values."""
    if not isinstance(value, str) or value not in allowed:
        listed = ", ".join(map(str, allowed))
        raise ControlRefused(f"{_label(name)} = {value!r}: allowed values are {listed}", name,
                             f"{value!r} is not a choice for the {_plain(name)}: pick one of {listed}.")
    return value


#: the ranges that do not depend on the scene: (low, high, step)
FIXED = {
    "load": Range(-2.0, 2.0, 0.1),
    "load_angle": Range(-180.0, 180.0, 5.0),
    "nu": Range(0.0, 0.5, 0.01),
    "friction": Range(0.0, 1.0, 0.05),
    "magnification": Range(0.0, 1e9, 1.0),
}


def e_range(E: float) -> Range:
    """E_DECADES decades either side of the starting E (which must be > 0)."""
    if isinstance(E, bool) or not isinstance(E, Real) or not math.isfinite(E) or E <= 0:
        raise InputError(f"E (Young's modulus) = {E!r} refused: it must be a number > 0")
    E = float(E)
    return Range(E * 10 ** -E_DECADES, E * 10 ** E_DECADES, 0.1, log=True)


def mesh_size_range(scene, element: str, maxh: float | None, solve_options: dict) -> tuple[Range, float]:
    """(the allowed mesh sizes, the starting one): from the finest one whose estimated
    unknowns stay below MAX_UNKNOWNS (or the given maxh, if finer) to sqrt(10) times the start."""
    from ...planar.sizing import estimate_size, mesh_sizes

    kw = {k: solve_options.get(k) for k in ("tip_h", "crack_h", "grading")}
    if maxh is not None:
        if isinstance(maxh, bool) or not isinstance(maxh, Real) or not math.isfinite(maxh) or maxh <= 0:
            raise InputError(f"maxh (mesh size) = {maxh!r} refused: it must be a number > 0 (or None: the scene's)")
        maxh = float(maxh)
    h0 = mesh_sizes(scene, maxh, **kw)[0]
    high = h0 * 10 ** 0.5

    def unknowns(h):  # (every element of the explorer has its size estimate)
        return estimate_size(scene, element, maxh=h, **kw).unknowns

    lo, hi = h0 * 1e-3, high
    if unknowns(lo) <= MAX_UNKNOWNS:
        finest = lo
    else:
        for _ in range(60):  # bisection in log h (the estimate falls as h grows)
            mid = math.sqrt(lo * hi)
            lo, hi = (mid, hi) if unknowns(mid) > MAX_UNKNOWNS else (lo, mid)
        finest = hi
    rounded = float(f"{finest:.3g}")
    low = min(rounded if rounded >= finest else finest, h0)
    return Range(low, high, 0.05, log=True), h0


def pressure_range(scene) -> Range:
    """The crack pressures offered: up to PRESSURE_SPAN times the scene's largest traction
    (E / 1000 when it has none, a strain of 1e-3), either sign, and the scene's own uniform
    pressures if larger."""
    loads = [math.hypot(*bc.value) for bc in scene.boundary.values() if bc.type == "traction" and bc.value]
    own = [abs(c.pressure) for c in scene.cracks if isinstance(c.pressure, float)]
    scale = max(loads, default=0.0) or 1e-3 * scene.material.E
    high = max([PRESSURE_SPAN * scale] + own)
    return Range(-high, high, high / 40.0)


#: the pressure slider spans this many times the scene's largest traction
PRESSURE_SPAN = 2.0


def wire_steps(slider, box, status, last: int, show) -> None:
    """Tie a step slider and a typed step box together (a step view's controls): moving the slider
    shows its step and sets the box; a typed step in 0..`last` moves the slider; any other typed
    value is refused in one line in `status` and the box goes back to the step shown. Shows the
    slider's step at once."""
    syncing = [False]  # the box set from the slider: not a value the user typed

    def typed(value) -> None:
        if syncing[0]:
            return
        if isinstance(value, int) and 0 <= value <= last:
            slider.value = value  # (the slider shows it)
            return
        syncing[0] = True
        box.value = slider.value  # refused: the box goes back to the step shown
        syncing[0] = False
        status.value = (f"<span style='color:#b00020'>&#9888; Step {value} is out of range: choose a step from 0 "
                        f"to {last}. The step box is back to {slider.value}.</span>")

    def moved(n: int) -> None:
        syncing[0] = True
        box.value = n
        syncing[0] = False
        show(n)

    slider.observe(lambda change: moved(change["new"]), names="value")
    box.observe(lambda change: typed(change["new"]), names="value")
    show(slider.value)

