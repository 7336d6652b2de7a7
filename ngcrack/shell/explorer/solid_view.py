"""The explorer of a 3D scene: `nc.explore("penny")` or `nc.explore(scene3d)`.

`SolidExplorer` is the model (no widgets): a 3D scene (`ngcrack.solid`), the controls that make
sense in 3D and a kept `Pipeline` (a new load re-assembles only the load vector):

- ``load``: a factor on every load of the scene (tractions, prescribed displacements, body
  force; -1 reverses them: the penny's tension becomes a compression that shuts it);
- ``nu``: Poisson's ratio, below 1/2 (3D);
- ``friction``: the Coulomb coefficient on every crack;
- ``tilt``: the crack's orientation, degrees: every crack turned about its centre, about the
  axis in its plane normal to the scene's own normal and the z axis (x for a crack normal
  to z), so that 45 puts the penny at 45 degrees to the load, where a compression closes
  it and makes it slide;
- ``front_h``: the mesh size along the fronts (the crack's own size twice it).

`update(**changes)` never raises for a bad value: `error` is one plain sentence, `error_detail`
the technical line, and the controls stay those of the answer shown (as in 2D).

`draw(sol)` is the figure (matplotlib, PNG): K_I, K_II and K_III along every front against the
front's angle, beside the map of each crack's faces in its own plane, each face open, closed
and sticking, or closed and sliding. `webgui_body(sol)` is NGSolve's webgui scene of the body,
deformed and coloured by the von Mises stress, cut open through the crack's plane.
"""

from __future__ import annotations

import io
import math
import time
from typing import Any

import numpy as np

from ...core.errors import InputError
from .controls import ControlRefused, Range

#: the ranges of the controls (front_h: relative to the scene's crack size, set per scene)
SOLID_RANGES = {"load": Range(-2.0, 2.0, 0.1), "nu": Range(0.0, 0.4999, 0.01), "friction": Range(0.0, 1.5, 0.05),
                "tilt": Range(-80.0, 80.0, 5.0)}
#: the controls in the order they are shown
SOLID_CONTROLS = ("load", "nu", "friction", "tilt", "front_h")
#: the explorer's front_h, as a fraction of the crack's smallest semi-axis: coarse, for seconds per solve
TEACHING_FRONT = 0.5
#: the front_h offered, as fractions of the crack's smallest semi-axis
FRONT_RANGE = (0.15, 1.0)
#: a closed face slides where its sliding exceeds this fraction of the crack's largest jump
SLIDE_RTOL = 1e-6
#: colours of the face map
STATE_COLORS = {"open": "#dbeafe", "stick": "0.6", "slip": "#f59e0b"}
#: the map's words for the states
STATE_LABELS = {"open": "open", "stick": "closed, sticking", "slip": "closed, sliding"}
#: figure size (inches) and resolution
FIGURE_SIZE = (11.0, 4.2)
FIGURE_DPI = 88


def _rotation(axis: np.ndarray, degrees: float) -> np.ndarray:
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    t = math.radians(degrees)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * K @ K


def _half_size(crack) -> float:
    """A crack's smallest semi-axis; half the diameter of a polygon or a curve (whose semi_axes are zeros)."""
    axes = [float(a) for a in (crack.semi_axes or ()) if a]
    return min(axes) if axes else 0.5 * float(crack.size)


