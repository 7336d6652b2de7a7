"""`ngcrack grow SCENE --da D --steps N [--K-Ic K] [--criterion pls|mts|gmts [--r-c R]] [solve options] --json OUT
[--csv OUT] [--gif OUT] [--png OUT]`: grow the scene's cracks and write the result."""

from __future__ import annotations

import json
import signal
import threading

from ngcrack.cli_errors import Terminated, check_finite
from ngcrack.files import Staged, check_distinct, check_output, check_output_stem
from ngcrack.interrupts import check as check_interrupt
from ngcrack.interrupts import interruption, pending


def _at_hole(text: str):
    """--at-hole: "stop" or a length (grow checks the value)."""
    if text == "stop":
        return text
    try:
        return float(text)
    except ValueError:
        return text  # grow refuses it, naming at_hole and the allowed values


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
    p.add_argument("--element", default=None, help="tdnns (default), bdm, peers, h1p1 or h1p2")
    p.add_argument("--order", type=int, help="polynomial order of elements that have one")
    p.add_argument("--maxh", type=positive, help="global mesh size (overrides the scene)")
    p.add_argument("--tip-h", dest="tip_h", type=positive, help="mesh size at the crack tips")
    p.add_argument("--crack-h", dest="crack_h", type=positive, help="mesh size along the cracks")
    p.add_argument("--nu", type=positive, help="Poisson ratio (overrides the scene)")
    p.add_argument("--E", type=positive, help="Young's modulus (overrides the scene)")
    p.add_argument("--friction", type=positive, metavar="MU", help="Coulomb coefficient of every crack")
    p.add_argument("--qp-solver", dest="qp_solver", help="the crack QP's solver (default: solve's)")
    p.add_argument("--crack-model", dest="crack_model", default="contact", help="contact (default), free or bonded")
    p.add_argument("--max-dof", dest="max_dof", type=count, help="largest number of unknowns of each solve")
    p.add_argument("--json", required=True, help="write the result here: scene, element, criterion, da, K_Ic, "
                                                 "stopped, steps (with their tips) and the final cracks")
    p.add_argument("--csv", help="write the table (one row per step and tip) here")
    p.add_argument("--gif", help="write an animation of the deformed body and the crack faces here")
    p.add_argument("--png", help="write the paths and the load factors against crack length here")
    p.add_argument("--vtk", metavar="OUT", help="ParaView: OUT_NNNN.vtu and OUT_NNNN_cracks.vtu per step, written as "
                                                "the steps finish, and their collection OUT.pvd")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    from ngcrack import scenes

    from .criteria import check_r_c
    from .loop import MAX_STEPS, check_growth_options, grow

    json_path = check_output(args.json, "--json")
    csv_path = check_output(args.csv, "--csv", ".csv")
    gif_path = check_output(args.gif, "--gif", ".gif")
    png_path = check_output(args.png, "--png", ".png")
    steps = args.steps if isinstance(args.steps, int) and 0 <= args.steps <= MAX_STEPS else 0
    stem = check_output_stem(args.vtk, "--vtk", [".pvd"] + [f"_{k:04d}{part}" for k in range(steps + 1)
                                                           for part in (".vtu", "_cracks.vtu")])
    check_distinct({"--json": json_path, "--csv": csv_path, "--gif": gif_path, "--png": png_path,
                    "--vtk": None if stem is None else [stem.with_name(stem.name + ".pvd")] + [
                        stem.with_name(f"{stem.name}_{k:04d}{part}") for k in range(steps + 1)
                        for part in (".vtu", "_cracks.vtu")]})
    series = None
    if stem is not None:
        from ngcrack.extras import require
        from ngcrack.vtk import SeriesWriter

        require("meshio", "--vtk")
        series = SeriesWriter(stem)  # its stale step files go when it writes the first step
    from ngcrack.sweeps import check_friction_applies

    check_friction_applies(args.friction, args.crack_model, "--friction")  # as solve refuses it
    scene = scenes.resolve(args.scene)
    changes = {k: v for k, v in (("nu", args.nu), ("E", args.E), ("friction", args.friction)) if v is not None}
    if changes:
        scene = scene.with_(**changes)
    options = {k: v for k, v in (("element", args.element), ("order", args.order), ("maxh", args.maxh),
                                 ("tip_h", args.tip_h), ("crack_h", args.crack_h), ("qp_solver", args.qp_solver),
                                 ("crack_model", args.crack_model), ("max_dof", args.max_dof)) if v is not None}
    check_growth_options(scene, args.da, args.steps, args.K_Ic, args.criterion, options)  # before any work
    check_r_c(args.r_c, args.criterion)

    finished = _Finished(json_path, csv_path, series, args.steps, [p for p in (png_path, gif_path) if p is not None])
    args.on_interrupt = finished.write  # the command line calls it if a signal ends the run in a long C call

    def progress(n, result):
        finished.keep(result)
        step = result.steps[-1]
        lam = step["load_factor"]
        print(f"step {n}: load factor {lam:.4g}, {step['ndof']} dofs, {step['time_s']:.2f} s"
              if lam is not None else f"step {n}", flush=True)
        if series is not None:
            series(n, result)  # the step's solution, and the collection rewritten: a valid series at every step
        check_interrupt()  # a signal a library swallowed during the step

    try:
        result = grow(scene, args.da, args.steps, K_Ic=args.K_Ic, criterion=args.criterion, r_c=args.r_c,
                      at_hole=args.at_hole, frames=gif_path is not None, progress=progress, **options)
        data = result.to_json_dict()
        check_finite(data)
        check_interrupt()
        return _write_all(result, data, scene, json_path, csv_path, png_path, gif_path, series)
    except BaseException as exc:
        signum = pending()
        if isinstance(exc, KeyboardInterrupt) or signum is not None:
            signum = signum or (signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT)
            stop = interruption(signum)
            stop.note = finished.write(signum)
            raise stop from exc
        raise


