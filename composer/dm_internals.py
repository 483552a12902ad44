"""dm_control's Environment internals, for subclasses of `composer.Environment` written on them.

    class Static(composer.Environment):               # skips recompiles, as mujoco_utils's
        def _reset_attempt(self):
            self._hooks.initialize_episode(self._physics_proxy, self._random_state)
            self._observation_updater.reset(self._physics_proxy, self._random_state)
            return dm_env.restart(self._observation_updater.get_observation())

What is kept (`env._hooks`, `env._observation_updater`, the methods and attributes) is listed
in docs/dm_control_composer.md; an override that cannot be kept raises OverrideError.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from composer import errors, stepping

if TYPE_CHECKING:
    import mjcf
    from composer.environment import Environment

__all__ = ["EnvironmentHooks", "UpdaterView", "reset_result"]


class EnvironmentHooks:
    """dm_control's `env._hooks`: the environment's hooks called as dm_control calls them.
    Reads the environment's resolved hooks and step plan (its friend, as dm_control's own
    hooks object is part of its environment)."""

    def __init__(self, env: Environment) -> None:
        """The hooks of `env`, as resolved at each call."""
        self._env = env

    def refresh_entity_hooks(self) -> None:
        """Resolve the hooks again, after entities were attached or detached."""
        self._env._resolve_hooks()

    def add_extra_hook(self, hook_name: str, hook_callable: Any) -> None:
        """`Environment.add_extra_hook`."""
        self._env.add_extra_hook(hook_name, hook_callable)

    def initialize_episode_mjcf(self, random_state: np.random.RandomState) -> None:
        """The task's, the entities' and the extra `initialize_episode_mjcf` hooks."""
        for hook in self._env._mjcf_hooks()[0]:
            hook(random_state)

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Everyone's `after_compile` hooks."""
        for hook in self._env._resolved_hooks.after_compile:
            hook(physics, random_state)

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """Everyone's `initialize_episode` hooks."""
        for hook in self._env._resolved_hooks.initialize_episode:
            hook(physics, random_state)

    def before_step(
        self, physics: mjcf.Physics, action: Any, random_state: np.random.RandomState
    ) -> None:
        """The task's `before_step` (which applies `action`, checked and clipped as `step()`
        does; raises EpisodeError for the wrong shape or a value not finite), then the
        entities' and the extra ones."""
        env = self._env
        rule = env._actions
        action = rule.clipped(rule.shaped(action))
        env._methods.apply(env._batch, action[None])
        env._methods.apply_each(env._task, env._resolved_hooks, physics, action, random_state)

    def before_substep(
        self, physics: mjcf.Physics, action: Any, random_state: np.random.RandomState
    ) -> None:
        """The task's `before_substep` (with `action`), the entities' and the extra ones."""
        stepping.substep_hooks(self._env._resolved_hooks, physics, action, random_state, True)

    def after_substep(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Everyone's `after_substep` hooks."""
        no_action = np.empty(0)  # after a physics step the hooks get no action
        stepping.substep_hooks(self._env._resolved_hooks, physics, no_action, random_state, False)

    def after_step(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """The task's `after_step`, then the entities' and the extra ones."""
        env = self._env
        env._methods.finish(env._batch)
        env._methods.finish_each(env._task, env._resolved_hooks, physics, random_state)


class UpdaterView:
    """dm_control's `env._observation_updater`: the environment's own observation pipeline
    (`composer.observation.Updater`) driven by dm_control's calls, counting the control
    and physics steps as `step()` does."""

    def __init__(self, env: Environment) -> None:
        """The pipeline of `env`, as rebuilt by each compile."""
        self._env = env
        self._first: int | None = None  # the control step's first physics step, once prepared
        self._offset = 0  # its physics steps updated so far

    def reset(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Start an episode: every observable sampled now, the step counts at zero."""
        self._env._restart_observations(random_state)
        self._first = None

    def prepare_for_next_control_step(self) -> None:
        """A control step begins: `update()` follows each of its physics steps."""
        self._first = self._env._physics_steps
        self._offset = 0

    def update(self) -> None:
        """After a physics step of the control step: sample what is due after it. Raises
        EpisodeError before `prepare_for_next_control_step()`."""
        if self._first is None:
            raise errors.EpisodeError(
                "_observation_updater.update() before prepare_for_next_control_step(): a "
                "control step begins with it"
            )
        env = self._env
        self._offset += 1
        if self._offset in env._updater.offsets(env._steps):
            env._updater.sample(env._steps, self._first, self._offset)

    def get_observation(self) -> dict[str, np.ndarray] | np.ndarray:
        """The current observation (new arrays); ends the control step under way."""
        env = self._env
        if self._first is not None:
            env._steps += 1
            env._physics_steps = self._first + self._offset
            self._first = None
        return env._updater.observation(env._physics_steps)

    def observation_spec(self) -> Any:
        """The dm_env specs of the observation space (the [dm] extra)."""
        from composer import dm_env_specs  # imports dm_env: only when asked for

        return dm_env_specs.spec_from_space(self._env.observation_space)


def reset_result(result: Any, owner: str) -> tuple[Any, dict[str, Any]]:
    """What `reset` returns of `_reset_attempt`'s `result`: an (obs, info) pair as it is, a
    dm_env TimeStep (from an override written for dm_control) as (its observation, {}).
    Raises OverrideError, naming the class `owner`, for anything else."""
    if isinstance(result, tuple) and hasattr(result, "step_type"):
        timestep: Any = result  # a dm_env.TimeStep (a NamedTuple)
        return timestep.observation, {}
    if isinstance(result, tuple) and len(result) == 2:
        return result
    raise errors.OverrideError(
        f"{owner}._reset_attempt() returned {type(result).__name__}: reset() needs "
        "(observation, info), as super()._reset_attempt() returns, or a dm_env.TimeStep"
    )
