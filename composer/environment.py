"""Environment: a composer Task served as a `gymnasium.Env`.

    env = composer.Environment(task, time_limit=10.0, render_mode='rgb_array')
    obs, info = env.reset(seed=0)                  # obs: {'arm/joint_positions': array, ...}
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

Promises (`Environment` states each, with dm_control's options): the scene compiles once, and
again only when `initialize_episode_mjcf` changed it; hooks run in dm_control's order; the same
seed and actions give bit-identical episodes; a diverged simulation truncates its episode
(`info['physics_error']`); a NaN or infinite action raises EpisodeError.
"""

from __future__ import annotations

import logging
import math
import warnings
from collections.abc import Callable
from typing import Any

import gymnasium
import numpy as np

import mjcf
from composer import dm_internals, errors, hooks, stepping
from composer.batch import timer
from composer.batch.single import BatchOfOne
from composer.errors import EpisodeInitializationError
from composer.hooks import HOOK_NAMES
from composer.observation import ObservationPadding, Updater
from composer.task import Task

RENDER_MODES = ("rgb_array", "depth_array")
_LOG = logging.getLogger(__name__)

__all__ = [
    "HOOK_NAMES",
    "RENDER_MODES",
    "Environment",
    "EpisodeInitializationError",
    "ObservationPadding",
]


