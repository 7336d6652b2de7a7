"""Loads that vary over a 3D body: face tractions and crack-face pressures as functions of position.

A face traction (``[boundary.<label>] type = "traction"``) or a crack's ``pressure`` may be,
besides a constant,

a table along an axis
    ``value = {axis = [ax, ay, az], origin = [ox, oy, oz], table = [[s, gx, gy, gz], ...]}``
    (a pressure: rows ``[s, p]``): piecewise linear in s = axis . (x - origin), the s values
    non-decreasing (a repeated s is a jump there), held constant beyond the first and last
    row. ``origin`` defaults to [0, 0, 0] for a face and to the crack's centre for a crack,
    whose axis must lie in its plane (its component along the normal is dropped): s is then
    an in-plane coordinate of the crack. A linear table of two rows is a bending load, a
    linearly varying pressure;
a Python callable
    ``g(x, y, z) -> [gx, gy, gz]`` (a pressure ``p(x, y, z) -> p``), evaluated when the scene is
    built at every point of the grid the elements take it through (a failure, a value of the
    wrong shape or a non-finite one refused by field, before any meshing): its trilinear
    interpolation on GRID_POINTS per direction over the body's bounding box (a crack's
    pressure: bilinear on GRID_POINTS_CRACK per direction over the crack in its plane), exact
    for linear functions, second order in the grid's spacing otherwise. The front's pressure
    term, the error estimate and the outputs evaluate the callable itself (refused by field
    where it is not finite).

At most two rows of a table share an s (a jump); more are refused, as are unsorted rows and
non-finite numbers.

A pressure is a field in space: the table's origin (the crack's centre when not given) and the
callable stay where they are when the crack changes (3D growth re-validates the grown crack):
the grown crack's new parts take the field's values there. A callable's grid is re-fitted to
the new crack (the grid covers the crack it was made for only); a table keeps its origin, written
out (`origin`) once it is no longer the crack's centre, so that the scene's file says the same.

A table's CoefficientFunction is exact (a sum of ramps in s). A callable cannot be written to a
scene file (refused by name in ``to_toml_string``).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core.fields import SceneError, check_keys, is_number, short
from .parts import perpendicular, vector3

#: the most rows of a table
MAX_ROWS = 10000
#: grid points per direction of a callable face traction's interpolation (over the body's bounding box)
GRID_POINTS = 33
#: grid points per in-plane direction of a callable crack pressure's interpolation (over the crack)
GRID_POINTS_CRACK = 129
#: points at which a callable is probed when the scene is built (per direction of a small grid)
PROBE = 3


@dataclass(frozen=True, eq=False)
class VaryingField:
    """A load of `ncomp` components (3: a traction, 1: a pressure) varying in space (module docstring).

    `axis`, `origin`, `rows` for a table ((s, v_1, ..., v_ncomp), ...); `fn` a callable; `lo`, `hi`,
    `frame` the box of the callable's interpolation grid in the coordinates of `frame`'s rows about
    `origin`."""

    ncomp: int
    origin: np.ndarray
    axis: np.ndarray | None = None
    rows: tuple[tuple[float, ...], ...] = ()
    fn: Callable | None = None
    frame: np.ndarray | None = None
    lo: np.ndarray | None = None
    hi: np.ndarray | None = None
    given_origin: bool = False
    name: str = ""  # the field's name in the scene, for the errors
    grid: np.ndarray | None = None  # a callable's values on its interpolation grid (GRID_POINTS per direction)

    @property
    def is_table(self) -> bool:
        return self.fn is None

    def values(self, xyz: np.ndarray) -> np.ndarray:
        """The field at the points (rows of xyz): shape (n, ncomp)."""
        xyz = np.atleast_2d(np.asarray(xyz, dtype=float))
        if self.is_table:
            table = np.asarray(self.rows)
            s = (xyz - self.origin) @ self.axis
            return np.column_stack([np.interp(s, table[:, 0], table[:, 1 + k]) for k in range(self.ncomp)])
        out = np.empty((len(xyz), self.ncomp))
        for i, p in enumerate(xyz):
            out[i] = _checked(self.fn, p, self.name, self.ncomp)
        return out

    def largest(self) -> float:
        """The largest |component| of a table (the scale check); a callable's on its probe points."""
        if self.is_table:
            return float(np.abs(np.asarray(self.rows)[:, 1:]).max())
        return float(np.abs(self.values(self._probe_points())).max())

    def _probe_points(self, n: int = PROBE) -> np.ndarray:
        t = [np.linspace(a, b, n) for a, b in zip(self.lo, self.hi)]
        grid = np.stack(np.meshgrid(*t, indexing="ij"), axis=-1).reshape(-1, len(t))
        return self.origin + grid @ self.frame

    def grid_points(self) -> int:
        """Points per direction of a callable's interpolation grid."""
        return GRID_POINTS if len(self.lo) == 3 else GRID_POINTS_CRACK

    def with_grid(self) -> VaryingField:
        """A callable's field with its values on the interpolation grid (evaluated and checked here, once)."""
        n = self.grid_points()
        return dataclasses.replace(self, grid=self.values(self._probe_points(n)).reshape(*(n,) * len(self.lo), self.ncomp))

    def cf(self):
        """The field as an NGSolve CoefficientFunction of position (module docstring)."""
        import ngsolve as ngs

        if self.is_table:
            s = sum(float(a) * (c - float(o)) for a, c, o in zip(self.axis, (ngs.x, ngs.y, ngs.z), self.origin))
            table = np.asarray(self.rows)
            comps = []
            for k in range(self.ncomp):
                ss, vv = table[:, 0], table[:, 1 + k]
                out = ngs.CF(float(vv[0]))
                for i in range(len(ss) - 1):
                    dv = float(vv[i + 1] - vv[i])
                    if dv == 0.0:
                        continue
                    a, b = float(ss[i]), float(ss[i + 1])
                    if b > a:
                        out = out + dv / (b - a) * ngs.IfPos(s - a, ngs.IfPos(s - b, b - a, s - a), 0.0)
                    else:
                        out = out + dv * ngs.IfPos(s - a, 1.0, 0.0)
                comps.append(out)
            return comps[0] if self.ncomp == 1 else ngs.CF(tuple(comps))
        vals = self.grid if self.grid is not None else self.with_grid().grid
        local = tuple(sum(float(a) * (c - float(o)) for a, c, o in zip(e, (ngs.x, ngs.y, ngs.z), self.origin))
                      for e in self.frame)
        comps = [ngs.VoxelCoefficient(tuple(map(float, self.lo)), tuple(map(float, self.hi)),
                                      np.ascontiguousarray(vals[..., k].T), linear=True, trafocf=ngs.CF(local))
                 for k in range(self.ncomp)]
        return comps[0] if self.ncomp == 1 else ngs.CF(tuple(comps))

    def to_toml(self, fld: str) -> dict[str, Any] | VaryingField:
        """The TOML table of a table field; a callable's field itself (`check_writable` refuses it in a file)."""
        if not self.is_table:
            return self
        d: dict[str, Any] = {"axis": self.axis.tolist(), "table": [list(r) for r in self.rows]}
        if self.given_origin:
            d["origin"] = self.origin.tolist()
        return d


