"""K_I, K_II, K_III and G at points along every crack front: a domain interaction integral.

At a front point P with the local frame e1 (in the crack plane, normal to the front,
pointing away from the crack), e2 (the crack normal) and e3 = e1 x e2 (along the
front), the domain integrals over the tube around the front weighted by a q-function
that is 1 at P and falls to 0 along the front and away from it, with the extension
direction v = e1 of each point's foot on the front (v turns along a curved front),

    J   = int P_lj (q v_l),j dV / int q ds,       P = sigma_ij u_i,l - W delta_lj
    I_m = int [ P^m_lj (q v_l),j + (div P^m)_l q v_l ] dV / int q ds,
          P^m = sigma_ij u^m_i,l + sigma^m_ij u_i,l - sigma_ij eps^m_ij delta_lj

give G = J and, with the auxiliary fields of mode m with unit K (the 2D Williams fields of
ngcrack.planar.tips in plane strain for modes I and II, the antiplane field for mode III, each in
the frame of the point's foot and at its distance from the front),

    K_I = E' I_1 / 2,   K_II = E' I_2 / 2,   K_III = mu I_3,     E' = E / (1 - nu^2).

Along a curved front (curvature kappa, turn = kappa / (1 + kappa x1)) these auxiliary
fields are neither compatible nor in equilibrium, and div P^m is not zero: the auxiliary
displacement turns with the frame, so its gradient along e3 gains the column
turn (-u_3, 0, u_1), and div sigma^m = turn (s11 - s33, s12, 2 s13). Both are in I_m,
in closed form: div P^m = sigma^m_ij,j u_i,1 + sigma_ij (u^m_i,1j - eps^m_ij,1). Left out,
they bias the mode mix by O(kappa R): on a penny in shear K_II came 27% low and K_III 27%
high. (q v),j includes q turn e3 e3 (v turns towards e3).

q(x) = h(s) g(r): s the arc length of x's foot on the front from P, r the distance from
the front in the plane normal to it; h = cos^2(pi s / 2 L) for |s| < L (a smooth bump
of half-width L along the front), g = 1 for r < R/4 falling linearly to 0 at r = R.
Both and their gradients are evaluated exactly at the quadrature points (numpy; the
fields come from vectorized NGSolve evaluations). The gradient of u is that of 2D
TDNNS: the strain from the stress (A sigma) plus the skew part of grad u. R is at most
REACH_FRACTION of the front's reach (the distance inwards to the crack's medial axis), so
that every point of the tube has one foot on the front.

The curvature terms are weighted by q itself and grow as 1/r at the front, where a fixed Gauss rule on
the tetrahedra that touch it integrates them poorly (the pointwise K scattered by 0.5% along the default
penny's front and sat 0.3-0.75% low): on q's plateau they are blended from the tetrahedra into their
closed form for the front's asymptotic fields, linear in the point's K, and each point's three K solve
I = I(tetrahedra) + C I (`ngcrack.solid.front_near`, NEAR_DISC_H).

Each point's integral is the average of the pointwise K over h(s - s_k) / L; along a
closed front that average is undone mode by mode in the front's Fourier series (_unsmooth),
which removes its O(L^2 K'') bias where K varies (1% on a penny in shear at L = 2 front_h).

A polygon's front is taken side by side (SegmentFront): straight, so without curvature terms,
with points at least L + R from both corners (K at the corners is not computed).

A crack that crosses the body's faces has open fronts (ngcrack.solid.surface): an arc of a disc or
an ellipse (ArcFront) or a side cut by the surface (ClippedSide). Each point's bump is normalised by
its part on the front, ahead of the front the tube is squeezed to REACH_FRACTION of the body's
thickness beyond it (q's radial coordinate stretched along e1 > 0, so that q vanishes before the face
the crack does not cross, while the tube keeps its radius R across the crack plane and behind the
front: a tube capped as a whole shrank to about one element on a deep crack, whose deepest point then
moved from -5% to -11% against Newman-Raju when the mesh was refined; squeezed, it stays between
-7% and -10% at front_h a/6 to a/12 and at order 2), and the points start SURFACE_INSET L inside the surface; the front's end points on the
surface carry the values of the nearest point that far inside (surface_take). An embedded (closed)
front squeezes its tube the same way, point by point, where a face is nearer to the point than the
tube reaches (the point's clearance taken for the ligament): an embedded penny half its radius below
a face had its nearest point 4% below Sneddon's with the tube across the face, 4.6% above squeezed.

Approximations, stated: the crack-face traction terms of the 2D integral are left out,
which is exact for frictionless faces that are open (no traction) and for closed ones for
K_II and K_III (the same normal traction on both faces does no work in their auxiliary
fields); where the faces at P are closed K_I is set to 0 (it is the multiplier's, not the
field's).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
from scipy.spatial import cKDTree

from ..core.quadrature import DOMAIN_INTEGRAL_ORDER
from .curve import ClosedArcs
from .face_friction import face_friction
from .face_pressure import face_pressure
from .front_near import aux_fields, aux_strain, blend, curvature_integrand, near_matrix
from .surface import bump_inside, clearance, open_arcs, open_sides, surface_take

#: the tube radius R and the half-width L along the front, in front_h (the mesh size at the front)
TUBE_RADIUS_H, HALF_WIDTH_H = 4.0, 3.0
#: along a closed front the bump's half-width is at least this many times the front's least reach
#: (the penny's radius; b^2/a on an ellipse): the pointwise K of an order-1 mesh scatters by about
#: 1% from point to point, which a bump of 3 front_h passes on and a wider one averages out (the
#: default penny: K_I within -1.8% and +0.2% of Sneddon's at 3 front_h, -0.7% and -0.1% at 1.6 a);
#: the Fourier step (`_unsmooth`) restores the modes whose transfer is at least MIN_TRANSFER (on
#: the penny at 1.6 a: the cos and sin of the angle, 0.84), so a K that varies faster along the
#: front is smoothed there. BENCHMARKS section 21
BUMP_REACH = 1.6
#: on a closed front the tube's radius is this fraction of the reach (at most REACH_FRACTION, which
#: still caps it point by point) whatever front_h: a tube of
#: TUBE_RADIUS_H front_h shrinks with the mesh, so that the integral saw the same few elements
#: across the tube at every size and order 1 stalled (the penny's K_I 0.9% low on average at
#: front_h = 0.15a and 0.1a; 0.48% and 0.36% with the tube at 0.8a). BENCHMARKS section 21
CLOSED_TUBE_REACH = 0.8
#: q's plateau: g = 1 for r < PLATEAU_FRACTION * R
PLATEAU_FRACTION = 0.25
#: the tube radius at a front point is at most this fraction of the front's reach there (the
#: distance inwards to the crack's medial axis, at most the radius of curvature: b^2 / a at the
#: ends of an ellipse's major axis), so that every point of the tube has one foot on the front
REACH_FRACTION = 0.8
#: the curvature terms within r0 = NEAR_DISC_H front_h of the front (at most q's plateau, PLATEAU_FRACTION R) come
#: from the front's asymptotic fields in closed form, blended into the tetrahedra's quadrature
#: (`ngcrack.solid.front_near`); 0: from the tetrahedra alone, whose fixed Gauss rule meets their 1/r growth at the
#: front (the default penny's worst front point 0.71% off Sneddon; 0.14% with the disc). r0 shrinks with the mesh:
#: the asymptotic fields leave out the terms that do not grow at the front, whose part grows as r0^(3/2) (the disc
#: over the whole plateau, 0.2a on the penny, left K_I 0.4% high at front_h 0.1a). The penny's worst front point
#: at front_h 0.3a, 0.2a, 0.15a, 0.1a: 0.32, 0.14, 0.46, 0.41% at 1 front_h; 0.32, 0.14, 0.26, 0.14% at 1.5 (taken);
#: 0.32, 0.14, 0.26, 0.51% over the plateau. BENCHMARKS, "3D K tighter than 1%"
NEAR_DISC_H = 1.5
#: the modes whose disc comes from the closed form (0: K_I). Not K_II and K_III: on a penny at 60 degrees to a
#: compression (faces closed, sliding) the worst front point's K_II came 3.3% off Kassir-Sih with the disc, 0.8%
#: without (K_III 0.4% and 1.6%): the asymptotic fields leave out the normal stress on the closed faces
DISC_MODES = (0,)
#: undo the bump average along closed fronts (Fourier modes divided by the bump's transfer, at least MIN_TRANSFER)
DECONVOLVE, MIN_TRANSFER = True, 0.75
#: quadrature order on the tetrahedra in the tube of a closed front: two above the 2D domain integrals'
#: (`ngcrack.core.quadrature`): with the rule of order 6 the pointwise K of the default penny scattered by 0.5% along
#: the front, by 0.15% at 8 (BENCHMARKS, "3D K tighter than 1%")
QUADRATURE_ORDER = DOMAIN_INTEGRAL_ORDER + 2
#: ... and of an open front (a polygon's side, an arc ending on the body's surface): the built-in surface crack's
#: deepest point was -2.8% off Newman-Raju at order 6, -3.0% at 8 (their equation's stated accuracy is 5%)
OPEN_QUADRATURE_ORDER = DOMAIN_INTEGRAL_ORDER
#: angles of the table of arc lengths along a disc's or an ellipse's front
ARC_TABLE_POINTS = 2000


@dataclass
class FrontParameters:
    """The fracture parameters at points along one crack's front."""

    crack: int
    points: np.ndarray  # (n, 3)
    K_I: np.ndarray
    K_II: np.ndarray
    K_III: np.ndarray
    G: np.ndarray
    closed: np.ndarray  # the faces at the point are closed (K_I set to 0)
    angle: np.ndarray  # the front's parameter at each point (disc, ellipse: the angle; polygon: arc length)
    scaled_to_J: np.ndarray | None = None  # (n, 3): K_I, K_II, K_III scaled per point to G = J (a check)

    def to_json_dict(self) -> dict:
        return {"crack": self.crack, "points": self.points.tolist(), "K_I": self.K_I.tolist(),
                "K_II": self.K_II.tolist(), "K_III": self.K_III.tolist(), "G": self.G.tolist()}


