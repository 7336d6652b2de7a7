"""The T-stress at a crack tip by the interaction integral with a point-force auxiliary field.

Near a tip the stress is the singular field plus a constant stress T along the crack,
sigma_11 = T (in the tip frame of ngcrack.planar.tips: e1 out of the crack), plus terms that vanish
at the tip. T changes the hoop stress at a finite distance r_c (the generalized MTS
criterion, growth/criteria.py) and the constraint of the tip.

The auxiliary field (Kfouri 1986; Michell's wedge solution for a full plane slit along
theta = pi): a force f e1 applied to the tip of a semi-infinite crack,

    sigma_rr = -f cos(theta) / (pi r),  sigma_tt = sigma_rt = 0,

i.e. sigma_11 = -f cos^3 / (pi r), sigma_22 = -f cos sin^2 / (pi r), sigma_12 = -f cos^2 sin / (pi r);
its faces are traction free, and its displacement (mu the shear modulus, kappa Kolosov's)

    u_1 = -f (kappa + 1) / (8 pi mu) ln r - f / (4 pi mu) sin^2(theta)
    u_2 = -f (kappa - 1) / (8 pi mu) theta + f / (4 pi mu) sin(theta) cos(theta)

has a constant jump across the faces, so the crack-face term of the interaction integral
vanishes (contact and friction tractions do not enter). The interaction integral of the
solution with this field, in the domain form of ngcrack.planar.tips with the same weight q,

    I_T = int_A (sigma_ij du^aux_i/dx_1 + sigma^aux_ij du_i/dx_1 - sigma : eps^aux delta_1j) dq/dx_j dA
          - int_A f . du^aux/dx_1 q dA

picks out the constant term: the singular terms' cross products integrate to zero around the
tip, and T = E' I_T / f (E' = E / (1 - nu^2) in plane strain, E in plane stress). The
functions below are small and pure (numpy arrays in, arrays out): the auxiliary field with
f = 1, and the integrand on sampled fields, which ngcrack.planar.tips evaluates beside the Williams
fields on the same quadrature points.
"""

from __future__ import annotations

import math

import numpy as np

#: the auxiliary point force (its value cancels in T = E' I_T / f)
AUX_FORCE = 1.0


def point_force_stress(r, theta, f: float = AUX_FORCE):
    """(sigma_11, sigma_22, sigma_12) of the force f e1 at the tip of a crack along theta = pi."""
    c, s = np.cos(theta), np.sin(theta)
    k = -f * c / (math.pi * r)
    return k * c * c, k * s * s, k * c * s


def point_force_displacement(r, theta, kappa: float, mu: float, f: float = AUX_FORCE):
    """(u_1, u_2) of the point-force field (up to a rigid translation: ln r, not ln(r / d))."""
    s, c = np.sin(theta), np.cos(theta)
    b = f / (4.0 * math.pi * mu)
    return (-f * (kappa + 1.0) / (8.0 * math.pi * mu) * np.log(r) - b * s * s,
            -f * (kappa - 1.0) / (8.0 * math.pi * mu) * theta + b * s * c)


def point_force_dx1(r, theta, kappa: float, mu: float, f: float = AUX_FORCE):
    """(du_1/dx_1, du_2/dx_1) of the point-force field: d/dx_1 = cos d/dr - sin / r d/dtheta."""
    s, c = np.sin(theta), np.cos(theta)
    a = f * (kappa + 1.0) / (8.0 * math.pi * mu)
    b = f / (4.0 * math.pi * mu)
    e = f * (kappa - 1.0) / (8.0 * math.pi * mu)
    return c / r * (-a + 2.0 * b * s * s), s / r * (e - b * np.cos(2.0 * theta))


def interaction_integrand(sig, du1, gql, r, theta, compliance, kappa: float, mu: float):
    """The area integrand of I_T at the sample points, in the tip frame.

    sig (n, 2, 2) the solution's stress, du1 (n, 2) its du_i/dx_1, gql (n, 2) grad q;
    compliance has `apply` (stress -> strain, the material's A). Returns (integrand (n,),
    du^aux/dx_1 (n, 2)) (the latter for the body-force term).
    """
    s11, s22, s12 = point_force_stress(r, theta)
    sig_aux = np.stack([np.stack([s11, s12], -1), np.stack([s12, s22], -1)], -2)
    eps_aux = compliance.apply(sig_aux)
    dua = np.column_stack(point_force_dx1(r, theta, kappa, mu))
    sig_gq = (sig @ gql[:, :, None])[:, :, 0]
    val = ((dua * sig_gq).sum(axis=1) + (du1 * (sig_aux @ gql[:, :, None])[:, :, 0]).sum(axis=1)
           - (sig * eps_aux).sum(axis=(1, 2)) * gql[:, 0])
    return val, dua


def t_stress(I_T: float, e_prime: float, f: float = AUX_FORCE) -> float:
    """T = E' I_T / f."""
    return e_prime * I_T / f
