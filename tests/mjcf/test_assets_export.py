"""Assets of composed models, and export to a folder or zip that stock MuJoCo loads to
the model we compile."""

from __future__ import annotations

import hashlib
import os
import re
import zipfile
from pathlib import Path

import mujoco
import pytest

import mjcf
from tests.conftest import MENAGERIE, MUJOCO_TESTDATA, ROBOTIQ, UR5E
from tests.mjcf.compare import model_differences
from tools.mjcf_schema._cases import _png

PAD = MENAGERIE / "robotiq_2f85" / "assets" / "pad.stl"
DRIVER = MENAGERIE / "robotiq_2f85" / "assets" / "driver.stl"
# A 2x2 PNG image (a texture given as bytes, with no file name of its own).
DOTS_PNG = bytes.fromhex(
    "89504e470d0a1a0a0000000d4948445200000002000000020802000000fdd49a7300000012494441"
    "54789c63f8cfc0c000c20cff8100001fee05fb0bd9688b0000000049454e44ae426082"
)


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
        assert archive.namelist()[0] == "scene/model.xml"  # one folder, named like the zip
        archive.extractall(tmp_path / "extracted")
    extracted = tmp_path / "extracted" / "scene" / "model.xml"
    _identical(compiled, mujoco.MjModel.from_xml_path(str(extracted)))
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
        assert archive.namelist()[0] == "two_arms/two_arms.xml"  # dm_control's and MJZ's layout
    _identical(compiled, mujoco.MjSpec.from_zip(str(named)).compile())
    _identical(compiled, mjcf.Physics.from_mjcf_model(mjcf.from_zip(named)).model)
    new_folder = tmp_path / "new" / "exports"  # dm_control's keywords; the folder is created
    keywords = mjcf.export_with_assets_as_zip(scene, out_dir=new_folder, model_name="arms")
    assert Path(keywords) == new_folder / "arms.zip"
    with zipfile.ZipFile(keywords) as archive:
        names = archive.namelist()
    assert names[0] == "arms/arms.xml" and {n.split("/")[0] for n in names} == {"arms"}
    _identical(compiled, mujoco.MjSpec.from_zip(str(keywords)).compile())
    default_name = mjcf.export_with_assets_as_zip(scene, out_dir=new_folder)
    assert Path(default_name) == new_folder / "scene.zip"  # the model's name
    with pytest.raises(TypeError, match="not both"):
        mjcf.export_with_assets_as_zip(scene, tmp_path / "x.zip", out_dir=folder)
    with pytest.raises(TypeError, match="not both"):
        mjcf.export_with_assets_as_zip(
            scene, out_dir=folder, model_name="a", model_filename="b.xml"
        )


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


def _part(
    name: str, files: dict[str, bytes], file_name: str = "part.stl", scale: float = 0.001
) -> mjcf.RootElement:
    model = mjcf.RootElement(model=name, assets=files)
    model.asset.add("mesh", name="part", file=file_name, scale=[scale] * 3)
    model.worldbody.add("body", name="b").add("geom", type="mesh", mesh="part")
    return model


def test_identical_contents_share_a_name_different_ones_get_readable_names(menagerie) -> None:
    pad, driver = PAD.read_bytes(), DRIVER.read_bytes()
    scene = mjcf.RootElement(model="scene")
    scene.attach(_part("a", {"part.stl": pad}))
    scene.attach(_part("b", {"part.stl": pad}, scale=0.002))  # its own mesh, the same file
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


def _menagerie_recipe(model: mjcf.RootElement) -> dict[str, bytes]:
    """MuJoCo Menagerie's FAQ recipe for loading a dm_control.mjcf model in MuJoCo."""
    assets = {}
    for asset in model.asset.all_children():
        if asset.file is not None:
            assets[asset.file.get_vfs_filename()] = asset.file.contents
    return assets


