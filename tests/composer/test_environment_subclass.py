"""Subclasses of `composer.Environment` written against dm_control's internals (issue 37,
item 4; `composer.dm_internals`).

Public projects subclass dm_control's `composer.Environment` and override or call its
internals; each way is written here in our own words, on a real task:
- kevinzakka/mujoco_utils (`composer_utils.Environment`, which google-research/robopianist
  builds its environments with) overrides `_reset_attempt` to skip recompiles: it calls
  `_hooks.initialize_episode_mjcf`, `_recompile_physics_and_update_observables`,
  `_physics.reset_context`, `_hooks.initialize_episode`, `_observation_updater.reset` and
  `get_observation`, sets `_reset_next_step` and returns a dm_env TimeStep;
- OpenMOSS/VLABench (`VLABench/envs/dm_env.py`) changes the task's distractor entities in
  its `_reset_attempt`, calls `_hooks.refresh_entity_hooks()`, then returns
  `super()._reset_attempt()`; a fork of it overrides `step` as dm_control's is written
  (`_hooks.before_step`/`after_step`, `_observation_updater.prepare_for_next_control_step`
  / `update` / `get_observation`, `_substep`, `_n_sub_steps`, `_reset_next_step`);
- a safe-RL fork of mujoco_utils (its `CMDPEnvironment`) overrides `_reset_attempt` and
  `step` that way too, its steps carrying a cost.
And dm_control's own `_reset_attempt`, `step` and `_substep` (from its wheel, fetched at test
time) run as a subclass's methods on ours: the same episode as our own, to the last bit.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
import pytest

import composer
import mjcf
from composer import observation
from tests.composer import dm_control_environment
from tests.composer.scenes import Block, SwingTask

ACTIONS = np.random.default_rng(11).uniform(-1, 1, size=(24, 1))


class BusyTask(SwingTask):
    """SwingTask with observables on every schedule (buffered, every other step, delayed),
    an `after_step` that moves the hinge, counted compile hooks, and a cost."""

    def __init__(self) -> None:
        super().__init__(substeps=4)
        pendulum = self.pendulum
        pendulum.joint_positions.configure(enabled=True, buffer_size=3)
        pendulum.joint_velocities.configure(enabled=True, update_interval=3, delay=2)
        self.steps = 0
        self.mjcf_hook_calls = 0
        self.after_compile_calls = 0
        self._count = observation.Generic(lambda physics: np.array([float(self.steps)]))
        self._count.enabled = True

    @property
    def task_observables(self) -> dict[str, observation.Observable]:
        return {"count": self._count}

    def initialize_episode_mjcf(self, random_state: np.random.RandomState) -> None:
        self.mjcf_hook_calls += 1
        self.pendulum.motor.gear = [1.0 + random_state.uniform()]

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        self.after_compile_calls += 1

    def initialize_episode(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        super().initialize_episode(physics, random_state)
        self.steps = 0

    def after_step(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        self.steps += 1
        if self.steps % 5 == 0:
            physics.bind(self.pendulum.hinge).qpos = random_state.uniform(-1, 1)

    def get_cost(self, physics: mjcf.Physics) -> float:
        return float(abs(physics.bind(self.pendulum.hinge).qvel[0]) > 2)


def _episodes(env: composer.Environment, count: int = 3, dm_style: bool = False) -> list[Any]:
    """`count` episodes of ACTIONS: every observation and reward, as (key, array) lists."""
    record: list[Any] = []
    for _ in range(count):
        observation_, _ = env.reset()
        record.append(sorted(observation_.items()))
        for action in ACTIONS:
            if dm_style:
                timestep = env.step(action)
                observation_, reward = timestep.observation, timestep.reward
            else:
                observation_, reward, *_ = env.step(action)
            record.append((sorted(observation_.items()), reward))
    return record


def _assert_same(ours: list[Any], theirs: list[Any]) -> None:
    assert len(ours) == len(theirs)
    for k, (mine, other) in enumerate(zip(ours, theirs, strict=True)):
        if isinstance(mine, tuple):
            (mine, mine_reward), (other, other_reward) = mine, other
            assert mine_reward == other_reward, f"reward {k}"
        assert [key for key, _ in mine] == [key for key, _ in other]
        for (key, value), (_, other_value) in zip(mine, other, strict=True):
            np.testing.assert_array_equal(value, other_value, err_msg=f"{key} at {k}")


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """dm_control's composer `environment` module, on our mjcf and our observables."""
    with dm_control_environment.loaded(tmp_path_factory.mktemp("reference")) as module:
        yield module


@pytest.mark.parametrize("recompile", [True, False])
def test_dm_control_s_own_reset_and_step_run_as_a_subclass_s_methods(reference, recompile):
    class DmControlMethods(composer.Environment):
        _reset_attempt = reference.Environment._reset_attempt
        step = reference.Environment.step
        _substep = reference.Environment._substep

    options = {"random_state": 3, "recompile_mjcf_every_episode": recompile}
    ours_task, their_task = BusyTask(), BusyTask()
    ours = composer.Environment(ours_task, **options)
    theirs = DmControlMethods(their_task, **options)
    _assert_same(_episodes(ours), _episodes(theirs, dm_style=True))
    assert their_task.mjcf_hook_calls == ours_task.mjcf_hook_calls == (3 if recompile else 1)
    assert their_task.after_compile_calls == ours_task.after_compile_calls


