"""Sweeps over element, mesh size and Poisson ratio: one tidy row per run, errors, rates.

    df = sweep(scene, elements=["bdm", "peers"], maxh=[0.2, 0.1, 0.05], nu=[0.49],
               reference_maxh=0.025)
    with_rates(df)            # observed rates between consecutive meshes
    fitted_rates(df)          # least-squares rates per (scene, element, nu, friction, quantity)

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
(ngcrack/tips.py) as the columns `K_I[c,end]`, `K_II[c,end]`, `G[c,end]` (c the crack's
index, end "first" or "last"), after ROW_COLUMNS; `time_tips` is their cost (part of
time_total) and `err_K_I`, where the scene has a closed form (griffith, inclined), the
largest |K_I - K_I exact| / (|p| sqrt(pi a)) over the tips (`k_error`).

Rates. With e the error, h the mesh's largest edge length and N = ndof_total:

    rate_h   = log(e_prev / e) / log(h_prev / h)        (e ~ h^rate_h)
    rate_dof = log(e_prev / e) / log(N / N_prev)         (e ~ N^-rate_dof)

In 2D N ~ h^-2, so rate_dof ~ rate_h / 2. The paper's rates (0.81, 0.65, 0.93, 0.78)
are least-squares slopes of log e against log dof: rate_dof in this convention (the
slopes of its Tables 1-4 are 0.82, 0.65, 0.94, 0.85).

Expected rates. The paper proves, in its energy-type norm (stress in L2 plus the
multiplier on the crack), h^(1/2) for PEERS and h^(3/4) for BDM; both come from the
regularity of the solution (u in H^(3/2 - eps) near the crack tips, the stress
singular like r^(-1/2)). For the L2 quantities here: the stress error is bounded by
that norm, and a r^(-1/2) singularity on a quasi-uniform mesh costs exactly h^(1/2) in
L2, so h^(1/2) is the asymptotic floor; the displacement is P0 per triangle, so its L2
error cannot beat h^1. On the meshes of a study (where the smooth part of the error still
dominates) the observed rate_h lie between these: see tests/test_study.py for the bands
and the measured values.

Memory. `memory_peak_mb` is the peak resident set size (VmHWM) of the process that ran
the case during its solve (not the error evaluation), reset at its start (Linux: /proc/self/clear_refs) after freed heap memory is
handed back to the OS (gc, glibc malloc_trim). It is the run's own peak plus what the
process still held at the start, `memory_start_mb` (the interpreter and NGSolve, about
150 MB, plus whatever earlier runs in a long-lived process left behind); their
difference estimates the run's own footprint. Where the reset is unavailable (not
Linux) the peak is the process's peak since it started, an upper bound. Runs sharing a
process (dask threads) share one peak: again an upper bound.

Output. `sweep(..., out="results.csv")` appends one CSV line per finished run (one
`write` of a complete line, then fsync), so an interruption loses at most the runs in
progress; running the same sweep again skips the rows already present (keyed by scene,
element, maxh, nu, friction) and drops a trailing partial line. Reference samples are cached next
to the CSV (`results.csv.refs/`, npz files) so a resumed sweep need not recompute them;
a missing or unreadable cache file is recomputed.
"""

from __future__ import annotations

import csv
import io
import itertools
import math
import os
import sys
import time
import warnings
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

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
#: degree for which the quadrature on the reference mesh's triangles is exact
QUADRATURE_ORDER = 4
#: a reference quantity whose L2 norm is below this fraction of its group's largest
#: (u1, u2 or sigma_t1, sigma_nu) counts as zero: its error is then relative to that largest
ZERO_FIELD = 1e-8
#: columns that identify a row (resume key)
KEY = ("scene", "element", "maxh", "nu", "friction")
#: significant digits used to compare maxh and nu when matching rows
KEY_DIGITS = 12
#: solve options that shape the mesh or the element (what ngcrack.sizing's checks read)
MESH_OPTIONS = ("tip_h", "crack_h", "grading", "order")

#: the row schema: column -> type; the CSV has exactly these columns in this order
ROW_SCHEMA: dict[str, type] = {
    "scene": str,
    "element": str,
    "maxh": float,                # requested global mesh size
    "nu": float,                  # Poisson's ratio
    "friction": float,            # Coulomb coefficient of the cracks (the largest, if they differ)
    "E": float,
    "h": float,                   # the mesh's largest edge length
    "n_elements": int,
    "ndof_total": int,
    "ndof_global": int,           # after static condensation
    "ndof_contact": int,          # crack normal unknowns in the QP
    "n_active": int,              # QP unknowns in contact (w = 0)
    "time_mesh": float,           # seconds, wall clock
    "time_assemble": float,
    "time_linear": float,         # factorization, solves and local recovery
    "time_contact": float,        # Schur complement and QP
    "time_total": float,          # the whole solve, mesh included
    "time_error": float,          # evaluating the errors (not part of the solve)
    "time_tips": float,           # the tips' domain integrals (part of time_total)
    "memory_peak_mb": float,
    "memory_start_mb": float,
    "kkt_max_penetration": float,
    "kkt_max_tension": float,
    "kkt_complementarity": float,
    "kkt_friction": float,        # the discrete Coulomb law's residual (0 without friction)
    "max_opening": float,         # max [u].nu over the crack samples
    "max_slip": float,            # max |[u].t|
    "n_stick": int,               # crack samples that stick (friction only)
    "min_normal_stress": float,   # most compressive sigma_n on the crack
    "reference": bool,            # this row is the reference of its group
    "reference_element": str,
    "reference_maxh": float,
    "reference_ndof": int,
    "err_u1": float,
    "err_u2": float,
    "err_sigma_t1": float,
    "err_sigma_nu": float,
    "err_opening": float,         # against the closed form (griffith); empty elsewhere
    "err_K_I": float,             # K_I against the closed form (griffith, inclined); empty elsewhere
    "crack_model": str,
    "qp_solver": str,
    "adapt": bool,                # an adaptive run: maxh holds its tolerance (the relative estimate)
    "estimate": float,            # the solve's relative error estimate (estimate.py), energy norm
    "estimate_energy": float,     # the same, absolute
}
ROW_COLUMNS = tuple(ROW_SCHEMA)
#: per crack end inside the body, the columns `K_I[c,end]`, `K_II[c,end]`, `G[c,end]`
#: (c the crack's index, end "first" or "last") follow ROW_COLUMNS (see `tip_columns`)
TIP_QUANTITIES = ("K_I", "K_II", "G")
#: columns `with_rates` adds to a sweep's DataFrame
RATE_COLUMNS = tuple(f"rate_{kind}_{q}" for q in RATE_QUANTITIES for kind in ("h", "dof"))
#: columns that must agree between a CSV's rows and a resumed sweep asking for the same keys
_SETUP_COLUMNS = ("reference_element", "reference_maxh", "crack_model", "qp_solver", "adapt")


