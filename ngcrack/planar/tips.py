"""Fracture parameters at the crack tips: K_I, K_II and G by the domain (equivalent-domain) integral.

The tip frame. At a crack end inside the body, e1 is the unit tangent of
the crack's tip segment pointing out of the crack, e2 is e1 turned by +90 degrees, and
(r, theta) are polar coordinates about the tip in that frame (theta = +-pi on the crack
faces, + on the side e2 points into). K_I and K_II are defined by
sigma_22 ~ K_I / sqrt(2 pi r), sigma_12 ~ K_II / sqrt(2 pi r) ahead of the tip, and
G = J = (K_I^2 + K_II^2) / E' with E' = E / (1 - nu^2) in plane strain, E in plane stress.

The J-integral (Rice) in domain form, for a weight q = 1 near the tip and 0 outside a
disc of radius R (Moes, Dolbow, Belytschko 1999; Yau, Wang, Corten 1980; Shih, Moran,
Nakamura 1986), with all components in the tip frame:

    J = int_A (sigma_ij du_i/dx_1 - W delta_1j) dq/dx_j dA            (domain)
        - int_A f_i du_i/dx_1 q dA                                     (body force)
        + int_crack T . d[u]/dx_1 q ds                                 (crack faces)

W = sigma : eps / 2; T = sigma e2 the traction the faces carry (equal and opposite on
the two faces), [u] = u(theta = pi) - u(theta = -pi) and d/dx_1 = -d/dr along the faces.
The interaction integral of the solution with the auxiliary Williams field of mode m
(K^aux = 1, `williams_*` below) is the cross term of J(u + u_aux):

    I_m = int_A (sigma_ij du^aux_i/dx_1 + sigma^aux_ij du_i/dx_1 - sigma : eps^aux delta_1j) dq/dx_j dA
          - int_A f . du^aux/dx_1 q dA + int_crack T . d[u^aux]/dx_1 q ds

and K_I = E' I_1 / 2, K_II = E' I_2 / 2. The auxiliary faces are traction free, so only
the solution's face traction enters; [u^aux] = (kappa + 1) / mu sqrt(r / 2 pi) (K_II, K_I)
in the tip frame. A crack-face pressure p loads the open faces with T = (0, -p); with
contact or friction the closed faces carry T = (tau, sigma_n):
the face term is what makes K_I = 0 come out of a crack held closed by a compression
(without it a uniform compression across the crack would read as a negative K_I). It is
written from the whole traction vector, normal and shear, so it covers friction; for
frictionless contact the J face term vanishes in the limit (sigma_n [u].nu = 0, tau = 0).
At a tip whose faces touch, with contact, K_I is reported as 0 (`domain_integral`).

What each element gives the integral. Every term needs sigma and the displacement
gradient grad u (row i: grad u_i); W and sigma^aux : grad u need only its symmetric part,
but sigma_ij du_i/dx_1 dq/dx_j needs the rotation too (du_2/dx_1 = eps_21 + omega).
- peers, bdm: u is P0 (its gradient is zero on each triangle), so the strain is the
  compliance strain eps = A sym(sigma_h) and the rotation is the weak-symmetry
  multiplier r, which approximates omega = (du_2/dx_1 - du_1/dx_2) / 2:
  grad u = A sym(sigma_h) + r [[0, -1], [1, 0]]. sigma_h is equilibrated (div sigma_h = -f
  on each triangle, normal traces continuous), which the domain form assumes.
- tdnns: the same compliance strain, and the skew part of the element's own H(curl)
  displacement gradient for the rotation (measured: its whole own gradient gives K within
  0.1% of this, slightly further from the converged Griffith value).
- h1p1, h1p2: the gradient of the displacement itself (sigma = C eps(u) is post-computed).
The face traction is the crack profile's (sigma_n, tau) at each crack edge's mid point
(both sides averaged for the post-computed stresses, see post.py) and the jumps are the
profile's; the face integrals are sums over the crack edges, the singular one
(d[u^aux]/dr ~ r^(-1/2)) integrated exactly on each edge.

The domain. q is the P1 interpolant of the radial profile q(r) = 1 for r <= R/2, falling
linearly to 0 at r = R, so that grad q vanishes on the triangles at the tip (where the
fields are least accurate) and is constant on each triangle. R is chosen from the
geometry: DOMAIN_FRACTION of the tip's clearance (its distance to the body's boundary,
to other cracks, to its own crack beyond the tip segment and to the tip segment's far
end, so that the faces inside the domain are straight); the number of element rings in
the annulus R/2 < r < R is reported (the solve's table marks fewer than MIN_RINGS as
coarse). The integrals are vectorized: the fields are evaluated by NGSolve at once at
the quadrature points of the triangles where q_h != 0 (and only there), the Williams
fields and the integrands in numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..core.constraints import faces_closed
from ..core.errors import InputError
from ..core.quadrature import DOMAIN_INTEGRAL_ORDER
from .materials import compliance as _compliance
from .scene import tip_label
from .scene.measures import point_segment_distance
from .scene.pressure import pressure_values
from .tstress import interaction_integrand as _t_integrand

#: the integration radius as a fraction of the tip's clearance (distance to the boundary,
#: other cracks, the crack beyond its tip segment): 1/2 leaves room for elements
#: reaching past R and lets a check halve it (measured: the answers move by well under 1%)
DOMAIN_FRACTION = 0.5
#: q = 1 inside this fraction of R (the plateau), linear to 0 at R. Measured on paper-2
#: (bdm): 0.5 is the most accurate of 0, 0.25, 0.5 at maxh 0.2, 0.1 and 0.05; the cone
#: (0, the tip's triangles in the domain) is 1-2% off at maxh 0.1 and 0.05
PLATEAU_FRACTION = 0.5
#: fewer element rings than this in the annulus where grad q is nonzero: a coarse tip mesh.
#: Measured on paper-2 (bdm, K_II against a mesh graded to 0.002 at the tips): 0.5 rings
#: (maxh 0.2) 3.7% off, 1.3 rings (maxh 0.1) 0.1%, 2.4 rings (maxh 0.05) 0.3%
MIN_RINGS = 1.0
#: quadrature degree of the domain integral (`ngcrack.core.quadrature`)
QUADRATURE_ORDER = DOMAIN_INTEGRAL_ORDER
#: r below this fraction of R is floored (no quadrature point sits at a tip; this only
#: keeps r^(-1/2) finite in the expression)
R_FLOOR = 1e-12
#: a crack end closer than this fraction of the body's diameter to another crack is a
#: junction, not a tip: it gets no fracture parameters
JUNCTION_RTOL = 1e-6
#: consecutive crack segments whose unit tangents' cross product is at most this are one straight
#: line (a path grown without a kink): the domain integral's radius may reach past their joints
STRAIGHT_RTOL = 1e-9
#: `body_force` default of the domain integral: the scene's body force
SCENE = "scene"


# ------------------------------------------------------------------ material constants
def kolosov(nu: float, plane: str) -> float:
    """Kolosov's constant kappa: 3 - 4 nu in plane strain, (3 - nu) / (1 + nu) in plane stress."""
    if plane == "strain":
        return 3.0 - 4.0 * nu
    if plane == "stress":
        return (3.0 - nu) / (1.0 + nu)
    raise InputError(f"material.plane = {plane!r}: allowed values are strain, stress")


