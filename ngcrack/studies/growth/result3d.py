"""SolidGrowthResult: the steps of a 3D growth run (loop3d.py) as a tidy table, the `grow --json`
dictionary and a figure of the front shapes over the steps."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...core.errors import InputError

#: the tidy table's columns, in order (one row per step and front point)
COLUMNS = ("step", "crack", "point", "x", "y", "z", "K_I", "K_II", "K_III", "G", "K_eq", "kink_deg", "closed",
           "advance", "load_factor", "crack_size", "ndof", "solves", "time_s", "kkt")


def _finite_or_none(x):
    return float(x) if x is not None and math.isfinite(x) else None


@dataclass
class SolidGrowthResult:
    """What `nc.grow` returns for a 3D scene.

    `table`: a pandas DataFrame, one row per step and front point (COLUMNS): K_I, K_II, K_III, G and K_eq
    at the scene's load (fronts3d.py), kink_deg the MTS kink a non-planar code would take there, advance the
    point's advance after this step (0 at the last step), load_factor the step's (quasi-static: K_Ic / max
    K_eq; fatigue: 1, the cycle's maximum), crack_size the crack's equivalent radius sqrt(area / pi), and
    with paris a `cycles` column (cumulative, 0 at step 0). `scenes[n]`: the scene of step n (its cracks
    `curve` cracks once grown); `fronts[n]`: per front the points of step n; `stopped`: why the run ended;
    `events`: (step, what) as cracks broke through a face or the run stopped; `transitions`: per embedded crack
    re-characterised as a surface crack (breakthrough.py) a dictionary: `step` (the first step of the surface
    crack), `crack`, `event` ("surface"), `face`, the embedded front's `ligament`, `half_height` and `half_length`,
    the surface crack's `depth` and `surface_half_length`, and `what`; `solution`: the last solve.
    """

    scene: object
    element: str
    da: float
    K_Ic: float | None
    paris: tuple | None = None
    R: float = 0.0
    criterion: str = "planar"
    steps: list = field(default_factory=list)
    rows: list = field(default_factory=list)
    scenes: list = field(default_factory=list)
    fronts: list = field(default_factory=list)
    events: list = field(default_factory=list)
    transitions: list = field(default_factory=list)
    stopped: str = ""
    solution: object = None

    def add_step(self, n, scene, sol, values, advances, load_factor, time_s, cycles=None, solves: int = 1) -> None:
        """One step's row: its fronts (with K_eq, kink_deg and the advance; a surface crack's with its `depth` and
        `half_length`), load factor, cost and cycles."""
        from .surface3d import depth_and_length, is_surface_crack

        ndof = int(sol.ndof["total"])
        kkt = {k: float(v) for k, v in sol.kkt.items()}
        fronts, shapes = [], []
        for k, (f, v) in enumerate(zip(sol.fronts, values)):
            adv = np.zeros(len(f.K_I)) if advances is None else np.asarray(advances[k], dtype=float)
            kink = np.degrees(v["kink"]) + 0.0
            size = math.sqrt(float(scene.cracks[f.crack].area) / math.pi)
            d = f.to_json_dict()
            d.update(K_eq=v["K_eq"].tolist(), K_drive=v["K_drive"].tolist(), kink_deg=kink.tolist(), advance=adv.tolist(), size=size)
            if is_surface_crack(scene.domain, scene.cracks[f.crack]):  # its depth a and half-length c on the surface
                d["depth"], d["half_length"] = depth_and_length(scene.domain, scene.cracks[f.crack])
            fronts.append(d)
            shapes.append(np.asarray(f.points, dtype=float))
            for j, p in enumerate(f.points):
                self.rows.append({"step": n, "crack": int(f.crack), "point": j, "x": float(p[0]), "y": float(p[1]),
                                  "z": float(p[2]), "K_I": float(f.K_I[j]), "K_II": float(f.K_II[j]),
                                  "K_III": float(f.K_III[j]), "G": float(f.G[j]), "K_eq": float(v["K_eq"][j]),
                                  "kink_deg": float(kink[j]), "closed": bool(f.closed[j]), "advance": float(adv[j]),
                                  "load_factor": _finite_or_none(load_factor), "crack_size": size, "ndof": ndof,
                                  "solves": int(solves), "time_s": float(time_s), "kkt": max(kkt.values(), default=0.0),
                                  **({} if cycles is None else {"cycles": float(cycles)})})
        self.steps.append({"step": n, "load_factor": _finite_or_none(load_factor), "ndof": ndof, "time_s": float(time_s),
                           "solves": int(solves), "kkt": kkt, "error_estimate": None, "tips": [], "force": {}, "displacement": {},
                           "fronts": fronts, **({} if cycles is None else {"cycles": float(cycles)})})
        self.scenes.append(scene)
        self.fronts.append(shapes)

    # ------------------------------------------------------------------ views
    @property
    def final_scene(self):
        return self.scenes[-1]

    @property
    def table(self):
        import pandas as pd

        fatigue = bool(self.rows) and "cycles" in self.rows[0]
        return pd.DataFrame(self.rows, columns=list(COLUMNS) + (["cycles"] if fatigue else []))

    def cycles(self) -> np.ndarray:
        """The cumulative cycles of every step (fatigue runs)."""
        return np.array([s.get("cycles", math.nan) for s in self.steps])

    def sizes(self, crack: int = 0) -> np.ndarray:
        """The equivalent radius sqrt(area / pi) of a crack at every step."""
        return np.array([math.sqrt(float(s.cracks[crack].area) / math.pi) for s in self.scenes])

    def depth_and_length(self, crack: int = 0) -> np.ndarray:
        """A surface crack's depth a and half-length c on the surface at every step ((steps, 2)): the semi-axes
        of its ellipse across and along the face its centre lies on, or a curve's extent measured on its front
        (studies.growth.surface3d); NaN at the steps
        before an embedded crack broke through a face."""
        from .surface3d import depth_and_length, is_surface_crack

        surface = [is_surface_crack(s.domain, s.cracks[crack]) for s in self.scenes]
        if not any(surface):
            raise InputError(f"crack {crack}: not a surface crack (a disc, an ellipse or a curve crossing a face), so it has no "
                             f"depth and surface length")
        return np.array([depth_and_length(s.domain, s.cracks[crack]) if on else (math.nan, math.nan)
                         for s, on in zip(self.scenes, surface)])

    def to_json_dict(self) -> dict:
        """The `ngcrack grow --json` dictionary of a 3D scene: the 2D grow keys, per step `fronts` (as `ngcrack
        solve`'s, with K_eq, kink_deg, advance and the crack's equivalent radius `size`) and, with paris, `cycles`;
        `events`: the embedded cracks re-characterised as surface cracks (`transitions`)."""
        fatigue = {} if self.paris is None else {"paris": list(self.paris), "R": self.R}
        return {"scene": self.scene.name, "element": self.element, "criterion": self.criterion, "da": float(self.da),
                "K_Ic": self.K_Ic, **fatigue, "stopped": self.stopped, "steps": self.steps,
                "cracks": [c.to_dict() for c in self.final_scene.cracks] if self.scenes else [],
                "events": [{k: (float(v) if isinstance(v, (float, np.floating)) else v) for k, v in e.items()}
                           for e in self.transitions]}

    def __repr__(self) -> str:
        K_Ic = "relative load factors" if self.K_Ic is None else f"K_Ic {self.K_Ic:g}"
        how = "quasi-static" if self.paris is None else f"Paris C {self.paris[0]:g}, m {self.paris[1]:g}, R {self.R:g}"
        return (f"SolidGrowthResult(scene={self.scene.name!r}, {how}, da={self.da:g}, {K_Ic})\n"
                f"  {len(self.steps)} steps; stopped: {self.stopped or '(running)'}")

    def summary(self) -> str:
        lines = [repr(self)]
        for s in self.steps:
            K = [max(f["K_drive"]) for f in s["fronts"]]
            kink = [max(abs(k) for k in f["kink_deg"]) for f in s["fronts"]]
            extra = f", cycles {s['cycles']:.4g}" if "cycles" in s else ""
            sizes = ", ".join(f"{f['size']:.4g}" for f in s["fronts"])
            lines.append(f"step {s['step']}: sizes {sizes}, max K_eq "
                         f"{max(K):.4g}, max |kink| {max(kink):.3g} deg{extra}")
        lines += [f"step {e['step']}: {e['what']}" for e in self.transitions]
        return "\n".join(lines)

    def plot(self, path=None, crack: int = 0):
        """The front shapes of a crack over the steps in its plane (coloured by step; a surface crack's part
        inside the body), beside the cycles (fatigue) or the load factor (quasi-static) against the crack's
        equivalent radius (a surface crack: its depth)."""
        from ngcrack.planar.plots import new_figure

        fig, (ax, ax2) = new_figure(path, ncols=2, figsize=(10, 4.5), constrained_layout=True)
        c0 = self.scene.cracks[crack]
        import matplotlib

        cmap = matplotlib.colormaps["viridis"]
        n = max(len(self.scenes) - 1, 1)
        for k, s in enumerate(self.scenes):
            q = s.cracks[crack].outline(512)
            p = np.r_[q, q[:1]] - c0.center
            u, v = p @ c0.e_a, p @ c0.e_b
            outside = s.domain.clearance(np.r_[q, q[:1]]) < 0  # a surface crack: its front, the part inside the body
            u, v = np.where(outside, np.nan, u), np.where(outside, np.nan, v)
            if outside.any():  # the arc runs through the outline's start: begin it at an outside point
                j = int(np.flatnonzero(outside)[0])
                u, v = np.roll(u[:-1], -j), np.roll(v[:-1], -j)
            ax.plot(u, v, color=cmap(k / n), lw=1.2, label=f"step {k}" if k in (0, n) else None)
        ax.set_aspect("equal")
        ax.set_xlabel("in-plane $e_a$")
        ax.set_ylabel("in-plane $e_b$")
        ax.set_title(f"crack[{crack}]'s front over {len(self.scenes)} steps")
        ax.legend(fontsize=8)
        from .surface3d import is_surface_crack

        surface = is_surface_crack(self.scene.domain, c0)
        broke = [e for e in self.transitions if e["crack"] == crack and e["event"] == "surface"]  # (not "through")
        L = self.depth_and_length(crack)[:, 0] if surface else self.sizes(crack)
        label = "depth $a$" if surface else r"equivalent radius $\sqrt{A/\pi}$"
        if broke:  # before and after a break-through: the depth below the face it broke through
            from ngcrack.solid.surface import face_distances

            face = broke[0]["face"]
            L = np.array([float(np.max(face_distances(s.domain, q[s.domain.clearance(q) > 0])[face]))
                          for s in self.scenes for q in [s.cracks[crack].outline(512)]])
            label = f"depth below face {face} (the surface crack's $a$)"
        if self.paris is not None:
            ax2.plot(L, self.cycles(), "o-", ms=3)
            ax2.set_ylabel("cycles $N$")
        else:
            ax2.plot(L, [s["load_factor"] for s in self.steps], "o-", ms=3)
            ax2.set_ylabel("load factor")
        ax2.set_xlabel(label)
        for e in broke:  # an embedded crack broke through a face
            if e["step"] < len(L):
                ax2.axvline(L[e["step"]], color="0.6", ls=":", lw=1)
        ax2.grid(alpha=0.3)
        if path is not None:
            fig.savefig(path, dpi=130)
        return fig

    def animate(self, path, fps: int = 4):
        raise InputError("animate: 3D growth has no animation; plot() draws the fronts over the steps")
