"""Assets of composed models, and export to a folder or zip that stock MuJoCo loads to
the model we compile."""

from __future__ import annotations

import os
import re
import zipfile
from pathlib import Path

import mujoco
import pytest

import mjcf
from tests.conftest import MENAGERIE, ROBOTIQ, UR5E
from tests.mjcf.compare import model_differences

PAD = MENAGERIE / "robotiq_2f85" / "assets" / "pad.stl"
DRIVER = MENAGERIE / "robotiq_2f85" / "assets" / "driver.stl"


def _scene() -> mjcf.RootElement:
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("geom", name="floor", type="plane", size=[2, 2, 0.1])
    for y, name in ((-0.5, "left"), (0.5, "right")):
        arm = mjcf.from_path(UR5E)
        arm.model = name
        arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
        scene.attach(arm).pos = [0, y, 0]
    return scene


@pytest.fixture(scope="module")
def scene_and_model() -> tuple[mjcf.RootElement, mujoco.MjModel]:
    scene = _scene()
    return scene, mjcf.Physics.from_mjcf_model(scene).model


def _identical(ours: mujoco.MjModel, theirs: mujoco.MjModel) -> None:
    assert model_differences(ours, theirs) == []
    assert ours.names == theirs.names  # every name, in every namespace, in order


def test_export_to_a_folder_loads_in_stock_mujoco(scene_and_model, tmp_path: Path) -> None:
    scene, compiled = scene_and_model
    path = mjcf.export_with_assets(scene, tmp_path / "out")
    assert Path(path) == tmp_path / "out" / "model.xml"
    files = sorted(os.listdir(tmp_path / "out"))
    assert "base_0.msh" in files and "pad.stl" in files  # readable, not name-<sha1>.stl
    assert len(files) == 1 + 20 + 8  # the model, the arm's meshes, the gripper's: once each
    _identical(compiled, mujoco.MjModel.from_xml_path(path))
    custom = mjcf.export_with_assets(scene, tmp_path / "named", model_filename="two_arms.xml")
    _identical(compiled, mujoco.MjModel.from_xml_path(custom))


def test_export_to_a_zip_loads_in_stock_mujoco_and_back(scene_and_model, tmp_path: Path) -> None:
    scene, compiled = scene_and_model
    zip_path = mjcf.export_with_assets_as_zip(scene, tmp_path / "scene.zip")
    with zipfile.ZipFile(zip_path) as archive:
        assert archive.namelist()[0] == "model.xml"
        archive.extractall(tmp_path / "extracted")
    _identical(compiled, mujoco.MjModel.from_xml_path(str(tmp_path / "extracted" / "model.xml")))
    _identical(compiled, mujoco.MjSpec.from_zip(str(zip_path)).compile())
    reread = mjcf.from_zip(zip_path)
    _identical(compiled, mjcf.Physics.from_mjcf_model(reread).model)
    assert reread.find("actuator", "left\\/robotiq_2f85\\/fingers_actuator") is not None


def test_zip_export_into_a_folder_as_dm_control_calls_it(scene_and_model, tmp_path: Path) -> None:
    scene, compiled = scene_and_model
    folder = tmp_path / "exports"
    folder.mkdir()
    zip_path = mjcf.export_with_assets_as_zip(scene, folder)
    assert Path(zip_path) == folder / "scene.zip"
    _identical(compiled, mujoco.MjSpec.from_zip(str(zip_path)).compile())
    named = mjcf.export_with_assets_as_zip(scene, folder, "two_arms")  # dm_control's model_name
    assert Path(named) == folder / "two_arms.zip"
    with zipfile.ZipFile(named) as archive:
        assert archive.namelist()[0] == "two_arms.xml"
    _identical(compiled, mujoco.MjSpec.from_zip(str(named)).compile())
    _identical(compiled, mjcf.Physics.from_mjcf_model(mjcf.from_zip(named)).model)


def test_written_model_compiles_in_stock_mujoco_to_ours(scene_and_model) -> None:
    scene, compiled = scene_and_model
    xml, assets = scene.to_xml_string(), scene.get_assets()
    _identical(compiled, mujoco.MjModel.from_xml_string(xml, assets))


def test_get_assets_is_exactly_what_the_xml_names(scene_and_model) -> None:
    scene, _ = scene_and_model
    xml, assets = scene.to_xml_string(), scene.get_assets()
    named = set(re.findall(r' file="([^"]+)"', xml))
    assert named == set(assets)
    assert len(assets) == 28  # each mesh file once, although two copies of each robot use it


# -- naming and supplying assets ----------------------------------------------------------------


def _part(name: str, files: dict[str, bytes], file_name: str = "part.stl") -> mjcf.RootElement:
    model = mjcf.RootElement(model=name, assets=files)
    model.asset.add("mesh", name="part", file=file_name, scale=[0.001] * 3)
    model.worldbody.add("body", name="b").add("geom", type="mesh", mesh="part")
    return model


