"""solve(scene, element, ...) -> Solution: the whole pipeline for one scene.

scene -> mesh -> element forms (condensed) -> K, F -> Schur complement S on the crack
normal jumps -> QP -> recovery of every unknown -> crack profiles and KKT residuals.
A scene without a crack gets one linear solve and no QP.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field

import numpy as np
import ngsolve as ngs

from . import elements as _elements
from .contact import (DEFAULT_SOLVER, KKT_KEYS, NATIVE_SOLVERS, QPResult, constraint_positions, discrete_contact_forces,
                      kkt_at_constraints, solve_qp, warm_start_data)
from .elements import Discretization, Loads
from .friction import (DEFAULT_FRICTION_METHOD, FrictionResult, check_friction_options, crack_problem,
                       solve_crack_problem)
from .geometry import CrackMesh, make_mesh
from .hybrid import CondensedSystem, ContactReduction, Factorization, condense, reduce_to_contact
from .schur import SCHUR_METHODS
from .materials import compliance
from .post import (CrackProfile, consistent_tractions, crack_profile, endpoint_map, field_scales, kkt_residuals,
                   component_forces, lumped_normal_traction, tributary_lengths)
from .scene import Scene
from .sizing import check_max_dof, check_request
from .tips import tip_parameters


#: scaled forward residual of the condensed solve above which a definite system counts
#: as singular: a safety net behind the exact rigid-motion check of the supports.
#: Measured: regular systems up to 3e-2 (nu = 1/2 - 1e-6, just before the incompressible
#: split takes over), singular ones (nothing holds the body) 8 to 60.
RESIDUAL_TOL = 1.0

#: how the crack faces interact: unilateral contact, traction-free, or bonded in the normal direction
CRACK_MODELS = ("contact", "free", "bonded")


class SolveError(RuntimeError):
    """A solve produced something unusable (a singular system, non-finite numbers)."""


def scene_loads(scene: Scene) -> Loads:
    """The scene's boundary conditions and loads as NGSolve CoefficientFunctions."""
    traction, displacement, clamped, roller = {}, {}, set(), set()
    for label, bc in scene.boundary.items():
        if bc.type == "clamped":
            clamped.add(label)
        elif bc.type == "roller":
            roller.add(label)
        elif bc.type == "displacement":
            displacement[label] = ngs.CF(tuple(float(v) for v in bc.value))
        elif bc.type == "traction" and any(float(v) != 0.0 for v in bc.value):
            traction[label] = ngs.CF(tuple(float(v) for v in bc.value))
    body = None
    if scene.body_force is not None and any(float(v) != 0.0 for v in scene.body_force):
        body = ngs.CF(tuple(float(v) for v in scene.body_force))
    return Loads(body_force=body, traction=traction, displacement=displacement,
                 clamped=frozenset(clamped), roller=frozenset(roller))


