"""Environment.step and reset of every shipped task against raw MuJoCo on its own model;
gymnasium's own v5 environments measured the same way, for reference.

    python bench/bench_task_step.py                          # every subject
    python bench/bench_task_step.py Reach AntRun Ant-v5      # some of them

Subjects: each shipped task (`tasks.IDS`), `AntV5` (ours on gymnasium's ant.xml,
`bench.ant_v5`, the same model as gymnasium's Ant-v5), and gymnasium's InvertedPendulum,
Reacher, Ant, Walker2d and Pusher v5. Each is made by `gym.make` (ours with flattened
observations, so with gymnasium's wrappers as a user gets it) and stepped with random
actions; the raw side steps the same compiled MjModel on its own MjData, from the state
each round of the environment starts in (`reset(seed=0)`: the same states, as far as the
episode runs without a reset), for the subject's physics steps per control step, writing
the actions to ctrl (no observation, reward or reset). `unwrapped` is the environment's
own step without gymnasium's wrappers. Resets: `reset()` through gym.make against raw
`mj_resetData` + `mj_forward`.

Figures are thread CPU time (other processes' time is not counted), timed over a
round's steps; the resets of episodes ending within a round are timed on their own and
taken out. Rounds alternate between the sides; each figure is the best round, with the
median and the rounds' spread in the JSON. Goal (issue 28): a shipped task's step at
most 1.1x raw, or at most 10 us over it for models whose step is tiny; its reset at
most gymnasium's on the same model (AntV5 against Ant-v5).
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium
import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import composer
import tasks
from bench import rounds
from bench.ant_v5 import AntV5

ROUNDS = 15
STEPS = 200
RESETS = 40
GOAL_RATIO, GOAL_ADDED_US = 1.1, 10.0
GYMNASIUM = ("InvertedPendulum-v5", "Reacher-v5", "Ant-v5", "Walker2d-v5", "Pusher-v5")
OURS_ON_GYMNASIUM_MODEL = "AntV5"
clock = time.thread_time_ns


def _register_ant_v5() -> None:
    if "bench/AntV5-v0" not in gymnasium.registry:
        gymnasium.register(
            "bench/AntV5-v0",
            entry_point=lambda **kw: composer.Environment(AntV5(), **kw),
        )


def shipped() -> tuple[str, ...]:
    """The names of the shipped tasks ('CartpoleSwingup' ...)."""
    return tuple(env_id.split("/")[1].rsplit("-", 1)[0] for env_id in tasks.IDS)


def make(name: str) -> tuple[Any, mujoco.MjModel, int]:
    """(the env as gym.make gives it, its compiled model, physics steps per control step)."""
    if name in GYMNASIUM:
        env = gymnasium.make(name)
        return env, env.unwrapped.model, env.unwrapped.frame_skip
    if name == OURS_ON_GYMNASIUM_MODEL:
        _register_ant_v5()
        env = gymnasium.make("bench/AntV5-v0", flatten_observations=True)
    else:  # a shipped task's name, or any registered id ('dm_control/cartpole-swingup-v0')
        env_id = name if "/" in name else f"composer/{name}-v0"
        env = gymnasium.make(env_id, flatten_observations=True)
    inner = env.unwrapped
    return env, inner.physics.model, inner.task.physics_steps_per_control_step


def _env_round(env: Any, actions: np.ndarray) -> Callable[[], float]:
    """A round of `env.step` over `actions`, ns of thread CPU time, episode resets out."""

    def run() -> float:
        env.reset(seed=0)
        step, resets = env.step, 0
        start = clock()
        for action in actions:
            _, _, terminated, truncated, _ = step(action)
            if terminated or truncated:
                began = clock()
                env.reset()
                resets += clock() - began
        return clock() - start - resets

    return run


_FULL_STATE = mujoco.mjtState.mjSTATE_FULLPHYSICS


def _start_state(env: Any, model: mujoco.MjModel) -> np.ndarray:
    """MuJoCo's full physics state `env` is in (ours or gymnasium's)."""
    inner = env.unwrapped
    data = inner.physics.data if hasattr(inner, "physics") else inner.data
    state = np.empty(mujoco.mj_stateSize(model, _FULL_STATE))
    mujoco.mj_getState(model, data, state, _FULL_STATE)
    return state


def _raw_round(
    model: mujoco.MjModel, state: np.ndarray, substeps: int, actions: np.ndarray
) -> Callable[[], float]:
    """A round of raw steps from MuJoCo's full physics state `state`."""
    data = mujoco.MjData(model)

    def run() -> float:
        mujoco.mj_resetData(model, data)
        mujoco.mj_setState(model, data, state, _FULL_STATE)
        mujoco.mj_forward(model, data)
        step = mujoco.mj_step
        start = clock()
        for action in actions:
            data.ctrl[:] = action
            step(model, data, substeps)
        return clock() - start

    return run


