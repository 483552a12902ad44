"""VectorPhysics: the simulations of a VectorEnvironment as (n, ...) numpy arrays, the
`composer.BatchPhysics` it passes to batched methods (the contract is `composer.batch`'s).

    def get_reward_batch(self, physics):                 # a Task's batched method
        return -np.abs(physics.bind(self.pendulum.hinge).qpos[:, 0])   # (n,): a row each
    physics.bind(self.arm.actuators).ctrl = u            # writes state fields, (n, nu)
    physics.field('time')                                # a whole MjData field, (n,)

Promise: derived fields (xpos, sensordata ...) describe the current state, as
`mjcf.Physics` bindings' do; reads are copies (`VectorPhysics` says what is read how).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np
from mujoco import batch as mujoco_batch

import mjcf
from composer.batch import protocol, timer
from mjcf.sim import fields, staleness

_ACC = staleness.Stage.ACCELERATION

if TYPE_CHECKING:
    from composer.environment import Environment
    from composer.task import Task


class _Field:
    """One bound field: where its rows are in the batch (`key`: a slice where they are a
    run), the per-environment shape, the stage a read needs fresh and what a write
    changes."""

    __slots__ = ("effect", "key", "model_name", "rows", "shape", "source", "stage", "writable")

    def __init__(
        self,
        source: np.ndarray | None,
        model_name: str,
        rows: np.ndarray,
        shape: tuple,
        stage: staleness.Stage,
        effect: staleness.Effect,
    ) -> None:
        self.source = source  # (num_envs, ...) batch array; None for an MjModel field
        self.model_name = model_name
        self.rows = rows
        run = rows.size > 0 and bool((np.diff(rows) == 1).all())
        self.key = slice(int(rows[0]), int(rows[-1]) + 1) if run else rows
        self.shape = shape
        self.stage = stage
        self.effect = effect
        self.writable = source is not None and source.flags.writeable


class BatchBinding(protocol.Binding):
    """Fields of bound elements in the environments of a VectorPhysics, (n, ...) each.
    Raises mjcf.BindingError for a field the elements' kind does not have."""

    __slots__ = ("_elements", "_fields", "_physics", "_reads")

    _physics: VectorPhysics
    _elements: Any  # an element or a tuple of elements of one kind
    _fields: dict[str, _Field]
    _reads: dict[str, Callable[[], np.ndarray]]  # each field's read, made at its first

    def __init__(self, physics: VectorPhysics, elements: Any, fields: dict[str, _Field]) -> None:
        """Bind `elements` (of the first environment's model) in the environments of
        `physics`; `fields` holds their fields as resolved, shared by every view."""
        object.__setattr__(self, "_physics", physics)
        object.__setattr__(self, "_elements", elements)
        object.__setattr__(self, "_fields", fields)
        object.__setattr__(self, "_reads", {})

    @staticmethod
    def _field_property(name: str) -> property:
        # A read is every step's: one lookup of the field's read, made once, and its call.
        def read(self: BatchBinding) -> np.ndarray:
            found = self._reads.get(name)
            if found is None:
                found = self._reads[name] = self._physics._reader(self._field(name))
            return found()

        return property(read)

    def _field(self, name: str) -> _Field:
        found = self._fields.get(name)
        if found is None:
            found = self._fields[name] = self._physics.simulations._resolve(self._elements, name)
        return found

    def _get(self, name: str) -> np.ndarray:
        found = self._reads.get(name)
        if found is None:
            found = self._reads[name] = self._physics._reader(self._field(name))
        return found()

    def _set(self, name: str, value: Any) -> None:
        self._physics._write(self._field(name), name, value)

    def __repr__(self) -> str:
        return f"<BatchBinding of {self._elements!r}>"


class _Lag:
    """Which simulations' derived fields of one stage lag their state: a flag a simulation,
    kept as one value (`every`) while all of them hold it, so that a call on every
    simulation (a step, a refresh) sets them without writing a row."""

    __slots__ = ("every", "rows")

    def __init__(self, nsim: int) -> None:
        self.every: bool | None = True  # the value of every row; None: the rows differ
        self.rows = np.ones(nsim, dtype=bool)

    def set(self, ids: Any, value: bool) -> None:
        """Flag simulations `ids` (None: all; an index or an index array) `value`."""
        value = bool(value)
        if ids is None:
            self.every = value
            return
        every = self.every
        if every is not None:
            if every is value:
                return
            self.rows[:] = every
            self.every = None
        self.rows[ids] = value

    def of(self, ids: np.ndarray | None) -> bool | np.ndarray:
        """The flags of simulations `ids` (None: all): one bool while all are alike."""
        if self.every is not None:
            return self.every
        return self.rows if ids is None else self.rows[ids]


