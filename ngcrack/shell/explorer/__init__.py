"""The interactive explorer: `nc.explore(...)`, a JupyterLab widget, and its model `nc.Explorer`.

- `model`: `Explorer`, the scene, its controls and the pipeline's caches (no widgets);
- `controls`: what each control accepts (ranges, choices), its name, the one-line refusal;
- `loads`: the scene's loads scaled by the load factor and turned;
- `fields`: what the figure shows, computed (stress field, crack faces, units, labels);
- `figure`: `Drawing`, the deformed body with its crack faces, loads and supports, a zoom
  on the crack and the crack profiles (matplotlib, PNG);
- `widget`: `explore()` and `ExplorerWidget`, the ipywidgets view;
- `growth_view`: `explore_growth(result)`, a step slider over a crack-growth path.
"""

from ...core.pipeline import ParameterLoads, load_structure
from ...planar.stages import geometry_key
from .figure import FIELDS, Drawing, draw, stress_values
from .growth_view import explore_growth
from .loads import scaled_loads
from .model import LEVELS, Explorer, Study, contact_length, overlap_length
from .widget import SLIDERS, explore

__all__ = ["Drawing", "Explorer", "explore_growth", "ExplorerWidget", "FIELDS", "LEVELS", "ParameterLoads", "SLIDERS",
           "Study", "contact_length", "draw", "explore", "geometry_key", "load_structure",
           "overlap_length",
           "scaled_loads", "stress_values"]


def __getattr__(name: str):
    if name == "ExplorerWidget":  # built on first use: ipywidgets is imported only when a widget is made
        from . import widget

        return widget.ExplorerWidget
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
