"""The compiled observation schedule against the slow, eager way: an oracle environment
records every observable's uncorrupted value after every physics step, and each observation
is rebuilt from that history by the documented rule (samples every `update_interval` steps,
visible `delay` steps later, the `buffer_size` newest visible ones, padded with the reset
value or zeros, corrupted when taken, reduced by the aggregator). Equal to the last bit, for
single environments (flattened or not, dm_control's shapes and padding) and, through them,
for vector environments."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import composer
import mjcf
from composer import observation
from composer.observation import ObservationPadding
from tests.composer.scenes import SwingTask

SUBSTEPS = 4
STEPS = 40


def _scaled(value: np.ndarray, random_state: Any = None) -> np.ndarray:
    """A corruptor the oracle can repeat: deterministic, with the random state a corruptor
    is handed."""
    return value * 2.0 + 0.25


def _spread(buffer: np.ndarray) -> np.ndarray:
    """A callable aggregator: the range over the buffer."""
    return buffer.max(axis=0) - buffer.min(axis=0)


def _physics_steps(physics: mjcf.Physics) -> np.ndarray:
    """The physics steps since reset, an integer observable."""
    return np.array([round(physics.data.time / 0.005)], dtype=np.int32)


class ScheduledSwing(SwingTask):
    """The swinging pendulum observed with every option of the schedule, on intervals that
    do and do not divide the 4 physics steps of a control step."""

    def __init__(self, terminate_above: float = np.inf) -> None:
        super().__init__(substeps=SUBSTEPS, terminate_above=terminate_above)
        pendulum = self.pendulum
        hinge, tip = pendulum.hinge, pendulum.tip
        qpos = observation.MJCFFeature("qpos", [hinge])
        qvel = observation.MJCFFeature("qvel", [hinge])
        self._scheduled: dict[str, observation.Observable] = {
            "angle_mean": observation.MJCFFeature(
                "qpos", [hinge], update_interval=3, buffer_size=3, delay=2, aggregator="mean"
            ),
            "angle_max": observation.MJCFFeature(
                "qpos", [hinge], update_interval=4, buffer_size=2, aggregator="max"
            ),
            "angle_spread": observation.MJCFFeature(
                "qpos", [hinge], buffer_size=2, delay=1, aggregator=_spread
            ),
            "speed_scaled": observation.MJCFFeature(
                "qvel", [hinge], update_interval=2, buffer_size=2, corruptor=_scaled
            ),
            "speed_scaled_now": observation.MJCFFeature("qvel", [hinge], corruptor=_scaled),
            "speed_min": observation.MJCFFeature(
                "qvel", [hinge], update_interval=5, buffer_size=3, delay=3, aggregator="min"
            ),
            "tip_median": observation.MJCFFeature(
                "xpos", tip, buffer_size=4, delay=5, aggregator="median"
            ),
            "tip_late": observation.BatchGeneric(
                lambda physics: physics.bind(tip).xpos[:, 2:], delay=7
            ),
            "tip_stack": observation.MJCFFeature("xpos", tip, update_interval=3, buffer_size=3),
            "clock_sum": observation.Generic(_physics_steps, buffer_size=3, aggregator="sum"),
            "clock_one": observation.Generic(_physics_steps, buffer_size=1, delay=6),
            "angle": qpos,
            "speed": qvel,
        }
        for item in self._scheduled.values():
            item.enabled = True

    @property
    def task_observables(self) -> dict[str, observation.Observable]:
        return self._scheduled


class Recording(ScheduledSwing):
    """The oracle: records every enabled observable's uncorrupted value after the reset and
    after every physics step (a substep hook makes the steps run one at a time)."""

    history: dict[str, list[np.ndarray]]

    def record(self, physics: mjcf.Physics) -> None:
        for name, item in self.enabled_observables().items():
            self.history.setdefault(name, []).append(
                np.array(observation.reader_of(item, physics)())
            )

    def after_substep(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        self.record(physics)


def _expected(
    item: observation.Observable,
    history: list[np.ndarray],
    step: int,
    dtype: np.dtype,
    strip: bool,
    padding: ObservationPadding,
) -> np.ndarray:
    """The observation of `item` after physics step `step`, from its whole history."""
    interval, size = item.update_interval, item.buffer_size or 1
    delay = item.delay or 0
    corrupt = item.corruptor or (lambda value, random_state=None: value)

    def sample(at: int) -> np.ndarray:
        return np.asarray(corrupt(np.asarray(history[at], dtype=dtype), random_state=None))

    visible = [at for at in range(0, step + 1, interval) if at + delay <= step]
    shown = [sample(at) for at in visible[-size:]]
    pad = np.zeros_like(sample(0)) if padding is ObservationPadding.ZERO else sample(0)
    buffer = np.stack([pad] * (size - len(shown)) + shown)
    if item.aggregator is not None:
        return np.asarray(item.aggregator(buffer), dtype=dtype)
    if size == 1 and strip:
        return buffer[0].astype(dtype)
    return buffer.astype(dtype)


def _run(
    seed: int, flatten: bool, strip: bool, padding: ObservationPadding
) -> tuple[list[Any], list[Any], composer.Environment]:
    """The observations of the environment under test and the oracle's, step by step."""
    options = dict(
        flatten_observations=flatten,
        strip_singleton_obs_buffer_dim=strip,
        delayed_observation_padding=padding,
    )
    tested = composer.Environment(ScheduledSwing(), **options)
    oracle_task = Recording()
    oracle = composer.Environment(oracle_task, **options)
    spaces = composer.Environment(ScheduledSwing(), **{**options, "flatten_observations": False})
    dtypes = {name: box.dtype for name, box in spaces.observation_space.spaces.items()}
    got = [tested.reset(seed=seed)[0]]
    oracle.reset(seed=seed)
    oracle_task.history = {}
    oracle_task.record(oracle.physics)
    actions = np.random.default_rng(seed).uniform(-1, 1, (STEPS, 1))
    for action in actions:
        got.append(tested.step(action)[0])
        oracle.step(action)
    expected = []
    for t in range(STEPS + 1):
        values = {
            name: _expected(
                item, oracle_task.history[name], t * SUBSTEPS, dtypes[name], strip, padding
            )
            for name, item in sorted(oracle_task.enabled_observables().items())
        }
        if flatten:
            expected.append(np.concatenate([v.ravel().astype(np.float64) for v in values.values()]))
        else:
            expected.append(values)
    return got, expected, tested


