"""The 3D solution in JupyterLab: the body and the crack faces for ``ngsolve.webgui.Draw``.

``webgui_scene(sol)`` returns what ``Draw`` takes: a coefficient function on the mesh's
surface, the regions to draw and the keyword arguments. The crack faces carry the
quantity as colour (``"opening"``: the normal jump [u].nu, the contact unknown of either
element; ``"sliding"``: |[u]_t|, from the + side's jump copy); the body is drawn as its
edges (its outline and the crack fronts), and with ``body=True`` also as its outer
faces, coloured 0, to be cut open with the viewer's clipping plane (the settings turn it
on through the crack's plane). ``draw(sol)`` calls ``Draw`` with them. Nothing here
changes the solution; the quantity's name is checked before anything is built.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import ngsolve as ngs
import numpy as np

from ..core.errors import InputError

#: the quantities shown on the crack faces
QUANTITIES = ("opening", "sliding")


@dataclass
class WebguiScene:
    """The arguments of ``ngsolve.webgui.Draw(cf, regions, **kwargs)``."""

    cf: ngs.CoefficientFunction
    regions: list
    kwargs: dict = field(default_factory=dict)

    def draw(self, **changes):
        """Draw it (``ngsolve.webgui.Draw``); `changes` update the keyword arguments."""
        from ngsolve.webgui import Draw

        return Draw(self.cf, self.regions, **{**self.kwargs, **changes})


def _crack_cf(sol, quantity: str, crack) -> ngs.CoefficientFunction:
    """The quantity on one crack's faces: the normal jump, or the tangential part of the jump copy."""
    if quantity == "opening":
        return sol.gf.components[sol.disc.jn]
    jump = sol.fields["jump"]
    nu = ngs.CF(tuple(float(x) for x in crack.normal))
    vt = jump - (jump * nu) * nu
    return ngs.sqrt(vt * vt)


def webgui_scene(sol, quantity: str = "opening", body: bool = False) -> WebguiScene:
    """The crack faces coloured by `quantity` (QUANTITIES) and the body's edges; `body`: its faces too."""
    if quantity not in QUANTITIES:
        raise InputError(f"quantity = {quantity!r}: allowed values are {', '.join(QUANTITIES)}")
    if not isinstance(body, bool):
        raise InputError(f"body = {body!r}: must be True or False")
    mesh = sol.smesh.mesh
    cracks = [c.label for c in sol.smesh.cracks]
    if not cracks:
        raise InputError("the scene has no crack: there are no crack faces to draw")
    cf = mesh.BoundaryCF({c.label: _crack_cf(sol, quantity, c) for c in sol.smesh.cracks}, default=0.0)
    labels = "|".join(cracks) if not body else ".*"
    regions = [mesh.Boundaries(labels), mesh.BBoundaries(".*")]
    values = sol.normal_jumps() if quantity == "opening" else sol.tangential_jumps()
    top = float(np.max(values)) if len(values) else 0.0
    kwargs = {"min": 0.0, "max": top if top > 0 else 1.0, "autoscale": False,
              "settings": {"Colormap": {"ncolors": 32}, "Objects": {"Edges": True, "Wireframe": False}}}
    if body:
        c = sol.smesh.cracks[0]
        nrm = [float(x) for x in c.normal]
        kwargs["clipping"] = {"x": nrm[0], "y": nrm[1], "z": nrm[2], "dist": float(np.dot(nrm, c.crack.center))}
    return WebguiScene(cf, regions, kwargs)


def draw(sol, quantity: str = "opening", body: bool = False, **kwargs):
    """``ngsolve.webgui.Draw`` of webgui_scene(sol, quantity, body); `kwargs` update Draw's arguments."""
    return webgui_scene(sol, quantity, body).draw(**kwargs)
