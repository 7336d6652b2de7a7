"""Reading one field of a scene (of either dimension): numbers, points, tables, each refused by name.

Every check of the scene package reports a bad value the same way: a
:class:`SceneError` (a ``ValueError``) whose one-line message starts with the field as
the user wrote it (``material.E``, ``crack[1].points[3]``, ``boundary.top.value``) and
says what is allowed. The coercions here are the shared vocabulary of those checks;
:class:`FrozenMap` is the immutable mapping the frozen scene stores its tables in.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from typing import Any

import numpy as np

from .errors import InputError

#: a point of the plane
Point = tuple[float, float]

__all__ = ["MAX_SCALE", "MIN_SIZE_RTOL", "FrozenMap", "SceneError", "check_scale", "pressure_kind"]

#: Scales a scene may hold, relative to its body: E, and every load as a strain (a
#: traction over E, a body force times the diameter over E, a displacement over the
#: diameter), and every length over the diameter, must lie between ``1 / MAX_SCALE`` and
#: ``MAX_SCALE`` (or be zero): beyond, products of two of them leave double precision.
MAX_SCALE = 1e150

#: The smallest mesh size (maxh, crack_h, tip_h, front_h) relative to the body's diameter. Netgen
#: meshes griffith's graded tip in under a second down to 2e-8 of the diameter, fails at
#: 1e-8, hangs at 4.5e-9 and crashes the interpreter below (measured); this keeps a factor
#: 20 from the failure.
MIN_SIZE_RTOL = 1e-6



class SceneError(InputError):
    """A scene field is invalid; the message names the field and what is allowed."""


def fmt(x: float) -> str:
    return f"{x:.6g}"


def fmt_pt(p: Sequence[float]) -> str:
    return f"({fmt(p[0])}, {fmt(p[1])})"


def is_number(v: Any) -> bool:
    """A real number: Python's or numpy's (np.float32, np.int64, ...), not a bool."""
    return isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, (bool, np.bool_))


def is_finite(v: Any) -> bool:
    """A finite real number (`is_number`, neither infinite nor NaN)."""
    return is_number(v) and math.isfinite(float(v))


def finite(v: Any, fld: str, what: str = "a finite number") -> float:
    if not is_number(v) or not math.isfinite(float(v)):
        raise SceneError(f"{fld} = {v!r}: must be {what}")
    return float(v)


def positive(v: Any, fld: str) -> float:
    what = "a finite number > 0"
    x = finite(v, fld, what)
    if not x > 0:
        raise SceneError(f"{fld} = {v!r}: must be {what}")
    return x


def pair(v: Any, fld: str, what: str = "a list of 2 finite numbers [x, y]") -> Point:
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if (isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) != 2
            or not all(is_number(c) and math.isfinite(float(c)) for c in v)):
        raise SceneError(f"{fld} = {short(v)}: must be {what}")
    return (float(v[0]), float(v[1]))


def points(v: Any, fld: str, minimum: int, what: str, maximum: int | None = None) -> tuple[Point, ...]:
    """A list of at least ``minimum`` (and at most ``maximum``) points [x, y]."""
    if isinstance(v, np.ndarray):
        v = v.tolist()
    if isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) < minimum:
        raise SceneError(f"{fld} = {short(v)}: must be {what}")
    if maximum is not None and len(v) > maximum:
        raise SceneError(f"{fld}: {len(v)} points; at most {maximum} are allowed (a documented "
                         f"ceiling that keeps validation and meshing fast); simplify the polyline")
    return tuple(pair(p, f"{fld}[{i}]") for i, p in enumerate(v))


def short(v: Any, limit: int = 60) -> str:
    s = repr(v)
    return s if len(s) <= limit else s[: limit - 3] + "..."


def check_keys(d: Mapping[str, Any], allowed: Sequence[str], fld: str) -> None:
    unknown = [k for k in d if k not in allowed]
    if unknown:
        where = f"{fld}: unknown key" if fld else "unknown top-level key"
        s = "s" if len(unknown) > 1 else ""
        raise SceneError(f"{where}{s} {', '.join(repr(k) for k in unknown)}; "
                         f"allowed keys: {', '.join(allowed)}")


def table(d: Mapping[str, Any], key: str, fld: str) -> Mapping[str, Any]:
    t = d.get(key, {})
    if not isinstance(t, Mapping):
        raise SceneError(f"{fld} = {short(t)}: must be a table ([{fld}] in TOML)")
    return t


def unique(seq: Sequence[str]) -> list[str]:
    return list(dict.fromkeys(seq))


class FrozenMap(Mapping):
    """An immutable, hashable, insertion-ordered mapping (compares equal as a dict)."""

    __slots__ = ("_d",)

    def __init__(self, items: Mapping[Any, Any] | Sequence[tuple[Any, Any]] = ()) -> None:
        self._d = dict(items)

    def __getitem__(self, key: Any) -> Any:
        return self._d[key]

    def __iter__(self) -> Iterator[Any]:
        return iter(self._d)

    def __len__(self) -> int:
        return len(self._d)

    def __hash__(self) -> int:
        return hash(frozenset(self._d.items()))

    def __repr__(self) -> str:
        return f"FrozenMap({self._d!r})"


def pressure_kind(p: Any) -> Any:
    """What an assembled load form depends on of a crack-face pressure (None, a number, a table
    of (s, p) rows or a callable): None, "uniform" (its value may change without re-building
    the form), the table itself, or the callable's identity."""
    if p is None:
        return None
    if isinstance(p, float):
        return "uniform"
    if isinstance(p, tuple):
        return ("table", p)
    return ("callable", id(p))


def check_scale(values: Any, scale: float, fld: str, what: str) -> None:
    """Refuse a value whose nonzero components, in size or times `scale` (as `what`: a strain, a length
    over the body's), leave the range 1/MAX_SCALE .. MAX_SCALE (beyond, products leave double precision)."""
    vals = np.atleast_1d(np.asarray(values, dtype=float))
    shown = fmt(vals[0]) if np.ndim(values) == 0 else "[" + ", ".join(fmt(v) for v in vals) + "]"
    for c in vals:
        if c != 0.0 and not (1.0 / MAX_SCALE <= abs(c) * scale <= MAX_SCALE and 1.0 / MAX_SCALE <= abs(c) <= MAX_SCALE):
            raise SceneError(f"{fld} = {shown}: out of range ({what} is {abs(c) * scale:.3g}); "
                             f"each component must be 0 or, in size and as {what}, lie between {1.0 / MAX_SCALE:g} "
                             f"and {MAX_SCALE:g} (change the units)")
