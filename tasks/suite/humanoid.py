"""Humanoid: stand up, walk and run with a 21-joint humanoid (dm_control's `humanoid`).

    env = gym.make('dm_control/humanoid-walk-v0')
    env = gym.make('dm_control/humanoid-run_pure_state-v0', flatten_observations=True)

Observations: `joint_angles`, `head_height`, `extremities`, `torso_vertical`,
`com_velocity`, `velocity`; with `pure_state=True`, `position` and `velocity` (qpos, qvel).
Reward in [0, 1]: `standing * upright * small_control * move`, move being staying still
for `move_speed` 0, else reaching `move_speed`. Episodes start from a random pose 1.5 m up
and fall; 1,000 steps of 25 ms. What each term and observation holds: docs/suite.md.
"""

from __future__ import annotations

import dataclasses

import numpy as np

import composer
import mjcf
from arenas.suite import SuiteArena
from composer import observation
from entities import suite as suite_entities
from tasks.rewards import Tolerance, row_means, row_norms
from tasks.suite import registry
from tasks.suite.base import SuiteTask
from tasks.suite.frames import in_frame
from tasks.suite.observables import BoundField
from tasks.suite.randomizers import randomize_limited_and_rotational_joints

TIME_LIMIT = 25.0
CONTROL_TIMESTEP = 0.025
STAND_HEIGHT = 1.4
WALK_SPEED = 1.0
RUN_SPEED = 10.0

_standing = Tolerance(bounds=(STAND_HEIGHT, float("inf")), margin=STAND_HEIGHT / 4)
_upright = Tolerance(bounds=(0.9, float("inf")), sigmoid="linear", margin=1.9,
                     value_at_margin=0)  # fmt: skip
_small_control = Tolerance(margin=1, value_at_margin=0, sigmoid="quadratic")
_still = Tolerance(margin=2)
# The reward's numbers as 0-d float64 arrays: the same values, and numpy's calls on arrays of
# one row take half the time with them than with Python numbers.
_ONE, _FOUR, _FIVE, _SIX = (np.array(value) for value in (1.0, 4.0, 5.0, 6.0))


@dataclasses.dataclass(frozen=True)
class BipedParts:
    """The elements a `Biped` task reads: the body whose frame the observations use and
    the entry of its orientation matrix that is 1 when upright (0 to 8, row-major), the
    head, the extremities (left hand, left foot, right hand, right foot) and the sensor of
    the robot's subtree linear velocity."""

    upright_body: mjcf.Element
    upright_entry: int
    head: mjcf.Element
    extremities: tuple[mjcf.Element, ...]
    subtree_velocity: mjcf.Element


