"""PropPlacer: random poses without penetration, and a clear error when there is none."""

from __future__ import annotations

import numpy as np
import pytest

import composer
import mjcf
from arenas import Floor
from composer import variation
from tests.composer.scenes import Block


def scene(count: int, half: float = 0.05):
    arena = Floor()
    blocks = [Block(name=f"block{i}", half=half) for i in range(count)]
    for block in blocks:
        arena.add_free_entity(block)
    return blocks, mjcf.Physics.from_mjcf_model(arena.mjcf_model)


def penetrations(physics: mjcf.Physics) -> int:
    physics.forward()
    return int((physics.data.contact.dist < 0).sum())


def test_props_are_placed_at_random_without_penetration():
    blocks, physics = scene(4)
    placer = composer.PropPlacer(
        blocks,
        position=variation.Uniform([-0.15, -0.15, 0.05], [0.15, 0.15, 0.06]),
        quaternion=None,
        max_attempts_per_prop=200,
    )
    assert penetrations(physics) > 0  # all four start at the origin
    placer(physics, np.random.RandomState(0))
    assert penetrations(physics) == 0
    positions = np.array([block.get_pose(physics)[0] for block in blocks])
    assert len({tuple(p) for p in positions.round(6)}) == 4
    assert (np.abs(positions[:, :2]) <= 0.15).all()
    placer(physics, np.random.RandomState(1))
    assert not np.allclose(positions, [block.get_pose(physics)[0] for block in blocks])


def test_no_room_raises_naming_the_prop_after_the_attempts():
    blocks, physics = scene(2)
    placer = composer.PropPlacer(blocks, position=[0, 0, 0.06], max_attempts_per_prop=3)
    with pytest.raises(composer.PlacementError, match="'block1' without collisions in 3 attempts"):
        placer(physics, np.random.RandomState(0))
    # An EpisodeInitializationError: the environment retries the episode.
    assert issubclass(composer.PlacementError, composer.EpisodeInitializationError)
    composer.PropPlacer(blocks, position=[0, 0, 0.05], ignore_collisions=True)(
        physics, np.random.RandomState(0)
    )


def test_bad_arguments_are_refused():
    blocks, _ = scene(1)
    with pytest.raises(composer.InitializerError, match="at least one prop"):
        composer.PropPlacer([], position=[0, 0, 0])
    with pytest.raises(composer.InitializerError, match="max_attempts_per_prop"):
        composer.PropPlacer(blocks, position=[0, 0, 0], max_attempts_per_prop=0)
