"""The former name of ngcrack.studies.sweeps: importing it warns once (DeprecationWarning); new code imports ngcrack.studies.sweeps.

Everything ngcrack.studies.sweeps exports is importable from here too, so that old scripts keep
working (README, "Changes").
"""

import warnings

from .studies.sweeps import *  # noqa: F403
from .studies.sweeps import __all__  # noqa: F401

warnings.warn("ngcrack.study is now ngcrack.studies.sweeps (the same names); import ngcrack.studies.sweeps", DeprecationWarning,
              stacklevel=2)