class SweepError(RuntimeError):
    """A run of a sweep failed; the message names the case."""


# --------------------------------------------------------------------- quantities
def quantity_normal(scene) -> np.ndarray:
    """n: the unit normal of the first crack's first segment, (0, 1) without a crack."""
    if scene.cracks:
        return np.array(scene.cracks[0].normals()[0], dtype=float)
    return np.array([0.0, 1.0])


def quadrature_points(mesh, order: int = QUADRATURE_ORDER) -> tuple[np.ndarray, np.ndarray]:
    """(points (N, 2), weights (N,)) of a rule exact for degree `order` on every triangle."""
    import ngsolve as ngs

    rule = ngs.IntegrationRule(ngs.TRIG, order)
    ref = np.array([p[:2] for p in rule.points])
    wref = np.array(rule.weights)  # sums to 1/2, the reference triangle's area
    # netgen's arrays: the vertices and triangles of NGSolve's mesh, in its order
    verts = np.array(mesh.ngmesh.Coordinates()[:, :2], dtype=float)
    tris = np.asarray(mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3], dtype=int) - 1
    a, b, c = verts[tris[:, 0]], verts[tris[:, 1]], verts[tris[:, 2]]
    pts = a[:, None, :] + ref[None, :, 0, None] * (b - a)[:, None, :] + ref[None, :, 1, None] * (c - a)[:, None, :]
    det = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    return pts.reshape(-1, 2), (det[:, None] * wref[None, :]).ravel()


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
        path = Path(path)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp.npz")
        np.savez(tmp, scene=self.scene, element=self.element, maxh=self.maxh, nu=self.nu, ndof=self.ndof,
                 normal=self.normal, points=self.points, weights=self.weights, values=self.values)
        os.replace(tmp, path)

    @classmethod
    def load(cls, path: Path) -> Reference:
        with np.load(path) as d:
            return cls(scene=str(d["scene"]), element=str(d["element"]), maxh=float(d["maxh"]), nu=float(d["nu"]),
                       ndof=int(d["ndof"]), normal=d["normal"], points=d["points"], weights=d["weights"],
                       values=d["values"])


def tip_columns(scene) -> tuple[str, ...]:
    """The tip columns of a sweep of `scene`: `K_I[c,end]`, `K_II[c,end]`, `G[c,end]` per interior crack end."""
    from .tips import tip_labels

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
        from .scenes import inclined_closed_form

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


# ------------------------------------------------------------ the paper's way of measuring
def element_means(nr: np.ndarray, weights: np.ndarray, values: np.ndarray, n_elements: int):
    """(areas, means): the L2 projection onto P0 of sampled fields, per coarse element.

    nr: the coarse element holding each sample point (its quadrature rule's points on a
    finer mesh), weights: their quadrature weights, values (N, k). The mean over element T
    is sum_{p in T} w_p v_p / |T|, |T| = sum_{p in T} w_p (exact for the finer mesh's
    piecewise fields up to the non-nestedness of the meshes).
    """
    area = np.bincount(nr, weights=weights, minlength=n_elements)
    sums = np.column_stack([np.bincount(nr, weights=weights * values[:, k], minlength=n_elements)
                            for k in range(values.shape[1])])
    return area, sums / np.where(area > 0, area, 1.0)[:, None]


def mean_errors(sol, fine: Reference) -> dict[str, float]:
    """err_<q>: relative L2 errors of the element means of `sol` against the element means
    of `fine` (both projected onto the triangles of `sol`'s mesh): || P0 q_h - P0 q_fine ||
    / || P0 q_fine ||, with the denominators of `Reference.denominators` (zero fields)."""
    mp = sol.mesh(fine.points[:, 0], fine.points[:, 1])
    nr = np.asarray(mp)["nr"].astype(int)
    if np.any(nr < 0):
        raise ValueError(f"{int(np.sum(nr < 0))} reference points lie outside the mesh of {sol.scene.name!r}")
    mine = sample_quantities(sol, fine.points, fine.normal)
    n = sol.mesh.ne
    area, m_h = element_means(nr, fine.weights, mine, n)
    _, m_f = element_means(nr, fine.weights, fine.values, n)
    den = np.sqrt(area @ m_f**2)
    group = [max(den[:2].max(), 1e-300)] * 2 + [max(den[2:].max(), 1e-300)] * 2
    den = np.maximum(den, ZERO_FIELD * np.array(group))
    rel = np.sqrt(area @ (m_h - m_f) ** 2) / den
    return {f"err_{q}": float(v) for q, v in zip(QUANTITIES, rel)}


