"""Bindings: the rows of every MjModel/MjData field that belong to a set of objects of one kind.

    JOINT = mujoco.mjtObj.mjOBJ_JOINT
    legs = physics._binding(JOINT, np.array([3, 4, 5]))   # or physics.bind(joint_elements)
    legs.qpos               # data.qpos rows of the three joints (via jnt_qposadr), shape (3,)
    legs.qpos = [0.1, 0.2, 0.3]                           # writes data.qpos
    legs.range              # model.jnt_range rows, shape (3, 2); `jnt_range` works too
    legs.damping[0] = 2.0   # model.dof_damping, written through
    root = physics._binding(JOINT, 0)                     # one object: no leading axis
    root.qpos.shape         # (7,) for a free joint; a hinge gives (1,)

Attributes are the fields `mjcf.fields.kind_fields(kind)` lists, under their short names
(`range` for `jnt_range`, `xpos` for a geom's `geom_xpos`) and full names. For a list of ids, a
field with one row per object comes with a leading axis of len(ids); an addressed field (qpos,
qvel, sensordata, act ...) comes as the objects' rows concatenated, so a free joint contributes
7 qpos rows. A single id drops the leading axis (a body's `xpos` is (3,), its `mass` a 0-d view).

Views and copies: when the bound rows are evenly spaced (a run, or every k-th row), a read is a
numpy view of the MjModel/MjData buffer. Otherwise it is a copy whose item assignments
(`b.qpos[0] = 1`, `b.qpos[:] += 1`) write the whole copy back; other in-place writes to such a
copy (`out=`, `np.copyto`, writes through a slice of it) do not. Assigning the attribute always
writes through. Index arrays are computed once per binding; a read costs one numpy index.
A binding reads the physics' current MjData: it stays valid through `reset()` and pickling, and
raises BindingError once the physics holds another model.
"""

from __future__ import annotations

import difflib
import functools
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mjcf import errors, fields

if TYPE_CHECKING:
    from mjcf.physics import Physics

Key = int | slice | tuple | np.ndarray


class WriteThrough(np.ndarray):
    """A copy of bound rows no slice covers, whose item assignments write back to the source.

    Only the array a binding returned writes back; arrays derived from it (slices, ufunc
    results) are plain copies that share its class.
    """

    __slots__ = ("_source",)  # (target array, index into it, True)

    def __setitem__(self, key: Any, value: Any) -> None:
        super().__setitem__(key, value)
        source = getattr(self, "_source", None)  # unset on arrays derived from this one
        if source is not None:
            source[0][source[1]] = self.view(np.ndarray)

    def __repr__(self) -> str:
        return repr(self.view(np.ndarray))


