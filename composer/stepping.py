"""A control step's rules, kept once for `composer.Environment` and `composer.VectorEnvironment`.

    timing = resolve_timing(task, physics)            # per compile: substeps, step limit
    action = actions.clipped(actions.shaped(action))  # ActionRule: float64, finite, in bounds

A control step: 1. the action is checked (`ActionRule`; EpisodeError before anything changes
for a wrong shape or a value not real and finite; clipped to bounds); 2. the task's (`TaskStep`)
and entities' `before_step`; 3. the physics steps, with substep hooks, sampling observables as
due (`physics_steps`); 4. `after_step` hooks, then the last step's samples; 5. an invalid state
truncates (reward 0, `info['physics_error']`: `diverged`), else `TaskStep.outcome` is read.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple, TypeVar

import numpy as np
from gymnasium import spaces

import mjcf
from composer import errors, hooks
from composer.batch import protocol

if TYPE_CHECKING:
    from composer.task import Task


F = TypeVar("F", bound=Callable[..., Any])

# How far a ratio of timesteps may be from a whole number (floating-point timesteps).
_TOLERANCE = 1e-6


def substeps(control_timestep: Any, physics_timestep: Any, owner: str = "task") -> int:
    """The physics steps in a control step of `control_timestep` seconds, with physics steps
    of `physics_timestep` seconds: the one rule of timesteps, which `Task.set_timesteps`
    checks too. Raises TaskError, naming `owner`, if either is not a positive number or the
    control timestep is not a whole multiple of the physics one."""
    for label, value in (("control", control_timestep), ("physics", physics_timestep)):
        if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
            raise errors.TaskError(
                f"{owner}: the {label} timestep must be a positive number, got {value!r}"
            )
    ratio = control_timestep / physics_timestep
    count = round(ratio)
    if count < 1 or abs(ratio - count) > _TOLERANCE * max(1.0, ratio):
        raise errors.TaskError(
            f"{owner}: the control timestep {control_timestep!r} must be a multiple of the "
            f"physics timestep {physics_timestep!r} (ratio {ratio:.6g})"
        )
    return count


def step_limit(
    time_limit: float | None, control_timestep: float, max_episode_steps: int | None = None
) -> float:
    """The number of control steps after which an episode is truncated: `time_limit`
    seconds (None or inf: no limit) rounded up to whole control steps, or fewer with
    `max_episode_steps`; math.inf for none."""
    limit = math.inf if time_limit is None else time_limit
    steps = math.inf if math.isinf(limit) else math.ceil(limit / control_timestep - 1e-9)
    return min(steps, math.inf if max_episode_steps is None else max_episode_steps)


class Timing(NamedTuple):
    """How a compiled task steps: `substeps` physics steps per control step, making
    `control_timestep` seconds of the compiled model. An environment resolves it once per
    compile (`resolve_timing`); everything that counts steps or seconds (the step limit,
    render fps, a VectorEnvironment) reads it."""

    substeps: int
    control_timestep: float

    def step_limit(self, time_limit: float | None, max_episode_steps: int | None = None) -> float:
        """The control steps after which an episode of `time_limit` seconds (or
        `max_episode_steps`) is truncated (`step_limit`)."""
        return step_limit(time_limit, self.control_timestep, max_episode_steps)


def resolve_timing(task: Task, physics: mjcf.Physics, n_sub_steps: int | None = None) -> Timing:
    """The timing of `task` compiled into `physics`: `n_sub_steps` (dm_control's override)
    or the task's control timestep over the model's physics timestep, in physics steps.
    Raises TaskError for timesteps that do not divide."""
    timestep = physics.timestep()
    if n_sub_steps is None:
        n_sub_steps = substeps(task.control_timestep, timestep, type(task).__name__)
    return Timing(n_sub_steps, n_sub_steps * timestep)


# numpy's kinds of real numbers: booleans, signed and unsigned integers, floats.
_REAL = frozenset("biuf")
_FLOAT64 = np.dtype(np.float64)


class ActionRule:
    """What an action must be: the action space's shape (with a row per environment for
    `num_envs`), finite, and within its bounds (clipped to them)."""

    def __init__(self, space: spaces.Box, num_envs: int | None = None) -> None:
        """Check actions of `space` (one environment's), for one environment or a batch."""
        self._low = space.low.astype(np.float64)
        self._high = space.high.astype(np.float64)
        self._batch = num_envs is not None
        self.shape = space.shape if num_envs is None else (num_envs, *space.shape)

    def checked(self, actions: Any) -> np.ndarray:
        """`clipped(shaped(actions))`: a float64 array of the right shape (what agents
        pass) is taken as it is, without converting it. Raises EpisodeError as they do."""
        given = type(actions) is np.ndarray and actions.dtype is _FLOAT64
        if not given or actions.shape != self.shape:
            actions = self.shaped(actions)
        return self.clipped(actions)

    def shaped(self, actions: Any) -> np.ndarray:
        """`actions` as a float64 array; raises EpisodeError if it is not an array of real
        numbers (strings, objects and complex numbers are refused, never converted: an
        imaginary part would be dropped) or its shape is not `shape`."""
        try:
            given = np.asarray(actions)
        except (ValueError, TypeError) as e:  # ragged rows
            raise errors.EpisodeError(f"{self._what('is')} not an array of numbers: {e}") from None
        if given.dtype.kind not in _REAL:
            held = "complex numbers (an imaginary part cannot be applied, nor is it dropped)" if (
                given.dtype.kind == "c") else f"values of type {given.dtype}"  # fmt: skip
            raise errors.EpisodeError(
                f"{self._what('holds')} {held}: actions are real numbers, an array of shape "
                f"{self.shape}"
            )
        actions = given.astype(np.float64, copy=False)
        if actions.shape != self.shape:
            hint = "a row per environment" if self._batch else "one value per actuator"
            raise errors.EpisodeError(
                f"{self._what('has')} shape {actions.shape}, expected {self.shape} ({hint})"
            )
        return actions

    def _what(self, verb: str) -> str:
        """'the action has' or 'the actions have' (for `verb` 'has'; 'is', 'holds' too)."""
        if not self._batch:
            return f"the action {verb}"
        return "the actions " + {"has": "have", "is": "are", "holds": "hold"}[verb]

    def clipped(self, actions: np.ndarray, ids: np.ndarray | None = None) -> np.ndarray:
        """`actions` clipped to the bounds; raises EpisodeError, naming the indices (or
        the environments `ids` of the rows), for a NaN or infinite value."""
        # The sum of squares is finite only if every value is (squares are >= 0, so no
        # inf - inf); a non-finite one also comes of finite values past 1e154, which the
        # exact test then tells apart. A third of that test's cost, every step. (np.vdot:
        # a vector's own `dot` is 0.15 us cheaper but warns of the overflow.)
        total = np.vdot(actions, actions)
        if not math.isfinite(total):
            finite = np.isfinite(actions)
            if not finite.all():
                if ids is None:
                    raise errors.EpisodeError(
                        f"action has non-finite values at indices {np.flatnonzero(~finite)}: "
                        f"{actions}; actions must be finite numbers"
                    )
                rows = sorted({int(ids[r]) for r in np.nonzero(~finite)[0]})
                raise errors.EpisodeError(
                    f"actions of environments {rows} have non-finite values; actions must be "
                    "finite numbers"
                )
        # Equal to np.clip for finite values, and a third of its cost on small arrays.
        return np.minimum(np.maximum(actions, self._low), self._high)


def physics_steps(
    substeps: int,
    offsets: Sequence[int] | np.ndarray,
    advance: Callable[[int], None],
    sample: Callable[[int], None],
    substep_hooks: Callable[[bool], None] | None = None,
) -> bool:
    """Run one control step's `substeps` physics steps: `advance(k)` runs k of them, and
    `sample(offset)` samples what is due after physics step `offset` (1..substeps - 1) of
    the control step, for each of `offsets` (ascending). With `substep_hooks`, the steps
    run one at a time, `substep_hooks(True)` before each and `substep_hooks(False)` after
    it, sampling after every one but the last. Returns whether something is due after the
    last physics step: the caller samples it, `sample(substeps)`, once the `after_step`
    hooks have run, so an observation agrees with what they changed (dm_control's order: a
    task whose `after_step` advances a goal shows the new goal in the same step's
    observation)."""
    last_due = len(offsets) > 0 and offsets[-1] == substeps
    if substep_hooks is not None:
        for offset in range(1, substeps + 1):
            substep_hooks(True)
            advance(1)
            substep_hooks(False)
            if offset < substeps:
                sample(offset)
        return last_due
    done = 0
    for offset in offsets:
        if offset == substeps:
            break
        advance(offset - done)
        sample(offset)
        done = offset
    if done < substeps:
        advance(substeps - done)
    return last_due


def substep_hooks(
    task_hooks: hooks.Hooks,
    physics: mjcf.Physics,
    action: np.ndarray,
    random_state: np.random.RandomState,
    before: bool,
) -> None:
    """One environment's hooks around a physics step: before it, the task's
    `before_substep` (with the action) and the entities'; after it, everyone's
    `after_substep`."""
    if before:
        for hook in task_hooks.task_before_substep:
            hook(physics, action, random_state)
        for hook in task_hooks.before_substep:
            hook(physics, random_state)
        for hook in task_hooks.extra_before_substep:
            hook(physics, action, random_state)
    else:
        for hook in task_hooks.after_substep:
            hook(physics, random_state)


def invalid_state(physics: mjcf.Physics) -> str | None:
    """Why MuJoCo reported `physics`' state invalid (bad qpos, qvel, qacc or ctrl), or None."""
    try:
        physics.check_invalid_state()
    except mjcf.PhysicsError as e:
        return str(e)
    return None


def diverged(message: str, stacklevel: int, environment: int | None = None) -> dict[str, str]:
    """Warn (DivergenceWarning, at `stacklevel` from the caller) that the episode of
    `environment` (None: the one) was truncated because of `message`; returns the info
    entries of that step. Its reward is 0 and it is not terminated."""
    where = "" if environment is None else f"environment {environment}: "
    warnings.warn(
        f"{where}episode truncated: {message}", errors.DivergenceWarning, stacklevel=stacklevel + 1
    )
    return {"physics_error": message}


def writes_controls(function: F) -> F:
    """Mark Task's batched `before_step`, which writes the actions to every actuator's
    ctrl and does nothing else: one environment writes a checked action to its physics
    directly instead (`TaskStep.writes_controls`), the same values without the batch of
    one's conversions."""
    function._composer_writes_controls = True  # type: ignore[attr-defined]
    return function


class Outcome(NamedTuple):
    """What the batched methods said of n environments: rewards (n,), terminations (n,)
    bool and discounts (n,), each an array, or the one value of every row where the method
    is Task's default (`protocol.constant_rows`, not called), or None where the single form
    runs; and info entries of (n, ...) each."""

    rewards: np.ndarray | float | None
    terminations: np.ndarray | bool | None
    discounts: np.ndarray | float | None
    info: dict[str, np.ndarray]


class _Rows:
    """One per-step method with a row per environment (reward, termination, discount):
    its batched form (None: the single form runs), the value all its rows hold (Task's
    defaults, not called), and its name and dtype for checking what it returns."""

    __slots__ = ("dtype", "method", "name", "value")

    def __init__(self, method: Callable[..., Any] | None, name: str, dtype: type) -> None:
        self.method = method
        self.value = protocol.NOT_CONSTANT if method is None else protocol.constant(method)
        self.name = f"{name}_batch"
        self.dtype = dtype

    def rows(self, physics: protocol.BatchPhysics) -> Any:
        """The (n,) rows of the environments of `physics`, or the one value of every row
        (a constant method's, not called); None for the single form."""
        if self.method is None:
            return None
        if self.value is not protocol.NOT_CONSTANT:
            return self.value
        return protocol.check_rows(self.name, self.method(physics), physics.num_envs, self.dtype)

    def first(self, physics: protocol.BatchPhysics) -> Any:
        """The row of the one environment of `physics`, a batch of one (batched form)."""
        if self.value is not protocol.NOT_CONSTANT:
            return self.value
        return protocol.check_rows(self.name, self.method(physics), 1, self.dtype)[0]  # type: ignore[misc]


class TaskStep:
    """How a task's per-step methods run (`composer.batch`): the batched form over a
    BatchPhysics of the environments of a step, the single form once per environment.
    Resolved once per compile; `single` names the methods that run per environment."""

    def __init__(self, task: Task) -> None:
        """Resolve every per-step method of `task`."""
        forms = {name: protocol.batched_method(task, name) for name in protocol.BATCHABLE}
        self.single = tuple(name for name, form in forms.items() if form is None)
        self._before = forms["before_step"]
        # Task's own: the actions written to ctrl (`writes_controls`), nothing else.
        self.writes_controls = getattr(self._before, "_composer_writes_controls", False)
        after, info = forms["after_step"], forms["get_info"]
        self._after = None if after is None or hooks.is_noop(after) else after
        self._reward = _Rows(forms["get_reward"], "get_reward", np.float64)
        self._terminate = _Rows(forms["should_terminate_episode"], "should_terminate_episode", bool)
        self._discount = _Rows(forms["get_discount"], "get_discount", np.float64)
        self._info = info
        self._info_entries = info is not None and not hooks.is_noop(info)
        self._batched_outcome = all(forms[name] is not None for name in protocol.BATCHABLE[2:])

    # -- the batched forms, over the environments of a BatchPhysics ------------------------

    def apply(self, physics: protocol.BatchPhysics, actions: np.ndarray) -> bool:
        """Run the batched `before_step` with (n, action size) actions; whether it ran."""
        if self._before is None:
            return False
        self._before(physics, actions)
        return True

    def finish(self, physics: protocol.BatchPhysics) -> bool:
        """Run the batched `after_step`; whether it ran (not for Task's empty one)."""
        if self._after is None:
            return False
        self._after(physics)
        return True

    def outcome(self, physics: protocol.BatchPhysics) -> Outcome:
        """The batched methods' rewards, terminations, discounts and info entries, each
        checked to hold a row per environment (see `Outcome`). Raises BatchError if one
        does not."""
        info = {}
        if self._info_entries:
            info = protocol.check_info(self._info(physics), physics.num_envs)  # type: ignore[misc]
        return Outcome(
            self._reward.rows(physics),
            self._terminate.rows(physics),
            self._discount.rows(physics),
            info,
        )

    # -- the single forms, once per environment ------------------------------------------

    def applies_each(self, task_hooks: hooks.Hooks) -> bool:
        """Whether `apply_each` has anything to run."""
        return self._before is None or bool(task_hooks.before_step or task_hooks.extra_before_step)

    def apply_each(
        self,
        task: Task,
        task_hooks: hooks.Hooks,
        physics: mjcf.Physics,
        action: np.ndarray,
        random_state: np.random.RandomState,
    ) -> None:
        """In one environment: the task's single `before_step` (unless batched), then the
        entities' `before_step` hooks, then the extra ones (with the action)."""
        if self._before is None:
            task.before_step(physics, action, random_state)
        for hook in task_hooks.before_step:
            hook(physics, random_state)
        for hook in task_hooks.extra_before_step:
            hook(physics, action, random_state)

    def finishes_each(self, task_hooks: hooks.Hooks) -> bool:
        """Whether `finish_each` has anything to run."""
        return "after_step" in self.single or bool(task_hooks.after_step)

    def finish_each(
        self,
        task: Task,
        task_hooks: hooks.Hooks,
        physics: mjcf.Physics,
        random_state: np.random.RandomState,
    ) -> None:
        """In one environment: the task's single `after_step` (unless batched), then the
        entities' `after_step` hooks."""
        if "after_step" in self.single:
            task.after_step(physics, random_state)
        for hook in task_hooks.after_step:
            hook(physics, random_state)

    def outcome_each(
        self, task: Task, physics: mjcf.Physics
    ) -> tuple[float | None, bool | None, dict[str, Any]]:
        """In one environment, the single forms: (reward or None, termination or None, the
        info entries of `get_info` and `get_discount`) where they are not batched."""
        reward = terminated = None
        if self._reward.method is None:
            reward = float(task.get_reward(physics))
        if self._terminate.method is None:
            terminated = bool(task.should_terminate_episode(physics))
        info = task.get_info(physics) if self._info is None else {}
        if self._discount.method is None:
            info["discount"] = task.get_discount(physics)
        return reward, terminated, info

    def outcome_of_one(
        self, physics: protocol.BatchPhysics, task: Task, own: mjcf.Physics
    ) -> tuple[float, bool, dict[str, Any]]:
        """(reward, terminated, info) of one environment: the batched forms over its batch
        of one `physics`, the single ones on its own physics `own`."""
        if self._batched_outcome:  # every form batched: nothing of outcome_each's runs
            reward: float | None = float(self._reward.first(physics))
            terminated: bool | None = bool(self._terminate.first(physics))
            info: dict[str, Any] = {}
        else:
            reward, terminated, info = self.outcome_each(task, own)
        if reward is None:
            reward = float(self._reward.first(physics))
        if terminated is None:
            terminated = bool(self._terminate.first(physics))
        if self._info_entries:
            entries = protocol.check_info(self._info(physics), 1)  # type: ignore[misc]
            for key, values in entries.items():
                info[key] = protocol.first_row(values)
        if self._discount.method is not None:
            info["discount"] = float(self._discount.first(physics))
        return reward, terminated, info
