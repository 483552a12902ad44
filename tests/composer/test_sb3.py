"""composer.sb3: a VectorEnvironment as a stable-baselines3 VecEnv."""

from __future__ import annotations

import numpy as np
import pytest
from stable_baselines3 import PPO

import composer
from composer.sb3 import VecEnvAdapter, make_vec_env
from composer.vector import VectorEnvironment, make_vector_environment
from tests.composer.vector_scenes import BatchedSwing


def test_sb3_adapter_trains_ppo_and_reports_episode_ends_as_sb3_expects():
    with pytest.raises(composer.TaskError, match="SAME_STEP"):
        VecEnvAdapter(VectorEnvironment(BatchedSwing, 2))
    venv = make_vec_env("tests.composer.vector_scenes:BatchedSwing", 4, time_limit=0.08)
    venv.seed(3)
    first = venv.reset()
    assert first.shape == (4, venv.observation_space.shape[0])
    reference = make_vector_environment(4, BatchedSwing, time_limit=0.08, flatten_observations=True)
    np.testing.assert_array_equal(first, reference.reset(seed=3)[0])  # seeds 3, 4, 5, 6
    assert venv.get_attr("render_mode") == [None] * 4
    for _ in range(4):
        obs, rewards, dones, infos = venv.step(np.zeros((4, 1)))
    assert dones.all() and rewards.dtype == np.float32
    assert all(info["TimeLimit.truncated"] and "discount" in info for info in infos)
    assert infos[0]["terminal_observation"].shape == first.shape[1:]
    assert not np.array_equal(obs, np.stack([info["terminal_observation"] for info in infos]))
    model = PPO("MlpPolicy", venv, n_steps=16, batch_size=32, n_epochs=1, device="cpu", seed=0)
    model.learn(total_timesteps=128)
    assert model.num_timesteps >= 128


def test_sb3_images_are_every_environment_frame():
    vector = make_vector_environment(
        2, BatchedSwing, render_mode="rgb_array", autoreset_mode="SameStep"
    )
    venv = VecEnvAdapter(vector)
    venv.seed(3)
    venv.reset()
    images = venv.get_images()
    assert len(images) == 2 and all(image.shape == (240, 320, 3) for image in images)
    np.testing.assert_array_equal(images[1], vector.render()[1])
    assert venv.render(mode="rgb_array").shape == (480, 320, 3)  # stable-baselines3 tiles them
    venv.close()
