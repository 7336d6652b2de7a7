"""The explorer's model: a scene, its controls, and the pipeline's caches (no widgets).

`Explorer` holds a scene (or a scene function of `nc.scenes.SCENE_FUNCTIONS` and its
parameters), the solve options and the caches of the pipeline

    scene -> mesh -> discretization (forms assembled) -> condensed K, F
          -> factorization of K_rr and Schur complement S -> QP -> recovery -> post-processing

and `update(**changes)` redoes only what a change invalidates:

- a new load (``load`` multiplier, ``load_angle``, ``friction``) keeps the mesh, the
  assembled matrix, its factorization and S: the load vector is re-assembled (the loads
  are NGSolve Parameters in the assembled linear form, `pipeline.ParameterLoads`), F is
  rebuilt (`CondensedSystem.with_load`), one solve gives the new x0 and b
  (`ContactReduction.with_load`), and a new QP is solved (warm-started from the last
  contact zone); a friction coefficient turned on from zero (or back) needs the
  reduction on the normal and tangential jumps, formed once (from the same assembly)
  and kept next to the frictionless one;
- a new material (``E``, ``nu``) or element re-assembles on the same mesh;
- a new geometry (a scene function's parameters, ``maxh``) remeshes;
- ``field`` (the stress shown) only redraws.

The stages are the library's own: the model keeps one `ngcrack.core.pipeline.Pipeline`, whose
stages are cached under exactly what each depends on, and runs it for every update. A
cached answer is therefore the library's answer to round-off, with everything `solve`
computes (crack profiles with their open / stick / slip states, KKT residuals, the
tips' K_I, K_II, the error estimate).

A bad combination (nu = 1/2 with a displacement baseline, a crack moved out of the
body, ...) never raises out of `update`: the message goes to `error`, the last good
solution stays. `Study` is the model's former name, kept as a deprecated alias.
"""

from __future__ import annotations

import time
import warnings
from typing import Any

import numpy as np

from ...core.errors import InputError
from ...core.options import CRACK_MODELS, SolveOptions
from ...core.pipeline import Pipeline
from ...planar.elements import ELEMENTS
from ...planar.scene import Scene
from ...scenes import SCENE_FUNCTIONS, SceneFunction, scene_function
from ...scenes import load as _load_scene
from ...scenes import names as _scene_names
from .controls import FIXED, SCALES, ControlRefused, Range, check_choice, e_range, mesh_size_range, pressure_range
from .fields import contact_length, overlap_length
from .figure import FIELDS
from .loads import scaled_loads
from .messages import refusal

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
    "load": "load", "load_angle": "load", "friction": "load", "pressure": "load", "crack_model": "load",
    "E": "assemble", "nu": "assemble", "element": "assemble",
    "maxh": "mesh",
}


