"""`@composer.observable` on a task (issue 37, item 3).

dm_control's `define.observable` is a cached property on any object, and real tasks declare
their own observables with it: TuragaLab/flybody's walk-on-ball task declares `ball_qvel` so
and adds it to its walker's observables in `__init__`; piano tasks list a goal in their own
`task_observables`. Written here in our words: a walker on a floating ball, whose task
declares both kinds, the goal advanced by `after_step` and indexed by the step count.
"""

from __future__ import annotations

import collections
import threading

import numpy as np
import pytest

import composer
import mjcf
from composer.observation import observable

GOALS = np.arange(12.0).reshape(6, 2)


class Walker(composer.Entity):
    """Two hinged legs with motors."""

    def _build(self, name: str = "walker") -> None:
        root = self._mjcf_root = mjcf.RootElement(model=name)
        thorax = root.worldbody.add("body", name="thorax", pos=[0, 0, 0.6])
        thorax.add("geom", type="sphere", size=[0.05], mass=0.1)
        for side, y in (("left", 0.05), ("right", -0.05)):
            leg = thorax.add("body", name=f"{side}_leg", pos=[0, y, 0])
            joint = leg.add("joint", name=f"{side}_hip", axis=[0, 1, 0], range=[-1, 1])
            leg.add("geom", type="capsule", fromto=[0, 0, 0, 0.1, 0, -0.15], size=[0.01])
            root.actuator.add("position", name=side, joint=joint, kp=2, ctrlrange=[-1, 1])


class BallArena(composer.Arena):
    """A ball on a ball joint under a tethered walker."""

    def _build(self, name: str = "arena") -> None:
        super()._build(name=name)
        ball = self.mjcf_model.worldbody.add("body", name="ball", pos=[0, 0, 0.25])
        ball.add("joint", name="ball", type="ball", damping=0.01)
        ball.add("geom", type="sphere", size=[0.25], mass=1)


class WalkingTask(composer.Task):
    """The base class of walking tasks: a goal observable for its subclasses."""

    def __init__(self) -> None:
        self._arena = BallArena()
        self._walker = Walker()
        self._arena.attach(self._walker)
        self.set_timesteps(control_timestep=0.01, physics_timestep=0.005)
        self._step = 0

    @property
    def root_entity(self) -> composer.Entity:
        return self._arena

    @composer.observable
    def goal(self) -> observable.Generic:
        """The target of the current step (the step count indexes the goals)."""
        return observable.Generic(lambda physics: GOALS[self._step % len(GOALS)])

    def initialize_episode(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        self._step = 0

    def after_step(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        self._step += 1

    def get_reward(self, physics: mjcf.Physics) -> float:
        return -float(np.linalg.norm(physics.named.data.qvel["ball"]))


class WalkOnBall(WalkingTask):
    """Declares the ball's velocity as a task observable and hands it to the walker."""

    def __init__(self) -> None:
        super().__init__()
        self._walker.observables.add_observable("ball_qvel", self.ball_qvel)
        self.goal.enabled = True

    @composer.observable
    def ball_qvel(self) -> observable.Generic:
        """The ball's rotational velocity."""
        return observable.Generic(lambda physics: physics.named.data.qvel["ball"])

    @property
    def task_observables(self) -> collections.OrderedDict[str, observable.Observable]:
        return collections.OrderedDict([("goal", self.goal)])


def test_a_task_s_observables_are_cached_properties_as_in_dm_control():
    task = WalkOnBall()
    assert isinstance(type(task).goal, property)  # dm_control's cached_property is one
    assert task.goal is task.goal and vars(task)["goal"] is task.goal
    assert task.ball_qvel is task._walker.observables["ball_qvel"]
    other = WalkOnBall()
    assert other.goal is not task.goal  # one per task object
    assert type(task).goal.__doc__.startswith("The target of the current step")


def test_a_task_s_observables_are_observed_where_it_puts_them():
    task = WalkOnBall()
    env = composer.Environment(task, random_state=0)
    assert {"goal", "walker/ball_qvel"} <= set(env.observation_space.spaces)
    obs, _ = env.reset()
    np.testing.assert_array_equal(obs["goal"], GOALS[0])
    for t in range(1, 9):
        obs, *_ = env.step(env.action_space.sample())
        # after_step advanced the goal: the observation shows the new one (item 1)
        np.testing.assert_array_equal(obs["goal"], GOALS[t % len(GOALS)])
        np.testing.assert_array_equal(obs["walker/ball_qvel"], env.physics.named.data.qvel["ball"])


def test_a_task_s_observable_is_made_once_when_first_read_from_two_threads():
    made = []

    class Counting(WalkOnBall):
        @composer.observable
        def clock(self) -> observable.Generic:
            made.append(1)
            return observable.Generic(lambda physics: np.array([physics.time()]))

    task = Counting()
    barrier = threading.Barrier(2)
    seen = []

    def read() -> None:
        barrier.wait()
        seen.append(task.clock)

    threads = [threading.Thread(target=read) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert len(made) == 1 and seen[0] is seen[1]


def test_an_entity_s_observable_is_still_its_observables_one():
    walker = Walker()

    class Sensing(Walker):
        @composer.observable
        def hips(self) -> observable.MJCFFeature:
            return observable.MJCFFeature("qpos", self.mjcf_model.find_all("joint"))

    sensing = Sensing()
    assert sensing.hips is sensing.observables["hips"] and "hips" not in vars(sensing)
    with pytest.raises(composer.ObservableNotFoundError):
        walker.observables["hips"]