def comparison_errors(scene, element: str, maxh: Sequence[float], reference_maxh: float, nu: float | None = None,
                      **solve_options):
    """One row per mesh: three ways of measuring the same solution's error.

    - `true_<q>`: the relative L2 error against the reference at `reference_maxh` (the
      sweep's err_<q>: pointwise, at the reference mesh's quadrature points);
    - `means_<q>`: element means against element means of that reference (both projected
      onto this mesh's triangles, `mean_errors`);
    - `next_<q>`: element means against element means of the next finer mesh of `maxh`
      (the finest against the reference): the paper's way, whose reference is a mesh only
      somewhat finer, sharing most of the discretization error.
    A mesh the element is refused on (sizing.check_thin_parts) gives no row; `coarse` marks
    the rows that warned (CoarseMeshWarning). Columns also: element, maxh, triangles, h, ndof.
    """
    import warnings

    import pandas as pd

    from .scenes import resolve
    from .sizing import CoarseMeshWarning, check_thin_parts
    from .solve import solve

    if isinstance(scene, (str, Path)):
        scene = resolve(scene)
    if nu is not None:
        scene = scene.with_(nu=nu)
    sizes = sorted(set(_check_sizes(_as_list(maxh, "maxh"), "maxh")), reverse=True)
    reference = Reference.from_solution(solve(scene, element=element, maxh=reference_maxh, **solve_options))
    rows, prev = [], None
    for h in sizes + [None]:
        sol, coarse = None, False
        if h is not None:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", CoarseMeshWarning)
                try:
                    check_thin_parts(scene, element, h, **{k: solve_options.get(k) for k in MESH_OPTIONS})
                    refused = False
                except ValueError:
                    refused = True  # too coarse for this element: no row
                if not refused:
                    sol = solve(scene, element=element, maxh=h, **solve_options)
            coarse = any(issubclass(w.category, CoarseMeshWarning) for w in caught)
        fine = Reference.from_solution(sol) if sol is not None else reference
        if prev is not None:
            psol, prow = prev
            prow.update({k.replace("err_", "next_"): v for k, v in mean_errors(psol, fine).items()})
            rows.append(prow)
        if sol is not None:
            hmax, ne = _mesh_stats(sol)
            row = {"scene": scene.name, "element": element, "maxh": h, "triangles": ne, "h": hmax,
                   "ndof": int(sol.ndof["total"]), "coarse": coarse}
            row.update({k.replace("err_", "true_"): v for k, v in reference.errors(sol).items()})
            row.update({k.replace("err_", "means_"): v for k, v in mean_errors(sol, reference).items()})
            prev = (sol, row)
    cols = ["scene", "element", "maxh", "triangles", "h", "ndof", "coarse"] + [
        f"{kind}_{q}" for kind in ("true", "means", "next") for q in QUANTITIES]
    return pd.DataFrame(rows, columns=cols)


# ------------------------------------------------------------------------- memory
def _release_memory() -> None:
    """Collect garbage and hand freed heap memory back to the OS (glibc malloc_trim)."""
    import ctypes
    import gc

    gc.collect()
    try:
        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        pass


def _reset_peak_memory() -> None:
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")  # resets VmHWM to the current RSS
    except OSError:
        pass


def _memory_mb() -> tuple[float, float]:
    """(current RSS, peak RSS) of this process in MB."""
    try:
        vals = {}
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith(("VmRSS:", "VmHWM:")):
                    vals[line[:5]] = float(line.split()[1]) / 1024
        return vals["VmRSS"], vals["VmHWM"]
    except (OSError, KeyError):
        import resource  # not on Windows; there the peak is unknown

        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        peak = peak / 2**20 if sys.platform == "darwin" else peak / 1024
        return math.nan, peak


# -------------------------------------------------------------------------- cases
@dataclass
class Case:
    """One run of a sweep: what to solve, against which reference, what to return."""

    scene: Any                   # a Scene (picklable)
    element: str
    maxh: float
    nu: float
    solve_options: dict
    reference: Reference | None = None
    make_reference: bool = False  # also return this run's Reference
    is_reference: bool = False    # this run's row is its group's reference row
    row: bool = True              # return a row (False: a separate reference run)
    setup: dict = field(default_factory=dict)
    friction: float | None = None  # None: the scene's own coefficients
    adapt_maxh: float | None = None  # adaptive run from this mesh size; maxh is then the tolerance

    @property
    def cost(self) -> float:
        """Estimated relative cost: the number of triangles, ~ maxh^-2."""
        return 1.0 / self.maxh**2

    def describe(self) -> str:
        what = "reference " if not self.row else ""
        mu = "" if self.friction is None else f" friction={self.friction:g}"
        return f"{what}run scene={self.scene.name!r} element={self.element!r} maxh={self.maxh:g} nu={self.nu:g}{mu}"


def _mesh_stats(sol) -> tuple[float, int]:
    """(h = the largest edge length, number of triangles) of the solution's mesh."""
    cm = sol.crack_mesh
    verts, tris = cm.points, cm.triangles
    corners = verts[tris]
    sides = corners - np.roll(corners, 1, axis=1)
    return float(np.linalg.norm(sides, axis=2).max()), int(len(tris))


def run_case(case: Case) -> tuple[dict | None, Reference | None]:
    """Solve one case: (its row or None, its Reference or None). Runs in any process."""
    from .geometry import reuse_meshes
    from .solve import solve

    _release_memory()
    _reset_peak_memory()
    mem_start, _ = _memory_mb()
    scene = case.scene.with_(nu=case.nu) if case.friction is None else case.scene.with_(nu=case.nu, friction=case.friction)
    if case.adapt_maxh is not None:  # refines its own meshes: none is shared
        with warnings.catch_warnings():  # a budget reached is recorded in the row (estimate > maxh)
            warnings.simplefilter("ignore", UserWarning)
            sol = solve(scene, element=case.element, maxh=case.adapt_maxh, adapt=case.maxh, **case.solve_options)
    else:
        with reuse_meshes():  # the elements and Poisson ratios of a sweep share each size's mesh
            sol = solve(scene, element=case.element, maxh=case.maxh, **case.solve_options)
    _, mem_peak = _memory_mb()  # the solve's peak, before the error evaluation adds its own
    t0 = time.perf_counter()
    ref = Reference.from_solution(sol) if case.make_reference else None
    row = None
    if case.row:
        h, ne = _mesh_stats(sol)
        errors = {f"err_{q}": math.nan for q in QUANTITIES}
        if case.reference is not None and not case.is_reference:
            errors = case.reference.errors(sol)
        errors["err_opening"] = opening_error(sol)
        errors["err_K_I"] = k_error(sol)
        t_err = time.perf_counter() - t0
        prof = sol.profiles
        t = sol.timings
        row = {
            "scene": scene.name, "element": case.element, "maxh": float(case.maxh), "nu": float(case.nu),
            "friction": scene_friction(scene),
            "E": float(scene.material.E), "h": h, "n_elements": ne,
            "ndof_total": int(sol.ndof["total"]), "ndof_global": int(sol.ndof["global"]),
            "ndof_contact": int(sol.ndof["contact"]),
            "n_active": int(len(sol.qp.active)) if sol.qp is not None else 0,
            "time_mesh": t["mesh"], "time_assemble": t["assemble"], "time_linear": t["linear"],
            "time_contact": t["contact"], "time_total": t.get("adapt_total", t["total"]), "time_error": t_err,
            "time_tips": t.get("tips", 0.0),
            "memory_peak_mb": mem_peak, "memory_start_mb": mem_start,
            "kkt_max_penetration": sol.kkt["max_penetration"], "kkt_max_tension": sol.kkt["max_tension"],
            "kkt_complementarity": sol.kkt["complementarity"], "kkt_friction": sol.kkt.get("friction", 0.0),
            "max_opening": max((float(p.normal_jump.max()) for p in prof), default=math.nan),
            "max_slip": max((float(np.abs(p.tangential_jump).max()) for p in prof), default=math.nan),
            "n_stick": int(sum(np.count_nonzero(p.state == "stick") for p in prof)),
            "min_normal_stress": min((float(p.normal_stress.min()) for p in prof), default=math.nan),
            "reference": bool(case.is_reference), "reference_ndof": -1,
            **case.setup,
            **errors,
            "estimate": sol.error_estimate.relative if sol.error_estimate is not None else math.nan,
            "estimate_energy": sol.error_estimate.energy if sol.error_estimate is not None else math.nan,
        }
        if case.is_reference:
            row["reference_ndof"] = int(sol.ndof["total"])
        elif case.reference is not None:
            row["reference_ndof"] = case.reference.ndof
        row = {k: row[k] for k in ROW_COLUMNS}
        row.update({f"{q}[{tip.label}]": float(getattr(tip, q)) for tip in sol.tips for q in TIP_QUANTITIES})
    return row, ref


