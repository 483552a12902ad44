"""The Control Suite's planar stacker: the planar arm with boxes to stack and a ghostly
target box showing where the top of the stack should be.

    stacker = Stacker(n_boxes=2)
    arena.attach(stacker)
    physics.bind(stacker.box_joints).qpos      # each box's x, y (its angle) and z
    physics.bind(stacker.target).pos           # where the target is drawn

dm_control's `stacker.xml` holds four boxes and its task removes those past `n_boxes`;
here only the task's are built, so the model is the one the suite's task compiles.
"""

from __future__ import annotations

import composer
import mjcf
from entities.suite.planar_arm import PlanarArm, add_planar_arm

CONTACT_SOLREF = (0.01, 1)
MAX_BOXES = 4
_BOX_SIZE = [0.022] * 3
_BOX_X = (0.5, 0.4, 0.3, 0.2)  # box i's starting x, as the file writes it


class Stacker(composer.Entity):
    """The planar arm with `n_boxes` boxes and the target.

    Box i (4.4 cm cubes) starts at x = 0.5 - 0.1 i, z = 0.4 and slides in x and z and turns
    about y (joints `box<i>_x`, `_z`, `_y`, in that order in the model); the target is a
    static body a task moves by editing the model. The contacts are a little softer than the
    manipulator's (`solref` 0.01 s).

    Attributes: `arm` (a PlanarArm), `boxes` (the boxes' bodies), `box_sites` (a site at
    each box's centre), `box_joints` (each box's x, y and z joints in turn: dm_control's
    order of observing them, not the model's), `target` (the target's body),
    `target_geom` and `target_site`."""

    def _build(self, name: str = "stacker", n_boxes: int = 2) -> None:
        """Make the model named `name` with `n_boxes` boxes (1 to 4). Raises
        composer.EntityError for another number."""
        if isinstance(n_boxes, bool) or not isinstance(n_boxes, int):
            raise composer.EntityError(f"n_boxes must be an int from 1 to 4, got {n_boxes!r}")
        if not 1 <= n_boxes <= MAX_BOXES:
            raise composer.EntityError(f"n_boxes must be from 1 to {MAX_BOXES}, got {n_boxes}")
        root = self._mjcf_root = mjcf.RootElement(model=name)
        self.arm: PlanarArm = add_planar_arm(root, CONTACT_SOLREF)
        boxes, sites, joints = [], [], []
        for index, x in enumerate(_BOX_X[:n_boxes]):
            box_name = f"box{index}"
            box = root.worldbody.add("body", name=box_name, pos=[x, 0, 0.4], childclass="object")
            slide_x = box.add("joint", name=f"{box_name}_x", type="slide", axis=[1, 0, 0], ref=x)
            slide_z = box.add("joint", name=f"{box_name}_z", type="slide", axis=[0, 0, 1], ref=0.4)
            hinge_y = box.add("joint", name=f"{box_name}_y", type="hinge", axis=[0, 1, 0])
            box.add("geom", name=box_name, type="box", size=_BOX_SIZE)
            sites.append(box.add("site", name=box_name, type="sphere"))
            boxes.append(box)
            joints += [slide_x, hinge_y, slide_z]
        self.boxes, self.box_sites, self.box_joints = tuple(boxes), tuple(sites), tuple(joints)
        self.target = root.worldbody.add(
            "body", name="target", pos=[0, 0.001, 0.022], childclass="ghost"
        )
        self.target_geom = self.target.add("geom", name="target", type="box", size=_BOX_SIZE)
        self.target_site = self.target.add("site", name="target", type="sphere")
