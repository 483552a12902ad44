"""The Control Suite's walker: a planar biped of a torso and two legs of thigh, leg and foot.

    walker = Walker()
    arena.attach(walker)
    physics.bind(walker.torso).xpos                  # the torso's position (height: [2])
    physics.bind(walker.bodies).xmat                 # each body's orientation
    physics.bind(walker.speed_sensor).sensordata     # the torso subtree's linear velocity

The numbers are the suite's (`walker.xml`): `Walker` lists them.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials

# (part, its position in its parent, joint, joint position, joint range (degrees), geom
#  attributes, motor gear): one leg from the thigh down, at y = -0.05 (right) or 0.05
# (left) of the torso.
_LEG = (
    ("thigh", (0, 0, -0.3), "hip", None, (-20, 100),
     {"pos": [0, 0, -0.225], "size": [0.05, 0.225]}, 100),
    ("leg", (0, 0, -0.7), "knee", (0, 0, 0.25), (-150, 0), {"size": [0.04, 0.25]}, 50),
    ("foot", (0.06, 0, -0.25), "ankle", (-0.06, 0, 0), (-45, 45),
     {"zaxis": [1, 0, 0], "size": [0.05, 0.1]}, 20),
)  # fmt: skip
_SIDES = (("right", -0.05), ("left", 0.05))
FLOOR_FRICTION = (0.7, 0.1, 0.1)


class Walker(composer.Entity):
    """The suite's planar walker.

    The numbers are the suite's (`walker.xml`): capsules with friction 0.7 that collide with
    the floor but not with each other; hinges about -y, damped 0.1 with armature 0.01 and
    soft limits (hip -20 to 100 degrees, knee -150 to 0, ankle +-45), each driven by a motor
    (gear 100, 50, 20); the torso slides in z and x and turns about y, freely (in that
    order); 2.5 ms steps. A light and the cameras `side` and `back` follow the torso's
    centre of mass.
    """

    def _build(self, name: str = "walker") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.option.timestep = 0.0025
        root.statistic.set_attributes(extent=2, center=[0, 0, 1])
        add_materials(root)
        main = root.default
        main.joint.set_attributes(
            damping=0.1, armature=0.01, limited=True, solimplimit=[0, 0.99, 0.01]
        )
        main.geom.set_attributes(contype=1, conaffinity=0, friction=list(FLOOR_FRICTION))
        main.motor.set_attributes(ctrlrange=[-1, 1], ctrllimited=True)
        main.site.size = [0.01]
        walker = main.add("default", dclass="walker")
        walker.geom.set_attributes(material="self", type="capsule")
        walker.joint.axis = [0, -1, 0]

        torso = self.torso = root.worldbody.add(
            "body", name="torso", pos=[0, 0, 1.3], childclass=walker
        )
        torso.add("light", name="light", pos=[0, 0, 2], mode="trackcom")
        self.cameras = (
            torso.add("camera", name="side", pos=[0, -2, 0.7], euler=[60, 0, 0], mode="trackcom"),
            torso.add(
                "camera", name="back", pos=[-2, 0, 0.5], xyaxes=[0, -1, 0, 1, 0, 3],
                mode="trackcom",
            ),
        )  # fmt: skip
        free = {"limited": False, "armature": 0, "damping": 0}
        self.root_joints = (
            torso.add("joint", name="rootz", axis=[0, 0, 1], type="slide", **free),
            torso.add("joint", name="rootx", axis=[1, 0, 0], type="slide", **free),
            torso.add("joint", name="rooty", axis=[0, 1, 0], type="hinge", **free),
        )
        torso.add("geom", name="torso", size=[0.07, 0.3])
        bodies, joints, gears = [torso], [], []
        for side, y in _SIDES:
            parent = torso
            for part, pos, joint, joint_pos, limits, geom, gear in _LEG:
                body_pos = [pos[0], y, pos[2]] if part == "thigh" else list(pos)
                parent = parent.add("body", name=f"{side}_{part}", pos=body_pos)
                position = {} if joint_pos is None else {"pos": list(joint_pos)}
                joints.append(
                    parent.add("joint", name=f"{side}_{joint}", range=list(limits), **position)
                )
                parent.add("geom", name=f"{side}_{part}", **geom)
                bodies.append(parent)
                gears.append(gear)
        self.bodies = tuple(bodies)
        self.leg_joints = tuple(joints)
        self.speed_sensor = root.sensor.add("subtreelinvel", name="torso_subtreelinvel", body=torso)
        self.motors = tuple(
            root.actuator.add("motor", name=joint.name, joint=joint, gear=[gear])
            for joint, gear in zip(self.leg_joints, gears, strict=True)
        )
