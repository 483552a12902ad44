"""BatchPhysics: the simulations of a VectorEnvironment as (n, ...) numpy arrays.

    def get_reward_batch(self, physics):                 # a Task's batched twin
        hinge = physics.bind(self.pendulum.hinge)        # bound once, cached
        return -np.abs(hinge.qpos[:, 0])                 # (n,): one row per environment
    physics.bind(self.arm.actuators).ctrl = u            # writes state fields, (n, nu)
    physics.field('time')                                # a whole MjData field, (n,)
    physics.ids, physics.tasks, physics.random_states    # who the n rows are

A BatchPhysics covers the environments of one call (`ids`, ascending). `bind(elements)`
takes elements of the first environment's model, as `mjcf.Physics.bind` does, and gives
their fields with a leading environment axis: `bind(joint).qpos` is (n, 1) for a hinge.
Reads are copies. MjData fields come from MuJoCo's batch (`mujoco.batch.Batch.bind`):
state fields (qpos, qvel, act, ctrl, mocap_pos, qfrc_applied ...) are the simulations'
state and can be assigned; derived fields (xpos, sensordata ...) are read-only and describe
the current state, as `mjcf.Physics` bindings' do: positions and velocities are computed
after each step, and acceleration-dependent fields (qacc, touch sensors ...), or anything
after a write of state, are recomputed for the environments read (`Batch.forward`) when
first read. Fields MuJoCo computes only for sensors (cfrc_ext, subtree_linvel ...) are
read per environment. MjModel fields (mass, geom_size ...) are read from each
environment's own model, one at a time.
"""

from __future__ import annotations

import contextlib
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np
from mujoco import batch as mujoco_batch

import mjcf
from composer.vector.protocol import BatchError
from mjcf import fields, tracking

_ACC = tracking.Stage.ACCELERATION

if TYPE_CHECKING:
    from composer.environment import Environment
    from composer.task import Task


class _Field:
    """One bound field: where its rows are in the batch, the per-environment shape, the
    stage a read needs fresh and what a write changes."""

    __slots__ = ("effect", "model_name", "rows", "shape", "source", "stage", "writable")

    def __init__(
        self,
        source: np.ndarray | None,
        model_name: str,
        rows: np.ndarray,
        shape: tuple,
        stage: tracking.Stage,
        effect: tracking.Effect,
    ) -> None:
        self.source = source  # (num_envs, ...) batch array; None for an MjModel field
        self.model_name = model_name
        self.rows = rows
        self.shape = shape
        self.stage = stage
        self.effect = effect
        self.writable = source is not None and source.flags.writeable


class BatchBinding:
    """Fields of bound elements in the environments of the current call, (n, ...) each.
    Raises mjcf.BindingError for a field the elements' kind does not have."""

    __slots__ = ("_elements", "_fields", "_physics")

    def __init__(self, physics: BatchPhysics, elements: Any) -> None:
        """Bind `elements` (of the first environment's model); resolved field by field."""
        object.__setattr__(self, "_physics", physics)
        object.__setattr__(self, "_elements", elements)
        object.__setattr__(self, "_fields", {})

    def _field(self, name: str) -> _Field:
        found = self._fields.get(name)
        if found is None:
            found = self._fields[name] = self._physics._resolve(self._elements, name)
        return found

    def __getattr__(self, name: str) -> np.ndarray:
        if name.startswith("__"):
            raise AttributeError(name)
        return self._physics._read(self._field(name))

    def __setattr__(self, name: str, value: Any) -> None:
        self._physics._write(self._field(name), name, value)

    def __repr__(self) -> str:
        return f"<BatchBinding of {self._elements!r}>"


class _EmptyBatchBinding:
    """The binding of no elements: every field reads (n, 0); only empty values write."""

    __slots__ = ("_physics",)

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


