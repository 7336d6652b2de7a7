"""The `ngcrack` command.

    ngcrack scenes
    ngcrack stability [--quick] [--out DIR]
    ngcrack solve SCENE [--element E] [--order K] [--maxh H] [--nu NU] [--E E] [--friction MU] [--tip-h H]
                        [--crack-h H] [--front-h H] [--accuracy E] [--qp-solver S] [--crack-model M] [--adapt TOL] [--max-dof N]
                        [--hp L] [--json OUT] [--plot OUT.png] [--vtk OUT]
    ngcrack sweep SCENE [--element E ...] (--maxh H [H ...] | --adapt TOL [TOL ...]) [--nu NU ...]
                        [--friction MU ...] --out results.csv [--reference-maxh H] [--reference-element E]
                        [--jobs N] [--dask ADDRESS] [--max-dof N] [--vtk OUT]
    ngcrack paper [--quick] [--out DIR] [--jobs N] [--dask ADDRESS]
    ngcrack grow SCENE --da D --steps N [--K-Ic K] [--criterion pls|mts] [solve options] --json OUT
                       [--csv OUT] [--gif OUT] [--png OUT]
    ngcrack hydrofrac SCENE --rate Q0 --K-Ic K --da D --steps N --json OUT [--csv OUT] [--gif OUT]

SCENE is a built-in scene name or a TOML file. No command shows a traceback: bad input
exits with code 2 and one line on stderr naming the field, before any meshing; a system
that cannot be solved (singular, a failed crack QP, out of memory) exits with code 3
and one line naming the cause; anything else is a fault of ngcrack: exit code 3 too, one
line naming the command and asking for a report, with the advice to run again with
--debug (which prints the traceback). Warnings are one
line each. Output files are written only after a successful solve, atomically (a
temporary file renamed into place), so none is left half-written and an existing one
is untouched on failure; an output that cannot be written, or two outputs on one file,
are refused before the solve. SIGTERM and SIGINT act within about a second in every stage
(ngcrack.shell.interrupts: netgen's mesher is stopped, a long C call ended): exit code 128 + the
signal and one line saying what was written (`grow` writes the steps it finished).
`sweep` writes its CSV one complete line per finished run and resumes (ngcrack.studies.sweeps);
`paper` runs the paper's study (ngcrack.studies.paper).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import signal
import sys
import traceback
import warnings
from contextlib import contextmanager

from .cli_errors import (
    EXIT_INPUT,
    EXIT_SOLVE,
    NotSolvedError,
    Terminated,
    UsageError,
    _causes,
    as_flags,
    check_finite,
    classify,
    first_rank,
    interrupted_line,
    one_line,
    one_line_warning,
    report_interrupted,
)
from .extras import require
from .files import PathError, check_distinct, check_output, check_output_folder, check_output_stem
from .interrupts import Interrupts
from .interrupts import check as check_interrupt

#: a size option (maxh, tip_h, crack_h) must lie within these multiples of the body's diameter
SIZE_RANGE = (1e-100, 1e100)


#: the address space the libraries of a solve map (measured: a solve of paper-2 at maxh 0.3 peaks at
#: 1.1 GB of address space with one thread and 1.55 GB with two; importing them alone takes 0.7-0.9 GB)
MIN_ADDRESS_SPACE = 2**30
#: the commands that solve (and load the numerical libraries)
SOLVING = ("solve", "sweep", "paper", "grow", "stability", "hydrofrac")
#: the files of `solve --vtk OUT`: OUT.vtu (the body) and OUT_cracks.vtu (the crack faces)
VTK_PARTS = (".vtu", "_cracks.vtu")


def _check_sizes(scene, sizes: dict) -> None:
    """Mesh sizes within SIZE_RANGE of the body's diameter (beyond it, no arithmetic on them is safe)."""
    d = scene.diameter
    lo, hi = SIZE_RANGE
    if scene.maxh is not None and not sizes.get("--maxh"):  # the scene's own, unless --maxh replaces it
        sizes = {f"the scene's mesh.maxh ({scene.name!r})": scene.maxh, **sizes}
    for flag, values in sizes.items():
        for v in values if isinstance(values, list) else [values]:
            if v is not None and not lo * d <= v <= hi * d:
                raise UsageError(f"{flag} = {v:g}: must lie between {lo:g} and {hi:g} times the body's "
                                 f"diameter ({d:g}); a mesh size is a length in the scene's units")


