"""One environment reads observables of MjData rows together (composer.observation.fused):
the observation must hold what each one's own reader reads, bit for bit, in every shipped
task, after steps, resets and recompiles, and for any kind of field, index or stage."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest

import composer
import mjcf
import tasks
from composer import observation
from entities import Clipped, HingeAngles
from tasks.suite.observables import BoundField, Concatenated
from tests.composer.scenes import Block, Pendulum


def _assert_observation_is_what_readers_read(env: composer.Environment, obs) -> None:
    """Every observable's entry equals its own reader's value now (each is shown as
    sampled, after the last physics step)."""
    updater = env.updater
    for k, (name, read) in enumerate(zip(updater.names, updater.readers, strict=True)):
        expected = np.asarray(read(), dtype=np.float64)
        shown = obs[name] if isinstance(obs, dict) else _flat_part(updater, obs, k)
        assert shown.tobytes() == expected.tobytes(), name


def _flat_part(updater: observation.Updater, obs: np.ndarray, k: int) -> np.ndarray:
    sizes = [int(np.prod(c.output_shape)) for c in updater.channels]
    start = sum(sizes[:k])
    return obs[start : start + sizes[k]].reshape(updater.channels[k].output_shape)


@pytest.mark.parametrize("flatten", [True, False])
@pytest.mark.parametrize("env_id", list(tasks.IDS))
def test_every_shipped_task_shows_what_its_readers_read(env_id, flatten):
    env = gymnasium.make(env_id, flatten_observations=flatten, time_limit=0.5).unwrapped
    names = set(env.updater.fused_names)
    assert names, "the shipped tasks' entity observables are read together"
    rng = np.random.default_rng(1)
    obs, _ = env.reset(seed=1)
    _assert_observation_is_what_readers_read(env, obs)
    for _ in range(40):  # several episodes: resets in between
        obs, _, terminated, truncated, _ = env.step(rng.uniform(-1, 1, env.action_space.shape))
        _assert_observation_is_what_readers_read(env, obs)
        if terminated or truncated:
            obs, _ = env.reset()
            _assert_observation_is_what_readers_read(env, obs)


class _Scene(composer.Task):
    """A pendulum and a free block with observables of every kind the fused read takes:
    an index, a sensor, a field MuJoCo computes only on demand, an acceleration-stage
    field, bounds per column, and a subclass that reads otherwise."""

    def __init__(self) -> None:
        self._arena = composer.Arena()
        self.pendulum = Pendulum()
        self.block = Block()
        self._arena.attach(self.pendulum)
        self._arena.add_free_entity(self.block)
        self.set_timesteps(control_timestep=0.02, physics_timestep=0.005)
        hinge, body = self.pendulum.hinge, self.block.body
        sensor = self.pendulum.mjcf_model.find("sensor", "angle")
        self._observables = {
            "height": observation.MJCFFeature("xpos", body)[2],
            "columns": observation.MJCFFeature("xmat", [body], index=(slice(None), [0, 4, 8])),
            "sensor": observation.MJCFFeature("sensordata", sensor),
            "external_force": observation.MJCFFeature("cfrc_ext", body),
            "acceleration": Clipped("qacc", [hinge], -50.0, 50.0),
            "tip": Clipped("xpos", self.pendulum.tip, [-0.1, -1, 0.6], [0.1, 1, 2.0]),
            "angle": HingeAngles([hinge]),
            "doubled": _Doubled("qpos", [hinge], -10.0, 10.0),
            "flat": BoundField("xmat", [body], index=(slice(None), [0, 4]), flat=True),
            "turned": BoundField("sensordata", sensor, function=np.arctan),
            "side_by_side": Concatenated(  # two fields, of two stages
                [BoundField("qvel", [hinge]), BoundField("xpos", body, index=slice(0, 2))]
            ),
        }
        for item in self._observables.values():
            item.enabled = True

    @property
    def root_entity(self) -> composer.Entity:
        return self._arena

    @property
    def task_observables(self) -> dict[str, observation.Observable]:
        return self._observables

    def initialize_episode(self, physics, random_state) -> None:
        physics.bind(self.pendulum.hinge).qpos = random_state.uniform(-2, 2)
        self.block.set_pose(physics, [0, 0.3, random_state.uniform(0.2, 0.5)])

    def get_reward(self, physics) -> float:
        return 0.0


class _Doubled(Clipped):
    """Reads twice the clipped value: its own reader, which `field_rows` does not describe."""

    def batch_reader(self, physics):
        read = super().batch_reader(physics)
        return lambda: 2.0 * read()


@pytest.mark.parametrize("legacy_step", [True, False])
def test_indices_sensors_on_demand_fields_and_stages_read_together_as_their_readers(
    legacy_step,
):
    env = composer.Environment(_Scene(), time_limit=0.2, legacy_step=legacy_step)
    names = set(env.updater.fused_names)
    assert {
        "height",
        "columns",
        "sensor",
        "external_force",
        "acceleration",
        "tip",
        "flat",
        "turned",
        "side_by_side",
    } <= names
    assert "angle" in names and "doubled" not in names  # its reader is not the declared one
    rng = np.random.default_rng(2)
    obs, _ = env.reset(seed=2)
    _assert_observation_is_what_readers_read(env, obs)
    for _ in range(30):
        obs, _, _, truncated, _ = env.step(rng.uniform(-1, 1, env.action_space.shape))
        _assert_observation_is_what_readers_read(env, obs)
        if truncated:
            obs, _ = env.reset()
            _assert_observation_is_what_readers_read(env, obs)


def test_a_recompiled_scene_is_read_in_its_new_model():
    task = _Scene()
    env = composer.Environment(task, recompile_mjcf_every_episode=True)
    env.reset(seed=0)
    before = env.physics.model
    task.block.geom.size = [0.08] * 3  # a change of the scene: the next reset recompiles
    obs, _ = env.reset(seed=0)
    assert env.physics.model is not before
    _assert_observation_is_what_readers_read(env, obs)
    obs, *_ = env.step(np.zeros(env.action_space.shape))
    _assert_observation_is_what_readers_read(env, obs)


def test_a_model_replaced_behind_the_environment_fails_as_the_readers_fail():
    task = _Scene()
    env = composer.Environment(task)
    env.reset(seed=3)
    env.physics.reload_from_mjcf_model(task.root_entity.mjcf_model)  # not through a reset
    with pytest.raises(mjcf.BindingError, match="no longer holds"):
        env.step(np.zeros(env.action_space.shape))