class Biped(SuiteTask):
    """What the humanoid domains share: observations, reward and initial state of a biped
    with a free root (module docstring); a subclass builds the scene and names its parts."""

    def __init__(
        self,
        arena: composer.Arena,
        parts: BipedParts,
        move_speed: float,
        pure_state: bool,
        control_timestep: float | None,
        default_control_timestep: float,
    ) -> None:
        """Serve `arena` (the robot attached) with the robot's `parts`; reward standing
        still for `move_speed` 0, else moving at `move_speed` m/s; observe qpos and qvel
        alone with `pure_state`. Raises composer.TaskError for a negative speed or a control
        timestep that is not a multiple of the physics timestep."""
        if not move_speed >= 0:
            raise composer.TaskError(f"move_speed must be >= 0, got {move_speed!r}")
        self._arena, self._parts = arena, parts
        self._move_speed = float(move_speed)
        self.use_control_timestep(control_timestep, default=default_control_timestep)
        self._move = Tolerance(
            bounds=(self._move_speed, float("inf")), margin=self._move_speed,
            value_at_margin=0, sigmoid="linear",
        )  # fmt: skip
        # The robot's joints in model order, the root's first: qpos and qvel, all of them.
        joints = arena.mjcf_model.find_all("joint")
        self._observables: dict[str, observation.Observable] = (
            {"position": BoundField("qpos", joints)}
            if pure_state
            else {
                "joint_angles": BoundField("qpos", joints[1:]),  # qpos after the root's 7
                "head_height": BoundField("xpos", parts.head, index=2),
                "extremities": observation.BatchGeneric(self._extremity_positions),
                "torso_vertical": BoundField("xmat", parts.upright_body, index=slice(6, 9)),
                "com_velocity": BoundField("sensordata", parts.subtree_velocity),
            }
        )
        self._observables["velocity"] = BoundField("qvel", joints)
        self.set_observables(self._observables)

    def _head_height(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The head's height, (n,)."""
        return physics.bind(self._parts.head).xpos[:, 2]

    def _com_velocity(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The centre of mass' velocity, (n, 3)."""
        return physics.bind(self._parts.subtree_velocity).sensordata

    def _extremity_positions(self, physics: composer.BatchPhysics) -> np.ndarray:
        """Each extremity's position relative to the upright body, in its frame, (n, 12)."""
        body = physics.bind(self._parts.upright_body)
        offsets = physics.bind(self._parts.extremities).xpos - body.xpos[:, None, :]
        return in_frame(offsets, body.xmat).reshape(len(offsets), -1)

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: random joint angles and orientation
        (`randomize_limited_and_rotational_joints`), drawn again until nothing touches."""
        while True:
            randomize_limited_and_rotational_joints(physics, random_state)
            physics.after_reset()
            if physics.data.ncon == 0:
                return

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """The reward of each environment (module docstring), shape (n,)."""
        parts = self._parts
        standing = _standing(self._head_height(physics))
        upright = _upright(physics.bind(parts.upright_body).xmat[:, parts.upright_entry])
        small_control = (_FOUR + row_means(_small_control(physics.field("ctrl")))) / _FIVE
        horizontal = self._com_velocity(physics)[:, :2]
        if self._move_speed == 0:
            move = row_means(_still(horizontal))
        else:
            move = (_FIVE * self._move(row_norms(horizontal)) + _ONE) / _SIX
        return small_control * (standing * upright) * move


class Humanoid(Biped):
    """Stand, walk or run with the suite's humanoid (module docstring)."""

    def __init__(
        self,
        move_speed: float = 0.0,
        pure_state: bool = False,
        control_timestep: float | None = None,
    ) -> None:
        """As `Biped`, in the humanoid's world, with its 25 ms control step."""
        self.humanoid = suite_entities.Humanoid()
        arena = SuiteArena(floor_size=(100.0, 100.0, 0.2))
        arena.attach(self.humanoid)
        left_hand, right_hand = self.humanoid.hands
        left_foot, right_foot = self.humanoid.feet
        parts = BipedParts(
            upright_body=self.humanoid.torso,
            upright_entry=8,  # z of the torso's z axis
            head=self.humanoid.head,
            extremities=(left_hand, left_foot, right_hand, right_foot),
            subtree_velocity=self.humanoid.subtree_velocity,
        )
        self.render_camera = f"{self.humanoid.name}/back"
        super().__init__(arena, parts, move_speed, pure_state, control_timestep, CONTROL_TIMESTEP)


for _name, _kwargs, _description, _tags in (
    ("stand", {"move_speed": 0.0}, "Stand up and stay still with a humanoid", ("benchmarking",)),
    ("walk", {"move_speed": WALK_SPEED}, "Walk at 1 m/s with a humanoid", ("benchmarking",)),
    ("run", {"move_speed": RUN_SPEED}, "Run at 10 m/s with a humanoid", ("benchmarking",)),
    ("run_pure_state", {"move_speed": RUN_SPEED, "pure_state": True},
     "Run at 10 m/s with a humanoid, observing qpos and qvel alone", ()),
):  # fmt: skip
    registry.add(
        registry.SuiteEntry("humanoid", _name, Humanoid, _kwargs, TIME_LIMIT, _description, _tags)
    )
