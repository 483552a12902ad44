"""`composer train [TASK]`: train a policy and show what it learned, with stable-baselines3
on this machine (the default) or with RLlib on Ray (`--engine ray`, docs/ray.md).

    $ composer train                      # Reach, with its recipe (see `composer train --help`)
    $ composer train CartpoleSwingup --algo ppo --timesteps 200000 --n-envs 8 --out runs/cp
    $ composer train CartpoleSwingup --engine ray --workers 2

Writes into the output folder (default runs/TASK-ALGO, with Ray runs/TASK-ALGO-ray) the
policy (`policy.zip`, with Ray the folder `policy/`; for `composer run` and `composer
eval`), `learning_curve.png`, `video.mp4` of the trained policy, `metrics.json` (engine,
timesteps, wall and CPU time, env steps per second, evaluations, final and random-policy
returns, success rate where the task reports `is_success`, forward speed where it reports
`forward_velocity`, and the engine's own keys) and `checkpoint/`. Ctrl-C saves a
checkpoint and exits with status 130; the same command then resumes it, up to
`--timesteps` in all. A folder holding a finished run is refused unless `--resume` (train
it on to a larger `--timesteps`) or `--fresh` (replace it) says what to do, and one holding
the other engine's run is refused (`composer.cli.run_folder` keeps these rules).
Evaluations (deterministic actions, fixed seeds) run every `--eval-every` timesteps, a
tenth of the run by default; each saves a checkpoint.

This module is the command, one for both engines; each engine gives it a checkpoint and a
trainer (`composer.cli.engine`): `composer.cli.training` for stable-baselines3,
`composer.cli.ray_training` for Ray. An option of one engine is refused with the other:
`--n-envs`, `--vec` and `--tensorboard DIR` (stable-baselines3's TensorBoard scalars, with
the evaluations as `eval/...`) are stable-baselines3's, `--workers`, `--envs-per-worker` and
`--address` Ray's.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import socket
from collections.abc import Callable
from contextlib import AbstractContextManager
from pathlib import Path
from typing import Any

from composer.cli import (
    catalog,
    output,
    plot,
    ray_files,
    ray_instance,
    ray_training,
    rollout,
    run_folder,
    training,
    video,
)
from composer.cli.engine import Trainer
from composer.cli.errors import CliError
from composer.cli.run_folder import CheckpointType, RunFolder
from composer.registration import TaskInfo

INTERRUPTED = 130
VIDEO_SECONDS = 3.0  # the trained policy's video: whole episodes, at least this long
# The options only one engine reads.
SB3_ONLY = ("n_envs", "vec", "tensorboard")
RAY_ONLY = ("workers", "envs_per_worker", "address")


def run(args: argparse.Namespace) -> int:
    """Train, then write the policy, curve, video and metrics; returns the exit status."""
    check_options(args)
    if args.engine == ray_files.ENGINE:
        return _run(args, run_folder.prepare(args, ray_files.Checkpoint), ray_training.trainer)
    return _run(args, run_folder.prepare(args, training.Checkpoint), training.trainer)


def _run(
    args: argparse.Namespace,
    folder: RunFolder[CheckpointType],
    open_trainer: Callable[
        [TaskInfo, RunFolder[CheckpointType], argparse.Namespace], AbstractContextManager[Trainer]
    ],
) -> int:
    """`run` with the engine of `folder`'s checkpoints, whose trainer `open_trainer` opens."""
    if args.engine == ray_files.ENGINE:
        ray_instance.authenticate(args.address)  # before Ray is imported
        ray_files.require_ray()
    elif args.tensorboard:
        training.require_tensorboard()
        output.directory(args.tensorboard)
    if not args.no_video:
        video.require()
    output.directory(folder.out)
    eval_env = catalog.make(args.info)
    try:
        with open_trainer(args.info, folder, args) as trainer:
            return _train(trainer, folder, eval_env, args)
    finally:
        eval_env.close()


def check_options(args: argparse.Namespace) -> None:
    """Raise CliError for options of the engine not chosen."""
    if args.engine == ray_files.ENGINE:
        given = [name for name in SB3_ONLY if getattr(args, name, None) is not None]
        if given:
            message = f"{_flags(given)} {'belongs' if len(given) == 1 else 'belong'} to the "
            message += "stable-baselines3 engine"
            if {"n_envs", "vec"} & set(given):
                message += "; with --engine ray give --workers and --envs-per-worker"
            if "tensorboard" in given:
                message += "; --engine ray logs no TensorBoard scalars (see docs/ray.md)"
            raise CliError(message)
    else:
        given = [name for name in RAY_ONLY if getattr(args, name, None) is not None]
        if given:
            raise CliError(f"{_flags(given)} need{'s' if len(given) == 1 else ''} --engine ray")


