"""Training with RLlib on Ray: the engine's `Trainer`, which `composer train --engine ray`
drives through the engine (`trainer`), and how a run is saved.

    with training.trainer(info, folder, args) as trainer:   # Ray running, the Algorithm built
        trainer.learn(session, stop)                        # algo.train() until done

Promise: an env runner that dies is restarted by Ray while the others sample the whole
batch, so no iteration is lost or short (`Trainer` says how runs are laid out and resumed).
"""

from __future__ import annotations

import argparse
import contextlib
import functools
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from composer.cli import describe, recipes
from composer.cli.engines import base
from composer.cli.engines.ray import instance
from composer.cli.engines.ray.algorithm import (
    EPISODES,
    SAC_FRAGMENT,
    Layout,
    build_algorithm,
    describe_runners,
)
from composer.cli.engines.ray.files import NAME, POLICY, Checkpoint
from composer.cli.engines.ray.policy import RayPolicy, current_policy, save_policy, uri
from composer.cli.errors import OutputError
from composer.cli.progress import Bar, evaluating
from composer.cli.progress import say as progress_line
from composer.registration import TaskInfo


class RayModel:
    """An RLlib Algorithm with what the run records of it: its timesteps, and `predict` by
    its current policy (call `sync()` after training changed it), which normalizes
    observations itself."""

    def __init__(self, algo: Any, info: dict[str, Any], layout: dict[str, Any]) -> None:
        """Wrap `algo`; `info` (task, env_id, algo) goes into policy files, `layout`
        (workers, envs per worker, restarts) into checkpoints."""
        self.algo = algo
        self.info = info
        self.layout = layout
        self.num_timesteps = 0
        self._policy: RayPolicy | None = None

    def sync(self) -> None:
        """Take the algorithm's current policy for `predict`."""
        self._policy = current_policy(self.algo, self.info)

    @property
    def policy(self) -> RayPolicy:
        """The policy `predict` uses (the algorithm's at the last `sync`)."""
        if self._policy is None:
            self.sync()
        assert self._policy is not None
        return self._policy

    def predict(self, observation: Any, deterministic: bool = True) -> tuple[np.ndarray, None]:
        """The policy's action (see RayPolicy.predict)."""
        return self.policy.predict(observation, deterministic)


