"""The Control Suite's hopper: a planar one-legged robot of torso, pelvis, thigh, calf and foot.

    hopper = Hopper()
    arena.attach(hopper)
    physics.bind(hopper.touch_sensors).sensordata      # the toe's and the heel's contact force
    physics.bind([hopper.torso, hopper.foot]).xipos    # centres of mass of torso and foot

The numbers are the suite's (`hopper.xml`): `Hopper` lists them.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials

# (body, its position in its parent, joint, joint range (degrees), geom fromto, geom
#  radius, motor gear): the leg from the pelvis down, each body in the previous one.
_LEG = (
    ("pelvis", (0, 0, -0.05), "waist", (-30, 30), (0, 0, 0, 0, 0, -0.15), 0.065, 30),
    ("thigh", (0, 0, -0.2), "hip", (-170, 10), (0, 0, 0, 0, 0, -0.33), 0.04, 40),
    ("calf", (0, 0, -0.33), "knee", (5, 150), (0, 0, 0, 0, 0, -0.32), 0.03, 30),
    ("foot", (0, 0, -0.32), "ankle", (-45, 45), (-0.08, 0, 0, 0.17, 0, 0), 0.04, 10),
)


class Hopper(composer.Entity):
    """The suite's hopper.

    The numbers are the suite's (`hopper.xml`): capsules of the suite's material on hinges
    damped 0.05 with armature 0.2, each limited (waist +-30 degrees, hip -170 to 10, knee 5
    to 150, ankle +-45) and driven by a motor (gear 30, 40, 30, 10); the torso slides in x
    and z and turns about y, freely; touch sensors at the toe and the heel; 5 ms steps. The
    cameras `cam0` and `back` stand in the world and follow the hopper's centre of mass, as
    does its light.
    """

    def _build(self, name: str = "hopper") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.statistic.set_attributes(extent=2, center=[0, 0, 0.5])
        root.option.timestep = 0.005
        add_materials(root)
        hopper = root.default.add("default", dclass="hopper")
        hopper.joint.set_attributes(
            type="hinge", axis=[0, 1, 0], limited=True, damping=0.05, armature=0.2
        )
        hopper.geom.set_attributes(type="capsule", material="self")
        hopper.site.set_attributes(type="sphere", size=[0.05], group=3)
        free = root.default.add("default", dclass="free")
        free.joint.set_attributes(limited=False, damping=0, armature=0, stiffness=0)
        root.default.motor.set_attributes(ctrlrange=[-1, 1], ctrllimited=True)

        world = root.worldbody
        self.cameras = (
            world.add(
                "camera", name="cam0", pos=[0, -2.8, 0.8], euler=[90, 0, 0], mode="trackcom"
            ),
            world.add(
                "camera", name="back", pos=[-2, -0.2, 1.2], xyaxes=[0.2, -1, 0, 0.5, 0, 2],
                mode="trackcom",
            ),
        )  # fmt: skip
        torso = self.torso = world.add("body", name="torso", pos=[0, 0, 1], childclass=hopper)
        torso.add("light", name="top", pos=[0, 0, 2], mode="trackcom")
        self.root_joints = (
            torso.add("joint", name="rootx", type="slide", axis=[1, 0, 0], dclass=free),
            torso.add("joint", name="rootz", type="slide", axis=[0, 0, 1], dclass=free),
            torso.add("joint", name="rooty", type="hinge", axis=[0, 1, 0], dclass=free),
        )
        torso.add("geom", name="torso", fromto=[0, 0, -0.05, 0, 0, 0.2], size=[0.0653])
        torso.add("geom", name="nose", fromto=[0.08, 0, 0.13, 0.15, 0, 0.14], size=[0.03])
        parent, joints, gears = torso, [], []
        for body, pos, joint, limits, fromto, radius, gear in _LEG:
            parent = parent.add("body", name=body, pos=list(pos))
            joints.append(parent.add("joint", name=joint, range=list(limits)))
            parent.add("geom", name=body, fromto=list(fromto), size=[radius])
            gears.append(gear)
        self.foot = parent
        sites = (
            parent.add("site", name="touch_toe", pos=[0.17, 0, 0]),
            parent.add("site", name="touch_heel", pos=[-0.08, 0, 0]),
        )
        self.leg_joints = tuple(joints)
        self.speed_sensor = root.sensor.add("subtreelinvel", name="torso_subtreelinvel", body=torso)
        self.touch_sensors = tuple(
            root.sensor.add("touch", name=site.name, site=site) for site in sites
        )
        self.motors = tuple(
            root.actuator.add("motor", name=joint.name, joint=joint, gear=[gear])
            for joint, gear in zip(self.leg_joints, gears, strict=True)
        )
