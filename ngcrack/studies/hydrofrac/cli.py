"""`ngcrack hydrofrac SCENE (--rate Q0 | --schedule FILE) --K-Ic K (--da D --steps N | [--da D] --time T)
[--viscosity MU [--leakoff C_L] [--inviscid]] --json OUT [--csv OUT] [--gif OUT] [--crack I]
[--injection X Y] [solve options]`: grow a fluid-driven crack and write the result (`--crack I J ...`:
several cracks fed from one injection at one pressure, `multi.py`). A 3D scene: a radial fracture of a
disc crack fed at its centre (`radial.py`, with --viscosity `radial_viscous.py`; --front-h, no --injection)."""

from __future__ import annotations

from ngcrack.shell.cli_runs import add_mesh_options, add_run_options


def add_parser(subparsers, positive, count):
    """Register `hydrofrac` on the ngcrack command's subparsers (`positive`, `count`: its number parsers)."""
    p = subparsers.add_parser("hydrofrac", help="hydraulic fracture: an inviscid fluid (uniform pressure, "
                                                "toughness-dominated) or a viscous one (--viscosity): time, pressure, "
                                                "opening and path; 3D scenes: a radial fracture of a disc crack "
                                                "(inviscid, or viscous with --viscosity); JSON, CSV, GIF")
    p.add_argument("scene", help="built-in scene name or TOML file (its loads are the in-situ stress)")
    p.add_argument("--rate", type=positive, help="injection rate Q0 (area per unit time, per unit thickness)")
    p.add_argument("--schedule", metavar="FILE", help="injection rates against time instead of --rate: lines 't rate' "
                                                      "from t = 0 (a rate holds until the next line; 0 is a shut-in)")
    p.add_argument("--K-Ic", dest="K_Ic", required=True, type=positive, help="fracture toughness")
    p.add_argument("--da", type=positive, help="growth of each tip per step (default with --time: a tenth of the "
                                               "crack's initial half-length)")
    p.add_argument("--steps", type=int, help="number of growth steps (or --time)")
    p.add_argument("--time", dest="end_time", type=positive, metavar="T", help="end the run at the first step at or "
                                                                              "past time T")
    p.add_argument("--viscosity", type=positive, metavar="MU", help="the fluid's viscosity (Pa s): lubrication flow "
                                                                   "along the crack (default: inviscid)")
    p.add_argument("--leakoff", type=float, default=0.0, metavar="C_L", help="Carter's leak-off coefficient "
                                                                             "(with --viscosity)")
    p.add_argument("--inviscid", action="store_true", help="the uniform-pressure model even with --viscosity "
                                                           "(K_m recorded; a warning where K_m < 4)")
    p.add_argument("--crack", type=int, nargs="+", default=[0], help="index of the fluid-driven crack (default 0); "
                                                                    "several indices: cracks fed from one injection at "
                                                                    "one pressure, each at its centre (inviscid)")
    p.add_argument("--injection", nargs=2, type=float, metavar=("X", "Y"),
                   help="injection point on the crack (default: its centre; 3D: always the disc's centre)")
    add_mesh_options(p, positive)
    p.add_argument("--front-h", dest="front_h", type=positive, help="3D: the mesh size at the disc's front (it and "
                                                                    "--crack-h scale with the radius)")
    add_run_options(p, count, "contact (default) or free", "scene, element, rate, K_Ic, stopped, steps (with their "
                    "tips, K_m, efficiency and the fluid's profile), the final cracks, model, viscosity, leakoff, K_m",
                    "the opening crack")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    import warnings

    from ngcrack import scenes
    from ngcrack.core.errors import InputError
    from ngcrack.shell.cli_errors import check_finite
    from ngcrack.shell.cli_runs import Finished, output_paths, run_until_signal, solve_options, write_all
    from ngcrack.shell.files import check_distinct
    from ngcrack.shell.interrupts import check as check_interrupt

    from .loop import MAX_STEPS
    from .run import RegimeWarning, check_run, default_da, hydrofrac, read_schedule

    if isinstance(args.crack, list):  # one index, or several cracks fed from one injection
        args.crack = args.crack[0] if len(args.crack) == 1 else args.crack
    paths = output_paths(args, "json", "csv", "gif")
    json_path, csv_path, gif_path = paths.values()
    check_distinct({f"--{name}": path for name, path in paths.items()})
    schedule = read_schedule(args.schedule) if args.schedule is not None else None
    scene = scenes.resolve(args.scene)
    options = solve_options(args, "element", "order", "maxh", "tip_h", "crack_h", "front_h", "crack_model", "max_dof")
    # before any work: the run's own options, then the solve options
    if args.da is None:
        if args.end_time is None:
            raise InputError("--da: required (the growth of each tip per step), unless --time is given")
        args.da = default_da(scene, args.crack)
    check_run(scene, args.rate, args.K_Ic, args.da, args.steps, args.end_time, args.viscosity, args.leakoff, schedule,
              args.inviscid, args.crack, args.injection, options)
    finished = Finished(json_path, csv_path, args.steps or MAX_STEPS)
    args.on_interrupt = finished.write  # the command line calls it if a signal ends the run in a long C call

    def progress(n, result):
        table = result.table
        finished.keep(result.to_json_dict(), lambda tmp: table.to_csv(tmp, index=False))
        s = result.steps[-1]
        size = f"radius {s['radius']:.4g}" if "radius" in s else f"half-length {s['half_length']:.4g}"
        K_m = f", K_m {s['K_m']:.3g}" if "radius" in s and s["K_m"] is not None else ""  # the radial K_m grows with t
        print(f"step {n}: t {s['time']:.4g}, {size}, pressure {s['pressure']:.4g}{K_m}, {s['ndof']} dofs, "
              f"{s['time_s']:.2f} s CPU", flush=True)
        check_interrupt()  # a signal a library swallowed during the step

    def work():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", RegimeWarning)
            result = hydrofrac(scene, args.rate, args.K_Ic, args.da, args.steps, time=args.end_time,
                               viscosity=args.viscosity, leakoff=args.leakoff, schedule=schedule,
                               inviscid=args.inviscid, crack=args.crack, injection=args.injection,
                               progress=progress, **options)
        for w in caught:
            if issubclass(w.category, RegimeWarning):
                print(f"warning: {w.message}", flush=True)
        data = result.to_json_dict()
        check_finite(data)
        check_interrupt()
        return write_all(result, data, scene, json_path,
                         [(csv_path, lambda tmp: result.table.to_csv(tmp, index=False)),
                          (gif_path, lambda tmp: result.animate(tmp))])

    return run_until_signal(work, finished)
