"""The Control Suite's planar arm: the four-link arm with a two-fingered hand that the
manipulator and stacker domains share (dm_control's `manipulator.xml` and `stacker.xml`).

    arm = add_planar_arm(root, contact_solref=(0.005, 1))   # into a robot's own model
    physics.bind(arm.joints).qpos        # dm_control's _ARM_JOINTS: root ... thumbtip
    physics.bind(arm.touch_sensors).sensordata             # palm, finger, thumb, tips
    physics.bind(arm.grasp).xpos         # the site between the fingers' tips

The numbers are the suite's (`add_planar_arm` lists them). The model's top-level defaults
apply to everything in it, props included; only the contacts' `solref` differs by domain.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import mjcf
from entities.suite.materials import add_materials

# The joints in the order the suite's tasks observe and randomize them.
ARM_JOINTS = (
    "arm_root", "arm_shoulder", "arm_elbow", "arm_wrist", "finger", "fingertip", "thumb",
    "thumbtip",
)  # fmt: skip
TOUCH_SENSORS = ("palm_touch", "finger_touch", "thumb_touch", "fingertip_touch", "thumbtip_touch")


@dataclasses.dataclass(frozen=True)
class PlanarArm:
    """The elements of a planar arm that tasks use: `joints` in ARM_JOINTS' order, the
    `hand` body, the `grasp` and `pinch` sites (between the fingers, at the palm and at the
    tips), `touch_sensors` in TOUCH_SENSORS' order, the five `actuators`, and the `hand`
    camera, which follows the fingers' tips."""

    joints: tuple[mjcf.Element, ...]
    hand: mjcf.Element
    grasp: mjcf.Element
    pinch: mjcf.Element
    touch_sensors: tuple[mjcf.Element, ...]
    actuators: tuple[mjcf.Element, ...]
    camera: mjcf.Element


def _add_defaults(root: mjcf.RootElement, contact_solref: Sequence[float]) -> None:
    main = root.default
    main.geom.set_attributes(friction=[0.7], solimp=[0.9, 0.97, 0.001], solref=contact_solref)
    main.joint.set_attributes(solimplimit=[0, 0.99, 0.01], solreflimit=[0.005, 1])
    main.general.ctrllimited = True
    main.tendon.width = 0.01
    main.site.set_attributes(size=[0.003] * 3, material="site", group=3)
    arm = main.add("default", dclass="arm")
    arm.geom.set_attributes(type="capsule", material="self", density=500)
    arm.joint.set_attributes(type="hinge", pos=[0, 0, 0], axis=[0, -1, 0], limited=True)
    hand = arm.add("default", dclass="hand")
    hand.joint.set_attributes(damping=0.5, range=[-10, 60])
    hand.geom.size = [0.008]
    hand.site.set_attributes(
        type="box", size=[0.018, 0.005, 0.005], pos=[0.022, 0, -0.002], euler=[0, 15, 0], group=4
    )
    fingertip = hand.add("default", dclass="fingertip")
    fingertip.geom.set_attributes(type="sphere", size=[0.008], material="effector")
    fingertip.joint.set_attributes(damping=0.01, stiffness=0.01, range=[-40, 20])
    fingertip.site.set_attributes(
        size=[0.012, 0.005, 0.008], pos=[0.003, 0, 0.003], group=4, euler=[0, 0, 0]
    )
    main.add("default", dclass="object").geom.material = "self"
    obstacle = main.add("default", dclass="obstacle")
    obstacle.geom.set_attributes(material="decoration", friction=[0])
    ghost = main.add("default", dclass="ghost")
    ghost.geom.set_attributes(material="target", contype=0, conaffinity=0)


def _add_digit(
    hand: mjcf.Element, name: str, tip: str, **pose: object
) -> tuple[mjcf.Element, mjcf.Element]:
    """A thumb or finger (two capsules and a touch site) with its two-sphere tip; returns
    the digit's joint and its tip's."""
    digit = hand.add("body", name=name, childclass="hand", **pose)
    joint = digit.add("joint", name=name)
    digit.add("geom", name=f"{name}1", fromto=[0, 0, 0, 0.02, 0, -0.01], size=[0.007])
    digit.add("geom", name=f"{name}2", fromto=[0.02, 0, -0.01, 0.04, 0, -0.01], size=[0.007])
    digit.add("site", name=f"{name}_touch")
    end = digit.add("body", name=tip, pos=[0.05, 0, -0.01], childclass="fingertip")
    tip_joint = end.add("joint", name=tip)
    end.add("geom", name=f"{tip}1", pos=[-0.003, 0, 0])
    end.add("geom", name=f"{tip}2", pos=[0.003, 0, 0])
    end.add("site", name=f"{tip}_touch")
    return joint, tip_joint


