"""arenas: places to put entities in: floors, corridors, tables and rough terrain.

    import arenas
    arena = arenas.Corridor(length=30, walls=True, gaps=[(6.0, 0.5)])
    arena.attach(walker)
    table = arenas.Table(height=0.4)
    table.attach(robot, attach_site=table.mount)
    terrain = arenas.RoughTerrain(seed=7, max_height=0.2)

Every arena is a `composer.Arena` (an Entity at the root of a scene): attach entities to
it, or `add_free_entity` for things that move freely. `Floor` is the base of the others and
builds its own world (where `composer.Arena` is dm_control's empty one): MuJoCo's default
physics options, a checkered floor, a skybox, lights and an `overview` camera.
"""

from arenas.corridor import Corridor
from arenas.floor import Floor
from arenas.table import Table
from arenas.terrain import RoughTerrain, terrain_heights

__all__ = ["Corridor", "Floor", "RoughTerrain", "Table", "terrain_heights"]
