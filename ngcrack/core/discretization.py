"""What an element family hands to the solver, independent of the body's dimension.

`Loads` (the data of one solve as NGSolve CoefficientFunctions keyed by boundary label),
`ElementTraits` (what the post-processing asks of an element), `Discretization` (the
base class of every element family: the compound space, its assembled forms, which
components are the facet trace and the crack jumps, and the methods the stages call)
and `PostProcessing` (what the stages ask of the post-processing of the body's
dimension). The condensed system, the reduction, the crack problem and the stages read
an element only through these; the 2D families (`ngcrack.planar.elements`) and the 3D one
(`ngcrack.solid.element`) implement them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Protocol

import ngsolve as ngs
import numpy as np

from .errors import InputError

if TYPE_CHECKING:
    from ..planar.geometry import CrackMesh

__all__ = ["Discretization", "ElementTraits", "Loads", "PostProcessing", "refuse"]


@dataclass
class Loads:
    """Data of one solve, as NGSolve CoefficientFunctions keyed by boundary label.

    Labels missing from every dict are traction-free. `body_force` None means none.
    """

    body_force: ngs.CoefficientFunction | None = None
    traction: dict[str, ngs.CoefficientFunction] = field(default_factory=dict)
    displacement: dict[str, ngs.CoefficientFunction] = field(default_factory=dict)
    clamped: frozenset[str] = frozenset()
    roller: frozenset[str] = frozenset()
    #: crack index -> the pressure p on its faces (a CoefficientFunction of position,
    #: evaluated on the crack's edges; ngcrack.planar.crack_loads), for the cracks that carry one
    crack_pressure: dict[int, ngs.CoefficientFunction] = field(default_factory=dict)
    #: label -> unit directions d along which the mean of u.d over the label's edges is held
    #: at zero (the pin and roller points of the scene; hybrid.condense imposes them)
    held_mean: dict[str, tuple[tuple[float, float], ...]] = field(default_factory=dict)

    @property
    def dirichlet_labels(self) -> frozenset[str]:
        """The labels whose displacement is prescribed (clamped or given)."""
        return frozenset(self.clamped) | frozenset(self.displacement)


@dataclass(frozen=True)
class ElementTraits:
    """What the post-processing asks of an element, declared by the element (so that no
    module outside `ngcrack.planar.elements` tests an element's name).

    `gradient`: how the domain integral (`ngcrack.planar.tips.displacement_gradient`) forms grad u from the fields:
    "rotation" (the strain of the stress, A sigma, plus the element's rotation field:
    PEERS, BDM), "skew" (A sigma plus the skew part of the field grad_u: TDNNS, whose
    displacement is only tangentially continuous) or "gradient" (grad_u itself: the
    displacement elements). `estimate`: the error estimate it has (`ngcrack.planar.estimate`):
    "prager-synge" (a displacement reconstructed against its stress) or "zz-recovery"
    (a recovered stress), "" (none); `estimate_degree` the degree of the reconstruction or the
    recovery. `hybrid_traces`: the reconstructed displacement is averaged from the
    hybrid facet traces (else sampled from u). `estimate_note`: why its estimate is not
    a guaranteed bound ("" where the estimate's own notes say it). `incompressible`: the
    element solves nu = 1/2 in plane strain (a displacement element does not: lambda is
    infinite); a request it cannot solve is refused before any meshing (`check_material`).
    """

    gradient: str = "gradient"
    estimate: str = ""
    estimate_degree: int = 1
    hybrid_traces: bool = False
    estimate_note: str = ""
    incompressible: bool = True

    def check_material(self, element: str, material, allowed) -> None:
        """Refuse plane strain at nu = 1/2 for an element that cannot solve it (InputError
        naming material.nu and the elements that can, `allowed`)."""
        if not self.incompressible and material.plane == "strain" and material.nu == 0.5:
            raise InputError(f"material.nu = 0.5: element {element!r} needs nu < 1/2 in plane strain (lambda is "
                             f"infinite); allowed elements at nu = 0.5: {', '.join(allowed)}")


@dataclass(eq=False)
class Discretization:
    """What an element family hands to the condensed solver: a base class whose methods
    every family implements (`ngcrack.planar.elements` in 2D, `ngcrack.solid.element` in 3D).

    Data. `fes` is the compound space, `a` its bilinear form (assembled, condense=True)
    and `f` the load (assembled). `uhat` names the two facet components of the
    displacement trace, `jn`/`jt` the crack jump components (None without a crack; `jt`
    None where the tangential jump is not a facet component). `built` records what was
    assembled, for the solution's report. `definite` is False when the condensed matrix
    is a saddle point (the element pressures of the incompressible split are global
    unknowns). `sign` turns the condensed matrix into the (positive) stiffness: -1 for
    mixed forms, +1 for displacement forms. `two_sided_traction` averages the crack-face
    traction of both sides (post-computed, discontinuous stresses); `fixed_dofs` are
    further dofs held at zero. `traction_rows` = (normal, shear): the compound
    components whose equations carry the crack's normal and tangential conditions,
    where the crack-face traction is to be taken from their residual (the variationally
    consistent traction) rather than sampled from sigma (None: sample sigma nu).
    `tangential` names the component whose crack dofs carry [u].t (the reduced problem
    with friction keeps them). `nodal_constraints`: the constraint points are nodes of
    the jump space (the displacement baselines) rather than equispaced points of each
    crack edge.

    Methods (each family implements them; none is optional): `fields(gf)` the
    CoefficientFunctions of the physical fields of a solution vector (keys "sigma",
    "u", "grad_u" and, where it exists, "rotation"); `boundary_values(gf, loads)` writes
    prescribed displacements into the fixed dofs of gf; `roller_pairs(labels)` the
    (dof of ux, dof of uy, outward normal) that the condensed solver must rotate to
    impose u.n = 0 (empty where the element imposes rollers itself); `traction(g)` the
    element's integrand of a boundary traction g (the work of g on u_hat is sign times
    its assembled form applied to the solution vector); `constraint_map()` G (jn dofs ->
    the values that must be >= 0); `constraint_positions()` (crack index, arc length) of
    every constrained value; `crack_jumps(gf, crack)` the (normal, tangential) jumps at
    the crack's sample points; `tangential_jump(gf)` a CoefficientFunction whose
    tangential trace on the crack equals [u].t; `assemble_load()` assembles `f` again
    after its loads' Parameters changed; `held_mean_rows(held_mean, T, free)` the
    rows of the pin and roller points' mean constraints. What an element cannot do is
    refused with an InputError naming the option (`refuse`), never signalled by a missing
    method.
    """

    element: str
    crack_mesh: CrackMesh
    fes: ngs.FESpace
    a: ngs.BilinearForm
    f: ngs.LinearForm
    uhat: tuple[int, int]
    jn: int | None
    jt: int | None
    facet_order: int
    built: list[str]
    definite: bool = True
    sign: float = -1.0
    two_sided_traction: bool = False
    fixed_dofs: tuple[int, ...] = ()
    traction_rows: tuple[int | None, int | None] = (None, None)
    tangential: int | None = None
    nodal_constraints: bool = False
    #: what the post-processing asks of the element (ElementTraits)
    traits: ElementTraits = field(default_factory=ElementTraits)

    @property
    def has_crack(self) -> bool:
        """Whether the mesh has crack unknowns (a crack jump component)."""
        return self.jn is not None

    def fields(self, gf: ngs.GridFunction) -> dict[str, ngs.CoefficientFunction]:
        """The physical fields of the solution vector `gf` ("sigma", "u", "grad_u", ...)."""
        raise NotImplementedError(f"{type(self).__name__}.fields")

    def boundary_values(self, gf: ngs.GridFunction, loads: Loads) -> None:
        """Write the prescribed displacements of `loads` into the fixed dofs of `gf`."""
        raise NotImplementedError(f"{type(self).__name__}.boundary_values")

    def roller_pairs(self, labels) -> list:
        """(dof of ux, dof of uy, outward unit normal) of the dofs on the roller `labels`
        that the condensed solver rotates (none: the element imposes u.n = 0 itself)."""
        return []

    def traction(self, g: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        """The element's integrand of a boundary traction `g` (what its load vector integrates)."""
        raise NotImplementedError(f"{type(self).__name__}.traction")

    def constraint_map(self) -> np.ndarray:
        """G: the normal jump dofs -> the values that must be >= 0 (square)."""
        raise NotImplementedError(f"{type(self).__name__}.constraint_map")

    def constraint_positions(self) -> tuple[np.ndarray, np.ndarray]:
        """(crack index, arc length or position label) of every constrained value (G's rows)."""
        raise NotImplementedError(f"{type(self).__name__}.constraint_positions")

    def crack_jumps(self, gf: ngs.GridFunction, crack) -> tuple[np.ndarray, np.ndarray]:
        """([u].nu, [u].t) at the sample points of `crack` (one of crack_mesh.cracks)."""
        raise NotImplementedError(f"{type(self).__name__}.crack_jumps")

    def tangential_jump(self, gf: ngs.GridFunction) -> ngs.CoefficientFunction:
        """A vector CoefficientFunction whose tangential component on the crack is [u].t."""
        raise NotImplementedError(f"{type(self).__name__}.tangential_jump")

    def friction_points(self, crack_mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(crack index, arc length, quadrature weight) of every constrained value (G's rows):
        where the Coulomb law is imposed."""
        raise refuse("friction", "> 0", "0", f"element {self.element!r} has no friction points")

    def tangential_point_map(self, crack_mesh, normal_map: np.ndarray) -> np.ndarray:
        """Gt: the tangential jump dofs -> the tangential jumps at the constraint points."""
        raise refuse("friction", "> 0", "0", f"element {self.element!r} has no tangential jumps")

    def assemble_load(self) -> None:
        """Assemble the load vector `f` again (its loads' Parameters changed)."""
        self.f.Assemble()

    def held_mean_rows(self, held_mean: dict, T, free: np.ndarray) -> tuple[np.ndarray, list]:
        """B (k x n) on the condensed unknowns (the columns of T) holding the means of
        `Loads.held_mean` at zero, and (label, direction) per row."""
        raise refuse("points", sorted(held_mean), "none", f"element {self.element!r} has no point supports")


def refuse(option: str, value, allowed, why: str = "") -> InputError:
    """The one refusal of a capability an element (or a dimension) lacks: an InputError
    naming the option, its value and the allowed values (raise it)."""
    allowed = ", ".join(map(str, allowed)) if not isinstance(allowed, str) else allowed
    return InputError(f"{option} = {value!r}: {why + '; ' if why else ''}allowed values are {allowed}")


class PostProcessing(Protocol):
    """What the stages ask, after the recovery, of the post-processing of the body's
    dimension (chosen once per pipeline; `ngcrack.planar.post2d.PLANE` in 2D). `profiles` the
    crack-face samples (one record per crack, a dataclass of arrays), `scales` (max |u|,
    max |sigma|, the largest sampled jump, a crack length) for the KKT residuals,
    `with_tractions` the profiles with the element's crack-face tractions,
    `sampled_kkt` the KKT residuals at the samples, `tips` the fracture parameters,
    `estimate` the error estimate (an InputError where the solve has none), `save_vtk`
    the ParaView files."""

    dimension: int

    def profiles(self, disc: Discretization, gf, fields: dict, friction, pressures) -> list:
        """One record of crack-face samples per crack (none without a crack)."""

    def scales(self, disc: Discretization, fields: dict, profiles: list) -> tuple[float, float, float, float]:
        """(max |u|, max |sigma|, the largest sampled jump, a crack length)."""

    def with_tractions(self, profiles: list, disc: Discretization, system, y, G, forces) -> list:
        """The profiles with the element's crack-face tractions."""

    def sampled_kkt(self, profiles: list, u_scale: float, sigma_scale: float) -> dict:
        """The KKT residuals at the profiles' samples."""

    def tips(self, sol, body_force) -> list:
        """The fracture parameters of a solved `sol`."""

    def estimate(self, sol, loads: Loads, crack_model: str):
        """The error estimate of `sol` (an InputError where it has none)."""

    def save_vtk(self, sol, path, **kwargs):
        """Write the fields and the crack faces for ParaView."""