class Environment(gymnasium.Env):
    """A gymnasium.Env running a composer Task (the module docstring shows reset and step).

        frame = env.render()                           # (240, 320, 3) uint8
        env.physics.bind(joint).qpos                   # the live simulation
        env.close()

    What it promises:
    - The scene is compiled once, at construction; `reset()` recompiles only when the
      `initialize_episode_mjcf` hooks changed the model (its `version`), otherwise it resets
      the same MjModel/MjData in place (no recompile).
    - Hook order: reset runs `initialize_episode_mjcf`, then (only if the model changed, and
      at construction) compiles and runs `after_compile`, then resets the physics and runs
      `initialize_episode`. A step runs the task's `before_step(physics, action, ...)` (which
      applies the action), the entities' `before_step`, then per physics step `before_substep`,
      `physics.step()`, `after_substep`, then `after_step`; then observations are sampled
      (those due after the last physics step only now, so they show what `after_step`
      changed, as in dm_control), and reward and termination are read. Each hook runs on
      the task, then on every entity (`composer.hooks`). MuJoCo runs a step's calls without
      the Python bindings' profiling timer (`composer.batch.timer`): the same numbers,
      0.7 to 2 us less a physics step, `MjData.timer`'s durations not accumulated.
    - `terminated` comes from `task.should_terminate_episode`; `truncated` is set when the time
      limit is reached (after ceil(time_limit / control_timestep) control steps) or when MuJoCo
      reported an invalid state (bad qacc, NaN): then `info['physics_error']` holds the
      message, the reward is 0.0, a `DivergenceWarning` is emitted, and the next `reset()`
      starts afresh.
    - `action_repeat=k` makes each `step()` k control steps with the same action (the frame
      skip of pixel-based RL): rewards summed, discounts multiplied, the last observation;
      an episode that ends within them ends the step.
    - Randomness: every draw the framework makes or hands on (hooks, initializers, corruptors,
      called `corruptor(value, random_state=...)`) is from one `numpy.random.RandomState`
      (dm_control's API) drawing from the same bit generator as `env.np_random`, never from
      numpy's global one; `reset(seed=s)` reseeds both, so the same seed and actions give
      bit-identical episodes (a task's `random_state_for_seed(s)` may give its own instead,
      as the Control Suite's tasks give dm_control's `RandomState(s)`). `random_state` at
      construction (an int, a RandomState or a Generator) is used until a seeded reset. With
      `fixed_initial_state=True` every episode starts from the random state the environment
      had at construction or at its last seeded reset, so its initial state is the same.
    - dm_control's options: `max_reset_attempts` retries a reset whose hooks raised
      `composer.EpisodeInitializationError` (the last one propagates); `n_sub_steps` overrides
      the task's physics steps per control step; `raise_exception_on_physics_error=True`
      raises `mjcf.PhysicsError` instead of truncating; `strip_singleton_obs_buffer_dim=False`
      and `delayed_observation_padding` shape observations as `composer.observation.Updater`
      says; `legacy_step` is `env.physics.legacy_step`; `recompile_mjcf_every_episode=True`
      recompiles every episode, as dm_control does, False never after the first reset (and
      runs `initialize_episode_mjcf` only then), None (the default) only when the model
      changed; `add_extra_hook(name, callable)` runs a callable after the task's and entities'
      hook of that name (`before_step` and `before_substep` ones get the action too).
    - Actions: a NaN or infinite action raises `EpisodeError` (it would silently corrupt the
      simulation); finite actions outside the action space are clipped to its bounds (the
      actuators' ctrlrange) before the task applies them.
    - Observations are new arrays every step (safe to keep); a step's `info` holds the task's
      `get_info(physics)` entries (e.g. 'is_success') and its `discount`.
    - A task's per-step method written in batched form (`get_reward_batch` ...,
      `composer.batch`) runs here with a batch of one (`composer.BatchOfOne`), so one
      environment computes what a `VectorEnvironment` computes for each of its own, to the
      last bit; the control step's rules are `composer.stepping`'s, which both keep.
    - Observations, rewards and hooks see derived quantities (xpos, site_xpos, sensordata ...)
      consistent with the current state, as `mj_forward` would compute them, not one physics
      step behind as with a bare `mujoco.mj_step` (see `mjcf.Physics.step`; this costs nothing
      over `mj_step`). `env.physics.legacy_step = False` restores bare `mj_step`s.
    - Subclasses written against dm_control's internals run: an override of `_reset_attempt`
      (what it returns is what `reset` returns; a dm_env TimeStep gives its observation), of
      `_recompile_physics_and_update_observables` (every compile, the first at construction,
      goes through it), `_recompile_physics`, `_make_observation_updater` or `_substep` (run for
      each physics step), and calls of `env._hooks` and `env._observation_updater` as
      dm_control's own `step` makes them (`composer.dm_internals` says what is kept). One that
      cannot be kept raises `composer.OverrideError` naming the method, when the environment is
      made (or, for what `_reset_attempt` returns, at the reset).
    """

    metadata = {"render_modes": list(RENDER_MODES), "render_fps": 50}
    # A Dict of the observables, or one Box with `flatten_observations`; the task's Box.
    observation_space: gymnasium.spaces.Dict | gymnasium.spaces.Box
    action_space: gymnasium.spaces.Box

    def __init__(
        self,
        task: Task,
        time_limit: float = math.inf,
        random_state: int | np.random.RandomState | np.random.Generator | None = None,
        n_sub_steps: int | None = None,
        raise_exception_on_physics_error: bool = False,
        strip_singleton_obs_buffer_dim: bool = True,
        max_reset_attempts: int = 1,
        recompile_mjcf_every_episode: bool | None = None,
        fixed_initial_state: bool = False,
        delayed_observation_padding: ObservationPadding = ObservationPadding.INITIAL_VALUE,
        legacy_step: bool = True,
        *,
        flatten_observations: bool = False,
        action_repeat: int = 1,
        render_mode: str | None = None,
        render_height: int = 240,
        render_width: int = 320,
        render_camera: int | str = -1,
    ) -> None:
        """Compile `task`'s scene and build the spaces (the options: see the class
        docstring). Raises TaskError for a bad time limit, render mode, option or
        timesteps, ObservableError for an observable that cannot be read,
        mjcf.CompileError when MuJoCo rejects the scene, and OverrideError for a subclass
        overriding dm_control's internals in a way this environment cannot keep."""
        if render_mode is not None and render_mode not in RENDER_MODES:
            raise errors.TaskError(
                f"render_mode must be one of {RENDER_MODES} or None, got {render_mode!r}"
            )
        if not (isinstance(time_limit, int | float) and time_limit > 0):
            raise errors.TaskError(f"time_limit must be a positive number, got {time_limit!r}")
        _check_count("max_reset_attempts", max_reset_attempts)
        _check_count("action_repeat", action_repeat)
        if n_sub_steps is not None:
            _check_count("n_sub_steps", n_sub_steps)
            warnings.warn(
                "n_sub_steps is deprecated (as in dm_control): set the task's control "
                "timestep instead",
                DeprecationWarning,
                stacklevel=2,
            )
        if not isinstance(delayed_observation_padding, ObservationPadding):
            raise errors.TaskError(
                "delayed_observation_padding must be an ObservationPadding, got "
                f"{delayed_observation_padding!r}"
            )
        # The private names and meanings are dm_control's where subclasses read them
        # (`composer.dm_internals`).
        self._task = task
        self._time_limit = float(time_limit)
        self._random_state = _as_random_state(random_state) or np.random.RandomState(
            self.np_random.bit_generator
        )
        self._overridden_n_sub_steps = n_sub_steps
        self._raise_exception_on_physics_error = raise_exception_on_physics_error
        self._strip_singleton_obs_buffer_dim = strip_singleton_obs_buffer_dim
        self._delayed_observation_padding = delayed_observation_padding
        self._legacy_step = legacy_step
        self._max_reset_attempts = max_reset_attempts
        self._recompile_mjcf_every_episode = recompile_mjcf_every_episode
        self._fixed_initial_state = fixed_initial_state
        self._extra_hooks: dict[str, list[Callable[..., Any]]] = {n: [] for n in HOOK_NAMES}
        self._flatten = flatten_observations
        self._action_repeat = int(action_repeat)
        self.render_mode = render_mode
        self._render_size = (int(render_height), int(render_width))
        self._render_camera = render_camera
        self._hooks = dm_internals.EnvironmentHooks(self)
        self._updater_view = dm_internals.UpdaterView(self)
        self._compile_count = 0
        self._recompile_physics_and_update_observables()
        if self._compile_count == 0:
            raise errors.OverrideError(
                f"{type(self).__name__}._recompile_physics_and_update_observables() did not "
                "call super()._recompile_physics_and_update_observables(), which compiles the "
                "scene here: call it first, then do your own work"
            )
        self._mjcf_never_compiled = True
        self.observation_space = self._updater.observation_space
        self.action_space = self._action_space
        self.metadata = {
            **self.metadata,
            "render_fps": 1.0 / (self.control_timestep * self._action_repeat),
        }
        self._fixed_random_state = self._random_state.get_state(legacy=False)
        self._reset_next_step = True

    # -- properties ----------------------------------------------------------------------

    @property
    def physics(self) -> mjcf.Physics:
        """The simulation; the same object for the environment's life (reset in place)."""
        return self._physics

    @property
    def task(self) -> Task:
        """The task this environment runs."""
        return self._task

    @property
    def random_state(self) -> np.random.RandomState:
        """The RandomState hooks get (drawing from `np_random`'s bit generator)."""
        return self._random_state

    @property
    def control_timestep(self) -> float:
        """Seconds of simulation per `step()`."""
        return self._timing.control_timestep

    @property
    def timing(self) -> stepping.Timing:
        """Physics steps per control step and the control timestep, as resolved at the
        last compile (`composer.stepping.resolve_timing`)."""
        return self._timing

    def add_extra_hook(self, hook_name: str, hook_callable: Callable[..., Any]) -> None:
        """Run `hook_callable` after the task's and the entities' hook `hook_name` (one of
        HOOK_NAMES), with the same arguments (`before_step` and `before_substep` ones get
        `(physics, action, random_state)`). Raises TaskError for another name or a value
        that is not callable."""
        if hook_name not in HOOK_NAMES:
            raise errors.TaskError(f"{hook_name!r} is not a valid hook name: {HOOK_NAMES}")
        if not callable(hook_callable):
            raise errors.TaskError(f"{hook_callable!r} is not a callable")
        self._extra_hooks[hook_name].append(hook_callable)
        self._resolve_hooks()

    @property
    def batch_physics(self) -> BatchOfOne:
        """The batch of one the task's batched methods get (its physics, task and random
        state), as a VectorEnvironment's `batch_physics` is over its environments."""
        return self._batch

    @property
    def updater(self) -> Updater:
        """The observation pipeline of the current compile (rebuilt by a recompile); a
        VectorEnvironment reads each environment's reset state from it."""
        return self._updater

    # -- dm_control's internal names, for subclasses (composer.dm_internals) -------------

    @property
    def _physics_proxy(self) -> mjcf.Physics:
        """dm_control's weak proxy of the physics; here the physics itself, which a
        recompile reloads in place."""
        return self._physics

    @property
    def _observation_updater(self) -> dm_internals.UpdaterView:
        """dm_control's observation updater: this environment's own pipeline, through
        dm_control's calls (`dm_internals.UpdaterView`)."""
        return self._updater_view

    # -- compiling -----------------------------------------------------------------------

    def _recompile_physics_and_update_observables(self) -> None:
        """Compile the task's current model and rebuild everything that depends on it
        (dm_control's name; a subclass may override it, calling this first). After the first
        compile the spaces must stay as they were. Raises TaskError if they changed, and
        OverrideError if an override of `_recompile_physics` left no physics."""
        self._recompile_physics()
        if not isinstance(getattr(self, "_physics", None), mjcf.Physics):
            raise errors.OverrideError(
                f"{type(self).__name__}._recompile_physics() left no mjcf.Physics in "
                "self._physics: call super()._recompile_physics(), which compiles the task's "
                "model, or assign the mjcf.Physics you make to self._physics"
            )
        self._after_compile()
        if self._compile_count == 1:
            return
        for label, old, new in (
            ("observation", self.observation_space, self._updater.observation_space),
            ("action", self.action_space, self._action_space),
        ):
            if old != new:
                raise errors.TaskError(
                    f"the {label} space changed when the model was recompiled after "
                    f"initialize_episode_mjcf: was {old}, now {new}; a gymnasium env keeps "
                    "its spaces, so change values, not shapes"
                )

    def _recompile_physics(self) -> None:
        """Compile the task's current model into `self._physics`: the first time a new
        `mjcf.Physics`, then reloaded in place (dm_control's name; it makes a new one)."""
        model = self._task.root_entity.mjcf_model
        physics = getattr(self, "_physics", None)
        if physics is None:
            self._physics = mjcf.Physics.from_mjcf_model(model)
            self._physics.legacy_step = self._legacy_step
        else:
            physics.reload_from_mjcf_model(model)

    def _make_observation_updater(self) -> Updater:
        """The observation pipeline of the compile that just happened (dm_control's name;
        an override must return a `composer.observation.Updater`)."""
        return Updater(
            self._task.enabled_observables(), self._physics, self._n_sub_steps, self._flatten,
            self._strip_singleton_obs_buffer_dim, self._delayed_observation_padding,
            keep_order=self._task.keep_observation_order,
        )  # fmt: skip

    def _after_compile(self) -> None:
        """After a compile: hooks, observation pipeline, spaces, step plan."""
        task, physics = self._task, self._physics
        self._compiled_root = task.root_entity.mjcf_model
        self._version = self._compiled_root.version
        self._methods = stepping.TaskStep(task)
        self._resolve_hooks()
        for hook in self._resolved_hooks.after_compile:
            hook(physics, self._random_state)
        self._timing = timing = stepping.resolve_timing(task, physics, self._overridden_n_sub_steps)
        self._n_sub_steps = timing.substeps
        physics.reset()
        updater = self._make_observation_updater()
        if not isinstance(updater, Updater):
            raise errors.OverrideError(
                f"{type(self).__name__}._make_observation_updater() returned "
                f"{type(updater).__name__}, not a composer.observation.Updater: observation "
                "options belong on the observables (or Environment's keywords), not here"
            )
        self._updater = updater
        self._action_space = task.action_space(physics)
        self._actions = stepping.ActionRule(self._action_space)
        self._step_limit = timing.step_limit(self._time_limit)
        # What the task's batched methods get, and its single forms' defaults run them
        # with: this physics as a batch of one.
        self._batch = task._served_batch = BatchOfOne(physics, task, lambda: self._random_state)
        self._compile_count += 1

    def _resolve_hooks(self) -> None:
        """The hooks of the task, its entities and the extra ones, and what a step runs: a
        subclass's `_substep` for each physics step, if it overrides it."""
        self._resolved_hooks = resolved = hooks.Hooks(self._task, self._extra_hooks)
        self._applies_each = self._methods.applies_each(resolved)
        self._finishes_each = self._methods.finishes_each(resolved)
        if type(self)._substep is not Environment._substep:
            self._advance: Callable[[int], None] = self._run_overridden_substeps
            self._substep_hooks = None  # the override runs them, through super()._substep
        else:
            self._advance = self._physics.step
            self._substep_hooks = self._run_substep_hooks if resolved.has_substep_hooks else None

    def _mjcf_hooks(self) -> tuple[tuple[Callable[..., Any], ...], bool]:
        """The `initialize_episode_mjcf` hooks to run now (the task's, the entities', the
        extra ones), and whether the model is as last compiled."""
        root = self._task.root_entity.mjcf_model
        if root is self._compiled_root and root.version == self._version:
            # The model as compiled, so the entity tree too (attaching or detaching
            # changes the version): its hooks are those resolved at the compile.
            return self._resolved_hooks.initialize_episode_mjcf, True
        everyone = [self._task, *self._task.root_entity.iter_entities()]
        found = hooks.overriders(everyone, "initialize_episode_mjcf")
        return found + tuple(self._extra_hooks["initialize_episode_mjcf"]), False

    # -- gymnasium API -------------------------------------------------------------------

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray] | np.ndarray, dict[str, Any]]:
        """Start an episode (see the class docstring for the hooks run); `seed` reseeds
        the environment's random state. `options` are not used. Returns (obs, info), what
        `_reset_attempt` returns (a dm_env TimeStep from a subclass's: its observation and
        {}). Raises EpisodeInitializationError when every one of `max_reset_attempts`
        attempts raised it, OverrideError when a subclass's `_reset_attempt` returns
        anything else."""
        super().reset(seed=seed)
        if seed is not None:
            own = self._task.random_state_for_seed(seed)
            if own is None:
                own = np.random.RandomState(self.np_random.bit_generator)
            self._random_state = own
            self._fixed_random_state = own.get_state(legacy=False)
        self._reset_next_step = True
        for attempt in range(1, self._max_reset_attempts + 1):
            try:
                # Untimed as a step is: an initialization's settling steps (cheetah's 200)
                # run at C MuJoCo's speed, to the same numbers.
                started = timer.untimed(self._reset_attempt)
            except EpisodeInitializationError as e:
                if attempt == self._max_reset_attempts:
                    raise
                _LOG.warning("episode initialization failed (attempt %d): %r", attempt, e)
            else:
                self._reset_next_step = False
                return dm_internals.reset_result(started, type(self).__name__)
        raise AssertionError("unreachable: max_reset_attempts >= 1")

    def _reset_attempt(self) -> tuple[dict[str, np.ndarray] | np.ndarray, dict[str, Any]]:
        """One attempt at starting an episode: (obs, info). dm_control's name; a subclass
        may override it (see `reset`)."""
        random_state = self._random_state
        if self._recompile_mjcf_every_episode is not False or self._mjcf_never_compiled:
            if self._fixed_initial_state:
                random_state.set_state(self._fixed_random_state)
            mjcf_hooks, as_compiled = self._mjcf_hooks()
            for hook in mjcf_hooks:
                hook(random_state)
            # True and False are dm_control's: a compile every episode, or at the first
            # reset only (their block runs once); None: when the model changed. No hook
            # ran on a model as compiled: it is unchanged.
            changed = (not as_compiled or bool(mjcf_hooks)) and (
                self._task.root_entity.mjcf_model.version != self._version
            )
            if changed or self._recompile_mjcf_every_episode is not None:
                self._recompile_physics_and_update_observables()
            self._mjcf_never_compiled = False
        if self._fixed_initial_state:
            random_state.set_state(self._fixed_random_state)
        physics = self._physics
        with physics.reset_context():
            for hook in self._resolved_hooks.initialize_episode:
                hook(physics, random_state)
        return self._restart_observations(random_state), {}

    def _restart_observations(
        self, random_state: np.random.RandomState
    ) -> dict[str, np.ndarray] | np.ndarray:
        """Count steps from zero and sample every observable: the first observation."""
        self._steps = 0
        self._physics_steps = 0
        return self._updater.reset(random_state)

    def step(
        self, action: Any
    ) -> tuple[dict[str, np.ndarray] | np.ndarray, float, bool, bool, dict[str, Any]]:
        """Advance one control step with `action` (`composer.stepping` says what a step
        is), or `action_repeat` of them with the same action, the rewards summed, the
        discounts multiplied, ending early with the episode. Returns (obs, reward,
        terminated, truncated, info): the last control step's, but for reward and
        info['discount']. Raises EpisodeError before reset, after the episode ended, or for
        an action of the wrong shape or not finite."""
        if self._reset_next_step:
            raise errors.EpisodeError(
                "step() called before reset() or after the episode ended; call reset()"
            )
        action = self._actions.checked(action)
        result = timer.untimed(self._control_step, action)
        if self._action_repeat == 1:
            return result
        observation, total, terminated, truncated, info = result
        discount = info.get("discount", 0.0)
        for _ in range(1, self._action_repeat):
            if terminated or truncated:
                break
            observation, reward, terminated, truncated, info = timer.untimed(
                self._control_step, action
            )
            total += reward
            discount *= info.get("discount", 0.0)
        if "discount" in info:
            info["discount"] = discount
        return observation, total, terminated, truncated, info

    def _control_step(
        self, action: np.ndarray
    ) -> tuple[dict[str, np.ndarray] | np.ndarray, float, bool, bool, dict[str, Any]]:
        """One control step with a checked `action` (see `step`)."""
        physics, random_state, methods = self._physics, self._random_state, self._methods
        task, batch = self._task, self._batch
        if methods.writes_controls:  # what Task's batched before_step does, directly
            physics.set_control(action)
        else:
            methods.apply(batch, action[None])
        if self._applies_each:
            methods.apply_each(task, self._resolved_hooks, physics, action, random_state)
        self._action = action
        self._first = first = self._physics_steps
        updater = self._updater
        last_due = stepping.physics_steps(
            self._n_sub_steps, updater.offsets(self._steps), self._advance, self._sample,
            self._substep_hooks,
        )  # fmt: skip
        methods.finish(batch)
        if self._finishes_each:
            methods.finish_each(task, self._resolved_hooks, physics, random_state)
        if last_due:
            self._sample(self._n_sub_steps)
        self._steps += 1
        last = self._physics_steps = first + self._n_sub_steps
        observation = updater.observation(last)
        message = stepping.invalid_state(physics)
        if message is not None:
            self._reset_next_step = True
            if self._raise_exception_on_physics_error:
                physics.check_invalid_state()  # raises mjcf.PhysicsError with the message
            return observation, 0.0, False, True, stepping.diverged(message, stacklevel=3)
        reward, terminated, info = methods.outcome_of_one(batch, task, physics)
        truncated = self._steps >= self._step_limit
        self._reset_next_step = terminated or truncated
        return observation, reward, terminated, truncated, info

    def _sample(self, offset: int) -> None:
        """Sample the observables due after physics step `offset` of this control step."""
        self._updater.sample(self._steps, self._first, offset)

    def _run_substep_hooks(self, before: bool) -> None:
        stepping.substep_hooks(
            self._resolved_hooks, self._physics, self._action, self._random_state, before
        )

    def _substep(self, action: np.ndarray) -> None:
        """One physics step with the substep hooks around it (dm_control's name): `step`
        runs a subclass's override of it for each physics step of a control step."""
        resolved, physics, random_state = self._resolved_hooks, self._physics, self._random_state
        stepping.substep_hooks(resolved, physics, action, random_state, True)
        physics.step()
        stepping.substep_hooks(resolved, physics, action, random_state, False)

    def _run_overridden_substeps(self, count: int) -> None:
        for _ in range(count):
            self._substep(self._action)

    # Gymnasium 1.2's Env.render returns a type variable no override can name.
    def render(self) -> np.ndarray | None:  # type: ignore[override, unused-ignore]
        """A frame of the current state for `render_mode` ('rgb_array': (h, w, 3) uint8,
        'depth_array': (h, w) float32 meters), or None without a render mode. Raises
        mjcf.RenderError when no OpenGL backend is available."""
        if self.render_mode is None:
            return None
        height, width = self._render_size
        return self._physics.render(
            height, width, camera_id=self._render_camera, depth=self.render_mode == "depth_array"
        )

    def close(self) -> None:
        """Free rendering resources; safe to call more than once."""
        self._physics.close()


def _check_count(label: str, value: Any) -> None:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise errors.TaskError(f"{label} must be a positive int, got {value!r}")


def _as_random_state(
    random_state: int | np.random.RandomState | np.random.Generator | None,
) -> np.random.RandomState | None:
    if random_state is None or isinstance(random_state, np.random.RandomState):
        return random_state
    if isinstance(random_state, np.random.Generator):
        return np.random.RandomState(random_state.bit_generator)
    if isinstance(random_state, int | np.integer) and not isinstance(random_state, bool):
        return np.random.RandomState(int(random_state))
    raise errors.TaskError(
        "random_state must be None, an int seed, a numpy RandomState or Generator, "
        f"got {type(random_state).__name__}"
    )
