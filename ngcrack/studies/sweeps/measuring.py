"""The paper's way of measuring an error beside the sweeps' own: element means against element means.

`comparison_errors` gives, per mesh, the pointwise error against a fine reference (a
sweep's err_<q>), the error of the element means against the reference's, and the
error of the element means against the next finer mesh's (the paper's way).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ...core.errors import InputError
from .cases import MESH_OPTIONS, _mesh_stats
from .grid import _as_list, _check_sizes
from .quantities import QUANTITIES, ZERO_FIELD, Reference, sample_quantities


def element_means(nr: np.ndarray, weights: np.ndarray, values: np.ndarray, n_elements: int):
    """(areas, means): the L2 projection onto P0 of sampled fields, per coarse element.

    nr: the coarse element holding each sample point (its quadrature rule's points on a
    finer mesh), weights: their quadrature weights, values (N, k). The mean over element T
    is sum_{p in T} w_p v_p / |T|, |T| = sum_{p in T} w_p (exact for the finer mesh's
    piecewise fields up to the non-nestedness of the meshes).
    """
    area = np.bincount(nr, weights=weights, minlength=n_elements)
    sums = np.column_stack([np.bincount(nr, weights=weights * values[:, k], minlength=n_elements)
                            for k in range(values.shape[1])])
    return area, sums / np.where(area > 0, area, 1.0)[:, None]


def mean_errors(sol, fine: Reference) -> dict[str, float]:
    """err_<q>: relative L2 errors of the element means of `sol` against the element means
    of `fine` (both projected onto the triangles of `sol`'s mesh): || P0 q_h - P0 q_fine ||
    / || P0 q_fine ||, with the denominators of `Reference.denominators` (zero fields)."""
    mp = sol.mesh(fine.points[:, 0], fine.points[:, 1])
    nr = np.asarray(mp)["nr"].astype(int)
    if np.any(nr < 0):
        raise ValueError(f"{int(np.sum(nr < 0))} reference points lie outside the mesh of {sol.scene.name!r}")
    mine = sample_quantities(sol, fine.points, fine.normal)
    n = sol.mesh.ne
    area, m_h = element_means(nr, fine.weights, mine, n)
    _, m_f = element_means(nr, fine.weights, fine.values, n)
    den = np.sqrt(area @ m_f**2)
    group = [max(den[:2].max(), 1e-300)] * 2 + [max(den[2:].max(), 1e-300)] * 2
    den = np.maximum(den, ZERO_FIELD * np.array(group))
    rel = np.sqrt(area @ (m_h - m_f) ** 2) / den
    return {f"err_{q}": float(v) for q, v in zip(QUANTITIES, rel)}


def comparison_errors(scene, element: str, maxh: Sequence[float], reference_maxh: float, nu: float | None = None,
                      **solve_options):
    """One row per mesh: three ways of measuring the same solution's error.

    - `true_<q>`: the relative L2 error against the reference at `reference_maxh` (the
      sweep's err_<q>: pointwise, at the reference mesh's quadrature points);
    - `means_<q>`: element means against element means of that reference (both projected
      onto this mesh's triangles, `mean_errors`);
    - `next_<q>`: element means against element means of the next finer mesh of `maxh`
      (the finest against the reference): the paper's way, whose reference is a mesh only
      somewhat finer, sharing most of the discretization error.
    A mesh the element is refused on (sizing.check_thin_parts) gives no row; `coarse` marks
    the rows that warned (CoarseMeshWarning). Columns also: element, maxh, triangles, h, ndof.
    """
    import warnings

    import pandas as pd

    from ...core.solve import solve
    from ...planar.sizing import CoarseMeshWarning, check_thin_parts
    from ...scenes import resolve

    if isinstance(scene, (str, Path)):
        scene = resolve(scene)
    if nu is not None:
        scene = scene.with_(nu=nu)
    sizes = sorted(set(_check_sizes(_as_list(maxh, "maxh"), "maxh")), reverse=True)
    reference = Reference.from_solution(solve(scene, element=element, maxh=reference_maxh, **solve_options))
    rows, prev = [], None
    for h in sizes + [None]:
        sol, coarse = None, False
        if h is not None:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", CoarseMeshWarning)
                try:
                    check_thin_parts(scene, element, h, **{k: solve_options.get(k) for k in MESH_OPTIONS})
                    refused = False
                except InputError:
                    refused = True  # too coarse for this element: no row
                if not refused:
                    sol = solve(scene, element=element, maxh=h, **solve_options)
            coarse = any(issubclass(w.category, CoarseMeshWarning) for w in caught)
        fine = Reference.from_solution(sol) if sol is not None else reference
        if prev is not None:
            psol, prow = prev
            prow.update({k.replace("err_", "next_"): v for k, v in mean_errors(psol, fine).items()})
            rows.append(prow)
        if sol is not None:
            hmax, ne = _mesh_stats(sol)
            row = {"scene": scene.name, "element": element, "maxh": h, "triangles": ne, "h": hmax,
                   "ndof": int(sol.ndof["total"]), "coarse": coarse}
            row.update({k.replace("err_", "true_"): v for k, v in reference.errors(sol).items()})
            row.update({k.replace("err_", "means_"): v for k, v in mean_errors(sol, reference).items()})
            prev = (sol, row)
    cols = ["scene", "element", "maxh", "triangles", "h", "ndof", "coarse"] + [
        f"{kind}_{q}" for kind in ("true", "means", "next") for q in QUANTITIES]
    return pd.DataFrame(rows, columns=cols)
