"""The dm_env bridge: dm_env's own conformance tests on composer environments (shipped
tasks and a test scene), discounts of terminations and truncations, tasks declaring
dm_control's `action_spec`, `Task.action_spec` against dm_control's own (issue 37, item 5),
spec conversions, and `import composer` without dm_env."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import types
import unittest
import zipfile

import mujoco
import numpy as np
import pytest
from gymnasium import spaces

import composer
from tests import dm_control_wheel
from tests.composer.scenes import SwingTask
from tests.conftest import REPO

dm_env = pytest.importorskip("dm_env")
test_utils = pytest.importorskip("dm_env.test_utils")
specs = dm_env.specs
from composer import dm_env_bridge  # noqa: E402  (after the skip without the extra)
from tasks.locomotion import WalkerRun  # noqa: E402
from tasks.reach import Reach  # noqa: E402


def adapter(task: composer.Task, time_limit: float = 1.0, seed: int = 0):
    return dm_env_bridge.DmEnvAdapter(composer.Environment(task, time_limit=time_limit), seed)


class RandomActions:
    """Random actions within the adapter's action spec, enough to end episodes."""

    steps = 120

    def make_action_sequence(self):
        spec = self.environment.action_spec()
        random = np.random.RandomState(0)
        for _ in range(self.steps):
            yield random.uniform(spec.minimum, spec.maximum).astype(spec.dtype)


class WalkerConformance(RandomActions, test_utils.EnvironmentTestMixin, unittest.TestCase):
    """A shipped task that terminates when the walker falls."""

    def make_object_under_test(self):
        return adapter(WalkerRun(), time_limit=20.0)


class ReachConformance(RandomActions, test_utils.EnvironmentTestMixin, unittest.TestCase):
    """A shipped task truncated by its time limit."""

    def make_object_under_test(self):
        return adapter(Reach(), time_limit=0.5)


class DeclaredSpecConformance(RandomActions, test_utils.EnvironmentTestMixin, unittest.TestCase):
    """A dm_control-style task declaring its own action spec."""

    def make_object_under_test(self):
        return adapter(DeclaresSpec(), time_limit=0.2)


def test_conformance_reaches_the_ends_of_episodes():
    for env in (adapter(WalkerRun(), 20.0), adapter(Reach(), 0.5)):
        kinds, timestep = [], env.reset()
        random = np.random.RandomState(0)
        spec = env.action_spec()
        for _ in range(RandomActions.steps):
            timestep = env.step(random.uniform(spec.minimum, spec.maximum))
            kinds.append(timestep.step_type)
        assert dm_env.StepType.LAST in kinds and dm_env.StepType.FIRST in kinds


class Falls(SwingTask):
    """Terminates at once; states no discount of its own."""

    def __init__(self) -> None:
        super().__init__(terminate_above=-1.0)


class FallsButBootstraps(Falls):
    """Terminates at once with discount 1, as dm_control tasks say an end to bootstrap."""

    def get_discount(self, physics):
        return 1.0


class Discounted(SwingTask):
    """Never terminates; discount 0.9 every step."""

    def get_discount(self, physics):
        return 0.9


def test_termination_has_discount_zero_unless_the_task_states_its_discount():
    first = adapter(Falls())
    assert first.step(np.zeros(1)).first()  # step before any reset starts an episode
    last = first.step(np.zeros(1))
    assert last.last() and last.discount == 0.0
    assert first.step(np.zeros(1)).first()  # after LAST: a new episode, action ignored
    stated = adapter(FallsButBootstraps())
    stated.reset()
    last = stated.step(np.zeros(1))
    assert last.last() and last.discount == 1.0


def test_transitions_and_truncation_keep_the_task_discount():
    env = adapter(Discounted(), time_limit=0.06)  # 3 control steps of 0.02 s
    assert env.reset().discount is None
    steps = [env.step(np.zeros(1)) for _ in range(3)]
    assert [s.step_type for s in steps] == [dm_env.StepType.MID] * 2 + [dm_env.StepType.LAST]
    assert all(s.discount == 0.9 and s.discount.dtype == np.float64 for s in steps)
    assert isinstance(steps[0].reward, np.float64)


