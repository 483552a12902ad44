"""The Control Suite's humanoid: a 21-joint biped of capsules on a free torso.

    humanoid = Humanoid()
    arena.attach(humanoid)
    physics.bind(humanoid.head).xpos              # the head's position
    physics.bind(humanoid.subtree_velocity).sensordata   # the centre of mass' velocity

The numbers are the suite's (`humanoid.xml`): `Humanoid` lists them.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials

# Each side's numbers as a sign: y (and the mirrored axes) of the left side are +, the
# right side's -.
_SIDES = (("right", -1), ("left", 1))
# (joint, gear) of each motor, in the suite's order ('{side}' for each side in turn).
_WAIST_GEARS = (("abdomen_y", 40), ("abdomen_z", 40), ("abdomen_x", 40))
_LEG_GEARS = (
    ("{side}_hip_x", 40), ("{side}_hip_z", 40), ("{side}_hip_y", 120), ("{side}_knee", 80),
    ("{side}_ankle_x", 20), ("{side}_ankle_y", 20),
)  # fmt: skip
_ARM_GEARS = (("{side}_shoulder1", 20), ("{side}_shoulder2", 20), ("{side}_elbow", 40))
# The joints whose force and torque are sensed, in the suite's order.
_FORCE_TORQUE_SITES = (
    "left_ankle", "right_ankle", "left_knee", "right_knee", "left_hip", "right_hip",
)  # fmt: skip


class Humanoid(composer.Entity):
    """The suite's humanoid. Attributes: `torso`, `head`, `hands` and `feet` (left, right),
    `root` (the free joint), `joints` (the 21 hinges in model order), `subtree_velocity`
    (the torso's subtree linear velocity sensor).

    The numbers are the suite's (`humanoid.xml`): a torso with a free joint 1.5 m up, a
    waist of two bodies (abdomen z, y, x), two legs of thigh (hip x, z, y), shin (knee) and
    foot (ankle y, x) with two toe capsules, two arms of upper arm (two shoulder joints),
    lower arm (elbow) and hand; 21 motors of unit control range, 5 ms steps. Sites of the
    class `touch` cover each part (a touch sensor each), `force-torque` sites sit at the
    hips, knees and ankles (force and torque sensors); the torso's root site carries an IMU
    (accelerometer, velocimeter, gyro). The light `top` and the cameras `back` and `side`
    follow the torso's centre of mass; `egocentric` looks out of the head.
    """

    def _build(self, name: str = "humanoid") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.statistic.set_attributes(extent=2, center=[0, 0, 1])
        root.option.timestep = 0.005
        add_materials(root)
        self._add_defaults(root)
        self._touch_sites: list[mjcf.Element] = []
        self._sites: dict[str, mjcf.Element] = {}
        torso = self.torso = root.worldbody.add(
            "body", name="torso", pos=[0, 0, 1.5], childclass="body"
        )
        torso.add("light", name="top", pos=[0, 0, 2], mode="trackcom")
        torso.add("camera", name="back", pos=[-3, 0, 1], xyaxes=[0, -1, 0, 1, 0, 2],
                  mode="trackcom")  # fmt: skip
        torso.add("camera", name="side", pos=[0, -3, 1], xyaxes=[1, 0, 0, 0, 1, 2],
                  mode="trackcom")  # fmt: skip
        self.root = torso.add("freejoint", name="root")
        self._force_torque_site(torso, "root")
        torso.add("geom", name="torso", fromto=[0, -0.07, 0, 0, 0.07, 0], size=[0.07])
        torso.add("geom", name="upper_waist", fromto=[-0.01, -0.06, -0.12, -0.01, 0.06, -0.12],
                  size=[0.06])  # fmt: skip
        self._touch_site(torso, "torso", type="box", pos=[0, 0, -0.05], size=[0.075, 0.14, 0.13])
        head = self.head = torso.add("body", name="head", pos=[0, 0, 0.19])
        head.add("geom", name="head", type="sphere", size=[0.09])
        self._touch_site(head, "head", type="sphere", size=[0.091])
        head.add("camera", name="egocentric", pos=[0.09, 0, 0], xyaxes=[0, -1, 0, 0.1, 0, 1],
                 fovy=80)  # fmt: skip
        pelvis = self._add_waist(torso)
        feet = {side: self._add_leg(pelvis, side, sign) for side, sign in _SIDES}
        hands = {side: self._add_arm(torso, side, sign) for side, sign in _SIDES}
        self.hands = (hands["left"], hands["right"])
        self.feet = (feet["left"], feet["right"])
        self.joints = tuple(j for j in root.find_all("joint") if j.tag == "joint")
        self._add_actuators(root)
        self._add_sensors(root)

    @staticmethod
    def _add_defaults(root: mjcf.RootElement) -> None:
        root.default.motor.set_attributes(ctrlrange=[-1, 1], ctrllimited=True)
        body = root.default.add("default", dclass="body")
        body.geom.set_attributes(
            type="capsule", condim=1, friction=[0.7], solimp=[0.9, 0.99, 0.003],
            solref=[0.015, 1], material="self",
        )  # fmt: skip
        body.joint.set_attributes(
            type="hinge", damping=0.2, stiffness=1, armature=0.01, limited=True,
            solimplimit=[0, 0.99, 0.01],
        )  # fmt: skip
        big_joint = body.add("default", dclass="big_joint")
        big_joint.joint.set_attributes(damping=5, stiffness=10)
        big_joint.add("default", dclass="big_stiff_joint").joint.stiffness = 20
        body.site.set_attributes(size=[0.04], group=3)
        force_torque = body.add("default", dclass="force-torque")
        force_torque.site.set_attributes(type="box", size=[0.01, 0.01, 0.02], rgba=[1, 0, 0, 1])
        body.add("default", dclass="touch").site.set_attributes(type="capsule",
                                                                rgba=[0, 0, 1, 0.3])  # fmt: skip

    def _touch_site(self, body: mjcf.Element, name: str, **attributes: object) -> None:
        self._touch_sites.append(body.add("site", name=name, dclass="touch", **attributes))

    def _force_torque_site(self, body: mjcf.Element, name: str, **attributes: object) -> None:
        self._sites[name] = body.add("site", name=name, dclass="force-torque", **attributes)

    def _add_waist(self, torso: mjcf.Element) -> mjcf.Element:
        """The lower waist and the pelvis (abdomen z, y, then x); returns the pelvis."""
        waist = torso.add("body", name="lower_waist", pos=[-0.01, 0, -0.26],
                          quat=[1, 0, -0.002, 0])  # fmt: skip
        waist.add("geom", name="lower_waist", fromto=[0, -0.06, 0, 0, 0.06, 0], size=[0.06])
        self._touch_site(waist, "lower_waist", size=[0.061, 0.06], zaxis=[0, 1, 0])
        waist.add("joint", name="abdomen_z", pos=[0, 0, 0.065], axis=[0, 0, 1],
                  range=[-45, 45], dclass="big_stiff_joint")  # fmt: skip
        waist.add("joint", name="abdomen_y", pos=[0, 0, 0.065], axis=[0, 1, 0],
                  range=[-75, 30], dclass="big_joint")  # fmt: skip
        pelvis = waist.add("body", name="pelvis", pos=[0, 0, -0.165], quat=[1, 0, -0.002, 0])
        pelvis.add("joint", name="abdomen_x", pos=[0, 0, 0.1], axis=[1, 0, 0],
                   range=[-35, 35], dclass="big_joint")  # fmt: skip
        pelvis.add("geom", name="butt", fromto=[-0.02, -0.07, 0, -0.02, 0.07, 0], size=[0.09])
        self._touch_site(pelvis, "butt", size=[0.091, 0.07], pos=[-0.02, 0, 0], zaxis=[0, 1, 0])
        return pelvis

    def _add_leg(self, pelvis: mjcf.Element, side: str, sign: int) -> mjcf.Element:
        """One leg (thigh, shin, foot) on `side`, mirrored by `sign`; returns the foot."""
        thigh = pelvis.add("body", name=f"{side}_thigh", pos=[0, 0.1 * sign, -0.04])
        self._force_torque_site(thigh, f"{side}_hip")
        hip_y_low = -110 if side == "right" else -120
        for axis_name, axis, joint_range, dclass in (
            ("x", [-sign, 0, 0], [-25, 5], "big_joint"),
            ("z", [0, 0, -sign], [-60, 35], "big_joint"),
            ("y", [0, 1, 0], [hip_y_low, 20], "big_stiff_joint"),
        ):
            thigh.add("joint", name=f"{side}_hip_{axis_name}", axis=axis, range=joint_range,
                      dclass=dclass)  # fmt: skip
        thigh.add("geom", name=f"{side}_thigh", fromto=[0, 0, 0, 0, -0.01 * sign, -0.34],
                  size=[0.06])  # fmt: skip
        self._touch_site(thigh, f"{side}_thigh", pos=[0, -0.005 * sign, -0.17],
                         size=[0.061, 0.17], zaxis=[0, sign, 34])  # fmt: skip
        shin = thigh.add("body", name=f"{side}_shin", pos=[0, -0.01 * sign, -0.403])
        self._force_torque_site(shin, f"{side}_knee", pos=[0, 0, 0.02])
        shin.add("joint", name=f"{side}_knee", pos=[0, 0, 0.02], axis=[0, -1, 0],
                 range=[-160, 2])  # fmt: skip
        shin.add("geom", name=f"{side}_shin", fromto=[0, 0, 0, 0, 0, -0.3], size=[0.049])
        self._touch_site(shin, f"{side}_shin", pos=[0, 0, -0.15], size=[0.05, 0.15])
        foot = shin.add("body", name=f"{side}_foot", pos=[0, 0, -0.39])
        self._force_torque_site(foot, f"{side}_ankle")
        foot.add("joint", name=f"{side}_ankle_y", pos=[0, 0, 0.08], axis=[0, 1, 0],
                 range=[-50, 50], stiffness=6)  # fmt: skip
        foot.add("joint", name=f"{side}_ankle_x", pos=[0, 0, 0.04], axis=[1, 0, 0.5],
                 range=[-50, 50], stiffness=3)  # fmt: skip
        # Two toe capsules, the outer one first; their touch sites right one first.
        other = "left" if side == "right" else "right"
        outer, inner = f"{side}_{side}_foot", f"{other}_{side}_foot"
        foot.add("geom", name=outer, fromto=[-0.07, 0.02 * sign, 0, 0.14, 0.04 * sign, 0],
                 size=[0.027])  # fmt: skip
        foot.add("geom", name=inner, fromto=[-0.07, 0, 0, 0.14, -0.02 * sign, 0], size=[0.027])
        toe_sites = (
            (outer, [0.035, 0.03 * sign, 0], [21, 2 * sign, 0]),
            (inner, [0.035, -0.01 * sign, 0], [21, -2 * sign, 0]),
        )
        for toe, pos, zaxis in toe_sites if side == "right" else toe_sites[::-1]:
            self._touch_site(foot, toe, pos=pos, size=[0.03, 0.11], zaxis=zaxis)
        return foot

    def _add_arm(self, torso: mjcf.Element, side: str, sign: int) -> mjcf.Element:
        """One arm (upper arm, lower arm, hand) on `side`, mirrored by `sign`; returns the
        hand."""
        upper = torso.add("body", name=f"{side}_upper_arm", pos=[0, 0.17 * sign, 0.06])
        shoulder_range = [-85, 60] if side == "right" else [-60, 85]
        upper.add("joint", name=f"{side}_shoulder1", axis=[2, -sign, 1], range=shoulder_range)
        upper.add("joint", name=f"{side}_shoulder2", axis=[0, sign, 1], range=shoulder_range)
        upper.add("geom", name=f"{side}_upper_arm", fromto=[0, 0, 0, 0.16, 0.16 * sign, -0.16],
                  size=[0.04, 0.16])  # fmt: skip
        self._touch_site(upper, f"{side}_upper_arm", pos=[0.08, 0.08 * sign, -0.08],
                         size=[0.041, 0.14], zaxis=[1, sign, -1])  # fmt: skip
        lower = upper.add("body", name=f"{side}_lower_arm", pos=[0.18, 0.18 * sign, -0.18])
        lower.add("joint", name=f"{side}_elbow", axis=[0, -1, -sign], range=[-90, 50],
                  stiffness=0)  # fmt: skip
        lower.add(
            "geom", name=f"{side}_lower_arm",
            fromto=[0.01, -0.01 * sign, 0.01, 0.17, -0.17 * sign, 0.17], size=[0.031],
        )  # fmt: skip
        self._touch_site(lower, f"{side}_lower_arm", pos=[0.09, -0.09 * sign, 0.09],
                         size=[0.032, 0.14], zaxis=[1, -sign, 1])  # fmt: skip
        hand = lower.add("body", name=f"{side}_hand", pos=[0.18, -0.18 * sign, 0.18])
        hand.add("geom", name=f"{side}_hand", type="sphere", size=[0.04])
        self._touch_site(hand, f"{side}_hand", type="sphere", size=[0.041])
        return hand

    def _add_actuators(self, root: mjcf.RootElement) -> None:
        gears = [*_WAIST_GEARS]
        for table in (_LEG_GEARS, _ARM_GEARS):
            gears += [
                (joint.format(side=side), gear) for side, _ in _SIDES for joint, gear in table
            ]
        self.motors = tuple(
            root.actuator.add("motor", name=joint, gear=[gear], joint=joint)
            for joint, gear in gears
        )

    def _add_sensors(self, root: mjcf.RootElement) -> None:
        sensor = root.sensor
        self.subtree_velocity = sensor.add(
            "subtreelinvel", name="torso_subtreelinvel", body=self.torso
        )
        imu = self._sites["root"]
        sensor.add("accelerometer", name="torso_accel", site=imu)
        sensor.add("velocimeter", name="torso_vel", site=imu)
        sensor.add("gyro", name="torso_gyro", site=imu)
        for kind in ("force", "torque"):
            for name in _FORCE_TORQUE_SITES:
                sensor.add(kind, name=f"{name}_{kind}", site=self._sites[name])
        for touch in self._touch_sites:
            sensor.add("touch", name=f"{touch.name}_touch", site=touch)
