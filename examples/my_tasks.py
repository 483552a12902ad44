"""A task of your own, whole: a two-link arm written as MJCF text, attached to an arena, an
observable of the arm and one of the task, a reward, its Gymnasium id, its training recipe
and a camera that frames it. Copy this file and change what you need.

    $ cd examples
    $ composer --import my_tasks list                       # Touch among the shipped tasks
    $ composer --import my_tasks show Touch --out ../runs/touch.png
    $ composer --import my_tasks train Touch                # with the recipe registered below
    $ composer --import my_tasks run Touch --policy ../runs/Touch-ppo --video ../runs/touch.mp4

(or, from the clone's root, `composer --import examples.my_tasks ...`). In Python:

    import gymnasium as gym
    import my_tasks                                         # registers composer/Touch-v0
    env = gym.make("composer/Touch-v0")                     # time_limit=3.0, flattened
    obs, info = env.reset(seed=0)

What each part is for:
- `ARM_XML` and `composer.Entity.from_mjcf_model(mjcf.from_xml_string(ARM_XML))`: an
  entity without a class of its own. Its observables are its joints' positions and
  velocities (enabled); `arm.observables.add_observable` adds one more, the fingertip.
  Attached to the arena, its names are scoped: `arm/shoulder`, `arm/tip`.
- `arenas.Floor`: the shipped floor, lights and skybox; the task adds its camera `top` there
  and names it in `render_camera`, which `composer show --out`, `composer run --video`,
  training's `video.mp4` and `gym.make(..., render_mode="rgb_array")` draw through.
- `task_observables`: what only the task knows (here, the target relative to the fingertip),
  as `observation.Generic` of a function of the physics, enabled.
- `registration.register` makes the Gymnasium id; `composer.cli.recipes.register` tells
  `composer train Touch` how to train it (without one, the generic PPO recipe).
"""

from __future__ import annotations

import numpy as np

import arenas
import composer
import mjcf
from composer import observation, registration
from composer.cli.recipes import Recipe
from composer.cli.recipes import register as register_recipe

# A planar arm turning about z on a post above the floor: links of 0.15 and 0.12 m, motors
# at both joints (actions in [-1, 1]), and a site at the fingertip.
ARM_XML = """
<mujoco model="arm">
  <default>
    <joint type="hinge" axis="0 0 1" damping="0.02"/>
    <geom type="capsule" size="0.012" rgba="0.95 0.6 0.2 1" contype="0" conaffinity="0"/>
    <motor ctrlrange="-1 1"/>
  </default>
  <worldbody>
    <geom name="post" type="cylinder" fromto="0 0 0 0 0 0.04" size="0.02" rgba="0.3 0.3 0.3 1"/>
    <body name="upper" pos="0 0 0.05">
      <joint name="shoulder"/>
      <geom name="upper" fromto="0 0 0 0.15 0 0"/>
      <body name="lower" pos="0.15 0 0">
        <joint name="elbow" range="-2.6 2.6"/>
        <geom name="lower" fromto="0 0 0 0.12 0 0" rgba="0.9 0.45 0.15 1"/>
        <site name="tip" pos="0.12 0 0" size="0.01"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor name="shoulder" joint="shoulder" gear="0.05"/>
    <motor name="elbow" joint="elbow" gear="0.03"/>
  </actuator>
</mujoco>
"""
REACH = 0.27  # the arm's reach (m): both links
SUCCESS_DISTANCE = 0.02  # m


class Touch(composer.Task):
    """Bring the arm's fingertip to a target drawn each episode within its reach.

    Reward per step, in (0, 1]: `exp(-d / 0.1)` with d the fingertip-target distance (m);
    `info["is_success"]` when d < 2 cm. Observations: `arm/joint_positions`,
    `arm/joint_velocities`, `arm/tip` (x, y, z) and `to_target` (target minus fingertip,
    x, y). Episodes last the id's `time_limit` and never terminate.
    """

    def __init__(self, control_timestep: float = 0.04) -> None:
        """Build the scene; raises composer.TaskError if `control_timestep` is not a whole
        number of physics steps (0.005 s)."""
        self._arena = arenas.Floor(size=(1.0, 1.0))
        self.arm = composer.Entity.from_mjcf_model(mjcf.from_xml_string(ARM_XML))
        self._arena.attach(self.arm)
        self.tip = self.arm.mjcf_model.find("site", "tip")
        self.arm.observables.add_observable("tip", observation.MJCFFeature("xpos", self.tip))
        self.arm.observables.get_observable("tip").enabled = True

        world = self._arena.mjcf_model.worldbody
        # A mocap body: moved each episode without a recompile, and never pushed around.
        self.target = world.add("body", name="target", mocap=True, pos=[0.15, 0.1, 0.05])
        self.target.add("geom", type="sphere", size=[0.015], rgba=[0.9, 0.2, 0.2, 0.8],
                        contype=0, conaffinity=0)  # fmt: skip
        # Looking down at the arm's disc from the front; xyaxes: the camera's x and y axes.
        world.add("camera", name="top", pos=[0, -0.4, 0.55], xyaxes=[1, 0, 0, 0, 0.81, 0.59])
        self.render_camera = "top"

        self._to_target = observation.Generic(self._target_minus_tip)
        self._to_target.enabled = True
        self.set_timesteps(control_timestep=control_timestep, physics_timestep=0.005)

    @property
    def root_entity(self) -> composer.Entity:
        """The arena, with the arm attached."""
        return self._arena

    @property
    def task_observables(self) -> dict[str, observation.Observable]:
        """`to_target`: the target minus the fingertip in the plane, (2,)."""
        return {"to_target": self._to_target}

    def _target_minus_tip(self, physics: mjcf.Physics) -> np.ndarray:
        target = physics.bind(self.target).mocap_pos[:2]
        return np.asarray(target - physics.bind(self.tip).xpos[:2])

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """Random joint angles, and the target uniform over the reachable disc (by area,
        at least 5 cm from the post)."""
        physics.bind(self.arm.mjcf_model.find_all("joint")).qpos = [
            random_state.uniform(-np.pi, np.pi),
            random_state.uniform(-2.0, 2.0),
        ]
        radius = np.sqrt(random_state.uniform((0.05 / REACH) ** 2, 0.9**2)) * REACH
        angle = random_state.uniform(-np.pi, np.pi)
        physics.bind(self.target).mocap_pos[:2] = radius * np.cos(angle), radius * np.sin(angle)

    def get_reward(self, physics: mjcf.Physics) -> float:
        """`exp(-d / 0.1)`, d the fingertip-target distance (m)."""
        return float(np.exp(-np.linalg.norm(self._target_minus_tip(physics)) / 0.1))

    def get_info(self, physics: mjcf.Physics) -> dict[str, bool]:
        """`is_success`: the fingertip within 2 cm of the target."""
        distance = np.linalg.norm(self._target_minus_tip(physics))
        return {"is_success": bool(distance < SUCCESS_DISTANCE)}


# The id `composer/Touch-v0`. The task is named by import path, so that the spec pickles
# into vector environments' worker processes; __name__ is this module's name however it was
# imported (`my_tasks` or `examples.my_tasks`).
registration.register(
    "Touch", f"{__name__}:Touch", "Bring a two-link arm's fingertip to a random target",
    time_limit=3.0,
)  # fmt: skip
# What `composer --import my_tasks train Touch` trains with: PPO on 8 environments.
register_recipe(Touch, Recipe("ppo", 300_000, 8, (64, 64), 3e-4, 256, gamma=0.95, normalize=True))
