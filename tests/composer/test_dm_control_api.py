"""dm_control's Composer API on ours: observables' configuration and naming, the decorators,
the abstract bases, the observables of the `base` module, and the Environment's options."""

from __future__ import annotations

import numpy as np
import pytest

import composer
import mjcf
from arenas import Floor
from composer import observation
from composer.observation import observable
from tests.composer.scenes import Block, Pendulum, SwingTask

# -- observables ------------------------------------------------------------------------------


class Lamp(composer.Entity):
    """An entity whose observables are declared on an Observables subclass, one reading
    another while they are made."""

    def _build(self, name="lamp"):
        self._mjcf_root = mjcf.RootElement(model=name)
        body = self._mjcf_root.worldbody.add("body", name="shade")
        self.hinge = body.add("joint", name="tilt", axis=[1, 0, 0])
        body.add("geom", type="sphere", size=[0.1])
        self.builds = 0

    def _build_observables(self):
        return LampObservables(self)

    @composer.cached_property
    def joints(self):
        self.builds += 1
        return self.mjcf_model.find_all("joint")


class LampObservables(composer.Observables):
    @composer.observable
    def tilt(self):
        return observable.MJCFFeature("qpos", self._entity.joints)

    @composer.define.observable
    def bright(self):
        return observable.Generic(lambda physics: self.tilt(physics) * 2)


def test_observables_are_named_by_scope_and_configured_as_in_dm_control():
    root, lamp = Lamp("room"), Lamp()
    assert list(lamp.observables.as_dict()) == ["bright", "tilt"]
    root.attach(lamp)
    assert list(lamp.observables.as_dict()) == ["lamp/bright", "lamp/tilt"]
    assert list(lamp.observables.as_dict(fully_qualified=False)) == ["bright", "tilt"]
    assert lamp.observables.dict_keys.tilt == "lamp/tilt"
    assert (
        lamp.observables.get_observable("lamp/tilt", name_fully_qualified=True)
        is lamp.observables.tilt
    )
    assert lamp.joints is lamp.joints and lamp.builds == 1  # a cached property
    lamp.observables.set_options({"update_interval": 2, "enabled": True})  # every one
    assert [o.update_interval for o in lamp.observables.values()] == [2, 2]
    lamp.observables.set_options({"tilt": {"buffer_size": 3}})
    assert lamp.observables.tilt.buffer_size == 3 and lamp.observables.bright.buffer_size is None
    with pytest.raises(KeyError, match="No observable with name 'dark'"):
        lamp.observables.set_options({"dark": {"delay": 1}})
    with pytest.raises(AttributeError, match="Cannot add attribute delai"):
        lamp.observables.set_options({"tilt": {"delay": 1}, "bright": {"delai": 1}})
    assert lamp.observables.tilt.delay is None  # the failed call changed nothing


def test_observable_options_at_construction_and_observation_callables():
    lamp = Lamp(observable_options={"tilt": {"enabled": True, "delay": 2}})
    assert (
        lamp.observables.tilt.enabled
        and lamp.observables.tilt.delay == 2
        and not lamp.observables.bright.enabled
    )
    physics = mjcf.Physics.from_mjcf_model(lamp.mjcf_model)
    physics.bind(lamp.hinge).qpos = 0.25
    assert lamp.observables.bright(physics) == 0.5

    def shift(value, random_state):
        return value + random_state.uniform()

    lamp.observables.tilt.corruptor = shift
    read = lamp.observables.tilt.observation_callable(physics, np.random.RandomState(0))
    np.testing.assert_allclose(read(), 0.25 + np.random.RandomState(0).uniform())


def test_an_mjcf_feature_indexed_is_a_new_observable_of_that_part():
    pendulum = Pendulum()
    physics = mjcf.Physics.from_mjcf_model(pendulum.mjcf_model)
    body = pendulum.mjcf_model.find("body", "base")
    whole = observable.MJCFFeature("xpos", body, update_interval=3)
    height = whole[2]
    assert height.update_interval == 3 and whole.index is None
    np.testing.assert_array_equal(height(physics), physics.bind(body).xpos[2])
    with pytest.raises(composer.ObservableError, match="already has index 2"):
        height[0]
    with pytest.raises(ValueError, match=r"expected an `mjcf\.Element`"):
        observable.MJCFFeature("qpos", "hinge")


