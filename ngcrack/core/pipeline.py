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

What depends on the body's dimension the stages ask of a body object chosen by the
scene (`scene.body`: `ngcrack.planar.stages.PLANAR`, or `ngcrack.solid.stages.SOLID` for a 3D scene):
the mesh and its key, the element and its key, the loads' crack pressures and held
means. A 3D scene runs through the same mesh, discretization and system stages
(`ngcrack.solid.stages.run_solid`, which `nc.solve` and `solve_solid` call), with the
sparse contact stage in place of the reduction and the QP.
"""

from __future__ import annotations

import functools
import time
import weakref
from typing import TYPE_CHECKING

import ngsolve as ngs
import numpy as np

from .fields import pressure_kind
from .scene import Scene

if TYPE_CHECKING:  # a planar body's mesh (a 3D body's is its own)
    from ..planar.geometry import CrackMesh
from .crack_problem import choose_strategy
from .discretization import Discretization, Loads
from .hybrid import CondensedSystem, ContactReduction, condense, reduce_to_contact
from .options import SolveOptions
from .solution import Backend, Solution
from .stages import (
    SolveError,
    built_line,
    condition_estimates,
    crack_stage,
    estimate_stage,
    faces_stage,
    recovery_stage,
    tips_stage,
)

#: scaled forward residual of the condensed solve above which a definite system counts
#: as singular: a safety net behind the exact rigid-motion check of the supports.
#: Measured: regular systems up to 3e-2 (nu = 1/2 - 1e-6, just before the incompressible
#: split takes over), singular ones (nothing holds the body) 8 to 60.
RESIDUAL_TOL = 1.0

#: the stages whose runs `Pipeline.counts` records
STAGES = ("mesh", "assemble", "load", "condense", "factorize")


# ------------------------------------------------------------------ loads

def load_structure(scene) -> tuple:
    """What the assembled forms depend on besides the load values: the supports and
    which labels carry loads (a scene of either dimension)."""
    return (tuple(sorted((lab, bc.type) for lab, bc in scene.boundary.items())), scene.body_force is not None,
            tuple((pc.label, pc.type) for pc in getattr(scene, "points", ())),
            tuple(pressure_kind(getattr(c, "pressure", None)) for c in scene.cracks))


class ParameterLoads:
    """The scene's loads as NGSolve Parameters: the assembled linear form follows their values.

    Every traction, displacement and body-force vector of the scene gets one Parameter
    per component (zero ones too, so a load scaled to zero keeps the same form);
    `set(scene)` copies a scene's values in (the scene must have the same
    `load_structure`). `body`: what depends on the body's dimension (PLANAR or the 3D one).
    """

    def __init__(self, scene, body=None):
        body = body if body is not None else scene.body
        self.structure = load_structure(scene)
        self.params: dict[tuple[str, str], tuple[ngs.Parameter, ...]] = {}
        traction, displacement, clamped, roller = {}, {}, set(), set()
        dim = body.dimension
        for label, bc in scene.boundary.items():
            if bc.type == "clamped":
                clamped.add(label)
            elif bc.type == "roller":
                roller.add(label)
            else:
                p = tuple(ngs.Parameter(0.0) for _ in range(dim))
                self.params[(bc.type, label)] = p
                (traction if bc.type == "traction" else displacement)[label] = ngs.CF(p)
        force = None
        if scene.body_force is not None:
            p = tuple(ngs.Parameter(0.0) for _ in range(dim))
            self.params[("body", "")] = p
            force = ngs.CF(p)
        # crack-face pressures: a uniform one a Parameter, a table or callable a fixed function
        self.pressures: dict[int, ngs.Parameter] = {}
        crack_pressure = {}
        for k, crack in enumerate(scene.cracks):
            pressure = getattr(crack, "pressure", None)
            if pressure is None:
                continue
            param = ngs.Parameter(0.0) if isinstance(pressure, float) else None
            cf = body.crack_pressure(scene, k, param)
            if cf is None:  # the element takes it as a number
                continue
            if param is not None:
                self.pressures[k] = param
            crack_pressure[k] = cf
        self.loads = Loads(body_force=force, traction=traction, displacement=displacement,
                           clamped=frozenset(clamped), roller=frozenset(roller), crack_pressure=crack_pressure,
                           held_mean=body.held_mean(scene))
        self.set(scene)

    def set(self, scene) -> None:
        """Copy the load values of `scene` (of the same load structure) into the Parameters."""
        for (kind, label), params in self.params.items():
            value = scene.body_force if kind == "body" else scene.boundary[label].value
            for p, v in zip(params, value):
                p.Set(float(v))
        for k, param in self.pressures.items():
            param.Set(float(scene.cracks[k].pressure))


def scene_loads(scene: Scene) -> Loads:
    """The scene's boundary conditions and loads as NGSolve CoefficientFunctions (ParameterLoads)."""
    return ParameterLoads(scene).loads


