"""The sides of the vector comparison (`bench_vector`): num_envs Ants, each stepped its way.

    side = SIDES['vector'](num_envs=32, nthread=2)
    side.reset(); side.run(steps=64)            # 64 control steps of the 32 environments
    describe('envpool')                          # what it runs: versions, model, options

Every side steps the model of gymnasium's Ant-v5 (its ant.xml, 5 physics steps per
control step) with the same random actions in [-1, 1] (`actions`), from a reset:
  vector         composer.VectorEnvironment of `bench.ant_v5.AntV5` on MuJoCo's batch
  floor          mujoco.batch.Batch of the same model, same threads: write ctrl,
                 step(nstep=5), copy the observed rows, the same reward and termination
                 in numpy (what any Python loop over MuJoCo's batch pays)
  physics        mujoco.rollout of the same model and controls, same threads, the whole
                 round in one call: physics alone, no Python per step
  sync           gymnasium's SyncVectorEnv of composer.Environments of AntV5
  envpool        envpool's Ant-v5 (C++ threads), its contact forces off (the observation
                 is then AntV5's), on the MuJoCo it bundles
  gymnasium      gymnasium's SyncVectorEnv of its own Ant-v5, contact forces out of the
                 observation (its step still runs mj_rnePostConstraint)
  antrun_vector  the shipped composer/AntRun-v0 (its own quadruped in a corridor) through
                 gym.make_vec's vector entry point ...
  antrun_sync    ... and through gymnasium's SyncVectorEnv
The floor and physics sides run MuJoCo without the Python bindings' profiling timer, as
the vector side steps its batch (`composer.batch.timer`) and envpool's C++ runs.
`OPTIONAL` names the sides that need a package of the [bench] extra.
"""

from __future__ import annotations

import importlib.util
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import gymnasium
import mujoco
import numpy as np

from bench.ant_v5 import ANT, HEALTHY_Z, SUBSTEPS, AntV5

# Sides that need a package the base install lacks: the package, and how to install it.
OPTIONAL = {"envpool": ("envpool", "pip install -e '.[bench]'  (or: pip install envpool)")}


def actions(num_envs: int, count: int = 20) -> np.ndarray:
    """(count, num_envs, 8) float64 random actions in [-1, 1], the same on every side."""
    return np.random.default_rng(0).uniform(-1.0, 1.0, size=(count, num_envs, 8))


class _Stepper:
    """A vector env stepped with `actions`: gymnasium's API (ours, envpool's, SyncVectorEnv)."""

    def __init__(self, env: Any, num_envs: int, seeded_at_make: bool = False) -> None:
        self.env = env
        self.actions = actions(num_envs)
        self.seed = None if seeded_at_make else 0

    def reset(self) -> None:
        self.env.reset(seed=self.seed)

    def run(self, steps: int) -> None:
        step, chosen = self.env.step, self.actions
        for k in range(steps):
            step(chosen[k % len(chosen)])


def _ant_model() -> mujoco.MjModel:
    import composer

    return composer.Environment(AntV5()).physics.model


class _Floor:
    """mujoco.batch with a step's numpy work (see the module docstring)."""

    def __init__(self, num_envs: int, nthread: int) -> None:
        from mujoco import batch

        self.batch = batch.Batch(_ant_model(), num_envs, nthread=nthread)
        self.actions = actions(num_envs)

    def reset(self) -> None:
        self.batch.reset()

    def run(self, steps: int) -> None:
        from composer.batch import timer

        timer.untimed(self._loop, steps)

    def _loop(self, steps: int) -> None:
        batch, chosen = self.batch, self.actions
        ctrl, qpos, qvel = batch.bind("ctrl"), batch.bind("qpos"), batch.bind("qvel")
        for k in range(steps):
            ctrl[:] = chosen[k % len(chosen)]
            batch.step(nstep=SUBSTEPS)
            observation = {"qpos": qpos.copy(), "qvel": qvel.copy()}
            control = ctrl.copy()
            reward = qvel[:, 0] + 1.0 - 0.5 * np.einsum("ij,ij->i", control, control)
            done = (qpos[:, 2] < HEALTHY_Z[0]) | (qpos[:, 2] > HEALTHY_Z[1])
            del observation, reward, done