@dataclass
class Solution:
    """The answer of one solve.

    `u`, `sigma`, `rotation` are NGSolve CoefficientFunctions (u is P0 per triangle,
    sigma the weakly symmetric 2x2 stress); `gf` is the full GridFunction. `profiles`
    holds one CrackProfile per crack (with its open / stick / slip `state`), `qp` the QP's
    answer (None without a crack; a friction.FrictionResult with friction).

    `kkt`: the relative residuals of the discrete Signorini conditions where the QP's
    constraints live (edge mid points for P0 jumps, edge end points for P1 jumps, crack
    nodes for h1p1/h1p2), with the constrained values w = G j of the answer and the
    discrete contact forces `forces` computed from the solved system
    (`contact.discrete_contact_forces`, `contact.kkt_at_constraints`): round-off small for
    crack_model "contact"; under "friction", the discrete Coulomb law's residual at the
    same points (0 without friction). For "free" and "bonded" they measure the same
    conditions on that model's answer: max_penetration > 0 where free faces
    interpenetrate, max_tension > 0 where bonded faces pull on each other. `kkt_sampled`:
    the same figures from the edge mid-point samples of the crack profiles (a diagnostic:
    a P1 jump sampled on the edge where contact ends carries both a small opening and a
    small pressure). No crack: all zero. `timings` in seconds, `ndof` counts (total,
    global after condensation, contact), `built` lists what was built.
    """

    scene: Scene
    element: str
    crack_mesh: CrackMesh
    disc: Discretization
    gf: ngs.GridFunction
    fields: dict
    profiles: list[CrackProfile]
    kkt: dict
    qp: QPResult | None
    timings: dict
    ndof: dict
    built: list[str]
    options: dict = field(default_factory=dict)
    conditioning: dict = field(default_factory=dict)
    #: K_I, K_II, G at every crack end inside the body (tips.py; the tip frame is in its docstring)
    tips: list = field(default_factory=list)
    kkt_sampled: dict = field(default_factory=lambda: dict.fromkeys(KKT_KEYS, 0.0))
    forces: np.ndarray | None = None
    #: the a posteriori estimate of the stress error (estimate.py), None where none exists
    error_estimate: object = None
    #: with adapt=TOL: one row per refinement step (adapt.py), a pandas DataFrame
    adapt_history: object = None

    @property
    def mesh(self) -> ngs.Mesh:
        return self.crack_mesh.mesh

    @property
    def u(self):
        return self.fields["u"]

    @property
    def sigma(self):
        return self.fields["sigma"]

    @property
    def rotation(self):
        return self.fields.get("rotation")

    @property
    def maxh(self) -> float:
        return self.crack_mesh.maxh

    def crack_profiles(self) -> list[CrackProfile]:
        """Per crack: s, x, y, jumps and crack-face stresses at the edge mid points."""
        return self.profiles

    def to_json_dict(self) -> dict:
        """The result as the `solve --json` dictionary (README, "Command line")."""
        t = self.timings
        return {
            "scene": self.scene.name,
            "element": self.element,
            "maxh": float(self.maxh),
            "nu": float(self.scene.material.nu),
            "E": float(self.scene.material.E),
            "ndof": {k: int(self.ndof[k]) for k in ("total", "global", "contact")},
            "time_s": {k: float(t[k]) for k in ("total", "mesh", "assemble", "linear", "contact")},
            "kkt": {k: float(self.kkt[k]) for k in KKT_KEYS},
            "kkt_sampled": {k: float(self.kkt_sampled[k]) for k in KKT_KEYS},
            "tips": [tip.to_dict() for tip in self.tips],
            "cracks": [p.to_dict() for p in self.profiles],
            **({"error_estimate": self.error_estimate.to_dict()} if self.error_estimate is not None else {}),
            **({"adapt": [{"ndof": int(r.ndof), "estimate": float(r.estimate)} for r in self.adapt_history.itertuples()]}
               if self.adapt_history is not None else {}),
        }


def _relative_residual(system: CondensedSystem, x_rest: np.ndarray) -> float:
    """|D (K_rr x - F_r)| / |D F_r|, D = diag(K_rr)^(-1/2): the forward residual in units
    that do not depend on the unknowns' units (rotations next to displacements).

    LU keeps the backward error at round-off even for a singular matrix, so it is the
    forward residual that tells: about eps cond(D K_rr D) for a regular system, O(1)
    for a singular one.
    """
    r, K = system.rest, system.K
    y = np.zeros(system.n)
    y[r] = x_rest  # K_rr x_rest = (K y)_r with y_c = 0, without copying K_rr
    diag = np.abs(K.diagonal()[r])
    D = np.where(diag > 0, 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0)), 1.0)
    Fs = D * system.F[r]
    norm_F = np.linalg.norm(Fs)
    return float(np.linalg.norm(D * ((K @ y)[r] - system.F[r])) / norm_F) if norm_F > 0 else 0.0


