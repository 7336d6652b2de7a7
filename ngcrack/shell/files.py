"""Files written whole or not at all, folders tried before the work, names that stay where they are put.

Every output of ngcrack (JSON, figures, tables, reference caches) goes through a
temporary file beside its target, renamed into place when complete (os.replace: atomic
on one file system), so an interruption or an error never leaves a half-written file
and an existing file is untouched until its replacement is whole. `Staged` does that
for several files at once: all are replaced, or none; a SIGINT or SIGTERM that comes while
they are being renamed is held until the last one is in place (`committing`, `hold`), then
raised with a note that the outputs were written. A low-level module: it imports nothing of
ngcrack but its error types.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import signal
import tempfile
from collections.abc import Callable
from pathlib import Path

from ..core.errors import InputError

#: the longest part of a file name taken from a user's text (a scene's name)
NAME_PART_MAX = 64

#: temporary files and folders being written now (removed by `remove_staged_files` when a
#: signal ends the process before they are renamed into place)
_temporary: set[str] = set()


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived: unwound like an interruption (workers stopped, temporary files removed)."""


#: the renaming of staged outputs under way (depth) and a signal that came meanwhile (held)
_commit: dict = {"depth": 0, "held": None}


def committing() -> bool:
    """Whether staged outputs are being renamed into place now (a signal must wait: `hold`)."""
    return _commit["depth"] > 0


def hold(signum: int) -> None:
    """Keep a signal that came while outputs were being renamed: raised when the last is in place."""
    _commit["held"] = _commit["held"] or signum


def register_temporary(path) -> None:
    """Note a temporary file or folder of an output being written (see `remove_staged_files`)."""
    _temporary.add(str(path))


def forget_temporary(path) -> None:
    _temporary.discard(str(path))


def remove_staged_files() -> None:
    """Remove every temporary file and folder still registered: the process is ending before
    they could be renamed into place (ngcrack.shell.interrupts), and nothing half-written may stay."""
    for path in list(_temporary):
        if os.path.isdir(path):
            shutil.rmtree(path, ignore_errors=True)
        elif os.path.exists(path):
            try:
                os.unlink(path)
            except OSError:
                pass
        _temporary.discard(path)


def _umask() -> int:
    """The process's file-creation mask (read by setting it and restoring it at once)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


class Staged:
    """Output files written to temporary files beside their targets, renamed into place together.

    Used as a context manager: on leaving it normally every staged file replaces its
    target; on an error the temporary files are removed and every target is left as it was.
    """

    def __init__(self) -> None:
        self.files: list[tuple[str, Path]] = []
        self.folders: list[str] = []

    def write(self, path, write: Callable[[str], object]) -> Path:
        """Stage `path`: `write(tmp)` writes the content to the temporary file `tmp` (same suffix)."""
        path = Path(path)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=path.suffix)
        os.close(fd)
        register_temporary(tmp)
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes it 0600: the target gets the user's usual mode
        self.files.append((tmp, path))
        write(tmp)
        return path

    def folder(self, parent) -> Path:
        """A temporary folder in `parent` for files written by another writer (`adopt` them);
        removed on leaving, whatever happens."""
        tmp = tempfile.mkdtemp(dir=parent, prefix=".ngcrack-stage-")
        register_temporary(tmp)
        self.folders.append(tmp)
        return Path(tmp)

    def adopt(self, tmp, path) -> Path:
        """Stage a file already written at `tmp` (in a `folder` of this stage) to replace `path`."""
        self.files.append((str(tmp), Path(path)))
        return Path(path)

    def __enter__(self) -> Staged:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        try:
            if exc_type is None:
                self._commit()
        finally:
            for tmp, _ in self.files:
                if os.path.exists(tmp):
                    os.unlink(tmp)
                forget_temporary(tmp)
            for tmp in self.folders:
                shutil.rmtree(tmp, ignore_errors=True)
                forget_temporary(tmp)

    def _commit(self) -> None:
        """Rename every staged file into place; a signal meanwhile is held and raised after the last."""
        _commit["depth"] += 1
        try:
            for tmp, path in self.files:
                os.replace(tmp, path)
        finally:
            _commit["depth"] -= 1
        held = _commit["held"] if _commit["depth"] == 0 else None
        if held is not None:
            _commit["held"] = None
            exc = Terminated() if held == signal.SIGTERM else KeyboardInterrupt()
            names = ", ".join(str(path) for _, path in self.files)
            exc.note = f"the outputs were written whole ({names})"
            raise exc


def atomic_write(path, write: Callable[[str], object]) -> Path:
    """Write `path` whole or not at all: `write(tmp)` fills a temporary file renamed into place."""
    with Staged() as staged:
        return staged.write(path, write)


def unwritable(folder) -> str | None:
    """Why this process cannot create a file in `folder` (tried, not guessed from the mode
    bits, which the superuser ignores), or None if it can."""
    try:
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".ngcrack-probe-")
    except OSError as exc:
        return exc.strerror or str(exc)
    os.close(fd)
    os.unlink(tmp)
    return None


def file_name_part(text: str) -> str:
    """`text` as a safe part of a file name: letters, digits, '.', '_' and '-' only, no
    leading dot, at most NAME_PART_MAX characters; a name that had to change gets a
    short hash of the original, so that two different names stay two different files."""
    safe = re.sub(r"[^A-Za-z0-9._-]+", "_", str(text)).lstrip(".") or "_"
    if safe == text and len(safe) <= NAME_PART_MAX:
        return safe
    digest = hashlib.sha1(str(text).encode()).hexdigest()[:8]
    return f"{safe[:NAME_PART_MAX]}-{digest}"


class PathError(InputError):
    """An output path that cannot be written (refused before any work; exit code 2)."""


def writable_folder(folder: Path, field: str, path) -> None:
    """Refuse a folder this process cannot create files in."""
    why = unwritable(folder)
    if why is not None:
        raise PathError(f"{field} = {str(path)!r}: cannot write in the directory {str(folder)!r} ({why}); "
                         f"choose a writable place")


def _refuse_empty(path, field: str) -> None:
    if not isinstance(path, (str, os.PathLike)):
        raise PathError(f"{field} = {path!r}: expected a file name")
    if not str(path).strip():
        raise PathError(f"{field} = {str(path)!r}: is empty; give a file name")


def _check_file(p: Path, field: str, given, name: str = "", probe: bool = True) -> None:
    """The checks of one file to write: its directory exists and is writable, it is not a directory,
    it is not read-only. `name` tells which of the option's files it is (for an option writing several)."""
    head = f"{field} = {str(given)!r}:"
    if not p.parent.is_dir():
        raise PathError(f"{head} the directory {str(p.parent)!r} does not exist")
    if p.is_dir():
        raise PathError(f"{head} {name} is a directory; give another name" if name else
                        f"{head} is a directory; give a file name")
    if probe:
        writable_folder(p.parent, field, given)
    if p.exists() and not os.access(p, os.W_OK):
        raise PathError(f"{head} {name or 'the file'} is read-only; choose another name or make it writable")