def test_every_name_of_an_asset_is_the_one_written(menagerie, tmp_path: Path) -> None:
    """get_vfs_filename(), get_assets(), the XML and the export name every file alike,
    even where different files share a name, an attached copy shares its twin's mesh,
    or an asset has no name of its own: Menagerie's recipe loads the model we compile."""
    pad, driver = PAD.read_bytes(), DRIVER.read_bytes()
    scene = mjcf.RootElement(model="scene")
    scene.attach(_part("a", {"part.stl": pad}))
    scene.attach(_part("c", {"part.stl": driver}))  # another file of the same name
    twin = _part("a", {"part.stl": pad})
    scene.attach(twin)  # 'a_1': compiled once with 'a' (mjcf.compose.sharing)
    scene.asset.add("texture", name="dots", type="2d", file=mjcf.Asset(DOTS_PNG, ".png"))
    recipe = _menagerie_recipe(scene)  # asked before anything is written
    xml = scene.to_xml_string()
    assert recipe == scene.get_assets()
    assert set(_file_names(xml)) == set(recipe)
    assert {"part.stl", "c-part.stl", hashlib.sha1(DOTS_PNG).hexdigest() + ".png"} == set(recipe)
    ours = mjcf.Physics.from_mjcf_model(scene).model
    assert model_differences(ours, mujoco.MjModel.from_xml_string(xml, recipe)) == []
    mjcf.export_with_assets(scene, tmp_path)
    assert {p.name for p in tmp_path.iterdir()} == {*recipe, "model.xml"}
    assert twin.find("mesh", "part").file.get_vfs_filename() == "part.stl"


def _file_names(xml: str) -> list[str]:
    return re.findall(r' file="([^"]+)"', xml)


def _assert_names_fit_mujoco(model: mjcf.RootElement) -> tuple[str, dict[str, bytes]]:
    """The XML names exactly the files `get_assets` holds, each once as MuJoCo's asset
    dict knows files (base name, any case), and stock MuJoCo compiles the pair to the
    model we compile."""
    xml, assets = model.to_xml_string(), model.get_assets()
    assert set(_file_names(xml)) == set(assets)
    assert len({name.lower() for name in assets}) == len(assets)
    assert all("/" not in name for name in assets)  # plain names, never paths
    ours = mjcf.Physics.from_mjcf_model(model).model
    assert model_differences(ours, mujoco.MjModel.from_xml_string(xml, assets)) == []
    return xml, assets


def _two_folders(tmp_path: Path, named: bool) -> Path:
    """A model whose two meshes are files named alike (but for case) in two folders;
    unnamed meshes take MuJoCo's names after their files ('part', 'Part')."""
    for folder, name, source in (("x", "part.stl", PAD), ("y", "Part.stl", DRIVER)):
        (tmp_path / folder).mkdir(exist_ok=True)
        (tmp_path / folder / name).write_bytes(source.read_bytes())
    first, second = ('name="pad" ', 'name="driver" ') if named else ("", "")
    path = tmp_path / f"two_{named}.xml"
    path.write_text(
        f'<mujoco model="two"><asset><mesh {first}file="x/part.stl" scale=".001 .001 .001"/>'
        f'<mesh {second}file="y/Part.stl" scale=".001 .001 .001"/></asset><worldbody>'
        f'<geom type="mesh" mesh="{"pad" if named else "part"}"/>'
        f'<geom type="mesh" mesh="{"driver" if named else "Part"}"/></worldbody></mujoco>'
    )
    return path


@pytest.mark.parametrize("named", [True, False], ids=["named", "named_after_files"])
def test_one_file_name_in_two_folders(menagerie, tmp_path: Path, named: bool) -> None:
    """MuJoCo's asset dict refuses 'x/part.stl' with 'y/Part.stl' ("Repeated file name"):
    the second file gets a name of its own, and both meshes keep their own vertices
    (and an unnamed one the name MuJoCo gives it after its file, written out)."""
    path = _two_folders(tmp_path, named)
    model = mjcf.from_path(path)
    xml, assets = _assert_names_fit_mujoco(model)
    assert _file_names(xml) == ["part.stl", "Part-2.stl"]
    stock = mujoco.MjModel.from_xml_path(str(path))
    reread = mujoco.MjModel.from_xml_string(xml, assets)
    assert model_differences(stock, reread) == []  # names too, object by object
    assert stock.mesh_vertnum[0] != stock.mesh_vertnum[1]


