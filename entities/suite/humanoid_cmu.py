"""The Control Suite's CMU humanoid: the 56-joint body of the CMU motion-capture subjects.

    humanoid = HumanoidCMU()
    arena.attach(humanoid)
    physics.bind(humanoid.thorax).xmat            # the frame its observations use
    physics.bind(humanoid.subtree_velocity).sensordata   # the thorax subtree's velocity

The numbers are the suite's (`humanoid_CMU.xml`, no mesh files): `HumanoidCMU` lists them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import composer
import mjcf
from entities.suite.materials import add_materials

Vector = Sequence[float]
# A joint: (name's suffix, whose last letter is its axis, range in degrees, default class
# or None for the main one's stiffness, its motor's gear).
Joint = tuple[str, tuple[float, float], str | None, int]

_AXES = {"x": [1, 0, 0], "y": [0, 1, 0], "z": [0, 0, 1]}
_SPINE_RANGES = ((-30, 30), (-30, 30), (-20, 45))  # about z, y, x


def _spine_joints(dclass: str, gear: int) -> tuple[Joint, ...]:
    """The rz, ry, rx joints of a spine or neck body."""
    return tuple(
        (f"r{axis}", joint_range, dclass, gear)
        for axis, joint_range in zip("zyx", _SPINE_RANGES, strict=True)
    )


Pose = tuple[Vector, Vector]  # a position and a quaternion


@dataclasses.dataclass(frozen=True)
class _Leg:
    """What differs between the legs (positions, quaternions, ranges in degrees)."""

    hip_geom: Pose
    femur: Pose
    femur_z_range: tuple[float, float]
    femur_geom: Pose
    tibia_quat: Vector
    foot_touch: Vector
    foot_z_range: tuple[float, float]
    foot_geoms: tuple[tuple[float, float], ...]  # (x, euler about y) of each
    toes: tuple[tuple[float, float], ...]  # (x, y) of each
    toe_touch: tuple[Vector, Vector]  # position and z axis


@dataclasses.dataclass(frozen=True)
class _Arm:
    """What differs between the arms (positions, quaternions, ranges in degrees)."""

    clavicle_ranges: tuple[tuple[float, float], tuple[float, float]]  # about z, about y
    clavicle_geom: Pose
    humerus: Pose
    humerus_geom: Vector
    radius_geom: Vector
    wrist: Vector
    hand_quat: Vector  # of the wrist's, the hand's and the thumb's geoms
    fingers: tuple[tuple[float, float, float], ...]  # (radius, x, y) of each
    thumb: Pose


# Each side's numbers: left ('l') then right ('r'), as the file orders them.
_LEGS = {
    "l": _Leg(
        hip_geom=((0.051, -0.046, 0.025), (0.5708, -0.566602, -0.594264, 0)),
        femur=((0.102, -0.092, 0.05), (1, 0, 0, 0.17365)),
        femur_z_range=(-60, 70),
        femur_geom=((-0.01, -0.202473, 0), (0.7, -0.7, -0.1228, -0.07)),
        tibia_quat=(0.7, -0.7, -0.1228, -0.1228),
        foot_touch=(-0.005, -0.02, -0.025),
        foot_z_range=(-70, 20),
        foot_geoms=((-0.02, -2), (0, 0), (0.01, 10)),
        toes=((-0.025, -0.01), (0, -0.005), (0.02, 0.001)),
        toe_touch=((-0.005, -0.005, -0.01), (1, 0.2, 0)),
    ),
    "r": _Leg(
        hip_geom=((-0.051, -0.046, 0.025), (0.574856, -0.547594, 0.608014, 0)),
        femur=((-0.102, -0.092, 0.05), (1, 0, 0, -0.17365)),
        femur_z_range=(-70, 60),
        femur_geom=((0.01, -0.202473, 0), (0.7, -0.7, 0.1228, 0.07)),
        tibia_quat=(0.7, -0.7, 0.1228, 0.1228),
        foot_touch=(0.005, -0.02, -0.025),
        foot_z_range=(-20, 70),
        foot_geoms=((0.02, 2), (0, 0), (-0.01, -10)),
        toes=((0.025, -0.01), (0, -0.005), (-0.02, 0.001)),
        toe_touch=((0.005, -0.005, -0.01), (1, -0.2, 0)),
    ),
}
_ARMS = {
    "l": _Arm(
        clavicle_ranges=((0, 20), (-20, 10)),
        clavicle_geom=((0.09, 0.05, -0.01), (1, 0, -1, -0.4)),
        humerus=((0.183, 0.076, 0.01), (0.18, 0.68, -0.68, 0.18)),
        humerus_geom=(0.612, -0.612, 0.35, 0.35),
        radius_geom=(0.612, -0.612, 0.35, 0.35),
        wrist=(-0.5, 0, 0.866, 0),
        hand_quat=(0, 0, -1, -1),
        fingers=(
            (0.01, -0.03, -0.05),
            (0.01, -0.008, -0.06),
            (0.009, 0.014, -0.06),
            (0.008, 0.032, -0.05),
        ),
        thumb=((-0.02, -0.03, 0), (0.92388, 0, 0, -0.382683)),
    ),
    "r": _Arm(
        clavicle_ranges=((-20, 0), (-10, 20)),
        clavicle_geom=((-0.09, 0.05, -0.01), (1, 0, -1, 0.4)),
        humerus=((-0.183, 0.076, 0.01), (0.18, 0.68, 0.68, -0.18)),
        humerus_geom=(0.61, -0.61, -0.35, -0.35),
        radius_geom=(0.612, -0.612, -0.35, -0.35),
        wrist=(-0.5, 0, -0.866, 0),
        hand_quat=(0, 0, 1, 1),
        fingers=(
            (0.01, 0.03, -0.05),
            (0.01, 0.008, -0.06),
            (0.009, -0.014, -0.06),
            (0.008, -0.032, -0.05),
        ),
        thumb=((0.02, -0.03, 0), (0.92388, 0, 0, 0.382683)),
    ),
}
# The neck and clavicles hang from the same point of the thorax.
_SHOULDERS = (0, 0.113945, 0.00468037)
# Body pairs that never collide.
_EXCLUDED = (("lclavicle", "rclavicle"), ("lowerneck", "lclavicle"), ("lowerneck", "rclavicle"),
             ("upperneck", "lclavicle"), ("upperneck", "rclavicle"))  # fmt: skip


class HumanoidCMU(composer.Entity):
    """The suite's CMU humanoid. Attributes: `pelvis` (the body `root`), `root` (its free
    joint), `thorax`, `head`, `hands` and `feet` (left, right), `joints` (the 56 hinges in
    model order), `subtree_velocity` (the thorax subtree's linear velocity sensor).

    The numbers are the suite's (`humanoid_CMU.xml`, built of capsules, spheres and
    ellipsoids: no mesh files): a pelvis body `root` with a free joint 1 m up, lying on its
    back in its own frame (rotated 90 degrees about x), whose y axis runs up the spine; two
    legs (hip, femur, tibia, foot, toes), a spine (lower back, upper back, thorax), a neck
    of two bodies, the head, and two arms (clavicle, humerus, radius, wrist, hand, fingers,
    thumb). Joints are named for their body and axis (`lfemurrx`: the left femur about x),
    limited, damped and sprung by three stiffness classes; a motor drives each, unit control
    range, listed by name as the file lists them. Sensors: the thorax subtree's linear
    velocity, an IMU at the root site (velocimeter, gyro, accelerometer) and touch sensors
    on the toes and feet. The clavicles do not collide with each other or with the neck.
    MuJoCo's default 2 ms step.
    """

    def _build(self, name: str = "humanoid_CMU") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.statistic.set_attributes(extent=2, center=[0, 0, 1])
        add_materials(root)
        self._add_defaults(root)
        self._gears: dict[str, int] = {}
        self._touch: dict[str, mjcf.Element] = {}
        pelvis = self.pelvis = root.worldbody.add(
            "body", name="root", childclass="humanoid", pos=[0, 0, 1], euler=[90, 0, 0]
        )
        self._imu_site = pelvis.add("site", name="root", size=[0.01], rgba=[0.5, 0.5, 0.5, 0])
        self.root = pelvis.add("freejoint", name="root")
        pelvis.add("geom", name="root_geom", size=[0.09, 0.06], pos=[0, -0.05, 0],
                   quat=[1, 0, -1, 0])  # fmt: skip
        feet = {side: self._add_leg(pelvis, side) for side in _LEGS}
        self._add_spine_and_arms(pelvis)
        self.feet = (feet["l"], feet["r"])
        self.joints = tuple(j for j in root.find_all("joint") if j.tag == "joint")
        for body1, body2 in _EXCLUDED:
            root.contact.add("exclude", body1=body1, body2=body2)
        self.motors = tuple(
            root.actuator.add("motor", name=joint, joint=joint, gear=[self._gears[joint]])
            for joint in sorted(self._gears)
        )
        self._add_sensors(root)

    @staticmethod
    def _add_defaults(root: mjcf.RootElement) -> None:
        main = root.default
        main.joint.set_attributes(limited=True, solimplimit=[0, 0.99, 0.01], stiffness=0.1,
                                  armature=0.01, damping=1)  # fmt: skip
        main.geom.set_attributes(friction=[0.7], solref=[0.015, 1], solimp=[0.95, 0.99, 0.003])
        main.motor.set_attributes(ctrllimited=True, ctrlrange=[-1, 1])
        humanoid = main.add("default", dclass="humanoid")
        humanoid.geom.set_attributes(type="capsule", material="self")
        for stiffness_class, stiffness, damping in (("stiff_low", 0.5, 4),
                                                    ("stiff_medium", 10, 5),
                                                    ("stiff_high", 30, 10)):  # fmt: skip
            humanoid.add("default", dclass=stiffness_class).joint.set_attributes(
                stiffness=stiffness, damping=damping
            )
        humanoid.add("default", dclass="touch").site.set_attributes(group=3, rgba=[0, 0, 1, 0.5])

    def _add_joints(self, body: mjcf.Element, joints: Sequence[Joint]) -> None:
        """`body`'s hinges, each named body name + suffix, with its motor's gear noted."""
        for suffix, joint_range, dclass, gear in joints:
            name = f"{body.name}{suffix}"
            classed = {} if dclass is None else {"dclass": dclass}
            body.add("joint", name=name, axis=_AXES[suffix[-1]], range=list(joint_range),
                     **classed)  # fmt: skip
            self._gears[name] = gear

    def _touch_site(self, body: mjcf.Element, name: str, **attributes: object) -> None:
        self._touch[name] = body.add("site", name=name, dclass="touch", **attributes)

    def _add_leg(self, pelvis: mjcf.Element, side: str) -> mjcf.Element:
        """The leg on `side` ('l' or 'r'), from the hip joint's body to the toes; returns
        the foot."""
        leg = _LEGS[side]
        hip = pelvis.add("body", name=f"{side}hipjoint")
        position, quat = leg.hip_geom
        hip.add("geom", name=f"{side}hipjoint", size=[0.008, 0.022], pos=list(position),
                quat=list(quat))  # fmt: skip
        position, quat = leg.femur
        femur = hip.add("body", name=f"{side}femur", pos=list(position), quat=list(quat))
        self._add_joints(femur, (("rz", leg.femur_z_range, "stiff_medium", 40),
                                 ("ry", (-70, 70), "stiff_medium", 40),
                                 ("rx", (-160, 20), "stiff_medium", 120)))  # fmt: skip
        position, quat = leg.femur_geom
        femur.add("geom", name=f"{side}femur", size=[0.06, 0.17], pos=list(position),
                  quat=list(quat))  # fmt: skip
        tibia = femur.add("body", name=f"{side}tibia", pos=[0, -0.404945, 0])
        self._add_joints(tibia, (("rx", (1, 170), "stiff_low", 80),))
        tibia.add("geom", name=f"{side}tibia", size=[0.03, 0.1825614], pos=[0, -0.202846, 0],
                  quat=list(leg.tibia_quat))  # fmt: skip
        tibia.add("geom", name=f"{side}calf", size=[0.045, 0.08], pos=[0, -0.1, -0.01],
                  quat=[0.7, -0.7, -0.1228, -0.1228])  # fmt: skip
        foot = tibia.add("body", name=f"{side}foot", pos=[0, -0.405693, 0],
                         quat=[0.707107, -0.707107, 0, 0])  # fmt: skip
        self._touch_site(foot, f"{side}foot_touch", type="box", pos=list(leg.foot_touch),
                         size=[0.04, 0.08, 0.02], euler=[10, 0, 0])  # fmt: skip
        self._add_joints(foot, (("rz", leg.foot_z_range, "stiff_medium", 20),
                                ("rx", (-45, 90), "stiff_medium", 20)))  # fmt: skip
        for index, (x, euler_y) in enumerate(leg.foot_geoms):
            foot.add("geom", name=f"{side}foot{index}", size=[0.02, 0.06],
                     pos=[x, -0.023, -0.01], euler=[100, euler_y, 0])  # fmt: skip
        toes = foot.add("body", name=f"{side}toes", pos=[0, -0.106372, -0.0227756])
        self._add_joints(toes, (("rx", (-90, 20), None, 20),))
        for index, (x, y) in enumerate(leg.toes):
            toes.add("geom", name=f"{side}toes{index}", type="sphere", size=[0.02],
                     pos=[x, y, -0.01])  # fmt: skip
        position, zaxis = leg.toe_touch
        self._touch_site(toes, f"{side}toes_touch", type="capsule", pos=list(position),
                         size=[0.025, 0.02], zaxis=list(zaxis))  # fmt: skip
        return foot

    def _add_spine_and_arms(self, pelvis: mjcf.Element) -> None:
        lower = pelvis.add("body", name="lowerback")
        self._add_joints(lower, _spine_joints("stiff_high", 40))
        lower.add("geom", name="lowerback", size=[0.065, 0.055], pos=[0, 0.056, 0.03],
                  quat=[1, 0, 1, 0])  # fmt: skip
        upper = lower.add("body", name="upperback", pos=[0, 0.1, -0.01])
        self._add_joints(upper, _spine_joints("stiff_high", 40))
        upper.add("geom", name="upperback", size=[0.06, 0.06], pos=[0, 0.06, 0.02],
                  quat=[1, 0, 1, 0])  # fmt: skip
        thorax = self.thorax = upper.add("body", name="thorax",
                                         pos=[0.000512528, 0.11356, 0.000936821])  # fmt: skip
        self._add_joints(thorax, _spine_joints("stiff_high", 40))
        thorax.add("geom", name="thorax", size=[0.08, 0.07], pos=[0, 0.05, 0], quat=[1, 0, 1, 0])
        lower_neck = thorax.add("body", name="lowerneck", pos=list(_SHOULDERS))
        self._add_joints(lower_neck, _spine_joints("stiff_medium", 20))
        lower_neck.add("geom", name="lowerneck", size=[0.08, 0.02], pos=[0, 0.04, -0.02],
                       quat=[1, 1, 0, 0])  # fmt: skip
        upper_neck = lower_neck.add("body", name="upperneck", pos=[0, 0.09, 0.01])
        self._add_joints(upper_neck, _spine_joints("stiff_medium", 20))
        upper_neck.add("geom", name="upperneck", size=[0.05, 0.03], pos=[0, 0.05, 0],
                       quat=[0.8, 1, 0, 0])  # fmt: skip
        head = self.head = upper_neck.add("body", name="head", pos=[0, 0.09, 0])
        head.add("camera", name="egocentric", pos=[0, 0, 0], xyaxes=[-1, 0, 0, 0, 1, 0],
                 fovy=80)  # fmt: skip
        self._add_joints(head, _spine_joints("stiff_medium", 20))
        head.add("geom", name="head", size=[0.085, 0.035], pos=[0, 0.11, 0.03],
                 quat=[1, 0.9, 0, 0])  # fmt: skip
        for eye, x in (("leye", 0.03), ("reye", -0.03)):
            head.add("geom", name=eye, type="sphere", size=[0.02], pos=[x, 0.11, 0.1])
        hands = {side: self._add_arm(thorax, side) for side in _ARMS}
        self.hands = (hands["l"], hands["r"])

    def _add_arm(self, thorax: mjcf.Element, side: str) -> mjcf.Element:
        """The arm on `side` ('l' or 'r'), from the clavicle to the thumb; returns the
        hand."""
        arm = _ARMS[side]
        z_range, y_range = arm.clavicle_ranges
        clavicle = thorax.add("body", name=f"{side}clavicle", pos=list(_SHOULDERS))
        self._add_joints(clavicle, (("rz", z_range, "stiff_high", 20),
                                    ("ry", y_range, "stiff_high", 20)))  # fmt: skip
        position, quat = arm.clavicle_geom
        clavicle.add("geom", name=f"{side}clavicle", size=[0.08, 0.04], pos=list(position),
                     quat=list(quat))  # fmt: skip
        position, quat = arm.humerus
        humerus = clavicle.add("body", name=f"{side}humerus", pos=list(position),
                               quat=list(quat))  # fmt: skip
        self._add_joints(humerus, (("rz", (-90, 90), "stiff_low", 40),
                                   ("ry", (-90, 90), "stiff_low", 40),
                                   ("rx", (-60, 90), "stiff_low", 40)))  # fmt: skip
        humerus.add("geom", name=f"{side}humerus", size=[0.035, 0.124], pos=[0, -0.138, 0],
                    quat=list(arm.humerus_geom))  # fmt: skip
        radius = humerus.add("body", name=f"{side}radius", pos=[0, -0.277, 0])
        self._add_joints(radius, (("rx", (-10, 170), "stiff_low", 40),))
        radius.add("geom", name=f"{side}radius", size=[0.03, 0.06], pos=[0, -0.08, 0],
                   quat=list(arm.radius_geom))  # fmt: skip
        wrist = radius.add("body", name=f"{side}wrist", pos=[0, -0.17, 0],
                           quat=list(arm.wrist))  # fmt: skip
        self._add_joints(wrist, (("ry", (-180, 0), None, 20),))
        hand_quat = list(arm.hand_quat)
        wrist.add("geom", name=f"{side}wrist", size=[0.025, 0.03], pos=[0, -0.02, 0],
                  quat=hand_quat)  # fmt: skip
        hand = wrist.add("body", name=f"{side}hand", pos=[0, -0.08, 0])
        self._add_joints(hand, (("rz", (-45, 45), None, 20), ("rx", (-90, 90), None, 20)))
        hand.add("geom", name=f"{side}hand", type="ellipsoid", size=[0.048, 0.02, 0.06],
                 pos=[0, -0.047, 0], quat=hand_quat)  # fmt: skip
        fingers = hand.add("body", name=f"{side}fingers", pos=[0, -0.08, 0])
        self._add_joints(fingers, (("rx", (0, 90), None, 20),))
        for index, (size, x, y) in enumerate(arm.fingers):
            fingers.add("geom", name=f"{side}finger{index}", size=[size, 0.04], pos=[x, y, 0],
                        quat=[1, -1, 0, 0])  # fmt: skip
        position, quat = arm.thumb
        thumb = hand.add("body", name=f"{side}thumb", pos=list(position), quat=list(quat))
        self._add_joints(thumb, (("rz", (-45, 45), None, 20), ("rx", (0, 90), None, 20)))
        thumb.add("geom", name=f"{side}thumb", size=[0.012, 0.04], pos=[0, -0.06, 0],
                  quat=hand_quat)  # fmt: skip
        return hand

    def _add_sensors(self, root: mjcf.RootElement) -> None:
        sensor, site = root.sensor, self._imu_site
        self.subtree_velocity = sensor.add(
            "subtreelinvel", name="thorax_subtreelinvel", body=self.thorax
        )
        sensor.add("velocimeter", name="sensor_root_veloc", site=site)
        sensor.add("gyro", name="sensor_root_gyro", site=site)
        sensor.add("accelerometer", name="sensor_root_accel", site=site)
        for part in ("ltoes", "rtoes", "rfoot", "lfoot"):
            sensor.add("touch", name=f"sensor_touch_{part}", site=self._touch[f"{part}_touch"])
