"""ParaView output: a solution's body and crack faces as VTK files, and collections of them.

``save_vtk(sol, "out/run")`` writes two XML VTK unstructured grids:

- ``out/run.vtu``, the body, through NGSolve's ``VTKOutput``: every triangle with its own
  three vertices (the mixed elements' fields are discontinuous), and at each of them the
  ``displacement`` (3 components, z = 0, for ParaView's Warp By Vector), the ``stress``
  (3 x 3, row by row, with sigma_zz = nu (sigma_xx + sigma_yy) in plane strain and 0 in
  plane stress), ``sigma_xx``, ``sigma_yy``, ``sigma_xy``, ``sigma_nu`` = (sigma nu).nu
  with nu the first crack's normal (scenes with a crack), ``von_mises`` (of the symmetric
  part, with that sigma_zz), ``rotation`` (the weak-symmetry multiplier of peers and bdm;
  (du_2/dx_1 - du_1/dx_2) / 2 for tdnns and the displacement elements) and
  ``error_indicator`` (eta_T of the error estimate, constant per triangle; where the
  solve has an estimate);
- ``out/run_cracks.vtu``, the crack faces (scenes with a crack): one line cell per crack
  edge, with the edge's mid-point samples of the crack profiles as cell data:
  ``opening`` [u].nu, ``sliding`` [u].t, ``normal_traction`` (sigma nu).nu,
  ``shear_traction`` (sigma nu).t, ``state`` (0 open, 1 stick, 2 slip), ``crack`` (its
  index), ``s`` (arc length from the crack's first point), ``normal`` and ``tangent``.

Values are written in double precision (NGSolve's binary appended format for the body,
meshio's for the cracks). ``write_collection(files, times, "out/run.pvd")`` writes a
ParaView collection (one entry per time or step, each with one or more parts), and
``save_series(solutions, times, "out/growth")`` writes ``out/growth_0000.vtu``, ... and
``out/growth.pvd`` in one call, for sweeps and crack growth; ``SeriesWriter("out/growth")``
does the same one solution at a time, keeping the collection up to date after each (the
``progress`` callback of ``nc.grow``: ``nc.grow(scene, ..., progress=SeriesWriter(path))``).

Sign conventions as everywhere in ngcrack: t runs from a crack's first point to its last,
nu is t turned by +90 degrees, [u] = u+ - u- with + the side nu points into.
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
from collections.abc import Sequence
from pathlib import Path
from xml.sax.saxutils import quoteattr

import ngsolve as ngs
import numpy as np

from ..core.errors import InputError
from ..core.fields import is_finite
from ..shell.files import PathError, forget_temporary, register_temporary

#: the `state` cell data of the crack data set: the code of each crack-face state
STATE_CODES = {"open": 0, "stick": 1, "slip": 2}
#: suffix of the crack data set's file name, after the body's stem
CRACK_SUFFIX = "_cracks"


def vtk_stem(path) -> Path:
    """The files' stem: `path` without a .vtu/.vtk suffix; refuses (ValueError naming
    `path`) what cannot be a file name, before any work."""
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path = {path!r}: expected a file name (str or os.PathLike)")
    p = Path(path)
    if p.name in ("", ".", "..") or str(path).endswith(os.sep):
        raise InputError(f"path = {str(path)!r}: expected a file name, e.g. 'out/run' (writes out/run.vtu)")
    if p.suffix in (".vtu", ".vtk"):
        p = p.with_suffix("")
    if p.parent.exists() and not p.parent.is_dir():
        raise InputError(f"path = {str(path)!r}: {p.parent} is not a directory")
    return p


def _rotation(sol):
    if sol.fields.get("rotation") is not None:
        return sol.fields["rotation"]
    grad = sol.fields.get("grad_u")
    if grad is None:
        return None
    return 0.5 * (grad[1, 0] - grad[0, 1])


def body_fields(sol) -> dict[str, ngs.CoefficientFunction]:
    """The body's fields as NGSolve CoefficientFunctions, by the names written to the .vtu."""
    u, sig = sol.u, sol.sigma
    mat = sol.scene.material
    sxx, syy, sxy, syx = sig[0, 0], sig[1, 1], sig[0, 1], sig[1, 0]
    szz = mat.nu * (sxx + syy) if mat.plane == "strain" else ngs.CF(0.0)
    s12 = 0.5 * (sxy + syx)
    fields = {
        "displacement": ngs.CF((u[0], u[1], 0.0)),
        "stress": ngs.CF((sxx, sxy, 0.0, syx, syy, 0.0, 0.0, 0.0, szz)),
        "sigma_xx": sxx,
        "sigma_yy": syy,
        "sigma_xy": s12,
        "von_mises": ngs.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3 * s12 ** 2),
    }
    cracks = sol.crack_mesh.cracks
    if cracks:
        n = [float(c) for c in cracks[0].normal[0]]
        fields["sigma_nu"] = n[0] * n[0] * sxx + n[0] * n[1] * (sxy + syx) + n[1] * n[1] * syy
    rot = _rotation(sol)
    if rot is not None:
        fields["rotation"] = rot
    if sol.error_estimate is not None:
        fields["error_indicator"] = sol.error_estimate.indicator
    return fields


