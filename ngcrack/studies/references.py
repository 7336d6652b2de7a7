"""Converged answers of the built-in scenes' finite bodies, with their uncertainty.

The ``griffith`` and ``inclined-compression`` scenes carry closed forms for the
*infinite* plate (``scene.exact``). Their bodies are finite plates (20 a wide), whose own
answers differ from the closed forms by more than a good mesh's error: on ``griffith``
the plate opens 0.94% more than the ellipse and K_I = 1.0094 p sqrt(pi a); on
``inclined-compression`` it slides 0.28% more and K_II is 0.25% and 0.30% larger than
tau sqrt(pi a) at the two tips. Accuracy is measured against these references; the
closed forms stay beside them (``Reference.closed_form``).

How they were obtained (``python benchmarks/references.py`` reproduces them and prints
the convergence tables): a sequence of tdnns solves at order 3 (and 2) on meshes refined
together (maxh, crack_h halved and tip_h divided by 5 per level; the finest has 2.1e6
unknowns on griffith, 1.2e6 on inclined-compression), the values extrapolated
Richardson-style from the last three levels of order 3 where their differences shrink at
least twofold per level (else the finest value, with the last change as its
uncertainty); the uncertainty is the larger of the distance between the finest level and
the estimate and the distance between the order-3 and order-2 estimates, rounded up. The crack-face profile is stored as the
closed form's shape times a smooth correction,

    [u](d) = shape(d) * sum_k c_k P_k(d / a),    shape(d) = 4 p' / E' sqrt(a^2 - d^2),

(P_k the Legendre polynomials, d the signed distance from the crack's centre along the
crack, p' the load normal to the crack (griffith) or its shear tau (inclined)), fitted by
weighted least squares to the edge mid-point samples of the two finest solves and
extrapolated like the values; ``profile_uncertainty`` is the relative L2 distance between
the extrapolated and the finest fit plus the fit's own residual. An independent code
agrees: GetFEM's tip-enriched P2 XFEM (benchmarks/getfem_peer.py) on its finest meshes
differs from these references by 5e-6 (K_I) and 2e-5 (opening) on griffith, 8e-6 (K_II)
and 8e-6 (sliding) on inclined-compression. At nu = 0.4999 the references agree with
those at 0.3 relative to the closed forms (which scale with 1 - nu^2) to 3e-6: the plates'
stress hardly depends on nu.

    >>> import ngcrack as nc
    >>> ref = nc.references.reference("griffith")
    >>> ref.tips["0,last"].K_I            # doctest: +ELLIPSIS
    1.78...
    >>> sol = nc.solve(nc.scenes.load("griffith"), element="tdnns", order=3)
    >>> nc.references.errors(sol)         # doctest: +SKIP
    {'K': 4.5e-06, 'profile': 1.3e-04, ...}
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import InputError

__all__ = [
    "K_error",
    "Reference",
    "TipReference",
    "closed_form_shape",
    "errors",
    "names",
    "poisson_ratios",
    "profile_error",
    "reference",
    "reference_for",
]


@dataclass(frozen=True)
class TipReference:
    """The converged K_I, K_II of one tip (label as ``ngcrack.planar.tips``: "crack,end")."""

    label: str
    K_I: float
    K_II: float


@dataclass(frozen=True)
class Reference:
    """The finite body's converged answer for one built-in scene.

    tips: label -> TipReference; K_uncertainty: absolute, for every K of every tip.
    mode: "K_I" or "K_II", the stress intensity the scene is about (errors are relative to it).
    profile: "normal" (the opening, griffith) or "tangential" (the sliding, inclined-compression).
    amplitude: the profile's L2 projection on the closed form's shape, relative to it
    (1 = the infinite plate); coefficients: the Legendre series of the profile / shape.
    closed_form: the infinite plate's K_I, K_II (at every tip) and amplitude 1, for comparison.
    method: how the numbers were obtained (reproduced by benchmarks/references.py).
    """

    scene: str
    tips: dict
    K_uncertainty: float
    mode: str
    profile: str
    amplitude: float
    amplitude_uncertainty: float
    coefficients: tuple
    profile_uncertainty: float
    closed_form: dict
    method: str
    center: tuple = (0.0, 0.0)
    direction: tuple = (1.0, 0.0)
    half_length: float = 1.0
    shape_factor: float = 1.0
    unknowns: int = 0
    nu: float = 0.3
    extra: dict = field(default_factory=dict)

    def distance(self, x, y) -> np.ndarray:
        """Signed distance d from the crack's centre along the crack, at points (x, y) on it."""
        return ((np.asarray(x, float) - self.center[0]) * self.direction[0]
                + (np.asarray(y, float) - self.center[1]) * self.direction[1])

    def shape(self, x, y) -> np.ndarray:
        """The infinite plate's profile (opening or sliding) at points (x, y) of the crack."""
        d = self.distance(x, y)
        return self.shape_factor * np.sqrt(np.clip(self.half_length**2 - d**2, 0.0, None))

    def jump(self, x, y) -> np.ndarray:
        """The finite body's profile (the reference) at points (x, y) of the crack."""
        t = np.clip(self.distance(x, y) / self.half_length, -1.0, 1.0)
        return self.shape(x, y) * np.polynomial.legendre.legval(t, np.asarray(self.coefficients))

    def K(self, label: str) -> float:
        """The reference value of the scene's mode (K_I or K_II) at tip `label`."""
        return getattr(self.tips[label], self.mode)


