"""`composer train TASK --engine ray`: train with RLlib on Ray, on this machine or a cluster,
with the outputs of the stable-baselines3 engine.

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

Writes into the output folder (default runs/TASK-ALGO-ray) what the stable-baselines3
engine writes, the policy being a folder: `policy/` (an RLlib RLModule with its
observation filter; `composer eval` and `composer run --policy` read it and the output
folder), `learning_curve.png`, `video.mp4`, `metrics.json` (the same keys, plus engine,
workers, envs_per_worker, env_steps_per_second, env_runner_restarts and ray) and
`checkpoint/` (see `composer.cli.ray_files`). A folder holding a checkpoint is resumed,
on as many workers as given now; Ctrl-C saves a checkpoint and exits with status 130.

An env runner that dies (killed, out of memory, its machine gone) is restarted by Ray and
rejoins with the current weights; meanwhile the others sample the whole batch, so no
iteration is lost or short. The command prints each loss and return as it happens.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import logging
import math
import os
import platform
import shutil
import socket
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
from tqdm import tqdm

from composer.cli import catalog, output, plot, recipes, rollout, train, training, video
from composer.cli.errors import CliError, PolicyError
from composer.cli.ray_algorithm import (
    EPISODES,
    Layout,
    build_algorithm,
    describe_runners,
    ray_recipe,
)
from composer.cli.ray_files import (
    ENGINE,
    Checkpoint,
    RayModel,
    quiet_ray,
    require_ray,
    save_policy,
)
from composer.registration import TaskInfo

INTERRUPTED = 130
# The stable-baselines3 options that have no meaning here, and ours that have none there.
SB3_ONLY = ("n_envs", "vec")
RAY_ONLY = ("workers", "envs_per_worker", "address")
# Seconds to wait for a cluster's address to accept a connection.
CONNECT_SECONDS = 5.0
# Object store of a local instance: RLlib only passes episodes and weights through it.
LOCAL_OBJECT_STORE_BYTES = 256 * 1024**2


def run(args: argparse.Namespace) -> int:
    """Train on Ray, then write the policy, curve, video and metrics; the exit status."""
    check_options(args)
    require_ray()
    info = args.info
    if not args.no_video:
        video.require()
    out, checkpoint = _output(info, args)
    resumed = checkpoint.exists()
    saved = checkpoint.state() if resumed else {}
    with ray_instance(args.address, args.workers or saved.get("workers")) as cpus:
        layout = _layout(args, saved, cpus)
        check_capacity(layout, cpus)
        progress, recipe = _start(info, checkpoint, out, args, layout)
        algo = build_algorithm(info, recipe, layout, progress.seed)
        eval_env = catalog.make(info)
        try:
            if resumed:
                algo.restore_from_path(str(checkpoint.algorithm_path().resolve()))
            restarts = saved.get("env_runner_restarts", 0)
            model = RayModel(algo, _policy_info(info, recipe), _layout_json(layout, restarts))
            model.num_timesteps = progress.timesteps
            session = training.Session(
                progress, checkpoint, eval_env,  # type: ignore[arg-type]
                eval_every=args.eval_every or max(1, recipe.timesteps // 10),
                eval_episodes=args.eval_episodes,
            )  # fmt: skip
            _announce(info, recipe, layout, out, progress.timesteps if resumed else None)
            print(f"env runners: {describe_runners(algo)}", flush=True)
            with training.StopOnInterrupt() as stop:
                if progress.timesteps < recipe.timesteps:
                    print("Ctrl-C saves a checkpoint and stops; the same command resumes",
                          flush=True)  # fmt: skip
                    _train(model, session, recipe, stop, layout)
            model.sync()
            session.save(model)
            if stop.requested:
                print(
                    f"stopped at {progress.timesteps:,} steps after "
                    f"{training.duration(session.elapsed())}; checkpoint saved in "
                    f"{checkpoint.folder}; run the same command to resume"
                )
                return INTERRUPTED
            _finish(info, model, session, out, args.eval_episodes, not args.no_video)
        finally:
            eval_env.close()
            algo.stop()
    return 0


def check_options(args: argparse.Namespace) -> None:
    """Raise CliError for options of the other engine."""
    if args.engine == ENGINE:
        given = [name for name in SB3_ONLY if getattr(args, name, None) is not None]
        if given:
            flags = " and ".join(_flag(name) for name in given)
            raise CliError(
                f"{flags} belong to the stable-baselines3 engine; with --engine ray give "
                "--workers and --envs-per-worker"
            )
    else:
        given = [name for name in RAY_ONLY if getattr(args, name, None) is not None]
        if given:
            flags = " and ".join(_flag(name) for name in given)
            raise CliError(f"{flags} need --engine ray")


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


# -- the Ray instance and the algorithm -------------------------------------------------------


@contextlib.contextmanager
def ray_instance(address: str | None, workers: int | None) -> Iterator[int]:
    """Within `with`: Ray started locally (address None) with `workers` CPUs (this
    machine's count if None: that many env runners fit, whatever the cores) or joined at
    `address`; yields the CPUs Ray has. Raises CliError when the cluster cannot be
    reached."""
    import ray  # only when training on Ray: `composer train` imports this module

    quiet_ray()
    options: dict[str, Any] = {
        "logging_level": logging.ERROR,
        "log_to_driver": False,
        "configure_logging": True,
    }
    if address is not None:
        _check_reachable(address)
        # `ray start` clusters use token authentication (Ray 2.60's default); a client in
        # token mode also joins a cluster without it.
        os.environ.setdefault("RAY_AUTH_MODE", "token")
    try:
        if address is None:
            cpus = workers or os.cpu_count() or 1
            ray.init(
                num_cpus=cpus, object_store_memory=LOCAL_OBJECT_STORE_BYTES,
                include_dashboard=False, **options,
            )  # fmt: skip
        else:
            ray.init(address=address, **options)
    except (ConnectionError, RuntimeError, ValueError) as e:
        if address is None:
            raise CliError(f"cannot start a local Ray instance: {e}") from e
        raise CliError(
            f"cannot join the Ray cluster at {address}: {e} (is this machine's token the "
            "cluster's? see docs/ray.md)"
        ) from e
    try:
        yield int(ray.cluster_resources().get("CPU", 0))
    finally:
        ray.shutdown()


def _check_reachable(address: str) -> None:
    """Raise CliError unless `address` is 'auto' or a HOST:PORT that accepts a connection
    within CONNECT_SECONDS (ray.init retries an unreachable address for minutes)."""
    if address == "auto":
        return
    host, colon, port = address.rpartition(":")
    if not colon or not host or not port.isdigit():
        raise CliError(
            f"--address {address!r}: expected HOST:PORT, the address `ray start --head` "
            "printed (e.g. 10.0.0.1:6379), or 'auto' for the cluster of this machine"
        )
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=CONNECT_SECONDS).close()
    except OSError as e:
        raise CliError(
            f"cannot reach the Ray cluster at {address}: {e.strerror or e}; start one with "
            "`ray start --head` (see docs/ray.md)"
        ) from e


def check_capacity(layout: Layout, cpus: int) -> None:
    """Raise CliError when the cluster has fewer CPUs than env runners (one each): Ray
    would wait for them forever."""
    if layout.workers > cpus:
        raise CliError(
            f"the Ray cluster at {layout.address} has {cpus} CPUs, and --workers "
            f"{layout.workers} needs one each; add machines (`ray start --address=...`) "
            "or give fewer --workers"
        )


# -- the run ---------------------------------------------------------------------------------


def _output(info: TaskInfo, args: argparse.Namespace) -> tuple[Path, Checkpoint]:
    """The output folder (checked writable) and its checkpoint, which --resume requires;
    PolicyError for a folder holding a stable-baselines3 checkpoint."""
    if args.resume and args.out and Path(args.resume) != Path(args.out):
        raise CliError(f"--resume {args.resume} and --out {args.out} differ; give one of them")
    algo = args.algo or recipes.default_algo(info.name)
    out = output.directory(args.resume or args.out or Path("runs") / f"{info.name}-{algo}-ray")
    checkpoint = Checkpoint(out / "checkpoint")
    if checkpoint.state_path.is_file() and not checkpoint.exists():
        raise PolicyError(
            f"the checkpoint in {out} was not written by --engine ray; choose another --out folder"
        )
    if args.resume and not checkpoint.exists():
        raise PolicyError(f"no checkpoint to resume in {out} (expected {checkpoint.state_path})")
    return out, checkpoint


def _layout(args: argparse.Namespace, saved: dict[str, Any], cpus: int) -> Layout:
    """The workers and environments of this session: as given, else those of the
    checkpoint's state `saved`, else as many workers as Ray has CPUs and the recipe's
    environments among them."""
    workers = args.workers or saved.get("workers") or max(1, cpus)
    algo = args.algo or saved.get("algo") or recipes.default_algo(args.info.name)
    default_envs = max(1, ray_recipe(args.info.name, algo).n_envs // workers)
    envs = args.envs_per_worker or saved.get("envs_per_worker") or default_envs
    return Layout(int(workers), int(envs), args.address)


def _start(
    info: TaskInfo, checkpoint: Checkpoint, out: Path, args: argparse.Namespace, layout: Layout
) -> tuple[training.Progress, recipes.Recipe]:
    """The progress and recipe to train with: the checkpoint's, or fresh ones."""
    if checkpoint.exists():
        progress = training.Progress.from_json(checkpoint.state())
        if progress.task != info.name:
            raise PolicyError(
                f"the checkpoint in {out} is of task {progress.task!r}, not {info.name!r}; "
                "choose another --out folder"
            )
        if args.algo and args.algo != progress.algo:
            raise PolicyError(
                f"the checkpoint in {out} was trained with {progress.algo}, not {args.algo}; "
                "choose another --out folder"
            )
        if args.seed is not None and args.seed != progress.seed:
            print(f"note: resuming keeps the checkpoint's --seed {progress.seed}")
        saved = recipes.Recipe(**{**progress.recipe, "net": tuple(progress.recipe["net"])})
        recipe = saved.replace(timesteps=args.timesteps)
    else:
        algo = args.algo or recipes.default_algo(info.name)
        recipe = ray_recipe(info.name, algo).replace(
            timesteps=args.timesteps, n_envs=layout.n_envs, vec="batched"
        )
        progress = training.Progress(info.name, info.env_id, algo, args.seed or 0, {})
    progress.recipe = recipe.table()
    progress.completed = False
    return progress, recipe


def _policy_info(info: TaskInfo, recipe: recipes.Recipe) -> dict[str, Any]:
    return {"task": info.name, "env_id": info.env_id, "algo": recipe.algo}


def _layout_json(layout: Layout, restarts: int) -> dict[str, Any]:
    """What checkpoints and metrics.json record of the layout and the cluster; `restarts`:
    env runners restarted so far in the run."""
    import ray  # only when training on Ray: `composer train` imports this module

    return {
        "engine": ENGINE,
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


def _announce(
    info: TaskInfo, recipe: recipes.Recipe, layout: Layout, out: Path, resumed_at: int | None
) -> None:
    verb = "training" if resumed_at is None else f"resuming at {resumed_at:,} steps:"
    envs = f"{layout.envs_per_worker} environment{'s' if layout.envs_per_worker > 1 else ''}"
    runners = f"{layout.workers} env runner{'s' if layout.workers > 1 else ''}"
    print(f"{verb} {info.name} with RLlib {recipe.algo.upper()} to {recipe.timesteps:,} steps "
          f"on {runners} x {envs} -> {out}")  # fmt: skip
    print("hyperparameters: " + ", ".join(f"{k}={v}" for k, v in recipe.table().items()))


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
    bar = _progress_bar(recipe.timesteps, progress.timesteps)
    say = bar.write if bar is not None else print
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
                bar.update(steps)
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
        say(f"env runner restarted ({total} restart{'s' if total > 1 else ''} in this run); "
            f"env runners: {describe_runners(model.algo)}")  # fmt: skip
    elif now_healthy < healthy:
        left = (f"{now_healthy} of {layout.workers} left sample the whole batch" if now_healthy
                else "training waits")  # fmt: skip
        say(f"env runner lost: {left} until Ray restarts it")
    return now_healthy, now_restarts


def _progress_bar(total: int, done: int) -> Any:
    """A tqdm bar on a terminal, else None."""
    if not sys.stderr.isatty():
        return None
    return tqdm(total=total, initial=min(done, total), unit="steps", unit_scale=True)


def _finish(
    info: TaskInfo, model: RayModel, session: training.Session, out: Path, episodes: int,
    record: bool,
) -> None:  # fmt: skip
    """After training: a final evaluation beside a random policy, then the output files."""
    progress = session.progress
    final = session.evaluate(model)
    env = session.eval_env
    random = rollout.summary(
        rollout.run_episodes(env, rollout.random_policy(env, 0), episodes, training.EVAL_SEED)
    )
    progress.completed = True
    session.save(model)
    policy = out / "policy"
    _replace_folder(policy, lambda folder: _save_policy(model, folder))
    metrics = {
        **progress.to_json(),
        "final": final,
        "random_policy": random,
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version(),
                    "host": socket.gethostname()},
        **model.layout,
        "env_steps_per_second": round(progress.timesteps / max(progress.wall_time, 1e-9)),
    }  # fmt: skip
    lines = [f" {json.dumps(key)}: {json.dumps(value)}" for key, value in metrics.items()]
    (out / "metrics.json").write_text("{\n" + ",\n".join(lines) + "\n}\n")
    plot.learning_curve(metrics, out / "learning_curve.png")
    written = ["policy/", "learning_curve.png", "metrics.json"]
    if record:
        written.append(_record(info, model, out / "video.mp4").name)
    print(f"{info.name}, trained policy: {rollout.describe_summary(final)}")
    print(f"{info.name}, random policy:  {rollout.describe_summary(random)}")
    print(
        f"trained {progress.timesteps:,} steps in {training.duration(progress.wall_time)} "
        f"({metrics['env_steps_per_second']:,} steps/s); wrote {', '.join(written)} in {out}"
    )
    print(f"watch it: composer run {info.name} --policy {out} --video {info.name}.mp4")


def _save_policy(model: RayModel, folder: Path) -> None:
    save_policy(model.algo, folder, model.info)


def _replace_folder(folder: Path, write: Any) -> None:
    """Write a folder through `write(path)` beside it, then swap it in."""
    partial = folder.with_name(f".{folder.name}.partial")
    shutil.rmtree(partial, ignore_errors=True)
    write(partial)
    shutil.rmtree(folder, ignore_errors=True)
    os.replace(partial, folder)


def _record(info: TaskInfo, model: RayModel, path: Path) -> Path:
    """A video of the model's episodes, at least train.VIDEO_SECONDS long."""
    env = catalog.make(info, render_mode="rgb_array")
    try:
        seconds = info.default_kwargs.get("time_limit") or train.VIDEO_SECONDS
        episodes = math.ceil(train.VIDEO_SECONDS / seconds)
        frames: list[Any] = []
        rollout.run_episodes(env, rollout.model_policy(model), episodes, training.EVAL_SEED, frames)
        return video.write_video(frames, path, rollout.video_fps(env))
    finally:
        env.close()