# ------------------------------------------------------------------------ front geometry
class FrontGeometry(ClosedArcs):
    """The front of a disc or an ellipse: points, frames and the coordinates of space points."""

    def __init__(self, crack):
        self.crack = crack
        self.a, self.b = crack.semi_axes
        self.c = crack.center
        self.ea, self.eb, self.n = crack.e_a, crack.e_b, crack.normal
        self._tabulate(ARC_TABLE_POINTS)

    def point(self, phi):
        return self.c + np.multiply.outer(self.a * np.cos(phi), self.ea) + np.multiply.outer(self.b * np.sin(phi), self.eb)

    def frame(self, phi):
        """(e1, e2, e3) at the angle(s) phi: e1 outward in the plane, e2 the normal, e3 = e1 x e2."""
        t = np.multiply.outer(-self.a * np.sin(phi), self.ea) + np.multiply.outer(self.b * np.cos(phi), self.eb)
        t = t / np.linalg.norm(t, axis=-1, keepdims=True)
        e1 = np.cross(t, self.n)
        e2 = np.broadcast_to(self.n, e1.shape)
        return e1, e2, np.cross(e1, e2)

    def speed(self, phi):
        """ds/dphi on the front."""
        return np.hypot(self.a * np.sin(phi), self.b * np.cos(phi))

    def reach(self, phi):
        """The distance inwards from the front point to the crack's medial axis (the major axis' segment)."""
        return self.b / self.a * self.speed(phi)

    def coordinates(self, x: np.ndarray):
        """For points x (k, 3): the foot's angle phi, (x1, x2) in the frame there and d(phi)/d(x3)."""
        d = x - self.c
        u, v, z = d @ self.ea, d @ self.eb, d @ self.n
        phi = np.arctan2(v / self.b, u / self.a)
        if self.a != self.b:  # the nearest of 4096 front points, then Newton steps to the nearest point
            table = np.linspace(0.0, 2 * np.pi, 4096, endpoint=False)
            _, nearest = cKDTree(np.column_stack([self.a * np.cos(table), self.b * np.sin(table)])).query(
                np.column_stack([u, v]))
            phi = table[nearest]
            for _ in range(6):
                c, s = np.cos(phi), np.sin(phi)
                f = (self.a * c - u) * (-self.a * s) + (self.b * s - v) * (self.b * c)
                df = (self.a * s) ** 2 + (self.b * c) ** 2 + (self.a * c - u) * (-self.a * c) + (self.b * s - v) * (-self.b * s)
                phi = phi - f / np.where(np.abs(df) > 1e-14, df, 1e-14)
        e1, _, e3 = self.frame(phi)
        rel = x - self.point(phi)
        x1 = np.sum(rel * e1, axis=1)
        # curvature of the front: moving by x1 along e1 stretches the arc by (1 + kappa x1)
        kappa = self.a * self.b / self.speed(phi) ** 3
        dphi_dx3 = -1.0 / (self.speed(phi) * np.maximum(1.0 + kappa * x1, 1e-3))
        return phi, x1, z, dphi_dx3

    def turning(self, phi, x1):
        """d e1 / d x3 . e3 at the point: the rate at which the frame turns along the front there."""
        kappa = self.a * self.b / self.speed(phi) ** 3
        return kappa / np.maximum(1.0 + kappa * x1, 1e-3)  # used where 1 + kappa x1 >= 1/2 only