class Simulations:
    """The simulations of a VectorEnvironment, and which of their derived fields in the
    batch lag their state: what every VectorPhysics over them shares.

        simulations = Simulations(batch, envs)
        simulations.physics()           # the VectorPhysics of every environment
        simulations.physics(ids)        # of environments `ids` (ascending)
        simulations.stepped(ids, True, mujoco.mjtStage.mjSTAGE_VEL)  # stepped, stages too
        simulations.changed(i)          # it wrote environment i's state from its MjData
    """

    def __init__(self, batch: mujoco_batch.Batch, envs: Sequence[Environment]) -> None:
        """Serve `batch`, whose simulation i is `envs[i]`; the first environment's physics
        resolves elements."""
        self.batch = batch
        self.envs = envs
        self.template = envs[0].physics
        self.nsim = batch.nsim
        # Per simulation: whether the batch's derived fields lag its state rows, for the
        # position/velocity stages and for the acceleration stage.
        self._pos = _Lag(batch.nsim)
        self._acc = _Lag(batch.nsim)
        self._all = np.arange(batch.nsim)
        self._sources: dict[str, np.ndarray] = {}  # the MjData fields bound from the batch
        # Whether a derived field (not state) was ever bound: until then a step need not
        # compute the stages of the new state (`stepped`).
        self.reads_derived = False
        # Whether a read made the acceleration stage current after a step (touch sensors,
        # accelerometers ...): from then on a step computes it (`step_stage`), in the
        # batch's own threaded call, as it does the position and velocity stages.
        self.reads_acceleration = False
        # Per bound elements: their binding class (None: no elements) and resolved fields.
        self._bound: dict[Any, tuple[type[BatchBinding] | None, dict[str, _Field]]] = {}
        self._every = VectorPhysics(self, None)

    def physics(self, ids: np.ndarray | None = None) -> VectorPhysics:
        """The VectorPhysics of environments `ids` (ascending; None: every one)."""
        if ids is None or len(ids) == self.nsim:
            return self._every
        return VectorPhysics(self, ids)

    def step_stage(self, consistent: bool) -> mujoco.mjtStage:
        """The stages a step should compute at the new state (`Batch.step`'s `stage`):
        none while nothing reads a derived field or reads need not describe the new state
        (not `consistent`), else those reads have needed."""
        if not (consistent and self.reads_derived):
            return mujoco.mjtStage.mjSTAGE_NONE
        if self.reads_acceleration:
            return mujoco.mjtStage.mjSTAGE_ACC
        return mujoco.mjtStage.mjSTAGE_VEL

    def stepped(self, ids: np.ndarray | None, consistent: bool, computed: mujoco.mjtStage) -> None:
        """Simulations `ids` (None: all) were stepped. `consistent` (reads must describe
        the new state): the stages of the new state up to `computed` (`step_stage`) are
        current, the later ones lag; not `consistent`: their fields lag as mj_step leaves
        them, which reads then give."""
        self._pos.set(ids, consistent and computed == mujoco.mjtStage.mjSTAGE_NONE)
        self._acc.set(ids, consistent and computed != mujoco.mjtStage.mjSTAGE_ACC)

    def changed(self, ids: Any) -> None:
        """The state rows of simulations `ids` were written from outside the batch."""
        self._pos.set(ids, True)
        self._acc.set(ids, True)

    def _wrote(self, ids: np.ndarray | None, effect: staleness.Effect) -> None:
        """Batched methods wrote the state rows of simulations `ids` (None: all)."""
        self._acc.set(ids, True)
        if effect != staleness.Effect.STEP_INPUT:
            self._pos.set(ids, True)

    def _refresh(self, ids: np.ndarray | None, stage: staleness.Stage) -> None:
        """Recompute the derived fields of simulations `ids` (ascending; None: all) that
        lag for `stage`."""
        acc = stage == _ACC
        if self._pos.every is False and not (acc and self._acc.every is not False):
            return  # a read of current fields, several a step: nothing to index
        stale = self._pos.of(ids)
        if acc:
            stale = stale | self._acc.of(ids)
        if stale is True:
            which = ids
        elif stale is False or not stale.any():
            return
        else:
            which = (self._all if ids is None else ids)[stale]
            if len(which) == self.nsim:
                which = None
        if acc:
            self.reads_acceleration = True
        # Simulations that raise here failed their step already, and are truncated.
        with contextlib.suppress(mujoco_batch.SimulationError):
            timer.untimed(
                self.batch.forward,
                which,
                mujoco.mjtStage.mjSTAGE_ACC if acc else mujoco.mjtStage.mjSTAGE_VEL,
            )
        self._pos.set(which, False)
        if acc:
            self._acc.set(which, False)

    def _source(self, name: str) -> np.ndarray:
        """MjData field `name` of every simulation, as the batch holds it. Raises
        BatchError for a field the batch does not hold."""
        source = self._sources.get(name)
        if source is not None:
            return source
        protocol.check_source(name)
        source = self._sources[name] = self.batch.bind(name)
        if name not in protocol.STATE_FIELDS:
            # MuJoCo's batch copies an output out at each call from its first bind on:
            # until the next call it holds nothing, whatever the stages say.
            self.changed(None)
            self.reads_derived = True
        return source

    def _binding(self, key: Any) -> tuple[type[BatchBinding] | None, dict[str, _Field]]:
        """How elements `key` (an element or a tuple of them) bind: their binding class
        (None for no elements) and their fields resolved so far. Raises mjcf.BindingError
        for elements of another model."""
        found = self._bound.get(key)
        if found is None:
            template = self.template.bind(key)
            if template is mjcf.sim.binding.EMPTY:
                found = (None, {})
            else:
                found = (protocol.binding_class(BatchBinding, template.kind), {})
            self._bound[key] = found
        return found

    def _resolve(self, elements: Any, name: str) -> _Field:
        """Field `name` of `elements`; raises mjcf.BindingError for one their kind has not."""
        model = self.template.model
        template = self.template.bind(list(elements) if isinstance(elements, tuple) else elements)
        value = getattr(template, name)  # raises mjcf.BindingError for an unknown field
        spec = fields.kind_fields(template.kind)[name]
        ids = np.atleast_1d(np.asarray(template.ids))
        rows, _ = fields.row_index(model, spec.address, ids)
        source = self._source(spec.name) if spec.struct == "data" else None
        if spec.name == "sensordata":
            stage = staleness.sensor_stage(model, ids)
        else:
            stage = staleness.field_stage(spec)
        effect = staleness.write_effect(spec)
        return _Field(source, spec.name, rows, np.shape(value), stage, effect)