def _check_friction(scene, args) -> None:
    """--friction only with --crack-model contact; a scene's own friction under free or bonded: a warning."""
    from ..core.friction_checks import check_friction_applies, warn_friction_not_applied

    check_friction_applies(args.friction, args.crack_model, "--friction")
    if args.friction is None and args.command == "solve":  # (a sweep warns itself)
        warn_friction_not_applied(scene, args.crack_model)


def cmd_scenes(args) -> int:
    from .. import scenes

    rows = scenes.describe()
    width = max(len(n) for n, _ in rows)
    for name, desc in rows:
        print(f"{name:<{width}}  {desc}")
    print("\nscene functions (Python: nc.scenes.SCENE_FUNCTIONS[name](**params); nc.explore(name)):")
    for fn in scenes.SCENE_FUNCTIONS.values():
        print(f"{fn.name}  {fn.summary}")
        for p in fn.parameters:
            print(f"    {p.name} = {p.default:g}  [{p.low:g}, {p.high:g}]  {p.kind}: {p.doc}")
    return 0


def cmd_solve(args) -> int:
    """`ngcrack solve`: the outputs checked, one `nc.solve` of any scene, the outputs written together, its report."""
    from ..core.solve import solve

    outputs = _solve_outputs(args)
    scene = _solve_scene(args)
    with as_flags({**{k: "--" + k.replace("_", "-") for k in SOLVE_FLAGS}, "estimate": "--no-estimate"}):
        sol = solve(scene, options=_solve_options(args))  # every option checked by the scene's body before meshing
    if sol is None:  # a rank > 0 of a distributed solve (mpiexec): rank 0 writes and prints
        return 0
    result = sol.to_json_dict()
    written = _write_outputs(sol, result, *outputs)
    print("\n".join(sol.report_lines(result)))
    for path in written:
        print(f"wrote {path}")
    return 0


def _solve_outputs(args) -> tuple:
    """--json, --plot, --vtk: each checked (folder, suffix, no two the same) before any work."""
    json_path = check_output(args.json, "--json")
    plot_path = check_output(args.plot, "--plot", ".png")
    vtk = check_output_stem(args.vtk, "--vtk", VTK_PARTS)
    if vtk is not None:
        require("meshio", "--vtk")  # the crack faces' file: before the solve
    vtk_files = None if vtk is None else [vtk.with_name(vtk.name + part) for part in VTK_PARTS]
    check_distinct({"--json": json_path, "--plot": plot_path, "--vtk": vtk_files})
    return json_path, plot_path, vtk, args.vtk


def _solve_scene(args):
    """The scene of `ngcrack solve` with --nu, --E, --friction applied, and the checks of the flags against it."""
    from .. import scenes

    scene = scenes.resolve(args.scene)
    changes = {k: v for k, v in (("nu", args.nu), ("E", args.E), ("friction", args.friction)) if v is not None}
    if changes:
        scene = scene.with_(**changes)
    if args.plot is not None and "plot" not in scene.body.outputs:
        raise UsageError(f"--plot: a figure of {scene.dimension}D scenes is not drawn; write --vtk files for ParaView")
    _check_sizes(scene, {"--maxh": args.maxh, "--tip-h": args.tip_h, "--crack-h": args.crack_h,
                         "--front-h": args.front_h})
    _check_friction(scene, args)
    return scene


#: the options of `ngcrack solve` that are flags of the same name (`front_h` is --front-h)
SOLVE_FLAGS = ("element", "order", "maxh", "tip_h", "crack_h", "front_h", "qp_solver", "adapt", "hp", "max_dof",
               "crack_model", "estimate", "accuracy")


def _solve_options(args):
    """The SolveOptions of the flags given (the body of the scene refuses those it cannot take)."""
    from ..core.options import SolveOptions

    given = {k: getattr(args, k) for k in SOLVE_FLAGS if getattr(args, k) is not None}
    return SolveOptions.of(**given)


