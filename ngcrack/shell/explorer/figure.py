"""The explorer's figure: the deformed body, its crack faces, the loads and supports, the profiles.

`Drawing` keeps one matplotlib figure (Agg canvas, no pyplot state) and redraws it for a
solution (`render` returns PNG bytes); `draw` is the one-off. What it draws is computed
in `fields` (the stress field, the crack faces, units and labels).

What a student should read off the picture is drawn, not left to the colours:

- each crack's two faces as two curves, each moved by its own side's displacement at the
  figure's magnification: an opening is a gap between them, an interpenetration (crack
  model ``free`` under compression) an overlap, shaded; a zoomed panel around the cracks;
- the crack's normal nu and tangent t as arrows, the loads as arrows on the loaded edges
  (traction, prescribed displacement; the body force at the centroid), clamped edges
  hatched and rollers as circles;
- the scales can be held (`render(hold=True)`): colour limits, profile axes,
  magnification and load-arrow scale stay those of the first frame held, so that two
  loads or crack models are compared on one scale; units on the colour bar and axes
  (the scene's, else "same unit as E" for stresses and "length unit");
- the displacement less the rigid motion that rollers alone leave free (`fields.drawn_displacements`),
  magnified by the factor the title gives, "auto" (fitted) or "as typed" (the legend says where the
  rigid motion is left out);
- the tips' K_I, K_II next to their names ("left tip (x, y): K_I = ..., K_II = ...", three
  significant digits), the stick / slip shading only where the faces move.
"""

from __future__ import annotations

import io
import math

import numpy as np

from .fields import (
    DEFORMED_FRACTION,
    FIELDS,
    K_DIGITS,
    PROFILE_FLOOR,  # noqa: F401  (kept for older imports)
    crack_faces,
    drawn_displacements,
    field_label,
    fit_scales,
    rigid_motion_drawn,
    significant,
    stress_values,
    tip_closed,
    tip_value,
    units,
)
from .messages import tip_names
from .supports import draw_boundary, mover

#: a held magnification is given up where it would draw a displacement larger than this
#: fraction of the body's diameter (the figure re-fits it)
MAX_DEFORMED_FRACTION = 0.25

#: shading of the crack profiles by the faces' state, where the solution reports one
STATE_COLORS = {"stick": "0.85", "slip": "#fde0b0"}
#: a face sample counts as sliding (shaded "slip") only where its sliding exceeds this
#: fraction of the largest displacement: at zero load nothing is shaded
SLIDE_RTOL = 1e-6

#: figure width in inches and resolution (the image is shown at its own size: 1 px per px)
FIGURE_WIDTH = 9.6
FIGURE_DPI = 96
#: kept for older imports: the size of a square body's figure
FIGURE_SIZE = (FIGURE_WIDTH, 5.4)
#: font size in points (11 px at 96 dpi)
FONT_SIZE = 8.5
#: zlib level of the figure's PNG: 1 encodes several times faster than the default 6, for a
#: somewhat larger image (sent to the browser on the same machine or network)
PNG_COMPRESSION = 1
#: above this many triangles no edges are drawn and antialiasing is off (no moire)
EDGE_LIMIT = 3000
#: triangle edges are drawn (grey) on triangles at least this many pixels across
EDGE_PIXELS = 7.0
#: a body this much wider than high is drawn above the panels, not beside them
WIDE = 2.0
#: arrows of a crack-face pressure on each face in the zoom, and their colour
PRESSURE_ARROWS = 5
PRESSURE_COLOR = "#0f766e"
#: colours of the two crack faces (+ side: the one nu points into)
FACE_COLORS = {"+": "#1f3b8c", "-": "#c2410c"}
#: the faces count as closed where |opening| is below this fraction of the largest
#: displacement (the post-processed displacements differ from the QP's jumps at 1e-5)
FACE_RTOL = 1e-3



def draw(sol, field: str = "sigma_nu", title: str = "") -> bytes:
    """The figure of a solution as PNG bytes (one-off; `Drawing` redraws a figure it keeps)."""
    return Drawing().render(sol, field, title)


