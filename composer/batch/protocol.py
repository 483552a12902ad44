"""The batch protocol: a task's per-step methods written once, for one environment or many.

    class Swing(composer.Task):
        def get_reward_batch(self, physics):                 # physics: a BatchPhysics
            hinge = physics.bind(self.pendulum.hinge)        # bound once, cached
            return -np.abs(hinge.qpos[:, 0])                 # (n,): a row per environment

Promises: one formula, so one environment (a batch of one) and many compute the same values
to the last bit (`BatchedTask`); which form runs is `batched_method`'s rule; what MuJoCo's
batch cannot give raises BatchError in a batch of one too (`BatchPhysics`).
"""

from __future__ import annotations

import abc
import operator
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Protocol, TypeVar

import mujoco
import numpy as np
from mujoco import batch as mujoco_batch

import mjcf
from composer import errors
from mjcf.sim import fields, staleness

if TYPE_CHECKING:
    from composer.task import Task

# The per-step task methods that have a batched form, named `<method>_batch`.
BATCHABLE = (
    "before_step",
    "after_step",
    "get_reward",
    "should_terminate_episode",
    "get_discount",
    "get_info",
)


class BatchPhysics(abc.ABC):
    """The simulations of n environments as (n, ...) numpy arrays: what batched methods get.
    `composer.vector`'s serves a VectorEnvironment; `composer.BatchOfOne` serves one
    environment.

    `bind(elements)` gives the elements' fields with a leading environment axis (a hinge's
    `qpos` is (n, 1), a motor's `ctrl` (n,)); reads are copies; state fields (qpos, qvel, act,
    ctrl, mocap_pos, qfrc_applied ...) can be assigned; `field(name)` reads a whole MjData
    field; `ids`, `tasks` and `random_states` say whose rows they are. Elements are bound on one
    model (the first environment's; all share its layout). Per-episode state a task keeps on
    `self` is per environment: read it from `physics.tasks`, or better, keep it in the
    simulation (a mocap body, a site). What MuJoCo's batch cannot give (arena arrays such as
    efc_*, fields MuJoCo computes only for sensors, assigning a derived or MjModel field) raises
    BatchError in a batch of one too, so a task that runs alone runs vectorized.
    """

    @property
    @abc.abstractmethod
    def num_envs(self) -> int:
        """n, the number of rows."""

    @property
    @abc.abstractmethod
    def ids(self) -> np.ndarray:
        """The environments of the rows, ascending: row k is environment ids[k]."""

    @property
    @abc.abstractmethod
    def tasks(self) -> list[Task]:
        """Each row's task (per-episode state a task keeps on itself is read here)."""

    @property
    @abc.abstractmethod
    def random_states(self) -> list[np.random.RandomState]:
        """Each row's RandomState: draw from these to stay reproducible per environment."""

    @abc.abstractmethod
    def bind(self, elements: Any) -> Any:
        """The fields of `elements` (one element or an iterable of one kind, as
        `mjcf.Physics.bind` takes them), each with a leading axis of n rows; no elements
        give fields of shape (n, 0). Raises mjcf.BindingError as `mjcf.Physics.bind`."""

    @abc.abstractmethod
    def field(self, name: str) -> np.ndarray:
        """MjData field `name` of every row, (n, ...), a copy, up to date. Raises
        BatchError for a field MuJoCo's batch does not hold (`check_source`)."""

    @abc.abstractmethod
    def set_control(self, controls: Any) -> None:
        """Write every actuator's control, (n, nu). Raises mjcf.BindingError for values
        that do not fit."""


