"""Running a sweep: `sweep()` and its plan (references first, each group's rows once its reference is ready).

The plan reads what the results file already holds (a resumed sweep skips those
rows), reuses cached references, submits the rest to an executor and appends each
row to the CSV as it finishes.
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Iterable
from pathlib import Path

from ...core.errors import InputError
from ...core.options import DEFAULT_ELEMENT
from .cases import Case, run_case
from .executors import _Dask, _executor, check_dask
from .grid import _Grid, _key, _same, check_friction_applies, warn_friction_not_applied
from .quantities import Reference, tip_columns
from .rates import with_rates
from .results import ROW_COLUMNS, ResultsFile, typed


class SweepError(RuntimeError):
    """A run of a sweep failed; the message names the case."""


def check_sweep(scene, elements=(DEFAULT_ELEMENT,), maxh=(0.2, 0.1, 0.05), nu=None, *, friction=None, reference_maxh=None,
                reference_element=None, jobs: int = 1, solve_options: dict | None = None, max_dof=None, adapt=None,
                adapt_maxh=None) -> _Grid:
    """Check a sweep's request as `sweep` does before any run (options, the size guard of every run);
    a bad one raises ValueError naming the field. Returns the checked grid."""
    from ...scenes import resolve

    if isinstance(scene, (str, Path)):
        scene = resolve(scene)
    if scene.dimension == 3:
        raise InputError(f"scene {scene.name!r} is 3D: its sweep varies front_h (nc.sweep(scene, front_h=[...]))")
    crack_model = (solve_options or {}).get("crack_model")
    check_friction_applies(friction, crack_model)
    if friction is None:
        warn_friction_not_applied(scene, crack_model)
    if max_dof is not None:
        from ...planar.sizing import check_max_dof

        check_max_dof(max_dof)
        if max_dof != int(max_dof):  # never truncated silently
            raise InputError(f"max_dof = {max_dof!r}: must be a whole number of unknowns")
        solve_options = {**(solve_options or {}), "max_dof": int(max_dof)}
    grid = _Grid.checked(scene, elements, maxh if adapt is None else adapt, nu, reference_maxh, reference_element,
                         jobs, solve_options, friction,
                         adapt_maxh=(adapt_maxh or scene.maxh or 0.0) if adapt is not None else None)
    grid.check_sizes()
    return grid


def sweep(
    scene,
    elements: Iterable[str] | str = (DEFAULT_ELEMENT,),
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
    vtk=None,
    front_h: Iterable[float] | float | None = None,
):
    """Run every (element, maxh, nu, friction) of `scene`; one row per run as a pandas DataFrame.

    A 3D scene sweeps `front_h` instead of maxh (`ngcrack.studies.sweeps.fronts`: its rows hold K
    along the fronts against the finest run's); the 2D-only arguments are refused for it by name.

    adapt: relative error tolerances in (0, 1) instead of mesh sizes: each run refines
    adaptively (solve(..., adapt=tol), from the mesh size adapt_maxh, default the
    scene's) and its row holds the tolerance in the maxh column, adapt = True, and the
    whole adaptive loop's wall time in time_total (max_dof is then the budget of each run).
    The reference is then the finest tolerance's run or a fixed mesh at reference_maxh.

    scene: a Scene, a built-in scene name or a TOML path. elements: element families
    (default: tdnns alone, as in `solve`). nu: Poisson ratios (default:
    the scene's). friction: Coulomb coefficients, each set on every crack (default: the
    scene's own; the `friction` column holds the cracks' largest). reference_maxh: the reference mesh size (default: the finest maxh,
    whose row is then the reference); reference_element: measure every element against
    this one's reference (default: each against its own). out: a CSV path, written row
    by row and resumed (see the module docstring). jobs: worker processes (spawned: a
    script calling this with jobs > 1 needs the usual `if __name__ == "__main__":`
    guard); dask: a scheduler address or a distributed.Client (then jobs is ignored).
    progress: a tqdm bar with ETA on stderr. solve_options go to `solve` unchanged
    (tip_h, crack_h, grading, qp_solver, crack_model, ...). max_dof: as in `solve`; every
    case (and reference) is checked against it (ngcrack.planar.sizing) before any run starts.
    vtk: a file stem OUT: every run writes its ParaView files OUT_<scene>-<element>-h<maxh>-nu<nu>
    (ngcrack.planar.vtk.save_vtk, in the process that ran it) and the sweep their collection OUT.pvd
    (one entry per row, in the table's order; a resumed sweep lists the runs whose files exist).

    Returns the rows of this grid (from the CSV where already there), ordered by
    element, nu and decreasing maxh, with ROW_COLUMNS and the rate columns of `with_rates`.
    """
    import pandas as pd

    from ...scenes import resolve

    check_dask(dask)  # a wrong kind of cluster refused before the scene is read
    scene = resolve(scene) if isinstance(scene, (str, Path)) else scene
    if scene.dimension == 3 or front_h is not None:
        return _sweep_3d(scene, elements, maxh, nu, front_h, friction=friction, out=out, progress=progress,
                         solve_options=solve_options, jobs=jobs, dask=dask, max_dof=max_dof, adapt=adapt,
                         adapt_maxh=adapt_maxh, reference_maxh=reference_maxh, reference_element=reference_element,
                         vtk=vtk)
    grid = check_sweep(scene, elements, maxh, nu, friction=friction, reference_maxh=reference_maxh,
                       reference_element=reference_element, jobs=jobs, solve_options=solve_options,
                       max_dof=max_dof, adapt=adapt, adapt_maxh=adapt_maxh)
    scene = grid.scene
    if vtk is not None:
        from ...planar.vtk import vtk_stem

        grid.vtk = str(vtk_stem(vtk))  # refuses a bad place before any run
        for _, element, h, v, f in grid.keys():  # and a run's file name taken by a folder
            for part in (".vtu", "_cracks.vtu"):
                taken = Path(grid.vtk_name(element, h, v, f) + part)
                if taken.is_dir():
                    raise InputError(f"vtk = {str(vtk)!r}: {str(taken)!r} (the ParaView file of the run {element}, "
                                     f"maxh {h:g}, nu {v:g}) is a directory; give another name")
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
    df = with_rates(df.drop(columns="_o").reset_index(drop=True))
    if vtk is not None:
        _write_vtk_collection(grid, df)
    return df


def _sweep_3d(scene, elements, maxh, nu, front_h, *, jobs, **given):
    """A 3D scene's sweep (`fronts.sweep_fronts`), the 2D-only arguments refused by name before any run."""
    from .fronts import PLANAR_SWEEP_ONLY, sweep_fronts

    if scene.dimension != 3:
        raise InputError(f"front_h: the size axis of 3D scenes; scene {scene.name!r} is 2D: sweep maxh (and tip_h in "
                         "solve_options)")
    if front_h is None:
        raise InputError(f"front_h: scene {scene.name!r} is 3D: give the front mesh sizes to sweep, front_h=[...]")
    if jobs != 1:
        raise InputError(f"jobs = {jobs!r}: a 3D sweep runs in this process (jobs = 1)")
    defaults = {"maxh": (0.2, 0.1, 0.05)}
    for name, value in (("maxh", maxh), *((k, given[k]) for k in PLANAR_SWEEP_ONLY if k in given)):
        if value is not None and value != defaults.get(name):
            instead = f": use {PLANAR_SWEEP_ONLY[name]}" if PLANAR_SWEEP_ONLY[name] else ""
            raise InputError(f"{name}: a sweep argument of 2D scenes; scene {scene.name!r} is 3D{instead}")
    return sweep_fronts(scene, elements, front_h, nu, friction=given["friction"], out=given["out"],
                        solve_options=given["solve_options"], progress=given["progress"])


def _write_vtk_collection(grid: _Grid, df) -> None:
    """OUT.pvd over the rows' ParaView files that exist, one entry per row in the table's order."""
    from ...planar.vtk import write_collection

    files = []
    for row in df.itertuples():
        stem = Path(grid.vtk_name(row.element, row.maxh, row.nu, row.friction))
        parts = [p for p in (stem.with_name(stem.name + ".vtu"), stem.with_name(stem.name + "_cracks.vtu")) if p.exists()]
        if parts:
            files.append(parts)
    if files:
        write_collection(files, [float(k) for k in range(len(files))], grid.vtk + ".pvd")



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