def _assert_identical(got: Any, expected: Any) -> None:
    if isinstance(expected, dict):
        assert list(got) == list(expected)
        for name in expected:
            _assert_identical(got[name], expected[name])
        return
    assert got.dtype == expected.dtype and got.shape == expected.shape
    assert np.array_equal(got, expected), (got, expected)


@pytest.mark.parametrize(
    ("flatten", "strip", "padding"),
    [
        (False, True, ObservationPadding.INITIAL_VALUE),
        (True, True, ObservationPadding.INITIAL_VALUE),
        (False, False, ObservationPadding.ZERO),
        (True, False, ObservationPadding.ZERO),
    ],
    ids=["dict", "flat", "dm_control shapes, zero padding", "flat, zero padding"],
)
def test_every_observation_equals_the_one_rebuilt_from_the_whole_history(flatten, strip, padding):
    got, expected, env = _run(seed=5, flatten=flatten, strip=strip, padding=padding)
    for t, (value, oracle) in enumerate(zip(got, expected, strict=True)):
        try:
            _assert_identical(value, oracle)
        except AssertionError as e:
            raise AssertionError(f"control step {t}: {e}") from None
    assert got[-1] in env.observation_space


def test_the_oracle_sees_what_it_checks():
    """The history differs from step to step and the options change what is shown: the
    comparison above could fail."""
    got, _, _ = _run(seed=5, flatten=False, strip=True, padding=ObservationPadding.INITIAL_VALUE)
    angles = np.array([obs["angle"][0] for obs in got])
    assert len(np.unique(angles)) == len(angles)
    assert not np.array_equal(got[3]["angle_mean"], got[3]["angle"])
    assert got[1]["clock_one"][0] == 0 and got[2]["clock_one"][0] == 2  # 6 steps late
    assert got[1]["tip_stack"].shape == (3, 3)


@pytest.mark.parametrize("padding", list(ObservationPadding))
def test_vector_environment_keeps_the_same_schedule_and_options(padding):
    options = dict(strip_singleton_obs_buffer_dim=False, delayed_observation_padding=padding)

    def swing() -> ScheduledSwing:
        return ScheduledSwing(terminate_above=0.6)

    vector = composer.VectorEnvironment(
        swing, 4, time_limit=0.3, autoreset_mode=AutoresetMode.NEXT_STEP, **options
    )
    reference = SyncVectorEnv(
        [lambda: composer.Environment(swing(), time_limit=0.3, **options)] * 4
    )
    assert vector.single_observation_space["clock_one"].shape == (1, 1)
    got, expected = vector.reset(seed=2)[0], reference.reset(seed=2)[0]
    rng = np.random.default_rng(2)
    ends = []
    for _ in range(60):  # through autoresets at different steps: different phases
        _assert_identical(got, expected)
        actions = rng.uniform(-1, 1, (4, 1))
        got, _, terminated, truncated, _ = vector.step(actions)
        expected = reference.step(actions)[0]
        ends.append(terminated | truncated)
    _assert_identical(got, expected)
    assert any(0 < end.sum() < 4 for end in ends)
