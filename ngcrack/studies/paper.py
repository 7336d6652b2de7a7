"""The paper's numerical study, reproduced and extended: `ngcrack paper [--quick]`.

Belhachmi et al., section 4: example 1 (`paper-1`, nu = 0.29) and example 2
(`paper-2`, nu = 0.49), each solved with every mixed element of ngcrack on a sequence of
meshes; relative L2 errors of u1, u2, sigma_t1 and sigma_nu against a finer reference
mesh (the quantities and conventions of `ngcrack.studies.sweeps`). Written to the output folder:

    sweep-<scene>.csv             every run (the sweep's rows; rerunning resumes)
    table<k>_<quantity>.csv/.md   Tables 1-4: dof, error, rates and run time per row
    rates.csv/.md                 fitted rates per scene and element, next to the paper's
    fig3..fig6_*.png              Figures 3-6: error against triangles, log-log (the paper's dof converted;
                                  paper-1's also ngcrack's coarse comparison meshes, down to the paper's)
    fig7/fig8_*_sigma_nu.png      Figures 7-8: isolines of sigma_nu
    time_<quantity>.png           error against CPU seconds, one line per element (and per
                                  element's adaptive runs, `adapt-<scene>.csv`)
    comparison.csv/.md, fig9_comparison.png
                                  paper-1 on a common footing with the paper's Tables 1-4:
                                  triangles on the abscissa, ngcrack's errors the paper's
                                  way (element means against a next-finer mesh) beside
                                  the true L2 errors against a fine reference

The common footing. The paper counts the unknowns of the standard (not hybridized)
formulation; ngcrack's dof are those of the hybridized one, about twice as many per
triangle. Its dof are converted to triangles with the standard PEERS count on ngcrack's
own meshes of paper-1 (`paper_triangles`): 2 E + 4 T + V unknowns for T triangles, E
edges and V vertices (RT0 rows, curls of the cubic bubbles, P0 displacement, continuous
P1 rotation), 9.0 per triangle on the coarsest meshes and 7.6 on fine ones. The paper
measures errors against its own finest mesh, only somewhat finer than its rows; the
comparison measures ngcrack's the same way (`study.comparison_errors`).

The paper stopped at 937 unknowns; the full study here reaches 3e5 in its rows (and
1.2e6 in its reference), `--quick` stops at 7.6e4 with a 3e5 reference.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from ..shell.files import atomic_write
from .sweeps import QUANTITIES, QUANTITY_LABELS, check_sweep, fitted_rates, markdown_table, sweep

#: (scene, Poisson ratio) of the paper's two examples
PAPER_SCENES = (("paper-1", 0.29), ("paper-2", 0.49))


@dataclass(frozen=True)
class Level:
    """The meshes of a study: the rows' maxh and the finer reference."""

    maxh: tuple[float, ...]
    reference_maxh: float


#: about 70 CPU seconds with the comparison (one process; measured: 44 s wall on an idle 2-core
#: machine, 8.5 minutes when it was shared at load 12)
QUICK = Level(maxh=(0.2, 0.1, 0.05), reference_maxh=0.025)
#: rows to 3e5 unknowns, reference 1.2e6 (about 5 minutes on 2 cores, 2.5 GB per process)
FULL = Level(maxh=(0.2, 0.14, 0.1, 0.07, 0.05, 0.035, 0.025), reference_maxh=0.0125)

#: adaptive runs of the error-against-time figures: relative estimate tolerances, the first
#: mesh size and the budget of unknowns (adapt.py); the tables' `estimate` column is the
#: relative estimate in the energy norm of every row (estimate.py)
#: (measured from maxh 0.2: bdm 0.30 on paper-1 and 0.99 on paper-2 (nu = 0.49, where the
#: estimate overestimates, see the README), peers 1.03 on paper-1; bdm reaches 0.13 on
#: paper-2 with 1.4e5 unknowns)
ADAPT_QUICK = {"tolerances": (0.5, 0.3), "maxh": 0.2, "max_dof": 40_000}
ADAPT_FULL = {"tolerances": (0.5, 0.3, 0.2, 0.15), "maxh": 0.2, "max_dof": 400_000}
#: with the mesh sizes overridden (tests, experiments): one cheap adaptive run per element
ADAPT_SMALL = {"tolerances": (0.6,), "max_dof": 15_000}

