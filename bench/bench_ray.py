"""Env steps per second of `composer train --engine ray` (RLlib on Ray) next to the
stable-baselines3 batched path and the raw mujoco.batch floor, and the time Ray and RLlib
add to each env step. Needs the [ray] extra.

    python bench/bench_ray.py                 # CartpoleSwingup: 1 and 2 env runners
    python bench/bench_ray.py AntRun          # another task (costlier physics)
    python -m bench ray

Everything uses the CLI's own objects: the SB3 engine's recipe, VecEnv and model (its
environments batched on two threads), and the Ray engine's recipe and Algorithm with its
default M environments per env runner on this machine (16 for CartpoleSwingup):
  raw_batch_1_thread   mujoco.batch of M sims on one thread: write ctrl, step the control
                       step's substeps, copy qpos and qvel (an env runner's floor)
  raw_batch_2_threads  the SB3 recipe's environments on two threads (this machine's floor)
  vector_1_thread      composer.VectorEnvironment of M on one thread, random actions
  sb3_collect_1_thread the SB3 engine's collection loop on those M: policy forward
                       (action, value, log-prob), then the VecEnv step: what an env runner
                       does, without Ray
  sb3_collect          the same on the SB3 recipe's environments, on two threads
  sb3_train            the SB3 engine's PPO.learn: one rollout and its update
  ray_sample_N         N env runners sampling M environments each, the episodes returned
                       to this process (N = 1, 2)
  ray_train_N          one Algorithm.train() with N env runners: sampling, the learner's
                       update in this process, the weights back to the runners
Rounds alternate between all of them (one Ray instance holds both algorithms) and each
figure is its best round, so a busy machine disturbs the comparison less. Besides
wall-clock rates, the CPU time per env step of the process(es) doing the stepping is
measured (process time: what a busy machine does not inflate); Ray's per-step cost is
ray_sample_1 against sb3_collect_1_thread in CPU time: the same environments, network and
core, with RLlib's episodes, connectors and Ray's transport around them.
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
# A round's result: env steps, wall seconds, CPU seconds (None when not measured).
Round = tuple[int, float, float | None]


def timed(steps: int, work: Callable[[], Any]) -> Round:
    """Run `work` (which steps `steps` env steps in this process) and time it."""
    wall, cpu = time.perf_counter(), time.process_time()
    work()
    return steps, time.perf_counter() - wall, time.process_time() - cpu


def raw_batch(vector: Any, nthread: int, steps: int) -> Callable[[], Round]:
    """The vector environment's sims on mujoco.batch directly (see the module docstring)."""
    from mujoco import batch as mujoco_batch

    physics = vector.environments[0].physics
    substeps = vector.environments[0].task.physics_steps_per_control_step
    batch = mujoco_batch.Batch(physics.model, vector.num_envs, nthread=nthread)
    ctrl, qpos, qvel = batch.bind("ctrl"), batch.bind("qpos"), batch.bind("qvel")
    actions = np.random.default_rng(0).uniform(-1, 1, (steps, *ctrl.shape))

    def work() -> None:
        for action in actions:
            ctrl[:] = action
            batch.step(nstep=substeps)
            np.concatenate([qpos, qvel], axis=1)

    def run() -> Round:
        batch.reset()
        return timed(steps * vector.num_envs, work)

    return run


def vector_steps(vector: Any, steps: int) -> Callable[[], Round]:
    """VectorEnvironment.step with random actions."""
    actions = np.random.default_rng(0).uniform(-1, 1, (steps, *vector.action_space.shape))

    def work() -> None:
        for action in actions:
            vector.step(action)

    def run() -> Round:
        vector.reset(seed=0)
        return timed(steps * vector.num_envs, work)

    return run


