"""composer.Environment: the gymnasium API, seeding, truncation, divergence, rendering."""

from __future__ import annotations

import warnings

import gymnasium
import mujoco
import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.utils.env_checker import check_env

import composer
import mjcf
from tests.composer.scenes import SwingTask

ENV_ID = "composer_tests/Swing-v0"


def make_env(**kwargs) -> composer.Environment:
    task_kwargs = {k: kwargs.pop(k) for k in ("gear", "substeps", "terminate_above") if k in kwargs}
    return composer.Environment(SwingTask(**task_kwargs), **kwargs)


if ENV_ID not in gymnasium.registry:
    gymnasium.register(ENV_ID, entry_point=lambda **kw: make_env(time_limit=1.0, **kw))


def rollout(env: composer.Environment, seed: int, steps: int = 100) -> list:
    obs, _ = env.reset(seed=seed)
    env.action_space.seed(seed)
    trajectory = [obs]
    for _ in range(steps):
        obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
        trajectory.append((obs, reward))
        if terminated or truncated:
            obs, _ = env.reset()
            trajectory.append(obs)
    return trajectory


def test_gymnasium_check_env_passes_without_warnings():
    env = gymnasium.make(ENV_ID, render_mode="rgb_array")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)
    env.close()


def test_stable_baselines3_check_env_passes():
    from stable_baselines3.common.env_checker import check_env as sb3_check_env

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sb3_check_env(make_env(time_limit=1.0, flatten_observations=True), warn=True)


def test_spaces_are_named_boxes_and_ctrlrange_actions():
    env = make_env()
    assert isinstance(env.observation_space, spaces.Dict)
    assert list(env.observation_space.spaces) == [
        "pendulum/angular_velocity",
        "pendulum/orientation",
    ]
    assert env.observation_space["pendulum/orientation"] == spaces.Box(-1.0, 1.0, (2,), np.float64)
    assert env.action_space == spaces.Box(-1.0, 1.0, (1,), np.float32)


def test_flattened_observation_concatenates_the_named_ones_in_name_order():
    named, flat = make_env(), make_env(flatten_observations=True)
    obs, _ = named.reset(seed=3)
    flat_obs, _ = flat.reset(seed=3)
    assert isinstance(flat.observation_space, spaces.Box)
    assert flat.observation_space.shape == (3,)
    np.testing.assert_array_equal(flat_obs, np.concatenate([obs[k] for k in sorted(obs)]))
    assert flat_obs in flat.observation_space


def test_same_seed_same_trajectory_bit_for_bit_and_other_seeds_differ():
    first = rollout(make_env(time_limit=0.2), seed=7)
    second = rollout(make_env(time_limit=0.2), seed=7)
    other = rollout(make_env(time_limit=0.2), seed=8)

    def flat(trajectory):
        parts = []
        for item in trajectory:
            obs, reward = item if isinstance(item, tuple) else (item, 0.0)
            parts.extend([*obs.values(), [reward]])
        return np.concatenate(parts)

    assert flat(first).tobytes() == flat(second).tobytes()
    assert not np.array_equal(flat(first), flat(other))


def test_random_state_given_at_construction_seeds_unseeded_resets():
    a = make_env(random_state=5)
    b = make_env(random_state=np.random.RandomState(5))
    np.testing.assert_array_equal(a.reset()[0]["pendulum/orientation"],
                                  b.reset()[0]["pendulum/orientation"])  # fmt: skip
    generator = make_env(random_state=np.random.default_rng(1))
    assert isinstance(generator.random_state, np.random.RandomState)
    with pytest.raises(composer.TaskError, match="random_state"):
        make_env(random_state="seed")


def test_time_limit_truncates_and_does_not_terminate():
    env = make_env(time_limit=0.1, substeps=4)  # control timestep 0.02: 5 steps
    env.reset(seed=0)
    flags = [env.step(np.zeros(1))[2:4] for _ in range(5)]
    assert flags == [(False, False)] * 4 + [(False, True)]
    with pytest.raises(composer.EpisodeError, match="reset"):
        env.step(np.zeros(1))


