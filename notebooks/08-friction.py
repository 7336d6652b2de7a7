# %% [markdown]
# # 08 — Coulomb friction on the crack faces
#
# **Question.** Closed cracks in rock, concrete or bone do not slide freely: their faces
# carry friction. With Coulomb's law, $|\sigma_t| \le \mu|\sigma_n|$, the faces stick where
# the inequality is strict and slip where it is an equality, $\sigma_t$ then pointing along
# the slip $[u]\cdot t$ (the friction traction on the $+$ face, $-\sigma_t$, opposes it).
# How does a closed crack's sliding change as $\mu$ grows, and where does a partly closed
# crack stick?
#
# **Experiment 1.** A straight crack of half-length $a = 1$ at $\beta = 30°$ in a large plate
# under remote compression $p = -1$ (`nc.scenes.inclined_crack`): on its faces
# $\sigma_n = p\cos^2\beta$ and $\tau = p \sin\beta\cos\beta$. In the infinite plate it slips
# everywhere with $[u]\cdot t = \frac{4(1-\nu^2)}{E}\,\mathrm{sign}(\tau)\,(|\tau| - \mu|\sigma_n|)\sqrt{a^2-s^2}$
# while $\mu < \tan\beta = 0.577$, and sticks everywhere (no sliding, the faces carry the
# uncracked shear $\tau$) for $\mu \ge \tan\beta$.
#
# **Experiment 2.** The paper's first scene (a cantilever resting on its lower half along a
# crack through the whole width): the open / stick / slip state along the crack for a range
# of $\mu$. The reduced crack problem (`sol.qp.problem`, a `CrackProblem`) does not depend on
# $\mu$: it is solved again for each coefficient without a new mesh or factorization.
#
# `NGCRACK_QUICK=1` uses coarser meshes and fewer coefficients.

# %%
import dataclasses
import math
import os

import matplotlib.pyplot as plt
import numpy as np

import ngcrack as nc
from ngcrack.core.friction import solve_crack_problem

SMOKE = os.environ.get("NGCRACK_QUICK") == "1"
ANGLE = 30.0
TAN_B = math.tan(math.radians(ANGLE))
MUS = [0.0, 0.3, 0.6] if SMOKE else [0.0, 0.15, 0.3, 0.45, 0.55, 0.6, 0.8]
MESH = dict(maxh=2.0, crack_h=0.1) if SMOKE else {}

scene = nc.scenes.inclined_crack(angle=ANGLE, load=-1.0)
cf = nc.scenes.inclined_closed_form(scene)
sols = {mu: nc.solve(scene.with_(friction=mu), element="bdm", **MESH) for mu in MUS}
print({mu: s.ndof["total"] for mu, s in sols.items()}, f"tan(beta) = {TAN_B:.3f}")


def closed_form(s_centre, mu):
    drive = max(abs(cf["tau"]) - mu * abs(cf["sigma_n"]), 0.0)
    return np.sign(cf["tau"]) * 4 * drive / cf["E_prime"] * np.sqrt(np.clip(1 - s_centre**2, 0, None))


# %% [markdown]
# ## Sliding and shear traction along the crack as $\mu$ grows through $\tan\beta$
# Lines: ngcrack (bdm); dashed: the closed form. $s$ is measured from the crack's centre.

# %%
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 4.5), constrained_layout=True)
colors = plt.cm.viridis(np.linspace(0, 0.9, len(MUS)))
errors = {}
for c, (mu, sol) in zip(colors, sols.items()):
    p = sol.crack_profiles()[0]
    s = p.s - 1.0
    exact = closed_form(s, mu)
    ax1.plot(s, p.tangential_jump, color=c, lw=2, label=f"mu = {mu:g}")
    ax1.plot(s, exact, "--", color="k", lw=0.8)
    ax2.plot(s, p.shear_stress, color=c, lw=2, label=f"mu = {mu:g}")
    scale = np.linalg.norm(closed_form(s, 0.0))
    errors[mu] = float(np.linalg.norm(p.tangential_jump - exact) / scale)
ax2.axhline(cf["tau"], color="k", ls=":", lw=1, label="uncracked shear tau")
ax1.set(xlabel="s (from the centre)", ylabel="sliding [u].t", title="sliding")
ax2.set(xlabel="s (from the centre)", ylabel="shear traction (sigma nu).t", title="shear traction on the faces")
ax1.legend(fontsize=8)
ax2.legend(fontsize=8)
for ax in (ax1, ax2):
    ax.grid(True, lw=0.3)
