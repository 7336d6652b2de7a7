"""The error quantities of a sweep, the reference they are measured against, the closed forms.

Error quantities (the paper's Tables 1-4). Let n be the unit normal of the first crack's
first segment (the crack normal nu of the paper and of the README; (0, 1) for a scene without a crack: the
column `nu` is Poisson's ratio). With (sigma n)_i = sum_j sigma_ij n_j:

    u1, u2      the displacement components
    sigma_t1    the first component of the tangential traction sigma n - sigma_n n
    sigma_nu    the normal traction sigma_n = (sigma n).n

For a horizontal crack, n = (0, 1): sigma_nu = sigma_22 and sigma_t1 = sigma_12 (row 1,
column 2 of the weakly symmetric stress). Each error is relative in L2(Omega):

    err_q = || q_h - q_ref ||_{L2(Omega)} / || q_ref ||_{L2(Omega)}

q_ref is the same quantity of the reference solution. The meshes are not nested, so both
fields are evaluated at the quadrature points of the reference mesh (the finer one; a
rule exact for degree QUADRATURE_ORDER on each of its triangles), and the integral is
that quadrature. (A reference quantity that vanishes, below ZERO_FIELD of the largest of
u1, u2 or of sigma_t1, sigma_nu, is measured relative to that largest instead.)
The reference is, per (element, nu, friction), the solution at `reference_maxh`:
by default the finest maxh of the sweep (its row is marked `reference` and its errors
are empty), or a separate finer run when `reference_maxh` is given (the paper's method:
every listed mesh has an error against a finer one that is not listed).
`reference_element` measures every element against one common reference instead.

Closed-form error: where the scene has `[exact] kind = "griffith"` (a centre crack of
half-length a under remote tension p), `err_opening` is the relative L2 error along the
crack of the normal jump against 4 p / E' sqrt(a^2 - s^2), E' = E / (1 - nu^2) in plane
strain and E in plane stress, s the distance from `exact.center`, by the mid-point rule
on the crack edges. Empty elsewhere.

Tips. Each row carries the fracture parameters of every crack end inside the body
(ngcrack/planar/tips.py) as the columns `K_I[c,end]`, `K_II[c,end]`, `G[c,end]` (c the crack's
index, end "first" or "last"), after ROW_COLUMNS; `time_tips` is their cost (part of
time_total) and `err_K_I`, where the scene has a closed form (griffith, inclined), the
largest |K_I - K_I exact| / (|p| sqrt(pi a)) over the tips (`k_error`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...planar.quadrature import QUADRATURE_ORDER, quadrature_points
from ...shell.files import atomic_write

#: the paper's error quantities, in the order of its Tables 1-4
QUANTITIES = ("u1", "u2", "sigma_t1", "sigma_nu")
#: quantities that get rates: the paper's four and the closed-form crack opening
RATE_QUANTITIES = QUANTITIES + ("opening", "K_I")
#: plain-text and LaTeX labels of the quantities
QUANTITY_LABELS = {
    "u1": r"$u_1$", "u2": r"$u_2$", "sigma_t1": r"$\sigma_{t,1}$", "sigma_nu": r"$\sigma_\nu$",
    "opening": r"crack opening $[u]\cdot\nu$",
    "K_I": r"$K_I$ at the tips",
}
#: a reference quantity whose L2 norm is below this fraction of its group's largest
#: (u1, u2 or sigma_t1, sigma_nu) counts as zero: its error is then relative to that largest
ZERO_FIELD = 1e-8
#: per crack end inside the body, the columns `K_I[c,end]`, `K_II[c,end]`, `G[c,end]`
#: (c the crack's index, end "first" or "last") follow a row's columns (see `tip_columns`)
TIP_QUANTITIES = ("K_I", "K_II", "G")



def quantity_normal(scene) -> np.ndarray:
    """n: the unit normal of the first crack's first segment, (0, 1) without a crack."""
    if scene.cracks:
        return np.array(scene.cracks[0].normals()[0], dtype=float)
    return np.array([0.0, 1.0])