class SegmentFront:
    """One straight side of a polygon crack's front: the parameter phi is the arc length from its start.

    Its front points keep a distance of at least L + R (the q-function's half-width along the
    front plus the tube's radius) from both corners, where the straight-front auxiliary fields and
    the half-plane crack of the side do not hold; K at the corners is not computed.
    """

    periodic = None

    def __init__(self, crack, side: int):
        p = crack.points
        self.crack = crack
        self.A, B = p[side], p[(side + 1) % len(p)]
        self.length = float(np.linalg.norm(B - self.A))
        self.t = (B - self.A) / self.length
        self.n = crack.normal
        q = p - crack.center
        ccw = np.dot(np.sum(np.cross(q, np.roll(q, -1, axis=0)), axis=0), self.n) > 0
        self.e1 = np.cross(self.t, self.n) * (1.0 if ccw else -1.0)  # outward: away from the crack
        self.e3 = np.cross(self.e1, self.n)
        self.start = float(sum(np.linalg.norm(p[(k + 1) % len(p)] - p[k]) for k in range(side)))
        self._others = [(p[k], p[(k + 1) % len(p)]) for k in range(len(p)) if k != side]

    def point(self, phi):
        return self.A + np.multiply.outer(phi, self.t)

    def frame(self, phi):
        shape = np.shape(phi) + (3,)
        return (np.broadcast_to(self.e1, shape), np.broadcast_to(self.n, shape), np.broadcast_to(self.e3, shape))

    def speed(self, phi):
        return np.ones(np.shape(phi))

    def turning(self, phi, x1):
        return np.zeros(np.shape(phi))

    def reach(self, phi):
        """The distance from the point to the nearest other side of the polygon."""
        x = np.atleast_2d(self.point(phi))
        out = np.full(len(x), np.inf)
        for a, b in self._others:
            d = b - a
            t = np.clip((x - a) @ d / (d @ d), 0.0, 1.0)
            out = np.minimum(out, np.linalg.norm(x - (a + np.multiply.outer(t, d)), axis=1))
        return out.reshape(np.shape(phi))

    def coordinates(self, x: np.ndarray):
        d = x - self.A
        phi = d @ self.t
        return phi, d @ self.e1, d @ self.n, np.full(len(x), float(self.t @ self.e3))

    def arc(self, phi):
        return np.asarray(phi, dtype=float)

    def delta(self, s, s0):
        return s - s0

    def stations(self, h: float, L: float, R: float, n_points: int | None, spacing: float | None = None):
        """Points about 2 h apart (or `spacing`) at least L + R from both corners."""
        margin = L + R
        room = self.length - 2 * margin
        if room < 0:
            return np.zeros(0), np.zeros(0)
        n = max(1, int(room / (spacing or 2 * h)) + 1)
        s_i = margin + (np.arange(n) + 0.5) * room / n if n > 1 else np.array([0.5 * self.length])
        return s_i, s_i

    def within(self, phi, pad):
        return (phi > -pad) & (phi < self.length + pad)


