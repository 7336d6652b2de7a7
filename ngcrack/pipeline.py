"""The staged pipeline of a solve, each stage cached under exactly what it depends on.

    scene -> mesh -> discretization (forms assembled) -> condensed system K, F
          -> reduction (factorization of K_rr, Schur complement S on the crack unknowns)
          -> crack problem (QP, or Coulomb friction) -> recovery -> Solution
          -> post-processing: crack profiles, KKT residuals, tips' K_I, K_II, G, estimate

`Pipeline.run(scene, options)` runs every stage; a `Pipeline` kept between runs (the
explorer's model, adaptivity, crack growth, a user's own loop) rebuilds a stage only
when its inputs change, the idea of NGSolve's own objects (a BilinearForm is assembled
once and again when a Parameter changes):

- mesh: keyed by the scene's geometry and mesh sizes and the options' mesh sizes (a
  ready CrackMesh may be handed in instead);
- discretization: keyed by the mesh object, the element and order, the material and
  the load structure (which edges are held, which carry loads). The loads are NGSolve
  Parameters in the assembled linear form: a new load value re-assembles the load
  vector only (`counts["load"]`);
- condensed system: per crack-unknown layout (normal jumps only, or with the tangential
  ones for friction) of the current discretization; a new load rebuilds F only;
- reduction: per layout and solver options; a new load costs one solve with the kept
  factorization and S.

`counts` tells how often each stage ran for real (mesh, assemble, condense, factorize)
or was reused for a new load (load), `redone` what the last run recomputed. Answers
from cached stages equal fresh ones to round-off: the same functions run on the same
data. `nc.solve` is the one-shot use: a fresh Pipeline, one run.
"""

from __future__ import annotations

import dataclasses
import time

import ngsolve as ngs
import numpy as np

from . import elements as _elements
from .constraints import discrete_contact_forces, kkt_at_constraints
from .contact import constraint_positions, solve_qp, warm_start_data
from .crack_loads import pressure_cf
from .elements import Discretization, Loads
from .errors import InputError
from .friction import FrictionResult, solve_crack_problem
from .friction_setup import crack_problem
from .geometry import CrackMesh, make_mesh
from .hp import hp_mesh
from .hybrid import CondensedSystem, ContactReduction, condense, reduce_to_contact
from .materials import compliance
from .options import SolveOptions
from .post import (
    CrackProfile,
    component_forces,
    consistent_tractions,
    crack_profile,
    endpoint_map,
    field_scales,
    kkt_residuals,
    lumped_traction,
    tributary_lengths,
)
from .scene import BoundaryCondition, Scene
from .scene.points import held_directions
from .scene.pressure import pressure_kind, pressure_values
from .sizing import check_request
from .solution import Solution
from .tips import tip_parameters

#: scaled forward residual of the condensed solve above which a definite system counts
#: as singular: a safety net behind the exact rigid-motion check of the supports.
#: Measured: regular systems up to 3e-2 (nu = 1/2 - 1e-6, just before the incompressible
#: split takes over), singular ones (nothing holds the body) 8 to 60.
RESIDUAL_TOL = 1.0

#: the stages whose runs `Pipeline.counts` records
STAGES = ("mesh", "assemble", "load", "condense", "factorize")


class SolveError(RuntimeError):
    """A solve produced something unusable (a singular system, non-finite numbers)."""


# ------------------------------------------------------------------ loads

def load_structure(scene: Scene) -> tuple:
    """What the assembled forms depend on besides the load values: the supports and
    which labels carry loads."""
    return (tuple(sorted((lab, bc.type) for lab, bc in scene.boundary.items())), scene.body_force is not None,
            tuple((pc.label, pc.type) for pc in getattr(scene, "points", ())),
            tuple(pressure_kind(c.pressure) for c in scene.cracks))