def crack_arrays(sol) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """(points (n, 3), lines (m, 2), cell data) of the crack faces: one line per crack edge."""
    cm = sol.crack_mesh
    used = np.unique(np.concatenate([np.concatenate([c.va, c.vb]) for c in cm.cracks]))
    index = {int(v): i for i, v in enumerate(used)}
    points = np.zeros((len(used), 3))
    points[:, :2] = cm.points[used]
    lines, data = [], {k: [] for k in ("opening", "sliding", "normal_traction", "shear_traction", "state", "crack",
                                       "s", "normal", "tangent")}
    for crack, prof in zip(cm.cracks, sol.crack_profiles()):
        m = len(crack)
        lines.append(np.column_stack([[index[int(v)] for v in crack.va], [index[int(v)] for v in crack.vb]]))
        data["opening"].append(prof.normal_jump)
        data["sliding"].append(prof.tangential_jump)
        data["normal_traction"].append(prof.normal_stress)
        data["shear_traction"].append(prof.shear_stress)
        states = prof.state if prof.state is not None else ["open"] * m
        data["state"].append(np.array([STATE_CODES[str(s)] for s in states], dtype=np.int32))
        data["crack"].append(np.full(m, crack.index, dtype=np.int32))
        data["s"].append(prof.s)
        data["normal"].append(np.column_stack([crack.normal, np.zeros(m)]))
        data["tangent"].append(np.column_stack([crack.tangent, np.zeros(m)]))
    cells = {k: np.concatenate(v) for k, v in data.items()}
    return points, np.concatenate(lines).astype(np.int64), cells


def save_vtk(sol, path, subdivision: int = 0) -> list[Path]:
    """Write the body (``path.vtu``) and its crack faces (``path_cracks.vtu``) for ParaView.

    Parameters
    ----------
    sol : Solution
        The answer of `ngcrack.core.solve`.
    path : str or os.PathLike
        The files' stem; a ``.vtu`` suffix is dropped. The folder is created if missing.
    subdivision : int
        Each triangle is cut into ``4**subdivision`` for the body's file (NGSolve's
        ``VTKOutput``); 0 writes the fields at the mesh's own vertices, 1 or 2 show the
        higher-order fields of tdnns and h1p2.

    Returns
    -------
    list of Path
        The files written: the body's, then the cracks' (scenes with a crack).

    The files are written to a temporary folder beside them and moved into place, so an
    error leaves no partial file. The fields are listed in the module's docstring.
    """
    if isinstance(subdivision, bool) or not isinstance(subdivision, (int, np.integer)) or not 0 <= subdivision <= 4:
        raise InputError(f"subdivision = {subdivision!r}: expected an integer from 0 to 4")
    base = vtk_stem(path)
    base.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=".ngcrack-vtk-", dir=base.parent))
    register_temporary(tmp)
    try:
        fields = body_fields(sol)
        ngs.VTKOutput(sol.mesh, coefs=list(fields.values()), names=list(fields), filename=str(tmp / "body"),
                      subdivision=int(subdivision)).Do()
        written = [(tmp / "body.vtu", base.with_name(base.name + ".vtu"))]
        if sol.crack_mesh.cracks:
            import meshio

            points, lines, cells = crack_arrays(sol)
            meshio.write(tmp / "cracks.vtu", meshio.Mesh(points, [("line", lines)],
                                                         cell_data={k: [v] for k, v in cells.items()}),
                         binary=True)
            written.append((tmp / "cracks.vtu", base.with_name(base.name + CRACK_SUFFIX + ".vtu")))
        for _, dst in written:  # both files or neither
            if dst.is_dir():
                raise PathError(f"path = {str(path)!r}: {str(dst)!r} is a directory; give another name")
        for src, dst in written:
            try:
                os.replace(src, dst)
            except OSError as exc:  # the target, not the temporary folder, is what the user can change
                raise PathError(f"path = {str(path)!r}: cannot write {str(dst)!r} ({exc.strerror or exc})") from None
        return [dst for _, dst in written]
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        forget_temporary(tmp)


