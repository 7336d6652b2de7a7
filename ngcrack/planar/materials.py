"""Isotropic linear elasticity in 2D: Lame parameters and the compliance A = C^{-1}.

The mixed elements only ever need the compliance, written here in E and nu so that it
stays finite and well defined up to and including nu = 1/2 (where lambda = infinity):

    plane strain:  A sigma = (1 + nu)/E * (sigma - nu tr(sigma) I)
    plane stress:  A sigma = 1/E * ((1 + nu) sigma - nu tr(sigma) I)

Both formulas also act on non-symmetric matrices (the weakly symmetric stress of the
PEERS and BDM elements). Units: E in stress units, A sigma is a strain (dimensionless).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError

PLANES = ("strain", "stress")


@dataclass(frozen=True)
class Compliance:
    """A sigma = c_dev * sigma - c_tr * tr(sigma) I, with the two scalars below."""

    c_dev: float
    c_tr: float

    @property
    def spherical(self) -> float:
        """A(I) = spherical * I: zero for plane strain at nu = 1/2 (incompressible)."""
        return self.c_dev - 2.0 * self.c_tr

    def with_spherical_floor(self, floor: float) -> Compliance:
        """The same compliance with A(I) at least `floor * c_dev` (see elements/base.py)."""
        if self.spherical >= floor * self.c_dev:
            return self
        return Compliance(c_dev=self.c_dev, c_tr=0.5 * (1.0 - floor) * self.c_dev)

    def apply(self, sigma):
        """A sigma for an NGSolve 2x2 matrix CoefficientFunction, or a numpy array of 2x2
        matrices (shape (..., 2, 2): one stress, or many at once)."""
        import ngsolve as ngs

        if isinstance(sigma, np.ndarray):
            return self.c_dev * sigma - self.c_tr * np.trace(sigma, axis1=-2, axis2=-1)[..., None, None] * np.eye(2)
        return self.c_dev * sigma - self.c_tr * ngs.Trace(sigma) * ngs.Id(2)


def compliance(E: float, nu: float, plane: str = "strain") -> Compliance:
    """The compliance of an isotropic material in plane strain or plane stress."""
    if plane == "strain":
        return Compliance(c_dev=(1.0 + nu) / E, c_tr=(1.0 + nu) * nu / E)
    if plane == "stress":
        return Compliance(c_dev=(1.0 + nu) / E, c_tr=nu / E)
    raise InputError(f"material.plane = {plane!r}: allowed values are {', '.join(PLANES)}")


def lame_parameters(E: float, nu: float, plane: str = "strain") -> tuple[float, float]:
    """(lambda, mu) of the 2D constitutive law sigma = 2 mu eps + lambda tr(eps) I.

    In plane stress lambda is the effective 2D value 2 lambda mu / (lambda + 2 mu).
    lambda is math.inf for plane strain at nu = 1/2.
    """
    mu = E / (2.0 * (1.0 + nu))
    if plane == "strain":
        lam = math.inf if nu == 0.5 else E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    elif plane == "stress":
        lam = E * nu / (1.0 - nu * nu)
    else:
        raise InputError(f"material.plane = {plane!r}: allowed values are {', '.join(PLANES)}")
    return lam, mu