# ---------------------------------------------------------------------- CSV file
def _key(scene: str, element: str, maxh: float, nu: float, friction: float = 0.0) -> tuple:
    return (str(scene), str(element), float(f"{float(maxh):.{KEY_DIGITS}g}"), float(f"{float(nu):.{KEY_DIGITS}g}"),
            float(f"{float(friction):.{KEY_DIGITS}g}"))


def scene_friction(scene) -> float:
    """The scene's Coulomb coefficient for the `friction` column: its cracks' largest (0 without a crack)."""
    return max((float(c.friction) for c in scene.cracks), default=0.0)


def _format(value) -> str:
    if isinstance(value, (bool, np.bool_)):
        return "True" if value else "False"
    if isinstance(value, (float, np.floating)):
        return "" if not math.isfinite(value) else repr(float(value))
    return str(value)


def csv_line(row: dict, columns: Sequence[str] = ROW_COLUMNS) -> str:
    """One complete CSV line (with its newline) of a row, in the order of `columns` (missing: empty)."""
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([_format(row.get(c, math.nan)) for c in columns])
    return buf.getvalue()


def typed(df):
    """`df` with the ROW_SCHEMA dtypes (str, float, int, bool) on the columns it has."""
    import pandas as pd

    df = df.copy()
    schema = dict(ROW_SCHEMA, **{c: float for c in df.columns if _is_tip_column(str(c))})
    for col, typ in schema.items():
        if col not in df.columns:
            continue
        if typ is float:
            df[col] = pd.to_numeric(df[col], errors="coerce").astype(float)
        elif typ is int:
            df[col] = pd.to_numeric(df[col]).astype("int64")
        elif typ is bool:
            df[col] = df[col].map(lambda v: v if isinstance(v, (bool, np.bool_)) else str(v) == "True").astype(bool)
        else:
            df[col] = df[col].fillna("").astype(str)
    return df


def read_results(path):
    """A sweep CSV as a typed pandas DataFrame (ignoring a trailing partial line)."""
    import pandas as pd

    path = Path(path)
    text = path.read_text()
    if text and not text.endswith("\n"):
        text = text[: text.rfind("\n") + 1]
    if not text:
        return typed(pd.DataFrame(columns=list(ROW_COLUMNS)))
    # floats must read back exactly (resume keys, reproducible tables): pandas >= 3 parses
    # round-trip by default, older versions need asking
    exact = {} if int(pd.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}
    df = pd.read_csv(io.StringIO(text), **exact,
                     dtype={"scene": str, "element": str, "reference_element": str, "crack_model": str,
                            "qp_solver": str})
    n = len(ROW_COLUMNS)
    if tuple(df.columns[:n]) != ROW_COLUMNS or not all(_is_tip_column(str(c)) for c in df.columns[n:]):
        raise ValueError(f"out = {str(path)!r}: its columns are not those of a sweep of this version "
                         f"(expected {', '.join(ROW_COLUMNS)} and the tip columns); write to another file")
    return typed(df)


class ResultsFile:
    """The sweep's CSV: header once, then one complete line per finished run."""

    def __init__(self, path, columns: Sequence[str] = ROW_COLUMNS) -> None:
        self.path = Path(path)
        self.columns = tuple(columns)
        if not self.path.parent.exists():
            raise ValueError(f"out = {str(self.path)!r}: the directory {str(self.path.parent)!r} does not exist")
        if self.path.exists() and self.path.stat().st_size:
            data = self.path.read_bytes()
            if not data.endswith(b"\n"):  # a line cut by an interruption: drop it
                keep = data.rfind(b"\n") + 1
                warnings.warn(f"{self.path}: dropped a partial last line ({len(data) - keep} bytes) left by an "
                              f"interrupted run", stacklevel=3)
                with open(self.path, "r+b") as fh:
                    fh.truncate(keep)
            self.existing = read_results(self.path)
            if tuple(self.existing.columns) != self.columns:
                raise ValueError(f"out = {str(self.path)!r}: its columns are not this sweep's (another scene's "
                                 f"tips?); write to another file")
        else:
            self.existing = None
            buf = io.StringIO()  # tip columns hold a comma (K_I[0,last]): quoted
            csv.writer(buf, lineterminator="\n").writerow(self.columns)
            self._append(buf.getvalue())

    def _append(self, text: str) -> None:
        fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            data = text.encode()
            written = os.write(fd, data)  # one write of the whole line
            while written < len(data):  # only on exotic file systems
                written += os.write(fd, data[written:])
            os.fsync(fd)
        finally:
            os.close(fd)

    def append(self, row: dict) -> None:
        self._append(csv_line(row, self.columns))


