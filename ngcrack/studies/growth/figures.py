"""The pictures of a growth run: the paths and load factors (`plot_growth`), one step's
deformed body (`draw_frame`, the GIF `animate_growth` and the explorer's step view) and the
load-factor panel (`draw_load_factors`). Every figure saved to a file is a Figure with its
own Agg canvas (`plots.new_figure`): pyplot's backend and figures are left alone.

What a student reads off them is drawn, not left to a readout:

- the body at its true place: each step's displacement is drawn about the undeformed
  configuration with its rigid motion (the best-fitting translation and rotation) taken
  out, the undeformed crack dashed beneath the faces; axes in the scene's length unit;
- the kink each tip takes, as an arrow of the next segment's direction with its angle
  ("kink +70.5°", counter-clockwise positive from the crack's direction);
- a zoom is labelled as one, with the whole body in an inset and the zoomed box on it;
- the load factor of each tip (tips named by where they are: "left tip", "right tip"),
  on a scale set by the tips that can grow: a tip whose load factor is far above the
  step's (a closed tip that does not grow, or none at all) is marked at the panel's top,
  not plotted, so that it does not flatten the others.
"""

from __future__ import annotations

import math

import numpy as np

#: a tip whose load factor exceeds this many times its step's is "off the scale" (marked, not plotted)
OFF_SCALE = 5.0
#: the largest displacement drawn in a step's frame, as a fraction of the body's diameter
FRAME_FRACTION = 0.04


def length_unit(scene) -> str:
    """The scene's length unit, else "length units"."""
    u = getattr(scene, "units", None) or {}
    return u.get("length") or "length units"