def test_mujoco_features_and_cameras_by_name_and_camera_images():
    pendulum = Pendulum()
    physics = mjcf.Physics.from_mjcf_model(pendulum.mjcf_model)
    hinge = observable.MujocoFeature("qpos", "hinge")
    np.testing.assert_array_equal(hinge(physics), physics.named.data.qpos["hinge"])
    both = observable.MujocoFeature("xpos", lambda: ["base", "world"])
    assert both(physics).shape == (2, 3)
    camera = observable.MujocoCamera("front", height=24, width=32, depth=True)
    assert camera(physics).shape == (24, 32, 1)
    labels = observable.MJCFCamera(pendulum.camera, height=24, width=32, segmentation=True)
    image = labels(physics)
    assert image.shape == (24, 32, 2) and image.dtype == np.int32
    labels.configure(height=12, width=16)
    assert labels(physics).shape == (12, 16, 2)
    with pytest.raises(ValueError, match="cannot both be"):
        observable.MJCFCamera(pendulum.camera, depth=True, segmentation=True)
    with pytest.raises(ValueError, match="expected a <camera>"):
        observable.MJCFCamera(pendulum.hinge)


def test_abstract_bases_and_the_model_wrapper():
    with pytest.raises(TypeError, match="abstract"):

        class NoActuators(composer.Robot):
            def _build(self):
                self._mjcf_root = mjcf.RootElement()

        NoActuators()

    class PropObservables(composer.Observables, composer.FreePropObservableMixin):
        @composer.observable
        def position(self):
            return observable.Generic(lambda physics: np.zeros(3))

    with pytest.raises(TypeError, match="abstract"):
        PropObservables(Block())
    wrapped = composer.ModelWrapperEntity(mjcf.RootElement(model="thing"))
    assert len(wrapped.observables) == 0 and wrapped.name == "thing"
    assert composer.SENSOR_SITES_GROUP == composer.constants.SENSOR_SITES_GROUP == 4


