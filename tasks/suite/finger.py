"""Finger: spin a hinged body, or turn its tip onto a target (dm_control's `finger`).

    env = gym.make('dm_control/finger-spin-v0')
    env = gym.make('dm_control/finger-turn_easy-v0')    # a target 7 cm in radius; hard: 3 cm

Observations, all from sensors: `position`, `velocity`, `touch`; the turn tasks add
`target_position` and `dist_to_target`. Reward: spin, 1 while the spinner turns at
15 rad/s or faster the negative way about its hinge's axis; turn, 1 while the tip is
inside the target. 1,000 steps of 20 ms; what each observation holds and how episodes
start: docs/suite.md.
"""

from __future__ import annotations

import numpy as np

import composer
import entities.suite
import mjcf
from arenas.suite import SuiteArena
from composer import observation
from entities.suite.finger import SOLIMP, SOLREF
from tasks.rewards import squared_norms
from tasks.suite import randomizers, registry
from tasks.suite.base import SuiteTask
from tasks.suite.observables import BoundField

TIME_LIMIT = 20.0
CONTROL_TIMESTEP = 0.02
EASY_TARGET_SIZE, HARD_TARGET_SIZE = 0.07, 0.03  # the turn tasks' target radii (m)
_SPIN_VELOCITY = 15.0  # rad/s: spinning at least this fast is rewarded
_SPINNING = np.array(-_SPIN_VELOCITY)  # the hinge's velocity at most this (a 0-d array: faster)
_SPIN_DAMPING = 0.03  # the spinner's damping in the spin task
_MAX_ATTEMPTS = 1000  # random initial states tried before giving up on one without contacts
_XZ = [0, 2]


