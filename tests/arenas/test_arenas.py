"""Arenas: what they contain, and that their floors, walls, gaps and tables hold things."""

from __future__ import annotations

import numpy as np
import pytest

import arenas
import composer
import entities


def settle(arena: composer.Arena, prop: composer.Entity, position, steps: int = 400):
    """Drop `prop` at `position` in `arena` and return where it rests."""
    env = composer.Environment(composer.NullTask(arena))
    env.reset(seed=0)
    prop.set_pose(env.physics, position=position)
    env.physics.step(steps)
    return env.physics.bind(prop.body).xpos.copy()


def test_floor_has_lights_a_skybox_and_an_overview_camera():
    floor = arenas.Floor(size=(5, 6))
    model = floor.mjcf_model
    assert model.find("texture", "skybox") is not None
    assert len(model.find_all("light")) == 2
    assert model.find("camera", "overview") is floor.overview
    np.testing.assert_allclose(floor.floor.size[:2], [5, 6])


def test_corridor_walls_are_optional_and_hold_things_in():
    assert arenas.Corridor(walls=False).mjcf_model.find("geom", "left_wall") is None
    corridor = arenas.Corridor(width=2.0)
    ball = entities.Sphere(radius=0.1)
    corridor.attach(ball)
    env = composer.Environment(composer.NullTask(corridor))
    env.reset(seed=0)
    ball.set_pose(env.physics, position=[2.0, 0.0, 0.1])
    ball.set_velocity(env.physics, velocity=[0, 5.0, 0])
    env.physics.step(500)
    assert abs(env.physics.bind(ball.body).xpos[1]) < 1.0


def test_corridor_gaps_are_holes_in_the_floor():
    corridor = arenas.Corridor(gaps=[(3.0, 1.0)], pit_depth=1.0)
    box = entities.Box(half_sizes=(0.1, 0.1, 0.1))
    corridor.attach(box)
    assert settle(corridor, box, [3.5, 0, 0.2])[2] < -0.5  # fell into the gap
    corridor = arenas.Corridor(gaps=[(3.0, 1.0)], pit_depth=1.0)
    box = entities.Box(half_sizes=(0.1, 0.1, 0.1))
    corridor.attach(box)
    assert settle(corridor, box, [2.5, 0, 0.2])[2] == pytest.approx(0.1, abs=0.01)


@pytest.mark.parametrize("gaps", [[(-5.0, 1.0)], [(3.0, 0.0)], [(3.0, 1.0), (3.5, 1.0)]])
def test_corridor_rejects_gaps_outside_empty_or_overlapping(gaps):
    with pytest.raises(composer.EntityError, match="corridor gap"):
        arenas.Corridor(gaps=gaps)


def test_a_box_rests_on_the_table_top():
    table = arenas.Table(height=0.5)
    box = entities.Box(half_sizes=(0.05, 0.05, 0.05))
    table.attach(box)
    rest = settle(table, box, [0.1, 0.1, 0.7])
    assert rest[2] == pytest.approx(0.55, abs=0.005)
    assert table.mount.pos[0] == pytest.approx(-table.top_size[0] + 0.1)


def test_rough_terrain_is_reproducible_from_its_seed_and_flat_at_the_centre():
    first, again, other = (arenas.terrain_heights(32, seed) for seed in (1, 1, 2))
    np.testing.assert_array_equal(first, again)
    assert not np.array_equal(first, other)
    assert first.min() == 0.0 and first.max() <= 1.0 and first[16, 16] == 0.0
    terrain = arenas.RoughTerrain(seed=1, resolution=32, max_height=0.3)
    env = composer.Environment(composer.NullTask(terrain))
    model = env.physics.model
    assert model.hfield_nrow[0] == 32 and model.hfield_size[0][2] == 0.3
    assert np.ptp(model.hfield_data) == pytest.approx(1.0)
    with pytest.raises(composer.EntityError, match="resolution must be >= 8"):
        arenas.terrain_heights(4, 0)


def test_a_ball_dropped_on_rough_terrain_rests_on_it_not_under_it():
    terrain = arenas.RoughTerrain(seed=0, max_height=0.5, size=(4, 4))
    ball = entities.Sphere(radius=0.1)
    terrain.attach(ball)
    rest = settle(terrain, ball, [2.5, 2.5, 1.0], steps=1500)
    assert rest[2] > 0.09
