"""The Control Suite's half cheetah: a planar runner of a torso, a head and two three-part legs.

    cheetah = Cheetah()
    arena.attach(cheetah)
    physics.bind(cheetah.speed_sensor).sensordata      # the torso subtree's linear velocity
    physics.bind(cheetah.joints).qpos                  # rootx, rootz, rooty, then the legs

The numbers are the suite's (`cheetah.xml`): `Cheetah` lists them.
"""

from __future__ import annotations

import mujoco

import composer
import mjcf
from entities.suite.materials import add_materials

# (name, position in its parent, joint range (degrees), stiffness, damping,
#  geom position, geom euler (degrees), geom half-length, motor gear): the back leg
# from the thigh down, then the front one.
_LEGS = (
    (
        ("bthigh", (-0.5, 0, 0), (-30, 60), 240, 6, (0.1, 0, -0.13), -218, 0.145, 120),
        ("bshin", (0.16, 0, -0.25), (-50, 50), 180, 4.5, (-0.14, 0, -0.07), -116, 0.15, 90),
        ("bfoot", (-0.28, 0, -0.14), (-230, 50), 120, 3, (0.03, 0, -0.097), -15, 0.094, 60),
    ),
    (
        ("fthigh", (0.5, 0, 0), (-57, 0.4), 180, 4.5, (-0.07, 0, -0.12), 30, 0.133, 90),
        ("fshin", (-0.14, 0, -0.24), (-70, 50), 120, 3, (0.065, 0, -0.09), -34, 0.106, 60),
        ("ffoot", (0.13, 0, -0.18), (-28, 28), 60, 1.5, (0.045, 0, -0.07), -34, 0.07, 30),
    ),
)
_RADIUS = 0.046
_TOTAL_MASS = 14.0


class Cheetah(composer.Entity):
    """The suite's half cheetah.

    The numbers are the suite's (`cheetah.xml`): capsules of radius 0.046 with friction 0.4,
    scaled to a total mass of 14 kg (`_scale_to_total_mass`); the torso slides in x and z
    and turns about y, freely; each leg's thigh, shin and foot hinges are limited, sprung
    (stiffness 240 ... 60) and damped, and driven by motors of gear 120, 90, 60 (back) and
    90, 60, 30 (front); 10 ms steps. A light and the cameras `side` and `back` follow the
    torso's centre of mass.
    """

    def _build(self, name: str = "cheetah") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.statistic.set_attributes(center=[0, 0, 0.7], extent=2)
        root.option.timestep = 0.01
        add_materials(root)
        cheetah = root.default.add("default", dclass="cheetah")
        cheetah.joint.set_attributes(
            limited=True, damping=0.01, armature=0.1, stiffness=8, type="hinge", axis=[0, 1, 0]
        )
        cheetah.geom.set_attributes(
            contype=1, conaffinity=1, condim=3, friction=[0.4, 0.1, 0.1], material="self"
        )
        free = root.default.add("default", dclass="free")
        free.joint.set_attributes(limited=False, damping=0, armature=0, stiffness=0)
        root.default.motor.set_attributes(ctrllimited=True, ctrlrange=[-1, 1])

        torso = self.torso = root.worldbody.add(
            "body", name="torso", pos=[0, 0, 0.7], childclass=cheetah
        )
        torso.add("light", name="light", pos=[0, 0, 2], mode="trackcom")
        self.cameras = (
            torso.add(
                "camera", name="side", pos=[0, -3, 0], quat=[0.707, 0.707, 0, 0], mode="trackcom"
            ),
            torso.add(
                "camera", name="back", pos=[-1.8, -1.3, 0.8],
                xyaxes=[0.45, -0.9, 0, 0.3, 0.15, 0.94], mode="trackcom",
            ),
        )  # fmt: skip
        self.root_joints = (
            torso.add("joint", name="rootx", type="slide", axis=[1, 0, 0], dclass=free),
            torso.add("joint", name="rootz", type="slide", axis=[0, 0, 1], dclass=free),
            torso.add("joint", name="rooty", type="hinge", axis=[0, 1, 0], dclass=free),
        )
        torso.add("geom", name="torso", type="capsule", fromto=[-0.5, 0, 0, 0.5, 0, 0],
                  size=[_RADIUS])  # fmt: skip
        torso.add("geom", name="head", type="capsule", pos=[0.6, 0, 0.1], euler=[0, 50, 0],
                  size=[_RADIUS, 0.15])  # fmt: skip
        leg_joints, gears = [], []
        for leg in _LEGS:
            parent = torso
            for part, pos, limits, stiffness, damping, geom_pos, pitch, half, gear in leg:
                parent = parent.add("body", name=part, pos=list(pos))
                joint = parent.add("joint", name=part, range=list(limits), stiffness=stiffness,
                                   damping=damping)  # fmt: skip
                leg_joints.append(joint)
                parent.add("geom", name=part, type="capsule", pos=list(geom_pos),
                           euler=[0, pitch, 0], size=[_RADIUS, half])  # fmt: skip
                gears.append(gear)
        self.leg_joints = tuple(leg_joints)
        self.joints = self.root_joints + self.leg_joints
        self.speed_sensor = root.sensor.add("subtreelinvel", name="torso_subtreelinvel", body=torso)
        self.motors = tuple(
            root.actuator.add("motor", name=joint.name, joint=joint, gear=[gear])
            for joint, gear in zip(self.leg_joints, gears, strict=True)
        )
        _scale_to_total_mass(root, _TOTAL_MASS)


def _scale_to_total_mass(root: mjcf.RootElement, total: float) -> None:
    """Give every body of `root` an `<inertial>`: its mass, centre of mass and principal
    inertia as `root` compiled alone computes them from its geoms, mass and inertia scaled
    so that the bodies weigh `total` together.

    This is what the suite's `<compiler settotalmass>` does at compile time, to the last
    bit (the same sum of masses in body order, the same scale, the same products). MuJoCo
    4 deprecates that setting, and in a composed scene it would be converted into scaled
    densities, which round differently; explicit inertials keep the cheetah's masses in its
    model, whatever it is composed with or exported to."""
    model = root.compile_model().model
    unscaled = 0.0
    for mass in model.body_mass[1:]:  # in body order, as MuJoCo sums them
        unscaled += float(mass)
    scale = max(mujoco.mjMINVAL, total / max(mujoco.mjMINVAL, unscaled))
    for index, body in enumerate(root.worldbody.find_all("body"), start=1):
        body.add(
            "inertial", pos=model.body_ipos[index], quat=model.body_iquat[index],
            mass=model.body_mass[index] * scale, diaginertia=model.body_inertia[index] * scale,
        )  # fmt: skip
