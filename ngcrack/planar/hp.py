"""Geometric meshes towards the crack tips, made of triangles by marked bisection.

    cmesh = nc.hp.hp_mesh(scene, layers=4)                 # base mesh + 4 layers
    sol = nc.solve(scene, element="bdm", order=3, crack_mesh=cmesh)

Near a crack tip the stress behaves like r^(-1/2): on a quasi-uniform mesh a method of
any order converges only like h^(1/2) in energy. A geometric mesh with ratio sigma
(element sizes proportional to the distance from the tip, shrinking by sigma per layer)
with a polynomial order of at least the number of layers converges exponentially in the
number of unknowns (Babuska and Guo 1986; Schwab 1998, "p- and hp-Finite Element
Methods", ch. 4). Here the layers are built from triangles, so that every element
family works on them unchanged (netgen's `RefineHP` makes quadrilaterals too):

    for j = 1, ..., L:   r_j = r0 sigma^j
        bisect (netgen, with its conforming closure) every triangle that meets the disc
        of radius r_j about a tip and has a longest edge > r_j, until none is left.

After the L layers the triangles at a tip have longest edges <= r_L = r0 sigma^L, and a
triangle at distance d in (r_{j+1}, r_j) has longest edge <= r_j: one ring of
triangles per layer, each ring sigma times the size of the one outside it. The
refinement is `adapt.refine` (`geometry.refine_crack_mesh`): crack edges stay a chain of
mesh edges and the tips stay vertices, so the tips' domain integral, the crack
profiles, the error estimate and friction read an hp mesh like any other.

The factor and the start, as measured (benchmarks/higher_order.py, griffith and
inclined-compression, bdm and tdnns of order 3):
- sigma = HP_SIGMA = 0.2 (the range 0.15-0.25 of the literature for a square-root
  singularity; 0.15 and 0.25 give the same errors per unknown to within the scatter);
- r0 = HP_R0 = 0.25 times the tip's clearance (tips.py: its distance to the body's
  boundary, the other cracks and its own crack's far end), capped so that the first
  layer refines: the first disc lies well inside the domain integral's
  radius (half the clearance), so the integral's annulus sees the graded rings.
- the base mesh is the scene's own (its maxh, tip_h, crack_h, grading) unless given;
  `base_mesh(scene)` is the coarser one the measurements use (the layers do the grading).

The order is uniform (the element's `order`); it does not rise away from the tip.
NGSolve's spaces take per-element orders, but the crack's unknowns need one order along
each crack: the QP's constraint points (`post.endpoint_map`), the crack profiles
(`post.facet_basis`) and the estimate's reconstruction read k + 1 jump dofs on every
crack edge; and the trace u_hat on an edge between orders k1 < k2 must take one
side's order: k1 gives up the exact normal continuity of the stress (the equilibrium
the tips' integral and the estimate rely on), k2 keeps it with the flux in P_k1. Measured, the uniform order is enough: at order 3 the
errors fall by about sigma per layer down to 1e-6 (griffith: 5e-4, 1.3e-4, 2.4e-5,
3.4e-6 for the opening at 1-4 layers); at order 2 they stop near 3e-5 (K) and 8e-5
(opening), at order 1 near 2e-3 and 1e-2: there the base mesh's error dominates, not
the tip's. The layers hold about half of the triangles at L = 4, which bounds what a
lower order at the tip could save.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.errors import InputError

# the ratio of consecutive layer radii (r_{j+1} = HP_SIGMA r_j), its range and the most
# layers are solve options' bounds, checked there too
from ..core.options import HP_MAX_LAYERS as MAX_LAYERS
from ..core.options import HP_SIGMA, HP_SIGMA_RANGE
from .geometry import CrackMesh, make_mesh, refine_crack_mesh
from .tips import _clearance, crack_tips, tip_labels

#: the first radius r0 as a fraction of the tip's clearance
HP_R0 = 0.25
#: bisection rounds per layer at most (sigma = 0.2 needs about 5; a guard against a loop)
MAX_ROUNDS = 40
#: the base mesh of the hp measurements: sizes as fractions of the tip clearance
BASE_TIP_H = 0.25
BASE_CRACK_H = 0.25


def _point_triangle_distance(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Distance from the point p to each triangle of tri (n, 3, 2); 0 inside."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]

    def seg(u, v):
        d = v - u
        t = np.clip(np.einsum("ni,ni->n", p - u, d) / np.einsum("ni,ni->n", d, d), 0.0, 1.0)
        return np.linalg.norm(u + t[:, None] * d - p, axis=1)

    dist = np.minimum(np.minimum(seg(a, b), seg(b, c)), seg(c, a))

    def cross(u, v):
        return (u[:, 0] - p[0]) * (v[:, 1] - p[1]) - (u[:, 1] - p[1]) * (v[:, 0] - p[0])

    s1, s2, s3 = cross(a, b), cross(b, c), cross(c, a)
    inside = ((s1 >= 0) & (s2 >= 0) & (s3 >= 0)) | ((s1 <= 0) & (s2 <= 0) & (s3 <= 0))
    return np.where(inside, 0.0, dist)


def longest_edges(crack_mesh: CrackMesh) -> np.ndarray:
    """The longest edge of each triangle."""
    P = crack_mesh.points[crack_mesh.triangles]
    return np.linalg.norm(P - np.roll(P, 1, axis=1), axis=2).max(axis=1)


def singular_points(scene, crack_mesh: CrackMesh, points=()) -> list[tuple[np.ndarray, float]]:
    """(position, clearance) of every crack tip inside the body, then of the given points.

    The given points (other singular points the user marks: re-entrant corners, load
    discontinuities) get the clearance of the nearest tip, or the body's diameter / 20.
    """
    out = [(np.array([t.x, t.y]), float(t.clearance)) for t in crack_tips(scene, crack_mesh)]
    default = min((c for _, c in out), default=crack_mesh.diameter / 20.0)
    check_hp_options(0, points=points)
    out += [(np.asarray(p, dtype=float), default) for p in points]
    return out


def check_hp_options(layers, sigma=HP_SIGMA, r0=None, points=()) -> None:
    """Refuse a bad layer count, ratio, start radius or point, naming the field."""
    if isinstance(layers, bool) or not isinstance(layers, (int, np.integer)) or not 0 <= layers <= MAX_LAYERS:
        raise InputError(f"hp = {layers!r}: the number of layers must be an integer in 0..{MAX_LAYERS}")
    if isinstance(sigma, bool) or not isinstance(sigma, (int, float)) or not HP_SIGMA_RANGE[0] <= sigma <= HP_SIGMA_RANGE[1]:
        raise InputError(f"hp_sigma = {sigma!r}: the layer ratio must lie in [{HP_SIGMA_RANGE[0]:g}, {HP_SIGMA_RANGE[1]:g}]")
    if r0 is not None and (isinstance(r0, bool) or not isinstance(r0, (int, float)) or not (math.isfinite(r0) and 0 < r0 < 1)):
        raise InputError(f"hp_r0 = {r0!r}: the first radius, as a fraction of the tip clearance, must lie in (0, 1)")
    for p in points:
        q = np.asarray(p, dtype=float) if np.ndim(p) == 1 else None
        if q is None or q.shape != (2,) or not np.all(np.isfinite(q)):
            raise InputError(f"hp_points: {p!r} is not a point (x, y)")


def tip_clearances(scene) -> list[float]:
    """The clearance of every crack end inside the body, from the scene alone (tips.py)."""
    out = []
    for label in tip_labels(scene):
        k, end = label.split(",")
        pts = np.asarray(scene.cracks[int(k)].points, dtype=float)
        out.append(_clearance(scene, int(k), end, pts[0] if end == "first" else pts[-1]))
    return out


def base_mesh(scene, tip_h: float | None = None, crack_h: float | None = None, **mesh) -> CrackMesh:
    """The coarse mesh the hp layers start from: the scene's maxh and grading, the
    crack and tip sizes BASE_CRACK_H and BASE_TIP_H times the smallest tip clearance
    (or given). Without an interior tip: the scene's own mesh."""
    clearances = tip_clearances(scene)
    if not clearances:
        return make_mesh(scene, tip_h=tip_h, crack_h=crack_h, **mesh)
    c = min(clearances)
    return make_mesh(scene, tip_h=BASE_TIP_H * c if tip_h is None else tip_h,
                     crack_h=BASE_CRACK_H * c if crack_h is None else crack_h, **mesh)