def condition_estimates(red) -> dict:
    """1-norm condition estimates of D K_rr D and of D_S S D_S (Hager/Higham).

    D = diag(K_rr)^(-1/2) (1 on a zero diagonal): the Jacobi-scaled matrices, whose
    condition does not depend on the units of the unknowns (PEERS mixes rotations and
    displacements) and is what the factorization and the QP (scaled the same way) see.
    Keys "K" and "S" (S only with a crack). The inverse goes through the factorization.
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    sysm = red.system
    K_rr = sysm.K[sysm.rest][:, sysm.rest]
    n = K_rr.shape[0]
    diag = np.abs(K_rr.diagonal())
    d = np.where(diag > 0, 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0)), 1.0)
    scaled = sp.diags(d) @ K_rr @ sp.diags(d)

    def solve_scaled(b):
        b = np.asarray(b, dtype=float)
        dd = d if b.ndim == 1 else d[:, None]
        return red.factorization.solve(b / dd) / dd

    inv = spla.LinearOperator((n, n), matvec=solve_scaled, rmatvec=solve_scaled, matmat=solve_scaled, dtype=float)
    out = {"K": float(spla.onenormest(scaled) * spla.onenormest(inv))}
    if red.S.size:
        ds = 1.0 / np.sqrt(np.abs(np.diag(red.S)))
        out["S"] = float(np.linalg.cond(ds[:, None] * red.S * ds[None, :], 1))
    return out


def _check_supports(scene: Scene, loads: Loads) -> None:
    """Loads given directly: the scene's exact rigid-motion check on their supports."""
    from .scene import BoundaryCondition

    boundary = {lab: BoundaryCondition("clamped") for lab in loads.clamped}
    boundary.update({lab: BoundaryCondition("roller") for lab in loads.roller})
    boundary.update({lab: BoundaryCondition("displacement", (0.0, 0.0)) for lab in loads.displacement})
    scene.with_(boundary=boundary)  # raises SceneError (a ValueError) if a part is not held


def _check_pressure_determined(scene: Scene, loads: Loads) -> None:
    """Refuse an incompressible body (plane strain, nu = 1/2) with no traction edge.

    Then sigma + c I solves the problem for every constant c: the pressure is
    undetermined. An edge absent from [boundary] is traction-free and fixes it.
    """
    mat = scene.material
    if mat.plane != "strain" or mat.nu != 0.5:
        return
    held = set(loads.clamped) | set(loads.roller) | set(loads.displacement)
    if set(scene.labels) <= held:
        raise ValueError(
            "material.nu = 0.5 (incompressible, plane strain) with every edge clamped, displaced or on rollers: "
            "the pressure is undetermined; leave at least one edge traction-free or loaded by a traction, "
            "or use nu < 0.5"
        )


def qp_solvers() -> tuple[str, ...]:
    """The QP solvers available here: the native ones and cvxpy's installed QP solvers."""
    import cvxpy as cp

    qp_capable = {"CLARABEL", "OSQP", "SCS", "ECOS", "CVXOPT", "PIQP", "PROXQP", "MOSEK", "GUROBI", "CPLEX", "QPALM", "DAQP", "HIGHS"}
    return NATIVE_SOLVERS + tuple(s.lower() for s in cp.installed_solvers() if s in qp_capable)


def _check_options(element: str, maxh, tip_h, crack_h, qp_solver: str, linear_solver: str, schur: str = "auto") -> None:
    if element not in _elements.ELEMENTS:
        raise ValueError(f"element = {element!r}: allowed values are {', '.join(_elements.ELEMENTS)}")
    for name, val in (("maxh", maxh), ("tip_h", tip_h), ("crack_h", crack_h)):
        if val is not None and (isinstance(val, bool) or not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0)):
            raise ValueError(f"{name} = {val!r}: must be a finite number > 0")
    if linear_solver not in Factorization.BACKENDS:
        raise ValueError(f"linear_solver = {linear_solver!r}: allowed values are {', '.join(Factorization.BACKENDS)}")
    if schur not in SCHUR_METHODS:
        raise ValueError(f"schur = {schur!r}: allowed values are {', '.join(SCHUR_METHODS)}")
    # the native solvers need no cvxpy import (about 0.8 s of CPU in a fresh process)
    allowed = NATIVE_SOLVERS if qp_solver in NATIVE_SOLVERS else qp_solvers()
    if qp_solver not in allowed:
        raise ValueError(f"qp_solver = {qp_solver!r}: allowed values are {', '.join(allowed)}")


