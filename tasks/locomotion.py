"""AntRun and WalkerRun: run forward (+x) along a corridor without falling.

    env = gym.make('composer/AntRun-v0', flatten_observations=True)
    env = gym.make('composer/AntRun-v0', arena='terrain', terrain_seed=3)    # rough ground
    env = gym.make('composer/WalkerRun-v0', gaps=[(4.0, 0.4)], walls=False)

Each observes its robot's joints and torso (AntRun 28 numbers, WalkerRun 18: the classes
list them) and acts with torques in [-1, 1]. Episodes end when the robot falls, or at
`time_limit` (20 s); `info['forward_velocity']` is the torso's velocity along +x (m/s).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

import composer
import mjcf
from arenas import Corridor, RoughTerrain
from composer import BatchPhysics
from entities import Quadruped, Walker
from tasks.rewards import squared_norms

ARENAS = ("corridor", "terrain")


class _Run(composer.Task):
    """Shared by the running tasks: reward, randomized start, camera, timesteps."""

    robot: composer.Entity

    def _setup(
        self,
        arena: composer.Arena,
        robot: composer.Entity,
        control_timestep: float,
        physics_timestep: float,
        randomize: bool,
        control_cost: float,
        alive_bonus: float,
    ) -> None:
        self.arena = arena
        self.robot = robot
        arena.attach(robot)
        for observable in robot.observables.values():
            observable.enabled = True
        self.randomize = randomize
        self.control_cost = float(control_cost)
        self.alive_bonus = float(alive_bonus)
        self.render_camera = f"{robot.name}/track"
        self.set_timesteps(control_timestep, physics_timestep)

    @property
    def root_entity(self) -> composer.Entity:
        """The arena with the robot."""
        return self.arena

    def forward_velocity(self, physics: BatchPhysics) -> np.ndarray:
        """The torso's velocity along +x (m/s) of each environment, (n,)."""
        raise NotImplementedError

    def get_reward_batch(self, physics: BatchPhysics) -> np.ndarray:
        """`forward velocity - control_cost * sum(u^2) + alive_bonus` of each environment,
        (n,) (see the task)."""
        cost = self.control_cost * squared_norms(physics.field("ctrl"))
        return self.forward_velocity(physics) - cost + self.alive_bonus

    def get_info_batch(self, physics: BatchPhysics) -> dict[str, np.ndarray]:
        """'forward_velocity': `forward_velocity` (m/s), (n,); `composer eval` averages it
        over an episode into the forward speed it reports."""
        return {"forward_velocity": self.forward_velocity(physics)}

    def _perturb(
        self,
        physics: mjcf.Physics,
        joints: Sequence[mjcf.Element],
        random_state: np.random.RandomState,
    ) -> None:
        """With `randomize`: joint angles and velocities plus U(-0.1, 0.1) noise."""
        if not self.randomize:
            return
        binding = physics.bind(list(joints))
        binding.qpos = binding.qpos + random_state.uniform(-0.1, 0.1, len(joints))
        binding.qvel = random_state.uniform(-0.1, 0.1, len(joints))


