"""Stacker: a planar arm stacks boxes so that one reaches the target, then moves its hand
away (dm_control's `stacker`).

    env = gym.make('dm_control/stacker-stack_2-v0')
    env = gym.make('dm_control/stacker-stack_4-v0', fully_observable=False)

Observations: `arm_pos`, `arm_vel`, `touch`, and fully observable (the default)
`hand_pos`, `box_pos`, `box_vel` and `target_pos`. Reward in [0, 1]: a box at the target
while the hand is at least 10 cm from it. Episodes start from dm_control's draws in
dm_control's order; 1,000 steps of 10 ms (physics at 1 ms). Details in docs/suite.md.
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from arenas.suite import PlanarArena
from composer import observation
from entities.suite import Stacker
from entities.suite.stacker import CONTACT_SOLREF
from tasks.rewards import Tolerance, squared_norms
from tasks.suite import planar, registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 10.0
CONTROL_TIMESTEP = 0.01
_CLOSE = 0.01  # metres: the hand this much closer than 10 cm is not away any more


class Stack(SuiteTask):
    """Stack boxes up to the target (module docstring)."""

    def __init__(
        self, n_boxes: int = 2, fully_observable: bool = True, control_timestep: float | None = None
    ) -> None:
        """Build the scene with `n_boxes` boxes (1 to 4); the boxes' and target's
        observations with `fully_observable`. Raises composer.EntityError for another
        number of boxes, composer.TaskError for a control timestep that is not a multiple
        of 1 ms."""
        self._arena = PlanarArena(contact_solref=CONTACT_SOLREF)
        self.stacker = Stacker(n_boxes=n_boxes)
        self._arena.attach(self.stacker)
        self._n_boxes = n_boxes
        self.use_control_timestep(control_timestep, default=CONTROL_TIMESTEP)
        # The box size is the target's half-width, as the model has it.
        self._box_size = float(self.stacker.target_geom.size[0])
        self._box_is_close = Tolerance(margin=2 * self._box_size)
        self._hand_is_far = Tolerance(bounds=(0.1, float("inf")), margin=_CLOSE)
        arm, robot = self.stacker.arm, self.stacker
        sensors = self._arena.mjcf_model.find_all("sensor")  # its touch sensors, all of it
        observables: dict[str, observation.Observable] = {
            "arm_pos": observation.BatchGeneric(
                lambda physics: planar.bounded_joint_positions(physics, arm.joints)
            ),
            "arm_vel": BoundField("qvel", arm.joints),
            "touch": BoundField("sensordata", sensors, function=np.log1p),
        }
        if fully_observable:
            observables |= {
                "hand_pos": planar.observed_2d_pose(arm.hand),
                "box_pos": planar.observed_2d_pose(robot.boxes),
                "box_vel": BoundField("qvel", robot.box_joints),
                "target_pos": planar.observed_2d_pose(robot.target, orientation=False),
            }
        self.set_observables(observables)

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws, repeated until no two geoms touch (module docstring): the
        arm's pose, the target's height (`randint`) and x, then each box's x, z and
        angle."""
        target = physics.bind(self.stacker.target)
        boxes = [physics.bind(joints) for joints in _per_box(self.stacker.box_joints)]
        penetrating = True
        while penetrating:
            planar.randomize_arm(physics, self.stacker.arm, random_state)
            target_height = 2 * random_state.randint(self._n_boxes) + 1
            position = target.pos
            position[2] = self._box_size * target_height
            position[0] = random_state.uniform(-0.37, 0.37)
            target.pos = position
            for box in boxes:  # joints x, y, z
                x = random_state.uniform(0.1, 0.3)
                z = random_state.uniform(0, 0.7)
                box.qpos = [x, random_state.uniform(0, 2 * np.pi), z]
            physics.after_reset()
            penetrating = physics.data.ncon > 0

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        robot = self.stacker
        sites = physics.bind([robot.target_site, *robot.box_sites]).xpos  # (n, 1 + boxes, 3)
        distances = np.sqrt(squared_norms(sites[:, 1:] - sites[:, :1]))
        box_is_close = self._box_is_close(np.minimum.reduce(distances, axis=1))  # .min's
        hand = planar.site_distances(physics, robot.arm.grasp, robot.target_site)
        return box_is_close * self._hand_is_far(hand)


def _per_box(joints: tuple[mjcf.Element, ...]) -> list[tuple[mjcf.Element, ...]]:
    """Each box's (x, y, z) joints."""
    return [joints[i : i + 3] for i in range(0, len(joints), 3)]


for _name, _boxes in (("stack_2", 2), ("stack_4", 4)):
    registry.add(
        registry.SuiteEntry(
            "stacker", _name, Stack, {"n_boxes": _boxes}, TIME_LIMIT,
            f"Stack {_boxes} boxes up to a target with a planar arm", ("hard",),
        )
    )  # fmt: skip
