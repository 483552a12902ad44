"""Every random draw the framework makes or passes on comes from the environment's seeded
random state, never numpy's global one: dm_control-style noise as an observation corruptor
(called with `random_state` by keyword), variators and prop placement. Before the fix the
environment called corruptors as `corruptor(value, random_state)`, which put the state in
`Additive`'s `current_value` and drew the noise from the global state."""

from __future__ import annotations

import numpy as np
from gymnasium.utils import seeding

import composer
from composer import observation, variation
from composer.variation import distributions, noises, rotations
from tests.composer.scenes import Block

DT = 0.01
SUBSTEPS = 5


def step_count(physics) -> np.ndarray:
    return np.array([physics.data.time / DT, 0.0])


class NoisyClock(composer.Task):
    """One observable, the step count, with dm_control-style additive noise."""

    def __init__(self) -> None:
        self._arena = composer.Arena()
        noise = noises.Additive(distributions.Normal(0.0, 1.0))
        self._clock = observation.Generic(step_count, corruptor=noise, enabled=True)
        self.set_timesteps(control_timestep=DT * SUBSTEPS, physics_timestep=DT)

    @property
    def root_entity(self):
        return self._arena

    @property
    def task_observables(self):
        return {"clock": self._clock}

    def get_reward(self, physics):
        return 0.0


def unchanged(global_state: tuple) -> bool:
    """Whether numpy's global random state is still `global_state`."""
    now = np.random.get_state()
    return all(np.array_equal(a, b) for a, b in zip(global_state, now, strict=True))


def episode(env, seed: int, steps: int = 3) -> np.ndarray:
    observations = [env.reset(seed=seed)[0]["clock"]]
    observations += [env.step(np.zeros(0))[0]["clock"] for _ in range(steps)]
    return np.array(observations)


def test_dm_control_noise_as_corruptor_draws_from_the_environment_seed():
    env = composer.Environment(NoisyClock())
    np.random.seed(1)
    first = episode(env, seed=4)
    np.random.seed(2)
    global_state = np.random.get_state()
    second = episode(env, seed=4)
    np.testing.assert_array_equal(first, second)
    assert unchanged(global_state)
    generator, _ = seeding.np_random(4)
    noise = np.random.RandomState(generator.bit_generator).normal(0.0, 1.0, size=(4, 2))
    clock = np.stack([[0, 0], [5, 0], [10, 0], [15, 0]])
    np.testing.assert_allclose(first, clock + noise)


def test_vector_environment_corruptors_draw_from_each_environment_seed():
    vector = composer.VectorEnvironment(NoisyClock, 2)
    np.random.seed(1)
    first = vector.reset(seed=8)[0]["clock"]
    np.random.seed(2)
    second = vector.reset(seed=8)[0]["clock"]
    np.testing.assert_array_equal(first, second)
    assert not np.array_equal(first[0], first[1])  # each environment its own noise
    vector.close()


class VariedBlocks(composer.Task):
    """Two blocks: MJCF size and physics mass varied, placed at random orientations."""

    def __init__(self) -> None:
        self._arena = composer.Arena()
        self.blocks = [Block(name="left"), Block(name="right")]
        for block in self.blocks:
            self._arena.add_free_entity(block)
        self.mjcf_variator = variation.MJCFVariator()
        self.physics_variator = variation.PhysicsVariator()
        for block in self.blocks:
            self.mjcf_variator.bind_attributes(block.geom, size=distributions.Uniform(0.02, 0.05))
            self.physics_variator.bind_attributes(
                block.body, mass=noises.Multiplicative(distributions.LogNormal(0, 0.2))
            )
        self.placer = composer.PropPlacer(
            self.blocks,
            position=distributions.Uniform([-0.5, -0.5, 0.1], [0.5, 0.5, 0.2]),
            quaternion=rotations.UniformQuaternion(),
            max_attempts_per_prop=50,
        )

    @property
    def root_entity(self):
        return self._arena

    def initialize_episode_mjcf(self, random_state):
        self.mjcf_variator.apply_variations(random_state)

    def initialize_episode(self, physics, random_state):
        self.physics_variator.apply_variations(physics, random_state)
        self.placer(physics, random_state)

    def get_reward(self, physics):
        return 0.0


def varied_state(env) -> np.ndarray:
    physics = env.physics
    parts = []
    for block in env.task.blocks:
        parts += [physics.bind(block.geom).size, physics.bind(block.body).mass]
        parts += list(block.get_pose(physics))
    return np.concatenate([np.ravel(p) for p in parts])


def test_variators_and_placement_draw_from_the_environment_seed_only():
    env = composer.Environment(VariedBlocks())
    np.random.seed(1)
    env.reset(seed=5)
    first = varied_state(env)
    np.random.seed(2)
    global_state = np.random.get_state()
    env.reset(seed=5)
    np.testing.assert_array_equal(varied_state(env), first)
    assert unchanged(global_state)
    env.reset(seed=6)
    assert not np.array_equal(varied_state(env), first)


def test_prop_placer_gives_variations_the_pose_as_initial_value():
    # dm_control draws a scalar-parametrized position in the shape of the prop's position
    # (three numbers), and noises add to the pose the prop had.
    task = VariedBlocks()
    env = composer.Environment(task)
    env.reset(seed=0)
    block = task.blocks[0]
    before = block.get_pose(env.physics)[0]
    jitter = noises.Additive(distributions.Uniform(-0.01, 0.01))
    composer.PropPlacer([block], position=jitter, ignore_collisions=True)(
        env.physics, np.random.RandomState(3)
    )
    after = block.get_pose(env.physics)[0]
    np.testing.assert_allclose(after, before + np.random.RandomState(3).uniform(-0.01, 0.01, 3))
    composer.PropPlacer([block], position=distributions.Uniform(1, 2), ignore_collisions=True)(
        env.physics, np.random.RandomState(4)
    )
    placed = block.get_pose(env.physics)[0]
    np.testing.assert_array_equal(placed, np.random.RandomState(4).uniform(1, 2, 3))