def refine_towards_tips(crack_mesh: CrackMesh, scene, layers: int, sigma: float = HP_SIGMA, r0: float | None = None,
                        points=()) -> CrackMesh:
    """L = `layers` geometric layers of ratio `sigma` towards every tip (and `points`).

    r0 is a fraction of each tip's clearance (default HP_R0). Returns a new CrackMesh
    (the input is unchanged); layers = 0 returns the input.
    """
    check_hp_options(layers, sigma, r0, points)
    frac = HP_R0 if r0 is None else float(r0)
    centres = singular_points(scene, crack_mesh, points)
    if layers == 0 or not centres:
        return crack_mesh
    cmesh = crack_mesh
    for j in range(1, layers + 1):
        for _ in range(MAX_ROUNDS):
            P = cmesh.points[cmesh.triangles]
            h = longest_edges(cmesh)
            marked = np.zeros(len(h), dtype=bool)
            for p, clearance in centres:
                r = frac * clearance * sigma**j
                marked |= (_point_triangle_distance(p, P) < r) & (h > r)
            if not marked.any():
                break
            cmesh = refine_crack_mesh(cmesh, scene, marked)
        else:
            raise RuntimeError(f"hp layer {j}: the bisection did not reach the layer's size in {MAX_ROUNDS} rounds")
    return cmesh


