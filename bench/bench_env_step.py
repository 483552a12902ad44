"""Environment.step against a raw `mujoco.mj_step` loop on the same model, same run; and the
cost of a reset that does not change the model.

    python bench/bench_env_step.py               # gymnasium's humanoid, 5 substeps
    python bench/bench_env_step.py ant.xml 5     # any MJCF file, substeps

The scene is the model loaded with `composer.Entity.from_path` in an `arenas.Floor`, with
its default observables (joint positions and velocities; actuator activations when it has
any, sensors when it has any). The raw loop steps the same compiled MjModel on its own
MjData: write ctrl, `mj_step(model, data, substeps)`, copy the same observation rows. Both
replay the same random actions from the same reset state in alternating rounds; each figure
is the best round, so that noise from other processes hits both alike. Target: a ratio
within 1.2x, and a reset without model change under 1 ms that does not recompile.
"""

from __future__ import annotations

import os
import sys
import time
import timeit
from pathlib import Path

import gymnasium
import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import composer
from arenas import Floor

ROUNDS = 15
STEPS = 300
RESETS = 2000


def make_env(path: str, substeps: int) -> composer.Environment:
    """The model at `path` in an arena, default observables, NullTask."""
    robot = composer.Entity.from_path(path)
    arena = Floor()
    setting = robot.mjcf_model.compiler.inertiafromgeom  # compiler settings must agree
    if setting is not None:
        arena.mjcf_model.compiler.inertiafromgeom = setting
    arena.attach(robot)
    task = composer.NullTask(arena)
    timestep = task.physics_timestep
    task.set_timesteps(control_timestep=timestep * substeps, physics_timestep=timestep)
    return composer.Environment(task)


def raw_rows(env: composer.Environment) -> list[np.ndarray]:
    """The MjData rows each enabled observable reads, as index arrays."""
    rows = []
    for name, item in env.task.enabled_observables().items():
        binding = env.physics.bind(item.mjcf_element)
        field = getattr(binding, item.kind)
        if field.size == 0:
            continue
        source = getattr(env.physics.data, item.kind)
        # The rows of `source` whose values are `field`: found by marking them.
        saved = source.copy()
        source[:] = np.arange(source.size).reshape(source.shape)
        rows.append((item.kind, np.asarray(getattr(binding, item.kind)).astype(np.intp)))
        source[:] = saved
        print(f"  observable {name}: {field.size} values of data.{item.kind}")
    return rows


def main(path: str | None = None, substeps: int = 5, quick: bool = False) -> dict[str, float]:
    """Measure and print for the model at `path` (gymnasium's humanoid by default);
    returns steps/s, the ratio and the reset time. `quick`: a tiny budget."""
    default = os.path.join(os.path.dirname(gymnasium.__file__), "envs/mujoco/assets/humanoid.xml")
    path = path or default
    rounds, resets = (2, 20) if quick else (ROUNDS, RESETS)
    env = make_env(path, substeps)
    print(f"{Path(path).name}: {substeps} substeps of {env.physics.timestep()} s")
    rows = raw_rows(env)
    model = env.physics.model
    data = mujoco.MjData(model)
    rng = np.random.default_rng(0)
    space = env.action_space
    actions = rng.uniform(space.low, space.high, size=(STEPS, *space.shape))

    def env_round() -> float:
        env.reset(seed=0)
        step = env.step
        start = time.perf_counter()
        for action in actions:
            step(action)
        return time.perf_counter() - start

    def raw_round() -> float:
        mujoco.mj_resetData(model, data)
        mujoco.mj_forward(model, data)
        step = mujoco.mj_step
        start = time.perf_counter()
        for action in actions:
            data.ctrl[:] = action
            step(model, data, substeps)
            observation = {kind: getattr(data, kind)[index].copy() for kind, index in rows}
        del observation
        return time.perf_counter() - start

    best_env = best_raw = float("inf")
    for _ in range(rounds):
        best_env = min(best_env, env_round())
        best_raw = min(best_raw, raw_round())
    env_rate, raw_rate = STEPS / best_env, STEPS / best_raw
    print(f"env step: {env_rate:10.0f} steps/s  ({best_env / STEPS * 1e6:7.1f} us)")
    print(f"raw loop: {raw_rate:10.0f} steps/s  ({best_raw / STEPS * 1e6:7.1f} us)")
    print(f"ratio (env time / raw time): {best_env / best_raw:.3f}x  (target <= 1.2x)")

    physics_model = env.physics.model
    per_reset = min(timeit.repeat(lambda: env.reset(), number=resets, repeat=5)) / resets
    recompiled = env.physics.model is not physics_model
    print(
        f"reset without model change: {per_reset * 1e6:.1f} us (target < 1000 us); "
        f"recompiled: {recompiled}"
    )
    return {
        "env_steps_per_s": env_rate, "raw_steps_per_s": raw_rate,
        "env_vs_raw": best_env / best_raw, "reset_us": per_reset * 1e6,
        "reset_recompiled": float(recompiled),
    }  # fmt: skip


if __name__ == "__main__":
    main(*sys.argv[1:2], *map(int, sys.argv[2:3]))