class AntRun(_Run):
    """Run an ant-like quadruped forward.

    Observations: `quadruped/joint_positions` (8), `joint_velocities` (8), `torso_height`
    (1), `torso_orientation` (4), `torso_upright` (1) and `torso_velocity` (6): 28 numbers.
    Action: 8 torques in [-1, 1].

    Reward per step: `v_x - control_cost * sum(u^2) + alive_bonus`, with v_x the torso's
    forward velocity in m/s (defaults: control_cost 0.05, alive_bonus 0.5). Terminates
    when the torso turns over (its z axis points down) or drops below `min_height` m (into
    a gap).
    """

    robot: Quadruped

    def __init__(
        self,
        control_timestep: float = 0.05,
        physics_timestep: float = 0.01,
        randomize: bool = True,
        arena: str = "corridor",
        walls: bool = True,
        gaps: Sequence[tuple[float, float]] = (),
        terrain_seed: int = 0,
        terrain_height: float = 0.15,
        control_cost: float = 0.05,
        alive_bonus: float = 0.5,
        min_height: float = 0.1,
    ) -> None:
        """Build the scene on `arena` 'corridor' (with `walls`, `gaps`) or 'terrain'
        (rough ground from `terrain_seed`, up to `terrain_height` m). Raises
        composer.TaskError for an unknown arena or timesteps that do not divide."""
        if arena not in ARENAS:
            raise composer.TaskError(f"AntRun: arena must be one of {ARENAS}, got {arena!r}")
        if arena == "corridor":
            ground: composer.Arena = Corridor(walls=walls, gaps=gaps, width=4.0)
        else:
            ground = RoughTerrain(seed=terrain_seed, max_height=terrain_height)
        self.min_height = float(min_height)
        self._setup(ground, Quadruped(), control_timestep, physics_timestep, randomize,
                    control_cost, alive_bonus)  # fmt: skip

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """Torso at its start pose facing +x, leg joints perturbed (see `randomize`)."""
        self._perturb(physics, self.robot.joints, random_state)

    def forward_velocity(self, physics: BatchPhysics) -> np.ndarray:
        """The torso's world x velocity (m/s) of each environment, (n,)."""
        return physics.bind(self.robot.root_joint).qvel[:, 0]

    def should_terminate_episode_batch(self, physics: BatchPhysics) -> np.ndarray:
        """Turned over, or fallen below `min_height`: (n,) bool."""
        torso = physics.bind(self.robot.torso)
        return (torso.xmat[:, 8] < _ZERO) | (torso.xpos[:, 2] < self.min_height)


class WalkerRun(_Run):
    """Run a planar biped forward.

    Observations: `walker/joint_positions` (6), `joint_velocities` (9), `torso_height` (1),
    `torso_pitch` (2): 18 numbers. Action: 6 torques in [-1, 1].

    Reward per step: `v_x - control_cost * sum(u^2) + alive_bonus`, with v_x the torso's
    forward velocity in m/s (defaults: control_cost 0.001, alive_bonus 1.0). Terminates
    when the torso drops below `min_height` m or pitches more than 1 rad.
    """

    robot: Walker

    def __init__(
        self,
        control_timestep: float = 0.025,
        physics_timestep: float = 0.005,
        randomize: bool = True,
        walls: bool = False,
        gaps: Sequence[tuple[float, float]] = (),
        control_cost: float = 0.001,
        alive_bonus: float = 1.0,
        min_height: float = 0.7,
    ) -> None:
        """Build the scene on a corridor (with `walls`, `gaps`). Raises
        composer.TaskError for timesteps that do not divide."""
        self.min_height = float(min_height)
        self._setup(Corridor(walls=walls, gaps=gaps, width=1.0), Walker(), control_timestep,
                    physics_timestep, randomize, control_cost, alive_bonus)  # fmt: skip

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """Standing upright, leg joints perturbed (see `randomize`)."""
        self._perturb(physics, self.robot.leg_joints, random_state)

    def forward_velocity(self, physics: BatchPhysics) -> np.ndarray:
        """The torso's x velocity (m/s) of each environment, (n,)."""
        return physics.bind(self.robot.root_x).qvel[:, 0]

    def should_terminate_episode_batch(self, physics: BatchPhysics) -> np.ndarray:
        """Fallen: torso below `min_height` m or pitched more than 1 rad; (n,) bool."""
        height = physics.bind(self.robot.torso).xpos[:, 2]
        pitch = physics.bind(self.robot.root_y).qpos[:, 0]
        return (height < self.min_height) | (np.abs(pitch) > _ONE)


# Numbers of the per-step formulas as 0-d arrays: numpy's arithmetic on small arrays takes
# a third less time with these than with Python numbers, to the same result (the tasks'
# options stay Python floats: making a numpy number of one costs what it would save).
_ZERO, _ONE = np.array(0.0), np.array(1.0)
