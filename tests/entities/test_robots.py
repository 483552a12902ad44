"""Real robots: files, Menagerie folders (given, searched, from the package cache), and
the UR5e + Robotiq 2F-85 pair."""

from __future__ import annotations

import sys
import types

import mujoco
import numpy as np
import pytest

import composer
import mjcf
from arenas import Floor
from entities import menagerie, robots

TINY_ROBOT = """<mujoco model="tiny">
  <worldbody><body name="link"><joint name="hinge"/><geom size="0.1"/>
    <site name="flange"/></body></worldbody>
  <actuator><motor joint="hinge"/></actuator>
</mujoco>"""


@pytest.fixture
def no_search_paths(monkeypatch, tmp_path):
    """Nothing to find: no $MENAGERIE_ROOT, no shipped robots, no package."""
    monkeypatch.delenv(robots.MENAGERIE_ENV, raising=False)
    monkeypatch.setattr(robots.menagerie, "ROOT", tmp_path / "shipped")
    monkeypatch.setitem(sys.modules, "mujoco_menagerie", None)  # import fails
    return tmp_path


def robot_folder(base, name="tiny_robot", files=("tiny.xml",)):
    folder = base / name
    folder.mkdir(parents=True)
    for file in files:
        (folder / file).write_text(TINY_ROBOT)
    return folder


def test_from_path_makes_a_model_entity_with_default_observables(tmp_path):
    folder = robot_folder(tmp_path)
    robot = robots.from_path(folder / "tiny.xml", name="renamed")
    assert isinstance(robot, composer.ModelEntity) and robot.name == "renamed"
    assert {"joint_positions", "joint_velocities"} <= set(robot.observables)
    with pytest.raises(robots.RobotNotFoundError, match="no robot file"):
        robots.from_path(tmp_path / "missing.xml")


def test_from_menagerie_finds_the_robot_file_in_a_given_root(no_search_paths):
    root = no_search_paths / "menagerie"
    robot_folder(root, files=("tiny.xml", "scene.xml", "mjx_tiny.xml"))
    robot = robots.from_menagerie("tiny_robot", root=root)
    assert robot.name == "tiny" and len(robot.actuators) == 1


def test_from_menagerie_asks_for_model_when_a_folder_has_several_robots(no_search_paths):
    robot_folder(no_search_paths, files=("left.xml", "right.xml"))
    with pytest.raises(robots.RobotError, match=r"\['left.xml', 'right.xml'\]; pass model="):
        robots.from_menagerie("tiny_robot", root=no_search_paths)
    assert robots.from_menagerie("tiny_robot", root=no_search_paths, model="right.xml")


def test_from_menagerie_searches_the_environment_variable(no_search_paths, monkeypatch):
    robot_folder(no_search_paths / "env_root")
    monkeypatch.setenv(robots.MENAGERIE_ENV, str(no_search_paths / "env_root"))
    assert robots.from_menagerie("tiny_robot").name == "tiny"


def test_missing_robot_error_lists_every_place_looked(no_search_paths):
    with pytest.raises(robots.RobotNotFoundError) as caught:
        robots.from_menagerie("tiny_robot", root=no_search_paths / "given")
    message = str(caught.value)
    assert str(no_search_paths / "given" / "tiny_robot") in message
    assert str(no_search_paths / "shipped" / "tiny_robot") in message
    assert "pip install mujoco-menagerie" in message
    assert isinstance(caught.value, composer.Error)


def fake_menagerie_package(folder, cached: bool) -> types.ModuleType:
    """A stand-in for the mujoco_menagerie package's API that from_menagerie uses."""

    class MenagerieError(Exception):
        pass

    class Robot:
        name = "tiny_robot"

        def path(self, cache, progress=None):
            return folder

    class Cache:
        root = None

        def is_cached(self, robot):
            return cached

        def model_path(self, robot):
            return folder

    def get(name):
        if name != "tiny_robot":
            raise MenagerieError(f"unknown robot {name!r}")
        return Robot()

    return types.SimpleNamespace(get=get, Cache=Cache, MenagerieError=MenagerieError)


