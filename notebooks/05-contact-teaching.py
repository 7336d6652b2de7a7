# %% [markdown]
# # 05 — What unilateral contact does
#
# **Question.** A crack's faces may separate but never interpenetrate (Signorini):
# $[u]\cdot\nu \ge 0$, $\sigma_\nu \le 0$, $\sigma_\nu\,[u]\cdot\nu = 0$, and, without friction,
# no shear on the faces. What does that change, compared with the two linear models a user
# might take instead — a **traction-free** crack (faces that ignore each other, so they may
# pass through each other) and a **bonded** crack (faces that slide but never separate)?
#
# **Experiment.** A square plate $(-2,2)^2$, clamped at the bottom, with an inclined crack
# through its middle, loaded on the top edge by a uniform traction: once pulling (tension),
# once pushing (compression). Both loads are solved with `crack_model="contact"`, `"free"`
# and `"bonded"`. The crack's tangent runs from its first point to its last; $\nu$ is the
# tangent turned by +90°. `NGCRACK_QUICK=1` uses a coarser mesh.

# %%
import os

import matplotlib.pyplot as plt
import numpy as np

import ngcrack as nc

SMOKE = os.environ.get("NGCRACK_QUICK") == "1"
MAXH = 0.25 if SMOKE else 0.08

PLATE = """
name = "inclined-crack"
[domain]
polygon = [[-2, -2], [2, -2], [2, 2], [-2, 2]]
labels = ["bottom", "right", "top", "left"]
[[crack]]
points = [[-0.8, -0.45], [0.8, 0.45]]
[material]
E = 1000.0
nu = 0.3
plane = "strain"
[boundary.bottom]
type = "clamped"
[boundary.top]
type = "traction"
value = [0.0, {p}]
"""
scenes = {"tension": nc.Scene.from_toml_string(PLATE.format(p=1.0)),
          "compression": nc.Scene.from_toml_string(PLATE.format(p=-1.0))}
MODELS = ("contact", "free", "bonded")
sols = {(load, m): nc.solve(sc, element="bdm", maxh=MAXH, crack_model=m) for load, sc in scenes.items() for m in MODELS}
print({k: s.ndof["total"] for k, s in sols.items()})

# %% [markdown]
# ## Along the crack: opening, sliding and the normal traction

# %%
fig, axes = plt.subplots(2, 3, figsize=(15, 7), sharex=True, constrained_layout=True)
styles = {"contact": ("k", "-", 2.2), "free": ("tab:red", "--", 1.4), "bonded": ("tab:blue", ":", 1.8)}
for row, load in zip(axes, scenes):
    for m in MODELS:
        p = sols[(load, m)].profiles[0]
        color, ls, lw = styles[m]
        for ax, y in zip(row, (p.normal_jump, p.tangential_jump, p.normal_stress)):
            ax.plot(p.s, y, ls, color=color, lw=lw, label=m)
    row[0].set_ylabel(f"{load}\n\nopening [u].nu")
    row[1].set_ylabel("sliding [u].t")
    row[2].set_ylabel("normal traction sigma_nu")
    for ax in row:
        ax.axhline(0, color="0.6", lw=0.6)
        ax.grid(True, lw=0.3)
for ax in axes[1]:
    ax.set_xlabel("s along the crack")
axes[0, 0].legend()
fig.suptitle("inclined crack, bdm: unilateral contact against a traction-free and a bonded crack")
plt.show()

# %% [markdown]
# ## The deformed plates (displacements magnified)
# Each triangle is drawn moved by its displacement, half transparent: where the material
# overlaps itself the blue is darker — interpenetration. The grey outline is the plate at
# rest.

# %%
from matplotlib.collections import PolyCollection

from ngcrack.planar.plots import element_displacements

fig, axes = plt.subplots(2, 3, figsize=(13, 8.8), constrained_layout=True)
for row, load in zip(axes, scenes):
    scale = 0.15 * 4 / max(np.abs(element_displacements(sols[(load, "contact")])[1]).max(), 1e-300)
    for ax, m in zip(row, MODELS):
        corners, disp = element_displacements(sols[(load, m)])
        ax.add_collection(PolyCollection(corners + scale * disp, facecolors="tab:blue", edgecolors="none",
                                         alpha=0.5))
        ax.plot(*np.r_[scenes[load].polygon, scenes[load].polygon[:1]].T, "-", color="0.6", lw=0.8)
        ax.set_title(f"{load}, {m} crack (displacement x{scale:.3g})")
        ax.set_aspect("equal")
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.autoscale_view()
fig.suptitle("tension opens the crack; compression closes it, and only the traction-free model lets the faces "
             "pass through each other (darker blue)")
plt.show()

# %% [markdown]
# ## Try it: the same plate with sliders
# The compressed plate in `nc.explore`: drag *load x* through zero to −1 (tension) and watch
# the crack open; switch *crack model* between `contact`, `free` and `bonded` and compare
# with the figures above; turn the *load angle*. A new load re-uses the factorization (a
# tenth of a second); the readouts give the contact length and the KKT residual.

# %%
nc.explore(scenes["compression"], maxh=MAXH)

# %% [markdown]
# ## Conclusion in numbers


# %%
def summary(sol):
    p = sol.profiles[0]
    return {"min opening": p.normal_jump.min(), "max opening": p.normal_jump.max(),
            "max |sliding|": np.abs(p.tangential_jump).max(), "max sigma_nu": p.normal_stress.max(),
            "min sigma_nu": p.normal_stress.min()}


def gap(a, b):
    """Largest difference of the crack jumps of two solutions, relative to the larger jump."""
    pa, pb = a.profiles[0], b.profiles[0]
    da = np.abs(np.r_[pa.normal_jump - pb.normal_jump, pa.tangential_jump - pb.tangential_jump]).max()
    return da / max(np.abs(np.r_[pa.normal_jump, pa.tangential_jump]).max(), 1e-300)


for (load, m), sol in sols.items():
    print(f"{load:11s} {m:7s} " + "  ".join(f"{k} {v: .2e}" for k, v in summary(sol).items()))
t_c, t_f, t_b = (sols[("tension", m)] for m in MODELS)
c_c, c_f, c_b = (sols[("compression", m)] for m in MODELS)
print(f"Tension: the crack opens (max opening {summary(t_c)['max opening']:.2e}); contact = free to "
      f"{gap(t_c, t_f):.0e}; the bonded crack cannot open and carries a tension of up to "
      f"{summary(t_b)['max sigma_nu']:.2f} across its faces.")
print(f"Compression: the crack closes (max opening {summary(c_c)['max opening']:.1e}) and slides "
      f"(max sliding {summary(c_c)['max |sliding|']:.2e}); contact = bonded to {gap(c_c, c_b):.0e}; "
      f"the traction-free faces interpenetrate by up to {-summary(c_f)['min opening']:.2e}.")

# %%
# The conclusions above, in numbers: this cell fails when one of them stops holding.
assert gap(t_c, t_f) < 1e-8 and gap(c_c, c_b) < 1e-8  # contact = free in tension, = bonded in compression
assert summary(c_c)["max opening"] <= 1e-8 * summary(t_c)["max opening"]  # closed under compression
assert summary(t_c)["min opening"] > 0 and summary(t_b)["max sigma_nu"] > 0.1  # open; bonded pulls
assert -summary(c_f)["min opening"] > 0.5 * summary(t_c)["max opening"]  # free faces interpenetrate
assert max(c_c.kkt.values()) < 1e-8 and max(t_c.kkt.values()) < 1e-8  # KKT at round-off