class BatchedTask(Protocol):
    """The batched forms of a Task's per-step methods. Each gets a BatchPhysics over the
    environments of the call.

    A task writes each per-step method once, in one of two forms:
    - the single-environment form, as in dm_control: `get_reward(physics)` gets the
      environment's `mjcf.Physics` and returns a float. Simplest; a `VectorEnvironment` runs it
      once per environment, on that environment's materialized MjData (correct, but slower).
    - the batched form: `get_reward_batch(physics)` gets a `BatchPhysics` over n environments
      and returns one row per environment. A `VectorEnvironment` runs it once for all of them;
      a single `composer.Environment` runs the same method with a batch of one
      (`composer.BatchOfOne`, n = 1). One formula, so one environment and many compute the
      same values to the last bit.

    The methods are `before_step`, `after_step`, `get_reward`, `should_terminate_episode`,
    `get_discount` and `get_info` (`BATCHABLE`; signatures below). `Task` defines
    both forms of each: its defaults are batched (write the actions to every actuator's
    `ctrl`, no termination, discount 1, no info entries, nothing after the step), and its
    single forms run the batched ones with a batch of one, so `task.get_reward(physics)` works
    whichever form a task wrote.
    """

    def before_step_batch(self, physics: BatchPhysics, actions: np.ndarray) -> None:
        """Apply `actions`, (n, action size) float64, already clipped to the action space."""

    def after_step_batch(self, physics: BatchPhysics) -> None:
        """After the physics steps of a control step, before observations are read."""

    def get_reward_batch(self, physics: BatchPhysics) -> np.ndarray:
        """The rewards of the control step that just ended, shape (n,)."""

    def should_terminate_episode_batch(self, physics: BatchPhysics) -> np.ndarray:
        """Whether each episode ended in a terminal state, shape (n,) bool."""

    def get_discount_batch(self, physics: BatchPhysics) -> np.ndarray:
        """The discount of each step, shape (n,)."""

    def get_info_batch(self, physics: BatchPhysics) -> dict[str, np.ndarray]:
        """Extra info entries, each an array of shape (n, ...)."""


# -- which form runs -------------------------------------------------------------------


def defining_class(cls: type, name: str) -> type | None:
    """The class of `cls`'s MRO that defines attribute `name`, or None."""
    for klass in cls.__mro__:
        if name in vars(klass):
            return klass
    return None


def prefers_batched(cls: type, single: str, batched: str) -> bool:
    """Whether objects of `cls` have method `batched` defined on the class defining method
    `single` or on a subclass of it: then the batched form is the one that runs."""
    twin = defining_class(cls, batched)
    if twin is None:
        return False
    owner = defining_class(cls, single)
    return owner is None or issubclass(twin, owner)


def batched_method(task: Any, name: str) -> Callable[..., Any] | None:
    """`task`'s bound `<name>_batch` when it is the form of per-step method `name` that runs,
    else None: the single-environment form runs.

    The batched form runs when it is defined on the same class as the single one or on a
    subclass of it. So a subclass that overrides only `get_reward` gets its own
    `get_reward`, not an inherited, stale `get_reward_batch`; a class defining both runs the
    batched one everywhere (its single form is then what direct calls get).
    """
    if prefers_batched(type(task), name, f"{name}_batch"):
        return getattr(task, f"{name}_batch")
    return None


def constant_rows(value: Any, dtype: type, doc: str) -> Callable[[Any, BatchPhysics], np.ndarray]:
    """A batched method (`doc` its docstring) whose every row is `value`, as Task's
    defaults are: environments that run it use `value` without calling it (`constant`)."""

    def method(self: Any, physics: BatchPhysics) -> np.ndarray:
        return np.full(physics.num_envs, value, dtype=dtype)

    method.__doc__ = doc
    method._composer_constant = value  # type: ignore[attr-defined]
    return method


NOT_CONSTANT = object()


def constant(method: Callable[..., Any]) -> Any:
    """The value every row of batched `method` holds when it was made by `constant_rows`,
    else NOT_CONSTANT."""
    return getattr(method, "_composer_constant", NOT_CONSTANT)


def check_rows(name: str, values: Any, n: int, dtype: type) -> np.ndarray:
    """`values` as an (n,) array of `dtype`; raises BatchError naming method `name`."""
    array: np.ndarray = np.asarray(values, dtype=dtype)
    if array.shape != (n,):
        raise errors.BatchError(
            f"{name} returned shape {array.shape} for {n} environments; expected ({n},)"
        )
    return array


def check_info(entries: Any, n: int) -> dict[str, np.ndarray]:
    """`get_info_batch`'s `entries` as arrays of n rows each; raises BatchError for an
    entry without one row per environment."""
    checked = {}
    for key, values in entries.items():
        array = np.asarray(values)
        if array.shape[:1] != (n,):
            raise errors.BatchError(
                f"get_info_batch entry {key!r} has shape {array.shape}; expected ({n}, ...)"
            )
        checked[key] = array
    return checked


def first_row(values: np.ndarray) -> Any:
    """Row 0 of a batched result, as one environment's value: a Python number or bool for
    a row of one number (what a single-environment method returns), else an array."""
    row = values[0]
    return row.item() if values.ndim == 1 else row


# -- what a batch gives: the rules both kinds of BatchPhysics keep -------------------------

STATE_FIELDS = staleness.STATE_FIELDS  # the MjData fields a batch holds as state, writable
_MJTNUM = np.dtype(mujoco.MJTNUM_DTYPE)