def test_observations_follow_the_environment_and_its_spec():
    gym_env = composer.Environment(SwingTask(), time_limit=1.0)
    env = dm_env_bridge.DmEnvAdapter(gym_env, seed=3)
    expected, _ = composer.Environment(SwingTask(), time_limit=1.0).reset(seed=3)
    timestep = env.reset()
    assert timestep.observation.keys() == expected.keys()
    for name, value in expected.items():
        np.testing.assert_array_equal(timestep.observation[name], value)
    spec = env.observation_spec()
    assert spec["pendulum/orientation"].name == "pendulum/orientation"
    assert isinstance(spec["pendulum/orientation"], specs.BoundedArray)
    np.testing.assert_array_equal(spec["pendulum/orientation"].minimum, [-1, -1])
    assert env.physics is gym_env.physics and isinstance(env.task, SwingTask)


class DeclaresSpec(SwingTask):
    """A dm_control task's action spec: narrower than the motor's ctrlrange, float64."""

    def action_spec(self, physics):
        return specs.BoundedArray((1,), np.float64, [-0.5], [0.25], name="motor")


def test_a_task_declaring_a_dm_env_action_spec_gets_it_as_its_action_space():
    env = composer.Environment(DeclaresSpec())
    assert env.action_space == spaces.Box(-0.5, 0.25, (1,), np.float64)
    env.reset(seed=0)
    env.step(np.array([3.0]))
    np.testing.assert_array_equal(env.physics.data.ctrl, [0.25])  # clipped to the spec
    bridged = dm_env_bridge.DmEnvAdapter(env)
    assert bridged.action_spec().name == "motor"  # the task's own spec


def test_an_action_spec_that_is_not_one_array_of_numbers_is_refused():
    class Discrete(SwingTask):
        def action_spec(self, physics):
            return specs.DiscreteArray(3)

    with pytest.raises(composer.TaskError, match=r"one dm_env\.specs\.Array or BoundedArray"):
        composer.Environment(Discrete())


def _dm_control_task_module() -> types.ModuleType:
    """dm_control's own `composer/task.py` from its wheel (fetched at test time), run on
    its own `dm_control.mujoco` from the rewritten wheel."""
    dm_control_wheel.import_module("dm_control.mujoco.wrapper.core")  # its mujoco, imported
    with zipfile.ZipFile(dm_control_wheel.wheel()) as archive:
        source = archive.read("dm_control/composer/task.py").decode()
    module = types.ModuleType("dm_control_task_reference")
    exec(compile(source, "dm_control/composer/task.py", "exec"), module.__dict__)
    return module


def _with_odd_actuators() -> composer.Task:
    """SwingTask with an actuator that is not control-limited and an unnamed one."""
    task = SwingTask()
    model, hinge = task.pendulum.mjcf_model, task.pendulum.hinge
    model.actuator.add("velocity", name="spin", joint=hinge, kv=0.1, ctrllimited=False)
    model.actuator.add("motor", joint=hinge, ctrlrange=[-0.5, 2])
    return task


@pytest.mark.parametrize("make_task", [WalkerRun, _with_odd_actuators])
def test_task_action_spec_is_dm_control_s_on_the_same_model(make_task):
    task = make_task()
    physics = composer.Environment(task).physics
    core = dm_control_wheel.import_module("dm_control.mujoco.wrapper.core")
    their_physics = types.SimpleNamespace(model=core.MjModel(physics.model))
    theirs = _dm_control_task_module().Task.action_spec(task, their_physics)
    ours = task.action_spec(physics)
    assert type(ours) is specs.BoundedArray
    assert (ours.shape, ours.dtype, ours.name) == (theirs.shape, theirs.dtype, theirs.name)
    np.testing.assert_array_equal(ours.minimum, theirs.minimum)
    np.testing.assert_array_equal(ours.maximum, theirs.maximum)
    if make_task is _with_odd_actuators:
        assert ours.name.split("\t")[1:] == ["pendulum/spin", "pendulum//unnamed_actuator_2"]
        assert ours.maximum[1] == mujoco.mjMAXVAL and ours.minimum[2] == -0.5


