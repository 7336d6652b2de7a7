"""Hydraulic fracture, toughness-dominated: `hydrofrac(scene, rate=Q0, K_Ic=..., da=..., steps=...)`.

An inviscid fluid (uniform pressure in the crack; the viscous regime is a later step) is
injected at the rate Q0 into a crack of the scene; the scene's loads are the in-situ
stress. loop.py: the steps (pressure at propagation, volume and time, both tips
advanced by the growth package's MTS kink and path extension); result.py:
HydrofracResult (the JSON contract, the table, the animation); cli.py: `ngcrack hydrofrac`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ngcrack.shell.extras import lazy_exports

#: public name -> its module, imported on first use (the command line's parser loads cli.py
#: only, and with it this package: it must not load the solver)
_EXPORTS = {"KIC_RTOL": ".loop", "check_hydrofrac_options": ".loop", "hydrofrac": ".loop", "HydrofracResult": ".result"}

__all__ = ["KIC_RTOL", "HydrofracResult", "check_hydrofrac_options", "hydrofrac"]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)


if TYPE_CHECKING:
    from .loop import KIC_RTOL, check_hydrofrac_options, hydrofrac
    from .result import HydrofracResult
