"""Where a binding's values are in an MjModel/MjData field: its objects' ids, checked; the
key of their rows, computed once per binding and field (a slice where they are evenly
spaced, so that a read is a view of the buffer); the key of columns asked for by index,
slice, list or axis name ('x', ['x', 'z']; `mjcf.sim.fields.column_names`), and the field
and columns a subscript names. A bad index raises mjcf.BindingError.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from mjcf import errors
from mjcf.sim import fields

if TYPE_CHECKING:
    from mjcf.sim.binding import Target

Key = int | slice | tuple | np.ndarray


def checked_ids(
    model: mujoco.MjModel, kind: mujoco.mjtObj, ids: int | np.ndarray
) -> tuple[np.ndarray, bool]:
    """`ids` (an id or a 1-D list of ids of objects of `kind` in `model`) as an array of
    indices, and whether one id was given (not a list); raises BindingError if there are
    none, if they repeat or if one is out of range."""
    single = np.ndim(ids) == 0
    array = np.atleast_1d(np.asarray(ids))
    name = fields.kind_name(kind)
    if array.size == 0:
        raise errors.BindingError(f"cannot bind an empty list of {name}s")
    if array.ndim != 1 or not np.issubdtype(array.dtype, np.integer):
        raise errors.BindingError(f"{name} ids must be an int or a 1-D list of ints, got {ids!r}")
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
    return array.astype(np.intp), single


def row_key(
    model: mujoco.MjModel,
    kind: mujoco.mjtObj,
    ids: np.ndarray,
    single: bool,
    field: fields.Field,
    wide: bool,
) -> Key:
    """The index into `field`'s first axis of the rows of objects `ids` of `kind`: a slice
    where the rows are evenly spaced, else an index array; for one object (`single`) with
    one row, that row (an int for a field whose rows are arrays, `wide`, else (row, ...)).
    Raises BindingError for objects that own no rows of a field with one row each."""
    address = field.address
    rows, counts = fields.row_index(model, address, ids)
    one_row_each = address is None or address.one_each
    if address is not None and address.one_each and not counts.all():
        missing = ids[counts == 0]
        names = fields.names(model, kind)
        mocap = " (they are not mocap bodies)" if address.start == "body_mocapid" else ""
        raise errors.BindingError(
            f"{fields.kind_name(kind)} "
            f"{', '.join(repr(names[i] or i) for i in missing)} own no rows of "
            f"'{field.name}' (indexed by {address.start}){mocap}"
        )
    if one_row_each and (counts == 1).all():
        # One row each: index like a per-object field; a single object drops the axis.
        # An int indexes a row of a 2-D field fastest (a view); a 1-D field needs
        # (row, ...) to give a 0-d view rather than a detached scalar.
        row = int(rows[0])
        return _compact(rows) if not single else row if wide else (row, Ellipsis)
    return _compact(rows)


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


def column_key(target: Target, columns: Any) -> Key:
    """The key into `target.array` for `columns` (index, slice, list, axis names) of the
    bound rows; raises BindingError for a field without columns or an unknown name."""
    array, key, field = target.array, target.key, target.field
    if array.ndim < 2:
        raise errors.BindingError(f"'{field.name}' has no columns to index: each row is one number")
    cols = resolve_columns(field, columns)
    if isinstance(key, int):  # one object, one row
        return (key, cols)
    if isinstance(key, np.ndarray) and isinstance(cols, np.ndarray):
        return np.ix_(key, cols)
    return (key, cols)


def resolve_columns(field: fields.Field, columns: Any) -> Any:
    """Column names of `field` ('x', ['x', 'z']) as indices; ints and slices pass through."""
    if isinstance(columns, str):
        return _column_index(field, columns)
    if isinstance(columns, list | tuple | np.ndarray):
        items = list(np.asarray(columns, dtype=object).reshape(-1))
        if any(isinstance(item, str) for item in items):
            return np.array([_column_index(field, str(item)) for item in items], dtype=np.intp)
        return np.asarray(columns)
    return columns


def _column_index(field: fields.Field, name: str) -> int:
    names = fields.column_names(field.name)
    if names is None or name not in names:
        valid = f"its columns are {list(names)}" if names else "its columns have no names"
        raise errors.BindingError(
            f"'{field.name}' has no column named {name!r}: {valid}; index columns by number"
        )
    return names.index(name)


def split_index(index: Any) -> tuple[Any, Any]:
    """(field name, columns or None) of a binding's subscript: `binding['pos']` or
    `binding['pos', columns]`; raises BindingError for another tuple."""
    if isinstance(index, tuple):
        if len(index) != 2:
            raise errors.BindingError(
                f"index a binding as binding['field'] or binding['field', columns], got {index!r}"
            )
        return index
    return index, None
