"""The answer of one solve, whatever the body: `Solution`, and the crack fronts it reports (`Front`).

Every solve returns a `Solution`: `PlanarSolution` for a 2D scene (ngcrack.planar.solution),
`SolidSolution` for a 3D one (ngcrack.solid.output). Both carry the same names for what the
dimensions share: the scene, the element, the GridFunction and its fields (`gf`, `u`, `sigma`),
the mesh with its cracks (`crack_mesh`), the unknowns (`ndof`: total, global, contact), the
seconds per stage (`timings`: "total", "mesh", "assemble", "linear", "contact", ...), the crack
problem's answer (`contact`), its KKT residuals (`kkt`), the fracture parameters along every
crack front (`fronts`: a 2D crack tip is a front of one point), the error estimate where there is
one, and `to_json_dict()` (the `solve --json` record). Under mpiexec the distributed solve returns
the solution on rank 0 (`is_root`) and None on the other ranks.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .options import SolveOptions

__all__ = ["Backend", "Front", "Solution", "summary_line"]


@dataclass
class Front:
    """The fracture parameters at points along one crack's front (a 2D tip: a front of one point).

    `crack` the crack's index; `points` (n, dimension) the front's points; `K_I`, `K_II`, `K_III`
    the stress intensity factors there (K_III = 0 in 2D), `G` the energy release rate, `T` the
    T-stress (NaN where not computed), `closed` whether the faces touch at the point (K_I is then
    reported as 0); `label` names the front ("0,first": crack 0's first end in 2D; "crack 0" in 3D).
    """

    crack: int
    points: np.ndarray
    K_I: np.ndarray
    K_II: np.ndarray
    K_III: np.ndarray
    G: np.ndarray
    closed: np.ndarray
    T: np.ndarray | None = None
    label: str = ""

    def to_json_dict(self) -> dict:
        """The front as the JSON record's `fronts[i]` (crack, points, K_I, K_II, K_III, G)."""
        return {"crack": self.crack, "points": np.asarray(self.points).tolist(), "K_I": np.asarray(self.K_I).tolist(),
                "K_II": np.asarray(self.K_II).tolist(), "K_III": np.asarray(self.K_III).tolist(),
                "G": np.asarray(self.G).tolist()}


class Solution:
    """The answer of one solve of either dimension (module docstring); each kind fills in its fields.

    The error estimate is shared machinery: a kind keeps `_estimate`, `_no_estimate` and
    `_pending_estimate` (dataclass fields), and the solve either computes it or leaves it
    pending (`defer_estimate`) until `error_estimate` is first read.
    """

    #: 2 (PlanarSolution) or 3 (SolidSolution)
    dimension: ClassVar[int] = 0
    #: the process that holds the answer: every serial solve, rank 0 of a distributed one (the
    #: others get None from nc.solve)
    is_root: ClassVar[bool] = True

    #: the fracture parameters along every crack front inside the body (a list of Front)
    fronts: list

    @property
    def error_estimate(self):
        """The a posteriori estimate of the stress error (the body's estimate), None where none exists.

        Computed on first access unless the solve was asked for it (a run that does not ask
        for it skips its cost); `sol.timings["estimate"]` is its time from then on."""
        if self._pending_estimate is not None:
            pending, self._pending_estimate = self._pending_estimate, None
            self._estimate = pending()
        return self._estimate

    @error_estimate.setter
    def error_estimate(self, value) -> None:
        self._pending_estimate = None
        self._estimate = value

    @property
    def no_estimate(self) -> str:
        """Why the solve has no error estimate ("" where it has one)."""
        self.error_estimate  # noqa: B018 -- a pending estimate decides
        return self._no_estimate

    @no_estimate.setter
    def no_estimate(self, value: str) -> None:
        self._no_estimate = value

    def defer_estimate(self, compute) -> None:
        """`compute()` gives the error estimate (or None, setting `no_estimate`) when first asked for."""
        self._estimate, self._pending_estimate = None, compute

    @property
    def estimate_pending(self) -> bool:
        """True while the error estimate is still to be computed."""
        return self._pending_estimate is not None

    def to_json_dict(self) -> dict:
        """The `solve --json` record (the JSON record of the body's dimension: docs, "The command line")."""
        raise NotImplementedError


@dataclass(frozen=True)
class Backend:
    """What a solve chose where its options left the choice open (typed, for the stages
    after the solve and for the report): `qp_solver` the crack problem's solver,
    `linear_solver` the sparse factorization's back end ("auto" resolved), `schur` the
    Schur-complement method, `largest_dense` the largest dense block it formed,
    `tangential` whether the crack problem kept the tangential jumps (friction applied),
    `friction` each crack's Coulomb coefficient as applied (0 without contact)."""

    qp_solver: str
    linear_solver: str
    schur: str
    largest_dense: int
    tangential: bool
    friction: tuple[float, ...]

    def report(self, options: SolveOptions) -> dict:
        """The options and choices of a solve by name (`Solution.options`: what is printed and compared)."""
        return {"qp_solver": self.qp_solver, "linear_solver": self.linear_solver, "schur": self.schur,
                "largest_dense": self.largest_dense, "tip_h": options.tip_h, "crack_model": options.crack_model,
                "order": options.order, "friction": list(self.friction), "friction_method": options.friction_method,
                "tangential": self.tangential, "hp": options.hp or 0}


def summary_line(info: dict) -> str:
    """The one line `ngcrack solve` prints after a distributed solve: ranks, subdomains, preconditioner, steps."""
    steps = info["cg_steps"]
    cg = f"{sum(steps)} CG steps ({', '.join(map(str, steps))} per active-set step)"
    return (f"distributed over {info['ranks']} ranks ({info['subdomains']} subdomains), preconditioner "
            f"{info['preconditioner'].split(':')[0]}: {info['active_set_steps']} active-set steps, {cg}")
