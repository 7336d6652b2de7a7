"""Quasi-static crack growth: `grow(scene, da=..., steps=..., K_Ic=None, criterion="pls")`.

criteria.py: the kink criteria (MTS closed form, PLS helpers) as pure functions;
paths.py: extending a tip, clipping at the boundary, stopping before another crack;
loop.py: the step loop (a 3D scene goes to loop3d.py: planar growth of its fronts, fronts3d.py the
front-point rules, surface3d.py those of surface and corner cracks, newman_raju_growth.py their
reference life, result3d.py its result); result.py: GrowthResult (table, JSON, figures); study.py: one path per
parameter value through the sweep's executors; cli.py: `ngcrack grow`.

The names below are imported from their modules on first use (`ngcrack grow --help` and
the command line's parser need only criteria.py).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ngcrack.shell.extras import lazy_exports

#: public name -> the module that defines it
_EXPORTS = {
    "CRITERIA": ".criteria", "mts_angle": ".criteria", "mts_keq": ".criteria",
    "GROW_TOGETHER_RTOL": ".loop", "MAX_DA_FRACTION": ".loop", "MAX_STEPS": ".loop", "grow": ".loop",
    "GrowthResult": ".result",
    "grow_study": ".study",
}

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


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)


if TYPE_CHECKING:
    from .criteria import CRITERIA, mts_angle, mts_keq
    from .loop import GROW_TOGETHER_RTOL, MAX_DA_FRACTION, MAX_STEPS, grow
    from .result import GrowthResult
    from .study import grow_study