class UserActions(SwingTask):
    """Two actions of its own after the actuators' (as flybody's walkers add user actions),
    from dm_control's default spec."""

    def action_spec(self, physics):
        spec = super().action_spec(physics)
        return specs.BoundedArray(
            (spec.shape[0] + 2,), spec.dtype, np.append(spec.minimum, [-1, -1]),
            np.append(spec.maximum, [1, 1]), name=spec.name + "\tuser_0\tuser_1",
        )  # fmt: skip

    def before_step(self, physics, action, random_state):
        physics.set_control(action[:-2])
        self.user = action[-2:]


def test_an_action_spec_starting_from_super_is_the_action_space():
    task = UserActions()
    env = composer.Environment(task)
    assert env.action_space == spaces.Box(
        np.array([-1, -1, -1.0]), np.array([1, 1, 1.0]), (3,), np.float64
    )
    env.reset(seed=0)
    env.step(np.array([0.5, 2.0, -0.25]))
    np.testing.assert_array_equal(env.physics.data.ctrl, [0.5])
    np.testing.assert_array_equal(task.user, [1.0, -0.25])  # clipped to the spec
    spec = dm_env_bridge.DmEnvAdapter(env).action_spec()
    assert spec.name == "pendulum/motor\tuser_0\tuser_1"


def test_specs_and_spaces_convert_both_ways():
    nested = {
        "pos": specs.Array((3,), np.float64),
        "count": specs.Array((), np.int32),
        "flag": specs.Array((2,), bool),
        "arm": (specs.BoundedArray((2,), np.float32, 0.0, [1.0, 2.0]), specs.DiscreteArray(4)),
    }
    space = dm_env_bridge.space_from_spec(nested)
    assert space["pos"] == spaces.Box(-np.inf, np.inf, (3,), np.float64)
    assert space["count"] == spaces.Box(-(2**31), 2**31 - 1, (), np.int32)
    assert space["flag"].dtype == np.bool_
    assert space["arm"][0] == spaces.Box(0.0, np.array([1.0, 2.0], np.float32), (2,), np.float32)
    assert space["arm"][1] == spaces.Discrete(4)
    back = dm_env_bridge.spec_from_space(space)
    assert back["pos"] == specs.Array((3,), np.float64, name="pos")
    assert back["arm"][1].num_values == 4
    np.testing.assert_array_equal(back["arm"][0].maximum, [1.0, 2.0])
    shifted = dm_env_bridge.spec_from_space(spaces.Discrete(3, start=2))
    assert (shifted.minimum, shifted.maximum) == (2, 4)
    with pytest.raises(composer.TaskError, match="string spec"):
        dm_env_bridge.space_from_spec(specs.StringArray(()))
    with pytest.raises(composer.TaskError, match="no dm_env spec"):
        dm_env_bridge.spec_from_space(spaces.Text(5))


def run_python(code: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_composer_never_imports_dm_env():
    result = run_python(
        """
        import sys
        import numpy as np
        import composer, tasks
        from tests.composer.scenes import SwingTask
        env = composer.Environment(SwingTask(), time_limit=0.1)
        env.reset(seed=0)
        env.step(np.zeros(1))
        print(sorted(name for name in sys.modules if name.startswith("dm_env")))
        """
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "[]"


def test_without_dm_env_composer_works_and_the_bridge_says_how_to_install_it():
    result = run_python(
        """
        import sys
        sys.modules["dm_env"] = None  # as if the [dm] extra were not installed
        import numpy as np
        import composer
        from tests.composer.scenes import SwingTask
        env = composer.Environment(SwingTask(), time_limit=0.1)
        env.reset(seed=0)
        env.step(np.zeros(1))
        try:
            from composer import dm_env_bridge
        except ImportError as e:
            print(e)
        try:
            env.task.action_spec(env.physics)
        except ImportError as e:
            print(e)
        """
    )
    assert result.returncode == 0, result.stderr
    assert (
        result.stdout.count("pip install -e '.[dm]' from a checkout (or: pip install dm-env)") == 2
    )
