"""Observations of every environment at once, on the schedule a single Environment keeps.

    speed = BatchGeneric(lambda physics: physics.field('qvel')[:, :1])   # (n, 1)

An observable is read for all environments in one call when its `batch_reader(physics)`
gives a function of no arguments returning a (num_envs, *shape) array (as `BatchGeneric`
and `entities.features` do), or it is an `MJCFFeature` of an MjData field MuJoCo's batch
binds (automatic: qpos, qvel, xpos, sensordata ...). Others are read once per environment
from its materialized MjData, with the reader a single environment uses. The schedule
(update interval, delay, buffer, aggregator, corruptor) is that of
`composer.observation.Updater`, per environment: environments reset at different steps,
so each keeps its own phase and ring of samples. Corruptors run once per environment with
its random state (`corruptor(value, random_state=state)`); named aggregators reduce every
environment at once, callable ones run once per environment.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from composer.errors import BatchError
from composer.observation import Aggregator, MJCFFeature, Observable, Updater
from composer.vector.physics import VectorPhysics


def _feature_reader(item: MJCFFeature, physics: VectorPhysics) -> Callable[[], np.ndarray] | None:
    """An MJCFFeature's batched reader, or None when MuJoCo's batch lacks its field."""
    elements = item.mjcf_element
    binding = physics.bind(list(elements) if isinstance(elements, tuple) else elements)
    kind, index = item.kind, item.index
    try:
        getattr(binding, kind)
    except BatchError:
        return None
    if index is None:
        return lambda: getattr(binding, kind)
    key = (slice(None), *index) if isinstance(index, tuple) else (slice(None), index)
    return lambda: getattr(binding, kind)[key]


def _batch_reader(
    item: Observable, physics: VectorPhysics
) -> tuple[Callable[[], np.ndarray] | None, bool]:
    """(The reader of `item` for every environment or None, whether it is its own
    `batch_reader`, rather than one mirroring an MJCFFeature's binding)."""
    read = item.batch_reader(physics)
    if read is None and isinstance(item, MJCFFeature):
        return _feature_reader(item, physics), False
    return read, read is not None


class _Channel:
    """One observable over all environments: its reader, output rows and sample rings."""

    def __init__(self, index: int, single: Any, physics: VectorPhysics, out: np.ndarray) -> None:
        self.index = index
        self.name = single.name
        self.out = out
        self.shape = single.shape
        self.direct = single.direct
        self.delay = single.delay
        self.buffer_size = single.buffer_size
        self.corruptor = single.corruptor
        self.reduce = single.reduce
        self.dtype = single.dtype
        self.read, own = _batch_reader(single.observable, physics)
        num_envs = out.shape[0]
        if self.read is not None:
            shape = np.shape(self.read())
            if shape != (num_envs, *self.shape):
                if not own:
                    self.read = None  # an index the batched reader cannot mirror: per env
                else:
                    raise BatchError(
                        f"observable {self.name!r}: its batch reader gave shape {shape}; "
                        f"expected {(num_envs, *self.shape)}"
                    )
        if not self.direct:
            self.ring_size = single.ring_size
            self.ring = np.zeros((num_envs, self.ring_size, *self.shape), dtype=self.dtype)
            self.times = np.full((num_envs, self.ring_size), -np.inf)
            self.size = np.zeros(num_envs, dtype=np.int64)
            self.window = np.arange(self.buffer_size) - self.buffer_size

    def record(self, ids: np.ndarray, values: np.ndarray, steps: np.ndarray, states: list) -> None:
        """Take samples `values` of environments `ids` at physics steps `steps`."""
        samples: np.ndarray | list[np.ndarray] = values
        if self.corruptor is not None:
            corrupt, dtype = self.corruptor, self.dtype
            pairs = zip(values, states, strict=True)
            samples = [
                corrupt(np.asarray(value, dtype=dtype), random_state=state)
                for value, state in pairs
            ]
        slot = self.size[ids] % self.ring_size
        self.ring[ids, slot] = samples
        self.times[ids, slot] = steps
        self.size[ids] += 1

    def finish(self, ids: np.ndarray, steps: np.ndarray) -> None:
        """Write the observations visible after physics steps `steps` into output rows."""
        newer = (self.times[ids] > (steps - self.delay)[:, None]).sum(axis=1)
        end = self.size[ids] - newer
        slots = (end[:, None] + self.window) % self.ring_size
        buffer = self.ring[ids[:, None], slots]  # (n, buffer_size, *shape)
        if self.reduce is None:
            self.out[ids] = buffer.reshape((len(ids), *self.out.shape[1:]))
        elif isinstance(self.reduce, Aggregator):  # reduced for every environment at once
            self.out[ids] = self.reduce.reducer(buffer, axis=1)
        else:
            for row, i in zip(buffer, ids, strict=True):
                self.out[i] = self.reduce(row)


class BatchObservations:
    """The observation pipeline of a VectorEnvironment: every environment's enabled
    observables, sampled on its own schedule into (num_envs, ...) arrays."""

    def __init__(
        self,
        updater: Updater,
        physics: VectorPhysics,
        read_env: Callable[[int, int], np.ndarray],
        random_state: Callable[[int], np.random.RandomState],
    ) -> None:
        """Mirror `updater` (the first environment's) for `physics.num_envs` environments.
        `read_env(i, channel)` reads one observable of environment i from its own physics;
        `random_state(i)` is environment i's. Raises BatchError for a batch reader of the
        wrong shape."""
        num_envs = physics.num_envs
        self.flatten = updater.flatten
        self.substeps = updater.substeps
        self.period = updater.period
        self._physics = physics
        self._read_env = read_env
        self._random_state = random_state
        singles = updater.channels
        outs = self._allocate(singles, num_envs)
        self.channels = [
            _Channel(k, single, physics, out)
            for k, (single, out) in enumerate(zip(singles, outs, strict=True))
        ]
        self.per_environment = [c.name for c in self.channels if c.read is None]
        self._delayed = [c for c in self.channels if not c.direct]
        # due[c][phase, offset]: whether channel c samples after physics step `offset`
        # (1..substeps) of a control step in phase `phase` of the schedule.
        steps = np.arange(self.period)[:, None] * self.substeps + np.arange(self.substeps + 1)
        self._due = [
            np.array([[o > 0 and s.needed(int(t), self.substeps) for o, t in enumerate(row)]
                      for row in steps])
            for s in singles
        ]  # fmt: skip
        self._any_due = np.zeros((self.period, self.substeps + 1), dtype=bool)
        for due in self._due:
            self._any_due |= due

    def _allocate(self, singles: list[Any], num_envs: int) -> list[np.ndarray]:
        if self.flatten:
            sizes = [int(np.prod(s.output_shape)) for s in singles]
            self._flat = np.zeros((num_envs, sum(sizes)), dtype=np.float64)
            starts = np.cumsum([0, *sizes])
            return [
                self._flat[:, a:b].reshape(num_envs, *s.output_shape)
                for s, a, b in zip(singles, starts[:-1], starts[1:], strict=True)
            ]
        return [np.zeros((num_envs, *s.output_shape), dtype=s.dtype) for s in singles]

    def offsets(self, phases: np.ndarray) -> np.ndarray:
        """The physics steps (1..substeps) of this control step after which some channel
        samples, for environments in schedule phases `phases`."""
        if self.period == 1:
            return np.flatnonzero(self._any_due[0])
        return np.flatnonzero(self._any_due[np.unique(phases)].any(axis=0))

    def sample(self, ids: np.ndarray, phases: np.ndarray, offset: int, first: np.ndarray) -> None:
        """Sample the channels due after physics step `offset` of the control step, for
        environments `ids` in phases `phases` whose control step began at step `first`."""
        self._physics._select(None)
        for channel in self.channels:
            due = self._due[channel.index][phases, offset]
            if not due.any():
                continue
            chosen = ids if due.all() else ids[due]
            values = self._values(channel, chosen)
            if channel.direct:
                channel.out[chosen] = values
            else:
                states = [self._random_state(i) for i in chosen] if channel.corruptor else []
                channel.record(chosen, values, first[due] + offset, states)

    def _values(self, channel: _Channel, ids: np.ndarray) -> np.ndarray:
        if channel.read is not None:
            return channel.read()[ids]
        return np.stack([np.asarray(self._read_env(i, channel.index)) for i in ids])

    def finish(self, ids: np.ndarray, steps: np.ndarray) -> None:
        """Complete buffered, delayed or aggregated observations of environments `ids`,
        after their physics steps `steps` (counted from each one's reset)."""
        for channel in self._delayed:
            channel.finish(ids, steps)

    def load(self, i: int, singles: list[Any]) -> None:
        """Take environment i's state from its own pipeline's channels `singles`, just
        reset (the reset observation and the samples it holds). Raises BatchError if its
        observables are not those of the first environment."""
        names = [s.name for s in singles]
        if names != [c.name for c in self.channels]:
            raise BatchError(
                f"environment {i} observes {names}, the first environment "
                f"{[c.name for c in self.channels]}: every environment must enable the same "
                "observables"
            )
        for channel, single in zip(self.channels, singles, strict=True):
            channel.out[i] = single.out
            if not channel.direct:
                channel.ring[i] = single.ring
                channel.times[i] = single.times
                channel.size[i] = single.size

    def observation(self) -> dict[str, np.ndarray] | np.ndarray:
        """Every environment's current observation, new arrays: a dict of (num_envs, ...)
        arrays by name, or (num_envs, size) when flattened."""
        if self.flatten:
            return self._flat.copy()
        return {c.name: c.out.copy() for c in self.channels}

    def row(self, i: int) -> dict[str, np.ndarray] | np.ndarray:
        """Environment i's current observation, as its own Environment would return it."""
        if self.flatten:
            return self._flat[i].copy()
        return {c.name: c.out[i].copy() for c in self.channels}