def effective_modulus(E: float, nu: float, plane: str) -> float:
    """E' = E / (1 - nu^2) in plane strain, E in plane stress: G = (K_I^2 + K_II^2) / E'."""
    if plane == "strain":
        return E / (1.0 - nu * nu)
    if plane == "stress":
        return E
    raise InputError(f"material.plane = {plane!r}: allowed values are strain, stress")


# ----------------------------------------------------------- auxiliary Williams fields
# Functions of polar coordinates (r, theta) in the tip frame, for K = 1; `m` (keyword) is the
# math namespace: None for numpy (arrays), or ngsolve (CoefficientFunctions). mode 1 or 2.
# (A default of None, not the module: a module as a default shows its path in the signature.)

def williams_stress(r, theta, mode: int, *, m=None):
    """(sigma_11, sigma_22, sigma_12) of the mode-`mode` Williams field with K = 1."""
    m = np if m is None else m
    c, s = m.cos(0.5 * theta), m.sin(0.5 * theta)
    c3, s3 = m.cos(1.5 * theta), m.sin(1.5 * theta)
    k = 1.0 / m.sqrt(2.0 * math.pi * r)
    if mode == 1:
        return k * c * (1.0 - s * s3), k * c * (1.0 + s * s3), k * c * s * c3
    if mode == 2:
        return -k * s * (2.0 + c * c3), k * s * c * c3, k * c * (1.0 - s * s3)
    raise InputError(f"mode = {mode!r}: allowed values are 1, 2")