# ---------------------------------------------------------------------- executors
class _Serial:
    """Runs each case in this process when it is submitted."""

    capacity = 1

    def submit(self, fn, *args):
        fut: Future = Future()
        try:
            fut.set_result(fn(*args))
        except BaseException as exc:  # noqa: BLE001 -- handed back through the future
            if isinstance(exc, KeyboardInterrupt):
                raise
            fut.set_exception(exc)
        return fut

    def wait(self, futures):
        return wait(futures, return_when=FIRST_COMPLETED)

    def prepare(self, ref):
        return ref

    def close(self, cancel: bool = False):
        pass


def _limit_threads(threads: int) -> None:
    """Worker start: at most `threads` threads for libraries loaded later (MKL PARDISO)."""
    for var in ("MKL_NUM_THREADS", "OMP_NUM_THREADS"):
        os.environ.setdefault(var, str(threads))


class _Processes(_Serial):
    """A pool of `jobs` worker processes (spawned: a clean NGSolve in each).

    Each worker's threaded libraries get cpu_count // jobs threads, so that the
    workers do not oversubscribe the cores.
    """

    def __init__(self, jobs: int) -> None:
        import multiprocessing

        self.capacity = jobs
        threads = max(1, (os.cpu_count() or 1) // jobs)
        self.pool = ProcessPoolExecutor(max_workers=jobs, mp_context=multiprocessing.get_context("spawn"),
                                        initializer=_limit_threads, initargs=(threads,))

    def submit(self, fn, *args):
        return self.pool.submit(fn, *args)

    def close(self, cancel: bool = False):
        self.pool.shutdown(wait=True, cancel_futures=cancel)


#: how long to wait for a dask scheduler before giving up
DASK_CONNECT_TIMEOUT = "15s"


class _Dask(_Serial):
    """A dask.distributed cluster: a scheduler address or an existing Client."""

    def __init__(self, address) -> None:
        try:
            import distributed
        except ImportError:
            raise ValueError("dask: the dask.distributed package is not installed (pip install 'dask[distributed]')") from None
        self._distributed = distributed
        if isinstance(address, distributed.Client):
            self.client, self._own = address, False
        else:
            try:
                self.client, self._own = distributed.Client(address, timeout=DASK_CONNECT_TIMEOUT), True
            except (OSError, TimeoutError, ValueError) as exc:
                raise ValueError(f"dask = {address!r}: cannot connect to a scheduler there ({exc})") from None
        self.capacity = max(1, sum(self.client.nthreads().values()))

    def submit(self, fn, *args):
        return self.client.submit(fn, *args, pure=False)

    def wait(self, futures):
        done = self._distributed.wait(list(futures), return_when="FIRST_COMPLETED")
        return done.done, done.not_done

    def prepare(self, ref):
        return self.client.scatter(ref, hash=False) if ref is not None else None

    def close(self, cancel: bool = False):
        if self._own:
            self.client.close()


def _executor(jobs: int, dask):
    if dask is not None:
        return _Dask(dask)
    return _Processes(jobs) if jobs > 1 else _Serial()


# -------------------------------------------------------------------------- sweep
def _as_list(values, name: str) -> list:
    if values is None:
        return []
    if isinstance(values, (str, int, float)):
        values = [values]
    values = list(values)
    if not values:
        raise ValueError(f"{name}: give at least one value")
    return values


def _check_sizes(values: Sequence, name: str) -> list[float]:
    out = []
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} = {v!r}: must be a finite number > 0")
        out.append(float(v))
    return out


def sweep(
    scene,
    elements: Iterable[str] | str = ("bdm",),
    maxh: Iterable[float] | float = (0.2, 0.1, 0.05),
    nu: Iterable[float] | float | None = None,
    *,
    friction: Iterable[float] | float | None = None,
    reference_maxh: float | None = None,
    reference_element: str | None = None,
    out=None,
    jobs: int = 1,
    dask=None,
    progress: bool = False,
    solve_options: dict | None = None,
    max_dof: int | None = None,
    adapt: Iterable[float] | float | None = None,
    adapt_maxh: float | None = None,
):
    """Run every (element, maxh, nu, friction) of `scene`; one row per run as a pandas DataFrame.

    adapt: relative error tolerances in (0, 1) instead of mesh sizes: each run refines
    adaptively (solve(..., adapt=tol), from the mesh size adapt_maxh, default the
    scene's) and its row holds the tolerance in the maxh column, adapt = True, and the
    whole adaptive loop's wall time in time_total (max_dof is then the budget of each run).
    The reference is then the finest tolerance's run or a fixed mesh at reference_maxh.

    scene: a Scene, a built-in scene name or a TOML path. elements: element families
    (default: bdm alone, as in `solve`). nu: Poisson ratios (default:
    the scene's). friction: Coulomb coefficients, each set on every crack (default: the
    scene's own; the `friction` column holds the cracks' largest). reference_maxh: the reference mesh size (default: the finest maxh,
    whose row is then the reference); reference_element: measure every element against
    this one's reference (default: each against its own). out: a CSV path, written row
    by row and resumed (see the module docstring). jobs: worker processes (spawned: a
    script calling this with jobs > 1 needs the usual `if __name__ == "__main__":`
    guard); dask: a scheduler address or a distributed.Client (then jobs is ignored).
    progress: a tqdm bar with ETA on stderr. solve_options go to `solve` unchanged
    (tip_h, crack_h, grading, qp_solver, crack_model, ...). max_dof: as in `solve`; every
    case (and reference) is checked against it (ngcrack.sizing) before any run starts.

    Returns the rows of this grid (from the CSV where already there), ordered by
    element, nu and decreasing maxh, with ROW_COLUMNS and the rate columns of `with_rates`.
    """
    import pandas as pd

    from .scenes import resolve

    if isinstance(scene, (str, Path)):
        scene = resolve(scene)
    if max_dof is not None:
        from .sizing import check_max_dof

        check_max_dof(max_dof)
        solve_options = {**(solve_options or {}), "max_dof": int(max_dof)}
    grid = _Grid.checked(scene, elements, maxh if adapt is None else adapt, nu, reference_maxh, reference_element,
                         jobs, solve_options, friction,
                         adapt_maxh=(adapt_maxh or scene.maxh or 0.0) if adapt is not None else None)
    grid.check_sizes()
    # connect to a cluster before anything is written: a wrong address leaves no file
    executor = _Dask(dask) if dask is not None else None
    bar = None
    try:
        columns = ROW_COLUMNS + tip_columns(scene)
        results = ResultsFile(out, columns) if out is not None else None
        done: dict[tuple, dict] = {}
        if results is not None and results.existing is not None:
            for rec in results.existing.to_dict("records"):
                done.setdefault(_key(rec["scene"], rec["element"], rec["maxh"], rec["nu"], rec["friction"]), rec)
        grid.check_setup(done, out)
        plan = _Plan(grid, done, Path(str(out) + ".refs") if out is not None else None)
        if progress and plan.n_runs:
            from tqdm import tqdm

            # progress counts estimated work (triangles), so the ETA weighs fine meshes right
            bar = tqdm(total=plan.total_cost, file=sys.stderr, dynamic_ncols=True,
                       bar_format="{desc} {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]")
            bar.set_description_str(f"sweep {scene.name}: 0/{plan.n_runs} runs")
        if executor is None and plan.n_runs:
            executor = _executor(jobs, None)
        new_rows = plan.execute(executor, results, bar)
    except BaseException:
        if executor is not None:
            executor.close(cancel=True)
            executor = None
        raise
    finally:
        if bar is not None:
            bar.close()
        if executor is not None:
            executor.close()

    rows = [done[k] for k in grid.keys() if k in done]
    df = typed(pd.DataFrame(rows + new_rows, columns=list(columns)))
    order = {el: i for i, el in enumerate(grid.elements)}
    df = df.assign(_o=df["element"].map(order)).sort_values(["_o", "nu", "friction", "maxh"],
                                                                ascending=[True, True, True, False])
    return with_rates(df.drop(columns="_o").reset_index(drop=True))


