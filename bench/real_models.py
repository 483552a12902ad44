"""The real MJCF files the benchmarks read: gymnasium's, the Menagerie robots we ship, and
dm_control's walkers, taken from its published wheel at run time (nothing committed).

    files, note = real_models.files()     # {'rodent': Path(...), ...}; why some are absent

The walkers come from dm-control's wheel, downloaded once into the cache the tests use
(`tests/dm_control_wheel.fetch`: `$COMPOSER_TEST_CACHE` or the system's temporary
folder), with its walkers' folder (and the suite's dog meshes, which the dog names)
unpacked beside it as the wheel lays them out, so that their meshes and skins are where
the files name them. Offline and without the cached wheel, they are left out and
`note` says why.
"""

from __future__ import annotations

import os
import shutil
import zipfile
from pathlib import Path

import gymnasium

from tests import dm_control_wheel

REPO = Path(__file__).resolve().parents[1]
GYM = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
MENAGERIE = REPO / "entities" / "menagerie"  # shipped with the package

SHIPPED = {
    "humanoid": GYM / "humanoid.xml",
    "ant": GYM / "ant.xml",
    "ur5e": MENAGERIE / "universal_robots_ur5e" / "ur5e.xml",
    "2f85": MENAGERIE / "robotiq_2f85" / "2f85.xml",
}
# dm_control's walkers, by their paths under the wheel's walkers' assets folder; the
# folders unpacked.
_WALKERS_FOLDER = "dm_control/locomotion/walkers/assets/"
_UNPACKED = (_WALKERS_FOLDER, "dm_control/suite/dog_assets/")
WALKERS = {
    "rodent": "rodent.xml",
    "cmu_v2020": "humanoid_CMU_V2020.xml",
    "cmu_v2019": "humanoid_CMU_V2019.xml",
    "dog": "dog_v2/dog.xml",
    "fruitfly": "fruitfly_v2/fruitfly.xml",
    "jumping_ball": "jumping_ball/jumping_ball_with_head.xml",
}


def walkers() -> dict[str, Path]:
    """dm_control's walkers' files, unpacked from its wheel (see the module docstring).
    Raises dm_control_wheel.Unavailable when the wheel cannot be had."""
    wheel = dm_control_wheel.fetch()
    folder = wheel.parent / f"walkers-{dm_control_wheel.VERSION}"
    if not folder.is_dir():
        staging = folder.with_name(f"{folder.name}.partial-{os.getpid()}")
        with zipfile.ZipFile(wheel) as archive:
            members = [m for m in archive.namelist() if m.startswith(_UNPACKED)]
            archive.extractall(staging, members)
        try:
            os.replace(staging, folder)
        except OSError:  # another process unpacked it first
            if not folder.is_dir():
                raise
        finally:
            shutil.rmtree(staging, ignore_errors=True)
    return {name: folder / _WALKERS_FOLDER / path for name, path in WALKERS.items()}


def files(*names: str) -> tuple[dict[str, Path], str]:
    """The real files `names` (all by default) by name: the shipped ones, then the walkers
    when the wheel can be had (it is fetched only when a walker is asked for); and a note
    saying why walkers are left out ('' when none is). Raises KeyError for an unknown
    name."""
    unknown = set(names) - set(SHIPPED) - set(WALKERS)
    if unknown:
        raise KeyError(f"unknown model(s) {sorted(unknown)}; known: {[*SHIPPED, *WALKERS]}")
    wanted = names or (*SHIPPED, *WALKERS)
    found, note = {name: SHIPPED[name] for name in wanted if name in SHIPPED}, ""
    if any(name in WALKERS for name in wanted):
        try:
            unpacked = walkers()
        except dm_control_wheel.Unavailable as error:
            note = f"dm_control's walkers left out: {error}"
        else:
            found.update({name: unpacked[name] for name in wanted if name in WALKERS})
    return found, note