class VectorPhysics(protocol.BatchPhysics):
    """Numpy access to the simulations of some environments of a VectorEnvironment; made by
    `Simulations.physics`. Each covers a fixed set of environments (`ids`, ascending):
    `Simulations.physics(ids)` gives the one of the environments of a call, and
    `Simulations.physics()` the one of every environment, kept with its bindings; all share
    the `Simulations`, which knows what of the batch is fresh.
    `bind(elements)` takes elements of the first environment's model, as `mjcf.Physics.bind`
    does, and gives their fields with a leading environment axis: `bind(joint).qpos` is (n, 1)
    for a hinge. Reads are copies. MjData fields come from MuJoCo's batch
    (`mujoco.batch.Batch.bind`): state fields (qpos, qvel, act, ctrl, mocap_pos, qfrc_applied
    ...) are the simulations' state and can be assigned; derived fields (xpos, sensordata ...)
    are read-only and describe the current state, as `mjcf.Physics` bindings' do: positions and
    velocities are computed after each step, and acceleration-dependent fields (qacc, touch
    sensors ...), or anything after a write of state, are recomputed for the environments read
    (`Batch.forward`) when first read. Fields MuJoCo computes only for sensors (cfrc_ext,
    subtree_linvel ...) are read per environment. MjModel fields (mass, geom_size ...) are
    read from each environment's own model, one at a time.
    """

    def __init__(self, simulations: Simulations, ids: np.ndarray | None) -> None:
        """Cover environments `ids` (ascending; None: every one) of `simulations`."""
        self.simulations = simulations
        self._ids = ids
        self._every = np.arange(simulations.nsim) if ids is None else ids
        self._count = len(self._every)
        self._bindings: dict[Any, protocol.Binding | protocol.EmptyBinding] = {}
        self._fields: dict[str, Callable[[], np.ndarray]] = {}  # `field`'s reads, by name
        self._ctrl: np.ndarray | None = None  # the batch's ctrl, once `set_control` ran

    # -- who the rows are ----------------------------------------------------------------

    @property
    def ids(self) -> np.ndarray:
        """The environments covered, ascending: row k is environment ids[k]."""
        return self._every.copy()

    @property
    def num_envs(self) -> int:
        """n, the number of rows."""
        return self._count

    @property
    def tasks(self) -> list[Task]:
        """Each row's task (per-episode state a task keeps on itself is read here)."""
        envs = self.simulations.envs
        return [envs[i].task for i in self._every]

    @property
    def random_states(self) -> list[np.random.RandomState]:
        """Each row's RandomState: draw from these to stay reproducible per environment."""
        envs = self.simulations.envs
        return [envs[i].random_state for i in self._every]

    @property
    def batch(self) -> mujoco_batch.Batch:
        """The underlying `mujoco.batch.Batch`, every environment (not only those covered)."""
        return self.simulations.batch

    # -- access --------------------------------------------------------------------------

    def bind(self, elements: Any) -> protocol.Binding | protocol.EmptyBinding:
        """The fields of `elements` (one element or an iterable of one kind, of the first
        environment's model, as `mjcf.Physics.bind` takes them), cached; no elements give
        fields of shape (n, 0). Raises mjcf.BindingError as `mjcf.Physics.bind`."""
        key = elements if isinstance(elements, mjcf.Element) else tuple(elements)
        found = self._bindings.get(key)
        if found is None:
            cls, fields = self.simulations._binding(key)
            found = protocol.EmptyBinding(self) if cls is None else cls(self, key, fields)
            self._bindings[key] = found
        return found

    def field(self, name: str) -> np.ndarray:
        """See `composer.BatchPhysics.field`."""
        read = self._fields.get(name)
        if read is None:
            read = self._fields[name] = self._field_reader(name)
        return read()

    def _field_reader(self, name: str) -> Callable[[], np.ndarray]:
        """The read of MjData field `name` of the environments covered, made once. Raises
        BatchError for a field the batch does not hold."""
        simulations = self.simulations
        source = simulations._source(name)
        stage = staleness.read_stage(name)
        if name == "sensordata":
            model = simulations.template.model
            stage = staleness.sensor_stage(model, np.arange(model.nsensor))
        ids = self._ids
        if ids is None:
            return self._fresh(stage, source.copy)
        return self._fresh(stage, lambda: source[ids])

    def _reader(self, found: _Field) -> Callable[[], np.ndarray]:
        """The read of bound field `found` of the environments covered (a new array each
        call), made once."""
        ids, source, shape = self._ids, found.source, (self._count, *found.shape)
        if source is None:
            envs, name, rows = self.simulations.envs, found.model_name, found.rows
            every = self._every

            def read_models() -> np.ndarray:
                values = [getattr(envs[i].physics.model, name)[rows] for i in every]
                return np.stack(values).reshape(shape)

            return self._fresh(found.stage, read_models)
        key = found.key
        if ids is None:
            taken = source[:, key]
            if type(key) is slice:  # a view of a run of rows, copied at each read
                view = taken.view()
                with contextlib.suppress(AttributeError):  # unless only a copy has `shape`
                    view.shape = shape
                    return self._fresh(found.stage, view.copy)
                return self._fresh(found.stage, lambda: source[:, key].reshape(shape))
            if taken.shape == shape:
                return self._fresh(found.stage, lambda: source[:, key])
            return self._fresh(found.stage, lambda: source[:, key].reshape(shape))
        index = ids[:, None]
        rows = found.rows
        return self._fresh(found.stage, lambda: source[index, rows].reshape(shape))

    def _fresh(
        self, stage: staleness.Stage, read: Callable[[], np.ndarray]
    ) -> Callable[[], np.ndarray]:
        """`read`, after recomputing what lags for `stage` in the environments covered."""
        if not stage:
            return read
        refresh, ids, lags = self.simulations._refresh, self._ids, self.simulations._pos
        if stage == _ACC:
            acc = self.simulations._acc

            def after_acc() -> np.ndarray:
                if lags.every is not False or acc.every is not False:
                    refresh(ids, stage)
                return read()

            return after_acc

        def after_pos() -> np.ndarray:
            if lags.every is not False:
                refresh(ids, stage)
            return read()

        return after_pos

    def _write(self, found: _Field, name: str, value: Any) -> None:
        """Write `value`, (n, ...) rows, to bound field `found` (named `name`) of the
        environments covered. Raises BatchError for a field batched methods cannot
        assign, mjcf.BindingError for values that do not fit."""
        source = found.source
        if not found.writable or source is None:  # no source: not writable
            raise protocol.not_writable(name, model_field=source is None)
        n = self.num_envs
        rows = protocol.rows_to_write(value, n, found.shape, name)
        rows = rows.reshape(n, len(found.rows), *source.shape[2:])
        if self._ids is None:
            source[:, found.rows] = rows
        else:
            source[self._ids[:, None], found.rows] = rows
        self.simulations._wrote(self._ids, found.effect)

    def set_control(self, controls: Any) -> None:
        """See `composer.BatchPhysics.set_control`: controls of shape (n, nu)."""
        ctrl = self._ctrl
        if ctrl is None:
            ctrl = self._ctrl = self.simulations._source("ctrl")
        rows = protocol.rows_to_write(controls, self._count, ctrl.shape[1:], "ctrl")
        if self._ids is None:
            ctrl[...] = rows
        else:
            ctrl[self._ids] = rows
        self.simulations._wrote(self._ids, staleness.Effect.STEP_INPUT)
