"""SameModels: whether the simulations of a VectorEnvironment can all run on one MjModel
(which MuJoCo's batch steps faster than a model each: docs/performance_profile.md).

    same = SameModels(num_envs)
    same.update(models, changed)      # after resets: `changed` environments' models may differ
    same.identical                    # True: every model steps as models[0] does, bit for bit

Promise: `identical` only when every model equals the first in every byte the physics
reads (`SameModels` says which bytes).
"""

from __future__ import annotations

import ctypes
from collections.abc import Iterable, Sequence

import mujoco
import numpy as np

# Models of more bytes than this (textures left out) are never compared: comparing them at
# each reset would cost more than sharing saves.
LARGEST = 8 << 20
# MjModel's value fields outside its arrays that the physics reads.
_STRUCTS = ("opt", "stat")


class _Buffer:
    """Where a model's arrays lie in the one buffer MuJoCo allocates them in: from its
    lowest array (`first`, by name) to the end of its highest (`last`), `size` bytes, of
    which the textures' are `skip` (start, stop). Found on one model; a model of the same
    sizes has the same layout, which `view` checks by the last array's offset and size."""

    def __init__(self, model: mujoco.MjModel, arrays: dict[str, np.ndarray]) -> None:
        addresses = {name: array.ctypes.data for name, array in arrays.items()}
        self.first = min(addresses, key=addresses.__getitem__)
        self.last = max(addresses, key=addresses.__getitem__)
        start = addresses[self.first]
        self.last_at = addresses[self.last] - start
        self.last_bytes = arrays[self.last].nbytes
        self.size = self.last_at + self.last_bytes
        # One buffer: the arrays fill the span but for alignment padding.
        self.contiguous = self.size <= sum(a.nbytes for a in arrays.values()) + 64 * len(arrays)
        texture = model.tex_data
        begin = texture.ctypes.data - start if texture.size else 0
        self.skip = (begin, begin + texture.nbytes)
        self.compared = self.size - texture.nbytes

    def view(self, model: mujoco.MjModel) -> np.ndarray | None:
        """`model`'s buffer as bytes (a view of the model's memory: use it while `model`
        lives), or None for a model of another layout."""
        first, last = getattr(model, self.first), getattr(model, self.last)
        start = first.ctypes.data
        if first.size == 0 or last.ctypes.data - start != self.last_at:
            return None
        if last.nbytes != self.last_bytes:
            return None
        return np.ctypeslib.as_array((ctypes.c_uint8 * self.size).from_address(start))


def _arrays(model: mujoco.MjModel) -> dict[str, np.ndarray]:
    """Every non-empty array field of `model`, by name."""
    found = {}
    for name in dir(model):
        if name.startswith("_"):
            continue
        value = getattr(model, name, None)
        if isinstance(value, np.ndarray) and value.size:
            found[name] = value
    return found


def _values(model: mujoco.MjModel) -> list[np.ndarray]:
    """The fields of `model`'s option and statistic structs (timestep, gravity, the
    solver's settings, the mean inertia it scales by ...), as arrays."""
    found = []
    for struct_name in _STRUCTS:
        struct = getattr(model, struct_name)
        for name in sorted(dir(struct)):
            if not name.startswith("_"):
                value = getattr(struct, name)
                if not callable(value):
                    found.append(np.asarray(value))
    return found


class SameModels:
    """Which of n models step as the first one's, bit for bit. The environments' models
    are compiled apart, and tasks and variations may edit them at each reset: at each
    update they are compared in every array MuJoCo allocates in the model's buffer
    (geometry, masses, meshes, height fields, names ...) but its textures, which only
    rendering reads (and each environment renders with its own model), and in the option
    and statistic fields; shared only while all are the same. Models of more than
    `LARGEST` bytes beside their textures, or without arrays, are never compared."""

    def __init__(self, num_envs: int) -> None:
        """Know nothing yet: no model is taken to be the first one's."""
        self._same = np.zeros(num_envs, dtype=bool)
        self._buffer: _Buffer | None = None  # the layout of models[0]'s arrays
        self._first: tuple[np.ndarray, list[np.ndarray]] | None = None  # models[0]'s bytes

    @property
    def identical(self) -> bool:
        """Whether every model was the first one's at the last `update`."""
        return bool(self._same.all())

    def update(self, models: Sequence[mujoco.MjModel], changed: Iterable[int]) -> None:
        """Compare the models of environments `changed` (which may have been edited or
        recompiled since the last update) with the first; all of them if the first is
        among them."""
        changed = [int(i) for i in changed]
        if self._first is None or 0 in changed:
            arrays = _arrays(models[0])
            self._buffer = _Buffer(models[0], arrays) if arrays else None
            self._first = self._bytes(models[0])
            changed = list(range(1, len(models)))
            self._same[0] = self._first is not None
        if self._first is None:
            self._same[:] = False
            return
        memory, values = self._first
        for i in changed:
            found = self._bytes(models[i])
            self._same[i] = (
                found is not None
                and np.array_equal(found[0], memory)
                and all(np.array_equal(a, b) for a, b in zip(found[1], values, strict=True))
            )

    def _bytes(self, model: mujoco.MjModel) -> tuple[np.ndarray, list[np.ndarray]] | None:
        """What of `model` is compared (copied), or None where it is not comparable."""
        buffer = self._buffer
        if buffer is None or not buffer.contiguous or buffer.compared > LARGEST:
            return None
        memory = buffer.view(model)
        if memory is None:
            return None
        begin, stop = buffer.skip
        kept = np.concatenate((memory[:begin], memory[stop:])) if stop > begin else memory.copy()
        return kept, _values(model)
