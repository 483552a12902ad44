"""Observations of every environment at once, on the schedule a single Environment keeps.

    speed = BatchGeneric(lambda physics: physics.field('qvel')[:, :1])   # (n, 1)

Batched observables (a `batch_reader`, or an `MJCFFeature` of a field MuJoCo's batch binds)
are read for all environments in one call, the others per environment with a single
environment's reader; `BatchObservations` says how they are buffered and corrupted. A batch
reader of the wrong shape raises BatchError.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from composer.batch.vector import VectorPhysics
from composer.errors import BatchError
from composer.observation import MJCFCamera, MJCFFeature, Observable, Updater
from composer.observation.schedule import ALL, Rows, Schedule
from composer.vector.rendering import Ids


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
    name: str, item: Observable, shape: tuple[int, ...], physics: VectorPhysics
) -> Callable[[], np.ndarray] | None:
    """The reader of observable `name` (values of `shape`) for every environment of
    `physics`, or None: it is read per environment. Raises BatchError for an observable's
    own batch reader giving the wrong shape."""
    read = item.batch_reader(physics)
    own = read is not None
    if read is None and isinstance(item, MJCFFeature):
        read = _feature_reader(item, physics)
    if read is None:
        return None
    got, expected = np.shape(read()), (physics.num_envs, *shape)
    if got == expected:
        return read
    if own:
        raise BatchError(
            f"observable {name!r}: its batch reader gave shape {got}; expected {expected}"
        )
    return None  # an index the batched binding cannot mirror: per environment


class BatchObservations:
    """The observation pipeline of a VectorEnvironment: every environment's enabled
    observables, sampled on its own schedule into (num_envs, ...) arrays.

    An observable is read for all environments in one call when its `batch_reader(physics)`
    gives a function of no arguments returning a (num_envs, *shape) array (as `BatchGeneric`
    and `entities.features` do), or it is an `MJCFFeature` of an MjData field MuJoCo's batch
    binds (automatic: qpos, qvel, xpos, sensordata ...). Others are read once per environment
    from its materialized MjData, with the reader a single environment uses. The schedule,
    buffers, corruption and reduction are `composer.observation.schedule`'s, the same a single
    `Environment` keeps (as a schedule of one environment), here over num_envs: environments
    reset at different steps, so each keeps its own phase and ring of samples. Corruptors run
    once per environment with its random state (`corruptor(value, random_state=state)`); named
    aggregators reduce every environment at once, callable ones run once per environment.
    """

    def __init__(
        self,
        updater: Updater,
        physics: VectorPhysics,
        read_env: Callable[[int, int], np.ndarray],
        random_state: Callable[[int], np.random.RandomState],
        render_envs: Callable[[Ids, int], np.ndarray],
    ) -> None:
        """The pipeline of `updater` (the first environment's) for the `physics.num_envs`
        environments of `physics` (every one). `read_env(i, k)` reads observable k of
        environment i from its own physics, `render_envs(ids, k)` camera observable k of
        environments `ids` ((len(ids), *shape)); `random_state(i)` is environment i's.
        Raises BatchError for a batch reader of the wrong shape."""
        self.num_envs = physics.num_envs
        channels = updater.channels
        self._rendered = [isinstance(c.observable, MJCFCamera) for c in channels]
        self._reads = [
            None if rendered else _batch_reader(c.name, c.observable, c.shape, physics)
            for c, rendered in zip(channels, self._rendered, strict=True)
        ]
        # With a period of one control step, direct channels read for all environments
        # at once are sampled here, apart from the schedule: a read and a copy each.
        apart = {
            k: read
            for k, (c, read) in enumerate(zip(channels, self._reads, strict=True))
            if read is not None and c.direct and updater.period == 1
        }
        self.schedule = Schedule(
            channels, updater.substeps, self.num_envs, updater.flatten, apart=apart
        )
        self.period = self.schedule.period
        # Whether `sample` and `finish` need the environments' phases and physics steps.
        self.counts_steps = self.schedule.counts_steps
        substeps = updater.substeps
        # Per physics step of the control step (1..substeps): the channels sampled apart
        # then, as (output, read), and whether the schedule samples others.
        self._apart: list[list[tuple[np.ndarray, Callable[[], np.ndarray]]]] = [[]]
        self._scheduled = [False]
        for offset in range(1, substeps + 1):
            due = [k for k, c in enumerate(channels) if c.needed(offset, substeps)]
            self._apart.append([(self.schedule.output(k), apart[k]) for k in due if k in apart])
            self._scheduled.append(any(k not in apart for k in due))
        self.rendered = [c.name for c, r in zip(channels, self._rendered, strict=True) if r]
        self.per_environment = [
            c.name
            for c, read, rendered in zip(channels, self._reads, self._rendered, strict=True)
            if read is None and not rendered
        ]
        self._read_env = read_env
        self._render_envs = render_envs
        self._random_state = random_state

    def _rows(self, ids: np.ndarray) -> Rows:
        return ALL if len(ids) == self.num_envs else ids

    def _random_states(self, ids: np.ndarray) -> list[np.random.RandomState]:
        return [self._random_state(i) for i in ids]

    def offsets(self, phases: int | np.ndarray) -> list[int]:
        """The physics steps (1..substeps) of this control step after which some
        observable is sampled, for environments in schedule phases `phases` (one for all,
        or one each)."""
        return self.schedule.offsets(phases)

    def sample(
        self, ids: np.ndarray, phases: int | np.ndarray, offset: int, first: int | np.ndarray
    ) -> None:
        """Sample the observables due after physics step `offset` of the control step, for
        environments `ids` in phases `phases` (one for all, or one each) whose control
        step began at steps `first` (0 for all where the schedule does not count steps:
        `counts_steps`)."""
        rows = self._rows(ids)
        if self.period == 1:
            for out, read in self._apart[offset]:
                out[rows] = read() if rows is ALL else read()[rows]
            if not self._scheduled[offset]:
                return
        self.schedule.sample(
            0 if self.period == 1 else phases, offset, rows, first + offset,
            self._read, self._random_states,
        )  # fmt: skip

    def _read(self, k: int, rows: Rows) -> np.ndarray:
        """Observable k of environments `rows`: (n, *shape)."""
        batch = self._reads[k]
        if batch is not None:
            return batch() if isinstance(rows, slice) else batch()[rows]
        ids = range(self.num_envs) if isinstance(rows, slice) else rows
        if self._rendered[k]:
            return self._render_envs(ids, k)
        return np.stack([np.asarray(self._read_env(i, k)) for i in ids])

    def finish(self, ids: np.ndarray, steps: np.ndarray) -> None:
        """Complete buffered, delayed or aggregated observations of environments `ids`,
        after their physics steps `steps` (counted from each one's reset)."""
        self.schedule.finish(self._rows(ids), steps)

    def load(self, i: int, updater: Updater) -> None:
        """Take environment i's state from its own pipeline `updater`, just reset (the
        reset observation and the samples it holds). Raises BatchError if its observables
        are not those of the first environment."""
        if updater.names != self.schedule.names:
            raise BatchError(
                f"environment {i} observes {updater.names}, the first environment "
                f"{self.schedule.names}: every environment must enable the same observables"
            )
        self.schedule.copy_row(i, updater.schedule, 0)

    def observation(self) -> dict[str, np.ndarray] | np.ndarray:
        """Every environment's current observation, new arrays: a dict of (num_envs, ...)
        arrays by name, or (num_envs, size) when flattened."""
        return self.schedule.observation()

    def row(self, i: int) -> dict[str, np.ndarray] | np.ndarray:
        """Environment i's current observation, as its own Environment would return it."""
        return self.schedule.row(i)