def _table(v: Any, fld: str, ncomp: int) -> tuple[tuple[float, ...], ...]:
    row_what = "[s, p]" if ncomp == 1 else "[s, gx, gy, gz]"
    if isinstance(v, (str, bytes)) or not isinstance(v, Sequence) or len(v) < 2:
        raise SceneError(f"{fld} = {short(v)}: must be 2 or more rows {row_what}")
    if len(v) > MAX_ROWS:
        raise SceneError(f"{fld}: {len(v)} rows; at most {MAX_ROWS} are allowed")
    rows: list[tuple[float, ...]] = []
    for i, row in enumerate(v):
        if isinstance(row, np.ndarray):
            row = row.tolist()
        if (isinstance(row, (str, bytes)) or not isinstance(row, Sequence) or len(row) != 1 + ncomp
                or not all(is_number(c) and math.isfinite(float(c)) for c in row)):
            raise SceneError(f"{fld}[{i}] = {short(row)}: must be a row {row_what} of {1 + ncomp} finite numbers")
        if rows and float(row[0]) < rows[-1][0]:
            raise SceneError(f"{fld}[{i}]: s = {float(row[0]):g} is below the previous row's {rows[-1][0]:g}; "
                             f"the s values must be non-decreasing")
        if len(rows) >= 2 and float(row[0]) == rows[-1][0] == rows[-2][0]:
            raise SceneError(f"{fld}[{i}]: a third row at s = {float(row[0]):g}; at most two rows share an s (a jump "
                             f"from the first's values to the second's)")
        rows.append(tuple(float(c) for c in row))
    if rows[-1][0] == rows[0][0]:
        raise SceneError(f"{fld}: every row has s = {rows[0][0]:g}; give at least two distinct s")
    return tuple(rows)


