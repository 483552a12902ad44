"""Environment: a composer Task served as a `gymnasium.Env`.

    env = composer.Environment(task, time_limit=10.0, render_mode='rgb_array')
    obs, info = env.reset(seed=0)                  # obs: {'arm/joint_positions': array, ...}
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    frame = env.render()                           # (240, 320, 3) uint8
    env.physics.bind(joint).qpos                   # the live simulation
    env.close()

What it promises:
- The scene is compiled once, at construction; `reset()` recompiles only when the
  `initialize_episode_mjcf` hooks changed the model (its `version`), otherwise it resets
  the same MjModel/MjData in place (no recompile, well under a millisecond).
- Hook order: reset runs `initialize_episode_mjcf`, then (only if the model changed, and
  at construction) compiles and runs `after_compile`, then resets the physics and runs
  `initialize_episode`. A step runs the task's `before_step(physics, action, ...)` (which
  applies the action), the entities' `before_step`, then per physics step `before_substep`,
  `physics.step()`, `after_substep`, then `after_step`; then observations, reward,
  termination are read. Each hook runs on the task, then on every entity (`composer.hooks`).
- `terminated` comes from `task.should_terminate_episode`; `truncated` is set when the time
  limit is reached (after ceil(time_limit / control_timestep) steps) or when MuJoCo reported
  an invalid state (bad qacc, NaN): then `info['physics_error']` holds the message, the
  reward is 0.0, a `DivergenceWarning` is emitted, and the next `reset()` starts afresh.
- Randomness: hooks and corruptors get a `numpy.random.RandomState` (dm_control's API) that
  draws from the same bit generator as `env.np_random`; `reset(seed=s)` reseeds both, so the
  same seed and actions give bit-identical episodes. `random_state` at construction (an
  int, a RandomState or a Generator) is used until a seeded reset.
- Actions: a NaN or infinite action raises `EpisodeError` (it would silently corrupt the
  simulation); finite actions outside the action space are clipped to its bounds (the
  actuators' ctrlrange) before the task applies them.
- Observations are new arrays every step (safe to keep); a step's `info` holds the task's
  `get_info(physics)` entries (e.g. 'is_success') and its `discount`.
- Observations, rewards and hooks see derived quantities (xpos, site_xpos, sensordata ...)
  consistent with the current state, as `mj_forward` would compute them, not one physics
  step behind as with a bare `mujoco.mj_step` (see `mjcf.Physics.step`; this costs nothing
  over `mj_step`). `env.physics.legacy_step = False` restores bare `mj_step`s.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import gymnasium
import numpy as np

import mjcf
from composer import errors, hooks
from composer.observation import Updater
from composer.task import Task

RENDER_MODES = ("rgb_array", "depth_array")


class Environment(gymnasium.Env):
    """A gymnasium.Env running a composer Task."""

    metadata = {"render_modes": list(RENDER_MODES), "render_fps": 50}

    def __init__(
        self,
        task: Task,
        time_limit: float = math.inf,
        random_state: int | np.random.RandomState | np.random.Generator | None = None,
        flatten_observations: bool = False,
        render_mode: str | None = None,
        render_height: int = 240,
        render_width: int = 320,
        render_camera: int | str = -1,
    ) -> None:
        """Compile `task`'s scene and build the spaces. Raises TaskError for a bad time
        limit, render mode or timesteps, ObservableError for an observable that cannot be
        read, and mjcf.CompileError when MuJoCo rejects the scene."""
        if render_mode is not None and render_mode not in RENDER_MODES:
            raise errors.TaskError(
                f"render_mode must be one of {RENDER_MODES} or None, got {render_mode!r}"
            )
        if not (isinstance(time_limit, int | float) and time_limit > 0):
            raise errors.TaskError(f"time_limit must be a positive number, got {time_limit!r}")
        self._task = task
        self._time_limit = float(time_limit)
        self._random_state = _as_random_state(random_state)
        self._flatten = flatten_observations
        self.render_mode = render_mode
        self._render_size = (int(render_height), int(render_width))
        self._render_camera = render_camera
        self._physics = mjcf.Physics.from_mjcf_model(task.root_entity.mjcf_model)
        self._after_compile()
        self.observation_space = self._updater.observation_space
        self.action_space = self._action_space
        self.metadata = {**self.metadata, "render_fps": 1.0 / task.control_timestep}
        self._episode_over = True

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
        if self._random_state is None:
            self._random_state = np.random.RandomState(self.np_random.bit_generator)
        return self._random_state

    @property
    def control_timestep(self) -> float:
        """Seconds of simulation per `step()`."""
        return self._substeps * self._physics.timestep()

    @property
    def updater(self) -> Updater:
        """The observation pipeline of the current compile (rebuilt by a recompile); a
        VectorEnvironment reads each environment's reset state from it."""
        return self._updater

    # -- compiling -----------------------------------------------------------------------

    def _after_compile(self) -> None:
        """After a compile: hooks, observation pipeline, spaces, step plan."""
        task, physics = self._task, self._physics
        self._version = task.root_entity.mjcf_model.version
        self._hooks = hooks.Hooks(task)
        for hook in self._hooks.after_compile:
            hook(physics, self.random_state)
        self._substeps = task.physics_steps_per_control_step
        physics.reset()
        self._updater = Updater(task.enabled_observables(), physics, self._substeps, self._flatten)
        self._action_space = task.action_space(physics)
        self._action_shape = self._action_space.shape
        self._action_low = self._action_space.low.astype(np.float64)
        self._action_high = self._action_space.high.astype(np.float64)
        self._step_limit = (
            math.inf if math.isinf(self._time_limit)
            else math.ceil(self._time_limit / task.control_timestep - 1e-9)
        )  # fmt: skip
        # Per-step constants, bound once.
        self._plan = self._updater.plan
        self._period = len(self._plan)
        self._substep_plan = self._updater.substep_plan
        self._substep_hooks = self._hooks.has_substep_hooks

    def _recompile(self) -> None:
        """The model changed: recompile in place; spaces must stay as they were."""
        self._physics.reload_from_mjcf_model(self._task.root_entity.mjcf_model)
        self._after_compile()
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

    # -- gymnasium API -------------------------------------------------------------------

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray] | np.ndarray, dict[str, Any]]:
        """Start an episode (see the module docstring for the hooks run); `seed` reseeds
        the environment's random state. `options` are not used. Returns (obs, info)."""
        super().reset(seed=seed)
        if seed is not None:
            self._random_state = np.random.RandomState(self.np_random.bit_generator)
        random_state = self.random_state
        task = self._task
        everyone = [task, *task.root_entity.iter_entities()]
        for hook in hooks.overriders(everyone, "initialize_episode_mjcf"):
            hook(random_state)
        if task.root_entity.mjcf_model.version != self._version:
            self._recompile()
        physics = self._physics
        with physics.reset_context():
            for hook in self._hooks.initialize_episode:
                hook(physics, random_state)
        self._steps = 0
        self._physics_steps = 0
        self._episode_over = False
        return self._updater.reset(random_state), {}

    def step(
        self, action: Any
    ) -> tuple[dict[str, np.ndarray] | np.ndarray, float, bool, bool, dict[str, Any]]:
        """Advance one control step with `action`. Returns (obs, reward, terminated,
        truncated, info). Raises EpisodeError before reset, after the episode ended, or
        for an action of the wrong shape."""
        if self._episode_over:
            raise errors.EpisodeError(
                "step() called before reset() or after the episode ended; call reset()"
            )
        action = np.asarray(action, dtype=np.float64)
        if action.shape != self._action_shape:
            raise errors.EpisodeError(
                f"action has shape {action.shape}, expected {self._action_shape} "
                f"(one value per actuator)"
            )
        if not np.isfinite(action).all():
            raise errors.EpisodeError(
                f"action has non-finite values at indices {np.flatnonzero(~np.isfinite(action))}"
                f": {action}; actions must be finite numbers"
            )
        action = np.clip(action, self._action_low, self._action_high)
        physics, random_state, task_hooks = self._physics, self._random_state, self._hooks
        task_hooks.task_before_step(physics, action, random_state)
        for hook in task_hooks.before_step:
            hook(physics, random_state)
        first = self._physics_steps
        phase = self._steps % self._period
        if self._substep_hooks:
            self._run_substeps(action, first, self._substep_plan[phase])
        else:
            advance = physics.step
            for count, samples in self._plan[phase]:
                advance(count)
                for sample, offset in samples:
                    sample(first + offset)
        for hook in task_hooks.after_step:
            hook(physics, random_state)
        self._steps += 1
        last = self._physics_steps = first + self._substeps
        observation = self._updater.observation(last)
        task = self._task
        try:
            physics.check_invalid_state()
        except mjcf.PhysicsError as e:
            self._episode_over = True
            warnings.warn(f"episode truncated: {e}", errors.DivergenceWarning, stacklevel=2)
            return observation, 0.0, False, True, {"physics_error": str(e)}
        reward = float(task.get_reward(physics))
        terminated = bool(task.should_terminate_episode(physics))
        truncated = self._steps >= self._step_limit
        self._episode_over = terminated or truncated
        info = task.get_info(physics)
        info["discount"] = task.get_discount(physics)
        return observation, reward, terminated, truncated, info

    def _run_substeps(self, action: np.ndarray, first: int, plan: list[list[Any]]) -> None:
        physics, random_state, task_hooks = self._physics, self._random_state, self._hooks
        for samples in plan:
            for hook in task_hooks.task_before_substep:
                hook(physics, action, random_state)
            for hook in task_hooks.before_substep:
                hook(physics, random_state)
            physics.step()
            for hook in task_hooks.after_substep:
                hook(physics, random_state)
            for sample, offset in samples:
                sample(first + offset)

    def render(self) -> np.ndarray | None:
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
