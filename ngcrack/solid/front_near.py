"""The curvature terms of the front's interaction integral, and their part next to the front in closed form.

Along a curved front the interaction integral (`ngcrack.solid.front`) has terms weighted by q itself,
not by its gradient: the auxiliary fields turn with the frame (rate `turn` = kappa / (1 + kappa x1)),
so the integrand gains

    turn (sigma^a_i3 u_i,3 + sigma_i3 u^a_i,3 - sigma : eps^a) + sigma_ij (u^a_i,1j - eps^a_ij,1) + (div sigma^a)_i u_i,1

(`curvature_integrand`). Next to the front both fields grow as r^(-1/2), so these terms grow as 1/r:
integrable, but a fixed Gauss rule on the tetrahedra that touch the front integrates them with an
error of the order of their whole part there, which on the default penny is about 6% of K_I within
one front_h (r < front_h) and scatters from point to point with the tetrahedra. There, on the
plateau of q (q = 1), the fields are the front's asymptotic ones, linear in the point's K: the part
of the integral over the disc r < r0 around the front is, per unit length of front,

    I_m(near) = sum_n C_mn(kappa, r0) I_n,    I_n = K_n / c_n   (c = E'/2, E'/2, mu),

`near_matrix` integrates C on a polar grid of the disc (the same integrand with the unit Williams
fields of mode n in place of the solution's), and the front's integral takes the disc's part from
it instead of from the tetrahedra (`ngcrack.solid.front.NEAR_DISC_H`).
"""

from __future__ import annotations

import numpy as np

from ..planar.tips import williams_displacement, williams_dx1, williams_stress

#: Gauss points of the polar grid over the disc next to the front: radial, angular
DISC_RADIAL_POINTS, DISC_ANGULAR_POINTS = 24, 96


def aux_fields(x1, x2, E, nu):
    """Per point: the auxiliary stresses (3, k, 3, 3), du/dx1 and u (3, k, 3) of modes I, II, III (K = 1), local frame."""
    mu = E / (2 * (1 + nu))
    kappa = 3 - 4 * nu
    r = np.hypot(x1, x2)
    th = np.arctan2(x2, x1)
    k = len(r)
    sig = np.zeros((3, k, 3, 3))
    du = np.zeros((3, k, 3))
    u = np.zeros((3, k, 3))
    for m, mode in enumerate((1, 2)):
        s11, s22, s12 = williams_stress(r, th, mode)
        sig[m, :, 0, 0], sig[m, :, 1, 1], sig[m, :, 0, 1], sig[m, :, 1, 0] = s11, s22, s12, s12
        sig[m, :, 2, 2] = nu * (s11 + s22)  # plane strain along the front
        d1, d2 = williams_dx1(r, th, mode, kappa, mu)
        du[m, :, 0], du[m, :, 1] = d1, d2
        u[m, :, 0], u[m, :, 1] = williams_displacement(r, th, mode, kappa, mu)
    s = 1.0 / np.sqrt(2 * np.pi * r)
    sig[2, :, 0, 2] = sig[2, :, 2, 0] = -s * np.sin(th / 2)
    sig[2, :, 1, 2] = sig[2, :, 2, 1] = s * np.cos(th / 2)
    du[2, :, 2] = -s * np.sin(th / 2) / mu
    u[2, :, 2] = 2.0 / mu * np.sqrt(r / (2 * np.pi)) * np.sin(th / 2)
    return sig, du, u


def aux_strain(aux_sig, E, nu):
    """The auxiliary strains of the auxiliary stresses (3, k, 3, 3)."""
    c_dev, c_tr = (1 + nu) / E, nu / E
    return c_dev * aux_sig - c_tr * np.trace(aux_sig, axis1=-2, axis2=-1)[..., None, None] * np.eye(3)


