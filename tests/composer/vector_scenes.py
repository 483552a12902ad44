"""Tasks the vector environment tests share: the swinging pendulum of `scenes`, batched."""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas import Floor
from composer import BatchPhysics, observation
from composer.observation import BatchGeneric
from tests.composer.scenes import Pendulum, SwingTask


class BatchedSwing(SwingTask):
    """SwingTask with its per-step methods in batched form (overriding SwingTask's single
    forms) and batchable observables only: the fast path. `schedule=True` adds an update
    interval that does not divide the substeps, a delay, a buffer, an aggregator and a
    corruptor."""

    def __init__(
        self,
        schedule: bool = False,
        gear: float = 1.0,
        substeps: int = 4,
        terminate_above: float = np.inf,
    ) -> None:
        super().__init__(gear=gear, substeps=substeps, terminate_above=terminate_above)
        pendulum = self.pendulum
        pendulum.orientation.enabled = False
        pendulum.angular_velocity.enabled = False
        pendulum.joint_positions.enabled = True
        pendulum.joint_velocities.enabled = True
        if schedule:
            pendulum.joint_positions.configure(
                update_interval=3, buffer_size=3, delay=2, aggregator="mean"
            )
            pendulum.joint_velocities.configure(
                update_interval=2, buffer_size=2, corruptor=observation.GaussianNoise(0.1)
            )
        hinge = pendulum.hinge
        self._tip_height = BatchGeneric(
            lambda physics: physics.bind(pendulum.tip).xpos[:, 2:], enabled=True
        )
        self._angle_cos = BatchGeneric(
            lambda physics: np.cos(physics.bind(hinge).qpos), bounds=(-1, 1), enabled=True
        )

    @property
    def task_observables(self) -> dict[str, observation.Observable]:
        return {"tip_height": self._tip_height, "angle_cos": self._angle_cos}

    def get_reward_batch(self, physics: BatchPhysics) -> np.ndarray:
        return -np.abs(physics.bind(self.pendulum.hinge).qpos[:, 0])

    def should_terminate_episode_batch(self, physics: BatchPhysics) -> np.ndarray:
        return np.abs(physics.bind(self.pendulum.hinge).qpos[:, 0]) > self._terminate_above

    def get_info_batch(self, physics: BatchPhysics) -> dict[str, np.ndarray]:
        return {"low": physics.bind(self.pendulum.hinge).qpos[:, 0] < 0}


class Tower(composer.Entity):
    """Boxes stacked in the air, with too little arena memory for the pile they make:
    MuJoCo raises (mj_stackAlloc) a few hundred physics steps after a reset."""

    def _build(self) -> None:
        root = self._mjcf_root = mjcf.RootElement(model="tower")
        root.size.memory = "40K"
        root.worldbody.add("geom", type="plane", size=[5, 5, 0.1])
        for i in range(12):
            body = root.worldbody.add("body", pos=[0, 0, 0.3 + 0.25 * i])
            body.add("freejoint")
            body.add("geom", type="box", size=[0.1, 0.1, 0.1])


class TowerTask(composer.NullTask):
    """The falling tower, ten physics steps per control step."""

    def __init__(self) -> None:
        super().__init__(Tower())
        self.set_timesteps(control_timestep=0.02, physics_timestep=0.002)