# --------------------------------------------------------------------- the domain integral
def _tube_points(sol, geom: FrontGeometry, R: float, order: int):
    """Quadrature points of the tetrahedra within R (plus a cell) of the front, with weights."""
    mesh = sol.smesh.mesh
    pts = sol.smesh.points
    phi, x1, x2, _ = geom.coordinates(pts)
    dist = np.hypot(x1, x2)
    h = sol.smesh.sizes["front_h"]
    near = (dist < R + 2.0 * h) & geom.within(phi, R + 2.0 * h)
    tets = np.array([[v.nr for v in el.vertices] for el in mesh.Elements(ngs.VOL)])
    sel = np.flatnonzero(near[tets].any(axis=1))
    rule = ngs.IntegrationRule(ngs.TET, order)
    k = len(rule.weights)
    mp = mesh.MapToAllElements(rule, ngs.VOL).reshape(mesh.ne, k)[sel].ravel()
    jac = np.asarray(ngs.specialcf.JacobianMatrix(3)(mp)).reshape(-1, 3, 3)
    w = np.abs(np.linalg.det(jac)) * np.tile(np.array(rule.weights), len(sel))
    xyz = np.column_stack([np.asarray(c(mp)).ravel() for c in (ngs.x, ngs.y, ngs.z)])
    return mp, xyz, w


