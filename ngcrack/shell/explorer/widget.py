"""The explorer's ipywidgets view: `explore()` and `ExplorerWidget`.

Sliders, typed values and menus wired to `Explorer.update` (the model), the figure
(`Drawing`, a PNG in an ipywidgets Image), readouts and a one-line status. ipywidgets is
imported only when a widget is made.

Every numeric control is a slider and a box for a typed value: a typed value out of the
control's range is refused (the status says so in one line, naming the control and the
range), never clamped, and both the slider and the box go back to the model's value, so
that the widgets and the model always agree. While a solve runs the figure is greyed and
the status says "solving..."; the readout's time split adds up to the time from the
change to the new figure (solve stages, tips, estimate, the rest of the solve, drawing).
"""

from __future__ import annotations

import functools
import html
import json
import math
import time
from typing import Any

import ngsolve as ngs

from ...core.constraints import ContactSolverError
from ...core.errors import InputError
from ...core.options import CRACK_MODELS
from ...core.schur import LinearSolverError
from ...core.stages import SolveError
from ...planar import elements as _elements
from ...planar.scene import Scene
from ...scenes import SceneFunction
from .controls import CRACK_MODEL_HELP, CRACK_MODEL_LABELS, HELP, LABELS, SCALES
from .figure import FIELDS, Drawing
from .messages import GLOSSARY, WEBGUI_PACKAGES, WIDGET_PACKAGES, ArgumentError, MissingExtraError, require_extras  # noqa: F401
from .model import Explorer, _one_line
from .webgui import display_webgui

#: the page's style: the busy figure greyed, the refusals red
STYLE = """<style>
.ngcrack-busy { opacity: 0.35; filter: grayscale(100%); transition: opacity 0.1s; }
.ngcrack-status { color: #b00020; font-size: 13px; }
.ngcrack-readout { font-size: 13px; line-height: 1.45; }
.ngcrack-help { font-size: 12px; color: #444; }
</style>"""

#: the load factor's meaning, under the controls
LOAD_HELP = "+1: the loads as the scene gives them, -1: reversed, 0: unloaded"
#: what the scales menu does
SCALES_HELP = ("hold for load changes: colour limits and magnification are those of the scene's own load (load "
               "factor 1, angle 0, contact) for the current material, element, mesh and geometry, so that loads and "
               "crack models are compared on one scale; hold always (kept from the first frame held); or fit "
               "every frame")

#: width of a box for a typed value: room for E = 30000000000 (kgd's 30 GPa in Pa) without cutting it
TYPED_WIDTH = "110px"

#: the slider ranges of older imports (the model's `ranges` are what counts)
SLIDERS = {"load": (-2.0, 2.0, 0.1), "load_angle": (-180.0, 180.0, 5.0), "nu": (0.0, 0.5, 0.01),
           "friction": (0.0, 1.0, 0.05)}


def explore(scene: Scene | str | SceneFunction, element: str = "bdm", *, webgui: bool = False, **kwargs: Any):
    """An ipywidgets view of an `Explorer` of `scene` (see `Explorer` for the controls).

    ``nc.explore("inclined-crack")`` shows the inclined crack with sliders for its angle,
    half length and position; ``nc.explore(scene)`` a fixed geometry. ``webgui`` adds a
    checkbox for NGSolve's 3D view of the stress field. Returns an `ExplorerWidget`
    (an ipywidgets VBox; `.model` is the model). Bad arguments raise one ValueError
    naming the argument and what it allows, before any widget is made; a missing
    ``explorer`` extra one line naming it (`MissingExtraError`), before any solve.
    """
    require_extras("nc.explore", WIDGET_PACKAGES + (WEBGUI_PACKAGES if webgui else ()))  # before any solve
    if _is_3d(scene):  # the 3D explorer: K along the fronts, the faces' map, NGSolve's view of the body
        from .solid_view import explore_solid

        if element not in ("bdm", "tdnns"):  # (bdm is the 2D default: 3D solves with tdnns)
            raise ArgumentError(f"element = {element!r}: a 3D scene is solved with tdnns")
        return explore_solid(scene, webgui=webgui, **kwargs)
    try:
        model = Explorer(scene, element, **kwargs)  # (checks every argument before it builds anything)
    except InputError as exc:
        raise ArgumentError(str(exc)) from None
    return _widget_class()(model, webgui=webgui)


