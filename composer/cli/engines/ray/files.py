"""What the Ray engine writes, and how a folder shows it: its policy folder and its
checkpoint, told apart from the stable-baselines3 engine's without Ray installed.

    folder = files.find_policy(Path('runs/CartpoleSwingup-ppo-ray'))   # None: not Ray's
    checkpoint = files.Checkpoint('runs/CartpoleSwingup-ppo-ray/checkpoint')
    checkpoint.state()['timesteps'], checkpoint.algorithm_path()
    files.require_ray()          # MissingExtraError with the install command, without Ray

A policy is the folder `policy/` (policy.json, weights.npz, module/: see POLICY); a
checkpoint, `Checkpoint`'s folder. Reading either needs no Ray.
"""

from __future__ import annotations

import logging
from pathlib import Path

from composer.cli.engines import base
from composer.cli.errors import MissingExtraError

NAME = "ray"
# A policy is a folder: `policy.json` (the task, the algorithm, the network's settings as
# RLlib's model config, the action bounds, and the running mean and std of observations the
# module was fed: RLlib's MeanStdFilter, None without normalization), `weights.npz` (the
# inference part of the trained network: plain arrays), and `module/`, the same network as
# RLlib writes an RLModule (`RLModule.from_checkpoint` reads it, for your own RLlib code).
# `composer.cli.engines.ray.policy` reads and writes it.
POLICY = "policy"
RAY_INSTALL = "pip install torch==2.13.0 && pip install -e '.[ray]'"
POLICY_FILE = "policy.json"
WEIGHTS_FILE = "weights.npz"
POLICY_FORMAT = "composer-rllib-policy"
# policy.json's version: 2 says weights.npz and the model config are there.
POLICY_VERSION = 2


def require_ray(needs: str = "--engine ray needs") -> None:
    """Raise MissingExtraError with the install command unless Ray's RLlib and torch
    import; the message starts with `needs`."""
    try:
        import ray.rllib  # noqa: F401
        import torch  # noqa: F401  (RLlib's networks here are PyTorch's)
    except ImportError as e:
        raise MissingExtraError(
            f"{needs} the [ray] extra ({e.name or 'ray'} is missing): {RAY_INSTALL}"
        ) from e


def quiet_ray() -> None:
    """Keep Ray's and RLlib's Python notices (the new API stack, deprecations, token
    files) off the terminal: errors still show, and Ray's log files keep everything."""
    for name in ("ray", "ray.rllib", "ray.tune"):
        logging.getLogger(name).setLevel(logging.ERROR)


def find_policy(path: Path) -> Path | None:
    """The Ray policy folder `path` names: itself, its `policy/`, or the current policy of
    the checkpoint it is or holds; None when it names none (e.g. a stable-baselines3 file)."""
    for candidate in (path, path / POLICY):
        if (candidate / POLICY_FILE).is_file():
            return candidate
    for folder in (path, path / "checkpoint"):
        checkpoint = Checkpoint(folder)
        if checkpoint.exists():
            return checkpoint.current() / POLICY
    return None


class Checkpoint(base.Checkpoint):
    """A Ray training checkpoint in a folder.

    A checkpoint is a folder: one `<timesteps>-<tag>/` subfolder holding `algorithm/` (RLlib's
    Algorithm checkpoint: learner, optimizer, env-runner and filter states) and `policy/`,
    and `state.json` (the `Progress` with the engine's layout and which subfolder is current),
    saved atomically by `base.Checkpoint.save` (`composer.cli.engines.ray.training` saves it).
    """

    engine = NAME

    def algorithm_path(self) -> Path:
        """The RLlib Algorithm checkpoint of the last complete save."""
        return self.current() / "algorithm"

    def _complete(self) -> bool:
        return self.current() != self.folder and self.current().is_dir()