def williams_displacement(r, theta, mode: int, kappa: float, mu: float, *, m=None):
    """(u_1, u_2) of the mode-`mode` Williams field with K = 1 (no rigid motion: u = 0 at the tip)."""
    m = np if m is None else m
    f1, f2 = _angular(theta, mode, kappa, m)[:2]
    a = m.sqrt(r / (2.0 * math.pi)) / (2.0 * mu)
    return a * f1, a * f2


def williams_dx1(r, theta, mode: int, kappa: float, mu: float, *, m=None):
    """(du_1/dx_1, du_2/dx_1) of the mode-`mode` Williams field with K = 1.

    u = sqrt(r) f(theta) / (2 mu sqrt(2 pi)) and d/dx_1 = cos(theta) d/dr - sin(theta) / r d/dtheta.
    """
    m = np if m is None else m
    f1, f2, g1, g2 = _angular(theta, mode, kappa, m)
    ct, st = m.cos(theta), m.sin(theta)
    a = 1.0 / (2.0 * mu * m.sqrt(2.0 * math.pi * r))
    return a * (0.5 * ct * f1 - st * g1), a * (0.5 * ct * f2 - st * g2)


def _angular(theta, mode: int, kappa: float, m):
    """The angular functions f_1, f_2 of the Williams displacement and their derivatives."""
    c, s = m.cos(0.5 * theta), m.sin(0.5 * theta)
    sin_t = m.sin(theta)
    if mode == 1:
        f1 = c * (kappa - 1.0 + 2.0 * s * s)
        f2 = s * (kappa + 1.0 - 2.0 * c * c)
        g1 = -0.5 * s * (kappa - 1.0 + 2.0 * s * s) + c * sin_t
        g2 = 0.5 * c * (kappa + 1.0 - 2.0 * c * c) + s * sin_t
    elif mode == 2:
        f1 = s * (kappa + 1.0 + 2.0 * c * c)
        f2 = -c * (kappa - 1.0 - 2.0 * s * s)
        g1 = 0.5 * c * (kappa + 1.0 + 2.0 * c * c) - s * sin_t
        g2 = 0.5 * s * (kappa - 1.0 - 2.0 * s * s) + c * sin_t
    else:
        raise InputError(f"mode = {mode!r}: allowed values are 1, 2")
    return f1, f2, g1, g2


def face_opening_factor(kappa: float, mu: float) -> float:
    """c with [u^aux] = c sqrt(r) on the faces (K = 1): c = (kappa + 1) / (mu sqrt(2 pi)).

    Mode I opens ([u^aux].e2), mode II slides ([u^aux].e1), by the same amount.
    """
    return (kappa + 1.0) / (mu * math.sqrt(2.0 * math.pi))


# ---------------------------------------------------------------------------- tips
@dataclass(frozen=True)
class Tip:
    """A crack end inside the body and its frame.

    `e1` the unit tangent of the tip segment pointing out of the crack; `clearance` the
    distance from the tip to the body's boundary, to the other cracks, to its own crack
    beyond the tip segment and to the tip segment's far end (the largest domain radius).
    """

    crack: int
    end: str
    x: float
    y: float
    e1: tuple[float, float]
    clearance: float

    @property
    def label(self) -> str:
        """`crack,end`, e.g. `0,last`: how tables and columns name the tip (`tip_label`)."""
        return tip_label(self.crack, self.end)


def _straight_run(pts: np.ndarray, end: str) -> int:
    """How many segments at the `end` of the polyline continue the tip segment in a straight line
    (a path grown without kinks): the faces are straight over all of them."""
    q = pts if end == "last" else pts[::-1]
    t = np.diff(q, axis=0)
    t = t / np.linalg.norm(t, axis=1)[:, None]
    n = 1
    while n < len(t) and t[-1 - n] @ t[-1] > 0 and abs(t[-1 - n, 0] * t[-1, 1] - t[-1 - n, 1] * t[-1, 0]) <= STRAIGHT_RTOL:
        n += 1
    return n


