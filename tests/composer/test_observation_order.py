"""An observation shows what the `after_step` hooks changed (issue 37, item 1).

dm_control's `Environment.step` takes its last observation sample after the `after_step`
hooks, so that a hook that changes state (a goal advanced by a step counter, a joint moved)
never leaves the observation one step behind. Here: a task whose `after_step` does both,
observed through the single environment, the VectorEnvironment and the pixel environment;
and a whole episode compared with dm_control's own `Environment` (from the published wheel,
its environment, observation updater and control modules loaded under another name, run
on our task, physics and observables).
"""

from __future__ import annotations

import numpy as np
import pytest

import composer
import mjcf
from composer import observation
from tests.composer import dm_control_environment
from tests.composer.scenes import SwingTask

GOALS = np.linspace(-1.0, 1.0, 7)


class GoalTask(SwingTask):
    """SwingTask whose `after_step` advances a goal every step and nudges the hinge every
    third step: observables of both must show the state after the hook."""

    def __init__(self) -> None:
        super().__init__(substeps=4)
        self.steps = 0
        self.pendulum.joint_positions.enabled = True
        self.pendulum.joint_positions.buffer_size = 2
        self.pendulum.joint_velocities.enabled = True
        self.pendulum.joint_velocities.update_interval = 2
        self._goal = observation.Generic(lambda physics: np.array([GOALS[self.steps % 7]]))
        self._goal.enabled = True

    @property
    def task_observables(self) -> dict[str, observation.Observable]:
        return {"goal": self._goal}

    def initialize_episode(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        super().initialize_episode(physics, random_state)
        self.steps = 0

    def before_step(self, physics, action, random_state):
        physics.set_control(action)

    def after_step(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        self.steps += 1
        if self.steps % 3 == 0:
            physics.bind(self.pendulum.hinge).qpos = GOALS[self.steps % 7]


def _goal_after(steps: int) -> float:
    return float(GOALS[steps % 7])


def test_the_single_environment_observes_the_state_after_step_left():
    env = composer.Environment(GoalTask())
    obs, _ = env.reset(seed=1)
    assert obs["goal"][0] == _goal_after(0)
    for t in range(1, 10):
        obs, *_ = env.step(env.action_space.sample())
        assert obs["goal"][0] == _goal_after(t)
        if t % 3 == 0:  # the hinge was set by after_step: the newest buffered sample says so
            assert obs["pendulum/joint_positions"][-1, 0] == _goal_after(t)
            assert obs["pendulum/orientation"][0] == pytest.approx(np.cos(_goal_after(t)))


def test_the_vector_environment_observes_the_state_after_step_left():
    venv = composer.VectorEnvironment(GoalTask, num_envs=3)
    obs, _ = venv.reset(seed=1)
    actions = np.zeros((3, 1))
    for t in range(1, 10):
        obs, *_ = venv.step(actions)
        np.testing.assert_array_equal(obs["goal"][:, 0], _goal_after(t))
        if t % 3 == 0:
            np.testing.assert_array_equal(obs["pendulum/joint_positions"][:, -1, 0], _goal_after(t))
    venv.close()


def test_the_vector_environment_equals_single_ones_with_after_step_hooks():
    venv = composer.VectorEnvironment(GoalTask, num_envs=2)
    singles = [composer.Environment(GoalTask()) for _ in range(2)]
    obs, _ = venv.reset(seed=4)
    firsts = [env.reset(seed=4 + i)[0] for i, env in enumerate(singles)]
    rng = np.random.default_rng(0)
    for _ in range(12):
        actions = rng.uniform(-1, 1, size=(2, 1))
        obs, *_ = venv.step(actions)
        for i, env in enumerate(singles):
            single, *_ = env.step(actions[i])
            for key, value in single.items():
                np.testing.assert_array_equal(obs[key][i], value, err_msg=key)
    assert firsts  # both started
    venv.close()


class CameraGoalTask(GoalTask):
    """GoalTask observed through the pendulum's camera as well."""

    def __init__(self) -> None:
        super().__init__()
        self.pendulum.observables.add_observable(
            "front_image", observation.MJCFCamera(self.pendulum.camera, 24, 32)
        )
        self.pendulum.observables["front_image"].enabled = True


def test_camera_frames_show_the_state_after_step_left():
    env = composer.Environment(CameraGoalTask())
    venv = composer.VectorEnvironment(CameraGoalTask, num_envs=2)
    env.reset(seed=2)
    venv.reset(seed=2)
    for t in range(1, 7):
        obs, *_ = env.step(np.zeros(1))
        vector_obs, *_ = venv.step(np.zeros((2, 1)))
        # Drawn of the state the step ended in: after_step moved the hinge at t = 3, 6.
        now = env.physics.render(24, 32, camera_id=env.physics.model.ncam - 1)
        np.testing.assert_array_equal(obs["pendulum/front_image"], now, err_msg=f"step {t}")
        np.testing.assert_array_equal(vector_obs["pendulum/front_image"][0], now)
    pixels = composer.PixelEnvironment(
        composer.Environment(GoalTask(), flatten_observations=True),
        height=16, width=16, camera=0, proprioception=True,
    )  # fmt: skip
    pixels.reset(seed=0)
    for t in range(1, 5):
        obs, *_ = pixels.step(np.zeros(1))
        assert obs["proprioception"][0] == _goal_after(t)  # 'goal' sorts first
    env.close()
    venv.close()
    pixels.close()


# -- dm_control's own Environment, run on our task ---------------------------------------


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """dm_control's composer `environment` module, on our mjcf and our observables."""
    with dm_control_environment.loaded(tmp_path_factory.mktemp("reference")) as module:
        yield module


def test_an_episode_observes_what_dm_control_s_environment_observes(reference):
    ours = composer.Environment(GoalTask(), random_state=3)
    theirs = reference.Environment(
        GoalTask(),
        random_state=3,
        strip_singleton_obs_buffer_dim=True,
        delayed_observation_padding=reference.ObservationPadding.INITIAL_VALUE,
    )
    observation_ours, _ = ours.reset()
    timestep = theirs.reset()
    actions = np.random.default_rng(7).uniform(-1, 1, size=(60, 1))
    for t in range(len(actions) + 1):
        assert sorted(timestep.observation) == sorted(observation_ours)
        for key, value in timestep.observation.items():
            np.testing.assert_array_equal(observation_ours[key], value, err_msg=f"{key} at {t}")
        if t == len(actions):
            break
        observation_ours, reward, *_ = ours.step(actions[t])
        timestep = theirs.step(actions[t])
        assert reward == timestep.reward