class BatchPhysics:
    """Numpy access to the simulations of the environments of one call (see the module)."""

    def __init__(self, batch: mujoco_batch.Batch, envs: Sequence[Environment]) -> None:
        """Serve `batch`, whose simulation i is `envs[i]`; the first environment's physics
        resolves elements."""
        self._batch = batch
        self._envs = envs
        self._template = envs[0].physics
        self._ids: np.ndarray | None = None  # None: every environment
        self._bindings: dict[Any, BatchBinding] = {}
        # Per simulation: whether the batch's derived fields lag its state rows, for the
        # position/velocity stages and for the acceleration stage.
        self._pos_stale = np.ones(batch.nsim, dtype=bool)
        self._acc_stale = np.ones(batch.nsim, dtype=bool)

    # -- who the rows are ----------------------------------------------------------------

    @property
    def ids(self) -> np.ndarray:
        """The environments of this call, ascending: row k is environment ids[k]."""
        if self._ids is None:
            return np.arange(self._batch.nsim)
        return self._ids.copy()

    @property
    def num_envs(self) -> int:
        """n, the number of rows."""
        return self._batch.nsim if self._ids is None else len(self._ids)

    @property
    def tasks(self) -> list[Task]:
        """Each row's task (per-episode state a task keeps on itself is read here)."""
        return [self._envs[i].task for i in self.ids]

    @property
    def random_states(self) -> list[np.random.RandomState]:
        """Each row's RandomState: draw from these to stay reproducible per environment."""
        return [self._envs[i].random_state for i in self.ids]

    @property
    def batch(self) -> mujoco_batch.Batch:
        """The underlying `mujoco.batch.Batch`, every environment (not only this call's)."""
        return self._batch

    def _select(self, ids: np.ndarray | None) -> None:
        """Cover environments `ids` (ascending), or every one with None."""
        self._ids = ids

    def _stepped(self, ids: np.ndarray, consistent: bool) -> None:
        """Simulations `ids` were stepped: with stage mjSTAGE_VEL (`consistent`), only their
        acceleration stage lags; after plain steps their fields lag as mj_step leaves them."""
        self._pos_stale[ids] = False
        self._acc_stale[ids] = consistent

    def _changed(self, ids: Any) -> None:
        """The state rows of simulations `ids` were written from outside the batch."""
        self._pos_stale[ids] = True
        self._acc_stale[ids] = True

    def _refresh(self, stage: tracking.Stage) -> None:
        """Recompute the derived fields of the covered simulations that lag for `stage`."""
        ids = self.ids
        stale = self._pos_stale[ids]
        if stage == _ACC:
            stale = stale | self._acc_stale[ids]
        if not stale.any():
            return
        which = ids[stale]
        batch_stage = mujoco.mjtStage.mjSTAGE_ACC if stage == _ACC else mujoco.mjtStage.mjSTAGE_VEL
        # Simulations that raise here failed their step already, and are truncated.
        with contextlib.suppress(mujoco_batch.SimulationError):
            self._batch.forward(None if len(which) == self._batch.nsim else which, batch_stage)
        self._pos_stale[which] = False
        if stage == _ACC:
            self._acc_stale[which] = False

    # -- access --------------------------------------------------------------------------

    def bind(self, elements: Any) -> BatchBinding:
        """The fields of `elements` (one element or an iterable of one kind, of the first
        environment's model, as `mjcf.Physics.bind` takes them), cached; no elements give
        fields of shape (n, 0). Raises mjcf.BindingError as `mjcf.Physics.bind`."""
        key = elements if isinstance(elements, mjcf.Element) else tuple(elements)
        found = self._bindings.get(key)
        if found is None:
            single = isinstance(key, mjcf.Element)
            template = self._template.bind(key)  # raises BindingError for foreign elements
            if template is mjcf.binding.EMPTY:
                return _EmptyBatchBinding(self)
            found = self._bindings[key] = BatchBinding(self, key if single else list(key))
        return found

    def field(self, name: str) -> np.ndarray:
        """MjData field `name` of every row, (n, ...), a copy (up to date, as a bound
        field's). Raises BatchError for a field MuJoCo's batch does not bind (arena arrays
        such as efc_*)."""
        source = self._source(name)
        stage = tracking.read_stage(name)
        if name == "sensordata":
            model = self._template.model
            stage = tracking.sensor_stage(model, np.arange(model.nsensor))
        if stage:
            self._refresh(stage)
        return source.copy() if self._ids is None else source[self._ids]

    def _source(self, name: str) -> np.ndarray:
        if name in tracking.ON_DEMAND:
            raise BatchError(
                f"MjData field {name!r} is computed by MuJoCo only for sensors that need it, "
                "so the batch does not hold it; it is read per environment"
            )
        if name not in mujoco_batch.DATA_FIELDS:
            raise BatchError(
                f"MjData field {name!r} is not available from MuJoCo's batch (it binds "
                f"{len(mujoco_batch.DATA_FIELDS)} fields; arena arrays such as efc_* vary in "
                "size); compute it in the per-environment method instead"
            )
        return self._batch.bind(name)

    def _resolve(self, elements: Any, name: str) -> _Field:
        template = self._template.bind(elements)
        value = getattr(template, name)  # raises mjcf.BindingError for an unknown field
        spec = fields.kind_fields(template.kind)[name]
        ids = np.atleast_1d(np.asarray(template.ids))
        rows, _ = fields.row_index(self._template.model, spec.address, ids)
        source = self._source(spec.name) if spec.struct == "data" else None
        if spec.name == "sensordata":
            stage = tracking.sensor_stage(self._template.model, ids)
        else:
            stage = tracking.field_stage(spec)
        effect = tracking.write_effect(spec)
        return _Field(source, spec.name, rows, np.shape(value), stage, effect)

    def _read(self, found: _Field) -> np.ndarray:
        if found.stage:
            self._refresh(found.stage)
        ids, source = self._ids, found.source
        if source is None:
            envs = self._envs if ids is None else [self._envs[i] for i in ids]
            rows = [getattr(env.physics.model, found.model_name)[found.rows] for env in envs]
            return np.stack(rows).reshape(len(rows), *found.shape)
        if ids is None:
            values = np.take(source, found.rows, axis=1)
        else:
            values = source[ids[:, None], found.rows]
        return values.reshape(len(values), *found.shape)

    def _write(self, found: _Field, name: str, value: Any) -> None:
        if not found.writable:
            what = "an MjModel field" if found.source is None else "derived by MuJoCo"
            raise BatchError(
                f"cannot assign {name!r}: it is {what}; batched methods write state fields "
                "(qpos, qvel, act, ctrl, mocap_pos, qfrc_applied, xfrc_applied ...)"
            )
        n = self.num_envs
        try:
            rows = np.broadcast_to(np.asarray(value, dtype=mujoco.MJTNUM_DTYPE), (n, *found.shape))
        except ValueError as e:
            raise mjcf.BindingError(
                f"cannot write {np.shape(value)}-shaped values to {name!r} of {n} environments: "
                f"the bound rows have shape {(n, *found.shape)}"
            ) from e
        rows = rows.reshape(n, len(found.rows), *found.source.shape[2:])
        if self._ids is None:
            found.source[:, found.rows] = rows
        else:
            found.source[self._ids[:, None], found.rows] = rows
        written = slice(None) if self._ids is None else self._ids
        self._acc_stale[written] = True
        if found.effect != tracking.Effect.STEP_INPUT:
            self._pos_stale[written] = True
