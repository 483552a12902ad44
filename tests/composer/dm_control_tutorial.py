"""dm_control's Composer tutorial program (a legged creature that must press a button with a
force in a given range), written out from the tutorial's public description in dm_control's
style, with only its imports changed to ours: `from dm_control import composer, mjcf`
became `import composer, mjcf`, `dm_control.composer.*` became `composer.*`. dm_control's
own locomotion floor (`floors.Floor`, from the fetched wheel) is its arena.

    task = press_with_specific_force(floors)          # floors: dm_control's module
    env = composer.Environment(task, random_state=np.random.RandomState(42))
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from composer import variation
from composer.observation import observable
from composer.variation import distributions, noises

NUM_SUBSTEPS = 25  # physics steps per control step
BODY_RADIUS = 0.1
BODY_HEIGHT = 0.05


class Leg:
    """A two-link leg: a hip turning about z, a knee about y, each position-actuated."""

    def __init__(self, length, rgba):
        self.model = mjcf.RootElement()
        self.model.default.joint.damping = 2
        self.model.default.joint.type = "hinge"
        self.model.default.geom.type = "capsule"
        self.model.default.geom.rgba = rgba
        thigh = self.model.worldbody.add("body")
        self.hip = thigh.add("joint", axis=[0, 0, 1])
        thigh.add("geom", fromto=[0, 0, 0, length, 0, 0], size=[length / 4])
        shin = thigh.add("body", pos=[length, 0, 0])
        self.knee = shin.add("joint", axis=[0, 1, 0])
        shin.add("geom", fromto=[0, 0, 0, 0, 0, -length], size=[length / 5])
        self.model.actuator.add("position", joint=self.hip, kp=10)
        self.model.actuator.add("position", joint=self.knee, kp=10)


def make_creature(num_legs, rgba):
    """An ellipsoid torso with `num_legs` legs attached at sites around its rim."""
    model = mjcf.RootElement()
    model.compiler.angle = "radian"
    model.worldbody.add(
        "geom", name="torso", type="ellipsoid",
        size=[BODY_RADIUS, BODY_RADIUS, BODY_HEIGHT], rgba=rgba,
    )  # fmt: skip
    for i in range(num_legs):
        theta = 2 * i * np.pi / num_legs
        hip_position = BODY_RADIUS * np.array([np.cos(theta), np.sin(theta), 0])
        hip_site = model.worldbody.add("site", pos=hip_position, euler=[0, 0, theta])
        hip_site.attach(Leg(length=BODY_RADIUS, rgba=rgba).model)
    return model


class Creature(composer.Entity):
    """The legged creature, with its joints' positions and velocities as observables."""

    def _build(self, num_legs, rgba=(0.5, 0.5, 0.8, 1)):
        self._model = make_creature(num_legs, rgba)

    def _build_observables(self):
        return CreatureObservables(self)

    @property
    def mjcf_model(self):
        return self._model

    @property
    def actuators(self):
        return tuple(self._model.find_all("actuator"))


class CreatureObservables(composer.Observables):
    @composer.observable
    def joint_positions(self):
        return observable.MJCFFeature("qpos", self._entity.mjcf_model.find_all("joint"))

    @composer.observable
    def joint_velocities(self):
        return observable.MJCFFeature("qvel", self._entity.mjcf_model.find_all("joint"))


