"""The observation pipeline: observables sampled on schedule into preallocated arrays.

    updater = Updater({'arm/qpos': qpos, ...}, physics, substeps=5, flatten=False)
    updater.observation_space                      # spaces.Dict of Boxes (or one Box)
    obs = updater.reset(random_state)              # samples at step 0
    done = 0                                       # control step k, from physics step first:
    for offset in updater.offsets(k):              # after these of its physics steps,
        physics.step(offset - done)
        updater.sample(k, first, offset)           # sample what is due
        done = offset
    obs = updater.observation(last_step)           # fresh arrays, safe to keep

Everything per observable is resolved here, once per compile: its reader (bindings), its
output array, its ring of samples, and the schedule saying after which physics steps of a
control step it is sampled. The schedule only samples what some observation will show:
with the default options an observable is read once per control step, after the last
physics step. It repeats every `period` control steps. Observables whose value is empty
(e.g. activations of a model with none) are left out. An observable is read with
`observation.reader_of(observable, physics)`: with its batched reader and a batch of one
where that is the form it defines.

Two choices dm_control offers: `strip_singleton_buffer_dim=False` gives an observation of
`buffer_size` 1 (and no aggregator) its leading buffer axis of length 1, and
`padding=ObservationPadding.ZERO` fills the buffer with zeros before the first samples are
visible, where by default (INITIAL_VALUE) the reset value fills it.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from gymnasium import spaces

from composer import errors
from composer.observation.observable import Aggregator, Observable, reader_of

Sample = Callable[[int], None]

# What an option left None means, as dm_control names them.
DEFAULT_UPDATE_INTERVAL = 1
DEFAULT_BUFFER_SIZE = 1
DEFAULT_DELAY = 0


class ObservationPadding(enum.Enum):
    """What a buffer holds before its first samples are visible (dm_control's enum):
    the reset value (INITIAL_VALUE) or zeros (ZERO)."""

    INITIAL_VALUE = -1
    ZERO = 0


class _Channel:
    """One observable's reader, samples and output array."""

    def __init__(
        self, name: str, observable: Observable, physics: Any, strip: bool, zero_padding: bool
    ) -> None:
        observable.validate(name)
        self.name = name
        self.observable = observable
        try:
            self.read = reader_of(observable, physics)
            value = np.asarray(self.read())
        except errors.Error:
            raise  # composer's own, already explicit
        except Exception as e:  # a user's function or a binding failed: say which observable
            raise errors.ObservableError(
                f"observable {name!r} could not be read: {type(e).__name__}: {e}"
            ) from e
        dtype = value.dtype if value.dtype.kind in "fiu" else np.dtype(np.float64)
        self.shape = value.shape
        self.interval = int(observable.update_interval)
        self.buffer_size = int(_or_default(observable.buffer_size, DEFAULT_BUFFER_SIZE))
        self.delay = int(_or_default(observable.delay, DEFAULT_DELAY))
        self.corruptor = observable.corruptor
        self.reduce: Callable[[np.ndarray], np.ndarray] | None = observable.aggregator
        floating = np.issubdtype(dtype, np.floating)
        if (self.reduce is not None or self.corruptor is not None) and not floating:
            dtype = np.dtype(np.float64)  # a mean of integers, or noise, is not an integer
        self.dtype = dtype
        self.zero_padding = zero_padding
        if self.reduce is not None:
            self.output_shape = self._reduced_shape(np.zeros((self.buffer_size, *self.shape)))
        elif self.buffer_size == 1 and strip:
            self.output_shape = self.shape
        else:
            self.output_shape = (self.buffer_size, *self.shape)
        self.low, self.high = self._bounds(observable, value)
        # Observations with one sample, on time, unchanged are copied straight to the output.
        self.direct = (
            self.output_shape == self.shape and self.delay == 0 and self.corruptor is None
            and self.reduce is None
        )  # fmt: skip
        self.size = self.ring_size = 0
        self.random_state: Any = None

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

    def allocate(self, out: np.ndarray) -> None:
        """Take `out` (output_shape) as the output array; make the ring and the sampler."""
        self.out = out
        read = self.read
        if self.direct:
            copyto = np.copyto

            def sample(step: int) -> None:
                copyto(out, read())

            self.sample = sample
            return
        # Samples in flight (taken, not yet visible) plus the visible ones shown.
        self.ring_size = self.buffer_size + self.delay // self.interval + 1
        self.ring = np.zeros((self.ring_size, *self.shape), dtype=self.dtype)
        self.times = np.full(self.ring_size, -np.inf)
        self.window = np.arange(self.buffer_size)
        self.buffer = np.zeros((self.buffer_size, *self.shape), dtype=self.dtype)
        self.sample = self._record

    def _record(self, step: int) -> None:
        value = self.read()
        if self.corruptor is not None:
            value = self.corruptor(
                np.asarray(value, dtype=self.dtype), random_state=self.random_state
            )
        slot = self.size % self.ring_size
        self.ring[slot] = value
        self.times[slot] = step
        self.size += 1

    def reset(self, random_state: Any) -> None:
        """Forget the last episode; sample the reset value at step 0."""
        self.random_state = random_state
        if self.direct:
            self.sample(0)
            return
        self.size = 0
        self._record(0)
        # Before the episode, the reset value held (or zeros, with zero padding).
        if self.zero_padding:
            self.ring[1:] = 0
        else:
            self.ring[:] = self.ring[0]
        self.times[:] = -np.inf
        self.times[0] = 0

    def finish(self, step: int) -> None:
        """Write the observation visible after physics step `step` into the output array."""
        limit = step - self.delay
        end = self.size
        times, ring_size = self.times, self.ring_size
        while times[(end - 1) % ring_size] > limit:
            end -= 1
        buffer = self.buffer
        np.take(self.ring, (end - self.buffer_size + self.window) % ring_size, axis=0, out=buffer)
        if self.reduce is not None:
            self.out[...] = self.reduce(buffer)
        else:
            self.out[...] = buffer.reshape(self.output_shape)

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


class Updater:
    """Samples enabled observables into preallocated arrays on their schedule."""

    def __init__(
        self,
        observables: Mapping[str, Observable],
        physics: Any,
        substeps: int,
        flatten: bool = False,
        strip_singleton_buffer_dim: bool = True,
        padding: ObservationPadding = ObservationPadding.INITIAL_VALUE,
    ) -> None:
        """Resolve every observable in `physics` (sampled once to learn its shape and
        type); raises ObservableError naming the observable that cannot be read."""
        self.substeps = substeps
        self.flatten = flatten
        zero = padding is ObservationPadding.ZERO
        channels = [
            _Channel(name, observables[name], physics, strip_singleton_buffer_dim, zero)
            for name in sorted(observables)
        ]
        self.channels = [c for c in channels if math.prod(c.output_shape) > 0]
        self.names = [c.name for c in self.channels]
        self._allocate()
        self.delayed = [c for c in self.channels if not c.direct]
        self._make_schedule()

    def _allocate(self) -> None:
        if self.flatten:
            sizes = [math.prod(c.output_shape) for c in self.channels]
            self.flat = np.zeros(sum(sizes), dtype=np.float64)
            start = 0
            for channel, size in zip(self.channels, sizes, strict=True):
                channel.allocate(self.flat[start : start + size].reshape(channel.output_shape))
                start += size
            lows = [c.low.ravel() for c in self.channels]
            highs = [c.high.ravel() for c in self.channels]
            self.observation_space: spaces.Dict | spaces.Box = spaces.Box(
                np.concatenate(lows) if lows else np.zeros(0),
                np.concatenate(highs) if highs else np.zeros(0),
                dtype=np.float64,
            )
            return
        boxes: dict[str, spaces.Space] = {}
        for channel in self.channels:
            channel.allocate(np.zeros(channel.output_shape, dtype=channel.dtype))
            boxes[channel.name] = _box(channel.low, channel.high, channel.dtype)
        self.observation_space = spaces.Dict(boxes)
        self.outputs = [(c.name, c.out) for c in self.channels]

    def _make_schedule(self) -> None:
        """Per control-step phase: the samplers due after each physics step of it.

        The schedule repeats every `period` control steps, the least common multiple of
        each observable's interval with the substeps, counted in control steps.
        """
        substeps = self.substeps
        period = 1
        for channel in self.channels:
            period = math.lcm(period, math.lcm(channel.interval, substeps) // substeps)
        self.period = period
        # _due[phase][offset]: the samplers due after physics step `offset` (1..substeps).
        self._due: list[list[list[Sample]]] = []
        self._offsets: list[list[int]] = []
        for phase in range(period):
            due: list[list[Sample]] = [[]]
            for offset in range(1, substeps + 1):
                step = phase * substeps + offset
                due.append([c.sample for c in self.channels if c.needed(step, substeps)])
            self._due.append(due)
            self._offsets.append([offset for offset in range(1, substeps + 1) if due[offset]])

    def offsets(self, control_step: int) -> list[int]:
        """The physics steps (1..substeps) of control step `control_step` (counted from
        the reset) after which some observable is sampled, ascending."""
        return self._offsets[control_step % self.period]

    def sample(self, control_step: int, first: int, offset: int) -> None:
        """Sample what is due after physics step `offset` of control step `control_step`,
        which began after physics step `first` (both counted from the reset)."""
        for sample in self._due[control_step % self.period][offset]:
            sample(first + offset)

    def reset(self, random_state: Any) -> dict[str, np.ndarray] | np.ndarray:
        """Start an episode: sample every observable at step 0; the first observation."""
        for channel in self.channels:
            channel.reset(random_state)
        return self.observation(0)

    def observation(self, step: int) -> dict[str, np.ndarray] | np.ndarray:
        """The observation after physics step `step` (counted from reset), as new arrays."""
        for channel in self.delayed:
            channel.finish(step)
        if self.flatten:
            return self.flat.copy()
        return {name: out.copy() for name, out in self.outputs}


def _or_default(value: Any, default: int) -> Any:
    return default if value is None else value


def _box(low: np.ndarray, high: np.ndarray, dtype: np.dtype) -> spaces.Box:
    if np.issubdtype(dtype, np.integer):
        info = np.iinfo(dtype)
        low, high = np.clip(low, info.min, info.max), np.clip(high, info.min, info.max)
    return spaces.Box(low.astype(dtype), high.astype(dtype), dtype=dtype.type)
