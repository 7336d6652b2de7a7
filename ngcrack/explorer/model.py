"""The explorer's model: a scene, its controls, and the pipeline's caches (no widgets).

`Explorer` holds a scene (or a scene function of `nc.scenes.SCENE_FUNCTIONS` and its
parameters), the solve options and the caches of the pipeline

    scene -> mesh -> discretization (forms assembled) -> condensed K, F
          -> factorization of K_rr and Schur complement S -> QP -> recovery -> post-processing

and `update(**changes)` redoes only what a change invalidates:

- a new load (``load`` multiplier, ``load_angle``, ``friction``) keeps the mesh, the
  assembled matrix, its factorization and S: the load vector is re-assembled (the loads
  are NGSolve Parameters in the assembled linear form, `loads.ParameterLoads`), F is
  rebuilt (`CondensedSystem.with_load`), one solve gives the new x0 and b
  (`ContactReduction.with_load`), and a new QP is solved (warm-started from the last
  contact zone); a friction coefficient turned on from zero (or back) needs the
  reduction on the normal and tangential jumps, formed once (from the same assembly)
  and kept next to the frictionless one;
- a new material (``E``, ``nu``) or element re-assembles on the same mesh;
- a new geometry (a scene function's parameters, ``maxh``) remeshes;
- ``field`` (the stress shown) only redraws.

The stages are the library's own: `ngcrack.solve.solve` runs every stage, with the
model's caches standing in for `make_mesh`, `elements.build`, `condense` and
`reduce_to_contact` (bound in `ngcrack.solve` for the duration of the call, then
restored). A cached answer is therefore the library's answer to round-off, with
everything `solve` computes (crack profiles with their open / stick / slip states, KKT
residuals, the tips' K_I, K_II, the error estimate). Each cache is keyed by its stage's
arguments as bound to the stage's signature (defaults filled in: condense's
``tangential``, reduce_to_contact's ``linear_solver`` and ``schur``, the element's
material and order): a stage whose arguments differ from the cached ones, or cannot be
compared, runs for real, so a cache can never give a stale answer.

A bad combination (nu = 1/2 with a displacement baseline, a crack moved out of the
body, ...) never raises out of `update`: the message goes to `error`, the last good
solution stays. `Study` is the model's former name, kept as a deprecated alias.
"""

from __future__ import annotations

import contextlib
import dataclasses
import importlib
import inspect
import time
import warnings
from typing import Any

import numpy as np

from .. import elements as _elements
from ..contact import DEFAULT_SOLVER
from ..geometry import make_mesh as _make_mesh
from ..hybrid import condense as _condense, reduce_to_contact as _reduce_to_contact
from ..scene import Crack, Scene
from ..scenes import SCENE_FUNCTIONS, SceneFunction, load as _load_scene, scene_function
from ..scenes import names as _scene_names
from .controls import FIXED, SCALES, Range, check_choice, e_range, mesh_size_range
from .figure import FIELDS
from .loads import ParameterLoads, load_structure, scaled_loads

#: solve.py, whose stage functions the model stands in for (imported when first needed: no import cycle)
_SOLVE_MODULE = "ngcrack.solve"

#: a crack edge counts as closed where its mid-point opening is below this fraction of the
#: largest jump on the cracks (the QP gives exact zeros up to round-off where it is closed)
CLOSED_RTOL = 1e-6

#: the largest displacement drawn, as a fraction of the body's diameter (the magnification)
DEFORMED_FRACTION = 0.08

#: shading of the crack profiles by the faces' state, where the solution reports one
STATE_COLORS = {"stick": "0.85", "slip": "#fde0b0"}

#: the traction axis spans at least this fraction of the body's stress scale (so that
#: round-off on a traction-free crack is drawn as the zero it is)
PROFILE_FLOOR = 0.05

#: figure size in inches and resolution: small enough to draw in ~0.1 s
FIGURE_SIZE = (10.0, 4.4)
FIGURE_DPI = 80

#: what each control invalidates, from the cheapest: a redraw, a new load vector, a
#: re-assembly on the same mesh, a new mesh
LEVELS = ("view", "load", "assemble", "mesh")
_CONTROL_LEVEL = {
    "field": "view", "scales": "view", "magnification": "view",
    "load": "load", "load_angle": "load", "friction": "load", "crack_model": "load",
    "E": "assemble", "nu": "assemble", "element": "assemble",
    "maxh": "mesh",
}


