"""What the stepping commands (`grow`, `hydrofrac`) share: their solve options and output checks, the finished
steps kept and written if a signal stops the run, every output written or none, and under mpiexec one rank
that runs the command (`runs_here`)."""

from __future__ import annotations

import json
import signal
import sys
import threading

from ngcrack.shell.cli_errors import Terminated, check_finite
from ngcrack.shell.files import Staged, check_output
from ngcrack.shell.interrupts import interruption, pending


def add_mesh_options(p, positive) -> None:
    """The element and mesh options of a stepping command."""
    p.add_argument("--element", default=None, help="tdnns (default), bdm, peers, h1p1 or h1p2")
    p.add_argument("--order", type=int, help="polynomial order of elements that have one")
    p.add_argument("--maxh", type=positive, help="global mesh size (overrides the scene)")
    p.add_argument("--tip-h", dest="tip_h", type=positive, help="mesh size at the crack tips")
    p.add_argument("--crack-h", dest="crack_h", type=positive, help="mesh size along the cracks")


def add_run_options(p, count, crack_models: str, json_fields: str, animation: str) -> None:
    """The crack model, the size budget and the outputs of a stepping command: `crack_models`
    the --crack-model help, `json_fields` what its JSON holds, `animation` what its GIF shows."""
    p.add_argument("--crack-model", dest="crack_model", default="contact", help=crack_models)
    p.add_argument("--max-dof", dest="max_dof", type=count, help="largest number of unknowns of each solve")
    p.add_argument("--json", required=True, help=f"write the result here: {json_fields}")
    p.add_argument("--csv", help="write the table (one row per step and tip) here")
    p.add_argument("--gif", help=f"write an animation of {animation} here")


def output_paths(args, *names: str) -> dict:
    """Check the output options `names` (json first: any suffix; the others must end in .NAME), in order."""
    return {name: check_output(getattr(args, name), f"--{name}", None if name == "json" else f".{name}")
            for name in names}


def solve_options(args, *names: str) -> dict:
    """The solve options among `names` that the command line set, in that order."""
    return {k: getattr(args, k) for k in names if getattr(args, k) is not None}


def dump_json(data, tmp) -> None:
    with open(tmp, "w") as fh:
        json.dump(data, fh, indent=1)


def write_all(result, data, scene, json_path, outputs, also=()) -> int:
    """Write the JSON and every (path, writer) of `outputs` whose path is set, all or none; print what was written
    (then the files of `also`, written as the steps finished)."""
    written = [json_path]
    with Staged() as staged:  # every output or none; existing files untouched on failure
        staged.write(json_path, lambda tmp: dump_json(data, tmp))
        for path, write in outputs:
            if path is not None:
                staged.write(path, write)
                written.append(path)
    print(f"{scene.name}: {len(result.steps)} steps, stopped: {result.stopped}")
    written.extend(also)
    for path in written:
        print(f"wrote {path}")
    return 0


def runs_here() -> bool:
    """Whether this process runs a stepping command: yes without mpiexec; under `mpiexec -n N` (N > 1) on rank 0
    alone, which says so once on stderr. The stepping commands are not distributed (their solves are serial): every
    rank ran the whole job and wrote the same files. The other ranks end at once with status 0 after the input
    checks (which refuse alike on every rank, rank 0 printing the line); mpiexec waits for rank 0 and returns its
    status. Reads the rank from the environment: no MPI is started."""
    from ngcrack.distributed import world_rank, world_size

    size = world_size()
    if size <= 1:
        return True
    if world_rank() != 0:
        return False
    print(f"ngcrack: note: this command is not distributed: rank 0 runs it alone, the other {size - 1} rank(s) have "
          f"nothing to do (run it without mpiexec)", file=sys.stderr, flush=True)
    return True


def run_until_signal(work, finished: Finished):
    """`work()` on the rank that runs the command (`runs_here`; 0 elsewhere, nothing done); a signal that stops it
    writes the finished steps and raises the interruption with their note."""
    if not runs_here():
        return 0
    try:
        return work()
    except BaseException as exc:
        signum = pending()
        if isinstance(exc, KeyboardInterrupt) or signum is not None:
            signum = signum or (signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT)
            stop = interruption(signum)
            stop.note = finished.write(signum)
            raise stop from exc
        raise


class Finished:
    """The steps a run has finished, written (JSON and CSV, marked interrupted) if a signal stops it.

    `skipped`: the outputs an interrupted run does not write; `series`: a VTK series written as the steps finish."""

    def __init__(self, json_path, csv_path, steps, skipped=(), series=None):
        self.json_path, self.csv_path, self.steps, self.skipped, self.series = json_path, csv_path, steps, skipped, series
        self.snapshot = None  # (JSON data, CSV writer)
        self.note = None
        self.lock = threading.Lock()

    def keep(self, data, write_csv) -> None:
        """The latest finished steps: their JSON data and a writer of their CSV table."""
        self.snapshot = (data, write_csv)  # one assignment: a whole snapshot or the previous

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
        vtk = (f"; the VTK series {self.series.collection} holds the {len(self.series.files)} steps written"
               if self.series is not None and self.series.files else "")
        if self.snapshot is None:
            return "no step had finished, nothing was written" + vtk
        data, write_csv = self.snapshot
        data = dict(data)
        done = len(data["steps"])
        what = "SIGTERM" if signum == signal.SIGTERM else "SIGINT"
        data["stopped"] = f"interrupted: {what} after step {done - 1} of {self.steps}; the finished steps are kept"
        try:
            check_finite(data)
            with Staged() as staged:
                staged.write(self.json_path, lambda tmp: dump_json(data, tmp))
                if self.csv_path is not None:
                    staged.write(self.csv_path, write_csv)
        except Exception as exc:  # noqa: BLE001 -- the interruption is what is reported
            return f"the finished steps could not be written ({type(exc).__name__}: {exc}), nothing was written" + vtk
        files = " and ".join(str(p) for p in (self.json_path, self.csv_path) if p is not None)
        skipped = (f"; not written: {', '.join(str(p) for p in self.skipped)}" if self.skipped else "")
        return (f"wrote {files} with the {done} finished steps, marked \"stopped\": \"interrupted: ...\"" + skipped
                + vtk)