def geometry_key(scene: Scene) -> tuple:
    """What the mesh depends on: the polygon, its labels, the cracks' points and the mesh sizes."""
    return (scene.polygon, scene.labels, tuple(c.points for c in scene.cracks),
            scene.holes, scene.maxh, scene.tip_h, scene.crack_h, scene.grading)


class ParameterLoads:
    """The scene's loads as NGSolve Parameters: the assembled linear form follows their values.

    Every traction, displacement and body-force vector of the scene gets two Parameters
    (zero ones too, so a load scaled to zero keeps the same form); `set(scene)` copies a
    scene's values in (the scene must have the same `load_structure`).
    """

    def __init__(self, scene: Scene):
        self.structure = load_structure(scene)
        self.params: dict[tuple[str, str], tuple[ngs.Parameter, ngs.Parameter]] = {}
        traction, displacement, clamped, roller = {}, {}, set(), set()
        for label, bc in scene.boundary.items():
            if bc.type == "clamped":
                clamped.add(label)
            elif bc.type == "roller":
                roller.add(label)
            else:
                p = (ngs.Parameter(0.0), ngs.Parameter(0.0))
                self.params[(bc.type, label)] = p
                (traction if bc.type == "traction" else displacement)[label] = ngs.CF(p)
        body = None
        if scene.body_force is not None:
            p = (ngs.Parameter(0.0), ngs.Parameter(0.0))
            self.params[("body", "")] = p
            body = ngs.CF(p)
        # crack-face pressures: a uniform one a Parameter, a table or callable a fixed function
        self.pressures: dict[int, ngs.Parameter] = {}
        crack_pressure = {}
        for k, crack in enumerate(scene.cracks):
            if crack.pressure is None:
                continue
            if isinstance(crack.pressure, float):
                self.pressures[k] = ngs.Parameter(0.0)
            crack_pressure[k] = pressure_cf(crack.pressure, np.asarray(crack.points), scene.diameter,
                                            parameter=self.pressures.get(k))
        self.loads = Loads(body_force=body, traction=traction, displacement=displacement,
                           clamped=frozenset(clamped), roller=frozenset(roller), crack_pressure=crack_pressure,
                           held_mean=held_directions(scene.polygon, scene.labels, getattr(scene, "points", ())))
        self.set(scene)

    def set(self, scene: Scene) -> None:
        for (kind, label), (px, py) in self.params.items():
            value = scene.body_force if kind == "body" else scene.boundary[label].value
            px.Set(float(value[0]))
            py.Set(float(value[1]))
        for k, param in self.pressures.items():
            param.Set(float(scene.cracks[k].pressure))


def scene_loads(scene: Scene) -> Loads:
    """The scene's boundary conditions and loads as NGSolve CoefficientFunctions (ParameterLoads)."""
    return ParameterLoads(scene).loads


# ------------------------------------------------------------------ checks before any work

def check_supports(scene: Scene, loads: Loads) -> None:
    """Loads given directly: the scene's exact rigid-motion check on their supports."""
    boundary = {lab: BoundaryCondition("clamped") for lab in loads.clamped}
    boundary.update({lab: BoundaryCondition("roller") for lab in loads.roller})
    boundary.update({lab: BoundaryCondition("displacement", (0.0, 0.0)) for lab in loads.displacement})
    scene.with_(boundary=boundary)  # raises SceneError (a ValueError) if a part is not held


def check_pressure_determined(scene: Scene, loads: Loads | None = None) -> None:
    """Refuse an incompressible body (plane strain, nu = 1/2) with no traction edge.

    Then sigma + c I solves the problem for every constant c: the pressure is
    undetermined. An edge absent from [boundary] is traction-free and fixes it.
    `loads`: loads given instead of the scene's (None: the scene's supports).
    """
    mat = scene.material
    if mat.plane != "strain" or mat.nu != 0.5:
        return
    if loads is None:
        held = {lab for lab, bc in scene.boundary.items() if bc.type in ("clamped", "roller", "displacement")}
    else:
        held = set(loads.clamped) | set(loads.roller) | set(loads.displacement)
    if set(scene.boundary_labels) <= held:
        raise InputError(
            "material.nu = 0.5 (incompressible, plane strain) with every edge clamped, displaced or on rollers: "
            "the pressure is undetermined; leave at least one edge traction-free or loaded by a traction, "
            "or use nu < 0.5"
        )


