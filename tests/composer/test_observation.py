"""Observables: schedule, buffer, delay, aggregation and corruption against values worked
out by hand, bounds carried into the observation space, and the default observables."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.utils import seeding

import composer
from arenas import Floor
from composer import observation
from tests.composer.scenes import Pendulum
from tests.conftest import gym_model

DT = 0.01  # physics timestep
SUBSTEPS = 5


def step_count(physics) -> np.ndarray:
    """The number of physics steps since reset, read from the simulation time."""
    return np.array([physics.data.time / DT])


class ClockTask(composer.Task):
    """Serves the given task observables; 5 physics steps of 0.01 s per control step."""

    def __init__(self, **observables: observation.Observable) -> None:
        self._arena = Floor()
        self._observables = observables
        for item in observables.values():
            item.enabled = True
        self.set_timesteps(control_timestep=DT * SUBSTEPS, physics_timestep=DT)

    @property
    def root_entity(self):
        return self._arena

    @property
    def task_observables(self):
        return self._observables

    def get_reward(self, physics):
        return 0.0


class SubstepClockTask(ClockTask):
    """The same, with a substep hook: physics steps then run one at a time."""

    def after_substep(self, physics, random_state):
        self.substeps_seen = getattr(self, "substeps_seen", 0) + 1


def observe(
    steps: int = 4, seed: int = 0, task_class: type = ClockTask, **observables
) -> dict[str, list[np.ndarray]]:
    env = composer.Environment(task_class(**observables))
    obs, _ = env.reset(seed=seed)
    seen = {name: [obs[name]] for name in observables}
    for _ in range(steps):
        obs = env.step(np.zeros(0))[0]
        for name in observables:
            seen[name].append(obs[name])
    return seen


def test_default_options_show_the_value_after_the_last_physics_step():
    seen = observe(clock=observation.Generic(step_count))["clock"]
    np.testing.assert_allclose(np.concatenate(seen), [0, 5, 10, 15, 20])


def test_update_interval_holds_the_newest_sample():
    # Samples at 0, 3, 6, 9, 12, 15, 18: the newest one at each 5th step.
    seen = observe(clock=observation.Generic(step_count, update_interval=3))["clock"]
    np.testing.assert_allclose(np.concatenate(seen), [0, 3, 9, 15, 18])


def test_delay_shows_samples_taken_delay_steps_earlier():
    # At step T the newest sample taken at or before T - 7; before the episode, step 0's.
    seen = observe(clock=observation.Generic(step_count, delay=7))["clock"]
    np.testing.assert_allclose(np.concatenate(seen), [0, 0, 3, 8, 13])


def buffered(**options) -> observation.Observable:
    return observation.Generic(step_count, update_interval=2, buffer_size=3, delay=3, **options)


# Samples every 2 steps, visible 3 steps later, the 3 newest: at T = 0, 5, 10, 15, 20 the
# visible samples end at 0 (only the reset value held before), 2, 6, 12, 16.
BUFFERS = [[0, 0, 0], [0, 0, 2], [2, 4, 6], [8, 10, 12], [12, 14, 16]]


@pytest.mark.parametrize("task_class", [ClockTask, SubstepClockTask])
def test_buffer_with_interval_and_delay_matches_the_schedule_by_hand(task_class):
    seen = observe(task_class=task_class, clock=buffered())["clock"]
    np.testing.assert_allclose(np.stack(seen)[..., 0], BUFFERS)


@pytest.mark.parametrize(
    ("aggregator", "expected"),
    [
        ("mean", [0, 2 / 3, 4, 10, 14]),
        ("max", [0, 2, 6, 12, 16]),
        ("min", [0, 0, 2, 8, 12]),
        ("sum", [0, 2, 12, 30, 42]),
        ("median", [0, 0, 4, 10, 14]),
    ],
)
def test_aggregators_reduce_the_buffer(aggregator, expected):
    seen = observe(clock=buffered(aggregator=aggregator))["clock"]
    np.testing.assert_allclose(np.concatenate(seen), expected)


def test_corruptor_draws_from_the_environment_random_state():
    std = 0.5
    seen = observe(
        seed=11, clock=observation.Generic(step_count, corruptor=observation.GaussianNoise(std))
    )
    # One draw at reset, then one per control step: only the sample shown is taken.
    generator, _ = seeding.np_random(11)
    noise = np.random.RandomState(generator.bit_generator).normal(0, std, size=5)
    np.testing.assert_allclose(np.concatenate(seen["clock"]), np.array([0, 5, 10, 15, 20]) + noise)


def test_only_samples_that_are_shown_are_read():
    reads = []

    def counting(physics):
        reads.append(physics.data.time)
        return step_count(physics)

    observe(steps=2, clock=observation.Generic(counting))
    # Once at construction (shape), once at reset, once per control step.
    np.testing.assert_allclose(reads, [0, 0, 0.05, 0.1])
    reads.clear()
    observe(steps=1, clock=observation.Generic(counting, buffer_size=2))
    np.testing.assert_allclose(reads, [0, 0, 0.04, 0.05])


def test_bounds_survive_buffers_and_aggregators():
    def unit(**options):
        return observation.Generic(lambda physics: np.zeros(2), bounds=(-1, 1), **options)

    env = composer.Environment(
        ClockTask(
            plain=unit(),
            stacked=unit(buffer_size=3),
            mean=unit(buffer_size=3, aggregator="mean"),
            max=unit(buffer_size=3, aggregator="max"),
            total=unit(buffer_size=3, aggregator="sum"),
            noisy=unit(corruptor=observation.GaussianNoise(0.1)),
            custom=unit(
                buffer_size=2, aggregator=lambda b: np.median(b, axis=0), aggregator_bounds=(-1, 1)
            ),
            whole=unit(buffer_size=2, aggregator=np.median),  # called f(buffer): one number
        )
    )
    space = env.observation_space
    assert space["plain"] == spaces.Box(-1.0, 1.0, (2,), np.float64)
    assert space["stacked"] == spaces.Box(-1.0, 1.0, (3, 2), np.float64)
    assert space["mean"] == space["max"] == space["custom"] == space["plain"]
    assert space["total"] == spaces.Box(-3.0, 3.0, (2,), np.float64)
    assert space["noisy"] == spaces.Box(-np.inf, np.inf, (2,), np.float64)
    assert space["whole"] == spaces.Box(-np.inf, np.inf, (), np.float64)
    obs, _ = env.reset(seed=0)
    assert obs in space


def test_integer_observables_are_bounded_by_their_type_range():
    # int64's range is not exact in float64: its bounds must not wrap around when cast.
    def count(dtype):
        return observation.Generic(lambda physics: np.array([3, 4], dtype=dtype))

    env = composer.Environment(
        ClockTask(wide=count(np.int64), narrow=count(np.int32), small=count(np.uint8))
    )
    for name, dtype in (("wide", np.int64), ("narrow", np.int32), ("small", np.uint8)):
        box = env.observation_space[name]
        assert box.dtype == dtype
        assert (box.low == np.iinfo(dtype).min).all() and (box.high == np.iinfo(dtype).max).all()
    obs, _ = env.reset(seed=0)
    assert obs in env.observation_space


def test_invalid_options_name_the_observable():
    with pytest.raises(composer.ObservableError, match=r"'clock'.*buffer_size"):
        composer.Environment(ClockTask(clock=observation.Generic(step_count, buffer_size=0)))
    with pytest.raises(composer.UnknownAggregatorError, match=r"'mode'.*'median'"):
        observation.Generic(step_count, aggregator="mode")
    assert issubclass(composer.UnknownAggregatorError, KeyError)
    with pytest.raises(composer.ObservableError, match="'clock' could not be read"):
        composer.Environment(ClockTask(clock=observation.Generic(lambda physics: 1 / 0)))
    with pytest.raises(composer.ObservableError, match="no option 'interval'"):
        observation.Generic(step_count).configure(interval=2)


def test_mjcf_features_and_cameras_read_bound_elements():
    pendulum = Pendulum()
    task = ClockTask(
        angle=observation.MJCFFeature("qpos", [pendulum.hinge]),
        tip=observation.MJCFFeature("xpos", pendulum.tip, index=2),
        image=observation.MJCFCamera(pendulum.camera, height=24, width=32),
        depth=observation.MJCFCamera(pendulum.camera, height=24, width=32, depth=True),
    )
    task.root_entity.attach(pendulum)
    env = composer.Environment(task)
    space = env.observation_space
    assert space["image"] == spaces.Box(0, 255, (24, 32, 3), np.uint8)
    assert space["depth"].dtype == np.float32 and (space["depth"].low == 0).all()
    obs, _ = env.reset(seed=0)
    assert obs in space
    assert obs["angle"].shape == (1,) and obs["tip"].shape == ()
    np.testing.assert_allclose(obs["tip"], 0.5)  # the tip hangs 0.5 below the 1 m pivot
    np.testing.assert_array_equal(task.task_observables["angle"](env.physics), obs["angle"])
    assert obs["image"].std() > 0


def test_model_entity_default_observables_and_actions():
    humanoid = composer.Entity.from_path(gym_model("humanoid"))
    assert list(humanoid.observables) == [
        "joint_positions", "joint_velocities", "actuator_activations"
    ]  # fmt: skip
    assert all(item.enabled for item in humanoid.observables.values())
    assert len(humanoid.actuators) == 17
    env = composer.Environment(composer.NullTask(humanoid))
    # Motors have no activation: that observable is empty and left out.
    assert list(env.observation_space.spaces) == [
        "humanoid/joint_positions", "humanoid/joint_velocities"
    ]  # fmt: skip
    assert env.observation_space["humanoid/joint_positions"].shape == (24,)
    assert env.action_space.shape == (17,)


def test_observables_collection_and_decorator():
    pendulum = Pendulum()
    assert pendulum.joint_positions is pendulum.observables["joint_positions"]
    assert pendulum.observables.joint_positions is pendulum.joint_positions
    assert not pendulum.joint_positions.enabled
    pendulum.observables.enable_all()
    assert all(item.enabled for item in pendulum.observables.values())
    with pytest.raises(composer.ObservableNotFoundError, match="'pendulum' has no observable 'x'"):
        getattr(pendulum.observables, "x")  # noqa: B009 - attribute access is the test
    with pytest.raises(composer.ObservableError, match="already has"):
        pendulum.observables.add_observable("orientation", observation.Generic(step_count))

    class Custom(composer.Observables):
        @composer.observable
        def tip_height(self):
            return observation.MJCFFeature("xpos", self._entity.tip, index=2)

    class WithCustom(Pendulum):
        def _build_observables(self):
            return Custom(self)

    custom = WithCustom()
    assert "tip_height" in custom.observables and "orientation" in custom.observables
