"""Environments in training jobs: many processes, many steps, same results."""

from __future__ import annotations

import gc
import json
import os
import subprocess
import sys
import tracemalloc

import gymnasium as gym
import numpy as np
import pytest

import mjcf
import tasks  # noqa: F401 - registers the composer/* ids
from tests.conftest import REPO

ENV_ID = "composer/CartpoleSwingup-v0"


def _trajectory(env_id: str, seed: int, steps: int) -> list[float]:
    """Rewards and the last observation of `steps` seeded random-action steps."""
    env = gym.make(env_id, flatten_observations=True)
    observation, _ = env.reset(seed=seed)
    env.action_space.seed(seed)
    rewards = []
    for _ in range(steps):
        observation, reward, terminated, truncated, _ = env.step(env.action_space.sample())
        rewards.append(float(reward))
        if terminated or truncated:
            observation, _ = env.reset()
    env.close()
    return rewards + observation.tolist()


def test_same_seed_same_trajectory_across_processes_and_resets() -> None:
    here = _trajectory(ENV_ID, seed=7, steps=300)
    assert here == _trajectory(ENV_ID, seed=7, steps=300)
    assert here != _trajectory(ENV_ID, seed=8, steps=300)
    code = (
        "import json, tasks\n"
        "from tests.reliability.test_long_runs import _trajectory\n"
        f"print(json.dumps(_trajectory({ENV_ID!r}, 7, 300)))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, check=True,
        env={**os.environ, "PYTHONHASHSEED": "123"},
    )  # fmt: skip
    assert json.loads(out.stdout.strip().splitlines()[-1]) == here  # bit for bit


def test_async_vector_env_runs_in_subprocesses() -> None:
    envs = gym.make_vec(ENV_ID, num_envs=2, vectorization_mode="async", flatten_observations=True)
    observations, _ = envs.reset(seed=[1, 2])
    for _ in range(50):
        observations, rewards, _, _, _ = envs.step(envs.action_space.sample())
    assert observations.shape == (2, *envs.single_observation_space.shape)
    assert np.all(np.isfinite(observations)) and np.all(np.isfinite(rewards))
    envs.close()


def test_stable_baselines3_subproc_vec_env() -> None:
    pytest.importorskip("stable_baselines3")
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import SubprocVecEnv

    vec = make_vec_env("tasks:" + ENV_ID, n_envs=2, vec_env_cls=SubprocVecEnv,
                       env_kwargs={"flatten_observations": True}, seed=3)  # fmt: skip
    vec.reset()
    for _ in range(50):
        observations, rewards, _, _ = vec.step(np.stack([vec.action_space.sample()] * 2))
    assert np.all(np.isfinite(observations)) and np.all(np.isfinite(rewards))
    vec.close()


def test_no_memory_growth_over_steps_and_resets() -> None:
    """Python allocations do not grow with steps and resets once warmed up."""
    env = gym.make(ENV_ID, flatten_observations=True, time_limit=0.5)
    env.reset(seed=0)

    def run(steps: int) -> None:
        for _ in range(steps):
            _, _, terminated, truncated, _ = env.step(env.action_space.sample())
            if terminated or truncated:
                env.reset()

    run(1_000)
    gc.collect()
    tracemalloc.start()
    before, _ = tracemalloc.get_traced_memory()
    run(5_000)
    gc.collect()
    after, _ = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    env.close()
    assert after - before < 256 * 1024, f"Python memory grew by {after - before} bytes"


def test_environments_made_and_closed_in_a_loop_are_freed() -> None:
    """A job that makes and closes environments (a sweep, restarts) frees each with its MJCF
    models: none is left once they are closed."""

    def live_models() -> int:
        gc.collect()
        return sum(1 for o in gc.get_objects() if isinstance(o, mjcf.RootElement))

    before = live_models()
    for env_id in (ENV_ID, "composer/Reach-v0", "dm_control/walker-walk-v0") * 2:
        env = gym.make(env_id)
        env.reset(seed=0)
        env.step(env.action_space.sample())
        env.close()
    del env
    assert live_models() == before
