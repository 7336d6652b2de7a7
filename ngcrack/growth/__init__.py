"""Quasi-static crack growth: `grow(scene, da=..., steps=..., K_Ic=None, criterion="pls")`.

criteria.py: the kink criteria (MTS closed form, PLS helpers) as pure functions;
paths.py: extending a tip, clipping at the boundary, stopping before another crack;
loop.py: the step loop; result.py: GrowthResult (table, JSON, figures); study.py: one path per
parameter value through the sweep's executors; cli.py: `ngcrack grow`.
"""

from .criteria import CRITERIA, mts_angle, mts_keq
from .loop import GROW_TOGETHER_RTOL, MAX_DA_FRACTION, MAX_STEPS, grow
from .result import GrowthResult
from .study import grow_study

__all__ = [
           "CRITERIA",
           "GROW_TOGETHER_RTOL",
           "MAX_DA_FRACTION",
           "MAX_STEPS",
           "GrowthResult",
           "grow",
           "grow_study",
           "mts_angle",
           "mts_keq",
]