class StaticPhysicsEnvironment(composer.Environment):
    """As mujoco_utils' environment: recompiles at every reset, or only at the first."""

    def __init__(self, recompile_physics: bool = True, **base_kwargs: Any) -> None:
        super().__init__(**base_kwargs)
        self._recompile_physics_active = recompile_physics
        self._physics_recompiled_once = False

    def _reset_attempt(self) -> Any:
        import dm_env

        if self._recompile_physics_active or not self._physics_recompiled_once:
            self._hooks.initialize_episode_mjcf(self._random_state)
            self._recompile_physics_and_update_observables()
            self._physics_recompiled_once = True
        with self._physics.reset_context():
            self._hooks.initialize_episode(self._physics_proxy, self._random_state)
        self._observation_updater.reset(self._physics_proxy, self._random_state)
        self._reset_next_step = False
        first = self._observation_updater.get_observation()
        return dm_env.TimeStep(dm_env.StepType.FIRST, None, None, first)


@pytest.mark.parametrize("recompile", [True, False])
def test_a_subclass_skipping_recompiles_as_mujoco_utils_does(recompile):
    pytest.importorskip("dm_env")
    task, plain_task = BusyTask(), BusyTask()
    env = StaticPhysicsEnvironment(recompile_physics=recompile, task=task, random_state=5)
    plain = composer.Environment(plain_task, random_state=5, recompile_mjcf_every_episode=recompile)
    observation_, info = env.reset()
    assert isinstance(observation_, dict) and info == {}  # Gymnasium's, of its TimeStep
    plain_observation, _ = plain.reset()
    _assert_same([sorted(plain_observation.items())], [sorted(observation_.items())])
    env.reset(seed=9)
    plain.reset(seed=9)
    _assert_same(_episodes(plain), _episodes(env))
    resets = 5  # two above, three episodes
    assert task.mjcf_hook_calls == (resets if recompile else 1)
    assert task.after_compile_calls == 1 + task.mjcf_hook_calls  # construction, then each
    assert env.step(ACTIONS[0])[0].keys() == observation_.keys()


