"""`composer train [TASK]`: train a policy and show what it learned, with stable-baselines3
on this machine (the default) or with RLlib on Ray (`--engine ray`, docs/ray.md).

    $ composer train                      # Reach, with its recipe (see `composer train --help`)
    $ composer train CartpoleSwingup --algo ppo --timesteps 200000 --n-envs 8 --out runs/cp
    $ composer train CartpoleSwingup --engine ray --workers 2
    $ composer train CartpoleSwingup --pixels     # from 64x64 camera frames (docs/training)

Writes the policy, learning curve, video and metrics into the output folder (`_finish`);
Ctrl-C saves a checkpoint and exits with 130; the same command resumes it (`run_folder`).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import socket
from pathlib import Path
from typing import Any

from composer.cli import (
    arguments,
    catalog,
    describe,
    engines,
    output,
    plot,
    rollout,
    run_folder,
    video,
)
from composer.cli.engines.base import Engine, RunFolder, Session, StopOnInterrupt, Trainer
from composer.cli.errors import CliError
from composer.registration import TaskInfo

INTERRUPTED = 130
VIDEO_SECONDS = 3.0  # the trained policy's video: whole episodes, at least this long


def run(args: argparse.Namespace) -> int:
    """Train, then write the policy, curve, video and metrics; returns the exit status.
    One command for every engine, which it sees only through their contract
    (`composer.cli.engines`): the chosen engine's checks, trainer and policy name."""
    engine = engines.get(args.engine)
    check_options(args, engine)
    folder = run_folder.prepare(args, engine)
    engine.prepare(args)
    if not args.no_video:
        video.require()
    output.directory(folder.out)
    eval_env = catalog.make(args.info)
    try:
        with engine.trainer(args.info, folder, args) as trainer:
            return _train(engine, trainer, folder, eval_env, args)
    finally:
        eval_env.close()


def check_options(args: argparse.Namespace, engine: Engine[Any]) -> None:
    """Raise CliError for options of an engine other than `engine`: they belong to the
    default engine (and `engine` may say what to give instead), or need their own.
    `--n-envs`, `--vec` and `--tensorboard DIR` (stable-baselines3's TensorBoard scalars,
    with the evaluations as `eval/...`) are stable-baselines3's, `--workers`,
    `--envs-per-worker` and `--address` Ray's."""
    for other in engines.every():
        given = [name for name in other.options if getattr(args, name, None) is not None]
        if other.name == engine.name or not given:
            continue
        one = len(given) == 1
        if other.name == engines.DEFAULT:
            raise CliError(
                f"{arguments.flags(given)} {'belongs' if one else 'belong'} to the "
                f"{other.title} engine{engine.instead(given)}"
            )
        raise CliError(f"{arguments.flags(given)} need{'s' if one else ''} --engine {other.name}")