class Trainer(base.Trainer):
    """An RLlib Algorithm training on its env runners (`trainer` opens one).

    N env runners (Ray actors of one CPU each) each step M environments of the task as one
    `composer.VectorEnvironment` (MuJoCo's batch, see `composer.rllib`); the learner runs in
    this process. Without `--address` a local Ray instance is started for the run and stopped
    after it (`instance`); with one the run joins that cluster. `--workers` defaults to the
    CPUs Ray has, `--envs-per-worker` to the recipe's environments divided among them; a
    checkpoint resumes on as many workers as given now.

    An env runner that dies (killed, out of memory, its machine gone) is restarted by Ray and
    rejoins with the current weights; meanwhile the others sample the whole batch, so no
    iteration is lost or short. The command prints each loss and return as it happens.
    """

    library = "RLlib"

    def __init__(
        self,
        model: RayModel,
        progress: base.Progress,
        recipe: recipes.Recipe,
        checkpoint: Checkpoint,
        layout: Layout,
    ) -> None:
        """Train `model` on from `progress` as `recipe` says, sampling on `layout`'s env
        runners, saving into `checkpoint`."""
        super().__init__(progress, recipe)
        self.model = model
        self.checkpoint = checkpoint
        self.layout = layout

    @property
    def where(self) -> str:
        """'2 env runners x 16 environments'."""
        layout = self.layout
        return (f"{describe.count(layout.workers, 'env runner')} x "
                f"{describe.count(layout.envs_per_worker, 'environment')}")  # fmt: skip

    @property
    def timesteps(self) -> int:
        """The environment steps sampled in the run."""
        return int(self.model.num_timesteps)

    @property
    def collection(self) -> base.Collection:
        """PPO samples a batch of `n_steps` per environment each iteration (RLlib's
        train_batch_size); SAC's iterations sample as RLlib's replay ratio and minimum
        iteration size say, not known beforehand. Evaluations are checked after each."""
        recipe, layout = self.recipe, self.layout
        if recipe.algo == "ppo":
            batch = recipe.n_envs * recipe.n_steps
            return base.Collection(batch, "iterations of RLlib's train batch", batch)
        what = "RLlib's SAC samples in iterations of a size it chooses"
        return base.Collection(None, what, layout.n_envs * SAC_FRAGMENT)

    def learn(self, session: base.Session, stop: base.StopOnInterrupt) -> None:
        """Iterate the algorithm (see `_train`), then take its policy for evaluation."""
        local = "" if self.layout.address else ": a local Ray instance, on 127.0.0.1 only"
        print(f"env runners: {describe_runners(self.model.algo)}{local}", flush=True)
        _train(self, session, stop)
        self.model.sync()

    def predictor(self) -> RayModel:
        """The algorithm's policy at the last `sync`."""
        return self.model

    def save_checkpoint(self) -> None:
        """Save the algorithm and policy with the progress and the layout (through
        `Checkpoint.save`, atomically). Raises OutputError."""
        model, checkpoint, progress = self.model, self.checkpoint, self.progress

        def write(folder: Path) -> None:
            model.algo.save_to_path(uri(folder / "algorithm"))
            save_policy(model.algo, folder / POLICY, model.info)

        try:
            checkpoint.save(progress.timesteps, write, {**progress.to_json(), **model.layout})
        except OSError as e:
            raise OutputError(f"cannot save checkpoint in {checkpoint.folder}: {e}") from e

    def save_policy(self, path: Path) -> None:
        """The algorithm's current policy, as `policy.save_policy` writes it."""
        model = self.model
        base.replace(path, lambda folder: save_policy(model.algo, folder, model.info))

    def metrics(self) -> dict[str, Any]:
        """The layout, the env runners restarted and the Ray cluster."""
        return dict(self.model.layout)


@contextlib.contextmanager
def trainer(
    info: TaskInfo, folder: base.RunFolder[Checkpoint], args: argparse.Namespace
) -> Iterator[Trainer]:
    """Within `with`: Ray running (see `instance.running`) and the run in `folder` (resumed
    from its checkpoint, on the workers given now or else those it had, or new with the
    task's recipe as this engine runs it) as an RLlib Algorithm, which is stopped after.
    Raises CliError when Ray cannot start, the cluster cannot be reached or is too small,
    or RLlib cannot build the algorithm."""
    import torch  # with Ray: checked by the engine's `prepare`

    torch.set_num_threads(base.TORCH_THREADS)  # the learner runs in this process
    checkpoint = folder.checkpoint
    saved = checkpoint.state() if folder.resumes else {}
    with instance.running(args.address, args.workers or saved.get("workers")) as cpus:
        layout = _layout(args, saved, cpus)
        instance.check_capacity(layout, cpus)
        note = instance.oversubscribed(layout)
        if note is not None:
            print(note)
        progress, recipe = folder.start(
            args,
            lambda algo: recipes.for_task(info, algo, NAME).replace(
                timesteps=args.timesteps, n_envs=layout.n_envs, vec="batched"
            ),
        )
        algo = build_algorithm(info, recipe, layout, progress.seed)
        try:
            if folder.resumes:
                algo.restore_from_path(str(checkpoint.algorithm_path().resolve()))
            restarts = saved.get("env_runner_restarts", 0)
            model = RayModel(algo, _policy_info(info, recipe), _layout_json(layout, restarts))
            model.num_timesteps = progress.timesteps
            yield Trainer(model, progress, recipe, checkpoint, layout)
        finally:
            algo.stop()
            # The Algorithm made itself a log folder in ~/ray_results that only Ray Tune
            # fills: an empty folder per run otherwise.
            with contextlib.suppress(OSError):
                Path(algo.logdir).rmdir()


