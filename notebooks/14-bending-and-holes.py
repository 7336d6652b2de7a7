# %% [markdown]
# # 14 — Bending specimens: point supports, the load-displacement record, T and holes
#
# **Question.** A fracture test is a beam on two supports and a load: the machine records the
# force $P$ and the load-point displacement $\delta$ while the crack grows. Can ngcrack model the
# specimen as the laboratory sets it up, give the record the machine writes, and say where a
# crack goes when holes lie near its path?
#
# **Method.** Loads and supports at points (`[[point]]` in a scene file, `nc.PointCondition` in
# Python): a `force` is a total force spread over a short segment of the boundary, a `pin` holds
# its segment's mean displacement (the beam turns freely about it), a `roller` the mean normal
# displacement. `nc.grow` records, at every step, the force at which the crack grows and the
# displacement of every loaded point (`res.table["force"]`, `res.table["displacement"]`), and the
# T-stress at every tip (`res.table["T"]`, an interaction integral with a point-force auxiliary
# field). Checks in numbers: the reactions balance the load; $K_I$ of the single-edge-notched beam
# against the handbook; the energy release rate against Irwin and Kies' $G = \frac{P^2}{2}\frac{dC}{da}$
# from the recorded compliance $C = \delta / P$.
#
# **Experiments.** (a) the single-edge-notched beam in three-point bending (the built-in scene
# `three-point-bend`, span $S = 4W$, $a/W = 0.4$): reactions, $K_I$, $T$; (b) its crack grown
# straight up, the $P$-$\delta$ curve and Irwin-Kies; (c) the three-hole beam (a beam with an offset
# notch and a column of three holes between the notch and the load, after the experiments of
# Bittencourt, Wawrzynek, Ingraffea and Sousa 1996): the crack grows into a hole, a new crack
# leaves the hole and grows on until the beam is cut through; (d) a mixed-mode semi-circular bend
# specimen grown by MTS and by the generalized MTS with the T-stress.
#
# `NGCRACK_QUICK=1` uses coarser meshes and fewer steps.

# %%
import math
import os

import matplotlib.pyplot as plt
import numpy as np
import shapely

import ngcrack as nc
from ngcrack.planar.load_points import load_point_values
from ngcrack.studies.growth.records import plot_load_displacement

SMOKE = os.environ.get("NGCRACK_QUICK") == "1"
BEND_MESH = {"maxh": 0.3, "tip_h": 0.01} if SMOKE else {"maxh": 0.2, "tip_h": 0.01}
BEND_STEPS = 2 if SMOKE else 6
HOLE_MESH = {"maxh": 1.2, "tip_h": 0.05, "crack_h": 0.2} if SMOKE else {"maxh": 0.8, "tip_h": 0.02, "crack_h": 0.1}
HOLE_STEPS, HOLE_DA = (3, 0.5) if SMOKE else (40, 0.3)

# %% [markdown]
# ## (a) The single-edge-notched beam: reactions, $K_I$ and $T$
# A beam $9 \times 2$ ($W = 2$) on a pin at $x = 0.5$ and a roller at $x = 8.5$, a force $P = 1$ at the
# top of its midspan, an edge crack $a = 0.8$ up from the bottom. The beam is statically
# determinate: each support carries $P/2$. Srawley's fit of the handbook (Tada, Paris, Irwin):
# $K_I = \frac{PS}{W^{3/2}} f(a/W)$ with
# $f(\alpha) = \frac{3\sqrt\alpha\,[1.99 - \alpha(1-\alpha)(2.15 - 3.93\alpha + 2.7\alpha^2)]}{2(1+2\alpha)(1-\alpha)^{3/2}}$
# (0.5% for $S = 4W$).

# %%
bend = nc.scenes.load("three-point-bend")
sol = nc.solve(bend, **BEND_MESH)
values = load_point_values(sol)
for label, v in values.items():
    print(f"{label:>14} ({v['type']:>6}): force ({v['force'][0]: .6f}, {v['force'][1]: .6f}), "
          f"mean displacement ({v['displacement'][0]: .3e}, {v['displacement'][1]: .3e})")