class Drawing:
    """A figure kept between redraws (matplotlib's Agg canvas, no pyplot state).

    Panels: the deformed body (each triangle moved by the locally post-processed
    displacement, plots.element_displacements, magnified; coloured by a stress field,
    `stress_values`), a zoom on the cracks, and the crack profiles along s (opening
    [u].nu, sliding [u].t; normal and shear traction on a twin axis, stick / slip shaded).
    A body at least WIDE times wider than high spans the top; otherwise it is on the
    left. The axes, colour bar and fonts are made once per layout: a redraw replaces data.

    After `render`: `data` holds what was drawn, for checks without pixels: the
    magnification, the colour limits, the profile limits, per crack the faces' drawn
    points and openings, and `max_gap` / `max_overlap` (the largest opening and
    interpenetration of the faces, in length units, unmagnified).
    """

    def __init__(self):
        self.fig = None
        self._layout = None
        self._held: dict | None = None
        self._temporary: list = []
        self._side = None  # (crack_mesh, crack_side) of the last mesh
        self.data: dict = {}

    # ------------------------------------------------------------------ layout
    def _make(self, poly: np.ndarray) -> None:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import PolyCollection
        from matplotlib.figure import Figure

        w, h = float(np.ptp(poly[:, 0])), float(np.ptp(poly[:, 1]))
        aspect = w / h if h > 0 else 1.0
        wide = aspect >= WIDE
        if wide:
            body_h = min(3.6, 1.5 * FIGURE_WIDTH * 0.86 / aspect)  # (room for the axes labels and arrows)
            height = body_h + 3.6
            fig = Figure(figsize=(FIGURE_WIDTH, height), dpi=FIGURE_DPI)
            gs = fig.add_gridspec(2, 2, height_ratios=[body_h, 2.4], width_ratios=[1.0, 1.5], hspace=0.55,
                                  wspace=0.45, left=0.07, right=0.9, top=1 - 0.5 / height, bottom=1.05 / height)
            ax = fig.add_subplot(gs[0, :])
            axz, axp = fig.add_subplot(gs[1, 0]), fig.add_subplot(gs[1, 1])
        else:
            height = min(6.4, max(4.6, 0.55 * FIGURE_WIDTH / max(aspect, 0.35)))
            fig = Figure(figsize=(FIGURE_WIDTH, height), dpi=FIGURE_DPI)
            gs = fig.add_gridspec(2, 2, width_ratios=[1.25, 1.0], height_ratios=[1.0, 1.0], hspace=0.5,
                                  wspace=0.42, left=0.07, right=0.92, top=1 - 0.5 / height, bottom=1.05 / height)
            ax = fig.add_subplot(gs[:, 0])
            axz, axp = fig.add_subplot(gs[0, 1]), fig.add_subplot(gs[1, 1])
        FigureCanvasAgg(fig)
        self.fig, self.ax, self.axz, self.axp = fig, ax, axz, axp
        self.axt = axp.twinx()
        for a in (ax, axz, axp, self.axt):
            a.tick_params(labelsize=FONT_SIZE)
        self.body = PolyCollection(np.zeros((0, 3, 2)), cmap="RdBu_r")
        self.body.set_array(np.zeros(0))
        ax.add_collection(self.body)
        self.zoom = PolyCollection(np.zeros((0, 3, 2)), cmap="RdBu_r", edgecolors="face", linewidths=0.2)
        self.zoom.set_array(np.zeros(0))
        axz.add_collection(self.zoom)
        self.colorbar = fig.colorbar(self.body, ax=ax, shrink=0.9, extend="both", pad=0.02,
                                     fraction=0.035 if wide else 0.05)
        self.colorbar.ax.tick_params(labelsize=FONT_SIZE)
        ax.set_aspect("equal")
        axz.set_aspect("equal")
        self._layout = (round(aspect, 3), wide)
        self._height = height

    # ------------------------------------------------------------------ render
    def render(self, sol, field: str = "sigma_nu", title: str = "", *, hold: bool = False,
               magnification: float = 0.0, load_factor: float | None = None, scales: dict | None = None) -> bytes:
        """Draw `sol` with the stress `field` (one of FIELDS) and return the PNG bytes.

        ``hold``: keep the scales of the last frame drawn with hold (the first one sets
        them; a new field or layout sets them again). ``magnification`` > 0: displacements
        drawn times this factor (0: automatic, or the held one). ``load_factor``: shown in
        the title, with its sign's meaning. ``scales``: the scales to use (`fields.fit_scales`
        of a reference solution, the explorer's "hold for load changes"), before ``hold``."""
        from ...planar.plots import centroid_stress

        poly = np.asarray(sol.scene.polygon, float)
        self._start(poly)
        stress_unit, length_unit = units(sol.scene)
        model = (getattr(sol, "options", None) or {}).get("crack_model")
        sigma = centroid_stress(sol)
        corners, disp = drawn_displacements(sol, sigma)  # (less the rigid motion rollers leave free)
        diam = float(np.max(np.linalg.norm(poly[:, None] - poly[None], axis=2)))
        umax = float(np.max(np.linalg.norm(disp, axis=2))) if len(disp) else 0.0
        vals = stress_values(sol, field, sigma)
        profiles = sol.crack_profiles()
        held = self._hold_scales(fit_scales(sol, field, corners, disp, vals), field, hold, scales, umax, diam)
        auto = not (magnification and magnification > 0)
        scale = held["scale"] if auto else float(magnification)
        clim = held["clim"] or 1.0

        # the body, its outline, loads and supports
        moved = corners + scale * disp
        lo = self._draw_body(field, corners, moved, vals, clim, poly)
        peak, clipped = self._mark_peak(sol, field, moved, vals, clim)
        closed = np.vstack([poly, poly[:1]])
        self._temporary += self.ax.plot(*closed.T, color="0.55", lw=0.6, ls="--", zorder=1)
        artists, self._extent = draw_boundary(self.ax, sol.scene, poly, diam, held["load"], mover(corners, scale * disp),
                                              FONT_SIZE + 1)
        self._temporary += artists
        # the crack faces, each moved by its own side's displacement; the tips; nu and t
        faces = crack_faces(sol, corners, disp, self._crack_side(sol.crack_mesh))
        gap, overlap, drawn = self._draw_faces(faces, scale, FACE_RTOL * umax)
        tip_text = self._draw_tips(sol, model, corners, disp, scale)
        self._draw_frames(sol.crack_mesh, faces, scale, diam)
        self._label_body(sol, model, title, load_factor, scale, moved, poly, length_unit, auto)
        # the zoom on the cracks: the same magnification
        touching, total = _touching_length(sol, profiles)
        self._draw_zoom(faces, scale, corners, moved, vals, diam, length_unit, gap, overlap, touching, total)
        pressure = self._draw_pressure(faces, profiles, scale)
        jlim, tlim, shaded = self._draw_profiles(profiles, held, umax, model, sol.crack_mesh, stress_unit,
                                                 length_unit)
        if tip_text:
            self._temporary.append(self.fig.text(0.01, 0.1 / self._height, ";   ".join(tip_text), ha="left",
                                                 va="bottom", fontsize=FONT_SIZE + 0.5))
        self.data = {"magnification": scale, "magnification_auto": auto, "clim": (lo, clim), "peak": float(vals[peak]) if peak >= 0 else None,
                     "peak_clipped": bool(clipped), "jump_lim": jlim, "traction_lim": tlim,
                     "faces": drawn, "max_gap": gap, "max_overlap": overlap, "tips": tip_text,
                     "contact_length": touching, "pressure": pressure,
                     "held": bool(hold) or scales is not None, "field": field, "shaded": sorted(shaded)}
        buf = io.BytesIO()
        self.fig.savefig(buf, format="png", pil_kwargs={"compress_level": PNG_COMPRESSION})
        return buf.getvalue()

    # ------------------------------------------------------------------ parts
    def _start(self, poly: np.ndarray) -> None:
        """The figure for this body's layout (made again where the layout changed, its held scales
        dropped), with the previous frame's artists removed."""
        w, h = float(np.ptp(poly[:, 0])), float(np.ptp(poly[:, 1]))
        layout = (round(w / h if h > 0 else 1.0, 3), (w / h if h > 0 else 1.0) >= WIDE)
        if self.fig is None or layout != self._layout:
            self._make(poly)
            self._held = None
        for artist in self._temporary:
            artist.remove()
        self._temporary = []

    def _hold_scales(self, fresh: dict, field: str, hold: bool, scales: dict | None, umax: float,
                     diam: float) -> dict:
        """The frame's scales: the given `scales`, else the held ones (hold, same field), else `fresh`.
        A scale that is zero is taken from `fresh`, the profile axes only grow (no curve leaves them),
        and a magnification that would explode the body is re-fitted."""
        if scales is not None:  # given (the model's reference scales): the profile axes still show every curve
            held = {**scales, "field": field}
        elif hold and self._held is not None and self._held.get("field") == field:
            held = self._held
        else:
            held = {"field": field}
        for k, v in fresh.items():  # a held scale that was zero (an unloaded frame) is taken from this one
            if not held.get(k):
                held[k] = v
        for k in ("jump", "traction"):  # the profile axes only grow while held: no curve leaves them
            held[k] = max(held[k], fresh[k])
        if held["scale"] * umax > MAX_DEFORMED_FRACTION * diam:  # a held magnification that would explode the body
            held["scale"] = fresh["scale"]
        self._held = held
        return held

    def _draw_body(self, field: str, corners, moved, vals, clim: float, poly: np.ndarray) -> float:
        """The deformed triangles coloured by the field (body and zoom share the colour map); the
        colour bar's lower limit."""
        self.body.set_verts(moved)
        self.body.set_array(vals)
        cmap = "RdBu_r" if field == "sigma_nu" else "viridis"
        lo = -clim if field == "sigma_nu" else 0.0
        for coll in (self.body, self.zoom):
            coll.set_cmap(cmap)
            coll.set_clim(lo, clim)
        if len(corners) > EDGE_LIMIT:  # no edges, no antialiasing: no seams, no moire
            self.body.set_edgecolor("face")
            self.body.set_linewidth(0.0)
            self.body.set_antialiased(False)
        else:  # edges on the triangles large enough to show them; the small ones edged in their own colour
            px = _pixels_per_unit(self.ax, poly)
            a, b = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
            size = np.sqrt(0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]))
            big = size * px >= EDGE_PIXELS
            colors = self.body.cmap(self.body.norm(vals))
            colors[big] = (0.0, 0.0, 0.0, 0.2)
            self.body.set_edgecolor(colors)
            self.body.set_linewidth(np.where(big, 0.25, 0.4))
            self.body.set_antialiased(True)
        return lo

    def _mark_peak(self, sol, field: str, moved, vals, clim: float) -> tuple[int, bool]:
        """The colour bar's label; the singular peak beyond the bar circled where it is, its value on
        the bar. (index of the peak or -1, whether it is beyond the bar)"""
        peak = int(np.argmax(np.abs(vals))) if len(vals) else -1
        clipped = peak >= 0 and abs(float(vals[peak])) > 1.001 * clim
        label = field_label(field, sol.scene)
        if clipped:  # the singular peak beyond the colour bar: circled where it is, its value on the bar
            at = moved[peak].mean(axis=0)
            for a in (self.ax, self.axz):
                self._temporary += a.plot([at[0]], [at[1]], marker="o", ms=9, mfc="none", mec="k", mew=1.2,
                                          zorder=7)
            label += f"\n○ peak {significant(float(vals[peak]))}, beyond the bar"
        self.colorbar.set_label(label, fontsize=FONT_SIZE)
        return peak, clipped

    def _draw_faces(self, faces: list, scale: float, tol: float) -> tuple[float, float, list]:
        """Each crack's two faces in the body and the zoom, an interpenetration shaded: (the largest
        opening, the largest interpenetration (0 below `tol`), the faces' drawn points)."""
        gap = max([float(np.max(f["opening"], initial=0.0)) for f in faces] + [0.0])
        overlap = max([float(np.max(-f["opening"], initial=0.0)) for f in faces] + [0.0])
        gap, overlap = (gap if gap > tol else 0.0), (overlap if overlap > tol else 0.0)
        drawn = []
        for f in faces:
            plus = f["points"] + scale * f["plus"]
            minus = f["points"] + scale * f["minus"]
            drawn.append({"crack": f["crack"], "plus": plus.tolist(), "minus": minus.tolist(),
                          "opening": f["opening"].tolist()})
            for a, lw in ((self.ax, 2.0), (self.axz, 2.0)):
                self._temporary += a.plot(*plus.T, color=FACE_COLORS["+"], lw=lw, zorder=4)
                self._temporary += a.plot(*minus.T, color=FACE_COLORS["-"], lw=lw, zorder=4)
                over = f["opening"] < -tol
                if np.any(over):
                    poly_o = np.vstack([plus, minus[::-1]])
                    self._temporary += a.fill(*poly_o.T, color="#d00000", alpha=0.35, lw=0, zorder=3)
        return gap, overlap, drawn

    def _draw_tips(self, sol, model, corners, disp, scale: float) -> list[str]:
        """The tips, named A, B, ... in both panels; their lines of text (name, place, K_I, K_II)."""
        tips = [t for t in (getattr(sol, "tips", None) or []) if tip_value(t, "K_I") is not None]
        tip_text = []
        cm = sol.crack_mesh
        names = tip_names(tips, sol.scene)
        for k, tip in enumerate(tips):
            name = names[k]
            x, y = tip_value(tip, "x"), tip_value(tip, "y")
            if x is not None:
                at = np.array([x, y], float)
                nearest = int(np.argmin(np.linalg.norm(cm.points - at, axis=1)))
                u = self._vertex_displacement(cm, corners, disp, nearest)
                p = cm.points[nearest] + scale * u
                for a in (self.ax, self.axz):
                    self._temporary += a.plot([p[0]], [p[1]], "k*", ms=8, zorder=5)
                    left = "left tip" in name or "lower tip" in name  # (two tips close together: labels apart)
                    self._temporary.append(a.annotate(name, p, xytext=(-4 if left else 4, 4), textcoords="offset points",
                                                      ha="right" if left else "left", fontsize=FONT_SIZE + 1,
                                                      weight="bold", zorder=6))
                where = f"({significant(x)}, {significant(y)})"
            else:
                where = ""
            shut = model in (None, "contact") and tip_closed(sol, tip)  # (free faces may overlap: K_I < 0 is real)
            k1 = "0 (faces closed)" if shut else significant(tip_value(tip, "K_I"))
            tip_text.append(f"{name} {where}: K_I = {k1}, K_II = {significant(tip_value(tip, 'K_II'))}")
        return tip_text

    def _draw_pressure(self, faces: list, profiles, scale: float) -> float:
        """A crack-face pressure p as arrows on both faces in the zoom, pushing them apart (p > 0) or
        together, at PRESSURE_ARROWS points per crack; the largest |p| (0: none drawn)."""
        top = 0.0
        for prof in profiles:
            p = np.asarray(getattr(prof, "face_pressure", None), dtype=float)
            if p.ndim != 1 or not len(p) or not np.any(p != 0):
                continue
            top = max(top, float(np.max(np.abs(p))))
        if top == 0:
            return 0.0
        for f, prof in zip(faces, profiles):
            p = np.asarray(getattr(prof, "face_pressure", None), dtype=float)
            if p.ndim != 1 or not len(p) or not np.any(p != 0):
                continue
            pts = f["points"]
            length = 0.12 * float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
            edges = len(p)
            for k in np.linspace(0, edges - 1, min(PRESSURE_ARROWS, edges)).round().astype(int):
                i = min(k + 1, len(pts) - 2) if edges > 1 else 0  # a vertex inside the crack, not a tip
                n = f["normal"][i]
                L = length * float(p[k]) / top
                for face, sign in (("plus", 1.0), ("minus", -1.0)):
                    at = pts[i] + scale * f[face][i]
                    tail, head = (at, at + sign * L * n) if L > 0 else (at - sign * L * n, at)
                    self._temporary.append(self.axz.annotate(
                        "", xy=head, xytext=tail, zorder=6, annotation_clip=True,
                        arrowprops={"arrowstyle": "-|>", "color": PRESSURE_COLOR, "lw": 1.0}))
        return top

    def _draw_frames(self, cm, faces: list, scale: float, diam: float) -> None:
        """nu and t on each crack (undeformed directions, at the crack's middle edge), in both panels."""
        arrow = 0.07 * diam
        for crack, f in zip(cm.cracks, faces):
            k = len(crack) // 2
            base = crack.mid[k] + scale * 0.5 * (f["plus"][min(k, len(f["plus"]) - 1)]
                                                 + f["minus"][min(k, len(f["minus"]) - 1)])
            for a, length in ((self.ax, arrow), (self.axz, None)):
                L = length if length is not None else 0.12 * max(float(np.sum(crack.length)), 1e-12)
                for vec, lab, col in ((crack.normal[k], "ν", "#7a0177"), (crack.tangent[k], "t", "#006d2c")):
                    self._temporary.append(a.annotate("", xy=base + L * vec, xytext=base, zorder=6,
                                                      arrowprops={"arrowstyle": "->", "color": col, "lw": 1.3}))
                    self._temporary.append(a.text(*(base + 1.2 * L * vec), lab, color=col, fontsize=FONT_SIZE + 2,
                                                  ha="center", va="center", zorder=6))

    def _label_body(self, sol, model, title: str, load_factor, scale: float, moved, poly, length_unit: str,
                    auto: bool = True) -> None:
        """The body panel's extent, axes, title (element, crack model, load factor, magnification) and
        the legend of what is drawn."""
        ax, cm = self.ax, sol.crack_mesh
        ax.update_datalim(np.vstack([moved.reshape(-1, 2), poly] + ([np.array(self._extent)] if self._extent else [])))
        ax.autoscale_view()
        ax.set_xlabel(f"x [{length_unit}]", fontsize=FONT_SIZE)
        ax.set_ylabel(f"y [{length_unit}]", fontsize=FONT_SIZE)
        head = title or sol.scene.name
        load_txt = ""
        if load_factor is not None:
            load_txt = f", load factor {load_factor:+.2f}"
        pressures = [c.pressure for c in sol.scene.cracks if isinstance(getattr(c, "pressure", None), float)]
        if any(pressures):
            load_txt += f", crack pressure p = {significant(max(pressures, key=abs))}"
        how = "auto" if auto else "as typed"
        ax.set_title(f"{head} ({sol.element}{', ' + model if model else ''}{load_txt})\n"
                     f"displacements × {scale:.3g} ({how})", fontsize=FONT_SIZE + 1, pad=12)
        kinds = {bc.type for bc in sol.scene.boundary.values()}
        legend = [("red arrows: traction", "#b91c1c")] if "traction" in kinds else []
        legend += [("purple arrows: prescribed u", "#6d28d9")] if "displacement" in kinds else []
        legend += [("f: body force", "0.2")] if sol.scene.body_force is not None else []
        legend += [("hatched: clamped", "k")] if "clamped" in kinds else []
        legend += [("circles: roller", "k")] if "roller" in kinds else []
        legend += [("blue / orange: + / - face (ν points into +)", FACE_COLORS["+"])] if cm.cracks else []
        if any(getattr(c, "pressure", None) not in (None, 0.0) for c in sol.scene.cracks):
            legend += [("teal arrows on the faces (zoom): crack pressure", PRESSURE_COLOR)]
        if not rigid_motion_drawn(sol.scene):  # (rollers alone: where they sit is a modelling choice)
            legend += [("drawn without its rigid motion (held by rollers only)", "0.25")]
        self._temporary.append(self.fig.text(0.01, 0.05 / self._height * 6, ";  ".join(t for t, _ in legend),
                                             fontsize=FONT_SIZE - 0.5, color="0.25", va="bottom", ha="left"))

    def _draw_profiles(self, profiles, held: dict, umax: float, model, cm, stress_unit: str,
                       length_unit: str) -> tuple[float, float, set]:
        """The crack profiles along s: opening and sliding, normal and shear traction on the twin axis,
        stick / slip shaded. (the jump and traction axes' limits, the states shaded)"""
        axp, axt = self.axp, self.axt
        shaded: set[str] = set()
        jlim = 1.1 * (held["jump"] or 1.0)
        tlim = 1.1 * (held["traction"] or 1.0)
        jpow, tpow = _power(jlim), _power(tlim)
        for k, p in enumerate(profiles):
            sfx = f" (crack {k})" if len(profiles) > 1 else ""
            self._temporary += axp.plot(p.s, np.asarray(p.normal_jump) / jpow, "-", color="tab:blue",
                                        label="opening [u]·ν" + sfx)
            self._temporary += axp.plot(p.s, np.asarray(p.tangential_jump) / jpow, "--", color="tab:green",
                                        label="sliding [u]·t" + sfx)
            self._temporary += axt.plot(p.s, np.asarray(p.normal_stress) / tpow, "-", color="tab:red", lw=1,
                                        label="$\\sigma_n$" + sfx)
            self._temporary += axt.plot(p.s, np.asarray(p.shear_stress) / tpow, ":", color="tab:purple", lw=1,
                                        label="$\\sigma_t$" + sfx)
            state = getattr(p, "state", None)
            if state is not None and len(p.s) > 1 and umax > 0 and model in (None, "contact"):
                shaded |= self._shade_states(p, state, SLIDE_RTOL * umax)
        self._temporary.append(axp.axhline(0.0, color="0.5", lw=0.5))
        axp.set_ylim(-jlim / jpow, jlim / jpow)
        axt.set_ylim(-tlim / tpow, tlim / tpow)
        if profiles:
            axp.set_xlim(0.0, max(float(c.s_mid[-1] + 0.5 * c.length[-1]) for c in cm.cracks))
        axp.set_xlabel(f"s along the crack [{length_unit}]", fontsize=FONT_SIZE)
        axp.set_ylabel(f"jump [{_times(jpow)}{length_unit}]", fontsize=FONT_SIZE)
        axt.set_ylabel(f"traction [{_times(tpow)}{stress_unit}]", fontsize=FONT_SIZE)
        handles, labels = axp.get_legend_handles_labels()
        handles_t, labels_t = axt.get_legend_handles_labels()
        if handles:
            self._temporary.append(axp.legend(handles + handles_t, labels + labels_t, fontsize=FONT_SIZE - 1.5,
                                              loc="upper right", ncol=2, framealpha=0.8))
        ptitle = "crack profiles" if profiles else "no crack"
        if shaded:
            ptitle += " (grey: stick, orange: slip)"
        axp.set_title(ptitle, fontsize=FONT_SIZE + 0.5)
        return jlim, tlim, shaded

    def _shade_states(self, p, state, moving: float) -> set[str]:
        """The stick / slip shading of one profile (slip only where the faces slide more than
        `moving`); the states shaded."""
        from matplotlib.collections import PolyCollection

        s = np.asarray(p.s, float)
        mids = 0.5 * (s[1:] + s[:-1])
        edges = np.r_[s[0] - (mids[0] - s[0]), mids, s[-1] + (s[-1] - mids[-1])]
        slides = np.abs(np.asarray(p.tangential_jump, float)) > moving
        spans: dict[str, list] = {}  # one collection per state (not a patch per sample: drawn faster)
        for lo_s, hi_s, st, mv in zip(edges[:-1], edges[1:], state, slides):
            if st in STATE_COLORS and (st != "slip" or mv):
                spans.setdefault(str(st), []).append([(lo_s, 0.0), (hi_s, 0.0), (hi_s, 1.0), (lo_s, 1.0)])
        for st, verts in spans.items():
            coll = PolyCollection(verts, facecolors=STATE_COLORS[st], linewidths=0, zorder=0,
                                  transform=self.axp.get_xaxis_transform())
            self.axp.add_collection(coll, autolim=False)
            self._temporary.append(coll)
        return set(spans)

    def _crack_side(self, cm):
        from ...planar.geometry import crack_side

        if self._side is None or self._side[0] is not cm:
            self._side = (cm, crack_side(cm) if cm.cracks else np.zeros(len(cm.triangles)))
        return self._side[1]

    @staticmethod
    def _vertex_displacement(cm, corners, disp, v: int) -> np.ndarray:
        rows, cols = np.nonzero(cm.triangles == v)
        return disp[rows, cols].mean(axis=0) if len(rows) else np.zeros(2)

    def _draw_zoom(self, faces, scale, corners, moved, vals, diam, length_unit, gap, overlap, touching: float = 0.0,
                   total: float = 0.0) -> None:
        axz = self.axz
        if not faces:
            self.zoom.set_verts(np.zeros((0, 3, 2)))
            self.zoom.set_array(np.zeros(0))
            axz.set_title("no crack", fontsize=FONT_SIZE + 0.5)
            return
        pts = np.vstack([np.vstack([f["points"] + scale * f["plus"], f["points"] + scale * f["minus"]])
                         for f in faces])
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        extent = float(max(np.max(hi - lo), 1e-12))
        if extent <= 0.35 * diam:  # the whole crack
            c = 0.5 * (lo + hi)
            half = 0.65 * extent
            where = ""
        else:  # a long crack: around its largest opening or interpenetration
            f = max(faces, key=lambda f: float(np.max(np.abs(f["opening"]))))
            k = int(np.argmax(np.abs(f["opening"])))
            c = f["points"][k] + scale * 0.5 * (f["plus"][k] + f["minus"][k])
            half = 0.12 * diam
            where = " (largest |opening|)"
        lo, hi = c - half, c + half
        inside = np.all((moved.max(axis=1) >= lo) & (moved.min(axis=1) <= hi), axis=1)
        self.zoom.set_verts(moved[inside])
        self.zoom.set_array(vals[inside])
        axz.set_xlim(lo[0], hi[0])
        axz.set_ylim(lo[1], hi[1])
        axz.set_xlabel(f"x [{length_unit}]", fontsize=FONT_SIZE)
        if overlap > 0:
            state = f"faces overlap (up to {significant(overlap)})"
        elif total > 0 and touching >= (1.0 - 1e-9) * total:
            state = "faces closed"
        elif touching > 0:  # (the per-edge states, as the profiles shade them and the readout counts)
            state = f"faces touch over {significant(touching)} of {significant(total)}, open elsewhere"
        else:
            state = f"crack open (gap up to {significant(gap)})" if gap > 0 else "crack open"
        axz.set_title(f"zoom{where}:\n{state}", fontsize=FONT_SIZE)


