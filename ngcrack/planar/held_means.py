"""Constraints on the mean displacement of a boundary segment: the scene's pin and roller points.

A pin holds the mean of u over its segment at zero (two constraints), a roller point
the mean of u.n (one). The mean of u.d over a label's edges of total length w is the
work of the uniform traction d / w there, so its functional is the element's own load
vector of that traction (`Discretization.traction`): for every element, mean(u.d) = l_d . x
on the full solution vector x (`segment_mean`), and on the condensed unknowns y the
row B = sign T^T (l + E^T l) restricted to the free dofs, as `hybrid.condense` forms its F.

The constraints B y = 0 are eliminated (`hybrid.eliminate`, dimension-free) by a change of basis, as the rollers are: k pivot
unknowns in the constraints' support (column-pivoted QR, never a crack unknown) are
expressed by the others, y = Z z with Z = [I; -B_P^-1 B_N] in the pivots' rows, and the
condensed system becomes Z^T K Z z = Z^T F: still symmetric, positive definite where K
is on the constrained space, with a few more entries in the pivots' rows. The
constraint's multiplier is the support's reaction, a uniform traction over the segment
(`reactions`: from the residual of the solved system on the segment's dofs).
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from ..core import held_means as held
from ..core.csr import CSR
from .geometry import boundary_region


def segment_length(mesh: ngs.Mesh, label: str) -> float:
    """The total length of the boundary edges labelled `label` in the mesh."""
    return float(ngs.Integrate(ngs.CF(1.0), mesh, ngs.BND, definedon=boundary_region(mesh, [label])))


def segment_functional(disc, label: str, direction) -> np.ndarray:
    """l with sign * l . x = the mean of u.direction over the label's edges, x a full solution vector."""
    mesh = disc.crack_mesh.mesh
    w = segment_length(mesh, label)
    if not w > 0:
        raise ValueError(f"boundary label {label!r}: no edge of the mesh carries it")
    g = ngs.CF((float(direction[0]) / w, float(direction[1]) / w))
    lf = ngs.LinearForm(disc.fes)
    lf += disc.traction(g) * ngs.ds(definedon=boundary_region(mesh, [label]))
    lf.Assemble()
    return lf.vec.FV().NumPy().copy()


def segment_mean(disc, gf: ngs.GridFunction, label: str, direction) -> float:
    """The mean of u.direction over the label's edges, of the solution `gf` (its work-conjugate value)."""
    return float(disc.sign * segment_functional(disc, label, direction) @ gf.vec.FV().NumPy())


def constraint_rows(disc, held_mean: dict, T: CSR, free: np.ndarray) -> tuple[np.ndarray, list]:
    """B (k x n) on the condensed unknowns y = the columns of T, and (label, direction) per row."""
    return held.constraint_rows(disc, held_mean, T, free, segment_functional)


def reactions(disc, gf: ngs.GridFunction, held_mean: dict) -> dict[str, tuple[float, float]]:
    """label -> the total force (Fx, Fy) the support exerts on the body, from the residual of the
    solved system on the segment's dofs (`ngcrack.core.held_means.reactions`)."""
    return held.reactions(disc, gf, held_mean, segment_functional)
