"""Fish: turn upright, or swim to a target, as a fish in a fluid (dm_control's `fish`).

    env = gym.make('dm_control/fish-swim-v0')

Observations: `joint_angles` (the tail's and the fins' seven hinges), `upright`, for
swimming `target` (from the mouth, in its frame), then `velocity` (every joint's). Reward
in [0, 1]: upright, a gaussian of how far the torso's z axis is from straight up;
swimming, `(7 * in_target + is_upright) / 8`. 1,000 steps of 40 ms; the reward's terms
and how episodes start: docs/suite.md.
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import SuiteArena
from composer import observation
from composer.utils.rewards import Tolerance
from entities.suite import Fish
from tasks.rewards import squared_norms
from tasks.suite import registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 40.0
CONTROL_TIMESTEP = 0.04
_JOINT_RANGE = 0.2


class _FishTask(SuiteTask):
    """The fish in its world, its observations and its initial pose (module docstring)."""

    def __init__(self, control_timestep: float | None = None) -> None:
        """Build the scene. Raises composer.TaskError for a control timestep that is not a
        multiple of 4 ms."""
        self.fish = Fish()
        self._arena = SuiteArena(
            floor_name="ground", floor_size=(0.5, 0.5, 0.1), skybox_first=False
        )
        self._arena.attach(self.fish)
        self.use_control_timestep(control_timestep, default=CONTROL_TIMESTEP)
        self.set_observables(
            {
                "joint_angles": BoundField("qpos", self.fish.joints),
                "upright": BoundField("xmat", self.fish.torso, index=8),  # z of its z axis
                **self._more_observables(),
                "velocity": BoundField("qvel", self._arena.mjcf_model.find_all("joint")),
            }
        )

    def _more_observables(self) -> dict[str, observation.Observable]:
        """The task's observables between `upright` and `velocity`."""
        return {}

    def _upright(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The torso's z-z orientation entry: (n,)."""
        return physics.bind(self.fish.torso).xmat[:, 8]

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: the torso's orientation, a normalised `randn(4)`, then each
        hinge uniformly within +-0.2 rad, one draw each in model order."""
        root = physics.bind(self.fish.root_joint)
        pose = root.qpos.copy()
        quaternion = random_state.randn(4)
        pose[3:7] = quaternion / np.linalg.norm(quaternion)
        root.qpos = pose
        for joint in self.fish.joints:
            physics.bind(joint).qpos = random_state.uniform(-_JOINT_RANGE, _JOINT_RANGE)


class Upright(_FishTask):
    """Turn the fish upright (module docstring)."""

    def __init__(self, control_timestep: float | None = None) -> None:
        """Build the scene (see `_FishTask`)."""
        super().__init__(control_timestep)
        self._upright_reward = Tolerance(bounds=(1.0, 1.0), margin=1.0)

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """The fish's pose (`_FishTask`); the target, irrelevant here, made invisible."""
        super().initialize_episode(physics, random_state)
        target = physics.bind(self.fish.target)
        target.rgba = [*target.rgba[:3], 0.0]

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        return self._upright_reward(self._upright(physics))


class Swim(_FishTask):
    """Swim to the target (module docstring)."""

    def __init__(self, control_timestep: float | None = None) -> None:
        """Build the scene (see `_FishTask`)."""
        super().__init__(control_timestep)
        self._in_target: Tolerance | None = None

    def _more_observables(self) -> dict[str, observation.Observable]:
        """`target`: the mouth-to-target vector in the mouth's frame."""
        return {"target": observation.BatchGeneric(self._mouth_to_target)}

    def _mouth_to_target(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The vector from the mouth to the target in the mouth's frame: (n, 3)."""
        positions = physics.bind([self.fish.mouth, self.fish.target]).xpos  # (n, 2, 3)
        mouth_frame = physics.bind(self.fish.mouth).xmat.reshape(-1, 3, 3)
        to_target = positions[:, 1] - positions[:, 0]
        return np.matmul(to_target[:, None, :], mouth_frame)[:, 0]

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """The reward's reach: the mouth's and the target's radii, as compiled (model
        constants: read once, not every step)."""
        radii = float(physics.bind([self.fish.mouth, self.fish.target]).size[:, 0].sum())
        self._in_target = Tolerance(bounds=(0.0, radii), margin=2 * radii)

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """The fish's pose (`_FishTask`), then the target's place: x and y uniformly
        within +-0.4 m, z within 0.1 to 0.3 m, drawn in that order."""
        super().initialize_episode(physics, random_state)
        place = [random_state.uniform(-0.4, 0.4), random_state.uniform(-0.4, 0.4)]
        place.append(random_state.uniform(0.1, 0.3))
        physics.bind(self.fish.target).pos = place

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        assert self._in_target is not None, "after_compile runs before any step"
        distance = np.sqrt(squared_norms(self._mouth_to_target(physics)))
        is_upright = 0.5 * (self._upright(physics) + 1)
        return (7 * self._in_target(distance) + is_upright) / 8


registry.add(
    registry.SuiteEntry(
        "fish", "upright", Upright, {}, TIME_LIMIT, "Turn a swimming fish upright",
        ("benchmarking",),
    )
)  # fmt: skip
registry.add(
    registry.SuiteEntry(
        "fish", "swim", Swim, {}, TIME_LIMIT, "Swim a fish to a target placed at random",
        ("benchmarking",),
    )
)  # fmt: skip
