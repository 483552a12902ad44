"""Tracked arrays: what an element returns for a numeric attribute, the very array it
stores, so that an in-place edit (`geom.size[0] = 2`) edits the model and counts as a change
of it (see `RootElement.version`); `track` makes one.
"""

from __future__ import annotations

import copy
from typing import Any, Protocol, TypeVar, cast, overload

import numpy as np


class _Owner(Protocol):
    """What owns a tracked array: an element, told of every change."""

    def _modified(self) -> None: ...


_T = TypeVar("_T")


class TrackedArray(np.ndarray):
    """The array an element returns for a numeric attribute: editing it in place edits
    the model, and counts as a change of the model (see `RootElement.version`)."""

    _owner: _Owner | None = None

    def __array_finalize__(self, obj: object) -> None:
        # A view of the stored array edits the model too; other derived arrays do not.
        self._owner = getattr(obj, "_owner", None) if self.base is obj else None

    def __setitem__(self, key: Any, value: Any) -> None:
        super().__setitem__(key, value)
        owner = self._owner
        if owner is not None:
            owner._modified()

    def __reduce__(self) -> tuple[Any, ...]:
        constructor, arguments, state = cast(tuple, super().__reduce__())  # an ndarray's: 3 items
        return constructor, arguments, (state, self._owner)

    def __setstate__(self, state: tuple) -> None:
        array_state, owner = state
        super().__setstate__(array_state)
        self._owner = owner

    def __deepcopy__(self, memo: dict[int, Any] | None) -> TrackedArray:
        new = np.array(self).view(TrackedArray)
        new._owner = copy.deepcopy(self._owner, memo)
        return new


@overload
def track(value: np.ndarray, owner: _Owner) -> TrackedArray: ...
@overload
def track(value: _T, owner: _Owner) -> _T: ...
def track(value: object, owner: _Owner) -> object:
    """`value`, as a `TrackedArray` owned by `owner` if it is an array (the same memory).

    An array `owner` tracks already is returned as it is, and another tracked array is
    viewed through a plain view of the memory beneath it: numpy does not show an array's
    base to the garbage collector, so a tracked view of a tracked array would hold that
    array, and through its owner the whole model, unseen, and the model (a cycle of
    references) would never be freed. (An unpickled tracked array owns its memory, so a
    view of it holds it still.)"""
    if isinstance(value, np.ndarray):
        if type(value) is TrackedArray and value._owner is owner:
            return value  # tracked by `owner` already
        value = np.asarray(value).view(TrackedArray)  # asarray: a plain view of its memory
        value._owner = owner
    return value