imbalance = np.abs(np.sum([v["force"] for v in values.values()], axis=0)).max()


def srawley(alpha: float) -> float:
    return (3 * math.sqrt(alpha) * (1.99 - alpha * (1 - alpha) * (2.15 - 3.93 * alpha + 2.7 * alpha**2))
            / (2 * (1 + 2 * alpha) * (1 - alpha) ** 1.5))


S, W, a = 8.0, 2.0, 0.8
tip = sol.tips[0]
K_hb = 1.0 * S / W**1.5 * srawley(a / W)
beta = tip.T * math.sqrt(math.pi * a) / tip.K_I
print(f"K_I = {tip.K_I:.4f} against the handbook's {K_hb:.4f} ({tip.K_I / K_hb - 1:+.2%}); "
      f"T = {tip.T:.4f}, biaxiality beta = T sqrt(pi a) / K_I = {beta:.3f}; forces balance to {imbalance:.1e}")
assert imbalance < 1e-9 and abs(tip.K_I / K_hb - 1) < 0.01

# %% [markdown]
# ## (b) Growth to a deep crack: the $P$-$\delta$ record and Irwin-Kies
# With a toughness $K_{Ic} = 2$ the crack grows straight up (mode I, $T < 0$: the straight path is
# stable), each step at the force $P = \lambda \cdot 1$ that brings $K_I$ to $K_{Ic}$. The record falls:
# the deeper the crack, the smaller the force that grows it, and the softer the beam ($C = \delta/P$
# grows). Irwin and
# Kies: $G = \frac{P^2}{2}\frac{dC}{da}$, here $G = K_{Ic}^2/E'$ at every step, so
# $C(a_{n+2}) - C(a_n) = \frac{2 K_{Ic}^2}{E'} \int \frac{da}{P^2}$ (Simpson's rule over two steps).

# %%
K_Ic, DA = 2.0, 0.1
res = nc.grow(bend, da=DA, steps=BEND_STEPS, K_Ic=K_Ic, criterion="mts", frames=False, **BEND_MESH)
df = res.table
print(df[["step", "y", "K_I", "T", "load_factor", "force", "displacement", "compliance"]].to_string(index=False))
mat = bend.material
e_prime = mat.E / (1 - mat.nu**2)
P, C, a_n = df["force"].to_numpy(), df["compliance"].to_numpy(), df["y"].to_numpy()
errors = []
for n in range(0, len(df) - 2, 2):
    simpson = 2 * K_Ic**2 / e_prime * DA / 3 * (1 / P[n] ** 2 + 4 / P[n + 1] ** 2 + 1 / P[n + 2] ** 2)
    errors.append(simpson / (C[n + 2] - C[n]) - 1)
print("Irwin-Kies, 2 int G / P^2 da against the compliance's change: " + ", ".join(f"{e:+.3%}" for e in errors))
fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.2), constrained_layout=True)
plot_load_displacement(res, ax=ax)  # the same curve alone: res.plot("pd.png", curve="P-delta")
ax.set_title("three-point bend: load-displacement")
bx.plot(a_n / W, C, "o-")
bx.set_xlabel("a / W")
bx.set_ylabel(r"compliance $C = \delta / P$")
bx.grid(alpha=0.3)
plt.show()
assert np.all(np.diff(P) < 0) and np.all(np.diff(C) > 0) and max(map(abs, errors)) < 0.02

# %% [markdown]
# ## (c) The three-hole beam
# A beam $20 \times 8$ (plane stress, $E = 1000$, $\nu = 0.37$) on a pin at $x = 1$ and a roller at
# $x = 19$ (span 18), a force at the top of its midspan, a notch of depth 1 at $x = 4$ (6 from the
# midspan) and a column of three holes of radius 0.25 at $x = 6$, $y = 2.75, 4.75, 6.75$: the
# dimensions (in inches) of the drilled-beam experiment with the notch 6 in from the midspan, as
# the published models of it give them. The notch lies in the shear span: its tip sees $K_{II}$ and
# kinks towards the load; the holes' stress concentration pulls the path. A tip that reaches a hole
# joins it (the ligament is cut); with `at_hole=da` a new crack of length da leaves the hole where
# the hoop stress of the joined beam is largest and grows on, until the beam is cut through.