def solve(
    scene: Scene,
    element: str = "bdm",
    maxh: float | None = None,
    tip_h: float | None = None,
    crack_h: float | None = None,
    grading: float | None = None,
    qp_solver: str = DEFAULT_SOLVER,
    qp_options: dict | None = None,
    linear_solver: str = "auto",
    loads: Loads | None = None,
    crack_model: str = "contact",
    order: int | None = None,
    condition: bool = False,
    schur: str = "auto",
    warm_start=None,
    max_dof: int | None = None,
    friction_method: str = DEFAULT_FRICTION_METHOD,
    tangential: bool | None = None,
    adapt: float | None = None,
    crack_mesh: CrackMesh | None = None,
) -> Solution:
    """Solve the unilateral crack problem of `scene` with one element family.

    element: "bdm" (default: the most accurate per unknown and per second on the
    measured cases, README "Which element when"), "peers", "tdnns", "h1p1" or "h1p2".
    maxh / tip_h / crack_h / grading override the scene's [mesh] values. qp_solver is "pdas" (default),
    "uzawa" or a cvxpy solver ("clarabel", "osqp", ...); qp_options go to the solver unchanged
    (contact.py). linear_solver: "auto" (MKL PARDISO where installed, else SuperLU), "pardiso",
    "superlu", "cholespy" or "ngsolve"; schur: how the Schur complement on the crack is formed,
    "auto", "factor", "blocked" or "columns" (schur.py). warm_start: a previous Solution (its
    contact zone is carried over by crack position; the meshes may differ) or an active set. `loads`
    replaces the scene's loads by NGSolve CoefficientFunctions (manufactured solutions).
    crack_model: "contact" (unilateral contact, the default), "free" (traction-free
    crack faces that may interpenetrate: one linear solve) or "bonded" (jn = 0, the
    faces slide freely but never separate: one linear solve). order: the polynomial
    order of elements that have one (tdnns: 1, 2 or 3; default 1). condition: also
    estimate the 1-norm condition numbers of the condensed matrix K_rr and of the crack
    Schur complement S (a few extra solves), in `sol.conditioning`. max_dof: the largest
    number of unknowns a solve may have; a request estimated above it (before meshing,
    ngcrack.sizing) is refused with a ValueError. None: the default ceiling
    (sizing.DEFAULT_MAX_DOF) and the machine's available memory. A mesh too coarse across a
    thin part of the body for the element is refused, or warned about (sizing.check_thin_parts).

    Friction (a crack with `friction` > 0, e.g. `scene.with_(friction=0.3)`): the
    tangential jumps stay in the reduced problem and Coulomb's law is solved by
    `friction_method` ("fixed-point" of Tresca problems or "newton"; friction.py) with
    qp_solver "pdas" (native) or a cvxpy solver for the Tresca steps; warm_start is not
    used. `tangential`: keep the tangential jumps in the reduced problem (None: when a
    crack has friction; True with no friction solves the frictionless problem that way).

    adapt: a relative error tolerance in (0, 1): solve, estimate, mark and refine until
    the relative estimate is <= adapt or the next mesh would exceed max_dof unknowns
    (adapt.py, default budget adapt.DEFAULT_MAX_DOF; the mesh options give the first
    mesh, which the size guard checks). crack_mesh: solve on this mesh (a CrackMesh of the
    scene) instead of meshing. Every solve carries `sol.error_estimate` (estimate.py),
    None for an element or crack model without one.
    """
    _check_options(element, maxh, tip_h, crack_h, qp_solver, linear_solver, schur)
    if grading is not None and (isinstance(grading, bool) or not (isinstance(grading, (int, float)) and 0 < grading <= 1)):
        raise ValueError(f"grading = {grading!r}: must lie in (0, 1] (netgen's default is 0.3)")
    if crack_model not in CRACK_MODELS:
        raise ValueError(f"crack_model = {crack_model!r}: allowed values are {', '.join(CRACK_MODELS)}")
    if crack_model == "contact":  # the free and bonded models solve no crack problem: friction plays no part
        check_friction_options(scene, qp_solver, friction_method, tangential)
    check_max_dof(max_dof)
    if max_dof is not None:
        max_dof = int(max_dof)
    if adapt is not None:
        from .adapt import check_adapt_options, solve_adaptive

        check_adapt_options(adapt, max_dof, element, crack_model, scene)
        if crack_mesh is not None:
            raise ValueError("crack_mesh: adapt=TOL makes its own first mesh from maxh, tip_h, crack_h and grading; "
                             "give either adapt or crack_mesh")
    if crack_mesh is None:  # the size guard and the thin-part check, before any meshing
        check_request(scene, element, maxh, tip_h, crack_h, grading, order=order, max_dof=max_dof)
    if adapt is not None:
        return solve_adaptive(scene, element, adapt, max_dof=max_dof, maxh=maxh, tip_h=tip_h, crack_h=crack_h,
                              grading=grading, qp_solver=qp_solver, qp_options=qp_options,
                              linear_solver=linear_solver, loads=loads, crack_model=crack_model, order=order,
                              condition=condition, schur=schur, friction_method=friction_method,
                              tangential=tangential)
    if loads is None:
        loads = scene_loads(scene)
    else:
        _check_supports(scene, loads)
    _check_pressure_determined(scene, loads)
    t_start = time.perf_counter()
    timings: dict[str, float] = {}

    t0 = time.perf_counter()
    cmesh = crack_mesh if crack_mesh is not None else make_mesh(scene, maxh=maxh, tip_h=tip_h, crack_h=crack_h, grading=grading)
    timings["mesh"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    mat = scene.material
    disc = _elements.build(element, cmesh, compliance(mat.E, mat.nu, mat.plane), loads, order=order)
    mu = [c.friction for c in scene.cracks]
    if tangential is None:
        tangential = any(f > 0 for f in mu)
    tangential = bool(tangential) and crack_model == "contact" and disc.jn is not None
    system = condense(disc, loads, tangential=tangential)
    timings["assemble"] = time.perf_counter() - t0

    # the crack normal jumps' rows, whatever the crack model (with friction the tangential
    # jumps follow them in system.contact)
    contact = system.contact if system.n_normal is None else system.contact[:system.n_normal]
    normal_contact = contact
    if crack_model == "free":
        system = system.without_contact()
    case = f"scene {scene.name!r}, element {element!r}"
    if not (np.all(np.isfinite(system.K.data)) and np.all(np.isfinite(system.F))):
        raise SolveError(f"{case}: the assembled system has non-finite entries (check the loads and material data)")
    t0 = time.perf_counter()
    try:
        red = reduce_to_contact(system, linear_solver=linear_solver, schur=schur if crack_model == "contact" else False)
    except RuntimeError as exc:  # SuperLU: "Factor is exactly singular"
        raise SolveError(f"{case}: the condensed system is singular ({exc}); is every part of the body held?") from exc
    if not (np.all(np.isfinite(red.x0)) and np.all(np.isfinite(red.S))):
        raise SolveError(f"{case}: the condensed solve gave non-finite values (singular system; is every part of the body held?)")
    residual = _relative_residual(system, red.x0) if disc.definite else 0.0
    if residual > RESIDUAL_TOL:
        raise SolveError(f"{case}: the condensed system is singular to working precision (relative residual "
                         f"{residual:.1e} of its solve); is every part of the body held?")
    m = len(system.contact)
    timings.update(red.timings)

    qp = None
    t0 = time.perf_counter()
    G = None
    if len(contact):
        jn_space = disc.fes.components[disc.jn]
        G = disc.constraint_map() if disc.constraint_map is not None else endpoint_map(jn_space, cmesh, disc.facet_order)
    if m and crack_model == "contact":
        if tangential:
            qp = solve_crack_problem(crack_problem(red, disc, cmesh, G, mu), solver=qp_solver,
                                     solver_options=qp_options, method=friction_method)
            jn = qp.z
        else:
            positions = constraint_positions(disc, cmesh)
            initial_active, initial_guess = warm_start_data(warm_start, *positions)
            qp = solve_qp(red.S, red.b, G=G, solver=qp_solver, solver_options=qp_options,
                          initial_active=initial_active, initial_guess=initial_guess)
            qp.crack, qp.s = positions
            jn = qp.j
    else:  # no crack, or a bonded crack: jn = 0
        jn = np.zeros(len(system.contact))
    timings["qp"] = time.perf_counter() - t0

    conditioning = condition_estimates(red) if condition else {}

    t0 = time.perf_counter()
    y = red.recover(jn)
    if not np.all(np.isfinite(y)):
        raise SolveError(f"{case}: the condensed solve gave non-finite values (singular system)")
    gf = system.expand(y)
    timings["recover"] = time.perf_counter() - t0
    if not np.all(np.isfinite(gf.vec.FV().NumPy())):
        raise SolveError(f"{case}: the local recovery gave non-finite values")

    fields = disc.fields(gf)
    profiles = []
    if disc.jn is not None:
        comps = gf.components
        jn_vals = comps[disc.jn].vec.FV().NumPy()
        jt_vals = comps[disc.jt].vec.FV().NumPy() if disc.jt is not None else None
        displacement = disc.tangential_jump(gf) if disc.tangential_jump is not None else None
        jump_space = disc.fes.components[disc.jn]
        for k, crack in enumerate(cmesh.cracks):
            jumps = disc.crack_jumps(gf, crack) if disc.crack_jumps is not None else None
            profiles.append(crack_profile(cmesh, crack, jump_space, jn_vals, jt_vals, fields["sigma"],
                                          displacement=displacement, jumps=jumps, two_sided=disc.two_sided_traction,
                                          friction=mu[k] if tangential else 0.0))
    scales = field_scales(cmesh, fields["u"], fields["sigma"]) if profiles else (0.0, 0.0)
    kkt, forces = _constraint_kkt(system, y, normal_contact, G, cmesh, profiles, *scales)
    if profiles and any(c is not None for c in disc.traction_rows):
        lumped = disc.traction_rows[0] is not None and forces is not None  # nodal contact forces
        tractions = consistent_tractions(system, y, cmesh, skip=("normal_stress", "shear_stress") if lumped else ())
        if lumped:
            space = disc.fes.components[disc.jn]
            w = tributary_lengths(space, cmesh, G)
            normal = lumped_normal_traction(space, cmesh, G, forces, w)
            shear = lumped_normal_traction(space, cmesh, G, component_forces(system, y, disc.traction_rows[1], G), w)
            tractions = [dict(t, normal_stress=n, shear_stress=q) for t, n, q in zip(tractions, normal, shear)]
        profiles = [dataclasses.replace(p, **t) for p, t in zip(profiles, tractions)]
    kkt_sampled = kkt_residuals(profiles, *scales)
    # the discrete Coulomb law at the QP's constraint points (0 without friction)
    kkt["friction"] = float(qp.kkt["friction"]) if isinstance(qp, FrictionResult) else 0.0
    sampled = [getattr(p, k) for p in profiles for k in p.__dataclass_fields__ if k != "state"] + [
        np.array(list(kkt.values()) + list(kkt_sampled.values()))]
    if not all(np.all(np.isfinite(a)) for a in sampled):
        raise SolveError(f"{case}: the crack profiles or KKT residuals hold non-finite values")
    # linear: the factorization and solves a plain linear solve needs too (with the
    # local recovery); contact: what the crack adds (Schur complement and QP)
    timings["linear"] = timings["factorize"] + timings["solve"] + timings["recover"]
    timings["contact"] = timings["schur"] + timings["qp"]
    timings["total"] = time.perf_counter() - t_start
    ndof = {"total": disc.fes.ndof, "global": system.n, "contact": m}
    if isinstance(qp, FrictionResult):
        built = list(disc.built) + [f"crack problem with friction: {len(qp.w)} normal and {len(qp.wt)} tangential "
                                    f"values, solver {qp_solver}, {qp.method}: {qp.coulomb_iterations} iterations, "
                                    f"{qp.steps} active-set steps"]
    elif qp is not None:
        built = list(disc.built) + [f"contact QP: {m} unknowns, solver {qp_solver}"]
    elif disc.jn is None:
        built = list(disc.built) + ["no crack: one linear solve, no QP"]
    else:
        built = list(disc.built) + [f"crack model {crack_model!r}: one linear solve, no QP"]
    sol = Solution(
        scene=scene,
        element=element,
        crack_mesh=cmesh,
        disc=disc,
        gf=gf,
        fields=fields,
        profiles=profiles,
        kkt=kkt,
        qp=qp,
        timings=timings,
        ndof=ndof,
        built=built,
        options={"qp_solver": qp_solver, "linear_solver": red.factorization.backend, "schur": red.method,
                 "largest_dense": red.largest_dense,
                 "tip_h": tip_h, "crack_model": crack_model,
                 "order": order, "friction": [float(f) for f in mu], "friction_method": friction_method,
                 "tangential": tangential},
        conditioning=conditioning,
        kkt_sampled=kkt_sampled,
        forces=forces,
    )
    t0 = time.perf_counter()
    sol.tips = tip_parameters(sol, body_force=loads.body_force)
    timings["tips"] = time.perf_counter() - t0
    timings["total"] += timings["tips"]
    sol.error_estimate = _estimate(sol, loads, crack_model)
    return sol


def _estimate(sol: Solution, loads: Loads, crack_model: str):
    """The solve's error estimate (estimate.py), or None where none exists (with the reason
    in sol.options["error_estimate"])."""
    from .estimate import estimate

    try:
        est = estimate(sol, loads, crack_model)
    except ValueError as exc:
        sol.options["error_estimate"] = str(exc)
        return None
    sol.timings["estimate"] = est.time
    return est


def _constraint_kkt(system: CondensedSystem, y: np.ndarray, contact: np.ndarray, G, cmesh: CrackMesh,
                    profiles: list[CrackProfile], u_scale: float, sigma_scale: float) -> tuple[dict, np.ndarray | None]:
    """(kkt, forces) at the QP's constraint points: w = G j from the answer, the forces from its residual.

    W = the largest jump on the crack (|w| at the constraint points, |[u]| at the edge mid
    points); the body scales are max |u| and max |sigma| times the mean crack edge length.
    """
    if G is None or not len(contact):
        return kkt_at_constraints(np.zeros(0), np.zeros(0), 0.0), None
    w = G @ y[contact]
    forces, bound = discrete_contact_forces(system.K, system.F, y, contact, G)
    jump_max = max([float(np.max(np.abs(w)))] + [float(np.max(np.hypot(p.normal_jump, p.tangential_jump))) for p in profiles])
    edge = float(np.mean(np.concatenate([c.length for c in cmesh.cracks])))
    kkt = kkt_at_constraints(w, forces, jump_max, jump_scale=u_scale, force_scale=sigma_scale * edge, lam_bound=bound)
    return kkt, forces
