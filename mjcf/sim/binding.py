"""Bindings: the rows of every MjModel/MjData field that belong to a set of objects of one kind.

    hip = physics.bind(hip_joint)          # or physics.bind([j1, j2]), physics.bind_names(...)
    hip.qpos = 0.3                         # writes data.qpos at jnt_qposadr; marks physics dirty
    physics.bind(foot_site).xpos           # runs mj_forward first, so it sees qpos = 0.3
    legs = physics.bind(leg_joints)
    legs.qpos[0] += 0.1; legs["qpos", 0]   # item writes write through; dm_control's [field, col]

Fresh values, never stale ones: a read of a derived field catches up with tracked writes
first (the rules, shapes, views and copies: `Binding`). Bad binds and writes: BindingError.
"""

from __future__ import annotations

import functools
import weakref
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

import mujoco
import numpy as np

from mjcf import errors
from mjcf.sim import binding_index, fields, staleness
from mjcf.sim.binding_index import Key, split_index

# Where bound values are (rows, columns) and the empty binding have modules of their own;
# their names are importable from here as they were.
from mjcf.sim.binding_index import column_key as column_key
from mjcf.sim.binding_index import resolve_columns as resolve_columns
from mjcf.sim.empty_binding import EMPTY as EMPTY
from mjcf.sim.empty_binding import EmptyBinding as EmptyBinding

if TYPE_CHECKING:
    from mjcf.sim.physics import Physics

Effect = staleness.Effect

# Bits of `BoundPhysics._stale` (kept by the physics; defined here, where reads and writes
# test them).
ACC_BEHIND = 1  # the acceleration stage was computed for another state or other controls
POS_BEHIND = 2  # the position/velocity stages were computed for another state
LAGGING = 4  # a plain mj_step left the stages one step behind, as the caller asked
WRITTEN = 8  # state or model written through a binding since the last forward/step
# What a read of each stage must find unset, and what a write of each effect sets.
READ_MASK = {staleness.Stage.NONE: 0, staleness.Stage.POSITION: POS_BEHIND,
             staleness.Stage.ACCELERATION: POS_BEHIND | ACC_BEHIND}  # fmt: skip
WRITE_BITS = {
    Effect.DERIVED: 0,
    Effect.STEP_INPUT: WRITTEN | ACC_BEHIND,
    Effect.STATE: WRITTEN | POS_BEHIND | ACC_BEHIND,
    Effect.MODEL: WRITTEN | POS_BEHIND | ACC_BEHIND,
    Effect.MODEL_CONSTANT: WRITTEN | POS_BEHIND | ACC_BEHIND,
    Effect.VISUAL: 0,
}


class Target:
    """Where one bound field lives and what writing it entails (the slow path's data)."""

    __slots__ = (
        "array", "describe", "effect", "fancy", "field", "key", "mask", "physics", "refusal",
    )  # fmt: skip

    def __init__(
        self,
        physics: Physics,
        array: np.ndarray,
        key: Key,
        field: fields.Field,
        mask: int,
        describe: Any,
    ) -> None:
        self.physics = physics
        self.array = array
        self.key = key
        self.fancy = isinstance(key, np.ndarray)
        self.field = field
        self.effect = staleness.write_effect(field)
        self.mask = mask
        self.describe = describe  # a callable naming the field and rows, for messages
        self.refusal: str | None = None  # why these rows may not be written, if not

    def write(self, value: Any, columns: Any = None) -> None:
        """Assign `value` to the bound rows (or `columns` of them), with the write's effects.
        Raises BindingError for a value of the wrong shape or a bad column, or for rows a
        write may not change (`refusal`)."""
        self.check_writable()
        key = self.key if columns is None else column_key(self, columns)
        self.refresh_before_write()
        array = self.array
        old = array[key].copy() if self.effect == Effect.MODEL_CONSTANT else None
        try:
            array[key] = value
        except (ValueError, TypeError) as e:
            raise errors.BindingError(
                f"cannot write {np.shape(value)}-shaped values to {self.describe()}: the "
                f"bound rows have shape {np.shape(array[key])}"
            ) from e
        self.written(key, old)

    def check_writable(self) -> None:
        """Raise BindingError if these rows may not be written (see `refusal`)."""
        if self.refusal is not None:
            raise errors.BindingError(f"cannot write {self.describe()}: {self.refusal}")

    def refresh_before_write(self) -> None:
        """Bring derived fields up to date before one is overwritten, so that a later
        refresh does not overwrite the value written."""
        physics = self.physics
        if self.mask and physics._stale & self.mask:
            physics._refresh()

    def written(self, key: Key, old: np.ndarray | None) -> None:
        """After rows `key` were written (they held `old`): mark what is now stale, and
        update the model constants MuJoCo derives from them (undoing the write if it can't)."""
        physics = self.physics
        physics._stale |= WRITE_BITS[self.effect]
        if old is not None:
            array = self.array

            def undo() -> None:
                array[key] = old

            physics._update_constants(undo, self.describe())


