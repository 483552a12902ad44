"""Env steps per second of `composer train --engine ray` (RLlib on Ray) next to the
stable-baselines3 batched path and the raw mujoco.batch floor, and the time Ray and RLlib
add to each env step. Needs the [ray] extra.

    python bench/bench_ray.py                 # CartpoleSwingup: 1 and 2 env runners
    python bench/bench_ray.py AntRun          # another task (costlier physics)
    python -m bench ray

Each figure is the best of a few rounds and uses the CLI's own objects: the SB3 engine's
recipe, VecEnv and model (its environments batched on two threads), the Ray engine's
recipe and Algorithm with its default M environments per env runner (16 for
CartpoleSwingup, whose SB3 recipe has 16 in all):
  raw_batch_1_thread   mujoco.batch of M sims on one thread: write ctrl, step the control
                       step's substeps, copy qpos and qvel (an env runner's floor)
  raw_batch_2_threads  the SB3 recipe's environments on two threads (this machine's floor)
  vector_1_thread      composer.VectorEnvironment of M on one thread, random actions
  sb3_collect_1_thread the SB3 engine's collection loop on those M: policy forward
                       (action, value, log-prob), then the VecEnv step: what an env runner
                       does, without Ray
  sb3_collect          the same on the SB3 recipe's environments, on two threads
  sb3_train            the SB3 engine's PPO.learn (collection and updates)
  ray_sample_N         N env runners sampling M environments each, episodes returned to the
                       driver (N = 1, 2)
  ray_train_N          Algorithm.train() with N env runners: sampling, then the learner's
                       update in this process, then weights back to the runners
Ray's per-step cost is ray_sample_1 against sb3_collect_1_thread: the same environments,
network and core, with RLlib's episodes, connectors and Ray's transport around them.
"""

from __future__ import annotations

import logging
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

TASK = "CartpoleSwingup"
WORKERS = (1, 2)


def best(rounds: int, run: Callable[[], float]) -> float:
    """The best of `rounds` calls of `run` (each returns env-steps/s)."""
    return max(run() for _ in range(rounds))


def raw_batch(vector: Any, nthread: int, steps: int) -> Callable[[], float]:
    """The vector environment's sims on mujoco.batch directly (see the module docstring)."""
    from mujoco import batch as mujoco_batch

    physics = vector.environments[0].physics
    substeps = vector.environments[0].task.physics_steps_per_control_step
    batch = mujoco_batch.Batch(physics.model, vector.num_envs, nthread=nthread)
    ctrl, qpos, qvel = batch.bind("ctrl"), batch.bind("qpos"), batch.bind("qvel")
    actions = np.random.default_rng(0).uniform(-1, 1, (steps, *ctrl.shape))

    def run() -> float:
        batch.reset()
        start = time.perf_counter()
        for action in actions:
            ctrl[:] = action
            batch.step(nstep=substeps)
            observation = np.concatenate([qpos, qvel], axis=1)
        del observation
        return steps * vector.num_envs / (time.perf_counter() - start)

    return run


def vector_steps(vector: Any, steps: int) -> Callable[[], float]:
    """VectorEnvironment.step with random actions."""
    actions = np.random.default_rng(0).uniform(-1, 1, (steps, *vector.action_space.shape))

    def run() -> float:
        vector.reset(seed=0)
        start = time.perf_counter()
        for action in actions:
            vector.step(action)
        return steps * vector.num_envs / (time.perf_counter() - start)

    return run


def sb3_collect(model: Any, steps: int) -> Callable[[], float]:
    """stable-baselines3's rollout loop: policy forward, clip, VecEnv step."""
    import torch

    venv = model.get_env()
    low, high = venv.action_space.low, venv.action_space.high

    def run() -> float:
        observation = venv.reset()
        start = time.perf_counter()
        for _ in range(steps):
            with torch.no_grad():
                actions, _, _ = model.policy(torch.as_tensor(observation))
            observation, *_ = venv.step(np.clip(actions.numpy(), low, high))
        return steps * venv.num_envs / (time.perf_counter() - start)

    return run


def sb3_learn(model: Any, updates: int) -> Callable[[], float]:
    """PPO.learn for `updates` rollouts and updates."""
    steps = updates * model.n_steps * model.get_env().num_envs

    def run() -> float:
        start = time.perf_counter()
        model.learn(steps, reset_num_timesteps=True)
        return steps / (time.perf_counter() - start)

    return run


def sb3_figures(info: Any, recipe: Any, per_runner: int, quick: bool) -> dict[str, float]:
    """The SB3 engine's figures on `recipe`, and those of `per_runner` environments on one
    thread."""
    from composer import sb3
    from composer.cli import training
    from composer.vector import make_vector_environment

    steps, rounds = (5, 1) if quick else (400, 3)
    kwargs = {**info.default_kwargs, "flatten_observations": True}
    one = make_vector_environment(per_runner, info.task, nthread=1, **kwargs)
    two = make_vector_environment(recipe.n_envs, info.task, nthread=2, **kwargs)
    figures = {
        "raw_batch_1_thread": best(rounds, raw_batch(one, 1, steps)),
        "raw_batch_2_threads": best(rounds, raw_batch(two, 2, steps)),
        "vector_1_thread": best(rounds, vector_steps(one, steps)),
    }
    one.close()
    two.close()
    for name, n_envs, threads in (("sb3_collect_1_thread", per_runner, 1),
                                  ("sb3_collect", recipe.n_envs, 2)):  # fmt: skip
        # As training.vec_env builds the recipe's ('batched', normalized), on `threads`.
        batched = sb3.make_vec_env(info.task, n_envs, nthread=threads, **kwargs)
        batched.seed(0)
        venv = training.VecNormalize(training.VecMonitor(batched), gamma=recipe.gamma)
        model = training.new_model(recipe.replace(n_envs=n_envs), venv, seed=0)
        figures[name] = best(rounds, sb3_collect(model, steps))
        if threads == 2:
            figures["sb3_train"] = best(1, sb3_learn(model, 1 if quick else 3))
        venv.close()
    return figures


