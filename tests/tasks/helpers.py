"""What the task tests share: the registered ids and how to make them (skipping the
robot task when the Menagerie files are not beside the repository)."""

from __future__ import annotations

import gymnasium
import pytest

import tasks
from tests.conftest import MENAGERIE, ROBOTIQ, UR5E

NEEDS_MENAGERIE = {"composer/ArmPushBox-v0"}

# Documented flattened observation and action sizes (README's table says the same).
SIZES = {
    "composer/CartpoleSwingup-v0": (5, 1),
    "composer/Reach-v0": (10, 2),
    "composer/AntRun-v0": (28, 8),
    "composer/WalkerRun-v0": (18, 6),
    "composer/ArmPushBox-v0": (24, 7),
}


def has_menagerie() -> bool:
    """Whether the UR5e and 2F-85 folders are beside the repository."""
    return UR5E.exists() and ROBOTIQ.exists()


def ids() -> list:
    """Every id `import tasks` registers, as pytest params (robot task marked to skip)."""
    reason = f"menagerie robots not found at {MENAGERIE} (they come with ../shared in CI)"
    return [
        pytest.param(env_id, marks=pytest.mark.skipif(not has_menagerie(), reason=reason))
        if env_id in NEEDS_MENAGERIE
        else env_id
        for env_id in tasks.IDS
    ]


def make(env_id: str, **kwargs) -> gymnasium.Env:
    """gym.make(env_id, **kwargs)."""
    return gymnasium.make(env_id, **kwargs)
