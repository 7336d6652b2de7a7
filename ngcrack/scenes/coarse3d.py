"""Two coarse 3D scenes as dictionaries, shared by the 3D tests and benchmarks.

``coarse_penny``: a penny crack (radius 1, normal z) in a box 20 times its radius, rollers
on three faces and a unit traction on the top (tension; `load` -1 closes every face), at
maxh 5, crack_h 0.4, front_h 0.2: the coarsest mesh on which the front's K is close to
Sneddon's. ``bent_penny``: a penny (normal x) across a clamped beam 8 x 4 x 4 bent by a
shear load at its free end, at maxh 4, crack_h 0.6, front_h 0.4: the crack's lower half
closes (a mixed active set). ``inclined_penny``: a penny at 45 degrees to a compression
(normal (1, 0, 1)/sqrt 2) in a box 4 x 4 x 4 with rollers on three faces, on the tiny mesh
of the serial friction tests (maxh 1.5, crack_h 1, front_h 0.5; 509 tetrahedra): every face
closed, the faces sheared as much as pressed. Each call returns a new dictionary (``SolidScene.from_dict``
or ``nc.Scene.from_dict`` reads it); change it freely.
"""

from __future__ import annotations


def coarse_penny(load: float = 1.0) -> dict:
    """The coarse penny in a box under a normal traction `load` on its top face (module docstring)."""
    return {
        "name": "penny-coarse",
        "domain": {"box": [[-10.0, -10.0, -10.0], [10.0, 10.0, 10.0]]},
        "crack": [{"shape": "disc", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 1.0}],
        "material": {"E": 1000.0, "nu": 0.3},
        "boundary": {"xmin": {"type": "roller"}, "ymin": {"type": "roller"}, "zmin": {"type": "roller"},
                     "zmax": {"type": "traction", "value": [0.0, 0.0, float(load)]}},
        "mesh": {"maxh": 5.0, "crack_h": 0.4, "front_h": 0.2},
    }


def bent_penny() -> dict:
    """The penny across a clamped beam bent by a shear load (module docstring)."""
    return {
        "name": "bent-penny",
        "domain": {"box": [[-4.0, -2.0, -2.0], [4.0, 2.0, 2.0]]},
        "crack": [{"shape": "disc", "center": [0, 0, 0], "normal": [1, 0, 0], "radius": 1.0}],
        "material": {"E": 1000.0, "nu": 0.3},
        "boundary": {"xmin": {"type": "clamped"}, "xmax": {"type": "traction", "value": [0.0, 0.0, -1.0]}},
        "mesh": {"maxh": 4.0, "crack_h": 0.6, "front_h": 0.4},
    }


def inclined_penny(friction: float = 0.0) -> dict:
    """The inclined penny pressed shut (module docstring), Coulomb friction `friction` on its faces."""
    r = 0.5 ** 0.5
    return {
        "name": "inclined-tiny",
        "domain": {"box": [[-2.0, -2.0, -2.0], [2.0, 2.0, 2.0]]},
        "crack": [{"shape": "disc", "center": [0, 0, 0], "normal": [r, 0.0, r], "radius": 1.0,
                   "friction": float(friction)}],
        "material": {"E": 1000.0, "nu": 0.3},
        "boundary": {"xmin": {"type": "roller"}, "ymin": {"type": "roller"}, "zmin": {"type": "roller"},
                     "zmax": {"type": "traction", "value": [0.0, 0.0, -1.0]}},
        "mesh": {"maxh": 1.5, "crack_h": 1.0, "front_h": 0.5},
    }
