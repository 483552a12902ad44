"""physics_threads: how many threads a VectorEnvironment's batch steps on by default.

    physics_threads(model, num_envs=32, substeps=5, cpus=2)   # 1, or min(num_envs, cpus)

One thread while a step call's physics is short, the CPUs from `SPLIT_FROM` (1 ms) of it
(`physics_threads` says why); the count never changes a result, only its speed.
"""

from __future__ import annotations

import statistics
import time

import mujoco

SPLIT_FROM = 1e-3  # seconds of physics in one step call from which the batch uses threads
_TIMED = 2e-4  # seconds of thread CPU spent timing the model's mj_step, at most ...
_STEPS = 40  # ... or this many steps


def step_seconds(model: mujoco.MjModel) -> float:
    """Thread CPU seconds of one `mj_step` of `model` from its initial state (qpos0, no
    control), on a scratch MjData: the median of a few steps timed one by one after a
    first, untimed one (robust to a step the load slowed); 0.0 where MuJoCo raises."""
    data = mujoco.MjData(model)
    clock = time.thread_time
    times: list[float] = []
    try:
        mujoco.mj_step(model, data)  # the first step allocates and warms the caches
        spent = 0.0
        while len(times) < _STEPS and spent < _TIMED:
            start = clock()
            mujoco.mj_step(model, data)
            times.append(clock() - start)
            spent += times[-1]
    except mujoco.FatalError:
        return 0.0
    return statistics.median(times)


def physics_threads(model: mujoco.MjModel, num_envs: int, substeps: int, cpus: int) -> int:
    """The threads to step `num_envs` simulations of `model` by `substeps` physics steps a
    call on, with `cpus` CPUs at hand: 1 while a call's physics (num_envs x substeps x
    `step_seconds(model)`) is under `SPLIT_FROM` seconds, else min(num_envs, cpus).

    A thread of MuJoCo's batch that has finished its share of a call waits for the next
    one spinning (about 0.1 ms of CPU a call), and on a loaded machine a call waits for
    its slowest thread to get a core. A second thread pays only where the physics of a
    call is long: there its spin is under a tenth of the work, and an idle core nearly
    halves the wall time. (Measurements: docs/performance_profile.md, section 8.)"""
    most = max(1, min(num_envs, cpus))
    if most == 1:
        return 1
    work = num_envs * substeps * step_seconds(model)
    return most if work >= SPLIT_FROM else 1
