"""The explorer's ipywidgets view: `explore()` and `ExplorerWidget`.

Sliders and menus wired to `Explorer.update` (the model), the figure (`Drawing`, a PNG
in an ipywidgets Image), readouts and a one-line status. ipywidgets is imported only when
a widget is made.
"""

from __future__ import annotations

import functools
import math
import time
from typing import Any

import ngsolve as ngs

from .. import elements as _elements
from ..scene import Scene
from ..scenes import SceneFunction
from .figure import Drawing
from ..options import CRACK_MODELS
from .model import Explorer, _one_line

#: slider ranges of the controls every scene has: (low, high, step)
SLIDERS = {
    "load": (-2.0, 2.0, 0.1),
    "load_angle": (-180.0, 180.0, 5.0),
    "nu": (0.0, 0.5, 0.01),
    "friction": (0.0, 1.0, 0.05),
}


def explore(scene: Scene | str | SceneFunction, element: str = "bdm", *, webgui: bool = False, **kwargs: Any):
    """An ipywidgets view of an `Explorer` of `scene` (see `Explorer` for the controls).

    ``nc.explore("inclined-crack")`` shows the inclined crack with sliders for its angle,
    half length and position; ``nc.explore(scene)`` a fixed geometry. ``webgui`` adds a
    checkbox for NGSolve's 3D view of the stress field. Returns an `ExplorerWidget`
    (an ipywidgets VBox; `.model` is the model).
    """
    return _widget_class()(Explorer(scene, element, **kwargs), webgui=webgui)


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


class _ExplorerView:
    """Sliders and menus wired to `Explorer.update`, the figure, readouts and a status line
    (an ipywidgets VBox: `ngcrack.explorer.ExplorerWidget`).

    `model` is the `Explorer` (also as `study`, its former name);
    `controls` maps control names to their widgets; `image` holds the figure (PNG);
    `status` the one-line message of the last failure (empty after a success);
    `latency` the wall time from the last control change to the new figure (seconds).
    """

    def __init__(self, model: Explorer, webgui: bool = False):
        import ipywidgets as w

        self.model = model
        st = model.state
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
        h0 = float(st["maxh"] if st["maxh"] is not None else (model.solution.maxh if model.solution else 1.0))
        self.controls["maxh"] = w.FloatLogSlider(value=h0, base=10, min=math.log10(h0) - 1, max=math.log10(h0) + 0.5,
                                                 step=0.05, description="mesh size", readout_format=".3g", **cont)
        menu = {k: v for k, v in cont.items() if k != "continuous_update"}
        self.controls["element"] = w.Dropdown(options=list(_elements.ELEMENTS), value=st["element"],
                                              description="element", **menu)
        crack_models = CRACK_MODELS
        self.controls["crack_model"] = w.Dropdown(options=list(crack_models), value=st["crack_model"],
                                                  description="crack model", **menu)
        if model.function is not None:
            for p in model.function.geometry():
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

    @property
    def study(self) -> Explorer:
        """The model (former name of `model`)."""
        return self.model

    def _changed(self, name: str, value) -> None:
        t0 = time.perf_counter()
        self.model.update(**{name: value})
        self._refresh()
        self.latency = time.perf_counter() - t0

    def _refresh(self) -> None:
        s = self.model
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
        if not on or self.model.solution is None:
            return
        with self.webgui:
            try:
                from ngsolve.webgui import Draw

                sol = self.model.solution
                sig = sol.sigma
                vm = ngs.sqrt(sig[0, 0] ** 2 + sig[1, 1] ** 2 - sig[0, 0] * sig[1, 1] + 3 * sig[0, 1] ** 2)
                Draw(vm, sol.mesh, "von Mises (plane stress form)")
            except Exception as exc:  # noqa: BLE001
                print(_one_line(exc))


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
