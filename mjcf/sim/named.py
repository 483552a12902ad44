"""Named indexing: MjModel/MjData fields indexed by the names of the objects that own their rows.

    physics.named.data.qpos["hip"]               # data.qpos[jnt_qposadr[hip] : +1], shape (1,)
    physics.named.data.qpos["root"][:3] = 0, 0, 1 # a free joint's 7 rows are a view
    physics.named.data.xpos[["torso", "head"], ["x", "z"]]   # numpy pairs lists, as dm_control
    physics.named.model.geom_rgba["floor"] = [1, 0, 0, 1]
    print(physics.named.data.qpos)               # a table of names and values

Every field `mjcf.sim.fields.indexed_fields(struct)` lists is here, indexed as `FieldIndexer`
says; writes and reads are tracked as bindings' are (`mjcf.sim.binding.Binding`).
"""

from __future__ import annotations

import dataclasses
import functools
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mjcf import errors
from mjcf.sim import binding as binding_module
from mjcf.sim import binding_index, fields, staleness

if TYPE_CHECKING:
    from mjcf.sim.physics import Physics

_REPR_ROWS = 40  # longer fields print their head and tail only


@dataclasses.dataclass(frozen=True)
class Axis:
    """The row axis of a field: `names[i]` is the name of the object owning row i ('' if none)."""

    kind: mujoco.mjtObj
    names: tuple[str, ...]

    def convert_key_item(self, key: Any) -> Any:
        """`key` with object names turned into row indices, as dm_control's axes do: a
        name gives its row (an int) or rows (a slice), a list or array of names the
        concatenated rows; anything else is returned as it is. Raises NotFoundError for a
        name that owns no row."""
        if isinstance(key, str):
            rows = self._rows(key)
            return int(rows[0]) if rows.size == 1 else slice(int(rows[0]), int(rows[-1]) + 1)
        if isinstance(key, list | tuple | np.ndarray) and any(isinstance(k, str) for k in key):
            parts = [self._rows(k) if isinstance(k, str) else np.atleast_1d(k) for k in key]
            return np.concatenate(parts).astype(np.intp)
        return key

    def _rows(self, name: str) -> np.ndarray:
        rows = np.flatnonzero(np.asarray(self.names, dtype=object) == name)
        if not rows.size:
            hint = errors.did_you_mean(name, [n for n in self.names if n])
            raise errors.NotFoundError(f"no row named {name!r}{hint}")
        return rows


@dataclasses.dataclass(frozen=True)
class Axes:
    """The named axes of a field; only rows are named."""

    row: Axis


class _NameTable:
    """Object names of one kind and the rows each owns under one address scheme."""

    def __init__(self, model: mujoco.MjModel, field: fields.Field) -> None:
        self.kind = field.kind
        self.address = field.address
        self.names = fields.names(model, field.kind)
        ids = np.arange(len(self.names), dtype=np.intp)
        if field.address is None:
            self.starts, self.counts = ids, np.ones_like(ids)
        else:
            self.starts, self.counts = fields.rows(model, field.address)
        self.ids = {name: i for i, name in enumerate(self.names) if name}
        self._model = model
        self._field = field

    @functools.cached_property
    def row_names(self) -> tuple[str, ...]:
        """The name of the object owning each row ('' for none); built when first asked for."""
        ids = np.arange(len(self.names), dtype=np.intp)
        owners = np.full(int(getattr(self._model, self._field.size)), -1, dtype=np.intp)
        rows, _ = fields.row_index(self._model, self._field.address, ids)
        owners[rows] = np.repeat(ids, self.counts)
        return tuple(self.names[i] if i >= 0 else "" for i in owners)

    @functools.cached_property
    def first_rows(self) -> frozenset[int]:
        """The first row of every object that owns rows (where repr prints its name)."""
        return frozenset(int(s) for s, c in zip(self.starts, self.counts, strict=True) if c)

    def key(self, name: str, field_name: str) -> int | slice:
        """The index of `name`'s rows: an int for one-row-per-object fields, else a slice."""
        i = self.ids.get(name)
        one_each = self.address is not None and self.address.one_each
        if i is None or (one_each and self.counts[i] == 0):
            valid = [n for n, j in self.ids.items() if self.counts[j] or not one_each]
            hint = errors.did_you_mean(name, valid)
            kind = fields.kind_name(self.kind)
            owns = "" if i is None else f"; {kind} {name!r} owns no rows of it"
            raise errors.NotFoundError(
                f"{field_name} has no row named {name!r}{hint}{owns}; "
                f"{kind} names: {valid[:20]}{' ...' if len(valid) > 20 else ''}"
            )
        start, count = int(self.starts[i]), int(self.counts[i])
        if self.address is None or (one_each and count == 1):
            return start
        # An object may own no rows (a stateless actuator's act): an empty slice, not -1:-1.
        return slice(start, start + count) if count else slice(0, 0)

    def rows(self, names: list[Any], field_name: str) -> np.ndarray:
        """The rows of several names (or raw int rows) concatenated, as an index array."""
        parts = []
        for item in names:
            key = self.key(item, field_name) if isinstance(item, str) else item
            if isinstance(key, slice):
                parts.append(np.arange(key.start, key.stop, dtype=np.intp))
            else:
                parts.append(np.array([key], dtype=np.intp))
        return np.concatenate(parts) if parts else np.zeros(0, dtype=np.intp)