@dataclass
class _Grid:
    """A checked sweep request: what to run and against which reference."""

    scene: Any
    elements: list[str]
    sizes: list[float]       # decreasing
    nus: list[float]
    frictions: list[float | None]  # [None]: the scene's own coefficients
    ref_h: float
    separate: bool           # the reference is a run of its own, not the finest row
    reference_element: str | None
    solve_options: dict
    setup: dict              # the _SETUP_COLUMNS values of every row
    adapt_maxh: float | None = None  # adaptive runs (sizes are tolerances) from this mesh size

    @classmethod
    def checked(cls, scene, elements, maxh, nu, reference_maxh, reference_element, jobs, solve_options,
                friction=None, adapt_maxh: float | None = None) -> _Grid:
        from . import elements as _elements

        elements = _as_list(elements, "elements")
        for el in elements + ([reference_element] if reference_element is not None else []):
            if el not in _elements.ELEMENTS:
                raise ValueError(f"element = {el!r}: allowed values are {', '.join(_elements.ELEMENTS)}")
        sizes = sorted(set(_check_sizes(_as_list(maxh, "maxh" if adapt_maxh is None else "adapt"),
                                        "maxh" if adapt_maxh is None else "adapt")), reverse=True)
        nus = [float(v) for v in _as_list(nu, "nu")] if nu is not None else [float(scene.material.nu)]
        for v in nus:
            scene.with_(nu=v)  # validates (a SceneError names the field)
        frictions: list = [None]
        if friction is not None:
            values = _as_list(friction, "friction")
            for f in values:
                scene.with_(friction=f)  # validates (a SceneError names the field)
            frictions = list(dict.fromkeys(float(f) for f in values))
        for k in ("maxh", "element", "scene", "adapt"):
            if k in (solve_options or {}):
                raise ValueError(f"solve_options: {k!r} is set by the sweep itself")
        from .options import SolveOptions

        try:  # every solve option checked once, before any run starts
            options = SolveOptions.of(**(solve_options or {}))
        except TypeError as exc:
            raise ValueError(f"solve_options: {exc}") from None
        for f in frictions:  # every run's friction options
            options.check_for(scene if f is None else scene.with_(friction=f))
        if adapt_maxh is not None:  # every run's adaptivity options
            from .adapt import check_adapt_options

            for tol, el, v in itertools.product(sizes, elements, nus):
                check_adapt_options(options.replace(element=el, adapt=tol), scene.with_(nu=v))
            if not adapt_maxh or adapt_maxh <= 0:
                raise ValueError("adapt_maxh: the first mesh size of adaptive runs is missing (the scene has no maxh)")
        if reference_maxh is not None:
            (reference_maxh,) = _check_sizes([reference_maxh], "reference_maxh")
            if adapt_maxh is None and reference_maxh > sizes[-1] * (1 + 1e-12):
                raise ValueError(f"reference_maxh = {reference_maxh:g}: must be at most the finest maxh ({sizes[-1]:g})")
        if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
            raise ValueError(f"jobs = {jobs!r}: must be an integer >= 1")
        solve_options = dict(solve_options or {})
        ref_h = reference_maxh if reference_maxh is not None else sizes[-1]
        setup = {"reference_element": reference_element or "", "reference_maxh": ref_h,
                 "crack_model": options.crack_model, "qp_solver": options.qp_solver,
                 "adapt": adapt_maxh is not None}
        separate = not _same(ref_h, sizes[-1]) or (adapt_maxh is not None and reference_maxh is not None)
        return cls(scene=scene, elements=list(dict.fromkeys(elements)), sizes=sizes, nus=list(dict.fromkeys(nus)),
                   frictions=frictions,
                   ref_h=ref_h, separate=separate, reference_element=reference_element,
                   solve_options=solve_options, setup=setup, adapt_maxh=adapt_maxh)

    def check_sizes(self) -> None:
        """The size guard and the thin-part check of `solve` (ngcrack.sizing) for every run, before any starts."""
        from .sizing import CoarseMeshWarning, check_request

        opts = {k: self.solve_options.get(k) for k in MESH_OPTIONS + ("max_dof",)}
        # adaptive rows start from adapt_maxh (their sizes are tolerances); a reference
        # that is one of them needs no check of its own
        runs = {(el, h if self.adapt_maxh is None else self.adapt_maxh) for el in self.elements for h in self.sizes}
        refs = set()
        if self.adapt_maxh is None:
            runs |= {(self.ref_element(el), self.ref_h) for el in self.elements}
        elif self.separate:  # a fixed-mesh reference: the adaptive budget does not apply to it
            refs = {(self.ref_element(el), self.ref_h) for el in self.elements}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", CoarseMeshWarning)  # the run itself warns
            for el, h in sorted(runs):
                check_request(self.scene, el, h, what=f"sweep of {self.scene.name!r}, element {el!r}", **opts)
            for el, h in sorted(refs):
                check_request(self.scene, el, h, what=f"sweep of {self.scene.name!r}, reference {el!r}",
                              **dict(opts, max_dof=None))

    def cases(self) -> list[tuple[str, float, tuple]]:
        """(element, maxh, (nu, friction)) of every run; friction None: the scene's own."""
        return [(el, h, (v, f)) for el, v, f, h in itertools.product(self.elements, self.nus, self.frictions, self.sizes)]

    def friction_value(self, f: float | None) -> float:
        return scene_friction(self.scene) if f is None else float(f)

    def keys(self) -> list[tuple]:
        return [_key(self.scene.name, el, h, v, self.friction_value(f)) for el, h, (v, f) in self.cases()]

    def ref_element(self, element: str) -> str:
        return self.reference_element or element

    def is_reference_row(self, element: str, h: float) -> bool:
        return not self.separate and self.ref_element(element) == element and _same(h, self.ref_h)

    def check_setup(self, done: dict, out) -> None:
        """Refuse to mix rows of another setup (reference, crack model, QP solver) into one file."""
        for key in self.keys():
            rec = done.get(key)
            for col in _SETUP_COLUMNS if rec is not None else ():
                want, have = self.setup[col], rec[col]
                same = math.isclose(have, want, rel_tol=1e-9) if isinstance(want, float) else str(have) == str(want)
                if not same:
                    raise ValueError(f"out = {str(out)!r} holds a row for element={key[1]!r} maxh={key[2]:g} "
                                     f"nu={key[3]:g} friction={key[4]:g} computed with {col} = {have!r}, this sweep asks for {want!r}: "
                                     f"write to another file")

    def ref_file(self, ref_dir: Path, element: str, variant: tuple) -> Path:
        nu, f = variant
        mu = "" if f is None else f"-mu{float(f):.{KEY_DIGITS}g}"
        return ref_dir / f"{self.scene.name}-{element}-nu{nu:.{KEY_DIGITS}g}{mu}-h{self.ref_h:.{KEY_DIGITS}g}.npz"

    def case(self, element: str, h: float, variant: tuple, **kw) -> Case:
        nu, f = variant
        # adaptive grids: the rows (and a reference that is a row) adapt; a separate reference
        # is a fixed mesh, to which the budget max_dof of the adaptive runs does not apply
        adaptive = self.adapt_maxh is not None and (kw.get("row", True) or not self.separate)
        fixed_ref = self.adapt_maxh is not None and not adaptive
        options = {k: v for k, v in self.solve_options.items() if k != "max_dof"} if fixed_ref else self.solve_options
        return Case(self.scene, element, h, nu, options, setup=dict(self.setup), friction=f,
                    adapt_maxh=self.adapt_maxh if adaptive else None, **kw)


