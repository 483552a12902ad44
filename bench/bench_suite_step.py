"""One Control Suite environment's step: ours against dm_control's own environment on the
same model, and against raw MuJoCo (issue 38).

    python bench/bench_suite_step.py                               # walker-walk, cheetah-run ...
    python bench/bench_suite_step.py cartpole-swingup humanoid-run

Three sides per task, stepped with the same random actions:
- ours: `gym.make('dm_control/DOMAIN-TASK-v0')` (with gymnasium's wrappers, as a user gets
  it) and its `unwrapped` composer.Environment;
- dm_control: the suite's own task and `control.Environment` (its code, from the published
  wheel, run on our `mjcf.Physics`: dm_control itself cannot run on MuJoCo 4; the wheel is
  fetched as the tests fetch it, `tests/tasks/suite/oracle.py`);
- raw: `mujoco.mj_step` on the same compiled model for the task's physics steps per
  control step, actions written to ctrl, nothing else, as a Python loop runs it (the
  bindings' profiling timer on); raw_untimed: the same without that timer, as ours steps
  (`composer.batch.timer`) and C programs do: MuJoCo's own floor.
Every round of every side runs the same trajectory: ours from `reset(seed=0)`, dm_control's
task reseeded with 0 before its reset (the same episode, as the equality tests show), raw
from the state ours starts in (MuJoCo's full physics state), so that all three simulate the
same states: a contact-heavy or ray-heavy stretch (humanoid lying, quadruped-escape's
rangefinders on its terrain) costs every side alike. (LQR's unbounded actuators, given
random forces up to 1e10 here, diverge within a few steps on every side, so its figures
are of diverging, truncated episodes.)
Figures are thread CPU time per step (microseconds), the best of alternating rounds, with
the median; the ratios are against raw and against dm_control.
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

import tasks  # noqa: F401  (registers the ids)
from bench import rounds
from composer.batch import timer
from tests.tasks.suite import oracle

SUBJECTS = ("walker-walk", "cheetah-run", "cartpole-swingup", "humanoid-run")
ROUNDS, STEPS = 15, 300
clock = time.thread_time_ns


def _round(reset: Callable[[], Any], step: Callable[[Any], Any], actions: np.ndarray,
           ended: Callable[[Any], bool]) -> Callable[[], float]:  # fmt: skip
    """A round of `step` over `actions` (ns of thread CPU time), episode resets left out."""

    def run() -> float:
        reset()
        resets = 0
        start = clock()
        for action in actions:
            if ended(step(action)):
                began = clock()
                reset()
                resets += clock() - began
        return clock() - start - resets

    return run


_FULL_STATE = mujoco.mjtState.mjSTATE_FULLPHYSICS


def _raw_round(
    model: mujoco.MjModel, state: np.ndarray, substeps: int, actions: np.ndarray
) -> Callable[[], float]:
    """A round of raw steps from MuJoCo's full physics state `state`."""
    data = mujoco.MjData(model)

    def run() -> float:
        mujoco.mj_resetData(model, data)
        mujoco.mj_setState(model, data, state, _FULL_STATE)
        mujoco.mj_forward(model, data)
        start = clock()
        for action in actions:
            data.ctrl[:] = action
            mujoco.mj_step(model, data, substeps)
        return clock() - start

    return run


def measure(subject: str, round_count: int, steps: int) -> dict[str, float]:
    """Microseconds per step of each side (best, median) and the ratios."""
    domain, task = subject.split("-", 1)
    env = gymnasium.make(f"dm_control/{subject}-v0")
    inner = env.unwrapped
    theirs = oracle.reference(domain, task, seed=0)
    spec = theirs.action_spec()
    actions = np.random.default_rng(0).uniform(spec.minimum, spec.maximum, (steps, *spec.shape))
    gym_ended = lambda result: result[2] or result[3]  # noqa: E731
    env.reset(seed=0)
    model, data = inner.physics.model, inner.physics.data
    start = np.empty(mujoco.mj_stateSize(model, _FULL_STATE))
    mujoco.mj_getState(model, data, start, _FULL_STATE)

    def reset_theirs() -> None:
        theirs.task.random.seed(0)
        theirs.reset()

    raw = _raw_round(model, start, inner.timing.substeps, actions)
    timed = rounds.alternate(
        {
            "ours": _round(lambda: env.reset(seed=0), env.step, actions, gym_ended),
            "unwrapped": _round(lambda: inner.reset(seed=0), inner.step, actions, gym_ended),
            "dm_control": _round(reset_theirs, theirs.step, actions, lambda ts: ts.last()),
            "raw": raw,
            "raw_untimed": lambda: timer.untimed(raw),
        },
        round_count,
    )
    env.close()
    found: dict[str, float] = {"substeps": inner.timing.substeps}
    for side, times in timed.items():
        figures = rounds.spread([t / steps / 1e3 for t in times])
        found[f"{side}_us"], found[f"{side}_us_median"] = figures["best"], figures["median"]
    for side in ("ours", "unwrapped", "dm_control"):
        found[f"{side}_vs_raw"] = found[f"{side}_us"] / found["raw_us"]
    found["ours_vs_raw_untimed"] = found["ours_us"] / found["raw_untimed_us"]
    found["ours_vs_dm_control"] = found["ours_us"] / found["dm_control_us"]
    found["unwrapped_vs_dm_control"] = found["unwrapped_us"] / found["dm_control_us"]
    return found


def main(*subjects: str, quick: bool = False) -> dict[str, dict[str, float]]:
    """Measure and print `subjects` ('domain-task'; SUBJECTS that exist by default)."""
    registered = {env_id.split("/")[1].removesuffix("-v0") for env_id in gymnasium.registry
                  if env_id.startswith("dm_control/")}  # fmt: skip
    subjects = subjects or tuple(s for s in SUBJECTS if s in registered)
    round_count, steps = (2, 20) if quick else (ROUNDS, STEPS)
    print(f"{'task':22} {'raw us':>7} {'untimed':>7} {'ours':>7} {'unwrap':>7} {'dm_ctrl':>7} | "
          f"{'ours/raw':>8} {'/untimed':>8} {'unwr/raw':>8} {'dm/raw':>7} {'ours/dm':>7} "
          f"{'unwr/dm':>7}")  # fmt: skip
    results = {}
    for subject in subjects:
        f = results[subject] = measure(subject, round_count, steps)
        print(f"{subject:22} {f['raw_us']:7.1f} {f['raw_untimed_us']:7.1f} {f['ours_us']:7.1f} "
              f"{f['unwrapped_us']:7.1f} {f['dm_control_us']:7.1f} | {f['ours_vs_raw']:8.2f} "
              f"{f['ours_vs_raw_untimed']:8.2f} {f['unwrapped_vs_raw']:8.2f} "
              f"{f['dm_control_vs_raw']:7.2f} {f['ours_vs_dm_control']:7.2f} "
              f"{f['unwrapped_vs_dm_control']:7.2f}")  # fmt: skip
    return results


if __name__ == "__main__":
    main(*sys.argv[1:])