def curvature_integrand(sig, du1, du3, turn, aux_sig, aux_du, aux_u, aux_eps):
    """(3, k): the terms of mode m's integrand weighted by q (module docstring), at k points of the local frame.

    sig (k, 3, 3), du1 and du3 (k, 3): the solution's stress and u_i,1, u_i,3; turn (k,); the auxiliary fields (3, k, ...).
    The auxiliary displacement turns with the frame: its gradient along e3 gains the column T = turn (-u_3, 0, u_1);
    the strain is kept the 2D one, so the auxiliary fields are neither compatible nor in equilibrium."""
    aux_du3 = np.zeros_like(aux_du)
    aux_du3[:, :, 2] = turn * aux_u[:, :, 0]
    aux_du3[:, :, 0] = -turn * aux_u[:, :, 2]
    # sigma_ij (u^a_i,1j - eps^a_ij,1) = sigma_13 T_13,1 + sigma_33 T_33,1 (d turn / d x1 = -turn^2)
    incompat = (sig[None, :, 0, 2] * -(turn * aux_du[:, :, 2] - turn ** 2 * aux_u[:, :, 2])
                + sig[None, :, 2, 2] * (turn * aux_du[:, :, 0] - turn ** 2 * aux_u[:, :, 0]))
    # div sigma^a = turn (s11 - s33, s12, 2 s13) (the 2D fields are in 2D equilibrium), times u_i,1
    noneq = turn * ((aux_sig[:, :, 0, 0] - aux_sig[:, :, 2, 2]) * du1[None, :, 0] + aux_sig[:, :, 0, 1] * du1[None, :, 1]
                    + 2.0 * aux_sig[:, :, 0, 2] * du1[None, :, 2])
    # the virtual extension q e1 turns with the front: d(q e1)_k/dx_j has the part q turn delta_k3 delta_j3
    turned = (np.sum(aux_sig[:, :, :, 2] * du3[None], axis=2) + np.sum(sig[None, :, :, 2] * aux_du3, axis=2)
              - np.sum(sig[None] * aux_eps, axis=(2, 3)))
    return turn * turned + incompat + noneq


def blend(r, r0: float):
    """The tetrahedra's weight on the curvature terms at the distance r from the front: 0 at the front rising to 1 at
    r0 (the cubic smoothstep of r / r0; 1 everywhere for r0 = 0); the closed form takes the rest (`near_matrix`)."""
    if r0 <= 0.0:
        return np.ones(np.shape(r))
    t = np.clip(np.asarray(r, dtype=float) / r0, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def near_matrix(kappa: float, r0: float, E: float, nu: float) -> np.ndarray:
    """C (3, 3): mode m's integral of `curvature_integrand` over the disc r < r0 around the front (per unit length,
    q = 1) when the solution is mode n's asymptotic field with I_n = 1 (K_n = c_n)."""
    if kappa == 0.0 or r0 <= 0.0:
        return np.zeros((3, 3))
    mu = E / (2 * (1 + nu))
    c = np.array([0.5 * E / (1 - nu * nu), 0.5 * E / (1 - nu * nu), mu])
    xr, wr = np.polynomial.legendre.leggauss(DISC_RADIAL_POINTS)
    xt, wt = np.polynomial.legendre.leggauss(DISC_ANGULAR_POINTS)
    r, th = np.meshgrid(0.5 * r0 * (xr + 1.0), np.pi * xt, indexing="ij")
    w = np.outer(0.5 * r0 * wr, np.pi * wt).ravel() * r.ravel() * (1.0 - blend(r.ravel(), r0))
    x1, x2 = (r * np.cos(th)).ravel(), (r * np.sin(th)).ravel()
    stretch = 1.0 + kappa * x1  # the volume element (1 + kappa x1) dA ds
    turn = kappa / np.maximum(stretch, 1e-3)
    aux_sig, aux_du, aux_u = aux_fields(x1, x2, E, nu)
    aux_eps = aux_strain(aux_sig, E, nu)
    C = np.zeros((3, 3))
    for n in range(3):  # the solution: mode n's field with K_n = c_n, turning with the frame as the auxiliary one
        du3 = np.zeros((len(x1), 3))
        du3[:, 2], du3[:, 0] = turn * aux_u[n, :, 0], -turn * aux_u[n, :, 2]
        f = curvature_integrand(aux_sig[n], aux_du[n], du3, turn, aux_sig, aux_du, aux_u, aux_eps)
        C[:, n] = c[n] * (f @ (w * stretch))
    return C
