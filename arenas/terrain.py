"""Rough terrain: a height field generated from a seed, flat around the origin.

    arena = RoughTerrain(size=(8, 8), max_height=0.15, seed=3)
    arena.attach(quadruped)                           # starts on the flat patch
    RoughTerrain(seed=3).heights                      # the same (rows, cols) in [0, 1]

Heights are smooth noise: random grids of 4, 8 and 16 cells a side, bilinearly
interpolated and summed with halving amplitudes, scaled to [0, 1] and to `max_height`
m. The same seed gives the same terrain on every machine (numpy's PCG64).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

import composer
from arenas.floor import Floor

_OCTAVES = ((4, 1.0), (8, 0.5), (16, 0.25))


def terrain_heights(resolution: int, seed: int, flat_radius: float = 0.15) -> np.ndarray:
    """A (resolution, resolution) array in [0, 1] of smooth noise drawn from `seed`, 0
    within `flat_radius` (a fraction of the half size) of the centre, rising beyond.
    Raises composer.EntityError for a resolution below 8."""
    if resolution < 8:
        raise composer.EntityError(f"terrain resolution must be >= 8, got {resolution!r}")
    random = np.random.default_rng(seed)
    fine = np.linspace(0.0, 1.0, resolution)
    heights = np.zeros((resolution, resolution))
    for cells, amplitude in _OCTAVES:
        coarse = random.uniform(0.0, 1.0, (cells + 1, cells + 1))
        grid = np.linspace(0.0, 1.0, cells + 1)
        rows = np.array([np.interp(fine, grid, row) for row in coarse])
        heights += amplitude * np.array([np.interp(fine, grid, col) for col in rows.T]).T
    heights -= heights.min()
    heights /= heights.max()
    x = np.linspace(-1.0, 1.0, resolution)
    radius = np.hypot(*np.meshgrid(x, x))
    heights *= np.clip((radius - flat_radius) / 0.2, 0.0, 1.0)
    return heights


class RoughTerrain(Floor):
    """A `Floor` whose middle is the height field geom `terrain` of half sizes `size`."""

    # _build takes the constructor's arguments (see Entity.__init__): each arena its own.
    def _build(  # type: ignore[override]
        self,
        name: str = "terrain",
        size: Sequence[float] = (8.0, 8.0),
        max_height: float = 0.15,
        seed: int = 0,
        resolution: int = 64,
    ) -> None:
        """Make the arena named `name`: terrain of half sizes `size` (m), heights up to
        `max_height` m, drawn from `seed` at `resolution` samples a side. Raises
        composer.EntityError for a resolution below 8."""
        half_x, half_y = (float(v) for v in size)
        super()._build(name=name, size=(half_x + 4, half_y + 4))
        self.heights = terrain_heights(int(resolution), int(seed))
        root = self.mjcf_model
        field = root.asset.add(
            "hfield", name="terrain", nrow=resolution, ncol=resolution,
            size=[half_x, half_y, max_height, 0.1], elevation=self.heights.ravel(),
        )  # fmt: skip
        self.terrain = root.worldbody.add(
            "geom", name="terrain", type="hfield", hfield=field, material="grid",
            pos=[0, 0, 0.001],
        )  # fmt: skip
