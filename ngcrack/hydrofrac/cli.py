"""`ngcrack hydrofrac SCENE --rate Q0 --K-Ic K --da D --steps N --json OUT [--csv OUT] [--gif OUT]
[--crack I] [--injection X Y] [solve options]`: grow a fluid-driven crack and write the result."""

from __future__ import annotations

import json
import signal
import threading


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
    p.add_argument("--element", default=None, help="tdnns (default), bdm, peers, h1p1 or h1p2")
    p.add_argument("--order", type=int, help="polynomial order of elements that have one")
    p.add_argument("--maxh", type=positive, help="global mesh size (overrides the scene)")
    p.add_argument("--tip-h", dest="tip_h", type=positive, help="mesh size at the crack tips")
    p.add_argument("--crack-h", dest="crack_h", type=positive, help="mesh size along the cracks")
    p.add_argument("--crack-model", dest="crack_model", default="contact", help="contact (default) or free")
    p.add_argument("--max-dof", dest="max_dof", type=count, help="largest number of unknowns of each solve")
    p.add_argument("--json", required=True, help="write the result here: scene, element, rate, K_Ic, stopped, "
                                                 "steps (with their tips) and the final cracks")
    p.add_argument("--csv", help="write the table (one row per step and tip) here")
    p.add_argument("--gif", help="write an animation of the opening crack here")
    p.set_defaults(func=run)
    return p


def run(args) -> int:
    from ngcrack import scenes
    from ngcrack.cli_errors import Terminated, check_finite
    from ngcrack.files import check_distinct, check_output
    from ngcrack.interrupts import check as check_interrupt
    from ngcrack.interrupts import interruption, pending
    from ngcrack.options import SolveOptions

    from .loop import check_hydrofrac_options, hydrofrac

    json_path = check_output(args.json, "--json")
    csv_path = check_output(args.csv, "--csv", ".csv")
    gif_path = check_output(args.gif, "--gif", ".gif")
    check_distinct({"--json": json_path, "--csv": csv_path, "--gif": gif_path})
    scene = scenes.resolve(args.scene)
    options = {k: v for k, v in (("element", args.element), ("order", args.order), ("maxh", args.maxh),
                                 ("tip_h", args.tip_h), ("crack_h", args.crack_h),
                                 ("crack_model", args.crack_model), ("max_dof", args.max_dof)) if v is not None}
    # before any work: the run's own options, then the solve options
    check_hydrofrac_options(scene, args.rate, args.K_Ic, args.da, args.steps, args.crack, args.injection, options)
    SolveOptions.of(**options).check_for(scene)
    finished = _Finished(json_path, csv_path, args.steps)
    args.on_interrupt = finished.write  # the command line calls it if a signal ends the run in a long C call

    def progress(n, result):
        finished.keep(result)
        s = result.steps[-1]
        print(f"step {n}: t {s['time']:.4g}, half-length {s['half_length']:.4g}, pressure {s['pressure']:.4g}, "
              f"{s['ndof']} dofs, {s['time_s']:.2f} s", flush=True)
        check_interrupt()  # a signal a library swallowed during the step

    try:
        result = hydrofrac(scene, args.rate, args.K_Ic, args.da, args.steps, crack=args.crack,
                           injection=args.injection, progress=progress, **options)
        data = result.to_json_dict()
        check_finite(data)
        check_interrupt()
        return _write_all(result, data, scene, json_path, csv_path, gif_path)
    except BaseException as exc:
        signum = pending()
        if isinstance(exc, KeyboardInterrupt) or signum is not None:
            signum = signum or (signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT)
            stop = interruption(signum)
            stop.note = finished.write(signum)
            raise stop from exc
        raise


def _write_all(result, data, scene, json_path, csv_path, gif_path) -> int:
    from ngcrack.files import Staged

    written = [json_path]
    with Staged() as staged:  # every output or none; existing files untouched on failure
        staged.write(json_path, lambda tmp: _dump(data, tmp))
        if csv_path is not None:
            staged.write(csv_path, lambda tmp: result.table.to_csv(tmp, index=False))
            written.append(csv_path)
        if gif_path is not None:
            staged.write(gif_path, lambda tmp: result.animate(tmp))
            written.append(gif_path)
    print(f"{scene.name}: {len(result.steps)} steps, stopped: {result.stopped}")
    for path in written:
        print(f"wrote {path}")
    return 0


def _dump(data, tmp) -> None:
    with open(tmp, "w") as fh:
        json.dump(data, fh, indent=1)


class _Finished:
    """The steps a run has finished, written (JSON and CSV, marked interrupted) if a signal stops it."""

    def __init__(self, json_path, csv_path, steps):
        self.json_path, self.csv_path, self.steps = json_path, csv_path, steps
        self.data, self.table = None, None
        self.note = None
        self.lock = threading.Lock()

    def keep(self, result) -> None:
        data = result.to_json_dict()
        self.data, self.table = data, result.table  # one assignment each: a whole snapshot or the previous

    def write(self, signum) -> str:
        """Write the finished steps (once); the note says what was written."""
        if not self.lock.acquire(timeout=0.5):
            return "the finished steps were being written when the process ended; their files are whole or absent"
        try:
            if self.note is None:
                self.note = self._write(signum)
            return self.note
        finally:
            self.lock.release()

    def _write(self, signum) -> str:
        from ngcrack.cli_errors import check_finite
        from ngcrack.files import Staged

        if self.data is None:
            return "no step had finished, nothing was written"
        data = dict(self.data)
        done = len(data["steps"])
        what = "SIGTERM" if signum == signal.SIGTERM else "SIGINT"
        data["stopped"] = f"interrupted: {what} after step {done - 1} of {self.steps}; the finished steps are kept"
        try:
            check_finite(data)
            with Staged() as staged:
                staged.write(self.json_path, lambda tmp: _dump(data, tmp))
                if self.csv_path is not None:
                    staged.write(self.csv_path, lambda tmp: self.table.to_csv(tmp, index=False))
        except Exception as exc:  # noqa: BLE001 -- the interruption is what is reported
            return f"the finished steps could not be written ({type(exc).__name__}: {exc}), nothing was written"
        files = " and ".join(str(p) for p in (self.json_path, self.csv_path) if p is not None)
        return f"wrote {files} with the {done} finished steps, marked \"stopped\": \"interrupted: ...\""
