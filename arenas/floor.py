"""A flat floor arena: checkered floor, gradient skybox, a top light and a fill light.

    arena = Floor(size=(10, 10))
    arena.attach(robot)
    arena.add_free_entity(ball)

The floor every shipped arena stands on. It builds its own world rather than
`composer.Arena`'s dm_control settings: MuJoCo's default physics options (pyramidal
friction cones, no noslip iterations) and compiler settings, which the shipped tasks are
tuned for.
"""

from __future__ import annotations

from collections.abc import Sequence

import composer
import mjcf


class Floor(composer.Arena):
    """A floor of half sizes `size` (checkered, or a plain `floor_rgba` one), a headlight, a
    gradient skybox, a top light and a fill light, and the fixed camera `overview` looking
    at the origin from `camera_distance` m; the free camera's default view's
    `azimuth`/`elevation` in degrees. The checker's material is a 0.5 grey under a bright
    texture, so that MuJoCo's lighting never saturates before the texture and the floor
    looks the same drawn with shadows (several lighting passes) and without (one pass,
    small frames)."""

    def _build(  # type: ignore[override]  # its own world: no xml_path
        self,
        name: str = "floor",
        size: Sequence[float] = (8.0, 8.0),
        floor_rgba: Sequence[float] | None = None,
        camera_distance: float = 3.0,
        azimuth: float = 90.0,
        elevation: float = -25.0,
        reflectance: float = 0.2,
    ) -> None:
        """Make the arena named `name` with a floor of half sizes `size` (m); a plain
        `floor_rgba` replaces the checker, whose `reflectance` mirrors the scene (MuJoCo
        draws the scene again for it: 0 where that is costly)."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.visual.headlight.ambient = [0.4, 0.4, 0.4]
        root.visual.headlight.diffuse = [0.6, 0.6, 0.6]
        root.asset.add(
            "texture", name="skybox", type="skybox", builtin="gradient",
            rgb1=[0.4, 0.6, 0.8], rgb2=[0.0, 0.0, 0.0], width=256, height=256,
        )  # fmt: skip
        self.floor = root.worldbody.add(
            "geom", name="floor", type="plane", size=[*size, 1.0], condim=3
        )
        if floor_rgba is None:
            root.asset.add(
                "texture", name="grid", type="2d", builtin="checker", width=256, height=256,
                rgb1=[0.38, 0.57, 0.76], rgb2=[0.19, 0.38, 0.57], mark="edge", markrgb=[1.0] * 3,
            )  # fmt: skip
            grid = root.asset.add(
                "material", name="grid", texture="grid", texrepeat=[1, 1], texuniform=True,
                rgba=[0.5, 0.5, 0.5, 1], reflectance=reflectance,
            )  # fmt: skip
            self.floor.material = grid
        else:
            self.floor.rgba = floor_rgba
        root.worldbody.add("light", name="top", pos=[0, 0, 6], dir=[0, 0, -1], directional=True)
        global_ = getattr(root.visual, "global")
        global_.azimuth = azimuth
        global_.elevation = elevation
        root.worldbody.add("light", name="fill", pos=[2, -2, 3], dir=[-1, 1, -1.5],
                           diffuse=[0.3, 0.3, 0.3], castshadow=False)  # fmt: skip
        d = camera_distance
        self.overview = root.worldbody.add(
            "camera", name="overview", pos=[0, -d, 0.6 * d], xyaxes=[1, 0, 0, 0, 0.6, 1]
        )
