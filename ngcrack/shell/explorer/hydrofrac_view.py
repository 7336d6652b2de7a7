"""A hydraulic-fracture run in JupyterLab: a step (time) slider over the steps of `nc.hydrofrac`.

    res = nc.hydrofrac(nc.scenes.load("kgd"), rate=1e-4, K_Ic=1e6, da=0.1, steps=20)
    nc.explore_growth(res)          # (or nc.explore_hydrofrac(res))

Each step shows, side by side: the crack with its two faces opened at one magnification for
the whole run (so that the steps compare) and the fluid pressure drawn as arrows on the
faces; the opening and the fluid pressure along the crack; the pressure at injection
against time, the current step circled, beside the closed form of the toughness-dominated
KGD crack under a uniform pressure (K_I = p sqrt(pi l) = K_Ic at propagation and the
volume 2 pi p l^2 / E' = Q0 t, so that l(t) = (E' Q0 t / (2 sqrt(pi) K_Ic))^(2/3) and
p(t) = K_Ic / sqrt(pi l)). The readout gives the step's time, half-length, pressure and
opening at injection beside the closed form's. A step typed out of range is refused in one
red line; a failure to draw shows one line, never a traceback.
"""

from __future__ import annotations

import html
import io
import math
from typing import Any

import numpy as np

from .controls import wire_steps
from .messages import ArgumentError, require_extras

#: figure size in inches and resolution of a step's picture
FIGURE_SIZE = (12.0, 3.9)
FIGURE_DPI = 88
#: the largest opening drawn, as a fraction of the largest crack length of the run
FACE_FRACTION = 0.08
#: pressure arrows per face
PRESSURE_ARROWS = 7
PRESSURE_COLOR = "#0f766e"
#: colours of the two faces (+ side: the one the crack's normal points into), as in the explorer
FACE_COLORS = {"+": "#1f3b8c", "-": "#c2410c"}


def closed_form(result, time: np.ndarray | float) -> dict:
    """The toughness-dominated KGD crack under a uniform pressure at `time` (module docstring):
    half-length l, pressure p and opening at the centre w0 = 4 p l / E' (plane strain E')."""
    mat = result.scene.material
    e_prime = mat.E / (1.0 - mat.nu ** 2) if mat.plane == "strain" else mat.E
    t = np.asarray(time, float)
    length = (e_prime * result.rate * t / (2.0 * math.sqrt(math.pi) * result.K_Ic)) ** (2.0 / 3.0)
    with np.errstate(divide="ignore"):
        p = np.where(length > 0, result.K_Ic / np.sqrt(math.pi * np.maximum(length, 1e-300)), np.inf)
    return {"half_length": length, "pressure": p, "opening_at_injection": 4.0 * p * length / e_prime}