def _write_outputs(sol, result: dict, json_path, plot_path, vtk, given_vtk) -> list:
    """The JSON record, the figure and the ParaView files, written to temporary names and moved into place
    together: every file or none, existing ones untouched on failure or interrupt (files.Staged)."""
    from .files import Staged

    check_finite(result)
    with Staged() as staged:
        if json_path is not None:
            def write_json(tmp):
                with open(tmp, "w") as fh:
                    json.dump(result, fh, indent=1)
            staged.write(json_path, write_json)
        if plot_path is not None:
            from ..planar.plots import plot_solution

            staged.write(plot_path, lambda tmp: plot_solution(sol, tmp))
        vtk_paths = [] if vtk is None else _stage_vtk(staged, sol, vtk, given_vtk)
    return [p for p in (json_path, plot_path, *vtk_paths) if p is not None]


def _stage_vtk(staged, sol, stem, given) -> list:
    """ParaView: OUT.vtu (the body) and OUT_cracks.vtu (the crack faces), staged with the other outputs."""
    folder = staged.folder(stem.parent)
    try:
        written = sol.save_vtk(folder / "out")
    except OSError as exc:
        raise PathError(f"--vtk = {str(given)!r}: the ParaView files could not be written "
                        f"({exc.strerror or exc}); nothing was written") from None
    return [staged.adopt(f, stem.with_name(stem.name + f.name[len("out"):])) for f in written]


def _sweep_options(args) -> dict:
    from ..planar.elements import ELEMENTS

    named = [("--element", el) for el in args.element or []]
    if getattr(args, "reference_element", None):
        named.append(("--reference-element", args.reference_element))
    for flag, el in named:
        if el not in ELEMENTS:
            raise UsageError(f"{flag} = {el!r}: allowed values are {', '.join(ELEMENTS)}")
    for name in ("maxh", "reference_maxh"):
        vals = getattr(args, name, None)
        for v in (vals if isinstance(vals, list) else [vals] if vals is not None else []):
            if not (math.isfinite(v) and v > 0):
                raise UsageError(f"--{name.replace('_', '-')} = {v:g}: must be a finite number > 0")
    if args.jobs < 1:
        raise UsageError(f"--jobs = {args.jobs}: must be an integer >= 1")
    if args.dask is not None and args.jobs != 1:
        raise UsageError("--jobs and --dask exclude each other: the dask cluster decides the parallelism")
    return {"jobs": args.jobs, "dask": args.dask, "progress": not args.no_progress}