def closed_form_shape(scene) -> tuple[tuple, tuple, float, float, str]:
    """(centre, unit direction, a, factor, profile) of the closed form's profile of `scene`:
    profile(d) = factor sqrt(a^2 - d^2), "normal" for a griffith crack, "tangential" for an
    inclined one (factor 4 tau / E' with tau the shear on the crack)."""
    ex = scene.exact
    if ex is None or ex.get("kind") not in ("griffith", "inclined"):
        raise InputError(f"scene {scene.name!r}: has no griffith or inclined closed form")
    mat = scene.material
    e_prime = mat.E / (1 - mat.nu**2) if mat.plane == "strain" else mat.E
    pts = np.asarray(scene.cracks[0].points, float)
    t = pts[-1] - pts[0]
    t = t / np.linalg.norm(t)
    if ex["kind"] == "griffith":
        return tuple(ex["center"]), tuple(t), float(ex["a"]), 4 * ex["p"] / e_prime, "normal"
    b = math.radians(ex["angle"])
    tau = ex["p"] * math.sin(b) * math.cos(b)
    return tuple(ex["center"]), tuple(t), float(ex["a"]), 4 * tau / e_prime, "tangential"


def _root_pi() -> float:
    return math.sqrt(math.pi)


# The numbers below are printed by `python benchmarks/references.py` (its last lines).
# K in absolute units (p = a = 1: the closed form's K_I = sqrt(pi) = 1.7725).
_DATA = {
    ("griffith", 0.3): dict(
        tips={"0,last": (1.7890471, -0.0008809)},
        K_uncertainty=4e-06,
        mode="K_I",
        amplitude=1.0093911,
        amplitude_uncertainty=2e-05,
        coefficients=(1.0093866, 0.0, -2.28e-05, 0.0, 1.6e-06, 0.0, 1.3e-06, 0.0, 8e-07),
        profile_uncertainty=3e-06,
        closed_form={"0,last": (_root_pi(), 0.0)},
        unknowns=2080000,
    ),
    # K_I = 0: the crack is closed (the extrapolated domain integrals give at most 1.2e-3)
    ("inclined-compression", 0.3): dict(
        tips={"0,first": (0.0, -0.7694181), "0,last": (0.0, -0.7698124)},
        K_uncertainty=6e-06,
        mode="K_II",
        amplitude=1.0027664,
        amplitude_uncertainty=2e-05,
        coefficients=(1.0027599, 0.000243, -3.23e-05, -2.01e-05, -2.56e-05, -1.63e-05, -2.08e-05, -9.6e-06, -1.2e-05),
        profile_uncertainty=4e-05,
        closed_form={k: (0.0, -math.sin(math.pi / 6) * math.cos(math.pi / 6) * _root_pi()) for k in ("0,first", "0,last")},
        unknowns=1200144,
    ),
    # nu = 0.4999 (near incompressibility): the stress of these traction-loaded plates hardly depends
    # on nu, so K and the profile relative to the closed form (which scales with 1 - nu^2) are as at 0.3
    ("griffith", 0.4999): dict(
        tips={"0,last": (1.7890471, -0.0008809)},
        K_uncertainty=4e-06,
        mode="K_I",
        amplitude=1.0093910,
        amplitude_uncertainty=2e-05,
        coefficients=(1.0093864, 0.0, -2.33e-05, 0.0, 1e-06, 0.0, 9e-07, 0.0, 5e-07),
        profile_uncertainty=3e-06,
        closed_form={"0,last": (_root_pi(), 0.0)},
        unknowns=2080000,
    ),
    ("inclined-compression", 0.4999): dict(
        tips={"0,first": (0.0, -0.7694182), "0,last": (0.0, -0.7698125)},
        K_uncertainty=7e-06,
        mode="K_II",
        amplitude=1.0027640,
        amplitude_uncertainty=2e-05,
        coefficients=(1.0027552, 0.0002411, -4.36e-05, -2.26e-05, -3.76e-05, -1.84e-05, -3.06e-05, -1.09e-05, -1.76e-05),
        profile_uncertainty=5e-05,
        closed_form={k: (0.0, -math.sin(math.pi / 6) * math.cos(math.pi / 6) * _root_pi()) for k in ("0,first", "0,last")},
        unknowns=1200144,
    ),
}

