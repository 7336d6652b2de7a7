"""A growth path in JupyterLab: a step slider over the frames of a crack-growth result.

    res = nc.grow(scene, da=0.1, steps=20, K_Ic=1.0)
    nc.explore_growth(res)

Each step shows the deformed body at one magnification for the whole path (so that the
steps can be compared) with the crack faces open in red and closed in blue, and beside
it the paths coloured by step with the load factor against crack length, the current
step marked. The readout gives the step's tips (position, K_I, K_II, K_eq, kink) and its
load factor. Drawn with matplotlib's Agg canvas into an image widget; a failure to draw
shows one line, never a traceback.
"""

from __future__ import annotations

import io
from typing import Any

from ..errors import InputError
from ..growth.result import GrowthResult, draw_frame, frame_view

#: figure size in inches and resolution of a step's picture
FIGURE_SIZE = (10.0, 4.6)
FIGURE_DPI = 80


def render_step(result: GrowthResult, n: int, view=None) -> bytes:
    """PNG of step `n`: the deformed body and crack faces, and the load factor against crack length."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=FIGURE_SIZE, dpi=FIGURE_DPI, layout="constrained")
    ax, bx = fig.subplots(1, 2, width_ratios=(1.0, 1.0))
    draw_frame(ax, result, n, view)
    table = result.table
    for label, rows in table.groupby(["crack", "end"]):
        bx.plot(rows["crack_length"], rows["load_factor"], ".-", label=f"tip {label[0]},{label[1]}")
        here = rows[rows["step"] == n]
        bx.plot(here["crack_length"], here["load_factor"], "o", ms=9, mfc="none", mec="k")
    bx.set_xlabel("crack length")
    bx.set_ylabel("load factor" + (" (K_Ic / K_eq)" if result.K_Ic is not None else " (relative to step 0)"))
    bx.grid(alpha=0.3)
    bx.legend(fontsize=8)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return buf.getvalue()


def step_readout(result: GrowthResult, n: int) -> str:
    """One line per tip of step `n`: position, K_I, K_II, K_eq, kink (4 significant digits)."""
    step = result.steps[n]
    lam = step["load_factor"]
    lines = [f"step {n} of {len(result.steps) - 1}: load factor " + (f"{lam:.4g}" if lam is not None else "none")]
    for t in step["tips"]:
        kink = "" if t["kink_deg"] is None else f", kink {t['kink_deg']:+.1f} deg"
        lines.append(f"tip {t['crack']},{t['end']} ({t['x']:.4g}, {t['y']:.4g}): K_I = {t['K_I']:.4g}, "
                     f"K_II = {t['K_II']:.4g}, K_eq = {t['K_eq']:.4g}{kink}" + (" (grew)" if t["grew"] else ""))
    return "\n".join(lines)


def explore_growth(result: GrowthResult, **kwargs: Any):
    """An ipywidgets view of `result` (a GrowthResult kept with frames): a step slider,
    the step's picture and its tips' numbers."""
    import html

    import ipywidgets as w

    if not isinstance(result, GrowthResult):
        raise InputError(f"result = {result!r}: must be the GrowthResult of nc.grow(...)")
    view = frame_view(result)  # refuses a result kept without frames, naming the field
    slider = w.IntSlider(value=kwargs.get("step", 0), min=0, max=len(result.frames) - 1, description="step",
                         continuous_update=False)
    image = w.Image(format="png", layout=w.Layout(width="auto", max_width="100%"))
    readout = w.HTML()
    status = w.HTML()

    def show(n: int) -> None:
        try:
            image.value = render_step(result, n, view)
            readout.value = "<pre>" + html.escape(step_readout(result, n)) + "</pre>"
            status.value = ""
        except Exception as exc:  # noqa: BLE001  (a widget shows one line, never a traceback)
            status.value = f"<span style='color:#b00020'>{html.escape(type(exc).__name__)}: " \
                           f"{html.escape(str(exc).splitlines()[0] if str(exc) else '')}</span>"

    slider.observe(lambda change: show(change["new"]), names="value")
    show(slider.value)
    return w.VBox([slider, image, readout, status])