def _clearance(scene, k: int, end: str, p: np.ndarray) -> float:
    """Distance from the tip p of crack k to the boundary, the other cracks, crack k beyond its
    straight tip run (the tip segment and the segments continuing it in a straight line) and the
    far end of that run (a kink or the crack's other end)."""
    poly = np.asarray(scene.polygon, dtype=float)
    segs = [(poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly))]
    segs += [(np.asarray(a, float), np.asarray(b, float)) for _, a, b in scene.hole_pieces()]  # holes too
    pts = np.asarray(scene.cracks[k].points, dtype=float)
    run = _straight_run(pts, end)
    for j, crack in enumerate(scene.cracks):
        cp = np.asarray(crack.points, dtype=float)
        pairs = list(zip(cp[:-1], cp[1:]))
        if j == k:
            pairs = pairs[run:] if end == "first" else pairs[:-run]
        segs += pairs
    segment = float(np.linalg.norm(pts[run] - pts[0]) if end == "first" else np.linalg.norm(pts[-1] - pts[-1 - run]))
    return min([segment] + [point_segment_distance(p, a, b) for a, b in segs])


def crack_tips(scene, crack_mesh) -> list[Tip]:
    """The crack ends inside the body (not on its boundary nor on another crack).

    Crack by crack, first end then last.
    """
    out = []
    for c in crack_mesh.cracks:
        if not len(c):
            continue
        pts = np.asarray(scene.cracks[c.index].points, dtype=float)
        ends = (("first", c.va[0], pts[0], pts[0] - pts[1]), ("last", c.vb[-1], pts[-1], pts[-1] - pts[-2]))
        for end, vertex, p, t in ends:
            clearance = _clearance(scene, c.index, end, p)
            if int(vertex) not in crack_mesh.tip_vertices or clearance <= JUNCTION_RTOL * crack_mesh.diameter:
                continue  # on the boundary, or on another crack (a junction, not a tip)
            e1 = t / np.linalg.norm(t)
            out.append(Tip(crack=c.index, end=end, x=float(p[0]), y=float(p[1]), e1=(float(e1[0]), float(e1[1])),
                           clearance=clearance))
    return out


def tip_labels(scene) -> list[str]:
    """`crack,end` of every crack end inside the body, from the scene alone (no mesh)."""
    from .geometry import ON_EDGE_RTOL

    poly = np.asarray(scene.polygon, dtype=float)
    diameter = scene.diameter
    out = []
    for k, crack in enumerate(scene.cracks):
        pts = np.asarray(crack.points, dtype=float)
        for end, p in (("first", pts[0]), ("last", pts[-1])):
            on_boundary = min(point_segment_distance(p, poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly)))
            on_hole = getattr(scene, "on_hole", lambda x: None)(p) is not None  # a crack end joining a hole
            if on_boundary > ON_EDGE_RTOL * diameter and not on_hole and _clearance(scene, k, end, p) > JUNCTION_RTOL * diameter:
                out.append(tip_label(k, end))
    return out


# ---------------------------------------------------------------- the domain integral
@dataclass(frozen=True)
class TipParameters:
    """K_I, K_II, G and the T-stress at one tip, and how they were computed.

    `radius` R of the domain (q = 1 for r <= R/2, 0 for r >= R), `rings` the number of
    element rings across the annulus where grad q is nonzero, `J` the J-integral (= G but at
    a closed tip, `domain_integral`),
    `I` the two interaction integrals, `face_J`, `face_I` the crack-face parts of J and I
    (included in them), `elements` the triangles in the domain.
    """

    crack: int
    end: str
    x: float
    y: float
    K_I: float
    K_II: float
    G: float
    radius: float
    rings: float
    J: float
    I: tuple[float, float]
    face_J: float
    face_I: tuple[float, float]
    elements: int
    #: the T-stress (sigma_11 - its singular part at the tip, tip frame), tstress.py
    T: float = 0.0
    #: the faces at the tip touch (`tip_closed`); with the contact crack model K_I is then
    #: reported as 0 and G as K_II^2 / E', the integral's own K_I kept in `K_I_raw`
    closed: bool = False
    #: K_I as the interaction integral gives it (None: K_I)
    K_I_raw: float | None = None

    def __post_init__(self):
        if self.K_I_raw is None:
            object.__setattr__(self, "K_I_raw", self.K_I)

    @property
    def label(self) -> str:
        """`crack,end` (`tip_label`)."""
        return tip_label(self.crack, self.end)

    def to_dict(self) -> dict:
        """The `tips` entry of the JSON contract."""
        return {"crack": int(self.crack), "end": self.end, "x": float(self.x), "y": float(self.y),
                "K_I": float(self.K_I), "K_II": float(self.K_II), "G": float(self.G), "T": float(self.T),
                "closed": bool(self.closed), "K_I_raw": float(self.K_I_raw)}


