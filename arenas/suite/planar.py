"""PlanarArena: the world of the Control Suite's planar manipulation domains (manipulator
and stacker): a small floor between two walls at 45 degrees, seen from far away.

    arena = PlanarArena(contact_solref=(0.005, 1))
    arena.attach(Manipulator())          # entities.suite: the arm and its props

The numbers are the suite's files' (`manipulator.xml`, `stacker.xml`): `PlanarArena`
lists them.
"""

from __future__ import annotations

from collections.abc import Sequence

import mjcf
from arenas.suite.world import SuiteArena

_WALL_SIZE = [0.4, 0.2, 10]


class PlanarArena(SuiteArena):
    """The planar manipulation domains' world.

    The suite's files (`manipulator.xml`, `stacker.xml`): a 0.8 x 0.4 m checkered floor, two
    checkered walls leaning in at 45 degrees whose lower edges meet the floor's, a
    directional light from above, and the `fixed` camera, 16 m away with a 4 degree field
    of view, which sees the scene almost orthographically. The files' top-level defaults
    give the floor and walls the soft contacts the robot's geoms have (`contact_solref`
    differs between the domains); the arena sets them as its own defaults, which the
    robot's repeat.
    """

    def _build(  # type: ignore[override]
        self, name: str = "world", contact_solref: Sequence[float] = (0.005, 1)
    ) -> None:
        """Make the world model named `name`, its floor and walls with contacts of
        `contact_solref`."""
        super()._build(name=name, floor_size=_WALL_SIZE)
        root = self._mjcf_root
        root.visual.map.shadowclip = 0.5
        root.default.geom.set_attributes(
            friction=[0.7], solimp=[0.9, 0.97, 0.001], solref=list(contact_solref)
        )
        self.add_light(
            name="light", directional=True, diffuse=[0.6] * 3, pos=[0, 0, 1], specular=[0.3] * 3
        )
        walls = []
        for wall, x in (("wall1", -0.682843), ("wall2", 0.682843)):
            walls.append(root.worldbody.add(
                "geom", name=wall, type="plane", pos=[x, 0, 0.282843], size=_WALL_SIZE,
                material=self.grid, zaxis=[-x / abs(x), 0, 1],
            ))  # fmt: skip
        self.walls = tuple(walls)
        self.camera: mjcf.Element = root.worldbody.add(
            "camera", name="fixed", pos=[0, -16, 0.4], xyaxes=[1, 0, 0, 0, 0, 1], fovy=4
        )