# -- the run ---------------------------------------------------------------------------------


def _layout(args: argparse.Namespace, saved: dict[str, Any], cpus: int) -> Layout:
    """The workers and environments of this session: as given, else those of the
    checkpoint's state `saved`, else as many workers as Ray has CPUs and the recipe's
    environments among them."""
    workers = args.workers or saved.get("workers") or max(1, cpus)
    algo = args.algo or saved.get("algo") or recipes.default_algo(args.info)
    default_envs = max(1, recipes.for_task(args.info, algo, NAME).n_envs // workers)
    envs = args.envs_per_worker or saved.get("envs_per_worker") or default_envs
    return Layout(int(workers), int(envs), args.address)


def _policy_info(info: TaskInfo, recipe: recipes.Recipe) -> dict[str, Any]:
    return {"task": info.name, "env_id": info.env_id, "algo": recipe.algo}


def _layout_json(layout: Layout, restarts: int) -> dict[str, Any]:
    """What checkpoints and metrics.json record of the layout and the cluster; `restarts`:
    env runners restarted so far in the run."""
    import ray  # running: `trainer` started it

    return {
        "workers": layout.workers,
        "envs_per_worker": layout.envs_per_worker,
        "env_runner_restarts": int(restarts),
        "ray": {
            "version": ray.__version__,
            "cluster": layout.address or "local",
            "nodes": len([n for n in ray.nodes() if n.get("Alive")]),
            "cpus": int(ray.cluster_resources().get("CPU", 0)),
        },
    }


def _train(trainer: Trainer, session: base.Session, stop: base.StopOnInterrupt) -> None:
    """Iterate the algorithm until the recipe's timesteps, evaluating when due and
    reporting env runners that fail and return, until Ctrl-C asks to stop."""
    model, layout = trainer.model, trainer.layout
    algo = model.algo
    progress = session.progress
    end = trainer.end()
    evaluations = session.evaluations_until(end, progress.timesteps, trainer.collection.check_every)
    bar = Bar.open(end, progress.timesteps, evaluations)
    say = functools.partial(progress_line, bar)
    healthy = layout.workers
    restarts = algo.env_runner_group.num_remote_worker_restarts()
    try:
        while progress.timesteps < trainer.recipe.timesteps and not stop.requested:
            result = algo.train()
            runners = result.get("env_runners", {})
            # No runner sampled (all lost, restarting): RLlib reports NaN steps.
            steps = int(np.nan_to_num(runners.get("num_env_steps_sampled", 0)))
            progress.timesteps += steps
            model.num_timesteps = progress.timesteps
            for episode_return, success in runners.get(EPISODES, []):
                progress.record_episode(progress.timesteps, episode_return, success)
            if bar is not None:
                bar.advance_to(progress.timesteps)
            healthy, restarts = _watch_runners(model, healthy, restarts, layout, say)
            if not stop.requested and session.due(progress.timesteps):
                with evaluating(bar):
                    model.sync()
                    result = session.evaluate(trainer)
                say(describe.evaluation(result))
                session.save(trainer)
    finally:
        if bar is not None:
            bar.close()


def _watch_runners(
    model: RayModel, healthy: int, restarts: int, layout: Layout, say: Any
) -> tuple[int, int]:
    """Print when env runners stop or come back; the new healthy and restart counts."""
    group = model.algo.env_runner_group
    now_healthy = group.num_healthy_remote_workers()
    now_restarts = group.num_remote_worker_restarts()
    if now_restarts > restarts:
        total = model.layout["env_runner_restarts"] + now_restarts - restarts
        model.layout["env_runner_restarts"] = total
        say(f"env runner restarted ({describe.count(total, 'restart')} in this run); "
            f"env runners: {describe_runners(model.algo)}")  # fmt: skip
    elif now_healthy < healthy:
        left = (f"{now_healthy} of {layout.workers} left sample the whole batch" if now_healthy
                else "training waits")  # fmt: skip
        say(f"env runner lost: {left} until Ray restarts it")
    return now_healthy, now_restarts