def displacement_gradient(sol):
    """grad u (row i: grad u_i) as the domain integral uses it (see the module docstring)."""
    fields, how = sol.fields, sol.disc.traits.gradient
    if how == "gradient":  # displacement elements: grad u itself
        return fields["grad_u"]
    mat = sol.scene.material
    sig = fields["sigma"]
    eps = _compliance(mat.E, mat.nu, mat.plane).apply(0.5 * (sig + sig.trans))
    if how == "rotation":  # the strain of the stress plus the element's rotation (peers, bdm)
        r = fields["rotation"]
        return eps + ngs.CF((0.0, -r, r, 0.0), dims=(2, 2))
    grad = fields["grad_u"]  # "skew": plus the skew part of grad_u (tdnns)
    return eps + 0.5 * (grad - grad.trans)


def _quadrature(sol, tip: Tip, radius: float):
    """The triangles where q_h != 0 and NGSolve's quadrature points on them.

    Returns (mapped points (n k,) for CoefficientFunction evaluation, their coordinates
    (n k, 2), weights (n k,), q_h (n k,) and grad q_h (n k, 2) there). q_h is the P1
    interpolant of the radial profile q(r).
    """
    cm = sol.crack_mesh
    P, T = cm.points, cm.triangles
    rv = np.linalg.norm(P - np.array([tip.x, tip.y]), axis=1)
    inner = PLATEAU_FRACTION * radius
    q = ngs.GridFunction(ngs.H1(sol.mesh, order=1))  # vertex dofs in vertex order
    q.vec.FV().NumPy()[:] = np.clip((radius - rv) / (radius - inner), 0.0, 1.0)
    sel = np.flatnonzero((q.vec.FV().NumPy()[T] > 0).any(axis=1))
    rule = ngs.IntegrationRule(ngs.TRIG, QUADRATURE_ORDER)
    k = len(rule.weights)
    mp = sol.mesh.MapToAllElements(rule, ngs.VOL).reshape(len(T), k)[sel].ravel()
    d1, d2 = P[T[sel, 1]] - P[T[sel, 0]], P[T[sel, 2]] - P[T[sel, 0]]
    det = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    w = (det[:, None] * np.array(rule.weights)[None, :]).ravel()
    xy = np.column_stack([np.asarray(ngs.x(mp)).ravel(), np.asarray(ngs.y(mp)).ravel()])
    return mp, xy, w, np.asarray(q(mp)).ravel(), np.asarray(ngs.grad(q)(mp)).reshape(-1, 2)