def relative_residual(system: CondensedSystem, x_rest: np.ndarray) -> float:
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


def condition_estimates(red: ContactReduction) -> dict:
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


def constraint_kkt(system: CondensedSystem, y: np.ndarray, contact: np.ndarray, G, cmesh: CrackMesh,
                   profiles: list[CrackProfile], u_scale: float, sigma_scale: float) -> tuple[dict, np.ndarray | None]:
    """(kkt, forces) at the QP's constraint points: w = G j from the answer, the forces from its residual.

    W = the largest jump on the crack (|w| at the constraint points, |[u]| at the edge mid
    points); the body scales are max |u| and max |sigma| times the mean crack edge length.
    """
    if G is None or not len(contact):
        return kkt_at_constraints(np.zeros(0), np.zeros(0), 0.0), None
    w = G @ y[contact]
    forces, bound = discrete_contact_forces(system.K, system.F, y, contact, G)
    jump_max = max([float(np.max(np.abs(w)))] + [float(np.max(np.hypot(p.normal_jump, p.tangential_jump)))
                                                   for p in profiles])
    edge = float(np.mean(np.concatenate([c.length for c in cmesh.cracks])))
    kkt = kkt_at_constraints(w, forces, jump_max, jump_scale=u_scale, force_scale=sigma_scale * edge, lam_bound=bound)
    return kkt, forces


# ------------------------------------------------------------------ the pipeline