def _flags(names: list[str]) -> str:
    return " and ".join("--" + name.replace("_", "-") for name in names)


def _train(
    trainer: Trainer, folder: RunFolder[Any], eval_env: Any, args: argparse.Namespace
) -> int:
    """Announce the run, train it until done or Ctrl-C, save it, and finish it (or say how
    to resume it); the exit status."""
    progress, recipe = trainer.progress, trainer.recipe
    session = training.Session(
        progress, folder.checkpoint, eval_env,
        eval_every=args.eval_every or max(1, recipe.timesteps // 10),
        eval_episodes=args.eval_episodes,
    )  # fmt: skip
    folder.clear_if_fresh()
    verb = f"resuming at {progress.timesteps:,} steps:" if folder.resumes else "training"
    print(f"{verb} {args.info.name} with {trainer.algorithm} to {recipe.timesteps:,} steps on "
          f"{trainer.where} -> {folder.out}")  # fmt: skip
    print("hyperparameters: " + ", ".join(f"{k}={v}" for k, v in recipe.table().items()))
    with training.StopOnInterrupt() as stop:
        if progress.timesteps < recipe.timesteps:
            print("Ctrl-C saves a checkpoint and stops; the same command resumes", flush=True)
            trainer.learn(session, stop)
    session.save(trainer.model)
    if stop.requested:
        print(
            f"stopped at {progress.timesteps:,} steps after "
            f"{training.duration(session.elapsed())}; checkpoint saved in "
            f"{folder.checkpoint.folder}; run the same command to resume"
        )
        return INTERRUPTED
    _finish(args.info, trainer, session, folder, args.eval_episodes, not args.no_video)
    return 0


def _finish(
    info: TaskInfo,
    trainer: Trainer,
    session: training.Session,
    folder: RunFolder[Any],
    episodes: int,
    record: bool,
) -> None:
    """After training: a final evaluation beside a random policy, then the output files."""
    progress, model, out = session.progress, trainer.model, folder.out
    final = session.evaluate(model)
    env = session.eval_env
    random = rollout.summary(
        rollout.run_episodes(env, rollout.random_policy(env, 0), episodes, training.EVAL_SEED)
    )
    progress.completed = True
    session.save(model)
    policy = out / folder.checkpoint.policy
    trainer.save_policy(policy)
    metrics = {
        **progress.to_json(),
        "final": final,
        "random_policy": random,
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version(),
                    "host": socket.gethostname()},
        **trainer.metrics(),
        "env_steps_per_second": round(progress.timesteps / max(progress.wall_time, 1e-9)),
    }  # fmt: skip
    lines = [f" {json.dumps(key)}: {json.dumps(value)}" for key, value in metrics.items()]
    (out / run_folder.METRICS).write_text("{\n" + ",\n".join(lines) + "\n}\n")
    plot.learning_curve(metrics, out / run_folder.CURVE)
    written = [policy.name + ("/" if policy.is_dir() else ""), run_folder.CURVE, run_folder.METRICS]
    if record:
        written.append(_record(info, model, out / run_folder.VIDEO).name)
    print(f"{info.name}, trained policy: {rollout.describe_summary(final)}")
    print(f"{info.name}, random policy:  {rollout.describe_summary(random)}")
    print(
        f"trained {progress.timesteps:,} steps in {training.duration(progress.wall_time)} "
        f"({metrics['env_steps_per_second']:,} steps/s); wrote {', '.join(written)} in {out}"
    )
    print(f"watch it: composer run {info.name} --policy {out} --video {info.name}.mp4")


def _record(info: TaskInfo, model: Any, path: Path) -> Path:
    """A video of the model's episodes, at least VIDEO_SECONDS long; the path written."""
    env = catalog.make(info, render_mode="rgb_array")
    try:
        seconds = info.default_kwargs.get("time_limit") or VIDEO_SECONDS
        episodes = math.ceil(VIDEO_SECONDS / seconds)
        frames: list[Any] = []
        rollout.run_episodes(env, rollout.model_policy(model), episodes, training.EVAL_SEED, frames)
        return video.write_video(frames, path, rollout.video_fps(env))
    finally:
        env.close()
