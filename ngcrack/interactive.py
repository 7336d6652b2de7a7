"""Interactive exploration: a model that redoes only what a change invalidates, and its widget.

`Study` is the model (no browser, no widgets): it holds a scene (or a scene function of
`nc.scenes.SCENE_FUNCTIONS` and its parameters), the solve options and the caches of the
pipeline

    scene -> mesh -> discretization (forms assembled) -> condensed K, F
          -> factorization of K_rr and Schur complement S -> QP -> recovery -> post-processing

and `update(**changes)` redoes only what a change invalidates:

- a new load (``load`` multiplier, ``load_angle``, ``friction``) keeps the mesh, the
  assembled matrix, its factorization and S: the load vector is re-assembled (the loads
  are NGSolve Parameters in the assembled linear form), F is rebuilt
  (`CondensedSystem.with_load`), one solve gives the new x0 and b
  (`ContactReduction.with_load`), and a new QP is solved (warm-started from the last
  contact zone); a friction coefficient turned on from zero (or back) needs the
  reduction on the normal and tangential jumps, formed once (from the same assembly)
  and kept next to the frictionless one;
- a new material (``E``, ``nu``) or element re-assembles on the same mesh;
- a new geometry (a scene function's parameters, ``maxh``) remeshes;
- ``field`` (the stress shown) only redraws.

The stages are the library's own: the model keeps one `ngcrack.pipeline.Pipeline`, whose
stages are cached under exactly what each depends on, and runs it for every update. A
cached answer is therefore the library's answer to round-off, with everything `solve`
computes (crack profiles with their open / stick / slip states, KKT residuals, the
tips' K_I, K_II, the error estimate).

`explore(...)` wraps a `Study` in an ipywidgets view (`Explorer`): sliders and menus wired
to `update`, a figure (PNG from matplotlib's Agg canvas: the deformed body coloured by a
stress field, the crack profiles, the tips' K_I, K_II), readouts and a one-line status.
A bad combination (nu = 1/2 with a displacement baseline, a crack moved out of the
body, ...) never raises out of `update`: the message goes to `study.error` and the
status line, the last good solution and figure stay.
"""

from __future__ import annotations

import dataclasses
import functools
import io
import math
import time
from typing import Any

import numpy as np
import ngsolve as ngs

from . import elements as _elements
from .options import CRACK_MODELS, SolveOptions
from .pipeline import Pipeline
from .scene import Crack, Scene
from .scenes import SCENE_FUNCTIONS, SceneFunction, load as _load_scene, scene_function


#: stress fields the figure can show: the crack-normal stress (sigma nu).nu and von Mises
FIELDS = ("sigma_nu", "von_mises")

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
    "field": "view",
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


def _rotate(v, degrees: float, factor: float) -> tuple[float, float]:
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return (factor * (c * v[0] - s * v[1]), factor * (s * v[0] + c * v[1]))


def scaled_loads(scene: Scene, load: float = 1.0, load_angle: float = 0.0) -> Scene:
    """The scene with every load vector (tractions, prescribed displacements, body force)
    multiplied by ``load`` and turned by ``load_angle`` degrees (counter-clockwise)."""
    if load == 1.0 and load_angle == 0.0:
        return scene
    boundary = {}
    for label, bc in scene.boundary.items():
        if bc.type in ("traction", "displacement"):
            boundary[label] = {"type": bc.type, "value": list(_rotate(bc.value, load_angle, load))}
        else:
            boundary[label] = bc
    body = None if scene.body_force is None else _rotate(scene.body_force, load_angle, load)
    return scene.with_(boundary=boundary, body_force=body)


