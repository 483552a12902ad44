"""`composer train [TASK]`: train a policy with stable-baselines3 and show what it learned.

    $ composer train                      # Reach, with its recipe (see `composer train --help`)
    $ composer train CartpoleSwingup --algo ppo --timesteps 200000 --n-envs 8 --out runs/cp

Writes into the output folder (default runs/TASK-ALGO): `policy.zip` (for `composer run` and
`composer eval`), `learning_curve.png`, `video.mp4` of the trained policy, `metrics.json`
(timesteps, wall and CPU time, evaluations, final and random-policy returns, success rate
where the task reports `is_success`, forward speed where it reports `forward_velocity`)
and `checkpoint/`. Ctrl-C saves a checkpoint and exits with status 130; the same command
then resumes it, up to `--timesteps` in all. A folder holding a finished run is refused
unless `--resume` (train it on to a larger `--timesteps`) or `--fresh` (replace it) says
what to do (`composer.cli.run_folder`). Evaluations (deterministic actions, fixed seeds)
run every `--eval-every` timesteps, a tenth of the run by default; each saves a checkpoint.
`--tensorboard DIR` also logs stable-baselines3's TensorBoard scalars there, with the
evaluations as `eval/...`.
`--engine ray` trains with RLlib on Ray instead (`composer.cli.ray_training`).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
from pathlib import Path
from typing import Any

from composer.cli import catalog, output, plot, recipes, rollout, run_folder, training, video
from composer.cli.errors import CliError, PolicyError
from composer.registration import TaskInfo

INTERRUPTED = 130
VIDEO_SECONDS = 3.0  # the trained policy's video: whole episodes, at least this long


def run(args: argparse.Namespace) -> int:
    """Train, then write the policy, curve, video and metrics; returns the exit status."""
    from composer.cli import ray_training  # imports Ray only when it trains

    if args.engine == ray_training.ENGINE:
        return ray_training.run(args)
    ray_training.check_options(args)
    info = args.info
    if not args.no_video:
        video.require()
    if args.tensorboard:
        training.require_tensorboard()
        output.directory(args.tensorboard)
    out, checkpoint = _output(info, args)
    resumed = checkpoint.exists()
    progress, recipe = _start(info, checkpoint, out, args)
    saved = checkpoint.normalization_path
    venv = training.vec_env(
        info, recipe, progress.seed, saved if resumed and saved.is_file() else None
    )
    eval_env = catalog.make(info)
    try:
        if resumed:
            model = checkpoint.load(recipe.algo, venv, args.tensorboard)
            model.set_random_seed(progress.seed + model.num_timesteps)
        else:
            model = training.new_model(recipe, venv, progress.seed, args.tensorboard)
        session = training.Session(
            progress, checkpoint, eval_env,
            eval_every=args.eval_every or max(1, recipe.timesteps // 10),
            eval_episodes=args.eval_episodes,
        )  # fmt: skip
        _announce(info, recipe, out, model.num_timesteps if resumed else None)
        with training.StopOnInterrupt() as stop:
            remaining = recipe.timesteps - model.num_timesteps
            if remaining > 0:
                print("Ctrl-C saves a checkpoint and stops; the same command resumes", flush=True)
                model.learn(
                    remaining, callback=session.callback(stop, sys.stderr.isatty()),
                    reset_num_timesteps=not resumed, tb_log_name=out.name,
                )  # fmt: skip
        session.save(model)
        if stop.requested:
            print(
                f"stopped at {model.num_timesteps:,} steps after "
                f"{training.duration(session.elapsed())}; checkpoint saved in "
                f"{checkpoint.folder}; run the same command to resume"
            )
            return INTERRUPTED
        _finish(info, model, session, out, args.eval_episodes, not args.no_video)
    finally:
        venv.close()
        eval_env.close()
    return 0


def _output(info: TaskInfo, args: argparse.Namespace) -> tuple[Path, training.Checkpoint]:
    """The output folder (checked writable, cleared with --fresh) and its checkpoint, which
    --resume requires; raises CliError for a finished run without --resume or --fresh."""
    if args.resume and args.fresh:
        raise CliError("--resume and --fresh contradict each other; give one of them")
    resume = args.resume if isinstance(args.resume, str) else None  # --resume alone: True
    if resume and args.out and Path(resume) != Path(args.out):
        raise CliError(f"--resume {resume} and --out {args.out} differ; give one of them")
    algo = args.algo or recipes.default_algo(info.name)
    out = Path(resume or args.out or Path("runs") / f"{info.name}-{algo}")
    checkpoint = training.Checkpoint(out / "checkpoint")
    if args.resume and not checkpoint.exists():
        raise PolicyError(f"no checkpoint to resume in {out} (expected {checkpoint.state_path})")
    output.directory(out)
    run_folder.prepare(out, checkpoint, resume=bool(args.resume), fresh=args.fresh)
    return out, checkpoint


def _start(
    info: TaskInfo, checkpoint: training.Checkpoint, out: Path, args: argparse.Namespace
) -> tuple[training.Progress, recipes.Recipe]:
    """The progress and recipe to train with: the checkpoint's, or fresh ones."""
    if checkpoint.exists():
        progress = checkpoint.progress()
        recipe = _resumed_recipe(progress, info.name, out, args)
    else:
        algo = args.algo or recipes.default_algo(info.name)
        recipe = recipes.for_task(info.name, algo).replace(
            timesteps=args.timesteps, n_envs=args.n_envs, vec=args.vec
        )
        progress = training.Progress(info.name, info.env_id, algo, args.seed or 0, {})
    progress.recipe = recipe.table()
    progress.completed = False
    return progress, recipe


