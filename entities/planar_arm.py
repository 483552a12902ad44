"""A planar two-link arm moving in the horizontal plane, with a fingertip site.

    arm = PlanarArm(link_lengths=(0.12, 0.12))
    arena.attach(arm)                                  # base at the world origin
    arm.observables.joint_angles.enabled = True        # (cos q1, cos q2, sin q1, sin q2)
    physics.bind(arm.fingertip).xpos                   # where the tip is

The shoulder turns freely about world z; the elbow is limited to +-`elbow_range` rad so the
arm cannot fold onto itself. Links float `height` above the floor and touch nothing, so
the arm moves as a damped double pendulum without gravity effects in its plane.
"""

from __future__ import annotations

from collections.abc import Sequence

import composer
import mjcf
from composer import observation
from entities.features import Clipped, HingeAngles, velocities

ACTUATORS = ("motor", "position")


class PlanarArm(composer.Entity):
    """Joints `shoulder` and `elbow`, an actuator on each (torque motors by default), and
    the site `fingertip` at the end of the second link."""

    def _build(
        self,
        name: str = "arm",
        link_lengths: Sequence[float] = (0.12, 0.12),
        height: float = 0.02,
        gear: float = 0.05,
        damping: float = 0.01,
        elbow_range: float = 2.8,
        actuator: str = "motor",
        kp: float = 1.0,
    ) -> None:
        """Make the arm model named `name`: link lengths in m, joint `damping` (N m s/rad),
        the elbow's limit in rad, and `actuator` 'motor' (torque `gear * control` N m,
        control in [-1, 1]) or 'position' (servos to a joint angle with stiffness `kp`
        N m/rad and torque up to `gear`). Raises composer.EntityError for another actuator."""
        if actuator not in ACTUATORS:
            raise composer.EntityError(
                f"PlanarArm actuator must be one of {ACTUATORS}, got {actuator!r}"
            )
        upper_length, lower_length = (float(v) for v in link_lengths)
        root = self._mjcf_root = mjcf.RootElement(model=name)
        root.compiler.angle = "radian"
        root.default.geom.set_attributes(contype=0, conaffinity=0, type="capsule", size=[0.01])
        root.default.joint.set_attributes(type="hinge", axis=[0, 0, 1], damping=damping)
        root.asset.add("material", name="link", rgba=[0.2, 0.5, 0.8, 1])
        root.asset.add("material", name="tip", rgba=[0.9, 0.6, 0.1, 1])
        root.worldbody.add(
            "geom", name="base", type="cylinder", size=[0.025, height / 2],
            pos=[0, 0, height / 2], rgba=[0.3, 0.3, 0.3, 1],
        )  # fmt: skip
        upper = root.worldbody.add("body", name="upper", pos=[0, 0, height])
        self.shoulder = upper.add("joint", name="shoulder")
        upper.add("geom", name="upper", fromto=[0, 0, 0, upper_length, 0, 0], material="link")
        lower = upper.add("body", name="lower", pos=[upper_length, 0, 0])
        self.elbow = lower.add("joint", name="elbow", limited=True,
                               range=[-elbow_range, elbow_range])  # fmt: skip
        lower.add("geom", name="lower", fromto=[0, 0, 0, lower_length, 0, 0], material="link")
        lower.add("geom", name="tip", type="sphere", size=[0.012], pos=[lower_length, 0, 0],
                  material="tip")  # fmt: skip
        self.fingertip = lower.add("site", name="fingertip", pos=[lower_length, 0, 0],
                                   size=[0.005])  # fmt: skip
        self.joints = [self.shoulder, self.elbow]
        self.reach = upper_length + lower_length
        for joint in self.joints:
            if actuator == "motor":
                root.actuator.add("motor", name=joint.name, joint=joint, gear=[gear],
                                  ctrllimited=True, ctrlrange=[-1, 1])  # fmt: skip
            else:
                root.actuator.add("position", name=joint.name, joint=joint, kp=kp,
                                  forcelimited=True, forcerange=[-gear, gear])  # fmt: skip

    @composer.observable
    def joint_angles(self) -> observation.Observable:
        """(cos shoulder, cos elbow, sin shoulder, sin elbow)."""
        return HingeAngles(self.joints)

    @composer.observable
    def joint_velocities(self) -> observation.Observable:
        """Shoulder and elbow angular velocities (rad/s)."""
        return velocities(self.joints)

    @composer.observable
    def fingertip_position(self) -> observation.Observable:
        """World (x, y) of the fingertip (m)."""
        return Clipped("xpos", self.fingertip, -self.reach, self.reach, index=slice(0, 2))