def _same(a: float, b: float) -> bool:
    return _key("", "", a, 0)[2] == _key("", "", b, 0)[2]


class _Plan:
    """The runs a sweep still needs: references first, then each group's rows as its reference is ready."""

    def __init__(self, grid: _Grid, done: dict, ref_dir: Path | None) -> None:
        self.grid, self.ref_dir = grid, ref_dir
        todo = [(el, h, v) for el, h, v in grid.cases()
                if _key(grid.scene.name, el, h, v[0], grid.friction_value(v[1])) not in done]
        needed = sorted({(grid.ref_element(el), v) for el, h, v in todo}, key=lambda k: (k[0], k[1][0], grid.friction_value(k[1][1])))
        self.refs: dict[tuple, Reference] = {}
        self.ref_cases: list[Case] = []
        for rel, v in needed:
            cached = self._cached(rel, v)
            if cached is not None:
                self.refs[(rel, v)] = cached
                continue
            row_too = (rel, grid.ref_h, v) in todo and grid.is_reference_row(rel, grid.ref_h)
            self.ref_cases.append(grid.case(rel, grid.ref_h, v, make_reference=True, is_reference=row_too,
                                            row=row_too))
        written_by_ref = {(c.element, (c.nu, c.friction)) for c in self.ref_cases if c.row}
        self.pending: dict[tuple, list[Case]] = {key: [] for key in needed}
        for el, h, v in todo:
            if (el, v) in written_by_ref and grid.is_reference_row(el, h):
                continue  # the reference run writes this row itself
            self.pending[(grid.ref_element(el), v)].append(grid.case(el, h, v, is_reference=grid.is_reference_row(el, h)))
        all_cases = self.ref_cases + [c for cs in self.pending.values() for c in cs]
        self.n_runs = len(all_cases)
        self.total_cost = sum(c.cost for c in all_cases)

    def _cached(self, element: str, variant: tuple) -> Reference | None:
        if self.ref_dir is None:
            return None
        nu = variant[0]
        path = self.grid.ref_file(self.ref_dir, element, variant)
        if not path.exists():
            return None
        try:
            r = Reference.load(path)
        except (OSError, ValueError, KeyError) as exc:
            warnings.warn(f"{path}: unreadable reference cache ({exc}); recomputing it", stacklevel=4)
            return None
        ok = (r.scene, r.element) == (self.grid.scene.name, element) and _same(r.maxh, self.grid.ref_h) \
            and _same(r.nu, nu)
        return r if ok else None

    def _release(self, key: tuple, ready: list[Case]) -> None:
        for c in self.pending.pop(key, []):
            c.reference = self.refs[key]
            ready.append(c)

    def execute(self, executor, results: ResultsFile | None, bar) -> list[dict]:
        """Run everything on `executor`; append each row to `results` as it finishes."""
        ready = list(self.ref_cases)
        for key in list(self.pending):
            if key in self.refs:
                self._release(key, ready)
        rows: list[dict] = []
        running: dict = {}
        scattered: dict = {}
        finished = 0
        while ready or running:
            ready.sort(key=lambda c: (not c.make_reference, -c.cost))  # references, then the largest first
            while ready and len(running) < executor.capacity:
                c = ready.pop(0)
                if isinstance(executor, _Dask) and c.reference is not None:
                    rk = id(c.reference)
                    if rk not in scattered:
                        scattered[rk] = executor.prepare(c.reference)
                    running[executor.submit(_run_with_reference, _without_reference(c), scattered[rk])] = c
                else:
                    running[executor.submit(run_case, c)] = c
            finished_now, _ = executor.wait(list(running))
            for fut in finished_now:
                c = running.pop(fut)
                try:
                    row, ref = fut.result()
                except Exception as exc:
                    raise SweepError(f"{c.describe()} failed: {type(exc).__name__}: {exc}") from exc
                if ref is not None:
                    variant = (c.nu, c.friction)
                    self.refs[(c.element, variant)] = ref
                    if self.ref_dir is not None:
                        self.ref_dir.mkdir(exist_ok=True)
                        ref.save(self.grid.ref_file(self.ref_dir, c.element, variant))
                    self._release((c.element, variant), ready)
                if row is not None:
                    if results is not None:
                        results.append(row)
                    rows.append(row)
                finished += 1
                if bar is not None:
                    bar.update(c.cost)
                    bar.set_description_str(f"sweep {self.grid.scene.name}: {finished}/{self.n_runs} runs",
                                            refresh=False)
        return rows


