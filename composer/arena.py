"""Arenas: the entity at the root of a scene, holding the scene's global settings.

    arena = composer.Arena()                            # an empty world, as in dm_control
    arena.attach(robot)                                 # fixed at the world origin
    frame = arena.add_free_entity(ball)                 # a frame with a free joint
    frame.pos = [0, 0, 1]                               # its initial position (qpos0)

Promises: `Arena()` is dm_control's base arena (`GLOBAL_SETTINGS`; no floor, no lights), so
dm_control's arena subclasses build the world they build there; `Arena(xml_path=...)` is a
model of your own. A model that floats already keeps its own free joint when added free.
"""

from __future__ import annotations

import os
from typing import Any

import mjcf
import mjcf.compose.defaults
from composer.entity import Entity
from composer.errors import EntityError

# dm_control's base arena settings: {section path: {attribute: value}}.
GLOBAL_SETTINGS: dict[str, dict[str, Any]] = {
    "compiler": {"angle": "radian", "eulerseq": "xyz", "boundmass": 1e-5, "boundinertia": 1e-11},
    "option": {"cone": "elliptic", "noslip_iterations": 5, "noslip_tolerance": 0.0,
               "timestep": 0.002},
    "visual.map": {"znear": 0.01},
    "visual.headlight": {"diffuse": [0.6] * 3, "ambient": [0.3] * 3, "specular": [0.0] * 3},
    "visual.scale": {"forcewidth": 0.01, "contactwidth": 0.06, "contactheight": 0.01,
                     "jointwidth": 0.01, "framewidth": 0.01, "framelength": 0.3},
}  # fmt: skip


def _with_global_settings(name: str) -> mjcf.RootElement:
    root = mjcf.RootElement(model=name)
    for path, attributes in GLOBAL_SETTINGS.items():
        section: Any = root
        for part in path.split("."):
            section = getattr(section, part)
        section.set_attributes(**attributes)
    return root


class Arena(Entity):
    """An empty world with dm_control's global settings.

    `composer.Arena` is dm_control's base arena: no floor, no lights, and the global settings
    dm_control's Composer defines (`GLOBAL_SETTINGS`: radians, xyz euler sequence, mass and
    inertia bounds, elliptic friction cones with five noslip iterations, the 2 ms timestep,
    the headlight and the sizes of drawn decorations), so that dm_control arena subclasses
    (which add their floors and lights in `_build` after `super()._build(name=...)`) build the
    world they build there. The shipped arenas (`arenas.Floor` and those built on it) make
    their own worlds, with a checkered floor, a skybox and lights.
    """

    def _build(
        self, name: str | None = None, xml_path: str | os.PathLike[str] | None = None
    ) -> None:
        """Make the arena model: dm_control's global settings in a model named `name`
        ('arena' if None), or the model in the MJCF file `xml_path` (renamed `name` if
        given). Raises mjcf.Error subclasses when that file does not parse."""
        if xml_path is None:
            self._mjcf_root = _with_global_settings(name or "arena")
        else:
            self._mjcf_root = mjcf.from_path(os.fspath(xml_path))
            if name:
                self._mjcf_root.model = name

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
            if geom.tag == "geom" and mjcf.compose.defaults.effective_value(geom, "type") == "plane"
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
