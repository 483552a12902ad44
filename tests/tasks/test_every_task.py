"""Every registered task: gym.make, spaces, random rollouts, seeding, check_env, rendering."""

from __future__ import annotations

import math
import warnings

import gymnasium
import mujoco
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import tasks
from composer import registration
from tests.tasks.helpers import SIZES, make

IDS = list(tasks.IDS)


def test_import_tasks_registers_every_documented_id():
    assert set(tasks.IDS) == set(SIZES)
    for env_id in tasks.IDS:
        assert env_id in gymnasium.registry
        assert env_id in registration.registered()


@pytest.mark.parametrize("env_id", IDS)
def test_flattened_spaces_have_the_documented_sizes(env_id):
    env = make(env_id, flatten_observations=True)
    obs_size, action_size = SIZES[env_id]
    assert env.observation_space.shape == (obs_size,)
    assert env.action_space.shape == (action_size,)
    assert env.action_space.dtype == np.float32
    assert np.all(env.action_space.low == -1) and np.all(env.action_space.high == 1)
    env.close()


def rollout(env: gymnasium.Env, seed: int, steps: int) -> list:
    """`steps` random steps from reset(seed), resetting after each episode end; checks
    what every step must satisfy and returns the trajectory."""
    obs, info = env.reset(seed=seed)
    env.action_space.seed(seed)
    assert obs in env.observation_space
    trajectory: list = [obs]
    for _ in range(steps):
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        assert obs in env.observation_space
        assert all(np.all(np.isfinite(v)) for v in _values(obs))
        assert isinstance(reward, float) and math.isfinite(reward)
        assert isinstance(terminated, bool) and isinstance(truncated, bool)
        assert "physics_error" not in info
        trajectory.append((obs, reward, terminated, truncated))
        if terminated or truncated:
            obs, info = env.reset()
            trajectory.append(obs)
    return trajectory


def _values(obs):
    return obs.values() if isinstance(obs, dict) else [obs]


def _same(a, b) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list | tuple):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    return bool(np.array_equal(a, b))


@pytest.mark.parametrize("env_id", IDS)
def test_two_hundred_random_steps_and_the_same_seed_gives_the_same_trajectory(env_id):
    # A short time limit so that truncation (and reset after it) happens within the run.
    first = rollout(make(env_id, time_limit=2.0), seed=3, steps=200)
    second = rollout(make(env_id, time_limit=2.0), seed=3, steps=200)
    assert _same(first, second)
    ends = [step for step in first if isinstance(step, tuple) and (step[2] or step[3])]
    assert ends, "no episode ended within 200 steps of a 2 s time limit"
    other = rollout(make(env_id, time_limit=2.0), seed=4, steps=20)
    assert not _same(first[:21], other)


@pytest.mark.parametrize("env_id", IDS)
def test_time_limit_truncates_after_its_steps(env_id):
    env = make(env_id, time_limit=0.5, randomize=False)
    control = env.unwrapped.control_timestep
    env.reset(seed=0)
    zero = np.zeros(env.action_space.shape, np.float32)
    expected = math.ceil(0.5 / control - 1e-9)
    for step in range(1, expected + 1):
        _, _, terminated, truncated, _ = env.step(zero)
        if terminated:
            pytest.skip("terminated before the time limit with zero actions")
        assert truncated == (step == expected)


@pytest.mark.parametrize("env_id", IDS)
def test_check_env_passes_with_warnings_as_errors(env_id):
    env = make(env_id, render_mode="rgb_array")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)
    env.close()


@pytest.mark.parametrize("env_id", IDS)
def test_rendered_frame_shows_the_entities_not_just_the_arena(env_id):
    env = make(env_id, render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (240, 320, 3) and frame.dtype == np.uint8
    # The same view with every entity's geoms hidden is the empty arena's render.
    task = env.unwrapped.task
    physics = env.unwrapped.physics
    for entity in task.root_entity.iter_entities():
        if entity is not task.root_entity:
            geoms = entity.mjcf_model.find_all("geom")
            physics.model.geom_group[np.atleast_1d(physics.bind(geoms).ids)] = 5
    option = mujoco.MjvOption()
    option.geomgroup[5] = 0
    camera = getattr(task, "render_camera", -1)
    empty = physics.render(240, 320, camera_id=camera, scene_option=option)
    changed = np.any(frame != empty, axis=-1).mean()
    assert changed > 0.005, f"only {changed:.2%} of the pixels show the task's entities"
    assert frame.std() > 5  # not a blank frame
    env.close()
