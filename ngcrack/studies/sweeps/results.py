"""The results file of a sweep: its row schema, the CSV written one complete line at a time, and read back.

Output. `sweep(..., out="results.csv")` appends one CSV line per finished run (one
`write` of a complete line, then fsync), so an interruption loses at most the runs in
progress; running the same sweep again skips the rows already present (keyed by scene,
element, maxh, nu, friction) and drops a trailing partial line. The last column,
`row_check`, is a digest of the row's other cells: a row changed afterwards (a key edited
by hand) is refused naming the row, not taken for another run. Reference samples are cached next
to the CSV (`results.csv.refs/`, npz files) so a resumed sweep need not recompute them;
a missing or unreadable cache file is recomputed.
"""

from __future__ import annotations

import csv
import hashlib
import io
import math
import os
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ...core.errors import InputError
from ...core.friction_checks import scene_friction  # noqa: F401 (the friction column; re-exported)
from .quantities import _is_tip_column

#: columns that identify a row (resume key)
KEY = ("scene", "element", "maxh", "nu", "friction")
#: significant digits used to compare maxh and nu when matching rows
KEY_DIGITS = 12

#: the row schema: column -> type; the CSV has exactly these columns in this order
ROW_SCHEMA: dict[str, type] = {
    "scene": str,
    "element": str,
    "maxh": float,                # requested global mesh size
    "nu": float,                  # Poisson's ratio
    "friction": float,            # Coulomb coefficient applied (the cracks' largest; 0 for free and bonded cracks)
    "E": float,
    "h": float,                   # the mesh's largest edge length
    "n_elements": int,
    "ndof_total": int,
    "ndof_global": int,           # after static condensation
    "ndof_contact": int,          # crack normal unknowns in the QP
    "n_active": int,              # QP unknowns in contact (w = 0)
    "time_mesh": float,           # seconds, wall clock
    "time_assemble": float,
    "time_linear": float,         # factorization, solves and local recovery
    "time_contact": float,        # Schur complement and QP
    "time_total": float,          # the whole solve, mesh included
    "time_error": float,          # evaluating the errors (not part of the solve)
    "time_tips": float,           # the tips' domain integrals (part of time_total)
    "time_cpu": float,            # the whole solve's CPU seconds (process time, all threads; time_total's span)
    "memory_peak_mb": float,
    "memory_start_mb": float,
    "kkt_max_penetration": float,
    "kkt_max_tension": float,
    "kkt_complementarity": float,
    "kkt_friction": float,        # the discrete Coulomb law's residual (0 without friction)
    "max_opening": float,         # max [u].nu over the crack samples
    "max_slip": float,            # max |[u].t|
    "n_stick": int,               # crack samples that stick (friction only)
    "min_normal_stress": float,   # most compressive sigma_n on the crack
    "reference": bool,            # this row is the reference of its group
    "reference_element": str,
    "reference_maxh": float,
    "reference_ndof": int,
    "err_u1": float,
    "err_u2": float,
    "err_sigma_t1": float,
    "err_sigma_nu": float,
    "err_opening": float,         # against the closed form (griffith); empty elsewhere
    "err_K_I": float,             # K_I against the closed form (griffith, inclined); empty elsewhere
    "crack_model": str,
    "qp_solver": str,
    "adapt": bool,                # an adaptive run: maxh holds its tolerance (the relative estimate)
    "estimate": float,            # the solve's relative error estimate (estimate.py), energy norm
    "estimate_energy": float,     # the same, absolute
}
ROW_COLUMNS = tuple(ROW_SCHEMA)
#: columns added since files were first written: a file without them is read with them empty
#: and, when a sweep resumes it, rewritten once with them (its rows' cells unchanged)
ADDED_COLUMNS = ("time_cpu",)
_OLD_COLUMNS = tuple(c for c in ROW_COLUMNS if c not in ADDED_COLUMNS)
#: the last column of a results file: a digest of the row's other cells, so that a row changed
#: after the sweep wrote it (a key edited by hand would otherwise pass for another run) is refused
CHECK_COLUMN = "row_check"
#: hexadecimal digits of the digest kept
CHECK_DIGITS = 16
#: columns that must agree between a CSV's rows and a resumed sweep asking for the same keys
_SETUP_COLUMNS = ("reference_element", "reference_maxh", "crack_model", "qp_solver", "adapt")


def _key(scene: str, element: str, maxh: float, nu: float, friction: float = 0.0) -> tuple:
    return (str(scene), str(element), float(f"{float(maxh):.{KEY_DIGITS}g}"), float(f"{float(nu):.{KEY_DIGITS}g}"),
            float(f"{float(friction):.{KEY_DIGITS}g}"))


