"""`composer train TASK --engine ray`: train with RLlib on Ray, on this machine or a cluster,
with the outputs and the rules of the stable-baselines3 engine.

    $ composer train CartpoleSwingup --engine ray --workers 2 --timesteps 300000
    $ composer train AntRun --engine ray --address 10.0.0.1:6379 --workers 32

N env runners (Ray actors of one CPU each) each step M environments of the task as one
`composer.VectorEnvironment` (MuJoCo's batch, see `composer.rllib`); the learner runs in
this process. Without `--address` a local Ray instance is started for the run and stopped
after it; with one the run joins that cluster (`ray start --head` on one machine, `ray
start --address=HEAD:6379` on the others; docs/ray.md). `--workers` defaults to the CPUs
Ray has, `--envs-per-worker` to the recipe's environments divided among them.

The recipe is the task's stable-baselines3 recipe (`composer train --help`), adapted and
translated to RLlib as `composer.cli.ray_algorithm` says.

`composer.cli.train` drives the run through `trainer(info, folder, args)`, this engine's
`engine.Trainer`, as it drives stable-baselines3's: the same output folder rules
(`composer.cli.run_folder`: resuming, --resume, --fresh, a finished run refused), and the
same files, the policy being a folder: `policy/` (an RLlib RLModule with its observation
filter; `composer eval` and `composer run --policy` read it and the output folder),
`learning_curve.png`, `video.mp4`, `metrics.json` (the same keys, plus workers,
envs_per_worker, env_runner_restarts and ray) and `checkpoint/` (see
`composer.cli.ray_files`). A checkpoint resumes on as many workers as given now.

An env runner that dies (killed, out of memory, its machine gone) is restarted by Ray and
rejoins with the current weights; meanwhile the others sample the whole batch, so no
iteration is lost or short. The command prints each loss and return as it happens.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from composer.cli import engine, ray_instance, recipes, training
from composer.cli.progress import Bar
from composer.cli.progress import say as progress_line
from composer.cli.ray_algorithm import (
    EPISODES,
    Layout,
    build_algorithm,
    describe_runners,
    ray_recipe,
)
from composer.cli.ray_files import Checkpoint, RayModel, save_policy
from composer.cli.run_folder import RunFolder
from composer.registration import TaskInfo


class Trainer(engine.Trainer):
    """An RLlib Algorithm training on its env runners (`trainer` opens one)."""

    library = "RLlib"

    def __init__(
        self, model: RayModel, progress: engine.Progress, recipe: recipes.Recipe, layout: Layout
    ) -> None:
        """Train `model` on from `progress` as `recipe` says, sampling on `layout`'s env
        runners."""
        super().__init__(model, progress, recipe)
        self.layout = layout

    @property
    def where(self) -> str:
        """'2 env runners x 16 environments'."""
        layout = self.layout
        return (f"{engine.plural(layout.workers, 'env runner')} x "
                f"{engine.plural(layout.envs_per_worker, 'environment')}")  # fmt: skip

    def learn(self, session: training.Session, stop: training.StopOnInterrupt) -> None:
        """Iterate the algorithm (see `_train`), then take its policy for evaluation."""
        print(f"env runners: {describe_runners(self.model.algo)}", flush=True)
        _train(self.model, session, self.recipe, stop, self.layout)
        self.model.sync()

    def save_policy(self, path: Path) -> None:
        """The algorithm's current policy, as `ray_files.save_policy` writes it."""
        model = self.model
        engine.replace(path, lambda folder: save_policy(model.algo, folder, model.info))

    def metrics(self) -> dict[str, Any]:
        """The layout, the env runners restarted and the Ray cluster."""
        return dict(self.model.layout)


@contextlib.contextmanager
def trainer(
    info: TaskInfo, folder: RunFolder[Checkpoint], args: argparse.Namespace
) -> Iterator[Trainer]:
    """Within `with`: Ray running (see `ray_instance.running`) and the run in `folder` (resumed
    from its checkpoint, on the workers given now or else those it had, or new with the
    Ray engine's recipe) as an RLlib Algorithm, which is stopped after. Raises CliError
    when Ray cannot start, the cluster cannot be reached or is too small, or RLlib cannot
    build the algorithm."""
    checkpoint = folder.checkpoint
    saved = checkpoint.state() if folder.resumes else {}
    with ray_instance.running(args.address, args.workers or saved.get("workers")) as cpus:
        layout = _layout(args, saved, cpus)
        ray_instance.check_capacity(layout, cpus)
        note = ray_instance.oversubscribed(layout)
        if note is not None:
            print(note)
        progress, recipe = folder.start(
            args,
            lambda algo: ray_recipe(info.name, algo).replace(
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
            yield Trainer(model, progress, recipe, layout)
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
    algo = args.algo or saved.get("algo") or recipes.default_algo(args.info.name)
    default_envs = max(1, ray_recipe(args.info.name, algo).n_envs // workers)
    envs = args.envs_per_worker or saved.get("envs_per_worker") or default_envs
    return Layout(int(workers), int(envs), args.address)


def _policy_info(info: TaskInfo, recipe: recipes.Recipe) -> dict[str, Any]:
    return {"task": info.name, "env_id": info.env_id, "algo": recipe.algo}


def _layout_json(layout: Layout, restarts: int) -> dict[str, Any]:
    """What checkpoints and metrics.json record of the layout and the cluster; `restarts`:
    env runners restarted so far in the run."""
    import ray  # only when training on Ray: `composer train` imports this module

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


def _train(
    model: RayModel,
    session: training.Session,
    recipe: recipes.Recipe,
    stop: training.StopOnInterrupt,
    layout: Layout,
) -> None:
    """Iterate the algorithm until `recipe.timesteps`, evaluating when due and reporting
    env runners that fail and return, until Ctrl-C asks to stop."""
    algo = model.algo
    progress = session.progress
    bar = Bar.open(recipe.timesteps, progress.timesteps)
    say = functools.partial(progress_line, bar)
    healthy = layout.workers
    restarts = algo.env_runner_group.num_remote_worker_restarts()
    try:
        while progress.timesteps < recipe.timesteps and not stop.requested:
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
                model.sync()
                say(training.report(session.evaluate(model)))
                session.save(model)
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
        say(f"env runner restarted ({engine.plural(total, 'restart')} in this run); "
            f"env runners: {describe_runners(model.algo)}")  # fmt: skip
    elif now_healthy < healthy:
        left = (f"{now_healthy} of {layout.workers} left sample the whole batch" if now_healthy
                else "training waits")  # fmt: skip
        say(f"env runner lost: {left} until Ray restarts it")
    return now_healthy, now_restarts