def test_identical_contents_share_a_name_different_ones_get_readable_names(menagerie) -> None:
    pad, driver = PAD.read_bytes(), DRIVER.read_bytes()
    scene = mjcf.RootElement(model="scene")
    scene.attach(_part("a", {"part.stl": pad}))
    scene.attach(_part("b", {"part.stl": pad}))
    scene.attach(_part("c", {"part.stl": driver}))
    assets = scene.get_assets()
    assert assets == {"part.stl": pad, "c-part.stl": driver}
    xml = scene.to_xml_string()
    assert xml.count('file="part.stl"') == 2 and xml.count('file="c-part.stl"') == 1
    model = mujoco.MjModel.from_xml_string(xml, assets)
    assert model.nmesh == 3
    driver_mesh = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_MESH, "c/part")
    alone = mujoco.MjModel.from_xml_string(_part("c", {}).to_xml_string(), {"part.stl": driver})
    assert model.mesh_vertnum[driver_mesh] == alone.mesh_vertnum[0]


def test_files_on_disk_with_one_base_name(menagerie, tmp_path: Path) -> None:
    for folder, source in (("x", PAD), ("y", DRIVER)):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "part.stl").write_bytes(source.read_bytes())
        (tmp_path / folder / "m.xml").write_text(
            f'<mujoco model="{folder}"><asset><mesh file="part.stl" scale=".001 .001 .001"/>'
            '</asset><worldbody><body><geom type="mesh" mesh="part"/></body></worldbody></mujoco>'
        )
    scene = mjcf.RootElement(model="scene", model_dir=str(tmp_path))
    scene.attach(mjcf.from_path(tmp_path / "x" / "m.xml"))
    scene.attach(mjcf.from_path(tmp_path / "y" / "m.xml"))
    xml = scene.to_xml_string()
    assert 'file="x/part.stl"' in xml  # a path that loads from the scene's folder
    model = mujoco.MjModel.from_xml_string(xml, scene.get_assets())
    assert sorted(model.mesh_vertnum) == sorted(
        mujoco.MjModel.from_xml_path(str(tmp_path / d / "m.xml")).mesh_vertnum[0] for d in "xy"
    )
    out = Path(mjcf.export_with_assets(scene, tmp_path / "out")).parent
    assert sorted(os.listdir(out)) == ["model.xml", "part.stl", "y-part.stl"]
    assert (out / "y-part.stl").read_bytes() == DRIVER.read_bytes()
    assert mujoco.MjModel.from_xml_path(str(out / "model.xml")).nmesh == 2


def test_assets_given_as_bytes_need_no_file(
    menagerie, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)  # no part.stl anywhere on disk
    model = _part("bytes", {"part.stl": PAD.read_bytes()})
    physics = mjcf.Physics.from_mjcf_model(model)
    assert physics.model.nmesh == 1 and physics.model.mesh_vertnum[0] > 0
    asset = model.find("mesh", "part").file
    assert isinstance(asset, mjcf.Asset)
    assert (asset.contents, asset.extension, asset.prefix) == (PAD.read_bytes(), ".stl", "part")


def test_a_mesh_file_reads_back_as_an_asset(menagerie) -> None:
    gripper = mjcf.from_path(ROBOTIQ)
    asset = gripper.find("mesh", "pad").file
    assert isinstance(asset, mjcf.Asset)
    assert asset.extension == ".stl" and asset.prefix == "pad"
    assert asset.contents == PAD.read_bytes()
    mesh = gripper.asset.add(
        "mesh", name="extra", file=mjcf.Asset(DRIVER.read_bytes(), ".stl", "extra")
    )
    assert "extra.stl" in gripper.get_assets()
    assert mjcf.Physics.from_mjcf_model(gripper).bind(mesh) is not None


def test_a_missing_file_names_the_element_and_the_path(tmp_path: Path) -> None:
    model = mjcf.RootElement(model="broken", model_dir=str(tmp_path))
    model.asset.add("mesh", name="ghost", file="ghost.stl")
    model.worldbody.add("geom", type="mesh", mesh="ghost")
    expected = rf'<mesh name="ghost">: .*{re.escape(str(tmp_path / "ghost.stl"))}'
    before = model.to_xml_string()
    for action in (
        model.get_assets,
        lambda: mjcf.Physics.from_mjcf_model(model),
        lambda: mjcf.export_with_assets(model, tmp_path / "out"),
        lambda: mjcf.export_with_assets_as_zip(model, tmp_path / "out.zip"),
    ):
        with pytest.raises(mjcf.AssetError, match=expected):
            action()
    assert model.to_xml_string() == before
    assert not (tmp_path / "out.zip").exists()


def test_many_meshes_compose_and_export(tmp_path: Path) -> None:
    """dm_control issue 387: thousands of meshes. Each model has its own tetrahedron."""
    scene = mjcf.RootElement(model="scene")
    for i in range(2000):
        tetra = f"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 {1 + i}\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
        model = mjcf.RootElement(model=f"m{i}", assets={"tetra.obj": tetra.encode()})
        model.asset.add("mesh", name="tetra", file="tetra.obj")
        model.worldbody.add("geom", type="mesh", mesh="tetra", contype=0, conaffinity=0)
        scene.attach(model)
    assets = scene.get_assets()
    assert len(assets) == 2000 and "tetra.obj" in assets and "m1999-tetra.obj" in assets
    exported = mujoco.MjModel.from_xml_path(mjcf.export_with_assets(scene, tmp_path))
    assert exported.nmesh == 2000
    assert model_differences(mjcf.Physics.from_mjcf_model(scene).model, exported) == []
