"""Copies of a model compose with their meshes and textures compiled once (mjcf.compose.sharing):
the compiled scene is what the unshared scene is, but for the duplicated assets, and the
copies' trees and names are untouched."""

from __future__ import annotations

import copy
import re
import shutil
from pathlib import Path

import mujoco
import numpy as np
import pytest

import mjcf
from tests.conftest import MENAGERIE
from tests.mjcf.compare import model_differences

ROBOT_FOLDERS = ("universal_robots_ur5e", "robotiq_2f85")


def _arm(menagerie: Path) -> mjcf.RootElement:
    arm = mjcf.from_path(menagerie / "universal_robots_ur5e" / "ur5e.xml")
    arm.find("site", "attachment_site").attach(
        mjcf.from_path(menagerie / "robotiq_2f85" / "2f85.xml")
    )
    return arm


def _scene(arms: list[mjcf.RootElement]) -> mjcf.RootElement:
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("geom", name="floor", type="plane", size=[5, 5, 0.1])
    for i, arm in enumerate(arms):
        arm.model = f"arm{i}"
        scene.attach(arm).pos = [0, 1.0 * i, 0]
    return scene


def _rollout(physics: mjcf.Physics, steps: int = 100) -> np.ndarray:
    controls = np.random.default_rng(0).uniform(-1, 1, (steps, physics.model.nu))
    states = []
    for control in controls:
        physics.data.ctrl[:] = control * physics.model.actuator_ctrlrange[:, 1]
        physics.step()
        states.append(np.concatenate([physics.data.qpos, physics.data.qvel]))
    return np.array(states)


def test_copies_of_a_robot_compile_its_meshes_once_and_simulate_as_unshared_copies(
    menagerie, tmp_path: Path
) -> None:
    one = mjcf.Physics.from_mjcf_model(_scene([_arm(menagerie)])).model
    arm = _arm(menagerie)
    shared = mjcf.Physics.from_mjcf_model(_scene([copy.deepcopy(arm) for _ in range(3)]))
    assert shared.model.nmesh == one.nmesh == 28  # 20 of the UR5e's, 8 of the 2F-85's
    assert mujoco.mj_sizeModel(shared.model) < 1.1 * mujoco.mj_sizeModel(one)
    # The same robots from three folders of their own: three sets of meshes, as MuJoCo
    # compiles files it finds in different places; otherwise the same scene.
    folders = []
    for i in range(3):
        for name in ROBOT_FOLDERS:
            shutil.copytree(menagerie / name, tmp_path / str(i) / name)
        folders.append(_arm(tmp_path / str(i)))
    unshared = mjcf.Physics.from_mjcf_model(_scene(folders))
    assert unshared.model.nmesh == 3 * 28
    for size in ("nbody", "njnt", "ngeom", "nq", "nu", "nsite"):
        assert getattr(shared.model, size) == getattr(unshared.model, size), size
    np.testing.assert_array_equal(shared.model.geom_size, unshared.model.geom_size)
    np.testing.assert_array_equal(shared.model.body_mass, unshared.model.body_mass)
    np.testing.assert_array_equal(_rollout(shared), _rollout(unshared))


def test_copies_keep_their_own_elements_and_names(menagerie) -> None:
    arms = [copy.deepcopy(_arm(menagerie)) for _ in range(2)]
    scene = _scene(arms)
    physics = mjcf.Physics.from_mjcf_model(scene)
    first, second = (arm.find("mesh", "base_0") for arm in arms)
    assert first is not second
    assert second.full_identifier == "arm1/base_0"
    assert physics.bind(second).vertnum == physics.bind(first).vertnum > 0
    assert physics.model.mesh(int(physics.bind(second).element_id)).name == "arm0/base_0"
    geom = next(g for g in arms[1].find_all("geom") if g.mesh is second)
    mesh_of_geom = physics.model.geom_dataid[physics.bind(geom).element_id]
    assert mesh_of_geom == physics.bind(first).element_id
    gripper_pad = arms[1].find("mesh", "robotiq_2f85/pad")
    assert (
        physics.bind(gripper_pad).element_id
        == physics.bind(arms[0].find("mesh", "robotiq_2f85/pad")).element_id
    )