class Pipeline:
    """The stages of a solve with a cache each (module docstring).

    One Pipeline serves one sequence of related solves (the explorer's, an adaptive loop,
    a growth path); it is not meant to be shared between threads.
    """

    def __init__(self):
        self.counts = dict.fromkeys(STAGES, 0)
        self.redone: list[str] = []
        self._mesh: tuple | None = None  # (key, CrackMesh)
        self._disc: tuple | None = None  # (key, Discretization, ParameterLoads | None, Loads)
        self._systems: dict = {}  # tangential -> CondensedSystem of the current discretization
        self._reductions: dict = {}  # (reduction key, layout) -> ContactReduction

    def clear(self) -> None:
        """Forget every cached stage (the counts stay)."""
        self._mesh = self._disc = None
        self._systems, self._reductions = {}, {}

    # -------------------------------------------------------------- stages
    def mesh(self, scene: Scene, options: SolveOptions) -> CrackMesh:
        """The scene's mesh with cracks as interior edges (geometry.make_mesh), cached; with
        options.hp, hp.hp_mesh: a base mesh coarse at the tips and hp geometric layers towards them."""
        key = (geometry_key(scene), options.mesh_key)
        if self._mesh is None or self._mesh[0] != key:
            o = options
            sizes = dict(maxh=o.maxh, tip_h=o.tip_h, crack_h=o.crack_h, grading=o.grading)
            # hp: the coarse base mesh of hp.base_mesh (unless sizes are given) and the layers
            cmesh = hp_mesh(scene, o.hp, sigma=o.hp_sigma, **sizes) if o.hp else make_mesh(scene, **sizes)
            self._mesh = (key, cmesh)
            self.counts["mesh"] += 1
            self.redone.append("mesh")
        return self._mesh[1]

    def discretization(self, scene: Scene, crack_mesh: CrackMesh, options: SolveOptions,
                       loads: Loads | None = None) -> tuple[Discretization, Loads]:
        """The element's spaces and assembled forms on `crack_mesh` and the loads they hold.

        Without `loads`, the scene's loads become Parameters of the assembled linear form
        (ParameterLoads): a scene that differs only in load values re-assembles the load
        vector. Given `loads` (CoefficientFunctions), the forms are reused only for that
        same Loads object.
        """
        mat = scene.material
        key = (options.element_key, (mat.E, mat.nu, mat.plane),
               load_structure(scene) if loads is None else ("given", id(loads)))
        cached = self._disc
        if cached is not None and cached[0] == key and cached[1].crack_mesh is crack_mesh \
                and (loads is None or cached[3] is loads):
            _, disc, ploads, held = cached
            if ploads is not None:
                ploads.set(scene)
                disc.f.Assemble()  # (tens of microseconds: starting the TaskManager would cost more)
                self.counts["load"] += 1
                self.redone.append("load vector")
            return disc, held
        ploads = ParameterLoads(scene) if loads is None else None
        held = ploads.loads if ploads is not None else loads
        disc = _elements.build(options.element, crack_mesh, compliance(mat.E, mat.nu, mat.plane), held,
                               order=options.order)
        self._disc = (key, disc, ploads, held)
        self._systems, self._reductions = {}, {}
        self.counts["assemble"] += 1
        self.redone.append("assembly")
        return disc, held

    def system(self, disc: Discretization, loads: Loads, tangential: bool) -> CondensedSystem:
        """K, F on the global unknowns (hybrid.condense); a new load rebuilds F only."""
        cached = self._systems.get(tangential)
        if cached is not None and cached.disc is disc:
            system = cached.with_load(loads)
        else:
            system = condense(disc, loads, tangential=tangential)
            self.counts["condense"] += 1
            self.redone.append("condensation")
        self._systems[tangential] = system
        return system

    def reduction(self, system: CondensedSystem, options: SolveOptions) -> ContactReduction:
        """The factorization of K_rr and the Schur complement on the crack unknowns, cached per layout."""
        key = (options.reduction_key, len(system.contact), system.n_normal)
        cached = self._reductions.get(key)
        if cached is not None and cached.system.K is system.K and np.array_equal(cached.system.contact, system.contact):
            self.redone.append("one solve (factorization and S reused)")
            return cached.with_load(system)
        linear_solver, schur = options.reduction_key
        red = reduce_to_contact(system, linear_solver=linear_solver, schur=schur)
        self._reductions[key] = red
        self.counts["factorize"] += 1
        self.redone.append("factorization and S")
        return red

    # -------------------------------------------------------------- one run
    def run(self, scene: Scene, options: SolveOptions | None = None, *, loads: Loads | None = None,
            warm_start=None, crack_mesh: CrackMesh | None = None, check_size: bool = True) -> Solution:
        """Solve `scene` with `options` (SolveOptions; the defaults if None), reusing what is cached.

        `loads` replaces the scene's loads (manufactured solutions); `warm_start` a previous
        Solution or an active set (contact zone carried over); `crack_mesh` a ready mesh of
        the scene (no meshing, no size guard). `check_size`: run the size guard before
        meshing (sizing.check_request). Adaptivity is not a stage: see ngcrack.adapt.
        """
        o = options if options is not None else SolveOptions()
        self.redone = []
        o.check_for(scene)
        if crack_mesh is None and check_size:  # the size guard and the thin-part check, before any meshing
            check_request(scene, o.element, o.maxh, o.tip_h, o.crack_h, o.grading, order=o.order, max_dof=o.max_dof)
        if loads is not None:
            check_supports(scene, loads)
        check_pressure_determined(scene, loads)
        t_start = time.perf_counter()
        timings: dict[str, float] = {}

        t0 = time.perf_counter()
        cmesh = crack_mesh if crack_mesh is not None else self.mesh(scene, o)
        timings["mesh"] = time.perf_counter() - t0

        t0 = time.perf_counter()
        disc, loads = self.discretization(scene, cmesh, o, loads)
        mu = [c.friction for c in scene.cracks]
        tangential = o.tangential_for(scene) and disc.jn is not None
        system = self.system(disc, loads, tangential)
        timings["assemble"] = time.perf_counter() - t0

        # the crack normal jumps' rows, whatever the crack model (with friction the tangential
        # jumps follow them in system.contact)
        contact = system.contact if system.n_normal is None else system.contact[:system.n_normal]
        normal_contact = contact
        if o.crack_model == "free":
            system = system.without_contact()
        case = f"scene {scene.name!r}, element {o.element!r}"
        if not (np.all(np.isfinite(system.K.data)) and np.all(np.isfinite(system.F))):
            raise SolveError(f"{case}: the assembled system has non-finite entries (check the loads and material data)")
        try:
            red = self.reduction(system, o)
        except RuntimeError as exc:  # SuperLU: "Factor is exactly singular"
            raise SolveError(f"{case}: the condensed system is singular ({exc}); is every part of the body held?") from exc
        if not (np.all(np.isfinite(red.x0)) and np.all(np.isfinite(red.S))):
            raise SolveError(f"{case}: the condensed solve gave non-finite values (singular system; "
                             "is every part of the body held?)")
        residual = relative_residual(system, red.x0) if disc.definite else 0.0
        if residual > RESIDUAL_TOL:
            raise SolveError(f"{case}: the condensed system is singular to working precision (relative residual "
                             f"{residual:.1e} of its solve); is every part of the body held?")
        m = len(system.contact)
        timings.update(red.timings)

        qp, G, jn, t0 = None, None, None, time.perf_counter()
        if len(contact):
            jn_space = disc.fes.components[disc.jn]
            G = disc.constraint_map() if disc.constraint_map is not None else endpoint_map(jn_space, cmesh,
                                                                                            disc.facet_order)
        if m and o.crack_model == "contact":
            if tangential:
                qp = solve_crack_problem(crack_problem(red, disc, cmesh, G, mu), solver=o.qp_solver,
                                         solver_options=o.qp_options, method=o.friction_method)
                jn = qp.z
            else:
                positions = constraint_positions(disc, cmesh)
                initial_active, initial_guess = warm_start_data(warm_start, *positions)
                qp = solve_qp(red.S, red.b, G=G, solver=o.qp_solver, solver_options=o.qp_options,
                              initial_active=initial_active, initial_guess=initial_guess)
                qp.crack, qp.s = positions
                jn = qp.j
        else:  # no crack, or a bonded crack: jn = 0
            jn = np.zeros(len(system.contact))
        timings["qp"] = time.perf_counter() - t0

        conditioning = condition_estimates(red) if o.condition else {}

        t0 = time.perf_counter()
        y = red.recover(jn)
        if not np.all(np.isfinite(y)):
            raise SolveError(f"{case}: the condensed solve gave non-finite values (singular system)")
        gf = system.expand(y)
        timings["recover"] = time.perf_counter() - t0
        if not np.all(np.isfinite(gf.vec.FV().NumPy())):
            raise SolveError(f"{case}: the local recovery gave non-finite values")

        fields = disc.fields(gf)
        profiles = crack_profiles(disc, cmesh, gf, fields, mu if tangential else None,
                                  [c.pressure for c in scene.cracks])
        scales = field_scales(cmesh, fields["u"], fields["sigma"]) if profiles else (0.0, 0.0)
        kkt, forces = constraint_kkt(system, y, normal_contact, G, cmesh, profiles, *scales)
        profiles = with_tractions(profiles, disc, system, y, cmesh, G, forces)
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
        sol = Solution(
            scene=scene, element=o.element, crack_mesh=cmesh, disc=disc, gf=gf, fields=fields, profiles=profiles,
            kkt=kkt, qp=qp, timings=timings, ndof={"total": disc.fes.ndof, "global": system.n, "contact": m},
            built=list(disc.built) + [_built_line(qp, m, o, disc)],
            options={"qp_solver": o.qp_solver, "linear_solver": red.factorization.backend, "schur": red.method,
                     "largest_dense": red.largest_dense, "tip_h": o.tip_h, "crack_model": o.crack_model,
                     "order": o.order, "friction": [float(f) if o.crack_model == "contact" else 0.0 for f in mu],
                     "friction_method": o.friction_method,
                     "tangential": tangential, "hp": o.hp or 0},
            conditioning=conditioning, kkt_sampled=kkt_sampled, forces=forces,
        )
        self.post_process(sol, loads)
        return sol

    @staticmethod
    def post_process(sol: Solution, loads: Loads) -> None:
        """The tips' K_I, K_II, G and the error estimate of a solved `sol` (their times in sol.timings)."""
        t0 = time.perf_counter()
        sol.tips = tip_parameters(sol, body_force=loads.body_force)
        sol.timings["tips"] = time.perf_counter() - t0
        sol.timings["total"] += sol.timings["tips"]
        sol.error_estimate = _estimate(sol, loads, sol.options["crack_model"])


