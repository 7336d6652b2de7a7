"""The volume between a 3D crack's faces: the integral of the normal jump over them.

The jump is the element's own normal jump (P1 per crack face in TDNNS order 1) evaluated at a
quadrature rule of order VOLUME_RULE_ORDER on every face as NGSolve maps it (the mesh is curved
to second order near the crack, so the circle's area is not lost to flat triangles).
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

#: the order of the triangle rule on each crack face (the jump is linear there, the map quadratic)
VOLUME_RULE_ORDER = 4


def jump_at_faces(sol, crack: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(quadrature weights, points (n x 3), normal jump) on the faces of crack `crack`."""
    faces = sol.smesh.cracks[crack]
    mesh = sol.smesh.mesh
    rule = ngs.IntegrationRule(ngs.TRIG, VOLUME_RULE_ORDER)
    k = len(rule.weights)
    mp = mesh.MapToAllElements(rule, ngs.BND).reshape(mesh.GetNE(ngs.BND), k)[faces.elements].ravel()
    jac = np.asarray(ngs.specialcf.JacobianMatrix(3, 2)(mp)).reshape(-1, 3, 2)
    area = np.linalg.norm(np.cross(jac[:, :, 0], jac[:, :, 1]), axis=1)
    w = area * np.tile(np.array(rule.weights), len(faces.elements))
    xyz = np.column_stack([np.asarray(c(mp)).ravel() for c in (ngs.x, ngs.y, ngs.z)])
    return w, xyz, np.asarray(sol.gf.components[sol.disc.jn](mp)).ravel()


def crack_volume(sol, crack: int) -> float:
    """The volume between the faces of crack `crack`: the integral of its normal jump over its faces."""
    w, _, jump = jump_at_faces(sol, crack)
    return float(w @ jump)