class FieldIndexer:
    """One MjModel/MjData field, indexed by object names as well as numpy keys.

        physics.named.data.sensordata["touch"]       # sensor_adr / sensor_dim slice
        physics.named.data.qvel[3:6], physics.named.data.qpos[mask]   # ints, slices, masks
        physics.named.data.xpos["torso", 2]          # a tuple indexes the following axes too
        physics.named.data.xpos["torso", "z"]        # columns by name: x y z, qw qx qy qz ...
        physics.named.data.qpos.axes.row.names       # the owner name of every row

    A name stands for the rows its object owns: one row (an int index, so numpy drops the
    axis) for a field with one row per object, the object's block (a slice, kept as an
    axis) for an addressed field (qpos, qvel, sensordata, act ...). A list of names
    concatenates their rows. Reads follow numpy: a name or a slice gives a view, a list a
    copy. Assignment through any key writes through, and item assignment into a returned
    array of a state or model field does too. Writes and reads are tracked as bindings'
    are (`mjcf.sim.binding.Binding`): a derived field read after a state write is
    recomputed first. Column names are `mjcf.sim.fields.column_names`. Unnamed objects are
    reachable by integer index only."""

    __slots__ = ("_field", "_mask", "_physics", "_table", "_table_model")

    def __init__(self, physics: Physics, field: fields.Field) -> None:
        self._physics = physics
        self._field = field
        self._table: _NameTable | None = None
        self._table_model: mujoco.MjModel | None = None
        self._mask: int | None = None  # what a read needs fresh (per model: sensors vary)

    @property
    def field(self) -> fields.Field:
        """How this field is indexed (kind, address scheme, MjModel or MjData)."""
        return self._field

    @property
    def array(self) -> np.ndarray:
        """The whole MjModel/MjData array (a view, brought up to date for a derived field;
        writes into it are not tracked)."""
        self._refresh()
        return self._raw()

    def _raw(self) -> np.ndarray:
        physics = self._physics
        source = physics.model if self._field.struct == "model" else physics.data
        return getattr(source, self._field.name)

    def _refresh(self) -> None:
        """Recompute derived fields if a tracked write made this one stale."""
        physics = self._physics
        mask = self._read_mask()
        if mask:
            binding_module.bring_up_to_date(physics, mask)

    def _read_mask(self) -> int:
        self._names()  # re-resolves the mask when the model changed
        if self._mask is None:
            field, model = self._field, self._physics._model
            if field.name == "sensordata":
                stage = staleness.sensor_stage(model, np.arange(model.nsensor))
            elif field.name in staleness.ON_DEMAND:
                binding_module.compute_on_demand(self._physics, field.name)
                stage = staleness.Stage.ACCELERATION
            else:
                stage = staleness.field_stage(field)
            self._mask = binding_module.READ_MASK[stage]
        return self._mask

    @property
    def axes(self) -> Axes:
        """The names of the objects owning each row: `axes.row.names`."""
        table = self._names()
        return Axes(Axis(table.kind, table.row_names))

    @property
    def shape(self) -> tuple[int, ...]:
        """The shape of the whole array."""
        return self._raw().shape

    def __len__(self) -> int:
        return len(self._raw())

    def __array__(self, dtype: Any = None, copy: bool | None = None) -> np.ndarray:
        return np.array(self.array, dtype=dtype, copy=copy)

    def _target(self, key: Any, given: Any) -> binding_module.Target:
        """How to write rows `key` (resolved from the user's `given`)."""
        return binding_module.Target(
            self._physics, self._raw(), key, self._field, self._read_mask(),
            lambda: f"{self._field.name}[{given!r}]",
        )  # fmt: skip

    def _names(self) -> _NameTable:
        # Re-resolve when the physics holds another model than the one the names came from.
        model = self._physics._model
        if self._table is None or self._table_model is not model:
            self._table = _NameTable(model, self._field)
            self._table_model = model
            self._mask = None
        return self._table

    def _resolve(self, key: Any) -> Any:
        """Translate names in `key` to numpy indices: object names on the first axis,
        column names (mjcf.sim.fields.column_names) on the second."""
        if isinstance(key, tuple):
            if not key:
                return key
            rows = self._resolve(key[0])
            if len(key) > 1 and _has_name(key[1]):
                return (rows, self._columns(key[1]), *key[2:])
            return (rows, *key[1:])
        if isinstance(key, str):
            return self._names().key(key, self._field.name)
        if isinstance(key, np.ndarray) and key.dtype.kind in "US":
            rows = self._names().rows(key.reshape(-1).tolist(), self._field.name)
            # One row per name keeps the key's shape, for broadcasting against columns.
            return rows.reshape(key.shape) if rows.size == key.size else rows
        if isinstance(key, list) and any(isinstance(k, str) for k in key):
            return self._names().rows(key, self._field.name)
        return key

    def _columns(self, key: Any) -> Any:
        try:
            return binding_index.resolve_columns(self._field, key)
        except errors.BindingError as e:
            raise errors.NotFoundError(str(e)) from None

    def __getitem__(self, key: Any) -> Any:
        """Rows by name, list of names, int, slice or mask (and columns by index or name);
        raises NotFoundError for an unknown name, BindingError for a bad index."""
        self._refresh()
        array = self._raw()
        resolved = self._resolve(key)
        try:
            target = self._target(resolved, key)
            if target.effect not in (staleness.Effect.MODEL, staleness.Effect.MODEL_CONSTANT):
                return array[resolved]  # plain numpy, as bindings' MjData fields
            out = array.view(binding_module.WriteThrough)[resolved]
        except IndexError as e:
            raise errors.BindingError(f"{self._field.name}[{key!r}]: {e}") from e
        if not isinstance(out, binding_module.WriteThrough):
            return out  # one number: a copy, like numpy's scalars
        target.fancy = not np.may_share_memory(out, array)
        binding_module.write_through(out, target)
        return out

    def __setitem__(self, key: Any, value: Any) -> None:
        """Write rows selected as in __getitem__; raises BindingError for a shape mismatch."""
        resolved = self._resolve(key)
        try:
            self._target(resolved, key).write(value)
        except IndexError as e:
            raise errors.BindingError(f"{self._field.name}[{key!r}]: {e}") from e

    def __repr__(self) -> str:
        field = self._field
        array = self.array
        table = self._names()
        via = f" via {field.address.start}" if field.address else ""
        lines = [
            f"{field.struct}.{field.name}: {array.shape[0]} row{'' if len(array) == 1 else 's'} of "
            f"{fields.kind_name(field.kind)}{via}, shape {array.shape}"
        ]
        shown: range | list[int] = range(len(array))
        if len(array) > _REPR_ROWS:
            shown = [*range(_REPR_ROWS - 5), -1, *range(len(array) - 5, len(array))]
        width = max((len(n) for n in table.row_names), default=0)
        for row in shown:
            if row < 0:
                lines.append("  ...")
                continue
            label = table.row_names[row] if row in table.first_rows else ""
            value = np.array2string(
                np.asarray(array[row]), precision=4, suppress_small=True, max_line_width=200
            )
            lines.append(f"{row:>5}  {label:<{width}}  {value}")
        return "\n".join(lines)


