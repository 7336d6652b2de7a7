"""One run of a sweep (a Case) and what it returns: the solve, its row, its memory.

Memory. `memory_peak_mb` is the peak resident set size (VmHWM) of the process that ran
the case during its solve (not the error evaluation), reset at its start (Linux: /proc/self/clear_refs) after freed heap memory is
handed back to the OS (gc, glibc malloc_trim). It is the run's own peak plus what the
process still held at the start, `memory_start_mb` (the interpreter and NGSolve, about
150 MB, plus whatever earlier runs in a long-lived process left behind); their
difference estimates the run's own footprint. Where the reset is unavailable (not
Linux) the peak is the process's peak since it started, an upper bound. Runs sharing a
process (dask threads) share one peak: again an upper bound.
"""

from __future__ import annotations

import math
import sys
import threading
import time
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .quantities import QUANTITIES, TIP_QUANTITIES, Reference, k_error, opening_error
from .results import ROW_COLUMNS, scene_friction

#: solve options that shape the mesh or the element (what ngcrack.planar.sizing's checks read)
MESH_OPTIONS = ("tip_h", "crack_h", "grading", "order")


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
    vtk: str | None = None  # the ParaView files' stem of this run (ngcrack.planar.vtk.save_vtk), or None

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


_worker = threading.local()


def worker_pipeline():
    """The Pipeline of this worker (process or thread): its runs go through one Pipeline,
    so that the elements, Poisson ratios and friction coefficients of a sweep share each
    size's mesh (the stages after the mesh are released after every run)."""
    from ...core.pipeline import Pipeline

    if getattr(_worker, "pipeline", None) is None:
        _worker.pipeline = Pipeline()
    return _worker.pipeline


def run_case(case: Case) -> tuple[dict | None, Reference | None]:
    """Solve one case: (its row or None, its Reference or None). Runs in any process."""

    pipeline = worker_pipeline()
    try:
        return _run_case(case, pipeline)
    finally:
        pipeline.keep_mesh_only()  # the next run's assembly does not meet this one's factorization


def _run_case(case: Case, pipeline) -> tuple[dict | None, Reference | None]:
    from ...core.solve import solve

    _release_memory()
    _reset_peak_memory()
    mem_start, _ = _memory_mb()
    scene = case.scene.with_(nu=case.nu) if case.friction is None else case.scene.with_(nu=case.nu, friction=case.friction)
    cpu0 = time.process_time()  # the process's CPU time (all its threads): not inflated by other loads
    if case.adapt_maxh is not None:  # refines its own meshes: none is shared
        with warnings.catch_warnings():  # a budget reached is recorded in the row (estimate > maxh)
            warnings.simplefilter("ignore", UserWarning)
            sol = solve(scene, element=case.element, maxh=case.adapt_maxh, adapt=case.maxh, pipeline=pipeline,
                        **case.solve_options)
    else:
        sol = solve(scene, element=case.element, maxh=case.maxh, pipeline=pipeline, **case.solve_options)
    cpu_solve = time.process_time() - cpu0
    _, mem_peak = _memory_mb()  # the solve's peak, before the error evaluation adds its own
    if case.vtk is not None and case.row:
        sol.save_vtk(case.vtk)
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
            "friction": scene_friction(scene) if case.solve_options.get("crack_model", "contact") == "contact" else 0.0,
            "E": float(scene.material.E), "h": h, "n_elements": ne,
            "ndof_total": int(sol.ndof["total"]), "ndof_global": int(sol.ndof["global"]),
            "ndof_contact": int(sol.ndof["contact"]),
            "n_active": int(len(sol.qp.active)) if sol.qp is not None else 0,
            "time_mesh": t["mesh"], "time_assemble": t["assemble"], "time_linear": t["linear"],
            "time_contact": t["contact"], "time_total": t.get("adapt_total", t["total"]), "time_error": t_err,
            "time_cpu": cpu_solve,
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
