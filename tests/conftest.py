"""Shared paths to the real models the tests use: gymnasium's, mujoco's test models, and
the UR5e and Robotiq 2F-85 shipped with the package (entities/menagerie); after each test,
once a worker's memory has grown, what the tests freed is handed back (see _TRIM_STEP)."""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")  # before mujoco is imported: it reads it once

import ctypes
import fcntl
import gc
import shutil
import subprocess
import sys
from collections.abc import Iterator
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
# The packages the wheel installs, and the checkout's other Python folders, which it must not.
INSTALLED_PACKAGES = ("mjcf", "composer", "entities", "arenas", "tasks")
NOT_INSTALLED = ("tools", "bench", "tests")


# What the tests free stays in the worker's memory twice over: environments a test does not
# close are cycles of objects, freed at Python's rare full collections, and glibc keeps what
# freed allocations leave in its heaps (MJCF trees, MuJoCo models and frames of every size:
# fragments it cannot hand back one by one). A worker's resident memory grew to 6.4 GB, 2.0
# GB of it in use. Once it has grown by _TRIM_STEP since, a collection frees those cycles
# and malloc_trim hands the free pages back; what the tests hold is untouched, so a leak
# still shows. The objects made before the first test (modules, the tests collected) are
# left out of every collection (gc.freeze): a full collection costs milliseconds, not 0.5 s.
_TRIM_STEP = 512 << 20
_STATM = Path("/proc/self/statm")
_malloc_trim = getattr(ctypes.CDLL(None), "malloc_trim", None) if _STATM.exists() else None
_trimmed_at = [0]


def _resident_bytes() -> int:
    return int(_STATM.read_text().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def pytest_collection_finish(session: pytest.Session) -> None:
    """Before the first test: what exists now is never garbage (see _TRIM_STEP)."""
    gc.collect()
    gc.freeze()


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_teardown(item: pytest.Item) -> Iterator[None]:
    """After each test's teardown: unreachable cycles freed and glibc's free pages handed
    back, once the resident memory has grown by _TRIM_STEP (see there)."""
    yield
    if _malloc_trim is not None and _resident_bytes() > _trimmed_at[0] + _TRIM_STEP:
        gc.collect()
        _malloc_trim(0)
        _trimmed_at[0] = _resident_bytes()


def gym_model(name: str) -> Path:
    """A MuJoCo model shipped with gymnasium, e.g. 'humanoid'."""
    return GYM_ASSETS / f"{name}.xml"


@pytest.fixture
def menagerie() -> Path:
    """The folder of the robots shipped with the package, laid out as Menagerie's."""
    return MENAGERIE


@pytest.fixture(scope="session")
def built_wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The project's wheel, built offline (pip, no build isolation) from a copy of the
    checkout's Python folders, those not installed included; built once per test run,
    shared by pytest-xdist's workers through a lock in their common temporary folder."""
    base = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        base = base.parent
    with open(base / "built_wheel.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        folder = base / "built_wheel"
        if not list(folder.glob("dist/*.whl")):
            shutil.rmtree(folder, ignore_errors=True)  # what a failed build left
            sources = folder / "src"
            ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "corpus", "results")
            for name in (*INSTALLED_PACKAGES, *NOT_INSTALLED):
                shutil.copytree(REPO / name, sources / name, ignore=ignore)
            for file in ("pyproject.toml", "README.md"):
                shutil.copy(REPO / file, sources / file)
            pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "-q", "wheel"]
            build = ["--no-deps", "--no-build-isolation", "--no-index", "-w", "dist", "./src"]
            subprocess.run([*pip, *build], check=True, cwd=folder)
        (wheel,) = folder.glob("dist/*.whl")
    return wheel
