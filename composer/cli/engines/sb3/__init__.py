"""The stable-baselines3 engine (`--engine sb3`, the default): PPO and SAC on this machine,
the environments stepped in this process, one process each, or as one MuJoCo batch.

    engine = engines.get('sb3')                   # this package's ENGINE
    engine.find_policy(Path('runs/Reach-ppo'))    # runs/Reach-ppo/policy.zip

Modules: `files` (its checkpoint and policy file, read without any library), `policy`
(loading a policy, by default without unpickling) and `training` (environments, models,
the trainer). The last two import stable-baselines3 and torch, the [train] extra, and are
imported only when a policy is loaded or a run trains.
"""

from __future__ import annotations

import argparse
from contextlib import AbstractContextManager
from pathlib import Path
from typing import TYPE_CHECKING

import gymnasium

from composer.cli import arguments, recipes
from composer.cli.engines import base
from composer.cli.engines.sb3 import files
from composer.registration import TaskInfo

if TYPE_CHECKING:
    from composer.cli.engines.sb3.files import NormalizedPolicy


class Sb3Engine(base.Engine[files.Checkpoint]):
    """stable-baselines3 (see the package docstring)."""

    name = files.NAME
    title = "stable-baselines3"
    summary = "stable-baselines3 on this machine"
    extra = "train"
    checkpoint = files.Checkpoint
    policy = files.POLICY
    options = ("n_envs", "vec", "tensorboard")
    recipe_options = ("n_envs", "vec")

    def add_options(self, group: argparse._ArgumentGroup) -> None:
        """--n-envs, --vec and --tensorboard."""
        group.add_argument("--n-envs", type=arguments.positive_int, help="parallel environments")
        group.add_argument(
            "--vec", choices=recipes.VEC, help="step them in this process or one process each"
        )
        group.add_argument(
            "--tensorboard", metavar="DIR",
            help="also log to TensorBoard in DIR (stable-baselines3's)",
        )  # fmt: skip

    def prepare(self, args: argparse.Namespace) -> None:
        """stable-baselines3 and torch importable, and --tensorboard usable."""
        try:
            from composer.cli.engines.sb3 import training
        except ImportError as e:
            raise files.missing_library(e, "training with stable-baselines3 needs") from e
        training.require(args)

    def trainer(
        self, info: TaskInfo, folder: base.RunFolder[files.Checkpoint], args: argparse.Namespace
    ) -> AbstractContextManager[base.Trainer]:
        """`training.trainer`."""
        from composer.cli.engines.sb3 import training  # checked by `prepare`

        return training.trainer(info, folder, args)

    def find_policy(self, path: Path) -> Path | None:
        """`files.find_policy`."""
        return files.find_policy(path)

    def load_policy(self, found: Path, env: gymnasium.Env, trusted: bool) -> NormalizedPolicy:
        """`policy.load_policy`."""
        try:
            from composer.cli.engines.sb3 import policy
        except ImportError as e:
            needs = f"{found} was trained with --engine sb3: loading it needs"
            raise files.missing_library(e, needs) from e
        return policy.load_policy(found, env, trusted)


ENGINE = Sb3Engine()
