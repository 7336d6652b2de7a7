"""GrowthResult: the steps of a growth run as a tidy table, the scene of every step, the final
paths, the `grow --json` dictionary and the pictures (matplotlib and pillow, imported lazily)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from .records import step_loads

#: the tidy table's columns, in order (one row per step and tip)
COLUMNS = ("step", "crack", "end", "x", "y", "K_I", "K_II", "G", "T", "K_eq", "kink_deg", "load_factor",
           "tip_load_factor", "crack_length", "closed", "grew", "ndof", "solves", "time_s", "mesh_s", "assembly_s",
           "linear_s", "crack_s", "post_s", "error_estimate", "kkt", "force", "displacement", "compliance")
#: the largest crack-face opening drawn in the animation, as a fraction of the body's diameter
FACE_FRACTION = 0.03


def _finite_or_none(x):
    return float(x) if x is not None and math.isfinite(x) else None


@dataclass
class GrowthResult:
    """What `nc.grow` returns.

    `table`: a pandas DataFrame, one row per step and tip inside the body (COLUMNS):
    K_I, K_II, G, the T-stress T and K_eq at the scene's load; kink_deg the kink the tip takes (for a tip
    that does not grow: the MTS kink of its K, or with PLS the first trial's angle,
    criteria.pls_predictor) relative to its current direction,
    counter-clockwise positive; load_factor the step's (the smallest among the tips that
    grow), tip_load_factor the tip's own K_Ic / K_eq; closed whether the faces at the tip
    touch; grew whether the tip advanced after this step; solves the solves that made the
    step (more than one: PLS trials); time_s their wall-clock seconds, of which mesh_s
    meshing, assembly_s assembly, linear_s the factorization and linear solves, crack_s the
    crack problem (Schur complement and QP), post_s the tips' K and the error estimate; kkt
    the largest of the solve's KKT residuals; force and
    displacement the primary load's P and delta at the step's load factor (records.py: the
    P-delta record; None where the load factor is infinite), compliance delta / P.
    `scenes[n]`: the scene of step n (one more at the end if the last growth cut through
    the body); `stopped`: why the run ended; `events`: (step, tip, what) as tips reached the
    boundary; `frozen`: tip -> why it stopped inside the body; `solution`: the last solve;
    `paths`: the final crack paths (with the last segment where it cut the body through: stop
    reason "cut through", the last scene then kept only if every piece is still held).
    """

    scene: object
    element: str
    criterion: str
    da: float
    K_Ic: float | None
    steps: list = field(default_factory=list)
    rows: list = field(default_factory=list)
    scenes: list = field(default_factory=list)
    frames: list = field(default_factory=list)
    profiles: list = field(default_factory=list)
    events: list = field(default_factory=list)
    frozen: dict = field(default_factory=dict)
    stopped: str = ""
    solution: object = None
    final_cracks: list | None = None
    #: the critical distance of criterion "gmts" (None for the others)
    r_c: float | None = None
    #: the load whose P and delta the table's force and displacement columns hold (records.py)
    primary_load: str | None = None

    # ------------------------------------------------------------------ filling
    def add_step(self, n, scene, sol, values, lam_step, grew, time_s, solves, frames=True, parts=None,
                 cycles=None) -> None:
        ndof = int(sol.ndof["total"])
        kkt = {k: float(v) for k, v in sol.kkt.items()}
        est = None if sol.error_estimate is None else float(sol.error_estimate.relative)
        cost_columns = {f"{k}_s": float(v) for k, v in (parts or {}).items()}
        tips = []
        rec = step_loads(sol, lam_step)
        self.primary_load = self.primary_load or rec.primary
        for v in values:
            kink = math.degrees(v.get("kink", v["theta"])) + 0.0  # no -0.0
            did = v["label"] in grew
            length = float(scene.cracks[v["crack"]].length)
            self.rows.append({"step": n, "crack": v["crack"], "end": v["end"], "x": v["x"], "y": v["y"],
                              "K_I": v["K_I"], "K_II": v["K_II"], "G": v["G"], "T": v.get("T"), "K_eq": v["K_eq"],
                              "kink_deg": kink,
                              "load_factor": lam_step, "tip_load_factor": v["lambda"], "crack_length": length,
                              "closed": v["closed"], "grew": did, "ndof": ndof, "solves": int(solves),
                              "time_s": float(time_s), **cost_columns, "error_estimate": est,
                              "kkt": max(kkt.values(), default=0.0),
                              "force": rec.P, "displacement": rec.delta, "compliance": rec.compliance,
                              **({} if cycles is None else {"cycles": float(cycles)})})
            tips.append({"crack": v["crack"], "end": v["end"], "x": v["x"], "y": v["y"], "K_I": v["K_I"],
                         "K_II": v["K_II"], "G": v["G"], "K_eq": v["K_eq"], "kink_deg": kink, "grew": did,
                         "T": v.get("T")})
        self.steps.append({"step": n, "load_factor": _finite_or_none(lam_step), "ndof": ndof, "time_s": float(time_s),
                           "kkt": kkt, "error_estimate": est, "tips": tips,
                           "force": rec.force, "displacement": rec.displacement,
                           **({} if cycles is None else {"cycles": float(cycles)})})
        self.scenes.append(scene)
        self.profiles.append(list(sol.profiles))
        if frames:
            self.frames.append(_frame(sol))

    def add_final(self, scene, cracks=None) -> None:
        """The scene after the last growth; where it is no valid scene (the cracks cut the body and a
        piece is held by nothing) scene is None and `cracks` (their points) keep the last segments."""
        if scene is not None:
            self.scenes.append(scene)
        if cracks is not None:
            self.final_cracks = [np.asarray(c, dtype=float) for c in cracks]

    # ------------------------------------------------------------------ views
    @property
    def table(self):
        import pandas as pd

        fatigue = bool(self.rows) and "cycles" in self.rows[0]
        return pd.DataFrame(self.rows, columns=list(COLUMNS) + (["cycles"] if fatigue else []))

    @property
    def holes(self) -> list[dict]:
        """The closest approach of the final cracks to each hole of the scene (a near miss, or 0
        where a tip stopped at it): {"hole", "label", "distance", "crack", "point"} per hole."""
        from .paths import hole_approaches

        return hole_approaches(self.scene, self.paths)

    @property
    def final_scene(self):
        return self.scenes[-1]

    @property
    def paths(self) -> list[np.ndarray]:
        """The final crack paths, one (n, 2) array of points per crack (with the segment that cut through)."""
        if self.final_cracks is not None:
            return [np.asarray(c, dtype=float) for c in self.final_cracks]
        return [np.asarray(c.points, dtype=float) for c in self.final_scene.cracks]

    def load_factors(self) -> np.ndarray:
        """The load factor of every step (inf where no tip has a driving force)."""
        return np.array([np.inf if s["load_factor"] is None else s["load_factor"] for s in self.steps])

    def to_json_dict(self) -> dict:
        """The `ngcrack grow --json` dictionary (README, "Crack growth")."""
        r_c = {} if self.r_c is None else {"r_c": float(self.r_c)}  # the gmts criterion's critical distance
        return {"scene": self.scene.name, "element": self.element, "criterion": self.criterion, **r_c,
                "da": float(self.da), "K_Ic": self.K_Ic, "stopped": self.stopped, "steps": self.steps,
                "cracks": [{"points": [[float(x), float(y)] for x, y in c]} for c in self.paths],
                **({"holes": self.holes} if self.scene.holes else {})}

    def summary(self) -> str:
        df = self.table
        lines = [f"{self.scene.name}: {self.criterion}, da {self.da:g}, {len(self.steps)} steps; stopped: {self.stopped}"]
        if len(df):
            cols = ["step", "crack", "end", "x", "y", "K_I", "K_II", "K_eq", "kink_deg", "load_factor", "closed", "grew"]
            lines.append(df[cols].to_string(index=False, float_format=lambda v: f"{v:.4g}"))
        for h in self.holes:
            lines.append(f"closest approach to {h['label']}: {h['distance']:.4g} (crack {h['crack']} at "
                         f"({h['point'][0]:.4g}, {h['point'][1]:.4g}))")
        return "\n".join(lines)

    # ------------------------------------------------------------------ pictures
    def plot(self, path=None, curve: str = "load-factor"):
        """The paths over the body coloured by step, beside the load factor against crack length
        (``curve="load-factor"``), or the load-displacement (P-delta) curve of the primary load alone
        (``curve="P-delta"``)."""
        if curve == "P-delta":
            from .records import plot_load_displacement

            return plot_load_displacement(self, path=path)
        if curve != "load-factor":
            raise InputError(f"curve = {curve!r}: allowed values are load-factor, P-delta")
        return plot_growth(self, path)

    def animate(self, path, fps: int = 4):
        """A GIF of the deformed body and the crack faces, one frame per step (pillow)."""
        return animate_growth(self, path, fps=fps)


# ---------------------------------------------------------------------- frames
def _frame(sol) -> dict:
    """What a picture of one step needs, small (float32): the triangle corners and their
    post-processed displacements, and per crack the edge mid points with the displacement
    of each face there (from the triangle on that side) and the open / closed state."""
    from ngcrack.plots import element_displacements

    corners, disp = element_displacements(sol)
    faces = []
    for c, prof in zip(sol.crack_mesh.cracks, sol.profiles):
        mid = np.asarray(c.mid, dtype=float)
        eps = 1e-3 * np.asarray(c.length)[:, None] * np.asarray(c.normal)
        side = []
        for sign in (1.0, -1.0):
            p = mid + sign * eps
            nr = np.asarray(sol.mesh(p[:, 0], p[:, 1])["nr"], dtype=int)
            T = corners[nr]  # (m, 3, 2): barycentric coordinates of the mid point in its triangle
            M = np.stack([T[:, 1] - T[:, 0], T[:, 2] - T[:, 0]], axis=2)
            lam = np.linalg.solve(M, (mid - T[:, 0])[:, :, None])[:, :, 0]
            w = np.column_stack([1.0 - lam.sum(axis=1), lam])
            side.append(np.einsum("mk,mkd->md", w, disp[nr]))
        faces.append({"mid": mid.astype(np.float32), "plus": side[0].astype(np.float32),
                      "minus": side[1].astype(np.float32), "open": np.asarray(prof.state) == "open"})
    return {"corners": corners.astype(np.float32), "disp": disp.astype(np.float32), "faces": faces}


def _draw_body(ax, scene, **kw):
    from .paths import body_region

    region = body_region(scene)
    for ring in [region.exterior, *region.interiors]:
        xy = np.asarray(ring.coords)
        ax.plot(xy[:, 0], xy[:, 1], **{"color": "k", "lw": 1.0, **kw})


def plot_growth(result: GrowthResult, path=None):
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.collections import LineCollection
    from matplotlib.colors import Normalize

    from ..plots import new_figure

    fig, (ax, bx) = new_figure(path, nrows=1, ncols=2, figsize=(12, 5), constrained_layout=True)
    _draw_body(ax, result.scene)
    n_steps = max(len(result.scenes) - 1, 1)
    cmap = colormaps["viridis"]
    first = result.scenes[0]
    for c in first.cracks:
        p = np.asarray(c.points)
        ax.plot(p[:, 0], p[:, 1], color="k", lw=2.5, solid_capstyle="round")
    # each step's new segments, coloured by the step that added them
    for n in range(1, len(result.scenes)):
        old, new = result.scenes[n - 1], result.scenes[n]
        segs = []
        for co, cn in zip(old.cracks, new.cracks):
            po, pn = list(co.points), list(cn.points)
            k = pn.index(po[0]) if po[0] in pn else 0  # points added at the first end
            segs += [(pn[i], pn[i + 1]) for i in range(k)]
            segs += [(pn[i], pn[i + 1]) for i in range(k + len(po) - 1, len(pn) - 1)]
        if segs:
            ax.add_collection(LineCollection(segs, colors=[cmap(n / n_steps)], linewidths=2.0))
    if result.final_cracks is not None and len(result.scenes) < len(result.steps) + 1:  # the segment that cut through
        last = result.scenes[-1]
        segs = []
        for co, pn in zip(last.cracks, result.final_cracks):
            po = [tuple(p) for p in co.points]
            pn = [tuple(p) for p in pn]
            segs += [(pn[i], pn[i + 1]) for i in range(len(pn) - 1) if pn[i] not in po or pn[i + 1] not in po]
        if segs:
            ax.add_collection(LineCollection(segs, colors=[cmap(1.0)], linewidths=2.0))
    sm = ScalarMappable(cmap=cmap, norm=Normalize(0, n_steps))
    fig.colorbar(sm, ax=ax, label="step")
    xy = np.concatenate(result.paths)
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    pad = 0.25 * max(hi - lo) + 2 * result.da
    poly = np.asarray(result.scene.polygon)
    ax.set_xlim(max(lo[0] - pad, poly[:, 0].min() - result.da), min(hi[0] + pad, poly[:, 0].max() + result.da))
    ax.set_ylim(max(lo[1] - pad, poly[:, 1].min() - result.da), min(hi[1] + pad, poly[:, 1].max() + result.da))
    ax.set_aspect("equal")
    ax.set_title(f"crack paths, {result.criterion}, da = {result.da:g}: {result.scene.name}")
    df = result.table
    lam_name = "load factor" + ("" if result.K_Ic is not None else " (relative to step 0)")
    for (k, end), g in df.groupby(["crack", "end"]):
        ok = np.isfinite(g["tip_load_factor"])
        bx.plot(g["crack_length"][ok], g["tip_load_factor"][ok], "o-", ms=3, label=f"tip {k},{end}")
    steps = df.groupby("step").first()
    bx.plot(steps["crack_length"], steps["load_factor"], "k:", lw=1, label="step (smallest)")
    bx.set_xlabel("crack length of the tip's crack")
    bx.set_ylabel(lam_name)
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3)
    bx.set_title(r"$\lambda = K_{Ic} / K_{eq}$ at each step")
    if path is not None:
        fig.savefig(path, dpi=130)
    return fig


def frame_view(result: GrowthResult) -> tuple[float, np.ndarray, np.ndarray]:
    """(magnification, lower-left, upper-right) shared by every frame of `result`: the
    largest displacement drawn as 4% of the body's diameter, the view around the crack faces."""
    if not result.frames:
        raise InputError("frames: the result keeps no frames (grow(..., frames=False)); grow again with frames=True")
    diam = result.scene.diameter
    umax = max(float(np.max(np.linalg.norm(f["disp"], axis=2))) for f in result.frames)
    scale = 0.04 * diam / umax if umax > 0 else 0.0
    xy = np.concatenate([face["mid"] + scale * u for f in result.frames for face in f["faces"]
                         for u in (face["plus"], face["minus"])] +
                        list(result.paths))
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    pad = 0.3 * max(hi - lo) + 2 * result.da
    return scale, lo - pad, hi + pad


