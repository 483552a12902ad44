"""The Control Suite's quadruped: four legs of four hinges, driven through tendons.

    quadruped = Quadruped(rangefinders=True)
    arena.attach(quadruped)                       # arenas.suite.QuadrupedArena
    physics.bind(quadruped.hinges).qpos          # the 16 leg joints' angles
    physics.bind(quadruped.velocimeter).sensordata   # the torso's velocity, in its frame

The numbers are the suite's (`quadruped.xml`): `Quadruped` lists them; with `walls_and_ball`
the model also has what the suite's fetch task adds to the world.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials

# The legs in the suite's order: (name, hip position, hip yaw in degrees).
LEGS = (
    ("front_left", (0.2, 0.2, 0.0), 45),
    ("front_right", (0.2, -0.2, 0.0), -45),
    ("back_right", (-0.2, -0.2, 0.0), -135),
    ("back_left", (-0.2, 0.2, 0.0), 135),
)
# The rangefinders' rows on the face: (height at the face, where the beam's axis points
# back to: x and z); each row has five beams across y.
_RANGEFINDER_ROWS = ((0.11, 0.34, 0.115), (0.1, 0.36, 0.11), (0.09, 0.38, 0.105),
                     (0.08, 0.4, 0.1))  # fmt: skip
_RANGEFINDER_COLUMNS = (-0.02, -0.01, 0.0, 0.01, 0.02)
# (name, position, z axis, size) of the fetch arena's walls, inclined 45 degrees inward.
_WALLS = (
    ("wall_px", (-15.7, 0, 0.7), (1, 0, 1), (1, 15, 0.5)),
    ("wall_py", (0, -15.7, 0.7), (0, 1, 1), (15, 1, 0.5)),
    ("wall_nx", (15.7, 0, 0.7), (-1, 0, 1), (1, 15, 0.5)),
    ("wall_ny", (0, 15.7, 0.7), (0, -1, 1), (15, 1, 0.5)),
)


class Quadruped(composer.Entity):
    """The suite's quadruped. Attributes: `torso`, `root` (the free joint), `hinges` (the 16
    leg joints in model order), `toes` (bodies, in the legs' order), `workspace` (the site
    ahead of the torso the fetch task brings the ball to), `imu` (accelerometer, gyro),
    `velocimeter`, `force_torque` (force then torque sensors of each toe), `rangefinders`
    (sensors; empty without them), and with `walls_and_ball` `ball` (a body), `ball_root`
    (its free joint), `ball_geom` and `target` (a site).

    The numbers are the suite's (`quadruped.xml`): an ellipsoid torso on a free joint,
    0.57 m up, with two eyes; four legs (front left, front right, back right, back left) of
    hip (yaw, pitch), knee and ankle hinges ending in a toe sphere. Each leg's pitch, knee
    and ankle are coupled by an equality on a tendon; its 12 actuators are first-order
    filters with position feedback (yaw on the yaw joint, lift and extend on tendons over
    the pitch, knee and ankle). Sensors: an IMU (accelerometer, gyro, velocimeter) at the
    torso's site, force and torque at each toe, the torso subtree's centre of mass, and with
    `rangefinders` 20 rangefinders looking ahead from the face (their sites are there either
    way, as in the suite's file). The cameras `x` and `y` and the light follow the torso's
    centre of mass; `egocentric` looks out of the face. 5 ms steps.

    With `walls_and_ball` the model also has what the suite's fetch task adds to the world:
    four inclined walls around a 15 m floor, the `target` site at the origin and a free
    `ball`. They are this model's elements, not an arena's, because they wear the suite's
    materials (`decoration`, `target`, `ball`), which live in this model as in the suite's
    file; in the composed model they are world elements all the same.
    """

    def _build(
        self, name: str = "quadruped", rangefinders: bool = False, walls_and_ball: bool = False
    ) -> None:
        """Make the model named `name`, with rangefinder sensors if `rangefinders`, and
        the fetch task's walls, target and ball if `walls_and_ball`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.option.timestep = 0.005
        add_materials(root)
        self._add_defaults(root)
        root.asset.add(
            "texture", name="ball", builtin="checker", mark="cross", width=151, height=151,
            rgb1=[0.1, 0.1, 0.1], rgb2=[0.9, 0.9, 0.9], markrgb=[1, 1, 1],
        )  # fmt: skip
        ball_material = root.asset.add("material", name="ball", texture="ball")
        world = root.worldbody
        if walls_and_ball:
            for wall, pos, zaxis, size in _WALLS:
                world.add("geom", name=wall, dclass="wall", pos=list(pos), zaxis=list(zaxis),
                          size=list(size))  # fmt: skip
            self.target = world.add("site", name="target", type="cylinder", size=[0.4, 0.06],
                                    pos=[0, 0, 0.05], material="target")  # fmt: skip
        self._build_torso(world)
        if walls_and_ball:
            self.ball = world.add("body", name="ball", pos=[0, 0, 3])
            self.ball_root = self.ball.add("freejoint", name="ball_root")
            self.ball_geom = self.ball.add(
                "geom", name="ball", size=[0.15], material=ball_material, priority=1, condim=6,
                friction=[0.7, 0.005, 0.005], solref=[-10000, -30],
            )  # fmt: skip
            self.ball.add("light", name="ball_light", pos=[0, 0, 4], mode="trackcom")
        self._add_transmission(root)
        self._add_sensors(root, rangefinders)

    @staticmethod
    def _add_defaults(root: mjcf.RootElement) -> None:
        main = root.default
        main.geom.set_attributes(solimp=[0.9, 0.99, 0.003], solref=[0.01, 1])
        body = main.add("default", dclass="body")
        body.geom.set_attributes(type="capsule", size=[0.08], condim=1, material="self",
                                 density=500)  # fmt: skip
        body.joint.set_attributes(type="hinge", damping=30, armature=0.01, limited=True,
                                  solimplimit=[0, 0.99, 0.01])  # fmt: skip
        hip = body.add("default", dclass="hip")
        hip.add("default", dclass="yaw").joint.set_attributes(axis=[0, 0, 1], range=[-50, 50])
        hip.add("default", dclass="pitch").joint.set_attributes(axis=[0, 1, 0], range=[-20, 60])
        hip.geom.fromto = [0, 0, 0, 0.3, 0, 0.11]
        for segment, joint_range, size, fromto in (
            ("knee", [-60, 50], 0.065, [0, 0, 0, 0.25, 0, -0.25]),
            ("ankle", [-45, 55], 0.055, [0, 0, 0, 0, 0, -0.25]),
        ):
            segment_default = body.add("default", dclass=segment)
            segment_default.joint.set_attributes(axis=[0, 1, 0], range=joint_range)
            segment_default.geom.set_attributes(size=[size], fromto=fromto)
        toe = body.add("default", dclass="toe")
        toe.geom.set_attributes(type="sphere", size=[0.08], material="effector", friction=[1.5])
        toe.site.set_attributes(type="sphere", size=[0.084], material="site", group=4)
        main.add("default", dclass="rangefinder").site.set_attributes(
            type="capsule", size=[0.005, 0.1], material="site", group=4
        )
        main.add("default", dclass="wall").geom.set_attributes(type="plane",
                                                               material="decoration")  # fmt: skip
        main.add("default", dclass="coupling").equality.set_attributes(
            solimp=[0.95, 0.99, 0.01], solref=[0.005, 0.5]
        )
        main.general.set_attributes(
            ctrllimited=True, gainprm=[1000], biasprm=[0, -1000], biastype="affine",
            dyntype="filter", dynprm=[0.1],
        )  # fmt: skip
        for actuator, ctrlrange in (("yaw_act", [-1, 1]), ("lift_act", [-1, 1.1]),
                                    ("extend_act", [-0.8, 0.8])):  # fmt: skip
            main.add("default", dclass=actuator).general.ctrlrange = ctrlrange

    def _build_torso(self, world: mjcf.Element) -> None:
        torso = self.torso = world.add("body", name="torso", childclass="body", pos=[0, 0, 0.57])
        self.root = torso.add("freejoint", name="root")
        torso.add("camera", name="x", pos=[-1.7, 0, 1], xyaxes=[0, -1, 0, 0.75, 0, 1],
                  mode="trackcom")  # fmt: skip
        torso.add("camera", name="y", pos=[0, 4, 2], xyaxes=[-1, 0, 0, 0, -0.5, 1],
                  mode="trackcom")  # fmt: skip
        torso.add("camera", name="egocentric", pos=[0.3, 0, 0.11], xyaxes=[0, -1, 0, 0.4, 0, 1],
                  fovy=60)  # fmt: skip
        torso.add("light", name="light", pos=[0, 0, 4], mode="trackcom")
        for side, y in (("r", -0.07), ("l", 0.07)):
            torso.add("geom", name=f"eye_{side}", type="cylinder", size=[0.05],
                      fromto=[0.1, y, 0.12, 0.31, y, 0.08], mass=0)  # fmt: skip
            torso.add("site", name=f"pupil_{side}", type="sphere", size=[0.033],
                      pos=[0.3, y, 0.08], zaxis=[1, 0, 0], material="eye")  # fmt: skip
        self.workspace = torso.add("site", name="workspace", type="sphere", size=[0.3, 0.3, 0.3],
                                   material="site", pos=[0.8, 0, -0.2], group=3)  # fmt: skip
        self._rangefinder_sites = []
        for row, (z, back_x, back_z) in enumerate(_RANGEFINDER_ROWS):
            for column, y in enumerate(_RANGEFINDER_COLUMNS):
                # The suite's file starts the second row's second beam at y = -0.02, as
                # its first: a fact of the model, kept.
                y = -0.02 if (row, column) == (1, 1) else y
                self._rangefinder_sites.append(torso.add(
                    "site", name=f"rf_{row}{column}", dclass="rangefinder",
                    fromto=[0.41, y, z, back_x, 0, back_z],
                ))  # fmt: skip
        torso.add("geom", name="torso", type="ellipsoid", size=[0.3, 0.27, 0.2], density=1000)
        torso.add("site", name="torso_touch", type="box", size=[0.26, 0.26, 0.26],
                  rgba=[0, 0, 1, 0])  # fmt: skip
        self._imu_site = torso.add("site", name="torso", size=[0.05], rgba=[1, 0, 0, 1])
        hinges, toes, self._toe_sites = [], [], []
        for leg, pos, yaw in LEGS:
            hip = torso.add("body", name=f"hip_{leg}", pos=list(pos), euler=[0, 0, yaw],
                            childclass="hip")  # fmt: skip
            hinges.append(hip.add("joint", name=f"yaw_{leg}", dclass="yaw"))
            hinges.append(hip.add("joint", name=f"pitch_{leg}", dclass="pitch"))
            hip.add("geom", name=f"thigh_{leg}")
            knee = hip.add("body", name=f"knee_{leg}", pos=[0.3, 0, 0.11], childclass="knee")
            hinges.append(knee.add("joint", name=f"knee_{leg}"))
            knee.add("geom", name=f"shin_{leg}")
            ankle = knee.add("body", name=f"ankle_{leg}", pos=[0.25, 0, -0.25],
                             childclass="ankle")  # fmt: skip
            hinges.append(ankle.add("joint", name=f"ankle_{leg}"))
            ankle.add("geom", name=f"foot_{leg}")
            toe = ankle.add("body", name=f"toe_{leg}", pos=[0, 0, -0.3], childclass="toe")
            toe.add("geom", name=f"toe_{leg}")
            self._toe_sites.append(toe.add("site", name=f"toe_{leg}"))
            toes.append(toe)
        self.hinges, self.toes = tuple(hinges), tuple(toes)

    @staticmethod
    def _add_transmission(root: mjcf.RootElement) -> None:
        """Each leg's coupling, extend and lift tendons, the couplings' equalities and the
        12 actuators, in the suite's order."""
        tendons = root.tendon
        legs = [leg for leg, _, _ in LEGS]
        for leg in legs:
            coupling = tendons.add("fixed", name=f"coupling_{leg}")
            for joint in ("pitch", "knee", "ankle"):
                coupling.add("joint", joint=f"{joint}_{leg}", coef=0.333)
        for leg in legs:
            extend = tendons.add("fixed", name=f"extend_{leg}")
            for joint, coef in (("pitch", 0.25), ("knee", -0.5), ("ankle", 0.25)):
                extend.add("joint", joint=f"{joint}_{leg}", coef=coef)
            lift = tendons.add("fixed", name=f"lift_{leg}")
            for joint, coef in (("pitch", 0.5), ("ankle", -0.5)):
                lift.add("joint", joint=f"{joint}_{leg}", coef=coef)
        for leg in legs:
            root.equality.add("tendon", name=f"coupling_{leg}", tendon1=f"coupling_{leg}",
                              dclass="coupling")  # fmt: skip
        for leg in legs:
            root.actuator.add("general", name=f"yaw_{leg}", dclass="yaw_act",
                              joint=f"yaw_{leg}")  # fmt: skip
            for motion in ("lift", "extend"):
                root.actuator.add("general", name=f"{motion}_{leg}", dclass=f"{motion}_act",
                                  tendon=f"{motion}_{leg}")  # fmt: skip

    def _add_sensors(self, root: mjcf.RootElement, rangefinders: bool) -> None:
        sensor, site = root.sensor, self._imu_site
        self.imu = (
            sensor.add("accelerometer", name="imu_accel", site=site),
            sensor.add("gyro", name="imu_gyro", site=site),
        )
        self.velocimeter = sensor.add("velocimeter", name="velocimeter", site=site)
        self.force_torque = tuple(
            sensor.add(kind, name=f"{kind}_{toe.name}", site=toe)
            for kind in ("force", "torque")
            for toe in self._toe_sites
        )
        sensor.add("subtreecom", name="center_of_mass", body=self.torso)
        self.rangefinders = tuple(
            sensor.add("rangefinder", name=rf.name, site=rf)
            for rf in (self._rangefinder_sites if rangefinders else ())
        )