class Button(composer.Entity):
    """A flat cylinder with a touch sensor: activated (green) while the force pressing it is
    within the target range."""

    def _build(self, target_force_range=(5, 10)):
        self._min_force, self._max_force = target_force_range
        self._mjcf_model = mjcf.RootElement()
        self._geom = self._mjcf_model.worldbody.add(
            "geom", type="cylinder", size=[0.25, 0.02], rgba=[1, 0, 0, 1]
        )
        self._site = self._mjcf_model.worldbody.add(
            "site", type="cylinder", size=self._geom.size * 1.01, rgba=[1, 0, 0, 0]
        )
        self._sensor = self._mjcf_model.sensor.add("touch", site=self._site)
        self._num_activated_steps = 0

    def _build_observables(self):
        return ButtonObservables(self)

    @property
    def mjcf_model(self):
        return self._mjcf_model

    def _update_activation(self, physics):
        force = physics.bind(self.touch_sensor).sensordata[0]
        self._is_activated = self._min_force <= force <= self._max_force
        physics.bind(self._geom).rgba = [0, 1, 0, 1] if self._is_activated else [1, 0, 0, 1]
        self._num_activated_steps += int(self._is_activated)

    def initialize_episode(self, physics, random_state):
        self._num_activated_steps = 0
        self._update_activation(physics)

    def after_substep(self, physics, random_state):
        self._update_activation(physics)

    @property
    def touch_sensor(self):
        return self._sensor

    @property
    def num_activated_steps(self):
        return self._num_activated_steps


class ButtonObservables(composer.Observables):
    @composer.observable
    def touch_force(self):
        return observable.MJCFFeature("sensordata", self._entity.touch_sensor)


class UniformCircle(variation.Variation):
    """A point at a random heading, `distance` from the origin, on the ground."""

    def __init__(self, distance):
        self._distance = distance
        self._heading = distributions.Uniform(0, 2 * np.pi)

    def __call__(self, initial_value=None, current_value=None, random_state=None):
        distance, heading = variation.evaluate(
            (self._distance, self._heading), random_state=random_state
        )
        return distance * np.cos(heading), distance * np.sin(heading), 0


class PressWithSpecificForce(composer.Task):
    """Reward: the fraction of the control step's physics steps the button was pressed
    with a force in its range."""

    def __init__(self, creature, arena):
        self._creature = creature
        self._arena = arena
        self._arena.add_free_entity(self._creature)
        self._arena.mjcf_model.worldbody.add("light", pos=(0, 0, 4))
        self._button = Button()
        self._arena.attach(self._button)
        self._creature_initial_pose = (0, 0, 0.15)
        self._button_initial_pose = UniformCircle(distributions.Uniform(0.5, 0.75))
        self._mjcf_variator = variation.MJCFVariator()
        self._physics_variator = variation.PhysicsVariator()
        self._creature.observables.joint_positions.corruptor = noises.Additive(
            distributions.Normal(scale=0.01)
        )
        self._creature.observables.joint_positions.enabled = True
        self._creature.observables.joint_velocities.corruptor = noises.Multiplicative(
            distributions.LogNormal(sigma=0.01)
        )
        self._creature.observables.joint_velocities.enabled = True
        self._button.observables.touch_force.enabled = True

        def to_button(physics):
            button_position, _ = self._button.get_pose(physics)
            return self._creature.global_vector_to_local_frame(physics, button_position)

        self._task_observables = {"button_position": observable.Generic(to_button)}
        for item in self._task_observables.values():
            item.enabled = True
        self.control_timestep = NUM_SUBSTEPS * self.physics_timestep

    @property
    def root_entity(self):
        return self._arena

    @property
    def task_observables(self):
        return self._task_observables

    @property
    def button(self):
        return self._button

    def initialize_episode_mjcf(self, random_state):
        self._mjcf_variator.apply_variations(random_state)

    def initialize_episode(self, physics, random_state):
        self._physics_variator.apply_variations(physics, random_state)
        creature_pose, button_pose = variation.evaluate(
            (self._creature_initial_pose, self._button_initial_pose), random_state=random_state
        )
        self._creature.set_pose(physics, position=creature_pose)
        self._button.set_pose(physics, position=button_pose)

    def get_reward(self, physics):
        return self._button.num_activated_steps / NUM_SUBSTEPS


def press_with_specific_force(floors) -> PressWithSpecificForce:
    """The tutorial's task: a four-legged creature on dm_control's floor (`floors`, the
    module `dm_control.locomotion.arenas.floors`)."""
    return PressWithSpecificForce(Creature(num_legs=4), floors.Floor())