def sample_quantities(sol, points: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Values (N, 4) of u1, u2, sigma_t1, sigma_nu of `sol` at `points` (N, 2)."""
    mp = sol.mesh(points[:, 0], points[:, 1])
    missing = np.flatnonzero(np.asarray(mp)["nr"] < 0)
    if len(missing):
        x = points[missing[0]]
        raise ValueError(f"{len(missing)} evaluation points lie outside the mesh of {sol.scene.name!r} "
                         f"(first: ({x[0]:.6g}, {x[1]:.6g})): the meshes do not cover the same domain")
    return _quantities(sol, mp, normal)


def _quantities(sol, mp, normal: np.ndarray) -> np.ndarray:
    u = np.asarray(sol.u(mp)).reshape(-1, 2)
    sig = np.asarray(sol.sigma(mp)).reshape(-1, 2, 2)
    traction = np.einsum("pij,j->pi", sig, normal)
    s_nu = traction @ normal
    s_t1 = traction[:, 0] - s_nu * normal[0]
    return np.column_stack([u[:, 0], u[:, 1], s_t1, s_nu])


@dataclass
class Reference:
    """A reference solution sampled at its own mesh's quadrature points (picklable).

    `values[:, k]` is QUANTITIES[k] at `points`; `norms[k]` its L2 norm.
    """

    scene: str
    element: str
    maxh: float
    nu: float
    ndof: int
    normal: np.ndarray
    points: np.ndarray
    weights: np.ndarray
    values: np.ndarray
    norms: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self.norms = np.sqrt(self.weights @ self.values**2)

    @classmethod
    def from_solution(cls, sol, order: int = QUADRATURE_ORDER) -> Reference:
        points, weights = quadrature_points(sol.mesh, order)
        normal = quantity_normal(sol.scene)
        return cls(scene=sol.scene.name, element=sol.element, maxh=float(sol.maxh),
                   nu=float(sol.scene.material.nu), ndof=int(sol.ndof["total"]), normal=normal,
                   points=points, weights=weights, values=sample_quantities(sol, points, normal))

    def denominators(self) -> np.ndarray:
        """The norms the errors are divided by: each quantity's own, or (a zero field,
        see ZERO_FIELD) the largest of its group; 1 where the whole group is zero."""
        den = self.norms.copy()
        for group in (slice(0, 2), slice(2, 4)):
            scale = self.norms[group].max()
            den[group] = np.maximum(den[group], ZERO_FIELD * scale) if scale > 0 else 1.0
        return den

    def errors(self, sol) -> dict[str, float]:
        """err_<q>: relative L2 errors of `sol` against this reference (see the module)."""
        diff = sample_quantities(sol, self.points, self.normal) - self.values
        rel = np.sqrt(self.weights @ diff**2) / self.denominators()
        return {f"err_{q}": float(v) for q, v in zip(QUANTITIES, rel)}

    def save(self, path: Path) -> None:
        """Write to an npz file atomically (a temporary file renamed into place)."""
        atomic_write(path, lambda tmp: np.savez(
            tmp, scene=self.scene, element=self.element, maxh=self.maxh, nu=self.nu, ndof=self.ndof,
            normal=self.normal, points=self.points, weights=self.weights, values=self.values))

    @classmethod
    def load(cls, path: Path) -> Reference:
        with np.load(path) as d:
            return cls(scene=str(d["scene"]), element=str(d["element"]), maxh=float(d["maxh"]), nu=float(d["nu"]),
                       ndof=int(d["ndof"]), normal=d["normal"], points=d["points"], weights=d["weights"],
                       values=d["values"])


def tip_columns(scene) -> tuple[str, ...]:
    """The tip columns of a sweep of `scene`: `K_I[c,end]`, `K_II[c,end]`, `G[c,end]` per interior crack end."""
    from ...planar.tips import tip_labels

    return tuple(f"{q}[{label}]" for label in tip_labels(scene) for q in TIP_QUANTITIES)


def _is_tip_column(name: str) -> bool:
    return any(name.startswith(f"{q}[") and name.endswith("]") for q in TIP_QUANTITIES)


def k_error(sol) -> float:
    """max over the tips of |K_I - K_I exact| / (|p| sqrt(pi a)) where the scene has a closed form (NaN if none).

    griffith: K_I = p sqrt(pi a); inclined: K_I = max(p cos^2(angle), 0) sqrt(pi a)
    (infinite plate: the scenes' finite plates add about 0.6%).
    """
    ex = sol.scene.exact
    if ex is None or ex.get("kind") not in ("griffith", "inclined") or not sol.tips:
        return math.nan
    scale = abs(ex["p"]) * math.sqrt(math.pi * ex["a"])
    if ex["kind"] == "griffith":
        exact = ex["p"] * math.sqrt(math.pi * ex["a"])
    else:
        from ...scenes import inclined_closed_form

        exact = inclined_closed_form(sol.scene)["K_I"]
    return float(max(abs(t.K_I - exact) for t in sol.tips) / scale)


def griffith_opening(scene, x: np.ndarray, y: np.ndarray) -> np.ndarray | None:
    """The closed-form normal opening at points (x, y) of the crack, or None if the scene has none."""
    ex = scene.exact
    if ex is None or ex.get("kind") != "griffith":
        return None
    mat = scene.material
    e_prime = mat.E / (1 - mat.nu**2) if mat.plane == "strain" else mat.E
    c = ex["center"]
    s = np.hypot(np.asarray(x) - c[0], np.asarray(y) - c[1])
    return 4 * ex["p"] / e_prime * np.sqrt(np.maximum(ex["a"] ** 2 - s**2, 0.0))


def opening_error(sol) -> float:
    """Relative L2 error of the first crack's normal jump against the closed form (NaN if none)."""
    if not sol.profiles:
        return math.nan
    prof = sol.profiles[0]
    exact = griffith_opening(sol.scene, prof.x, prof.y)
    if exact is None:
        return math.nan
    L = sol.crack_mesh.cracks[0].length
    return float(math.sqrt(np.sum(L * (prof.normal_jump - exact) ** 2) / np.sum(L * exact**2)))
