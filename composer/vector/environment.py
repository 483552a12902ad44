"""VectorEnvironment: num_envs copies of a composer Task, stepped by MuJoCo's batch.

    venv = composer.VectorEnvironment(Swing, num_envs=64, time_limit=10.0)
    obs, info = venv.reset(seed=0)            # environment i is seeded 0 + i
    obs, reward, terminated, truncated, info = venv.step(venv.action_space.sample())
    obs['pendulum/orientation'].shape         # (64, 2): a leading environment axis

Promises (`VectorEnvironment` states each): the same trajectories and frames, bit for bit,
as num_envs single Environments seeded seed + i; Gymnasium's autoreset modes; a divergence
truncates that environment only; info is laid out as Gymnasium's (`info_layout`).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from typing import Any, cast

import gymnasium
import mujoco
import numpy as np
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space
from mujoco import batch as mujoco_batch

from composer import errors, hooks, stepping
from composer.batch.vector import Simulations, VectorPhysics
from composer.environment import RENDER_MODES, Environment
from composer.observation import ObservationPadding
from composer.task import Task
from composer.vector import threads
from composer.vector.control_step import ControlStep
from composer.vector.materialize import STALE
from composer.vector.models import SameModels
from composer.vector.observations import BatchObservations
from composer.vector.rendering import Ids, RenderThreads
from composer.vector.resets import Resets

# The warnings by which `mjcf.Physics.check_invalid_state` reports an invalid state: a run
# of mjtWarning, so that their counters are a view of the batch's.
_INVALID = slice(int(mujoco.mjtWarning.mjWARN_BADQPOS), int(mujoco.mjtWarning.mjWARN_BADCTRL) + 1)
assert _INVALID.stop - _INVALID.start == 4, "BADQPOS, BADQVEL, BADQACC, BADCTRL"
_OUTCOME = frozenset({"get_reward", "should_terminate_episode", "get_discount", "get_info"})


class VectorEnvironment(ControlStep, Resets, gymnasium.vector.VectorEnv):
    """num_envs environments of one task, stepped together. `per_environment` lists what runs
    once per environment each step, on a materialized MjData ([] when the task and its
    observables are fully batched).

        frames = venv.render()                    # a frame each, with render_mode='rgb_array'
        venv.rendered                             # camera observables, drawn on render threads

    What it promises:
    - Each environment is a `composer.Environment` of its own task (`task_factory()` is called
      num_envs times): it compiles, resets and runs its episode hooks exactly as that single
      environment would, so the same seeds and actions give the same trajectories, bit for
      bit, as num_envs single environments reset with seeds seed + i (and, after an episode
      ends, reset without a seed). Their models must share MuJoCo's data layout; each
      simulation runs on its environment's own MjModel (`mujoco.batch.Batch.set_models`).
    - Physics steps run on MuJoCo's thread pool (`mujoco.batch`, `nthread` threads: by
      default a thread for each 25 us of a step call's physics, at least one,
      `composer.vector.threads`; without the bindings' profiling timer,
      `composer.batch.timer`) and leave derived quantities (xpos, sensordata ...) consistent
      with the new state, as a single environment's `mjcf.Physics.step` does
      (`Batch.step(..., stage=mjSTAGE_VEL)`; acceleration-dependent fields are recomputed
      when read, and once read, computed by every step: `stage=mjSTAGE_ACC`). The batch
      keeps one MjData per simulation, so each step continues from the stages computed after
      the last. With `physics.legacy_step = False` on the environments they lag one physics
      step, as with bare `mj_step`. Actions, observations, rewards, terminations and
      discounts are numpy arrays over every environment, computed at once where the task
      writes its per-step methods in their batched form and its observables are batchable
      (`composer.batch`, `.observations`); the rest runs per environment on a materialized
      MjData. A control step keeps the order and rules of a single environment's
      (`composer.stepping`).
    - Autoreset as `gymnasium.vector.AutoresetMode` (`metadata['autoreset_mode']`): NEXT_STEP
      (default: the step after an episode ends resets that environment, ignores its action
      and returns reward 0), SAME_STEP (reset at once; the last observation and info are in
      info['final_obs'] and info['final_info']) or DISABLED (reset with
      `reset(options={'reset_mask': mask})`).
    - Camera observables (`MJCFCamera`) and `render()` draw each environment's frame with its
      own physics' renderers, as that single environment does (the same frames, bit for bit),
      on render threads that draw environments in parallel (`composer.vector.rendering`,
      `nthread` threads); a reset's first frame is drawn by its environment's reset, in turn.
    - Divergence truncates that environment only, with its reward 0 and the message in
      info['physics_error'], and a `DivergenceWarning`; MuJoCo errors in a simulation (e.g.
      arena overflow) are reported the same way instead of raising.
    - info holds the task's `get_info` entries and 'discount', as (num_envs,) arrays each with
      a boolean mask '_<key>' of the environments that have it (gymnasium's convention).

    Its parts are base classes in modules of their own: `Resets` (`reset()` and autoreset,
    `composer.vector.resets`), `ControlStep` (a control step, `.control_step`) and
    `Materialize` (each environment's own physics, `.materialize`).
    """

    metadata = {"render_modes": list(RENDER_MODES), "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(
        self,
        task_factory: Callable[[], Task],
        num_envs: int,
        *,
        time_limit: float | None = None,
        flatten_observations: bool = False,
        action_repeat: int = 1,
        seed: int | None = None,
        nthread: int | None = None,
        max_episode_steps: int | None = None,
        autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
        render_mode: str | None = None,
        render_height: int = 240,
        render_width: int = 320,
        render_camera: int | str | None = None,
        strip_singleton_obs_buffer_dim: bool = True,
        delayed_observation_padding: ObservationPadding = ObservationPadding.INITIAL_VALUE,
    ) -> None:
        """Build num_envs environments of `task_factory()` and one batch of their
        simulations. `time_limit` (seconds) and `max_episode_steps` truncate episodes;
        `action_repeat` is `composer.Environment`'s (each step that many control steps);
        `seed` seeds environment i's random state with seed + i until a seeded reset;
        `nthread` (physics and render threads) defaults to the CPUs this process may use
        for rendering and, for the physics, to a thread for each 25 us of a step's
        physics, at least one, at most those CPUs (`composer.vector.threads`; `nthread`);
        the render options are `composer.Environment`'s (`render_camera` None: the task's
        `render_camera`, else the free camera), and so are the observation options. Raises
        TaskError for a bad count, a factory that does not make new Tasks, or environments
        whose spaces or MuJoCo data layouts differ; what `composer.Environment` raises
        otherwise."""
        if isinstance(num_envs, bool) or not isinstance(num_envs, int) or num_envs < 1:
            raise errors.TaskError(f"num_envs must be a positive int, got {num_envs!r}")
        self.num_envs = num_envs
        self.autoreset_mode = AutoresetMode(autoreset_mode)
        self.render_mode = render_mode
        options = dict(
            flatten_observations=flatten_observations, action_repeat=action_repeat,
            strip_singleton_obs_buffer_dim=strip_singleton_obs_buffer_dim,
            delayed_observation_padding=delayed_observation_padding,
            render_height=render_height, render_width=render_width,
        )  # fmt: skip
        self._envs = self._make_envs(task_factory, time_limit, seed, options, render_camera)
        self._action_repeat = action_repeat
        self._same_models = SameModels(num_envs)
        first = self._envs[0]
        self.single_observation_space = first.observation_space
        self.single_action_space = first.action_space
        self.observation_space = batch_space(first.observation_space, num_envs)
        self.action_space = batch_space(first.action_space, num_envs)
        self.metadata = {
            **self.metadata,
            "render_fps": first.metadata["render_fps"],
            "autoreset_mode": self.autoreset_mode,
        }
        self._substeps = first.timing.substeps
        self._step_limit = first.timing.step_limit(time_limit, max_episode_steps)
        self._actions = stepping.ActionRule(first.action_space, num_envs)
        self._methods = stepping.TaskStep(first.task)
        self._outcome_each = bool(_OUTCOME.intersection(self._methods.single))
        self._constants: dict[tuple[Any, type], np.ndarray] = {}  # of `_constant_rows`
        self._hooks = [hooks.Hooks(env.task) for env in self._envs]
        self._resolve_hooks()
        if nthread is None:
            cpus = _cpus()
            self._render_threads = RenderThreads(min(cpus, num_envs))
            physics_nthread = threads.physics_threads(
                first.physics.model, num_envs, self._substeps, cpus
            )
        else:
            self._render_threads = RenderThreads(min(max(nthread, 1), num_envs))
            physics_nthread = min(nthread, num_envs)
        # One MjData per simulation (persistent), even when nothing reads a materialized
        # MjData per step: each step continues from the stages computed after the last,
        # where a batch of one MjData a thread computes them again (cheetah run on two
        # threads: 12.3 -> 8.7 us a step at N = 32).
        self._build_batch(physics_nthread)
        self.per_environment = self._per_env_parts()
        self.rendered = list(self._observations.rendered)
        self._state = self._batch.state
        self._warning = self._batch.warning
        self._invalid_counts = self._warning[:, _INVALID, 1]  # a view: (num_envs, 4)
        self._every = np.arange(num_envs)
        self._every.flags.writeable = False
        # Control steps since each environment's reset: _steps, plus _lag steps of every
        # environment not yet added (`_step_counts`); _most, the largest of them.
        self._steps = np.zeros(num_envs, dtype=np.int64)
        self._lag = self._most = 0
        self._over = np.zeros(num_envs, dtype=bool)
        self._ended = False  # whether some environment's episode ended (_over.any())
        # What each environment's own MjData holds of its simulation (`.materialize`).
        self._held = np.full(num_envs, STALE, dtype=np.int8)
        self._any_synced = False  # whether some environment may be SYNCED
        self._started = False

    def _build_batch(self, nthread: int) -> None:
        """The batch of every environment's simulation, and the pipeline reading it."""
        first = self._envs[0]
        self._batch = mujoco_batch.Batch(
            first.physics.model, self.num_envs, nthread=nthread, persistent=True
        )
        self._set_models()
        self._simulations = Simulations(self._batch, self._envs)
        self._observations = BatchObservations(
            first.updater,
            self._simulations.physics(),
            self._read_env,
            lambda i: self._envs[i].random_state,
            self._render_envs,
        )

    def _make_envs(
        self,
        task_factory: Callable[[], Task],
        time_limit: float | None,
        seed: int | None,
        options: dict[str, Any],
        camera: int | str | None,
    ) -> list[Environment]:
        envs: list[Environment] = []
        for i in range(self.num_envs):
            task = task_factory()
            if not isinstance(task, Task):
                raise errors.TaskError(
                    f"task_factory made a {type(task).__name__}, not a composer.Task"
                )
            if any(env.task is task for env in envs):
                raise errors.TaskError(
                    "task_factory returned the same task twice: it must make a new task (with "
                    "its own entities) each call"
                )
            env = Environment(
                task,
                time_limit=math.inf if time_limit is None else time_limit,
                random_state=None if seed is None else seed + i,
                render_mode=self.render_mode,
                render_camera=getattr(task, "render_camera", -1) if camera is None else camera,
                **options,
            )
            if envs:
                for label in ("observation_space", "action_space"):
                    if getattr(env, label) != getattr(envs[0], label):
                        raise errors.TaskError(
                            f"environment {i}'s {label} {getattr(env, label)} differs from "
                            f"environment 0's {getattr(envs[0], label)}: a vector environment "
                            "needs one space for all"
                        )
            envs.append(env)
        return envs

    def _set_models(self, changed: np.ndarray | None = None) -> None:
        """Run simulation i on environment i's own MjModel, or every one on environment
        0's while all are the same (`composer.vector.models`) and nothing runs per
        environment during a step (which could edit its model). `changed`: the
        environments just reset, whose models may differ now (None: compare none). Raises
        TaskError if layouts differ."""
        models = [env.physics.model for env in self._envs]
        shared = False
        if changed is not None and self.num_envs > 1 and not self.per_environment:
            self._same_models.update(models, changed)
            shared = self._same_models.identical
        try:
            self._batch.set_models(models[0] if shared else models)
        except mujoco.FatalError as e:
            raise errors.TaskError(
                f"the environments' models do not share MuJoCo's data layout ({e}); a "
                "vector environment needs models that differ only in values"
            ) from e

    def _resolve_hooks(self) -> None:
        """What runs per environment around a step, as the first environment's hooks say
        (every environment's task is made alike)."""
        task_hooks, methods = self._hooks[0], self._methods
        self._applies_each = methods.applies_each(task_hooks)
        self._finishes_each = methods.finishes_each(task_hooks)
        self._substeps_hooked = task_hooks.has_substep_hooks

    def _per_env_parts(self) -> list[str]:
        """What runs once per environment on a materialized MjData each step."""
        parts = [f"task.{name}" for name in self._methods.single]
        task_hooks = self._hooks[0]
        if task_hooks.before_step:
            parts.append("entity before_step hooks")
        if task_hooks.after_step:
            parts.append("entity after_step hooks")
        if task_hooks.has_substep_hooks:
            parts.append("substep hooks")
        parts += [f"observable {name}" for name in self._observations.per_environment]
        return parts

    # -- properties ----------------------------------------------------------------------

    @property
    def environments(self) -> tuple[Environment, ...]:
        """The per-environment `composer.Environment`s, for inspection (their `physics`
        holds the simulation only after `render()` or a per-environment method); stepping
        them directly would leave the batch behind."""
        return tuple(self._envs)

    @property
    def batch_physics(self) -> VectorPhysics:
        """The BatchPhysics batched methods get, over every environment between steps."""
        return self._simulations.physics()

    @property
    def nthread(self) -> int:
        """The threads MuJoCo's batch steps the simulations on."""
        return self._batch.nthread

    @property
    def control_timestep(self) -> float:
        """Seconds of simulation per `step()`."""
        return self._envs[0].timing.control_timestep

    # -- gymnasium API: step (reset is `Resets`'s) ---------------------------------------

    def step(
        self, actions: Any
    ) -> tuple[dict[str, np.ndarray] | np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict]:
        """Advance every environment one control step with its row of `actions` (see the
        class docstring for autoreset). Returns (observations, rewards, terminations,
        truncations, info). Raises EpisodeError before reset(), for actions of the wrong
        shape or not finite, and (autoreset DISABLED) for an environment whose episode
        ended."""
        if not self._started:
            raise errors.EpisodeError("step() called before reset(); call reset()")
        actions = self._actions.shaped(actions)
        n = self.num_envs
        ids = self._every  # the environments stepped: all but those reset now
        if self._ended:
            if self.autoreset_mode is not AutoresetMode.NEXT_STEP:
                raise errors.EpisodeError(
                    f"the episodes of environments {np.flatnonzero(self._over).tolist()} "
                    "ended; reset them with reset(options={'reset_mask': mask})"
                )
            resetting = self._over.copy()
            self._reset_envs(np.flatnonzero(resetting), [None] * int(resetting.sum()), None)
            ids = np.flatnonzero(~resetting)
        rewards = np.zeros(n)
        terminated = np.zeros(n, dtype=bool)
        truncated = np.zeros(n, dtype=bool)
        info: dict[str, Any] = {}
        ending = False  # whether an episode may have ended in this step
        if ids.size:
            ending = self._step_envs(ids, actions if ids is self._every else actions[ids],
                                     rewards, terminated, truncated, info)  # fmt: skip
            if self._action_repeat > 1:
                info = self._repeat(ids, actions, rewards, terminated, truncated, info)
                ending = True
        if ending or self._ended:
            self._over = terminated | truncated
            self._ended = bool(np.count_nonzero(self._over))
        if self._ended and self.autoreset_mode is AutoresetMode.SAME_STEP:
            info = self._final(np.flatnonzero(self._over), info)
        return self._observations.observation(), rewards, terminated, truncated, info

    # -- rendering -----------------------------------------------------------------------

    def _render_envs(self, ids: Ids, channel: int) -> np.ndarray:
        """Camera observable `channel` of environments `ids`, each drawn by its own reader
        on the render threads: (len(ids), *shape)."""
        return np.stack(self.draw(ids, lambda i: self._envs[i].updater.readers[channel]()))

    def draw(self, ids: Ids, draw: Callable[[int], Any]) -> list[Any]:
        """`draw(i)` for each environment i of `ids`, in order, on the render threads, with
        environment i's physics holding its simulation: a function drawing with
        `self.environments[i].physics` (its `render`), and nothing else of the
        environment, may run there. Raises what a draw raises."""
        for i in ids:
            self._materialize(i)
        return self._render_threads.draw(ids, draw)

    # gymnasium 1.2 types the frames with an unbound TypeVar (RenderFrame); 1.4 does not.
    def render(self) -> tuple[np.ndarray, ...] | None:  # type: ignore[override, unused-ignore]
        """Every environment's frame for `render_mode`, in order (a tuple, as Gymnasium's
        `VectorEnv.render` gives them), drawn on the render threads, or None without one
        (see `composer.Environment.render`)."""
        if self.render_mode is None:
            return None
        envs = self._envs
        return tuple(self.draw(range(self.num_envs), lambda i: cast(np.ndarray, envs[i].render())))

    def close_extras(self, **kwargs: Any) -> None:
        """Stop the render threads and free every environment's rendering resources."""
        # gymnasium 1.2's VectorEnv.__del__ closes an instance whose __init__ raised too.
        threads = getattr(self, "_render_threads", None)
        if threads is not None:
            threads.close()
        for env in getattr(self, "_envs", ()):
            env.close()


def _cpus() -> int:
    """The CPUs this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1