class BoundPhysics:
    """What bindings, named access and frame bindings use of the physics they read and
    write: the protocol `mjcf.Physics` implements (it derives from this class), defined
    here, where it is used. Its MjModel and MjData (`_model`, `_data`); what of MjData is
    behind (`_stale`, the bits above: `bring_up_to_date` refreshes it before a read, a
    write sets bits of it); a field MuJoCo computes only for sensors
    (`_compute_on_demand(field)`); the model constants mj_setConst derives, after a
    write of one of its inputs (`_update_constants(undo, what)`, which calls `undo` if they
    cannot be derived); and the bindings made on it (`_live_bindings`), detached before
    the physics changes its MjData (`_detach_bindings()`)."""

    _model: mujoco.MjModel
    _data: mujoco.MjData
    _stale: int
    _live_bindings: weakref.WeakSet[Binding]

    def _refresh(self) -> None:
        """Run the MuJoCo stages `_stale` says are behind."""
        raise NotImplementedError

    def _compute_on_demand(self, field: str) -> None:
        """Compute MjData field `field`, which MuJoCo computes only for sensors, with each
        refresh from now on."""
        raise NotImplementedError

    def _update_constants(self, undo: Callable[[], None], what: str) -> None:
        """Derive the model constants again after `what` was written (`undo` it if MuJoCo
        cannot)."""
        raise NotImplementedError

    def _detach_bindings(self) -> None:
        """Tell every binding made on this physics that its MjData is about to change."""
        for binding in self._live_bindings:
            binding._detach()


def bring_up_to_date(physics: BoundPhysics, mask: int) -> None:
    """Refresh `physics` if a read of `mask` (a `READ_MASK` value) would find MjData behind."""
    if physics._stale & mask:
        physics._refresh()


def compute_on_demand(physics: BoundPhysics, field: str) -> None:
    """Have `physics` compute `field` (one of `staleness.ON_DEMAND`) from now on."""
    physics._compute_on_demand(field)


def refuse_writes(binding: Binding, why: str) -> None:
    """Make every write through `binding` raise mjcf.BindingError saying `why` (a mesh
    shared by copies, see `mjcf.compose.sharing`)."""
    binding._refuse_writes(why)


def write_through(array: WriteThrough, target: Target) -> None:
    """Make item assignments to `array` (read from a binding or named access) write to
    `target`'s rows, with the write's effects."""
    array._writeback = target


class WriteThrough(np.ndarray):
    """An array read from a binding whose item assignments write to the simulation, with the
    write's effects (dirty marking, model constants): a view writes in place, a copy of rows
    no slice covers writes itself back.

    Only the array a binding returned does this; arrays derived from it (slices, ufunc
    results) are plain arrays of the same class.

    `write_through` gives it `_writeback`, the `Target` it writes to.
    """

    __slots__ = ("_writeback",)

    _writeback: Target

    def __setitem__(self, key: Any, value: Any) -> None:
        target = getattr(self, "_writeback", None)  # unset on arrays derived from this one
        if target is None:
            np.ndarray.__setitem__(self, key, value)
            return
        target.check_writable()
        target.refresh_before_write()
        old = target.array[target.key].copy() if target.effect == Effect.MODEL_CONSTANT else None
        np.ndarray.__setitem__(self, key, value)
        if target.fancy:
            target.array[target.key] = self.view(np.ndarray)
        target.written(target.key, old)

    def __repr__(self) -> str:
        return repr(self.view(np.ndarray))