#: the paper's Tables 1-4 (example 1, nu = 0.29): dof and relative L2 error
PAPER_TABLES = {
    "u1": ((83, 162, 461, 819, 937), (0.227449873, 0.0844177121, 0.0489419458, 0.0394980417, 0.0209586395)),
    "u2": ((83, 162, 461, 819, 937), (0.318122037, 0.144441467, 0.0821550301, 0.0752721434, 0.0529486423)),
    "sigma_t1": ((83, 162, 461, 819, 937), (0.425346615, 0.239523559, 0.0669139203, 0.05465566, 0.0448078919)),
    "sigma_nu": ((83, 162, 461, 819, 937), (0.412398168, 0.233872393, 0.0863552882, 0.0670412243, 0.0478285353)),
}
#: the rates the paper states in its text (example 1; fitted in dof, see ngcrack.studies.sweeps)
PAPER_RATES = {"u1": 0.81, "u2": 0.65, "sigma_t1": 0.93, "sigma_nu": 0.78}
#: the paper's a-priori rates in h (its energy-type norm); in dof they are half of these
THEORY_RATES_H = {"peers": 0.5, "bdm": 0.75}
#: the guide lines of Figures 3-6 by their rate in h (labels name the theory's elements)
GUIDE_LABELS = {0.5: r"$h^{1/2} \sim T^{-1/4}$ (peers, theory)", 0.75: r"$h^{3/4} \sim T^{-3/8}$ (bdm, theory)",
                1.0: r"$h^{1} \sim T^{-1/2}$"}
#: the comparison's meshes of paper-1 (from one triangle across each half, where the paper's
#: meshes are, to the study's) and its reference; the full study adds finer ones
COMPARISON_QUICK = Level(maxh=(0.5, 0.35, 0.25, 0.17, 0.12, 0.085), reference_maxh=0.042)
COMPARISON_FULL = Level(maxh=(0.5, 0.35, 0.25, 0.17, 0.12, 0.085, 0.06, 0.042, 0.03), reference_maxh=0.015)
#: mesh sizes of paper-1 on which the standard-count conversion is tabulated
_CONVERSION_MAXH = tuple(np.geomspace(0.8, 0.05, 16))


def standard_unknowns(crack_mesh) -> int:
    """The unknowns of the standard (not hybridized) PEERS on a mesh: 2 E + 4 T + V.

    Two RT0 rows (one unknown per edge each), two curls of cubic bubbles and a P0
    displacement (two each per triangle), a continuous P1 rotation (one per vertex).
    """
    m = crack_mesh.mesh
    return 2 * m.nedge + 4 * m.ne + m.nv


def paper_triangles(dof) -> np.ndarray:
    """Triangles of a paper-1 mesh whose standard PEERS has `dof` unknowns (log-log
    interpolation over ngcrack's own meshes of paper-1; see `standard_unknowns`)."""
    from .. import scenes
    from ..planar.geometry import make_mesh

    scene = scenes.load("paper-1")
    pairs = sorted((standard_unknowns(cm), cm.mesh.ne) for cm in (make_mesh(scene, maxh=h) for h in _CONVERSION_MAXH))
    n, t = np.log([p[0] for p in pairs]), np.log([p[1] for p in pairs])
    x = np.log(np.asarray(dof, float))
    # beyond the tabulated meshes: the end's unknowns per triangle
    return np.exp(np.interp(x, n, t) + np.where(x < n[0], x - n[0], 0.0) + np.where(x > n[-1], x - n[-1], 0.0))


def mixed_elements() -> list[str]:
    """The mixed elements among ngcrack's elements (those the paper's study is about)."""
    from ..planar import elements

    mixed = getattr(elements, "MIXED", ("peers", "bdm"))
    return [e for e in elements.ELEMENTS if e in mixed]


