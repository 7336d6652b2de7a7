"""The 3D point supports' constraints on the mean displacement of their patches, and their reactions.

A pin holds the mean of u over its patch (a face of its own in the mesh, `solid.points`), a
roller the mean of u.n. The mean of u.d over a patch of area A is the work of the uniform
traction d / A there, so its functional is the element's own load vector of that traction
(`SolidDiscretization.traction_of`), as in 2D (`ngcrack.planar.held_means`): on the condensed
unknowns the row sign T^T (l + E^T l), eliminated by `core.hybrid.eliminate`. The reaction of
a support is its constraints' multipliers, read from the residual of the solved system on the
patch's unknowns, in the element's force unit (`force_unit`).
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from ..core import held_means as held


def patch_area(mesh: ngs.Mesh, label: str) -> float:
    """The area of the mesh faces labelled `label`."""
    return float(ngs.Integrate(ngs.CF(1.0), mesh, ngs.BND, definedon=mesh.Boundaries(label)))


def patch_functional(disc, label: str, direction) -> np.ndarray:
    """l with sign * l . x = the mean of u.direction over the patch, x a full solution vector."""
    mesh = disc.crack_mesh.mesh
    area = patch_area(mesh, label)
    if not area > 0:
        raise ValueError(f"point label {label!r}: no face of the mesh carries it")
    lf = ngs.LinearForm(disc.fes)
    lf += disc.traction_of(ngs.CF(tuple(float(c) / area for c in direction))) * ngs.ds(definedon=mesh.Boundaries(label))
    lf.Assemble()
    return lf.vec.FV().NumPy().copy()


def patch_mean(disc, gf: ngs.GridFunction, label: str, direction) -> float:
    """The mean of u.direction over the patch, of the solution `gf`."""
    return float(disc.sign * patch_functional(disc, label, direction) @ gf.vec.FV().NumPy())


def constraint_rows(disc, held_mean: dict, T, free: np.ndarray) -> tuple[np.ndarray, list]:
    """B (k x n) on the condensed unknowns y = the columns of T, and (label, direction) per row."""
    return held.constraint_rows(disc, held_mean, T, free, patch_functional)


def reactions(disc, gf: ngs.GridFunction, held_mean: dict) -> dict[str, tuple[float, float, float]]:
    """label -> the total force (Fx, Fy, Fz) the support exerts on the body, in the element's force unit
    (`ngcrack.core.held_means.reactions`)."""
    return held.reactions(disc, gf, held_mean, patch_functional, disc.force_unit)


def point_values(sol) -> dict[str, dict]:
    """label -> {"type", "force": (Fx, Fy, Fz), "displacement": (ux, uy, uz)} for every point condition of a
    solved 3D scene: the applied force of a force point, the reaction of a pin or roller; the patch's mean
    displacement."""
    from .points import held_directions

    scene, disc, gf = sol.scene, sol.disc, sol.gf
    react = reactions(disc, gf, held_directions(scene.points))
    out = {}
    for pc in scene.points:
        force = pc.value if pc.type == "force" else react[pc.label]
        out[pc.label] = {"type": pc.type, "force": tuple(float(c) for c in force),
                         "displacement": tuple(patch_mean(disc, gf, pc.label, e) for e in np.eye(3))}
    return out