def test_from_menagerie_uses_the_package_cache_only_when_cached_or_asked(
    no_search_paths, monkeypatch
):
    folder = robot_folder(no_search_paths / "cache")
    monkeypatch.setitem(sys.modules, "mujoco_menagerie", fake_menagerie_package(folder, True))
    assert robots.from_menagerie("tiny_robot").name == "tiny"
    monkeypatch.setitem(sys.modules, "mujoco_menagerie", fake_menagerie_package(folder, False))
    with pytest.raises(robots.RobotNotFoundError, match="not downloaded; pass download=True"):
        robots.from_menagerie("tiny_robot")
    assert robots.from_menagerie("tiny_robot", download=True).name == "tiny"
    with pytest.raises(robots.RobotNotFoundError, match="unknown robot 'other'"):
        robots.from_menagerie("other")


def test_arm_with_gripper_attaches_at_the_named_site(tmp_path):
    arm = robots.from_path(robot_folder(tmp_path, "arm") / "tiny.xml", name="arm")
    hand = robots.from_path(robot_folder(tmp_path, "hand") / "tiny.xml", name="hand")
    with pytest.raises(robots.RobotError, match=r"no site 'wrist'; its sites: \['flange'\]"):
        robots.ArmWithGripper(arm, hand, attach_site="wrist")
    pair = robots.ArmWithGripper(arm, hand, attach_site="flange", name="pair")
    assert [e.name for e in pair.iter_entities()] == ["pair", "arm", "hand"]
    assert hand.parent is arm and pair.tcp.name == "flange"


def test_the_shipped_robots_come_before_the_package_and_after_menagerie_root(monkeypatch, tmp_path):
    monkeypatch.setenv(robots.MENAGERIE_ENV, str(tmp_path))
    assert robots.menagerie_roots() == [tmp_path, menagerie.ROOT]
    mine = robot_folder(tmp_path, "universal_robots_ur5e")
    assert robots.from_menagerie("universal_robots_ur5e").name == "tiny"  # $MENAGERIE_ROOT's
    # The pair is the shipped files unless a root is given, so tasks are the same everywhere.
    shipped = robots.ur5e_with_2f85()
    assert shipped.arm.name == "ur5e"
    with pytest.raises(robots.RobotError, match="entity 'tiny' has no site 'attachment_site'"):
        robots.ur5e_with_2f85(root=mine.parent)  # the tiny arm in the given root is used


def test_real_ur5e_with_robotiq_2f85():
    robot = robots.ur5e_with_2f85()
    arena = Floor()
    arena.attach(robot)
    env = composer.Environment(composer.NullTask(arena))
    assert env.action_space.shape == (7,)  # six arm servos and the gripper
    physics = env.physics
    arm_joints = robot.arm.mjcf_model.find_all("joint", exclude_attachments=True)
    assert len(arm_joints) == 6
    physics.bind(arm_joints).qpos = [-1.5708, -1.5708, 1.5708, -1.5708, -1.5708, 0]
    physics.forward()
    tcp = physics.bind(robot.tcp)
    np.testing.assert_allclose(tcp.xmat.reshape(3, 3)[:, 2], [0, 0, -1], atol=1e-3)  # down
    flange = physics.bind(robot.arm.mjcf_model.find("site", "attachment_site")).xpos
    assert 0.1 < np.linalg.norm(tcp.xpos - flange) < 0.2  # the fingers' length


def test_a_standalone_robot_file_s_floor_can_be_dropped_for_the_arena_s(tmp_path):
    from arenas import Floor
    from tests.conftest import gym_model

    def planes(without_floor: bool) -> tuple[list[str], float]:
        arena = Floor()
        ant = robots.from_path(gym_model("ant"), without_floor=without_floor)
        arena.add_free_entity(ant)
        physics = mjcf.Physics.from_mjcf_model(arena.mjcf_model)
        model = physics.model
        names = [model.geom(i).name for i in range(model.ngeom)
                 if model.geom_type[i] == mujoco.mjtGeom.mjGEOM_PLANE]  # fmt: skip
        physics.step(500)  # 5 s: the ant settles on whatever ground is there
        return names, float(physics.named.data.xpos["ant/torso", "z"])

    names, _ = planes(without_floor=False)
    assert sorted(names) == ["ant/floor", "floor"]  # two grounds in one place
    names, height = planes(without_floor=True)
    assert names == ["floor"]  # the arena's alone
    assert 0.2 < height < 1.0  # standing on it, not fallen through