def front_parameters(sol, points: int | None = None) -> list[FrontParameters]:
    """K_I, K_II, K_III and G at `points` points along every front (default: one per 2 front_h, 8 at least)."""
    out = []
    for i, crack_faces in enumerate(sol.smesh.cracks):
        crack = crack_faces.crack
        if crack.shape == "polygon":
            sides = [f for f in (_one_front(sol, i, g, None) for g in open_sides(sol, crack, SegmentFront))
                     if f is not None]
            if sides:
                out.append(_joined(i, sides))
            continue
        arcs = [f for f in (_one_front(sol, i, g, points) for g in open_arcs(sol, front_geometry(crack)))
                if f is not None]  # (a disc, an ellipse or a curve: its arcs in the body, or its closed front)
        out.append(arcs[0] if len(arcs) == 1 else _joined(i, arcs))
    return out


def front_geometry(crack):
    """The geometry of a closed front: a disc's or an ellipse's, or a curve's (ngcrack.solid.curve)."""
    if crack.shape == "curve":
        from .curve import CurveFront

        return CurveFront(crack)
    return FrontGeometry(crack)


def _joined(index: int, sides: list[FrontParameters]) -> FrontParameters:
    """One polygon's sides as one front (angle: the arc length along the outline from its first point)."""
    cat = {key: np.concatenate([getattr(f, key) for f in sides]) for key in
           ("points", "K_I", "K_II", "K_III", "G", "closed", "angle", "scaled_to_J")}
    return FrontParameters(index, **cat)


