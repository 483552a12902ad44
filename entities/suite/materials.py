"""The Control Suite's shared materials, which every suite robot's model carries.

    root = mjcf.RootElement(model="walker")
    add_materials(root)                  # self, effector, decoration ... as the suite names them
    body.add("geom", material="self", ...)

dm_control's suite models include one file of materials (`common/materials.xml`); the world
half of it (the checkered `grid`) is the suite arena's (`arenas.suite.SuiteArena`), this half
belongs to the robot, whose geoms name these materials.
"""

from __future__ import annotations

import mjcf

# (name, rgba) in the suite's order: a compiled model's materials keep it. The `*_default`
# and `*_highlight` pairs are what a task blends `self`, `effector` and `target` between when
# it colours them by the reward (`visualize_reward`).
MATERIALS: tuple[tuple[str, tuple[float, float, float, float]], ...] = (
    ("self", (0.7, 0.5, 0.3, 1.0)),
    ("self_default", (0.7, 0.5, 0.3, 1.0)),
    ("self_highlight", (0.0, 0.5, 0.3, 1.0)),
    ("effector", (0.7, 0.4, 0.2, 1.0)),
    ("effector_default", (0.7, 0.4, 0.2, 1.0)),
    ("effector_highlight", (0.0, 0.5, 0.3, 1.0)),
    ("decoration", (0.3, 0.5, 0.7, 1.0)),
    ("eye", (0.0, 0.2, 1.0, 1.0)),
    ("target", (0.6, 0.3, 0.3, 1.0)),
    ("target_default", (0.6, 0.3, 0.3, 1.0)),
    ("target_highlight", (0.6, 0.3, 0.3, 0.4)),
    ("site", (0.5, 0.5, 0.5, 0.3)),
)


def add_materials(root: mjcf.RootElement) -> None:
    """Add the suite's robot materials to `root`'s assets, in the suite's order."""
    for name, rgba in MATERIALS:
        root.asset.add("material", name=name, rgba=list(rgba))
