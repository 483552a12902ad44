"""Camera observables (`MJCFCamera`) through an episode's life: each frame is the physics'
own picture of the state observed, the same seed gives the same frames, and a recompile
of the scene (a colour changed by `initialize_episode_mjcf`) is seen in the next frames."""

from __future__ import annotations

import mujoco
import numpy as np

import composer
import mjcf
from composer import observation
from tests.composer.scenes import SwingTask

SIZE = (48, 64)


class CameraSwing(SwingTask):
    """SwingTask observed through the pendulum's camera; with `colours`, each episode paints
    the rod the next colour (a change of the model, so a recompile)."""

    def __init__(self, colours: list[list[float]] | None = None) -> None:
        super().__init__()
        self.pendulum.observables.add_observable(
            "front_image", observation.MJCFCamera(self.pendulum.camera, *SIZE)
        )
        self.pendulum.observables["front_image"].enabled = True
        self.rod = self.pendulum.mjcf_model.find("geom", "rod")
        self._colours = list(colours or [])

    def initialize_episode_mjcf(self, random_state: np.random.RandomState) -> None:
        if self._colours:
            self.rod.rgba = self._colours.pop(0)


def camera_frame(env: composer.Environment) -> np.ndarray:
    return env.physics.render(*SIZE, camera_id="pendulum/front")


def rod_colour(env: composer.Environment, frame: np.ndarray) -> np.ndarray:
    """The mean colour of the rod's pixels in `frame`."""
    objects = env.physics.render(*SIZE, camera_id="pendulum/front", segmentation=True)
    rod = mujoco.mj_name2id(env.physics.model, mujoco.mjtObj.mjOBJ_GEOM, "pendulum/rod")
    mask = (objects[..., 0] == rod) & (objects[..., 1] == mujoco.mjtObj.mjOBJ_GEOM)
    assert mask.sum() > 20
    return frame[mask].mean(axis=0)


def test_frames_are_the_state_observed_and_the_same_seed_gives_the_same_frames():
    env = composer.Environment(CameraSwing())
    key = "pendulum/front_image"
    assert env.observation_space[key].shape == (*SIZE, 3)
    episodes = []
    for seed in (3, 3, 4):
        obs, _ = env.reset(seed=seed)
        np.testing.assert_array_equal(obs[key], camera_frame(env))
        frames = [obs[key]]
        for action in (1.0, -1.0, 0.5):
            obs, *_ = env.step(np.array([action]))
            np.testing.assert_array_equal(obs[key], camera_frame(env))
            frames.append(obs[key])
        episodes.append(frames)
    for a, b in zip(episodes[0], episodes[1], strict=True):
        np.testing.assert_array_equal(a, b)
    assert not np.array_equal(episodes[0][0], episodes[2][0])  # another start angle
    env.close()


def test_a_recompiled_scene_is_what_the_camera_sees():
    red, blue = [0.9, 0.1, 0.1, 1.0], [0.1, 0.1, 0.9, 1.0]
    env = composer.Environment(CameraSwing(colours=[red, blue]))
    key = "pendulum/front_image"
    obs, _ = env.reset(seed=0)
    first_model = env.physics.model
    r, _, b = rod_colour(env, obs[key])
    assert r > b + 50
    obs, _ = env.reset(seed=0)  # paints the rod blue: a new model
    assert env.physics.model is not first_model
    np.testing.assert_array_equal(obs[key], camera_frame(env))
    r, _, b = rod_colour(env, obs[key])
    assert b > r + 50
    obs, *_ = env.step(np.array([1.0]))
    np.testing.assert_array_equal(obs[key], camera_frame(env))
    env.close()


def test_camera_frames_use_the_small_frame_settings_of_the_unchanged_model():
    env = composer.Environment(CameraSwing())
    obs, _ = env.reset(seed=0)
    model = env.physics.model
    assert model.vis.quality.shadowsize == 4096  # the model keeps MuJoCo's default
    fast = mujoco.MjModel.from_xml_string(env.task.root_entity.mjcf_model.to_xml_string())
    fast.vis.quality.shadowsize = fast.vis.quality.offsamples = 0
    fast.vis.global_.offwidth, fast.vis.global_.offheight = SIZE[1], SIZE[0]
    data = mujoco.MjData(fast)
    mujoco.mj_setState(fast, data, _state(env.physics), mujoco.mjtState.mjSTATE_INTEGRATION)
    mujoco.mj_forward(fast, data)
    renderer = mujoco.Renderer(fast, *SIZE)
    renderer.update_scene(data, camera="pendulum/front")
    np.testing.assert_array_equal(obs["pendulum/front_image"], renderer.render())
    renderer.close()
    env.close()


def _state(physics: mjcf.Physics) -> np.ndarray:
    spec = mujoco.mjtState.mjSTATE_INTEGRATION
    state = np.empty(mujoco.mj_stateSize(physics.model, spec))
    mujoco.mj_getState(physics.model, physics.data, state, spec)
    return state
