"""LQR: bring a randomly drawn linear spring system to rest (dm_control's `lqr`).

    env = gym.make('dm_control/lqr-lqr_2_1-v0')     # 2 bodies, the first actuated
    env = gym.make('dm_control/lqr-lqr_6_2-v0')     # 6 bodies, the first 2 actuated
    obs, info = env.reset(seed=3)                   # the system dm_control draws with random=3

Observations: `position` and `velocity` (every joint's). Reward:
`1 - (|qpos|^2 / 2 + 0.1 * |ctrl|^2 / 2)`. No time limit: an episode terminates (discount
0) once the state is within 1e-6 of rest. A reset with a seed (and the first) draws the
springs too, so `reset(seed=s)` is dm_control's `random=s` (docs/suite.md: what differs).
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import SuiteArena
from entities.suite import LQR
from tasks.rewards import squared_norms
from tasks.suite import registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = float("inf")
CONTROL_COST_COEF = 0.1
TERMINAL_TOLERANCE = 1e-6  # the state norm below which the system is at rest


# The reward's numbers as 0-d float64 arrays: the same values, and numpy's calls on arrays of
# one row take half the time with them than with Python numbers.
_HALF, _ONE = np.array(0.5), np.array(1.0)


class LQRLevel(SuiteTask):
    """Regulate an LQR system to rest (module docstring)."""

    def __init__(
        self,
        n_bodies: int = 2,
        n_actuators: int = 1,
        control_cost_coef: float = CONTROL_COST_COEF,
        control_timestep: float | None = None,
    ) -> None:
        """Build the scene: `n_bodies` spheres, the first `n_actuators` actuated, the
        controls' cost weighted by `control_cost_coef`. Raises composer.TaskError for a
        control cost that is not positive (as dm_control raises ValueError) or a control
        timestep that is not a multiple of 30 ms, composer.EntityError for bad counts."""
        if not control_cost_coef > 0:
            raise composer.TaskError(
                f"control_cost_coef must be positive, got {control_cost_coef!r}"
            )
        self._control_cost_coef = float(control_cost_coef)
        self.lqr = LQR(n_bodies=n_bodies, n_actuators=n_actuators)
        self._arena = SuiteArena(floor_size=(4, 1, 0.2))
        self._arena.add_light(name="light", pos=[0, 0, 2])
        world = self._arena.mjcf_model.worldbody
        world.add(
            "camera", name="cam0", pos=[-1.428, -0.311, 0.856],
            xyaxes=[0.099, -0.995, 0, 0.35, 0.035, 0.936],
        )  # fmt: skip
        world.add(
            "camera", name="cam1", pos=[1.787, 2.452, 4.331], xyaxes=[-1, 0, 0, 0, -0.868, 0.497]
        )
        self._arena.attach(self.lqr)
        self._draw_system = True  # at the first reset, seeded or not
        self.use_control_timestep(control_timestep, default=None)
        joints = self._arena.mjcf_model.find_all("joint")  # in model order: qpos, qvel
        self.set_observables(
            {"position": BoundField("qpos", joints), "velocity": BoundField("qvel", joints)}
        )

    @property
    def control_cost_coef(self) -> float:
        """The weight of the controls' cost (dm_control's name)."""
        return self._control_cost_coef

    def random_state_for_seed(self, seed: int) -> np.random.RandomState:
        """dm_control's `random=seed`; the next reset draws a new system from it."""
        self._draw_system = True
        return super().random_state_for_seed(seed)

    def initialize_episode_mjcf(self, random_state: np.random.RandomState) -> None:
        """At the first reset and after a seed, draw the system (`LQR.draw_system`)."""
        if self._draw_system:
            self.lqr.draw_system(random_state)
            self._draw_system = False

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draw: positions `sqrt(2) * u / |u|` for `u = randn(nq)`, at rest."""
        unit = random_state.randn(physics.model.nq)
        physics.data.qpos[:] = np.sqrt(2) * unit / np.linalg.norm(unit)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        state_cost = _HALF * squared_norms(physics.field("qpos"))
        control_cost = _HALF * squared_norms(physics.field("ctrl"))
        return _ONE - (state_cost + control_cost * self._control_cost_coef)

    def should_terminate_episode_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """Whether each system is at rest: its state's norm below TERMINAL_TOLERANCE, (n,)."""
        state = np.concatenate(
            (physics.field("qpos"), physics.field("qvel"), physics.field("act")), axis=1
        )
        return np.sqrt(squared_norms(state)) < TERMINAL_TOLERANCE

    def get_discount_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """0 where the system came to rest (the episode ends there), else 1: (n,)."""
        return np.where(self.should_terminate_episode_batch(physics), 0.0, 1.0)

    def get_termination(self, physics: mjcf.Physics) -> float | None:
        """dm_control's hook: 0.0 once the system is at rest, else None."""
        return 0.0 if self.should_terminate_episode(physics) else None


for _name, _bodies, _actuators in (("lqr_2_1", 2, 1), ("lqr_6_2", 6, 2)):
    registry.add(
        registry.SuiteEntry(
            "lqr", _name, LQRLevel, {"n_bodies": _bodies, "n_actuators": _actuators},
            TIME_LIMIT,
            f"Bring a random spring system of {_bodies} bodies ({_actuators} actuated) to rest",
        )
    )  # fmt: skip
