"""A smoke check that stable-baselines3 trains on a task: PPO's loss moves and its updates
change the policy. (Learning curves are the CLI's job; this only shows the pieces fit.)"""

from __future__ import annotations

import numpy as np
import pytest

import tasks  # noqa: F401  (registers the ids)

sb3 = pytest.importorskip("stable_baselines3", reason="the [train] extra is not installed")


@pytest.mark.parametrize("env_id", ["composer/Reach-v0", "composer/CartpoleSwingup-v0"])
def test_ppo_loss_moves_and_updates_change_the_policy(env_id):
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.logger import KVWriter, Logger

    class Losses(KVWriter):
        def __init__(self) -> None:
            self.values: list[float] = []

        def write(self, key_values, key_excluded, step=0) -> None:
            if "train/loss" in key_values:
                self.values.append(float(key_values["train/loss"]))

    env = make_vec_env(env_id, n_envs=2, seed=0, env_kwargs={"flatten_observations": True})
    model = sb3.PPO("MlpPolicy", env, n_steps=64, batch_size=64, n_epochs=2, seed=0,
                    device="cpu")  # fmt: skip
    losses = Losses()
    model.set_logger(Logger(folder=None, output_formats=[losses]))
    before = [p.detach().clone().numpy() for p in model.policy.parameters()]
    model.learn(total_timesteps=3 * 128)  # three rollouts: losses logged after two updates
    after = [p.detach().numpy() for p in model.policy.parameters()]
    assert len(losses.values) == 2 and np.all(np.isfinite(losses.values))
    assert losses.values[0] != losses.values[1]
    assert all(np.isfinite(p).all() for p in after)
    assert any(not np.array_equal(a, b) for a, b in zip(after, before, strict=True))
