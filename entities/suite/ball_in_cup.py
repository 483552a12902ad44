"""The Control Suite's ball in cup: a cup moved in a plane, a ball tied to it by a string.

    ball_in_cup = BallInCup()
    arena.attach(ball_in_cup)
    physics.bind(ball_in_cup.ball_joints).qpos    # the ball's x and z
    physics.bind(ball_in_cup.target).xpos         # the inside of the cup

The numbers are the suite's (`ball_in_cup.xml`): `BallInCup` lists them.
"""

from __future__ import annotations

import itertools

import composer
import mjcf
from entities.suite.materials import add_materials

# The cup's outline in its x-z plane, from the left rim down, across the bottom, up.
_CUP_OUTLINE = ((-0.05, 0), (-0.05, -0.075), (-0.025, -0.1), (0.025, -0.1), (0.05, -0.075),
                (0.05, 0))  # fmt: skip


class BallInCup(composer.Entity):
    """The suite's ball in cup.

    The numbers are the suite's (`ball_in_cup.xml`): a cup of five capsules of 8 mm radius,
    10 cm wide and deep, 0.6 m up, on two slide joints (x, z) held by springs of stiffness
    20 and damped at 3, each driven by a motor of gear 5; a ball of 2.5 cm radius on two
    unactuated slide joints, tied to the bottom of the cup by a 0.3 m string (a spatial
    tendon limited to its length); MuJoCo's default options (2 ms steps, gravity). The box
    site `target` is the inside of the cup. The cameras `cam0` and `cam1` look at it from
    the front.
    """

    def _build(self, name: str = "ball_in_cup") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.default.motor.set_attributes(ctrllimited=True, ctrlrange=[-1, 1], gear=[5])
        cup_class = root.default.add("default", dclass="cup")
        cup_class.joint.set_attributes(type="slide", damping=3, stiffness=20)
        cup_class.geom.set_attributes(type="capsule", size=[0.008], material="self")
        add_materials(root)
        world = root.worldbody
        self.cameras = tuple(
            world.add("camera", name=f"cam{index}", pos=[0, -1, height], xyaxes=xyaxes)
            for index, (height, xyaxes) in enumerate(
                ((0.8, [1, 0, 0, 0, 1, 2]), (0.4, [1, 0, 0, 0, 0, 1]))
            )
        )
        self.cup = world.add("body", name="cup", pos=[0, 0, 0.6], childclass=cup_class)
        self.cup_joints = tuple(
            self.cup.add("joint", name=f"cup_{axis}", axis=vector)
            for axis, vector in (("x", [1, 0, 0]), ("z", [0, 0, 1]))
        )
        for index, ((x0, z0), (x1, z1)) in enumerate(itertools.pairwise(_CUP_OUTLINE)):
            self.cup.add("geom", name=f"cup_part_{index}", fromto=[x0, 0, z0, x1, 0, z1])
        bottom = self.cup.add("site", name="cup", pos=[0, 0, -0.108], size=[0.005])
        self.target = self.cup.add(
            "site", name="target", type="box", pos=[0, 0, -0.05], size=[0.05, 0.006, 0.05],
            group=4,
        )  # fmt: skip
        self.ball_body = world.add("body", name="ball", pos=[0, 0, 0.2])
        self.ball_joints = tuple(
            self.ball_body.add("joint", name=f"ball_{axis}", type="slide", axis=vector)
            for axis, vector in (("x", [1, 0, 0]), ("z", [0, 0, 1]))
        )
        self.ball = self.ball_body.add(
            "geom", name="ball", type="sphere", size=[0.025], material="effector"
        )
        knot = self.ball_body.add("site", name="ball", size=[0.005])
        self.motors = tuple(
            root.actuator.add("motor", name=axis, joint=joint)
            for axis, joint in zip("xz", self.cup_joints, strict=True)
        )
        self.string = root.tendon.add(
            "spatial", name="string", limited=True, range=[0, 0.3], width=0.003
        )
        for site in (knot, bottom):
            self.string.add("site", site=site)
