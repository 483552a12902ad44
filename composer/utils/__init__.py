"""dm_control's utilities that Composer code imports, as `composer.utils`: `from
dm_control.utils import rewards` becomes `from composer.utils import rewards`.

    from composer.utils import inverse_kinematics, rewards, transformations
    reward = rewards.tolerance(height, bounds=(1.2, float("inf")), margin=0.6)
    quat = transformations.euler_to_quat([0.1, 0.2, 0.3], ordering="XYZ")
    result = inverse_kinematics.qpos_from_site_pose(physics, "arm/grip", target_pos=[0.3, 0, 0.4])

Promise: each gives dm_control's values (tests/composer/test_utils_reference.py); each module
is imported when first asked for, so `import composer` loads none of them.
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

# Imported on first use, so `import composer` loads none of them (`composer.variation`,
# itself loaded on first use, imports `transformations` for its rotations, as dm_control's).
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
