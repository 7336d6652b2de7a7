"""`ngcrack grow SCENE --da D --steps N [--K-Ic K] [--criterion pls|mts|gmts [--r-c R]] [solve options] --json OUT
[--csv OUT] [--gif OUT] [--png OUT]`: grow the scene's cracks and write the result."""

from __future__ import annotations

from ngcrack.shell.cli_errors import check_finite
from ngcrack.shell.cli_runs import Finished, add_mesh_options, add_run_options, output_paths, run_until_signal, solve_options, write_all
from ngcrack.shell.files import check_distinct, check_output_stem
from ngcrack.shell.interrupts import check as check_interrupt


def _at_hole(text: str):
    """--at-hole: "stop" or a length (grow checks the value)."""
    if text == "stop":
        return text
    try:
        return float(text)
    except ValueError:
        return text  # grow refuses it, naming at_hole and the allowed values


def _path_grading(text: str):
    """--path-grading: "none" (the path at crack_h) or a rate, a number; grow checks its range."""
    if text.lower() == "none":
        return "none"
    try:
        return float(text)
    except ValueError:
        return text  # refused before any work, naming path_grading and the allowed values


def add_parser(subparsers, positive, count):
    """Register `grow` on the ngcrack command's subparsers (`positive`, `count`: its number parsers)."""
    from .criteria import CRITERIA  # (a light module: the parser is built on every command, --help too)

    p = subparsers.add_parser("grow", help="grow the cracks quasi-statically (MTS or PLS kinks, load factors); JSON, CSV, GIF")
    p.add_argument("scene", help="built-in scene name or TOML file")
    p.add_argument("--da", required=True, type=positive, help="length of each growth segment")
    p.add_argument("--steps", required=True, type=int, help="number of growth steps (at least 1; the largest allowed is checked "
                                                                  "before any work)")
    p.add_argument("--K-Ic", dest="K_Ic", type=positive,
                   help="fracture toughness (default: load factors relative to the first step)")
    p.add_argument("--criterion", default="pls", help=f"kink criterion: {', '.join(CRITERIA)} (default pls)")
    p.add_argument("--r-c", dest="r_c", type=positive, help="the critical distance of --criterion gmts (a material length)")
    p.add_argument("--at-hole", dest="at_hole", default="stop", type=_at_hole, metavar="stop|LENGTH",
                   help="a tip that reaches a hole: stop there (default), or a new crack of LENGTH leaves the hole "
                        "where its hoop stress is largest")
    add_mesh_options(p, positive)
    p.add_argument("--path-grading", dest="path_grading", type=_path_grading, metavar="RATE|none",
                   help="the crack's mesh size grows from crack_h by RATE per unit distance from the crack ends "
                        "(default 0.1); none: crack_h all along the path")
    p.add_argument("--nu", type=positive, help="Poisson ratio (overrides the scene)")
    p.add_argument("--E", type=positive, help="Young's modulus (overrides the scene)")
    p.add_argument("--friction", type=positive, metavar="MU", help="Coulomb coefficient of every crack")
    p.add_argument("--qp-solver", dest="qp_solver", help="the crack QP's solver (default: solve's)")
    add_run_options(p, count, "contact (default), free or bonded", "scene, element, criterion, da, K_Ic, stopped, "
                    "steps (with their tips) and the final cracks", "the deformed body and the crack faces")
    p.add_argument("--png", help="write the paths and the load factors against crack length here")
    p.add_argument("--vtk", metavar="OUT", help="ParaView: OUT_NNNN.vtu and OUT_NNNN_cracks.vtu per step, written as "
                                                "the steps finish, and their collection OUT.pvd")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    from ngcrack import scenes

    from .criteria import check_r_c
    from .loop import MAX_STEPS, check_growth_options, grow

    paths = output_paths(args, "json", "csv", "gif", "png")
    json_path, csv_path, gif_path, png_path = paths.values()
    steps = args.steps if isinstance(args.steps, int) and 0 <= args.steps <= MAX_STEPS else 0
    stem = check_output_stem(args.vtk, "--vtk", [".pvd"] + [f"_{k:04d}{part}" for k in range(steps + 1)
                                                           for part in (".vtu", "_cracks.vtu")])
    check_distinct({"--json": json_path, "--csv": csv_path, "--gif": gif_path, "--png": png_path,
                    "--vtk": None if stem is None else [stem.with_name(stem.name + ".pvd")] + [
                        stem.with_name(f"{stem.name}_{k:04d}{part}") for k in range(steps + 1)
                        for part in (".vtu", "_cracks.vtu")]})
    series = None
    if stem is not None:
        from ngcrack.planar.vtk import SeriesWriter
        from ngcrack.shell.extras import require

        require("meshio", "--vtk")
        series = SeriesWriter(stem)  # its stale step files go when it writes the first step
    from ngcrack.core.friction_checks import check_friction_applies

    check_friction_applies(args.friction, args.crack_model, "--friction")  # as solve refuses it
    scene = scenes.resolve(args.scene)
    changes = {k: v for k, v in (("nu", args.nu), ("E", args.E), ("friction", args.friction)) if v is not None}
    if changes:
        scene = scene.with_(**changes)
    options = solve_options(args, "element", "order", "maxh", "tip_h", "crack_h", "qp_solver", "crack_model", "max_dof")
    if args.path_grading is not None:
        from ngcrack.planar.path_sizes import check_path_grading

        options["path_grading"] = None if args.path_grading == "none" else check_path_grading(args.path_grading)
    check_growth_options(scene, args.da, args.steps, args.K_Ic, args.criterion, options)  # before any work
    check_r_c(args.r_c, args.criterion)

    finished = Finished(json_path, csv_path, args.steps, [p for p in (png_path, gif_path) if p is not None], series)
    args.on_interrupt = finished.write  # the command line calls it if a signal ends the run in a long C call

    def progress(n, result):
        data = result.to_json_dict()
        data["steps"] = list(data["steps"])
        finished.keep(data, _rows_csv(list(result.rows)))
        step = result.steps[-1]
        lam = step["load_factor"]
        print(f"step {n}: load factor {lam:.4g}, {step['ndof']} dofs, {step['time_s']:.2f} s"
              if lam is not None else f"step {n}", flush=True)
        if series is not None:
            series(n, result)  # the step's solution, and the collection rewritten: a valid series at every step
        check_interrupt()  # a signal a library swallowed during the step

    def work():
        result = grow(scene, args.da, args.steps, K_Ic=args.K_Ic, criterion=args.criterion, r_c=args.r_c,
                      at_hole=args.at_hole, frames=gif_path is not None, progress=progress, **options)
        data = result.to_json_dict()
        check_finite(data)
        check_interrupt()
        return write_all(result, data, scene, json_path,
                         [(csv_path, lambda tmp: result.table.to_csv(tmp, index=False)),
                          (png_path, lambda tmp: result.plot(tmp)), (gif_path, lambda tmp: result.animate(tmp))],
                         also=() if series is None else (series.collection,))

    return run_until_signal(work, finished)


def _rows_csv(rows):
    """A writer of the CSV table of a run's `rows` (the finished steps')."""
    def write(tmp) -> None:
        import pandas as pd

        from .result import COLUMNS

        pd.DataFrame(rows, columns=list(COLUMNS)).to_csv(tmp, index=False)
    return write
