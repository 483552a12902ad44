"""What binding no elements gives: `EMPTY`, whose every field reads as an empty array and
takes only empty values, as dm_control's empty binding does.

    physics.bind([]).qpos                  # array([], dtype=float64)
    physics.bind([]).qpos = []             # a no-op; any other value: mjcf.BindingError
"""

from __future__ import annotations

from typing import Any

import numpy as np

from mjcf import errors
from mjcf.sim.binding_index import split_index


class EmptyBinding:
    """What binding no elements gives (`physics.bind([])`): every field reads as an empty
    array, and only empty values can be written (a no-op: `()`, `[]`, an empty array);
    writing any other raises BindingError, as dm_control refuses every write."""

    __slots__ = ()

    @property
    def element_id(self) -> np.ndarray:
        """No ids: an empty int array."""
        return np.zeros(0, dtype=np.intp)

    def __getattr__(self, name: str) -> np.ndarray:
        if name.startswith("__"):
            raise AttributeError(name)
        return np.zeros(0)

    def __setattr__(self, name: str, value: Any) -> None:
        if np.size(value) != 0:  # dm_control's words, which its code and tests expect
            raise errors.BindingError("Cannot assign a value to an empty binding.")

    def __getitem__(self, index: Any) -> np.ndarray:
        return np.zeros(0)

    def __setitem__(self, index: Any, value: Any) -> None:
        name, _ = split_index(index)
        self.__setattr__(str(name), value)

    def __repr__(self) -> str:
        return "<EmptyBinding of no elements>"


EMPTY = EmptyBinding()
