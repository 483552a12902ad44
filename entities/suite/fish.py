"""The Control Suite's fish: a free-swimming body with a two-part tail and two fins, in a
fluid without gravity, and the target it swims to.

    fish = Fish()
    arena.attach(fish)
    physics.bind(fish.joints).qpos                   # the tail's and the fins' angles
    physics.bind([fish.target, fish.mouth]).xpos     # where the target and the mouth are
    physics.bind(fish.torso).xmat                    # the torso's orientation

The numbers are the suite's (`fish.xml`): `Fish` lists them.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.materials import add_materials

# (body, its position in the torso, its geom's position in it): each fin.
_FINS = (
    ("finright", (0.01, 0, 0), (0.015, 0, 0)),
    ("finleft", (-0.01, 0, 0), (-0.015, 0, 0)),
)
_FIN_SIZE = (0.02, 0.015, 0.001)
# (name, type, attributes) of the torso's geoms without mass, in order: the shape that is
# seen; `torso_massive` gives the torso its mass.
_MASSLESS = (
    ("eye", "ellipsoid", {"pos": [0, 0.055, 0.015], "size": [0.008, 0.012, 0.008],
                          "euler": [-10, 0, 0], "material": "eye"}),
    ("mouth", "capsule", {"fromto": [0, 0.079, 0, 0, 0.07, 0], "size": [0.005],
                          "material": "effector"}),
    ("lower_mouth", "capsule", {"fromto": [0, 0.079, -0.004, 0, 0.07, -0.003],
                                "size": [0.0045], "material": "effector"}),
    ("torso", "ellipsoid", {"size": [0.01, 0.08, 0.04]}),
    ("back_fin", "ellipsoid", {"size": [0.001, 0.03, 0.015], "pos": [0, -0.03, 0.03],
                               "material": "effector"}),
)  # fmt: skip
# (actuator, gain kp): the position servos in the suite's order.
_SERVOS = (
    ("tail", 5e-4),
    ("tail_twist", 1e-4),
    ("fins_flap", 3e-4),
    ("finleft_pitch", 1e-4),
    ("finright_pitch", 1e-4),
)


class Fish(composer.Entity):
    """The suite's fish and its target.

    The numbers are the suite's (`fish.xml`): a torso of ellipsoids whose mass is a box's
    (`torso_massive`, hidden in group 4), moving freely in a fluid of density 5000 with no
    gravity and no constraints, in 4 ms steps; the tail turns (`tail1`), twists
    (`tail_twist`) and bends again (`tail2`, sprung); each fin rolls and pitches, the rolls
    driven together through the tendon `fins_flap` and held symmetric by the sprung tendon
    `fins_sym`. Five position servos (`tail`, `tail_twist`, `fins_flap`, `finleft_pitch`,
    `finright_pitch`) take controls in [-1, 1]. A velocimeter and a gyro at the torso. The
    world's cameras (`tracking_top`, `tracking_x`, `tracking_y` following the fish, and
    `fixed_top`) and the target sphere are the fish's too, since they belong to its task.
    """

    def _build(self, name: str = "fish") -> None:
        """Make the model named `name`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.option.set_attributes(timestep=0.004, density=5000)
        root.option.flag.set_attributes(gravity="disable", constraint="disable")
        add_materials(root)
        root.default.general.ctrllimited = True
        fish = root.default.add("default", dclass="fish")
        fish.joint.set_attributes(
            type="hinge", limited=False, range=[-60, 60], damping=2e-5, solreflimit=[0.1, 1],
            solimplimit=[0, 0.8, 0.1],
        )  # fmt: skip
        fish.geom.material = "self"

        world = root.worldbody
        self.cameras = (
            world.add("camera", name="tracking_top", pos=[0, 0, 1], xyaxes=[1, 0, 0, 0, 1, 0],
                      mode="trackcom"),
            world.add("camera", name="tracking_x", pos=[-0.3, 0, 0.2],
                      xyaxes=[0, -1, 0, 0.342, 0, 0.940], fovy=60, mode="trackcom"),
            world.add("camera", name="tracking_y", pos=[0, -0.3, 0.2],
                      xyaxes=[1, 0, 0, 0, 0.342, 0.940], fovy=60, mode="trackcom"),
            world.add("camera", name="fixed_top", pos=[0, 0, 5.5], fovy=10),
        )  # fmt: skip
        self.target = world.add(
            "geom", name="target", type="sphere", pos=[0, 0.4, 0.1], size=[0.04],
            material="target",
        )  # fmt: skip
        torso = self.torso = world.add("body", name="torso", pos=[0, 0, 0.1], childclass=fish)
        torso.add(
            "light", name="light", diffuse=[0.6] * 3, pos=[0, 0, 0.5], dir=[0, 0, -1],
            specular=[0.3] * 3, mode="track",
        )  # fmt: skip
        self.root_joint = torso.add("joint", name="root", type="free", damping=0, limited=False)
        self.torso_site = torso.add("site", name="torso", size=[0.01], rgba=[0, 0, 0, 0])
        geoms = {}
        for geom, kind, attributes in _MASSLESS:
            geoms[geom] = torso.add("geom", name=geom, type=kind, mass=0, **attributes)
        torso.add("camera", name="eye", pos=[0, 0.06, 0.02], xyaxes=[1, 0, 0, 0, 0, 1])
        self.mouth = geoms["mouth"]
        torso.add("geom", name="torso_massive", type="box", size=[0.002, 0.06, 0.03], group=4)

        tail1 = torso.add("body", name="tail1", pos=[0, -0.09, 0])
        tail = tail1.add("joint", name="tail1", axis=[0, 0, 1], pos=[0, 0.01, 0])
        twist = tail1.add(
            "joint", name="tail_twist", axis=[0, 1, 0], pos=[0, 0.01, 0], range=[-30, 30]
        )
        tail1.add("geom", name="tail1", type="ellipsoid", size=[0.001, 0.008, 0.016])
        tail2 = tail1.add("body", name="tail2", pos=[0, -0.028, 0])
        bend = tail2.add("joint", name="tail2", axis=[0, 0, 1], pos=[0, 0.02, 0], stiffness=8e-5)
        tail2.add("geom", name="tail2", type="ellipsoid", size=[0.001, 0.018, 0.035])
        rolls, pitches = {}, {}
        for fin, pos, geom_pos in _FINS:
            body = torso.add("body", name=fin, pos=list(pos))
            rolls[fin] = body.add("joint", name=f"{fin}_roll", axis=[0, 1, 0])
            pitches[fin] = body.add("joint", name=f"{fin}_pitch", axis=[1, 0, 0], pos=[0, 0.005, 0])
            body.add("geom", name=fin, type="ellipsoid", pos=list(geom_pos), size=list(_FIN_SIZE))
        self.joints = (
            tail, twist, bend, rolls["finright"], pitches["finright"], rolls["finleft"],
            pitches["finleft"],
        )  # fmt: skip

        flap = root.tendon.add("fixed", name="fins_flap")
        flap.add("joint", joint=rolls["finleft"], coef=-0.5)
        flap.add("joint", joint=rolls["finright"], coef=0.5)
        symmetric = root.tendon.add("fixed", name="fins_sym", stiffness=1e-4)
        symmetric.add("joint", joint=rolls["finleft"], coef=0.5)
        symmetric.add("joint", joint=rolls["finright"], coef=0.5)
        transmissions = {
            "tail": {"joint": tail},
            "tail_twist": {"joint": twist},
            "fins_flap": {"tendon": flap},
            "finleft_pitch": {"joint": pitches["finleft"]},
            "finright_pitch": {"joint": pitches["finright"]},
        }
        self.servos = tuple(
            root.actuator.add(
                "position", name=servo, ctrlrange=[-1, 1], kp=kp, **transmissions[servo]
            )
            for servo, kp in _SERVOS
        )
        self.velocimeter = root.sensor.add("velocimeter", name="velocimeter", site=self.torso_site)
        self.gyro = root.sensor.add("gyro", name="gyro", site=self.torso_site)