def _one_front(sol, index: int, geom, n_points: int | None) -> FrontParameters | None:
    """The parameters at the stations of one closed front or one polygon side (None: no station)."""
    E, nu = sol.scene.material.E, sol.scene.material.nu
    mu = E / (2 * (1 + nu))
    e_prime = E / (1 - nu * nu)
    h = sol.smesh.sizes["front_h"]
    R, L = TUBE_RADIUS_H * h, HALF_WIDTH_H * h
    if geom.periodic:  # a closed front: the bump at least BUMP_REACH of the front's least reach, the tube
        reach = geom.reach(np.linspace(0.0, 2 * np.pi, 256))  # as wide as the reach allows (REACH_FRACTION)
        L = max(L, BUMP_REACH * float(np.min(reach)))
        R = max(R, CLOSED_TUBE_REACH * float(np.max(reach)))
    elif getattr(geom, "open_arc", False):  # an arc ending on the surface: the tube as on a closed front
        R = max(R, CLOSED_TUBE_REACH * float(np.max(geom.reach(np.linspace(geom.phi0, geom.phi1, 256)))))
    phi_i, s_i = geom.stations(h, L, R, n_points)
    n = len(phi_i)
    if n == 0:
        return None
    mp, xyz, w = _tube_points(sol, geom, R, QUADRATURE_ORDER if geom.periodic else OPEN_QUADRATURE_ORDER)
    phi, x1, x2, dphi_dx3 = geom.coordinates(xyz)
    s = geom.arc(phi)
    radius_i = np.minimum(R, REACH_FRACTION * geom.reach(phi_i))
    # ahead of the front the tube stops short of a face the crack does not cross (the ligament): there q's
    # radial coordinate is stretched by `ahead` (q = 0 from REACH_FRACTION of the ligament on)
    lig = getattr(geom, "ligament", None)
    if lig is None and geom.periodic:  # an embedded front: each point's distance to the nearest face
        lig = clearance(sol.scene.domain, geom.point(phi_i))
    ahead = np.ones(n) if lig is None else np.maximum(1.0, radius_i / (REACH_FRACTION * lig))
    # fields in the local frame of each point's foot
    e1, e2, e3 = geom.frame(phi)
    Q = np.stack([e1, e2, e3], axis=1)  # rows: local = Q global
    fields = sol.fields
    sigma = np.asarray(fields["sigma"](mp)).reshape(-1, 3, 3)
    sigma = 0.5 * (sigma + np.swapaxes(sigma, 1, 2))
    grad = np.asarray(fields["grad_u"](mp)).reshape(-1, 3, 3)
    c_dev, c_tr = (1 + nu) / E, nu / E
    eps = c_dev * sigma - c_tr * np.trace(sigma, axis1=1, axis2=2)[:, None, None] * np.eye(3)
    grad = eps + 0.5 * (grad - np.swapaxes(grad, 1, 2))
    QT = np.swapaxes(Q, 1, 2)
    sig_l = Q @ sigma @ QT
    grad_l = Q @ grad @ QT
    eps_l = 0.5 * (grad_l + np.swapaxes(grad_l, 1, 2))
    du1, du3 = grad_l[:, :, 0], grad_l[:, :, 2]
    turn = geom.turning(phi, x1)
    W = 0.5 * np.sum(sig_l * eps_l, axis=(1, 2))
    aux_sig, aux_du, aux_u = aux_fields(x1, x2, E, nu)
    aux_eps = aux_strain(aux_sig, E, nu)
    curv = curvature_integrand(sig_l, du1, du3, turn, aux_sig, aux_du, aux_u, aux_eps)  # (3, k): weighted by q

    faces = face_pressure(sol, index, geom, R, e_prime)  # None without a pressure on the faces
    s_f = None if faces is None else geom.arc(faces.phi)
    fric = face_friction(sol, index, geom, R, e_prime, mu)  # None without friction on the faces
    s_t = None if fric is None else geom.arc(fric.phi)
    K = np.zeros((n, 3))
    J = np.zeros(n)
    near = np.zeros((n, 3, 3))
    for k in range(n):
        ds = geom.delta(s, s_i[k])
        Rk = radius_i[k]
        inner = PLATEAU_FRACTION * Rk
        stretch = np.where(x1 > 0, ahead[k], 1.0)  # r_k = |(stretch x1, x2)|: the tube squeezed ahead of the front
        rk = np.hypot(stretch * x1, x2)
        g, dg = _radial(rk, inner, Rk)
        inside = (np.abs(ds) < L) & (rk < Rk)
        if not inside.any():
            continue
        hk = np.where(inside, np.cos(0.5 * np.pi * ds / L) ** 2, 0.0)
        dh = np.where(inside, -np.pi / (2 * L) * np.sin(np.pi * ds / L), 0.0)
        # grad q in the local frame: (dq/dx1, dq/dx2, dq/dx3)
        rs = np.where(rk > 0, rk, 1.0)
        gq = np.column_stack([hk * dg * stretch ** 2 * x1 / rs, hk * dg * x2 / rs, dh * g * geom.speed(phi) * dphi_dx3])
        sel = np.flatnonzero(inside)
        wk, gqk = w[sel], gq[sel]
        sig_gq = np.einsum("kij,kj->ki", sig_l[sel], gqk)
        # the virtual extension q e1 turns with the front: d(q e1)_k/dx_j has the extra
        # part q turn delta_k3 delta_j3 (e1 rotates towards e3 along the front)
        qt = hk[sel] * g[sel] * turn[sel]
        # next to the front (r < r0, on q's plateau) the curvature terms come from the disc's closed form (front_near)
        r0 = min(NEAR_DISC_H * h, inner) / max(float(ahead[k]), 1.0)
        cut = blend(np.hypot(x1[sel], x2[sel]), r0)
        J[k] = wk @ (np.sum(du1[sel] * sig_gq, axis=1) - W[sel] * gqk[:, 0]
                     + qt * (np.sum(sig_l[sel][:, :, 2] * du3[sel], axis=1) - W[sel]))
        for m in range(3):
            asg = np.einsum("kij,kj->ki", aux_sig[m, sel], gqk)
            K[k, m] = wk @ (np.sum(aux_du[m, sel] * sig_gq, axis=1) + np.sum(du1[sel] * asg, axis=1)
                            - np.sum(sig_l[sel] * aux_eps[m, sel], axis=(1, 2)) * gqk[:, 0]
                            + hk[sel] * g[sel] * (cut if m in DISC_MODES else 1.0) * curv[m, sel])
        modes = np.ix_(DISC_MODES, DISC_MODES)
        near[k][modes] = near_matrix(float(geom.turning(np.atleast_1d(phi_i[k]), np.zeros(1))[0]), r0, E, nu)[modes]
        if faces is not None:  # the crack-face pressure's term (ngcrack.solid.face_pressure)
            ds_f = geom.delta(s_f, s_i[k])
            h_f = np.where(np.abs(ds_f) < L, np.cos(0.5 * np.pi * ds_f / L) ** 2, 0.0)
            g_f, dg_f = _radial(faces.r, inner, Rk)
            dJ, dI = faces.terms(h_f * g_f, -h_f * dg_f)
            J[k] += dJ
            K[k, 0] += dI
        if fric is not None:  # the crack faces' friction in the shear modes (ngcrack.solid.face_friction)
            ds_t = geom.delta(s_t, s_i[k])
            q_t = np.where(np.abs(ds_t) < L, np.cos(0.5 * np.pi * ds_t / L) ** 2, 0.0)
            K[k, 1:] += fric.terms(q_t * _radial(fric.r, inner, Rk)[0])
        # int h ds = L for the cos^2 bump of half-width L; on a front ending on the surface, over its part on the front
        length = L if geom.periodic or not getattr(geom, "length", None) else float(bump_inside(s_i[k], L, geom.length))
        J[k] /= length
        K[k] = np.linalg.solve(np.eye(3) - near[k], K[k] / length)  # I = I(r >= r0) + C I
    if DECONVOLVE and geom.periodic:
        K, J = _unsmooth(K, geom.periodic, L), _unsmooth(J, geom.periodic, L)
    K_I, K_II, K_III = 0.5 * e_prime * K[:, 0], 0.5 * e_prime * K[:, 1], mu * K[:, 2]
    closed = _closed_at(sol, index, geom.point(phi_i))
    K_I = np.where(closed, 0.0, K_I)
    angle = phi_i if geom.periodic else geom.start + phi_i
    if getattr(geom, "surface_ends", None):  # the surface points carry the values a little inside (surface_take)
        kept, take = surface_take(s_i, geom.length, L, geom.surface_ends)
        K_I, K_II, K_III, J, closed = (v[take] for v in (K_I, K_II, K_III, J, closed))
        phi_i, angle = phi_i[kept], angle[kept]
    if fric is not None:  # less the K of the friction's uniform shear (ngcrack.solid.face_friction)
        K_II, K_III = fric.less_uniform(K_II, K_III, lambda uniform: _one_front(uniform, index, geom, n_points))
    return FrontParameters(index, geom.point(phi_i), K_I, K_II, K_III, J, closed, angle,
                           scaled_to_J=_scaled_to_J(K_I, K_II, K_III, J, closed, e_prime, mu))