class _Finished:
    """The steps a run has finished, written (JSON and CSV, marked interrupted) if a signal stops it."""

    def __init__(self, json_path, csv_path, series, steps, skipped):
        self.json_path, self.csv_path, self.series, self.steps, self.skipped = json_path, csv_path, series, steps, skipped
        self.data, self.rows = None, None
        self.note = None
        self.lock = threading.Lock()

    def keep(self, result) -> None:
        data = result.to_json_dict()
        data["steps"] = list(data["steps"])
        self.data, self.rows = data, list(result.rows)  # one assignment each: a whole snapshot or the previous

    def write(self, signum) -> str:
        """Write the finished steps (once; a second caller gets the first's note); the note says what was written."""
        if not self.lock.acquire(timeout=0.5):
            return "the finished steps were being written when the process ended; their files are whole or absent"
        try:
            if self.note is None:
                self.note = self._write(signum)
            return self.note
        finally:
            self.lock.release()

    def _write(self, signum) -> str:
        import pandas as pd

        from .result import COLUMNS

        vtk = (f"; the VTK series {self.series.collection} holds the {len(self.series.files)} steps written"
               if self.series is not None and self.series.files else "")
        if self.data is None:
            return "no step had finished, nothing was written" + vtk
        data = dict(self.data)
        done = len(data["steps"])
        what = "SIGTERM" if signum == signal.SIGTERM else "SIGINT"
        data["stopped"] = f"interrupted: {what} after step {done - 1} of {self.steps}; the finished steps are kept"
        try:
            check_finite(data)
            with Staged() as staged:
                staged.write(self.json_path, lambda tmp: _dump(data, tmp))
                if self.csv_path is not None:
                    staged.write(self.csv_path, lambda tmp: pd.DataFrame(self.rows, columns=list(COLUMNS)).to_csv(
                        tmp, index=False))
        except Exception as exc:  # noqa: BLE001 -- the interruption is what is reported
            return f"the finished steps could not be written ({type(exc).__name__}: {exc}), nothing was written" + vtk
        files = " and ".join(str(p) for p in (self.json_path, self.csv_path) if p is not None)
        skipped = (f"; not written: {', '.join(str(p) for p in self.skipped)}" if self.skipped else "")
        return (f"wrote {files} with the {done} finished steps, marked \"stopped\": \"interrupted: ...\"" + skipped
                + vtk)


def _dump(data, tmp) -> None:
    with open(tmp, "w") as fh:
        json.dump(data, fh, indent=1)


def _write_all(result, data, scene, json_path, csv_path, png_path, gif_path, series) -> int:
    written = [json_path]
    with Staged() as staged:  # every output or none; existing files untouched on failure
        staged.write(json_path, lambda tmp: _dump(data, tmp))
        if csv_path is not None:
            staged.write(csv_path, lambda tmp: result.table.to_csv(tmp, index=False))
            written.append(csv_path)
        if png_path is not None:
            staged.write(png_path, lambda tmp: result.plot(tmp))
            written.append(png_path)
        if gif_path is not None:
            staged.write(gif_path, lambda tmp: result.animate(tmp))
            written.append(gif_path)
    print(f"{scene.name}: {len(result.steps)} steps, stopped: {result.stopped}")
    if series is not None:
        written.append(series.collection)
    for path in written:
        print(f"wrote {path}")
    return 0