def paper_rates_from_tables() -> dict[str, float]:
    """Least-squares rates in dof of the paper's Tables 1-4 (what its stated rates are)."""
    return {q: float(-np.polyfit(np.log(d), np.log(e), 1)[0]) for q, (d, e) in PAPER_TABLES.items()}


@dataclass
class PaperResult:
    """What `run` wrote: the combined rows, the fitted rates and the files by kind."""

    rows: object
    rates: object
    files: dict[str, list[Path]] = field(default_factory=dict)

    @property
    def all_files(self) -> list[Path]:
        return [p for ps in self.files.values() for p in ps]


def _table(df, q: str):
    cols = {"scene": "scene", "element": "element", "maxh": "maxh", "h": "h", "ndof_total": "dof",
            f"err_{q}": "error", "estimate": "estimate", f"rate_dof_{q}": "rate_dof", f"rate_h_{q}": "rate_h", "time_total": "time_s",
            "time_cpu": "cpu_s", "memory_peak_mb": "memory_mb"}
    return df[list(cols)].rename(columns=cols).reset_index(drop=True)


def _write_table(t, stem: Path, heading: str, note: str) -> list[Path]:
    csv = atomic_write(stem.with_suffix(".csv"), lambda tmp: t.to_csv(tmp, index=False, float_format="%.6g"))
    md = atomic_write(stem.with_suffix(".md"), lambda tmp: Path(tmp).write_text(f"## {heading}\n\n{note}\n\n" + markdown_table(t)))
    return [csv, md]


COMPARISON_NOTE = (
    "paper-1 (nu = 0.29), every element on meshes from one triangle across each half of the body (where the "
    "paper's meshes are) to the study's. triangles: of ngcrack's mesh; the paper's dof convert to triangles by "
    "the standard PEERS count 2E + 4T + V (paper.paper_triangles). true_<q>: relative L2 error against a fine "
    "reference of the same element; means_<q>: element means against the reference's element means (both "
    "projected onto the row's triangles); next_<q>: element means against the element means of the next finer "
    "row (the finest against the reference), the paper's way. coarse: the element warned that the mesh is too "
    "coarse across the body's thin halves (sizing.check_thin_parts); meshes it refuses have no row.")


def comparison_table(elements, sizes, reference_maxh):
    """`study.comparison_errors` of paper-1 (nu = 0.29) for every element, stacked."""
    import pandas as pd

    from .sweeps import comparison_errors

    nu = dict(PAPER_SCENES)["paper-1"]
    frames = [comparison_errors("paper-1", e, sizes, reference_maxh, nu=nu) for e in elements]
    return pd.concat(frames, ignore_index=True)


def _adaptive_runs(out: Path, level: dict, elements, ref_h: float, jobs: int, dask, progress: bool, files):
    """The adaptive sweeps (one CSV per scene) against the same references as the fixed
    meshes (their saved references are reused); rows relabelled "<element> (adaptive)"."""
    import shutil

    import pandas as pd

    from .. import scenes

    frames = []
    for name, nu in PAPER_SCENES:
        path = out / f"adapt-{name}.csv"
        refs = Path(str(path) + ".refs")
        refs.mkdir(exist_ok=True)
        for f in Path(str(out / f"sweep-{name}.csv") + ".refs").glob("*.npz"):
            if not (refs / f.name).exists():
                shutil.copy(f, refs / f.name)
        frames.append(sweep(scenes.load(name), elements=elements, nu=[nu], reference_maxh=ref_h, out=path, jobs=jobs,
                            dask=dask, progress=progress, adapt=level["tolerances"], adapt_maxh=level["maxh"],
                            solve_options={"max_dof": level["max_dof"]}))
        files["sweeps"].append(path)
    df = pd.concat(frames, ignore_index=True)
    return df.assign(element=[f"{e} (adaptive)" for e in df["element"]])


