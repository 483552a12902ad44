"""dm_control's utilities that Composer code imports next to `composer` and `mjcf`, as
`composer.utils`: a dm_control user changes `from dm_control.utils import rewards` to
`from composer.utils import rewards`.

    from composer.utils import inverse_kinematics, rewards, transformations

    reward = rewards.tolerance(height, bounds=(1.2, float("inf")), margin=0.6)
    quat = transformations.euler_to_quat([0.1, 0.2, 0.3], ordering="XYZ")
    result = inverse_kinematics.qpos_from_site_pose(physics, "arm/grip", target_pos=[0.3, 0, 0.4])

- `rewards`: `tolerance` with all of dm_control's sigmoids (and `Tolerance`, the same
  built once for every step).
- `transformations`: quaternion, Euler angle, axis-angle and rotation matrix conversions
  and products.
- `inverse_kinematics`: `qpos_from_site_pose` and `nullspace_method` on an `mjcf.Physics`.

Each gives dm_control's values (tests/composer/test_utils_reference.py compares them with
dm_control's own modules, and tests/composer/test_dm_control_utils.py runs dm_control's
tests of them on these). The modules are imported when asked for (`composer.utils.rewards`
too): `import composer` loads none of them; `composer.variation`, loaded on first use,
brings `transformations` for its rotations, as dm_control's does.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from composer.errors import (
    EulerOrderingError,
    InverseKinematicsError,
    RewardError,
    TransformationError,
)

_MODULES = ("inverse_kinematics", "rewards", "transformations")

__all__ = [
    "EulerOrderingError",
    "InverseKinematicsError",
    "RewardError",
    "TransformationError",
    "inverse_kinematics",
    "rewards",
    "transformations",
]


def __getattr__(name: str) -> ModuleType:
    """`composer.utils.rewards` and the others, imported on first use."""
    if name in _MODULES:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
