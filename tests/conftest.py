"""Shared paths to the real models the tests use."""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # before mujoco is imported: it reads it once

from pathlib import Path

import gymnasium
import mujoco
import pytest

REPO = Path(__file__).resolve().parents[1]
GYM_ASSETS = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
MUJOCO_TESTDATA = Path(mujoco.__file__).parent / "testdata"
SHARED_MODELS = REPO.parent / "shared" / "models"
MENAGERIE = SHARED_MODELS / "menagerie"
UR5E = MENAGERIE / "universal_robots_ur5e" / "ur5e.xml"
ROBOTIQ = MENAGERIE / "robotiq_2f85" / "2f85.xml"


def gym_model(name: str) -> Path:
    """A MuJoCo model shipped with gymnasium, e.g. 'humanoid'."""
    return GYM_ASSETS / f"{name}.xml"


@pytest.fixture
def menagerie() -> Path:
    """The menagerie robots folder; skips when ../shared/models is not beside the repo."""
    if not UR5E.exists() or not ROBOTIQ.exists():
        pytest.skip(f"menagerie robots not found at {MENAGERIE} (they come with ../shared in CI)")
    return MENAGERIE
