"""The answer of one solve of a 2D scene: `PlanarSolution`, what every stage of the pipeline hands to the user.

It holds the scene, the mesh, the discretization and its GridFunction, the fields, the
crack profiles, the KKT residuals, the tips' fracture parameters, the error estimate and
the timings; `to_json_dict` is the `solve --json` contract. NGSolve users find NGSolve's
names on it: `sol.gfu` (the GridFunction), `sol.fes` (its space), `sol.mesh`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import ngsolve as ngs
import numpy as np

from ..core.constraints import KKT_KEYS
from ..core.contact import QPResult
from ..core.discretization import Discretization, PostProcessing
from ..core.options import SolveOptions
from ..core.solution import Backend, Front, Solution, summary_line

if TYPE_CHECKING:
    from .geometry import CrackMesh
    from .post import CrackProfile
    from .scene import Scene


@dataclass
class PlanarSolution(Solution):
    """The answer of one solve of a 2D scene (a kind of `ngcrack.core.solution.Solution`).

    `u`, `sigma`, `rotation` are NGSolve CoefficientFunctions (u is P0 per triangle,
    sigma the weakly symmetric 2x2 stress); `gf` is the full GridFunction. `profiles`
    holds one CrackProfile per crack (with its open / stick / slip `state`), `qp` the QP's
    answer (None without a crack; a friction.FrictionResult with friction).

    `kkt`: the relative residuals of the discrete Signorini conditions where the QP's
    constraints live (edge mid points for P0 jumps, edge end points for P1 jumps, crack
    nodes for h1p1/h1p2), with the constrained values w = G j of the answer and the
    discrete contact forces `forces` computed from the solved system
    (`constraints.discrete_contact_forces`, `constraints.kkt_at_constraints`): round-off small for
    crack_model "contact"; under "friction", the discrete Coulomb law's residual at the
    same points (0 without friction). For "free" and "bonded" they measure the same
    conditions on that model's answer: max_penetration > 0 where free faces
    interpenetrate, max_tension > 0 where bonded faces pull on each other. `kkt_sampled`:
    the same figures from the edge mid-point samples of the crack profiles (a diagnostic:
    a P1 jump sampled on the edge where contact ends carries both a small opening and a
    small pressure). No crack: all zero. `timings` in seconds, `ndof` counts (total,
    global after condensation, contact), `built` lists what was built.

    `solve_options` are the options the solve was asked for (`SolveOptions`), `backend`
    what it chose (`Backend`); `options` names both for printing and comparing (and holds
    what a loop around the solve reports: `adapt`). `no_estimate` says why a solve has no
    error estimate ("" where it has one).
    """

    dimension = 2

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
    #: with adapt=TOL: one row per refinement step (adapt.py), a pandas DataFrame
    adapt_history: object = None
    #: the options the solve was asked for, and what it chose where they left it open
    solve_options: SolveOptions | None = None
    backend: Backend | None = None
    #: the error estimate once computed, why there is none, and the computation a solve
    #: leaves pending (`error_estimate`, `no_estimate`)
    _estimate: object = field(default=None, repr=False)
    _no_estimate: str = field(default="", repr=False)
    _pending_estimate: object = field(default=None, repr=False, compare=False)
    #: the post-processing of the body's dimension that made the profiles and tips (the pipeline's)
    post: PostProcessing | None = field(default=None, repr=False, compare=False)

    def __repr__(self) -> str:
        """A few lines: scene, element, sizes, KKT, the tips' K and the estimate if computed
        (printing a solution never computes anything nor dumps its arrays)."""
        nd = self.ndof
        lines = [f"Solution(scene={self.scene.name!r}, element={self.element!r}, crack_model={self.crack_model!r}, "
                 f"maxh={self.maxh:g})",
                 f"  unknowns: {nd.get('total', 0):,} total, {nd.get('global', 0):,} global, "
                 f"{nd.get('contact', 0):,} contact; {len(self.profiles)} crack(s); "
                 f"KKT max {max(self.kkt.values(), default=0.0):.1e}"]
        for t in self.tips:
            lines.append(f"  tip {t.label}: K_I {t.K_I:.4g}, K_II {t.K_II:.4g}")
        if self.estimate_pending:
            lines.append("  error estimate: not computed yet (sol.error_estimate)")
        elif self._estimate is not None:
            lines.append(f"  error estimate: relative {self._estimate.relative:.2%}")
        return "\n".join(lines)

    @property
    def fronts(self) -> list[Front]:
        """Every crack tip inside the body as a front of one point (`tips`: the same K_I, K_II, G, T)."""
        return [Front(crack=t.crack, points=np.array([[t.x, t.y]]), K_I=np.array([t.K_I]), K_II=np.array([t.K_II]),
                      K_III=np.zeros(1), G=np.array([t.G]), closed=np.array([bool(t.closed)]), T=np.array([t.T]),
                      label=t.label) for t in self.tips]

    @property
    def contact(self):
        """The crack problem's answer (a QPResult; a FrictionResult with friction; None without a crack): `qp`."""
        return self.qp

    @property
    def crack_model(self) -> str:
        """The crack model the solve used ("contact" unless its options say otherwise)."""
        return self.solve_options.crack_model if self.solve_options is not None else "contact"

    @property
    def friction_applied(self) -> bool:
        """Whether the crack problem kept the tangential jumps, i.e. friction acted."""
        return bool(self.backend is not None and self.backend.tangential)

    @property
    def mesh(self) -> ngs.Mesh:
        """The NGSolve mesh (cracks as interior edges)."""
        return self.crack_mesh.mesh

    @property
    def gfu(self) -> ngs.GridFunction:
        """The GridFunction of every unknown (NGSolve's name; also `gf`)."""
        return self.gf

    @property
    def fes(self) -> ngs.FESpace:
        """The (compound) finite element space of `gfu`."""
        return self.gf.space

    @property
    def u(self):
        """The displacement field (a CoefficientFunction)."""
        return self.fields["u"]

    @property
    def sigma(self):
        """The stress field (a 2x2 CoefficientFunction)."""
        return self.fields["sigma"]

    @property
    def rotation(self):
        """The rotation field of the weakly symmetric elements (None for the others)."""
        return self.fields.get("rotation")

    @property
    def maxh(self) -> float:
        """The mesh size the solve was meshed with."""
        return self.crack_mesh.maxh

    def crack_profiles(self) -> list[CrackProfile]:
        """Per crack: s, x, y, jumps and crack-face stresses at the edge mid points."""
        return self.profiles

    def save_vtk(self, path, **kwargs):
        """Write the fields and the crack faces for ParaView (the post-processor's writer: ngcrack.planar.vtk.save_vtk in 2D)."""
        return self.post.save_vtk(self, path, **kwargs)

    def report_lines(self, result: dict | None = None) -> list[str]:
        """What `ngcrack solve` prints of a 2D solve: sizes and seconds, the mesh sizes, the KKT residuals,
        friction, the tips' K, the error estimate, a distributed or adaptive run's record."""
        result = result if result is not None else self.to_json_dict()  # (the record, when already made)
        scene, o = self.scene, self.solve_options
        k, t, n, ks = result["kkt"], result["time_s"], result["ndof"], result["kkt_sampled"]
        lines = [f"{scene.name}: element {self.element}, maxh {self.maxh:g}, nu {scene.material.nu:g}, "
                 f"{n['total']} dofs ({n['global']} global, {n['contact']} contact), {t['total']:.2f} s"]
        if o is not None and not o.hp:
            from .sizing import describe_mesh_sizes

            lines.append(describe_mesh_sizes(scene, o.maxh, o.tip_h, o.crack_h))
        lines += [f"KKT at the constraint points: penetration {k['max_penetration']:.1e}, tension {k['max_tension']:.1e}, "
                  f"complementarity {k['complementarity']:.1e}, friction {k['friction']:.1e}",
                  f"    at the edge mid points:   penetration {ks['max_penetration']:.1e}, tension "
                  f"{ks['max_tension']:.1e}, complementarity {ks['complementarity']:.1e} (a diagnostic)"]
        if self.options.get("tangential"):
            states = [st for c in result["cracks"] for st in c["state"]]
            lines.append(f"friction: {self.qp.coulomb_iterations} Coulomb iterations; crack samples "
                         + ", ".join(f"{st} {states.count(st)}" for st in ("open", "stick", "slip")))
        if self.tips:
            from .tips import format_table

            lines.append(format_table(self.tips))
        if self.error_estimate is not None:
            lines.append(self.error_estimate.line())
        if "distributed" in result:
            lines.append(summary_line(result["distributed"]))
        if self.adapt_history is not None:
            steps = ", ".join(f"{r.ndof}: {r.estimate:.2%}" for r in self.adapt_history.itertuples())
            reached = "reached" if self.options["adapt"]["reached"] else "NOT reached (dof budget)"
            lines.append(f"adapt to {self.options['adapt']['tol']:g}: {reached}; dofs and relative estimate per step: {steps}")
        return lines

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
            # each adaptive step: its unknowns, its relative estimate, and its seconds (solve,
            # estimate and the refinement that made its mesh); time_s.total is the whole run
            **({"adapt": [{"ndof": int(r.ndof), "estimate": float(r.estimate),
                           "time_s": float(r.time_solve + r.time_estimate + r.time_refine)}
                          for r in self.adapt_history.itertuples()]}
               if self.adapt_history is not None else {}),
            # under mpiexec: ranks, subdomains, preconditioner, active-set and CG steps, memory per rank
            **({"distributed": self.options["distributed"]} if "distributed" in self.options else {}),
        }