def _domain_terms(sol, tip: Tip, radius: float, A, kappa: float, mu: float, body_force) -> np.ndarray:
    """The area parts of (J, I_1, I_2, I_T): the fields sampled at quadrature points of the
    triangles where q_h != 0 (vectorized NGSolve evaluations), the rest in numpy; I_T the
    interaction with the point-force field (tstress.py)."""
    mp, flat, w, qp, gq = _quadrature(sol, tip, radius)
    Q = np.array([tip.e1, (-tip.e1[1], tip.e1[0])])  # rows e1, e2: local = Q global
    sig = Q @ np.asarray(sol.sigma(mp)).reshape(-1, 2, 2) @ Q.T
    grad = Q @ np.asarray(displacement_gradient(sol)(mp)).reshape(-1, 2, 2) @ Q.T
    gql = gq @ Q.T  # grad q in the tip frame
    X = (flat - np.array([tip.x, tip.y])) @ Q.T
    r = np.sqrt(X[:, 0] ** 2 + X[:, 1] ** 2 + (R_FLOOR * radius) ** 2)
    theta = np.arctan2(X[:, 1], X[:, 0])
    eps = 0.5 * (grad + np.swapaxes(grad, 1, 2))
    du1 = grad[:, :, 0]  # du_i/dx_1
    W = 0.5 * (sig * eps).sum(axis=(1, 2))
    sig_gq = (sig @ gql[:, :, None])[:, :, 0]
    terms = [(du1 * sig_gq).sum(axis=1) - W * gql[:, 0]]
    dua = []
    for mode in (1, 2):
        s11, s22, s12 = williams_stress(r, theta, mode)
        sig_aux = np.stack([np.stack([s11, s12], -1), np.stack([s12, s22], -1)], -2)
        eps_aux = A.apply(sig_aux)
        dua.append(np.column_stack(williams_dx1(r, theta, mode, kappa, mu)))
        terms.append((dua[-1] * sig_gq).sum(axis=1) + (du1 * (sig_aux @ gql[:, :, None])[:, :, 0]).sum(axis=1)
                     - (sig * eps_aux).sum(axis=(1, 2)) * gql[:, 0])
    t_val, t_dua = _t_integrand(sig, du1, gql, r, theta, A, kappa, mu)
    terms.append(t_val)
    dua.append(t_dua)
    integrand = np.stack(terms, axis=1)
    if body_force is not None:
        f = np.asarray(body_force(mp)).reshape(-1, 2) @ Q.T
        body = np.column_stack([(f * du1).sum(axis=1)] + [(f * d).sum(axis=1) for d in dua])
        integrand = integrand - qp.reshape(-1, 1) * body
    return w @ integrand


def _rings(sol, tip: Tip, radius: float) -> tuple[float, int]:
    """(element rings across the annulus R/2 < r < R, triangles where q != 0)."""
    cm = sol.crack_mesh
    corners = cm.points[cm.triangles]
    rc = np.linalg.norm(corners.mean(axis=1) - np.array([tip.x, tip.y]), axis=1)
    r_min = np.linalg.norm(corners - np.array([tip.x, tip.y]), axis=2).min(axis=1)
    inner = PLATEAU_FRACTION * radius
    ann = (rc > inner) & (rc < radius)
    if not np.any(ann):
        return 0.0, int(np.sum(r_min < radius))
    sides = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2)
    h = float(np.mean(sides[ann]))
    return (radius - inner) / h, int(np.sum(r_min < radius))


def face_traction(sol, k: int) -> tuple[np.ndarray, np.ndarray]:
    """(sigma_n, tau) the faces of crack k carry at its edges' mid points, by the crack's law.

    The crack law fixes which tractions the faces can carry: only the crack-face pressure
    (sigma_n = -p, `ngcrack.planar.scene.pressure`; 0 without one) where the crack is open or
    its faces pass (crack_model "free"), no shear without friction
    (a crack's `friction` coefficient, where the scene gives one, > 0 keeps the sampled
    shear). Where the faces touch (constraints.faces_closed at the edges' mid points) the
    sampled normal stress is kept. Applying the law rather than the raw samples matters
    for the elements whose stress has no single-valued face traction: the TDNNS shear and
    the baselines' post-computed stress near the tip, which are far from zero on an
    open crack's faces.
    """
    prof = sol.profiles[k]
    model = sol.crack_model
    sn = np.asarray(prof.normal_stress, dtype=float)
    # the crack-face pressure p loads the open faces: sigma_n = -p there
    applied_p = -pressure_values(getattr(sol.scene.cracks[k], "pressure", None), prof.s)
    if model == "free":
        return applied_p, np.zeros_like(sn)
    jn, jt = np.asarray(prof.normal_jump), np.asarray(prof.tangential_jump)
    scale = float(np.max(np.hypot(jn, jt))) if len(jn) else 0.0
    closed = faces_closed(jn, scale)
    sn = np.where(closed, sn, applied_p)
    # friction acts only where the solve applied it (unilateral contact with the tangential jumps kept)
    applied = sol.friction_applied
    friction = float(getattr(sol.scene.cracks[k], "friction", 0.0) or 0.0) if applied else 0.0
    tau = np.where(closed, np.asarray(prof.shear_stress, dtype=float), 0.0) if friction > 0 else np.zeros_like(sn)
    return sn, tau