def cmd_sweep(args) -> int:
    from .. import scenes

    opts = _sweep_options(args)
    out = check_output(args.out, "--out", ".csv")
    vtk = check_output_stem(args.vtk, "--vtk", [".pvd"])
    if vtk is not None:
        require("meshio", "--vtk")
    check_distinct({"--out": out, "--vtk": None if vtk is None else [vtk.with_name(vtk.name + ".pvd")]})
    scene = scenes.resolve(args.scene)
    for v in args.nu or []:
        scene.with_(nu=v)  # a bad nu is refused here, before any meshing
    for v in args.friction or []:
        scene.with_(friction=v)
    solve_options = {k: v for k, v in (("tip_h", args.tip_h), ("crack_h", args.crack_h), ("grading", args.grading))
                     if v is not None}
    solve_options["crack_model"] = args.crack_model
    if args.qp_solver is not None:
        solve_options["qp_solver"] = args.qp_solver
    from ..core.solve import CRACK_MODELS, qp_solvers

    if args.crack_model not in CRACK_MODELS:
        raise UsageError(f"--crack-model = {args.crack_model!r}: allowed values are {', '.join(CRACK_MODELS)}")
    if args.qp_solver is not None and args.qp_solver not in qp_solvers():
        raise UsageError(f"--qp-solver = {args.qp_solver!r}: allowed values are {', '.join(qp_solvers())}")
    if args.grading is not None and not 0 < args.grading <= 1:
        raise UsageError(f"--grading = {args.grading:g}: must lie in (0, 1]")
    _check_sizes(scene, {"--maxh": args.maxh, "--reference-maxh": args.reference_maxh, "--tip-h": args.tip_h,
                         "--crack-h": args.crack_h, "--front-h": args.front_h})
    _check_friction(scene, args)
    from ..studies.sweeps import QUANTITIES, fitted_rates, sweep

    if args.front_h is not None or scene.dimension == 3:  # a 3D scene sweeps its front size
        return _sweep_fronts(args, scene, out, solve_options)
    before = len(open(out).read().splitlines()) - 1 if out.exists() and out.stat().st_size else 0
    adaptive = {}
    if args.adapt is not None:  # tolerances instead of mesh sizes; --maxh (one value) is the first mesh
        if args.maxh is not None and len(args.maxh) != 1:
            raise UsageError("--maxh: with --adapt give one value, the first mesh's size")
        adaptive = {"adapt": args.adapt, "adapt_maxh": args.maxh[0] if args.maxh else None}
    elif args.maxh is None:
        raise UsageError("--maxh: give the mesh sizes (or --adapt with tolerances)")
    from ..core.options import DEFAULT_ELEMENT

    with _workers_lost(out):
        df = sweep(scene, elements=args.element or [DEFAULT_ELEMENT], maxh=args.maxh, nu=args.nu,
                   friction=args.friction, reference_maxh=args.reference_maxh, reference_element=args.reference_element,
                   out=out, solve_options=solve_options, max_dof=args.max_dof, vtk=args.vtk, **opts, **adaptive)
    after = len(open(out).read().splitlines()) - 1 if out.exists() else 0
    cols = ["element", "maxh", "nu", "ndof_total"] + [f"err_{q}" for q in QUANTITIES] + ["estimate", "time_total"]
    if args.friction is not None:
        cols[3:3] = ["friction", "n_stick", "kkt_friction"]
    if df["err_opening"].notna().any():
        cols.insert(-1, "err_opening")
    if df["err_K_I"].notna().any():
        cols.insert(-1, "err_K_I")
    with _pandas_display():
        print(df[cols].to_string(index=False, float_format=lambda v: f"{v:.3g}"))
        rates = fitted_rates(df)
        if len(rates):
            print("fitted rates (e ~ h^rate_h ~ dof^-rate_dof):")
            print(rates[["element", "nu"] + (["friction"] if args.friction is not None else [])
                        + ["quantity", "rate_h", "rate_dof", "points"]].to_string(
                index=False, float_format=lambda v: f"{v:.3g}"))
    print(f"wrote {out} ({after - before} new rows, {after} in the file)")
    return 0


