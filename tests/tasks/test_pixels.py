"""Rendering and pixel observations through gym.make, as Gymnasium's MuJoCo environments
take them (`width`, `height`, `camera_id`, `camera_name`), and the pixel variants of the
shipped tasks (`pixels=True`, `frame_stack`, `proprioception`): their spaces, check_env,
frames that are the physics' own, seeding, and stable-baselines3's image pipeline."""

from __future__ import annotations

import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import composer
import tasks  # noqa: F401  (registers the ids)
from composer.pixels import PixelEnvironment
from tests.tasks.helpers import make

PIXEL_TASKS = ["composer/CartpoleSwingup-v0", "composer/Reach-v0"]


def checked(env: gymnasium.Env) -> None:
    """check_env of the unwrapped environment passes without a warning."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(env.unwrapped, skip_render_check=False)
    assert [str(w.message) for w in caught] == []


def test_render_size_and_camera_come_from_gym_make():
    env = make("composer/Reach-v0", render_mode="rgb_array", width=64, height=48)
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (48, 64, 3) and frame.dtype == np.uint8
    physics = env.unwrapped.physics
    np.testing.assert_array_equal(frame, physics.render(48, 64, camera_id=-1))
    checked(env)
    env.close()
    by_name = make("composer/Reach-v0", render_mode="rgb_array", camera_name="overview")
    by_id = make("composer/Reach-v0", render_mode="rgb_array", camera_id=0)
    for env in (by_name, by_id):
        env.reset(seed=0)
        frame = env.render()
        assert frame.shape == (240, 320, 3)
        np.testing.assert_array_equal(
            frame, env.unwrapped.physics.render(240, 320, camera_id="overview")
        )
        env.close()
    # The task's own camera when neither is given: CartpoleSwingup's follows the cart.
    env = make("composer/CartpoleSwingup-v0", render_mode="rgb_array", width=32, height=32)
    env.reset(seed=0)
    np.testing.assert_array_equal(
        env.render(), env.unwrapped.physics.render(32, 32, camera_id="cartpole/track")
    )
    env.close()


@pytest.mark.parametrize(
    ("keywords", "message"),
    [
        ({"camera_id": 0, "camera_name": "overview"}, "camera_id or camera_name, not both"),
        ({"camera_name": "nope"}, "no camera named 'nope'; it has \\['overview'\\]"),
        ({"camera_id": 3}, "camera id 3 is out of range"),
        ({"width": 0}, "width must be a positive int, got 0"),
        ({"frame_stack": 2}, "give pixels=True with them"),
        ({"pixels": True, "frame_stack": 0}, "frame_stack must be a positive int"),
    ],
)
def test_bad_render_and_pixel_keywords_are_refused(keywords, message):
    with pytest.raises(composer.TaskError, match=message):  # a ValueError
        make("composer/Reach-v0", **keywords)


@pytest.mark.parametrize("env_id", PIXEL_TASKS)
def test_pixel_variants_observe_uint8_frames_of_the_task_camera(env_id):
    env = make(env_id, pixels=True)
    space = env.observation_space
    assert isinstance(space, gymnasium.spaces.Box)
    assert (space.shape, space.dtype, space.low.min(), space.high.max()) == (
        (84, 84, 3), np.uint8, 0, 255
    )  # fmt: skip
    assert isinstance(env.unwrapped, PixelEnvironment)
    checked(env)
    obs, _ = env.reset(seed=1)
    camera = getattr(env.unwrapped.task, "render_camera", -1)
    physics = env.unwrapped.physics
    np.testing.assert_array_equal(obs, physics.render(84, 84, camera_id=camera))
    obs, *_ = env.step(env.action_space.sample())
    np.testing.assert_array_equal(obs, physics.render(84, 84, camera_id=camera))
    assert obs.std() > 5  # a picture, not a blank
    env.close()


def test_frame_stacks_hold_the_latest_frames_oldest_first():
    env = make("composer/CartpoleSwingup-v0", pixels=True, width=64, height=64, frame_stack=3)
    assert env.observation_space.shape == (64, 64, 9)
    checked(env)
    obs, _ = env.reset(seed=0)
    for slot in (1, 2):  # at a reset, every slot holds the first frame
        np.testing.assert_array_equal(obs[..., 3 * slot : 3 * slot + 3], obs[..., :3])
    frames = [obs[..., :3]]
    for _ in range(4):
        obs, *_ = env.step(np.ones(1, np.float32))
        frames.append(obs[..., 6:9].copy())
        np.testing.assert_array_equal(
            obs[..., 6:9], env.unwrapped.physics.render(64, 64, camera_id="cartpole/track")
        )
    np.testing.assert_array_equal(obs, np.concatenate(frames[-3:], axis=-1))
    assert not np.array_equal(frames[-1], frames[-3])  # the cart moved
    env.close()


def test_proprioception_is_the_flattened_state_alongside_the_frames():
    pixels = make("composer/Reach-v0", pixels=True, proprioception=True, width=64, height=64)
    state = make("composer/Reach-v0", flatten_observations=True)
    assert set(pixels.observation_space.spaces) == {"pixels", "proprioception"}
    assert pixels.observation_space["proprioception"] == state.observation_space
    checked(pixels)
    observed, _ = pixels.reset(seed=5)
    expected, _ = state.reset(seed=5)
    np.testing.assert_array_equal(observed["proprioception"], expected)
    action = np.array([0.5, -0.5], np.float32)
    observed, *_ = pixels.step(action)
    expected, *_ = state.step(action)
    np.testing.assert_array_equal(observed["proprioception"], expected)
    assert observed["pixels"].shape == (64, 64, 3)
    pixels.close()
    state.close()


def test_the_same_seed_gives_the_same_frames_and_another_seed_others():
    def episode(seed: int) -> list[np.ndarray]:
        env = make("composer/CartpoleSwingup-v0", pixels=True, width=64, height=64)
        obs, _ = env.reset(seed=seed)
        frames = [obs]
        for action in np.linspace(-1, 1, 5):
            obs, *_ = env.step(np.array([action], np.float32))
            frames.append(obs)
        env.close()
        return frames

    first, again, other = episode(7), episode(7), episode(8)
    for a, b in zip(first, again, strict=True):
        np.testing.assert_array_equal(a, b)
    assert not np.array_equal(first[0], other[0])  # the cart starts elsewhere


def test_stable_baselines3_trains_a_cnn_policy_on_pixels_without_glue():
    torch = pytest.importorskip("torch")
    sb3 = pytest.importorskip("stable_baselines3")
    from stable_baselines3.common.vec_env import VecTransposeImage

    torch.set_num_threads(1)
    env = make("composer/CartpoleSwingup-v0", pixels=True, width=64, height=64, frame_stack=2)
    model = sb3.PPO("CnnPolicy", env, n_steps=128, batch_size=64, n_epochs=2, seed=0)
    assert isinstance(model.get_env(), VecTransposeImage)
    assert model.observation_space.shape == (6, 64, 64)
    before = [p.detach().clone() for p in model.policy.parameters()]
    model.learn(total_timesteps=256)
    assert model.num_timesteps == 256
    changed = [
        not torch.equal(a, b) for a, b in zip(before, model.policy.parameters(), strict=True)
    ]
    assert any(changed)  # it learned something, from the frames
    env.close()
    both = make("composer/Reach-v0", pixels=True, proprioception=True, width=48, height=48)
    model = sb3.PPO("MultiInputPolicy", both, n_steps=64, batch_size=32, n_epochs=1, seed=0)
    model.learn(total_timesteps=64)
    assert model.num_timesteps == 64
    both.close()
