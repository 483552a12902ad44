"""A flat floor arena: checkered floor, gradient skybox, a top light and a fill light.

    arena = Floor(size=(10, 10))
    arena.attach(robot)
    arena.add_free_entity(ball)

`composer.Arena` already makes the floor, skybox and top light; `Floor` adds a fill light,
a fixed overview camera `overview`, and lets the free camera's default view be set.
"""

from __future__ import annotations

from collections.abc import Sequence

import composer


class Floor(composer.Arena):
    """`composer.Arena` plus a fill light and the camera `overview` looking at the origin
    from `camera_distance` m, and the free camera's `azimuth`/`elevation` in degrees."""

    def _build(
        self,
        name: str = "floor",
        size: Sequence[float] = (8.0, 8.0),
        floor_rgba: Sequence[float] | None = None,
        camera_distance: float = 3.0,
        azimuth: float = 90.0,
        elevation: float = -25.0,
    ) -> None:
        """Make the arena named `name` with a floor of half sizes `size` (m); a plain
        `floor_rgba` replaces the checker."""
        super()._build(name=name, floor_size=size, floor_rgba=floor_rgba)
        root = self.mjcf_model
        global_ = getattr(root.visual, "global")
        global_.azimuth = azimuth
        global_.elevation = elevation
        root.worldbody.add("light", name="fill", pos=[2, -2, 3], dir=[-1, 1, -1.5],
                           diffuse=[0.3, 0.3, 0.3], castshadow=False)  # fmt: skip
        d = camera_distance
        self.overview = root.worldbody.add(
            "camera", name="overview", pos=[0, -d, 0.6 * d], xyaxes=[1, 0, 0, 0, 0.6, 1]
        )