# %%
def three_hole_beam(notch_x: float = 4.0) -> nc.Scene:
    return nc.Scene(
        name="three-hole-beam",
        description=f"beam 20 x 8 on a pin and a roller, force at midspan, notch at x = {notch_x:g}, three holes at x = 6",
        polygon=[[0, 0], [20, 0], [20, 8], [0, 8]], labels=["bottom", "right", "top", "left"],
        material={"E": 1000.0, "nu": 0.37, "plane": "stress"},
        holes=[{"center": [6.0, y], "radius": 0.25, "label": f"hole{k + 1}"} for k, y in enumerate((2.75, 4.75, 6.75))],
        cracks=[[[notch_x, 0.0], [notch_x, 1.0]]],
        points=[nc.PointCondition(at=(1.0, 0.0), type="pin", width=0.2),
                nc.PointCondition(at=(19.0, 0.0), type="roller", width=0.2),
                nc.PointCondition(at=(10.0, 8.0), type="force", value=(0.0, -1.0), width=0.2, label="load")])


beam = three_hole_beam()
holes = beam.with_(maxh=HOLE_MESH["maxh"])
run = nc.grow(holes, da=HOLE_DA, steps=HOLE_STEPS, K_Ic=1.0, frames=False, at_hole=HOLE_DA, **HOLE_MESH)
print(run.stopped)
for n, _tip, what in run.events:
    print(f"step {n}: {what}")
print(run.table[["step", "crack", "x", "y", "K_I", "K_II", "kink_deg", "force"]].to_string(index=False))
paths = shapely.MultiLineString([p for p in run.paths if len(p) > 1])
approach = {h.labels[0]: paths.distance(shapely.Point(h.center)) - h.radius for h in beam.holes}
print("closest approach of the paths to each hole: " + ", ".join(f"{k} {max(v, 0.0):.3f}" for k, v in approach.items()))

fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 4.5), constrained_layout=True, gridspec_kw={"width_ratios": [2, 1]})
ax.plot(*np.asarray(beam.polygon + (beam.polygon[0],)).T, "k-", lw=1)
for h in beam.holes:
    ax.add_patch(plt.Circle(h.center, h.radius, fill=False, color="k"))
for pc in beam.points:
    ax.plot(*pc.at, "v" if pc.type == "force" else "^", color="C3", ms=9)
for k, p in enumerate(run.paths):
    ax.plot(*p.T, "o-", ms=3, color=f"C{k}", label="from the notch" if k == 0 else "from the hole")
ax.set_aspect("equal")
ax.set_xlim(0, 20)
ax.legend(fontsize=8)
ax.set_title(f"three-hole beam: the paths ({len(run.steps)} steps)")
plot_load_displacement(run, ax=bx)
plt.show()
nearest = min(approach, key=approach.get)
steps_done = int(run.table["step"].max())
if not SMOKE:  # into the middle hole, out of it towards the load, and through the top
    assert nearest == "hole2" and approach["hole2"] < 1e-9 and approach["hole1"] > 0.5
    assert run.stopped.startswith("cut through") and len(run.paths) == 2

# %% [markdown]
# ## (d) A mixed-mode semi-circular bend specimen: MTS against the generalized MTS
# A half disc of radius $R = 50$ (mm; PMMA-like $E = 2940$ MPa, $\nu = 0.38$, $K_{Ic} = 62$ MPa$\sqrt{\rm mm}$),
# on a pin and a roller at $x = \pm 21.5$, a force at the top of its arc, a crack of length 15 from
# the centre of its flat edge inclined $30°$ from the vertical (ngcrack's own version of the
# specimen used in mixed-mode tests). Its tip sees $K_I$, $K_{II}$ and a positive $T$: the
# generalized MTS criterion with a critical distance $r_c = 0.1$ mm (a material length) kinks
# it further than MTS, which takes the singular field alone.

