"""HydrofracResult: the steps of a hydraulic-fracture run, the `hydrofrac --json` dictionary,
the tidy table and the animation (matplotlib and pillow, imported lazily)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: the step keys of the JSON contract, in order (each step also has "tips")
STEP_KEYS = ("step", "time", "half_length", "pressure", "opening_at_injection", "volume", "ndof", "time_s", "kkt")
#: the step keys the fluid model added (after STEP_KEYS; "profile" holds the fluid's s, opening, pressure)
FLUID_KEYS = ("K_m", "efficiency", "profile")
#: the tip keys of the JSON contract
TIP_KEYS = ("crack", "end", "x", "y", "K_I", "K_II", "kink_deg", "advanced")
#: a radial (3D) fracture's step keys besides those: the front's mean distance from the centre, the front's
#: K_I mean, least, largest and spread ((largest - least) / mean), the volume leaked so far
RADIAL_KEYS = ("radius", "front", "leaked")
#: a radial fracture's front points (its "tips", "end" the point's index) add these to TIP_KEYS
RADIAL_TIP_KEYS = ("z", "K_III")
#: the largest opening drawn in the animation, as a fraction of the crack's length
FACE_FRACTION = 0.08


@dataclass
class HydrofracResult:
    """What `nc.hydrofrac` returns.

    `steps`: one dict per step (STEP_KEYS, FLUID_KEYS, "tips" with TIP_KEYS, and "solves": the
    solves the step took); `table`: a pandas DataFrame, one row per step and tip; `frames`:
    per step the crack's points and its opening profile (mid points, normals, openings);
    `scenes[n]`: the scene of step n (its crack carrying the pressure field, not the value);
    `final`: the scene after the last growth; `stopped`: why the run ended.
    """

    scene: object
    element: str
    rate: float
    K_Ic: float
    da: float
    viscosity: float | None = None
    leakoff: float = 0.0
    K_m: float | None = None
    model: str = "toughness"
    schedule: object = None
    steps: list = field(default_factory=list)
    frames: list = field(default_factory=list)
    scenes: list = field(default_factory=list)
    stopped: str = ""
    final: object = None

    def __repr__(self) -> str:
        """A few lines: scene, model, rate and toughness, the steps' reach, the stop reason (printing a result
        never dumps its profiles: `table` is the DataFrame, `to_json_dict()` the record)."""
        fluid = "" if self.viscosity is None else f", viscosity={self.viscosity:g}, leakoff={self.leakoff:g}"
        K_m = "" if self.K_m is None else f", K_m={self.K_m:.3g}"
        lines = [f"HydrofracResult(scene={self.scene.name!r}, model={self.model!r}, rate={self.rate:g}, "
                 f"K_Ic={self.K_Ic:g}, da={self.da:g}{fluid}{K_m})"]
        if self.steps:
            first, last = self.steps[0], self.steps[-1]
            lines.append(f"  {len(self.steps)} steps: half-length {first['half_length']:.4g} -> {last['half_length']:.4g}, "
                         f"time {first['time']:.4g} -> {last['time']:.4g}, pressure {last['pressure']:.4g} at the last")
        lines.append(f"  stopped: {self.stopped or '(running)'}")
        return "\n".join(lines)

    def add(self, row: dict, frame: dict, scene) -> None:
        self.steps.append(row)
        self.frames.append(frame)
        self.scenes.append(scene)

    @property
    def table(self):
        """One row per step and tip: the step's values, then the tip's."""
        import pandas as pd

        radial = self.radial
        extra = ["solves", "K_m", "efficiency"] + (["radius", "leaked"] if radial else [])
        tip_keys = list(TIP_KEYS) + (list(RADIAL_TIP_KEYS) if radial else [])
        rows = [{**{k: s[k] for k in STEP_KEYS}, **{k: s[k] for k in extra}, **{k: t[k] for k in tip_keys}}
                for s in self.steps for t in s["tips"]]
        return pd.DataFrame(rows, columns=list(STEP_KEYS) + extra + tip_keys)

    @property
    def radial(self) -> bool:
        """A radial fracture: the scene is 3D."""
        return getattr(self.scene, "dimension", 2) == 3

    def to_json_dict(self) -> dict:
        """The `ngcrack hydrofrac --json` contract."""
        final = self.final if self.final is not None else self.scene
        radial = self.radial
        step_keys = STEP_KEYS + FLUID_KEYS + (RADIAL_KEYS if radial else ())
        tip_keys = TIP_KEYS + (RADIAL_TIP_KEYS if radial else ())
        return {
            "scene": self.scene.name, "element": self.element, "rate": self.rate, "K_Ic": self.K_Ic,
            "stopped": self.stopped,
            "steps": [{**{k: s[k] for k in step_keys}, "tips": [{k: t[k] for k in tip_keys} for t in s["tips"]],
                       **({"fractures": s["fractures"]} if "fractures" in s else {})}  # several cracks (multi.py)
                      for s in self.steps],
            # a radial fracture's disc: shape, center, normal, radius (its pressure left out: the last solve's trial)
            "cracks": [{k: v for k, v in c.to_dict().items() if k != "pressure"} if radial else
                       {"points": [list(p) for p in c.points]} for c in final.cracks],
            "model": self.model, "viscosity": self.viscosity, "leakoff": self.leakoff, "K_m": self.K_m,
            **({"dimension": 3} if radial else {}),
        }

    def animate(self, path, fps: int = 4):
        """A GIF: per step the crack's faces opened (exaggerated), time, pressure and half-length (a radial
        fracture: its section through the disc's centre, in the disc's plane coordinate and the opening)."""
        from matplotlib.animation import PillowWriter

        from ...planar.plots import new_figure

        pts = np.concatenate([np.asarray(c["points"]) for f in self.frames for c in f.get("all", [f])])
        span = float(np.max(np.ptp(pts, axis=0))) or 1.0
        wmax = max((max(c["opening"], default=0.0) for f in self.frames for c in f.get("all", [f])), default=0.0)
        scale = FACE_FRACTION * span / wmax if wmax > 0 else 0.0
        center = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
        fig, ax = new_figure(path, figsize=(6, 3.5), constrained_layout=True)
        writer = PillowWriter(fps=fps)
        with writer.saving(fig, str(path), dpi=fig.dpi):
            for row, frame in zip(self.steps, self.frames):
                ax.clear()
                for f in frame.get("all", [frame]):  # several fluid-driven cracks: each
                    ends = np.asarray(f["points"])[[0, -1]]
                    # the mid-point samples, closed at the crack's ends (zero opening there)
                    xy = np.vstack([ends[:1], np.column_stack([f["x"], f["y"]]), ends[1:]])
                    half = 0.5 * scale * np.asarray(f["opening"])[:, None] * np.asarray(f["normal"])
                    half = np.vstack([np.zeros((1, 2)), half, np.zeros((1, 2))])
                    for sign in (1, -1):
                        face = xy + sign * half
                        ax.plot(face[:, 0], face[:, 1], "-", color="tab:blue", lw=1.2)
                ax.set_xlim(center[0] - 0.6 * span, center[0] + 0.6 * span)
                ax.set_ylim(center[1] - 0.3 * span, center[1] + 0.3 * span)
                ax.set_aspect("equal")
                ax.set_title(f"step {row['step']}: t = {row['time']:.4g}, p = {row['pressure']:.4g}, "
                             f"l = {row['half_length']:.4g}", fontsize=9)
                ax.text(0.02, 0.03, f"opening x {scale:.3g}", transform=ax.transAxes, fontsize=8)
                writer.grab_frame()
        return path