def without_rigid_motion(points: np.ndarray, disp: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """(translation a, centre c, rotation w) of the rigid motion u ~ a + w (-(y - c_y), x - c_x)
    that fits `disp` at `points` best in least squares (points and disp: (..., 2))."""
    p = np.asarray(points, float).reshape(-1, 2)
    u = np.asarray(disp, float).reshape(-1, 2)
    c = p.mean(axis=0)
    a = u.mean(axis=0)
    r = p - c
    den = float(np.sum(r * r))
    w = float(np.sum(r[:, 0] * (u[:, 1] - a[1]) - r[:, 1] * (u[:, 0] - a[0])) / den) if den > 0 else 0.0
    return a, c, w


def _minus_rigid(points: np.ndarray, disp: np.ndarray, rigid) -> np.ndarray:
    a, c, w = rigid
    r = np.asarray(points, float) - c
    return np.asarray(disp, float) - a - w * np.stack([-r[..., 1], r[..., 0]], axis=-1)


def _draw_body(ax, scene, **kw):
    from .paths import body_region

    region = body_region(scene)
    for ring in [region.exterior, *region.interiors]:
        xy = np.asarray(ring.coords)
        ax.plot(xy[:, 0], xy[:, 1], **{"color": "k", "lw": 1.0, **kw})


def _tip_direction(scene, crack: int, end: str) -> np.ndarray | None:
    pts = np.asarray(scene.cracks[crack].points, float) if crack < len(scene.cracks) else None
    if pts is None or len(pts) < 2:
        return None
    d = pts[0] - pts[1] if end == "first" else pts[-1] - pts[-2]
    n = float(np.hypot(*d))
    return d / n if n > 0 else None


def draw_kinks(ax, result, n: int, length: float, fontsize: float = 8.0, arrows: bool = True) -> list[str]:
    """At each tip of step `n` with a kink: an arrow of `length` in the kinked direction and
    its angle (without `arrows`: the angle alone, written beside the tip, away from the
    path). Returns the labels drawn."""
    step = result.steps[n]
    scene = result.scenes[n]
    labels = []
    for t in step["tips"]:
        kink = t.get("kink_deg")
        d = _tip_direction(scene, t["crack"], t["end"])
        if kink is None or d is None or not math.isfinite(kink):
            continue
        th = math.radians(kink)
        e = np.array([math.cos(th) * d[0] - math.sin(th) * d[1], math.sin(th) * d[0] + math.cos(th) * d[1]])
        p = np.array([t["x"], t["y"]], float)
        color = "#15803d" if t.get("grew") else "0.45"
        label = f"kink {kink:+.1f}°" + ("" if t.get("grew") else " (does not grow)")
        if arrows:
            ax.annotate("", xy=p + length * e, xytext=p, zorder=7,
                        arrowprops={"arrowstyle": "-|>", "color": color, "lw": 1.4, "shrinkA": 0, "shrinkB": 0})
            ax.annotate(label, p + length * e, xytext=(3, 3), textcoords="offset points", fontsize=fontsize,
                        color=color, zorder=7)
        else:  # beside the tip, on the side away from the kinked path
            side = -np.sign(e[0] * d[1] - e[1] * d[0]) or 1.0
            off = 14.0 * np.array([-d[1], d[0]]) * side + 10.0 * d
            ax.annotate(label, p, xytext=tuple(off), textcoords="offset points", fontsize=fontsize, color="k",
                        ha="center", va="center", zorder=7,
                        bbox={"boxstyle": "round,pad=0.15", "fc": "white", "alpha": 0.8, "lw": 0})
        labels.append(label)
    return labels


def draw_load_factors(bx, result, step: int | None = None) -> dict:
    """The load factor of each tip against the crack length, on a scale the growing tips
    set; tips off the scale (more than OFF_SCALE times their step's load factor, or no
    driving force) marked at the top with a triangle. `step`: that step circled. Returns
    {"ylim", "off_scale": [(step, tip name)], "tips": [names]}."""
    from ...planar.plots import tip_names

    df = result.table
    lam_name = "load factor λ" + (" = K_Ic / K_eq" if result.K_Ic is not None else " (relative to step 0)")
    if df.empty:
        bx.set_xlabel("crack length")
        bx.set_ylabel(lam_name)
        return {"ylim": (0.0, 1.0), "off_scale": [], "tips": []}
    first = [t for t in result.steps[0]["tips"]]
    names = dict(zip([(t["crack"], t["end"]) for t in first], tip_names(first)))
    step_lam = df.groupby("step")["load_factor"].first()
    lam = df["tip_load_factor"].to_numpy(float)
    ref = step_lam.reindex(df["step"]).to_numpy(float)
    off = ~np.isfinite(lam) | (np.isfinite(ref) & (lam > OFF_SCALE * ref))
    shown = lam[~off & np.isfinite(lam)]
    top = 1.2 * float(np.max(np.r_[shown, step_lam[np.isfinite(step_lam)].to_numpy(float)], initial=0.0)) or 1.0
    off_list = []
    length_unit_ = length_unit(result.scene)
    for (crack, end), g in df.groupby(["crack", "end"], sort=False):
        name = names.get((crack, end), f"crack {crack}, {end} tip")
        gl = g["tip_load_factor"].to_numpy(float)
        goff = off[g.index.to_numpy()]
        x = g["crack_length"].to_numpy(float)
        y = np.where(goff, np.nan, gl)
        line, = bx.plot(x, y, "-", lw=1.4, label=name)
        grew = g["grew"].to_numpy(bool)
        bx.plot(x[grew & ~goff], y[grew & ~goff], "o", ms=5, color=line.get_color())
        bx.plot(x[~grew & ~goff], y[~grew & ~goff], "o", ms=5, mfc="white", color=line.get_color())
        if np.any(goff):
            bx.plot(x[goff], np.full(goff.sum(), 0.97 * top), "^", ms=7, color=line.get_color(), mfc="white",
                    clip_on=False)
            off_list += [(int(s), name) for s in g["step"].to_numpy()[goff]]
    steps = df.groupby("step").first()
    bx.plot(steps["crack_length"], steps["load_factor"], "k:", lw=1, label="the step's (smallest) λ")
    if off_list:
        bx.plot([], [], "^", color="0.3", mfc="white", label=f"off the scale (λ > {OFF_SCALE:g}× the step's: "
                                                            "closed or no driving force)")
    if step is not None:
        here = df[df["step"] == step]
        ok = ~off[here.index.to_numpy()]
        bx.plot(here["crack_length"][ok], here["tip_load_factor"][ok], "o", ms=11, mfc="none", mec="k",
                label=f"step {step}")
    bx.set_ylim(0.0, top)
    bx.set_xlabel(f"crack length [{length_unit_}]")
    bx.set_ylabel(lam_name)
    bx.grid(alpha=0.3)
    bx.legend(fontsize=7, loc="lower right")
    bx.set_title("load factor of each tip (filled: the tip grew)", fontsize=9)
    return {"ylim": (0.0, top), "off_scale": off_list, "tips": list(names.values())}


def plot_growth(result, path=None):
    """The paths over the body coloured by step with each tip's first kink, beside the load
    factor of each tip against crack length."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.collections import LineCollection
    from matplotlib.colors import Normalize

    from ...planar.plots import new_figure

    fig, (ax, bx) = new_figure(path, nrows=1, ncols=2, figsize=(12, 5), constrained_layout=True)
    _draw_body(ax, result.scene)
    n_steps = max(len(result.scenes) - 1, 1)
    cmap = colormaps["viridis"]
    for c in result.scenes[0].cracks:
        p = np.asarray(c.points)
        ax.plot(p[:, 0], p[:, 1], color="k", lw=2.5, solid_capstyle="round")
    for n in range(1, len(result.scenes)):  # each step's new segments, coloured by the step that added them
        old, new = result.scenes[n - 1], result.scenes[n]
        segs = []
        for co, cn in zip(old.cracks, new.cracks):
            po, pn = list(co.points), list(cn.points)
            k = pn.index(po[0]) if po[0] in pn else 0  # points added at the first end
            segs += [(pn[i], pn[i + 1]) for i in range(k)]
            segs += [(pn[i], pn[i + 1]) for i in range(k + len(po) - 1, len(pn) - 1)]
        for cn in new.cracks[len(old.cracks):]:  # a crack that left a hole (grow's at_hole)
            segs += list(zip(cn.points[:-1], cn.points[1:]))
        if segs:
            ax.add_collection(LineCollection(segs, colors=[cmap(n / n_steps)], linewidths=2.0))
    if result.final_cracks is not None and len(result.scenes) <= len(result.steps):  # the segment that cut through
        segs = []
        for co, pn in zip(result.scenes[-1].cracks, result.paths):
            po, pn = {tuple(p) for p in co.points}, [tuple(p) for p in pn]
            segs += [(a, b) for a, b in zip(pn[:-1], pn[1:]) if a not in po or b not in po]
        ax.add_collection(LineCollection(segs, colors=[cmap(1.0)], linewidths=2.0))
    fig.colorbar(ScalarMappable(cmap=cmap, norm=Normalize(0, n_steps)), ax=ax, label="step")
    xy = np.concatenate(result.paths)
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    pad = 0.25 * max(hi - lo) + 2 * result.da
    poly = np.asarray(result.scene.polygon)
    blo, bhi = poly.min(axis=0), poly.max(axis=0)
    vlo = np.maximum(lo - pad, blo - result.da)
    vhi = np.minimum(hi + pad, bhi + result.da)
    draw_kinks(ax, result, 0, 0.0, fontsize=8, arrows=False)  # (the first kink of each tip)
    ax.set_xlim(vlo[0], vhi[0])
    ax.set_ylim(vlo[1], vhi[1])
    ax.set_aspect("equal")
    unit = length_unit(result.scene)
    ax.set_xlabel(f"x [{unit}]")
    ax.set_ylabel(f"y [{unit}]")
    zoom = bool(np.any(vlo > blo + 1e-9) or np.any(vhi < bhi - 1e-9))
    ax.set_title(f"crack paths, {result.criterion}, da = {result.da:g}: {result.scene.name}"
                 + (f"\nzoom: the body is [{blo[0]:g}, {bhi[0]:g}] × [{blo[1]:g}, {bhi[1]:g}]" if zoom else ""),
                 fontsize=10)
    if zoom:
        _inset_body(ax, result, vlo, vhi)
    draw_load_factors(bx, result)
    if path is not None:
        fig.savefig(path, dpi=130)
    return fig


def _inset_body(ax, result, lo, hi) -> None:
    """The whole body, small, in the corner of `ax`, with the zoomed box on it."""
    from matplotlib.patches import Rectangle

    poly = np.asarray(result.scene.polygon)
    w, h = float(np.ptp(poly[:, 0])), float(np.ptp(poly[:, 1]))
    size = 0.28
    hs = size * min(h / w, 1.5) if w else size
    ins = ax.inset_axes([0.01, 1 - hs - 0.05, size, hs])  # (top left: the legend text is at the bottom)
    _draw_body(ins, result.scene, lw=0.6)
    for p in result.paths:
        ins.plot(p[:, 0], p[:, 1], "r-", lw=1.0)
    ins.add_patch(Rectangle(lo, *(hi - lo), fill=False, ec="tab:blue", lw=1.0))
    ins.set_aspect("equal")
    ins.set_xticks([])
    ins.set_yticks([])
    ins.set_title("whole body", fontsize=6, pad=1)


def frame_view(result) -> tuple[float, np.ndarray, np.ndarray]:
    """(magnification, lower-left, upper-right) shared by every frame of `result`: the
    largest displacement (rigid motion taken out) drawn as FRAME_FRACTION of the body's
    diameter, the view around the cracks."""
    from ...core.errors import InputError

    if not result.frames:
        raise InputError("frames: the result keeps no frames (grow(..., frames=False)); grow again with frames=True")
    diam = result.scene.diameter
    umax = 0.0
    for f in result.frames:
        rigid = without_rigid_motion(f["corners"], f["disp"])
        umax = max(umax, float(np.max(np.linalg.norm(_minus_rigid(f["corners"], f["disp"], rigid), axis=2))))
    scale = FRAME_FRACTION * diam / umax if umax > 0 else 0.0
    xy = np.concatenate([np.asarray(c.points) for s in result.scenes for c in s.cracks])
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    pad = 0.3 * max(hi - lo) + 3 * result.da
    poly = np.asarray(result.scene.polygon)
    return scale, np.maximum(lo - pad, poly.min(axis=0)), np.minimum(hi + pad, poly.max(axis=0))


def draw_frame(ax, result, n: int, view=None) -> dict:
    """Step `n` on `ax`: the deformed body about its undeformed place (rigid motion taken
    out, magnified), the undeformed crack dashed, the crack faces (open red, closed blue),
    each tip's kink, axes in the scene's unit, a labelled zoom with the whole body inset.
    Returns what was drawn: {"scale", "rigid", "kinks", "zoom"}."""
    from matplotlib.collections import PolyCollection

    scale, lo, hi = view if view is not None else frame_view(result)
    f = result.frames[n]
    rigid = without_rigid_motion(f["corners"], f["disp"])
    disp = _minus_rigid(f["corners"], f["disp"], rigid)
    ax.add_collection(PolyCollection(f["corners"] + scale * disp, facecolors="0.85", edgecolors="0.65",
                                     linewidths=0.15))
    _draw_body(ax, result.scene, color="0.4", lw=0.8, ls="--")
    for c in result.scenes[n].cracks:
        p = np.asarray(c.points)
        ax.plot(p[:, 0], p[:, 1], "--", color="0.2", lw=0.8, zorder=3)
    for face in f["faces"]:
        is_open = face["open"]
        for u in (face["plus"], face["minus"]):
            p = face["mid"] + scale * _minus_rigid(face["mid"], u, rigid)
            ax.plot(np.where(is_open, p[:, 0], np.nan), np.where(is_open, p[:, 1], np.nan), "-", color="#d62728",
                    lw=1.6, zorder=4)
            ax.plot(np.where(~is_open, p[:, 0], np.nan), np.where(~is_open, p[:, 1], np.nan), "-", color="#1f4eb4",
                    lw=1.6, zorder=4)
    kinks = draw_kinks(ax, result, n, 2.0 * result.da + 0.04 * float(np.max(hi - lo)), fontsize=8)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    unit = length_unit(result.scene)
    ax.set_xlabel(f"x [{unit}]", fontsize=8)
    ax.set_ylabel(f"y [{unit}]", fontsize=8)
    ax.tick_params(labelsize=7)
    poly = np.asarray(result.scene.polygon)
    blo, bhi = poly.min(axis=0), poly.max(axis=0)
    zoom = bool(np.any(lo > blo + 1e-9) or np.any(hi < bhi - 1e-9))
    lam = result.steps[n]["load_factor"]
    head = f"step {n}: load factor {lam:.3g}" if lam is not None else f"step {n}"
    ax.set_title(head + (" (zoom on the cracks)" if zoom else ""), fontsize=10)
    if zoom:
        _inset_body(ax, result, lo, hi)
    ax.text(0.01, 0.01, f"displacement × {scale:.3g} about the undeformed body (rigid motion taken out)\n"
                        "faces: red open, blue closed; dashed: undeformed crack; arrows: kinks",
            transform=ax.transAxes, fontsize=7, va="bottom",
            bbox={"boxstyle": "round,pad=0.2", "fc": "white", "alpha": 0.8, "lw": 0})
    return {"scale": scale, "rigid": rigid, "kinks": kinks, "zoom": zoom}


def animate_growth(result, path, fps: int = 4):
    """Write a GIF of `draw_frame` for every step (its own canvas: pyplot untouched)."""
    from matplotlib.animation import PillowWriter

    from ...planar.plots import new_figure

    view = frame_view(result)
    fig, ax = new_figure(path, figsize=(6, 6), constrained_layout=True)
    writer = PillowWriter(fps=fps)
    with writer.saving(fig, str(path), dpi=fig.dpi):
        for n in range(len(result.frames)):
            fig.clear()
            ax = fig.add_subplot()
            draw_frame(ax, result, n, view)
            writer.grab_frame()
    return path