def write_collection(files: Sequence, times: Sequence[float], path) -> Path:
    """Write a ParaView collection (``.pvd``) of `files`, one entry per time.

    Parameters
    ----------
    files : sequence
        One entry per time: a file name, or a sequence of file names (the parts of that
        step, e.g. what `save_vtk` returned). Names are stored relative to the
        collection's folder.
    times : sequence of float
        The time (load factor, step number, swept parameter) of each entry, finite.
    path : str or os.PathLike
        The collection's file name; ``.pvd`` is appended if missing.

    Returns
    -------
    Path
        The collection written.
    """
    files, times = list(files), list(times)
    if len(files) != len(times):
        raise InputError(f"files, times: {len(files)} files but {len(times)} times; expected one time per entry")
    for t in times:
        if not is_finite(t):
            raise InputError(f"times: {t!r} is not a finite number")
    out = Path(path)
    if out.suffix != ".pvd":
        out = out.with_name(out.name + ".pvd")
    out.parent.mkdir(parents=True, exist_ok=True)
    rows = []
    for t, entry in zip(times, files):
        parts = [entry] if isinstance(entry, (str, os.PathLike)) else list(entry)
        for part, f in enumerate(parts):
            rel = os.path.relpath(Path(f).resolve(), out.parent.resolve())
            rows.append(f'    <DataSet timestep="{float(t)!r}" part="{part}" file={quoteattr(Path(rel).as_posix())}/>')
    text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
            "  <Collection>\n" + "\n".join(rows) + "\n  </Collection>\n</VTKFile>\n")
    tmp = out.with_name(f".{out.name}.tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, out)
    return out


def save_series(solutions: Sequence, times: Sequence[float], path, subdivision: int = 0) -> Path:
    """Write every solution with `save_vtk` (``path_0000``, ``path_0001``, ...) and the
    collection ``path.pvd`` of them at `times` (load factors, steps, a swept parameter).

    Returns the collection's path. The times are checked before anything is written.
    """
    solutions, times = list(solutions), list(times)
    if len(solutions) != len(times):
        raise InputError(f"solutions, times: {len(solutions)} solutions but {len(times)} times; "
                          "expected one time per solution")
    for t in times:
        if not is_finite(t):
            raise InputError(f"times: {t!r} is not a finite number")
    base = vtk_stem(path)
    files = [save_vtk(sol, base.with_name(f"{base.name}_{k:04d}"), subdivision) for k, sol in enumerate(solutions)]
    return write_collection(files, times, base.with_name(base.name + ".pvd"))


class SeriesWriter:
    """Write solutions one at a time (``path_0000``, ``path_0001``, ...), rewriting the
    collection ``path.pvd`` after each, so that an interrupted run leaves a valid series.

    ``writer.add(sol, time)`` writes one; ``writer(step, result)`` is the ``progress``
    callback of `ngcrack.grow` (it writes ``result.solution`` at time = the step number).
    ``files`` and ``times`` hold what was written. The first ``add`` removes the step files
    of an earlier series on the same path (``path_NNNN.vtu``, ``path_NNNN_cracks.vtu``), so
    that the folder holds this series only, the one its collection lists.
    """

    def __init__(self, path, subdivision: int = 0):
        self.base = vtk_stem(path)
        self.subdivision = subdivision
        self.files: list[list[Path]] = []
        self.times: list[float] = []

    @property
    def collection(self) -> Path:
        return self.base.with_name(self.base.name + ".pvd")

    def add(self, sol, time: float) -> list[Path]:
        if not is_finite(time):
            raise InputError(f"time = {time!r}: expected a finite number")
        if not self.files:
            self._remove_stale()
        files = save_vtk(sol, self.base.with_name(f"{self.base.name}_{len(self.files):04d}"), self.subdivision)
        self.files.append(files)
        self.times.append(float(time))
        write_collection(self.files, self.times, self.collection)
        return files

    def __call__(self, step, result) -> None:
        self.add(result.solution, step)

    def _remove_stale(self) -> None:
        """Remove an earlier series' step files on this stem (exactly the names this writer makes)."""
        folder = self.base.parent
        if not folder.is_dir():
            return
        pattern = re.compile(re.escape(self.base.name) + r"_\d{4}(" + re.escape(CRACK_SUFFIX) + r")?\.vtu")
        for f in folder.iterdir():
            if pattern.fullmatch(f.name) and f.is_file():
                f.unlink()