def _train(
    engine: Engine[Any],
    trainer: Trainer,
    folder: RunFolder[Any],
    eval_env: Any,
    args: argparse.Namespace,
) -> int:
    """Announce the run, train it until done or Ctrl-C, save it, and finish it (or say how
    to resume it); the exit status. Evaluations (deterministic actions, fixed seeds) run
    every `--eval-every` timesteps, a tenth of `--timesteps` by default, and once more after
    training; each saves a checkpoint. Ctrl-C saves a checkpoint and exits with status 130;
    the same command then resumes it, up to `--timesteps` in all."""
    progress, recipe = trainer.progress, trainer.recipe
    session = Session(
        progress, eval_env,
        eval_every=args.eval_every or max(1, recipe.timesteps // 10),
        eval_episodes=args.eval_episodes,
    )  # fmt: skip
    run_folder.clear_if_fresh(folder, engine)
    verb = f"resuming at {progress.timesteps:,} steps:" if folder.resumes else "training"
    print(f"{verb} {args.info.name} with {trainer.algorithm} to {trainer.end():,} steps on "
          f"{trainer.where} -> {folder.out}")  # fmt: skip
    for line in _plan(trainer, session):
        print("  " + line)
    print("hyperparameters: " + ", ".join(f"{k}={v}" for k, v in recipe.table().items()))
    with StopOnInterrupt() as stop:
        if progress.timesteps < recipe.timesteps:
            print("Ctrl-C saves a checkpoint and stops; the same command resumes", flush=True)
            trainer.learn(session, stop)
    session.save(trainer)
    if stop.requested:
        print(
            f"stopped at {progress.timesteps:,} steps after "
            f"{describe.duration(session.elapsed())}; checkpoint saved in "
            f"{folder.checkpoint.folder}; run the same command to resume"
        )
        return INTERRUPTED
    _finish(args.info, trainer, session, folder.out / engine.policy, args.eval_episodes,
            not args.no_video)  # fmt: skip
    return 0


def _plan(trainer: Trainer, session: Session) -> list[str]:
    """What the announcement says after its first line: why the run ends past the
    recipe's timesteps (its algorithm collects whole batches: PPO's whole rollouts, so
    `--timesteps 5000` on 8 environments of 256 steps trains 6,144), and when it evaluates
    (the progress bar's time left counts the evaluations: `composer.cli.progress`)."""
    lines = []
    collection, target, done = trainer.collection, trainer.recipe.timesteps, trainer.timesteps
    end = trainer.end()
    if end > target and done < target and collection.batch:
        lines.append(f"{target:,} steps rounded up to whole {collection.what} "
                     f"({collection.batch:,} steps each)")  # fmt: skip
    elif collection.batch is None and done < target:
        lines.append(f"{collection.what}: the run may end past {target:,} steps")
    evaluations = session.evaluations_until(end, done, collection.check_every)
    episodes = describe.count(session.eval_episodes, "episode")
    if evaluations:
        times = describe.count(evaluations, "time")
        lines.append(f"evaluating every {session.eval_every:,} steps ({times}, {episodes} "
                     "each), then once more after training")  # fmt: skip
    else:
        lines.append(f"evaluating once, after training ({episodes})")
    return lines


def _finish(
    info: TaskInfo, trainer: Trainer, session: Session, policy: Path, episodes: int, record: bool
) -> None:
    """After training: a final evaluation beside a random policy, then the output files
    (the policy at `policy`, the rest beside it). The output folder (default
    runs/TASK-ALGO, with Ray runs/TASK-ALGO-ray) gets the policy (`policy.zip`, with Ray the
    folder `policy/`; for `composer run` and `composer eval`), `learning_curve.png`,
    `video.mp4` of the trained policy, `metrics.json` (engine, timesteps, wall and CPU time,
    env steps per second, evaluations, final and random-policy returns, success rate where
    the task reports `is_success`, forward speed where it reports `forward_velocity`, and
    the engine's own keys) beside `checkpoint/`."""
    progress, out = session.progress, policy.parent
    final = session.evaluate(trainer)
    env = session.eval_env
    random = rollout.summary(
        rollout.run_episodes(env, rollout.random_policy(env, 0), episodes, rollout.EVAL_SEED)
    )
    progress.completed = True
    session.save(trainer)
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
        written.append(_record(info, trainer, out / run_folder.VIDEO).name)
    print(f"{info.name}, trained policy: {describe.summary(final)}")
    print(f"{info.name}, random policy:  {describe.summary(random)}")
    print(
        f"trained {progress.timesteps:,} steps in {describe.duration(progress.wall_time)} "
        f"({metrics['env_steps_per_second']:,} steps/s); wrote {', '.join(written)} in {out}"
    )
    print(f"watch it: composer run {catalog.command_line(info)} --policy {out} "
          f"--video {out / 'replay.mp4'}")  # fmt: skip


def _record(info: TaskInfo, trainer: Trainer, path: Path) -> Path:
    """A video of the trained policy's episodes, at least VIDEO_SECONDS long; the path
    written."""
    env = catalog.make(info, render_mode="rgb_array")
    try:
        seconds = info.default_kwargs.get("time_limit") or VIDEO_SECONDS
        episodes = math.ceil(VIDEO_SECONDS / seconds)
        frames: list[Any] = []
        policy = rollout.model_policy(trainer.predictor())
        rollout.run_episodes(env, policy, episodes, rollout.EVAL_SEED, frames)
        return video.write_video(frames, path, rollout.video_fps(env))
    finally:
        env.close()
