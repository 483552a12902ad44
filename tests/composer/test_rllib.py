"""composer.rllib: one call makes a composer task id an RLlib environment; each env runner
steps its environments as one VectorEnvironment, with a seed of its own for each."""

from __future__ import annotations

import logging

import gymnasium
import numpy as np
import pytest

import composer
from composer.registration import RegistrationError
from composer.vector import VectorEnvironment

ray = pytest.importorskip("ray", reason="Ray is not installed: pip install -e '.[ray]'")
pytest.importorskip("ray.rllib", reason="RLlib is not installed: pip install -e '.[ray]'")

import composer.rllib  # noqa: E402  (needs Ray)
from composer.rllib import EnvCreator  # noqa: E402

CARTPOLE = "tasks.cartpole:CartpoleSwingup"


@pytest.fixture(scope="module")
def local_ray(ray_cluster):
    """This module's tests join the session's local Ray cluster (tests/ray_cluster.py)."""
    ray.init(address=ray_cluster.address, log_to_driver=False, logging_level=logging.ERROR)
    yield
    ray.shutdown()


def test_creator_makes_one_batch_whose_environments_have_seeds_of_their_own():
    creator = EnvCreator(CARTPOLE, {"time_limit": 10.0})
    vector = creator({"num_envs": 3, "nthread": 1})
    assert isinstance(vector.unwrapped, VectorEnvironment)
    assert vector.num_envs == 3 and vector.unwrapped.per_environment == []
    assert vector.single_observation_space.shape == (5,)  # flattened for RLlib's models
    observations, _ = vector.reset(seed=2)  # RLlib's seed for env runner 2 of seed 0
    for i in range(3):
        single = creator({"nthread": 1})  # a single environment ignores the batch's option
        assert isinstance(single, composer.Environment)
        expected, _ = single.reset(seed=2 * 3 + i)
        np.testing.assert_array_equal(observations[i], expected)
    assert len({tuple(row) for row in observations}) == 3


def test_creator_passes_env_config_to_the_task_and_environment():
    creator = EnvCreator(CARTPOLE, {"time_limit": 10.0})
    env = creator({"time_limit": 0.5, "flatten_observations": False})
    assert isinstance(env.observation_space, gymnasium.spaces.Dict)
    env.reset(seed=0)
    steps = 0
    while True:
        *_, terminated, truncated, _ = env.step(env.action_space.sample())
        steps += 1
        if terminated or truncated:
            break
    assert steps == 10  # 0.5 s of 0.05 s steps
    with pytest.raises(RegistrationError, match=r"unknown keyword argument\(s\) \['pole_mass'\]"):
        creator({"num_envs": 2, "pole_mass": 3.0})


def test_register_env_takes_a_gymnasium_id_or_module_and_id():
    assert composer.rllib.register_env("tasks:composer/Reach-v0") == "composer/Reach-v0"
    assert composer.rllib.register_env("composer/Reach-v0") == "composer/Reach-v0"
    with pytest.raises(RegistrationError, match="no composer task is registered as 'Reach'"):
        composer.rllib.register_env("Reach")
    with pytest.raises(RegistrationError, match="cannot import 'no_such_module'"):
        composer.rllib.register_env("no_such_module:composer/Reach-v0")


def test_rllib_trains_ppo_on_batched_env_runners(local_ray):
    from ray.rllib.algorithms.ppo import PPOConfig

    def runner_env(runner):  # nested: travels by value to the env runner
        env = runner.env.unwrapped
        return type(env).__name__, env.num_envs, env.per_environment

    env_id = composer.rllib.register_env("tasks:composer/CartpoleSwingup-v0")
    config = (
        PPOConfig()
        .environment(env_id, env_config={"time_limit": 1.0})  # 20-step episodes
        .env_runners(num_env_runners=1, num_envs_per_env_runner=4,
                     gym_env_vectorize_mode="vector_entry_point", rollout_fragment_length=32)
        .training(train_batch_size_per_learner=128, minibatch_size=64, num_epochs=1)
        .debugging(seed=0)
    )  # fmt: skip
    algo = config.build_algo()
    try:
        result = algo.train()["env_runners"]
        kinds = algo.env_runner_group.foreach_env_runner(runner_env, local_env_runner=False)
    finally:
        algo.stop()
    assert kinds == [("VectorEnvironment", 4, [])]  # one batch, nothing per environment
    assert result["num_env_steps_sampled"] == 128
    assert result["num_episodes"] >= 4 and result["episode_len_mean"] == 20


def test_an_unchanged_rllib_config_runs_on_single_environments(local_ray):
    from ray.rllib.algorithms.ppo import PPOConfig

    env_id = composer.rllib.register_env("tasks:composer/Reach-v0")
    config = (
        PPOConfig()
        .environment(env_id)
        .env_runners(num_env_runners=0, num_envs_per_env_runner=2, rollout_fragment_length=75)
        .training(train_batch_size_per_learner=150, minibatch_size=75, num_epochs=1)
    )
    algo = config.build_algo()
    try:
        result = algo.train()["env_runners"]
        env = algo.env_runner.env.unwrapped
        first = env.envs[0].unwrapped
    finally:
        algo.stop()
    assert isinstance(env, gymnasium.vector.SyncVectorEnv) and env.num_envs == 2
    assert isinstance(first, composer.Environment)
    assert result["num_episodes"] == 2 and result["episode_len_mean"] == 75