def _scaled_to_J(K_I, K_II, K_III, J, closed, e_prime: float, mu: float) -> np.ndarray:
    """(n, 3): G = J; the K scaled per point to J's energy (`FrontParameters.scaled_to_J`, a check: both converge)."""
    J_K = (K_I ** 2 + K_II ** 2) / e_prime + K_III ** 2 / (2 * mu)
    scale = np.where((J_K > 0) & (J > 0) & ~closed, np.sqrt(np.maximum(J, 0.0) / np.where(J_K > 0, J_K, 1.0)), 1.0)
    return scale[:, None] * np.column_stack([K_I, K_II, K_III])


def _radial(r, inner: float, R: float):
    """q's radial factor g(r) (1 on the plateau r < inner, falling linearly to 0 at R) and dg/dr."""
    t = np.clip((np.asarray(r, dtype=float) - inner) / (R - inner), 0.0, 1.0)
    ramp = (t > 0.0) & (t < 1.0)
    return 1.0 - t, np.where(ramp, -1.0 / (R - inner), 0.0)


def bump_transfer(omega, L):
    """The factor by which the average over h(s) / L (h the cos^2 bump of half-width L) scales cos(omega s)."""
    x = np.asarray(omega, dtype=float) * L
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.sinc(x / np.pi) * np.pi ** 2 / (np.pi ** 2 - x * x)
    return np.where(np.abs(np.abs(x) - np.pi) < 1e-9, 0.5, out)


