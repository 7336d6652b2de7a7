# %% [markdown]
# # 09 — Explore: what unilateral contact does, with sliders
#
# **Setting.** A straight crack of half-length $a = 1$ at 30° in the plate $[-5, 5]^2$
# (plane strain, $E = 1000$, $\nu = 0.3$), loaded on its top edge by a uniform traction
# $(0, p)$ with $p = -1$ (compression), held by rollers on the left and bottom edges
# (`nc.scenes.SCENE_FUNCTIONS["inclined-crack"]`). The crack faces obey Signorini's
# conditions without friction:
# $[u]\cdot\nu \ge 0$, $\sigma_\nu \le 0$, $\sigma_\nu\,[u]\cdot\nu = 0$, $\sigma_t = 0$.
#
# **The widget.** `nc.explore` solves the scene with the BDM element and redraws when a
# control moves. It redoes only what a change invalidates: a new load (the *load x*
# multiplier, the *load angle*) re-uses the mesh, the assembled matrix, its factorization
# and the Schur complement on the crack — a new right-hand side and a small QP, a tenth of
# a second; a new material re-assembles on the same mesh; moving the crack remeshes.
# The left panel shows the deformed plate (displacements magnified: gaps and offsets on
# the crack are its opening and sliding) coloured by $\sigma_\nu = (\sigma\nu)\cdot\nu$
# or von Mises; the right panel the crack profiles along the crack.
#
# `NGCRACK_QUICK=1` uses a coarser mesh.

# %%
import os

import matplotlib.pyplot as plt
import numpy as np

import ngcrack as nc

SMOKE = os.environ.get("NGCRACK_QUICK") == "1"
MAXH = 2.0 if SMOKE else None  # None: the teaching mesh (about 3e4 unknowns)

w = nc.explore("inclined-crack", maxh=MAXH)
w

# %% [markdown]
# ## Prompts for a student
#
# 1. **Compression.** With *load x* = 1 the top edge pushes. Is the crack open? Read the
#    *contact length* under the figure. Which way do the faces slide, and why does the
#    sliding look like half an ellipse?
# 2. **Reverse the load.** Drag *load x* to −1 (the top edge pulls). What happens to the
#    opening, to $\sigma_n$ on the faces, to the contact length? Is the answer for −1 the
#    negative of the answer for +1?
# 3. **Turn the load.** Move *load angle*: the traction on the top edge turns. At which
#    angle does the crack start to open? Where along the crack does it open first, and why
#    there?
# 4. **The crack model.** Switch *crack model* to `free` under compression: the faces pass
#    through each other (look at the deformed plate and the negative opening), and the KKT
#    residual under the figure says the contact conditions are violated. `bonded`?
# 5. **Poisson's ratio.** Move *nu* to 0.5 with `bdm`, then pick the displacement element
#    `h1p1`: the widget refuses (one line in red) and keeps the last good figure. Why can a
#    displacement element not take $\nu = 1/2$?
# 6. **Geometry.** Change the crack's *angle*: at which angle does the crack slide most
#    under compression? (The shear on the crack line is $p\sin\beta\cos\beta$.)
#
# The cells below do experiments 2 and 3 with `nc.Explorer`, the model behind the widget
# (`w.study`) without the widget, so that the numbers are on the page; `update(**changes)`
# is what a slider calls.

# %%
study = nc.Explorer("inclined-crack", maxh=MAXH)
loads = np.linspace(-1.0, 1.0, 9)
rows = []
for lam in loads:
    study.update(load=float(lam), load_angle=0.0)
    p = study.solution.crack_profiles()[0]
    r = study.readouts()
    rows.append((lam, p.normal_jump.max(), np.abs(p.tangential_jump).max(), p.normal_stress.min(),
                 r["contact_length"], r["latency_s"], ", ".join(study.redone)))
for lam, op, sl, sn, cl, t, what in rows:
    print(f"load x {lam:+.2f}: max opening {op:.2e}, max |sliding| {sl:.2e}, min sigma_n {sn:+.3f}, "
          f"contact length {cl:.2f}, {t:.3f} s ({what})")

# %% [markdown]
# ## Contact length and opening against the load

# %%
angles = np.arange(0.0, 181.0, 15.0)
contact = []
for ang in angles:
    study.update(load=1.0, load_angle=float(ang))
    contact.append(study.readouts()["contact_length"])
fig, axes = plt.subplots(1, 2, figsize=(11, 3.8), constrained_layout=True)
axes[0].plot([r[0] for r in rows], [r[1] for r in rows], "o-", label="max opening")
axes[0].plot([r[0] for r in rows], [r[2] for r in rows], "s--", label="max |sliding|")
axes[0].set_xlabel("load x (1: compression as given, -1: tension)")
axes[0].set_ylabel("crack jump")
axes[0].legend()
axes[0].grid(True, lw=0.3)
axes[1].plot(angles, contact, "o-")
axes[1].set_xlabel("load angle (degrees; 180 turns the compression into tension)")
axes[1].set_ylabel("contact length (crack length 2)")
axes[1].grid(True, lw=0.3)
fig.suptitle("one-sided: the crack answers compression and tension differently")
plt.show()

# %% [markdown]
# ## Conclusion
# Under compression the crack is closed over its whole length and only slides; under
# tension it opens and carries no traction. The response is linear on each side of the
# switch but not across it: the answer to a reversed load is not the reversed answer.

# %%
study.update(load=1.0, load_angle=0.0)
comp = study.solution.crack_profiles()[0]
closed = study.readouts()["contact_length"]
study.update(load=-1.0)
tens = study.solution.crack_profiles()[0]
# a linear (free) crack would answer -p with the reversed answer: opening -> -opening
reversal = np.abs(tens.tangential_jump + comp.tangential_jump).max() / np.abs(comp.tangential_jump).max()
print(f"Unilateral contact: closed over {closed:.2f} of 2.00 under compression (max opening "
      f"{comp.normal_jump.max():.1e}), open under tension (max opening {tens.normal_jump.max():.2e}, "
      f"contact length {study.readouts()['contact_length']:.2f}); reversing the load reverses the sliding "
      f"(to {reversal:.0%} of its size) but not the opening; {study.counts['factorize']} factorization(s) "
      f"for {study.counts['load'] + study.counts['factorize']} solves.")
