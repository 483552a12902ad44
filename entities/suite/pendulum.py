"""The Control Suite's pendulum: a 1 kg mass on a light pole, hinged at its top.

    pendulum = Pendulum()
    arena.attach(pendulum)
    physics.bind(pendulum.hinge).qpos             # the pole's angle from upright
    physics.bind(pendulum.pole).xmat              # its orientation: zz is cos(angle)

The numbers are the suite's (`pendulum.xml`): `Pendulum` lists them.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials


class Pendulum(composer.Entity):
    """The suite's pendulum.

    The numbers are the suite's (`pendulum.xml`): a massless 0.5 m pole, a 1 kg sphere of
    5 cm radius at its tip, a hinge 0.6 m above the floor damped at 0.1, a 1 N m motor,
    Euler at 20 ms, no contacts. The camera `fixed` looks at it from the front, `lookat`
    follows it.
    """

    def _build(self, name: str = "pendulum") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.option.timestep = 0.02
        root.option.flag.set_attributes(contact="disable", energy="enable")
        add_materials(root)
        world = root.worldbody
        self.pole = world.add("body", name="pole", pos=[0, 0, 0.6])
        self.hinge = self.pole.add("joint", name="hinge", type="hinge", axis=[0, 1, 0], damping=0.1)
        self.pole.add(
            "geom", name="base", material="decoration", type="cylinder",
            fromto=[0, -0.03, 0, 0, 0.03, 0], size=[0.021], mass=0,
        )  # fmt: skip
        self.pole.add(
            "geom", name="pole", material="self", type="capsule", fromto=[0, 0, 0, 0, 0, 0.5],
            size=[0.02], mass=0,
        )  # fmt: skip
        self.mass = self.pole.add(
            "geom", name="mass", material="effector", type="sphere", pos=[0, 0, 0.5],
            size=[0.05], mass=1,
        )  # fmt: skip
        self.cameras = (
            world.add("camera", name="fixed", pos=[0, -1.5, 2], xyaxes=[1, 0, 0, 0, 1, 1]),
            world.add(
                "camera", name="lookat", mode="targetbodycom", target=self.pole, pos=[0, -2, 1]
            ),
        )
        self.motor = root.actuator.add(
            "motor", name="torque", joint=self.hinge, gear=[1], ctrlrange=[-1, 1],
            ctrllimited=True,
        )  # fmt: skip