def check_output(path: str | None, field: str, suffix: str | None = None) -> Path | None:
    """A file to write: its directory exists and is writable, it is not a directory, it has `suffix`."""
    if path is None:
        return None
    _refuse_empty(path, field)
    p = Path(path)
    if str(path).endswith(os.sep) or p.name in ("", ".", "..") or p.is_dir():
        raise PathError(f"{field} = {str(path)!r}: is a directory; give a file name")
    if suffix and p.suffix.lower() != suffix:
        raise PathError(f"{field} = {str(path)!r}: must end in {suffix}")
    _check_file(p, field, path)
    return p


def check_output_stem(path: str | None, field: str, names: list[str],
                      drop: tuple[str, ...] = (".vtu", ".vtk")) -> Path | None:
    """A stem OUT of several files (OUT + each of `names`, e.g. ".vtu", "_cracks.vtu", ".pvd"): every one
    checked as `check_output` checks a file (the same rule for every output: the folder must exist); the
    stem is `path` without a suffix of `drop`."""
    if path is None:
        return None
    _refuse_empty(path, field)
    stem = Path(path)
    if str(path).endswith(os.sep) or stem.name in ("", ".", ".."):
        raise PathError(f"{field} = {str(path)!r}: expected a file name stem, e.g. 'out/run'")
    if stem.suffix in drop:
        stem = stem.with_suffix("")
    for k, name in enumerate(names):
        f = stem.with_name(stem.name + name)
        _check_file(f, field, path, name=f.name, probe=k == 0)  # one folder: tried once
    return stem


def check_distinct(outputs: dict) -> None:
    """Refuse two outputs on one file: `outputs` maps an option to its file or files (None: not given)."""
    seen: dict[str, str] = {}
    for field, paths in outputs.items():
        for p in ([] if paths is None else [paths] if isinstance(paths, (str, os.PathLike)) else paths):
            key = os.path.normcase(os.path.realpath(p))
            if key in seen and seen[key] != field:
                raise PathError(f"{field}: {str(p)!r} is also the file of {seen[key]}; give each output its own "
                                f"file")
            seen.setdefault(key, field)


def check_output_folder(path: str, field: str) -> Path:
    """A folder to write into: its parent exists, it is a directory if it exists, it is writable."""
    out = Path(path)
    if not out.parent.is_dir():
        raise PathError(f"{field} = {str(path)!r}: the directory {str(out.parent)!r} does not exist")
    if out.exists() and not out.is_dir():
        raise PathError(f"{field} = {str(path)!r}: exists and is not a directory")
    writable_folder(out if out.exists() else out.parent, field, path)
    return out