def _reset_rounds(env: Any, model: mujoco.MjModel, count: int) -> dict[str, Callable[[], float]]:
    data = mujoco.MjData(model)

    def ours() -> float:
        reset = env.reset
        start = clock()
        for _ in range(count):
            reset()
        return clock() - start

    def raw() -> float:
        start = clock()
        for _ in range(count):
            mujoco.mj_resetData(model, data)
            mujoco.mj_forward(model, data)
        return clock() - start

    return {"reset": ours, "raw_reset": raw}


def measure(name: str, round_count: int, steps: int, resets: int) -> dict[str, float]:
    """Per-step and per-reset microseconds of the subject `name` and of raw MuJoCo (best
    round, median, spread), and the ratios."""
    env, model, substeps = make(name)
    env.reset(seed=0)
    state = _start_state(env, model)  # raw steps from where each round of env starts
    space = env.action_space
    actions = np.random.default_rng(0).uniform(space.low, space.high, (steps, *space.shape))
    timed = rounds.alternate(
        {"env": _env_round(env, actions), "unwrapped": _env_round(env.unwrapped, actions),
         "raw": _raw_round(model, state, substeps, actions), **_reset_rounds(env, model, resets)},
        round_count,
    )  # fmt: skip
    env.close()
    found: dict[str, float] = {"substeps": substeps}
    for side, times in timed.items():
        per = resets if "reset" in side else steps
        figures = rounds.spread([t / per / 1e3 for t in times])
        found[f"{side}_us"] = figures["best"]
        found[f"{side}_us_median"] = figures["median"]
        found[f"{side}_spread"] = figures["spread"]
    found["env_vs_raw"] = found["env_us"] / found["raw_us"]
    found["env_median_vs_raw_median"] = found["env_us_median"] / found["raw_us_median"]
    found["added_us"] = found["env_us"] - found["raw_us"]
    found["unwrapped_vs_raw"] = found["unwrapped_us"] / found["raw_us"]
    found["reset_vs_raw_reset"] = found["reset_us"] / found["raw_reset_us"]
    return found


def meets_goal(found: dict[str, float]) -> bool:
    """Whether a step is within the goal: <= 1.1x raw, or <= 10 us over it."""
    return found["env_vs_raw"] <= GOAL_RATIO or found["added_us"] <= GOAL_ADDED_US


def main(*names: str, quick: bool = False) -> dict[str, dict[str, float]]:
    """Measure and print the subjects `names` (all by default, see the module docstring)."""
    names = names or (*shipped(), OURS_ON_GYMNASIUM_MODEL, *GYMNASIUM)
    round_count, steps, resets = (2, 20, 3) if quick else (ROUNDS, STEPS, RESETS)
    print(f"{'subject':20} {'raw us':>7} {'step us':>8} {'ratio':>6} {'added':>6} {'goal':>4} "
          f"{'unwrapped':>9} {'spread':>6} | {'reset us':>8} {'raw+fwd':>7}")  # fmt: skip
    results = {}
    for name in names:
        f = results[name] = measure(name, round_count, steps, resets)
        goal = ("yes" if meets_goal(f) else "no") if name in shipped() else ""
        print(f"{name:20} {f['raw_us']:7.1f} {f['env_us']:8.1f} {f['env_vs_raw']:6.2f} "
              f"{f['added_us']:6.1f} {goal:>4} {f['unwrapped_us']:9.1f} "
              f"{max(f['env_spread'], f['raw_spread']):6.0%} | {f['reset_us']:8.1f} "
              f"{f['raw_reset_us']:7.1f}")  # fmt: skip
    if OURS_ON_GYMNASIUM_MODEL in results and "Ant-v5" in results:
        ours, theirs = results[OURS_ON_GYMNASIUM_MODEL], results["Ant-v5"]
        ours["reset_vs_gymnasium_reset"] = ours["reset_us"] / theirs["reset_us"]
        ours["step_vs_gymnasium_step"] = ours["env_us"] / theirs["env_us"]
        print(f"AntV5 / gymnasium's Ant-v5 (same ant.xml): step "
              f"{ours['step_vs_gymnasium_step']:.2f}, reset "
              f"{ours['reset_vs_gymnasium_reset']:.2f} (goal <= 1)")  # fmt: skip
    return results


if __name__ == "__main__":
    main(*sys.argv[1:])
