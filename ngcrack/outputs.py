"""Writing results safely: outputs checked before any work, written whole or not at all.

`check_output` and `check_output_folder` refuse, before a solve starts, a path that
cannot be written (a missing or read-only directory, a directory where a file is
meant, a wrong suffix), naming the option; `StagedWrites` writes every output to a
temporary file beside its target and renames them into place together only when all
succeeded (os.replace, atomic per file), so no file is left half-written and an
existing one is untouched on failure; `check_finite` refuses NaN or infinity in a
result before it is written. Used by the command line and by crack growth's outputs.
"""

from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path


class UsageError(ValueError):
    """Bad command-line input (exit code 2)."""


class StagedWrites:
    """Output files written to temporary files beside their targets, renamed into place together.

    Used as a context manager: on leaving it normally every staged file replaces its
    target (os.replace, atomic per file); on an error the temporary files are removed
    and every target is left as it was.
    """

    def __init__(self) -> None:
        self.files: list[tuple[str, Path]] = []

    def write(self, path: Path, write) -> None:
        path = Path(path)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix)
        os.close(fd)
        self.files.append((tmp, path))
        write(tmp)

    def __enter__(self) -> StagedWrites:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is None:
                for tmp, path in self.files:
                    os.replace(tmp, path)
        finally:
            for tmp, _ in self.files:
                if os.path.exists(tmp):
                    os.unlink(tmp)


def writable_folder(folder: Path, field: str, path) -> None:
    """Refuse a folder this process cannot create files in (tried, not guessed from the mode bits)."""
    try:
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".ngcrack-probe-")
    except OSError as exc:
        raise UsageError(f"{field} = {str(path)!r}: cannot write in the directory {str(folder)!r} "
                         f"({exc.strerror or exc}); choose a writable place") from None
    os.close(fd)
    os.unlink(tmp)


def check_output(path: str | None, field: str, suffix: str | None = None) -> Path | None:
    """A file to write: its directory exists and is writable, it is not a directory, it has `suffix`."""
    if path is None:
        return None
    p = Path(path)
    if not p.parent.is_dir():
        raise UsageError(f"{field} = {str(path)!r}: the directory {str(p.parent)!r} does not exist")
    if p.is_dir():
        raise UsageError(f"{field} = {str(path)!r}: is a directory; give a file name")
    if suffix and p.suffix.lower() != suffix:
        raise UsageError(f"{field} = {str(path)!r}: must end in {suffix}")
    writable_folder(p.parent, field, path)
    if p.exists() and not os.access(p, os.W_OK):
        raise UsageError(f"{field} = {str(path)!r}: the file is read-only; choose another or make it writable")
    return p


def check_output_folder(path: str, field: str) -> Path:
    """A folder to write into: its parent exists, it is a directory if it exists, it is writable."""
    out = Path(path)
    if not out.parent.is_dir():
        raise UsageError(f"{field} = {str(path)!r}: the directory {str(out.parent)!r} does not exist")
    if out.exists() and not out.is_dir():
        raise UsageError(f"{field} = {str(path)!r}: exists and is not a directory")
    writable_folder(out if out.exists() else out.parent, field, path)
    return out


class NotSolvedError(RuntimeError):
    """The solve finished but its answer cannot be used (exit code 3)."""


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
