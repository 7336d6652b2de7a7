"""Hydraulic fracture: `hydrofrac(scene, rate=Q0, K_Ic=..., da=..., steps=..., viscosity=mu, ...)`.

A fluid is injected into a crack of the scene (the scene's loads are the in-situ stress).
run.py: the entry, its checks and the regime (K_m); loop.py: the inviscid fluid (uniform
pressure, toughness-dominated: the pressure at propagation, the tips at K_Ic advanced by
the growth package's MTS kink and path extension); viscous.py, flow.py, elastic.py: the
viscous fluid (lubrication along the crack, the tip asymptotes, leak-off, the compliance
from the mixed solve); radial.py: a 3D scene's radial fracture (a disc crack fed at its centre,
toughness-dominated, leak-off, K_m per step); multi.py: several cracks fed from one injection at
one pressure (the stress shadow decides which grows); transition.py: KGD between its vertices (the
universal tip asymptote over the whole crack, a reference); result.py: HydrofracResult (the JSON contract,
the table, the animation); cli.py: `ngcrack hydrofrac`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ngcrack.shell.extras import lazy_exports

#: public name -> its module, imported on first use (the command line's parser loads cli.py
#: only, and with it this package: it must not load the solver)
_EXPORTS = {"KIC_RTOL": ".loop", "check_hydrofrac_options": ".loop", "hydrofrac": ".run", "HydrofracResult": ".result",
            "RegimeWarning": ".run", "check_fluid_options": ".run", "read_schedule": ".run"}

__all__ = ["KIC_RTOL", "HydrofracResult", "RegimeWarning", "check_fluid_options", "check_hydrofrac_options", "hydrofrac",
           "read_schedule"]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)


if TYPE_CHECKING:
    from .loop import KIC_RTOL, check_hydrofrac_options
    from .result import HydrofracResult
    from .run import RegimeWarning, check_fluid_options, hydrofrac, read_schedule
