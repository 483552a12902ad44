"""The Ray engine (`--engine ray`, the [ray] extra): RLlib's PPO and SAC on N Ray env
runners of M environments each, on this machine or a cluster (docs/ray.md).

    $ composer train CartpoleSwingup --engine ray --workers 2 --timesteps 300000
    $ composer train AntRun --engine ray --address 10.0.0.1:6379 --workers 32

It keeps the other engine's outputs and output-folder rules; its policy is a folder,
`policy/`, and docs/ray.md lists what it writes. Ray is imported only inside the functions
of its modules (`files`, `policy`, `algorithm`, `instance`, `training`), to train or load.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from contextlib import AbstractContextManager
from pathlib import Path
from typing import TYPE_CHECKING

import gymnasium

from composer.cli import arguments, catalog
from composer.cli.engines import base
from composer.cli.engines.ray import files
from composer.cli.errors import CliError
from composer.registration import TaskInfo

if TYPE_CHECKING:
    from composer.cli.engines.ray.policy import RayPolicy


class RayEngine(base.Engine[files.Checkpoint]):
    """RLlib on Ray (see the package docstring)."""

    name = files.NAME
    title = "RLlib on Ray"
    summary = "RLlib on Ray ([ray] extra)"
    extra = "ray"
    checkpoint = files.Checkpoint
    policy = files.POLICY
    options = ("workers", "envs_per_worker", "address")

    def add_options(self, group: argparse._ArgumentGroup) -> None:
        """--workers, --envs-per-worker and --address."""
        group.add_argument(
            "--workers", type=arguments.positive_int, metavar="N",
            help="env runners (default: CPUs)",
        )  # fmt: skip
        group.add_argument(
            "--envs-per-worker", type=arguments.positive_int, metavar="M",
            help="environments each (default: the recipe's, divided among them)",
        )  # fmt: skip
        group.add_argument(
            "--address", metavar="HOST:PORT", help="join this cluster (default: start locally)"
        )

    def instead(self, given: Sequence[str]) -> str:
        """Where the environments are set with Ray; that RLlib logs no TensorBoard scalars."""
        hints = ""
        if {"n_envs", "vec"} & set(given):
            hints += "; with --engine ray give --workers and --envs-per-worker"
        if "tensorboard" in given:  # RLlib writes them only under Ray Tune, not run here
            hints += "; --engine ray logs no TensorBoard scalars (see docs/ray.md)"
        return hints

    def prepare(self, args: argparse.Namespace) -> None:
        """A cluster's address reachable, Ray's RLlib and torch importable, in token mode
        for a cluster that has one, a local instance on 127.0.0.1 only
        (`instance.loopback_only`); a task observed through its camera is refused
        (CliError): the env runners' batch (`composer.VectorEnvironment`) has no camera
        observations yet."""
        from composer.cli.engines.ray import instance

        if catalog.observes_pixels(args.info):
            raise CliError(
                f"--engine ray cannot train {args.info.name} yet: its env runners step their "
                "environments as one composer.VectorEnvironment, which has no camera "
                "observations; train from pixels with --engine sb3 (docs/training)"
            )

        if args.address is not None:  # at once, not after Ray's and torch's imports
            instance.check_reachable(args.address)
        instance.authenticate(args.address)  # before Ray is imported
        instance.loopback_only(args.address)
        files.require_ray()

    def trainer(
        self, info: TaskInfo, folder: base.RunFolder[files.Checkpoint], args: argparse.Namespace
    ) -> AbstractContextManager[base.Trainer]:
        """`training.trainer`."""
        from composer.cli.engines.ray import training

        return training.trainer(info, folder, args)

    def find_policy(self, path: Path) -> Path | None:
        """`files.find_policy`."""
        return files.find_policy(path)

    def load_policy(self, found: Path, env: gymnasium.Env, trusted: bool) -> RayPolicy:
        """`policy.load_policy`."""
        from composer.cli.engines.ray import policy

        return policy.load_policy(found, env, trusted)


ENGINE = RayEngine()