class _FingerTask(SuiteTask):
    """The finger's scene and the observations both tasks make (module docstring)."""

    def __init__(self, control_timestep: float | None) -> None:
        """Build the scene. Raises composer.TaskError for a control timestep that is not
        a multiple of 10 ms."""
        self.finger = entities.suite.Finger()
        self._arena = SuiteArena(
            floor_size=(0.6, 0.2, 10.0), floor_name="ground",
            floor_attributes={"solimp": list(SOLIMP), "solref": list(SOLREF)},
        )  # fmt: skip
        self._arena.add_light(
            name="light", directional=True, diffuse=[0.6] * 3, pos=[0, 0, 2],
            specular=[0.3] * 3,
        )  # fmt: skip
        self._arena.attach(self.finger)
        self.render_camera = f"{self.finger.name}/cam0"
        self.use_control_timestep(control_timestep, default=CONTROL_TIMESTEP)
        finger = self.finger
        # The sensors of every position the tasks observe, read together.
        self._positions = (
            *finger.joint_positions, finger.tip_position, finger.target_position,
            finger.spinner_position,
        )  # fmt: skip
        self._observables: dict[str, observation.Observable] = {
            "position": observation.BatchGeneric(self._bounded_position),
            "velocity": BoundField("sensordata", finger.joint_velocities),
            "touch": BoundField("sensordata", finger.touches, function=np.log1p),
        }

    def after_compile(self, physics: mjcf.Physics, random_state: np.random.RandomState) -> None:
        """Find each position's columns of the positions' bound sensordata (each sensor's
        values follow the previous one's): the angles', and the x and z columns of the
        frame positions."""
        dims = physics.bind(list(self._positions)).dim
        starts = np.concatenate(([0], np.cumsum(dims)[:-1]))
        angles = starts[: len(self.finger.joint_positions)]
        self._tip, self._target, self._spinner = starts[len(angles) :, None] + _XZ
        self._angles_and_tip = np.concatenate((angles, self._tip))

    def _from_axis(self, sensordata: np.ndarray, xz: np.ndarray) -> np.ndarray:
        """The x and z of `sensordata`'s columns `xz` (a frame position's) from the
        spinner's axis, (n, 2)."""
        return sensordata.take(xz, axis=1) - sensordata.take(self._spinner, axis=1)

    def _bounded_position(self, physics: composer.BatchPhysics) -> np.ndarray:
        """Both finger joints' angles, then the tip's x and z from the axis: (n, 4)."""
        sensordata = physics.bind(self._positions).sensordata
        position = sensordata.take(self._angles_and_tip, axis=1)  # a new array
        position[:, -2:] -= sensordata.take(self._spinner, axis=1)  # the tip from the axis
        return position

    def _set_random_joint_angles(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: random joint angles (`randomizers`) until no contact is
        found. Raises composer.EpisodeInitializationError after 1,000 attempts."""
        for _ in range(_MAX_ATTEMPTS):
            randomizers.randomize_limited_and_rotational_joints(physics, random_state)
            physics.after_reset()  # finds the contacts
            if physics.data.ncon == 0:
                return
        raise composer.EpisodeInitializationError(
            f"no initial finger pose without contacts in {_MAX_ATTEMPTS} attempts"
        )


class Spin(_FingerTask):
    """Spin the spinner fast (module docstring)."""

    def __init__(self, control_timestep: float | None = None) -> None:
        """Build the scene. Raises composer.TaskError for a control timestep that is not
        a multiple of 10 ms."""
        super().__init__(control_timestep)
        self.set_observables(self._observables)

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """Hide the target and the tip, damp the spinner at 0.03, then draw the joints."""
        physics.bind(self.finger.target).rgba[3] = 0
        physics.bind(self.finger.tip).rgba[3] = 0
        physics.bind(self.finger.hinge).damping = _SPIN_DAMPING
        self._set_random_joint_angles(physics, random_state)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """1 where the spinner turns at -15 rad/s or faster, else 0; shape (n,)."""
        velocity = physics.bind(self.finger.joint_velocities[2]).sensordata[:, 0]  # hinge's
        return (velocity <= _SPINNING).astype(np.float64)


class Turn(_FingerTask):
    """Turn the spinner's tip onto the target (module docstring)."""

    def __init__(
        self, target_radius: float = EASY_TARGET_SIZE, control_timestep: float | None = None
    ) -> None:
        """Build the scene with a target `target_radius` m in radius. Raises
        composer.TaskError for a radius that is not a positive number, or a control
        timestep that is not a multiple of 10 ms."""
        if isinstance(target_radius, bool) or not (
            isinstance(target_radius, (int, float)) and target_radius > 0
        ):
            raise composer.TaskError(
                f"target_radius must be a positive number of metres, got {target_radius!r}"
            )
        super().__init__(control_timestep)
        self._target_radius = float(target_radius)
        self._observables["target_position"] = observation.BatchGeneric(
            lambda physics: self._from_axis(physics.bind(self._positions).sensordata, self._target)
        )
        self._observables["dist_to_target"] = observation.BatchGeneric(self._dist_to_target)
        self.set_observables(self._observables)

    def _dist_to_target(self, physics: composer.BatchPhysics) -> np.ndarray:
        """From the tip to the target's surface (the task's radius), negative inside: (n,)."""
        sensordata = physics.bind(self._positions).sensordata
        target = self._from_axis(sensordata, self._target)
        to_target = target - self._from_axis(sensordata, self._tip)
        return np.sqrt(squared_norms(to_target)) - self._target_radius

    def initialize_episode(
        self, physics: mjcf.Physics, random_state: np.random.RandomState
    ) -> None:
        """dm_control's draws: the target's angle U(-pi, pi) on the circle of the tip
        about the hinge (the radius of a cap plus its half length); the target resized;
        then the joints."""
        angle = random_state.uniform(-np.pi, np.pi)
        hinge_x, hinge_z = physics.bind(self.finger.hinge).xanchor[_XZ]
        radius = physics.bind(self.finger.caps[0]).size.sum()
        target = physics.bind(self.finger.target)
        target.pos[_XZ] = hinge_x + radius * np.sin(angle), hinge_z + radius * np.cos(angle)
        target.size[0] = self._target_radius
        self._set_random_joint_angles(physics, random_state)

    def get_reward_batch(self, physics: composer.BatchPhysics) -> np.ndarray:
        """1 where the tip is inside the target, else 0; shape (n,)."""
        return (self._dist_to_target(physics) <= 0).astype(np.float64)


registry.add(
    registry.SuiteEntry(
        "finger", "spin", Spin, {}, TIME_LIMIT, "Spin a hinged body fast with a finger",
        ("benchmarking",),
    )
)  # fmt: skip
for _name, _radius, _description in (
    ("turn_easy", EASY_TARGET_SIZE, "Turn a hinged body's tip onto a 7 cm target"),
    ("turn_hard", HARD_TARGET_SIZE, "Turn a hinged body's tip onto a 3 cm target"),
):  # fmt: skip
    registry.add(
        registry.SuiteEntry(
            "finger", _name, Turn, {"target_radius": _radius}, TIME_LIMIT, _description,
            ("benchmarking",),
        )
    )  # fmt: skip