def draw_frame(ax, result: GrowthResult, n: int, view=None) -> None:
    """Step `n` on `ax`: the magnified deformed body (each triangle moved by its
    post-processed displacement) and the crack faces (open in red, closed in blue)."""
    from matplotlib.collections import PolyCollection

    scale, lo, hi = view if view is not None else frame_view(result)
    f = result.frames[n]
    ax.add_collection(PolyCollection(f["corners"] + scale * f["disp"], facecolors="0.82", edgecolors="0.6",
                                     linewidths=0.15))
    for face in f["faces"]:
        is_open = face["open"]
        for u in (face["plus"], face["minus"]):
            p = face["mid"] + scale * u
            ax.plot(np.where(is_open, p[:, 0], np.nan), np.where(is_open, p[:, 1], np.nan), "r-", lw=1.2)
            ax.plot(np.where(~is_open, p[:, 0], np.nan), np.where(~is_open, p[:, 1], np.nan), "b-", lw=1.2)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    lam = result.steps[n]["load_factor"]
    ax.set_title(f"step {n}: load factor {lam:.3g}" if lam is not None else f"step {n}", fontsize=10)
    ax.text(0.02, 0.02, f"displacement x {scale:.3g}; faces: red open, blue closed", transform=ax.transAxes,
            fontsize=8)


def animate_growth(result: GrowthResult, path, fps: int = 4):
    """Write a GIF of `draw_frame` for every step."""
    from matplotlib.animation import PillowWriter

    from ..plots import new_figure

    view = frame_view(result)
    fig, ax = new_figure(path, figsize=(6, 6), constrained_layout=True)  # (its own canvas: pyplot untouched)
    writer = PillowWriter(fps=fps)
    with writer.saving(fig, str(path), dpi=fig.dpi):
        for n in range(len(result.frames)):
            ax.clear()
            draw_frame(ax, result, n, view)
            writer.grab_frame()
    return path
