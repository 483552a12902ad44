"""Trained policies as `composer train` writes them, made quickly in the test's process: a
stable-baselines3 .zip trained briefly, and a Ray policy folder of a new RLlib module."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from composer.cli import catalog


def trained(tmp_path: Path, algo: str, normalized: bool) -> tuple[Path, Any]:
    """A stable-baselines3 model of `algo` ('ppo', 'sac') trained briefly on Reach and saved
    as `composer train` saves it; the path and the environment. Skips without the [train]
    extra."""
    sb3 = pytest.importorskip("stable_baselines3", reason="needs the [train] extra")
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    from composer.cli.engines.sb3 import training

    info = catalog.find("Reach")
    venv = DummyVecEnv([lambda: catalog.make(info)] * 2)
    if normalized:
        venv = VecNormalize(venv)
    algorithm = {"ppo": sb3.PPO, "sac": sb3.SAC}[algo]
    settings = {"n_steps": 64, "batch_size": 64} if algo == "ppo" else {"learning_starts": 32}
    model = algorithm("MlpPolicy", venv, policy_kwargs={"net_arch": [16, 16]}, seed=0,
                      device="cpu", **settings)  # fmt: skip
    model.learn(256)
    training.keep_normalization(model)
    path = tmp_path / f"{algorithm.__name__}.zip"
    model.save(path)
    return path, catalog.make(info)


def ray_policy_folder(tmp_path: Path, algo: str) -> Path:
    """A policy folder as `composer train --engine ray` writes it, of a new RLlib module of
    `algo` for CartpoleSwingup (random weights: what is compared is how they load). Skips
    without the [ray] extra."""
    pytest.importorskip("ray.rllib", reason="needs the [ray] extra")
    from ray.rllib.algorithms.ppo import PPOConfig
    from ray.rllib.algorithms.sac import SACConfig

    from composer.cli.engines.ray import files
    from composer.cli.engines.ray.policy import write_module

    env = catalog.make(catalog.find("CartpoleSwingup"))
    config = (PPOConfig() if algo == "ppo" else SACConfig()).rl_module(
        model_config={"fcnet_hiddens": [16, 16], "fcnet_activation": "tanh"}
    )
    spec = config.get_default_rl_module_spec()
    spec.observation_space, spec.action_space = env.observation_space, env.action_space
    spec.model_config = config.model_config  # with what the algorithm adds (SAC's twin_q)
    spec.inference_only = True
    module = spec.build()
    folder = tmp_path / "policy"
    write_module(module, folder)
    (folder / files.POLICY_FILE).write_text(json.dumps({
        "format": files.POLICY_FORMAT, "version": files.POLICY_VERSION,
        "task": "CartpoleSwingup", "env_id": "composer/CartpoleSwingup-v0", "algo": algo,
        "model_config": dict(module.model_config),
        "observation_shape": list(env.observation_space.shape),
        "action_low": env.action_space.low.tolist(), "action_high": env.action_space.high.tolist(),
        "observation_filter": {"mean": [0.1] * 5, "std": [2.0] * 5, "clip": 10.0},
    }))  # fmt: skip
    return folder