def ray_figures(
    info: Any, recipe: Any, workers: int, per_runner: int, quick: bool
) -> dict[str, Any]:
    """One Ray instance of `workers` CPUs, each runner stepping `per_runner` environments
    of the Ray engine's `recipe`: sampling and training rates, and the learner's share."""
    import ray

    from composer.cli import ray_algorithm, ray_files, ray_training

    ray_files.quiet_ray()
    ray.init(
        num_cpus=workers, object_store_memory=ray_training.LOCAL_OBJECT_STORE_BYTES,
        include_dashboard=False, log_to_driver=False, logging_level=logging.ERROR,
    )  # fmt: skip
    try:
        layout = ray_algorithm.Layout(workers, per_runner, None)
        recipe = recipe.replace(n_envs=layout.n_envs)
        algo = ray_algorithm.build_algorithm(info, recipe, layout, seed=0)
        steps_each = 64 if quick else recipe.n_steps * per_runner

        def sample() -> float:
            start = time.perf_counter()
            algo.env_runner_group.foreach_env_runner(
                lambda runner: len(runner.sample(num_timesteps=steps_each, explore=True)),
                local_env_runner=False,
            )
            return workers * steps_each / (time.perf_counter() - start)

        sampling = best(1 if quick else 3, sample)
        algo.train()  # the first iteration warms up the learner
        iterations = 1 if quick else 4
        steps, timers = 0, {"sampling": 0.0, "learning": 0.0, "total": 0.0}
        for _ in range(iterations):
            result = algo.train()
            steps += int(result["env_runners"]["num_env_steps_sampled"])
            timers["sampling"] += result["timers"]["env_runner_sampling_timer"]
            timers["learning"] += result["timers"]["learner_update_timer"]
            timers["total"] += result["timers"]["training_iteration"]
        algo.stop()
    finally:
        ray.shutdown()
    return {
        "sample": sampling,
        "train": steps / timers["total"],
        "learner_share": timers["learning"] / timers["total"],
        "sampling_share": timers["sampling"] / timers["total"],
    }


def main(quick: bool = False, task: str = TASK) -> dict[str, Any]:
    """Measure `task` and print; returns the figures (steps/s, ratios, microseconds per
    env step)."""
    try:
        import ray  # noqa: F401
    except ImportError:
        print("skipped: Ray is not installed (pip install -e '.[ray]')")
        return {}
    from composer.cli import catalog, ray_algorithm, recipes

    info = catalog.find(task)
    sb3_recipe = recipes.for_task(task).replace(vec="batched")
    ray_recipe = ray_algorithm.ray_recipe(task, sb3_recipe.algo)
    per_runner = max(1, ray_recipe.n_envs // max(WORKERS))  # the CLI's default M here
    figures: dict[str, Any] = sb3_figures(info, sb3_recipe, per_runner, quick)
    for workers in WORKERS:
        measured = ray_figures(info, ray_recipe, workers, per_runner, quick)
        figures[f"ray_sample_{workers}"] = measured["sample"]
        figures[f"ray_train_{workers}"] = measured["train"]
        figures[f"ray_learner_share_{workers}"] = measured["learner_share"]
    micro = {name: 1e6 / rate for name, rate in figures.items() if "share" not in name}
    figures["ray_overhead_us_per_step"] = micro["ray_sample_1"] - micro["sb3_collect_1_thread"]
    figures["ray_sample_1_vs_sb3_collect_1_thread"] = (
        figures["ray_sample_1"] / figures["sb3_collect_1_thread"]
    )
    figures["ray_sample_2_vs_1"] = figures["ray_sample_2"] / figures["ray_sample_1"]
    figures["ray_train_2_vs_sb3_train"] = figures["ray_train_2"] / figures["sb3_train"]
    figures["ray_sample_2_vs_raw_batch_2_threads"] = (
        figures["ray_sample_2"] / figures["raw_batch_2_threads"]
    )
    print(f"{task}: env steps/s (and microseconds per env step); {per_runner} environments "
          f"per env runner, {sb3_recipe.n_envs} for SB3")  # fmt: skip
    for name, rate in figures.items():
        if name in micro:
            print(f"  {name:22} {rate:10.0f} steps/s  {micro[name]:8.1f} us")
    for workers in WORKERS:
        share = figures[f"ray_learner_share_{workers}"]
        print(f"  ray, {workers} env runner(s): the learner's update is {share:.0%} of an "
              "iteration")  # fmt: skip
    print(f"  Ray + RLlib add {figures['ray_overhead_us_per_step']:.0f} us per env step "
          f"(1 runner samples at {figures['ray_sample_1_vs_sb3_collect_1_thread']:.2f}x the "
          "same loop without Ray)")  # fmt: skip
    print(
        f"  2 runners / 1 runner sampling: {figures['ray_sample_2_vs_1']:.2f}x; "
        f"ray training (2 runners) / SB3 training: {figures['ray_train_2_vs_sb3_train']:.2f}x"
    )
    return figures


if __name__ == "__main__":
    names = [a for a in sys.argv[1:] if not a.startswith("--")]
    main(quick="--quick" in sys.argv, task=names[0] if names else TASK)