def _format(value) -> str:
    if isinstance(value, (bool, np.bool_)):
        return "True" if value else "False"
    if isinstance(value, (float, np.floating)):
        return "" if not math.isfinite(value) else repr(float(value))
    return str(value)


def csv_line(row: dict, columns: Sequence[str] = ROW_COLUMNS) -> str:
    """One complete CSV line (with its newline) of a row, in the order of `columns` (missing: empty)."""
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([_format(row.get(c, math.nan)) for c in columns])
    return buf.getvalue()


def row_check(cells: Sequence[str]) -> str:
    """The digest of a row's cells, as written (the CHECK_COLUMN's value)."""
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow(list(cells))
    return hashlib.sha256(buf.getvalue().encode()).hexdigest()[:CHECK_DIGITS]


def _check_digests(path: Path, header: list[str], records: list[list[str]]) -> None:
    """Refuse a row whose cells no longer give its digest: changed after the sweep wrote it."""
    for i, rec in enumerate(records, start=1):
        if rec[-1] != row_check(rec[:-1]):
            key = ", ".join(f"{k} = {rec[header.index(k)]}" for k in KEY)
            raise _corrupted(path, f"row {i} (line {i + 1}) was changed after the sweep wrote it ({key}: its "
                                   f"{CHECK_COLUMN} does not match its cells)")


def typed(df):
    """`df` with the ROW_SCHEMA dtypes (str, float, int, bool) on the columns it has."""
    import pandas as pd

    df = df.copy()
    for col, typ in _schema(df.columns).items():
        if col not in df.columns:
            continue
        if typ is float:
            df[col] = pd.to_numeric(df[col], errors="coerce").astype(float)
        elif typ is int:
            df[col] = pd.to_numeric(df[col]).astype("int64")
        elif typ is bool:
            df[col] = df[col].map(lambda v: v if isinstance(v, (bool, np.bool_)) else str(v) == "True").astype(bool)
        else:
            df[col] = df[col].fillna("").astype(str)
    return df


def _schema(columns) -> dict[str, type]:
    return dict(ROW_SCHEMA, **{c: float for c in columns if _is_tip_column(str(c))})


def _corrupted(path: Path, what: str) -> InputError:
    return InputError(f"{path}: {what}; the file is corrupted (edited by hand or written by something else): "
                      f"repair or delete that row, or write to another file")


def _check_cells(path: Path, header: list[str], records: list[list[str]]) -> None:
    """Refuse a cell that is not what a sweep writes: a finite number (or empty: not
    computed) in a float column, an integer, True or False; row i is line i + 1."""
    schema = _schema(header)
    for i, rec in enumerate(records, start=1):
        for col, cell in zip(header, rec):
            typ = schema.get(col, str)
            if typ is str:
                continue
            ok = True
            if typ is float:
                if cell != "":
                    try:
                        ok = math.isfinite(float(cell))
                    except ValueError:
                        ok = False
            elif typ is int:
                ok = cell.lstrip("-").isdigit()
            elif typ is bool:
                ok = cell in ("True", "False")
            if not ok:
                kind = {float: "a finite number (or empty)", int: "an integer", bool: "True or False"}[typ]
                raise _corrupted(path, f"row {i} (line {i + 1}), column {col!r}: {cell!r} is not {kind}")


def _check_unique(path: Path, df) -> None:
    """Refuse two rows of the same run (a duplicated line)."""
    seen: dict[tuple, int] = {}
    for i, rec in enumerate(df[list(KEY)].itertuples(index=False), start=1):
        key = _key(*rec)
        if key in seen:
            what = ", ".join(f"{k} = {v!r}" for k, v in zip(KEY, rec))
            raise _corrupted(path, f"rows {seen[key]} and {i} (lines {seen[key] + 1} and {i + 1}) are the same run "
                                   f"({what})")
        seen[key] = i


