"""What the explorer's figure shows, computed (no matplotlib): stress fields, crack faces, units, labels.

`drawn_displacements` the displacement the figure draws: the computed one, less the rigid
motion that the supports leave to a modelling choice (a body held by rollers and symmetry
lines alone: its translation and rotation are where the rollers happen to sit, so that
griffith's crack, 10 lengths above its bottom roller, would be drawn displaced by the
plate's stretch times the magnification); a body with a clamped or prescribed edge or a
point support is drawn as computed (its supports stay where they are);
`stress_values` the stress field shown, per triangle; `crack_faces` the two faces of each
crack, each with its own side's displacement, and the opening between them; `units` the
scene's stress and length units; `field_label` the colour bar's label; `significant` a
number at fixed significant digits (the tips' K values); `load_magnitude` the largest load
vector (the scale of the load arrows).
"""

from __future__ import annotations

import numpy as np

from ...core.constraints import CLOSED_RTOL
from ...planar.plots import crack_faces  # noqa: F401  (the faces are drawn by plots.plot_solution too)

#: stress fields the figure can show: the crack-normal stress (sigma nu).nu and von Mises
FIELDS = ("sigma_nu", "von_mises")
#: significant digits of the K values
K_DIGITS = 3


def tip_value(tip, key):
    return tip.get(key) if isinstance(tip, dict) else getattr(tip, key, None)


def tip_closed(sol, tip) -> bool:
    """Whether the faces at `tip` touch: the tip's own `closed` (ngcrack.planar.tips.tip_closed, the
    rule the growth loop reads too). With contact the library reports a closed tip's K_I
    as 0 (the crack cannot open there; the integral's value, its error about zero, is
    `K_I_raw`)."""
    return bool(tip_value(tip, "closed"))


def significant(value: float, digits: int = K_DIGITS) -> str:
    """`value` at `digits` significant digits, trailing zeros kept (0.500, 1.20e-05)."""
    return f"{value:#.{digits}g}".rstrip(".")


#: the stress unit of a scene that names none: stresses are in the unit E is given in (the
#: words cannot be read as "sigma / E")
STRESS_UNIT = "same unit as E"
#: the length unit of a scene that names none
LENGTH_UNIT = "length unit"


def units(scene) -> tuple[str, str]:
    """(stress unit, length unit) of a scene: its own where it names them, else STRESS_UNIT, LENGTH_UNIT."""
    u = getattr(scene, "units", None) or {}
    return (u.get("stress") or STRESS_UNIT, u.get("length") or LENGTH_UNIT)


#: the supports that hold a body where it is: with one of them the displacement is drawn as computed
HOLDING_SUPPORTS = frozenset({"clamped", "displacement"})


def rigid_motion_drawn(scene) -> bool:
    """Whether the figure draws the displacement as computed (True: a clamped or prescribed edge
    or a point support holds the body where it is) or less its rigid motion (False: rollers and
    tractions alone)."""
    held = any(bc.type in HOLDING_SUPPORTS for bc in scene.boundary.values())
    return held or any(pc.type != "force" for pc in (getattr(scene, "points", None) or ()))