def test_files_on_disk_with_one_base_name_in_attached_models(menagerie, tmp_path: Path) -> None:
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
    xml, assets = _assert_names_fit_mujoco(scene)
    assert _file_names(xml) == ["part.stl", "y-part.stl"]  # the second by its model's scope
    assert assets["y-part.stl"] == DRIVER.read_bytes()
    out = Path(mjcf.export_with_assets(scene, tmp_path / "out")).parent
    assert sorted(os.listdir(out)) == ["model.xml", "part.stl", "y-part.stl"]
    assert (out / "model.xml").read_text() == xml  # export writes what to_xml_string writes
    assert mujoco.MjModel.from_xml_path(str(out / "model.xml")).nmesh == 2


def test_a_file_on_disk_is_not_shadowed_by_an_asset_of_its_name(menagerie, tmp_path: Path) -> None:
    """Compiling passes files on disk to MuJoCo by path, which MuJoCo looks up in the
    asset dict by base name first: an asset 'part.stl' of another model must not take
    the place of this model's 'part.stl' on disk."""
    (tmp_path / "part.stl").write_bytes(PAD.read_bytes())
    (tmp_path / "b.xml").write_text(
        '<mujoco model="b"><asset><mesh file="part.stl"/></asset>'
        '<worldbody><geom type="mesh" mesh="part"/></worldbody></mujoco>'
    )
    from_bytes = _part("a", {"part.stl": DRIVER.read_bytes()})
    scene = mjcf.RootElement(model="scene")
    scene.attach(from_bytes)
    scene.attach(mjcf.from_path(tmp_path / "b.xml"))
    compiled = mjcf.Physics.from_mjcf_model(scene).model
    on_disk = mujoco.MjModel.from_xml_path(str(tmp_path / "b.xml"))
    disk_mesh = mujoco.mj_name2id(compiled, mujoco.mjtObj.mjOBJ_MESH, "b/part")
    assert compiled.mesh_vertnum[disk_mesh] == on_disk.mesh_vertnum[0]
    _assert_names_fit_mujoco(scene)


def test_shipped_and_robot_models_composed_keep_their_files_apart(menagerie) -> None:
    """Menagerie robots twice, MuJoCo's own test model with meshes in two folders and a
    texture read twice (through two paths), and a second copy of that model: every
    file once, under a name MuJoCo's asset dict accepts."""
    scene = mjcf.RootElement(model="scene")
    for name in ("left", "right"):
        arm = mjcf.from_path(UR5E)
        arm.model = name
        arm.find("site", "attachment_site").attach(mjcf.from_path(ROBOTIQ))
        scene.attach(arm)
    for name in ("cubes", "more_cubes"):
        cubes = mjcf.from_zip(MUJOCO_TESTDATA / "MJCF_Root.zip")
        cubes.model = name
        scene.attach(cubes).pos = [0, 2, 0]
    _, assets = _assert_names_fit_mujoco(scene)
    assert {"cube.stl", "cube.msh", "deepmind.png", "pad.stl", "base_0.msh"} <= set(assets)
    assert len(assets) == 28 + 3


def test_dm_control_hash_names_on_request(menagerie) -> None:
    gripper = mjcf.from_path(ROBOTIQ)
    xml = gripper.to_xml_string(filename_with_hash=True)
    assets = gripper.get_assets(filename_with_hash=True)
    pad_hash = hashlib.sha1(PAD.read_bytes()).hexdigest()
    assert f"pad-{pad_hash}.stl" in assets and f'file="pad-{pad_hash}.stl"' in xml
    assert set(_file_names(xml)) == set(assets)
    expected = mjcf.Physics.from_mjcf_model(gripper).model
    assert model_differences(expected, mujoco.MjModel.from_xml_string(xml, assets)) == []
    asset = gripper.find("mesh", "pad").file
    assert asset.get_vfs_filename(filename_with_hash=True) == f"pad-{pad_hash}.stl"
    assert asset.get_vfs_filename() == "pad.stl"  # the name to_xml_string() writes
    assert 'file="pad.stl"' in gripper.to_xml_string(filename_with_hash=False)


# -- export file names --------------------------------------------------------------------------