def tilt_axis(normal) -> np.ndarray:
    """The axis a crack turns about: in its plane, normal to its normal and to z (x for a crack normal to z)."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    a = np.cross(n, (0.0, 0.0, 1.0))
    return np.array([1.0, 0.0, 0.0]) if np.linalg.norm(a) < 1e-9 else a / np.linalg.norm(a)


class SolidExplorer:
    """The model behind `nc.explore` of a 3D scene (module docstring): ``scene`` a SolidScene or the
    name of a built-in 3D scene; ``order`` the TDNNS order; the controls as keywords."""

    def __init__(self, scene, *, order: int = 1, solve_now: bool = True, **controls: Any):
        from ...core.pipeline import Pipeline
        from ...scenes import load as load_scene
        from ...scenes import names

        if isinstance(scene, str):
            if scene not in names():
                raise InputError(f"scene = {scene!r}: a 3D scene, or the name of a built-in one")
            scene = load_scene(scene)
        if getattr(scene, "dimension", 2) != 3:
            raise InputError(f"scene = {getattr(scene, 'name', scene)!r}: not a 3D scene (nc.explore draws 2D scenes "
                             f"in its own figure)")
        if not scene.cracks:
            raise InputError(f"scene {scene.name!r}: has no crack to explore")
        if order not in (1, 2, 3):
            raise InputError(f"order = {order!r}: allowed values are 1, 2, 3")
        self.base, self.order, self.name = scene, order, scene.name
        size = min(_half_size(c) for c in scene.cracks)
        self.ranges = dict(SOLID_RANGES)
        self.ranges["front_h"] = Range(FRONT_RANGE[0] * size, FRONT_RANGE[1] * size, 0.05 * size)
        self.state = {"load": 1.0, "nu": float(scene.material.nu), "friction": float(scene.cracks[0].friction),
                      "tilt": 0.0, "front_h": max(TEACHING_FRONT * size, float(scene.front_h or 0.0))}
        unknown = sorted(set(controls) - set(SOLID_CONTROLS))
        if unknown:
            raise InputError(f"{unknown[0]}: not a control of a 3D scene; allowed: {', '.join(SOLID_CONTROLS)}")
        for k, v in controls.items():
            self.state[k] = self.ranges[k].check(k, v)
        self.state["front_h"] = min(self.state["front_h"], self.ranges["front_h"].high)
        self.pipeline = Pipeline()
        self.solution = None
        self.scene = None
        self.error = self.error_detail = None
        self.refused: tuple[str, ...] = ()
        self.latency = 0.0
        if solve_now:
            self.update()

    def controls(self) -> tuple[str, ...]:
        return SOLID_CONTROLS

    def make_scene(self):
        """The scene the controls describe: loads scaled, nu, friction, the cracks turned, front_h."""
        from ...solid.loads import scaled
        from ...solid.scene import SolidScene

        st = self.state
        d = self.base.to_dict()
        for bc in d["boundary"].values():
            if bc.get("type") in ("traction", "displacement") and bc.get("value") is not None:
                bc["value"] = scaled(bc["value"], st["load"])  # a traction varying over the face too (solid.loads)
        if "load" in d and d["load"].get("body_force") is not None:
            d["load"]["body_force"] = [st["load"] * float(v) for v in d["load"]["body_force"]]
        d["material"]["nu"] = st["nu"]
        for c, crack in zip(d.get("crack", []), self.base.cracks):
            c["friction"] = st["friction"]
            if st["tilt"]:  # a polygon's or a curve's dictionary has no normal: the crack's own
                normal = np.asarray(crack.normal, float)
                R = _rotation(tilt_axis(normal), st["tilt"])
                center = np.asarray(c.get("center", np.mean(c.get("points", [[0, 0, 0]]), axis=0)), float)
                if c.get("normal") is not None:
                    c["normal"] = (R @ normal).tolist()
                for key in ("major_axis",):
                    if c.get(key) is not None:
                        c[key] = (R @ np.asarray(c[key], float)).tolist()
                if c.get("points") is not None:
                    c["points"] = [(center + R @ (np.asarray(p, float) - center)).tolist() for p in c["points"]]
        mesh = d.setdefault("mesh", {})
        ratio = (self.base.crack_h / self.base.front_h) if self.base.crack_h and self.base.front_h else 2.0
        mesh["front_h"], mesh["crack_h"] = st["front_h"], ratio * st["front_h"]
        return SolidScene.from_dict(d)

    def update(self, **changes: Any):
        """Apply `changes` and solve; None after a refusal (then `error`, `error_detail`, `refused`)."""
        from ...core.solve import solve

        t0 = time.perf_counter()
        before = dict(self.state)
        try:
            unknown = [k for k in changes if k not in SOLID_CONTROLS]
            if unknown:
                raise ControlRefused(f"unknown control {unknown[0]}; allowed: {', '.join(SOLID_CONTROLS)}", unknown[0],
                                     f"There is no control called {unknown[0]}: the controls are "
                                     f"{', '.join(SOLID_CONTROLS)}.")
            changes = {k: self.ranges[k].check(k, v) for k, v in changes.items()}
            self.state.update(changes)
            scene = self.make_scene()
            self.solution = solve(scene, order=self.order, pipeline=self.pipeline)
            self.scene = scene
            self.error = self.error_detail = None
            self.refused = ()
            return self.solution
        except Exception as exc:  # noqa: BLE001  (shown as one line; the last answer stays)
            detail = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
            sentence = exc.sentence if isinstance(exc, ControlRefused) else (
                f"The 3D scene cannot be solved with this {', '.join(changes) or 'start'}: change it back or change "
                f"another control (details below).")
            self.error, self.error_detail, self.refused = sentence, detail, tuple(changes)
            if self.solution is not None:
                self.state = before
            return None
        finally:
            self.latency = time.perf_counter() - t0

    def readouts(self) -> dict[str, Any]:
        """Unknowns, KKT residual, closed fraction per crack, K ranges per front, the time of the last update."""
        sol = self.solution
        if sol is None:
            return {}
        fronts = [{k: (float(np.min(getattr(f, k))), float(np.max(getattr(f, k)))) for k in ("K_I", "K_II", "K_III")}
                  for f in sol.fronts]
        return {"unknowns": dict(sol.ndof), "kkt": max((float(v) for v in sol.kkt.values()), default=0.0),
                "closed_fraction": [float(c["closed_fraction"]) for c in sol.crack_summaries()],
                "fronts": fronts, "latency_s": self.latency}


def face_states(sol) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(points, triangles, per triangle "open" / "stick" / "slip", per triangle its crack) of the crack
    faces: a face is closed where most of its corners are (the contact's active set), and slides
    where its closed corners move along it by more than SLIDE_RTOL of the largest jump."""
    points, tris, data = sol.crack_arrays()
    closed = data["closed"][tris].mean(axis=1) > 0.5
    scale = float(max(np.max(np.abs(data["opening"]), initial=0.0), np.max(data["sliding"], initial=0.0)))
    moving = data["sliding"][tris].max(axis=1) > SLIDE_RTOL * scale
    state = np.where(~closed, "open", np.where(moving, "slip", "stick"))
    owner = np.concatenate([np.full(len(c.elements), i) for i, c in enumerate(sol.smesh.cracks)])
    return points, tris, state, owner


