"""Humanoid_CMU: stand up, walk and run with the 56-joint CMU humanoid (dm_control's
`humanoid_CMU`).

    env = gym.make('dm_control/humanoid_CMU-run-v0')

The humanoid domain's task (`tasks.suite.humanoid`: the same observations, reward and
random start) with the CMU body: the thorax is the frame of `extremities` and
`torso_vertical`, and 'upright' is its y axis (which runs up the spine) along the world's
z. Observations: `joint_angles` (56), `head_height`, `extremities` (12), `torso_vertical`
(3), `com_velocity` (3), `velocity` (62). 1,000 steps of 20 ms.
"""

from __future__ import annotations

from arenas.suite import SuiteArena
from entities.suite import HumanoidCMU as HumanoidCMURobot
from tasks.suite import registry
from tasks.suite.humanoid import RUN_SPEED, WALK_SPEED, Biped, BipedParts

TIME_LIMIT = 20.0
CONTROL_TIMESTEP = 0.02


class HumanoidCMU(Biped):
    """Stand, walk or run with the CMU humanoid (module docstring)."""

    def __init__(self, move_speed: float = 0.0, control_timestep: float | None = None) -> None:
        """As `tasks.suite.humanoid.Biped`, in the CMU humanoid's world, with its 20 ms
        control step."""
        self.humanoid = HumanoidCMURobot()
        arena = SuiteArena(floor_size=(100.0, 100.0, 0.2))
        # The file's main defaults reach its floor too.
        arena.mjcf_model.default.geom.set_attributes(
            friction=[0.7], solref=[0.015, 1], solimp=[0.95, 0.99, 0.003]
        )
        arena.add_light(name="tracking_light", pos=[0, 0, 7], dir=[0, 0, -1], mode="trackcom")
        world = arena.mjcf_model.worldbody
        world.add("camera", name="back", pos=[0, 3, 2.4], xyaxes=[-1, 0, 0, 0, -1, 2],
                  mode="trackcom")  # fmt: skip
        world.add("camera", name="side", pos=[-3, 0, 2.4], xyaxes=[0, -1, 0, 1, 0, 2],
                  mode="trackcom")  # fmt: skip
        arena.attach(self.humanoid)
        left_hand, right_hand = self.humanoid.hands
        left_foot, right_foot = self.humanoid.feet
        parts = BipedParts(
            upright_body=self.humanoid.thorax,
            upright_entry=7,  # z of the thorax' y axis
            head=self.humanoid.head,
            extremities=(left_hand, left_foot, right_hand, right_foot),
            subtree_velocity=self.humanoid.subtree_velocity,
        )
        self.render_camera = "back"
        super().__init__(arena, parts, move_speed, False, control_timestep, CONTROL_TIMESTEP)


for _name, _speed, _description in (
    ("stand", 0.0, "Stand up and stay still with the CMU humanoid"),
    ("walk", WALK_SPEED, "Walk at 1 m/s with the CMU humanoid"),
    ("run", RUN_SPEED, "Run at 10 m/s with the CMU humanoid"),
):
    registry.add(
        registry.SuiteEntry(
            "humanoid_CMU", _name, HumanoidCMU, {"move_speed": _speed}, TIME_LIMIT, _description
        )
    )
