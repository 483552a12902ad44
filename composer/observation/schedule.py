"""Schedule: when each observable is sampled, and every environment's samples and outputs.

    schedule = Schedule(channels, substeps=5, num_envs=n, flatten=False)
    schedule.restart(k, ALL, value, random_states, zero_padding=False)  # at a reset
    for offset in schedule.offsets(phase):      # phase: control steps since reset % period
        schedule.sample(phase, offset, ALL, steps, read, random_states)  # after step offset
    schedule.finish(ALL, steps)                 # the observation after physics step `steps`

The one schedule of `composer.Environment` (of one environment) and `VectorEnvironment` (of
num_envs), each environment on its own phase; it samples only what an observation shows.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection, Sequence
from typing import Any

import numpy as np
from gymnasium import spaces

from composer.observation.channel import Channel

Rows = slice | np.ndarray
ALL = slice(None)  # every environment of the schedule
Read = Callable[[int, Rows], Any]  # (channel k, rows) -> channel k's values of those rows
RandomStates = Callable[[np.ndarray], list[np.random.RandomState]]


class _Direct:
    """A channel shown as sampled: one sample, on time, unchanged, written to the output."""

    __slots__ = ("out",)

    def __init__(self, out: np.ndarray) -> None:
        self.out = out

    def take(self, rows: Rows, values: Any, steps: Any, random_states: RandomStates) -> None:
        self.out[rows] = values

    def restart(self, rows: Rows, values: Any, random_states: RandomStates, zero: bool) -> None:
        self.out[rows] = values

    def copy_row(self, i: int, other: _Direct, j: int) -> None:
        self.out[i] = other.out[j]


class _Ring:
    """A channel with a buffer, delay, corruptor or aggregator: each environment's recent
    samples, in flight and visible. The sample taken at physics step t (a multiple of the
    interval) is kept in slot t // interval of the ring, so the samples an observation
    shows are found by arithmetic: the ring holds every sample in flight plus the buffer
    (`Channel.ring_size`), and the schedule takes every sample an observation shows
    (`Channel.needed`)."""

    __slots__ = (
        "channel",
        "corrupted",
        "cycle",
        "every",
        "interval",
        "length",
        "out",
        "ring",
        "span",
    )

    def __init__(self, channel: Channel, out: np.ndarray) -> None:
        num_envs = out.shape[0]
        self.channel = channel
        self.interval = channel.interval
        self.length = channel.ring_size
        self.corrupted = channel.corruptor is not None
        self.out = out
        self.ring = np.zeros((num_envs, channel.ring_size, *channel.shape), dtype=channel.dtype)
        size = channel.buffer_size
        # The slots of the buffer from slot s: cycle[s:s + size] (s + arange(size), wrapped).
        self.cycle = np.arange(self.length + size) % self.length
        self.span = np.arange(size)
        self.every = np.arange(num_envs)

    def _corrupt(self, rows: Rows, values: Any, random_states: RandomStates) -> list[Any]:
        """`values` of `rows` corrupted, with each row's random state."""
        channel = self.channel
        ids = self.every if isinstance(rows, slice) else rows
        corrupt, dtype = channel.corruptor, channel.dtype
        assert corrupt is not None, "only a corrupted channel's samples are corrupted"
        values = np.reshape(values, (len(ids), *channel.shape))
        return [
            corrupt(np.asarray(value, dtype=dtype), random_state=state)
            for value, state in zip(values, random_states(ids), strict=True)
        ]

    def take(self, rows: Rows, values: Any, steps: Any, random_states: RandomStates) -> None:
        slots = steps // self.interval % self.length  # one, or one per row
        if isinstance(rows, slice) and isinstance(slots, np.ndarray):
            rows = self.every
        if self.corrupted:
            values = self._corrupt(rows, values, random_states)
        self.ring[rows, slots] = values

    def restart(self, rows: Rows, values: Any, random_states: RandomStates, zero: bool) -> None:
        """Forget the episode: the reset sample in slot 0 (step 0); before it, the reset
        value held (or zeros) in every slot."""
        sample = self._corrupt(rows, values, random_states) if self.corrupted else values
        ring = self.ring
        if zero:
            ring[rows] = 0
            ring[rows, 0] = sample
        else:
            ring[rows] = np.reshape(sample, (-1, 1, *self.channel.shape))

    def show(self, rows: Rows, steps: Any) -> None:
        """Write the observations visible after physics steps `steps` into the output."""
        channel, size = self.channel, len(self.span)
        newest = (steps - channel.delay) // self.interval  # the newest visible sample
        start = (newest + 1 - size) % self.length  # the slot of the oldest shown
        if isinstance(start, np.ndarray):  # a step per row
            index = (self.every if isinstance(rows, slice) else rows)[:, None]
            buffers = self.ring[index, self.cycle[start[:, None] + self.span]]
        elif isinstance(rows, slice):  # one step for every row
            buffers = self.ring.take(self.cycle[start : start + size], axis=1)
        else:
            buffers = self.ring[rows[:, None], self.cycle[start : start + size]]
        # buffers: (n, buffer_size, *shape), oldest first
        if channel.reduce is None:
            self.out[rows] = buffers.reshape((len(buffers), *self.out.shape[1:]))
        else:
            self.out[rows] = channel.reduce_rows(buffers)

    def copy_row(self, i: int, other: _Ring, j: int) -> None:
        self.out[i] = other.out[j]
        self.ring[i] = other.ring[j]


