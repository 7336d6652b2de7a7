"""`ngcrack grow SCENE --da D --steps N [--K-Ic K] [--paris C m [DK_TH]] [--R R] [--criterion pls|mts|gmts [--r-c R]]
[solve options] --json OUT [--csv OUT] [--gif OUT] [--png OUT]`: grow the scene's cracks and write the result.

A 3D scene grows its fronts in their planes (loop3d.py; `--front-h` sets the mesh size at the fronts, `--accuracy`
the error of K asked for along them (each step meshed for it), the
2D-only options and outputs are refused by name before any meshing); its JSON has the 2D keys and per step
`fronts` and, with --paris, `cycles`."""

from __future__ import annotations

from ngcrack.core.errors import InputError
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
    p.add_argument("--paris", nargs="+", type=float, metavar="NUM",
                   help="C m [DK_TH], fatigue: Paris's law da/dN = C Delta_K^m (C > 0, m > 0; DK_TH >= 0 a threshold); the scene's load "
                        "is the cycle's maximum, the JSON and CSV gain the cumulative cycles")
    p.add_argument("--R", dest="R", type=float, help="the load ratio K_min / K_max of a fatigue cycle (< 1; with --paris only)")
    p.add_argument("--corrector", action="store_true",
                   help="3D surface cracks: Heun's predictor-corrector step (two solves a step, second order in --da)")
    add_mesh_options(p, positive)
    p.add_argument("--front-h", dest="front_h", type=positive, help="mesh size at the crack fronts (3D scenes)")
    p.add_argument("--accuracy", type=positive, metavar="E",
                   help="relative error of K asked for along the crack fronts, in [0.005, 0.5]: sets each step's "
                        "front and crack mesh sizes (3D scenes; not with --front-h or --crack-h)")
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
    from .fatigue import check_paris
    from .loop import MAX_STEPS, check_growth_options, grow

    paths = output_paths(args, "json", "csv", "gif", "png")
    json_path, csv_path, gif_path, png_path = paths.values()
    paris, R = _paris(args)
    scene = scenes.resolve(args.scene)
    if scene.dimension == 3:
        return _run_solid(args, scene, paris, R, json_path, csv_path, png_path)
    if args.corrector:
        raise InputError(f"--corrector: an option of 3D growth (Heun's step of surface cracks); scene {scene.name!r} is 2D")
    if args.front_h is not None:
        raise InputError(f"--front-h: an option of 3D scenes (the mesh size at their crack fronts); scene {scene.name!r} "
                         f"is 2D: use --tip-h")
    if args.accuracy is not None:
        raise InputError(f"--accuracy: an option of 3D scenes (the error of K along their crack fronts); scene "
                         f"{scene.name!r} is 2D: use --tip-h")
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
    changes = {k: v for k, v in (("nu", args.nu), ("E", args.E), ("friction", args.friction)) if v is not None}
    if changes:
        scene = scene.with_(**changes)
    options = solve_options(args, "element", "order", "maxh", "tip_h", "crack_h", "qp_solver", "crack_model", "max_dof")
    if args.path_grading is not None:
        from ngcrack.planar.path_sizes import check_path_grading

        options["path_grading"] = None if args.path_grading == "none" else check_path_grading(args.path_grading)
    check_growth_options(scene, args.da, args.steps, args.K_Ic, args.criterion, options)  # before any work
    check_r_c(args.r_c, args.criterion)
    check_paris(paris, R)

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
                      at_hole=args.at_hole, frames=gif_path is not None, progress=progress, paris=paris, R=R, **options)
        data = result.to_json_dict()
        check_finite(data)
        check_interrupt()
        return write_all(result, data, scene, json_path,
                         [(csv_path, lambda tmp: result.table.to_csv(tmp, index=False)),
                          (png_path, lambda tmp: result.plot(tmp)), (gif_path, lambda tmp: result.animate(tmp))],
                         also=() if series is None else (series.collection,))

    return run_until_signal(work, finished)


