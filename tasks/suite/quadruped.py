"""Quadruped: walk, run, escape a bumpy bowl and fetch a ball (dm_control's `quadruped`).

    env = gym.make('dm_control/quadruped-walk-v0')
    env = gym.make('dm_control/quadruped-escape-v0', flatten_observations=True)

Observations: `egocentric_state`, `torso_velocity`, `torso_upright`, `imu`, `force_torque`;
escape adds `origin` and `rangefinder`, fetch `ball_state` and `target_position`. Rewards
in [0, 1], each times `upright`: walk and run, the forward velocity reaching 0.5 or 5 m/s;
escape, the distance from the origin reaching the terrain's radius; fetch, reaching the
ball times bringing it onto the target. 1,000 steps of 20 ms (details in docs/suite.md).
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import QuadrupedArena
from composer import observation
from entities.suite import Quadruped
from tasks.rewards import Tolerance, row_norms
from tasks.suite import registry
from tasks.suite.base import SuiteTask
from tasks.suite.frames import in_frame
from tasks.suite.observables import BoundField, Concatenated

TIME_LIMIT = 20.0
CONTROL_TIMESTEP = 0.02
WALK_SPEED = 0.5
RUN_SPEED = 5.0
_MAX_HEIGHT_ATTEMPTS = 10000  # 1 cm each: the search for a height without contacts


def upright_reward(deviation_angle: float) -> Tolerance:
    """1 while the torso's z axis is within `deviation_angle` degrees of the world's,
    falling linearly to 0 at upside down (a function of the z axis' z)."""
    deviation = np.cos(np.deg2rad(deviation_angle))
    return Tolerance(bounds=(deviation, float("inf")), sigmoid="linear",
                     margin=1 + deviation, value_at_margin=0)  # fmt: skip


class QuadrupedTask(SuiteTask):
    """What the quadruped's tasks share: the scene, the common observations and the start
    without contacts (module docstring)."""

    def __init__(
        self,
        floor_size: float = 15.0,
        terrain: bool = False,
        rangefinders: bool = False,
        walls_and_ball: bool = False,
        control_timestep: float | None = None,
    ) -> None:
        """Build the scene: a floor of half-size `floor_size`, with the heightfield's geom
        if `terrain`, the quadruped with rangefinders if `rangefinders`, and the fetch
        task's walls, target and ball if `walls_and_ball`. Raises composer.TaskError for a
        control timestep that is not a multiple of 5 ms."""
        self._arena: QuadrupedArena = QuadrupedArena(floor_size=floor_size, terrain=terrain)
        self.quadruped = Quadruped(rangefinders=rangefinders, walls_and_ball=walls_and_ball)
        self._arena.attach(self.quadruped)
        self.render_camera = f"{self.quadruped.name}/y"  # camera 2, as pixel papers use
        self.use_control_timestep(control_timestep, default=CONTROL_TIMESTEP)
        quadruped = self.quadruped
        self._observables: dict[str, observation.Observable] = {
            # The hinges' angles and velocities and the actuators' states, (n, 44).
            "egocentric_state": Concatenated(
                [
                    BoundField("qpos", quadruped.hinges),
                    BoundField("qvel", quadruped.hinges),
                    BoundField("act", self._arena.mjcf_model.find_all("actuator")),
                ]
            ),
            "torso_velocity": BoundField("sensordata", quadruped.velocimeter),
            "torso_upright": BoundField("xmat", quadruped.torso, index=8),  # z of its z axis
            "imu": BoundField("sensordata", quadruped.imu),
            "force_torque": BoundField("sensordata", quadruped.force_torque, function=np.arcsinh),
        }

    def _torso_upright(self, physics: composer.BatchPhysics) -> np.ndarray:
        """z of the torso's z axis, (n,)."""
        return physics.bind(self.quadruped.torso).xmat[:, 8]

    def _torso_frame(self, physics: composer.BatchPhysics) -> tuple[np.ndarray, np.ndarray]:
        """The torso's position (n, 3) and orientation matrix (n, 9)."""
        torso = physics.bind(self.quadruped.torso)
        return torso.xpos, torso.xmat

    def _find_non_contacting_height(
        self, physics: mjcf.Physics, orientation: np.ndarray, x: float = 0.0, y: float = 0.0
    ) -> None:
        """dm_control's search: reset with the torso at (x, y) in `orientation`, from the
        floor up in 1 cm steps, until nothing touches. Raises
        composer.EpisodeInitializationError when 100 m up still touches."""
        root = physics.bind(self.quadruped.root)
        z = 0.0
        for _ in range(_MAX_HEIGHT_ATTEMPTS):
            try:
                with physics.reset_context():
                    root.qpos = np.concatenate(((x, y, z), orientation))
            except mjcf.PhysicsError:
                pass  # a full contact buffer: higher up there are fewer contacts
            if physics.data.ncon == 0:
                return
            z += 0.01
        raise composer.EpisodeInitializationError(
            f"no height without contacts for the quadruped at ({x}, {y}) below {z:.2f} m"
        )

    def _random_orientation(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draw: a normalised randn(4) quaternion, at the origin."""
        orientation = random_state.randn(4)
        orientation /= np.linalg.norm(orientation)
        self._find_non_contacting_height(physics, orientation)


class Move(QuadrupedTask):
    """Walk or run forward (module docstring)."""

    def __init__(
        self,
        desired_speed: float = WALK_SPEED,
        floor_size: float | None = None,
        control_timestep: float | None = None,
    ) -> None:
        """Reward forward velocity up to `desired_speed` (m/s, > 0) on a floor of half-size
        `floor_size` (None: as far as the speed goes in the default episode, as
        dm_control's). Raises composer.TaskError for a speed that is not positive."""
        if not desired_speed > 0:
            raise composer.TaskError(f"desired_speed must be > 0, got {desired_speed!r}")
        size = TIME_LIMIT * desired_speed if floor_size is None else floor_size
        super().__init__(floor_size=size, control_timestep=control_timestep)
        self.set_observables(self._observables)
        self._upright = upright_reward(0)
        self._move = Tolerance(bounds=(desired_speed, float("inf")), margin=desired_speed,
                               value_at_margin=0.5, sigmoid="linear")  # fmt: skip

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """A random orientation at the lowest height without contacts."""
        self._random_orientation(physics, random_state)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        forward = physics.bind(self.quadruped.velocimeter).sensordata[:, 0]
        return self._upright(self._torso_upright(physics)) * self._move(forward)


class Escape(QuadrupedTask):
    """Escape a bowl of bumpy terrain (module docstring)."""

    def __init__(self, control_timestep: float | None = None) -> None:
        """The 40 m floor with the terrain, and the rangefinders."""
        super().__init__(floor_size=40.0, terrain=True, rangefinders=True,
                         control_timestep=control_timestep)  # fmt: skip
        self._observables["origin"] = observation.BatchGeneric(self._origin)
        self._observables["rangefinder"] = observation.BatchGeneric(self._rangefinder)
        self.set_observables(self._observables)
        self._upright = upright_reward(20)

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """The terrain's radius (its heightfield's x size) sets the reward's scale."""
        radius = float(physics.bind(self._arena.heightfield).size[0])
        self._escape = Tolerance(bounds=(radius, float("inf")), margin=radius,
                                 value_at_margin=0, sigmoid="linear")  # fmt: skip

    def _origin(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The world's origin in the torso's frame, (n, 3)."""
        position, frame = self._torso_frame(physics)
        return -in_frame(position[:, None, :], frame)[:, 0]

    def _rangefinder(self, physics: composer.BatchPhysics) -> np.ndarray:
        """tanh of each beam's distance, 1 where it hits nothing, (n, 20)."""
        readings = physics.bind(self.quadruped.rangefinders).sensordata
        return np.where(readings == -1.0, 1.0, np.tanh(readings))

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: a new bowl of terrain, then a random orientation."""
        self._arena.shape_bowl(physics, random_state)
        self._random_orientation(physics, random_state)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        workspace = physics.bind(self.quadruped.workspace).xpos
        escape = self._escape(row_norms(workspace))
        return self._upright(self._torso_upright(physics)) * escape


class Fetch(QuadrupedTask):
    """Bring the ball to the target at the centre of a walled arena (module docstring)."""

    def __init__(self, control_timestep: float | None = None) -> None:
        """The 15 m floor with walls, the target and the ball."""
        super().__init__(walls_and_ball=True, control_timestep=control_timestep)
        self._observables["ball_state"] = observation.BatchGeneric(self._ball_state)
        self._observables["target_position"] = observation.BatchGeneric(self._target_position)
        self.set_observables(self._observables)
        self._upright = upright_reward(0)

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """The sizes the reward and the start read: the floor's, the workspace's, the
        ball's and the target's."""
        quadruped = self.quadruped
        floor_size = float(physics.bind(self._arena.floor).size[0])
        self._spawn_radius = 0.9 * floor_size
        arena_radius = floor_size * np.sqrt(2)
        workspace_radius = float(physics.bind(quadruped.workspace).size[0])
        ball_radius = float(physics.bind(quadruped.ball_geom).size[0])
        target_radius = float(physics.bind(quadruped.target).size[0])
        self._reach = Tolerance(bounds=(0, workspace_radius + ball_radius), sigmoid="linear",
                                margin=arena_radius, value_at_margin=0)  # fmt: skip
        self._fetch = Tolerance(bounds=(0, target_radius), sigmoid="linear",
                                margin=arena_radius, value_at_margin=0)  # fmt: skip

    def _ball_state(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The ball's position and velocity relative to the torso and its angular
        velocity, each in the torso's frame, (n, 9)."""
        position, frame = self._torso_frame(physics)
        ball = physics.bind(self.quadruped.ball).xpos
        ball_velocity = physics.bind(self.quadruped.ball_root).qvel  # (n, 6)
        root_velocity = physics.bind(self.quadruped.root).qvel
        rows = np.concatenate(  # (n, 3, 3): np.stack's rows, without its Python wrapper
            (ball - position, ball_velocity[:, :3] - root_velocity[:, :3], ball_velocity[:, 3:]),
            axis=1,
        ).reshape(-1, 3, 3)
        # dm_control multiplies the three rows at once (a matrix product, which rounds as
        # numpy's matmul of each environment's pair does).
        return np.matmul(rows, frame.reshape(-1, 3, 3)).reshape(len(rows), -1)

    def _target_position(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The target relative to the torso, in its frame, (n, 3)."""
        position, frame = self._torso_frame(physics)
        target = physics.bind(self.quadruped.target).xpos
        return in_frame((target - position)[:, None, :], frame)[:, 0]

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: a heading U(0, 2 pi), a place U(-r, r)^2 (r: 0.9 of the
        floor's half-size) at the lowest height without contacts, then the ball at
        U(-r, r)^2, 2 m up, thrown at 5 N(0, 1)^2 m/s."""
        azimuth = random_state.uniform(0, 2 * np.pi)
        orientation = np.array((np.cos(azimuth / 2), 0, 0, np.sin(azimuth / 2)))
        radius = self._spawn_radius
        x, y = random_state.uniform(-radius, radius, size=(2,))
        self._find_non_contacting_height(physics, orientation, x, y)
        ball = physics.bind(self.quadruped.ball_root)
        ball.qpos = np.concatenate((random_state.uniform(-radius, radius, size=(2,)), (2,),
                                    ball.qpos[3:]))  # fmt: skip
        ball.qvel = np.concatenate((5 * random_state.randn(2), ball.qvel[2:]))

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        workspace = physics.bind(self.quadruped.workspace).xpos
        ball = physics.bind(self.quadruped.ball).xpos
        target = physics.bind(self.quadruped.target).xpos
        reach = self._reach(row_norms((workspace - ball)[:, :2]))
        fetch = self._fetch(row_norms((target - ball)[:, :2]))
        return self._upright(self._torso_upright(physics)) * (reach * (0.5 + 0.5 * fetch))


for _name, _class, _kwargs, _description in (
    ("walk", Move, {"desired_speed": WALK_SPEED}, "Walk forward at 0.5 m/s with a quadruped"),
    ("run", Move, {"desired_speed": RUN_SPEED}, "Run forward at 5 m/s with a quadruped"),
    ("escape", Escape, {}, "Climb out of a bowl of random bumpy terrain with a quadruped"),
    ("fetch", Fetch, {}, "Bring a ball to the centre of a walled arena with a quadruped"),
):
    registry.add(registry.SuiteEntry("quadruped", _name, _class, _kwargs, TIME_LIMIT, _description))
