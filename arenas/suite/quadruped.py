"""QuadrupedArena: the quadruped domain's world, with the escape task's bowl of terrain.

    arena = QuadrupedArena(floor_size=40, terrain=True)
    arena.attach(quadruped)                   # entities.suite.Quadruped
    arena.shape_bowl(physics, random_state)   # the escape task's terrain, each episode

The suite's world (`SuiteArena`) as the quadruped's file changes it (`QuadrupedArena`
lists how); `shape_bowl` draws the escape task's terrain as dm_control draws it.
"""

from __future__ import annotations

import numpy as np

import mjcf
from arenas.suite.spline_zoom import spline_zoom
from arenas.suite.world import SuiteArena

# The heightfield's rows and columns, and its size (x and y radius, height, base depth).
TERRAIN_RESOLUTION = 201
TERRAIN_SIZE = (30.0, 30.0, 5.0, 0.1)
# The escape terrain's bumps: the lowest (0: bumpiest, 1: flat) and their spacing (m).
BUMP_SMOOTHNESS = 0.15
BUMP_SCALE = 2.0


class QuadrupedArena(SuiteArena):
    """The quadruped domain's world.

    The suite's world (`SuiteArena`) as the quadruped's file changes it: the floor a square
    plane of half-size `floor_size`, its contacts as the file's top-level geom defaults make
    them (solimp 0.9 0.99 0.003, solref 0.01 1), a closer near clip plane (5 mm, far 20 m),
    rangefinder beams drawn yellow, the camera `global` looking down on the robot from 10 m
    away and a 201 x 201 heightfield asset of 60 m x 60 m x 5 m (always there, as in the
    file), with `terrain` the geom showing it, 1 cm under the floor.
    """

    def _build(  # type: ignore[override]
        self, name: str = "world", floor_size: float = 15.0, terrain: bool = False
    ) -> None:
        """Make the world named `name` with a floor of half-size `floor_size` (m), and the
        heightfield's geom if `terrain`."""
        super()._build(name=name, floor_size=(floor_size, floor_size, 0.5))
        root = self.mjcf_model
        root.default.geom.set_attributes(solimp=[0.9, 0.99, 0.003], solref=[0.01, 1])
        root.visual.rgba.rangefinder = [1, 1, 0.1, 0.1]
        root.visual.map.set_attributes(znear=0.005, zfar=20)
        self.heightfield = root.asset.add(
            "hfield", name="terrain", ncol=TERRAIN_RESOLUTION, nrow=TERRAIN_RESOLUTION,
            size=list(TERRAIN_SIZE),
        )  # fmt: skip
        self.terrain: mjcf.Element | None = None
        if terrain:
            self.terrain = root.worldbody.add(
                "geom", name="terrain", type="hfield", hfield=self.heightfield,
                rgba=[0.2, 0.3, 0.4, 1], pos=[0, 0, -0.01],
            )  # fmt: skip
        root.worldbody.add("camera", name="global", pos=[-10, 10, 10],
                           xyaxes=[-1, -1, 0, 1, 0, 1], mode="trackcom")  # fmt: skip

    def shape_bowl(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Write a new escape terrain into `physics`' heightfield, as dm_control draws it: a
        sinusoidal bowl (0 at the centre, 1 at the rim, flat within 4% of the radius) times
        bumps, one per 2 m square, uniform in [0.15, 1], smoothed with cubic splines
        (`arenas.suite.spline_zoom`, scipy's zoom); draws (bumps per side)^2 uniforms from
        `random_state`. A renderer uploads a heightfield when it is made, so the physics'
        renderers are closed: the next frame's shows the new terrain (dm_control uploads it
        again to its render context)."""
        field = physics.bind(self.heightfield)
        resolution = int(field.nrow)
        rows, columns = np.ogrid[-1 : 1 : resolution * 1j, -1 : 1 : resolution * 1j]
        radius = np.clip(np.sqrt(columns**2 + rows**2), 0.04, 1)
        bowl = 0.5 - np.cos(2 * np.pi * radius) / 2
        bumps_per_side = int(2 * field.size[0] / BUMP_SCALE)
        bumps = random_state.uniform(BUMP_SMOOTHNESS, 1, (bumps_per_side, bumps_per_side))
        heights = bowl * spline_zoom(bumps, resolution / float(bumps_per_side))
        start = int(field.adr)
        physics.model.hfield_data[start : start + resolution * resolution] = heights.ravel()
        physics.close()
