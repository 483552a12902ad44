"""The exceptions composer raises: one base, `composer.Error`, and a subclass per kind of
mistake. Messages name the entity, observable or task involved and what was expected.

    try:
        env = composer.Environment(task)
    except composer.Error as e:       # any composer mistake
        ...

MuJoCo divergence during a step is not raised: the step is truncated, `info['physics_error']`
holds the message, and a `DivergenceWarning` is emitted.
"""

from __future__ import annotations


class Error(Exception):
    """Base class of every error composer raises."""


class _PlainMessage(Exception):
    """Shows the message as given (KeyError alone would show its repr)."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


class EntityError(Error, RuntimeError):
    """An entity was attached, detached or posed in a way its model does not allow."""


class PoseError(EntityError, ValueError):
    """A pose, velocity, vector or matrix an entity cannot take: the wrong shape, or a
    velocity of an entity without a free joint."""


class ObservableError(Error, ValueError):
    """An observable is misconfigured, or its value does not match its declared shape."""


class ObservableNotFoundError(_PlainMessage, ObservableError, AttributeError, KeyError):
    """An entity has no observable of the name asked for (by attribute or by key)."""


class ObservableOptionError(ObservableError, AttributeError):
    """`configure` or `set_options` was given an option observables do not have."""


class UnknownAggregatorError(_PlainMessage, ObservableError, KeyError):
    """An aggregator was named that is not one of `AGGREGATORS`."""


class TaskError(Error, ValueError):
    """A task is misconfigured: timesteps that do not divide, a missing root entity, an
    action or observation space that changed after a recompile."""


class EpisodeInitializationError(Error, RuntimeError):
    """An episode could not be set up (e.g. an initializer found no valid pose); the
    environment retries the reset, up to its `max_reset_attempts`, as dm_control does."""


class EpisodeError(Error):
    """The environment was used out of order, e.g. `step()` before `reset()` or after the
    episode ended, or with an action of the wrong shape."""


class OverrideError(Error, NotImplementedError):
    """A subclass of `composer.Environment` overrides one of dm_control's internal methods
    in a way this environment cannot keep (`composer.dm_internals`); the message names the
    method and what to do instead. Raised when the environment is made, or for what a
    method returns, when it returns it."""


class VariationError(Error, ValueError):
    """A variation or variator was given values it cannot use."""


class InitializerError(Error, ValueError):
    """An initializer was given arguments it cannot use (no props, attempts below 1)."""


class RewardError(TaskError):
    """A reward shaping function (`composer.utils.rewards`) was given parameters it cannot
    use: bounds out of order, a negative margin, an unknown sigmoid, a value at the margin
    out of range."""


class TransformationError(Error, ValueError):
    """A rotation helper (`composer.utils.transformations`) was given a value outside its
    domain, e.g. a quaternion's scalar part beyond [-1, 1] by more than the tolerance."""


class EulerOrderingError(_PlainMessage, TransformationError, KeyError):
    """An Euler angle ordering `composer.utils.transformations` does not have (a KeyError
    too, as dm_control's lookup raises)."""


class InverseKinematicsError(Error, ValueError):
    """`composer.utils.inverse_kinematics` was given no target, joints of the wrong type or
    no step to take."""


class PlacementError(EpisodeInitializationError):
    """An initializer found no valid pose for a prop within its attempts."""


class BatchError(Error):
    """A batched method or observable returned values of the wrong shape, or asked a batch
    for something it cannot give (a field MuJoCo's batch does not hold, an assignment to a
    field that is not state)."""


class DivergenceWarning(RuntimeWarning):
    """MuJoCo reported an invalid state during a step; the episode was truncated."""