def add_planar_arm(root: mjcf.RootElement, contact_solref: Sequence[float]) -> PlanarArm:
    """Add the planar arm to `root`: its options, defaults (contacts with
    `contact_solref`), materials, backdrop, bodies, tendons, coupling, touch sensors and
    motors. Returns its elements; props go into `root`'s world body after it.

    The numbers are the suite's: an arm rooted at 0.4 m on an unlimited hinge, three
    limited hinges (+-160, +-160, +-140 degrees), a hand whose thumb and finger are coupled
    by a tendon equality so that one motor (`grasp`) closes both, five touch sensors and
    five motors (gears 12, 8, 4, 2 and 2 on the grasp tendon, controls in [-1, 1]). A
    grey-blue backdrop plane (`background`) behind the scene comes first, as in the suite's
    files, with its texture and material after the suite's robot materials.
    """
    root.option.set_attributes(timestep=0.001, cone="elliptic")
    _add_defaults(root, list(contact_solref))
    add_materials(root)
    root.asset.add(
        "texture", name="background", builtin="flat", type="2d", mark="random",
        markrgb=[1, 1, 1], width=800, height=800, rgb1=[0.2, 0.3, 0.4],
    )  # fmt: skip
    root.asset.add(
        "material", name="background", texture="background", texrepeat=[1, 1], texuniform=True
    )
    world = root.worldbody
    world.add(
        "geom", name="background", type="plane", pos=[0, 0.2, 0.5], size=[1, 0.5, 10],
        material="background", zaxis=[0, -1, 0],
    )  # fmt: skip
    world.add(
        "geom", name="arm_root", type="cylinder", fromto=[0, -0.022, 0.4, 0, 0.022, 0.4],
        size=[0.024], material="decoration", contype=0, conaffinity=0,
    )  # fmt: skip
    upper = world.add("body", name="upper_arm", pos=[0, 0, 0.4], childclass="arm")
    joints = {"arm_root": upper.add("joint", name="arm_root", damping=2, limited=False)}
    upper.add("geom", name="upper_arm", size=[0.02], fromto=[0, 0, 0, 0, 0, 0.18])
    middle = upper.add("body", name="middle_arm", pos=[0, 0, 0.18], childclass="arm")
    joints["arm_shoulder"] = middle.add(
        "joint", name="arm_shoulder", damping=1.5, range=[-160, 160]
    )
    middle.add("geom", name="middle_arm", size=[0.017], fromto=[0, 0, 0, 0, 0, 0.15])
    lower = middle.add("body", name="lower_arm", pos=[0, 0, 0.15])
    joints["arm_elbow"] = lower.add("joint", name="arm_elbow", damping=1, range=[-160, 160])
    lower.add("geom", name="lower_arm", size=[0.014], fromto=[0, 0, 0, 0, 0, 0.12])
    hand = lower.add("body", name="hand", pos=[0, 0, 0.12])
    joints["arm_wrist"] = hand.add("joint", name="arm_wrist", damping=0.5, range=[-140, 140])
    hand.add("geom", name="hand", size=[0.011], fromto=[0, 0, 0, 0, 0, 0.03])
    hand.add("geom", name="palm1", fromto=[0, 0, 0.03, 0.03, 0, 0.045], dclass="hand")
    hand.add("geom", name="palm2", fromto=[0, 0, 0.03, -0.03, 0, 0.045], dclass="hand")
    grasp = hand.add("site", name="grasp", pos=[0, 0, 0.065])
    pinch_body = hand.add("body", name="pinch site", pos=[0, 0, 0.09])
    pinch = pinch_body.add("site", name="pinch")
    pinch_body.add("inertial", pos=[0, 0, 0], mass=1e-6, diaginertia=[1e-12] * 3)
    camera = pinch_body.add(
        "camera", name="hand", pos=[0, -0.3, 0], xyaxes=[1, 0, 0, 0, 0, 1], mode="track"
    )
    hand.add(
        "site", name="palm_touch", type="box", group=4, size=[0.025, 0.005, 0.008],
        pos=[0, 0, 0.043],
    )  # fmt: skip
    for digit, tip, pose in (
        ("thumb", "thumbtip", {"pos": [0.03, 0, 0.045], "euler": [0, -90, 0]}),
        ("finger", "fingertip", {"pos": [-0.03, 0, 0.045], "euler": [0, 90, 180]}),
    ):
        joints[digit], joints[tip] = _add_digit(hand, digit, tip, **pose)

    for name, coefficients in (("grasp", (0.5, 0.5)), ("coupling", (-0.5, 0.5))):
        tendon = root.tendon.add("fixed", name=name)
        for joint, coefficient in zip(("thumb", "finger"), coefficients, strict=True):
            tendon.add("joint", joint=joint, coef=coefficient)
    root.equality.add(
        "tendon", name="coupling", tendon1="coupling", solimp=[0.95, 0.99, 0.001],
        solref=[0.005, 0.5],
    )  # fmt: skip
    sensors = tuple(root.sensor.add("touch", name=name, site=name) for name in TOUCH_SENSORS)
    actuators = tuple(
        root.actuator.add("motor", name=name, ctrlrange=[-1, 1], gear=[gear], **target)
        for name, gear, target in (
            ("root", 12, {"joint": "arm_root"}),
            ("shoulder", 8, {"joint": "arm_shoulder"}),
            ("elbow", 4, {"joint": "arm_elbow"}),
            ("wrist", 2, {"joint": "arm_wrist"}),
            ("grasp", 2, {"tendon": "grasp"}),
        )
    )
    arm_joints = tuple(joints[name] for name in ARM_JOINTS)
    return PlanarArm(arm_joints, hand, grasp, pinch, sensors, actuators, camera)