def friction_supported() -> bool:
    """True where the installed ngcrack's cracks carry a Coulomb ``friction`` coefficient."""
    return "friction" in {f.name for f in dataclasses.fields(Crack)}


def _one_line(exc: BaseException) -> str:
    """An exception as one line: its type and the first line of its message."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0] if text else 'no message'}"



def geometry_key(scene: Scene) -> tuple:
    """What the mesh depends on: the polygon, its labels, the cracks' points and the mesh sizes."""
    return (scene.polygon, scene.labels, tuple(c.points for c in scene.cracks),
            scene.maxh, scene.tip_h, scene.crack_h, scene.grading)


#: the stages' signatures, read once (what a call's arguments are compared by)
_MESH_SIGNATURE = inspect.signature(_make_mesh)
_BUILD_SIGNATURE = inspect.signature(_elements.build)
_CONDENSE_SIGNATURE = inspect.signature(_condense)
_REDUCE_SIGNATURE = inspect.signature(_reduce_to_contact)


def _options_key(signature: inspect.Signature, skip: tuple[str, ...], args: tuple, kwargs: dict) -> tuple | None:
    """The arguments of a call of a stage with `signature` other than those named in `skip`, defaults filled
    in, as a hashable key (so that positional and keyword spellings of one call agree);
    None where they cannot be bound or compared: then the stage runs for real."""
    try:
        bound = signature.bind(*args, **kwargs)
    except TypeError:
        return None
    bound.apply_defaults()
    items = []
    for name, value in bound.arguments.items():
        if name in skip:
            continue
        if isinstance(value, dict):  # **kwargs
            value = tuple(sorted(value.items()))
        items.append((name, value))
    key = tuple(items)
    try:
        hash(key)
    except TypeError:
        return None
    return key


class _ElementsView:
    """`ngcrack.elements` with `build` replaced by the model's cached stage."""

    def __init__(self, build):
        self.build = build

    def __getattr__(self, name):
        return getattr(_elements, name)


