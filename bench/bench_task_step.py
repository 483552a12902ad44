"""Environment.step of every shipped task against raw `mujoco.mj_step` of its own model.

    python bench/bench_task_step.py                  # every task in `tasks`
    python bench/bench_task_step.py Reach AntRun     # some of them

Each task is made as `gym.make` makes it (flattened observations) and stepped with random
actions; the raw side steps the same compiled MjModel on its own MjData for the task's
physics steps per control step, writing the actions to ctrl. What the environment adds is
the task's own per-step work (its batched methods and observables, run with a batch of one)
and the framework's (action checks, hooks, observation pipeline, divergence check). Each
figure is the best round of thread CPU time summed over the steps alone (resets at episode
ends are not counted), so that other processes on the machine hit both sides alike.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import gymnasium
import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import tasks

ROUNDS = 15
STEPS = 200


def measure(name: str, rounds: int, steps: int) -> dict[str, float]:
    """Best per-step microseconds of the environment and of the raw loop, and their ratio."""
    env = gymnasium.make(f"composer/{name}-v0", flatten_observations=True).unwrapped
    env.reset(seed=0)
    model = env.physics.model
    data = mujoco.MjData(model)
    substeps = env.task.physics_steps_per_control_step
    space = env.action_space
    actions = np.random.default_rng(0).uniform(space.low, space.high, (steps, *space.shape))
    clock = time.thread_time_ns

    def env_round() -> int:
        env.reset(seed=0)
        step, total = env.step, 0
        for action in actions:
            start = clock()
            _, _, terminated, truncated, _ = step(action)
            total += clock() - start
            if terminated or truncated:
                env.reset()
        return total

    def raw_round() -> int:
        mujoco.mj_resetData(model, data)
        total = 0
        for action in actions:
            start = clock()
            data.ctrl[:] = action
            mujoco.mj_step(model, data, substeps)
            total += clock() - start
        return total

    best_env = best_raw = float("inf")
    for _ in range(rounds):
        best_env = min(best_env, env_round())
        best_raw = min(best_raw, raw_round())
    env.close()
    env_us, raw_us = best_env / steps / 1e3, best_raw / steps / 1e3
    return {"env_us": env_us, "raw_us": raw_us, "env_vs_raw": env_us / raw_us}


def main(*names: str, quick: bool = False) -> dict[str, dict[str, float]]:
    """Measure and print the tasks `names` (all registered ones by default)."""
    names = names or tuple(env_id.split("/")[1].rsplit("-", 1)[0] for env_id in tasks.IDS)
    rounds, steps = (2, 20) if quick else (ROUNDS, STEPS)
    results = {}
    for name in names:
        found = results[name] = measure(name, rounds, steps)
        print(
            f"{name:16} env step {found['env_us']:7.1f} us  raw mj_step {found['raw_us']:7.1f} us"
            f"  added {found['env_us'] - found['raw_us']:6.1f} us  ratio {found['env_vs_raw']:.2f}"
        )
    return results


if __name__ == "__main__":
    main(*sys.argv[1:])