def test_termination_is_reported_as_terminated_not_truncated():
    env = make_env(terminate_above=-1.0)  # any angle ends the episode
    env.reset(seed=0)
    _, _, terminated, truncated, info = env.step(np.zeros(1))
    assert (terminated, truncated) == (True, False)
    assert info == {"discount": 1.0}


def test_step_checks_order_and_action_shape():
    env = make_env()
    with pytest.raises(composer.EpisodeError, match="before reset"):
        env.step(np.zeros(1))
    env.reset(seed=0)
    with pytest.raises(composer.EpisodeError, match=r"shape \(2,\), expected \(1,\)"):
        env.step(np.zeros(2))


def test_divergence_truncates_with_the_error_and_the_next_episode_runs():
    env = make_env(gear=1e30, time_limit=1.0)
    env.reset(seed=0)
    with pytest.warns(composer.DivergenceWarning):
        for _ in range(50):
            obs, reward, terminated, truncated, info = env.step(np.ones(1))
            if truncated:
                break
    assert truncated and not terminated
    assert "physics state is invalid" in info["physics_error"]
    assert reward == 0.0
    obs, _ = env.reset(seed=1)
    obs, _, terminated, truncated, info = env.step(np.zeros(1))
    assert not truncated and "physics_error" not in info
    assert np.isfinite(obs["pendulum/orientation"]).all()


def _step_timer(data: mujoco.MjData) -> tuple[int, float]:
    entry = data.timer[mujoco.mjtTimer.mjTIMER_STEP]
    return int(entry.number), float(entry.duration)


def test_a_step_runs_without_mujocos_profiling_timer_and_puts_it_back():
    env = make_env(substeps=3, time_limit=1.0, raise_exception_on_physics_error=True)
    env.reset(seed=0)
    plain = mujoco.MjData(env.physics.model)
    mujoco.mj_step(env.physics.model, plain)
    assert _step_timer(plain)[1] > 0  # the bindings' timer is installed
    count, duration = _step_timer(env.physics.data)
    env.step(np.ones(1))
    # MuJoCo counted the step's calls without timing them: the timer was unset.
    assert _step_timer(env.physics.data)[0] > count
    assert _step_timer(env.physics.data)[1] == duration
    mujoco.mj_step(env.physics.model, plain)
    assert _step_timer(plain)[1] > 0  # installed again after the step
    diverging = make_env(gear=1e30, time_limit=1.0, raise_exception_on_physics_error=True)
    diverging.reset(seed=0)
    with pytest.raises(mjcf.PhysicsError):
        for _ in range(50):
            diverging.step(np.ones(1))
    before = _step_timer(plain)[1]
    mujoco.mj_step(env.physics.model, plain)
    assert _step_timer(plain)[1] > before  # and after a step that raised


def test_a_step_without_the_timer_gives_the_numbers_of_a_timed_one(monkeypatch):
    def entries(trajectory: list) -> list:
        """(observation, reward) of each entry; a reset's observation with reward None."""
        return [(e, None) if isinstance(e, dict) else e for e in trajectory]

    untimed = entries(rollout(make_env(substeps=3, time_limit=1.0), seed=4))
    monkeypatch.setattr(composer.environment.timer, "untimed", lambda call, *args: call(*args))
    timed = entries(rollout(make_env(substeps=3, time_limit=1.0), seed=4))
    assert len(untimed) == len(timed) > 100  # through a time-limit reset
    for (obs, reward), (timed_obs, timed_reward) in zip(untimed, timed, strict=True):
        assert reward == timed_reward
        assert {k: v.tobytes() for k, v in obs.items()} == {
            k: v.tobytes() for k, v in timed_obs.items()
        }