# %%
SCB_R, SCB_N = 50.0, 61  # an arc of 61 chords; the top of the arc is the middle of a chord
scb_beta = math.radians(30.0)
scb = nc.Scene(
    name="semi-circular-bend", description="SCB specimen R = 50, crack 15 at 30 degrees, supports at +-21.5",
    polygon=[(SCB_R * math.cos(k * math.pi / SCB_N), SCB_R * math.sin(k * math.pi / SCB_N)) for k in range(SCB_N + 1)],
    labels=["arc"] * SCB_N + ["flat"], material={"E": 2940.0, "nu": 0.38, "plane": "strain"},
    cracks=[[[0.0, 0.0], [15.0 * math.sin(scb_beta), 15.0 * math.cos(scb_beta)]]],
    points=[nc.PointCondition(at=(-21.5, 0.0), type="pin", width=1.0),
            nc.PointCondition(at=(21.5, 0.0), type="roller", width=1.0),
            nc.PointCondition(at=(0.0, SCB_R * math.cos(math.pi / (2 * SCB_N))), value=(0.0, -1.0), width=1.0,
                              label="load")])
SCB_MESH = {"maxh": 8.0, "tip_h": 0.2, "crack_h": 1.0} if SMOKE else {"maxh": 5.0, "tip_h": 0.1, "crack_h": 0.5}
SCB_STEPS = 2 if SMOKE else 6
scb_runs = {c: nc.grow(scb, da=2.5, steps=SCB_STEPS, K_Ic=62.0, criterion=c, frames=False,
                       **({"r_c": 0.1} if c == "gmts" else {}), **SCB_MESH) for c in ("mts", "gmts")}
first = {c: r.table.iloc[0] for c, r in scb_runs.items()}
print(f"initial tip: K_I = {first['mts'].K_I:.4f}, K_II = {first['mts'].K_II:.4f}, T = {first['mts']['T']:.4f} "
      f"(per unit force)")
for c, r in scb_runs.items():
    print(f"{c:>5}: first kink {first[c].kink_deg:.2f} degrees, force at initiation {first[c].force:.1f} N/mm, "
          f"kinks after it " + ", ".join(f"{k:.1f}" for k in r.table.kink_deg[1:]))
gap = shapely.LineString(scb_runs["mts"].paths[0]).hausdorff_distance(shapely.LineString(scb_runs["gmts"].paths[0]))
print(f"the two paths lie within {gap:.3f} mm of each other")
fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.5), constrained_layout=True)
ax.plot(*np.asarray(scb.polygon + (scb.polygon[0],)).T, "k-", lw=1)
for c, r in scb_runs.items():
    ax.plot(*r.paths[0].T, "o-", ms=2, label=c)
    plot_load_displacement(r, ax=bx)
ax.set_aspect("equal")
ax.legend()
ax.set_title("semi-circular bend: paths")
bx.legend([bx.lines[1], bx.lines[3]], ["mts", "gmts"])
plt.show()
assert first["mts"]["T"] > 0 and first["gmts"].kink_deg > first["mts"].kink_deg > 0

# %%
print(f"Bending and holes: the reactions balance the load to {imbalance:.0e}; K_I of the notched beam "
      f"{tip.K_I / K_hb - 1:+.2%} from the handbook, T = {tip.T:.3f}; Irwin-Kies holds to "
      f"{max(map(abs, errors)):.2%} along {len(df) - 1} steps; in the three-hole beam the crack reaches {nearest} "
      f"(closest approach {max(approach[nearest], 0.0):.3f} after {steps_done} steps) while the force falls from "
      f"{run.table['force'].iloc[0]:.3f} to {run.table['force'].dropna().iloc[-1]:.3f}; in the semi-circular bend "
      f"specimen (T > 0) the generalized MTS kinks {first['gmts'].kink_deg - first['mts'].kink_deg:.1f} degrees further "
      f"than MTS.")
