"""The sides of the Control Suite throughput comparison (`bench_suite`): num_envs
environments of one suite task, each side stepping them its way.

    side = SIDES['vector'](32, 2, 'cheetah-run')   # num_envs, nthread, the task
    side.reset(); side.run(steps=64)                # 64 control steps of the 32 environments
    envpool_id('humanoid_CMU-run')                  # 'HumanoidCMURun-v1', envpool's spelling

Every side steps the same task (dm_control's model, its physics steps per control step)
with the same random actions: uniform within the actuators' control ranges, drawn from one
seed (`actions`), from a reset, on the threads it is given (`nthread`; `default_threads`
of the vector side says what its default would pick). The floor and batch sides run MuJoCo
without the Python bindings' profiling timer (`composer.batch.timer`), as ours steps its
batch and envpool's C++ runs: physics alone.
  vector     ours: gym.make_vec('dm_control/DOMAIN-TASK-v0', n,
             vectorization_mode='vector_entry_point'), a composer VectorEnvironment on
             MuJoCo's batch, dm_control's observations (a dict) and reward
  floor      mujoco.rollout of the same model from our environments' reset states, the
             same threads, the whole round in one call: physics alone, no Python per step
  batch      mujoco.batch of the same model (persistent, the stages of the new state
             computed after each control step as dm_control's step leaves them): write
             ctrl, step; what any Python loop over MuJoCo's batch pays, no observation or
             reward
  envpool    envpool's C++ port of the same task (its DOMAINTASK-v1 id, dm_control's XML
             files, on the MuJoCo it bundles), its C++ threads
  gymnasium  gymnasium's SyncVectorEnv of our single environments
             (gym.make_vec(..., vectorization_mode='sync'))
`OPTIONAL` names the sides that need a package of the [bench] extra.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Any

import numpy as np

# Sides that need a package the base install lacks: the package, and how to install it.
OPTIONAL = {"envpool": ("envpool", "pip install -e '.[bench]'  (or: pip install envpool)")}
ACTION_ROWS = 20  # a round cycles through this many rows of actions


def split(subject: str) -> tuple[str, str]:
    """('cheetah', 'run') of 'cheetah-run' (a suite task: DOMAIN-TASK, dm_control's names)."""
    domain, _, task = subject.partition("-")
    return domain, task


def our_id(subject: str) -> str:
    """The Gymnasium id of a suite task: 'dm_control/cheetah-run-v0'."""
    return f"dm_control/{subject}-v0"


def envpool_id(subject: str) -> str:
    """envpool's id of a suite task, as its registration spells it: 'CheetahRun-v1'."""
    camel = lambda name: "".join(part[:1].upper() + part[1:] for part in name.split("_"))  # noqa: E731
    domain, task = split(subject)
    return f"{camel(domain)}{camel(task)}-v1"


def actions(low: np.ndarray, high: np.ndarray, num_envs: int) -> np.ndarray:
    """(ACTION_ROWS, num_envs, nu) float64 actions uniform in [low, high], the same on
    every side for the same bounds."""
    return np.random.default_rng(0).uniform(low, high, size=(ACTION_ROWS, num_envs, len(low)))


class _Stepper:
    """A vector env of gymnasium's API (ours, envpool's, SyncVectorEnv) stepped with
    `actions` from its action space."""

    def __init__(self, env: Any, num_envs: int, seeded_at_make: bool = False) -> None:
        self.env = env
        self.default_threads: int | None = None  # the vector side's default, where known
        space = env.single_action_space if hasattr(env, "single_action_space") else None
        space = space if space is not None else env.action_space
        self.actions = actions(space.low, space.high, num_envs)
        self.seed = None if seeded_at_make else 0

    def reset(self) -> None:
        self.env.reset(seed=self.seed)

    def run(self, steps: int) -> None:
        step, chosen = self.env.step, self.actions
        for k in range(steps):
            step(chosen[k % ACTION_ROWS])


def _vector(num_envs: int, nthread: int, subject: str) -> _Stepper:
    import gymnasium

    import tasks  # noqa: F401  registers the dm_control/... ids
    from bench.bench_vector import usable_cpus
    from composer.vector import threads

    env = gymnasium.make_vec(
        our_id(subject), num_envs=num_envs, vectorization_mode="vector_entry_point",
        nthread=nthread,
    )  # fmt: skip
    stepper = _Stepper(env, num_envs)
    first = env.environments[0]
    stepper.default_threads = threads.physics_threads(
        first.physics.model, num_envs, first.timing.substeps, usable_cpus()
    )
    return stepper


def _gymnasium(num_envs: int, nthread: int, subject: str) -> _Stepper:
    import gymnasium

    import tasks  # noqa: F401

    env = gymnasium.make_vec(our_id(subject), num_envs=num_envs, vectorization_mode="sync")
    return _Stepper(env, num_envs)


def _envpool(num_envs: int, nthread: int, subject: str) -> _Stepper:
    import envpool

    env = envpool.make(
        envpool_id(subject), env_type="gymnasium", num_envs=num_envs, batch_size=num_envs,
        num_threads=nthread, seed=0,
    )  # fmt: skip
    return _Stepper(env, num_envs, seeded_at_make=True)


class _Model:
    """Our compiled model of a task, its physics steps per control step, its control
    ranges, and the states our environments start episodes from (seeds 0 to n - 1)."""

    def __init__(self, subject: str, num_envs: int, spec: Any) -> None:
        import mujoco

        from tasks import suite

        env = suite.load(*split(subject))
        self.model, self.substeps = env.physics.model, env.timing.substeps
        self.low, self.high = self.model.actuator_ctrlrange.T
        size = mujoco.mj_stateSize(self.model, spec)
        self.states = np.empty((num_envs, size))
        for i in range(num_envs):
            env.reset(seed=i)
            mujoco.mj_getState(self.model, env.physics.data, self.states[i], spec)
        env.close()


class _Floor:
    """mujoco.rollout of the whole round in one call (see the module docstring)."""

    def __init__(self, num_envs: int, nthread: int, subject: str) -> None:
        import mujoco
        from mujoco import rollout

        found = _Model(subject, num_envs, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        self.model, self.substeps, self.initial = found.model, found.substeps, found.states
        self.pool = rollout.Rollout(nthread=nthread if nthread > 1 else 0)
        self.data = [mujoco.MjData(self.model) for _ in range(max(1, nthread))]
        self.actions = actions(found.low, found.high, num_envs)

    def reset(self) -> None:
        pass  # every round starts from `initial`

    def run(self, steps: int) -> None:
        from composer.batch import timer

        chosen = self.actions[np.arange(steps) % ACTION_ROWS]  # (steps, n, nu)
        control = np.repeat(chosen.transpose(1, 0, 2), self.substeps, axis=1)
        timer.untimed(self.pool.rollout, self.model, self.data, self.initial, control)


class _Batch:
    """mujoco.batch stepped from Python, nothing read (see the module docstring)."""

    def __init__(self, num_envs: int, nthread: int, subject: str) -> None:
        import mujoco
        from mujoco import batch

        found = _Model(subject, num_envs, mujoco.mjtState.mjSTATE_INTEGRATION)
        self.batch = batch.Batch(found.model, num_envs, nthread=nthread, persistent=True)
        self.substeps, self.initial = found.substeps, found.states
        self.actions = actions(found.low, found.high, num_envs)
        self.stage = mujoco.mjtStage.mjSTAGE_VEL

    def reset(self) -> None:
        self.batch.state[:] = self.initial
        self.batch.forward(None, self.stage)

    def run(self, steps: int) -> None:
        from composer.batch import timer

        timer.untimed(self._loop, steps)

    def _loop(self, steps: int) -> None:
        step, chosen, substeps, stage = self.batch.step, self.actions, self.substeps, self.stage
        ctrl = self.batch.bind("ctrl")
        for k in range(steps):
            ctrl[:] = chosen[k % ACTION_ROWS]
            step(None, substeps, stage)


SIDES: dict[str, Any] = {
    "vector": _vector,
    "floor": _Floor,
    "batch": _Batch,
    "envpool": _envpool,
    "gymnasium": _gymnasium,
}


def missing(side: str) -> str | None:
    """How to install what `side` needs, or None if it is installed."""
    package, how = OPTIONAL.get(side, (None, ""))
    if package is None or importlib.util.find_spec(package) is not None:
        return None
    return how


def describe(side: str) -> str:
    """What `side` runs: the packages' versions and what differs."""
    import mujoco

    ours = f"MuJoCo {mujoco.__version__} (python bindings)"
    if side == "envpool":
        import envpool

        from bench.vector_sides import bundled_mujoco

        library = Path(envpool.__file__).parent / "mujoco" / "mujoco_dmc_envpool.so"
        bundled = bundled_mujoco(library) if library.exists() else "unknown"
        return (
            f"envpool {envpool.__version__} DOMAINTASK-v1, on the MuJoCo it bundles "
            f"({bundled}); dm_control's XML files, its C++ threads"
        )
    if side == "gymnasium":
        import gymnasium

        return f"gymnasium {gymnasium.__version__} SyncVectorEnv of our environments on {ours}"
    if side == "floor":
        return f"mujoco.rollout of our compiled model on {ours}, no profiling timer"
    if side == "batch":
        return (
            f"mujoco.batch (persistent, stage VEL) of our compiled model on {ours}, no "
            "profiling timer"
        )
    return f"gym.make_vec(..., 'vector_entry_point') of our dm_control/ ids on {ours}"