class Binding:
    """Fields of the objects `ids` of one `kind`, read and written in one physics.

    Make bindings with `Physics._binding(kind, ids)`: the physics caches them and tells them
    when it changes MjData, which a binding made directly would not hear.
    """

    __slots__ = (
        "__weakref__",
        "_cache",
        "_data",
        "_ids",
        "_keys",
        "_kind",
        "_model",
        "_physics",
        "_single",
    )
    _fields: dict[str, fields.Field] = {}

    def __init__(self, physics: Physics, kind: mujoco.mjtObj, ids: int | np.ndarray) -> None:
        """Validate ids; raises BindingError if empty, duplicated or out of range."""
        model = physics._model
        single = np.ndim(ids) == 0
        array = np.atleast_1d(np.asarray(ids))
        name = fields.kind_name(kind)
        if array.size == 0:
            raise errors.BindingError(f"cannot bind an empty list of {name}s")
        if array.ndim != 1 or not np.issubdtype(array.dtype, np.integer):
            raise errors.BindingError(
                f"{name} ids must be an int or a 1-D list of ints, got {ids!r}"
            )
        n = fields.count(model, kind)
        bad = array[(array < 0) | (array >= n)]
        if bad.size:
            raise errors.BindingError(
                f"{name} id {int(bad[0])} is out of range: the model has {n} {name}s"
            )
        if np.unique(array).size != array.size:
            raise errors.BindingError(
                f"{name} ids must not repeat (writes would race), got {array.tolist()}"
            )
        self.__setstate__(
            {"physics": physics, "kind": kind, "ids": array.astype(np.intp), "single": single}
        )
        object.__setattr__(self, "_model", model)
        object.__setattr__(self, "_data", physics._data)
        physics._live_bindings.add(self)  # so that the physics can `_detach` us

    def __reduce__(self) -> tuple[Any, tuple[dict[str, Any]]]:
        # By state, not by class: binding classes are made at run time, one per kind.
        return _restore, (self.__getstate__(),)

    def __getstate__(self) -> dict[str, Any]:
        # Cached arrays would unpickle as detached copies: keep only what says what is bound.
        return {"physics": self._physics, "kind": int(self._kind), "ids": self._ids,
                "single": self._single}  # fmt: skip

    def __setstate__(self, state: dict[str, Any]) -> None:
        """Bind `state`'s ids; the model and data are adopted at the first read (`_entry`)."""
        object.__setattr__(self, "_physics", state["physics"])
        object.__setattr__(self, "_kind", mujoco.mjtObj(state["kind"]))
        object.__setattr__(self, "_ids", state["ids"])
        object.__setattr__(self, "_single", state["single"])
        object.__setattr__(self, "_model", None)
        object.__setattr__(self, "_data", None)
        object.__setattr__(self, "_cache", {})
        object.__setattr__(self, "_keys", {})

    @property
    def kind(self) -> mujoco.mjtObj:
        """The object kind (mujoco.mjtObj) this binding indexes."""
        return self._kind

    @property
    def ids(self) -> np.ndarray | int:
        """The bound object id (single binding) or ids in binding order."""
        return int(self._ids[0]) if self._single else self._ids.copy()

    def _entry(self, name: str) -> tuple[np.ndarray, Key, bool]:
        """(field array, key, key is fancy) for attribute `name`, refreshed if data changed."""
        physics = self._physics
        if physics._data is not self._data:
            if self._model is None:  # unpickled: adopt the physics' model
                object.__setattr__(self, "_model", physics._model)
                physics._live_bindings.add(self)  # so that `_detach` reaches us
            elif physics._model is not self._model:
                raise errors.BindingError(
                    f"this {fields.kind_name(self._kind)} binding was made for a model the "
                    "physics no longer holds; bind again"
                )
            # New MjData for the same model: the cached arrays are stale.
            object.__setattr__(self, "_data", physics._data)
            self._cache.clear()
        entry = self._cache.get(name)
        if entry is None:
            field = self._fields[name]
            key = self._key(field)
            source = self._model if field.struct == "model" else self._data
            array = getattr(source, field.name)
            entry = self._cache[name] = (array, key, isinstance(key, np.ndarray))
        return entry

    def _key(self, field: fields.Field) -> Key:
        """The index into `field`'s first axis for the bound ids (cached per address scheme)."""
        address = field.address
        key = self._keys.get(address)
        if key is not None:
            return key
        rows, counts = fields.row_index(self._model, address, self._ids)
        one_row_each = address is None or address.one_each
        if address is not None and address.one_each and not counts.all():
            missing = self._ids[counts == 0]
            names = fields.names(self._model, self._kind)
            raise errors.BindingError(
                f"{fields.kind_name(self._kind)} "
                f"{', '.join(repr(names[i] or i) for i in missing)} own no rows of "
                f"'{field.name}' (indexed by {address.start})"
            )
        if one_row_each and (counts == 1).all():
            # One row each: index like a per-object field; a single object drops the axis.
            key = (int(rows[0]), Ellipsis) if self._single else _compact(rows)
        else:
            key = _compact(rows)
        self._keys[address] = key
        return key

    def _read(self, name: str) -> np.ndarray:
        entry = self._entry(name)
        array, key, fancy = entry
        if fancy:
            out = array[key].view(WriteThrough)
            out._source = entry
            return out
        return array[key]

    def _detach(self) -> None:
        """Drop cached arrays: the physics is about to hold another MjData (or MjModel)."""
        self._cache.clear()

    def _write(self, name: str, value: Any) -> None:
        array, key, _ = self._entry(name)
        try:
            array[key] = value
        except (ValueError, TypeError) as e:
            shape = np.shape(value)
            raise errors.BindingError(
                f"cannot write {shape}-shaped values to '{name}' of {self._describe()}: "
                f"the bound rows have shape {array[key].shape}"
            ) from e

    def __getattr__(self, name: str) -> Any:
        if name in self._fields:
            # A field property raised BindingError, which Python, seeing an AttributeError,
            # answered by calling us: read again to let that error through.
            return self._read(name)
        raise errors.BindingError(self._unknown(name))

    def __setattr__(self, name: str, value: Any) -> None:
        # Hot path first: a cached field is written with one numpy assignment.
        entry = self._cache.get(name)
        if entry is not None:
            try:
                entry[0][entry[1]] = value
                return
            except (ValueError, TypeError):
                pass  # _write raises the explanatory error
        if name not in self._fields:
            raise errors.BindingError(self._unknown(name))
        self._write(name, value)

    def __dir__(self) -> list[str]:
        return sorted({*super().__dir__(), *self._fields})

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self._describe()}>"

    def _describe(self) -> str:
        names = fields.names(self._model, self._kind)
        shown = [names[i] or str(i) for i in self._ids]
        if self._single:
            return f"{fields.kind_name(self._kind)} {shown[0]!r}"
        return f"{len(shown)} {fields.kind_name(self._kind)}s {shown}"

    def _unknown(self, name: str) -> str:
        valid = sorted(n for n, f in self._fields.items() if n == fields.short_name(f))
        close = difflib.get_close_matches(name, list(self._fields), n=3)
        hint = f" (did you mean {', '.join(map(repr, close))}?)" if close else ""
        return (
            f"{fields.kind_name(self._kind)} bindings have no field '{name}'{hint}; "
            f"valid fields: {', '.join(valid)} (full MjModel/MjData names work too)"
        )