class Explorer:
    """The model behind `explore`: one scene, its solve options, the pipeline's caches.

    ``scene`` is a Scene, the name of a built-in scene, or a scene function (a
    `SceneFunction`, or the name of one in `nc.scenes.SCENE_FUNCTIONS`) whose geometry
    parameters then become controls. Controls (all keywords of `update`): ``load`` (a
    multiplier of every load of the scene, 1 = as given, negative reverses it),
    ``load_angle`` (degrees, turns every load vector), ``E``, ``nu``, ``friction``
    (where supported), ``maxh``, ``element``, ``crack_model``, ``field`` (the stress shown,
    one of FIELDS), ``scales`` (the figure's: "auto", "hold", "fit"), ``magnification``
    (0: automatic) and the scene function's parameters. ``solve_options`` go to
    `ngcrack.solve` unchanged (qp_solver, linear_solver, tip_h, ...).

    Every value is checked (`check`, `ranges`: controls.py) when the model is made and
    on every `update`: a bad argument to the constructor raises a ValueError naming the
    control and what it allows, before anything is built; a value out of range later is
    refused (`error`) and not kept. ``name`` is the scene's name as given (for titles).

    After each `update`: ``solution`` the last good `Solution`, ``error`` the one-line
    message of the last failure (None after a success), ``redone`` what the last update
    recomputed, ``counts`` how often each stage ran for real (mesh, assemble,
    factorize) or was reused (load: a load vector only), ``latency`` the wall time
    of the last update in seconds.
    """

    def __init__(self, scene: Scene | str | SceneFunction, element: str = "bdm", *, maxh: float | None = None,
                 crack_model: str = "contact", field: str = "sigma_nu", load: float = 1.0, load_angle: float = 0.0,
                 solve_options: dict | None = None, solve_now: bool = True, **params: Any):
        self.function: SceneFunction | None = None
        self.base: Scene | None = None
        if isinstance(scene, SceneFunction):
            self.function = scene
        elif isinstance(scene, str) and scene in SCENE_FUNCTIONS:
            self.function = scene_function(scene)
        elif isinstance(scene, str) and scene in _scene_names():
            self.base = _load_scene(scene)
        elif isinstance(scene, Scene):
            self.base = scene
        else:
            raise ValueError(f"scene = {scene!r}: a Scene, or one of the scene functions "
                             f"({', '.join(SCENE_FUNCTIONS)}) or built-in scenes ({', '.join(_scene_names())})")
        #: the scene's name as given (a scene function's or built-in scene's name), for titles
        self.name = scene.name if isinstance(scene, (Scene, SceneFunction)) else scene
        self.solve_options = dict(solve_options or {})
        self.state: dict[str, Any] = {"element": element, "maxh": maxh, "crack_model": crack_model, "field": field,
                                      "load": load, "load_angle": load_angle, "scales": "auto", "magnification": 0.0}
        if self.function is not None:
            self.state.update({p.name: p.default for p in self.function.parameters if p.kind == "geometry"})
        unknown = [k for k in params if k not in self.state and k not in ("E", "nu", "friction")]
        if unknown:
            raise ValueError(f"unknown control{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}; "
                             f"allowed: {', '.join(self.controls())}")
        self.state.update(params)
        # the friction control overrides the scene's per-crack coefficients only once it is set
        self._friction_set = "friction" in params
        if self.function is not None:
            ref = self.function()  # the material and mesh-size defaults (the geometry is checked by the first update)
        else:
            ref = self.base
        self.state.setdefault("E", ref.material.E)
        self.state.setdefault("nu", ref.material.nu)
        if friction_supported():
            self.state.setdefault("friction", float(getattr(ref.cracks[0], "friction", 0.0) or 0.0) if ref.cracks else 0.0)
        # every value checked before anything is built: ValueError naming the control and what it allows
        check_choice("element", element, _elements.ELEMENTS)
        self.ranges: dict[str, Range] = dict(FIXED)
        self.ranges["E"] = e_range(self.state["E"])
        self.ranges["maxh"], self.start_maxh = mesh_size_range(ref, element, maxh, self.solve_options)
        if self.function is not None:
            self.ranges.update({p.name: Range(p.low, p.high, p.step) for p in self.function.geometry()})
        for name in list(self.state):
            if name in self.controls() or name in ("scales", "magnification"):
                if name == "maxh" and self.state[name] is None:
                    continue
                self.state[name] = self.check(name, self.state[name])
        self.solution = None
        self.scene: Scene | None = None
        self.error: str | None = None
        self.redone: list[str] = []
        self.latency = 0.0
        self.counts = {"mesh": 0, "assemble": 0, "factorize": 0, "load": 0}
        self._mesh = None  # (key, CrackMesh)
        self._disc = None  # (key, Discretization, _ParameterLoads)
        self._systems: dict = {}  # condense options -> CondensedSystem of the current discretization
        self._reductions: dict = {}  # options -> ContactReduction on the current matrix
        if solve_now:
            self.update()

    # ------------------------------------------------------------------ controls
    def controls(self) -> tuple[str, ...]:
        """The names `update` accepts."""
        names = ["load", "load_angle", "E", "nu"] + (["friction"] if friction_supported() else [])
        names += ["maxh", "element", "crack_model", "field", "scales", "magnification"]
        if self.function is not None:
            names += [p.name for p in self.function.geometry()]
        return tuple(names)

    def check(self, name: str, value: Any) -> Any:
        """`value` as control `name` takes it, or ValueError (one line: the control and what it allows)."""
        if name in self.ranges:
            return self.ranges[name].check(name, value)
        if name == "element":
            return check_choice(name, value, _elements.ELEMENTS)
        if name == "crack_model":
            return check_choice(name, value, importlib.import_module(_SOLVE_MODULE).CRACK_MODELS)
        if name == "field":
            return check_choice(name, value, FIELDS)
        if name == "scales":
            return check_choice(name, value, tuple(SCALES))
        return value

    def level(self, name: str) -> str:
        """What a change of control `name` invalidates (one of LEVELS)."""
        return _CONTROL_LEVEL.get(name, "mesh")

    def _base_scene(self) -> Scene:
        """The scene before load scaling and material: the base scene or the function's value."""
        if self.function is None:
            return self.base
        geo = {p.name: self.state[p.name] for p in self.function.geometry()}
        return self.function(**geo)

    def make_scene(self) -> Scene:
        """The scene the current controls describe (validated; raises on a bad combination)."""
        st = self.state
        scene = scaled_loads(self._base_scene(), st["load"], st["load_angle"]).with_(E=st["E"], nu=st["nu"])
        if friction_supported() and scene.cracks and self._friction_set:
            scene = scene.with_(friction=st["friction"])
        return scene

    # ------------------------------------------------------------------ update
    def update(self, **changes: Any):
        """Apply `changes` to the controls and redo what they invalidate.

        Returns the new Solution, or None after a failure (then `error` holds its
        one-line message and `solution` stays the last good one). Never raises for a
        bad value or combination of values.
        """
        t0 = time.perf_counter()
        self.redone = []
        try:
            unknown = [k for k in changes if k not in self.controls()]
            if unknown:
                raise ValueError(f"unknown control{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}; "
                                 f"allowed: {', '.join(self.controls())}")
            # a refused value is not kept: the state stays as it was
            changes = {k: self.check(k, v) for k, v in changes.items()}
            self.state.update(changes)
            self._friction_set = self._friction_set or "friction" in changes
            if self.solution is not None and changes and all(self.level(k) == "view" for k in changes) \
                    and self.error is None:
                self.redone = ["figure"]
                return self.solution
            self.solution = self._solve(self.make_scene())
            self.error = None
            return self.solution
        except Exception as exc:  # noqa: BLE001  (the widget shows every failure as one line)
            self.error = _one_line(exc)
            return None
        finally:
            self.latency = time.perf_counter() - t0

    def _solve(self, scene: Scene):
        solve_mod = importlib.import_module(_SOLVE_MODULE)
        st = self.state
        self._scene_in_flight = scene
        options = dict(self.solve_options)
        if self.solution is not None and self.solution.qp is not None and "warm_start" not in options:
            options["warm_start"] = self.solution
        with self._stages(solve_mod):
            sol = solve_mod.solve(scene, element=st["element"], maxh=st["maxh"], crack_model=st["crack_model"],
                                  qp_solver=options.pop("qp_solver", DEFAULT_SOLVER), **options)
        self.scene = scene
        return sol

    @contextlib.contextmanager
    def _stages(self, solve_mod):
        """Bind solve.py's four expensive stages to this model's caches for one call."""
        names = ("make_mesh", "_elements", "condense", "reduce_to_contact")
        saved = {n: getattr(solve_mod, n) for n in names}
        solve_mod.make_mesh = self._mesh_stage
        solve_mod._elements = _ElementsView(self._build_stage)
        solve_mod.condense = self._condense_stage
        solve_mod.reduce_to_contact = self._reduce_stage
        try:
            yield
        finally:
            for n, v in saved.items():
                setattr(solve_mod, n, v)

    def _mesh_stage(self, scene, *args, **kwargs):
        options = _options_key(_MESH_SIGNATURE, ("scene",), (scene,) + args, kwargs)
        if options is None:  # arguments the model cannot compare: the real stage, no cache
            return _make_mesh(scene, *args, **kwargs)
        key = (geometry_key(scene), options)
        if self._mesh is None or self._mesh[0] != key:
            self._mesh = (key, _make_mesh(scene, *args, **kwargs))
            self._disc = None
            self._systems, self._reductions = {}, {}
            self.counts["mesh"] += 1
            self.redone.append("mesh")
        return self._mesh[1]

    def _build_stage(self, name, crack_mesh, material, loads, *args, **kwargs):
        scene = self._scene_in_flight
        options = _options_key(_BUILD_SIGNATURE, ("crack_mesh", "loads"), (name, crack_mesh, material, loads) + args, kwargs)
        key = (options, load_structure(scene))
        if options is not None and self._disc is not None and self._disc[0] == key \
                and self._disc[1].crack_mesh is crack_mesh:
            _, disc, ploads = self._disc
            ploads.set(scene)
            disc.f.Assemble()  # (tens of microseconds: starting the TaskManager would cost more)
            self.counts["load"] += 1
            self.redone.append("load vector")
            return disc
        if options is None:  # arguments the model cannot compare: the real stage, no cache
            return _elements.build(name, crack_mesh, material, loads, *args, **kwargs)
        ploads = ParameterLoads(scene)
        disc = _elements.build(name, crack_mesh, material, ploads.loads, *args, **kwargs)
        self._disc = (key, disc, ploads)
        self._systems = {}
        self._reductions = {}
        self.counts["assemble"] += 1
        self.redone.append("assembly")
        return disc

    def _condense_stage(self, disc, loads, *args, **kwargs):
        ploads = self._disc[2] if self._disc is not None and self._disc[1] is disc else None
        options = _options_key(_CONDENSE_SIGNATURE, ("disc", "loads"), (disc, loads) + args, kwargs)
        if ploads is None or options is None:  # not built by this model, or arguments it cannot compare
            return _condense(disc, loads, *args, **kwargs)
        cached = self._systems.get(options)
        if cached is not None:
            system = cached.with_load(ploads.loads)
        else:
            system = _condense(disc, ploads.loads, *args, **kwargs)
            self.redone.append("condensation")
        self._systems[options] = system
        return system

    def _reduce_stage(self, system, *args, **kwargs):
        options = _options_key(_REDUCE_SIGNATURE, ("system",), (system,) + args, kwargs)
        if options is None:
            return _reduce_to_contact(system, *args, **kwargs)
        key = (options, len(system.contact), system.n_normal)
        cached = self._reductions.get(key)
        if cached is not None and cached.system.K is system.K \
                and np.array_equal(cached.system.contact, system.contact):
            self.redone.append("one solve (factorization and S reused)")
            return cached.with_load(system)
        red = _reduce_to_contact(system, *args, **kwargs)
        self._reductions[key] = red
        self.counts["factorize"] += 1
        self.redone.append("factorization and S")
        return red

    # ------------------------------------------------------------------ readouts
    def readouts(self) -> dict[str, Any]:
        """The numbers a user quotes: unknowns, run time split, KKT residual, contact length."""
        sol = self.solution
        if sol is None:
            return {}
        t = sol.timings
        return {
            "unknowns": dict(sol.ndof),
            "time_s": {k: float(t.get(k, 0.0)) for k in ("mesh", "assemble", "linear", "contact", "tips", "estimate",
                                                        "total")},
            "latency_s": self.latency,
            "redone": list(self.redone),
            "kkt": max((float(v) for v in sol.kkt.values() if isinstance(v, (int, float))), default=0.0),
            "contact_length": contact_length(sol),
            "overlap_length": overlap_length(sol),
            "crack_length": float(sum(np.sum(c.length) for c in sol.crack_mesh.cracks)),
        }



