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
# control moves. It redoes only what a change invalidates: a new load (the *load factor*,
# which multiplies every load of the scene: +1 as given, here compression; −1 reversed,
# tension; and the *load angle*) re-uses the mesh, the assembled matrix, its
# factorization and the Schur complement on the crack — a new right-hand side and a small
# QP, a tenth of a second; a new material re-assembles on the same mesh; moving the crack
# remeshes. Every slider has a box for a typed value; a value out of range is refused
# (one red line names the control and its range) and the slider keeps the model's value.
#
# The figure: the deformed plate (displacements magnified by the factor in the title),
# coloured by $\sigma_{\nu\nu} = (\sigma\nu)\cdot\nu$ or von Mises, with the two crack
# faces drawn as two curves (blue: the + face, into which $\nu$ points; orange: the −
# face), each moved by its own side's displacement — an opening is a gap between them,
# an interpenetration an overlap shaded red —, the load arrows, the supports (circles:
# rollers), $\nu$ and $t$ on the crack; a zoom on the crack; the crack profiles along the
# crack; the tips' $K_I$, $K_{II}$ by name. While only the load changes the scales are
# held (*scales*: hold, or fit every frame), so that two loads compare on one scale.
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
# 1. **Compression.** With *load factor* = 1 the top edge pushes. Is the crack open? Read the
#    *contact length* under the figure. Which way do the faces slide, and why does the
#    sliding look like half an ellipse?
# 2. **Reverse the load.** Drag *load factor* to −1 (the top edge pulls). What happens to the
#    opening, to $\sigma_n$ on the faces, to the contact length? Is the answer for −1 the
#    negative of the answer for +1?
# 3. **Turn the load.** Move *load angle*: the traction on the top edge turns. At which
#    angle does the crack start to open? Where along the crack does it open first, and why
#    there?
# 4. **The crack model.** Switch *crack model* to `free` under compression: the faces pass
#    through each other (the zoom shows the two faces overlapping, the opening is
#    negative), and the KKT residual under the figure says the contact conditions are
#    violated. `bonded` glues the faces: why does it look like `contact` under compression
#    but not under tension?
# 5. **Poisson's ratio.** Move *nu* to 0.5 with `bdm`, then pick the displacement element
#    `h1p1`: the widget refuses (one sentence in red saying what to change), puts the
#    element menu back on `bdm` and keeps the last good figure. Why can a
#    displacement element not take $\nu = 1/2$? Type 0.7 into the box next to *nu*: why
#    is it refused?
# 6. **Geometry.** Change the *crack angle*: at which angle does the crack slide most
#    under compression? (The shear on the crack line is $p\sin\beta\cos\beta$.) Set
#    *scales* to *hold always* first, so that 30° and 60° are drawn on one colour scale:
#    how does $\sigma_n$ on the faces change ($-p\cos^2\beta$)?
# 7. **Stiffness.** With *scales* on *hold always*, multiply *E* by 10: what happens to
#    the deformation, and to the stresses? Why?
#
# The cells below do experiments 2 and 3 with `nc.Explorer`, the model behind the widget
# (`w.model`) without the widget, so that the numbers are on the page; `update(**changes)`
# is what a slider calls.

# %%
model = nc.Explorer("inclined-crack", maxh=MAXH)
loads = np.linspace(-1.0, 1.0, 9)
rows = []
for lam in loads:
    model.update(load=float(lam), load_angle=0.0)
    p = model.solution.crack_profiles()[0]
    r = model.readouts()
    rows.append((lam, p.normal_jump.max(), np.abs(p.tangential_jump).max(), p.normal_stress.min(),
                 r["contact_length"], r["latency_s"], ", ".join(model.redone)))
for lam, op, sl, sn, cl, t, what in rows:
    print(f"load factor {lam:+.2f}: max opening {op:.2e}, max |sliding| {sl:.2e}, min sigma_n {sn:+.3f}, "
          f"contact length {cl:.2f}, {t:.3f} s ({what})")

# %% [markdown]
# ## Contact length and opening against the load

# %%
angles = np.arange(0.0, 181.0, 15.0)
contact = []
for ang in angles:
    model.update(load=1.0, load_angle=float(ang))
    contact.append(model.readouts()["contact_length"])
fig, axes = plt.subplots(1, 2, figsize=(11, 3.8), constrained_layout=True)
axes[0].plot([r[0] for r in rows], [r[1] for r in rows], "o-", label="max opening")
axes[0].plot([r[0] for r in rows], [r[2] for r in rows], "s--", label="max |sliding|")
axes[0].set_xlabel("load factor (1: compression as given, -1: tension)")
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
model.update(load=1.0, load_angle=0.0)
comp = model.solution.crack_profiles()[0]
closed = model.readouts()["contact_length"]
model.update(load=-1.0)
tens = model.solution.crack_profiles()[0]
# a linear (free) crack would answer -p with the reversed answer: opening -> -opening
reversal = np.abs(tens.tangential_jump + comp.tangential_jump).max() / np.abs(comp.tangential_jump).max()
print(f"Unilateral contact: closed over {closed:.2f} of 2.00 under compression (max opening "
      f"{comp.normal_jump.max():.1e}), open under tension (max opening {tens.normal_jump.max():.2e}, "
      f"contact length {model.readouts()['contact_length']:.2f}); reversing the load reverses the sliding "
      f"(to {reversal:.0%} of its size) but not the opening; {model.counts['factorize']} factorization(s) "
      f"for {model.counts['load'] + model.counts['factorize']} solves.")

# %%
# The conclusions above, in numbers: this cell fails when one of them stops holding.
assert abs(closed - 2.0) < 1e-3 and comp.normal_jump.max() <= 1e-12  # closed over the whole crack
assert tens.normal_jump.max() > 0 and model.readouts()["contact_length"] < 1e-9  # open under tension
assert reversal < 0.05  # the sliding reverses with the load
assert model.counts["factorize"] == 1  # one factorization for every load