def draw(sol, title: str = "") -> tuple[bytes, dict]:
    """PNG of the fronts' K and the crack faces' map (module docstring) and what was drawn."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    fig = Figure(figsize=FIGURE_SIZE, dpi=FIGURE_DPI, layout="constrained")
    FigureCanvasAgg(fig)
    ax, bx = fig.subplots(1, 2, width_ratios=(1.3, 1.0))
    for k, f in enumerate(sol.fronts):
        deg = np.degrees(np.asarray(f.angle, float)) if np.ptp(f.angle) < 7 else np.asarray(f.angle, float)
        sfx = f" (crack {k + 1})" if len(sol.fronts) > 1 else ""
        for key, style in (("K_I", "-o"), ("K_II", "--s"), ("K_III", ":^")):
            ax.plot(deg, getattr(f, key), style, ms=3, label=f"{key}{sfx}")
    ax.axhline(0.0, color="0.5", lw=0.5)
    ax.set_xlabel("position along the front (angle, degrees)")
    ax.set_ylabel("K [same unit as E × √length]")
    ax.set_title("stress intensity factors along the front", fontsize=9)
    ax.legend(fontsize=8, ncol=3)
    points, tris, state, owner = face_states(sol)
    counts = {s: int(np.sum(state == s)) for s in STATE_COLORS}
    c0 = sol.smesh.cracks[0]
    n = np.asarray(c0.normal, float)
    e1 = tilt_axis(n) if abs(n[2]) < 1 - 1e-9 else np.array([1.0, 0.0, 0.0])
    e1 = e1 - (e1 @ n) * n
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    centre = np.asarray(c0.crack.center, float)
    xy = np.column_stack([(points - centre) @ e1, (points - centre) @ e2])
    colors = [STATE_COLORS[s] for s in state]
    bx.add_collection(PolyCollection(xy[tris], facecolors=colors, edgecolors="0.3", linewidths=0.3))
    bx.autoscale_view()
    bx.set_aspect("equal")
    bx.set_xlabel("in the crack's plane, e1")
    bx.set_ylabel("e2 = ν × e1")
    frac = 1.0 - counts["open"] / max(len(state), 1)
    bx.set_title(f"crack faces: {100 * frac:.0f}% closed", fontsize=9)
    bx.legend(handles=[Patch(color=c, label=STATE_LABELS[s]) for s, c in STATE_COLORS.items()], fontsize=8,
              loc="upper right")
    if title:
        fig.suptitle(title, fontsize=10)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return buf.getvalue(), {"states": counts, "closed_fraction": frac, "fronts": len(sol.fronts)}


def webgui_body(sol, magnification: float | None = None):
    """NGSolve's webgui scene of the body (``Draw(..., show=False)``): deformed (the largest
    displacement 5% of the body, or `magnification`), coloured by the von Mises stress, cut open by
    the viewer's clipping plane through the first crack."""
    import ngsolve as ngs
    from ngsolve.webgui import Draw

    s = sol.sigma
    sym = 0.5 * (s + s.trans)
    tr = sym[0, 0] + sym[1, 1] + sym[2, 2]
    dev = sym - tr / 3 * ngs.Id(3)
    vm = ngs.sqrt(1.5 * ngs.InnerProduct(dev, dev))
    mesh = sol.smesh.mesh
    if magnification is None:
        pts = sol.smesh.points
        umax = float(np.max(np.linalg.norm(np.asarray(sol.u(mesh(pts[:, 0], pts[:, 1], pts[:, 2]))), axis=1)))
        size = float(np.max(np.ptp(pts, axis=0)))
        magnification = 0.05 * size / umax if umax > 0 else 0.0
    # the solution's fields live in spaces the webgui cannot evaluate vectorised (SIMD): their L2
    # projections are drawn, continuous at order 1 (the webgui evaluates them on the surfaces too: a
    # discontinuous one gave the surfaces no values and the view no size)
    stress = ngs.GridFunction(ngs.H1(mesh, order=1))
    stress.Set(vm)
    u = ngs.GridFunction(ngs.VectorH1(mesh, order=1))
    u.Set(sol.u)
    c = sol.smesh.cracks[0]
    nrm = [float(x) for x in c.normal]
    return Draw(stress, mesh, "von Mises", deformation=magnification * u, show=False,
                clipping={"x": nrm[0], "y": nrm[1], "z": nrm[2], "dist": float(np.dot(nrm, c.crack.center))})