def sb3_collect(model: Any, steps: int) -> Callable[[], Round]:
    """stable-baselines3's rollout loop: policy forward, clip, VecEnv step."""
    import torch

    venv = model.get_env()
    low, high = venv.action_space.low, venv.action_space.high

    def work() -> None:
        observation = venv.reset()
        for _ in range(steps):
            with torch.no_grad():
                actions, _, _ = model.policy(torch.as_tensor(observation))
            observation, *_ = venv.step(np.clip(actions.numpy(), low, high))

    return lambda: timed(steps * venv.num_envs, work)


def sb3_learn(model: Any) -> Callable[[], Round]:
    """PPO.learn of one rollout and its update."""
    steps = model.n_steps * model.get_env().num_envs
    return lambda: timed(steps, lambda: model.learn(steps, reset_num_timesteps=True))


def sb3_sides(info: Any, recipe: Any, per_runner: int, quick: bool) -> dict[str, Any]:
    """The floors' and the SB3 engine's measurements on `recipe`, and `per_runner`
    environments on one thread."""
    from composer import sb3
    from composer.cli.engines.sb3 import training
    from composer.vector import make_vector_environment

    steps = 5 if quick else 300
    kwargs = {**info.default_kwargs, "flatten_observations": True}
    one = make_vector_environment(per_runner, info.task, nthread=1, **kwargs)
    two = make_vector_environment(recipe.n_envs, info.task, nthread=2, **kwargs)
    sides = {
        "raw_batch_1_thread": raw_batch(one, 1, steps),
        "raw_batch_2_threads": raw_batch(two, 2, steps),
        "vector_1_thread": vector_steps(one, steps),
    }
    for name, n_envs, threads in (("sb3_collect_1_thread", per_runner, 1),
                                  ("sb3_collect", recipe.n_envs, 2)):  # fmt: skip
        # As training.vec_env builds the recipe's ('batched', normalized), on `threads`.
        batched = sb3.make_vec_env(info.task, n_envs, nthread=threads, **kwargs)
        batched.seed(0)
        venv = training.VecNormalize(training.VecMonitor(batched), gamma=recipe.gamma)
        model = training.new_model(recipe.replace(n_envs=n_envs), venv, seed=0)
        sides[name] = sb3_collect(model, steps)
        if threads == 2:
            sides["sb3_train"] = sb3_learn(model)
    return sides


def ray_sides(algo: Any, workers: int, per_runner: int, quick: bool) -> dict[str, Any]:
    """Sampling and one training iteration of `algo` (`workers` runners of `per_runner`)."""
    steps_each = 64 if quick else 2048

    def sample_on_runner(runner: Any) -> float:
        cpu = time.process_time()
        runner.sample(num_timesteps=steps_each, explore=True)
        return time.process_time() - cpu

    def sample() -> Round:
        start = time.perf_counter()
        cpus = algo.env_runner_group.foreach_env_runner(sample_on_runner, local_env_runner=False)
        return workers * steps_each, time.perf_counter() - start, sum(cpus)

    shares: list[float] = []

    def train() -> Round:
        start = time.perf_counter()
        result = algo.train()
        wall = time.perf_counter() - start
        shares.append(result["timers"]["learner_update_timer"] / wall)
        # The batch: the result's step count would include sample()'s steps since the last.
        return algo.config.train_batch_size_per_learner, wall, None

    return {f"ray_sample_{workers}": sample, f"ray_train_{workers}": train, "shares": shares}