def _sweep_fronts(args, scene, out, solve_options: dict) -> int:
    """`ngcrack sweep` of a 3D scene: its front sizes (`nc.sweep(scene, front_h=[...])`), the table printed."""
    from ..core.options import DEFAULT_ELEMENT
    from ..studies.sweeps import sweep

    given = {"maxh": args.maxh, "adapt": args.adapt, "reference_maxh": args.reference_maxh,
             "reference_element": args.reference_element, "vtk": args.vtk, "dask": args.dask, "max_dof": args.max_dof}
    given = {k: v for k, v in given.items() if v is not None}
    if args.front_h is None and scene.dimension == 3:
        raise UsageError(f"--front-h: scene {scene.name!r} is 3D: give the front mesh sizes to sweep")
    solve_options = {k: v for k, v in solve_options.items() if k != "crack_model" or v != "contact"}
    df = sweep(scene, elements=args.element or [DEFAULT_ELEMENT], nu=args.nu, friction=args.friction, out=out,
               solve_options=solve_options, front_h=args.front_h, jobs=args.jobs, progress=not args.no_progress, **given)
    cols = ["element", "order", "front_h", "nu", "ndof_total", "K_I_min", "K_I_max", "err_K_I", "err_K", "time_total",
            "memory_peak_mb"]
    with _pandas_display():
        print(df[cols].to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    print(f"err_K_I, err_K: against the finest front_h of each element and nu (its own row: NaN); wrote {out} "
          f"({len(df)} rows)")
    return 0


def cmd_paper(args) -> int:
    opts = _sweep_options(args)
    out = check_output_folder(args.out, "--out")
    from ..studies.paper import run

    with _workers_lost(out):
        res = run(out, quick=args.quick, elements=args.element, maxh=args.maxh, reference_maxh=args.reference_maxh,
                  **opts)
    with _pandas_display():
        for scene, g in res.rates.groupby("scene", sort=False):
            piv = g.pivot(index="element", columns="quantity", values="rate_dof")
            piv = piv[[q for q in ("u1", "u2", "sigma_t1", "sigma_nu") if q in piv.columns]]
            print(f"{scene}: fitted rates in dof (paper, example 1: u1 0.81, u2 0.65, sigma_t 0.93, sigma_nu 0.78)")
            print(piv.to_string(float_format=lambda v: f"{v:.2f}"))
    return 0


@contextmanager
def _workers_lost(out):
    """A worker process that dies (a signal, the kernel's out-of-memory killer) ends the sweep with one line."""
    from concurrent.futures.process import BrokenProcessPool

    try:
        yield
    except Exception as exc:
        lost = next((c for c in _causes(exc) if isinstance(c, BrokenProcessPool)), None)
        if lost is None:
            raise
        raise NotSolvedError(f"a worker process of the sweep ended abruptly (killed by a signal, or by the system "
                             f"when memory ran out); the finished runs are saved in {str(out)!r}: run the same "
                             f"command again to resume") from None


def _check_address_space() -> None:
    """Refuse to start work under an address-space limit (ulimit -v) that the libraries alone exceed: there
    OpenBLAS aborts or loops while loading, with no message of ngcrack's."""
    from ..core.memory import address_space_limit

    limit = address_space_limit()
    if limit is not None and limit < MIN_ADDRESS_SPACE:
        raise NotSolvedError(f"out of memory: the address-space limit (ulimit -v) is {limit / 2**20:.0f} MB, and "
                             f"NGSolve, SciPy and OpenBLAS map about {MIN_ADDRESS_SPACE / 2**30:.1f} GB before the "
                             f"first solve; raise the limit (ulimit -v {2 * MIN_ADDRESS_SPACE // 1024}) or remove it")


def cmd_stability(args) -> int:
    out = check_output_folder(args.out, "--out")
    from ..studies.stability import run

    for what, path in run(quick=args.quick, out=out).items():
        print(f"{what}: {path}")
    return 0


class _pandas_display:
    def __enter__(self):
        import pandas as pd

        self._ctx = pd.option_context("display.width", 200, "display.max_columns", 50)
        self._ctx.__enter__()

    def __exit__(self, *exc):
        return self._ctx.__exit__(*exc)


def _positive(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None


def _layers(text: str) -> int:
    """A number of hp layers: an integer from 0 to the most the hp meshes allow."""
    from ..core.options import HP_MAX_LAYERS

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number of layers") from None
    if not 0 <= value <= HP_MAX_LAYERS:
        raise argparse.ArgumentTypeError(f"{text!r}: the number of layers must be an integer in 0..{HP_MAX_LAYERS}")
    return value


def _count(text: str) -> int:
    """A number of unknowns: a whole number, also written like 2e6."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if not (math.isfinite(value) and value >= 1):
        raise argparse.ArgumentTypeError(f"{text!r}: must be a number of unknowns >= 1")
    if value != math.floor(value):
        raise argparse.ArgumentTypeError(f"{text!r}: must be a whole number of unknowns")
    return int(value)


class _Parser(argparse.ArgumentParser):
    """argparse with its errors on one line (the usage is one `--help` away)."""

    def error(self, message: str):
        self.exit(EXIT_INPUT, f"{self.prog}: error: {one_line(message)} (see {self.prog} --help)\n" if first_rank() else None)


MAX_DOF_HELP = ("largest number of unknowns a solve may have; a request estimated above it is refused before "
                "meshing (default: 5e6 and what fits in the available memory); with --adapt also the budget of "
                "the refinement (default 2e5)")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="ngcrack", description="Cracked elastic bodies with unilateral crack contact (NGSolve).")
    parser.add_argument("--debug", action="store_true",
                        help="on an error, print the traceback too (also accepted after the command)")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("scenes", help="list the built-in scenes and the scene functions with their parameters")
    p.set_defaults(func=cmd_scenes)
    p = sub.add_parser("solve", help="solve one scene")
    p.add_argument("scene", help="built-in scene name or TOML file")
    p.add_argument("--element", default=None,
                   help="tdnns (default), bdm, peers, h1p1 or h1p2 (README: \"Which element when\")")
    p.add_argument("--order", type=int, help="polynomial order of elements that have one (bdm, tdnns: 1, 2 or 3)")
    p.add_argument("--maxh", type=_positive, help="global mesh size (overrides the scene)")
    p.add_argument("--tip-h", dest="tip_h", type=_positive, help="mesh size at crack tips")
    p.add_argument("--crack-h", dest="crack_h", type=_positive, help="mesh size along cracks")
    p.add_argument("--front-h", dest="front_h", type=_positive, help="mesh size at crack fronts (3D scenes)")
    p.add_argument("--accuracy", type=_positive, metavar="E",
                   help="relative error of K asked for along the crack fronts, in [0.005, 0.5]: sets --front-h and "
                        "--crack-h (3D scenes; in 2D use --adapt)")
    p.add_argument("--hp", type=_layers, metavar="L",
                   help="L layers of geometric refinement (ratio 0.2) towards every crack tip; with --order 2 or 3")
    p.add_argument("--nu", type=_positive, help="Poisson ratio (overrides the scene)")
    p.add_argument("--E", type=_positive, help="Young's modulus (overrides the scene)")
    p.add_argument("--friction", type=_positive, metavar="MU",
                   help="Coulomb friction coefficient of every crack (overrides the scene; 0: frictionless)")
    p.add_argument("--qp-solver", dest="qp_solver", help="pdas (default), uzawa, clarabel, osqp, scs, ...")
    p.add_argument("--crack-model", dest="crack_model", default="contact", help="contact (default), free or bonded")
    p.add_argument("--adapt", type=_positive, metavar="TOL",
                   help="refine adaptively until the relative error estimate is <= TOL, in (0, 1)")
    p.add_argument("--json", help="write the result to this JSON file: scene, element, maxh, nu, E, ndof, time_s, "
                                  "kkt, kkt_sampled, tips, error_estimate, adapt (with --adapt), distributed "
                                  "(under mpiexec) and one crack profile per crack (README: \"Command line\")")
    p.add_argument("--plot", help="write a PNG with isolines of sigma_nu and the deformed body")
    p.add_argument("--vtk", metavar="OUT", help="write ParaView files: OUT.vtu (mesh and fields), OUT_cracks.vtu (crack faces)")
    p.add_argument("--max-dof", dest="max_dof", type=_count, help=MAX_DOF_HELP)
    p.add_argument("--no-estimate", dest="estimate", action="store_false", default=None,
                   help="skip the error estimate (about a third of a 3D solve's CPU); the JSON then has no error_estimate")
    p.set_defaults(func=cmd_solve)

    def parallel(p):
        p.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
        p.add_argument("--dask", metavar="ADDRESS", help="run on a dask.distributed scheduler at ADDRESS")
        p.add_argument("--no-progress", dest="no_progress", action="store_true", help="no progress bar")

    p = sub.add_parser("sweep", help="solve every (element, maxh, nu); errors, rates, timings; CSV row by row")
    p.add_argument("scene", help="built-in scene name or TOML file")
    p.add_argument("--element", nargs="+", default=None,
                   help="element families (default tdnns; see `solve --element`)")
    p.add_argument("--maxh", nargs="+", type=_positive, help="global mesh sizes (with --adapt: the first mesh's)")
    p.add_argument("--adapt", nargs="+", type=_positive, metavar="TOL",
                   help="adaptive runs to these relative error estimates, in (0, 1), instead of mesh sizes")
    p.add_argument("--nu", nargs="+", type=_positive, help="Poisson ratios (default: the scene's)")
    p.add_argument("--friction", nargs="+", type=_positive, metavar="MU",
                   help="Coulomb coefficients, each on every crack (default: the scene's); a key column of the rows")
    p.add_argument("--out", required=True, help="CSV file; rerunning skips the rows already in it")
    p.add_argument("--vtk", metavar="OUT", help="ParaView: OUT_<scene>-<element>-h<maxh>-nu<nu>.vtu (and _cracks.vtu) "
                                                "per run, and their collection OUT.pvd")
    p.add_argument("--reference-maxh", dest="reference_maxh", type=_positive,
                   help="mesh size of a separate reference run (default: the finest --maxh is the reference)")
    p.add_argument("--reference-element", dest="reference_element",
                   help="measure every element against this element's reference (default: each its own)")
    p.add_argument("--tip-h", dest="tip_h", type=_positive, help="mesh size at crack tips")
    p.add_argument("--crack-h", dest="crack_h", type=_positive, help="mesh size along cracks")
    p.add_argument("--front-h", dest="front_h", nargs="+", type=_positive,
                   help="a 3D scene's front mesh sizes to sweep (instead of --maxh)")
    p.add_argument("--grading", type=_positive, help="mesh grading in (0, 1]")
    p.add_argument("--qp-solver", dest="qp_solver", help="the crack QP's solver (default: solve's default)")
    p.add_argument("--crack-model", dest="crack_model", default="contact", help="contact (default), free or bonded")
    p.add_argument("--max-dof", dest="max_dof", type=_count, help=MAX_DOF_HELP + "; checked for every case before any run")
    parallel(p)
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("paper", help="reproduce the paper's study: tables, convergence and isoline figures")
    p.add_argument("--quick", action="store_true", help="the small study (about 70 CPU seconds)")
    p.add_argument("--out", default="paper-results", help="output folder (default paper-results)")
    p.add_argument("--element", nargs="+", help="elements (default: every mixed element)")
    p.add_argument("--maxh", nargs="+", type=_positive, help="override the study's mesh sizes")
    p.add_argument("--reference-maxh", dest="reference_maxh", type=_positive, help="override the reference mesh size")
    parallel(p)
    p.set_defaults(func=cmd_paper)

    p = sub.add_parser("stability", help="locking against nu, scaling laws, extreme geometry: tables and plots")
    p.add_argument("--quick", action="store_true", help="the small study (about a minute and a half on 2 cores)")
    p.add_argument("--out", default="stability-results", help="output folder (default stability-results)")
    p.set_defaults(func=cmd_stability)

    from ..studies.growth.cli import add_parser as add_grow_parser

    add_grow_parser(sub, _positive, _count)
    from ..studies.hydrofrac.cli import add_parser as add_hydrofrac_parser

    add_hydrofrac_parser(sub, _positive, _count)
    return parser


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    argv = [str(a) for a in argv]
    debug = "--debug" in argv
    argv = [a for a in argv if a != "--debug"]
    if next((a for a in argv if not a.startswith("-")), None) in SOLVING:  # before the parser loads numpy
        try:
            _check_address_space()
        except NotSolvedError as exc:
            print(f"ngcrack: error: {exc}", file=sys.stderr)
            return EXIT_SOLVE
    parser = build_parser()
    args = parser.parse_args(argv)
    shown = warnings.showwarning
    warnings.showwarning = one_line_warning
    args.on_interrupt = None  # a command may set it: signum -> the note of what it wrote, called once

    def farewell(signum: int) -> str:  # the watcher ends the process (the main thread is in a long C call)
        if not first_rank():  # under mpiexec rank 0 says it, once
            return ""
        note = None
        if args.on_interrupt is not None:
            try:
                note = args.on_interrupt(signum)
            except Exception:  # noqa: BLE001 -- the line is printed regardless
                note = None
        return interrupted_line(args.command, signum, note)

    with Interrupts(farewell) as interrupts:
        try:
            code = _run(args, interrupts, debug)
            from ..distributed.world import same_exit

            return same_exit(code)  # under mpiexec every rank ends as rank 0 did
        except KeyboardInterrupt as exc:  # a rank of mpiexec waiting for rank 0's end: quietly, rank 0 says it
            return 128 + (signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT)
        finally:
            warnings.showwarning = shown


def _run(args, interrupts: Interrupts, debug: bool) -> int:
    """The command of `args`, every error and interruption turned into one line and an exit code."""
    try:
        code = args.func(args)
        check_interrupt()  # a signal swallowed on the way (a library turned it into nothing)
        sys.stdout.flush()  # a closed pipe shows here, inside the handling below
        return code
    except KeyboardInterrupt as exc:
        signum = signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT
        return report_interrupted(args, interrupts, signum, exc)
    except BrokenPipeError:  # the reader of stdout went away (| head): stop quietly, as a shell tool does
        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):
            pass
        return 128 + signal.SIGPIPE
    except Exception as exc:  # noqa: BLE001 -- every error becomes one line and an exit code
        if interrupts.signum is not None:  # the signal came back as a library's exception
            return report_interrupted(args, interrupts, interrupts.signum, exc)
        code, message = classify(exc, args.command)
        if debug:
            traceback.print_exc()
        if code != EXIT_INPUT or first_rank():  # bad input: every rank of mpiexec finds it alike, one line
            print(f"ngcrack: error: {message}", file=sys.stderr)
        return code


if __name__ == "__main__":
    sys.exit(main())
