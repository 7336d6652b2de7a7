"""The elastic crack seen by the fluid: a compliance over the fluid cells from ngcrack's mixed solve.

The crack problem of a solve is posed on the crack's normal-jump unknowns: S jn = b, S the
Schur complement of the condensed mixed system (`ngcrack.core.hybrid`), b = b_0 + B p, where
a crack-face pressure p only loads those unknowns (the virtual work int p [v].nu ds). For a
pressure constant on each crack edge (the fluid cells), B's column of an edge is the load
of a unit pressure on it: the edge's length at its mean-jump unknown (the jumps are
discontinuous per edge), 0 elsewhere. So, with the factorization and S of one Pipeline
kept, the opening at the cells' mid points is w = C p + w_is with

    C = R S^-1 B,    w_is = R S^-1 b_0,

R picking the mean-jump unknowns (the mid-point opening of a linear jump). Two load vectors
(the scene's loads with p = 0 and with p = 1, which give b_0 and B's columns) and one
Cholesky factorization of S (m x m, m the crack unknowns) give C for every cell: no solve
per cell. The faces are taken as open (the crack is filled with fluid: no lag); the
step's mixed solve with the fluid's pressure and contact reports the K's and the KKT check.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ...core.element_names import MIXED
from ...core.options import SolveOptions
from ...core.pipeline import Pipeline, SolveError
from ..growth.loop import tip_values
from ..volume import with_pressure

#: the probe pressure's load is this many times the in-situ load on the crack unknowns
PROBE_RATIO = 1e6
#: entries of B below this fraction of its largest are round-off (not a mean-jump unknown)
B_RTOL = 1e-10
#: B's entries must be the edge lengths to this relative precision (the element's jumps are
#: one mean unknown per crack edge)
LENGTH_RTOL = 1e-8
#: the elements whose crack unknowns have that structure, the mixed ones (their normal jump is
#: discontinuous per edge; checked again at every step): the displacement elements' jump is the
#: duplicated faces' continuous displacement
ELEMENTS = MIXED


@dataclass
class CrackCompliance:
    """The fluid cells of crack `crack` (its mesh edges, in arc-length order): mid arc lengths
    `s`, lengths `h`, mid points `x`, `y`, the compliance `C` and the in-situ opening `w_is`;
    `K_unit`: per tip end, K_I under a unit pressure on the crack alone (the interaction integral)."""

    s: np.ndarray
    h: np.ndarray
    x: np.ndarray
    y: np.ndarray
    C: np.ndarray
    w_is: np.ndarray
    crack_mesh: object
    K_unit: dict


def crack_compliance(pipe: Pipeline, scene, crack: int, options: SolveOptions) -> CrackCompliance:
    """The compliance of crack `crack` of `scene` over its edges (module docstring), through `pipe`."""
    from scipy.linalg import cho_factor, cho_solve

    o = SolveOptions.of(options, crack_model="contact")
    scene0 = with_pressure(scene, [crack], 0.0)
    Pipeline.check(scene0, o)
    cmesh = pipe.mesh(scene0, o)

    def reduction(sc):
        disc, loads = pipe.discretization(sc, cmesh, o)
        return disc, pipe.reduction(pipe.system(disc, loads, False), o)

    disc, red0 = reduction(scene0)
    b0, S = np.array(red0.b), red0.S
    edges = cmesh.cracks[crack]
    order = np.argsort(edges.s_mid)
    h = np.asarray(edges.length)
    # a probe pressure whose load dwarfs the in-situ one, so that B = (b(p) - b_0) / p keeps its digits
    probe = max(1.0, PROBE_RATIO * float(np.max(np.abs(b0), initial=0.0)) / float(np.max(h)))
    B = (reduction(with_pressure(scene, [crack], probe))[1].b - b0) / probe
    nz = mean_jump_unknowns(disc, edges, red0.system.contact)
    others = np.setdiff1d(np.arange(len(B)), nz if nz is not None else [])
    if nz is None or not np.allclose(B[nz], h, rtol=LENGTH_RTOL, atol=0) \
            or np.any(np.abs(B[others]) > B_RTOL * np.max(np.abs(B))):
        raise SolveError(f"element {o.element!r}: its crack unknowns are not one mean jump per crack edge; "
                         f"the viscous fluid needs one of {', '.join(ELEMENTS)}")
    factor = cho_factor(S)
    rhs = np.zeros((len(b0), len(nz) + 1))
    rhs[:, 0] = b0
    rhs[nz, np.arange(1, len(nz) + 1)] = h
    X = cho_solve(factor, rhs)[nz]
    C, w_is = X[:, 1:][order][:, order], X[:, 0][order]
    mid = np.asarray(edges.mid)[order]
    # the tips' K_I under a unit pressure alone (the scene's other loads set to zero: the same
    # assembled forms and factorization, one more solve), for the tip calibration
    unit = pipe.run(unloaded(scene, crack), o, crack_mesh=cmesh)
    K_unit = {v["end"]: v["K_I"] for v in tip_values(unit) if v["crack"] == crack}
    return CrackCompliance(s=np.asarray(edges.s_mid)[order], h=h[order], x=mid[:, 0], y=mid[:, 1], C=C, w_is=w_is,
                           crack_mesh=cmesh, K_unit=K_unit)


def unloaded(scene, crack: int):
    """The scene with a unit pressure on crack `crack` and every other load value zero (the
    same load structure: the assembled forms are reused)."""
    from ...planar.scene.types import BoundaryCondition

    boundary = {lab: BoundaryCondition(bc.type, None if bc.value is None else tuple(0.0 for _ in bc.value))
                for lab, bc in scene.boundary.items()}
    changes = {"boundary": boundary}
    if scene.body_force is not None:
        changes["body_force"] = tuple(0.0 for _ in scene.body_force)
    if getattr(scene, "points", ()):
        changes["points"] = tuple(dataclasses.replace(pc, value=None if pc.value is None else tuple(0.0 for _ in pc.value))
                                  for pc in scene.points)
    cracks = tuple(dataclasses.replace(c, pressure=1.0 if k == crack else (0.0 if isinstance(c.pressure, float) else c.pressure))
                   for k, c in enumerate(scene.cracks))
    return scene.with_(cracks=cracks, **changes)


def mean_jump_unknowns(disc, edges, contact) -> np.ndarray | None:
    """The crack unknown (its position in the crack problem) of each edge's mean normal jump:
    the edge's first (lowest-order) dof of the jump space, None where the layout differs."""
    if disc.jn is None:
        return None
    import ngsolve as ngs

    space = disc.fes.components[disc.jn]
    if len(contact) != space.ndof:
        return None
    first = [list(space.GetDofNrs(ngs.NodeId(ngs.EDGE, int(e)))) for e in edges.edge]
    if any(not d or d[0] < 0 for d in first):
        return None
    return np.array([d[0] for d in first], dtype=int)


def pressure_table(s_edges: np.ndarray, p: np.ndarray) -> list:
    """The crack-face pressure table (rows [s, p], a repeated s a jump) that is p[i] on the cell
    between s_edges[i] and s_edges[i + 1]."""
    rows = []
    for i, v in enumerate(p):
        rows += [[float(s_edges[i]), float(v)], [float(s_edges[i + 1]), float(v)]]
    return rows
