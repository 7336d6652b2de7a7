"""How the command line reports what went wrong: one line, and an exit code that says whose problem it is.

    2  bad input: an `ngcrack.InputError` (SceneError, PathError, MeshingError, the
       command line's UsageError, every option the package refuses), named in the line;
       or an optional package that the command needs is not installed (the line names
       the extra that brings it, `ngcrack.shell.extras`)
    3  not the input: a system that cannot be solved (singular, a failed crack QP, out of
       memory), or a fault of ngcrack itself (any other exception, a plain ValueError from
       numpy included): then the line names the command, asks for a report and points
       to --debug for the traceback

`classify` follows an exception's causes (a sweep's SweepError wraps the run's own).
Warnings are shown on one line each too.
"""

from __future__ import annotations

import math
import re
import signal
import sys
from contextlib import contextmanager

from ..core.errors import InputError
from .files import Terminated  # noqa: F401 -- the commands' name for it

#: exit codes: bad input (the user's), anything else (a system that cannot be solved, or a fault of ngcrack)
EXIT_INPUT, EXIT_SOLVE = 2, 3


class UsageError(InputError):
    """Bad command-line input (exit code 2)."""


@contextmanager
def as_flags(names):
    """A refusal of an option that came from a flag names the flag (`element = 'x'` -> `--element = 'x'`)."""
    try:
        yield
    except InputError as exc:
        m = re.match(r"(\w+)( =|:)", str(exc))
        if m is None or m.group(1) not in names:
            raise
        flag = names[m.group(1)] if isinstance(names, dict) else "--" + m.group(1).replace("_", "-")
        raise UsageError(flag + str(exc)[len(m.group(1)):]) from None


class NotSolvedError(RuntimeError):
    """The solve finished but its answer cannot be used (exit code 3)."""


def one_line(text) -> str:
    """`text` on one line: its whitespace runs (newlines too) as single spaces."""
    return " ".join(str(text).split())


def _causes(exc: BaseException):
    """`exc` and the exceptions it was raised from (a SweepError wraps the run's own)."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        seen.add(id(exc))
        yield exc
        exc = exc.__cause__ or exc.__context__


def classify(exc: BaseException, command: str | None = None) -> tuple[int, str]:
    """(exit code, one-line message) of an error that reached the command line from `command`.

    Only an `InputError` in the cause chain is the user's input (exit 2; so is an optional
    package that is not installed: the line names its extra); everything else
    exits with 3: with a hint where the cause is known (memory, a singular system, a
    failed solve, an overflow, a file the system refuses), otherwise as a fault of ngcrack
    that names the command and asks for a report."""
    from ..core.contact import ContactSolverError
    from ..core.errors import InputError
    from ..core.schur import LinearSolverError
    from ..core.solve import SolveError
    from .extras import missing_extra

    text = one_line(exc)
    for cause in _causes(exc):
        if missing_extra(cause):  # an optional package not installed: what to install
            return EXIT_INPUT, missing_extra(cause)
        netgen = type(cause).__name__ == "NgException"
        if isinstance(cause, InputError):  # SceneError, UsageError, PathError, every option the package refuses
            return EXIT_INPUT, text
        if isinstance(cause, MemoryError) or (netgen and "allocate" in str(cause)):
            return EXIT_SOLVE, (f"out of memory ({text or type(cause).__name__}); use a larger maxh or a smaller "
                                f"--max-dof")
        if isinstance(cause, (SolveError, ContactSolverError, LinearSolverError, NotSolvedError)):
            return EXIT_SOLVE, text
        if netgen and "singular" in str(cause):
            where = text.split('in Assemble')[0].strip()
            return EXIT_SOLVE, (f"the system is singular (netgen: {where}); is every part of the body held, and are the "
                                f"material values and loads finite and of a sane size?")
        if isinstance(cause, ArithmeticError):
            return EXIT_SOLVE, (f"a value beyond what double precision holds ({type(cause).__name__}: {text}); "
                                f"check the mesh sizes, the loads and the material values")
        if isinstance(cause, OSError) and cause.filename is not None:
            return EXIT_SOLVE, f"cannot use {cause.filename!r}: {cause.strerror or cause}"
    where = f"ngcrack {command}" if command else "ngcrack"
    return EXIT_SOLVE, (f"unexpected {type(exc).__name__} in {where}: {text}; this is a fault of ngcrack: please "
                        f"report it with the command line and the traceback (run with --debug for the traceback)")


def one_line_warning(message, category, filename, lineno, file=None, line=None):
    """`warnings.showwarning` for the command line: the warning as one line on stderr."""
    print(f"ngcrack: warning: {one_line(message)}", file=sys.stderr if file is None else file)


def check_finite(obj) -> None:
    """Refuse NaN or infinity anywhere in the result (json would write invalid tokens)."""
    if isinstance(obj, float) and not math.isfinite(obj):
        raise NotSolvedError("the result contains a non-finite number (are the loads and the material of a sane "
                             "size?); nothing was written")
    if isinstance(obj, dict):
        for v in obj.values():
            check_finite(v)
    elif isinstance(obj, list):
        for v in obj:
            check_finite(v)


def interrupted_line(command: str, signum: int, note: str | None = None) -> str:
    """The one line an interrupted command prints: what stopped it and what was written."""
    what = "terminated" if signum == signal.SIGTERM else "interrupted"
    if note is None:
        note = ("finished runs are saved, run the same command again to resume" if command in ("sweep", "paper")
                else "nothing was written" if command in ("solve", "grow") else None)
    return f"ngcrack: {what}" + (f"; {note}" if note else "")


def first_rank() -> bool:
    """Whether this process prints what every rank would (rank 0 of mpiexec, or no mpiexec)."""
    from ..distributed import world_rank

    return world_rank() == 0


def report_interrupted(args, interrupts, signum: int, exc: BaseException) -> int:
    """Say once (rank 0) that `signum` stopped the command and what was written; its exit code."""
    note = getattr(exc, "note", None)
    if first_rank():  # under mpiexec every rank is interrupted; rank 0 says it, once
        print(interrupted_line(args.command, signum, note), file=sys.stderr)
    interrupts.handled()
    return 128 + signum
