"""The Control Suite's reacher: a two-link planar arm reaching for a target.

    reacher = Reacher()
    arena.attach(reacher)
    physics.bind(reacher.joints).qpos             # shoulder and wrist angles
    physics.bind([reacher.finger, reacher.target]).xpos

The numbers are the suite's (`reacher.xml`): `Reacher` lists them.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials
from entities.suite.walls import add_walls


class Reacher(composer.Entity):
    """The suite's reacher.

    The numbers are the suite's (`reacher.xml`): an arm of two 1 cm capsules, 12 and 10 cm
    long, on hinges about z damped at 0.01 (the wrist limited to +-160 degrees), with a 1 cm
    sphere `finger` 12 cm beyond the wrist, in the 0.6 m square of walls
    (`entities.suite.walls`), two motors of gear 0.05, Euler at 20 ms, no contacts. The
    target is a sphere in the plane of the arm, 5 cm in radius as compiled (a task may
    resize and move it). The camera `fixed` looks down on the square, `hand` follows the
    finger.
    """

    def _build(self, name: str = "reacher") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.option.timestep = 0.02
        root.option.flag.contact = "disable"
        root.default.joint.set_attributes(type="hinge", axis=[0, 0, 1], damping=0.01)
        root.default.motor.set_attributes(gear=[0.05], ctrlrange=[-1, 1], ctrllimited=True)
        add_materials(root)
        world = root.worldbody
        fixed = world.add("camera", name="fixed", pos=[0, 0, 0.75], quat=[1, 0, 0, 0])
        self.walls = add_walls(world)
        world.add(
            "geom", name="root", type="cylinder", fromto=[0, 0, 0, 0, 0, 0.02], size=[0.011],
            material="decoration",
        )  # fmt: skip
        self.arm = world.add("body", name="arm", pos=[0, 0, 0.01])
        self.arm.add(
            "geom", name="arm", type="capsule", fromto=[0, 0, 0, 0.12, 0, 0], size=[0.01],
            material="self",
        )  # fmt: skip
        self.shoulder = self.arm.add("joint", name="shoulder")
        self.hand = self.arm.add("body", name="hand", pos=[0.12, 0, 0])
        self.hand.add(
            "geom", name="hand", type="capsule", fromto=[0, 0, 0, 0.1, 0, 0], size=[0.01],
            material="self",
        )  # fmt: skip
        self.wrist = self.hand.add("joint", name="wrist", limited=True, range=[-160, 160])
        fingertip = self.hand.add("body", name="finger", pos=[0.12, 0, 0])
        follow = fingertip.add("camera", name="hand", pos=[0, 0, 0.2], mode="track")
        self.finger = fingertip.add(
            "geom", name="finger", type="sphere", size=[0.01], material="effector"
        )
        self.target = world.add(
            "geom", name="target", pos=[0, 0, 0.01], material="target", type="sphere",
            size=[0.05],
        )  # fmt: skip
        self.cameras = (fixed, follow)
        self.joints = (self.shoulder, self.wrist)
        self.motors = tuple(
            root.actuator.add("motor", name=joint.name, joint=joint) for joint in self.joints
        )
