"""What the task tests share: the documented sizes of the registered ids, and making them."""

from __future__ import annotations

import gymnasium

# Documented flattened observation and action sizes (README's table says the same).
SIZES = {
    "composer/CartpoleSwingup-v0": (5, 1),
    "composer/Reach-v0": (10, 2),
    "composer/AntRun-v0": (28, 8),
    "composer/WalkerRun-v0": (18, 6),
    "composer/ArmPushBox-v0": (24, 7),
}


def make(env_id: str, **kwargs) -> gymnasium.Env:
    """gym.make(env_id, **kwargs)."""
    return gymnasium.make(env_id, **kwargs)