def _has_name(key: Any) -> bool:
    if isinstance(key, str):
        return True
    if isinstance(key, list | tuple):
        return any(isinstance(k, str) for k in key)
    return isinstance(key, np.ndarray) and key.dtype.kind in "US"


class StructView:
    """The indexed fields of MjModel (`physics.named.model`) or MjData (`physics.named.data`)."""

    __slots__ = ("_indexers", "_physics", "_struct")

    def __init__(self, physics: Physics, struct: fields.Struct) -> None:
        self._physics = physics
        self._struct = struct
        self._indexers: dict[str, FieldIndexer] = {}

    def __getattr__(self, name: str) -> FieldIndexer:
        indexer = self._indexers.get(name)
        if indexer is not None:
            return indexer
        field = fields.indexed_fields(self._struct).get(name)
        if field is None:
            raise errors.BindingError(self._unknown(name))
        indexer = self._indexers[name] = FieldIndexer(self._physics, field)
        return indexer

    def __setattr__(self, name: str, value: Any) -> None:
        if name in self.__slots__:
            object.__setattr__(self, name, value)
            return
        # `named.model.geom_rgba = x` would silently do nothing useful: write the rows instead.
        self.__getattr__(name)[:] = value

    def __dir__(self) -> list[str]:
        return sorted({*super().__dir__(), *fields.indexed_fields(self._struct)})

    def _unknown(self, name: str) -> str:
        raw = self._physics.model if self._struct == "model" else self._physics.data
        label = "MjModel" if self._struct == "model" else "MjData"
        if isinstance(getattr(raw, name, None), np.ndarray):
            return (
                f"{label} field '{name}' is not indexed by any kind of object; "
                f"use physics.{self._struct}.{name}"
            )
        hint = errors.did_you_mean(name, fields.indexed_fields(self._struct))
        return f"{label} has no indexed field '{name}'{hint}"


class NamedAccess:
    """`physics.named`: `.model` and `.data` views of every field indexed by object names."""

    __slots__ = ("data", "model")

    def __init__(self, physics: Physics) -> None:
        self.model = StructView(physics, "model")
        self.data = StructView(physics, "data")
