"""Channel: one enabled observable compiled for a physics: its value's shape and type, its
options, the shape and bounds of what the observation shows, and its reduction.

    channel = Channel('arm/qpos', observable, value, strip=True)   # value: one reading
    channel.output_shape, channel.low, channel.high, channel.box()
    channel.needed(step, substeps)           # whether a sample at `step` is ever shown
    channel.reduce_rows(buffers)             # (n, buffer_size, *shape) -> (n, *output_shape)

A channel holds no samples and reads nothing (`composer.observation.schedule` keeps every
environment's samples); one that is `direct` is copied straight to the output.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from gymnasium import spaces

from composer import errors
from composer.observation.observable import Aggregator, Observable

# What an option left None means, as dm_control names them.
DEFAULT_UPDATE_INTERVAL = 1
DEFAULT_BUFFER_SIZE = 1
DEFAULT_DELAY = 0


class Channel:
    """One observable's schedule options, value type and observation shape and bounds."""

    def __init__(self, name: str, observable: Observable, value: Any, strip: bool) -> None:
        """Compile `observable` (named `name`) from one reading `value`; `strip` drops the
        buffer axis of an unaggregated buffer of one. Raises ObservableError for bounds that
        do not fit, or an aggregator that fails on a buffer."""
        value = np.asarray(value)
        self.name = name
        self.observable = observable
        dtype = value.dtype if value.dtype.kind in "fiu" else np.dtype(np.float64)
        self.shape: tuple[int, ...] = value.shape
        self.interval = int(observable.update_interval)
        self.buffer_size = int(_or_default(observable.buffer_size, DEFAULT_BUFFER_SIZE))
        self.delay = int(_or_default(observable.delay, DEFAULT_DELAY))
        self.corruptor = observable.corruptor
        self.reduce: Callable[[np.ndarray], np.ndarray] | None = observable.aggregator
        floating = np.issubdtype(dtype, np.floating)
        if (self.reduce is not None or self.corruptor is not None) and not floating:
            dtype = np.dtype(np.float64)  # a mean of integers, or noise, is not an integer
        self.dtype: np.dtype = dtype
        if self.reduce is not None:
            self.output_shape = self._reduced_shape(np.zeros((self.buffer_size, *self.shape)))
        elif self.buffer_size == 1 and strip:
            self.output_shape = self.shape
        else:
            self.output_shape = (self.buffer_size, *self.shape)
        self.low, self.high = self._bounds(observable, value)
        # One sample, on time and unchanged: copied straight to the output.
        self.direct = (
            self.output_shape == self.shape and self.delay == 0 and self.corruptor is None
            and self.reduce is None
        )  # fmt: skip
        # Samples in flight (taken, not yet visible) plus the visible ones shown.
        self.ring_size = self.buffer_size + self.delay // self.interval + 1

    def _reduced_shape(self, buffer: np.ndarray) -> tuple[int, ...]:
        """The shape the aggregator makes of a buffer (dm_control learns it so, too)."""
        try:
            return np.shape(self.reduce(buffer))  # type: ignore[misc]
        except Exception as e:
            raise errors.ObservableError(
                f"observable {self.name!r}: its aggregator failed on a buffer of shape "
                f"{buffer.shape}: {type(e).__name__}: {e}"
            ) from e

    def _bounds(self, observable: Observable, value: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        given = observable.bounds
        low, high = given if given is not None else observable.default_bounds(value)
        try:
            low = np.broadcast_to(np.asarray(low, dtype=np.float64), value.shape).copy()
            high = np.broadcast_to(np.asarray(high, dtype=np.float64), value.shape).copy()
        except ValueError as e:
            raise errors.ObservableError(
                f"observable {self.name!r}: bounds do not fit its shape {value.shape}: {e}"
            ) from None
        if np.any(low > high):
            raise errors.ObservableError(
                f"observable {self.name!r}: a low bound exceeds its high bound: {low}, {high}"
            )
        if self.corruptor is not None:
            if hasattr(self.corruptor, "bounds"):
                low, high = (np.asarray(b, np.float64) for b in self.corruptor.bounds(low, high))
            else:
                low, high = np.full_like(low, -np.inf), np.full_like(high, np.inf)
        reduce = observable.aggregator
        if reduce is None:
            if self.output_shape != self.shape:
                low = np.broadcast_to(low, self.output_shape).copy()
                high = np.broadcast_to(high, self.output_shape).copy()
        elif isinstance(reduce, Aggregator) and not reduce.preserves_bounds:  # a sum
            low, high = low * self.buffer_size, high * self.buffer_size
        elif observable.aggregator_bounds is not None:
            bounds = observable.aggregator_bounds
            low = np.broadcast_to(np.asarray(bounds[0], np.float64), self.output_shape).copy()
            high = np.broadcast_to(np.asarray(bounds[1], np.float64), self.output_shape).copy()
        elif not getattr(reduce, "preserves_bounds", False) or self.output_shape != self.shape:
            low = np.full(self.output_shape, -np.inf)
            high = np.full(self.output_shape, np.inf)
        return low, high

    def box(self) -> spaces.Box:
        """The observation space of this channel: its bounds in its dtype (an integer
        type's bounds within its range)."""
        low, high, dtype = self.low, self.high, self.dtype
        if np.issubdtype(dtype, np.integer):
            low, high = _integer_bounds(low, dtype), _integer_bounds(high, dtype)
        return spaces.Box(low.astype(dtype), high.astype(dtype), dtype=dtype.type)

    def needed(self, step: int, substeps: int) -> bool:
        """Whether a sample at physics step `step` will ever be in an observation, given
        control-step boundaries every `substeps` physics steps."""
        if step % self.interval:
            return False
        # The first control-step boundary at which it is visible, and the newest visible
        # sample there: it is shown if it is among the buffer_size newest.
        boundary = -(-(step + self.delay) // substeps) * substeps
        newest = (boundary - self.delay) // self.interval * self.interval
        return step >= newest - (self.buffer_size - 1) * self.interval

    def reduce_rows(self, buffers: np.ndarray) -> np.ndarray | list[np.ndarray]:
        """The aggregator over each environment's buffer: `buffers` (n, buffer_size,
        *shape) -> (n, *output_shape). A named aggregator reduces every row at once; a
        callable one is called on each row, as dm_control calls it."""
        reduce = self.reduce
        if isinstance(reduce, Aggregator):
            return reduce.reducer(buffers, axis=1)
        return [reduce(buffer) for buffer in buffers]  # type: ignore[misc]


def _or_default(value: Any, default: int) -> Any:
    return default if value is None else value


def _integer_bounds(bounds: np.ndarray, dtype: np.dtype) -> np.ndarray:
    """Float `bounds` as integers of `dtype`, saturated at its range: a float64 at the edge
    of int64's range rounds beyond it, where a plain cast would wrap around."""
    info = np.iinfo(dtype)
    top, bottom = bounds >= float(info.max), bounds <= float(info.min)
    values = np.where(top | bottom, 0, bounds).astype(dtype)
    values[top] = info.max
    values[bottom] = info.min
    return values
