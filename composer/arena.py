"""Arenas: the entity at the root of a scene, with a floor, lights and a sky.

    arena = composer.Arena(floor_size=(4, 4))
    arena.attach(robot)                                 # fixed at the world origin
    arena.attach(robot, attach_site=arena.mjcf_model.find('site', 'mount'))
    frame = arena.add_free_entity(ball)                 # a frame with a free joint
    frame.pos = [0, 0, 1]                               # its initial position (qpos0)

An arena is an `Entity`: subclasses call `super()._build(...)` and add walls, tables or
terrain to `self.mjcf_model`.
"""

from __future__ import annotations

from collections.abc import Sequence

import mjcf
from composer.entity import Entity


class Arena(Entity):
    """A flat checkered floor, a gradient skybox, a headlight and a top light."""

    def _build(
        self,
        name: str = "arena",
        floor_size: Sequence[float] = (8.0, 8.0),
        floor_rgba: Sequence[float] | None = None,
    ) -> None:
        """Make the arena model named `name` with a floor plane of half sizes `floor_size`
        (a plain `floor_rgba` color instead of the checker if given)."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.visual.headlight.ambient = [0.4, 0.4, 0.4]
        root.visual.headlight.diffuse = [0.6, 0.6, 0.6]
        root.asset.add(
            "texture", name="skybox", type="skybox", builtin="gradient",
            rgb1=[0.4, 0.6, 0.8], rgb2=[0.0, 0.0, 0.0], width=256, height=256,
        )  # fmt: skip
        self.floor = root.worldbody.add(
            "geom", name="floor", type="plane", size=[*floor_size, 0.1], condim=3
        )
        if floor_rgba is None:
            root.asset.add(
                "texture", name="grid", type="2d", builtin="checker", width=256, height=256,
                rgb1=[0.2, 0.3, 0.4], rgb2=[0.1, 0.2, 0.3], mark="edge", markrgb=[0.8] * 3,
            )  # fmt: skip
            grid = root.asset.add(
                "material", name="grid", texture="grid", texrepeat=[1, 1], texuniform=True,
                reflectance=0.2,
            )  # fmt: skip
            self.floor.material = grid
        else:
            self.floor.rgba = floor_rgba
        root.worldbody.add("light", name="top", pos=[0, 0, 6], dir=[0, 0, -1], directional=True)

    def add_free_entity(self, entity: Entity) -> mjcf.Element:
        """Attach `entity` at the world body with a free joint, and return the frame;
        raises EntityError as `attach`."""
        frame = self.attach(entity)
        frame.add("freejoint")
        return frame
