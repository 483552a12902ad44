"""Tasks: timesteps and substeps, the action space, observable names."""

from __future__ import annotations

import numpy as np
import pytest

import composer
import mjcf
from arenas import Floor
from composer import observation
from tests.composer.scenes import Pendulum, SwingTask
from tests.conftest import gym_model


def test_substeps_follow_from_the_timesteps():
    task = SwingTask(substeps=4)
    assert task.physics_timestep == 0.005 and task.physics_steps_per_control_step == 4
    assert task.root_entity.mjcf_model.option.timestep == 0.005
    task.control_timestep = 0.015
    assert task.physics_steps_per_control_step == 3
    env = composer.Environment(task)
    assert env.control_timestep == pytest.approx(0.015)
    assert env.metadata["render_fps"] == pytest.approx(1 / 0.015)


def test_timesteps_that_do_not_divide_are_refused():
    task = SwingTask()
    with pytest.raises(composer.TaskError, match=r"0.012 must be a multiple of .* 0.005"):
        task.set_timesteps(control_timestep=0.012, physics_timestep=0.005)
    with pytest.raises(composer.TaskError, match="physics timestep must be a positive"):
        task.set_timesteps(control_timestep=0.01, physics_timestep=0)
    assert task.physics_steps_per_control_step == 4  # unchanged by the refused calls


def test_defaults_without_timesteps_are_mujoco_own():
    task = composer.NullTask(Floor())
    assert task.physics_timestep == 0.002 and task.physics_steps_per_control_step == 1


def test_action_space_is_bounded_by_ctrlrange_where_limited():
    arena, pendulum = Floor(), Pendulum()
    arena.attach(pendulum)
    hinge = pendulum.hinge
    pendulum.mjcf_model.actuator.add("motor", joint=hinge, ctrlrange=[-2, 3])
    pendulum.mjcf_model.actuator.add("velocity", joint=hinge, ctrllimited=False)
    physics = mjcf.Physics.from_mjcf_model(arena.mjcf_model)
    space = composer.NullTask(arena).action_space(physics)
    np.testing.assert_array_equal(space.low, [-1, -2, -np.inf])
    np.testing.assert_array_equal(space.high, [1, 3, np.inf])
    assert space.dtype == np.float32


def test_observable_names_are_scoped_and_unique():
    task = SwingTask()
    names = set(task.observables)
    assert {"pendulum/orientation", "pendulum/joint_positions"} <= names
    assert set(task.enabled_observables()) == {"pendulum/orientation", "pendulum/angular_velocity"}

    class Clashing(SwingTask):
        @property
        def task_observables(self):
            return {"pendulum/orientation": observation.Generic(lambda physics: 0.0)}

    with pytest.raises(
        composer.TaskError, match="two observables are named 'pendulum/orientation'"
    ):
        _ = Clashing().observables


def test_a_recompile_that_changes_a_space_is_refused():
    class Growing(SwingTask):
        def initialize_episode_mjcf(self, random_state):
            if getattr(self, "grown", False):
                return
            self.grown = True
            self.pendulum.mjcf_model.actuator.add("motor", joint=self.pendulum.hinge)

    env = composer.Environment(Growing())
    with pytest.raises(composer.TaskError, match="action space changed"):
        env.reset(seed=0)


def test_an_entity_timestep_is_the_scene_timestep_and_set_timesteps_keeps_them_agreeing():
    arena, humanoid = Floor(), composer.Entity.from_path(gym_model("humanoid"))
    arena.mjcf_model.compiler.inertiafromgeom = "true"  # as humanoid.xml sets it
    arena.attach(humanoid)
    task = composer.NullTask(arena)
    assert task.physics_timestep == 0.003  # humanoid.xml's own
    task.set_timesteps(control_timestep=0.01, physics_timestep=0.005)
    assert humanoid.mjcf_model.option.timestep == arena.mjcf_model.option.timestep == 0.005
    env = composer.Environment(task)
    assert env.physics.timestep() == 0.005 and env.control_timestep == pytest.approx(0.01)