plt.show()
print("sliding error against the closed form (relative to the frictionless slide):",
      {mu: f"{e:.2%}" for mu, e in errors.items()})

# %% [markdown]
# ## The crack's centre: sliding against $\mu$
# One reduced problem, re-solved for many coefficients: the centre's sliding falls linearly
# to zero at $\tan\beta$ and stays there.

# %%
base = sols[MUS[1]]
problem = base.qp.problem
mus = np.linspace(0.0, 1.0, 11 if SMOKE else 41)
centre = np.argmin(np.abs(problem.s - 1.0))
iterations = []
slide = []
for mu in mus:
    res = solve_crack_problem(dataclasses.replace(problem, mu=np.full_like(problem.mu, mu)))
    k = int(np.flatnonzero(res.t_point == centre)[0])
    slide.append(res.wt[k])
    iterations.append(res.coulomb_iterations)
fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
ax.plot(mus, slide, "o", ms=4, label="ngcrack (bdm), reduced problem re-solved")
ax.plot(mus, [closed_form(np.array([problem.s[centre] - 1.0]), mu)[0] for mu in mus], "k-", lw=1, label="closed form")
ax.axvline(TAN_B, color="0.5", ls=":", label="tan(beta)")
ax.set(xlabel="mu", ylabel="[u].t at the centre")
ax.legend()
ax.grid(True, lw=0.3)
plt.show()
print("Coulomb iterations per coefficient:", dict(zip(np.round(mus, 3).tolist(), iterations)))

# %% [markdown]
# ## Stick-slip map of paper-1
# Each row is one coefficient, each column a constraint point along the crack (the end
# points of its edges, bdm): open (the faces apart), stick or slip.

# %%
paper = nc.scenes.load("paper-1").with_(friction=1.0)
psol = nc.solve(paper, element="bdm", maxh=0.2 if SMOKE else 0.05)
pp = psol.qp.problem
map_mus = np.linspace(0.0, 3.0, 7 if SMOKE else 31)
order = np.argsort(pp.s)
STATE_CODE = {"open": 0, "stick": 1, "slip": 2}
state_map = np.zeros((len(map_mus), pp.m))
first_stick = None
for i, mu in enumerate(map_mus):
    res = solve_crack_problem(dataclasses.replace(pp, mu=np.full_like(pp.mu, mu)))
    codes = np.array([STATE_CODE[st] for st in res.point_states()])
    state_map[i] = codes[order]
    if first_stick is None and np.any(codes == 1):
        first_stick = mu
fig, ax = plt.subplots(figsize=(9, 4), constrained_layout=True)
cmap = plt.matplotlib.colors.ListedColormap(["#dddddd", "tab:blue", "tab:orange"])
ax.pcolormesh(pp.s[order], map_mus, state_map, cmap=cmap, vmin=-0.5, vmax=2.5, shading="nearest")
ax.set(xlabel="s along the crack (from x = 0)", ylabel="mu", title="paper-1, bdm: open (grey), stick (blue), slip (orange)")
plt.show()
print(f"paper-1: {psol.ndof['total']} dofs; stick appears from mu = {first_stick}; "
      f"Coulomb residual of the mu = 1 solve {psol.kkt['friction']:.1e}")

# %%
slip_err = max(e for mu, e in errors.items() if mu < TAN_B)
stick_slide = max(np.max(np.abs(s.crack_profiles()[0].tangential_jump)) for mu, s in sols.items() if mu >= TAN_B)
print(f"Friction: the inclined crack slips below tan(beta) = {TAN_B:.3f} within {slip_err:.2%} of the closed form "
      f"and sticks above it (largest sliding {stick_slide:.1e}); paper-1 sticks from mu = {first_stick}")

# %%
# The conclusions above, in numbers: this cell fails when one of them stops holding.
assert slip_err < 0.02  # slips below tan(beta) as the closed form says
assert stick_slide < 1e-10  # and sticks above it
assert first_stick is not None and 0 < first_stick <= 3.0
assert psol.kkt["friction"] < 1e-8  # the discrete Coulomb law holds at round-off
