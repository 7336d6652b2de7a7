"""GrowthResult: the steps of a growth run as a tidy table, the scene of every step, the final
paths, the `grow --json` dictionary and the pictures (matplotlib and pillow, imported lazily)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...core.errors import InputError
from .figures import animate_growth, draw_frame, frame_view, plot_growth  # noqa: F401  (the pictures)
from .records import step_loads

#: the tidy table's columns, in order (one row per step and tip)
COLUMNS = ("step", "crack", "end", "x", "y", "K_I", "K_II", "G", "T", "K_eq", "kink_deg", "load_factor",
           "tip_load_factor", "crack_length", "closed", "grew", "stopped", "ndof", "solves", "time_s", "mesh_s",
           "assembly_s", "linear_s", "crack_s", "post_s", "error_estimate", "kkt", "force", "displacement", "compliance")
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
    grow), tip_load_factor the tip's own K_Ic / K_eq (both empty where no finite load makes
    a tip grow); closed whether the faces at the tip touch; grew whether the tip advanced
    after this step; stopped why the tip stopped inside the body (a hole, a crack ahead, or
    its new tip closing; empty while it may grow); solves the solves that made the
    step (more than one: PLS trials); time_s their wall-clock seconds, of which mesh_s
    meshing, assembly_s assembly, linear_s the factorization and linear solves, crack_s the
    crack problem (Schur complement and QP), post_s the tips' K and the error estimate
    (error_estimate: the relative estimate, computed only with grow(..., estimate=True)); kkt
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
    #: whether the steps' error estimates are computed (grow(..., estimate=True))
    estimates: bool = False

    # ------------------------------------------------------------------ filling
    def add_step(self, n, scene, sol, values, lam_step, grew, time_s, solves, frames=True, parts=None,
                 cycles=None) -> None:
        ndof = int(sol.ndof["total"])
        kkt = {k: float(v) for k, v in sol.kkt.items()}
        est = sol.error_estimate if self.estimates else None
        est = None if est is None else float(est.relative)
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
                              "load_factor": _finite_or_none(lam_step), "tip_load_factor": _finite_or_none(v["lambda"]),
                              "crack_length": length, "closed": v["closed"], "grew": did,
                              "stopped": v.get("stopped", ""), "ndof": ndof, "solves": int(solves),
                              "time_s": float(time_s), **cost_columns, "error_estimate": est,
                              "kkt": max(kkt.values(), default=0.0),
                              "force": rec.P, "displacement": rec.delta, "compliance": rec.compliance,
                              **({} if cycles is None else {"cycles": float(cycles)})})
            tips.append({"crack": v["crack"], "end": v["end"], "x": v["x"], "y": v["y"], "K_I": v["K_I"],
                         "K_II": v["K_II"], "G": v["G"], "K_eq": v["K_eq"], "kink_deg": kink, "grew": did,
                         "T": v.get("T"), "stopped": v.get("stopped", "")})
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
    def __repr__(self) -> str:
        """A few lines: scene, criterion, da, the steps, the stop reason, the final tips (printing a result never
        dumps its arrays: `summary()` gives the table, `table` the DataFrame)."""
        lam = [s["load_factor"] for s in self.steps if s["load_factor"] is not None]
        K_Ic = "relative load factors" if self.K_Ic is None else f"K_Ic {self.K_Ic:g}"
        lines = [f"GrowthResult(scene={self.scene.name!r}, element={self.element!r}, criterion={self.criterion!r}, "
                 f"da={self.da:g}, {K_Ic})",
                 f"  {len(self.steps)} steps, {len(self.rows)} tip rows"
                 + (f"; load factor {lam[0]:.4g} at step 0, {lam[-1]:.4g} at the last" if lam else "; no load factor"),
                 f"  stopped: {self.stopped or '(running)'}"]
        if self.steps:
            tips = ", ".join(f"{t['crack']},{t['end']} at ({t['x']:.4g}, {t['y']:.4g})" for t in self.steps[-1]["tips"])
            lines.append(f"  tips of the last step: {tips or 'none'}")
        return "\n".join(lines)

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
    from ngcrack.planar.plots import element_displacements

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