def _compact(rows: np.ndarray) -> slice | np.ndarray:
    """A slice (a view when read) if `rows` ascend by a constant step, else the index array."""
    if rows.size == 0:
        return slice(0, 0)
    start = int(rows[0])
    if rows.size == 1:
        return slice(start, start + 1)
    step = int(rows[1]) - start
    if step > 0 and (np.diff(rows) == step).all():
        return slice(start, int(rows[-1]) + 1, step)
    return rows


def _field_property(name: str) -> property:
    def fget(self: Binding) -> np.ndarray:
        # Hot path, inlined: one dict lookup and one numpy index. The physics empties
        # `_cache` when it changes MjData (see `_detach`), so a hit is never stale.
        entry = self._cache.get(name)
        if entry is None:
            return self._read(name)
        array, key, fancy = entry
        if not fancy:
            return array[key]
        out = array[key].view(WriteThrough)
        out._source = entry
        return out

    # Writes go through Binding.__setattr__, which every assignment reaches first anyway.
    return property(fget, doc=f"The bound rows of {name}.")


@functools.cache
def binding_class(kind: mujoco.mjtObj) -> type[Binding]:
    """The Binding subclass for `kind`, with one property per field; raises BindingError."""
    kind = mujoco.mjtObj(kind)
    if kind not in fields.KINDS:
        valid = ", ".join(fields.kind_name(k) for k in fields.KINDS)
        raise errors.BindingError(
            f"no MjModel/MjData field is indexed by {kind.name}; kinds that are: {valid}"
        )
    table = dict(fields.kind_fields(kind))
    namespace: dict[str, Any] = {"__slots__": (), "_fields": table}
    for name in table:
        namespace[name] = _field_property(name)
    class_name = "".join(part.capitalize() for part in fields.kind_name(kind).split("_"))
    return type(f"{class_name}Binding", (Binding,), namespace)


def _restore(state: dict[str, Any]) -> Binding:
    """Unpickle a binding; it adopts its (possibly still unpickling) physics at first read."""
    binding = object.__new__(binding_class(mujoco.mjtObj(state["kind"])))
    binding.__setstate__(state)
    return binding