def _pixels_per_unit(ax, poly: np.ndarray) -> float:
    """About how many pixels one length unit takes in the body panel (equal aspect), from the
    panel's box as laid out (not as the last drawing's aspect shrank it: the same for every redraw)."""
    bbox = ax.get_position(original=True).transformed(ax.figure.transFigure)
    w, h = float(np.ptp(poly[:, 0])), float(np.ptp(poly[:, 1]))
    return min(bbox.width / (1.25 * w) if w else np.inf, bbox.height / (1.25 * h) if h else np.inf)


def _touching_length(sol, profiles) -> tuple[float, float]:
    """(length of the crack edges whose faces touch by their state, stick or slip; the cracks'
    whole length): the readout's contact length (fields.contact_length), for the zoom's words."""
    from .fields import contact_length

    total = float(sum(np.sum(c.length) for c in sol.crack_mesh.cracks))
    return (contact_length(sol) if profiles else 0.0), total


def _power(limit: float) -> float:
    """A power of ten to divide an axis by, so that its ticks read 0.1 to 1000 (1 if they do already)."""
    if not limit or not np.isfinite(limit):
        return 1.0
    e = math.floor(math.log10(limit))
    return 1.0 if -1 <= e <= 3 else 10.0 ** e


def _times(power: float) -> str:
    return "" if power == 1.0 else f"$10^{{{int(round(math.log10(power)))}}}$ "




__all__ = ["DEFORMED_FRACTION", "Drawing", "FIELDS", "K_DIGITS", "crack_faces", "draw", "field_label", "stress_values",
           "units"]