def _face_terms(sol, tip: Tip, radius: float, c_open: float) -> tuple[float, float, float]:
    """The crack-face parts (J, I_1, I_2): sums over the tip's crack edges inside the domain.

    With T = (tau, sigma_n) in the tip frame (`face_traction`; for either end
    e1.sigma e2 = t.sigma nu and e2.sigma e2 = nu.sigma nu):
    J_f = -int (sigma_n d[u].nu/dr + tau d[u].t/dr) q dr, I_f = -(c/2) int (sigma_n, tau) r^(-1/2) q dr.
    """
    if not sol.profiles:
        return 0.0, 0.0, 0.0
    c = sol.crack_mesh.cracks[tip.crack]
    prof = sol.profiles[tip.crack]
    sn_all, tau_all = face_traction(sol, tip.crack)
    p = np.array([tip.x, tip.y])
    ra, rb = np.linalg.norm(c.a - p, axis=1), np.linalg.norm(c.b - p, axis=1)
    r0, r1 = np.minimum(ra, rb), np.maximum(ra, rb)
    inner = PLATEAU_FRACTION * radius

    def q(r):
        return np.clip((radius - r) / (radius - inner), 0.0, 1.0)

    keep = r0 < radius
    r0, r1 = r0[keep], r1[keep]
    sn, tau = sn_all[keep], tau_all[keep]
    # interaction: T constant per edge, q linear on the edge (its P1 interpolant),
    # int_{r0}^{r1} q / (2 sqrt r) dr exactly
    qa, qb = q(r0), q(r1)
    slope = (qb - qa) / (r1 - r0)
    s0, s1 = np.sqrt(r0), np.sqrt(r1)
    w = qa * (s1 - s0) + slope * ((r1 ** 1.5 - r0 ** 1.5) / 3.0 - r0 * (s1 - s0))
    I_1 = -c_open * float(np.sum(sn * w))
    I_2 = -c_open * float(np.sum(tau * w))
    # J, the contact's part (sigma_n + p, zero where open): a Stieltjes sum over the jumps at
    # the mid points (zero at the tip)
    pressure = getattr(sol.scene.cracks[tip.crack], "pressure", None)
    sn_c = sn_all + pressure_values(pressure, prof.s)
    rm = np.linalg.norm(c.mid - p, axis=1)
    order = np.argsort(rm)
    rm = np.concatenate([[0.0], rm[order]])
    jn = np.concatenate([[0.0], prof.normal_jump[order]])
    jt = np.concatenate([[0.0], prof.tangential_jump[order]])
    sn_m = np.concatenate([sn_c[order][:1], sn_c[order]])
    tau_m = np.concatenate([tau_all[order][:1], tau_all[order]])
    qm = q(0.5 * (rm[:-1] + rm[1:]))
    J = -float(np.sum(qm * (0.5 * (sn_m[:-1] + sn_m[1:]) * np.diff(jn) + 0.5 * (tau_m[:-1] + tau_m[1:]) * np.diff(jt))))
    if pressure is not None:
        # the pressure's part, int p q d[u].nu = -int [u].nu d(p q) (by parts: [u].nu = 0 at
        # the tip, q = 0 at R), with [u].nu at the mid points and p q at the edge ends
        near, far = np.where(ra <= rb, -0.5, 0.5), np.where(ra <= rb, 0.5, -0.5)
        pq = [pressure_values(pressure, prof.s + side * c.length) * q(r)
              for side, r in ((near, np.minimum(ra, rb)), (far, np.maximum(ra, rb)))]
        J -= float(np.sum(prof.normal_jump * (pq[1] - pq[0])))
    return J, I_1, I_2


def tip_closed(sol, tip) -> bool:
    """Whether the faces at `tip` touch: the crack sample nearest it is not "open" (the
    profiles' states, post.profile_states, from constraints.faces_closed: the one rule)."""
    prof = sol.profiles[tip.crack] if sol.profiles and tip.crack < len(sol.profiles) else None
    if prof is None or prof.state is None or not len(prof.state):
        return False
    i = int(np.argmin((np.asarray(prof.x) - tip.x) ** 2 + (np.asarray(prof.y) - tip.y) ** 2))
    return str(prof.state[i]) != "open"