class Study:
    """The model behind `explore`: one scene, its solve options, the pipeline's caches.

    ``scene`` is a Scene, the name of a built-in scene, or a scene function (a
    `SceneFunction`, or the name of one in `nc.scenes.SCENE_FUNCTIONS`) whose geometry
    parameters then become controls. Controls (all keywords of `update`): ``load`` (a
    multiplier of every load of the scene, 1 = as given, negative reverses it),
    ``load_angle`` (degrees, turns every load vector), ``E``, ``nu``, ``friction``
    (where supported), ``maxh``, ``element``, ``crack_model``, ``field`` (the stress shown,
    one of FIELDS) and the scene function's parameters. ``solve_options`` go to
    `ngcrack.solve` unchanged (qp_solver, linear_solver, tip_h, ...).

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
        elif isinstance(scene, str):
            self.base = _load_scene(scene)
        elif isinstance(scene, Scene):
            self.base = scene
        else:
            raise ValueError(f"scene = {scene!r}: a Scene, a built-in scene name or a scene function "
                             f"({', '.join(SCENE_FUNCTIONS)})")
        self.solve_options = dict(solve_options or {})
        self.state: dict[str, Any] = {"element": element, "maxh": maxh, "crack_model": crack_model, "field": field,
                                      "load": float(load), "load_angle": float(load_angle)}
        if self.function is not None:
            self.state.update({p.name: p.default for p in self.function.parameters if p.kind == "geometry"})
        unknown = [k for k in params if k not in self.state and k not in ("E", "nu", "friction")]
        if unknown:
            raise ValueError(f"unknown control{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}; "
                             f"allowed: {', '.join(self.controls())}")
        self.state.update(params)
        # the friction control overrides the scene's per-crack coefficients only once it is set
        self._friction_set = "friction" in params
        try:
            ref = self._base_scene()
        except ValueError:  # bad geometry parameters: shown by the first update; material from the defaults
            ref = self.function() if self.function is not None else self.base
        self.state.setdefault("E", ref.material.E)
        self.state.setdefault("nu", ref.material.nu)
        if friction_supported():
            self.state.setdefault("friction", float(getattr(ref.cracks[0], "friction", 0.0) or 0.0) if ref.cracks else 0.0)
        self.solution = None
        self.scene: Scene | None = None
        self.error: str | None = None
        self.redone: list[str] = []
        self.latency = 0.0
        self.pipeline = Pipeline()
        if solve_now:
            self.update()

    # ------------------------------------------------------------------ controls
    def controls(self) -> tuple[str, ...]:
        """The names `update` accepts."""
        names = ["load", "load_angle", "E", "nu"] + (["friction"] if friction_supported() else [])
        names += ["maxh", "element", "crack_model", "field"]
        if self.function is not None:
            names += [p.name for p in self.function.geometry()]
        return tuple(names)

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
            if "field" in changes and changes["field"] not in FIELDS:
                raise ValueError(f"field = {changes['field']!r}: allowed values are {', '.join(FIELDS)}")
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
            "time_s": {k: float(t.get(k, 0.0)) for k in ("mesh", "assemble", "linear", "contact", "total")},
            "latency_s": self.latency,
            "redone": list(self.redone),
            "kkt": max((float(v) for v in sol.kkt.values() if isinstance(v, (int, float))), default=0.0),
            "contact_length": contact_length(sol),
            "crack_length": float(sum(np.sum(c.length) for c in sol.crack_mesh.cracks)),
        }


def contact_length(sol) -> float:
    """Total length of the crack edges that are closed (mid-point opening below
    CLOSED_RTOL times the largest jump on the cracks; all of them if nothing moves)."""
    profiles = sol.crack_profiles()
    if not profiles:
        return 0.0
    J = max(float(np.max(np.hypot(p.normal_jump, p.tangential_jump), initial=0.0)) for p in profiles)
    total = 0.0
    for p, crack in zip(profiles, sol.crack_mesh.cracks):
        closed = p.normal_jump <= CLOSED_RTOL * J
        total += float(np.sum(crack.length[closed]))
    return total


# ---------------------------------------------------------------------- the figure


def _tip_value(tip, key):
    return tip.get(key) if isinstance(tip, dict) else getattr(tip, key, None)


def stress_values(sol, field: str) -> np.ndarray:
    """Per triangle (at its centroid): sigma_nu = (sigma nu).nu with nu the first crack's
    normal ((0, 1) without a crack), or the von Mises stress of the symmetric part (with
    sigma_zz = nu (sigma_xx + sigma_yy) in plane strain, 0 in plane stress)."""
    cm = sol.crack_mesh
    cent = cm.centroids
    sig = np.asarray(sol.sigma(sol.mesh(cent[:, 0], cent[:, 1]))).reshape(-1, 2, 2)
    sig = 0.5 * (sig + np.transpose(sig, (0, 2, 1)))
    if field == "sigma_nu":
        nu = cm.cracks[0].normal[0] if cm.cracks else np.array([0.0, 1.0])
        return np.einsum("i,eij,j->e", nu, sig, nu)
    mat = sol.scene.material
    sxx, syy, sxy = sig[:, 0, 0], sig[:, 1, 1], sig[:, 0, 1]
    szz = mat.nu * (sxx + syy) if mat.plane == "strain" else 0.0 * sxx
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3 * sxy ** 2)


def draw(sol, field: str = "sigma_nu", title: str = "") -> bytes:
    """The figure of a solution as PNG bytes (one-off; `Drawing` redraws a figure it keeps)."""
    return Drawing().render(sol, field, title)


class Drawing:
    """A figure kept between redraws (matplotlib's Agg canvas, no pyplot state).

    Left: the deformed body, each triangle moved by the locally post-processed
    displacement (plots.element_displacements), magnified so that the largest
    displacement is DEFORMED_FRACTION of the body's diameter (the crack opening and
    sliding show as gaps and offsets), coloured by a stress field (`stress_values`).
    Right: the crack profiles along s (opening [u].nu, sliding [u].t; normal and shear
    traction on a twin axis), the stick/slip state as shaded bands where the profiles
    carry one, the tips' K_I, K_II in the title where the solution has them. The axes,
    colour bar and fonts are made once: a redraw only replaces data (measured: a new
    figure with a layout engine took 0.5-0.9 s, this 0.1-0.2 s).
    """

    def __init__(self):
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import PolyCollection
        from matplotlib.figure import Figure

        self.fig = fig = Figure(figsize=FIGURE_SIZE, dpi=FIGURE_DPI)
        FigureCanvasAgg(fig)
        self.ax, self.axp = fig.subplots(1, 2, width_ratios=[1.15, 1])
        fig.subplots_adjust(left=0.04, right=0.92, bottom=0.12, top=0.87, wspace=0.32)
        self.axt = self.axp.twinx()
        self.body = PolyCollection(np.zeros((0, 3, 2)), cmap="RdBu_r", edgecolors="face", linewidths=0.1)
        self.body.set_array(np.zeros(0))
        self.ax.add_collection(self.body)
        self.colorbar = fig.colorbar(self.body, ax=self.ax, shrink=0.85)
        self.ax.set_aspect("equal")
        self.axp.set_xlabel("s along the crack")
        self.axp.set_ylabel("jump")
        self.axt.set_ylabel("traction")
        self._temporary: list = []

    def render(self, sol, field: str = "sigma_nu", title: str = "") -> bytes:
        """Draw `sol` with the stress `field` (one of FIELDS) and return the PNG bytes."""
        from .plots import element_displacements

        for artist in self._temporary:
            artist.remove()
        self._temporary = []
        ax, axp, axt = self.ax, self.axp, self.axt
        corners, disp = element_displacements(sol)
        poly = np.asarray(sol.scene.polygon)
        diam = float(np.max(np.linalg.norm(poly[:, None] - poly[None], axis=2)))
        umax = float(np.max(np.linalg.norm(disp, axis=2)))
        scale = DEFORMED_FRACTION * diam / umax if umax > 0 else 0.0
        vals = stress_values(sol, field)
        self.body.set_verts(corners + scale * disp)
        self.body.set_array(vals)
        if field == "sigma_nu":
            lim = float(np.percentile(np.abs(vals), 99)) or 1.0
            self.body.set_cmap("RdBu_r")
            self.body.set_clim(-lim, lim)
        else:
            self.body.set_cmap("viridis")
            self.body.set_clim(0.0, float(np.percentile(vals, 99)) or 1.0)
        self.colorbar.set_label("σ_ν = (σν)·ν" if field == "sigma_nu" else "von Mises stress")
        self._temporary += ax.plot(*np.vstack([poly, poly[:1]]).T, color="0.6", lw=0.6, ls="--")
        # the cracks drawn where the body went: each crack vertex moved by the mean of its
        # triangles' corner displacements (the middle of the gap where the crack opens)
        cm = sol.crack_mesh
        moved = np.zeros_like(cm.points)
        count = np.zeros(len(cm.points))
        np.add.at(moved, cm.triangles.ravel(), disp.reshape(-1, 2))
        np.add.at(count, cm.triangles.ravel(), 1.0)
        moved = cm.points + scale * moved / np.maximum(count, 1.0)[:, None]
        for crack in cm.cracks:
            pts = moved[crack.vertices()]
            self._temporary += ax.plot(pts[:, 0], pts[:, 1], color="k", lw=0.6, alpha=0.5)
        tips = [t for t in (getattr(sol, "tips", None) or []) if _tip_value(t, "K_I") is not None]
        for tip in tips:
            if _tip_value(tip, "x") is not None:
                at = np.array([_tip_value(tip, "x"), _tip_value(tip, "y")], float)
                nearest = int(np.argmin(np.linalg.norm(cm.points - at, axis=1)))  # the tip is a mesh vertex
                self._temporary += ax.plot([moved[nearest, 0]], [moved[nearest, 1]], "k*", ms=7)
        ax.relim()
        ax.update_datalim(np.vstack([(corners + scale * disp).reshape(-1, 2), poly]))
        ax.autoscale_view()
        ax.set_title(f"{title or sol.scene.name} ({sol.element}): displacement x {scale:.3g}", fontsize=10)
        profiles = sol.crack_profiles()
        has_state = False
        for k, p in enumerate(profiles):
            sfx = f" (crack {k})" if len(profiles) > 1 else ""
            self._temporary += axp.plot(p.s, p.normal_jump, "-", color="tab:blue", label="opening [u]·ν" + sfx)
            self._temporary += axp.plot(p.s, p.tangential_jump, "--", color="tab:green", label="sliding [u]·t" + sfx)
            self._temporary += axt.plot(p.s, p.normal_stress, "-", color="tab:red", lw=1, label="σ_n" + sfx)
            self._temporary += axt.plot(p.s, p.shear_stress, ":", color="tab:purple", lw=1, label="σ_t" + sfx)
            state = getattr(p, "state", None)
            if state is not None and len(p.s) > 1:
                s = np.asarray(p.s, float)
                mids = 0.5 * (s[1:] + s[:-1])
                edges = np.r_[s[0] - (mids[0] - s[0]), mids, s[-1] + (s[-1] - mids[-1])]
                for lo, hi, st in zip(edges[:-1], edges[1:], state):
                    if st in STATE_COLORS:
                        self._temporary.append(axp.axvspan(lo, hi, color=STATE_COLORS[st], lw=0, zorder=0))
                        has_state = True
        self._temporary.append(axp.axhline(0.0, color="0.5", lw=0.5))
        # symmetric axes (both zeros on one line); round-off is not magnified to fill them
        stress_scale = float(np.percentile(np.abs(vals), 99)) or 1.0
        jmax = max([float(np.max(np.abs(np.r_[p.normal_jump, p.tangential_jump]), initial=0.0)) for p in profiles] + [0.0])
        tmax = max([float(np.max(np.abs(np.r_[p.normal_stress, p.shear_stress]), initial=0.0)) for p in profiles] + [0.0])
        axp.set_ylim(-1.1 * (jmax or 1.0), 1.1 * (jmax or 1.0))
        tlim = max(tmax, PROFILE_FLOOR * stress_scale)
        axt.set_ylim(-1.1 * tlim, 1.1 * tlim)
        if profiles:
            axp.set_xlim(0.0, max(float(c.s_mid[-1] + 0.5 * c.length[-1]) for c in sol.crack_mesh.cracks))
        handles, labels = axp.get_legend_handles_labels()
        handles_t, labels_t = axt.get_legend_handles_labels()
        if handles:
            self._temporary.append(axp.legend(handles + handles_t, labels + labels_t, fontsize=7, loc="best"))
        title = "crack profiles" if profiles else "no crack"
        if has_state:
            title += " (grey: stick, orange: slip)"
        if tips:
            title = "(K_I, K_II) at the tips: " + ", ".join(
                f"({_tip_value(t, 'K_I'):.3g}, {_tip_value(t, 'K_II'):.3g})" for t in tips) + "\n" + title
        axp.set_title(title, fontsize=8 if tips or has_state else 10)
        buf = io.BytesIO()
        self.fig.savefig(buf, format="png")
        return buf.getvalue()


# ---------------------------------------------------------------------- the widget

#: slider ranges of the controls every scene has: (low, high, step)
SLIDERS = {
    "load": (-2.0, 2.0, 0.1),
    "load_angle": (-180.0, 180.0, 5.0),
    "nu": (0.0, 0.5, 0.01),
    "friction": (0.0, 1.0, 0.05),
}


def explore(scene: Scene | str | SceneFunction, element: str = "bdm", *, webgui: bool = False, **kwargs: Any):
    """An ipywidgets view of a `Study` of `scene` (see `Study` for the controls).

    ``nc.explore("inclined-crack")`` shows the inclined crack with sliders for its angle,
    half length and position; ``nc.explore(scene)`` a fixed geometry. ``webgui`` adds a
    checkbox for NGSolve's 3D view of the stress field. Returns an `Explorer`
    (an ipywidgets VBox; `.study` is the model).
    """
    return _explorer_class()(Study(scene, element, **kwargs), webgui=webgui)


@functools.lru_cache(maxsize=1)
def _explorer_class() -> type:
    """`Explorer`, built on first use (ipywidgets is imported only when a widget is made)."""
    import ipywidgets

    return type("Explorer", (_ExplorerView, ipywidgets.VBox), {"__doc__": _ExplorerView.__doc__,
                                                                "__module__": __name__})


def __getattr__(name: str):
    if name == "Explorer":
        return _explorer_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class _ExplorerView:
    """Sliders and menus wired to `Study.update`, the figure, readouts and a status line
    (an ipywidgets VBox: `ngcrack.interactive.Explorer`).

    `controls` maps control names to their widgets; `image` holds the figure (PNG);
    `status` the one-line message of the last failure (empty after a success);
    `latency` the wall time from the last control change to the new figure (seconds).
    """

    def __init__(self, study: Study, webgui: bool = False):
        import ipywidgets as w

        self.study = study
        st = study.state
        self.controls: dict[str, Any] = {}
        cont = {"continuous_update": False, "style": {"description_width": "90px"},
                "layout": w.Layout(width="320px")}
        for name in ("load", "load_angle", "nu") + (("friction",) if "friction" in st else ()):
            lo, hi, step = SLIDERS[name]
            self.controls[name] = w.FloatSlider(value=float(st[name]), min=lo, max=hi, step=step,
                                                description={"load_angle": "load angle", "load": "load x"}.get(name, name),
                                                readout_format=".2f", **cont)
        E = float(st["E"])
        self.controls["E"] = w.FloatLogSlider(value=E, base=10, min=math.log10(E) - 2, max=math.log10(E) + 2, step=0.1,
                                              description="E", readout_format=".3g", **cont)
        h0 = float(st["maxh"] if st["maxh"] is not None else (study.solution.maxh if study.solution else 1.0))
        self.controls["maxh"] = w.FloatLogSlider(value=h0, base=10, min=math.log10(h0) - 1, max=math.log10(h0) + 0.5,
                                                 step=0.05, description="mesh size", readout_format=".3g", **cont)
        menu = {k: v for k, v in cont.items() if k != "continuous_update"}
        self.controls["element"] = w.Dropdown(options=list(_elements.ELEMENTS), value=st["element"],
                                              description="element", **menu)
        crack_models = CRACK_MODELS
        self.controls["crack_model"] = w.Dropdown(options=list(crack_models), value=st["crack_model"],
                                                  description="crack model", **menu)
        if study.function is not None:
            for p in study.function.geometry():
                self.controls[p.name] = w.FloatSlider(value=float(st[p.name]), min=p.low, max=p.high, step=p.step,
                                                      description=p.name.replace("_", " "), tooltip=p.doc,
                                                      readout_format=".2f", **cont)
        self.controls["field"] = w.ToggleButtons(options=[("sigma_nu", "sigma_nu"), ("von Mises", "von_mises")],
                                                 value=st["field"], description="stress",
                                                 style={"description_width": "90px", "button_width": "90px"})
        for name, widget in self.controls.items():
            widget.observe(lambda change, name=name: self._changed(name, change["new"]), names="value")
        self.image = w.Image(format="png", layout=w.Layout(width="800px"))
        self.image.add_class("ngcrack-figure")
        self.readout = w.HTML()
        self.status = w.HTML()
        self.status.add_class("ngcrack-status")
        self._png = b""
        self.latency = 0.0
        self.drawing = Drawing()
        children_controls = [self.controls[k] for k in self.controls if k != "field"]
        half = (len(children_controls) + 1) // 2
        grid = w.HBox([w.VBox(children_controls[:half]), w.VBox(children_controls[half:])])
        parts = [grid, self.controls["field"], self.status, self.image, self.readout]
        self.webgui = None
        if webgui:
            self.webgui = w.Output()
            box = w.Checkbox(value=False, description="NGSolve webgui (3D) view")
            box.observe(lambda change: self._draw_webgui(change["new"]), names="value")
            parts += [box, self.webgui]
        super().__init__(parts)
        self._refresh()

    def _changed(self, name: str, value) -> None:
        t0 = time.perf_counter()
        self.study.update(**{name: value})
        self._refresh()
        self.latency = time.perf_counter() - t0

    def _refresh(self) -> None:
        s = self.study
        if s.error is None and s.solution is not None:
            try:
                self._png = self.drawing.render(s.solution, s.state["field"])
                self.image.value = self._png
            except Exception as exc:  # noqa: BLE001  (a drawing failure is reported, never raised)
                s.error = _one_line(exc)
        kept = "showing the last good answer" if s.solution is not None else "no answer yet"
        self.status.value = ("" if s.error is None else
                             f"<span style='color:#b00020'>&#9888; {_escape(s.error)} ({kept})</span>")
        r = s.readouts()
        if r:
            t = r["time_s"]
            nd = r["unknowns"]
            self.readout.value = (
                f"<b>unknowns</b> {nd['total']} (global {nd['global']}, contact {nd['contact']}) &nbsp; "
                f"<b>time</b> mesh {t['mesh']:.2f} s, assemble {t['assemble']:.2f} s, linear {t['linear']:.2f} s, "
                f"contact {t['contact']:.2f} s; update {r['latency_s']:.2f} s ({_escape(', '.join(r['redone']) or '-')})"
                f"<br><b>KKT residual</b> {r['kkt']:.1e} &nbsp; <b>contact length</b> {r['contact_length']:.3g} "
                f"of {r['crack_length']:.3g}")
        if self.webgui is not None and getattr(self, "_webgui_on", False):
            self._draw_webgui(True)

    def _draw_webgui(self, on: bool) -> None:
        self._webgui_on = on
        self.webgui.clear_output()
        if not on or self.study.solution is None:
            return
        with self.webgui:
            try:
                from ngsolve.webgui import Draw

                sol = self.study.solution
                sig = sol.sigma
                vm = ngs.sqrt(sig[0, 0] ** 2 + sig[1, 1] ** 2 - sig[0, 0] * sig[1, 1] + 3 * sig[0, 1] ** 2)
                Draw(vm, sol.mesh, "von Mises (plane stress form)")
            except Exception as exc:  # noqa: BLE001
                print(_one_line(exc))


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
