"""The observation pipeline of one environment: observables sampled on schedule into
preallocated arrays.

    updater = Updater({'arm/qpos': qpos, ...}, physics, substeps=5, flatten=False)
    obs = updater.reset(random_state)              # samples at step 0
    for offset in updater.offsets(k):              # control step k, from physics step first:
        updater.sample(k, first, offset)           # after stepping the physics up to offset
    obs = updater.observation(last_step)           # fresh arrays, safe to keep

An observable that cannot be read raises ObservableError naming it; empty ones are left out.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
from gymnasium import spaces

from composer import errors
from composer.observation.channel import Channel
from composer.observation.fused import FusedRead, Plan
from composer.observation.observable import Observable, reader_of, row_reader_of
from composer.observation.schedule import ALL, Schedule


class ObservationPadding(enum.Enum):
    """What a buffer holds before its first samples are visible (dm_control's enum):
    the reset value (INITIAL_VALUE) or zeros (ZERO)."""

    INITIAL_VALUE = -1
    ZERO = 0


class Updater:
    """Samples one environment's enabled observables into preallocated arrays on their
    schedule.

    Each observable is resolved here, once per compile: its reader (`observation.reader_of`:
    its batched reader with a batch of one where that is the form it defines) and its channel
    (`observation.channel`: shape, type, bounds). Observables whose value is empty (e.g.
    activations of a model with none) are left out. Those whose value is rows of bound MjData
    fields (`Observable.field_rows`), shown as sampled, are read together, a gather per field
    (`observation.fused`), instead of one by one through their readers: the same values.
    What is sampled when, and the samples themselves, are kept by `observation.schedule`, the
    schedule a `VectorEnvironment` keeps for all its environments; here it is a schedule of
    one environment.

    Two choices dm_control offers: `strip_singleton_buffer_dim=False` gives an observation of
    `buffer_size` 1 (and no aggregator) its leading buffer axis of length 1, and
    `padding=ObservationPadding.ZERO` fills the buffer with zeros before the first samples are
    visible, where by default (INITIAL_VALUE) the reset value fills it.
    """

    def __init__(
        self,
        observables: Mapping[str, Observable],
        physics: Any,
        substeps: int,
        flatten: bool = False,
        strip_singleton_buffer_dim: bool = True,
        padding: ObservationPadding = ObservationPadding.INITIAL_VALUE,
        *,
        keep_order: bool = False,
    ) -> None:
        """Resolve every observable in `physics` (read once to learn its shape and type),
        in the order of `observables` with `keep_order`, else sorted by name (the order
        of flattened observations); raises ObservableError naming the observable that
        cannot be read."""
        self.substeps = substeps
        self.flatten = flatten
        self.zero_padding = padding is ObservationPadding.ZERO
        self.channels: list[Channel] = []
        self.readers: list[Callable[[], Any]] = []
        plans: list[Plan | None] = []
        for name in observables if keep_order else sorted(observables):
            observable = observables[name]
            observable.validate(name)
            read, value = _resolve(name, observable, physics)
            channel = Channel(name, observable, value, strip_singleton_buffer_dim)
            if math.prod(channel.output_shape) > 0:
                self.channels.append(channel)
                self.readers.append(read)
                fusable = channel.direct and channel.dtype == np.float64
                plans.append(FusedRead.plan(observable, value, physics) if fusable else None)
        self.names = [channel.name for channel in self.channels]
        self._fused_channels = frozenset(k for k, plan in enumerate(plans) if plan is not None)
        # The observables read together (`observation.fused`), for inspection.
        self.fused_names = [self.names[k] for k in sorted(self._fused_channels)]
        # Direct channels read apart are written here, straight into their outputs.
        self._direct_channels = frozenset(
            k for k, channel in enumerate(self.channels)
            if channel.direct and k not in self._fused_channels
        )  # fmt: skip
        apart = self._fused_channels | self._direct_channels
        self.schedule = Schedule(self.channels, substeps, 1, flatten, apart)
        self.period = self.schedule.period
        self.observation_space: spaces.Dict | spaces.Box = self.schedule.observation_space
        self._random_state: Any = None
        self._fuse(physics, plans)
        self._plan_direct(physics, observables)

    def _fuse(self, physics: Any, plans: list[Plan | None]) -> None:
        """One FusedRead per sampling interval of the planned channels, and which of them
        are due after each physics step of each phase of the schedule."""
        by_interval: dict[int, list[int]] = {}
        for k in sorted(self._fused_channels):
            by_interval.setdefault(self.channels[k].interval, []).append(k)
        self._fused: list[tuple[int, FusedRead]] = []  # (a channel of it, the read)
        for ks in by_interval.values():
            columns: list[tuple[Plan, int]] = []
            row = None
            for k in ks:
                plan, block = plans[k], self.schedule.block(k)
                assert plan is not None and block is not None, "float64: in the block"
                row, column = block[0][0], block[1]  # one environment's row of the block
                columns.append((plan, column))
            assert row is not None
            read = FusedRead(physics, columns, row, [self.readers[k] for k in ks])
            self._fused.append((ks[0], read))
        substeps = self.substeps
        # _fused_due[phase][offset]: the fused reads due after that physics step.
        self._fused_due = [
            [
                [read for k, read in self._fused
                 if offset and self.channels[k].needed(phase * substeps + offset, substeps)]
                for offset in range(substeps + 1)
            ]
            for phase in range(self.period)
        ]  # fmt: skip

    def _plan_direct(self, physics: Any, observables: Mapping[str, Observable]) -> None:
        """Which direct channels are due after each physics step of each phase, each with
        its output (a row of one) and its row reader (`row_reader_of`): a sample is one
        assignment of the batched reader's row of one (or the reader's value) to it, the
        same values the schedule's `_Direct.take` writes, without its dispatch."""
        direct = {
            k: (self.schedule.output(k), row_reader_of(observables[self.names[k]], physics))
            for k in sorted(self._direct_channels)
        }
        substeps = self.substeps
        # Whether the schedule samples any other channel then (buffered, delayed ...).
        others = [k for k in range(len(self.channels)) if k not in self._direct_channels
                  and k not in self._fused_channels]  # fmt: skip
        self._scheduled = [
            [any(offset and self.channels[k].needed(phase * substeps + offset, substeps)
                 for k in others) for offset in range(substeps + 1)]
            for phase in range(self.period)
        ]  # fmt: skip
        self._direct_due = [
            [
                [direct[k] for k in direct
                 if offset and self.channels[k].needed(phase * substeps + offset, substeps)]
                for offset in range(substeps + 1)
            ]
            for phase in range(self.period)
        ]  # fmt: skip

    def _read(self, k: int, rows: Any) -> Any:
        return self.readers[k]()

    def _random_states(self, rows: np.ndarray) -> list[Any]:
        return [self._random_state]

    def offsets(self, control_step: int) -> list[int]:
        """The physics steps (1..substeps) of control step `control_step` (counted from
        the reset) after which some observable is sampled, ascending."""
        return self.schedule.offsets(control_step % self.period)

    def sample(self, control_step: int, first: int, offset: int) -> None:
        """Sample what is due after physics step `offset` of control step `control_step`,
        which began after physics step `first` (both counted from the reset)."""
        phase = control_step % self.period
        for read in self._fused_due[phase][offset]:
            read.read()
        for out, read_row in self._direct_due[phase][offset]:
            out[...] = read_row()
        if self._scheduled[phase][offset]:
            self.schedule.sample(
                phase, offset, ALL, first + offset, self._read, self._random_states
            )

    def reset(self, random_state: Any) -> dict[str, np.ndarray] | np.ndarray:
        """Start an episode: sample every observable at step 0 (corruptors draw from
        `random_state` from now on); the first observation."""
        self._random_state = random_state
        schedule, zero, fused = self.schedule, self.zero_padding, self._fused_channels
        for _, read in self._fused:
            read.read()
        for k, read_k in enumerate(self.readers):
            if k not in fused:
                schedule.restart(k, ALL, read_k(), self._random_states, zero)
        return self.observation(0)

    def observation(self, step: int) -> dict[str, np.ndarray] | np.ndarray:
        """The observation after physics step `step` (counted from reset), as new arrays."""
        self.schedule.finish(ALL, step)
        return self.schedule.row(0)


def _resolve(name: str, observable: Observable, physics: Any) -> tuple[Callable[[], Any], Any]:
    """(The reader of `observable` in `physics`, its current value); ObservableError
    naming it if either fails."""
    try:
        read = reader_of(observable, physics)
        return read, read()
    except errors.Error:
        raise  # composer's own, already explicit
    except Exception as e:  # a user's function or a binding failed: say which observable
        raise errors.ObservableError(
            f"observable {name!r} could not be read: {type(e).__name__}: {e}"
        ) from e