def _unsmooth(values, perimeter: float, L: float):
    """Undo the bump average along a closed front: values at n points equally spaced in arc length.

    Each point's domain integral is the average of the pointwise value over h(s - s_k) / L;
    in the Fourier modes of the front that multiplies mode m by bump_transfer(2 pi m / perimeter, L).
    Dividing by it (at most by 1 / MIN_TRANSFER, so that the point-to-point noise of the shortest
    modes is not amplified more) removes the O(L^2 K'') bias of the average where K varies.
    """
    n = values.shape[0]
    omega = 2.0 * np.pi * np.fft.fftfreq(n, d=perimeter / n)
    factor = 1.0 / np.maximum(bump_transfer(omega, L), MIN_TRANSFER)
    spec = np.fft.fft(values, axis=0)
    return np.real(np.fft.ifft(spec * factor.reshape((n,) + (1,) * (values.ndim - 1)), axis=0))


def _closed_at(sol, index: int, points: np.ndarray) -> np.ndarray:
    """True where the constraint points of the crack nearest to each front point are all closed."""
    if sol.contact is None:
        return np.zeros(len(points), dtype=bool)
    where, active = sol.crack_constraints(index)
    out = np.zeros(len(points), dtype=bool)
    for k, p in enumerate(points):
        near = np.argsort(np.linalg.norm(where - p, axis=1))[:6]
        out[k] = bool(active[near].all())
    return out


def sneddon_K_I(pressure: float, radius: float) -> float:
    """K_I of a penny crack of radius a under remote tension p in an infinite body: 2 p sqrt(a / pi)."""
    return 2.0 * pressure * math.sqrt(radius / math.pi)
