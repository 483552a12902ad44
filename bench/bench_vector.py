"""composer.VectorEnvironment against MuJoCo's own batch stepping and against Gymnasium's
SyncVectorEnv over our single environments: 64 Ant sims, same process, same run.

    python bench/bench_vector.py              # 64 envs, nthread = the CPUs we may use
    python bench/bench_vector.py 16           # another number of environments

The task is gymnasium's ant.xml (the model of Ant-v5, 5 physics steps per control step)
with Ant-v5's reward, termination and start noise, written once in batched form
(`get_reward_batch` ...; a single environment runs them with a batch of one), and its
default observables (joint positions and velocities).
  vector  VectorEnvironment.step with random actions
  raw     mujoco.batch.Batch of the same compiled model, same threads: write ctrl,
          step(nstep=5), copy the same observation rows, compute the same reward and
          termination with numpy (and on one thread: what the threads give here)
  sync    gymnasium.vector.SyncVectorEnv of composer.Environments of the same task
and the shipped composer/AntRun-v0 through `gym.make_vec(..., 'vector_entry_point')`
(fully batched: its twins and observables run over all environments at once) against
its SyncVectorEnv. Rounds alternate and each figure is the best round. Targets: vector
>= 0.8x raw throughput, >= 2.5x sync.
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable
from pathlib import Path

import gymnasium
import numpy as np
from mujoco import batch as mujoco_batch

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run from a checkout

import composer
import mjcf

ANT = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "ant.xml"
SUBSTEPS = 5
HEALTHY_Z = (0.2, 1.0)


class AntV5(composer.Task):
    """Ant-v5's task on its own model: forward velocity + 1 (healthy) - 0.5 |u|^2."""

    def __init__(self) -> None:
        self.ant = composer.Entity.from_path(ANT)
        timestep = self.physics_timestep
        self.set_timesteps(control_timestep=SUBSTEPS * timestep, physics_timestep=timestep)
        self.root = self.ant.mjcf_model.find("joint", "root")
        self.joints = self.ant.mjcf_model.find_all("joint")

    @property
    def root_entity(self) -> composer.Entity:
        return self.ant

    def initialize_episode(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        joints = physics.bind(self.joints)
        joints.qpos = joints.qpos + random_state.uniform(-0.1, 0.1, joints.qpos.shape)
        joints.qvel = 0.1 * random_state.standard_normal(joints.qvel.shape)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        control = physics.field("ctrl")
        return (
            physics.bind(self.root).qvel[:, 0] + 1.0 - 0.5 * np.einsum("ij,ij->i", control, control)
        )

    def should_terminate_episode_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        z = physics.bind(self.root).qpos[:, 2]
        return (z < HEALTHY_Z[0]) | (z > HEALTHY_Z[1])


def best_rates(rounds: int, steps: int, sides: dict[str, Callable[[int], float]]) -> dict:
    """Best env-steps/s of each side over alternating rounds of `steps` steps."""
    best = dict.fromkeys(sides, 0.0)
    for _ in range(rounds):
        for name, run in sides.items():
            best[name] = max(best[name], run(steps))
    return best


def stepper(env: object, actions: np.ndarray) -> Callable[[int], float]:
    """A round of `env.step` with the actions, in env-steps per second."""

    def run(steps: int) -> float:
        env.reset(seed=0)
        step = env.step
        start = time.perf_counter()
        for k in range(steps):
            step(actions[k % len(actions)])
        return steps * len(actions[0]) / (time.perf_counter() - start)

    return run


def raw_stepper(
    vector: composer.VectorEnvironment, actions: np.ndarray, nthread: int
) -> Callable[[int], float]:
    """The same sims stepped on mujoco.batch directly, with the same per-step numpy work."""
    physics = vector.environments[0].physics
    model, num_envs = physics.model, vector.num_envs
    batch = mujoco_batch.Batch(model, num_envs, nthread=nthread)
    ctrl, qpos, qvel = batch.bind("ctrl"), batch.bind("qpos"), batch.bind("qvel")

    def run(steps: int) -> float:
        batch.reset()
        start = time.perf_counter()
        for k in range(steps):
            ctrl[:] = actions[k % len(actions)]
            batch.step(nstep=SUBSTEPS)
            observation = {"qpos": qpos.copy(), "qvel": qvel.copy()}
            control = ctrl.copy()
            reward = qvel[:, 0] + 1.0 - 0.5 * np.einsum("ij,ij->i", control, control)
            done = (qpos[:, 2] < HEALTHY_Z[0]) | (qpos[:, 2] > HEALTHY_Z[1])
        del observation, reward, done
        return steps * num_envs / (time.perf_counter() - start)

    return run


def main(num_envs: int = 64, quick: bool = False) -> dict[str, float]:
    """Measure and print; returns steps/s and ratios. `quick`: 4 envs, a few steps."""
    rounds, steps = (1, 5) if quick else (5, 60)
    num_envs = min(num_envs, 4) if quick else num_envs
    nthread = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 0
    vector = composer.VectorEnvironment(AntV5, num_envs, nthread=nthread)
    print(f"{num_envs} Ant sims, {vector.batch_physics.batch.nthread} threads; "
          f"per-environment parts: {vector.per_environment or 'none'}")  # fmt: skip
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, size=(20, *vector.action_space.shape)).astype(np.float32)
    sync = gymnasium.vector.SyncVectorEnv(
        [lambda: composer.Environment(AntV5()) for _ in range(num_envs)]
    )
    rates = best_rates(
        rounds, steps,
        {"vector": stepper(vector, actions),
         "raw_batch": raw_stepper(vector, actions, vector.batch_physics.batch.nthread),
         "raw_batch_1_thread": raw_stepper(vector, actions, 1), "sync": stepper(sync, actions)},
    )  # fmt: skip
    import tasks  # noqa: F401  registers composer/AntRun-v0

    shipped = gymnasium.make_vec(
        "composer/AntRun-v0", num_envs=num_envs, vectorization_mode="vector_entry_point"
    )
    print(f"composer/AntRun-v0 per-environment parts: {shipped.per_environment or 'none'}")
    shipped_sync = gymnasium.make_vec(
        "composer/AntRun-v0", num_envs=num_envs, vectorization_mode="sync"
    )
    fallback = best_rates(
        max(1, rounds // 2), steps,
        {"antrun_vector": stepper(shipped, actions), "antrun_sync": stepper(shipped_sync, actions)},
    )  # fmt: skip
    results = {
        **{f"{name}_steps_per_s": rate for name, rate in {**rates, **fallback}.items()},
        "vector_vs_raw_batch": rates["vector"] / rates["raw_batch"],
        "vector_vs_sync": rates["vector"] / rates["sync"],
        "raw_batch_vs_sync": rates["raw_batch"] / rates["sync"],
        "raw_batch_vs_1_thread": rates["raw_batch"] / rates["raw_batch_1_thread"],
        "antrun_vector_vs_sync": fallback["antrun_vector"] / fallback["antrun_sync"],
    }
    for name, rate in {**rates, **fallback}.items():
        print(f"  {name:14} {rate:10.0f} env-steps/s")
    print(f"  vector / raw batch: {results['vector_vs_raw_batch']:.2f}x (target >= 0.8x)")
    print(f"  vector / sync:      {results['vector_vs_sync']:.2f}x (target >= 2.5x; the raw "
          f"batch's own is {results['raw_batch_vs_sync']:.2f}x, its threads give "
          f"{results['raw_batch_vs_1_thread']:.2f}x)")  # fmt: skip
    print(f"  AntRun-v0 (shipped task) vector / sync: "
          f"{results['antrun_vector_vs_sync']:.2f}x")  # fmt: skip
    return results


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 64)