class _SettlingSwing(SwingTask):
    """Starts at a random angle, then lets the pendulum fall for 20 physics steps, as
    cheetah's initialization settles it for 200."""

    def initialize_episode(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        super().initialize_episode(physics, random_state)
        for _ in range(20):
            physics.step()


def test_a_reset_settles_without_mujocos_profiling_timer_to_the_numbers_of_a_timed_one(
    monkeypatch,
):
    env = composer.Environment(_SettlingSwing())
    first, _ = env.reset(seed=3)  # a reset zeroes MjData's timers, then settles
    count, duration = _step_timer(env.physics.data)
    assert count >= 20 and duration == 0.0  # the settling steps ran, untimed
    plain = mujoco.MjData(env.physics.model)
    mujoco.mj_step(env.physics.model, plain)
    assert _step_timer(plain)[1] > 0  # the timer is back after the reset
    monkeypatch.setattr(composer.environment.timer, "untimed", lambda call, *args: call(*args))
    timed = composer.Environment(_SettlingSwing())
    timed_first, _ = timed.reset(seed=3)
    assert _step_timer(timed.physics.data)[1] > 0  # this one was timed
    assert {k: v.tobytes() for k, v in first.items()} == {
        k: v.tobytes() for k, v in timed_first.items()
    }


def test_reset_without_model_change_does_not_recompile():
    env = make_env()
    model, data = env.physics.model, env.physics.data
    for seed in range(3):
        env.reset(seed=seed)
        env.step(np.zeros(1))
    assert env.physics.model is model and env.physics.data is data


def test_render_modes_give_frames_of_the_scene():
    rgb = make_env(render_mode="rgb_array", render_height=48, render_width=64)
    rgb.reset(seed=0)
    frame = rgb.render()
    assert frame.shape == (48, 64, 3) and frame.dtype == np.uint8 and frame.std() > 0
    depth = make_env(render_mode="depth_array", render_height=48, render_width=64)
    depth.reset(seed=0)
    image = depth.render()
    assert image.shape == (48, 64) and image.dtype == np.float32 and (image > 0).all()
    assert make_env().render() is None
    rgb.close()
    rgb.close()
    with pytest.raises(composer.TaskError, match="render_mode"):
        make_env(render_mode="human")


def test_bad_time_limit_is_refused():
    with pytest.raises(composer.TaskError, match="time_limit"):
        make_env(time_limit=0)


def test_observations_and_rewards_read_the_state_after_the_step() -> None:
    """Positions and sensors observed after a step are those of the new state, as mj_forward
    computes them on a copy, not one physics step behind (and legacy_step=False lags)."""
    from tests.composer.vector_scenes import SensingSwing

    env = composer.Environment(SensingSwing(substeps=3))
    env.reset(seed=0)
    physics = env.physics
    task = env.task
    tip = mujoco.mj_name2id(physics.model, mujoco.mjtObj.mjOBJ_SITE, "pendulum/tip")
    rng = np.random.default_rng(0)
    for _ in range(20):
        obs, reward, *_ = env.step(rng.uniform(-1, 1, env.action_space.shape))
        expected = mujoco.MjData(physics.model)
        mujoco.mj_copyData(expected, physics.model, physics.data)
        mujoco.mj_forward(physics.model, expected)
        assert obs["tip_height"][0] == expected.site_xpos[tip, 2]
        ids = physics.bind(task.sensors).element_id
        rows = np.concatenate(
            [
                np.arange(a, a + n)
                for a, n in zip(
                    physics.model.sensor_adr[ids], physics.model.sensor_dim[ids], strict=True
                )
            ]
        )
        assert np.array_equal(obs["sensed"], expected.sensordata[rows])
        assert reward == expected.sensordata[physics.model.sensor_adr[ids[0]] + 2]
    physics.legacy_step = False  # bare mj_step: what it computed before its integration
    obs, *_ = env.step(np.zeros(env.action_space.shape))
    fresh = mujoco.MjData(physics.model)
    mujoco.mj_copyData(fresh, physics.model, physics.data)
    mujoco.mj_forward(physics.model, fresh)
    assert obs["tip_height"][0] == physics.data.site_xpos[tip, 2] != fresh.site_xpos[tip, 2]