def test_frames_of_a_free_entity_turn_world_vectors_into_its_own():
    arena, block = Floor(), Block()
    arena.add_free_entity(block)
    physics = mjcf.Physics.from_mjcf_model(arena.mjcf_model)
    block.set_pose(physics, quaternion=[np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)])  # z, 90°
    physics.forward()
    local = block.global_vector_to_local_frame
    np.testing.assert_allclose(local(physics, [0, 1, 0]), [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(local(physics, [0, 1]), [1, 0], atol=1e-12)
    xmat = physics.bind(block.root_body).xmat.reshape(3, 3)
    np.testing.assert_allclose(block.global_xmat_to_local_frame(physics, np.eye(3)), xmat.T)
    with pytest.raises(ValueError, match="final dimension 2 or 3"):
        block.global_vector_to_local_frame(physics, [1, 2, 3, 4])
    block.configure_joints(physics, [])  # it has no joints of its own: nothing to set


# -- the environment's options ----------------------------------------------------------------


class FlakyTask(SwingTask):
    """Fails to initialize its first `failures` episodes, as an initializer that finds no
    pose would."""

    def __init__(self, failures: int):
        super().__init__()
        self.failures = failures
        self.attempts = 0

    def initialize_episode(self, physics, random_state):
        super().initialize_episode(physics, random_state)
        self.attempts += 1
        if self.attempts <= self.failures:
            raise composer.EpisodeInitializationError(f"attempt {self.attempts}")


def test_failed_episode_initialization_is_retried_up_to_max_reset_attempts():
    env = composer.Environment(FlakyTask(failures=2), max_reset_attempts=3)
    env.reset(seed=0)
    assert env.task.attempts == 3
    env = composer.Environment(FlakyTask(failures=2), max_reset_attempts=2)
    with pytest.raises(composer.EpisodeInitializationError, match="attempt 2"):
        env.reset(seed=0)
    with pytest.raises(composer.EpisodeError, match="before reset"):
        env.step(np.zeros(1))
    env.reset()  # the third attempt succeeds
    env.step(np.zeros(1))


def test_a_fixed_initial_state_starts_every_episode_the_same():
    fixed = composer.Environment(SwingTask(), random_state=5, fixed_initial_state=True)
    free = composer.Environment(SwingTask(), random_state=5)
    starts = [fixed.reset()[0]["pendulum/orientation"] for _ in range(3)]
    others = [free.reset()[0]["pendulum/orientation"] for _ in range(3)]
    np.testing.assert_array_equal(starts[0], starts[1])
    np.testing.assert_array_equal(starts[0], starts[2])
    np.testing.assert_array_equal(starts[0], others[0])
    assert not np.array_equal(others[0], others[1])
    reseeded = fixed.reset(seed=1)[0]["pendulum/orientation"]
    np.testing.assert_array_equal(fixed.reset()[0]["pendulum/orientation"], reseeded)


def test_n_sub_steps_and_observation_shapes_and_padding_options():
    with pytest.warns(DeprecationWarning, match="n_sub_steps"):
        env = composer.Environment(SwingTask(substeps=4), n_sub_steps=2)
    assert env.control_timestep == pytest.approx(0.01)
    env.reset(seed=0)
    env.step(np.zeros(1))
    assert env.physics.data.time == pytest.approx(0.01)
    task = SwingTask()
    task.pendulum.orientation.configure(delay=8)
    env = composer.Environment(
        task, strip_singleton_obs_buffer_dim=False,
        delayed_observation_padding=composer.ObservationPadding.ZERO,
    )  # fmt: skip
    assert env.observation_space["pendulum/angular_velocity"].shape == (1, 1)
    obs, _ = env.reset(seed=0)
    np.testing.assert_array_equal(obs["pendulum/orientation"], [[0, 0]])  # not yet visible
    for _ in range(2):
        obs = env.step(np.zeros(1))[0]
    assert obs["pendulum/orientation"][0, 0] > 0.5  # the reset value, 8 steps on


def test_physics_errors_raise_when_asked_and_legacy_step_reaches_the_physics():
    task = SwingTask()
    env = composer.Environment(task, raise_exception_on_physics_error=True, legacy_step=False)
    assert env.physics.legacy_step is False
    env.reset(seed=0)
    env.physics.data.qvel[:] = np.nan
    env.physics.mark_as_dirty()
    with pytest.raises(mjcf.PhysicsError):
        env.step(np.zeros(1))


class CountingTask(SwingTask):
    def __init__(self):
        super().__init__()
        self.calls: list[str] = []

    def initialize_episode_mjcf(self, random_state):
        self.calls.append("initialize_episode_mjcf")

    def after_compile(self, physics, random_state):
        self.calls.append("after_compile")


@pytest.mark.parametrize(
    ("recompile", "expected"),
    [
        (None, ["initialize_episode_mjcf"] * 3),  # an unchanged model is not recompiled
        (True, ["initialize_episode_mjcf", "after_compile"] * 3),  # dm_control's default
        (False, ["initialize_episode_mjcf", "after_compile"]),  # the first reset only
    ],
)
def test_recompile_mjcf_every_episode(recompile, expected):
    task = CountingTask()
    env = composer.Environment(task, recompile_mjcf_every_episode=recompile)
    task.calls.clear()
    for _ in range(3):
        env.reset(seed=0)
    assert task.calls == expected


def test_extra_hooks_run_after_the_task_and_entities_with_their_arguments():
    calls = []
    env = composer.Environment(SwingTask(substeps=2))
    for name in composer.HOOK_NAMES:
        env.add_extra_hook(name, lambda *args, name=name: calls.append((name, len(args))))
    env.reset(seed=0)
    env.step(np.zeros(1))
    assert calls == [
        ("initialize_episode_mjcf", 1), ("initialize_episode", 2), ("before_step", 3),
        ("before_substep", 3), ("after_substep", 2), ("before_substep", 3),
        ("after_substep", 2), ("after_step", 2),
    ]  # fmt: skip
    with pytest.raises(ValueError, match="'after_reset' is not a valid hook name"):
        env.add_extra_hook("after_reset", print)
    with pytest.raises(ValueError, match="not a callable"):
        env.add_extra_hook("after_step", 3)


def test_prop_placer_settles_props_and_restores_time():
    arena, block = Floor(), Block()
    arena.add_free_entity(block)
    physics = mjcf.Physics.from_mjcf_model(arena.mjcf_model)
    physics.data.time = 7.0
    placer = composer.initializers.PropPlacer(
        [block], position=[0, 0, 0.3], settle_physics=True, max_settle_physics_time=3.0
    )
    placer(physics, np.random.RandomState(0))
    position, quaternion = block.get_pose(physics)
    assert position[2] == pytest.approx(0.05, abs=2e-3)  # resting on the floor
    np.testing.assert_allclose(quaternion, [1, 0, 0, 0], atol=1e-3)  # upright, by default
    assert physics.data.time == 7.0
    assert isinstance(observation.observable.base.AGGREGATORS["median"], observation.Aggregator)
