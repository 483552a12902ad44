"""SuiteArena: the world of a Control Suite domain: skybox, headlight, checkered floor, lights.

    arena = SuiteArena(floor_size=(4, 4, 0.2), floor_pos=(0, 0, -0.05))
    arena.add_light(name="light", pos=(0, 0, 6))
    arena.attach(robot)                  # entities.suite: each domain's robot

What every domain's file includes, as the suite writes it (`SuiteArena` lists it). The
arena sets no physics option: those are the robot's (its model's `<option>`), so the
composed model compiles to what the domain's own file compiles to.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import composer
import mjcf


class SuiteArena(composer.Arena):
    """A suite domain's world.

    Every domain of dm_control's suite includes the same three files: a gradient skybox
    with random white marks, the visual settings (headlight, near clip plane, shadow map
    size) and the materials; the checkered `grid` texture and material of the last are the
    world's, the robot's materials travel with the robot (`entities.suite.materials`). The
    floor is a plane of the domain's name (`floor`, or `ground` as some files say), size and
    place, with the attributes the domain's top-level defaults give it (`floor_attributes`:
    finger's solref ...).
    """

    def _build(  # type: ignore[override]
        self,
        name: str = "world",
        floor_size: Sequence[float] | None = (4.0, 4.0, 0.2),
        floor_pos: Sequence[float] = (0.0, 0.0, 0.0),
        grid_repeat: Sequence[float] = (1.0, 1.0),
        grid_reflectance: float = 0.2,
        floor_name: str = "floor",
        floor_attributes: Mapping[str, object] | None = None,
        skybox_first: bool = True,
    ) -> None:
        """Make the world model named `name`, with a floor plane named `floor_name` of
        `floor_size` (None: no floor) at `floor_pos`, with `floor_attributes` besides (as
        MJCF's `<geom>` takes them), its grid material repeated `grid_repeat` times per unit
        (`texuniform`) with `grid_reflectance`. The skybox texture comes before the grid's
        unless not `skybox_first` (a compiled model keeps the file's order of textures)."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        if skybox_first:
            self._add_skybox()
        root.visual.headlight.set_attributes(
            ambient=[0.4] * 3, diffuse=[0.8] * 3, specular=[0.1] * 3
        )
        root.visual.map.znear = 0.01
        root.visual.quality.shadowsize = 2048
        root.asset.add(
            "texture", name="grid", type="2d", builtin="checker", rgb1=[0.1, 0.2, 0.3],
            rgb2=[0.2, 0.3, 0.4], width=300, height=300, mark="edge", markrgb=[0.2, 0.3, 0.4],
        )  # fmt: skip
        self.grid = root.asset.add(
            "material", name="grid", texture="grid", texrepeat=list(grid_repeat),
            texuniform=True, reflectance=grid_reflectance,
        )  # fmt: skip
        if not skybox_first:
            self._add_skybox()
        self.floor = None
        if floor_size is not None:
            self.floor = root.worldbody.add(
                "geom", name=floor_name, type="plane", pos=list(floor_pos),
                size=list(floor_size), material=self.grid, **dict(floor_attributes or {}),
            )  # fmt: skip

    def _add_skybox(self) -> None:
        self._mjcf_root.asset.add(
            "texture", name="skybox", type="skybox", builtin="gradient", rgb1=[0.4, 0.6, 0.8],
            rgb2=[0, 0, 0], width=800, height=800, mark="random", markrgb=[1, 1, 1],
        )  # fmt: skip

    def add_light(self, **attributes: object) -> mjcf.Element:
        """Add a light to the world body (`name`, `pos`, `dir` ... as MJCF's `<light>`)."""
        return self._mjcf_root.worldbody.add("light", **attributes)
