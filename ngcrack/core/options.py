"""The options of a solve, checked once: one validated value that every entry passes on.

`SolveOptions` holds everything `solve` accepts besides the scene and the loads: the
element and its order, the mesh sizes, the crack model, the solvers and their options,
the size budget and the adaptive tolerance. It is built (and so checked) once, by
`nc.solve`, `nc.sweep`, the explorer and the command line alike, and handed on
unchanged: no module re-checks another's options or reads another's signature.

What can be checked without a scene is checked when the value is made (types, ranges,
the names of elements, solvers and methods); `check_for(scene)` adds what depends on the
scene (friction with the chosen solver, adaptivity with its material). Numbers may be
Python or numpy numbers; booleans are not numbers here.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

from ..planar.path_sizes import PathGrading, check_path_grading
from .contact import DEFAULT_SOLVER, NATIVE_SOLVERS
from .element_names import check_element
from .errors import InputError
from .fields import is_number
from .friction import DEFAULT_FRICTION_METHOD, FRICTION_METHODS, check_friction_solver
from .hybrid import Factorization
from .schur import SCHUR_METHODS

#: the default element family: measured against the finite bodies' converged answers at
#: the scenes' default meshes, tdnns is 4 (opening) to 10 (K) times more accurate than bdm
#: for about 1.25 times its CPU time (README, "Which element when")
DEFAULT_ELEMENT = "tdnns"

#: how the crack faces interact: unilateral contact, traction-free, or bonded in the normal direction
CRACK_MODELS = ("contact", "free", "bonded")

#: the QP solvers cvxpy offers that can solve the crack problem (when installed)
CVXPY_QP_SOLVERS = ("CLARABEL", "OSQP", "SCS", "ECOS", "CVXOPT", "PIQP", "PROXQP", "MOSEK", "GUROBI", "CPLEX",
                    "QPALM", "DAQP", "HIGHS")


#: hp meshes (ngcrack.planar.hp): the ratio of consecutive layer radii, its allowed range, and the
#: most layers (beyond about 10 the innermost triangles reach round-off relative to the body)
HP_SIGMA = 0.2
HP_SIGMA_RANGE = (0.05, 0.7)
HP_MAX_LAYERS = 12

#: `accuracy`, the relative error of K asked for along the crack fronts (3D scenes): the values a solve honours.
#: Not below 0.005: the penny's worst front point is 0.14-0.41% off Sneddon from front_h 0.3a to 0.1a with order 1
#: and does not fall further with front_h (the front integral's bias, 0.1-0.4%; BENCHMARKS, "3D K tighter than 1%")
ACCURACY_RANGE = (0.005, 0.5)


def qp_solvers() -> tuple[str, ...]:
    """The QP solvers available here: the native ones and cvxpy's installed QP solvers."""
    import cvxpy as cp

    return NATIVE_SOLVERS + tuple(s.lower() for s in cp.installed_solvers() if s in CVXPY_QP_SOLVERS)


def positive_size(name: str, value) -> float | None:
    """None, or a finite number > 0 as a float (the error names `name`)."""
    if value is None:
        return None
    if not is_number(value) or not (math.isfinite(float(value)) and float(value) > 0):
        raise InputError(f"{name} = {value!r}: must be a finite number > 0")
    return float(value)


def whole_number(name: str, value, minimum: int = 1) -> int | None:
    """None, or an integer >= minimum (whole-number floats such as 2e5 accepted, 2.5 refused)."""
    if value is None:
        return None
    if not is_number(value) or not math.isfinite(float(value)) or float(value) != int(value) or int(value) < minimum:
        raise InputError(f"{name} = {value!r}: must be a whole number >= {minimum}")
    return int(value)


def check_accuracy(value) -> float:
    """`accuracy` as a float in ACCURACY_RANGE, else an InputError naming it and the allowed values."""
    lo, hi = ACCURACY_RANGE
    if not is_number(value) or not (math.isfinite(float(value)) and lo <= float(value) <= hi):
        raise InputError(f"accuracy = {value!r}: the relative error of K along the crack fronts must be a number in "
                         f"[{lo:g}, {hi:g}] (0.005: the default sizes; a tighter K along a 3D front is not reached yet)")
    return float(value)


def _choice(name: str, value, allowed) -> str:
    if not isinstance(value, str) or value not in allowed:
        raise InputError(f"{name} = {value!r}: allowed values are {', '.join(allowed)}")
    return value