def _checked(fn: Callable, p: np.ndarray, fld: str, ncomp: int) -> list[float]:
    """fn at the point p, refused by field unless it is `ncomp` finite numbers."""
    what = "a finite number" if ncomp == 1 else "3 finite numbers [gx, gy, gz]"
    where = short([round(float(c), 12) for c in p])
    try:
        v = fn(*map(float, p))
    except Exception as exc:  # the user's function: its failure reported by field
        raise SceneError(f"{fld}: the callable failed at (x, y, z) = {where} ({type(exc).__name__}: "
                         f"{exc}); it must return {what} everywhere on the body") from None
    arr = np.atleast_1d(np.asarray(v, dtype=object)).ravel()
    if len(arr) != ncomp or not all(is_number(c) and math.isfinite(float(c)) for c in arr):
        raise SceneError(f"{fld}: the callable returned {short(v)} at (x, y, z) = {where}; it must return {what}")
    return [float(c) for c in arr]


def _field(v: Any, fld: str, ncomp: int, origin: np.ndarray, frame: np.ndarray, lo, hi,
           in_plane: np.ndarray | None = None) -> VaryingField:
    what = "3 numbers [gx, gy, gz]" if ncomp == 3 else "a number"
    if isinstance(v, VaryingField):  # an existing field on a changed crack or face (module docstring)
        if v.is_table:  # its origin stays; written out once it is no longer the crack's centre
            return v if v.given_origin or np.array_equal(v.origin, origin) else dataclasses.replace(v, given_origin=True)
        if (v.grid is not None and np.array_equal(v.frame, frame) and np.array_equal(v.lo, lo)
                          and np.array_equal(v.hi, hi)):
            return v
        return dataclasses.replace(v, frame=frame, lo=np.asarray(lo, float), hi=np.asarray(hi, float), name=fld,
                                   grid=None).with_grid()
    if callable(v):
        f = VaryingField(ncomp, origin, fn=v, frame=frame, lo=np.asarray(lo, float), hi=np.asarray(hi, float), name=fld)
        f.values(f._probe_points())  # a few points first: a bad function refused quickly
        return f.with_grid()
    if not isinstance(v, Mapping):
        raise SceneError(f"{fld} = {short(v)}: must be {what}, a table {{axis, origin, table}} or in Python a "
                         f"callable of (x, y, z)")
    check_keys(v, ("axis", "origin", "table"), fld)
    for key in ("axis", "table"):
        if key not in v:
            raise SceneError(f"{fld}.{key}: missing; a varying load needs axis = [ax, ay, az] and table = rows")
    axis = vector3(v["axis"], f"{fld}.axis", unit=True)
    if in_plane is not None:
        axis = axis - np.dot(axis, in_plane) * in_plane
        if np.linalg.norm(axis) < 1e-6:
            raise SceneError(f"{fld}.axis = {short(v['axis'])}: along the crack's normal; give a direction in its plane")
        axis = axis / np.linalg.norm(axis)
    given = "origin" in v
    org = vector3(v["origin"], f"{fld}.origin") if given else origin
    return VaryingField(ncomp, org, axis=axis, rows=_table(v["table"], f"{fld}.table", ncomp), given_origin=given,
                        name=fld)


