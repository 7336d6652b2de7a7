"""Matplotlib figures of a solution (matplotlib is imported lazily, headless-safe).

- isolines of sigma_nu = (sigma nu).nu, nu the first crack's normal ((0, 1) without a crack),
  as in the paper's Figures 7-8;
- the deformed body, each triangle moved by the locally post-processed displacement
  u*(x) = u_T + (A sigma + r W)(x - c_T) (the constitutive law grad u = A sigma + r W,
  W = [[0, -1], [1, 0]]), magnified so that the crack opening is visible.
"""

from __future__ import annotations

import numpy as np

#: the largest displacement of the deformed plot, as a fraction of the body's diameter
DEFORMED_FRACTION = 0.06


def _element_data(sol):
    mesh = sol.mesh
    verts = np.array([v.point for v in mesh.vertices])
    tris = np.array([[v.nr for v in el.vertices] for el in mesh.Elements()], dtype=int)
    cent = verts[tris].mean(axis=1)
    return verts, tris, cent


def sigma_nu_field(sol):
    """(vertices, triangles, vertex values of sigma_nu, nu): sigma_nu averaged at the vertices."""
    verts, tris, cent = _element_data(sol)
    nu = sol.crack_mesh.cracks[0].normal[0] if sol.crack_mesh.cracks else np.array([0.0, 1.0])
    mp = sol.mesh(cent[:, 0], cent[:, 1])
    sig = np.asarray(sol.sigma(mp)).reshape(-1, 2, 2)
    snn = np.einsum("i,eij,j->e", nu, sig, nu)
    vals = np.zeros(len(verts))
    cnt = np.zeros(len(verts))
    np.add.at(vals, tris.ravel(), np.repeat(snn, 3))
    np.add.at(cnt, tris.ravel(), 1.0)
    return verts, tris, vals / np.maximum(cnt, 1), nu


def element_displacements(sol) -> tuple[np.ndarray, np.ndarray]:
    """(corner points (ne, 3, 2), corner displacements (ne, 3, 2)) of u* per triangle."""
    from .materials import compliance

    verts, tris, cent = _element_data(sol)
    mp = sol.mesh(cent[:, 0], cent[:, 1])
    u = np.asarray(sol.u(mp)).reshape(-1, 2)
    sig = np.asarray(sol.sigma(mp)).reshape(-1, 2, 2)
    mat = sol.scene.material
    A = compliance(mat.E, mat.nu, mat.plane)
    tr = sig[:, 0, 0] + sig[:, 1, 1]
    grad = A.c_dev * sig - A.c_tr * tr[:, None, None] * np.eye(2)[None]
    if sol.rotation is not None:
        r = np.asarray(sol.rotation(mp)).reshape(-1)
        grad = grad + r[:, None, None] * np.array([[0.0, -1.0], [1.0, 0.0]])[None]
    corners = verts[tris]
    disp = u[:, None, :] + np.einsum("eij,ekj->eki", grad, corners - cent[:, None, :])
    return corners, disp


def plot_solution(sol, path=None, levels: int = 20):
    """Isolines of sigma_nu next to the magnified deformed body; saved to `path` if given."""
    import matplotlib

    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    from matplotlib.tri import Triangulation

    verts, tris, snn, nu = sigma_nu_field(sol)
    poly = np.asarray(sol.scene.polygon)
    width = np.ptp(poly[:, 0])
    height = np.ptp(poly[:, 1])
    horizontal = width >= height
    fig, axes = plt.subplots(2 if horizontal else 1, 1 if horizontal else 2,
                             figsize=(9, 6) if horizontal else (11, 5), constrained_layout=True)
    ax = axes[0]
    tri = Triangulation(verts[:, 0], verts[:, 1], tris)
    cf = ax.tricontourf(tri, snn, levels=levels, cmap="RdBu_r")
    ax.tricontour(tri, snn, levels=levels, colors="k", linewidths=0.3)
    fig.colorbar(cf, ax=ax, label=r"$\sigma_\nu$")
    ax.set_title(rf"$\sigma_\nu$, $\nu$ = ({nu[0] + 0.0:.2f}, {nu[1] + 0.0:.2f}) — {sol.scene.name}, {sol.element}")
    ax = axes[1]
    corners, disp = element_displacements(sol)
    diam = float(np.max(np.linalg.norm(poly[:, None] - poly[None], axis=2)))
    umax = float(np.max(np.linalg.norm(disp, axis=2)))
    scale = DEFORMED_FRACTION * diam / umax if umax > 0 else 0.0
    ax.add_collection(PolyCollection(corners, facecolors="none", edgecolors="0.85", linewidths=0.3))
    ax.add_collection(PolyCollection(corners + scale * disp, facecolors="tab:blue", edgecolors="tab:blue",
                                     linewidths=0.2, alpha=0.6))
    for pts in sol.crack_mesh.polylines:
        ax.plot(pts[:, 0], pts[:, 1], "r-", lw=1.0)
    ax.set_title(f"deformed body, displacement x {scale:.3g}")
    for a in axes:
        a.set_aspect("equal")
        a.autoscale_view()
    if path is not None:
        fig.savefig(path, dpi=150)
        plt.close(fig)
    return fig
