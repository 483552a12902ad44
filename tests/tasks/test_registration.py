"""composer.registration: ids, specs that pickle, kwargs routing and their errors."""

from __future__ import annotations

import math
import pickle
import subprocess
import sys
import warnings

import gymnasium
import numpy as np
import pytest

import composer
import tasks
from composer import registration
from tests.composer.scenes import SwingTask
from tests.conftest import REPO


def test_register_returns_the_id_and_records_what_it_registered():
    env_id = registration.register(
        "TestSwing", "tests.composer.scenes:SwingTask", "a test pendulum", version=3, gear=2.0
    )
    assert env_id == "composer/TestSwing-v3"
    spec = gymnasium.spec(env_id)
    assert spec.entry_point == "composer.registration:make_environment"
    assert spec.vector_entry_point == "composer.vector:make_vector_environment"
    assert spec.kwargs == {"task": "tests.composer.scenes:SwingTask", "gear": 2.0}
    info = registration.registered()[env_id]
    assert (info.name, info.task, info.description) == ("TestSwing", spec.kwargs["task"],
                                                        "a test pendulum")  # fmt: skip
    assert info.default_kwargs == {"gear": 2.0}


def test_registering_an_id_again_is_a_silent_no_op():
    before = gymnasium.spec("composer/Reach-v0")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert registration.register("Reach", "tasks.reach:Reach", "again") == before.id
    assert gymnasium.spec("composer/Reach-v0") is before
    assert registration.registered()["composer/Reach-v0"].description != "again"


def test_register_rejects_a_task_that_is_not_an_import_path():
    with pytest.raises(registration.RegistrationError, match="import path"):
        registration.register("Bad", SwingTask, "a class, not a string")  # type: ignore[arg-type]


def test_specs_pickle_for_subprocess_vector_envs():
    for env_id in tasks.IDS:
        spec = pickle.loads(pickle.dumps(gymnasium.spec(env_id)))
        assert spec.kwargs["task"].startswith("tasks.")


def test_resolve_task_imports_paths_and_passes_callables_through():
    assert registration.resolve_task("tasks.reach:Reach") is tasks.Reach
    assert registration.resolve_task("tasks.reach.Reach") is tasks.Reach
    assert registration.resolve_task(SwingTask) is SwingTask
    with pytest.raises(registration.RegistrationError, match=r"cannot import 'tasks\.nope'"):
        registration.resolve_task("tasks.nope:Task")
    with pytest.raises(registration.RegistrationError, match="no callable 'Nope'"):
        registration.resolve_task("tasks.reach:Nope")
    with pytest.raises(registration.RegistrationError, match="not an import path"):
        registration.resolve_task("Reach")


def test_unknown_keyword_names_the_task_and_lists_what_it_accepts():
    with pytest.raises(composer.Error) as caught:
        gymnasium.make("composer/Reach-v0", colour="red")
    message = str(caught.value)
    assert "'tasks.reach:Reach'" in message and "['colour']" in message
    assert "success_distance" in message and "time_limit" in message


def test_keywords_reach_the_task_and_the_environment():
    env = gymnasium.make(
        "composer/Reach-v0", success_distance=0.05, time_limit=0.2, flatten_observations=True
    )
    assert env.unwrapped.task.success_distance == 0.05
    assert isinstance(env.observation_space, gymnasium.spaces.Box)
    env.reset(seed=0)
    steps = 0
    truncated = False
    while not truncated:
        *_, truncated, _ = env.step(env.action_space.sample())
        steps += 1
    assert steps == math.ceil(0.2 / 0.04)


def test_make_environment_without_a_time_limit_never_truncates():
    env = registration.make_environment(SwingTask, gear=2.0)
    env.reset(seed=0)
    for _ in range(300):
        assert not env.step(np.zeros(1))[3]


def test_make_environment_renders_through_the_tasks_camera():
    env = registration.make_environment("tasks.locomotion:WalkerRun", render_mode="rgb_array")
    env.reset(seed=0)
    physics = env.physics
    np.testing.assert_array_equal(env.render(), physics.render(camera_id="walker/track"))
    assert not np.array_equal(env.render(), physics.render(camera_id=-1))


def test_a_factory_that_makes_no_task_is_an_error():
    with pytest.raises(registration.RegistrationError, match=r"not a composer\.Task"):
        registration.make_environment(lambda: "a task?")


def test_gym_make_with_the_module_prefix_imports_tasks_itself():
    code = (
        "import gymnasium as gym\n"
        "env = gym.make('tasks:composer/Reach-v0', flatten_observations=True)\n"
        "print(env.observation_space.shape)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, check=True
    )
    assert result.stdout.strip() == "(10,)"


def test_render_list_modes_are_offered_through_the_entry_point_metadata():
    env = gymnasium.make("composer/Reach-v0", render_mode="rgb_array_list")
    env.reset(seed=0)
    env.step(env.action_space.sample())
    frames = env.render()
    assert len(frames) == 2 and frames[0].shape == (240, 320, 3)
