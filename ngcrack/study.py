"""The former name of ngcrack.sweeps (sweeps over element, mesh size, Poisson ratio, friction).

Everything ngcrack.sweeps exports is importable from here too, so that scripts and
notebooks written against `ngcrack.study` keep working; new code imports ngcrack.sweeps.
"""

from .sweeps import *  # noqa: F403
from .sweeps import __all__  # noqa: F401
