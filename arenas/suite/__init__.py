"""arenas.suite: the worlds of dm_control's Control Suite domains.

    from arenas.suite import SuiteArena
    arena = SuiteArena(floor_size=(4, 4, 0.2))   # skybox, headlight, checkered floor

Each domain's task builds its world from `SuiteArena` with the numbers of the domain's file.
"""

from arenas.suite.quadruped import QuadrupedArena
from arenas.suite.world import SuiteArena

__all__ = ["QuadrupedArena", "SuiteArena"]
