"""The Control Suite's finger: a two-link planar finger that turns a spinner on a hinge.

    finger = Finger()
    arena.attach(finger)
    physics.bind(finger.sensors).sensordata       # every observation the tasks make
    physics.bind(finger.hinge).qpos               # the spinner's angle

The numbers are the suite's (`finger.xml`): `Finger` lists them.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials

# The soft contacts of every geom, the world's floor too (the file's top-level default).
SOLIMP, SOLREF = (0.0, 0.9, 0.01), (0.02, 1.0)


class Finger(composer.Entity):
    """The suite's finger and spinner.

    The numbers are the suite's (`finger.xml`): a finger of a 17 cm and a 16 cm capsule on
    hinges limited to +-110 degrees (the proximal one's reference at -90), damped at 2.5,
    its motors of gear 30 and 15; a spinner of two capsules of 4 cm radius on an unactuated
    hinge with friction loss 0.1 and damping 0.5, a `tip` site 13 cm from its axis; no
    gravity, soft contacts (solimp 0 0.9 0.01, solref 0.02 1, which the world's floor
    shares), an elliptic friction cone, 200 solver iterations, Euler at 10 ms. Two touch
    sensors sit at the fingertip. Every observation the suite's tasks make is a sensor (in
    the file's order, `sensors`), so that they can be finite-differenced. The world's
    `target` site marks where the tip should go. The cameras `cam0` and `cam1` look at it
    from the front.
    """

    def _build(self, name: str = "finger") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.option.set_attributes(timestep=0.01, cone="elliptic", iterations=200)
        root.option.flag.gravity = "disable"
        root.default.geom.set_attributes(solimp=list(SOLIMP), solref=list(SOLREF))
        root.default.joint.set_attributes(type="hinge", axis=[0, -1, 0])
        root.default.motor.set_attributes(ctrllimited=True, ctrlrange=[-1, 1])
        link = root.default.add("default", dclass="finger")
        link.joint.set_attributes(damping=2.5, limited=True)
        link.site.set_attributes(
            type="ellipsoid", size=[0.025, 0.03, 0.025], material="site", group=3
        )
        add_materials(root)
        world = root.worldbody
        self.cameras = tuple(
            world.add("camera", name=f"cam{index}", pos=[0, -1, height], xyaxes=xyaxes)
            for index, (height, xyaxes) in enumerate(
                ((0.8, [1, 0, 0, 0, 1, 2]), (0.4, [1, 0, 0, 0, 0, 1]))
            )
        )
        self.proximal = world.add("body", name="proximal", pos=[-0.2, 0, 0.4], childclass=link)
        self.proximal.add(
            "geom", name="proximal_decoration", type="cylinder",
            fromto=[0, -0.033, 0, 0, 0.033, 0], size=[0.034], material="decoration",
        )  # fmt: skip
        proximal_joint = self.proximal.add("joint", name="proximal", range=[-110, 110], ref=-90)
        self.proximal.add(
            "geom", name="proximal", type="capsule", material="self", size=[0.03],
            fromto=[0, 0, 0, 0, 0, -0.17],
        )  # fmt: skip
        self.distal = self.proximal.add("body", name="distal", pos=[0, 0, -0.18], childclass=link)
        distal_joint = self.distal.add("joint", name="distal", range=[-110, 110])
        self.distal.add(
            "geom", name="distal", type="capsule", size=[0.028], material="self",
            fromto=[0, 0, 0, 0, 0, -0.16], contype=0, conaffinity=0,
        )  # fmt: skip
        self.distal.add(
            "geom", name="fingertip", type="capsule", size=[0.03], material="effector",
            fromto=[0, 0, -0.13, 0, 0, -0.161],
        )  # fmt: skip
        touch_sites = tuple(
            self.distal.add("site", name=f"touch{side}", pos=[x, 0, -0.17])
            for side, x in (("top", 0.01), ("bottom", -0.01))
        )
        self.joints = (proximal_joint, distal_joint)
        self.spinner = world.add("body", name="spinner", pos=[0.2, 0, 0.4])
        self.hinge = self.spinner.add("joint", name="hinge", frictionloss=0.1, damping=0.5)
        self.caps = tuple(
            self.spinner.add(
                "geom", name=f"cap{index}", type="capsule", size=[0.04, 0.09],
                material="self", pos=[x, 0, 0],
            )
            for index, x in ((1, 0.02), (2, -0.02))
        )  # fmt: skip
        self.tip = self.spinner.add(
            "site", name="tip", type="sphere", size=[0.02], pos=[0, 0, 0.13], material="target"
        )
        self.spinner.add(
            "geom", name="spinner_decoration", type="cylinder",
            fromto=[0, -0.045, 0, 0, 0.045, 0], size=[0.02], material="decoration",
        )  # fmt: skip
        self.target = world.add(
            "site", name="target", type="sphere", size=[0.03], pos=[0, 0, 0.4],
            material="target",
        )  # fmt: skip
        self.motors = tuple(
            root.actuator.add("motor", name=joint.name, joint=joint, gear=[gear])
            for joint, gear in zip(self.joints, (30, 15), strict=True)
        )
        self._add_sensors(root, touch_sites)

    def _add_sensors(self, root: mjcf.RootElement, touch_sites: tuple[mjcf.Element, ...]) -> None:
        """The file's sensors, in its order, as attributes named for what they measure."""
        sensor = root.sensor
        self.joint_positions = tuple(
            sensor.add("jointpos", name=joint.name, joint=joint) for joint in self.joints
        )
        self.joint_velocities = tuple(
            sensor.add("jointvel", name=f"{joint.name}_velocity", joint=joint)
            for joint in (*self.joints, self.hinge)
        )
        self.tip_position, self.target_position, self.spinner_position = (
            sensor.add("framepos", name=name, objtype=kind, objname=element)
            for name, kind, element in (
                ("tip", "site", self.tip), ("target", "site", self.target),
                ("spinner", "xbody", self.spinner),
            )
        )  # fmt: skip
        self.touches = tuple(sensor.add("touch", name=site.name, site=site) for site in touch_sites)
        self.touch_positions = tuple(
            sensor.add("framepos", name=f"{site.name}_pos", objtype="site", objname=site)
            for site in touch_sites
        )
        self.sensors = (
            *self.joint_positions, *self.joint_velocities, self.tip_position,
            self.target_position, self.spinner_position, *self.touches, *self.touch_positions,
        )  # fmt: skip
