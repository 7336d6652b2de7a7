"""A sweep's request, checked before any run: the grid of (element, maxh, nu, friction) and its reference.

`_Grid.checked` refuses a bad request (elements, sizes, Poisson ratios, friction
coefficients, adaptivity and solve options) with the field named before anything is
written; `_Grid.check_sizes` runs solve's size guard on every run. The grid then names
every run (its key in the CSV, its Case, its reference's cache file).
"""

from __future__ import annotations

import itertools
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ...core.errors import InputError
from ...core.friction_checks import check_friction_applies, warn_friction_not_applied  # noqa: F401 (re-exported)
from ...core.options import SolveOptions
from ...shell.files import file_name_part
from .cases import MESH_OPTIONS, Case
from .results import _SETUP_COLUMNS, KEY_DIGITS, _key, scene_friction


def _as_list(values, name: str) -> list:
    if values is None:
        return []
    if isinstance(values, (str, int, float)):
        values = [values]
    values = list(values)
    if not values:
        raise InputError(f"{name}: give at least one value")
    return values


def _check_sizes(values: Sequence, name: str) -> list[float]:
    out = []
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or not (math.isfinite(v) and v > 0):
            raise InputError(f"{name} = {v!r}: must be a finite number > 0")
        out.append(float(v))
    return out



