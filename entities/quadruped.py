"""An ant-like quadruped: a ball torso on a free joint and four two-segment legs.

    ant = Quadruped()
    arena.attach(ant)                                   # the torso carries its free joint
    ant.set_pose(physics, position=[0, 0, 0.6])
    physics.bind(ant.root_joint).qvel[0]                # forward (x) speed

Legs point diagonally; each has a hip turning about the vertical and a knee lifting the
foot, both torque-driven with control in [-1, 1]. The torso's frame has x forward.
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from composer import observation
from entities.features import Clipped, angles, positions, velocities

_LEGS = (("front_left", 45.0), ("front_right", -45.0), ("back_left", 135.0),
         ("back_right", -135.0))  # fmt: skip


class Quadruped(composer.Entity):
    """Torso body `torso` (site `torso`, free joint `root`), legs named front_left,
    front_right, back_left, back_right with joints `<leg>_hip` and `<leg>_knee`."""

    def _build(
        self,
        name: str = "quadruped",
        torso_radius: float = 0.2,
        thigh_length: float = 0.3,
        shin_length: float = 0.45,
        gear: float = 30.0,
        height: float = 0.6,
    ) -> None:
        """Make the quadruped model named `name`: segment lengths in m (horizontal reach
        of each segment), motor `gear` (N m at full control), torso starting `height` m
        above the floor."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.compiler.angle = "radian"
        root.default.geom.set_attributes(
            type="capsule", size=[0.06], density=200, friction=[1.0, 0.5, 0.5], condim=3,
            contype=1, conaffinity=0,  # touches the world and props, not itself
        )  # fmt: skip
        root.default.joint.set_attributes(type="hinge", damping=1.0, armature=0.02,
                                          limited=True)  # fmt: skip
        root.default.motor.set_attributes(gear=[gear], ctrllimited=True, ctrlrange=[-1, 1])
        root.asset.add("material", name="body", rgba=[0.8, 0.6, 0.4, 1])
        root.asset.add("material", name="leg", rgba=[0.6, 0.4, 0.25, 1])
        torso = root.worldbody.add("body", name="torso", pos=[0, 0, height])
        self.root_joint = torso.add("freejoint", name="root")
        torso.add("geom", name="torso", type="sphere", size=[torso_radius], material="body")
        self.torso_site = torso.add("site", name="torso", size=[0.01])
        torso.add("camera", name="track", mode="trackcom", pos=[0, -3.5, 1.5],
                  xyaxes=[1, 0, 0, 0, 0.4, 1])  # fmt: skip
        self.torso = torso
        self.hips: list[mjcf.Element] = []
        self.knees: list[mjcf.Element] = []
        for leg, angle in _LEGS:
            direction = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle)), 0.0])
            side = np.cross([0, 0, 1], direction)
            hip_body = torso.add("body", name=f"{leg}_hip", pos=direction * torso_radius * 0.9)
            self.hips.append(hip_body.add("joint", name=f"{leg}_hip", axis=[0, 0, 1],
                                          range=[-0.6, 0.6]))  # fmt: skip
            thigh_end = direction * thigh_length
            hip_body.add("geom", name=f"{leg}_thigh", fromto=[0, 0, 0, *thigh_end],
                         material="leg")  # fmt: skip
            knee_body = hip_body.add("body", name=f"{leg}_shin", pos=thigh_end)
            self.knees.append(knee_body.add("joint", name=f"{leg}_knee", axis=side,
                                            range=[-0.15, 1.0]))  # fmt: skip
            foot = direction * shin_length * 0.6 + np.array([0, 0, -shin_length * 0.8])
            knee_body.add("geom", name=f"{leg}_shin", fromto=[0, 0, 0, *foot], material="leg")
        for joint in self.hips + self.knees:
            root.actuator.add("motor", name=joint.name, joint=joint)

    @property
    def joints(self) -> list[mjcf.Element]:
        """The eight leg joints: hips, then knees."""
        return self.hips + self.knees

    @composer.observable
    def joint_positions(self) -> observation.Observable:
        """Leg joint angles (rad), hips then knees, shape (8,)."""
        return angles(self.joints)

    @composer.observable
    def joint_velocities(self) -> observation.Observable:
        """Leg joint angular velocities (rad/s), shape (8,)."""
        return velocities(self.joints)

    @composer.observable
    def torso_height(self) -> observation.Observable:
        """Torso height above the world origin (m), shape (1,)."""
        return positions(self.torso, index=slice(2, 3))

    @composer.observable
    def torso_upright(self) -> observation.Observable:
        """1 when the torso is upright, -1 upside down, shape (1,)."""
        return Clipped("xmat", self.torso, -1.0, 1.0, index=slice(8, 9))

    @composer.observable
    def torso_orientation(self) -> observation.Observable:
        """Torso quaternion (w, x, y, z), shape (4,)."""
        return Clipped("xquat", self.torso, -1.0, 1.0)

    @composer.observable
    def torso_velocity(self) -> observation.Observable:
        """Free-joint velocity: world linear (m/s) then local angular (rad/s), shape (6,)."""
        return velocities(self.root_joint)
