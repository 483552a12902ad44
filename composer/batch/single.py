"""BatchOfOne: one environment's `mjcf.Physics` as a batch of one, for batched methods.

    view = env.batch_physics                         # what a single Environment passes
    view = BatchOfOne(physics, task)                 # one of your own (no random state)
    view.bind(hinge).qpos                            # (1, 1): the hinge's qpos, a copy
    view.bind(motor).ctrl = [[0.5]]                  # writes through physics.bind(motor)
    task.get_reward_batch(view)[0]                   # the reward of this one environment

Promise: one environment computes what a `VectorEnvironment` computes for each of its own,
bit for bit; a strict view (the default) raises the BatchErrors MuJoCo's batch would.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

import mjcf
from composer import errors
from composer.batch import protocol
from mjcf.sim import fields, staleness

if TYPE_CHECKING:
    from composer.task import Task

_MJTNUM = mujoco.MJTNUM_DTYPE


class _Field:
    """How one bound field reads and writes in a batch of one: its shape in the physics,
    the dtype of a read (mjtNum for state, as the batch holds it), whether a read is a
    plain view to copy, whether it may be assigned and whether it is an MjModel field."""

    __slots__ = ("dtype", "model", "ndmin", "plain", "shape", "writable")

    def __init__(
        self, shape: tuple[int, ...], dtype: Any, plain: bool, writable: bool, model: bool
    ) -> None:
        self.shape = shape
        self.ndmin = len(shape) + 1
        self.dtype = dtype
        self.plain = plain
        self.writable = writable
        self.model = model


class _Binding(protocol.Binding):
    """Fields of bound elements with a leading axis of one row (see `BatchOfOne`)."""

    __slots__ = ("_binding", "_fields", "_reads", "_strict")

    _binding: Any  # the mjcf.Physics binding of the elements
    _fields: dict[str, _Field]
    _reads: dict[str, Callable[[], np.ndarray]]  # each field's read, made at its first
    _strict: bool

    def __init__(self, binding: Any, strict: bool) -> None:
        object.__setattr__(self, "_binding", binding)
        object.__setattr__(self, "_fields", {})
        object.__setattr__(self, "_reads", {})
        object.__setattr__(self, "_strict", strict)

    @staticmethod
    def _field_property(name: str) -> property:
        # A read is every step's: one lookup of the field's read, made once, and its call.
        def read(self: _Binding) -> np.ndarray:
            found = self._reads.get(name)
            if found is None:
                found = self._read(name)
            return found()

        return property(read)

    def _read(self, name: str) -> Callable[[], np.ndarray]:
        """Field `name`'s read, made once: the physics' binding read (fresh as it makes it),
        copied with the leading axis. Raises BindingError, BatchError."""
        found = self._fields.get(name) or self._field(name)
        binding, dtype, ndmin = self._binding, found.dtype, found.ndmin

        def view() -> np.ndarray:  # a plain view of the rows: copied at once
            return getattr(binding, name)[None].copy()

        def converted() -> np.ndarray:  # a write-back copy, or a dtype to change
            return np.array(getattr(binding, name), dtype=dtype, ndmin=ndmin)

        read = view if found.plain else converted
        self._reads[name] = read
        return read

    def _field(self, name: str) -> _Field:
        binding = self._binding
        value = getattr(binding, name)  # raises mjcf.BindingError for an unknown field
        spec = fields.kind_fields(binding.kind)[name]
        model = spec.struct == "model"
        state = not model and spec.name in protocol.STATE_FIELDS
        if self._strict and not model:
            protocol.check_source(spec.name)
        # A read copies the physics' rows: at once for a plain view, through np.array for
        # a copy that writes itself back (mjcf.sim.binding.WriteThrough) or a dtype to change.
        dtype = _MJTNUM if state else None
        plain = type(value) is np.ndarray and (dtype is None or value.dtype == dtype)
        writable = state or not self._strict
        found = _Field(np.shape(value), dtype, plain, writable, model)
        self._fields[name] = found
        return found

    def _get(self, name: str) -> np.ndarray:
        found = self._reads.get(name)
        return (found or self._read(name))()

    def _set(self, name: str, value: Any) -> None:
        found = self._fields.get(name) or self._field(name)
        if not found.writable:
            raise protocol.not_writable(name, model_field=found.model)
        rows = np.asarray(value, dtype=_MJTNUM)
        if rows.shape[:1] != (1,) or rows.shape[1:] != found.shape:
            rows = protocol.rows_to_write(rows, 1, found.shape, name)
        setattr(self._binding, name, rows[0])

    def __repr__(self) -> str:
        return f"<batch-of-one binding of {self._binding!r}>"


class BatchOfOne(protocol.BatchPhysics):
    """One environment's simulation as a `composer.BatchPhysics` of one row.

    A single `composer.Environment` runs a task's batched methods (`composer.batch`) with
    its view (made at each compile, with its task and random state; the task's own single
    forms run their batched forms with it too), so one environment computes what a
    `VectorEnvironment` computes for each of its environments, bit for bit. It reads and
    writes through the physics' own bindings (cached, fresh as `mjcf.sim.binding` promises), adding
    the leading axis of one row: reads are new arrays (state fields as mjtNum, as MuJoCo's batch
    holds them), writes take (1, ...) rows or anything that broadcasts to them.

    A strict view (the default) gives exactly what MuJoCo's batch gives a `VectorEnvironment`
    (`composer.protocol.check_source`): the same fields readable, the same state fields
    writable, the same BatchErrors otherwise, so a batched method that runs here runs
    vectorized. Observables are read through a permissive one (`strict=False`, every field
    `mjcf.Physics` reads), since a VectorEnvironment reads the ones its batch cannot serve per
    environment, through that same single-environment reader.
    """

    num_envs = 1

    def __init__(
        self,
        physics: mjcf.Physics,
        task: Task | None = None,
        random_state: Callable[[], np.random.RandomState] | None = None,
        strict: bool = True,
    ) -> None:
        """Serve `physics`; `task` and `random_state()` (a function returning the current
        RandomState) are what `tasks` and `random_states` give. `strict` (see the class
        docstring): only what MuJoCo's batch gives."""
        self._physics = physics
        self._task = task
        self._random_state = random_state
        self._strict = strict
        self._model: mujoco.MjModel | None = None
        self._bindings: dict[Any, Any] = {}
        self._readers: dict[str, Callable[[], Any]] = {}

    @property
    def physics(self) -> mjcf.Physics:
        """The environment's own physics."""
        return self._physics

    @property
    def ids(self) -> np.ndarray:
        """[0]: the one environment."""
        return np.zeros(1, dtype=np.intp)

    @property
    def tasks(self) -> list[Task]:
        """[the task]; raises BatchError for a view made without one."""
        if self._task is None:
            raise errors.BatchError("this batch of one was made without a task")
        return [self._task]

    @property
    def random_states(self) -> list[np.random.RandomState]:
        """[the environment's RandomState]; raises BatchError outside an environment."""
        if self._random_state is None:
            raise errors.BatchError(
                "this batch of one serves a physics outside an environment: it has no random "
                "state (an Environment's own view has its random state)"
            )
        return [self._random_state()]

    def bind(self, elements: Any) -> Any:
        """See `composer.BatchPhysics.bind`: fields of shape (1, ...)."""
        model = self._physics.model
        if model is not self._model:  # recompiled: bindings of the old model are stale
            self._model = model
            self._bindings.clear()
        key = elements if isinstance(elements, mjcf.Element) else tuple(elements)
        found = self._bindings.get(key)
        if found is None:
            binding = self._physics.bind(key)  # raises BindingError for foreign elements
            if binding is mjcf.sim.binding.EMPTY:
                found = protocol.EmptyBinding(self)
            else:
                found = protocol.binding_class(_Binding, binding.kind)(binding, self._strict)
            self._bindings[key] = found
        return found

    def field(self, name: str) -> np.ndarray:
        """See `composer.BatchPhysics.field`: shape (1, ...)."""
        reader = self._readers.get(name)
        if reader is None:
            reader = self._readers[name] = self._field_reader(name)
        return reader()

    def _field_reader(self, name: str) -> Callable[[], np.ndarray]:
        if self._strict:
            protocol.check_source(name)
        physics = self._physics
        state = name in protocol.STATE_FIELDS
        dtype = _MJTNUM if state else None
        stage = staleness.read_stage(name)
        if stage == staleness.Stage.NONE:
            return lambda: np.array(getattr(physics.data, name), dtype=dtype)[None]
        try:
            fields.indexed_field(name, "data")
        except KeyError:
            # Not indexed by object: no named view to bring it up to date, so recompute
            # whatever may be behind (a position-stage field is only after a write).
            def read() -> np.ndarray:
                if stage == staleness.Stage.ACCELERATION or physics.is_dirty:
                    physics.forward()
                value = getattr(physics.data, name)
                # MjData's counts (ncon, nefc ...) are C ints, as MuJoCo's batch gives them.
                return np.array(value, dtype=np.intc if isinstance(value, int) else None)[None]

            return read
        return lambda: np.array(getattr(physics.named.data, name).array)[None]

    def set_control(self, controls: Any) -> None:
        """See `composer.BatchPhysics.set_control`: controls of shape (1, nu)."""
        physics = self._physics
        rows = np.asarray(controls, dtype=_MJTNUM)
        shape = (physics.model.nu,)
        if rows.shape[:1] != (1,) or rows.shape[1:] != shape:
            rows = protocol.rows_to_write(rows, 1, shape, "ctrl")
        physics.set_control(rows[0])
