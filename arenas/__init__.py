"""arenas: places to put entities in: floors, corridors, tables and rough terrain.

    import arenas
    arena = arenas.Corridor(length=30, walls=True, gaps=[(6.0, 0.5)])   # or RoughTerrain
    arena.attach(walker)
    table = arenas.Table(height=0.4)
    table.attach(robot, attach_site=table.mount)

Each is a `composer.Arena` (the root of a scene): attach entities to it, or `add_free_entity`
what moves freely. `Floor`, the others' base, builds its own world (MuJoCo's default options).
"""

from arenas.corridor import Corridor
from arenas.floor import Floor
from arenas.table import Table
from arenas.terrain import RoughTerrain, terrain_heights

__all__ = ["Corridor", "Floor", "RoughTerrain", "Table", "terrain_heights"]
