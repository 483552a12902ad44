"""Robots from real MJCF files: any file, MuJoCo Menagerie folders, an arm with a gripper.

    arm = robots.from_path('ur5e.xml')                              # a ModelEntity
    gripper = robots.from_menagerie('robotiq_2f85')   # $MENAGERIE_ROOT, then the shipped ones
    robot = robots.ArmWithGripper(arm, gripper, attach_site='attachment_site', tcp_site='pinch')
    arena.attach(robot, attach_site=table.mount)
    physics.bind(robot.tcp).xpos             # tool centre point; ur5e_with_2f85(): shipped

Robots are `composer.ModelEntity`s: their actuators are the action; their observables
`joint_positions`, `joint_velocities`, `actuator_activations` and `sensors` are enabled.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import composer
import mjcf
from entities import menagerie

MENAGERIE_ENV = "MENAGERIE_ROOT"


class RobotError(composer.EntityError):
    """A robot file or folder cannot be used: a site missing, several candidate files."""


class RobotNotFoundError(RobotError, FileNotFoundError):
    """A robot's files were not found; the message lists where they were looked for."""


def from_path(
    path: str | os.PathLike[str], name: str | None = None, without_floor: bool = False
) -> composer.ModelEntity:
    """The robot in the MJCF file `path` (renamed `name` if given). `without_floor` drops
    the ground a standalone robot file brings (the planes directly in its worldbody, as in
    gymnasium's ant.xml and humanoid.xml), which would lie in the arena's floor, drawn over
    it in renders; the robot then stands on the arena's floor. Raises RobotNotFoundError
    for a missing file and mjcf.Error subclasses for a bad one."""
    file = Path(path).expanduser()
    if not file.is_file():
        raise RobotNotFoundError(f"no robot file at {str(file)!r}")
    robot = composer.Entity.from_path(file, name=name)
    if without_floor:
        for geom in robot.mjcf_model.worldbody.get_children("geom"):
            if geom.type == "plane":
                geom.remove()
    return robot


def menagerie_roots(root: str | os.PathLike[str] | None = None) -> list[Path]:
    """The Menagerie folders `from_menagerie` searches without the package, in order:
    `root`, $MENAGERIE_ROOT, and the robots shipped with this package (`menagerie.ROOT`)."""
    roots = [Path(root).expanduser()] if root is not None else []
    if os.environ.get(MENAGERIE_ENV):
        roots.append(Path(os.environ[MENAGERIE_ENV]).expanduser())
    roots.append(menagerie.ROOT)
    return roots


def _package_folder(name: str, download: bool, looked: list[str]) -> Path | None:
    """The robot folder from the mujoco_menagerie package's cache, or None (noted)."""
    try:
        import mujoco_menagerie
    except ImportError:
        looked.append("the mujoco_menagerie package (not installed: pip install mujoco-menagerie)")
        return None
    try:
        robot = mujoco_menagerie.get(name)
        cache = mujoco_menagerie.Cache()
        if download or cache.root is not None or cache.is_cached(robot):
            return Path(robot.path(cache, progress=None))
        looked.append(
            f"the mujoco_menagerie cache {cache.model_path(robot)} (not downloaded; pass "
            "download=True)"
        )
    except mujoco_menagerie.MenagerieError as e:
        looked.append(f"the mujoco_menagerie package ({e})")
    return None


def _robot_file(folder: Path, model: str | None) -> Path:
    """The robot XML in a Menagerie folder; raises RobotError when it is ambiguous."""
    if model is not None:
        file = folder / model
        if not file.is_file():
            raise RobotNotFoundError(f"no file {model!r} in the robot folder {str(folder)!r}")
        return file
    candidates = sorted(p for p in folder.glob("*.xml") if not p.name.startswith(("scene", "mjx_")))
    if len(candidates) != 1:
        names = [p.name for p in candidates]
        raise RobotError(
            f"the robot folder {str(folder)!r} has {len(candidates)} candidate robot files "
            f"{names}; pass model='<file>.xml'"
        )
    return candidates[0]


def from_menagerie(
    name: str,
    root: str | os.PathLike[str] | None = None,
    *,
    model: str | None = None,
    download: bool = False,
) -> composer.ModelEntity:
    """The Menagerie robot `name` (a folder name, e.g. 'universal_robots_ur5e').

    The folder `<name>/` is looked for in, in order: `root`, the `MENAGERIE_ROOT`
    environment variable (a clone of MuJoCo Menagerie, for any of its robots), the robots
    shipped with this package (`entities.menagerie`: the UR5e and the Robotiq 2F-85), and
    the `mujoco_menagerie` package's download cache when that package is installed
    (`download=True` lets it download). In a folder, the robot is the one XML file that is
    not a scene (`scene*.xml`) or an MJX variant (`mjx_*.xml`), else `model` names it.
    Raises RobotNotFoundError listing every place looked, RobotError for an ambiguous folder.
    """
    looked: list[str] = []
    for base in menagerie_roots(root):
        folder = base / name
        if folder.is_dir():
            return from_path(_robot_file(folder, model))
        looked.append(str(folder))
    downloaded = _package_folder(name, download, looked)
    if downloaded is not None:
        return from_path(_robot_file(downloaded, model))
    raise RobotNotFoundError(f"Menagerie robot {name!r} not found; looked in: " + "; ".join(looked))


class ArmWithGripper(composer.Entity):
    """An arm entity with a gripper entity attached at one of the arm's sites, under one
    root named `name`: entities `arm` and `gripper`, site `tcp` (the tool centre point)."""

    def _build(
        self,
        arm: composer.Entity,
        gripper: composer.Entity,
        attach_site: str | mjcf.Element = "attachment_site",
        tcp_site: str | None = None,
        name: str | None = None,
    ) -> None:
        """Attach `gripper` to `arm` at `attach_site` (a site name in the arm's model, or
        the element); `tcp_site` names the gripper's tool site (None: the attach site).
        Raises RobotError for a site that does not exist (listing those that do) and
        EntityError when an entity is attached already."""
        self._mjcf_root = mjcf.RootElement(model=name or f"{arm.name}_{gripper.name}")
        site = _find_site(arm, attach_site)
        tcp = site if tcp_site is None else _find_site(gripper, tcp_site)
        self.attach(arm)
        arm.attach(gripper, attach_site=site)
        self.arm = arm
        self.gripper = gripper
        self.tcp = tcp


def _find_site(entity: composer.Entity, site: str | mjcf.Element) -> mjcf.Element:
    if not isinstance(site, str):
        return site
    found = entity.mjcf_model.find("site", site)
    if found is None:
        known = [s.name for s in _sites(entity)]
        raise RobotError(f"entity {entity.name!r} has no site {site!r}; its sites: {known}")
    return found


def _sites(entity: composer.Entity) -> Iterator[mjcf.Element]:
    yield from entity.mjcf_model.find_all("site", exclude_attachments=True)


def ur5e_with_2f85(root: str | os.PathLike[str] | None = None) -> ArmWithGripper:
    """A Universal Robots UR5e with a Robotiq 2F-85 at its flange (tcp: the 'pinch' site
    between the fingers): the files shipped with this package, or with `root` the
    Menagerie folders found from there as `from_menagerie` does ($MENAGERIE_ROOT does not
    replace the shipped files here, so a task built on them is the same everywhere)."""
    base = menagerie.ROOT if root is None else root
    arm = from_menagerie("universal_robots_ur5e", base)
    gripper = from_menagerie("robotiq_2f85", base)
    return ArmWithGripper(arm, gripper, "attachment_site", tcp_site="pinch", name="robot")