@dataclass(frozen=True)
class SolveOptions:
    """Everything a solve is asked for besides the scene and its loads, validated on creation.

    element: "tdnns" (default, DEFAULT_ELEMENT), "bdm", "peers", "h1p1" or "h1p2"; order: the polynomial
    order of a family that has several (tdnns 1-3; None: the family's default). maxh,
    tip_h, crack_h, grading: override the scene's [mesh] values (sizes > 0, grading in
    (0, 1]). crack_model: "contact", "free" or "bonded". qp_solver: "pdas", "uzawa" or an
    installed cvxpy QP solver; qp_options go to it unchanged. linear_solver: "auto",
    "pardiso", "superlu", "cholespy" or "ngsolve"; schur: "auto", "factor", "blocked" or
    "columns". friction_method: "fixed-point" or "newton"; tangential: keep the tangential
    jumps in the crack problem (None: where a crack has friction). condition: estimate
    condition numbers. max_dof: the largest number of unknowns (None: the size guard's
    default ceiling and the memory the process may use). adapt: a relative error
    tolerance in (0, 1) for adaptive refinement (None: one solve). path_grading: the
    crack's mesh size grows from crack_h with the distance from the nearest crack end at this
    rate, or a `path_sizes.PathGrading` (None, the default: crack_h all along; growth
    grades its path by default, `ngcrack.studies.growth.checks.GROWTH_PATH_GRADING`).

    3D scenes: front_h the mesh size at the crack fronts (> 0); accuracy: the relative error of K
    asked for along the fronts, in ACCURACY_RANGE, which sets front_h and crack_h from the measured
    rate of K's error (`ngcrack.solid.sizing.accuracy_sizes`; not with front_h or crack_h); fronts: compute the fracture
    parameters along the fronts; front_points: how many points along each front (None: one per
    two front sizes). estimate: compute the error estimate (None: in 2D when first asked for,
    in 3D not at all; True: during the solve; False: never). preconditioner: the distributed
    solve's preconditioner (under mpiexec only; ngcrack.distributed). What a body cannot take
    is refused by its body before any meshing (`check_for`).
    """

    element: str = DEFAULT_ELEMENT
    order: int | None = None
    maxh: float | None = None
    tip_h: float | None = None
    crack_h: float | None = None
    grading: float | None = None
    crack_model: str = "contact"
    qp_solver: str = DEFAULT_SOLVER
    qp_options: dict | None = field(default=None, compare=False)
    linear_solver: str = "auto"
    schur: str = "auto"
    friction_method: str = DEFAULT_FRICTION_METHOD
    tangential: bool | None = None
    condition: bool = False
    max_dof: int | None = None
    adapt: float | None = None
    hp: int | None = None
    hp_sigma: float | None = None
    path_grading: PathGrading | float | None = None
    front_h: float | None = None
    accuracy: float | None = None
    fronts: bool = True
    front_points: int | None = None
    estimate: bool | None = None
    preconditioner: str | None = None

    def __post_init__(self):
        set_ = object.__setattr__
        set_(self, "order", check_element(self.element, self.order))
        for name in ("maxh", "tip_h", "crack_h", "front_h"):
            set_(self, name, positive_size(name, getattr(self, name)))
        for name in ("fronts", "condition"):
            if not isinstance(getattr(self, name), bool):
                raise InputError(f"{name} = {getattr(self, name)!r}: must be True or False")
        if self.estimate is not None and not isinstance(self.estimate, bool):
            raise InputError(f"estimate = {self.estimate!r}: must be None (when asked for), True or False")
        set_(self, "front_points", whole_number("front_points", self.front_points, minimum=3))
        if self.accuracy is not None:
            set_(self, "accuracy", check_accuracy(self.accuracy))
            given = [k for k in ("front_h", "crack_h") if getattr(self, k) is not None]
            if given:
                raise InputError(f"accuracy = {self.accuracy:g} sets front_h and crack_h; give accuracy or {given[0]}, "
                                 "not both")
        if self.preconditioner is not None and not isinstance(self.preconditioner, str):
            raise InputError(f"preconditioner = {self.preconditioner!r}: must be None or the name of a distributed "
                             "solve's preconditioner")
        if self.grading is not None:
            g = self.grading
            if not is_number(g) or not 0 < float(g) <= 1:
                raise InputError(f"grading = {g!r}: must lie in (0, 1] (netgen's default is 0.3)")
            set_(self, "grading", float(g))
        set_(self, "crack_model", _choice("crack_model", self.crack_model, CRACK_MODELS))
        set_(self, "linear_solver", _choice("linear_solver", self.linear_solver, Factorization.BACKENDS))
        set_(self, "schur", _choice("schur", self.schur, SCHUR_METHODS))
        set_(self, "friction_method", _choice("friction_method", self.friction_method, FRICTION_METHODS))
        # the native solvers need no cvxpy import (about 0.8 s of CPU in a fresh process)
        allowed = NATIVE_SOLVERS if self.qp_solver in NATIVE_SOLVERS else qp_solvers()
        set_(self, "qp_solver", _choice("qp_solver", self.qp_solver, allowed))
        if self.qp_options is not None and not isinstance(self.qp_options, dict):
            raise InputError(f"qp_options = {self.qp_options!r}: must be a dict of the QP solver's options (or None)")
        if self.tangential is not None and not isinstance(self.tangential, bool):
            raise InputError(f"tangential = {self.tangential!r}: must be None, True or False")
        set_(self, "max_dof", whole_number("max_dof", self.max_dof))
        set_(self, "path_grading", check_path_grading(self.path_grading))
        if self.hp is not None or self.hp_sigma is not None:
            set_(self, "hp", whole_number("hp", self.hp, minimum=0) if self.hp is not None else 0)
            if self.hp > HP_MAX_LAYERS:
                raise InputError(f"hp = {self.hp!r}: the number of layers must be an integer in 0..{HP_MAX_LAYERS}")
            sigma = HP_SIGMA if self.hp_sigma is None else self.hp_sigma
            if not is_number(sigma) or not HP_SIGMA_RANGE[0] <= float(sigma) <= HP_SIGMA_RANGE[1]:
                raise InputError(f"hp_sigma = {sigma!r}: the layer ratio must lie in [{HP_SIGMA_RANGE[0]:g}, "
                                  f"{HP_SIGMA_RANGE[1]:g}]")
            set_(self, "hp_sigma", float(sigma))
        if self.adapt is not None:
            a = self.adapt
            if not is_number(a) or not (math.isfinite(float(a)) and 0 < float(a) < 1):
                raise InputError(f"adapt = {a!r}: the relative error tolerance must lie in (0, 1)")
            set_(self, "adapt", float(a))
            if self.estimate is False:
                raise InputError("estimate = False: adapt refines where the error estimate is largest; leave the "
                                 "estimate on (None or True) or give no adapt")

    @classmethod
    def of(cls, options: SolveOptions | None = None, **changes: Any) -> SolveOptions:
        """`options` (or the defaults) with `changes`; an unknown name is refused with the allowed ones."""
        known = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(changes) - known)
        if unknown:
            raise TypeError(f"unknown solve option{'s' if len(unknown) > 1 else ''} {', '.join(unknown)}; "
                            f"allowed: {', '.join(sorted(known))}")
        base = options if options is not None else cls()
        return dataclasses.replace(base, **changes) if changes else base

    def replace(self, **changes: Any) -> SolveOptions:
        """A copy with `changes` (checked again)."""
        return SolveOptions.of(self, **changes)

    def as_dict(self) -> dict[str, Any]:
        """The options by name (qp_options copied)."""
        out = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        out["qp_options"] = dict(self.qp_options) if self.qp_options is not None else None
        return out

    # ------------------------------------------------------------ what each stage depends on
    @property
    def mesh_key(self) -> tuple:
        """The mesh options (besides the scene's geometry and [mesh] values)."""
        return (self.maxh, self.tip_h, self.crack_h, self.grading, self.hp or 0, self.hp_sigma, self.path_grading)

    @property
    def element_key(self) -> tuple:
        """What the discretization depends on besides the mesh, material and load structure."""
        return (self.element, self.order)

    @property
    def reduction_key(self) -> tuple:
        """What the factorization and the crack Schur complement depend on besides the system."""
        return (self.linear_solver, self.schur if self.crack_model == "contact" else False)

    def tangential_for(self, scene) -> bool:
        """Whether the crack problem keeps the tangential jumps (friction), before the element is known."""
        wanted = self.tangential if self.tangential is not None else any(c.friction > 0 for c in scene.cracks)
        return bool(wanted) and self.crack_model == "contact"

    def given(self) -> dict[str, Any]:
        """The options that differ from the defaults, by name (what a body checks it can take)."""
        default = SolveOptions()
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)
                if getattr(self, f.name) != getattr(default, f.name) or f.name == "qp_options" and self.qp_options}

    def check_for(self, scene) -> None:
        """The checks that need the scene, before any meshing: what its body can take
        (`scene.body.check_options`), friction with the chosen solver and with a crack model;
        hp layers only where the scene has a crack tip inside the body to grade towards."""
        scene.body.check_options(scene, self)
        if scene.dimension != 2:
            return
        if self.hp and not scene.tip_points():
            raise InputError(f"hp = {self.hp}: scene {scene.name!r} has no crack tip inside the body, so the hp "
                             f"layers have nothing to refine towards; leave hp out (or 0)")
        if self.crack_model == "contact" and (self.tangential or any(c.friction > 0 for c in scene.cracks)):
            check_friction_solver(self.qp_solver, self.friction_method)
