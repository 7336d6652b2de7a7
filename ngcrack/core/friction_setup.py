"""The crack problem with friction built from a solve's reduction.

`crack_problem` assembles the `friction.CrackProblem` that the solvers of friction.py
take from the reduction and what the element says of its crack: the constraint points
with their quadrature weights (`Discretization.friction_points`) and the map from the
tangential jumps to those points (`Discretization.tangential_point_map`).
"""

from __future__ import annotations

import numpy as np

from .friction import CrackProblem


def crack_problem(red, disc, crack_mesh, normal_map: np.ndarray, mu_per_crack, threshold=None) -> CrackProblem:
    """The CrackProblem of a reduction with tangential unknowns (`condense(..., tangential=True)`).

    `normal_map` is Gn (the QP's constraint map of the normal jumps), `mu_per_crack`
    the Coulomb coefficients, `threshold` an optional Tresca threshold per crack
    (stress units) instead of Coulomb.
    """
    system = red.system
    if system.n_normal is None:
        raise ValueError("crack_problem: the reduction has no tangential unknowns (condense with tangential=True)")
    crack_of, s_of, weight = disc.friction_points(crack_mesh)
    Gt_full = disc.tangential_point_map(crack_mesh, normal_map)
    cols = np.asarray(system.tangential_dofs, dtype=int)
    sub = Gt_full[:, cols]
    rows = np.flatnonzero(np.any(sub != 0.0, axis=1))
    if len(rows) != len(cols):
        raise ValueError(f"friction: element {disc.element!r}: the tangential jumps held at zero leave a non-square "
                         "map to the constraint points")
    mu = np.asarray(mu_per_crack, dtype=float)[np.maximum(crack_of, 0)]
    g = None
    if threshold is not None:
        g = np.asarray(threshold, dtype=float)[np.maximum(crack_of, 0)]
    return CrackProblem(S=red.S, b=red.b, Gn=np.asarray(normal_map, dtype=float), Gt=sub[rows], t_point=rows,
                        weights=weight, mu=mu, threshold=g, crack=crack_of, s=s_of)