def main(quick: bool = False, task: str = TASK) -> dict[str, Any]:
    """Measure `task` and print; returns the figures (steps/s, CPU microseconds per env
    step, ratios)."""
    try:
        import ray
    except ImportError:
        print("skipped: Ray is not installed (pip install -e '.[ray]')")
        return {}
    from composer.cli import catalog, recipes
    from composer.cli.engines.ray import algorithm as ray_algorithm
    from composer.cli.engines.ray import files as ray_files
    from composer.cli.engines.ray import instance as ray_instance

    info = catalog.find(task)
    sb3_recipe = recipes.for_task(info).replace(vec="batched")
    ray_recipe = recipes.for_task(info, sb3_recipe.algo, ray_files.NAME)
    per_runner = max(1, ray_recipe.n_envs // max(WORKERS))  # the CLI's default M here
    sides = sb3_sides(info, sb3_recipe, per_runner, quick)
    ray_files.quiet_ray()
    ray.init(
        num_cpus=sum(WORKERS), object_store_memory=ray_instance.LOCAL_OBJECT_STORE_BYTES,
        include_dashboard=False, log_to_driver=False, logging_level=logging.ERROR,
    )  # fmt: skip
    shares: dict[int, list[float]] = {}
    try:
        algos = []
        for workers in WORKERS:
            layout = ray_algorithm.Layout(workers, per_runner, None)
            recipe = ray_recipe.replace(n_envs=layout.n_envs)
            algos.append(ray_algorithm.build_algorithm(info, recipe, layout, seed=0))
            algos[-1].train()  # warm up: the first iteration builds the learner's graph
            measured = ray_sides(algos[-1], workers, per_runner, quick)
            shares[workers] = measured.pop("shares")
            sides.update(measured)
        best: dict[str, Round] = {}
        for _ in range(1 if quick else 5):
            for name, run in sides.items():
                steps, wall, cpu = run()
                if name not in best or steps / wall > best[name][0] / best[name][1]:
                    best[name] = (steps, wall, cpu)
        for algo in algos:
            algo.stop()
    finally:
        ray.shutdown()
    return report(task, best, shares, per_runner, sb3_recipe.n_envs)


def report(
    task: str, best: dict[str, Round], shares: dict[int, list[float]], per_runner: int,
    sb3_envs: int,
) -> dict[str, Any]:  # fmt: skip
    """Print the figures and return them."""
    figures: dict[str, Any] = {}
    print(f"{task}: env steps/s and CPU microseconds per env step; {per_runner} environments "
          f"per env runner, {sb3_envs} for SB3")  # fmt: skip
    for name, (steps, wall, cpu) in best.items():
        figures[f"{name}_steps_per_s"] = steps / wall
        if cpu is not None:
            figures[f"{name}_cpu_us"] = 1e6 * cpu / steps
        cpu_text = f"{1e6 * cpu / steps:8.1f} us" if cpu is not None else ""
        print(f"  {name:22} {steps / wall:10.0f} steps/s  {cpu_text}")
    for workers, values in shares.items():
        figures[f"ray_learner_share_{workers}"] = share = float(np.median(values))
        print(f"  ray, {workers} env runner(s): the learner's update takes {share:.0%} of an "
              "iteration (median)")  # fmt: skip
    rate = {k.removesuffix("_steps_per_s"): v for k, v in figures.items() if "steps_per_s" in k}
    figures["ray_overhead_cpu_us_per_step"] = (
        figures["ray_sample_1_cpu_us"] - figures["sb3_collect_1_thread_cpu_us"]
    )
    figures["ray_sample_1_vs_sb3_collect_1_thread"] = (
        rate["ray_sample_1"] / rate["sb3_collect_1_thread"]
    )
    figures["ray_sample_2_vs_1"] = rate["ray_sample_2"] / rate["ray_sample_1"]
    figures["ray_train_2_vs_sb3_train"] = rate["ray_train_2"] / rate["sb3_train"]
    figures["ray_sample_2_vs_raw_batch_2_threads"] = (
        rate["ray_sample_2"] / rate["raw_batch_2_threads"]
    )
    print(f"  Ray + RLlib add {figures['ray_overhead_cpu_us_per_step']:.0f} us of CPU per env "
          f"step to the same loop without Ray (which takes "
          f"{figures['sb3_collect_1_thread_cpu_us']:.0f})")  # fmt: skip
    print(
        f"  2 runners / 1 runner sampling: {figures['ray_sample_2_vs_1']:.2f}x; "
        f"ray training (2 runners) / SB3 training: {figures['ray_train_2_vs_sb3_train']:.2f}x"
    )
    return figures


if __name__ == "__main__":
    names = [a for a in sys.argv[1:] if not a.startswith("--")]
    main(quick="--quick" in sys.argv, task=names[0] if names else TASK)