_METHOD = ("tdnns order 3 (and 2) on the scene with maxh, crack_h halved and tip_h / 5 per level, four levels "
           "(griffith, finest 2.1e6 unknowns) or three (inclined-compression, 1.2e6); Richardson extrapolation of "
           "the last three order-3 levels where their differences shrink at least twofold per level (else the "
           "finest value, the last change its uncertainty); uncertainty: the larger of the distance to the finest "
           "level and to the order-2 estimate, rounded up; profile: Legendre fit of profile / closed-form shape "
           "to the two finest levels' samples, extrapolated alike (benchmarks/references.py)")


#: the Poisson ratios of the references of each scene (the first: the scene's own)
def poisson_ratios(name: str) -> list[float]:
    """The Poisson ratios at which scene `name` has a reference (the scene's own first)."""
    _check_name(name)
    return [nu for (n, nu) in _DATA if n == name]


def names() -> list[str]:
    """The scenes that have a reference."""
    return sorted({n for n, _ in _DATA})


def _check_name(name: str) -> None:
    if name not in names():
        raise InputError(f"scene = {name!r}: no finite-body reference; scenes with one: {', '.join(names())}")


def reference(name: str, nu: float | None = None) -> Reference:
    """The finite-body reference of the built-in scene `name` ("griffith", "inclined-compression"),
    at its own Poisson ratio or at `nu` (one of ``poisson_ratios(name)``)."""
    _check_name(name)
    from ngcrack import scenes

    scene = scenes.load(name)
    nu = scene.material.nu if nu is None else nu
    if (name, nu) not in _DATA:
        raise InputError(f"nu = {nu!r}: scene {name!r} has references at nu = "
                          f"{', '.join(f'{v:g}' for v in poisson_ratios(name))}")
    d = _DATA[(name, nu)]
    center, direction, a, factor, profile = closed_form_shape(scene.with_(nu=nu))
    return Reference(
        scene=name, tips={k: TipReference(k, *v) for k, v in d["tips"].items()}, K_uncertainty=d["K_uncertainty"],
        mode=d["mode"], profile=profile, amplitude=d["amplitude"], amplitude_uncertainty=d["amplitude_uncertainty"],
        coefficients=tuple(d["coefficients"]), profile_uncertainty=d["profile_uncertainty"],
        closed_form={"tips": {k: TipReference(k, *v) for k, v in d["closed_form"].items()}, "amplitude": 1.0},
        method=_METHOD, center=center, direction=direction, half_length=a, shape_factor=factor,
        unknowns=d["unknowns"], nu=nu)


def reference_for(scene) -> Reference | None:
    """The reference of `scene` if it is a built-in scene that has one (unchanged but for a Poisson
    ratio that has one); else None."""
    from ngcrack import scenes

    name = getattr(scene, "name", None)
    if name not in names():
        return None
    nu = scene.material.nu
    if (name, nu) in _DATA and scene == scenes.load(name).with_(nu=nu):
        return reference(name, nu)
    return None


def _ref(sol, ref: Reference | None) -> Reference:
    ref = reference_for(sol.scene) if ref is None else ref
    if ref is None:
        raise InputError(f"scene {sol.scene.name!r}: no finite-body reference (a built-in scene of "
                          f"{', '.join(names())}, unchanged but for a Poisson ratio of references.poisson_ratios, "
                          f"has one)")
    return ref


def profile_jump(sol, ref: Reference) -> np.ndarray:
    prof = sol.profiles[0]
    return prof.normal_jump if ref.profile == "normal" else prof.tangential_jump


def profile_error(sol, ref: Reference | None = None, closed_form: bool = False) -> float:
    """Relative L2 error of the first crack's profile (opening or sliding, by the reference's
    kind) over the edge mid points, weighted by the edge lengths, against the finite-body
    reference (or, ``closed_form=True``, against the infinite plate's closed form)."""
    ref = _ref(sol, ref)
    prof = sol.profiles[0]
    exact = ref.shape(prof.x, prof.y) if closed_form else ref.jump(prof.x, prof.y)
    L = sol.crack_mesh.cracks[0].length
    jump = profile_jump(sol, ref)
    return float(math.sqrt(np.sum(L * (jump - exact) ** 2) / np.sum(L * exact**2)))


def K_error(sol, ref: Reference | None = None, closed_form: bool = False) -> float:
    """max over the tips of |K - K_ref| / |K_ref| for the scene's mode (K_I or K_II)."""
    ref = _ref(sol, ref)
    tips = ref.closed_form["tips"] if closed_form else ref.tips
    out = 0.0
    for tip in sol.tips:
        want = getattr(tips[tip.label], ref.mode)
        out = max(out, abs(getattr(tip, ref.mode) - want) / abs(want))
    return out


def errors(sol, ref: Reference | None = None) -> dict[str, float]:
    """K and profile errors against the finite-body reference, and against the closed form."""
    ref = _ref(sol, ref)
    return {"K": K_error(sol, ref), "profile": profile_error(sol, ref),
            "K_closed_form": K_error(sol, ref, True), "profile_closed_form": profile_error(sol, ref, True)}