def _faces(frame: dict, scale: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(points along the crack, + face, - face, normals) of a frame: the mid-point samples, closed
    at the crack's ends, each face moved by half the opening times `scale`."""
    ends = np.asarray(frame["points"], float)[[0, -1]]
    xy = np.vstack([ends[:1], np.column_stack([frame["x"], frame["y"]]), ends[1:]])
    normal = np.asarray(frame["normal"], float)
    normal = np.vstack([normal[:1], normal, normal[-1:]])
    w = np.r_[0.0, np.asarray(frame["opening"], float), 0.0]
    half = 0.5 * scale * w[:, None] * normal
    return xy, xy + half, xy - half, normal


def _scale(result) -> float:
    """One magnification for the whole run: its largest opening drawn FACE_FRACTION of its longest crack."""
    longest = max((2.0 * s["half_length"] for s in result.steps), default=0.0)
    wmax = max((max(f["opening"], default=0.0) for f in result.frames), default=0.0)
    return FACE_FRACTION * longest / wmax if wmax > 0 and longest > 0 else 0.0


def render_step(result, n: int, scale: float | None = None) -> tuple[bytes, dict]:
    """PNG of step `n` (the crack with its pressure, the profiles along it, the injection pressure
    against time beside the closed form) and what was drawn (for checks without pixels)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    scale = _scale(result) if scale is None else scale
    step, frame = result.steps[n], result.frames[n]
    fig = Figure(figsize=FIGURE_SIZE, dpi=FIGURE_DPI, layout="constrained")
    FigureCanvasAgg(fig)
    ax, bx, cx = fig.subplots(1, 3, width_ratios=(1.2, 1.0, 1.0))
    p = float(step["pressure"])
    # the crack, opened, with the fluid pressure on its faces
    xy, plus, minus, normal = _faces(frame, scale)
    ax.plot(*plus.T, color=FACE_COLORS["+"], lw=1.8)
    ax.plot(*minus.T, color=FACE_COLORS["-"], lw=1.8)
    allpts = np.concatenate([np.asarray(f["points"], float) for f in result.frames])
    span = float(np.max(np.ptp(allpts, axis=0))) or 1.0
    center = 0.5 * (allpts.min(axis=0) + allpts.max(axis=0))
    arrows = 0
    top = max(abs(float(s["pressure"])) for s in result.steps) or 1.0
    if p != 0 and len(xy) > 2:
        L = 0.06 * span * p / top
        for i in np.linspace(1, len(xy) - 2, min(PRESSURE_ARROWS, len(xy) - 2)).round().astype(int):
            for face, sign in ((plus, 1.0), (minus, -1.0)):
                tail, head = (face[i], face[i] + sign * L * normal[i]) if L > 0 else (face[i] - sign * L * normal[i],
                                                                                     face[i])
                ax.annotate("", xy=head, xytext=tail, arrowprops={"arrowstyle": "-|>", "color": PRESSURE_COLOR,
                                                                   "lw": 1.0})
                arrows += 1
    ax.set_xlim(center[0] - 0.6 * span, center[0] + 0.6 * span)
    ax.set_ylim(center[1] - 0.3 * span, center[1] + 0.3 * span)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"step {step['step']}: t = {step['time']:.4g} s, p = {p:.4g} Pa\nopening × {scale:.3g}; "
                 f"arrows: fluid pressure", fontsize=9)
    # the opening and the fluid pressure along the crack
    s_along = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))]
    s_along -= 0.5 * s_along[-1]
    w = np.r_[0.0, np.asarray(frame["opening"], float), 0.0]
    bx.plot(s_along, w * 1e6, "-", color="tab:blue", label="opening w [µm]")
    bx.set_xlabel("s from the crack's middle [m]")
    bx.set_ylabel("opening w [µm]")
    wmax = max((max(f["opening"], default=0.0) for f in result.frames), default=0.0)
    bx.set_ylim(0.0, 1.1 * wmax * 1e6 if wmax > 0 else 1.0)
    bt = bx.twinx()
    bt.plot(s_along, np.full_like(s_along, p / 1e6), "-", color=PRESSURE_COLOR, label="fluid pressure p [MPa]")
    bt.set_ylim(0.0, 1.1 * top / 1e6)
    bt.set_ylabel("fluid pressure p [MPa]", color=PRESSURE_COLOR)
    bx.set_title("along the crack", fontsize=9)
    # the pressure at injection against time, the closed form beside it
    t = np.array([s["time"] for s in result.steps], float)
    pn = np.array([s["pressure"] for s in result.steps], float)
    tt = np.linspace(max(t.min(), 1e-12), max(t.max(), 1e-12), 200)
    cx.plot(tt, closed_form(result, tt)["pressure"] / 1e6, "-", color="0.6", label="KGD closed form (toughness)")
    cx.plot(t, pn / 1e6, "o", ms=3, color="tab:blue", label="ngcrack")
    cx.plot([t[n]], [pn[n] / 1e6], "o", ms=10, mfc="none", mec="k")
    cx.set_xlabel("t [s]")
    cx.set_ylabel("pressure at injection [MPa]")
    cx.legend(fontsize=8)
    cx.set_title("pressure at injection against time", fontsize=9)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return buf.getvalue(), {"scale": scale, "pressure_arrows": arrows, "pressure": p, "step": n}


def step_readout(result, n: int) -> str:
    """Step `n`: time, half-length, pressure and opening at injection beside the closed form's (4 digits)."""
    s = result.steps[n]
    ref = closed_form(result, s["time"])
    lines = [f"step {n} of {len(result.steps) - 1}: t = {s['time']:.4g} s"]
    for key, label, unit, factor in (("half_length", "half-length l", "m", 1.0), ("pressure", "pressure p", "MPa", 1e-6),
                                     ("opening_at_injection", "opening at injection w0", "µm", 1e6)):
        value, closed = float(s[key]), float(ref[key])
        dev = f" ({100 * (value / closed - 1):+.2f}%)" if math.isfinite(closed) and closed > 0 else ""
        lines.append(f"{label} = {value * factor:.4g} {unit}; KGD closed form {closed * factor:.4g} {unit}{dev}")
    return "\n".join(lines)


def explore_hydrofrac(result, **kwargs: Any):
    """An ipywidgets view of `result` (what `nc.hydrofrac` returns): a step slider and a box for a
    typed step, the step's picture and its numbers beside the closed form's."""
    from ...studies.hydrofrac.result import HydrofracResult

    if not isinstance(result, HydrofracResult):
        raise ArgumentError(f"result = <{type(result).__name__}>: explore_hydrofrac takes the HydrofracResult of "
                            f"nc.hydrofrac(...)")
    unknown = sorted(set(kwargs) - {"step"})
    if unknown:
        raise ArgumentError(f"{unknown[0]}: not an argument of explore_hydrofrac; allowed: step")
    if not result.steps or len(result.frames) != len(result.steps):
        raise ArgumentError("result: has no steps with frames to show")
    last = len(result.steps) - 1
    start = kwargs.get("step", 0)
    if isinstance(start, bool) or not isinstance(start, int) or not 0 <= start <= last:
        raise ArgumentError(f"step = {start!r}: a whole number from 0 to {last}")
    require_extras("nc.explore_growth")
    import ipywidgets as w

    scale = _scale(result)
    slider = w.IntSlider(value=start, min=0, max=last, description="step", readout=False, continuous_update=False)
    slider.add_class("ngcrack-hydrofrac-step")
    box = w.IntText(value=start, layout=w.Layout(width="80px"), tooltip=f"a step from 0 to {last}")
    box.add_class("ngcrack-hydrofrac-typed-step")
    image = w.Image(format="png", layout=w.Layout(width="auto", max_width="100%"))
    image.add_class("ngcrack-hydrofrac-figure")
    readout, status = w.HTML(), w.HTML()
    status.add_class("ngcrack-status")

    def show(n: int) -> None:
        try:
            image.value = render_step(result, n, scale)[0]
            readout.value = "<pre>" + html.escape(step_readout(result, n)) + "</pre>"
            status.value = ""
        except Exception as exc:  # noqa: BLE001  (a widget shows one line, never a traceback)
            detail = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            status.value = ("<span style='color:#b00020'>&#9888; The step could not be drawn: choose another "
                            f"step.</span><div style='color:#666; font-size:11px'>details: {html.escape(detail)}</div>")

    wire_steps(slider, box, status, last, show)
    return w.VBox([w.HBox([slider, box]), status, image, readout])
