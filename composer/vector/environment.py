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
from collections.abc import Callable, Sequence
from typing import Any, cast

import gymnasium
import mujoco
import numpy as np
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space
from mujoco import batch as mujoco_batch

import mjcf
from composer import errors, hooks, stepping
from composer.batch import timer
from composer.batch.vector import Simulations, VectorPhysics
from composer.environment import RENDER_MODES, Environment
from composer.observation import ObservationPadding
from composer.task import Task
from composer.vector import info_layout, threads
from composer.vector.models import SameModels
from composer.vector.observations import BatchObservations
from composer.vector.rendering import Ids, RenderThreads
from mjcf.sim import rendering

_STATE = mujoco.mjtState.mjSTATE_INTEGRATION
# The warnings by which `mjcf.Physics.check_invalid_state` reports an invalid state: a run
# of mjtWarning, so that their counters are a view of the batch's.
_INVALID = slice(int(mujoco.mjtWarning.mjWARN_BADQPOS), int(mujoco.mjtWarning.mjWARN_BADCTRL) + 1)
assert _INVALID.stop - _INVALID.start == 4, "BADQPOS, BADQVEL, BADQACC, BADCTRL"
_STALE, _SYNCED, _DERIVED = 0, 1, 2
_OUTCOME = frozenset({"get_reward", "should_terminate_episode", "get_discount", "get_info"})


