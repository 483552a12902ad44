"""The Control Suite's planar manipulator: the planar arm with a prop to bring (a ball or a
peg), the prop's ghostly target and, to insert it, a receptacle (a cup or a slot).

    manipulator = Manipulator(use_peg=False, insert=True)     # ball, cup, target ball
    arena.attach(manipulator)                 # manipulator.arm: entities.suite.planar_arm
    physics.bind(manipulator.object_joints).qpos               # the prop's x, z and angle
    physics.bind(manipulator.target).pos                       # where the target is drawn

dm_control's `manipulator.xml` holds every prop and its task removes those it does not use;
here only the task's are built, so the model is the one the suite's task compiles.
"""

from __future__ import annotations

import itertools

import composer
import mjcf
from entities.suite.planar_arm import PlanarArm, add_planar_arm

CONTACT_SOLREF = (0.005, 1)


class Manipulator(composer.Entity):
    """The planar arm with its prop, target and receptacle.

    The props are built in the file's order (ball, peg, slot, cup, target ball, target peg).
    They slide in x and z and turn about y (joints `<prop>_x`, `_z`, `_y`); targets and
    receptacles are static bodies a task moves by editing the model (their `body_pos` and
    `body_quat`).

    Attributes: `arm` (a PlanarArm), `object` (the prop's body), `object_joints` (its x, z
    and y joints, in that order), `target` (the target's body), `receptacle` (the cup's or
    slot's body, None unless inserting), and the sites rewards measure between:
    `object_site`, `target_site`, and for the peg `peg_pinch`, `peg_grasp`, `peg_tip`,
    `target_peg_tip`."""

    def _build(
        self, name: str = "manipulator", use_peg: bool = False, insert: bool = False
    ) -> None:
        """Make the model named `name`: the peg and its slot with `use_peg`, else the ball
        and its cup; the receptacle only with `insert`."""
        root = self._mjcf_root = mjcf.RootElement(model=name)
        self.arm: PlanarArm = add_planar_arm(root, CONTACT_SOLREF)
        self.use_peg, self.insert = bool(use_peg), bool(insert)
        world = root.worldbody
        if not self.use_peg:
            self.object = world.add("body", name="ball", pos=[0.4, 0, 0.4], childclass="object")
            self.object_joints = self._add_planar_joints(self.object, "ball", x=0.4, z=0.4)
            self.object.add("geom", name="ball", type="sphere", size=[0.022])
            self.object_site = self.object.add("site", name="ball", type="sphere")
        else:
            self.object = world.add("body", name="peg", pos=[-0.4, 0, 0.4], childclass="object")
            self.object_joints = self._add_planar_joints(self.object, "peg", x=-0.4, z=0.4)
            self._add_peg_geoms(self.object, "", pommel_body=True)
            self.object_site, self.peg_pinch, self.peg_grasp, self.peg_tip = self._add_peg_sites(
                self.object, "peg"
            )
        self.receptacle: mjcf.Element | None = None
        if self.insert and self.use_peg:
            self.receptacle = slot = world.add(
                "body", name="slot", pos=[-0.405, 0, 0.2], euler=[0, 20, 0], childclass="obstacle"
            )
            for index, (x, z, size) in enumerate(
                ((-0.0252, -0.083, [0.0198, 0.01, 0.035]), (0.0252, -0.083, [0.0198, 0.01, 0.035]),
                 (0, -0.138, [0.045, 0.01, 0.02]))
            ):  # fmt: skip
                slot.add("geom", name=f"slot_{index}", type="box", pos=[x, 0, z], size=size)
            slot.add("site", name="slot", type="box", pos=[0, 0, 0])
            slot.add("site", name="slot_end", type="box", pos=[0, 0, -0.05])
        elif self.insert:
            self.receptacle = cup = world.add(
                "body", name="cup", pos=[0.3, 0, 0.4], euler=[0, -15, 0], childclass="obstacle"
            )
            corners = ([-0.03, 0, 0.06], [-0.03, 0, -0.015], [0, 0, -0.04], [0.03, 0, -0.015],
                       [0.03, 0, 0.06])  # fmt: skip
            for index, (start, end) in enumerate(itertools.pairwise(corners)):
                cup.add("geom", name=f"cup_{index}", type="capsule", size=[0.008],
                        fromto=start + end)  # fmt: skip
            cup.add("site", name="cup", size=[0.005])
        if not self.use_peg:
            self.target = world.add(
                "body", name="target_ball", pos=[0.4, 0.001, 0.4], childclass="ghost"
            )
            self.target.add("geom", name="target_ball", type="sphere", size=[0.02])
            self.target_site = self.target.add("site", name="target_ball", type="sphere")
        else:
            self.target = world.add(
                "body", name="target_peg", pos=[-0.2, 0.001, 0.4], childclass="ghost"
            )
            self._add_peg_geoms(self.target, "target_", pommel_body=False)
            self.target_site, _, _, self.target_peg_tip = self._add_peg_sites(
                self.target, "target_peg"
            )

    @staticmethod
    def _add_planar_joints(
        body: mjcf.Element, prefix: str, x: float, z: float
    ) -> tuple[mjcf.Element, ...]:
        """The prop's x and z slides (their reference positions its body's) and y hinge."""
        return (
            body.add("joint", name=f"{prefix}_x", type="slide", axis=[1, 0, 0], ref=x),
            body.add("joint", name=f"{prefix}_z", type="slide", axis=[0, 0, 1], ref=z),
            body.add("joint", name=f"{prefix}_y", type="hinge", axis=[0, 1, 0]),
        )

    @staticmethod
    def _add_peg_geoms(body: mjcf.Element, prefix: str, pommel_body: bool) -> None:
        """A peg's blade, guard and pommel; the prop's pommel is a body of its own."""
        body.add("geom", name=f"{prefix}blade", type="capsule", size=[0.005],
                 fromto=[0, 0, -0.013, 0, 0, -0.113])  # fmt: skip
        body.add("geom", name=f"{prefix}guard", type="capsule", size=[0.005],
                 fromto=[-0.017, 0, -0.043, 0.017, 0, -0.043])  # fmt: skip
        if pommel_body:
            pommel = body.add("body", name="pommel", pos=[0, 0, -0.013])
            pommel.add("geom", name="pommel", type="sphere", size=[0.009])
        else:
            body.add("geom", name=f"{prefix}pommel", type="sphere", size=[0.009],
                     pos=[0, 0, -0.013])  # fmt: skip

    @staticmethod
    def _add_peg_sites(body: mjcf.Element, prefix: str) -> tuple[mjcf.Element, ...]:
        """A peg's sites, centre, pinch, grasp and tip, in the file's order."""
        return tuple(
            body.add("site", name=f"{prefix}{suffix}", type="box", pos=[0, 0, z])
            for suffix, z in (("", -0.063), ("_pinch", -0.025), ("_grasp", 0), ("_tip", -0.113))
        )