def test_export_names_the_file_after_the_model(menagerie, tmp_path: Path) -> None:
    gripper = mjcf.from_path(ROBOTIQ)
    path = mjcf.export_with_assets(gripper, tmp_path / "a", None)
    assert Path(path) == tmp_path / "a" / "robotiq_2f85.xml"
    dm_control_style = mjcf.export_with_assets(gripper, tmp_path / "b", out_file_name=None)
    assert Path(dm_control_style) == tmp_path / "b" / "robotiq_2f85.xml"
    named = mjcf.export_with_assets(gripper, tmp_path / "c", out_file_name="gripper.xml")
    assert Path(named) == tmp_path / "c" / "gripper.xml"
    expected = mjcf.Physics.from_mjcf_model(gripper).model
    for written in (path, dm_control_style, named):
        assert Path(written).read_text() == gripper.to_xml_string()
        assert model_differences(expected, mujoco.MjModel.from_xml_path(written)) == []
    assert sorted(os.listdir(tmp_path / "a")) == sorted(["robotiq_2f85.xml", *gripper.get_assets()])


def test_export_takes_dm_control_keywords_alone(menagerie, tmp_path: Path) -> None:
    """dm_control's call, every argument by its keyword: `mjcf_model`, `out_dir`,
    `out_file_name` (and `model_name` for the zip)."""
    gripper = mjcf.from_path(ROBOTIQ)
    path = mjcf.export_with_assets(mjcf_model=gripper, out_dir=tmp_path, out_file_name="g.xml")
    assert Path(path) == tmp_path / "g.xml" and Path(path).read_text() == gripper.to_xml_string()
    expected = mjcf.Physics.from_mjcf_model(gripper).model
    assert model_differences(expected, mujoco.MjModel.from_xml_path(path)) == []
    zipped = mjcf.export_with_assets_as_zip(mjcf_model=gripper, out_dir=tmp_path, model_name="z")
    assert Path(zipped) == tmp_path / "z.zip"
    assert model_differences(expected, mujoco.MjSpec.from_zip(zipped).compile()) == []
    with pytest.raises(TypeError, match="not both"):
        mjcf.export_with_assets(gripper, tmp_path, mjcf_model=gripper)
    with pytest.raises(TypeError, match="needs"):
        mjcf.export_with_assets(out_dir=tmp_path)


@pytest.mark.parametrize("name", ["model", "model.stl", "sub/model.xml", "", 3])
def test_export_refuses_a_model_file_name_it_cannot_use(tmp_path: Path, name) -> None:
    model = mjcf.RootElement(model="m")
    with pytest.raises(ValueError, match=r"model_filename|out_file_name"):
        mjcf.export_with_assets(model, tmp_path / "out", name)
    with pytest.raises(mjcf.AssetError, match="out_file_name"):
        mjcf.export_with_assets(model, tmp_path / "out", out_file_name=name)
    assert not (tmp_path / "out").exists()
    with pytest.raises(TypeError, match="not both"):
        mjcf.export_with_assets(model, tmp_path / "out", "a.xml", out_file_name="b.xml")


def test_export_keeps_numbers_as_to_xml_string_writes_them(tmp_path: Path) -> None:
    model = mjcf.RootElement(model="m")
    model.worldbody.add("geom", size=[1 / 3], pos=[1e-12, 0, 0.5])
    path = mjcf.export_with_assets(model, tmp_path, precision=3, zero_threshold=1e-9)
    text = Path(path).read_text()
    assert text == model.to_xml_string(precision=3, zero_threshold=1e-9)
    assert 'size="0.333"' in text and 'pos="0 0 0.5"' in text


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


