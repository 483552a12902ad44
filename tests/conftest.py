"""Shared paths to the real models the tests use: gymnasium's, mujoco's test models, and
the UR5e and Robotiq 2F-85 shipped with the package (entities/menagerie)."""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # before mujoco is imported: it reads it once

from pathlib import Path

import gymnasium
import hypothesis
import mujoco
import pytest

from entities import menagerie as shipped
from tests.ray_cluster import ray_cluster  # noqa: F401  (a fixture: one Ray cluster per session)

# Property tests are deterministic by default (the README's test command, CI): the same
# examples on every run and no example database, so a run's outcome never depends on an
# earlier one. `HYPOTHESIS_PROFILE=explore` searches with fresh random examples by hand,
# keeping failures in `.hypothesis/` to replay them (`--hypothesis-seed=N` picks a seed).
hypothesis.settings.register_profile("ci", derandomize=True, database=None)
hypothesis.settings.register_profile("explore", derandomize=False)
hypothesis.settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))

REPO = Path(__file__).resolve().parents[1]
GYM_ASSETS = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
MUJOCO_TESTDATA = Path(mujoco.__file__).parent / "testdata"
MENAGERIE = shipped.ROOT
UR5E = MENAGERIE / "universal_robots_ur5e" / "ur5e.xml"
ROBOTIQ = MENAGERIE / "robotiq_2f85" / "2f85.xml"
# Menagerie's own files (the UR5e with its OBJ meshes), beside the repository in CI only:
# the tests that compare the shipped files with them skip elsewhere.
ORIGINAL_MENAGERIE = REPO.parent / "shared" / "models" / "menagerie"


def gym_model(name: str) -> Path:
    """A MuJoCo model shipped with gymnasium, e.g. 'humanoid'."""
    return GYM_ASSETS / f"{name}.xml"


@pytest.fixture
def menagerie() -> Path:
    """The folder of the robots shipped with the package, laid out as Menagerie's."""
    return MENAGERIE