def crack_profiles(disc: Discretization, cmesh: CrackMesh, gf: ngs.GridFunction, fields: dict,
                   friction: list[float] | None, pressures: list | None = None) -> list[CrackProfile]:
    """One CrackProfile per crack from the solved GridFunction (no crack: an empty list);
    `pressures`: each crack's face pressure (scene.pressure fields), kept in the profiles."""
    if disc.jn is None:
        return []
    comps = gf.components
    jn_vals = comps[disc.jn].vec.FV().NumPy()
    jt_vals = comps[disc.jt].vec.FV().NumPy() if disc.jt is not None else None
    displacement = disc.tangential_jump(gf) if disc.tangential_jump is not None else None
    jump_space = disc.fes.components[disc.jn]
    profiles = []
    for k, crack in enumerate(cmesh.cracks):
        jumps = disc.crack_jumps(gf, crack) if disc.crack_jumps is not None else None
        prof = crack_profile(cmesh, crack, jump_space, jn_vals, jt_vals, fields["sigma"],
                             displacement=displacement, jumps=jumps, two_sided=disc.two_sided_traction,
                             friction=friction[k] if friction is not None else 0.0)
        if pressures is not None and pressures[k] is not None:
            prof = dataclasses.replace(prof, face_pressure=pressure_values(pressures[k], prof.s))
        profiles.append(prof)
    return profiles


