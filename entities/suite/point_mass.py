"""The Control Suite's point mass: a ball sliding in a plane, pushed through two tendons.

    point_mass = PointMass()
    arena.attach(point_mass)
    physics.bind(point_mass.joints).qpos          # its x and y
    physics.bind(point_mass.target).xpos          # the target it should reach

The numbers are the suite's (`point_mass.xml`): `PointMass` lists them.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials
from entities.suite.walls import add_walls


class PointMass(composer.Entity):
    """The suite's point mass.

    The numbers are the suite's (`point_mass.xml`): a 0.3 kg ball of 1 cm radius on two
    slide joints limited to +-0.29 m, damped at 1, inside the 0.6 m square of walls
    (`entities.suite.walls`), Euler at 20 ms, no contacts. Each motor (gear 0.1) pulls a
    fixed tendon, `t1` along x and `t2` along y: a task may change the tendons' coefficients
    (MjModel `wrap_prm`) so that each motor pushes along another direction. The target is a
    1.5 cm sphere at the centre. The camera `fixed` looks down on the square, `cam0` rides
    with the ball.
    """

    def _build(self, name: str = "point_mass") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.option.timestep = 0.02
        root.option.flag.contact = "disable"
        root.default.joint.set_attributes(
            type="hinge", axis=[0, 0, 1], limited=True, range=[-0.29, 0.29], damping=1
        )
        root.default.motor.set_attributes(gear=[0.1], ctrlrange=[-1, 1], ctrllimited=True)
        add_materials(root)
        world = root.worldbody
        fixed = world.add("camera", name="fixed", pos=[0, 0, 0.75], quat=[1, 0, 0, 0])
        self.walls = add_walls(world)
        self.body = world.add("body", name="pointmass", pos=[0, 0, 0.01])
        follow = self.body.add(
            "camera", name="cam0", pos=[0, -0.3, 0.3], xyaxes=[1, 0, 0, 0, 0.7, 0.7]
        )
        self.cameras = (fixed, follow)
        self.joints = tuple(
            self.body.add("joint", name=f"root_{axis}", type="slide", pos=[0, 0, 0], axis=vector)
            for axis, vector in (("x", [1, 0, 0]), ("y", [0, 1, 0]))
        )
        self.mass = self.body.add(
            "geom", name="pointmass", type="sphere", size=[0.01], material="self", mass=0.3
        )
        self.target = world.add(
            "geom", name="target", pos=[0, 0, 0.01], material="target", type="sphere",
            size=[0.015],
        )  # fmt: skip
        tendons = []
        for index in (1, 2):
            tendon = root.tendon.add("fixed", name=f"t{index}")
            for joint, coefficient in zip(self.joints, (index == 1, index == 2), strict=True):
                tendon.add("joint", joint=joint, coef=float(coefficient))
            tendons.append(tendon)
        self.tendons = tuple(tendons)
        self.motors = tuple(
            root.actuator.add("motor", name=tendon.name, tendon=tendon) for tendon in tendons
        )
