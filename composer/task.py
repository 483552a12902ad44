"""Tasks: what the agent should do in a scene of entities (`Task` shows a whole one).

    task = composer.NullTask(arena)                    # zero reward, never terminates
    env = composer.Environment(task, time_limit=10.0)
    task.action_space(env.physics)                     # every actuator's control, bounded

Promises: the default action is every actuator's control in model order, bounded by its
ctrlrange and written to `physics.data.ctrl`; a per-step method written once in batched
form (`get_reward_batch` ...) gives one environment and many the same values
(`composer.batch`). Timesteps that do not divide raise TaskError.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import mujoco
import numpy as np
from gymnasium import spaces

import mjcf
from composer import errors, hooks, stepping
from composer.batch import protocol
from composer.batch.single import BatchOfOne
from composer.entity import Entity
from composer.observation import Observable

_DEFAULT_PHYSICS_TIMESTEP = float(mujoco.MjOption().timestep)


class Task(hooks.EpisodeHooks):
    """The goal: root entity, timesteps, reward, termination, observables and hooks.

        class Reach(composer.Task):
            def __init__(self):
                self._arena = composer.Arena()
                self._arm = Arm()
                self._arena.attach(self._arm)
                self.set_timesteps(control_timestep=0.02, physics_timestep=0.005)  # 4 substeps

            @property
            def root_entity(self):
                return self._arena

            def get_reward(self, physics):
                return -float(np.linalg.norm(physics.bind(self._arm.tip).xpos))

    A task names the scene's root entity, its timesteps, its reward, when an episode ends, and
    extra `task_observables`. By default the action is every actuator's control, in model
    order, bounded by `ctrlrange` where the actuator is control-limited; `before_step` writes it
    to `physics.data.ctrl`. A task may instead override dm_control's `action_spec(physics)`
    (starting from `super().action_spec(physics)` if it likes: the [dm] extra). The hooks are
    those of entities (see `composer.hooks` for the order); the task's `before_step` and
    `before_substep` also get the action.

    Each per-step method (`before_step`, `after_step`, `get_reward`, `should_terminate_episode`,
    `get_discount`, `get_info`) can be written instead in batched form, once for one
    environment and many: `get_reward_batch(physics)` gets a `composer.BatchPhysics` of n
    environments and returns (n,) rows; a single Environment runs it with a batch of one, a
    `VectorEnvironment` over all its environments at once (`composer.batch`).

    `_served_batch` is the batch of one of the environment stepping the task, which that
    environment sets at each compile (`composer.Environment`); the single forms' defaults
    run the batched forms with it (`_batch_of_one`)."""

    _control_timestep: float | None = None
    _served_batch: BatchOfOne | None = None
    #: Whether observations keep the order of `observables` (task observables first, in
    #: the order `task_observables` gives them) in flattened observations, as dm_control's
    #: `flat_observation` concatenates its observation dict; False: sorted by name.
    keep_observation_order: bool = False

    def random_state_for_seed(self, seed: int) -> np.random.RandomState | None:
        """The random state an environment's `reset(seed=seed)` hands this task's hooks,
        or None (the default) for the environment's own: one drawing from Gymnasium's
        `np_random`. A task that must start as dm_control's suite task seeded with
        `random=seed` (as Shimmy serves it) returns `np.random.RandomState(seed)`."""
        return None

    @property
    def root_entity(self) -> Entity:
        """The entity at the root of the scene (usually an Arena)."""
        raise NotImplementedError(f"{type(self).__name__} must define root_entity")

    # -- timesteps -----------------------------------------------------------------------

    @property
    def physics_timestep(self) -> float:
        """The physics timestep: the `option.timestep` of the root model (which the models
        attached into it share: see `mjcf.compose.global_settings`), else MuJoCo's default."""
        timestep = self.root_entity.mjcf_model.option.timestep
        return _DEFAULT_PHYSICS_TIMESTEP if timestep is None else float(timestep)

    @physics_timestep.setter
    def physics_timestep(self, value: float) -> None:
        self.set_timesteps(self._control_timestep or value, value)

    @property
    def control_timestep(self) -> float:
        """The agent's timestep, a multiple of the physics timestep (default: equal)."""
        if self._control_timestep is None:
            return self.physics_timestep
        return self._control_timestep

    @control_timestep.setter
    def control_timestep(self, value: float) -> None:
        self.set_timesteps(value, self.physics_timestep)

    def set_timesteps(self, control_timestep: float, physics_timestep: float) -> None:
        """Set both timesteps; the physics one is written to the root model's option, which
        the models attached into it share. Raises TaskError if either is not positive or
        the control timestep is not a multiple of the physics one."""
        stepping.substeps(control_timestep, physics_timestep, type(self).__name__)
        self.root_entity.mjcf_model.option.timestep = physics_timestep
        self._control_timestep = float(control_timestep)

    @property
    def physics_steps_per_control_step(self) -> int:
        """Physics steps per control step (`composer.stepping.substeps`); raises TaskError
        if the timesteps do not divide."""
        return stepping.substeps(self.control_timestep, self.physics_timestep, type(self).__name__)

    # -- what the agent sees and does ----------------------------------------------------

    @property
    def task_observables(self) -> dict[str, Observable]:
        """Observables of the task itself, by name (no entity prefix); none by default."""
        return {}

    @property
    def observables(self) -> dict[str, Observable]:
        """Every observable of the task and its entities, named as in observations:
        'name' for the task's, 'arm/name' for an entity's (the root entity's model name,
        or an attached entity's scope, 'arm/gripper/name'). Raises TaskError for a name
        two observables share."""
        found = dict(self.task_observables)
        root = self.root_entity
        for entity in root.iter_entities():
            prefix = entity.scope_in(root) or root.name
            for name, item in entity.observables.items():
                full = f"{prefix}/{name}"
                if full in found:
                    raise errors.TaskError(
                        f"two observables are named {full!r}: rename one of them "
                        f"(entity {entity.name!r})"
                    )
                found[full] = item
        return found

    def iter_entities(self) -> Iterator[Entity]:
        """The root entity and every entity attached under it (`Entity.iter_entities`)."""
        return self.root_entity.iter_entities()

    def get_reward_spec(self) -> Any:
        """dm_control's hook for a non-scalar reward's dm_env spec; None: a float reward."""
        return None

    def get_discount_spec(self) -> Any:
        """dm_control's hook for a non-scalar discount's dm_env spec; None: a float."""
        return None

    def enabled_observables(self) -> dict[str, Observable]:
        """The enabled ones of `observables`: what observations contain."""
        return {name: item for name, item in self.observables.items() if item.enabled}

    def action_space(self, physics: mjcf.Physics) -> spaces.Box:
        """A float32 Box (as Gymnasium's MuJoCo envs and stable-baselines3 expect) over every
        actuator's control, bounded by its ctrlrange where it is control-limited,
        unbounded otherwise. MuJoCo clamps controls to ctrlrange itself. A task overriding
        dm_control's `action_spec(physics)` gets its dm_env spec as a Box instead
        (`composer.dm_env_specs`, the [dm] extra)."""
        declared = type(self).action_spec
        if declared is not Task.action_spec:
            from composer import dm_env_specs  # imports dm_env: only for such tasks

            return dm_env_specs.action_space_from_spec(declared(self, physics))
        low, high = _control_bounds(physics.model, np.inf)
        return spaces.Box(low.astype(np.float32), high.astype(np.float32), dtype=np.float32)

    def action_spec(self, physics: mjcf.Physics) -> Any:
        """dm_control's default action spec, for an override that starts from
        `super().action_spec(physics)`: a dm_env `BoundedArray` of shape (nu,), float64,
        bounded by each actuator's ctrlrange where it is control-limited and by
        -/+`mujoco.mjMAXVAL` otherwise, named by the actuators' names joined by tabs (an
        unnamed one by its index). Only an override changes the action space
        (`action_space`). Needs dm_env: raises ImportError saying to install the [dm]
        extra."""
        from composer import dm_env_specs  # imports dm_env: only when asked for

        model = physics.model
        low, high = _control_bounds(model, mujoco.mjMAXVAL)
        names = [
            mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, i) or str(i)
            for i in range(model.nu)
        ]
        return dm_env_specs.actuator_spec(low, high, names)

    def _batch_of_one(self, physics: mjcf.Physics) -> BatchOfOne:
        """What the single forms' defaults run the batched forms with: the batch of one of
        the environment stepping this task (with its random state and bound fields) when
        `physics` is its physics, else a new one around `physics`."""
        served = self._served_batch
        if served is not None and served.physics is physics:
            return served
        return BatchOfOne(physics, self)

    # -- per-step methods (composer.batch): each in its single or its batched form -----
    # A task defines a method's single form (dm_control's, on one mjcf.Physics) or its
    # batched form (`<name>_batch`, on a BatchPhysics of n environments). The defaults
    # here are batched; the single forms run the batched ones with a batch of one.

    def get_reward(self, physics: mjcf.Physics) -> float:
        """The reward of the control step that just ended. Define this or
        `get_reward_batch` (this then runs it with a batch of one)."""
        rows = self.get_reward_batch(self._batch_of_one(physics))
        return float(protocol.check_rows("get_reward_batch", rows, 1, np.float64)[0])

    def get_reward_batch(self, physics: protocol.BatchPhysics) -> np.ndarray:
        """The rewards of the control step that just ended, shape (n,)."""
        raise NotImplementedError(
            f"{type(self).__name__} must implement get_reward(physics) or get_reward_batch(physics)"
        )

    def should_terminate_episode(self, physics: mjcf.Physics) -> bool:
        """Whether the episode ended in a terminal state (not a time limit); by default
        what `should_terminate_episode_batch` says, with a batch of one."""
        rows = self.should_terminate_episode_batch(self._batch_of_one(physics))
        return bool(protocol.check_rows("should_terminate_episode_batch", rows, 1, bool)[0])

    should_terminate_episode_batch = protocol.constant_rows(
        False,
        bool,
        """Whether each episode ended in a terminal state, shape (n,) bool; never here.""",
    )

    def get_discount(self, physics: mjcf.Physics) -> float:
        """The discount of the step (dm_env style, in info['discount']); by default what
        `get_discount_batch` says, with a batch of one."""
        rows = self.get_discount_batch(self._batch_of_one(physics))
        return float(protocol.check_rows("get_discount_batch", rows, 1, np.float64)[0])

    get_discount_batch = protocol.constant_rows(
        1.0, np.float64, """The discount of each step, shape (n,); 1.0 here."""
    )

    def get_info(self, physics: mjcf.Physics) -> dict[str, Any]:
        """Extra entries for the step's `info`, a new dict (e.g. {'is_success': True}, as
        stable-baselines3 reads it); by default those of `get_info_batch`, with a batch of
        one (a number or bool for a row of one number)."""
        entries = protocol.check_info(self.get_info_batch(self._batch_of_one(physics)), 1)
        return {key: protocol.first_row(values) for key, values in entries.items()}

    @hooks.noop
    def get_info_batch(self, physics: protocol.BatchPhysics) -> dict[str, np.ndarray]:
        """Extra info entries, each an array of shape (n, ...); none here."""
        return {}

    # -- hooks (see composer.hooks for the order; the others are in hooks.EpisodeHooks) --

    def before_step(
        self, physics: mjcf.Physics, action: np.ndarray, random_state: np.random.RandomState
    ) -> None:
        """Each control step, first: apply `action`; by default `before_step_batch`, with
        a batch of one."""
        actions = np.asarray(action, dtype=np.float64)[None]
        self.before_step_batch(self._batch_of_one(physics), actions)

    @stepping.writes_controls
    def before_step_batch(self, physics: protocol.BatchPhysics, actions: np.ndarray) -> None:
        """Apply `actions`, (n, action size) float64 clipped to the action space; here,
        write them to every actuator's ctrl."""
        physics.set_control(actions)

    def after_step(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """After the physics steps of a control step, before observations are read; by
        default `after_step_batch`, with a batch of one."""
        self.after_step_batch(self._batch_of_one(physics))

    @hooks.noop
    def after_step_batch(self, physics: protocol.BatchPhysics) -> None:
        """`after_step` of n environments at once; nothing here."""

    @hooks.noop
    def before_substep(
        self, physics: mjcf.Physics, action: np.ndarray, random_state: np.random.RandomState
    ) -> None:
        """Before each physics step."""


def _control_bounds(model: mujoco.MjModel, unlimited: float) -> tuple[np.ndarray, np.ndarray]:
    """(low, high), (nu,) float64 each: every actuator's ctrlrange where it is
    control-limited, -/+`unlimited` where it is not."""
    limited = model.actuator_ctrllimited.astype(bool)
    low = np.where(limited, model.actuator_ctrlrange[:, 0], -unlimited)
    high = np.where(limited, model.actuator_ctrlrange[:, 1], unlimited)
    return low, high


class NullTask(Task):
    """A task around `root_entity` with zero reward and no termination: for looking at a
    scene, benchmarks and tests."""

    def __init__(self, root_entity: Entity) -> None:
        """Serve `root_entity`'s scene."""
        self._root_entity = root_entity

    @property
    def root_entity(self) -> Entity:
        """The entity given at construction."""
        return self._root_entity

    # A batched method made by constant_rows (marked constant), which the type checker
    # cannot see as the method it is.
    get_reward_batch = protocol.constant_rows(  # type: ignore[assignment]
        0.0, np.float64, """Always 0.0."""
    )
