"""Small real entities and tasks the composer tests share."""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas import Floor
from composer import observation


class Pendulum(composer.Entity):
    """A hinged rod with a motor, a joint sensor and a camera."""

    def _build(self, name: str = "pendulum", gear: float = 1.0) -> None:
        root = self._mjcf_root = mjcf.RootElement(model=name)
        base = root.worldbody.add("body", name="base", pos=[0, 0, 1])
        self.hinge = base.add("joint", name="hinge", type="hinge", axis=[0, 1, 0], damping=0.1)
        base.add("geom", name="rod", type="capsule", fromto=[0, 0, 0, 0, 0, -0.5], size=[0.03])
        self.tip = base.add("site", name="tip", pos=[0, 0, -0.5])
        self.motor = root.actuator.add(
            "motor", name="motor", joint=self.hinge, gear=[gear], ctrlrange=[-1, 1]
        )
        root.sensor.add("jointpos", name="angle", joint=self.hinge)
        self.camera = root.worldbody.add(
            "camera", name="front", pos=[0, -2, 1], xyaxes=[1, 0, 0, 0, 0, 1]
        )

    @composer.observable
    def orientation(self) -> observation.Observable:
        """(cos, sin) of the angle: bounded, unlike the angle."""
        hinge = self.hinge
        return observation.Generic(
            lambda physics: np.array([np.cos(physics.bind(hinge).qpos[0]),
                                      np.sin(physics.bind(hinge).qpos[0])]),
            bounds=(-1, 1),
        )  # fmt: skip

    @composer.observable
    def angular_velocity(self) -> observation.Observable:
        hinge = self.hinge
        return observation.Generic(
            lambda physics: np.clip(physics.bind(hinge).qvel, -20, 20), bounds=(-20, 20)
        )

    @composer.observable
    def joint_positions(self) -> observation.Observable:
        return observation.MJCFFeature("qpos", [self.hinge])

    @composer.observable
    def joint_velocities(self) -> observation.Observable:
        return observation.MJCFFeature("qvel", [self.hinge])


class Block(composer.Entity):
    """A free box prop."""

    def _build(self, name: str = "block", half: float = 0.05) -> None:
        root = self._mjcf_root = mjcf.RootElement(model=name)
        body = root.worldbody.add("body", name="body")
        self.geom = body.add("geom", name="geom", type="box", size=[half] * 3, mass=0.2)
        self.body = body


class SwingTask(composer.Task):
    """Keep a pendulum near its lowest point; starts at a random angle."""

    def __init__(self, gear: float = 1.0, substeps: int = 4, terminate_above: float = np.inf):
        self._arena = Floor(size=(2, 2))
        self.pendulum = Pendulum(gear=gear)
        self._arena.attach(self.pendulum)
        self.pendulum.orientation.enabled = True
        self.pendulum.angular_velocity.enabled = True
        self.set_timesteps(control_timestep=0.005 * substeps, physics_timestep=0.005)
        self._terminate_above = terminate_above

    @property
    def root_entity(self) -> composer.Entity:
        return self._arena

    def initialize_episode(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        physics.bind(self.pendulum.hinge).qpos = random_state.uniform(-1, 1)

    def get_reward(self, physics: mjcf.Physics) -> float:
        return float(-abs(physics.bind(self.pendulum.hinge).qpos[0]))

    def should_terminate_episode(self, physics: mjcf.Physics) -> bool:
        return bool(abs(physics.bind(self.pendulum.hinge).qpos[0]) > self._terminate_above)
