"""`action_repeat=k`: each step is k control steps with the same action (the frame skip of
pixel-based RL), rewards summed, discounts multiplied, ending early with the episode; the
same in one environment, in a VectorEnvironment (equal to SyncVectorEnv of single ones
through autoresets, with episodes ending within a repeat) and through gym.make."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import composer
import tasks  # noqa: F401  (registers the ids)
from tests.composer.scenes import SwingTask
from tests.composer.vector_scenes import BatchedSwing
from tests.vector_runs import assert_same_runs


def test_a_step_is_k_control_steps_with_their_rewards_summed():
    repeated = composer.Environment(SwingTask(), time_limit=1.0, action_repeat=3)
    plain = composer.Environment(SwingTask(), time_limit=1.0)
    repeated.reset(seed=2)
    plain.reset(seed=2)
    rng = np.random.default_rng(0)
    for _ in range(4):
        action = rng.uniform(-1, 1, 1)
        observation, reward, terminated, truncated, info = repeated.step(action)
        expected_reward = 0.0
        for _ in range(3):
            expected, step_reward, *_ = plain.step(action)
            expected_reward += step_reward
        assert reward == expected_reward
        for key, value in expected.items():
            np.testing.assert_array_equal(observation[key], value)
        assert info["discount"] == 1.0
        assert not (terminated or truncated)
    assert repeated.metadata["render_fps"] == pytest.approx(1 / (3 * repeated.control_timestep))


def test_the_episode_ends_within_a_repeat():
    # 1 s of 20 ms control steps is 50 of them: the 17th step of 3 runs two.
    env = composer.Environment(SwingTask(), time_limit=1.0, action_repeat=3)
    env.reset(seed=0)
    steps = 0
    truncated = False
    while not truncated:
        *_, truncated, _ = env.step(np.zeros(1))
        steps += 1
    assert steps == 17
    with pytest.raises(composer.EpisodeError):
        env.step(np.zeros(1))


@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP])
def test_vector_environments_repeat_as_single_ones(mode):
    def factory():
        return BatchedSwing(terminate_above=0.9)

    vector = composer.VectorEnvironment(
        factory, 3, time_limit=0.5, action_repeat=4, autoreset_mode=mode
    )
    reference = SyncVectorEnv(
        [lambda: composer.Environment(factory(), time_limit=0.5, action_repeat=4)] * 3,
        autoreset_mode=mode,
    )
    assert assert_same_runs(vector, reference, steps=40, seed=3) > 3
    vector.close()
    reference.close()


def test_gym_make_takes_action_repeat_and_refuses_a_bad_one():
    env = gymnasium.make("dm_control/cartpole-swingup-v0", action_repeat=2)
    env.reset(seed=0)
    steps = 0
    truncated = False
    while not truncated:
        *_, truncated, _ = env.step(np.zeros(1))
        steps += 1
    assert steps == 500  # 1,000 control steps of 10 ms
    with pytest.raises(composer.TaskError, match="action_repeat"):
        gymnasium.make("dm_control/cartpole-swingup-v0", action_repeat=0)