class Schedule:
    """The sampling schedule of `channels` and the samples and outputs of `num_envs`
    environments.

    The one schedule of `composer.Environment` (a schedule of one environment) and
    `composer.VectorEnvironment` (of num_envs): every array has a leading environment axis, and
    every per-step method takes the environments it concerns as `rows`, `ALL` (every one) or
    ascending indices, with their physics steps since each one's reset (`steps`: one number for
    all, or one each). Environments reset at different times, so each has its own ring of
    samples and its own phase of the schedule (`phases`: one for all, or one each).

    The schedule samples only what some observation will show (`Channel.needed`): with the
    default options an observable is read once per control step, after the last physics step,
    and copied straight to the output. It repeats every `period` control steps, the least
    common multiple of each observable's interval with the substeps, counted in control steps.
    A sample is corrupted when it is taken, with its environment's random state
    (`corruptor(value, random_state=state)`); the buffer of the newest visible samples is
    reduced when an observation is finished (`Channel.reduce_rows`).
    """

    def __init__(
        self,
        channels: Sequence[Channel],
        substeps: int,
        num_envs: int,
        flatten: bool,
        apart: Collection[int] = (),
    ) -> None:
        """Allocate the outputs ((num_envs, ...) per channel, or (num_envs, size) when
        flattened) and rings, and compute when each channel is sampled, for control steps
        of `substeps` physics steps. Channels `apart` (direct ones) are sampled by the
        schedule's owner, who writes their outputs itself (`block`): `sample` leaves them
        out, and `offsets` still counts them."""
        self.channels = list(channels)
        self.names = [channel.name for channel in self.channels]
        self.substeps = substeps
        self.num_envs = num_envs
        self.flatten = flatten
        self._apart = frozenset(apart)
        outs = self._allocate()
        self._buffers: list[_Direct | _Ring] = [
            _Direct(out) if channel.direct else _Ring(channel, out)
            for channel, out in zip(self.channels, outs, strict=True)
        ]
        self._outputs = list(zip(self.names, outs, strict=True))
        self._rows: dict[int, list[tuple[str, np.ndarray]]] = {}  # views of a row's outputs
        self._shown = [b for b in self._buffers if isinstance(b, _Ring)]
        self._plan()

    def _allocate(self) -> list[np.ndarray]:
        """Each channel's output: a view of columns of one (n, size) float64 block where
        it is float64 (every channel when flattened), else an array of its own."""
        n, channels = self.num_envs, self.channels
        in_block = [self.flatten or c.dtype == np.float64 for c in channels]
        sizes = [
            math.prod(c.output_shape) if b else 0 for c, b in zip(channels, in_block, strict=True)
        ]
        self._flat = np.zeros((n, sum(sizes)), dtype=np.float64)
        starts = np.cumsum([0, *sizes])
        self._starts: list[int | None] = [
            int(a) if b else None for a, b in zip(starts[:-1], in_block, strict=True)
        ]
        # Views into the block's rows (splitting their contiguous last axis keeps them views).
        return [
            self._flat[:, a:b].reshape(n, *c.output_shape)
            if block
            else np.zeros((n, *c.output_shape), dtype=c.dtype)
            for c, a, b, block in zip(channels, starts[:-1], starts[1:], in_block, strict=True)
        ]

    def _plan(self) -> None:
        """Per phase of the period and physics step `offset` (1..substeps) of a control
        step: the channels sampled after that step."""
        substeps, channels = self.substeps, self.channels
        period = 1
        for channel in channels:
            period = math.lcm(period, math.lcm(channel.interval, substeps) // substeps)
        self.period = period
        self._due: list[list[tuple[int, ...]]] = []
        self._offsets: list[list[int]] = []
        # _table[phase, offset, k]: whether channel k samples then (for rows of many phases).
        self._table = np.zeros((period, substeps + 1, len(channels)), dtype=bool)
        for phase in range(period):
            due: list[tuple[int, ...]] = [()]
            offsets = []
            for offset in range(1, substeps + 1):
                step = phase * substeps + offset
                needed = [k for k, c in enumerate(channels) if c.needed(step, substeps)]
                if needed:
                    offsets.append(offset)
                due.append(tuple(k for k in needed if k not in self._apart))
                self._table[phase, offset, list(due[-1])] = True
            self._due.append(due)
            self._offsets.append(offsets)
        self._every = np.arange(self.num_envs)

    @property
    def counts_steps(self) -> bool:
        """Whether sampling and finishing read the physics steps and schedule phases
        given them (a buffered, delayed, corrupted or reduced channel, or a period longer
        than a control step); if not, `sample` and `finish` may be given 0 for both."""
        return self.period > 1 or bool(self._shown)

    @property
    def observation_space(self) -> spaces.Dict | spaces.Box:
        """One environment's observation space: a Dict of each channel's Box in the
        channels' order, or one float64 Box when flattened."""
        if not self.flatten:
            # Pairs, not a mapping: gymnasium's Dict sorts a mapping's keys, keeps pairs'.
            return spaces.Dict([(c.name, c.box()) for c in self.channels])
        lows = [c.low.ravel() for c in self.channels]
        highs = [c.high.ravel() for c in self.channels]
        return spaces.Box(
            np.concatenate(lows) if lows else np.zeros(0),
            np.concatenate(highs) if highs else np.zeros(0),
            dtype=np.float64,
        )

    # -- per step --------------------------------------------------------------------------

    def offsets(self, phases: int | np.ndarray) -> list[int]:
        """The physics steps (1..substeps) of a control step after which some channel is
        sampled, ascending, for environments in schedule phase(s) `phases`."""
        if self.period == 1:
            return self._offsets[0]
        if isinstance(phases, int | np.integer):
            return self._offsets[phases]
        return sorted({offset for phase in np.unique(phases) for offset in self._offsets[phase]})

    def sample(
        self,
        phases: int | np.ndarray,
        offset: int,
        rows: Rows,
        steps: Any,
        read: Read,
        random_states: RandomStates,
    ) -> None:
        """Sample the channels due after physics step `offset` of a control step, for
        environments `rows` in schedule phases `phases` (one for all, or one per row) at
        physics steps `steps` (since each one's reset): `read(k, rows)` gives channel k's
        values of those rows, (n, *shape) (or one environment's value, for one row);
        `random_states(ids)` their random states, for corruptors."""
        buffers = self._buffers
        if not isinstance(phases, np.ndarray):
            for k in self._due[phases][offset]:
                buffers[k].take(rows, read(k, rows), steps, random_states)
            return
        ids = self._every if isinstance(rows, slice) else rows
        due = self._table[phases, offset]  # (n, channels): who samples what
        for channel in np.flatnonzero(due.any(axis=0)).tolist():
            chosen = due[:, channel]
            if chosen.all():
                buffers[channel].take(rows, read(channel, rows), steps, random_states)
            else:
                some = ids[chosen]
                buffers[channel].take(some, read(channel, some), steps[chosen], random_states)

    def restart(
        self, k: int, rows: Rows, values: Any, random_states: RandomStates, zero_padding: bool
    ) -> None:
        """Start the episodes of environments `rows` for channel k: `values` sampled at
        step 0; before them the reset value (or zeros, with `zero_padding`)."""
        self._buffers[k].restart(rows, values, random_states, zero_padding)

    def output(self, k: int) -> np.ndarray:
        """Channel k's outputs, (num_envs, *output_shape): what the owner writes for a
        channel sampled apart."""
        return self._buffers[k].out

    def block(self, k: int) -> tuple[np.ndarray, int] | None:
        """Where channel k's outputs are: the (num_envs, size) float64 array whose columns
        from the second item on they are a view of, or None for an array of their own."""
        start = self._starts[k]
        return None if start is None else (self._flat, start)

    def finish(self, rows: Rows, steps: Any) -> None:
        """Complete the buffered, delayed, corrupted or reduced observations of
        environments `rows` after their physics steps `steps`."""
        for buffer in self._shown:
            buffer.show(rows, steps)

    # -- outputs -----------------------------------------------------------------------------

    def observation(self) -> dict[str, np.ndarray] | np.ndarray:
        """Every environment's current observation, new arrays: a dict of (num_envs, ...)
        arrays by name, or (num_envs, size) when flattened."""
        if self.flatten:
            return self._flat.copy()
        return {name: out.copy() for name, out in self._outputs}

    def row(self, i: int) -> dict[str, np.ndarray] | np.ndarray:
        """Environment i's current observation, new arrays."""
        if self.flatten:
            return self._flat[i].copy()
        views = self._rows.get(i)
        if views is None:  # out[i, ...]: a 0-d array, where out[i] would be a scalar
            views = self._rows[i] = [(name, out[i, ...]) for name, out in self._outputs]
        return {name: view.copy() for name, view in views}

    def copy_row(self, i: int, other: Schedule, j: int) -> None:
        """Make environment i's samples and outputs those of environment j of `other`, a
        schedule of the same channels."""
        for mine, theirs in zip(self._buffers, other._buffers, strict=True):
            mine.copy_row(i, theirs, j)  # type: ignore[arg-type]