def test_written_scene_holds_each_file_once_and_stock_mujoco_compiles_it_to_ours(
    menagerie, tmp_path: Path
) -> None:
    scene = _scene([copy.deepcopy(_arm(menagerie)) for _ in range(2)])
    ours = mjcf.Physics.from_mjcf_model(scene).model
    xml, assets = scene.to_xml_string(), scene.get_assets()
    assert len(re.findall(r"<mesh [^>]*file=", xml)) == 28
    assert model_differences(ours, mujoco.MjModel.from_xml_string(xml, assets)) == []
    out = Path(mjcf.export_with_assets(scene, tmp_path / "out"))
    assert len(list(out.parent.iterdir())) == 1 + 28
    assert model_differences(ours, mujoco.MjModel.from_xml_path(str(out))) == []


def _textured(name: str) -> mjcf.RootElement:
    model = mjcf.RootElement(model=name)
    grid = model.asset.add(
        "texture", name="grid", type="2d", builtin="checker", rgb1=[0.1, 0.2, 0.3],
        rgb2=[0.2, 0.3, 0.4], width=256, height=256,
    )  # fmt: skip
    model.asset.add("material", name="grid", texture=grid, texrepeat=[2, 2])
    body = model.worldbody.add("body", name="box")
    body.add("geom", type="box", size=[0.1, 0.1, 0.1], material="grid")
    return model


def test_textures_are_shared_and_each_copy_keeps_its_material() -> None:
    models = [_textured("a"), _textured("b"), _textured("c")]
    models[2].find("texture", "grid").width = 128  # another texture: its own
    scene = mjcf.RootElement(model="scene")
    for model in models:
        scene.attach(model)
    compiled = mjcf.Physics.from_mjcf_model(scene).model
    assert compiled.ntex == 2 and compiled.nmat == 3
    texture_of = [compiled.mat_texid[i, mujoco.mjtTextureRole.mjTEXROLE_RGB] for i in range(3)]
    assert texture_of[0] == texture_of[1] != texture_of[2]
    assert compiled.tex_width[texture_of[2]] == 128


def test_what_compiles_differently_is_not_shared(menagerie) -> None:
    arms = [copy.deepcopy(_arm(menagerie)) for _ in range(4)]
    arms[1].find("mesh", "base_0").scale = [2, 2, 2]  # its own attribute
    arms[2].default.mesh.scale = [0.5, 0.5, 0.5]  # its main class: all its meshes
    scene = _scene(arms)
    compiled = mjcf.Physics.from_mjcf_model(scene).model
    # The gripper's meshes take their scale from its own class, which the change to arm
    # 2's main class leaves alone: only the UR5e's 20 change there.
    assert compiled.nmesh == 28 + 1 + 20
    scaled = mujoco.mj_name2id(compiled, mujoco.mjtObj.mjOBJ_MESH, "arm1/base_0")
    assert scaled >= 0
    # Within one model, two identical meshes stay two, as the model's author wrote them.
    model = mjcf.from_path(MENAGERIE / "robotiq_2f85" / "2f85.xml")
    pad = model.find("mesh", "pad")
    model.asset.add("mesh", name="pad_again", file=pad.file, dclass=pad.dclass)
    assert mjcf.Physics.from_mjcf_model(model).model.nmesh == 9


def test_a_write_through_a_shared_mesh_is_refused_and_says_how_to_compile_apart(
    menagerie,
) -> None:
    """A write through one copy's mesh would reach every copy's (measured with `scale` on
    two UR5e copies): refused, for each copy; reads work; share_assets=False compiles
    each copy its own mesh, which a write then changes alone."""
    scene = _scene([_arm(menagerie), _arm(menagerie)])
    first, second = (scene.find("mesh", f"arm{i}/base_0") for i in (0, 1))
    physics = mjcf.Physics.from_mjcf_model(scene)
    scale = physics.bind(first).scale.copy()
    assert np.array_equal(physics.bind(second).scale, scale)
    for mesh in (first, second):
        with pytest.raises(mjcf.BindingError, match=r"compiled once for 2 copies.*share_assets"):
            physics.bind(mesh).scale = 2 * scale
        with pytest.raises(mjcf.BindingError, match="compiled once for 2 copies"):
            physics.bind(mesh).scale[0] = 7
        with pytest.raises(mjcf.BindingError, match="compiled once for 2 copies"):
            physics.bind([mesh])["scale", 0] = 7
    assert np.array_equal(physics.model.mesh_scale[physics.bind(first).element_id], scale)
    apart = mjcf.Physics.from_mjcf_model(scene, share_assets=False)
    assert apart.model.nmesh == 2 * physics.model.nmesh
    apart.bind(second).scale = 2 * scale
    assert np.array_equal(apart.bind(second).scale, 2 * scale)
    assert np.array_equal(apart.bind(first).scale, scale)
    unique = physics.bind(scene.find("geom", "floor"))
    unique.size = [4, 4, 0.1]  # what is not shared is written as ever
