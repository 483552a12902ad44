"""PixelVectorEnvironment and `make_vec(..., pixels=True)`: the observations of num_envs
PixelEnvironments (in Gymnasium's SyncVectorEnv), pixel for pixel, with frame stacks and
proprioception, through every autoreset mode, seeds and a reset mask; the vector make takes
Gymnasium's rendering keywords as `gym.make` does."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import composer
from composer.registration import RegistrationError
from composer.vector import PixelVectorEnvironment, VectorEnvironment
from tests.composer.test_vector import TEST_ID
from tests.vector_runs import assert_same_runs

CARTPOLE = "composer/CartpoleSwingup-v0"
REACH = "composer/Reach-v0"


@pytest.fixture(scope="module", autouse=True)
def _tasks():
    import tasks  # noqa: F401  registers the composer/ ids


def pair(env_id, n, mode=AutoresetMode.NEXT_STEP, **kwargs):
    vector = gymnasium.make_vec(
        env_id, num_envs=n, vectorization_mode="vector_entry_point", autoreset_mode=mode,
        **kwargs,
    )  # fmt: skip
    reference = SyncVectorEnv(
        [lambda: gymnasium.make(env_id, **kwargs) for _ in range(n)], autoreset_mode=mode
    )
    return vector, reference


@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP])
def test_stacked_frames_equal_pixel_environments_through_autoresets(mode):
    options = dict(pixels=True, width=32, height=24, frame_stack=3, time_limit=0.1)
    vector, reference = pair(CARTPOLE, 3, mode, **options)
    assert isinstance(vector, PixelVectorEnvironment)
    assert vector.single_observation_space == reference.single_observation_space
    assert vector.observation_space.shape == (3, 24, 32, 9)
    assert assert_same_runs(vector, reference, steps=14, seed=2) >= 6  # two episodes each
    vector.close()
    reference.close()


def test_pixels_with_proprioception_equal_pixel_environments():
    vector, reference = pair(REACH, 2, pixels=True, width=32, height=32, proprioception=True,
                             time_limit=0.2)  # fmt: skip
    assert vector.single_observation_space == reference.single_observation_space
    assert assert_same_runs(vector, reference, steps=12, seed=2) >= 2
    obs, _ = vector.reset(seed=0)
    assert obs["pixels"].shape == (2, 32, 32, 3) and obs["proprioception"].ndim == 2
    vector.close()
    reference.close()


def test_a_reset_mask_refills_only_the_stacks_of_those_reset():
    vector = PixelVectorEnvironment(
        lambda: _swing(),
        3,
        height=16,
        width=16,
        frame_stack=2,
        autoreset_mode=AutoresetMode.DISABLED,
    )
    obs, _ = vector.reset(seed=0)
    np.testing.assert_array_equal(obs[..., :3], obs[..., 3:])  # the first frame twice
    obs, *_ = vector.step(np.ones((3, 1), np.float32))
    mask = np.array([False, True, False])
    again, _ = vector.reset(seed=[None, 9, None], options={"reset_mask": mask})
    np.testing.assert_array_equal(again[[0, 2]], obs[[0, 2]])
    np.testing.assert_array_equal(again[1, ..., :3], again[1, ..., 3:])
    assert not np.array_equal(again[1], obs[1])
    vector.close()


def _swing():
    from tests.composer.vector_scenes import BatchedSwing

    return BatchedSwing()


def test_the_vector_make_takes_gymnasiums_render_keywords():
    vector = gymnasium.make_vec(
        CARTPOLE, num_envs=2, vectorization_mode="vector_entry_point",
        render_mode="rgb_array", width=48, height=40,
    )  # fmt: skip
    assert type(vector) is VectorEnvironment
    vector.reset(seed=1)
    single = gymnasium.make(CARTPOLE, render_mode="rgb_array", width=48, height=40)
    single.reset(seed=2)
    frames = vector.render()
    assert frames[0].shape == (40, 48, 3)
    np.testing.assert_array_equal(frames[1], single.render())
    single.close()
    vector.close()


def test_the_vector_make_refuses_what_gym_make_refuses():
    make = dict(num_envs=2, vectorization_mode="vector_entry_point")
    with pytest.raises(RegistrationError, match="no camera named 'nope'"):
        gymnasium.make_vec(TEST_ID, pixels=True, camera_name="nope", **make)
    with pytest.raises(RegistrationError, match="no camera named 'nope'"):
        gymnasium.make_vec(TEST_ID, render_mode="rgb_array", camera_name="nope", **make)
    with pytest.raises(RegistrationError, match="not both"):
        gymnasium.make_vec(TEST_ID, camera_id=0, camera_name="pendulum/front", **make)
    with pytest.raises(RegistrationError, match="give pixels=True"):
        gymnasium.make_vec(TEST_ID, frame_stack=2, **make)
    with pytest.raises(composer.TaskError, match="frame_stack must be a positive int"):
        gymnasium.make_vec(TEST_ID, pixels=True, frame_stack=0, **make)


def test_stable_baselines3_trains_a_cnn_policy_on_pixel_vector_environments():
    pytest.importorskip("stable_baselines3")
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecTransposeImage

    from composer.sb3 import make_vec_env

    venv = make_vec_env("tasks.cartpole:CartpoleSwingup", 2, time_limit=0.5, pixels=True,
                        width=36, height=36, frame_stack=2)  # fmt: skip
    model = PPO("CnnPolicy", venv, n_steps=16, batch_size=16, n_epochs=1, seed=0, device="cpu")
    assert isinstance(model.get_env(), VecTransposeImage)  # SB3's own image pipeline
    model.learn(total_timesteps=64)
    assert model.num_timesteps >= 64
    venv.close()


def test_simplified_meshes_in_a_shared_context_equal_pixel_environments():
    """ArmPushBox's meshes are drawn simplified in small frames (mjcf.sim.render_meshes), by
    renderers that share one OpenGL context per render thread: each draws into its own
    buffers, as a single environment's renderer does."""
    options = dict(pixels=True, width=32, height=24, time_limit=0.1)
    vector = gymnasium.make_vec(
        "composer/ArmPushBox-v0", num_envs=3, vectorization_mode="vector_entry_point",
        nthread=1, **options,
    )  # fmt: skip
    reference = SyncVectorEnv(
        [lambda: gymnasium.make("composer/ArmPushBox-v0", **options) for _ in range(3)]
    )
    assert_same_runs(vector, reference, steps=3, seed=2)
    vector.close()