class _Physics:
    """mujoco.rollout of the whole round in one call (see the module docstring)."""

    def __init__(self, num_envs: int, nthread: int) -> None:
        from mujoco import rollout

        self.model = model = _ant_model()
        self.pool = rollout.Rollout(nthread=nthread)
        self.data = [mujoco.MjData(model) for _ in range(max(1, nthread))]
        data = mujoco.MjData(model)
        mujoco.mj_forward(model, data)
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        state = np.empty(mujoco.mj_stateSize(model, spec))
        mujoco.mj_getState(model, data, state, spec)
        self.initial = np.tile(state, (num_envs, 1))
        self.actions = actions(num_envs)
        self.num_envs = num_envs

    def reset(self) -> None:
        pass  # every round starts from `initial`

    def run(self, steps: int) -> None:
        chosen = self.actions[np.arange(steps) % len(self.actions)]  # (steps, n, nu)
        control = np.repeat(chosen.transpose(1, 0, 2), SUBSTEPS, axis=1)
        from composer.batch import timer

        timer.untimed(self.pool.rollout, self.model, self.data, self.initial, control)


def _vector(num_envs: int, nthread: int) -> _Stepper:
    import composer

    return _Stepper(composer.VectorEnvironment(AntV5, num_envs, nthread=nthread), num_envs)


def _sync(num_envs: int, nthread: int) -> _Stepper:
    import composer

    factories = [lambda: composer.Environment(AntV5()) for _ in range(num_envs)]
    return _Stepper(gymnasium.vector.SyncVectorEnv(factories), num_envs)


def _envpool(num_envs: int, nthread: int) -> _Stepper:
    import envpool

    env = envpool.make(
        "Ant-v5", env_type="gymnasium", num_envs=num_envs, batch_size=num_envs,
        num_threads=nthread, seed=0, use_contact_force=False, post_constraint=False,
    )  # fmt: skip
    return _Stepper(env, num_envs, seeded_at_make=True)


def _gymnasium(num_envs: int, nthread: int) -> _Stepper:
    env = gymnasium.make_vec(
        "Ant-v5", num_envs=num_envs, vectorization_mode="sync",
        include_cfrc_ext_in_observation=False,
    )  # fmt: skip
    return _Stepper(env, num_envs)


def _antrun(mode: str) -> Callable[[int, int], _Stepper]:
    def make(num_envs: int, nthread: int) -> _Stepper:
        import tasks  # noqa: F401  registers composer/AntRun-v0

        env = gymnasium.make_vec("composer/AntRun-v0", num_envs=num_envs, vectorization_mode=mode)
        return _Stepper(env, num_envs)

    return make


SIDES: dict[str, Callable[[int, int], Any]] = {
    "vector": _vector,
    "floor": _Floor,
    "physics": _Physics,
    "sync": _sync,
    "envpool": _envpool,
    "gymnasium": _gymnasium,
    "antrun_vector": _antrun("vector_entry_point"),
    "antrun_sync": _antrun("sync"),
}


def missing(side: str) -> str | None:
    """How to install what `side` needs, or None if it is installed."""
    package, how = OPTIONAL.get(side, (None, ""))
    if package is None or importlib.util.find_spec(package) is not None:
        return None
    return how


def bundled_mujoco(library: Path) -> str:
    """The MuJoCo version compiled into a native library that links MuJoCo statically (as
    envpool's do): the version string stored among its symbol names, or 'unknown'."""
    found = set(re.findall(rb"\x00([1-9]\.\d{1,2}\.\d{1,2})\x00", library.read_bytes()))
    return found.pop().decode() if len(found) == 1 else "unknown"


def describe(side: str) -> str:
    """What `side` runs: the packages' versions, the model and what differs."""
    ours = f"MuJoCo {mujoco.__version__} (python bindings)"
    if side == "envpool":
        import envpool

        library = Path(envpool.__file__).parent / "mujoco" / "mujoco_gym_envpool.so"
        bundled = bundled_mujoco(library) if library.exists() else "unknown"
        return (
            f"envpool {envpool.__version__}, on the MuJoCo it bundles ({bundled}); its copy "
            "of gymnasium's ant.xml: the same file as far as that MuJoCo reads it alike"
        )
    if side == "gymnasium":
        return f"gymnasium {gymnasium.__version__} Ant-v5 on {ours}"
    if side.startswith("antrun"):
        return f"composer/AntRun-v0 (its own quadruped, not ant.xml) on {ours}"
    return f"{ANT.name} on {ours}"