def _check_request(quick: bool, elements, sizes, ref_h: float, ref_given: bool, jobs) -> None:
    """Refuse a bad request before anything is written, naming the option the user gave."""
    from .. import scenes

    for name, nu in PAPER_SCENES:  # the rows' own checks (elements, sizes, size guard) first
        check_sweep(scenes.load(name), elements=elements, maxh=sizes, nu=[nu], jobs=jobs)
    finest = min(sizes)
    if ref_h > finest * (1 + 1e-12):
        if ref_given:
            raise InputError(f"reference_maxh = {ref_h:g}: must be at most the finest maxh ({finest:g})")
        raise InputError(f"maxh = {finest:g}: finer than the reference mesh of the {'quick' if quick else 'full'} "
                          f"study (maxh {ref_h:g}); give reference_maxh (--reference-maxh) at most {finest:g} too")
    for name, nu in PAPER_SCENES:
        check_sweep(scenes.load(name), elements=elements, maxh=sizes, nu=[nu], reference_maxh=ref_h, jobs=jobs)


def run(out="paper-results", quick: bool = False, *, elements=None, maxh=None, reference_maxh=None, jobs: int = 1,
        dask=None, progress: bool = True, log: Callable[[str], None] = print) -> PaperResult:
    """Run the study and write its tables and figures to `out` (created if missing).

    quick: the QUICK meshes instead of FULL. elements / maxh / reference_maxh override
    the level (for tests and experiments). jobs / dask: as in `study.sweep`.
    """
    import pandas as pd

    from .. import scenes
    from ..core.solve import solve
    from ..planar import plots

    out = Path(out)
    if not out.parent.exists():
        raise InputError(f"out = {str(out)!r}: the directory {str(out.parent)!r} does not exist")
    level = QUICK if quick else FULL
    sizes = tuple(maxh) if maxh is not None else level.maxh
    ref_h = reference_maxh if reference_maxh is not None else level.reference_maxh
    elements = list(elements) if elements is not None else mixed_elements()
    _check_request(quick, elements, sizes, ref_h, reference_maxh is not None, jobs)
    out.mkdir(exist_ok=True)  # only once the request is sound: a refusal leaves no folder
    files: dict[str, list[Path]] = {"sweeps": [], "tables": [], "figures": []}

    frames = []
    for name, nu in PAPER_SCENES:
        path = out / f"sweep-{name}.csv"
        frames.append(sweep(scenes.load(name), elements=elements, maxh=sizes, nu=[nu], reference_maxh=ref_h,
                            out=path, jobs=jobs, dask=dask, progress=progress))
        files["sweeps"].append(path)
    df = pd.concat(frames, ignore_index=True)
    rates = fitted_rates(df, QUANTITIES)

    # Tables 1-4
    ref_note = {name: int(g["reference_ndof"].iloc[0]) for name, g in df.groupby("scene")}
    for k, q in enumerate(QUANTITIES, start=1):
        note = (f"Relative L2(Omega) error of {q} against the reference mesh (maxh {ref_h:g}; "
                + ", ".join(f"{s}: {n:,} dof".replace(",", " ") for s, n in ref_note.items())
                + "), per element. dof: all unknowns; rate_dof: log(e_prev/e)/log(dof/dof_prev); "
                  "rate_h: log(e_prev/e)/log(h_prev/h), h the largest edge; estimate: the a posteriori "
                  "estimate of the relative stress error in the energy norm (a different norm from the error "
                  "column: compare trends, not values); time_s: the whole solve, "
                  "wall clock; cpu_s: the same span in CPU seconds of the process (what the solve costs, "
                  "whatever else the machine runs); memory_mb: peak resident memory of the process.")
        files["tables"] += _write_table(_table(df, q), out / f"table{k}_{q}", f"Table {k}: {q}", note)

    # fitted rates next to the paper's
    r = rates.copy()
    r["paper_rate_dof"] = [PAPER_RATES[q] if s == "paper-1" else math.nan for s, q in zip(r.scene, r.quantity)]
    r["theory_rate_h"] = [THEORY_RATES_H.get(e, math.nan) for e in r.element]
    r = r[["scene", "element", "nu", "quantity", "rate_dof", "rate_h", "paper_rate_dof", "theory_rate_h", "points",
           "ndof_max"]]
    note = ("Least-squares slopes: rate_dof of -log e against log dof (the paper's convention: its stated "
            "rates u1 0.81, u2 0.65, sigma_t 0.93, sigma_nu 0.78 are such slopes for example 1; it gives "
            "no table for example 2), rate_h of log e against log h. In 2D dof ~ h^-2, so rate_dof ~ "
            "rate_h / 2. theory_rate_h: the paper's a-priori rate in its energy-type norm.")
    files["tables"] += _write_table(r, out / "rates", "Fitted rates", note)

    # the paper's Tables 1-4 on a common footing (paper-1): its meshes reach down to the paper's
    comp_level = COMPARISON_QUICK if quick else COMPARISON_FULL
    comp_sizes = tuple(maxh) if maxh is not None else comp_level.maxh
    comp_ref = reference_maxh if reference_maxh is not None else comp_level.reference_maxh
    comp = comparison_table(elements, comp_sizes, comp_ref)

    # Figures 3-6, on triangles (T ~ h^-2): the theory's rates in h drawn as T^(-rate/2)
    guides = {GUIDE_LABELS[r]: r / 2 for r in sorted(set(THEORY_RATES_H.values()) | {1.0})}
    fig_no = 3
    for name, nu in PAPER_SCENES:
        sub = df[df.scene == name]
        for kind, qs in (("displacement", ("u1", "u2")), ("stress", ("sigma_t1", "sigma_nu"))):
            path = out / f"fig{fig_no}_{name}_{kind}.png"
            pts = {q: (paper_triangles(PAPER_TABLES[q][0]), PAPER_TABLES[q][1]) for q in qs} if name == "paper-1" else None
            coarse = ({q: {e: (g["triangles"].to_numpy(float), g[f"true_{q}"].to_numpy(float))
                           for e, g in comp.groupby("element", sort=False)} for q in qs} if name == "paper-1" else None)
            labels = " and ".join(QUANTITY_LABELS[q] for q in qs)
            title = f"Figure {fig_no} analog: {labels}, {name} (Poisson ratio {nu:g})"
            atomic_write(path, functools.partial(plots.plot_convergence, sub, qs, paper_points=pts, guides=guides,
                                                 x="n_elements", title=title, coarse_points=coarse))
            files["figures"].append(path)
            fig_no += 1

    # Figures 7-8: isolines of sigma_nu on the finest mesh of the rows
    h_iso = min(sizes)
    for name, nu in PAPER_SCENES:
        sols = [solve(scenes.load(name).with_(nu=nu), element=e, maxh=h_iso) for e in elements]
        path = out / f"fig{fig_no}_{name}_sigma_nu.png"
        title = rf"Figure {fig_no} analog: isolines of $\sigma_\nu$, {name} (Poisson ratio {nu:g})"
        atomic_write(path, functools.partial(plots.plot_sigma_nu_isolines, sols, title=title))
        files["figures"].append(path)
        fig_no += 1

    # error against run time, one figure per quantity, with the adaptive runs
    level = (ADAPT_QUICK if quick else ADAPT_FULL) if maxh is None else {**ADAPT_SMALL, "maxh": max(sizes)}
    adaptive = _adaptive_runs(out, level, elements, ref_h, jobs, dask, progress, files)
    timed = pd.concat([df, adaptive], ignore_index=True) if adaptive is not None else df
    for q in QUANTITIES:
        path = out / f"time_{q}.png"
        atomic_write(path, functools.partial(plots.plot_error_vs_time, timed, q))
        files["figures"].append(path)

    files["tables"] += _write_table(comp, out / "comparison", "paper-1 against the paper's Tables 1-4", COMPARISON_NOTE)
    path = out / "fig9_comparison.png"
    atomic_write(path, lambda tmp: plots.plot_paper_comparison(
        comp, {q: (paper_triangles(d), e) for q, (d, e) in PAPER_TABLES.items()}, tmp))
    files["figures"].append(path)

    log(f"paper study ({'quick' if quick else 'full'}): elements {', '.join(elements)}; maxh "
        f"{', '.join(f'{h:g}' for h in sizes)}; reference maxh {ref_h:g}")
    for paths in files.values():
        for p in paths:
            log(f"wrote {p}")
    return PaperResult(rows=df, rates=rates, files=files)