#: what each control is, on hover
SOLID_HELP = {"load": "a factor on every load of the scene: 1 as given, -1 reversed (tension becomes compression)",
              "nu": "Poisson's ratio (below 1/2 in 3D)", "friction": "Coulomb friction coefficient on the crack faces",
              "tilt": "the crack turned about its centre, degrees (about the axis in its plane normal to z)",
              "front_h": "mesh size along the crack fronts (smaller: more accurate, slower)"}
SOLID_LABELS = {"load": "load factor", "nu": "Poisson's ratio", "friction": "friction", "tilt": "crack tilt [deg]",
                "front_h": "front mesh size"}


def explore_solid(scene, *, webgui: bool = False, order: int = 1, **controls: Any):
    """An ipywidgets view of a `SolidExplorer` of `scene`: a slider and a box for a typed value per
    control, the figure (K along the fronts, the faces' map), the numbers, a one-line status and,
    with `webgui`, a checkbox for NGSolve's view of the deformed body."""
    import html

    from .messages import WEBGUI_PACKAGES, WIDGET_PACKAGES, ArgumentError, require_extras

    require_extras("nc.explore", WIDGET_PACKAGES + (WEBGUI_PACKAGES if webgui else ()))
    try:
        model = SolidExplorer(scene, order=order, **controls)
    except InputError as exc:
        raise ArgumentError(str(exc).splitlines()[0]) from None
    import ipywidgets as w

    sliders, boxes = {}, {}
    rows = []
    syncing = [False]
    image = w.Image(format="png", layout=w.Layout(width="auto", max_width="100%"))
    image.add_class("ngcrack-solid-figure")
    readout, status = w.HTML(), w.HTML()
    status.add_class("ngcrack-status")
    view = w.Output()
    box3d = w.Checkbox(value=False, description="NGSolve webgui (3D) view of the body")

    def refresh() -> None:
        if model.error is not None:
            status.value = (f"<span style='color:#b00020'>&#9888; {html.escape(model.error)}</span>"
                            f"<div style='color:#666; font-size:11px'>details: {html.escape(model.error_detail or '')}"
                            f"</div>")
        else:
            status.value = ""
        if model.solution is None:
            return
        try:
            image.value = draw(model.solution, model.name)[0]
        except Exception as exc:  # noqa: BLE001  (one line, never a traceback)
            status.value = f"<span style='color:#b00020'>&#9888; The figure could not be drawn: {html.escape(str(exc))}</span>"
        r = model.readouts()
        ks = "; ".join(f"K_I {f['K_I'][0]:.3g} to {f['K_I'][1]:.3g}, K_II {f['K_II'][0]:.3g} to {f['K_II'][1]:.3g}, "
                       f"K_III {f['K_III'][0]:.3g} to {f['K_III'][1]:.3g}" for f in r["fronts"])
        readout.value = (f"<div>unknowns {r['unknowns']['total']} (crack faces {r['unknowns']['contact']}); contact "
                         f"check (KKT) {r['kkt']:.1e}; closed {', '.join(f'{100 * c:.0f}%' for c in r['closed_fraction'])}"
                         f" of the crack; time {r['latency_s']:.1f} s<br>along the front: {html.escape(ks)}</div>")
        if box3d.value:
            show3d(True)

    def sync() -> None:
        syncing[0] = True
        for k in SOLID_CONTROLS:
            sliders[k].value = boxes[k].value = model.state[k]
        syncing[0] = False

    def changed(name: str, value) -> None:
        if syncing[0]:
            return
        image.add_class("ngcrack-busy")
        status.value = "<span style='color:#555'>solving (3D: seconds to a minute)...</span>"
        try:
            model.update(**{name: value})
        finally:
            sync()
            image.remove_class("ngcrack-busy")
        refresh()

    def show3d(on: bool) -> None:
        from .webgui import display_webgui

        view.clear_output()
        if not on or model.solution is None:
            return
        with view:
            try:
                display_webgui(webgui_body(model.solution))
            except Exception as exc:  # noqa: BLE001
                print("The 3D view could not be drawn: " + (str(exc).splitlines() or [type(exc).__name__])[0])

    for name in SOLID_CONTROLS:
        r = model.ranges[name]
        sliders[name] = w.FloatSlider(value=model.state[name], min=r.low, max=r.high, step=r.step, readout=False,
                                      continuous_update=False, description=SOLID_LABELS[name],
                                      tooltip=SOLID_HELP[name], style={"description_width": "125px"},
                                      layout=w.Layout(width="300px"))
        sliders[name].add_class(f"ngcrack-solid-slider-{name}")
        boxes[name] = w.FloatText(value=model.state[name], layout=w.Layout(width="80px"), tooltip=SOLID_HELP[name])
        boxes[name].add_class(f"ngcrack-solid-typed-{name}")
        sliders[name].observe(lambda c, name=name: changed(name, c["new"]), names="value")
        boxes[name].observe(lambda c, name=name: changed(name, c["new"]), names="value")
        rows.append(w.HBox([sliders[name], boxes[name]]))
    box3d.observe(lambda c: show3d(c["new"]), names="value")
    refresh()
    parts = [w.VBox(rows), status, readout, image] + ([box3d, view] if webgui else [])
    widget = w.VBox(parts)
    widget.model, widget.controls, widget.typed = model, sliders, boxes
    widget.image, widget.status, widget.readout = image, status, readout
    return widget
