# %% [markdown]
# # 06 — Stiff and extreme cases: locking, $\nu = 1/2$, scale
#
# **Question.** Do the mixed elements stay accurate and their answers exact in the ways
# linear elasticity demands, where a user would expect trouble: $\nu \to 1/2$ (and
# $\nu = 1/2$ itself), Young's moduli from $10^{-3}$ to $10^{12}$, loads from $10^{-9}$ to
# $10^9$, bodies from a millimetre to a kilometre, a 1:100 strip and a crack tip meshed at
# $10^{-4}$ of the mesh size? And what does a displacement element do instead?
#
# **Method.** `ngcrack.studies.stability` (the same code as `ngcrack stability`): a manufactured
# solution exact for every $\nu$, Griffith's closed form, and paper-2 against BDM on a finer
# mesh, for every element; then paper-1 rescaled, checking that jumps scale with
# load · size / E and stresses with load. `NGCRACK_QUICK=1` runs a reduced set.

# %%
import os
import warnings

from ngcrack import CoarseMeshWarning
from ngcrack.studies import stability

# Some meshes here put under 3 triangles across the beam's 0.5-thick halves, where peers and
# h1p1 are known to be more than 20% off: ngcrack warns about each such solve
# (CoarseMeshWarning, see the size-guard guide); the errors below show it, so the warnings are
# silenced here.
warnings.simplefilter("ignore", CoarseMeshWarning)

SMOKE = os.environ.get("NGCRACK_QUICK") == "1"
NUS = (0.3, 0.4999, 0.5) if SMOKE else stability.NUS
locking = stability.locking_table(nus=NUS, maxh=0.2 if SMOKE else 0.1, paper_maxh=0.2 if SMOKE else 0.1,
                                  griffith_mesh=dict(maxh=2.0, crack_h=0.1, tip_h=0.01) if SMOKE else None)
locking[["case", "element", "nu", "error_u", "error_sigma", "error_opening"]].round(4)

# %% [markdown]
# ## Error against $1/2 - \nu$
# The displacement baselines are refused at $\nu = 1/2$ (no finite Lamé $\lambda$); the
# mixed elements solve it through the incompressible split (element pressures kept out of
# the local solves).

# %%
from IPython.display import Image

stability.plot_locking(locking, "locking.png")
Image("locking.png")

# %% [markdown]
# ## Scaling laws, KKT residuals and conditioning

# %%
factors = ([("E", stability.E_FACTORS[0]), ("E", stability.E_FACTORS[-1]), ("load", 1e-9), ("size", 1e3)]
           if SMOKE else None)
scale = stability.scale_table(factors=factors)
scale[["element", "scaled", "factor", "jump_law_deviation", "stress_law_deviation", "kkt_max_tension", "cond_K", "cond_S"]]

# %%
extreme = stability.extreme_table(elements=("bdm",) if SMOKE else ("peers", "bdm", "tdnns"))
extreme

# %% [markdown]
# ## Conclusion

# %%
mixed = locking[locking.element.isin(["peers", "bdm", "tdnns"]) & (locking.case == "manufactured")]
growth_mixed = max(g.error_u.max() / g.error_u.min() for _, g in mixed[mixed.nu >= 0.49].groupby("element")) \
    if (mixed.nu >= 0.49).sum() else float("nan")
h1 = locking[(locking.element == "h1p1") & (locking.case == "manufactured")].dropna(subset=["error_u"])
growth_h1 = h1.error_u.iloc[-1] / h1.error_u.iloc[0]
print(f"Locking: from nu = 0.3 to {h1.nu.iloc[-1]} the h1p1 error of u grows {growth_h1:.1f}x; "
      f"the mixed elements' errors for nu in [0.49, 1/2] differ by at most {100 * (growth_mixed - 1):.1f}%.")
print(f"Scaling laws hold to {max(scale.jump_law_deviation.max(), scale.stress_law_deviation.max()):.1e} "
      f"(relative), with KKT penetration/tension at most "
      f"{max(scale.kkt_max_penetration.max(), scale.kkt_max_tension.max()):.1e}.")
print(f"1:100 strip: stress error {extreme[extreme.case.str.startswith('strip')].error.max():.1e} against the exact "
      f"uniform state; tip at 1e-4 maxh: Griffith opening error {extreme[extreme.case.str.startswith('griffith')].error.max():.3f}.")

# %%
# The conclusions above, in numbers: this cell fails when one of them stops holding.
assert max(scale.jump_law_deviation.max(), scale.stress_law_deviation.max()) < 1e-6  # exact scaling laws
assert max(scale.kkt_max_penetration.max(), scale.kkt_max_tension.max()) < 1e-10  # KKT at round-off
assert extreme[extreme.case.str.startswith("strip")].error.max() < 1e-6  # the exact uniform state
assert extreme[extreme.case.str.startswith("griffith")].error.max() < 0.02  # the closed form, tiny tip mesh
assert growth_h1 > 2 and not growth_mixed > 1.15  # h1p1 locks; the mixed elements stay within about 10%
