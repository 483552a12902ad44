"""Arenas: the entity at the root of a scene, with a floor, lights and a sky.

    arena = composer.Arena(floor_size=(4, 4))
    arena.attach(robot)                                 # fixed at the world origin
    arena.attach(robot, attach_site=arena.mjcf_model.find('site', 'mount'))
    frame = arena.add_free_entity(ball)                 # a frame with a free joint
    frame.pos = [0, 0, 1]                               # its initial position (qpos0)
    arena.add_free_entity(composer.Entity.from_path('ant.xml'))   # floats already

A model that floats already (a standalone robot file whose top body has a free joint,
such as gymnasium's ant or humanoid) keeps its own free joint when added as a free
entity, and its world body (a ground plane of its own, say) stays static.

An arena is an `Entity`: subclasses call `super()._build(...)` and add walls, tables or
terrain to `self.mjcf_model`.
"""

from __future__ import annotations

from collections.abc import Sequence

import mjcf
import mjcf.defaults
from composer.entity import Entity
from composer.errors import EntityError


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
        """Attach `entity` at the world body with a free joint, and return the frame. An
        entity whose model has a top body with a free joint already floats: it is attached
        as it is (a second free joint could not compile), its world body static. Raises
        EntityError as `attach`, and for a model whose world body holds a plane, which
        MuJoCo allows in static bodies only, when the frame would get the free joint."""
        model = entity.mjcf_model
        if any(mjcf.get_freejoint(body) is not None for body in _top_bodies(model.worldbody)):
            return self.attach(entity)
        planes = [
            geom
            for geom in _static_children(model.worldbody)
            if geom.tag == "geom" and mjcf.defaults.effective_value(geom, "type") == "plane"
        ]
        if planes:
            raise EntityError(
                f"cannot add entity {entity.name!r} as a free entity: its world body holds "
                f"{planes[0].path}, a plane, which MuJoCo allows only in static bodies; give "
                "its top body a free joint, or attach it with arena.attach(entity)"
            )
        frame = self.attach(entity)
        frame.add("freejoint")
        return frame


def _static_children(element: mjcf.Element) -> list[mjcf.Element]:
    """The children of a world body, with those of MuJoCo `<frame>`s in it (not bodies,
    not attached models)."""
    found = []
    for child in element.all_children():
        if child.tag == "frame":
            found.extend(_static_children(child))
        else:
            found.append(child)
    return found


def _top_bodies(worldbody: mjcf.Element) -> list[mjcf.Element]:
    return [child for child in _static_children(worldbody) if child.tag == "body"]