def domain_integral(sol, tip: Tip, radius: float, body_force=SCENE) -> TipParameters:
    """K_I, K_II and G at `tip` from the domain integrals over the disc of radius `radius`.

    At a closed tip (`tip_closed`) under the contact crack model (with or without friction)
    K_I is reported as 0 and G as K_II^2 / E' (the crack cannot open there: the integral's
    K_I is its error about zero, kept in `K_I_raw`, J in `J`); under "free" the faces may
    pass through each other and the negative K_I is reported as computed.

    `body_force`: an NGSolve CoefficientFunction f, None for none, or SCENE (default) for
    the scene's own.
    """
    if not (isinstance(radius, (int, float)) and math.isfinite(radius) and radius > 0):
        raise InputError(f"radius = {radius!r}: must be a finite number > 0")
    mat = sol.scene.material
    E, nu, plane = mat.E, mat.nu, mat.plane
    mu = E / (2.0 * (1.0 + nu))
    kappa = kolosov(nu, plane)
    e_prime = effective_modulus(E, nu, plane)
    A = _compliance(E, nu, plane)
    if isinstance(body_force, str) and body_force == SCENE:
        f = sol.scene.body_force
        body_force = ngs.CF(tuple(float(v) for v in f)) if f is not None and any(v != 0.0 for v in f) else None

    *vals, I_T = _domain_terms(sol, tip, radius, A, kappa, mu, body_force)
    face = _face_terms(sol, tip, radius, face_opening_factor(kappa, mu))
    J, I_1, I_2 = np.asarray(vals) + np.asarray(face)  # the point-force field has no face term
    if not np.all(np.isfinite([J, I_1, I_2, I_T])):
        raise RuntimeError(f"tip {tip.label}: the domain integral gave non-finite values (radius {radius:g})")
    rings, n_el = _rings(sol, tip, radius)
    K_I, K_II, G, closed = 0.5 * e_prime * I_1, 0.5 * e_prime * I_2, float(J), tip_closed(sol, tip)
    if closed and sol.crack_model == "contact":  # the faces cannot open there ("free" keeps its K_I < 0)
        K_I, G = 0.0, K_II * K_II / e_prime
    return TipParameters(
        crack=tip.crack, end=tip.end, x=tip.x, y=tip.y, closed=closed, K_I_raw=0.5 * e_prime * I_1,
        K_I=K_I, K_II=K_II, G=G,
        radius=float(radius), rings=float(rings), J=float(J), I=(float(I_1), float(I_2)),
        face_J=float(face[0]), face_I=(float(face[1]), float(face[2])), elements=n_el,
        T=float(e_prime * I_T),
    )


def default_radius(tip: Tip) -> float:
    """R = DOMAIN_FRACTION times the tip's clearance."""
    return DOMAIN_FRACTION * tip.clearance


def tip_parameters(sol, radius: float | None = None, body_force=SCENE) -> list[TipParameters]:
    """K_I, K_II, G at every crack end inside the body of `sol` (crack by crack, first end then last).

    radius: the domain radius for every tip (default: `default_radius` of each); a radius
    beyond a tip's clearance is refused. Each result records the element rings across
    its annulus (`rings`); below MIN_RINGS the mesh is coarse at the tip and the values
    less accurate (`format_table` marks them; no warning: coarse study meshes are normal).
    """
    out = []
    for tip in crack_tips(sol.scene, sol.crack_mesh):
        R = default_radius(tip) if radius is None else radius
        if R >= tip.clearance:
            raise InputError(f"radius = {R!r}: must be below the clearance {tip.clearance:.4g} of tip "
                              f"{tip.label} (its distance to the boundary, other cracks, or its crack's kink)")
        res = domain_integral(sol, tip, R, body_force=body_force)
        out.append(res)
    return out


def format_table(tips: list[TipParameters]) -> str:
    """A small text table of the tips (what `ngcrack solve` prints); `rings` below MIN_RINGS marked coarse."""
    if not tips:
        return "tips: none inside the body"
    lines = [f"{'tip':<10} {'x':>10} {'y':>10} {'K_I':>11} {'K_II':>11} {'G':>11} {'R':>8} {'rings':>5}"]
    for t in tips:
        note = "  coarse: refine at the tip (tip_h)" if t.rings < MIN_RINGS else ""
        lines.append(f"{t.label:<10} {t.x:>10.4g} {t.y:>10.4g} {t.K_I:>11.4e} {t.K_II:>11.4e} {t.G:>11.4e} "
                     f"{t.radius:>8.3g} {t.rings:>5.1f}{note}")
    return "\n".join(lines)
