"""The Control Suite's swimmer: a planar chain of links in a viscous fluid, and its target.

    swimmer = Swimmer(n_links=6)
    arena.attach(swimmer)
    physics.bind(swimmer.joints).qpos                # the angle of each link on the previous
    physics.bind(swimmer.velocity_sensors).sensordata  # each link's velocity and rotation
    physics.bind([swimmer.target, swimmer.nose]).xpos

dm_control generates this model for any number of links from `swimmer.xml`; so does
`Swimmer`, with the same numbers (its docstring lists them).
"""

from __future__ import annotations

import numpy as np

import composer
import mjcf
from entities.suite.materials import add_materials

_LINK_LENGTH = 0.1


class Swimmer(composer.Entity):
    """The suite's swimmer of `n_links` links.

    dm_control writes this model for any number of links from its file (`swimmer.xml`, the
    head) by code; so does this class, with the same numbers: a head with a nose and eyes,
    then links of 0.1 m, each a box of 10 g (invisible) and a capsule (seen), hinged at its
    front end to the previous one within +-360/n_links degrees and driven by a motor of gear
    5e-4. The head slides in x and y and turns about z freely. A fluid of density 3000, no
    contacts, 2 ms steps. Sensors: the nose's and the target's positions, the head's x and y
    axes, then a velocimeter and a gyro on the head and on every link. The cameras
    `tracking1` and `tracking2` follow the swimmer's centre of mass from further away the
    longer it is (by n_links / 6); `eyes` looks forward from the head. The target sphere and
    its light are the swimmer's too, since they belong to its task.
    """

    def _build(self, name: str = "swimmer", n_links: int = 6) -> None:
        """Make the model named `name` of `n_links` links, the head among them. Raises
        composer.EntityError for fewer than 3, as dm_control does."""
        if isinstance(n_links, bool) or not isinstance(n_links, int) or n_links < 3:
            raise composer.EntityError(f"n_links must be an int >= 3, got {n_links!r}")
        self.n_links = n_links
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.option.set_attributes(timestep=0.002, density=3000)
        root.option.flag.contact = "disable"
        add_materials(root)
        swimmer = root.default.add("default", dclass="swimmer")
        swimmer.joint.set_attributes(
            type="hinge", pos=[0, -0.05, 0], axis=[0, 0, 1], limited=True,
            solreflimit=[0.05, 1], solimplimit=[0, 0.8, 0.1], armature=1e-6,
        )  # fmt: skip
        inertial = swimmer.add("default", dclass="inertial")
        inertial.geom.set_attributes(
            type="box", size=[0.001, 0.05, 0.01], rgba=[0, 0, 0, 0], mass=0.01
        )
        visual = swimmer.add("default", dclass="visual")
        visual.geom.set_attributes(
            type="capsule", size=[0.01], fromto=[0, -0.05, 0, 0, 0.05, 0], material="self",
            mass=0,
        )  # fmt: skip
        swimmer.site.set_attributes(size=[0.01], rgba=[0, 0, 0, 0])
        free = root.default.add("default", dclass="free")
        free.joint.set_attributes(limited=False, stiffness=0, armature=0)
        root.default.motor.set_attributes(gear=[5e-4], ctrllimited=True, ctrlrange=[-1, 1])

        world = root.worldbody
        head = self.head = world.add("body", name="head", pos=[0, 0, 0.05], childclass=swimmer)
        head.add("light", name="light_1", diffuse=[0.8] * 3, pos=[0, 0, 1.5])
        head.add("geom", name="head", type="ellipsoid", size=[0.02, 0.04, 0.017],
                 pos=[0, -0.022, 0], material="self", mass=0)  # fmt: skip
        self.nose = head.add("geom", name="nose", type="sphere", pos=[0, -0.06, 0],
                             size=[0.004], material="effector", mass=0)  # fmt: skip
        head.add("geom", name="eyes", type="capsule", fromto=[-0.006, -0.054, 0.005, 0.006,
                 -0.054, 0.005], size=[0.004], material="eye", mass=0)  # fmt: skip
        # The tracking cameras move back as the chain grows, by dm_control's rule.
        scale = n_links / 6.0
        self.cameras = (
            head.add("camera", name="tracking1", pos=np.array([0, -0.2, 0.5]) * scale,
                     xyaxes=[1, 0, 0, 0, 1, 1], mode="trackcom", fovy=60),
            head.add("camera", name="tracking2", pos=np.array([-0.9, 0.5, 0.15]) * scale,
                     xyaxes=[0, -1, 0, 0.3, 0, 1], mode="trackcom", fovy=60),
            head.add("camera", name="eyes", pos=[0, -0.058, 0.005], xyaxes=[-1, 0, 0, 0, 0, 1]),
        )  # fmt: skip
        self.root_joints = tuple(
            head.add("joint", name=joint, dclass=free, type=kind, axis=axis, pos=[0, -0.05, 0])
            for joint, kind, axis in (
                ("rootx", "slide", [1, 0, 0]),
                ("rooty", "slide", [0, 1, 0]),
                ("rootz", "hinge", [0, 0, 1]),
            )
        )
        head.add("geom", name="inertial", dclass=inertial)
        head.add("geom", name="visual", dclass=visual)
        sites = [head.add("site", name="head")]

        limit = 360.0 / n_links
        parent, links, joints = head, [head], []
        for index in range(n_links - 1):
            parent = parent.add("body", name=f"segment_{index}", pos=[0, _LINK_LENGTH, 0])
            parent.add("geom", dclass=visual, name=f"visual_{index}")
            parent.add("geom", dclass=inertial, name=f"inertial_{index}")
            sites.append(parent.add("site", name=f"site_{index}"))
            joints.append(parent.add("joint", name=f"joint_{index}", range=[-limit, limit]))
            links.append(parent)
        self.links, self.joints = tuple(links), tuple(joints)

        self.target = world.add("geom", name="target", type="sphere", pos=[1, 1, 0.05],
                                size=[0.1], material="target")  # fmt: skip
        self.target_light = world.add(
            "light", name="target_light", diffuse=[1, 1, 1], pos=[1, 1, 1.5]
        )

        sensors = root.sensor
        sensors.add("framepos", name="nose_pos", objtype="geom", objname=self.nose)
        sensors.add("framepos", name="target_pos", objtype="geom", objname=self.target)
        sensors.add("framexaxis", name="head_xaxis", objtype="xbody", objname=head)
        sensors.add("frameyaxis", name="head_yaxis", objtype="xbody", objname=head)
        names = [("head_vel", "head_gyro")]
        names += [(f"velocimeter_{index}", f"gyro_{index}") for index in range(n_links - 1)]
        velocities = []
        for site, (linear, angular) in zip(sites, names, strict=True):
            velocities.append(sensors.add("velocimeter", name=linear, site=site))
            velocities.append(sensors.add("gyro", name=angular, site=site))
        self.velocity_sensors = tuple(velocities)
        self.motors = tuple(
            root.actuator.add("motor", name=f"motor_{index}", joint=joint)
            for index, joint in enumerate(self.joints)
        )