@dataclass
class _Grid:
    """A checked sweep request: what to run and against which reference."""

    scene: Any
    elements: list[str]
    sizes: list[float]       # decreasing
    nus: list[float]
    frictions: list[float | None]  # [None]: the scene's own coefficients
    ref_h: float
    separate: bool           # the reference is a run of its own, not the finest row
    reference_element: str | None
    solve_options: dict
    setup: dict              # the _SETUP_COLUMNS values of every row
    adapt_maxh: float | None = None  # adaptive runs (sizes are tolerances) from this mesh size
    vtk: str | None = None           # every row's ParaView files go to this stem (sweep's vtk=)

    @classmethod
    def checked(cls, scene, elements, maxh, nu, reference_maxh, reference_element, jobs, solve_options,
                friction=None, adapt_maxh: float | None = None) -> _Grid:
        from ...planar import elements as _elements

        elements = _as_list(elements, "elements")
        for el in elements + ([reference_element] if reference_element is not None else []):
            if el not in _elements.ELEMENTS:
                raise InputError(f"element = {el!r}: allowed values are {', '.join(_elements.ELEMENTS)}")
        sizes = sorted(set(_check_sizes(_as_list(maxh, "maxh" if adapt_maxh is None else "adapt"),
                                        "maxh" if adapt_maxh is None else "adapt")), reverse=True)
        nus = [float(v) for v in _as_list(nu, "nu")] if nu is not None else [float(scene.material.nu)]
        for v in nus:
            scene.with_(nu=v)  # validates (a SceneError names the field)
        frictions: list = [None]
        if friction is not None:
            values = _as_list(friction, "friction")
            for f in values:
                scene.with_(friction=f)  # validates (a SceneError names the field)
            frictions = list(dict.fromkeys(float(f) for f in values))
        for k in ("maxh", "element", "scene", "adapt"):
            if k in (solve_options or {}):
                raise InputError(f"solve_options: {k!r} is set by the sweep itself")
        try:  # every solve option checked once, before any run starts
            options = SolveOptions.of(**(solve_options or {}))
        except TypeError as exc:
            raise InputError(f"solve_options: {exc}") from None
        for f in frictions:  # every run's friction options
            options.check_for(scene if f is None else scene.with_(friction=f))
        if adapt_maxh is not None:  # every run's adaptivity options
            from ..adapt import check_adapt_options

            for tol, el, v in itertools.product(sizes, elements, nus):
                check_adapt_options(options.replace(element=el, adapt=tol), scene.with_(nu=v))
            if not adapt_maxh or adapt_maxh <= 0:
                raise InputError("adapt_maxh: the first mesh size of adaptive runs is missing (the scene has no maxh)")
        if reference_maxh is not None:
            (reference_maxh,) = _check_sizes([reference_maxh], "reference_maxh")
            if adapt_maxh is None and reference_maxh > sizes[-1] * (1 + 1e-12):
                raise InputError(f"reference_maxh = {reference_maxh:g}: must be at most the finest maxh ({sizes[-1]:g})")
        if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
            raise InputError(f"jobs = {jobs!r}: must be an integer >= 1")
        solve_options = dict(solve_options or {})
        ref_h = reference_maxh if reference_maxh is not None else sizes[-1]
        setup = {"reference_element": reference_element or "", "reference_maxh": ref_h,
                 "crack_model": options.crack_model, "qp_solver": options.qp_solver,
                 "adapt": adapt_maxh is not None}
        separate = not _same(ref_h, sizes[-1]) or (adapt_maxh is not None and reference_maxh is not None)
        return cls(scene=scene, elements=list(dict.fromkeys(elements)), sizes=sizes, nus=list(dict.fromkeys(nus)),
                   frictions=frictions,
                   ref_h=ref_h, separate=separate, reference_element=reference_element,
                   solve_options=solve_options, setup=setup, adapt_maxh=adapt_maxh)

    def check_sizes(self) -> None:
        """The size guard and the thin-part check of `solve` (ngcrack.planar.sizing) for every run, before any starts."""
        from ...planar.sizing import CoarseMeshWarning, check_request

        opts = {k: self.solve_options.get(k) for k in MESH_OPTIONS + ("max_dof",)}
        # adaptive rows start from adapt_maxh (their sizes are tolerances); a reference
        # that is one of them needs no check of its own
        runs = {(el, h if self.adapt_maxh is None else self.adapt_maxh) for el in self.elements for h in self.sizes}
        refs = set()
        if self.adapt_maxh is None:
            runs |= {(self.ref_element(el), self.ref_h) for el in self.elements}
        elif self.separate:  # a fixed-mesh reference: the adaptive budget does not apply to it
            refs = {(self.ref_element(el), self.ref_h) for el in self.elements}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", CoarseMeshWarning)  # the run itself warns
            for el, h in sorted(runs):
                check_request(self.scene, el, h, what=f"sweep of {self.scene.name!r}, element {el!r}", **opts)
            for el, h in sorted(refs):
                check_request(self.scene, el, h, what=f"sweep of {self.scene.name!r}, reference {el!r}",
                              **dict(opts, max_dof=None))

    def cases(self) -> list[tuple[str, float, tuple]]:
        """(element, maxh, (nu, friction)) of every run; friction None: the scene's own."""
        return [(el, h, (v, f)) for el, v, f, h in itertools.product(self.elements, self.nus, self.frictions, self.sizes)]

    def friction_value(self, f: float | None) -> float:
        """The friction a run applies (its row's `friction`): 0 for free and bonded cracks."""
        if self.solve_options.get("crack_model", "contact") != "contact":
            return 0.0
        return scene_friction(self.scene) if f is None else float(f)

    def keys(self) -> list[tuple]:
        return [_key(self.scene.name, el, h, v, self.friction_value(f)) for el, h, (v, f) in self.cases()]

    def ref_element(self, element: str) -> str:
        return self.reference_element or element

    def is_reference_row(self, element: str, h: float) -> bool:
        return not self.separate and self.ref_element(element) == element and _same(h, self.ref_h)

    def check_setup(self, done: dict, out) -> None:
        """Refuse to mix rows of another setup (reference, crack model, QP solver) into one file."""
        for key in self.keys():
            rec = done.get(key)
            for col in _SETUP_COLUMNS if rec is not None else ():
                want, have = self.setup[col], rec[col]
                same = math.isclose(have, want, rel_tol=1e-9) if isinstance(want, float) else str(have) == str(want)
                if not same:
                    raise InputError(f"out = {str(out)!r} holds a row for element={key[1]!r} maxh={key[2]:g} "
                                      f"nu={key[3]:g} friction={key[4]:g} computed with {col} = {have!r}, this sweep asks for {want!r}: "
                                      f"write to another file")

    def ref_file(self, ref_dir: Path, element: str, variant: tuple) -> Path:
        nu, f = variant
        mu = "" if f is None else f"-mu{float(f):.{KEY_DIGITS}g}"
        name = f"{file_name_part(self.scene.name)}-{element}-nu{nu:.{KEY_DIGITS}g}{mu}-h{self.ref_h:.{KEY_DIGITS}g}.npz"
        return ref_dir / name  # a plain name: inside ref_dir, whatever the scene is called

    def case(self, element: str, h: float, variant: tuple, **kw) -> Case:
        nu, f = variant
        # adaptive grids: the rows (and a reference that is a row) adapt; a separate reference
        # is a fixed mesh, to which the budget max_dof of the adaptive runs does not apply
        adaptive = self.adapt_maxh is not None and (kw.get("row", True) or not self.separate)
        fixed_ref = self.adapt_maxh is not None and not adaptive
        options = {k: v for k, v in self.solve_options.items() if k != "max_dof"} if fixed_ref else self.solve_options
        vtk = self.vtk_name(element, h, nu, self.friction_value(f)) if self.vtk and kw.get("row", True) else None
        return Case(self.scene, element, h, nu, options, setup=dict(self.setup), friction=f,
                    adapt_maxh=self.adapt_maxh if adaptive else None, vtk=vtk, **kw)

    def vtk_name(self, element: str, h: float, nu: float, friction: float) -> str:
        """The ParaView files' stem of a row: OUT_<scene>-<element>-h<maxh>-nu<nu>[-mu<friction>]."""
        mu = f"-mu{friction:.{KEY_DIGITS}g}" if friction else ""
        return (f"{self.vtk}_{file_name_part(self.scene.name)}-{element}-h{h:.{KEY_DIGITS}g}"
                f"-nu{nu:.{KEY_DIGITS}g}{mu}")


def _same(a: float, b: float) -> bool:
    return _key("", "", a, 0)[2] == _key("", "", b, 0)[2]