def rigid_fit(points: np.ndarray, disp: np.ndarray, weights: np.ndarray | None = None) -> tuple:
    """(translation a, centre c, rotation w) of the rigid motion a + w (-(y - c_y), x - c_x) closest
    to `disp` at `points` in least squares, each point counted with its weight (..., 2 arrays)."""
    p = np.asarray(points, float).reshape(-1, 2)
    u = np.asarray(disp, float).reshape(-1, 2)
    wt = np.ones(len(p)) if weights is None else np.repeat(np.asarray(weights, float), len(p) // len(weights))
    total = float(np.sum(wt))
    if total <= 0:
        return np.zeros(2), np.zeros(2), 0.0
    c = (wt[:, None] * p).sum(axis=0) / total
    a = (wt[:, None] * u).sum(axis=0) / total
    r, du = p - c, u - a
    den = float(np.sum(wt * np.sum(r * r, axis=1)))
    w = float(np.sum(wt * (r[:, 0] * du[:, 1] - r[:, 1] * du[:, 0])) / den) if den > 0 else 0.0
    return a, c, w


def drawn_displacements(sol, sigma: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(corners, displacements) per triangle as the figure draws them (`plots.element_displacements`),
    less the rigid motion closest to them (area-weighted) where `rigid_motion_drawn` says the
    supports leave it to a modelling choice. Jumps across the cracks are unchanged."""
    from ...planar.plots import element_displacements

    corners, disp = element_displacements(sol, sigma)
    if not len(disp) or rigid_motion_drawn(sol.scene):
        return corners, disp
    a_, b_ = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    area = 0.5 * np.abs(a_[:, 0] * b_[:, 1] - a_[:, 1] * b_[:, 0])
    a, c, w = rigid_fit(corners, disp, area)
    r = corners - c
    return corners, disp - a - w * np.stack([-r[..., 1], r[..., 0]], axis=-1)


def stress_values(sol, field: str, sigma: np.ndarray | None = None) -> np.ndarray:
    """Per triangle (at its centroid): sigma_nu = (sigma nu).nu with nu the first crack's
    normal ((0, 1) without a crack), or the von Mises stress of the symmetric part (with
    sigma_zz = nu (sigma_xx + sigma_yy) in plane strain, 0 in plane stress). `sigma`:
    the stress at the centroids (plots.centroid_stress), if the caller has it."""
    from ...planar.plots import centroid_stress

    cm = sol.crack_mesh
    sig = centroid_stress(sol) if sigma is None else sigma
    sig = 0.5 * (sig + np.transpose(sig, (0, 2, 1)))
    if field == "sigma_nu":
        nu = cm.cracks[0].normal[0] if cm.cracks else np.array([0.0, 1.0])
        return np.einsum("i,eij,j->e", nu, sig, nu)
    mat = sol.scene.material
    sxx, syy, sxy = sig[:, 0, 0], sig[:, 1, 1], sig[:, 0, 1]
    szz = mat.nu * (sxx + syy) if mat.plane == "strain" else 0.0 * sxx
    return np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3 * sxy ** 2)


def field_label(field: str, scene) -> str:
    """The colour bar's label: the field, its formula and its unit (mathtext, no literal underscores)."""
    stress = units(scene)[0]
    if field == "sigma_nu":
        return rf"$\sigma_{{\nu\nu}} = (\sigma\nu)\cdot\nu$  [{stress}]"
    plane = "plane strain" if scene.material.plane == "strain" else "plane stress"
    return f"von Mises stress ({plane})  [{stress}]"


#: the colour limits cover this area-weighted percentile of the field (the tip's singular
#: peak, on tiny triangles, is clipped and marked, not the scale)
CLIM_PERCENTILE = 98.0
#: the largest displacement drawn, as a fraction of the body's diameter (the magnification)
DEFORMED_FRACTION = 0.08
#: the traction axis spans at least this fraction of the body's stress scale (so that
#: round-off on a traction-free crack is drawn as the zero it is)
PROFILE_FLOOR = 0.05


def weighted_percentile(values: np.ndarray, weights: np.ndarray, q: float) -> float:
    """The q-th percentile of `values` with each counted by its weight (a triangle's area):
    a field's level over the body, not over the many small triangles at a tip."""
    v, w = np.asarray(values, float), np.asarray(weights, float)
    ok = np.isfinite(v) & (w > 0)
    if not np.any(ok):
        return 0.0
    order = np.argsort(v[ok])
    cum = np.cumsum(w[ok][order])
    k = int(np.searchsorted(cum, q / 100.0 * cum[-1]))
    return float(v[ok][order][min(k, len(order) - 1)])


def color_limits(vals: np.ndarray, corners: np.ndarray, field: str) -> tuple[float, float]:
    """(low, high) of the colour bar: sigma_nu symmetric about 0 at the CLIM_PERCENTILE-th
    area-weighted percentile of |sigma_nu|; von Mises from 0 to its percentile."""
    a, b = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    area = 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    if field == "sigma_nu":
        m = weighted_percentile(np.abs(vals), area, CLIM_PERCENTILE)
        return -m, m
    return 0.0, weighted_percentile(vals, area, CLIM_PERCENTILE)


def fit_scales(sol, field: str, corners=None, disp=None, vals=None) -> dict:
    """The figure's scales fitted to `sol`: magnification ("scale"), colour limit ("clim",
    the upper one), the profiles' jump and traction limits, the load arrows' reference."""
    from ...planar.plots import centroid_stress

    if corners is None or disp is None or vals is None:
        sigma = centroid_stress(sol)
        corners, disp = drawn_displacements(sol, sigma)
        vals = stress_values(sol, field, sigma)
    poly = np.asarray(sol.scene.polygon, float)
    diam = float(np.max(np.linalg.norm(poly[:, None] - poly[None], axis=2)))
    umax = float(np.max(np.linalg.norm(disp, axis=2))) if len(disp) else 0.0
    profiles = sol.crack_profiles()
    jmax = max([float(np.max(np.abs(np.r_[p.normal_jump, p.tangential_jump]), initial=0.0)) for p in profiles]
               + [0.0])
    tmax = max([float(np.max(np.abs(np.r_[p.normal_stress, p.shear_stress]), initial=0.0)) for p in profiles]
               + [0.0])
    clim = color_limits(vals, corners, field)[1] if len(vals) else 0.0
    stress_scale = color_limits(np.abs(vals), corners, "von_mises")[1] if len(vals) else 0.0
    return {"scale": DEFORMED_FRACTION * diam / umax if umax > 0 else 0.0, "clim": clim, "jump": jmax,
            "traction": max(tmax, PROFILE_FLOOR * stress_scale), "load": load_magnitude(sol.scene)}


def load_magnitude(scene) -> float:
    """The largest load vector of a scene (traction, displacement, body force): the arrows' scale."""
    mags = [float(np.hypot(*bc.value)) for bc in scene.boundary.values() if bc.type in ("traction", "displacement")]
    if scene.body_force is not None:
        mags.append(float(np.hypot(*scene.body_force)))
    return max(mags, default=0.0) or 0.0


def contact_length(sol) -> float:
    """Total length of the crack edges whose faces touch: the edges whose state is not "open"
    (stick or slip: `CrackProfile.state`, the per-edge states the figure shades, which also
    count a pressed edge with a small positive jump as closed); faces that pass through each
    other (crack model free) are not."""
    profiles = sol.crack_profiles()
    total = 0.0
    for p, crack in zip(profiles, sol.crack_mesh.cracks):
        jn = np.asarray(p.normal_jump, dtype=float)
        W = float(np.max(np.hypot(p.normal_jump, p.tangential_jump), initial=0.0))
        touching = (np.asarray(p.state) != "open") & (jn >= -CLOSED_RTOL * W)
        total += float(np.sum(crack.length[touching]))
    return total


def overlap_length(sol) -> float:
    """Total length of the crack edges whose faces pass through each other (opening below
    -CLOSED_RTOL times the crack's largest jump: only without the contact condition)."""
    return _length_where(sol, lambda jn, W: jn < -CLOSED_RTOL * W)


def _length_where(sol, test) -> float:
    profiles = sol.crack_profiles()
    if not profiles:
        return 0.0
    total = 0.0
    for p, crack in zip(profiles, sol.crack_mesh.cracks):
        W = float(np.max(np.hypot(p.normal_jump, p.tangential_jump), initial=0.0))
        total += float(np.sum(crack.length[test(np.asarray(p.normal_jump, dtype=float), W)]))
    return total
