"""A growth path in JupyterLab: a step slider over the frames of a crack-growth result.

    res = nc.grow(scene, da=0.1, steps=20, K_Ic=1.0)
    nc.explore_growth(res)

Each step shows the deformed body at one magnification for the whole path (so that the
steps can be compared), drawn about the undeformed body with its rigid motion taken out,
the crack faces open in red and closed in blue and each tip's kink as an arrow with its
angle; beside it each tip's load factor against crack length, the current step circled
(growth.figures). A step typed out of range is refused in one red line and the box goes
back to the step shown. The readout gives the step's tips (position, K_I, K_II, K_eq, kink) and its
load factor. Drawn with matplotlib's Agg canvas into an image widget; a failure to draw
shows one line, never a traceback.
"""

from __future__ import annotations

import io
from typing import Any

from ...core.errors import InputError
from ...planar.plots import tip_names
from ...studies.growth.figures import draw_frame, draw_load_factors, frame_view
from ...studies.growth.result import GrowthResult
from .controls import wire_steps
from .messages import ArgumentError, require_extras

#: figure size in inches and resolution of a step's picture
FIGURE_SIZE = (11.0, 5.0)
FIGURE_DPI = 88


def render_step(result: GrowthResult, n: int, view=None) -> bytes:
    """PNG of step `n`: the deformed body, crack faces and kinks (growth.figures.draw_frame),
    and each tip's load factor against crack length, step `n` circled."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=FIGURE_SIZE, dpi=FIGURE_DPI, layout="constrained")
    FigureCanvasAgg(fig)
    ax, bx = fig.subplots(1, 2, width_ratios=(1.25, 1.0))
    draw_frame(ax, result, n, view)
    draw_load_factors(bx, result, step=n)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return buf.getvalue()


def step_tip_names(result: GrowthResult, n: int) -> list[str]:
    """The names of step `n`'s tips: those of the first step (by crack and end), as the figure's
    legend names them, so that a tip keeps its name as its path turns; a tip the first step
    does not have is named by where it is."""
    first = result.steps[0]["tips"]
    scene = getattr(result, "scene", None)
    names = dict(zip([(t["crack"], t["end"]) for t in first], tip_names(first, scene)))
    tips = result.steps[n]["tips"]
    own = tip_names(tips, result.scenes[n] if getattr(result, "scenes", None) else scene)
    return [names.get((t["crack"], t["end"]), mine) for t, mine in zip(tips, own)]


def step_readout(result: GrowthResult, n: int) -> str:
    """One line per tip of step `n`: position, K_I, K_II, K_eq, kink (4 significant digits)."""
    step = result.steps[n]
    lam = step["load_factor"]
    lines = [f"step {n} of {len(result.steps) - 1}: load factor " + (f"{lam:.4g}" if lam is not None else "none")]
    rows = result.table[result.table["step"] == n]
    closed = {(r.crack, r.end): bool(r.closed) for r in rows.itertuples()}
    for t, name in zip(step["tips"], step_tip_names(result, n)):
        kink = "" if t["kink_deg"] is None else f", kink {t['kink_deg']:+.1f}°"
        # a closed tip's K_I is 0 (the crack cannot open there): the computed value is the method's error
        k1 = "0 (faces closed)" if closed.get((t["crack"], t["end"])) else f"{t['K_I']:.4g}"
        lines.append(f"{name} ({t['x']:.4g}, {t['y']:.4g}): K_I = {k1}, "
                     f"K_II = {t['K_II']:.4g}, K_eq = {t['K_eq']:.4g}{kink}" + (" (grew)" if t["grew"] else ""))
    return "\n".join(lines)


def explore_growth(result: GrowthResult, **kwargs: Any):
    """An ipywidgets view of `result` (a GrowthResult kept with frames): a step slider,
    the step's picture and its tips' numbers. The result of `nc.hydrofrac` gets its own view
    (`hydrofrac_view.explore_hydrofrac`: the crack with its fluid pressure, the profiles along
    it, the pressure at injection against time beside the closed form)."""
    import html

    from ...studies.hydrofrac.result import HydrofracResult

    if isinstance(result, HydrofracResult):
        from .hydrofrac_view import explore_hydrofrac

        return explore_hydrofrac(result, **kwargs)
    if not isinstance(result, GrowthResult):  # named by its type: a result's repr is its arrays
        raise ArgumentError(f"result = <{type(result).__name__}>: explore_growth takes the result of nc.grow(...) "
                            f"or nc.hydrofrac(...)")
    unknown = sorted(set(kwargs) - {"step"})
    if unknown:
        raise ArgumentError(f"{unknown[0]}: not an argument of explore_growth; allowed: step")
    try:
        view = frame_view(result)  # refuses a result kept without frames, naming the field
    except InputError as exc:
        raise ArgumentError(str(exc).splitlines()[0]) from None
    last = len(result.frames) - 1
    start = kwargs.get("step", 0)
    if isinstance(start, bool) or not isinstance(start, int) or not 0 <= start <= last:
        raise ArgumentError(f"step = {start!r}: a whole number from 0 to {last}")
    require_extras("nc.explore_growth")
    import ipywidgets as w
    slider = w.IntSlider(value=start, min=0, max=last, description="step", readout=False,
                         continuous_update=False)
    slider.add_class("ngcrack-growth-step")
    box = w.IntText(value=start, layout=w.Layout(width="80px"), tooltip=f"a step from 0 to {last}")
    box.add_class("ngcrack-growth-typed-step")
    image = w.Image(format="png", layout=w.Layout(width="auto", max_width="100%"))
    image.add_class("ngcrack-growth-figure")
    readout = w.HTML()
    status = w.HTML()
    status.add_class("ngcrack-status")

    def show(n: int) -> None:
        try:
            image.value = render_step(result, n, view)
            readout.value = "<pre>" + html.escape(step_readout(result, n)) + "</pre>"
            status.value = ""
        except Exception as exc:  # noqa: BLE001  (a widget shows one line, never a traceback)
            status.value = ("<span style='color:#b00020'>&#9888; The step could not be drawn: choose another "
                            f"step.</span><div style='color:#666; font-size:11px'>details: "
                            f"{html.escape(str(exc).splitlines()[0] if str(exc) else type(exc).__name__)}</div>")

    wire_steps(slider, box, status, last, show)
    return w.VBox([w.HBox([slider, box]), status, image, readout])
