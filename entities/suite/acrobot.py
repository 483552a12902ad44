"""The Control Suite's acrobot: a two-link pendulum actuated at the elbow only.

    acrobot = Acrobot()
    arena.attach(acrobot)
    physics.bind(acrobot.joints).qpos             # shoulder and elbow angles
    physics.bind([acrobot.tip, acrobot.target]).xpos   # the tip and where it should be

The numbers are the suite's (`acrobot.xml`, Coulom's acrobot rather than Spong's):
`Acrobot` lists them.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials


class Acrobot(composer.Entity):
    """The suite's acrobot.

    The numbers are the suite's (`acrobot.xml`, Coulom's acrobot rather than Spong's): two
    1 m capsules of 1 kg, the shoulder 2 m above the floor, both hinges damped at 0.05, a
    2 N m motor at the elbow, RK4 at 10 ms, no constraints. The target site, 0.2 m in
    radius, is where the tip is when both links point straight up; the camera `fixed` looks
    at it from the front, `lookat` follows the upper arm.
    """

    def _build(self, name: str = "acrobot") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.option.set_attributes(timestep=0.01, integrator="RK4")
        root.option.flag.set_attributes(constraint="disable", energy="enable")
        root.default.joint.damping = 0.05
        root.default.geom.set_attributes(type="capsule", mass=1)
        add_materials(root)
        world = root.worldbody
        self.target = world.add(
            "site", name="target", type="sphere", pos=[0, 0, 4], size=[0.2], material="target",
            group=3,
        )  # fmt: skip
        self.upper_arm = world.add("body", name="upper_arm", pos=[0, 0, 2])
        self.shoulder = self.upper_arm.add("joint", name="shoulder", type="hinge", axis=[0, 1, 0])
        self.upper_arm.add(
            "geom", name="upper_arm_decoration", material="decoration", type="cylinder",
            fromto=[0, -0.06, 0, 0, 0.06, 0], size=[0.051], mass=0,
        )  # fmt: skip
        self.upper_arm.add(
            "geom", name="upper_arm", fromto=[0, 0, 0, 0, 0, 1], size=[0.05], material="self"
        )
        self.lower_arm = self.upper_arm.add("body", name="lower_arm", pos=[0, 0, 1])
        self.elbow = self.lower_arm.add("joint", name="elbow", type="hinge", axis=[0, 1, 0])
        self.lower_arm.add(
            "geom", name="lower_arm", fromto=[0, 0, 0, 0, 0, 1], size=[0.049], material="self"
        )
        self.tip = self.lower_arm.add("site", name="tip", pos=[0, 0, 1], size=[0.01])
        self.arms = (self.upper_arm, self.lower_arm)
        self.joints = (self.shoulder, self.elbow)
        self.cameras = (
            world.add("camera", name="fixed", pos=[0, -6, 2], zaxis=[0, -1, 0]),
            world.add(
                "camera", name="lookat", mode="targetbodycom", target=self.upper_arm,
                pos=[0, -2, 3],
            ),
        )  # fmt: skip
        self.motor = root.actuator.add(
            "motor", name="elbow", joint=self.elbow, gear=[2], ctrllimited=True,
            ctrlrange=[-1, 1],
        )  # fmt: skip