def _is_3d(scene) -> bool:
    """Whether `scene` is a 3D scene or the name of a built-in one."""
    if isinstance(scene, str):
        from ...scenes import load, names

        return scene in names() and getattr(load(scene), "dimension", 2) == 3
    return getattr(scene, "dimension", 2) == 3


@functools.lru_cache(maxsize=1)
def _widget_class() -> type:
    """`ExplorerWidget`, built on first use (ipywidgets is imported only when a widget is made)."""
    import ipywidgets

    return type("ExplorerWidget", (_ExplorerView, ipywidgets.VBox), {"__doc__": _ExplorerView.__doc__,
                                                                      "__module__": __name__})


def __getattr__(name: str):
    if name == "ExplorerWidget":
        return _widget_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _escape(text: str) -> str:
    return html.escape(text, quote=False)


def _term(key: str, shown: str) -> str:
    """A readout's word with its one-line meaning on hover (messages.GLOSSARY)."""
    return (f"<b><abbr title='{html.escape(GLOSSARY[key], quote=True)}' style='text-decoration: underline dotted; "
            f"cursor: help'>{_escape(shown)}</abbr></b>")


def status_html(model) -> str:
    """The refusal: one plain sentence (red), and the technical line beneath it, smaller and
    grey (also its tooltip); where the controls went back, it says so."""
    back = ""
    if model.refused and model.solution is not None:
        names = [LABELS.get(k, k.replace("_", " ")) for k in model.refused if k in model.state]
        if names:
            back = " The " + " and ".join(names) + (" is" if len(names) == 1 else " are") + " back to the figure's value."
    kept = "" if model.solution is not None else " No answer yet."
    detail = model.error_detail or ""
    return (f"<div title='{html.escape(detail, quote=True)}'>&#9888; {_escape(model.error)}{_escape(back + kept)}"
            + (f"<div style='color:#666; font-size:11px'>details: {_escape(detail)}</div>" if detail else "")
            + "</div>")