def read_results(path):
    """A sweep CSV as a typed pandas DataFrame (ignoring a trailing partial line).

    A file that is not a sweep's is refused with a ValueError naming the file and, for a
    corrupted row, the row, the column and the cell: a row with the wrong number of
    cells, a cell that does not parse as its column's type (never read as NaN), two
    rows of the same run.
    """
    import pandas as pd

    path = Path(path)
    try:
        text = path.read_text()
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: not a text file ({exc.reason} at byte {exc.start}); write to another file") from None
    if text and not text.endswith("\n"):
        text = text[: text.rfind("\n") + 1]
    if not text:
        return typed(pd.DataFrame(columns=list(ROW_COLUMNS)))
    try:
        lines = list(csv.reader(io.StringIO(text)))
    except csv.Error as exc:
        raise InputError(f"{path}: not a CSV file ({exc}); write to another file") from None
    header, records = lines[0], lines[1:]
    n = len(ROW_COLUMNS)
    checked = bool(header) and header[-1] == CHECK_COLUMN  # files of older versions have no digests
    data_header = header[:-1] if checked else header
    old = tuple(data_header[: len(_OLD_COLUMNS)]) == _OLD_COLUMNS and tuple(data_header[:n]) != ROW_COLUMNS
    m = len(_OLD_COLUMNS) if old else n
    if tuple(data_header[:m]) not in (ROW_COLUMNS, _OLD_COLUMNS) or not all(_is_tip_column(str(c))
                                                                          for c in data_header[m:]):
        raise InputError(f"out = {str(path)!r}: its columns are not those of a sweep of this version "
                          f"(expected {', '.join(ROW_COLUMNS)} and the tip columns); write to another file")
    for i, rec in enumerate(records, start=1):
        if len(rec) != len(header):
            raise _corrupted(path, f"row {i} (line {i + 1}) has {len(rec)} cells, the header {len(header)}")
    _check_cells(path, data_header, records)
    # floats must read back exactly (resume keys, reproducible tables): pandas >= 3 parses
    # round-trip by default, older versions need asking
    exact = {} if int(pd.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}
    df = pd.read_csv(io.StringIO(text), **exact,
                     dtype={"scene": str, "element": str, "reference_element": str, "crack_model": str,
                            "qp_solver": str, CHECK_COLUMN: str})
    df = typed(df)
    _check_unique(path, df)
    if checked:
        _check_digests(path, header, records)
        df = df.drop(columns=CHECK_COLUMN)
    for col in ADDED_COLUMNS if old else ():  # a file of an earlier version: not recorded then
        df.insert(ROW_COLUMNS.index(col), col, math.nan)
    return df


class ResultsFile:
    """The sweep's CSV: the header with the first row, then one complete line per finished run.

    A new file is created only with its first row (header and row in one write): a
    sweep that fails or is interrupted before any run finishes leaves no file.
    """

    def __init__(self, path, columns: Sequence[str] = ROW_COLUMNS) -> None:
        self.path = Path(path)
        self.columns = tuple(columns)
        self._header = ""
        self._checked = True  # rows carry their digest (CHECK_COLUMN), except in a file of an older version
        if not self.path.parent.exists():
            raise InputError(f"out = {str(self.path)!r}: the directory {str(self.path.parent)!r} does not exist")
        if self.path.is_dir():
            raise InputError(f"out = {str(self.path)!r}: is a directory; give a file name")
        if self.path.exists() and self.path.stat().st_size:
            data = self.path.read_bytes()
            if not data.endswith(b"\n"):  # a line cut by an interruption: drop it
                keep = data.rfind(b"\n") + 1
                warnings.warn(f"{self.path}: dropped a partial last line ({len(data) - keep} bytes) left by an "
                              f"interrupted run", stacklevel=3)
                with open(self.path, "r+b") as fh:
                    fh.truncate(keep)
            self.existing = read_results(self.path)
            with open(self.path, newline="") as fh:
                first = next(csv.reader(fh), [""])
            self._checked = first[-1] == CHECK_COLUMN
            if any(c not in first for c in ADDED_COLUMNS) and tuple(self.existing.columns) == self.columns:
                self._upgrade()
            if tuple(self.existing.columns) != self.columns:
                raise InputError(f"out = {str(self.path)!r}: its columns are not this sweep's (another scene's "
                                  f"tips?); write to another file")
        else:
            self.existing = None
            buf = io.StringIO()  # tip columns hold a comma (K_I[0,last]): quoted
            csv.writer(buf, lineterminator="\n").writerow((*self.columns, CHECK_COLUMN))
            self._header = buf.getvalue()

    def _upgrade(self) -> None:
        """Rewrite a file of an earlier version with this version's columns (the added ones
        empty, every row's digest recomputed), atomically: the resumed sweep appends to it."""
        buf = io.StringIO()
        writer = csv.writer(buf, lineterminator="\n")
        writer.writerow((*self.columns, CHECK_COLUMN))
        for rec in self.existing.to_dict("records"):
            cells = [_format(rec.get(c, math.nan)) for c in self.columns]
            writer.writerow([*cells, row_check(cells)])
        tmp = self.path.with_name(self.path.name + ".upgrade")
        tmp.write_text(buf.getvalue())
        os.replace(tmp, self.path)
        self._checked = True

    def _append(self, text: str) -> None:
        fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            data = text.encode()
            written = os.write(fd, data)  # one write of the whole line
            while written < len(data):  # only on exotic file systems
                written += os.write(fd, data[written:])
            os.fsync(fd)
        finally:
            os.close(fd)

    def append(self, row: dict) -> None:
        cells = [_format(row.get(c, math.nan)) for c in self.columns]
        if self._checked:
            cells.append(row_check(cells))
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerow(cells)
        self._append(self._header + buf.getvalue())
        self._header = ""
