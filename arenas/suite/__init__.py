"""arenas.suite: the worlds of dm_control's Control Suite domains.

    from arenas.suite import SuiteArena
    arena = SuiteArena(floor_size=(4, 4, 0.2))   # skybox, headlight, checkered floor
    arena = PlanarArena()                         # manipulator's and stacker's walled floor

Each domain's task builds its world from `SuiteArena` with the numbers of the domain's file.
"""

from arenas.suite.planar import PlanarArena
from arenas.suite.quadruped import QuadrupedArena
from arenas.suite.world import SuiteArena

__all__ = ["PlanarArena", "QuadrupedArena", "SuiteArena"]