class _ExplorerView:
    """Sliders, typed values and menus wired to `Explorer.update`, the figure, readouts and
    a status line (an ipywidgets VBox: `ngcrack.shell.explorer.ExplorerWidget`).

    `model` is the `Explorer` (also as `study`, its former name); `controls` maps control
    names to their main widgets (sliders, menus), `typed` the numeric controls to their
    boxes for typed values; `image` holds the figure (PNG); `status` the one-line message
    of the last failure or refusal (empty after a success); `readout` the numbers;
    `data` (hidden) what the figure shows, as JSON, for checks; `latency` the wall time
    from the last control change to the new figure, `timing` its split (seconds).
    """

    def __init__(self, model: Explorer, webgui: bool = False):
        import ipywidgets as w

        self.model = model
        st = model.state
        self.controls: dict[str, Any] = {}
        self.typed: dict[str, Any] = {}
        self._syncing = False
        self._png = b""
        self.latency = 0.0
        self.timing: dict[str, float] = {}
        self.drawing = Drawing()
        style = {"description_width": "125px"}
        rows = []
        numeric = ["load", "load_angle", "E", "nu"] + [k for k in ("friction", "pressure") if k in st] + ["maxh"]
        if model.function is not None:
            numeric += [p.name for p in model.function.geometry()]
        for name in numeric:
            r = model.ranges[name]
            value = st[name] if st[name] is not None else model.start_maxh
            tip = HELP.get(name) or (self._param_doc(name) or "")
            common = {"description": LABELS.get(name, name.replace("_", " ")), "readout": False,
                      "continuous_update": False, "style": style, "layout": w.Layout(width="300px"),
                      "tooltip": tip}
            if r.log:
                slider = w.FloatLogSlider(value=float(value), base=10, min=math.log10(r.low), max=math.log10(r.high),
                                          step=r.step, **common)
            else:
                slider = w.FloatSlider(value=float(value), min=r.low, max=r.high, step=r.step, **common)
            box = w.FloatText(value=float(value), layout=w.Layout(width=TYPED_WIDTH), tooltip=tip)
            box.add_class(f"ngcrack-typed-{name}")
            slider.add_class(f"ngcrack-slider-{name}")
            self.controls[name], self.typed[name] = slider, box
            rows.append(w.HBox([slider, box]))
        menu = {"style": style, "layout": w.Layout(width="300px")}
        self.controls["element"] = w.Dropdown(options=list(_elements.ELEMENTS), value=st["element"],
                                              description="element", **menu)
        self.controls["crack_model"] = w.Dropdown(options=[(CRACK_MODEL_LABELS.get(c, c), c) for c in CRACK_MODELS],
                                                  value=st["crack_model"], description="crack model", **menu)
        self.controls["field"] = w.Dropdown(options=[("σ_νν (crack normal)", "sigma_nu"),
                                                     ("von Mises", "von_mises")],
                                            value=st["field"], description="stress shown", **menu)
        self.controls["scales"] = w.Dropdown(options=[(v, k) for k, v in SCALES.items()], value=st["scales"],
                                             description="scales", tooltip=SCALES_HELP, **menu)
        self.controls["magnification"] = w.FloatText(value=float(st["magnification"]), description="magnification (0: auto)",
                                                     tooltip=HELP["magnification"], style=style,
                                                     layout=w.Layout(width="300px"))
        self.controls["magnification"].add_class("ngcrack-typed-magnification")
        for name, widget in self.controls.items():
            widget.observe(lambda change, name=name: self._changed(name, change["new"]), names="value")
        for name, widget in self.typed.items():
            widget.observe(lambda change, name=name: self._changed(name, change["new"]), names="value")
        menus = [self.controls[k] for k in ("element", "crack_model", "field", "scales", "magnification")]
        half = (len(rows) + 1) // 2
        grid = w.HBox([w.VBox(rows[:half] + menus[:2]), w.VBox(rows[half:] + menus[2:])])
        self.help = w.HTML()
        self.help.add_class("ngcrack-help")
        self.status = w.HTML()
        self.status.add_class("ngcrack-status")
        self.readout = w.HTML()
        self.readout.add_class("ngcrack-readout")
        self.data = w.HTML(layout=w.Layout(display="none"))
        self.data.add_class("ngcrack-data")
        self.image = w.Image(format="png", layout=w.Layout(width="auto", max_width="100%"))
        self.image.add_class("ngcrack-figure")
        parts = [w.HTML(STYLE), grid, self.help, self.status, self.readout, self.image, self.data]
        self.webgui = None
        if webgui:
            self.webgui = w.Output()
            box = w.Checkbox(value=False, description="NGSolve webgui (3D) view")
            box.observe(lambda change: self._draw_webgui(change["new"]), names="value")
            parts += [box, self.webgui]
        super().__init__(parts)
        self._refresh(hold=False)

    @property
    def study(self) -> Explorer:
        """The model (former name of `model`)."""
        return self.model

    def _param_doc(self, name: str) -> str | None:
        fn = self.model.function
        return next((p.doc for p in fn.parameters if p.name == name), None) if fn is not None else None

    # ------------------------------------------------------------------ events
    def _changed(self, name: str, value) -> None:
        if self._syncing:
            return
        t0 = time.perf_counter()
        level = self.model.level(name)
        if level != "view":
            self._busy(True)
        try:
            self.model.update(**{name: value})
        finally:
            self._sync()
        self._refresh(hold=self.model.state["scales"] == "hold", t0=t0)
        self._busy(False)
        self.latency = time.perf_counter() - t0

    def _busy(self, on: bool) -> None:
        if on:
            self.image.add_class("ngcrack-busy")
            self.status.value = "<span style='color:#555'>solving...</span>"
        else:
            self.image.remove_class("ngcrack-busy")

    def _sync(self) -> None:
        """Every widget shows the model's value (a refused value goes back to the kept one)."""
        st = self.model.state
        self._syncing = True
        try:
            for name, widget in list(self.controls.items()) + list(self.typed.items()):
                value = st.get(name)
                if name == "maxh" and value is None:
                    value = self.model.start_maxh
                if value is not None and widget.value != value:
                    widget.value = value
        finally:
            self._syncing = False

    # ------------------------------------------------------------------ drawing
    def _refresh(self, hold: bool = False, t0: float | None = None) -> None:
        m = self.model
        draw_s = scales_s = 0.0
        if m.error is None and m.solution is not None:
            try:
                t_scales = time.perf_counter()
                scales = None
                if m.state["scales"] == "auto":  # the reference load's scales (a documented rule, not history)
                    try:
                        scales = m.reference_scales(m.state["field"])
                    except (InputError, SolveError, ContactSolverError, LinearSolverError):  # no reference answer: the frame's own scales
                        scales = None
                t_draw = time.perf_counter()
                scales_s = t_draw - t_scales
                self._png = self.drawing.render(m.solution, m.state["field"], title=m.name, hold=hold,
                                                magnification=m.state["magnification"],
                                                load_factor=m.state["load"], scales=scales)
                self.image.value = self._png
                draw_s = time.perf_counter() - t_draw
            except Exception as exc:  # noqa: BLE001  (a drawing failure is reported, never raised)
                m.error = "The figure could not be drawn: change a control to try again."
                m.error_detail = _one_line(exc)
        self.status.value = "" if m.error is None else status_html(m)
        self.help.value = (f"<div style='line-height:1.35'><b>crack model</b> "
                           f"{_escape(CRACK_MODEL_HELP.get(m.state['crack_model'], ''))}. <b>load factor</b> "
                           f"{_escape(LOAD_HELP)}.</div>")
        if m.error is None:  # (after a failure the readout stays that of the figure shown)
            self._readout(draw_s, scales_s)
        self._data()
        if self.webgui is not None and getattr(self, "_webgui_on", False):
            self._draw_webgui(True)

    def _readout(self, draw_s: float, scales_s: float = 0.0) -> None:
        m = self.model
        r = m.readouts()
        if not r:
            self.readout.value = ""
            return
        t, nd = r["time_s"], r["unknowns"]
        if m.redone == ["figure"]:
            split = {"drawing": draw_s}
        else:
            split = {k: t[k] for k in ("mesh", "assemble", "linear", "contact", "tips", "estimate")}
            split["rest of the solve"] = max(0.0, r["latency_s"] - sum(split.values()))
            if scales_s >= 0.005:  # the reference load's answer, solved for the held scales
                split["scales"] = scales_s
            split["drawing"] = draw_s
        self.timing = split
        total = sum(split.values())
        parts = " + ".join(f"{k} {v:.2f}" for k, v in split.items())
        tips = self.drawing.data.get("tips") or []
        self.readout.value = (
            "<div style='line-height:1.4'>"
            f"{_term('unknowns', 'unknowns')} {nd['total']} (whole body {nd['global']}, crack faces {nd['contact']})"
            f" &nbsp; {_term('time', 'time')} {total:.2f} s = {parts} s ({_escape(', '.join(r['redone']) or '-')})"
            f"<br>{_term('KKT', 'contact check (KKT residual)')} {r['kkt']:.1e} &nbsp; "
            f"{_term('contact length', 'contact length')} {r['contact_length']:.3g} of {r['crack_length']:.3g}"
            + (f" &nbsp; <b>faces pass through each other</b> over {r['overlap_length']:.3g}"
               if r["overlap_length"] > 0 else "")
            + (f"<br>{_term('tip', 'tips')}, {_term('K', 'K')}: {_escape(';  '.join(tips))}" if tips else "")
            + "</div>")

    def _data(self) -> None:
        m = self.model
        d = self.drawing.data
        state = {k: (v if isinstance(v, (int, float, str)) or v is None else str(v)) for k, v in m.state.items()}
        widgets = {k: w.value for k, w in self.controls.items()}
        typed = {k: w.value for k, w in self.typed.items()}
        self.data.value = _escape(json.dumps({
            "state": state, "controls": widgets, "typed": typed, "error": m.error,
            "max_gap": d.get("max_gap"), "max_overlap": d.get("max_overlap"),
            "magnification": d.get("magnification"), "clim": d.get("clim"), "held": d.get("held"),
            "timing": self.timing}))

    def _draw_webgui(self, on: bool) -> None:
        self._webgui_on = on
        self.webgui.clear_output()
        if not on or self.model.solution is None:
            return
        with self.webgui:
            try:
                from .webgui import webgui_scene

                d = self.drawing.data
                cf, name = webgui_field(self.model.solution, self.model.state["field"])
                show_webgui(cf, name, self.model.solution.mesh,
                            **webgui_scene(self.model.solution, d.get("magnification") or 0.0, d.get("clim"), name))
            except Exception as exc:  # noqa: BLE001
                print("The 3D view could not be drawn: " + _one_line(exc))


