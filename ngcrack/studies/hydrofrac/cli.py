"""`ngcrack hydrofrac SCENE --rate Q0 --K-Ic K --da D --steps N --json OUT [--csv OUT] [--gif OUT]
[--crack I] [--injection X Y] [solve options]`: grow a fluid-driven crack and write the result."""

from __future__ import annotations

from ngcrack.shell.cli_runs import add_mesh_options, add_run_options


def add_parser(subparsers, positive, count):
    """Register `hydrofrac` on the ngcrack command's subparsers (`positive`, `count`: its number parsers)."""
    p = subparsers.add_parser("hydrofrac", help="hydraulic fracture, toughness-dominated (uniform fluid pressure): "
                                                "time, pressure, opening and path; JSON, CSV, GIF")
    p.add_argument("scene", help="built-in scene name or TOML file (its loads are the in-situ stress)")
    p.add_argument("--rate", required=True, type=positive, help="injection rate Q0 (area per unit time, per unit "
                                                                 "thickness)")
    p.add_argument("--K-Ic", dest="K_Ic", required=True, type=positive, help="fracture toughness")
    p.add_argument("--da", required=True, type=positive, help="growth of each tip per step")
    p.add_argument("--steps", required=True, type=int, help="number of growth steps")
    p.add_argument("--crack", type=int, default=0, help="index of the fluid-driven crack (default 0)")
    p.add_argument("--injection", nargs=2, type=float, metavar=("X", "Y"),
                   help="injection point on the crack (default: its centre)")
    add_mesh_options(p, positive)
    add_run_options(p, count, "contact (default) or free", "scene, element, rate, K_Ic, stopped, steps (with their "
                    "tips) and the final cracks", "the opening crack")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    from ngcrack import scenes
    from ngcrack.core.options import SolveOptions
    from ngcrack.shell.cli_errors import check_finite
    from ngcrack.shell.cli_runs import Finished, output_paths, run_until_signal, solve_options, write_all
    from ngcrack.shell.files import check_distinct
    from ngcrack.shell.interrupts import check as check_interrupt

    from .loop import check_hydrofrac_options, hydrofrac

    paths = output_paths(args, "json", "csv", "gif")
    json_path, csv_path, gif_path = paths.values()
    check_distinct({f"--{name}": path for name, path in paths.items()})
    scene = scenes.resolve(args.scene)
    options = solve_options(args, "element", "order", "maxh", "tip_h", "crack_h", "crack_model", "max_dof")
    # before any work: the run's own options, then the solve options
    check_hydrofrac_options(scene, args.rate, args.K_Ic, args.da, args.steps, args.crack, args.injection, options)
    SolveOptions.of(**options).check_for(scene)
    finished = Finished(json_path, csv_path, args.steps)
    args.on_interrupt = finished.write  # the command line calls it if a signal ends the run in a long C call

    def progress(n, result):
        table = result.table
        finished.keep(result.to_json_dict(), lambda tmp: table.to_csv(tmp, index=False))
        s = result.steps[-1]
        print(f"step {n}: t {s['time']:.4g}, half-length {s['half_length']:.4g}, pressure {s['pressure']:.4g}, "
              f"{s['ndof']} dofs, {s['time_s']:.2f} s", flush=True)
        check_interrupt()  # a signal a library swallowed during the step

    def work():
        result = hydrofrac(scene, args.rate, args.K_Ic, args.da, args.steps, crack=args.crack,
                           injection=args.injection, progress=progress, **options)
        data = result.to_json_dict()
        check_finite(data)
        check_interrupt()
        return write_all(result, data, scene, json_path,
                         [(csv_path, lambda tmp: result.table.to_csv(tmp, index=False)),
                          (gif_path, lambda tmp: result.animate(tmp))])

    return run_until_signal(work, finished)
