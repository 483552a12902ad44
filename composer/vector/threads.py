"""physics_threads: how many threads a VectorEnvironment's batch steps on by default.

    physics_threads(model, num_envs=32, substeps=5, cpus=8)   # 1 to min(num_envs, cpus)

A thread for each `WORK_PER_THREAD` (25 us) of physics in a step call, at least one
(`physics_threads` says why); the count never changes a result, only its speed.
"""

from __future__ import annotations

import statistics
import time

import mujoco

# Seconds of physics in a step call for each thread of the batch: on 2 idle cores a second
# thread paid in wall time from about 30 us a call (cheetah run N = 8: 244k against 155k
# steps/s; cartpole swingup N = 8, about 26 us: 130k against 157k; N = 128: 457k against
# 240k), though under load its spin costs CPU time (docs/suite.md, Speed).
WORK_PER_THREAD = 25e-6
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
    call on, with `cpus` CPUs at hand: one for each `WORK_PER_THREAD` seconds of a call's
    physics (num_envs x substeps x `step_seconds(model)`), at least 1 and at most
    min(num_envs, cpus).

    A thread of MuJoCo's batch that has finished its share of a call waits for the next
    one spinning (about 0.1 ms of CPU a call), and on a loaded machine a call waits for
    its slowest thread to get a core; on idle cores k threads nearly divide the wall time
    by k once a call holds a few tens of microseconds of physics. The default serves wall
    time on idle cores; `nthread=1` saves the spin's CPU time where cores are busy.
    (Measurements: docs/performance_profile.md, section 8; docs/suite.md, Speed.)"""
    most = max(1, min(num_envs, cpus))
    if most == 1:
        return 1
    work = num_envs * substeps * step_seconds(model)
    return max(1, min(most, int(work / WORK_PER_THREAD)))