def hp_mesh(scene, layers: int, sigma: float = HP_SIGMA, r0: float | None = None, points=(),
            crack_mesh: CrackMesh | None = None, **mesh) -> CrackMesh:
    """The geometric mesh of `scene`: `crack_mesh` (default `base_mesh(scene, **mesh)`)
    refined by `refine_towards_tips`."""
    check_hp_options(layers, sigma, r0, points)
    cmesh = crack_mesh if crack_mesh is not None else base_mesh(scene, **mesh)
    return refine_towards_tips(cmesh, scene, layers, sigma=sigma, r0=r0, points=points)


def jump_integrals(sol, crack: int = 0) -> tuple[float, float]:
    """(int [u].nu ds, int [u].t ds) over crack `crack`: the opening and sliding "areas"
    the hp measurements compare (exact integrals of the discrete jumps; the crack's
    frame as in post.py, nu the normal, t the tangent from its first point)."""
    import ngsolve as ngs

    from .geometry import crack_bc, crack_frame_cf

    disc, cmesh = sol.disc, sol.crack_mesh
    if disc.jn is None:
        raise InputError(f"crack = {crack!r}: this solve has no crack unknowns")
    comps = sol.gf.components
    region = cmesh.mesh.Boundaries(crack_bc(cmesh.cracks[crack].index))
    _, t = crack_frame_cf(cmesh)
    tangential = comps[disc.jt] if disc.jt is not None else disc.tangential_jump(sol.gf) * t
    opening = ngs.Integrate(comps[disc.jn], cmesh.mesh, ngs.BND, definedon=region)
    sliding = ngs.Integrate(tangential, cmesh.mesh, ngs.BND, definedon=region)
    return float(opening), float(sliding)


#: offset (times the edge length) into the + side where a tangential trace is sampled
TRACE_OFFSET = 1e-6


def jump_at(sol, s: float, crack: int = 0) -> tuple[float, float]:
    """([u].nu, [u].t) at arc length `s` along crack `crack` (from its first point), from
    the discrete jumps' polynomials on the edge holding s (an edge's end: its first
    edge's). A facet jump is evaluated from its dofs; the TDNNS tangential jump (the
    crack edges' H(curl) copy) at TRACE_OFFSET of the edge length inside the + side."""
    from .post import facet_basis

    disc, cmesh = sol.disc, sol.crack_mesh
    if disc.jn is None:
        raise InputError(f"crack = {crack!r}: this solve has no crack unknowns")
    c = cmesh.cracks[crack]
    s0 = c.s_mid - 0.5 * c.length
    e = int(np.clip(np.searchsorted(s0 + c.length, s), 0, len(c) - 1))
    t = float(np.clip((s - s0[e]) / c.length[e], 0.0, 1.0))
    comps = sol.gf.components
    space = disc.fes.components[disc.jn]
    dofs, B = facet_basis(space, cmesh, c, [t])
    jn = float(comps[disc.jn].vec.FV().NumPy()[dofs[e]] @ B[e, :, 0])
    if disc.jt is not None:
        jt = float(comps[disc.jt].vec.FV().NumPy()[dofs[e]] @ B[e, :, 0])
    else:
        x = c.a[e] + t * (c.b[e] - c.a[e]) + TRACE_OFFSET * c.length[e] * c.normal[e]
        val = np.asarray(disc.tangential_jump(sol.gf)(cmesh.mesh(x[0], x[1]))).reshape(-1)
        jt = float(val @ c.tangent[e])
    return jn, jt
