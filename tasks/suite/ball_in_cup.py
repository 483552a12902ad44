"""Ball in cup: swing a ball on a string up into a cup (dm_control's `ball_in_cup`).

    env = gym.make('dm_control/ball_in_cup-catch-v0')

Observations: `position` and `velocity` (the cup's x and z, then the ball's, and their
rates). Reward: 1 while the ball is wholly inside the cup (its centre within the cup's
inner box, shrunk by the ball's radius, in x and z), else 0. Each episode starts with the
ball at x uniform in [-0.2, 0.2) and z in [0.2, 0.5) m, drawn again while it touches
anything; 1,000 steps of 20 ms (ten physics steps each).
"""

from __future__ import annotations

import numpy as np

import composer
import entities.suite
import mjcf
from arenas.suite import SuiteArena
from tasks.suite import registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 20.0
CONTROL_TIMESTEP = 0.02
_MAX_ATTEMPTS = 1000  # initial ball positions tried before giving up on one without contacts
_XZ = np.array([0, 2])


class BallInCup(SuiteTask):
    """Catch the ball in the cup (module docstring)."""

    def __init__(self, control_timestep: float | None = None) -> None:
        """Build the scene. Raises composer.TaskError for a control timestep that is not a
        multiple of 2 ms."""
        self.ball_in_cup = entities.suite.BallInCup()
        self._arena = SuiteArena(floor_size=(0.6, 0.2, 10.0), floor_name="ground")
        self._arena.add_light(
            name="light", directional=True, diffuse=[0.6] * 3, pos=[0, 0, 2],
            specular=[0.3] * 3,
        )  # fmt: skip
        self._arena.attach(self.ball_in_cup)
        self.render_camera = f"{self.ball_in_cup.name}/cam0"
        self.use_control_timestep(control_timestep, default=CONTROL_TIMESTEP)
        joints = self._arena.mjcf_model.find_all("joint")  # in model order: qpos, qvel
        self.set_observables(
            {"position": BoundField("qpos", joints), "velocity": BoundField("qvel", joints)}
        )

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Fix how far from the target's centre the ball's may be, in x and z: the
        target's half sizes less the ball's radius, as compiled."""
        half_sizes = physics.bind(self.ball_in_cup.target).size[_XZ]
        self._inside = half_sizes - physics.bind(self.ball_in_cup.ball).size[0]

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: the ball's x U(-0.2, 0.2) and z U(0.2, 0.5), drawn again
        while it touches anything. Raises composer.EpisodeInitializationError after
        1,000 attempts."""
        ball_x, ball_z = (physics.bind(joint) for joint in self.ball_in_cup.ball_joints)
        for _ in range(_MAX_ATTEMPTS):
            ball_x.qpos = random_state.uniform(-0.2, 0.2)
            ball_z.qpos = random_state.uniform(0.2, 0.5)
            physics.after_reset()  # finds the contacts
            if physics.data.ncon == 0:
                return
        raise composer.EpisodeInitializationError(
            f"no initial ball position without contacts in {_MAX_ATTEMPTS} attempts"
        )

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """1 where the ball is inside the cup, else 0; shape (n,)."""
        target = physics.bind(self.ball_in_cup.target).xpos.take(_XZ, axis=1)
        ball = physics.bind(self.ball_in_cup.ball_body).xpos.take(_XZ, axis=1)
        # np.all's reduction, without its Python wrapper (a microsecond every step).
        inside = np.logical_and.reduce(np.abs(target - ball) < self._inside, axis=1)
        return inside.astype(np.float64)


registry.add(
    registry.SuiteEntry(
        "ball_in_cup", "catch", BallInCup, {}, TIME_LIMIT,
        "Swing a ball on a string up into a cup", ("benchmarking", "easy"),
    )
)  # fmt: skip
