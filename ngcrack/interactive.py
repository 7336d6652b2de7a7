"""Former home of the explorer, kept so that old imports work (importing it warns once): see `ngcrack.shell.explorer`.

The explorer's model is `ngcrack.shell.explorer.Explorer` (formerly `Study`, still importable
here and as `nc.Study`, deprecated); the ipywidgets view is
`ngcrack.shell.explorer.ExplorerWidget` (formerly `ngcrack.interactive.Explorer`, which this
module still gives).
"""

import warnings

from .core.constraints import CLOSED_RTOL
from .shell.explorer import (
    FIELDS,
    LEVELS,
    SLIDERS,
    Drawing,
    Study,
    contact_length,
    draw,
    explore,
    geometry_key,
    load_structure,
    scaled_loads,
    stress_values,
)
from .shell.explorer.figure import DEFORMED_FRACTION, FIGURE_DPI, FIGURE_SIZE, PROFILE_FLOOR, STATE_COLORS

warnings.warn("ngcrack.interactive is now ngcrack.shell.explorer (nc.explore, nc.Explorer); import ngcrack.shell.explorer",
              DeprecationWarning, stacklevel=2)

__all__ = ["CLOSED_RTOL", "DEFORMED_FRACTION", "Drawing", "FIELDS", "FIGURE_DPI", "FIGURE_SIZE", "LEVELS",
           "PROFILE_FLOOR", "SLIDERS", "STATE_COLORS", "Study", "contact_length", "draw", "explore",
           "geometry_key", "load_structure", "scaled_loads", "stress_values"]


def __getattr__(name: str):
    if name == "Explorer":  # the widget class, as this module called it
        from .shell.explorer import widget

        return widget.ExplorerWidget
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