def _rows_csv(rows, solid: bool = False):
    """A writer of the CSV table of a run's `rows` (the finished steps'; `solid`: of a 3D run)."""
    def write(tmp) -> None:
        import pandas as pd

        from .result import COLUMNS
        if solid:
            from .result3d import COLUMNS

        extra = ["cycles"] if rows and "cycles" in rows[0] else []
        pd.DataFrame(rows, columns=list(COLUMNS) + extra).to_csv(tmp, index=False)
    return write


def _paris(args):
    """(paris, R) from --paris and --R: the numbers as given (grow's checks name a bad one), R 0 without --R."""
    paris = args.paris
    if paris is not None and len(paris) not in (2, 3):
        raise InputError(f"--paris {' '.join(f'{v:g}' for v in paris)}: give C and m, and optionally the threshold DK_TH "
                         f"(2 or 3 numbers)")
    return (None if paris is None else tuple(paris)), (0.0 if args.R is None else args.R)


#: the options of `ngcrack grow` that only 2D scenes take (3D growth is planar, without holes or animations)
PLANAR_FLAGS = {"tip_h": "--tip-h (3D: --front-h)", "path_grading": "--path-grading", "r_c": "--r-c", "gif": "--gif",
                "vtk": "--vtk"}


def _run_solid(args, scene, paris, R, json_path, csv_path, png_path) -> int:
    """`ngcrack grow` on a 3D scene: planar growth of its fronts (loop3d.py)."""
    from .fronts3d import GROW_TOGETHER_RTOL
    from .loop3d import PLANAR_GROWTH_ONLY, check_solid_grow, grow_solid, planar_options

    for key, flag in PLANAR_FLAGS.items():
        if getattr(args, key) is not None:
            raise InputError(f"{flag}: an option of 2D growth; scene {scene.name!r} is 3D (planar growth of its fronts)")
    planar = planar_options(args.criterion, None, args.at_hole, False)
    if planar:
        key, value = next(iter(planar.items()))
        raise InputError(f"--{key.replace('_', '-')} {value}: an option of 2D growth; scene {scene.name!r} is 3D "
                         f"({PLANAR_GROWTH_ONLY[key]})")
    changes = {k: v for k, v in (("nu", args.nu), ("E", args.E), ("friction", args.friction)) if v is not None}
    if changes:
        scene = scene.with_(**changes)
    options = solve_options(args, "element", "order", "maxh", "crack_h", "front_h", "qp_solver", "crack_model", "max_dof",
                            "accuracy")
    check_solid_grow(scene, args.da, args.steps, args.K_Ic, paris, R, GROW_TOGETHER_RTOL, None, options, {})
    finished = Finished(json_path, csv_path, args.steps, [p for p in (png_path,) if p is not None])
    args.on_interrupt = finished.write

    def progress(n, result):
        finished.keep(result.to_json_dict(), _rows_csv(list(result.rows), solid=True))
        step = result.steps[-1]
        K = max(max(f["K_drive"]) for f in step["fronts"])
        size = ", ".join(f"{f['size']:.4g}" for f in step["fronts"])
        cycles = f", cycles {step['cycles']:.4g}" if "cycles" in step else ""
        for e in result.transitions:  # an embedded crack re-characterised as a surface crack this step
            if e["step"] == n:
                print(f"step {n}: {e['what']}", flush=True)
        print(f"step {n}: crack sizes {size}, max K_eq {K:.4g}{cycles}, {step['ndof']} dofs, {step['time_s']:.2f} s",
              flush=True)
        check_interrupt()

    def work():
        result = grow_solid(scene, args.da, args.steps, args.K_Ic, paris=paris, R=R, progress=progress,
                            corrector=args.corrector, **options)
        data = result.to_json_dict()
        check_finite(data)
        check_interrupt()
        return write_all(result, data, scene, json_path,
                         [(csv_path, lambda tmp: result.table.to_csv(tmp, index=False)),
                          (png_path, lambda tmp: result.plot(tmp))])

    return run_until_signal(work, finished)
