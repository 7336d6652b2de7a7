"""What NGSolve's webgui view of the explorer draws besides the stress field: the deformed
body, the crack faces as lines, the figure's colour limits and a caption naming the field.

The deformation is the figure's: each triangle moved by the locally post-processed
displacement u*(x) = u_T + (A sigma + r W)(x - c_T) (fields.drawn_displacements, here as
an NGSolve CoefficientFunction: on each triangle the affine map through its corners'
displacements, from piecewise constant functions), times the figure's magnification. The crack faces are the figure's too
(plots.crack_faces): two black polylines per crack, each moved by its own side's
displacement, so that an opening is a gap in the 3D view as in the figure. The colour map
is fixed at the figure's limits (robust percentiles, fields.color_limits) instead of the
webgui's own autoscale, which a crack tip's singular peak would set.
"""

from __future__ import annotations

import numpy as np


def deformation_cf(sol, scale: float):
    """scale * u* as a 3-vector CoefficientFunction (z = 0) on the solution's mesh: on each
    triangle the affine map through its corners' displacements (plots.element_displacements),
    held as piecewise constants (centroid, value there, gradient)."""
    import ngsolve as ngs

    from .fields import drawn_displacements

    corners, disp = drawn_displacements(sol)  # the figure's: less the rigid motion that rollers leave free
    cent = corners.mean(axis=1)
    uc = disp.mean(axis=1)  # (affine on the triangle: its mean over the corners is its value at the centroid)
    M = np.stack([corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]], axis=2)  # columns: edges
    D = np.stack([disp[:, 1] - disp[:, 0], disp[:, 2] - disp[:, 0]], axis=2)
    G = D @ np.linalg.inv(M)  # (ne, 2, 2): the displacement's gradient on each triangle
    order = _element_order(sol)
    fes = ngs.L2(sol.mesh, order=0)

    def piecewise(values):
        gf = ngs.GridFunction(fes)
        gf.vec.FV().NumPy()[:] = values[order]
        return gf

    cx, cy, ux, uy = (piecewise(v) for v in (cent[:, 0], cent[:, 1], uc[:, 0], uc[:, 1]))
    g = [[piecewise(G[:, i, j]) for j in range(2)] for i in range(2)]
    dx, dy = ngs.x - cx, ngs.y - cy
    return ngs.CF((scale * (ux + g[0][0] * dx + g[0][1] * dy), scale * (uy + g[1][0] * dx + g[1][1] * dy), 0))


def _element_order(sol) -> np.ndarray:
    """For each NGSolve element (in its numbering) the crack mesh's triangle: the same order
    where the mesh was built from it (checked by the centroids), else found by point search."""
    cm = sol.crack_mesh
    cent = cm.points[cm.triangles].mean(axis=1)
    mp = sol.mesh(cent[:, 0], cent[:, 1])
    nr = np.asarray(mp["nr"], dtype=int)
    order = np.empty(len(nr), dtype=int)
    order[nr] = np.arange(len(nr))
    return order


def crack_lines(sol, scale: float) -> list[dict]:
    """The crack faces as webgui line objects (segments as point pairs), moved by `scale` times
    their own side's displacement."""
    from ...planar.plots import crack_faces
    from .fields import drawn_displacements

    corners, disp = drawn_displacements(sol)
    position = []
    for f in crack_faces(sol, corners, disp):
        for side in ("plus", "minus"):
            p = f["points"] + scale * f[side]
            for a, b in zip(p[:-1], p[1:]):
                position += [float(a[0]), float(a[1]), 0.0, float(b[0]), float(b[1]), 0.0]
    return [{"type": "lines", "position": position, "name": "crack faces", "color": "#000000"}] if position else []


def webgui_scene(sol, scale: float, clim, name: str) -> dict:
    """The keywords of `widget.show_webgui` for the figure's view of `sol`: deformation,
    crack-face lines, colour limits `clim` (low, high) and a caption."""
    kw = {"deformation": deformation_cf(sol, scale) if scale else None, "objects": crack_lines(sol, scale)}
    if clim is not None:
        lo, hi = float(clim[0]), float(clim[1])
        kw["settings"] = {"Colormap": {"autoscale": False, "min": lo, "max": hi, "ncolors": 24}}
    kw["caption"] = (f"{name}: colours from {lo:.3g} to {hi:.3g} (the figure's limits), " if clim is not None
                     else f"{name}: ") + (f"displacements × {scale:.3g}, " if scale else "") + \
        "black lines: the crack faces"
    return kw


def display_webgui(scene, height: str = "420px") -> None:
    """Display a webgui scene made with ``ngsolve.webgui.Draw(..., show=False)`` (a 2D field, or
    ``ngcrack.solid.view.webgui_scene(sol).draw(show=False)``): in webgui_jupyter_widgets' widget
    where it is installed (its JavaScript ships with it: the view works offline, in JupyterLab
    as in the classic notebook), else through the scene's own ``Draw`` (which loads its
    JavaScript from a CDN, and shows an empty space without the network)."""
    from IPython.display import display

    try:
        import ipywidgets
        from webgui_jupyter_widgets import WebGuiWidget
    except ImportError:
        scene.Draw()
        return
    widget = WebGuiWidget(layout=ipywidgets.Layout(width="100%", height=height))
    widget.value = scene.GetData()
    display(widget)
