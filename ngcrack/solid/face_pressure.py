"""The crack-face pressure's term in the front's domain integrals (ngcrack.solid.front).

With a traction t on the crack faces the divergence theorem leaves a face integral
beside the volume one (the faces are flat and e1 lies in them):

    J   += - int_faces t_i u_i,1 q dA
    I_m += - int_faces t_i u^m_i,1 q dA        (the auxiliary fields are traction-free there)

For a uniform pressure p (t = p nu on the + face, -p nu on the - face) both are
-p int q d[u_2]/dx_1 dA over the crack's plane, [u_2] the opening ([u_2^m] the auxiliary
one: (8 / E') sqrt(r / 2 pi) for mode I, r the distance behind the front; none for modes
II and III). They are integrated by parts along x_1 (the opening is 0 on the front and
q is 0 at r = R):

    -p int q dw/dx_1 dA = p int w (dq/dx_1 + q kappa / (1 + kappa x_1)) dA,

kappa the front's curvature (the area element is (1 + kappa x_1) dx_1 ds). A pressure that
varies over the crack (`solid.loads`) adds its derivative along e_1 inside the integral:
-int q p dw/dx_1 dA = int w (p dq/dx_1 + q dp/dx_1 + p q kappa / (1 + kappa x_1)) dA, dp/dx_1 by a
central difference of DP_STEP_RTOL of the crack's size at each point. The opening w
is then the element's normal jump itself (the contact unknown, exact at the quadrature
points), not a derivative of the displacement; the quadrature is NGSolve's on the crack's
surface elements (curved to the front).
"""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..core.quadrature import FACE_TERM_ORDER

#: quadrature order on the crack faces (the auxiliary term has an integrable r^(-1/2): `ngcrack.core.quadrature`)
QUADRATURE_ORDER = FACE_TERM_ORDER
#: the step of the central difference of a varying pressure along e_1, over the crack's size
DP_STEP_RTOL = 1e-6


@dataclass
class FacePressure:
    """Quadrature points of one crack's faces near its front, with what the q-weighted sums need."""

    phi: np.ndarray  # the foot's parameter on the front
    r: np.ndarray  # distance behind the front (>= 0)
    w: np.ndarray  # quadrature weights
    opening: np.ndarray  # [u].nu of the solution
    aux: np.ndarray  # the mode I auxiliary opening (8 / E') sqrt(r / 2 pi)
    turning: np.ndarray  # kappa / (1 + kappa x_1)
    p: float | np.ndarray  # the pressure at the points
    dp: float | np.ndarray = 0.0  # its derivative along e_1

    def terms(self, q: np.ndarray, dq: np.ndarray) -> tuple[float, float]:
        """(the J term, the mode I interaction term) for q and dq/dx_1 at the points."""
        weight = self.w * (self.p * (dq + q * self.turning) + q * self.dp)
        return float(weight @ self.opening), float(weight @ self.aux)


def face_pressure(sol, index: int, geom, R: float, e_prime: float) -> FacePressure | None:
    """The crack's face points within R of its front, or None without a pressure on it."""
    from .loads import is_varying

    pressure = getattr(sol.scene.cracks[index], "pressure", 0.0)
    if not is_varying(pressure) and not float(pressure or 0.0):
        return None
    faces = sol.smesh.cracks[index]
    mesh = sol.smesh.mesh
    rule = ngs.IntegrationRule(ngs.TRIG, QUADRATURE_ORDER)
    k = len(rule.weights)
    n_bnd = mesh.GetNE(ngs.BND)
    mp = mesh.MapToAllElements(rule, ngs.BND).reshape(n_bnd, k)[faces.elements].ravel()
    xyz = np.column_stack([np.asarray(c(mp)).ravel() for c in (ngs.x, ngs.y, ngs.z)])
    jac = np.asarray(ngs.specialcf.JacobianMatrix(3, 2)(mp)).reshape(-1, 3, 2)
    area = np.linalg.norm(np.cross(jac[:, :, 0], jac[:, :, 1]), axis=1)
    w = area * np.tile(np.array(rule.weights), len(faces.elements))
    opening = np.asarray(sol.gf.components[sol.disc.jn](mp)).ravel()
    phi, x1, _, _ = geom.coordinates(xyz)
    r = np.maximum(-x1, 0.0)
    near = r < R
    aux = 8.0 / e_prime * np.sqrt(r[near] / (2 * np.pi))
    p, dp = pressure, 0.0
    if is_varying(pressure):
        pts = xyz[near]
        p = pressure.values(pts)[:, 0]
        e1 = np.asarray(geom.frame(phi[near])[0]).reshape(-1, 3)
        h = DP_STEP_RTOL * sol.scene.cracks[index].size
        dp = (pressure.values(pts + h * e1)[:, 0] - pressure.values(pts - h * e1)[:, 0]) / (2 * h)
    return FacePressure(phi[near], r[near], w[near], opening[near], aux, geom.turning(phi[near], x1[near]), p, dp)
