"""The former name of ngcrack.sweeps: importing it warns once (DeprecationWarning); new code imports ngcrack.sweeps.

Everything ngcrack.sweeps exports is importable from here too, so that old scripts keep
working (README, "Changes").
"""

import warnings

from .sweeps import *  # noqa: F403
from .sweeps import __all__  # noqa: F401

warnings.warn("ngcrack.study is now ngcrack.sweeps (the same names); import ngcrack.sweeps", DeprecationWarning,
              stacklevel=2)
