"""The load-displacement record of a growth run: what a test machine would have written.

At every step the load that grows the crack is lambda times the scene's load (lambda the
step's load factor): `step_loads` gives, per loaded label and point (and the pin and
roller points' reactions), the force lambda F and the mean displacement lambda u of its
segment or edges (`ngcrack.planar.load_points`), in the scene's units. The primary load (the
first force point, else the first traction label) gives the scalars of the table: the
force P = |lambda F| and the displacement delta = lambda F . u / |F| along it, so that
delta / P is the body's compliance C at that crack length. Irwin and Kies: the energy
release rate of a crack growing under the force P is G = P^2 / 2 dC/da (unit thickness),
which the growth tests hold against the interaction integral's G.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ngcrack.planar.load_points import load_displacement, load_point_values


@dataclass
class StepLoads:
    """One step's forces and displacements at the load factor (None where it is infinite)."""

    force: dict = field(default_factory=dict)  # label -> [Fx, Fy]
    displacement: dict = field(default_factory=dict)  # label -> [ux, uy]
    primary: str | None = None
    P: float | None = None
    delta: float | None = None
    compliance: float | None = None  # delta / P, independent of the load factor


def step_loads(sol, load_factor) -> StepLoads:
    """The forces and displacements of `sol` (solved at the scene's load) times `load_factor`."""
    values = load_point_values(sol)
    pd = load_displacement(values)
    primary = next(iter(pd), None)
    compliance = None
    if primary is not None and pd[primary][0] > 0:
        compliance = pd[primary][1] / pd[primary][0]
    if load_factor is None or not math.isfinite(load_factor):
        return StepLoads(primary=primary, compliance=compliance)
    lam = float(load_factor)
    force = {lab: [lam * v["force"][0], lam * v["force"][1]] for lab, v in values.items()}
    disp = {lab: [lam * v["displacement"][0], lam * v["displacement"][1]] for lab, v in values.items()}
    P = delta = None
    if primary is not None:
        P, delta = lam * pd[primary][0], lam * pd[primary][1]
    return StepLoads(force=force, displacement=disp, primary=primary, P=P, delta=delta, compliance=compliance)


def plot_load_displacement(result, ax=None, path=None):
    """The P-delta curve of the run's primary load: one point per step, the origin first
    (the linear loading up to the first growth), labelled by step."""
    import numpy as np

    from ...planar.plots import new_figure

    fig = None
    if ax is None:  # (to a file: a figure of its own, pyplot's backend untouched)
        fig, ax = new_figure(path, figsize=(6, 4.5), constrained_layout=True)
    table = result.table.groupby("step").first()
    P, d = table["force"].to_numpy(dtype=float), table["displacement"].to_numpy(dtype=float)
    ok = np.isfinite(P) & np.isfinite(d)
    if np.any(ok):
        ax.plot(np.r_[0.0, d[ok][:1]], np.r_[0.0, P[ok][:1]], "k:", lw=1)
        ax.plot(d[ok], P[ok], "o-", ms=3, label=result.primary_load or "load")
        for n, x, y in zip(table.index[ok], d[ok], P[ok]):
            ax.annotate(str(n), (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel(r"load-point displacement $\delta$")
    ax.set_ylabel("force $P$ at which the crack grows")
    ax.set_title("load-displacement" + ("" if result.K_Ic is not None else " (relative to step 0)"))
    ax.grid(alpha=0.3)
    if path is not None and fig is not None:
        fig.savefig(path, dpi=130)
    return fig if fig is not None else ax.figure
