"""A table workspace on a floor: a table with a robot mount at one edge.

    arena = Table(top_size=(0.5, 0.7), height=0.4)
    arena.attach(robot, attach_site=arena.mount)       # robot base on the table edge
    frame = arena.add_free_entity(box)
    frame.pos = [*arena.top_center[:2], arena.top_height + 0.03]

The table top's centre is at x = 0, y = 0; its upper surface at `height`. The site
`mount` sits on the surface `mount_inset` m in from the -x edge, facing +x, for an arm.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from arenas.floor import Floor


class Table(Floor):
    """A `Floor` with a table (geom `top`, four legs), sites `mount` and `top`."""

    # _build takes the constructor's arguments (see Entity.__init__): each arena its own.
    def _build(  # type: ignore[override]
        self,
        name: str = "table",
        top_size: Sequence[float] = (0.5, 0.7),
        height: float = 0.4,
        thickness: float = 0.04,
        mount_inset: float = 0.1,
        friction: float = 1.0,
    ) -> None:
        """Make the arena named `name` with a table top of half sizes `top_size` (m) whose
        upper surface is `height` m above the floor."""
        # No floor reflections: mirroring a robot's meshes doubles the cost of a frame.
        super()._build(name=name, camera_distance=2.0, azimuth=150.0, elevation=-30.0,
                       reflectance=0.0)  # fmt: skip
        root = self.mjcf_model
        half_x, half_y = (float(v) for v in top_size)
        root.asset.add("material", name="wood", rgba=[0.55, 0.4, 0.28, 1])
        table = root.worldbody.add("body", name="table", pos=[0, 0, height])
        self.top_geom = table.add(
            "geom", name="top", type="box", size=[half_x, half_y, thickness / 2],
            pos=[0, 0, -thickness / 2], material="wood", friction=[friction, 0.005, 0.0001],
        )  # fmt: skip
        leg_height = height - thickness
        for index, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
            table.add(
                "geom", name=f"leg_{index}", type="box", size=[0.03, 0.03, leg_height / 2],
                pos=[sx * (half_x - 0.05), sy * (half_y - 0.05), -thickness - leg_height / 2],
                material="wood",
            )  # fmt: skip
        invisible = {"size": [0.01], "rgba": [0, 0, 0, 0]}
        self.mount = table.add("site", name="mount", pos=[-half_x + mount_inset, 0, 0],
                               **invisible)  # fmt: skip
        self.top = table.add("site", name="top", **invisible)
        self.top_height = float(height)
        self.top_size = (half_x, half_y)
        self.top_center = np.array([0.0, 0.0, height])
