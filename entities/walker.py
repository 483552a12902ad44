"""A planar biped walker: a torso on three planar joints and two three-segment legs.

    walker = Walker()
    arena.attach(walker)
    physics.bind(walker.torso).xpos[2]                 # torso height, ~1.3 standing
    physics.bind(walker.root_x).qvel                   # forward speed

The walker moves in the world x-z plane: `root_x` slides forward, `root_z` up, `root_y`
pitches the torso (0 upright). Each leg has hip, knee and ankle hinges, torque-driven with
control in [-1, 1]. The right leg is drawn lighter than the left.
"""

from __future__ import annotations

import composer
import mjcf
from composer import observation
from entities.features import HingeAngles, angles, positions, velocities


class Walker(composer.Entity):
    """Torso `torso`; joints `root_x`, `root_z`, `root_y`, and per side ('left',
    'right') `<side>_hip`, `<side>_knee`, `<side>_ankle` with a motor each."""

    def _build(
        self,
        name: str = "walker",
        thigh_length: float = 0.45,
        shin_length: float = 0.5,
        gear: float = 100.0,
    ) -> None:
        """Make the walker model named `name`: segment lengths in m, motor `gear` (N m at
        full control)."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.compiler.angle = "radian"
        root.default.geom.set_attributes(  # touches the world and props, not itself
            type="capsule", friction=[0.9, 0.1, 0.1], condim=3, contype=1, conaffinity=0
        )
        root.default.joint.set_attributes(type="hinge", axis=[0, -1, 0], damping=0.1,
                                          armature=0.01, limited=True)  # fmt: skip
        root.default.motor.set_attributes(gear=[gear], ctrllimited=True, ctrlrange=[-1, 1])
        root.asset.add("material", name="torso", rgba=[0.7, 0.5, 0.3, 1])
        root.asset.add("material", name="left", rgba=[0.6, 0.4, 0.25, 1])
        root.asset.add("material", name="right", rgba=[0.85, 0.7, 0.5, 1])
        hip_height = thigh_length + shin_length + 0.1
        torso = root.worldbody.add("body", name="torso", pos=[0, 0, hip_height + 0.2])
        self.root_x = torso.add("joint", name="root_x", type="slide", axis=[1, 0, 0],
                                limited=False, damping=0, armature=0)  # fmt: skip
        self.root_z = torso.add("joint", name="root_z", type="slide", axis=[0, 0, 1],
                                limited=False, damping=0, armature=0)  # fmt: skip
        self.root_y = torso.add("joint", name="root_y", limited=False, damping=0, armature=0)
        torso.add("geom", name="torso", size=[0.07], fromto=[0, 0, -0.2, 0, 0, 0.2],
                  material="torso")  # fmt: skip
        torso.add("camera", name="track", mode="trackcom", pos=[0, -4.0, -0.4],
                  xyaxes=[1, 0, 0, 0, 0, 1])  # fmt: skip
        self.torso = torso
        self.leg_joints: list[mjcf.Element] = []
        for side, y in (("left", 0.05), ("right", -0.05)):
            thigh = torso.add("body", name=f"{side}_thigh", pos=[0, y, -0.2])
            hip = thigh.add("joint", name=f"{side}_hip", range=[-2.0, 0.7])
            thigh.add("geom", name=f"{side}_thigh", size=[0.05],
                      fromto=[0, 0, 0, 0, 0, -thigh_length], material=side)  # fmt: skip
            shin = thigh.add("body", name=f"{side}_shin", pos=[0, 0, -thigh_length])
            knee = shin.add("joint", name=f"{side}_knee", range=[-2.5, 0.0])
            shin.add("geom", name=f"{side}_shin", size=[0.04],
                     fromto=[0, 0, 0, 0, 0, -shin_length], material=side)  # fmt: skip
            foot = shin.add("body", name=f"{side}_foot", pos=[0, 0, -shin_length])
            ankle = foot.add("joint", name=f"{side}_ankle", range=[-0.8, 0.8])
            foot.add("geom", name=f"{side}_foot", size=[0.05], fromto=[-0.05, 0, 0, 0.15, 0, 0],
                     material=side)  # fmt: skip
            self.leg_joints += [hip, knee, ankle]
        for joint in self.leg_joints:
            root.actuator.add("motor", name=joint.name, joint=joint)

    @property
    def root_joints(self) -> list[mjcf.Element]:
        """The planar joints of the torso: x slide, z slide, pitch hinge."""
        return [self.root_x, self.root_z, self.root_y]

    @composer.observable
    def joint_positions(self) -> observation.Observable:
        """Leg joint angles (rad): left hip, knee, ankle, then right; shape (6,)."""
        return angles(self.leg_joints)

    @composer.observable
    def joint_velocities(self) -> observation.Observable:
        """Velocities of every joint, root ones first (m/s, rad/s), shape (9,)."""
        return velocities(self.root_joints + self.leg_joints)

    @composer.observable
    def torso_height(self) -> observation.Observable:
        """Torso height above the world origin (m), shape (1,)."""
        return positions(self.torso, index=slice(2, 3))

    @composer.observable
    def torso_pitch(self) -> observation.Observable:
        """(cos, sin) of the torso's pitch; (1, 0) upright."""
        return HingeAngles([self.root_y])