def _without_reference(case: Case) -> Case:
    from dataclasses import replace

    return replace(case, reference=None)


def _run_with_reference(case: Case, reference: Reference):
    """run_case with the reference passed separately (dask resolves a scattered future)."""
    case.reference = reference
    return run_case(case)


# -------------------------------------------------------------------------- rates
def _groups(df):
    cols = [c for c in ("scene", "element", "nu", "friction") if c in df.columns]
    return df.groupby(cols, sort=False, dropna=False)


def _adaptive(g) -> bool:
    """Whether a group's rows are adaptive runs (their maxh column holds tolerances)."""
    return "adapt" in g.columns and bool(g["adapt"].fillna(False).astype(bool).any())


def with_rates(df):
    """`df` plus rate_h_<q> and rate_dof_<q> between consecutive meshes of each (scene, element, nu).

    Rows are taken in order of decreasing h (adaptive rows: of increasing unknowns, and
    no rate in h, since adaptive refinement leaves the largest edge where it is); rows
    without a finite positive error (the reference) are skipped, and the first row of
    each group has no rate (NaN). Groups are (scene, element, nu, friction).
    """
    df = df.copy()
    for col in RATE_COLUMNS:
        df[col] = np.nan
    if df.empty:
        return df
    for _, g in _groups(df):
        adaptive = _adaptive(g)
        g = g.sort_values("ndof_total", kind="stable") if adaptive else g.sort_values("h", ascending=False, kind="stable")
        for q in RATE_QUANTITIES:
            e = g[f"err_{q}"].to_numpy(dtype=float)
            ok = np.isfinite(e) & (e > 0)
            idx = g.index[ok]
            e, h, n = e[ok], g["h"].to_numpy(float)[ok], g["ndof_total"].to_numpy(float)[ok]
            if len(e) < 2:
                continue
            de = np.log(e[:-1] / e[1:])
            with np.errstate(divide="ignore", invalid="ignore"):
                df.loc[idx[1:], f"rate_h_{q}"] = np.nan if adaptive else de / np.log(h[:-1] / h[1:])
                df.loc[idx[1:], f"rate_dof_{q}"] = de / np.log(n[1:] / n[:-1])
    return df


def fitted_rates(df, quantities: Sequence[str] = RATE_QUANTITIES):
    """Least-squares rates per (scene, element, nu, quantity): slopes of log e against log h and log dof.

    Columns: scene, element, nu, quantity, rate_h, rate_dof, points (rows used), h_min,
    ndof_max. Rows without a finite positive error are left out; a quantity with fewer
    than two such rows gives no line. Adaptive groups have no rate in h (NaN).
    """
    import pandas as pd

    out = []
    for keys, g in _groups(df):
        keys = dict(zip([c for c in ("scene", "element", "nu", "friction") if c in g.columns],
                        keys if isinstance(keys, tuple) else (keys,)))
        for q in quantities:
            col = f"err_{q}"
            if col not in g:
                continue
            e = g[col].to_numpy(float)
            ok = np.isfinite(e) & (e > 0)
            if ok.sum() < 2:
                continue
            le = np.log(e[ok])
            h, n = g["h"].to_numpy(float)[ok], g["ndof_total"].to_numpy(float)[ok]
            rate_h = math.nan if _adaptive(g) else float(np.polyfit(np.log(h), le, 1)[0])
            out.append({**keys, "quantity": q, "rate_h": rate_h,
                        "rate_dof": float(-np.polyfit(np.log(n), le, 1)[0]), "points": int(ok.sum()),
                        "h_min": float(h.min()), "ndof_max": int(n.max())})
    return pd.DataFrame(out, columns=["scene", "element", "nu", "friction", "quantity", "rate_h", "rate_dof", "points",
                                      "h_min", "ndof_max"])


def markdown_table(df, floatfmt: str = ".3g") -> str:
    """A GitHub-flavoured Markdown table of `df` (NaN shown as an empty cell)."""
    def cell(v):
        if isinstance(v, (float, np.floating)):
            return "" if not math.isfinite(v) else format(float(v), floatfmt)
        return str(v)

    cols = [str(c) for c in df.columns]
    lines = ["| " + " | ".join(cols) + " |",
             "|" + "|".join("---:" if df[c].dtype.kind in "fiu" else ":---" for c in df.columns) + "|"]
    for rec in df.itertuples(index=False):
        lines.append("| " + " | ".join(cell(v) for v in rec) + " |")
    return "\n".join(lines) + "\n"
