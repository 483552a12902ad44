"""Acrobot: swing a two-link pendulum, actuated at the elbow only, up to balance its tip
on a target (dm_control's `acrobot`).

    env = gym.make('dm_control/acrobot-swingup-v0')
    env = gym.make('dm_control/acrobot-swingup_sparse-v0')

Observations: `orientations` (each link's sin, then each link's cos of its angle from
upright), `velocity` (both joints'). Reward in [0, 1]: 1 while the tip is within the
target's 0.2 m radius; outside it, dense, a gaussian of the distance (0.1 at 1 m beyond),
sparse, 0. 1,000 steps of 10 ms; starts and details in docs/suite.md.
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import SuiteArena
from entities.suite import Acrobot
from tasks.rewards import Tolerance, squared_norms
from tasks.suite import registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 10.0


class Balance(SuiteTask):
    """Swing up the acrobot and hold its tip on the target (module docstring)."""

    def __init__(self, sparse: bool = False, control_timestep: float | None = None) -> None:
        """Build the scene, rewarded sparsely with `sparse`. Raises composer.TaskError for
        a control timestep that is not a multiple of 10 ms."""
        self.acrobot = Acrobot()
        self._arena = SuiteArena(floor_size=(3.0, 3.0, 0.2))
        self._arena.add_light(name="light", pos=[0, 0, 6])
        self._arena.attach(self.acrobot)
        self._sparse = bool(sparse)
        self.render_camera = f"{self.acrobot.name}/fixed"
        self.use_control_timestep(control_timestep, default=None)
        # Both links' xz entries of their xmat (sines), then their zz entries (cosines):
        # (n, 4), as (2, links) entries flattened.
        links = np.arange(len(self.acrobot.arms))
        entries = (np.stack([links, links]), np.array([[2], [8]]).repeat(len(links), axis=1))
        self.set_observables(
            {
                "orientations": BoundField("xmat", self.acrobot.arms, index=entries, flat=True),
                "velocity": BoundField("qvel", self._arena.mjcf_model.find_all("joint")),
            }
        )

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Fix the reward's shape: 1 within the target's radius as compiled (0.2 m)."""
        radius = float(physics.bind(self.acrobot.target).size[0])
        self._on_target = Tolerance(bounds=(0.0, radius), margin=0.0 if self._sparse else 1.0)

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draw: shoulder and elbow at U(-pi, pi), in that order."""
        physics.bind(self.acrobot.joints).qpos = random_state.uniform(-np.pi, np.pi, 2)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        tip_to_target = physics.bind(self.acrobot.target).xpos - physics.bind(self.acrobot.tip).xpos
        return self._on_target(np.sqrt(squared_norms(tip_to_target)))


for _name, _sparse, _description in (
    ("swingup", False, "Swing up an acrobot and hold its tip on a target"),
    ("swingup_sparse", True,
     "Swing up an acrobot and hold its tip on a target; reward 1 while on it"),
):  # fmt: skip
    registry.add(
        registry.SuiteEntry(
            "acrobot", _name, Balance, {"sparse": _sparse}, TIME_LIMIT, _description,
            ("benchmarking",),
        )
    )  # fmt: skip
