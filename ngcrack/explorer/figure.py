"""The explorer's figure: the deformed body coloured by a stress field and the crack profiles.

`Drawing` keeps one matplotlib figure (Agg canvas, no pyplot state) and redraws it for a
solution (`render` returns PNG bytes); `draw` is the one-off; `stress_values` the stress
field shown, per triangle.
"""

from __future__ import annotations

import io

import numpy as np

#: stress fields the figure can show: the crack-normal stress (sigma nu).nu and von Mises
FIELDS = ("sigma_nu", "von_mises")
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
        from ..plots import element_displacements

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