class _Entry(NamedTuple):
    """What a binding keeps of one field, made at its first read (see `Binding._entry`)."""

    fixed: np.ndarray | None  # what a read returns every time (a view), or None: copy rows
    mask: int  # the stale stages a read must refresh first (`READ_MASK` of its stage)
    array: np.ndarray  # the MjModel/MjData field
    key: Key  # the bound rows of `array`
    view: np.ndarray | None  # `array` as a WriteThrough, for fields whose writes are tracked
    bits: int | None  # the stale bits a write sets, or None: writes go through `target`
    target: Target  # the rows' writer (checks, effects)


class Binding:
    """Fields of the objects `ids` of one `kind`, read and written in one physics.

    Make bindings with `Physics.bind(elements)` or `Physics.bind_names(kind, names)`: the
    physics caches them and tells them when it changes MjData, which a binding made directly
    would not hear (`BoundPhysics._detach_bindings`; `refuse_writes` makes one read-only).

        hip.range, hip.jnt_range               # model.jnt_range row; short and full names
        legs["damping", 0]                     # dm_control's [field, columns] form
        hip.element_id                         # the compiled object's id (an array for a list)

    Attributes are the fields `mjcf.sim.fields.kind_fields(kind)` lists, under their short
    names (`range` for `jnt_range`, `xpos` for a geom's `geom_xpos`) and full names. For a
    list of objects, a field with one row per object comes with a leading axis of len(ids);
    an addressed field (qpos, qvel, sensordata, act ...) comes as the objects' rows
    concatenated, so a free joint contributes 7 qpos rows. A single object drops the
    leading axis (a body's `xpos` is (3,), its `mass` 0-d). Columns are given by index,
    slice, list or axis name; named columns follow dm_control: x y z (positions, axes,
    sizes), qw qx qy qz (quaternions), xx xy ... zz (3x3 matrices), r g b a (colors); see
    `mjcf.sim.fields.column_names`.

    Fresh values, never stale ones. Writes through bindings and `physics.named` are
    tracked; reads of derived quantities catch up with them first:
    - Writing state (qpos, qvel, act, mocap_pos/quat, eq_active ...) or a model field marks
      the physics dirty (`physics.is_dirty`). The next read of a derived MjData field (xpos,
      xmat, site_xpos, ten_length, sensordata, qacc ...) through a binding or named access
      runs `mj_forward` first. Reading model fields, or the state itself, never runs
      anything.
    - Writing ctrl, qfrc_applied or xfrc_applied changes only what depends on the controls:
      reads of acceleration-dependent fields (qacc, actuator_force, cfrc_ext, touch and
      force sensors) recompute that stage; positions stay as they are.
    - `physics.forward()` and `physics.step()` leave every derived field consistent with the
      state (see `Physics.step`), and clear `is_dirty`. Writing a derived field directly
      brings the physics up to date first, so the value written is not overwritten by a
      later refresh.
    - A model field that MuJoCo derives other constants from (geom/site/body pos and quat,
      body ipos/iquat and mass, geom size, joint axes ... the inputs of `mj_setConst`) is
      followed by `mj_setConst` at once: sameframe flags, bounding volumes, subtree masses
      and the like are recomputed, so `xpos` after `forward()` uses the new pose and
      contacts use the new size. A body compiled as "simple" whose inertial frame is moved
      off its body frame loses the flag, as a recompile would give it (see
      `mjcf.sim.set_const`). A value MuJoCo cannot accept is undone and raises
      BindingError.
    - Fields MuJoCo computes only when a sensor asks (cacc, cfrc_int, cfrc_ext,
      subtree_linvel, subtree_angmom) are computed when read.
    - Not tracked: writes to `physics.data` / `physics.model` directly (call
      `physics.forward()` or `physics.mark_as_dirty()` after them), writes through a slice
      of a returned array, and in-place writes that bypass item assignment (`out=`,
      `np.copyto`).

    Views and copies: when the bound rows are evenly spaced (a run, or every k-th row), a
    read is a numpy view of the MjModel/MjData buffer, made once: every read returns that
    view, whose values are the live buffer's (copy it to keep a value). Otherwise a read is
    a new copy whose item assignments (`b.qpos[0] = 1`, `b.qpos[:] += 1`) write the whole
    copy back. Assigning the attribute always writes through. Index arrays are computed
    once per binding. A binding reads the physics' current MjData: it stays valid through
    `reset()` and pickling, and raises BindingError once the physics holds another model.
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
        "_refusal",
        "_single",
    )
    _fields: dict[str, fields.Field] = {}

    def __init__(self, physics: Physics, kind: mujoco.mjtObj, ids: int | np.ndarray) -> None:
        """Validate ids; raises BindingError if empty, duplicated or out of range."""
        model = physics._model
        array, single = binding_index.checked_ids(model, kind, ids)
        self.__setstate__({"physics": physics, "kind": kind, "ids": array, "single": single})
        object.__setattr__(self, "_model", model)
        object.__setattr__(self, "_data", physics._data)
        physics._live_bindings.add(self)  # so that the physics can `_detach` us

    def __reduce__(self) -> tuple[Any, tuple[dict[str, Any]]]:
        # By state, not by class: binding classes are made at run time, one per kind.
        return _restore, (self.__getstate__(),)

    def __getstate__(self) -> dict[str, Any]:
        # Cached arrays would unpickle as detached copies: keep only what says what is bound.
        return {"physics": self._physics, "kind": int(self._kind), "ids": self._ids,
                "single": self._single, "refusal": self._refusal}  # fmt: skip

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
        object.__setattr__(self, "_refusal", state.get("refusal"))

    def _refuse_writes(self, why: str) -> None:
        """Make every write through this binding raise BindingError saying `why` (reads
        stay as they are)."""
        object.__setattr__(self, "_refusal", why)
        self._cache.clear()

    @property
    def kind(self) -> mujoco.mjtObj:
        """The object kind (mujoco.mjtObj) this binding indexes."""
        return self._kind

    @property
    def ids(self) -> np.ndarray | int:
        """The bound object id (single binding) or ids in binding order."""
        return int(self._ids[0]) if self._single else self._ids.copy()

    @property
    def element_id(self) -> np.ndarray | int:
        """dm_control's name for `ids`: the id (one element) or a read-only array of ids."""
        if self._single:
            return int(self._ids[0])
        out = self._ids.copy()
        out.flags.writeable = False
        return out

    def _entry(self, name: str) -> _Entry:
        """(the view a read returns or None, read mask, array, key, WriteThrough view of the
        array or None, write bits or None, Target) for field `name`, refreshed if the physics
        changed MjData; raises BindingError."""
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
            source = self._model if field.struct == "model" else self._data
            array = getattr(source, field.name)
            key = self._key(field, array.ndim > 1)
            mask = READ_MASK[self._stage(field)]
            if field.name in staleness.ON_DEMAND:
                physics._compute_on_demand(field.name)
            target = Target(physics, array, key, field, mask, functools.partial(self._label, name))
            target.refusal = self._refusal
            effect = target.effect
            # Arrays of model fields track item writes (sameframe flags, constants); copies
            # of rows no slice covers write themselves back. Views of MjData fields are plain
            # ndarrays: numpy is several hundred ns slower per operation on a subclass, and
            # state is read every step.
            tracked = effect in (Effect.MODEL, Effect.MODEL_CONSTANT)
            view = array.view(WriteThrough) if tracked or target.fancy or target.refusal else None
            # Writes whose effects need more than setting bits take the slow path (None),
            # as do writes that are refused.
            slow = effect in (Effect.DERIVED, Effect.MODEL_CONSTANT) or target.refusal
            bits = None if slow else WRITE_BITS[effect]
            # What a read returns when it is a view: the same object every time (its values
            # are the live buffer's); None when each read must copy rows no slice covers.
            fixed = None
            if not target.fancy:
                fixed = array[key] if view is None else view[key]
            entry = _Entry(fixed, mask, array, key, view, bits, target)
            if fixed is not None and view is not None:
                fixed._writeback = target
            self._cache[name] = entry
        return entry

    def _stage(self, field: fields.Field) -> staleness.Stage:
        if field.name == "sensordata":  # one buffer, each sensor computed at its own stage
            return staleness.sensor_stage(self._model, self._ids)
        if field.name in staleness.ON_DEMAND:
            return staleness.Stage.ACCELERATION  # recomputed with that stage (see _refresh)
        return staleness.field_stage(field)

    def _key(self, field: fields.Field, wide: bool) -> Key:
        """The index into `field`'s first axis for the bound ids (cached per address scheme
        and whether rows are arrays, `wide`, or numbers); raises BindingError."""
        key = self._keys.get((field.address, wide))
        if key is None:
            key = binding_index.row_key(
                self._model, self._kind, self._ids, self._single, field, wide
            )
            self._keys[(field.address, wide)] = key
        return key

    def _detach(self) -> None:
        """Drop cached arrays: the physics is about to hold another MjData (or MjModel)."""
        self._cache.clear()

    def __getattr__(self, name: str) -> Any:
        if name in self._fields:
            # A field property raised BindingError, which Python, seeing an AttributeError,
            # answered by calling us: read again to let that error through.
            return getattr(type(self), name).fget(self)
        raise errors.BindingError(self._unknown(name))

    def __setattr__(self, name: str, value: Any) -> None:
        # Hot path first: a cached field whose write only marks the physics is one numpy
        # assignment and one bitwise or.
        entry = self._cache.get(name)
        if entry is not None and entry.bits is not None:
            try:
                entry.array[entry.key] = value
            except (ValueError, TypeError):
                pass  # Target.write raises the explanatory error
            else:
                self._physics._stale |= entry.bits
                return
        if name not in self._fields:
            raise errors.BindingError(self._unknown(name))
        self._entry(name).target.write(value)

    def __getitem__(self, index: str | tuple[str, Any]) -> np.ndarray:
        """dm_control's `binding['pos']` and `binding['pos', columns]`: columns by index,
        slice, list or name ('x', ['x', 'z']). Raises BindingError as attribute access."""
        name, columns = split_index(index)
        if columns is None:
            return getattr(self, name)
        self._check_field(name)
        target = self._entry(name).target
        key = column_key(target, columns)
        if target.mask and self._physics._stale & target.mask:
            self._physics._refresh()
        try:
            return target.array[key]
        except IndexError as e:
            raise errors.BindingError(f"'{name}' columns {columns!r}: {e}") from e

    def __setitem__(self, index: str | tuple[str, Any], value: Any) -> None:
        """Write `binding['pos'] = v` or `binding['pos', ['x', 'z']] = v` through."""
        name, columns = split_index(index)
        self._check_field(name)
        try:
            self._entry(name).target.write(value, columns)
        except IndexError as e:
            raise errors.BindingError(f"'{name}' columns {columns!r}: {e}") from e

    def _check_field(self, name: Any) -> None:
        if not isinstance(name, str) or name not in self._fields:
            raise errors.BindingError(self._unknown(str(name)))

    def __dir__(self) -> list[str]:
        return sorted({*super().__dir__(), *self._fields})

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self._describe()}>"

    def _describe(self) -> str:
        names = fields.names(self._model or self._physics._model, self._kind)
        shown = [names[i] or str(i) for i in self._ids]
        if self._single:
            return f"{fields.kind_name(self._kind)} {shown[0]!r}"
        return f"{len(shown)} {fields.kind_name(self._kind)}s {shown}"

    def _label(self, name: str) -> str:
        return f"'{name}' of {self._describe()}"

    def _unknown(self, name: str) -> str:
        valid = sorted(n for n, f in self._fields.items() if n == fields.short_name(f))
        hint = errors.did_you_mean(name, self._fields)
        return (
            f"{fields.kind_name(self._kind)} bindings have no field '{name}'{hint}; "
            f"valid fields: {', '.join(valid)} (full MjModel/MjData names work too)"
        )


def _field_property(name: str) -> property:
    def fget(self: Binding) -> np.ndarray:
        # The hot path: one dict lookup, one flag test, and the cached view (or one numpy
        # index). The physics empties `_cache` when it changes MjData (see `_detach`), so a
        # hit is never stale.
        entry = self._cache.get(name)
        if entry is None:
            entry = self._entry(name)
        fixed, mask, _, key, view, _, _ = entry
        if mask and self._physics._stale & mask:
            self._physics._refresh()
        if fixed is not None:
            return fixed
        out = view[key]
        out._writeback = entry.target
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
