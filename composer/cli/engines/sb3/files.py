"""What the stable-baselines3 engine writes, and how a folder shows it: its checkpoint, its
policy file, and the observation statistics a policy is served with. Reading these needs no
library.

    checkpoint = files.Checkpoint('runs/Reach-ppo/checkpoint')   # state.json, a save's folder
    checkpoint.model_path        # its model.zip
    files.find_policy(Path('runs/Reach-ppo'))    # runs/Reach-ppo/policy.zip, or None
    files.algo_of(Path('runs/Reach-ppo/policy.zip'))   # 'ppo'
    policy = files.NormalizedPolicy(model, statistics)  # predict() normalizes first
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from composer.cli.engines import base, untrusted
from composer.cli.errors import TRAIN_INSTALL, MissingExtraError, PolicyError

NAME = base.DEFAULT_ENGINE
# The policy is the model's .zip, whose `data` carries the training environments'
# observation statistics as plain JSON under NORMALIZATION (mean, var, epsilon, clip), so a
# policy normalizes what it is given as training did.
POLICY = "policy.zip"
ALGORITHMS = ("ppo", "sac")
# The model attribute, and the key of its .zip's `data`, that holds the observation
# statistics it was trained with (None or absent: no normalization).
NORMALIZATION = "observation_normalization"


class Checkpoint(base.Checkpoint):
    """A stable-baselines3 training checkpoint in a folder: the paths of its files in the
    last complete save.

    A checkpoint is a folder: a `<timesteps>-<tag>/` subfolder holding `model.zip`,
    `replay_buffer.pkl` for off-policy algorithms and `vecnormalize.pkl` for normalized recipes,
    and `state.json` (the `Progress`, naming that subfolder), saved atomically by
    `base.Checkpoint.save`: the weights are never paired with another save's statistics or
    buffer. (Checkpoints written before saves had subfolders hold the three files beside
    state.json; they are read, and replaced by the next save.)
    """

    engine = NAME
    MODEL = "model.zip"
    BUFFER = "replay_buffer.pkl"
    NORMALIZATION = "vecnormalize.pkl"

    @property
    def model_path(self) -> Path:
        """The model's .zip of the last save."""
        return self.current() / self.MODEL

    @property
    def buffer_path(self) -> Path:
        """The replay buffer of the last save (there for off-policy algorithms)."""
        return self.current() / self.BUFFER

    @property
    def normalization_path(self) -> Path:
        """The VecNormalize statistics of the last save (there for normalized recipes)."""
        return self.current() / self.NORMALIZATION

    def engine_files(self) -> list[Path]:
        """The saves' subfolders, and the files of a checkpoint written before saves had
        subfolders (and their partial files)."""
        earlier = [self.folder / name for name in (self.MODEL, self.BUFFER, self.NORMALIZATION)]
        files = [p for path in earlier for p in (path, base.partial_path(path)) if p.is_file()]
        return [*files, *super().engine_files()]

    def _complete(self) -> bool:
        return self.model_path.is_file()


def find_policy(path: Path) -> Path | None:
    """The policy .zip `path` names: itself, or in a folder written by `composer train` its
    policy.zip, else its checkpoint's model; None when there is none."""
    if path.suffix == ".zip":
        return path if path.is_file() else None
    if (path / POLICY).is_file():
        return path / POLICY
    for folder in (path / "checkpoint", path):
        checkpoint = Checkpoint(folder)
        if checkpoint.exists():
            return checkpoint.model_path
    return None


def algo_of(path: Path) -> str:
    """The algorithm ('ppo', 'sac') a stable-baselines3 .zip was saved by, from the module
    of its policy class: `stable_baselines3.sac.policies` for SAC, the shared actor-critic
    policies of `stable_baselines3.common.policies` for PPO. Its `data` is read as a
    stranger's (`untrusted`). Raises PolicyError."""
    with untrusted.archive(path, f"{path} as a stable-baselines3 policy file") as archive:
        data = untrusted.entry(untrusted.unpacker(), archive, "data", path)
    where = f"{path}: data"
    policy_class = untrusted.mapping(untrusted.json_data(data, where), where).get("policy_class")
    module = policy_class.get("__module__") if isinstance(policy_class, dict) else None
    if not isinstance(module, str):
        raise PolicyError(f"{path} does not name the module of its policy class")
    if module == "stable_baselines3.common.policies":
        algo = "ppo"
    else:
        algo = module.removeprefix("stable_baselines3.").partition(".")[0]
    if algo not in ALGORITHMS:
        raise PolicyError(f"{path} holds a {module!r} policy, not one of {list(ALGORITHMS)}")
    return algo


class NormalizedPolicy:
    """A stable-baselines3 policy or model served with the observation statistics it was
    trained with (NORMALIZATION's dict, or None): `predict` normalizes, then predicts."""

    def __init__(self, network: Any, statistics: dict[str, Any] | None) -> None:
        """Serve `network` (anything with stable-baselines3's `predict`)."""
        self.network = network
        self.statistics = statistics
        self.observation_space = network.observation_space
        self.action_space = network.action_space
        if statistics is not None:
            self._mean = np.asarray(statistics["mean"])
            self._scale = np.sqrt(np.asarray(statistics["var"]) + statistics["epsilon"])
            self._clip = statistics["clip"]

    def predict(self, observation: Any, deterministic: bool = True) -> tuple[np.ndarray, Any]:
        """The network's action for `observation`, normalized as in training first."""
        if self.statistics is not None:
            observation = np.clip((observation - self._mean) / self._scale, -self._clip,
                                  self._clip)  # fmt: skip
        return self.network.predict(observation, deterministic=deterministic)


def missing_library(error: ImportError, needs: str) -> MissingExtraError:
    """What to raise when stable-baselines3 or torch (the [train] extra) cannot be imported:
    '`needs` the [train] extra (torch is missing): `TRAIN_INSTALL`'."""
    missing = error.name or "stable_baselines3"
    return MissingExtraError(f"{needs} the [train] extra ({missing} is missing): {TRAIN_INSTALL}")
