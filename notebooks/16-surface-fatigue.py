# %% [markdown]
# # 16 — Fatigue of a surface crack: a semi-ellipse grows towards a/c ≈ 0.8
#
# **Question.** A shallow semi-elliptical surface crack in a plate under cyclic tension: how does its
# shape change as it grows through the thickness, and how many cycles does it take? This is the case
# fatigue assessments (BS 7910, API 579, NASGRO) are built on, with Newman and Raju's stress-intensity
# equations and Paris's law as their reference.
#
# **Method.** `nc.grow(scene3d, da=..., steps=..., paris=(C, m))` on a scene whose crack is an ellipse
# centred on a face (its part inside the plate is the crack, its front the half-ellipse from surface
# to surface). Each step solves, takes $K$ along the front, and advances every front point in the
# crack's plane by $da\,(\Delta K_i/\Delta K_{max})^m$: the inner points normal to the front, the two
# surface points along the face. Near the surface $K$ falls in a boundary layer (the singularity is
# not the square root there), so the surface points grow, as the engineering codes grow them, with
# $K$ taken a little inside: at 5% of the front's length from the surface. The grown crack is the
# ellipse with the same centre and axes fitted to the advanced points, meshed afresh at the next step.
#
# **Reference.** Newman and Raju's $K$ at the deepest point $A$ and at the same 5% point $C$ integrated
# with the same Paris law, $dc/da = (K_C/K_A)^m$, $dN/da = 1/(C\,\Delta K_A^m)$
# (`ngcrack.studies.growth.newman_raju_growth.trajectory`).
#
# **Experiment.** The plate of the built-in `surface-crack` scene (thickness $t = 1.5$, width 10, unit
# tension), a crack of depth $a = 0.4$ and half-length $c = 1$ ($a/c = 0.4$), three steps of
# $da = 0.1$ (one with `NGCRACK_QUICK=1`), $C = 10^{-3}$, $m = 3$, a coarse mesh (`front_h` = 0.12, a
# step about 10 s of CPU).

# %%
import copy
import os

import matplotlib.pyplot as plt
import numpy as np

import ngcrack as nc
from ngcrack.studies.growth.newman_raju_growth import surface_K_any, trajectory

T, WIDTH_HALF = 1.5, 5.0
A0, C0, DA, C, M = 0.4, 1.0, 0.1, 1e-3, 3.0
STEPS = 1 if os.environ.get("NGCRACK_QUICK") == "1" else 3
d = copy.deepcopy(nc.scenes.load("surface-crack").to_dict())
d["name"] = "surface-fatigue"
d["crack"][0]["semi_axes"] = [C0, A0]  # along the face (x), then the depth
d["mesh"] = {"front_h": 0.12, "crack_h": 0.25, "maxh": 1.5}
scene = nc.Scene.from_dict(d)
res = nc.grow(scene, da=DA, steps=STEPS, paris=(C, M))
print(res.summary())

# %% [markdown]
# ## The fronts over the steps
# Left: the fronts in the crack's plane (the face at the bottom, the depth upwards); right: the
# cumulative cycles against the depth $a$. The crack deepens faster than it lengthens.

# %%
res.plot()  # the figure is returned, not displayed: the cell's value shows it once

# %% [markdown]
# ## $K$ along the front at every step, against Newman and Raju's
# $\varphi$ is their parametric angle from the surface ($90°$ the deepest point). The computed
# surface points carry the value a bump half-width inside (the first inner station); `K_drive` is
# what the growth uses: smoothed, and flat from the 5% point to the surface.

# %%
ac = res.depth_and_length()
fig, ax = plt.subplots(figsize=(7, 4), constrained_layout=True)
colors = plt.cm.viridis(np.linspace(0, 1, len(res.steps)))
for k, (step, (a, c)) in enumerate(zip(res.steps, ac)):
    f = step["fronts"][0]
    p = np.array(f["points"])
    phi = np.degrees(np.arctan2((T - p[:, 2]) / a, p[:, 0] / c))
    fine = np.linspace(0, 180, 181)
    nr = surface_K_any(1.0, a, c, T, WIDTH_HALF, np.radians(np.minimum(fine, 180 - fine)))
    ax.plot(fine, nr, "-", color=colors[k], lw=1, label=f"Newman-Raju, step {k}")
    ax.plot(phi, f["K_I"], "o", color=colors[k], ms=4)
    ax.plot(phi, f["K_drive"], "x", color=colors[k], ms=5)