class Distractor(Block):
    """A block placed by its own `initialize_episode` hook."""

    def initialize_episode(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        physics.bind(self.body).pos = [random_state.uniform(1, 2), 0, 0.3]


class DistractorTask(BusyTask):
    """BusyTask with distractor blocks, replaced by `reset_distractors` (as VLABench's)."""

    def __init__(self) -> None:
        super().__init__()
        self.distractors: list[Distractor] = []

    def reset_distractors(self, count: int) -> None:
        for block in self.distractors:
            block.detach()
        self.distractors = [Distractor(name=f"distractor_{i}") for i in range(count)]
        for block in self.distractors:
            self.root_entity.attach(block)


class DistractingEnvironment(composer.Environment):
    """As VLABench's: new distractors each episode, then dm_control's reset attempt."""

    def _reset_attempt(self) -> Any:
        self.task.reset_distractors(len(self.task.distractors) + 1)
        self._hooks.refresh_entity_hooks()
        return super()._reset_attempt()


def test_a_subclass_changing_entities_before_super_reset_attempt_as_vlabench_does():
    task = DistractorTask()
    env = DistractingEnvironment(task, random_state=2)
    for episode in range(1, 4):
        observation_, info = env.reset()
        assert info == {} and observation_.keys() == set(env.observation_space.spaces)
        assert [block.name for block in task.distractors] == [
            f"distractor_{i}" for i in range(episode)
        ]
        for block in task.distractors:  # the new entities' hooks ran on the new model
            x = env.physics.bind(block.body).pos[0]
            assert 1 <= x <= 2
        env.step(ACTIONS[0])


def test_what_an_override_of_reset_attempt_returns_is_what_reset_returns():
    class Annotating(composer.Environment):
        def _reset_attempt(self):
            observation_, info = super()._reset_attempt()
            return observation_, {**info, "start": observation_["count"].copy()}

    observation_, info = Annotating(BusyTask()).reset(seed=0)
    np.testing.assert_array_equal(info["start"], observation_["count"])
    assert observation_["count"][0] == 0


def test_an_override_of_recompile_runs_at_every_compile():
    class Caching(composer.Environment):
        compiles: list[int]

        def _recompile_physics_and_update_observables(self):
            super()._recompile_physics_and_update_observables()
            self.compiles = [*getattr(self, "compiles", []), self._physics.model.nbody]

    task = BusyTask()
    env = Caching(task, recompile_mjcf_every_episode=True)
    assert len(env.compiles) == 1  # at construction, as dm_control compiles there
    for episode in range(1, 4):
        env.reset()
        assert len(env.compiles) == 1 + episode
    assert task.after_compile_calls == 4
    lazy = Caching(BusyTask())  # recompiles when initialize_episode_mjcf changed the model
    lazy.reset()
    lazy.reset()
    assert len(lazy.compiles) == 3


class SafeStep(NamedTuple):
    """A step with a cost, as the safe-RL environment's TimeSteps carry one."""

    step_type: int
    reward: float | None
    cost: float | None
    discount: float | None
    observation: Any


class CostEnvironment(composer.Environment):
    """As the safe-RL fork's CMDPEnvironment: dm_control's step, written out, with a cost."""

    def _reset_attempt(self) -> SafeStep:
        self._hooks.initialize_episode_mjcf(self._random_state)
        self._recompile_physics_and_update_observables()
        with self._physics.reset_context():
            self._hooks.initialize_episode(self._physics_proxy, self._random_state)
        self._observation_updater.reset(self._physics_proxy, self._random_state)
        self._reset_next_step = False
        return SafeStep(0, None, None, None, self._observation_updater.get_observation())

    def step(self, action: Any) -> Any:
        if self._reset_next_step:
            self._reset_next_step = False
            return self.reset()
        self._hooks.before_step(self._physics_proxy, action, self._random_state)
        self._observation_updater.prepare_for_next_control_step()
        for i in range(self._n_sub_steps):
            self._substep(action)
            if i < self._n_sub_steps - 1:
                self._observation_updater.update()
        self._hooks.after_step(self._physics_proxy, self._random_state)
        self._observation_updater.update()
        reward = self._task.get_reward(self._physics_proxy)
        cost = self._task.get_cost(self._physics_proxy)
        discount = self._task.get_discount(self._physics_proxy)
        observation_ = self._observation_updater.get_observation()
        if self._physics.time() >= self._time_limit:
            self._reset_next_step = True
            return SafeStep(2, reward, cost, discount, observation_)
        return SafeStep(1, reward, cost, discount, observation_)


def test_a_step_written_as_dm_control_s_with_a_cost_observes_what_ours_does():
    task = BusyTask()
    env = CostEnvironment(task, random_state=4, recompile_mjcf_every_episode=True)
    plain = composer.Environment(BusyTask(), random_state=4, recompile_mjcf_every_episode=True)
    _assert_same(_episodes(plain), _episodes(env, dm_style=True))
    assert env.step(ACTIONS[0]).cost == task.get_cost(env.physics)
    limited = CostEnvironment(BusyTask(), time_limit=0.1)  # 5 steps of 0.02 s
    limited.reset()
    steps = [limited.step(ACTIONS[0]) for _ in range(6)]
    assert [step.step_type for step in steps[:5]] == [1, 1, 1, 1, 2]
    assert len(steps[5]) == 2 and steps[5][1] == {}  # after LAST, a reset: (obs, info)


def test_an_override_of_substep_runs_for_each_physics_step():
    class Counting(composer.Environment):
        substeps = 0

        def _substep(self, action):
            super()._substep(action)
            self.substeps += 1

    env = Counting(BusyTask(), random_state=1)
    plain = composer.Environment(BusyTask(), random_state=1)
    _assert_same(_episodes(plain, count=1), _episodes(env, count=1))
    assert env.substeps == len(ACTIONS) * 4


def test_overrides_that_cannot_be_kept_are_refused_when_the_environment_is_made():
    class NoSuper(composer.Environment):
        def _recompile_physics_and_update_observables(self):
            self.compiled = False

    with pytest.raises(composer.OverrideError, match=r"NoSuper\._recompile_physics_and_upd"):
        NoSuper(BusyTask())

    class NoPhysics(composer.Environment):
        def _recompile_physics(self):
            pass

    with pytest.raises(composer.OverrideError, match=r"NoPhysics\._recompile_physics\(\) left"):
        NoPhysics(BusyTask())

    class OwnUpdater(composer.Environment):
        def _make_observation_updater(self):
            return {"count": None}

    with pytest.raises(composer.OverrideError, match=r"_make_observation_updater\(\) returned"):
        OwnUpdater(BusyTask())


def test_a_reset_attempt_returning_something_else_is_named():
    class Forgetful(composer.Environment):
        def _reset_attempt(self):
            super()._reset_attempt()

    env = Forgetful(BusyTask())
    with pytest.raises(composer.OverrideError, match=r"Forgetful\._reset_attempt\(\) returned"):
        env.reset()


def test_dm_control_s_calls_out_of_order_or_with_bad_actions_are_composer_errors():
    env = composer.Environment(BusyTask())
    env.reset(seed=0)
    with pytest.raises(composer.EpisodeError, match="prepare_for_next_control_step"):
        env._observation_updater.update()
    with pytest.raises(composer.EpisodeError):
        env._hooks.before_step(env.physics, np.zeros(3), env.random_state)
    env._hooks.before_step(env.physics, [0.5], env.random_state)
    assert env.physics.data.ctrl[0] == 0.5