def _one_line(exc: BaseException) -> str:
    """An exception as one line: its type and the first line of its message."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0] if text else 'no message'}"



#: the crack pressure, relative to E, that a scene loaded by nothing else opens with
UNLOADED_PRESSURE = 1e-3


def _loaded(scene) -> bool:
    """Whether something loads `scene`: a traction or a prescribed displacement that is not zero, a
    body force, a point force or a crack pressure."""
    for bc in scene.boundary.values():
        if bc.type in ("traction", "displacement") and bc.value is not None and any(v != 0 for v in bc.value):
            return True
    if scene.body_force is not None and any(v != 0 for v in scene.body_force):
        return True
    if any(pc.type == "force" for pc in (getattr(scene, "points", None) or ())):
        return True
    return any(c.pressure not in (None, 0.0) for c in scene.cracks)


def _planar_names() -> list[str]:
    """The built-in scenes the explorer draws: the 2D ones."""
    return [n for n in _scene_names() if getattr(_load_scene(n), "dimension", 2) == 2]


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
    `ngcrack.core.solve` unchanged (qp_solver, linear_solver, tip_h, ...).

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
        elif isinstance(scene, str) and scene in _scene_names() and getattr(_load_scene(scene), "dimension", 2) == 2:
            self.base = _load_scene(scene)
        elif isinstance(scene, Scene):
            self.base = scene
        elif isinstance(scene, str) and scene in _scene_names():  # a built-in 3D scene
            raise InputError(f"scene = {scene!r}: a 3D scene; this model holds 2D scenes (one of the scene "
                              f"functions {', '.join(SCENE_FUNCTIONS)} or built-in scenes {', '.join(_planar_names())}); "
                              f"nc.explore({scene!r}) opens the 3D explorer (ngcrack.shell.explorer.SolidExplorer)")
        else:
            raise InputError(f"scene = {scene!r}: a Scene, or one of the scene functions "
                              f"({', '.join(SCENE_FUNCTIONS)}) or built-in 2D scenes ({', '.join(_planar_names())})")
        if self.base is not None and getattr(self.base, "dimension", 2) == 3:  # a 3D scene object
            raise InputError(f"scene {self.base.name!r} is 3D: this model holds 2D scenes; nc.explore(scene) opens the "
                              f"3D explorer (ngcrack.shell.explorer.SolidExplorer)")
        #: the scene's name as given (a scene function's or built-in scene's name), for titles
        self.name = scene.name if isinstance(scene, (Scene, SceneFunction)) else scene
        self.solve_options = dict(solve_options or {})
        self.state: dict[str, Any] = {"element": element, "maxh": maxh, "crack_model": crack_model, "field": field,
                                      "load": load, "load_angle": load_angle, "scales": "auto", "magnification": 0.0}
        if self.function is not None:
            self.state.update({p.name: p.default for p in self.function.parameters if p.kind == "geometry"})
        unknown = [k for k in params if k not in self.state and k not in ("E", "nu", "friction", "pressure")]
        if unknown:
            raise InputError(f"unknown control{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}; "
                              f"allowed: {', '.join(self.controls())}")
        self.state.update(params)
        # the friction control overrides the scene's per-crack coefficients only once it is set
        self._friction_set = "friction" in params
        # likewise the pressure control overrides the cracks' own pressures once it is set
        self._pressure_set = "pressure" in params
        if self.function is not None:
            ref = self.function()  # the material and mesh-size defaults (the geometry is checked by the first update)
        else:
            ref = self.base
        self.state.setdefault("E", ref.material.E)
        self.state.setdefault("nu", ref.material.nu)
        self.state.setdefault("friction", ref.cracks[0].friction if ref.cracks else 0.0)
        own = ref.cracks[0].pressure if ref.cracks else None
        self.state.setdefault("pressure", own if isinstance(own, float) else 0.0)
        if ref.cracks and "pressure" not in params and not _loaded(ref):
            # nothing loads the body (kgd: a crack in a clamped block, loaded by its fluid): open on a
            # crack pressure of E / 1000 (a strain of 1e-3), not on an unloaded body
            self.state["pressure"] = UNLOADED_PRESSURE * ref.material.E
            self._pressure_set = True
        # every value checked before anything is built: ValueError naming the control and what it allows
        check_choice("element", element, ELEMENTS)
        self.ranges: dict[str, Range] = dict(FIXED)
        self.ranges["E"] = e_range(self.state["E"])
        self.ranges["pressure"] = pressure_range(ref)
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
        self.error_detail: str | None = None
        self.refused: tuple[str, ...] = ()
        self.redone: list[str] = []
        self.latency = 0.0
        self.pipeline = Pipeline()
        if solve_now:
            self.update()

    # ------------------------------------------------------------------ controls
    def controls(self) -> tuple[str, ...]:
        """The names `update` accepts."""
        names = ["load", "load_angle", "E", "nu", "friction", "pressure"]
        names += ["maxh", "element", "crack_model", "field", "scales", "magnification"]
        if self.function is not None:
            names += [p.name for p in self.function.geometry()]
        return tuple(names)

    def check(self, name: str, value: Any) -> Any:
        """`value` as control `name` takes it, or ValueError (one line: the control and what it allows)."""
        if name in self.ranges:
            return self.ranges[name].check(name, value)
        if name == "element":
            return check_choice(name, value, ELEMENTS)
        if name == "crack_model":
            return check_choice(name, value, CRACK_MODELS)
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
        if scene.cracks and self._friction_set:
            scene = scene.with_(friction=st["friction"])
        if scene.cracks and self._pressure_set:
            scene = scene.with_(pressure=st["pressure"])
        return scene

    # ------------------------------------------------------------------ update
    def update(self, **changes: Any):
        """Apply `changes` to the controls and redo what they invalidate.

        Returns the new Solution, or None after a failure. Never raises for a bad value or
        combination of values: then `error` is one plain sentence naming the control and
        what to do, `error_detail` the technical line (the field and the rule it breaks),
        `refused` the controls that went back, and the controls, `scene` and `solution`
        stay those of the last good answer (a refused combination is not kept, so that the
        next change starts from values that work). Only before any good answer (a bad
        start) are the new values kept, so that the student can repair them one by one.
        """
        t0 = time.perf_counter()
        self.redone = []
        before, set_before = dict(self.state), (self._friction_set, self._pressure_set)
        try:
            unknown = [k for k in changes if k not in self.controls()]
            if unknown:
                names = ", ".join(unknown)
                raise ControlRefused(f"unknown control{'s' if len(unknown) > 1 else ''} {names}; "
                                     f"allowed: {', '.join(self.controls())}", unknown[0],
                                     f"There is no control called {names}: the controls are "
                                     f"{', '.join(self.controls())}.")
            # a refused value is not kept: the state stays as it was
            changes = {k: self.check(k, v) for k, v in changes.items()}
            self.state.update(changes)
            self._friction_set = self._friction_set or "friction" in changes
            self._pressure_set = self._pressure_set or "pressure" in changes
            if self.solution is not None and changes and all(self.level(k) == "view" for k in changes):
                # the controls are those of the answer shown (a refusal put them back): only a redraw
                self.redone = ["figure"]
                self.error = self.error_detail = None
                self.refused = ()
                return self.solution
            self.solution = self._solve(self.make_scene())
            self.error = self.error_detail = None
            self.refused = ()
            return self.solution
        except Exception as exc:  # noqa: BLE001  (the widget shows every failure as one line)
            self.error, self.error_detail = refusal(exc, changes, self.state)
            self.refused = tuple(changes)
            if self.solution is not None:  # back to the controls of the answer shown
                self.state, (self._friction_set, self._pressure_set) = before, set_before
            return None
        finally:
            self.latency = time.perf_counter() - t0

    def _solve(self, scene: Scene):
        st = self.state
        options = dict(self.solve_options)
        warm = options.pop("warm_start", None)
        if warm is None and self.solution is not None and self.solution.qp is not None:
            warm = self.solution
        opts = SolveOptions.of(**options, element=st["element"], maxh=st["maxh"], crack_model=st["crack_model"])
        sol = self.pipeline.run(scene, opts, warm_start=warm)
        self.redone.extend(self.pipeline.redone)
        self.scene = scene
        return sol

    # ------------------------------------------------------------------ scales
    #: the controls the held scales do not depend on ("hold for load changes"): the scales
    #: are those of the reference load whatever their values
    HELD_AT_REFERENCE = ("load", "load_angle", "friction", "pressure", "crack_model")

    def reference_controls(self) -> dict[str, Any]:
        """The controls of the scales' reference: the current ones with the scene's own load
        (load factor 1, load angle 0), its own friction and crack model contact."""
        return {**self.state, "load": 1.0, "load_angle": 0.0, "crack_model": "contact"}

    def reference_scales(self, field: str | None = None) -> dict:
        """The figure's scales in "hold for load changes" (`fields.fit_scales`): fitted to the
        answer at the scene's reference load (load factor 1, load angle 0, the scene's own
        friction, crack model contact) for the current material, element, mesh size and
        geometry. They depend on these controls only, never on the order in which the
        controls were changed: a load change keeps them, any other change re-fits them.
        Where the current answer is a positive multiple L of the reference's (load factor
        L > 0, load angle 0, crack model contact, the scene's friction: the problem is
        positively homogeneous in the load) they are the current answer's scaled by 1/L;
        otherwise one extra solve at the reference load on the same mesh gives them."""
        from .fields import fit_scales

        field = field or self.state["field"]
        ref = self.reference_controls()
        key = tuple((k, ref[k]) for k in sorted(ref) if k not in self.HELD_AT_REFERENCE
                    and k not in ("field", "scales", "magnification"))
        cached = getattr(self, "_reference", None)
        if cached is None or cached[0] != key:
            st = self.state
            proportional = st["load_angle"] == ref["load_angle"] and st["crack_model"] == "contact" \
                and not self._friction_set and not self._pressure_set and self.error is None \
                and self.solution is not None
            if proportional and st["load"] > 0:
                # contact (and friction) under one proportional load: the answer at load factor
                # L is L times the reference's (positively homogeneous), so no solve is needed
                sol, factor = self.solution, float(st["load"])
            else:
                base = self._base_scene()
                scene = scaled_loads(base, 1.0, 0.0).with_(E=ref["E"], nu=ref["nu"])
                opts = SolveOptions.of(**{k: v for k, v in self.solve_options.items() if k != "warm_start"},
                                       element=ref["element"], maxh=ref["maxh"], crack_model="contact")
                sol, factor = self.pipeline.run(scene, opts), 1.0
            cached = (key, sol, factor, {})
            self._reference = cached
        _, sol, factor, fitted = cached
        if field not in fitted:
            sc = fit_scales(sol, field)
            fitted[field] = {"scale": sc["scale"] * factor, "clim": sc["clim"] / factor, "jump": sc["jump"] / factor,
                             "traction": sc["traction"] / factor, "load": sc["load"] / factor}
        return dict(fitted[field])

    @property
    def counts(self) -> dict[str, int]:
        """How often each stage of the model's pipeline ran for real, or was reused for a load."""
        return self.pipeline.counts

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



class Study(Explorer):
    """Deprecated name of `Explorer` (the explorer's model; `ngcrack.studies.sweeps` holds the sweeps)."""

    def __init__(self, *args: Any, **kwargs: Any):
        warnings.warn("nc.Study is now nc.Explorer (the explorer's model; ngcrack.studies.sweeps holds the sweeps)",
                      DeprecationWarning, stacklevel=2)
        super().__init__(*args, **kwargs)