def test_include_copy_keeps_the_files_of_the_model_copied(
    menagerie, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A copy made elsewhere (another folder, no model_dir) reads the files the source
    read: each copied file is the source's asset, path and all, as in dm_control."""
    source = mjcf.from_path(ROBOTIQ)
    monkeypatch.chdir(tmp_path)  # relative names would be looked for here
    copied = mjcf.RootElement(model="copied")
    copied.include_copy(source)
    for original, copy_ in zip(source.find_all("mesh"), copied.find_all("mesh"), strict=True):
        assert copy_.file is original.file and Path(copy_.file.path).is_file()
    expected = mjcf.Physics.from_mjcf_model(source).model
    assert model_differences(expected, mjcf.Physics.from_mjcf_model(copied).model) == []


def test_an_included_file_and_the_files_it_names_given_as_assets(menagerie) -> None:
    """A model read from a string whose <include> and meshes exist only as `assets`:
    get_assets() gives the files the XML names (not the included XML), stock MuJoCo
    compiles them alike; without the assets the missing file is a FileNotFoundError."""
    xml = """<mujoco><asset><texture name="dots" type="2d" file="no_such_dir/dots.png"/>
      <material name="dotted" texture="dots"/></asset>
      <include file="parts.xml"/>
      <worldbody><geom type="sphere" size=".1" material="dotted"/></worldbody></mujoco>"""
    parts = b"""<mujoco><asset><mesh name="pad" file="elsewhere/pad.stl" scale=".01 .01 .01"/>
      </asset><worldbody><geom type="mesh" mesh="pad"/></worldbody></mujoco>"""
    with pytest.raises(FileNotFoundError, match=r"parts\.xml"):
        mjcf.from_xml_string(xml)
    files = {"parts.xml": parts, "dots.png": DOTS_PNG, "pad.stl": PAD.read_bytes()}
    model = mjcf.from_xml_string(xml, assets=files)
    assets = model.get_assets()
    assert assets == {"dots.png": DOTS_PNG, "pad.stl": PAD.read_bytes()}
    _assert_names_fit_mujoco(model)


@pytest.mark.parametrize("by_reference", ["embed", "passthrough"])
def test_textures_left_by_reference_compile_from_an_export_as_the_physics_compiles_them(
    tmp_path: Path, by_reference: str
) -> None:
    """MuJoCo leaves a texture by reference only when it reads it from a file on disk, so
    the README's recipe (assets in memory) refuses `embed="false"` and embeds the pixels
    under `passthrough="textures"`, as the README says next to it; an export compiles to
    what `Physics.from_mjcf_model` compiles."""
    image = tmp_path / "tex.png"
    image.write_bytes(_png())
    model = mjcf.RootElement(model="m")
    if by_reference == "passthrough":
        model.compiler.passthrough = "textures"
    extra = {"embed": "false"} if by_reference == "embed" else {}
    texture = model.asset.add("texture", name="t", type="2d", file=str(image), **extra)
    model.asset.add("material", name="mat", texture=texture)
    model.worldbody.add("geom", size=[1], material="mat")
    physics = mjcf.Physics.from_mjcf_model(model)
    assert physics.model.ntexdata == 0  # by reference
    if by_reference == "embed":
        with pytest.raises(ValueError, match="cannot be by reference"):
            mujoco.MjModel.from_xml_string(model.to_xml_string(), model.get_assets())
    else:
        recipe = mujoco.MjModel.from_xml_string(model.to_xml_string(), model.get_assets())
        assert recipe.ntexdata > 0  # embedded: MuJoCo read it from memory
    out = tmp_path / "out"
    mjcf.export_with_assets(model, out)
    exported = mujoco.MjModel.from_xml_path(str(out / "model.xml"))
    assert model_differences(exported, physics.model) == []


def test_files_read_are_kept_up_to_a_limit_and_read_again_after(monkeypatch, tmp_path) -> None:
    """A process that writes models of thousands of mesh files (a data set of objects, one
    scene after another) keeps the latest read, `FILE_CACHE_LIMIT` bytes in all, not every
    file it ever read; a file no longer kept is read again, as it is on disk then."""
    monkeypatch.setattr(mjcf.tree.assets, "FILE_CACHE_LIMIT", 10_000)
    files = [tmp_path / f"part{i}.stl" for i in range(30)]
    for i, file in enumerate(files):
        file.write_bytes(bytes([i]) * 1_000)
    assets = [mjcf.Asset(None, ".stl", prefix=file.stem, path=str(file)) for file in files]
    assert [asset.contents for asset in assets] == [file.read_bytes() for file in files]
    kept = mjcf.tree.assets._file_cache
    assert sum(len(contents) for _, _, contents in kept.values()) <= 10_000
    assert str(files[-1]) in kept and str(files[0]) not in kept
    assert assets[0].contents == files[0].read_bytes()
    files[-1].write_bytes(b"changed")
    assert assets[-1].contents == b"changed"
