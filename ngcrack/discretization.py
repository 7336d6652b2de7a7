"""What an element family hands to the solver, independent of the body's dimension.

`Loads` (the data of one solve as NGSolve CoefficientFunctions keyed by boundary label),
`ElementTraits` (what the post-processing asks of an element) and `Discretization` (the
compound space, its assembled forms, which components are the facet trace and the crack
jumps, and the element's callbacks). The condensed system, the reduction, the crack
problem and the stages read an element only through these; the 2D families
(`ngcrack.elements`) and a 3D one build them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import ngsolve as ngs
import numpy as np

if TYPE_CHECKING:
    from .geometry import CrackMesh

__all__ = ["Discretization", "ElementTraits", "Loads"]


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
    #: evaluated on the crack's edges; ngcrack.crack_loads), for the cracks that carry one
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
    module outside `ngcrack.elements` tests an element's name).

    `gradient`: how the domain integral (`ngcrack.tips.displacement_gradient`) forms grad u from the fields:
    "rotation" (the strain of the stress, A sigma, plus the element's rotation field:
    PEERS, BDM), "skew" (A sigma plus the skew part of the field grad_u: TDNNS, whose
    displacement is only tangentially continuous) or "gradient" (grad_u itself: the
    displacement elements). `estimate`: the error estimate it has (`ngcrack.estimate`):
    "prager-synge" (a displacement reconstructed against its stress) or "zz-recovery"
    (a recovered stress), "" (none); `estimate_degree` the degree of the reconstruction or the
    recovery. `hybrid_traces`: the reconstructed displacement is averaged from the
    hybrid facet traces (else sampled from u). `estimate_note`: why its estimate is not
    a guaranteed bound ("" where the estimate's own notes say it).
    """

    gradient: str = "gradient"
    estimate: str = ""
    estimate_degree: int = 1
    hybrid_traces: bool = False
    estimate_note: str = ""


@dataclass
class Discretization:
    """What an element family hands to the condensed solver.

    `fes` is the compound space, `a` its bilinear form (assembled, condense=True) and
    `f` the load (assembled). `uhat` names the two facet components (x, y) of the
    displacement trace, `jn`/`jt` the crack jump components (None without a crack).
    `fields(gf)` returns the NGSolve CoefficientFunctions of the physical fields of a
    solution vector (keys "sigma", "u" and, where it exists, "rotation").
    `built` records what was assembled, for the solution's report. `definite` is False
    when the condensed matrix is a saddle point (the element pressures of the
    incompressible split are global unknowns). `sign` turns the condensed matrix into
    the (positive) stiffness: -1 for mixed forms, +1 for displacement forms.
    `boundary_values(gf, loads)` writes prescribed displacements into the fixed dofs of
    gf; `roller_pairs(labels)` lists (dof of ux, dof of uy, outward normal) for the dofs
    that the condensed solver must rotate to impose u.n = 0 (empty where the element
    imposes rollers itself). `tangential_jump(gf)`, where given, is a
    CoefficientFunction whose tangential trace on a crack edge is single-valued and
    equals [u].t (else the jt facet component is used). `constraint_map()`, where
    given, returns G (jn dofs -> values that must be >= 0) instead of the facet
    end-point map; `crack_jumps(gf, crack)` returns the (normal, tangential) jumps at
    the crack's mid points instead of the facet evaluation; `two_sided_traction`
    averages the crack-face traction of both sides (post-computed, discontinuous
    stresses); `fixed_dofs` are further dofs held at zero. `traction_rows` = (normal,
    shear): the compound components whose equations carry the crack's normal and
    tangential conditions, where the crack-face traction is to be taken from their
    residual (the variationally consistent traction, `post.consistent_tractions`)
    rather than sampled from sigma (None: sample sigma nu). `tangential`, where jt is
    None, names the component whose crack dofs carry [u].t (the reduced problem with
    friction keeps them; `tangential_jump` evaluates them).
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
    fields: Callable[[ngs.GridFunction], dict[str, ngs.CoefficientFunction]]
    built: list[str]
    boundary_values: Callable[[ngs.GridFunction, Loads], None]
    roller_pairs: Callable[[frozenset], list]
    definite: bool = True
    sign: float = -1.0
    tangential_jump: Callable[[ngs.GridFunction], ngs.CoefficientFunction] | None = None
    constraint_map: Callable[[], np.ndarray] | None = None
    crack_jumps: Callable[[ngs.GridFunction, object], tuple[np.ndarray, np.ndarray]] | None = None
    two_sided_traction: bool = False
    fixed_dofs: tuple[int, ...] = ()
    traction_rows: tuple[int | None, int | None] = (None, None)
    tangential: int | None = None
    #: traction(g): the element's integrand of a boundary traction g (what `load_vector`
    #: integrates over a loaded edge, with the element's sign): the work of g on u_hat is
    #: sign times its assembled form applied to the solution vector
    traction: Callable[[ngs.CoefficientFunction], ngs.CoefficientFunction] | None = None
    #: what the post-processing asks of the element (ElementTraits)
    traits: ElementTraits = field(default_factory=ElementTraits)
