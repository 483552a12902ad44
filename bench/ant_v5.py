"""Gymnasium's Ant-v5 as a composer task, on its own model file, for side-by-side runs.

    env = composer.Environment(AntV5())                  # one environment
    vector = composer.VectorEnvironment(AntV5, 32)       # 32 of them on MuJoCo's batch

The model is gymnasium's ant.xml (the file Ant-v5 loads) with Ant-v5's 5 physics steps per
control step; the reward is Ant-v5's forward velocity + 1 (healthy) - 0.5 |u|^2 without the
contact cost, termination leaves the healthy z range (0.2, 1.0), and the start noise is
Ant-v5's (uniform 0.1 on qpos, normal 0.1 on qvel). Its observables are the entity's
defaults (joint positions and velocities: Ant-v5's observation without the contact
forces). Each per-step method is written once, batched (`get_reward_batch` ...); a single
environment runs it with a batch of one.
"""

from __future__ import annotations

from pathlib import Path

import gymnasium
import numpy as np

import composer
import mjcf

ANT = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "ant.xml"
SUBSTEPS = 5
HEALTHY_Z = (0.2, 1.0)


class AntV5(composer.Task):
    """Ant-v5's task on its own model (see the module docstring)."""

    def __init__(self) -> None:
        self.ant = composer.Entity.from_path(ANT)
        timestep = self.physics_timestep
        self.set_timesteps(control_timestep=SUBSTEPS * timestep, physics_timestep=timestep)
        self.root = self.ant.mjcf_model.find("joint", "root")
        self.joints = self.ant.mjcf_model.find_all("joint")

    @property
    def root_entity(self) -> composer.Entity:
        return self.ant

    def initialize_episode(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        joints = physics.bind(self.joints)
        joints.qpos = joints.qpos + random_state.uniform(-0.1, 0.1, joints.qpos.shape)
        joints.qvel = 0.1 * random_state.standard_normal(joints.qvel.shape)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        control = physics.field("ctrl")
        return (
            physics.bind(self.root).qvel[:, 0] + 1.0 - 0.5 * np.einsum("ij,ij->i", control, control)
        )

    def should_terminate_episode_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        z = physics.bind(self.root).qpos[:, 2]
        return (z < HEALTHY_Z[0]) | (z > HEALTHY_Z[1])