class HookedPendulum(Pendulum):
    """A pendulum whose hooks act on the simulation: per-environment work every step."""

    def before_step(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Push along with the motor's control, plus noise."""
        push = 0.5 * physics.bind(self.motor).ctrl + random_state.normal(0.0, 0.01)
        physics.bind(self.hinge).qfrc_applied = push

    def after_substep(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Damp a little more after every physics step."""
        physics.bind(self.hinge).qvel = 0.99 * physics.bind(self.hinge).qvel


class HookedSwing(composer.Task):
    """The pendulum with entity hooks; the reward reads what its before_step wrote."""

    def __init__(self) -> None:
        self._arena = Floor(size=(2, 2))
        self.pendulum = HookedPendulum()
        self._arena.attach(self.pendulum)
        self.pendulum.joint_positions.enabled = True
        self.set_timesteps(control_timestep=0.02, physics_timestep=0.005)

    @property
    def root_entity(self) -> composer.Entity:
        return self._arena

    def initialize_episode(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        physics.bind(self.pendulum.hinge).qpos = random_state.uniform(-1, 1)

    def get_reward(self, physics: mjcf.Physics) -> float:
        return float(physics.bind(self.pendulum.hinge).qfrc_applied[0])

    def get_discount(self, physics: mjcf.Physics) -> float:
        return 0.5 if physics.bind(self.pendulum.hinge).qpos[0] < 0 else 1.0

    def get_info(self, physics: mjcf.Physics) -> dict:
        return {"angle": physics.bind(self.pendulum.hinge).qpos.copy()}


class SensingSwing(BatchedSwing):
    """BatchedSwing observing acceleration-dependent sensors (an accelerometer at the tip,
    the motor's force) and a position sensor, batched, with a reward read from them: values
    MuJoCo computes in the acceleration stage, which a step leaves for the state before it."""

    def __init__(self, **options) -> None:
        super().__init__(**options)
        pendulum = self.pendulum
        sensor = pendulum.mjcf_model.sensor
        self.sensors = [
            sensor.add("accelerometer", name="tip_acc", site=pendulum.tip),
            sensor.add("actuatorfrc", name="motor_force", actuator=pendulum.motor),
            sensor.add("framepos", name="tip_pos", objtype="site", objname=pendulum.tip),
        ]
        self._sensed = observation.MJCFFeature("sensordata", self.sensors, enabled=True)

    @property
    def task_observables(self) -> dict[str, observation.Observable]:
        return {**super().task_observables, "sensed": self._sensed}

    def get_reward_batch(self, physics: BatchPhysics) -> np.ndarray:
        return physics.bind(self.sensors[0]).sensordata[:, 2]


class SingleFormSwing(BatchedSwing):
    """BatchedSwing written as before batched forms existed: its per-step methods in single
    form (SwingTask's formulas, taking precedence over the inherited batched forms) and its
    function observables as `Generic`s of one environment. The oracle its batched forms
    are checked against."""

    def __init__(self, **options) -> None:
        super().__init__(**options)
        pendulum = self.pendulum
        self._tip_height = observation.Generic(
            lambda physics: physics.bind(pendulum.tip).xpos[2:], enabled=True
        )
        self._angle_cos = observation.Generic(
            lambda physics: np.cos(physics.bind(pendulum.hinge).qpos), bounds=(-1, 1), enabled=True
        )

    get_reward = SwingTask.get_reward
    should_terminate_episode = SwingTask.should_terminate_episode

    def get_info(self, physics: mjcf.Physics) -> dict:
        return {"low": bool(physics.bind(self.pendulum.hinge).qpos[0] < 0)}


class SingleFormSensingSwing(SingleFormSwing, SensingSwing):
    """SensingSwing with its reward in single form, on SingleFormSwing's oracle."""

    def get_reward(self, physics: mjcf.Physics) -> float:
        return float(physics.bind(self.sensors[0]).sensordata[2])


class LateSight(BatchedSwing):
    """BatchedSwing observing the state only, whose info reads the tip's height and the
    hinge's acceleration from its fourth control step on: nothing derived before."""

    def __init__(self, **options) -> None:
        super().__init__(**options)
        self.steps = 0

    @property
    def task_observables(self) -> dict[str, observation.Observable]:
        return {"angle_cos": self._angle_cos}

    def after_step_batch(self, physics: BatchPhysics) -> None:
        self.steps += 1

    def get_info_batch(self, physics: BatchPhysics) -> dict[str, np.ndarray]:
        info = super().get_info_batch(physics)
        if self.steps >= 4:
            info["tip_height"] = physics.bind(self.pendulum.tip).xpos[:, 2]
            info["acceleration"] = physics.bind(self.pendulum.hinge).qacc[:, 0]
        return info


class VariedSwing(BatchedSwing):
    """BatchedSwing whose hinge damping is drawn at each episode's start, in the model
    (written raw, as variations of model fields are): each environment's differs."""

    def initialize_episode(self, physics: mjcf.Physics, random_state: np.random.RandomState):
        hinge = physics.bind(self.pendulum.hinge)
        physics.model.dof_damping[hinge.dofadr] = random_state.uniform(0.05, 2.0)
        super().initialize_episode(physics, random_state)