def contact_length(sol) -> float:
    """Total length of the crack edges that are closed: faces touching, |mid-point
    opening| below CLOSED_RTOL times the largest jump on the cracks (all of them if
    nothing moves); faces that pass through each other (crack model free) are not."""
    return _length_where(sol, lambda jn, tol: np.abs(jn) <= tol)


def overlap_length(sol) -> float:
    """Total length of the crack edges whose faces pass through each other (opening below
    -CLOSED_RTOL times the largest jump: only without the contact condition)."""
    return _length_where(sol, lambda jn, tol: jn < -tol)


def _length_where(sol, test) -> float:
    profiles = sol.crack_profiles()
    if not profiles:
        return 0.0
    J = max(float(np.max(np.hypot(p.normal_jump, p.tangential_jump), initial=0.0)) for p in profiles)
    total = 0.0
    for p, crack in zip(profiles, sol.crack_mesh.cracks):
        total += float(np.sum(crack.length[test(np.asarray(p.normal_jump), CLOSED_RTOL * J)]))
    return total


class Study(Explorer):
    """Deprecated name of `Explorer` (the explorer's model; `ngcrack.study` is sweeps)."""

    def __init__(self, *args: Any, **kwargs: Any):
        warnings.warn("nc.Study is now nc.Explorer (the explorer's model; ngcrack.study holds the sweeps)",
                      DeprecationWarning, stacklevel=2)
        super().__init__(*args, **kwargs)
