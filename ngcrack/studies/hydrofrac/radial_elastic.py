"""The elastic penny seen by the radial fluid: a ring compliance from ngcrack's 3D mixed solve.

A 3D solve's crack problem is posed on the crack's normal-jump unknowns jn (P_k per crack
face, `solid.element`), and a crack-face pressure p loads only those: its load vector is
the integral of p against jn's test functions over the crack's faces. For the fluid's ring
pressures (p uniform on each ring r_j < r < r_(j+1) of the disc) the load is linear in the
ring values, b = b_is + B p, B's column j the load of the ring's indicator chi_j (assembled
by NGSolve with that CoefficientFunction of the distance from the centre, mapped to the
condensed system's unknowns as the scene's loads are). One mesh, one assembly and one sparse
factorization of the condensed system K then give, by N + 1 solves with the same factor,
Y = K^-1 [b_is, B], and the rings' volumes exactly:

    V_kj = int chi_k w^(j) dA = B_k . Y_j (in the system's units),

the work of ring k's unit pressure on ring j's opening: symmetric (Maxwell-Betti) to
round-off, and summing over k to the crack's whole volume (the indicators sum to one at
every quadrature point). The compliance the flow sees is the rings' mean opening,
C_kj = V_kj / A_k, and w_is = V_k,is / A_k the opening of the scene's other loads (in-situ
stress). The faces are taken as open (the crack is filled with fluid, no lag): the
opening is the free crack's, linear in p.

The tip calibration (as the plane model's `flow.tip_calibration`): the front's mean K_I under
a unit pressure alone, by the interaction integral on the solution K^-1 B 1 (no further
solve), gives the K field's mean opening over the ring next to the front ring; the ratio
of the compliance's to it is the factor by which the mesh's opening there is off (the
linear jump on faces that end at the front), taken out where the tip asymptote is imposed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...core.options import SolveOptions
from ...core.pipeline import Pipeline, SolveError

#: extra quadrature order of the ring indicators' loads (a discontinuous integrand on the faces the ring
#: edges cut: the volumes still sum exactly, the rings' shares converge with it)
RING_BONUS_ORDER = 6
#: the compliance's asymmetry above this fraction of its largest volume is not round-off
SYMMETRY_RTOL = 1e-8


@dataclass
class RingElastic:
    """The elastic disc over the fluid's rings: `edges` (0 .. R), the compliance `C` (ring-mean opening per
    unit ring pressure), `w_is` (the other loads' opening), `K_unit` (the front's mean K_I under a unit
    pressure alone) and `K_spread` (its (largest - least) / mean), `scale` (the calibration, module
    docstring), the front's points, the solutions `Y` ([b_is, B] solved) and what evaluates an opening at
    points (`opening_at`)."""

    edges: np.ndarray
    C: np.ndarray
    w_is: np.ndarray
    K_unit: float
    K_spread: float
    scale: float
    front_points: np.ndarray
    ndof: int
    asymmetry: float
    Y: np.ndarray
    system: object
    crack: object
    jn: int

    def opening_at(self, p: np.ndarray, radii) -> np.ndarray:
        """The 3D solve's normal jump at distances `radii` from the centre along the disc's e_a, under the
        ring pressures `p` (one expansion of the condensed solution)."""
        import ngsolve as ngs

        gf = self.system.expand(self.Y @ np.concatenate([[1.0], p]))
        jn = gf.components[self.jn]
        mesh = self.system.disc.crack_mesh.mesh
        c = self.crack
        out = []
        for r in radii:
            x = c.center + float(r) * c.e_a
            out.append(float(np.asarray(jn(mesh(float(x[0]), float(x[1]), float(x[2]), ngs.BND))).ravel()[0]))
        return np.array(out)


def ring_indicator(center, normal, a: float, b: float, last: bool):
    """The CoefficientFunction 1 on a <= r < b (r the in-plane distance from `center`), 0 elsewhere; `last`
    reaches out to every r >= a (the front ring: the curved faces at the front stay inside it)."""
    import ngsolve as ngs

    d = [c - float(o) for c, o in zip((ngs.x, ngs.y, ngs.z), center)]
    along = sum(float(n) * di for n, di in zip(normal, d))
    r2 = sum(di * di for di in d) - along * along
    r = ngs.sqrt(ngs.IfPos(r2, r2, 0.0))
    inner = ngs.IfPos(r - a, 1.0, 0.0) if a > 0 else ngs.CF(1.0)
    return inner if last else inner * ngs.IfPos(r - b, 0.0, 1.0)


def ring_loads(system, disc, smesh, crack: int, disc_crack, edges: np.ndarray) -> np.ndarray:
    """B: per ring, the condensed system's load vector of a unit pressure on the ring (module docstring),
    mapped as `hybrid.CondensedSystem.with_load` maps the scene's loads; `disc_crack` the scene's disc."""
    import ngsolve as ngs

    c = smesh.cracks[crack]
    center, normal = np.asarray(disc_crack.center, float), np.asarray(disc_crack.normal, float)
    test = disc.fes.TestFunction()
    mesh = smesh.mesh
    cols = []
    for k in range(len(edges) - 1):
        chi = ring_indicator(center, normal, float(edges[k]), float(edges[k + 1]), k == len(edges) - 2)
        lf = ngs.LinearForm(disc.fes)
        lf += -chi * test[disc.jn].Trace() * ngs.ds(definedon=mesh.Boundaries(c.label), bonus_intorder=RING_BONUS_ORDER)
        lf.Assemble()
        fmod = lf.vec.CreateVector()
        fmod.data = lf.vec
        fmod.data += disc.a.harmonic_extension_trans * fmod
        rhs = fmod.FV().NumPy()[system._free] / disc.force_unit
        cols.append(disc.sign * (system._T_csr.T @ rhs))
    return np.column_stack(cols)


def ring_elastic(pipe: Pipeline, scene, crack: int, edges: np.ndarray, options: SolveOptions, E_prime: float,
                 tip_mean) -> RingElastic:
    """The ring compliance of crack `crack` (a disc of radius edges[-1]) of `scene` (module docstring), through
    `pipe`. `tip_mean(K)`: the mean over the ring next to the front ring of the K field K' x^(1/2) / E'
    for the front's K_I = K (the calibration)."""
    from ...core.schur import Factorization
    from ...solid.front import front_parameters
    from ...solid.options import solid_options
    from ...solid.output import SolidSolution
    from ...solid.stages import check_request
    from .radial import disc_scene

    R = float(edges[-1])
    unit = disc_scene(scene, crack, R, 1.0)
    o = SolveOptions.of(options, crack_model="free")
    opts = solid_options(o)
    check_request(unit, opts, o.max_dof)
    smesh = pipe.mesh(unit, opts)
    disc, loads = pipe.discretization(unit, smesh, opts)
    system = pipe.system(disc, loads, False)
    B = ring_loads(system, disc, smesh, crack, unit.cracks[crack], edges)
    F_is = system.F - B.sum(axis=1)  # the other loads alone
    fac = Factorization(system.K, opts["linear_solver"])
    Y = fac.solve(np.column_stack([F_is, B]))
    if not np.all(np.isfinite(Y)):
        raise SolveError("the condensed solve gave non-finite values (is every part of the body held?)")
    vol = -disc.sign * disc.force_unit * (B.T @ Y)  # ring volumes: [other loads, per unit ring pressure]
    Vp = vol[:, 1:]
    asym = float(np.max(np.abs(Vp - Vp.T)) / np.max(np.abs(Vp)))
    if asym > SYMMETRY_RTOL:
        raise SolveError(f"the ring compliance is not symmetric ({asym:.2e} of its largest entry): the crack "
                         "unknowns are not the pressure's work-conjugates")
    area = math.pi * (edges[1:] ** 2 - edges[:-1] ** 2)
    C = 0.5 * (Vp + Vp.T) / area[:, None]
    w_is = vol[:, 0] / area
    # the calibration: the front's K_I under a unit pressure alone, on K^-1 B 1 (no other solve)
    y_unit = Y[:, 1:].sum(axis=1)
    alone = SolidSolution(scene=unit, smesh=smesh, disc=disc, system=system, y=y_unit, gf=system.expand(y_unit),
                          contact=None, G=None, options={}, timings={})
    fronts = front_parameters(alone, points=opts["front_points"])
    front = next((f for f in fronts if f.crack == crack), None)
    if front is None:
        raise SolveError(f"the solve gave no front for crack {crack}")
    K_unit = float(np.mean(front.K_I))
    if not K_unit > 0:
        raise SolveError(f"a unit pressure does not open the front of crack {crack} (mean K_I = {K_unit:.4g})")
    scale = float(np.sum(C[-2])) / tip_mean(K_unit)
    K_spread = float((np.max(front.K_I) - np.min(front.K_I)) / K_unit)
    return RingElastic(edges=edges, C=C, w_is=w_is, K_unit=K_unit, K_spread=K_spread, scale=scale,
                       front_points=np.asarray(front.points),
                       ndof=int(disc.fes.ndof), asymmetry=asym, Y=Y, system=system, crack=unit.cracks[crack], jn=disc.jn)