def traction_field(v: Any, fld: str, domain) -> VaryingField:
    """A varying face traction (module docstring), its callable's grid over the domain's bounding box."""
    lo, hi = _bounds(domain)
    return _field(v, fld, 3, np.zeros(3), np.eye(3), lo, hi)


def pressure_field(v: Any, fld: str, crack) -> VaryingField:
    """A varying crack-face pressure, its table's origin the crack's centre, its callable's grid over the crack."""
    e_a = crack.e_a
    e_b = np.cross(crack.normal, e_a)
    out = crack.outline(64) - crack.center
    u, w = out @ e_a, out @ e_b
    pad = 0.01 * crack.size
    return _field(v, fld, 1, crack.center, np.array([e_a, e_b]), [u.min() - pad, w.min() - pad],
                  [u.max() + pad, w.max() + pad], in_plane=crack.normal)


def _bounds(domain) -> tuple[np.ndarray, np.ndarray]:
    if hasattr(domain, "bounds"):
        return domain.bounds
    if hasattr(domain, "lo"):
        return domain.lo, domain.hi
    e1 = perpendicular(domain.axis)
    e2 = np.cross(domain.axis, e1)
    corners = [domain.center + s * 0.5 * domain.height * domain.axis + domain.radius * (r1 * e1 + r2 * e2)
               for s in (-1, 1) for r1 in (-1, 1) for r2 in (-1, 1)]
    return np.min(corners, axis=0), np.max(corners, axis=0)


def check_writable(d: Any, fld: str = "") -> None:
    """Refuse, by field, a callable load in a scene's dict about to be written as TOML."""
    if isinstance(d, VaryingField):
        raise SceneError(f"{fld}: a Python callable cannot be written to a scene file; give a number or a table")
    if isinstance(d, dict):
        for k, v in d.items():
            check_writable(v, f"{fld}.{k}" if fld else k)
    elif isinstance(d, list):
        for i, v in enumerate(d):
            check_writable(v, f"{fld}[{i}]")


def coefficients(scene, traction: Mapping) -> tuple[list, dict]:
    """(per crack its pressure for the elements: a number, None for none, or a CoefficientFunction when it varies;
    the face tractions `traction` with the varying ones added as CoefficientFunctions): the loads the element
    builders take (`solid.element.build`, `solid.h1.build`)."""
    pressure = [element_pressure(c.pressure) for c in scene.cracks]
    return pressure, {**traction, **{k: c.value.cf() for k, c in getattr(scene, "tractions", {}).items()}}


def scaled(value: Any, factor: float) -> Any:
    """A load of a scene's dict times `factor`: a number or a vector, a table (its values, not its s), a
    VaryingField (a callable's values on its grid as well)."""
    factor = float(factor)
    if isinstance(value, VaryingField):
        if value.is_table:
            return dataclasses.replace(value, rows=tuple((r[0], *(factor * v for v in r[1:])) for r in value.rows))
        fn = value.fn
        return dataclasses.replace(value, fn=lambda x, y, z: factor * np.asarray(fn(x, y, z), dtype=float),
                                   grid=None if value.grid is None else factor * value.grid)
    if isinstance(value, Mapping):
        return {**value, "table": [[r[0], *(factor * float(v) for v in r[1:])] for r in value["table"]]}
    if isinstance(value, (int, float)):
        return factor * float(value)
    return [factor * float(v) for v in value]


def element_pressure(p: Any):
    """A crack's pressure as the elements take it: a CoefficientFunction when it varies, a number, None for none."""
    return p.cf() if is_varying(p) else (float(p or 0.0) or None)


def is_varying(v: Any) -> bool:
    return isinstance(v, VaryingField)