def webgui_field(sol, field: str) -> tuple[Any, str]:
    """The figure's stress field as an NGSolve CoefficientFunction, and its name: sigma_nu
    (the first crack's normal) or von Mises with sigma_zz = nu (sigma_xx + sigma_yy) in
    plane strain, 0 in plane stress (as `figure.stress_values`)."""
    if field not in FIELDS:
        raise InputError(f"field = {field!r}: allowed values are {', '.join(FIELDS)}")
    sig = sol.sigma
    sxx, syy, sxy = sig[0, 0], sig[1, 1], 0.5 * (sig[0, 1] + sig[1, 0])
    if field == "sigma_nu":
        cm = sol.crack_mesh
        n = cm.cracks[0].normal[0] if cm.cracks else (0.0, 1.0)
        return n[0] * n[0] * sxx + 2 * n[0] * n[1] * sxy + n[1] * n[1] * syy, "sigma_nu"
    mat = sol.scene.material
    szz = mat.nu * (sxx + syy) if mat.plane == "strain" else 0.0 * sxx
    vm = ngs.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3 * sxy ** 2)
    return vm, f"von Mises (plane {mat.plane})"


def show_webgui(cf, name: str, mesh, deformation=None, objects=None, settings=None, caption: str = "") -> None:
    """NGSolve's webgui view of `cf` on `mesh`, displayed: through webgui_jupyter_widgets
    where it is installed (its JavaScript ships with it, so the view works offline), else
    through ngsolve.webgui's own widget (anywidget; it loads its JavaScript from a CDN).
    ``deformation`` (a 3-vector CoefficientFunction), ``objects`` (lines, text) and
    ``settings`` (the colour map's limits) go to `Draw`; ``caption`` is shown above it."""
    from IPython.display import HTML, display
    from ngsolve.webgui import Draw

    if caption:
        display(HTML(f"<div class='ngcrack-webgui-caption' style='font-size:13px'>{_escape(caption)}</div>"))
    kw = {k: v for k, v in (("deformation", deformation), ("objects", objects), ("settings", settings))
          if v is not None}
    display_webgui(Draw(cf, mesh, name, show=False, **kw))


