"""Constraints on the mean displacement of a held part of the boundary, and their reactions.

A pin or roller support holds the mean of u.d over its part of the boundary (a segment in 2D,
a patch in 3D). That mean is the work of the uniform traction d / size there, so its functional
l is the element's own load vector of that traction; the body supplies it
(`functional(disc, label, d)`: `ngcrack.planar.held_means.segment_functional`,
`ngcrack.solid.point_means.patch_functional`). On the condensed unknowns y (the columns of T)
the constraint's row is sign T^T (l + E^T l) on the free dofs, as `hybrid.condense` forms its F,
and `hybrid.eliminate` removes it. The reaction of a support is its constraints' multipliers,
read from the residual of the solved system on the support's unknowns (global ones: static
condensation is exact there), at the cost of a few sparse rows.
"""

from __future__ import annotations

from collections.abc import Callable

import ngsolve as ngs
import numpy as np

from .csr import CSR
from .hybrid import SUPPORT_RTOL

#: (disc, label, direction) -> l, with sign * l . x the mean of u.direction over the label's part of the boundary
Functional = Callable[[object, str, object], np.ndarray]


def constraint_rows(disc, held_mean: dict, T, free: np.ndarray, functional: Functional) -> tuple[np.ndarray, list]:
    """B (k x n) on the condensed unknowns y = the columns of T, and (label, direction) per row."""
    rows, names = [], []
    for label in sorted(held_mean):
        for d in held_mean[label]:
            vec = ngs.BaseVector(disc.fes.ndof)
            vec.FV().NumPy()[:] = functional(disc, label, d)
            vec.data += disc.a.harmonic_extension_trans * vec
            rows.append(disc.sign * (T.T @ vec.FV().NumPy()[free]))
            names.append((label, tuple(float(c) for c in d)))
    return np.array(rows).reshape(len(rows), T.shape[1]), names


def reactions(disc, gf: ngs.GridFunction, held_mean: dict, functional: Functional, force_unit: float = 1.0) -> dict[str, tuple]:
    """label -> the total force the support exerts on the body (one component per dimension): the
    multipliers R_d of its constraints from the residual sign (A x - f) = sum_d R_d l_d on the
    support's unknowns, times the system's force unit."""
    if not held_mean:
        return {}
    A = CSR.from_ngsolve(disc.a.mat)
    fmod = disc.f.vec.CreateVector()
    fmod.data = disc.f.vec
    fmod.data += disc.a.harmonic_extension_trans * disc.f.vec
    f, x = fmod.FV().NumPy(), gf.vec.FV().NumPy()
    out = {}
    for label, dirs in held_mean.items():
        L = np.column_stack([disc.sign * functional(disc, label, d) for d in dirs])
        sup = np.flatnonzero(np.abs(L).max(axis=1) > SUPPORT_RTOL * np.abs(L).max())
        r = disc.sign * (A[sup] @ x - f[sup])
        R, *_ = np.linalg.lstsq(L[sup], r, rcond=None)
        force = force_unit * sum(Rd * np.asarray(d, float) for Rd, d in zip(R, dirs))
        out[label] = tuple(float(c) for c in force)
    return out