def _announce(info: TaskInfo, recipe: recipes.Recipe, out: Path, resumed_at: int | None) -> None:
    verb = "training" if resumed_at is None else f"resuming at {resumed_at:,} steps:"
    envs = f"{recipe.n_envs} environment{'s' if recipe.n_envs > 1 else ''}"
    print(f"{verb} {info.name} with {recipe.algo.upper()} to {recipe.timesteps:,} steps on "
          f"{envs} -> {out}")  # fmt: skip
    print("hyperparameters: " + ", ".join(f"{k}={v}" for k, v in recipe.table().items()))


def _resumed_recipe(
    progress: training.Progress, task: str, out: Path, args: argparse.Namespace
) -> recipes.Recipe:
    """The checkpoint's recipe, with a new total of timesteps if given."""
    if progress.task != task:
        raise PolicyError(
            f"the checkpoint in {out} is of task {progress.task!r}, not {task!r}; "
            "choose another --out folder"
        )
    if args.algo and args.algo != progress.algo:
        raise PolicyError(
            f"the checkpoint in {out} was trained with {progress.algo}, not {args.algo}; "
            "choose another --out folder"
        )
    recipe = recipes.Recipe(**{**progress.recipe, "net": tuple(progress.recipe["net"])})
    for option, given, kept in (
        ("--n-envs", args.n_envs, recipe.n_envs),
        ("--vec", args.vec, recipe.vec),
        ("--seed", args.seed, progress.seed),
    ):
        if given is not None and given != kept:
            print(f"note: resuming keeps the checkpoint's {option} {kept}")
    recipe = recipe.replace(timesteps=args.timesteps)
    if recipe.timesteps <= progress.timesteps and (progress.completed or args.timesteps):
        raise CliError(
            f"the run in {out} has {progress.timesteps:,} steps already "
            f"({run_folder.describe(progress)}); give --timesteps above that to train on"
        )
    return recipe


def _finish(
    info: TaskInfo, model: Any, session: training.Session, out: Path, episodes: int, record: bool
) -> None:
    """After training: a final evaluation beside a random policy, then the output files."""
    progress = session.progress
    final = session.evaluate(model)
    env = session.eval_env
    random = rollout.summary(
        rollout.run_episodes(env, rollout.random_policy(env, 0), episodes, training.EVAL_SEED)
    )
    progress.completed = True
    session.save(model)
    model.save(out / "policy.zip")
    metrics = {
        **progress.to_json(),
        "final": final,
        "random_policy": random,
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version()},
    }
    lines = [f" {json.dumps(key)}: {json.dumps(value)}" for key, value in metrics.items()]
    (out / "metrics.json").write_text("{\n" + ",\n".join(lines) + "\n}\n")
    plot.learning_curve(metrics, out / "learning_curve.png")
    written = ["policy.zip", "learning_curve.png", "metrics.json"]
    if record:
        written.append(_record(info, model, out / "video.mp4").name)
    print(f"{info.name}, trained policy: {rollout.describe_summary(final)}")
    print(f"{info.name}, random policy:  {rollout.describe_summary(random)}")
    print(
        f"trained {model.num_timesteps:,} steps in {training.duration(progress.wall_time)}; "
        f"wrote {', '.join(written)} in {out}"
    )
    print(f"watch it: composer run {info.name} --policy {out} --video {info.name}.mp4")


def _record(info: TaskInfo, model: Any, path: Path) -> Path:
    """A video of the model's episodes, at least VIDEO_SECONDS long; the path written."""
    env = catalog.make(info, render_mode="rgb_array")
    try:
        seconds = info.default_kwargs.get("time_limit") or VIDEO_SECONDS
        episodes = math.ceil(VIDEO_SECONDS / seconds)
        frames: list[Any] = []
        policy = rollout.model_policy(model)
        rollout.run_episodes(env, policy, episodes, training.EVAL_SEED, frames)
        return video.write_video(frames, path, rollout.video_fps(env))
    finally:
        env.close()
