"""The Control Suite's LQR system: a chain of spheres on springs sliding along y, the
first few pushed by motors (dm_control's procedurally generated `lqr` model).

    system = LQR(n_bodies=6, n_actuators=2)
    arena.attach(system)
    system.draw_system(random_state)     # each spring's stiffness (and damping): dm_control's draws
    physics.bind(system.joints).qpos      # each sphere's offset, relative to the one before

The numbers are the suite's (`lqr.xml` and its generator): `LQR` lists them.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

import composer
import mjcf
from entities.suite.materials import add_materials


class LQR(composer.Entity):
    """A chain of `n_bodies` spring-mounted spheres, the first `n_actuators` actuated.
    Attributes: `bodies`, `joints`, `sites` (one per sphere, in chain order), `motors`.

    The numbers are the suite's (`lqr.xml` and its generator): spheres of 10 cm radius,
    25 cm apart along x (the first 10 cm up), each on a slide joint along y relative to the
    one before; joint i's stiffness is drawn uniformly from `stiffness_range` and its
    damping from `damping_range` (both drawn, body after body, even when the range is a
    point); motors of unit gear and unlimited control on the first `n_actuators` joints;
    constraints disabled, 30 ms steps. Tendons between neighbouring spheres are drawn only.
    Until `draw_system` runs the springs hold the middle of the ranges.
    """

    def _build(
        self,
        name: str = "lqr",
        n_bodies: int = 2,
        n_actuators: int = 1,
        stiffness_range: Sequence[float] = (15.0, 25.0),
        damping_range: Sequence[float] = (0.0, 0.0),
    ) -> None:
        """Make the model named `name`. Raises composer.EntityError for fewer than one body
        or actuator, or more actuators than bodies."""
        for label, value in (("n_bodies", n_bodies), ("n_actuators", n_actuators)):
            if isinstance(value, bool) or not isinstance(value, int):
                raise composer.EntityError(f"{label} must be an int, got {value!r}")
        if n_bodies < 1 or n_actuators < 1:
            raise composer.EntityError(
                f"an LQR system needs at least 1 body and 1 actuator, got n_bodies={n_bodies}, "
                f"n_actuators={n_actuators}"
            )
        if n_actuators > n_bodies:
            raise composer.EntityError(
                f"an LQR system has at most 1 actuator per body, got n_actuators={n_actuators} "
                f"for n_bodies={n_bodies}"
            )
        self._ranges = (tuple(stiffness_range), tuple(damping_range))
        root = self._mjcf_root = mjcf.RootElement(model=name)
        add_materials(root)
        root.option.timestep = 0.03
        root.option.flag.constraint = "disable"
        root.default.joint.set_attributes(type="slide", axis=[0, 1, 0])
        root.default.geom.set_attributes(type="sphere", size=[0.1], material="self")
        root.default.site.size = [0.01]
        root.default.tendon.set_attributes(width=0.02, material="self")
        # The file's world geom takes the defaults' material: it belongs with the materials.
        root.worldbody.add(
            "geom", name="origin", pos=[2, 0, 0.05], size=[2, 0.003, 0.05], type="box",
            rgba=[0.5, 0.5, 0.5, 0.5],
        )  # fmt: skip
        stiffness, damping = (float(np.mean(bounds)) for bounds in self._ranges)
        parent, bodies, joints, sites = root.worldbody, [], [], []
        for index in range(n_bodies):
            position = [0.25, 0, 0.1] if index == 0 else [0.25, 0, 0]
            body = parent.add("body", name=f"body_{index}", pos=position)
            joints.append(
                body.add("joint", name=f"joint_{index}", stiffness=stiffness, damping=damping)
            )
            body.add("geom", name=f"geom_{index}")
            sites.append(body.add("site", name=f"site_{index}"))
            bodies.append(body)
            parent = body
        self.bodies, self.joints, self.sites = tuple(bodies), tuple(joints), tuple(sites)
        self.motors = tuple(
            root.actuator.add("motor", name=f"motor_{index}", joint=joints[index])
            for index in range(n_actuators)
        )
        for index in range(n_bodies - 1):
            tendon = root.tendon.add("spatial", name=f"tendon_{index}")
            tendon.add("site", site=sites[index])
            tendon.add("site", site=sites[index + 1])

    def draw_system(self, random_state: np.random.RandomState) -> None:
        """Draw each joint's stiffness and damping, uniformly within the ranges, joint by
        joint (stiffness, then damping), as dm_control's generator draws them. The model
        changes: an environment recompiles it at the next reset."""
        (stiffness_low, stiffness_high), (damping_low, damping_high) = self._ranges
        for joint in self.joints:
            joint.stiffness = random_state.uniform(stiffness_low, stiffness_high)
            joint.damping = random_state.uniform(damping_low, damping_high)
