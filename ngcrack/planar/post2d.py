"""The post-processing of a planar solve, as one object the pipeline chooses once (`PLANE`).

The stages (`ngcrack.core.stages`) are dimension-free: what they do after the recovery that
depends on the body's dimension they ask of a post-processor (`PostProcessing` in
`ngcrack.core.discretization`). This is the 2D one: the crack profiles sampled at the crack
edges' mid points (`ngcrack.planar.post`), the consistent or lumped crack-face tractions, the
sampled KKT residuals, the tips' K_I, K_II, G (the 2D interaction integral,
`ngcrack.planar.tips`), the error estimate on triangles (`ngcrack.planar.estimate`) and the ParaView
files (`ngcrack.planar.vtk`). The estimate, the tips and the writer are imported when first used.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .post import (
    CrackProfile,
    component_forces,
    consistent_tractions,
    crack_profile,
    field_scales,
    kkt_residuals,
    lumped_traction,
    tributary_lengths,
)
from .scene.pressure import pressure_values


class PlanarPost:
    """The 2D post-processing of a solve (module docstring); stateless, one instance `PLANE`."""

    dimension = 2

    def profiles(self, disc, gf, fields: dict, friction: list[float] | None,
                 pressures: list | None = None) -> list[CrackProfile]:
        """One CrackProfile per crack from the solved GridFunction (no crack: an empty list);
        `pressures`: each crack's face pressure (scene.pressure fields), kept in the profiles."""
        if not disc.has_crack:
            return []
        cmesh = disc.crack_mesh
        profiles = []
        for k, crack in enumerate(cmesh.cracks):
            prof = crack_profile(cmesh, crack, disc.crack_jumps(gf, crack), fields["sigma"],
                                 two_sided=disc.two_sided_traction,
                                 friction=friction[k] if friction is not None else 0.0)
            if pressures is not None and pressures[k] is not None:
                prof = dataclasses.replace(prof, face_pressure=pressure_values(pressures[k], prof.s))
            profiles.append(prof)
        return profiles

    def scales(self, disc, fields: dict, profiles: list[CrackProfile]) -> tuple[float, float, float, float]:
        """(max |u|, max |sigma| over the triangles, the largest sampled jump |[u]|, the mean
        crack edge length): the scales the KKT residuals are measured against."""
        if not profiles:
            return 0.0, 0.0, 0.0, 0.0
        u_scale, sigma_scale = field_scales(disc.crack_mesh, fields["u"], fields["sigma"])
        jump = max(float(np.max(np.hypot(p.normal_jump, p.tangential_jump))) for p in profiles)
        length = float(np.mean(np.concatenate([c.length for c in disc.crack_mesh.cracks])))
        return u_scale, sigma_scale, jump, length

    def with_tractions(self, profiles: list[CrackProfile], disc, system, y: np.ndarray, G,
                       forces) -> list[CrackProfile]:
        """The profiles with the element's consistent (or, for the baselines, lumped nodal) crack tractions."""
        if not profiles or not any(c is not None for c in disc.traction_rows):
            return profiles
        cmesh = disc.crack_mesh
        lumped = disc.traction_rows[0] is not None and forces is not None  # nodal contact forces
        tractions = consistent_tractions(system, y, cmesh, skip=("normal_stress", "shear_stress") if lumped else ())
        if lumped:
            space = disc.fes.components[disc.jn]
            w = tributary_lengths(space, cmesh, G)
            normal = lumped_traction(space, cmesh, G, forces, w)
            # the nodal forces are the contact's; the faces carry the crack-face pressure besides
            normal = [nv - p.face_pressure for nv, p in zip(normal, profiles)]
            shear = lumped_traction(space, cmesh, G, component_forces(system, y, disc.traction_rows[1], G), w)
            tractions = [dict(t, normal_stress=n, shear_stress=q) for t, n, q in zip(tractions, normal, shear)]
        return [dataclasses.replace(p, **t) for p, t in zip(profiles, tractions)]

    def sampled_kkt(self, profiles: list[CrackProfile], u_scale: float, sigma_scale: float) -> dict:
        """The KKT residuals at the profiles' samples (`post.kkt_residuals`)."""
        return kkt_residuals(profiles, u_scale, sigma_scale)

    def tips(self, sol, body_force) -> list:
        """K_I, K_II, G at every crack end inside the body (`tips.tip_parameters`)."""
        from .tips import tip_parameters

        return tip_parameters(sol, body_force=body_force)

    def estimate(self, sol, loads, crack_model: str):
        """The error estimate (`estimate.estimate`; an InputError where the solve has none)."""
        from .estimate import estimate

        return estimate(sol, loads, crack_model)

    def save_vtk(self, sol, path, **kwargs):
        """Write the fields and the crack faces for ParaView (`vtk.save_vtk`)."""
        from .vtk import save_vtk

        return save_vtk(sol, path, **kwargs)


#: the one 2D post-processor
PLANE = PlanarPost()