def with_tractions(profiles: list[CrackProfile], disc: Discretization, system: CondensedSystem, y: np.ndarray,
                   cmesh: CrackMesh, G, forces) -> list[CrackProfile]:
    """The profiles with the element's consistent (or, for the baselines, lumped nodal) crack tractions."""
    if not profiles or not any(c is not None for c in disc.traction_rows):
        return profiles
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


def _built_line(qp, m: int, o: SolveOptions, disc: Discretization) -> str:
    """What the crack stage did, for `sol.built`."""
    if isinstance(qp, FrictionResult):
        return (f"crack problem with friction: {len(qp.w)} normal and {len(qp.wt)} tangential values, solver "
                f"{o.qp_solver}, {qp.method}: {qp.coulomb_iterations} iterations, {qp.steps} active-set steps")
    if qp is not None:
        return f"contact QP: {m} unknowns, solver {o.qp_solver}"
    if disc.jn is None:
        return "no crack: one linear solve, no QP"
    return f"crack model {o.crack_model!r}: one linear solve, no QP"


def _estimate(sol: Solution, loads: Loads, crack_model: str):
    """The solve's error estimate (estimate.py), or None where none exists (with the reason
    in sol.options["error_estimate"])."""
    from .estimate import estimate

    try:
        est = estimate(sol, loads, crack_model)
    except InputError as exc:
        sol.options["error_estimate"] = str(exc)
        return None
    sol.timings["estimate"] = est.time
    return est