ax.set_xlabel(r"$\varphi$ (degrees from the surface point $x = c$)")
ax.set_ylabel(r"$K_I$ (o computed, x the growth's drive)")
ax.legend(fontsize=7)
plt.show()

# %% [markdown]
# ## a/c against a/t
# The reference trajectories from $a/c = 0.4$ and from $a/c = 1.2$ converge towards 0.8-0.9; the
# computed steps follow the one from 0.4.

# %%
ref = trajectory(A0, C0, 1.2, T, WIDTH_HALF, C, M)
deep = trajectory(0.3, 0.25, 1.2, T, WIDTH_HALF, C, M)
shallow = trajectory(0.3, 0.75, 1.2, T, WIDTH_HALF, C, M)
fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
for tr, label in ((ref, "Newman-Raju, from this crack"), (shallow, "from a/c = 0.4 at a/t = 0.2"),
                  (deep, "from a/c = 1.2 at a/t = 0.2")):
    ax.plot(tr["a"] / T, tr["a"] / tr["c"], "-" if tr is ref else "--", label=label)
ax.plot(ac[:, 0] / T, ac[:, 0] / ac[:, 1], "ko", label="computed (nc.grow)")
ax.set_xlabel("a/t")
ax.set_ylabel("a/c")
ax.legend(fontsize=8)
plt.show()

# %% [markdown]
# ## Cycles, and what the command line writes
# `ngcrack grow surface-crack --da 0.1 --steps 3 --paris 1e-3 3 --json out.json` runs the same growth
# on the built-in scene; its JSON holds per step `cycles` and `fronts` (points from surface to surface,
# `K_I`, `K_eq`, `K_drive`, `advance`, `kink_deg`, and for a surface crack its `depth` and
# `half_length`): `res.to_json_dict()` here.

# %%
out = res.to_json_dict()
print("per step:", sorted(out["steps"][-1]), "\nper front:", sorted(out["steps"][-1]["fronts"][0]))
ratio = ac[:, 0] / ac[:, 1]
want = np.interp(ac[:, 0], ref["a"], ref["a"] / ref["c"])
N, N_ref = res.cycles(), np.interp(ac[:, 0], ref["a"], ref["N"])
K = [max(s["fronts"][0]["K_drive"]) for s in res.steps]
step1 = (N[1], (ac[1, 0] - ac[0, 0]) / (C * K[1] ** M), (ac[1, 0] - ac[0, 0]) / (C * K[0] ** M))
ends = np.array([[s["fronts"][0]["points"][0][2], s["fronts"][0]["points"][-1][2]] for s in res.steps])
for k in range(len(ac)):
    print(f"step {k}: a/t {ac[k, 0] / T:.3f}, a/c {ratio[k]:.3f} (Newman-Raju {want[k]:.3f}), cycles {N[k]:.1f} "
          f"(Newman-Raju {N_ref[k]:.1f})")

# %%
assert ratio[-1] > ratio[0] + 0.05, ratio  # the shallow crack deepens faster than it lengthens
assert np.max(np.abs(ratio / want - 1)) < 0.03, (ratio, want)  # on Newman and Raju's trajectory
assert np.max(np.abs(ends - T)) < 1e-9  # the surface points stay on the face
assert step1[1] < step1[0] < step1[2], step1  # the step's cycles between its two Paris bounds
assert np.all(np.abs(N[1:] / N_ref[1:] - 1) < 0.15), (N, N_ref)  # the coarse mesh's K_A is 3-4% low
print(f"Surface fatigue crack: a/c {ratio[0]:.2f} -> {ratio[-1]:.3f} within {np.max(np.abs(ratio / want - 1)):.1%} "
      f"of Newman-Raju's trajectory, {N[-1]:.0f} cycles ({N[-1] / N_ref[-1]:.3f} of theirs)")