def check_source(name: str) -> None:
    """Raise BatchError if MuJoCo's batch does not hold MjData field `name`."""
    if name in staleness.ON_DEMAND:
        raise errors.BatchError(
            f"MjData field {name!r} is computed by MuJoCo only for sensors that need it, "
            "so the batch does not hold it; it is read per environment"
        )
    if name not in mujoco_batch.DATA_FIELDS:
        raise errors.BatchError(
            f"MjData field {name!r} is not available from MuJoCo's batch (it binds "
            f"{len(mujoco_batch.DATA_FIELDS)} fields; arena arrays such as efc_* vary in "
            "size); compute it in the per-environment method instead"
        )


def not_writable(name: str, model_field: bool) -> errors.BatchError:
    """The error for assigning field `name` (an MjModel field, or one MuJoCo derives)."""
    what = "an MjModel field" if model_field else "derived by MuJoCo"
    return errors.BatchError(
        f"cannot assign {name!r}: it is {what}; batched methods write state fields "
        "(qpos, qvel, act, ctrl, mocap_pos, qfrc_applied, xfrc_applied ...)"
    )


def rows_to_write(value: Any, n: int, shape: tuple[int, ...], name: str) -> np.ndarray:
    """`value` broadcast to the (n, *shape) rows of field `name`, as mjtNum. Raises
    mjcf.BindingError for values that do not fit."""
    if type(value) is np.ndarray and value.dtype == _MJTNUM and value.shape == (n, *shape):
        return value  # the rows already: np.broadcast_to costs microseconds
    try:
        return np.broadcast_to(np.asarray(value, dtype=mujoco.MJTNUM_DTYPE), (n, *shape))
    except ValueError as e:
        raise mjcf.BindingError(
            f"cannot write {np.shape(value)}-shaped values to {name!r} of {n} environments: "
            f"the bound rows have shape {(n, *shape)}"
        ) from e


class Binding:
    """What `BatchPhysics.bind` gives: the fields of bound elements as attributes, each
    with a leading axis of n rows (`binding.qpos`; assigning one writes it). Subclasses
    implement `_get(name)` and `_set(name, value)`, and are made concrete per kind of
    element by `binding_class`. Raises mjcf.BindingError for a field the kind has not."""

    __slots__ = ()

    @staticmethod
    def _field_property(name: str) -> property:
        """The property of field `name` in the classes `binding_class` makes: `_get`."""
        return property(operator.methodcaller("_get", name))

    def _get(self, name: str) -> np.ndarray:
        raise NotImplementedError

    def _set(self, name: str, value: Any) -> None:
        raise NotImplementedError

    def __getattr__(self, name: str) -> np.ndarray:
        # Only names without a property get here: unknown fields, which _get reports.
        if name.startswith("__"):
            raise AttributeError(name)
        return self._get(name)

    def __setattr__(self, name: str, value: Any) -> None:
        self._set(name, value)


_BINDING_CLASSES: dict[tuple[type, int], type[Any]] = {}
_B = TypeVar("_B", bound=Binding)


def binding_class(base: type[_B], kind: mujoco.mjtObj) -> type[_B]:
    """`base` with a property for every field of elements of `kind` (its short and full
    names): reading one is a property lookup, where `__getattr__` would cost a failed
    lookup first (about a microsecond, per read, every step). Made once per kind."""
    key = (base, int(kind))
    cls = _BINDING_CLASSES.get(key)
    if cls is None:
        namespace: dict[str, Any] = {"__slots__": ()}
        for name in fields.kind_fields(kind):
            namespace[name] = base._field_property(name)
        kind_name = fields.kind_name(kind).capitalize()
        cls = _BINDING_CLASSES[key] = type(
            f"{kind_name}{base.__name__.lstrip('_')}", (base,), namespace
        )
    return cls


class EmptyBinding:
    """The binding of no elements: every field reads (n, 0); only empty values write."""

    __slots__ = ("_physics",)

    _physics: BatchPhysics

    def __init__(self, physics: BatchPhysics) -> None:
        object.__setattr__(self, "_physics", physics)

    def __getattr__(self, name: str) -> np.ndarray:
        if name.startswith("__"):
            raise AttributeError(name)
        return np.zeros((self._physics.num_envs, 0))

    def __setattr__(self, name: str, value: Any) -> None:
        if np.size(value) != 0:
            raise mjcf.BindingError(
                f"cannot write {np.shape(value)}-shaped values to {name!r} of a binding of no "
                "elements: only an empty value fits"
            )