class VectorEnvironment(gymnasium.vector.VectorEnv):
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
        # What each environment's own MjData holds of its simulation: _STALE (nothing
        # since its last physics step), _SYNCED (all of it), or _DERIVED (its derived
        # fields, but a batched write changed the state since).
        self._held = np.full(num_envs, _STALE, dtype=np.int8)
        self._any_synced = False  # whether some environment may be _SYNCED
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

    # -- gymnasium API -------------------------------------------------------------------

    def reset(
        self,
        *,
        seed: int | Sequence[int | None] | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[dict[str, np.ndarray] | np.ndarray, dict[str, Any]]:
        """Reset every environment, or those of `options['reset_mask']` (a (num_envs,)
        bool array). `seed`: an int seeds environment i with seed + i, a list one seed
        each. Returns (observations, info). Raises EpisodeError for a bad mask or seeds."""
        options = dict(options or {})
        mask = options.pop("reset_mask", None)
        seeds = _seeds(seed, self.num_envs)
        if seed is not None and _is_seed(seed):
            super().reset(seed=seeds[0])
        if mask is None:
            ids = np.arange(self.num_envs)
        else:
            mask = np.asarray(mask)
            if mask.dtype != np.bool_ or mask.shape != (self.num_envs,) or not mask.any():
                raise errors.EpisodeError(
                    f"options['reset_mask'] must be a ({self.num_envs},) bool array with a "
                    f"True, got {mask!r}"
                )
            ids = np.flatnonzero(mask)
        self._reset_envs(ids, [seeds[i] for i in ids], options or None)
        self._started = True
        return self._observations.observation(), {}

    def _reset_envs(
        self, ids: np.ndarray, seeds: Sequence[int | None], options: dict[str, Any] | None
    ) -> None:
        for i, seed in zip(ids, seeds, strict=True):
            env = self._envs[i]
            model = env.physics.model
            with rendering.context_group(self._render_threads.group(i)):
                env.reset(seed=seed, options=options)
            if env.physics.model is not model:  # recompiled: its hooks may have changed
                self._hooks[i] = hooks.Hooks(env.task)
                if i == 0:
                    self._resolve_hooks()
            self._save(i)
            self._observations.load(i, env.updater)
            self._held[i] = _SYNCED
        counts = self._step_counts()
        counts[ids] = 0
        self._most = int(counts.max())
        self._over[ids] = False
        self._ended = bool(self._over.any())
        self._any_synced = True
        self._set_models(ids)

    def _step_counts(self) -> np.ndarray:
        """Control steps since each environment's reset, (num_envs,) int64, up to date."""
        if self._lag:
            self._steps += self._lag
            self._lag = 0
        return self._steps

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

    def _repeat(
        self,
        ids: np.ndarray,
        actions: np.ndarray,
        rewards: np.ndarray,
        terminated: np.ndarray,
        truncated: np.ndarray,
        info: dict[str, Any],
    ) -> dict[str, Any]:
        """The control steps after the first of an `action_repeat` step, for environments
        `ids` whose episodes go on, as each one's Environment runs them: rewards summed,
        discounts multiplied, each environment's info that of its last control step."""
        n = self.num_envs
        discounts = np.ones(n)
        _multiply_discounts(discounts, info, ids)
        for _ in range(1, self._action_repeat):
            going = ids[~(terminated[ids] | truncated[ids])]
            if not going.size:
                break
            more_rewards = np.zeros(n)
            more: dict[str, Any] = {}
            self._step_envs(going, actions[going], more_rewards, terminated, truncated, more)
            rewards[going] += more_rewards[going]
            _multiply_discounts(discounts, more, going)
            info_layout.replace_rows(info, more, going)
        if "discount" in info:
            has = info["_discount"]
            info["discount"][has] = discounts[has]
        return info

    def _final(self, ended: np.ndarray, info: dict[str, Any]) -> dict[str, Any]:
        """SAME_STEP: move ended environments' observations and info to final_obs and
        final_info, then reset them."""
        mask = np.zeros(self.num_envs, dtype=bool)
        mask[ended] = True
        final_obs = np.full(self.num_envs, None, dtype=object)
        for i, row in zip(ended, self._final_observations(ended), strict=True):
            final_obs[i] = row
        kept, moved = info_layout.split(info, mask)
        self._reset_envs(ended, [None] * len(ended), None)
        return {**kept, "final_obs": final_obs, "_final_obs": mask, "final_info": moved,
                "_final_info": mask.copy()}  # fmt: skip

    def _final_observations(self, ended: np.ndarray) -> list[Any]:
        """The observations environments `ended` end their episodes with, before their
        reset, each as its own Environment returns it."""
        return [self._observations.row(i) for i in ended]

    # -- one control step (composer.stepping: its order and rules) ------------------------

    def _step_envs(
        self,
        ids: np.ndarray,
        actions: np.ndarray,
        rewards: np.ndarray,
        terminated: np.ndarray,
        truncated: np.ndarray,
        info: dict[str, Any],
    ) -> bool:
        """One control step of environments `ids` (`self._every`: all) with their rows of
        `actions`; fills their rows of the results. Returns whether an episode may have
        ended (False: every row of `terminated` and `truncated` is False)."""
        actions = self._actions.clipped(actions, ids)
        every = ids is self._every
        physics = self._simulations.physics(None if every else ids)
        self._before_step(physics, ids, actions)
        phases, first = self._phases(ids)
        failures, last_due = self._advance(ids, actions, phases, first)
        self._after_step(physics, ids)
        if last_due:
            self._observations.sample(ids, phases, self._substeps, first)
        if every:
            self._lag += 1
            self._most += 1
        else:
            counts = self._step_counts()
            counts[ids] += 1
            self._most = int(counts.max())
        if self._observations.counts_steps:
            steps = self._step_counts()
            self._observations.finish(ids, (steps if every else steps[ids]) * self._substeps)
        errors_found = self._invalid(ids, failures)
        for i, message in errors_found.items():
            entries = stepping.diverged(message, stacklevel=3, environment=i)
            info_layout.add(info, entries, i, self.num_envs)
            truncated[i] = True
        ok = ids
        if errors_found:
            ok = ids[~np.isin(ids, list(errors_found))]
            physics = self._simulations.physics(ok)
        ending = bool(errors_found)
        if ok.size:
            ending |= self._outcome(physics, rewards, terminated, info)
            if self._most >= self._step_limit:  # some episode is at its step limit
                steps = self._step_counts()
                if ok is self._every:
                    np.greater_equal(steps, self._step_limit, out=truncated)
                else:
                    truncated[ok] = steps[ok] >= self._step_limit
                ending = True
        return ending

    def _before_step(self, physics: VectorPhysics, ids: np.ndarray, actions: np.ndarray) -> None:
        methods = self._methods
        if methods.apply(physics, actions):
            self._wrote(ids)
        if self._applies_each:
            for k, i in enumerate(ids):
                env, own = self._envs[i], self._materialize(i)
                methods.apply_each(env.task, self._hooks[i], own, actions[k], env.random_state)
                self._save(i)

    def _phases(self, ids: np.ndarray) -> tuple[int | np.ndarray, int | np.ndarray]:
        """The phases of the observation schedule of environments `ids` in this control
        step (one for all, or one each), and the physics steps each ran before it (0 when
        the schedule does not count them: `BatchObservations.counts_steps`)."""
        observations = self._observations
        if not observations.counts_steps:
            return 0, 0
        steps = self._step_counts()
        if ids is not self._every:
            steps = steps[ids]
        period = observations.period
        return (steps % period if period > 1 else 0), steps * self._substeps

    def _advance(
        self,
        ids: np.ndarray,
        actions: np.ndarray,
        phases: int | np.ndarray,
        first: int | np.ndarray,
    ) -> tuple[dict[int, str], bool]:
        """Run the control step's physics steps, sampling observables when due but after
        the last step (environments `ids` in schedule `phases`, after physics steps
        `first`). Returns the MuJoCo error message of each simulation that raised one, and
        whether observables are due after the last step."""
        failures: dict[int, str] = {}
        sample = self._observations.sample
        around = None
        if self._substeps_hooked:

            def around(before: bool) -> None:
                self._substep_hooks(ids, actions, before)

        return failures, stepping.physics_steps(
            self._substeps,
            self._observations.offsets(phases),
            lambda nstep: self._run(ids, nstep, failures),
            lambda offset: sample(ids, phases, offset, first),
            around,
        )

    def _substep_hooks(self, ids: np.ndarray, actions: np.ndarray, before: bool) -> None:
        for k, i in enumerate(ids):
            env = self._envs[i]
            physics = self._materialize(i)
            stepping.substep_hooks(self._hooks[i], physics, actions[k], env.random_state, before)
            self._save(i)

    def _run(self, ids: np.ndarray, nstep: int, failures: dict[int, str]) -> None:
        """Step simulations `ids` (but those that failed) by nstep physics steps."""
        if failures:
            ids = ids[~np.isin(ids, list(failures))]
        every = len(ids) == self.num_envs
        simulations = self._simulations
        consistent = self._envs[0].physics.legacy_step
        # The stages of the new state only once something reads them: before, the fields
        # are recomputed if read (a first read of a derived field, in this control step).
        computed = simulations.step_stage(consistent)
        try:
            timer.untimed(self._batch.step, None if every else ids, nstep, computed)
        except mujoco_batch.SimulationError as e:
            for i in e.ids:
                failures[int(i)] = f"MuJoCo raised: {self._batch.error(int(i))}"
        if every:
            if self._any_synced:  # else every environment's is _STALE already
                self._held[:] = _STALE
                self._any_synced = False
            simulations.stepped(None, consistent, computed)
        else:
            self._held[ids] = _STALE
            simulations.stepped(ids, consistent, computed)

    def _after_step(self, physics: VectorPhysics, ids: np.ndarray) -> None:
        methods = self._methods
        if methods.finish(physics):
            self._wrote(ids)
        if self._finishes_each:
            for i in ids:
                env, own = self._envs[i], self._materialize(i)
                methods.finish_each(env.task, self._hooks[i], own, env.random_state)
                self._save(i)

    def _invalid(self, ids: np.ndarray, failures: dict[int, str]) -> dict[int, str]:
        """{environment: message} of the stepped environments whose state is invalid."""
        found = dict(failures)
        if not np.count_nonzero(self._invalid_counts):
            return found  # no warning of an invalid state anywhere
        counts = self._invalid_counts[ids]
        for i in ids[counts.any(axis=1)]:
            if int(i) not in found:
                message = stepping.invalid_state(self._materialize(i))
                if message is not None:
                    found[int(i)] = message
        return found

    def _outcome(
        self,
        physics: VectorPhysics,
        rewards: np.ndarray,
        terminated: np.ndarray,
        info: dict[str, Any],
    ) -> bool:
        """Reward, termination, info entries and discount of the environments of
        `physics`; whether an episode may have terminated (False: none did)."""
        methods, n = self._methods, self.num_envs
        ids = physics._every
        every = slice(None) if physics.num_envs == n else ids
        rows = methods.outcome(physics)
        if rows.rewards is not None:
            rewards[every] = rows.rewards
        ending = rows.terminations is not None and rows.terminations is not False
        if ending:
            terminated[every] = rows.terminations
        for key, values in rows.info.items():
            info_layout.put(info, key, ids, values, n)
        if rows.discounts is not None:
            discounts = rows.discounts
            if type(every) is slice and not isinstance(discounts, np.ndarray):
                info["discount"] = self._constant_rows(discounts, np.float64)  # Task's default
                info["_discount"] = self._constant_rows(True, bool)
            else:
                info_layout.put(info, "discount", ids, np.broadcast_to(discounts, len(ids)), n)
        if self._outcome_each:
            ending = True
            for i in ids:
                task, own = self._envs[i].task, self._materialize(i)
                reward, ended, entries = methods.outcome_each(task, own)
                if reward is not None:
                    rewards[i] = reward
                if ended is not None:
                    terminated[i] = ended
                info_layout.add(info, entries, i, n)
        return ending

    def _constant_rows(self, value: Any, dtype: type) -> np.ndarray:
        """A new (num_envs,) array of `value`: a copy of one made once (a copy costs less
        than filling one)."""
        key = (value, dtype)
        rows = self._constants.get(key)
        if rows is None:
            rows = self._constants[key] = np.full(self.num_envs, value, dtype=dtype)
        return rows.copy()

    # -- per-environment access ----------------------------------------------------------

    def _materialize(self, i: int) -> mjcf.Physics:
        """Environment i's physics, holding its simulation (state and derived fields)."""
        physics = self._envs[i].physics
        held = self._held[i]
        if held == _STALE:
            self._batch.get_data(int(i), physics.data)
            if physics.legacy_step:
                # Derived fields a single environment would recompute when read: the
                # acceleration stage.
                physics.mark_as_dirty()
        elif held == _DERIVED:
            mujoco.mj_setState(physics.model, physics.data, self._state[i], _STATE)
            physics.mark_as_dirty()
        self._held[i] = _SYNCED
        self._any_synced = True
        return physics

    def _wrote(self, ids: np.ndarray) -> None:
        """A batched method may have written the state rows of environments `ids`."""
        if not self._any_synced:
            return  # none holds its whole simulation: none can hold derived fields alone
        held = self._held[ids]
        self._held[ids] = np.where(held == _SYNCED, _DERIVED, held)

    def _save(self, i: int) -> None:
        """Write environment i's physics state (and warning counters) into its row."""
        physics = self._envs[i].physics
        mujoco.mj_getState(physics.model, physics.data, self._state[i], _STATE)
        self._warning[i, :, 0] = physics.data.warning.lastinfo
        self._warning[i, :, 1] = physics.data.warning.number
        self._simulations.changed(i)

    def _read_env(self, i: int, channel: int) -> np.ndarray:
        """Observable `channel` of environment i, read from its own physics."""
        self._materialize(i)
        return self._envs[i].updater.readers[channel]()

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


def _is_seed(seed: Any) -> bool:
    """Whether `seed` is one seed: an int (numpy's too) of at least 0, as Gymnasium takes."""
    return isinstance(seed, int | np.integer) and bool(seed >= 0)


def _seeds(seed: Any, n: int) -> list[int | None]:
    """The seed of each of `n` environments that `seed` gives (see `reset`); raises
    EpisodeError, before any environment is reset, for anything else."""
    if seed is None or _is_seed(seed):
        return [None if seed is None else int(seed) + i for i in range(n)]
    if (
        isinstance(seed, list | tuple | np.ndarray)
        and len(seed) == n
        and all(s is None or _is_seed(s) for s in seed)
    ):
        return [None if s is None else int(s) for s in seed]
    shown = repr(seed) if len(repr(seed)) <= 80 else repr(seed)[:77] + "..."
    raise errors.EpisodeError(
        f"seed must be None, an int of at least 0 (environment i gets seed + i) or {n} of "
        f"them (or None), got {shown}"
    )


def _multiply_discounts(discounts: np.ndarray, info: dict[str, Any], ids: np.ndarray) -> None:
    """discounts[ids] *= the step's discount of each of `ids` (0 where it has none: a
    diverged step, as a single Environment counts it)."""
    if "discount" in info:
        discounts[ids] *= np.where(info["_discount"][ids], info["discount"][ids], 0.0)
    else:
        discounts[ids] = 0.0