def relative_residual(system: CondensedSystem, x_rest: np.ndarray) -> float:
    """|D (K_rr x - F_r)| / |D F_r|, D = diag(K_rr)^(-1/2): the forward residual in units
    that do not depend on the unknowns' units (rotations next to displacements).

    LU keeps the backward error at round-off even for a singular matrix, so it is the
    forward residual that tells: about eps cond(D K_rr D) for a regular system, O(1)
    for a singular one.
    """
    r, K = system.rest, system.K_csr
    y = np.zeros(system.n)
    y[r] = x_rest  # K_rr x_rest = (K y)_r with y_c = 0, without copying K_rr
    diag = np.abs(K.diagonal()[r])
    D = np.where(diag > 0, 1.0 / np.sqrt(np.where(diag > 0, diag, 1.0)), 1.0)
    Fs = D * system.F[r]
    norm_F = np.linalg.norm(Fs)
    return float(np.linalg.norm(D * ((K @ y)[r] - system.F[r])) / norm_F) if norm_F > 0 else 0.0


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
        self._pending: list = []  # weak references to solutions whose error estimate is still to be computed

    def settle_estimates(self) -> None:
        """Compute the pending error estimates of this pipeline's solutions (before their loads change)."""
        pending, self._pending = self._pending, []
        for ref in pending:
            sol = ref()
            if sol is not None and sol.estimate_pending:
                sol.error_estimate  # noqa: B018 -- computed now, kept by the solution

    def clear(self) -> None:
        """Forget every cached stage (the counts stay)."""
        self._mesh = None
        self.keep_mesh_only()

    def keep_mesh_only(self) -> None:
        """Forget every stage after the mesh (the assembled forms, the factorizations): what
        a sweep's worker keeps between its runs, which share meshes but rarely more."""
        self._disc = None
        self._systems, self._reductions = {}, {}

    # -------------------------------------------------------------- stages
    @staticmethod
    def body_for(scene):
        """What the stages ask of the scene's body (`scene.body`: ngcrack.planar.stages.PLANAR in 2D,
        ngcrack.solid.stages.SOLID in 3D)."""
        return scene.body

    def mesh(self, scene, options):
        """The scene's mesh (a 2D CrackMesh with cracks as interior edges, or a 3D SolidMesh),
        cached under the body's mesh key (`PlanarBody.make_mesh`)."""
        body = self.body_for(scene)
        key = (body.dimension, body.mesh_key(scene, options))
        if self._mesh is None or self._mesh[0] != key:
            self._mesh = (key, body.make_mesh(scene, options))
            self.counts["mesh"] += 1
            self.redone.append("mesh")
        return self._mesh[1]

    def discretization(self, scene, crack_mesh, options, loads: Loads | None = None) -> tuple[Discretization, Loads]:
        """The element's spaces and assembled forms on `crack_mesh` and the loads they hold.

        Without `loads`, the scene's loads become Parameters of the assembled linear form
        (ParameterLoads): a scene that differs only in load values re-assembles the load
        vector. Given `loads` (CoefficientFunctions), the forms are reused only for that
        same Loads object.
        """
        body = self.body_for(scene)
        key = (body.dimension, body.element_key(scene, options),
               load_structure(scene) if loads is None else ("given", id(loads)))
        cached = self._disc
        if cached is not None and cached[0] == key and cached[1].crack_mesh is crack_mesh \
                and (loads is None or cached[3] is loads):
            _, disc, ploads, held = cached
            if ploads is not None:
                self.settle_estimates()  # before the loads' Parameters change under them
                ploads.set(scene)
                disc.assemble_load()  # (tens of microseconds: starting the TaskManager would cost more)
                self.counts["load"] += 1
                self.redone.append("load vector")
            return disc, held
        ploads = ParameterLoads(scene, body) if loads is None else None
        held = ploads.loads if ploads is not None else loads
        disc = body.build(scene, crack_mesh, options, held)
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
        """The factorization of K_rr and the Schur complement on the crack unknowns, cached per layout (no
        Schur complement where the crack problem's strategy is the sparse one: `crack_problem.choose_strategy`)."""
        linear_solver, schur = options.reduction_key
        if schur is not False and system.n_normal is None and choose_strategy(len(system.contact)) == "sparse":
            schur = False
        key = ((linear_solver, schur), len(system.contact), system.n_normal)
        cached = self._reductions.get(key)
        if cached is not None and cached.system.K_csr is system.K_csr and np.array_equal(cached.system.contact, system.contact):
            self.redone.append("one solve (factorization and S reused)")
            return cached.with_load(system)
        red = reduce_to_contact(system, linear_solver=linear_solver, schur=schur)
        self._reductions[key] = red
        self.counts["factorize"] += 1
        self.redone.append("factorization and S")
        return red

    # -------------------------------------------------------------- checks
    @staticmethod
    def check(scene: Scene, options: SolveOptions, loads: Loads | None = None, size: bool = True) -> None:
        """Every check of a request that needs the scene, before any work: the options
        against the scene (friction), what the element cannot solve (nu = 1/2), the size guard and the thin parts (`size`), the
        supports of given loads, an undetermined pressure."""
        options.check_for(scene)
        scene.body.check(scene, options, loads, size)

    # -------------------------------------------------------------- one run
    def run(self, scene: Scene, options: SolveOptions | None = None, *, loads: Loads | None = None,
            warm_start=None, crack_mesh: CrackMesh | None = None, check_size: bool = True) -> Solution:
        """Solve `scene` with `options` (SolveOptions; the defaults if None), reusing what is cached.

        `loads` replaces the scene's loads (manufactured solutions); `warm_start` a previous
        Solution or an active set (contact zone carried over); `crack_mesh` a ready mesh of
        the scene (no meshing, no size guard). `check_size`: run the size guard before
        meshing (sizing.check_request). Adaptivity is not a stage: see ngcrack.studies.adapt.

        The stages, in order: checks, mesh, discretization, condensed system, reduction,
        crack problem, recovery, crack faces (profiles and KKT), tips, estimate.
        """
        o = options if options is not None else SolveOptions()
        self.redone = []
        self.check(scene, o, loads, size=crack_mesh is None and check_size)
        t_start = time.perf_counter()
        timings: dict[str, float] = {}
        case = f"scene {scene.name!r}, element {o.element!r}"

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
        normal_contact = system.contact if system.n_normal is None else system.contact[:system.n_normal]
        if o.crack_model == "free":
            system = system.without_contact()

        red = self._reduce(system, o, case)
        timings.update(red.timings)
        answer = crack_stage(red, disc, cmesh, normal_contact, o, tangential, mu, warm_start)
        timings["qp"] = answer.time
        conditioning = condition_estimates(red) if o.condition else {}
        rec = recovery_stage(red, system, disc, answer.jn, case)
        timings["recover"] = rec.time
        post = scene.body.post
        faces = faces_stage(system, disc, post, rec, answer, normal_contact, mu if tangential else None,
                            [c.pressure for c in scene.cracks], case)

        # linear: the factorization and solves a plain linear solve needs too (with the
        # local recovery); contact: what the crack adds (Schur complement and QP)
        timings["linear"] = timings["factorize"] + timings["solve"] + timings["recover"]
        timings["contact"] = timings["schur"] + timings["qp"]
        timings["total"] = time.perf_counter() - t_start
        m = len(system.contact)
        backend = Backend(qp_solver=o.qp_solver, linear_solver=red.factorization.backend, schur=red.method,
                          largest_dense=red.largest_dense, tangential=bool(tangential),
                          friction=tuple(float(f) if o.crack_model == "contact" else 0.0 for f in mu))
        sol = scene.body.solution_type(
            scene=scene, element=o.element, crack_mesh=cmesh, disc=disc, gf=rec.gf, fields=rec.fields,
            profiles=faces.profiles, kkt=faces.kkt, qp=answer.qp, timings=timings,
            ndof={"total": disc.fes.ndof, "global": system.n, "contact": m},
            built=list(disc.built) + [built_line(answer.qp, m, o, disc)],
            options=backend.report(o), solve_options=o, backend=backend,
            conditioning=conditioning, kkt_sampled=faces.kkt_sampled, forces=faces.forces, post=post,
        )
        self.post_process(sol, loads)
        self.keep_pending(sol)
        return sol

    def keep_pending(self, sol) -> None:
        """Remember `sol` while its error estimate is pending: it is computed before the loads' Parameters
        change under it (`settle_estimates`, at the next load change)."""
        self._pending = [r for r in self._pending if r() is not None and r().estimate_pending]
        if sol.estimate_pending:
            self._pending.append(weakref.ref(sol))

    def _reduce(self, system: CondensedSystem, options: SolveOptions, case: str) -> ContactReduction:
        """The reduction stage with its checks: a finite system, a regular factorization, a finite solve."""
        if not (np.all(np.isfinite(system.K_csr.data)) and np.all(np.isfinite(system.F))):
            raise SolveError(f"{case}: the assembled system has non-finite entries (check the loads and material data)")
        try:
            red = self.reduction(system, options)
        except RuntimeError as exc:  # SuperLU: "Factor is exactly singular"
            raise SolveError(f"{case}: the condensed system is singular ({exc}); is every part of the body held?") from exc
        if not (np.all(np.isfinite(red.x0)) and np.all(np.isfinite(red.S))):
            raise SolveError(f"{case}: the condensed solve gave non-finite values (singular system; "
                             "is every part of the body held?)")
        residual = relative_residual(system, red.x0) if system.disc.definite else 0.0
        if residual > RESIDUAL_TOL:
            raise SolveError(f"{case}: the condensed system is singular to working precision (relative residual "
                             f"{residual:.1e} of its solve); is every part of the body held?")
        return red

    def post_process(self, sol: Solution, loads: Loads) -> None:
        """The tips' K_I, K_II, G and the error estimate of a solved `sol` (their times in sol.timings)."""
        tips_stage(sol, loads, sol.post)
        if sol.solve_options is not None and sol.solve_options.estimate is False:
            sol.no_estimate = "not asked for (estimate = False)"
            return
        # computed when first asked for; the Parameters of `loads` change with the next load value,
        # so a pending estimate is settled before that (Pipeline.discretization)
        sol.defer_estimate(functools.partial(estimate_stage, sol, loads, sol.crack_model, sol.post))
        if sol.solve_options is not None and sol.solve_options.estimate:
            sol.error_estimate  # noqa: B018 -- asked for: computed now, inside the solve
