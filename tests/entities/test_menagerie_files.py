"""The robot files shipped with the package: the same robots as MuJoCo Menagerie's files,
carried by a built wheel, and the OBJ-to-MSH conversion that made the UR5e's meshes."""

from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import mujoco
import numpy as np
import pytest

from entities import menagerie
from entities.menagerie import convert
from tests.conftest import ORIGINAL_MENAGERIE, REPO

needs_originals = pytest.mark.skipif(
    not (ORIGINAL_MENAGERIE / "universal_robots_ur5e").is_dir(),
    reason=f"Menagerie's original files are not at {ORIGINAL_MENAGERIE} (../shared, in CI)",
)
MESH_FIELDS = ("mesh_vert", "mesh_face", "mesh_normal", "mesh_facenormal", "mesh_vertadr")
# A tetrahedron with one normal per vertex, as Menagerie's OBJ files write them.
TETRA_OBJ = """mtllib Black.mtl
usemtl Black
v 0.00497600 -0.05767200 0.08487900
v 0.1 0 0
v 0 0.1 0
v 0 0 0.1
vn -0.57735 -0.57735 -0.57735
vn 1 0 0
vn 0 1 0
vn 0 0 1
f 1//1 3//3 2//2
f 1//1 2//2 4//4
f 1//1 4//4 3//3
f 2//2 3//3 4//4
"""
TETRA_XML = '<mujoco><asset><mesh file="tetra.obj"/></asset></mujoco>'


@needs_originals
def test_the_shipped_ur5e_compiles_to_the_model_of_menagerie_s_obj_files():
    original = mujoco.MjModel.from_xml_path(
        str(ORIGINAL_MENAGERIE / "universal_robots_ur5e" / "ur5e.xml")
    )
    shipped = mujoco.MjModel.from_xml_path(str(menagerie.ROOT / "universal_robots_ur5e/ur5e.xml"))
    assert original.nmesh == shipped.nmesh == 20
    for field in MESH_FIELDS:  # the same vertices, faces and normals, bit for bit
        assert np.array_equal(getattr(original, field), getattr(shipped, field)), field
    assert convert.model_differences(original, shipped) == []  # every other field too
    assert original.names == shipped.names


@needs_originals
def test_the_shipped_2f85_and_licenses_are_menagerie_s_files_unchanged():
    for name in menagerie.ROBOTS:
        original, shipped = ORIGINAL_MENAGERIE / name, menagerie.ROOT / name
        assert (shipped / "LICENSE").read_bytes() == (original / "LICENSE").read_bytes()
    robotiq = ORIGINAL_MENAGERIE / "robotiq_2f85"
    files = sorted(p.relative_to(robotiq) for p in robotiq.rglob("*") if p.is_file())
    assert len(files) == 10
    shipped = menagerie.ROOT / "robotiq_2f85"
    for file in files:
        assert (shipped / file).read_bytes() == (robotiq / file).read_bytes()


def test_convert_writes_msh_files_that_compile_like_the_obj_files(tmp_path):
    source = tmp_path / "robot"
    (source / "assets").mkdir(parents=True)
    (source / "assets" / "tetra.obj").write_text(TETRA_OBJ)
    (source / "LICENSE").write_text("license text")
    xml = TETRA_XML.replace('file="', 'file="assets/')
    (source / "robot.xml").write_text(xml)
    checked = convert.convert_robot(source, tmp_path / "out")
    out = tmp_path / "out"
    assert checked == [out / "robot.xml"]
    assert sorted(p.name for p in out.rglob("*") if p.is_file()) == [
        "LICENSE", "robot.xml", "tetra.msh"
    ]  # fmt: skip
    assert (out / "robot.xml").read_text() == xml.replace(".obj", ".msh")
    msh = (out / "assets" / "tetra.msh").read_bytes()
    assert len(msh) == 16 + 12 * (4 + 4 + 4)  # MuJoCo's size rule for 4 vertices, normals, faces
    original = mujoco.MjModel.from_xml_path(str(source / "robot.xml"))
    converted = mujoco.MjModel.from_xml_path(str(out / "robot.xml"))
    for field in MESH_FIELDS:
        assert np.array_equal(getattr(original, field), getattr(converted, field)), field


def test_a_conversion_that_changes_the_model_is_refused(tmp_path, monkeypatch):
    source = tmp_path / "robot"
    source.mkdir()
    (source / "tetra.obj").write_text(TETRA_OBJ)
    (source / "robot.xml").write_text(TETRA_XML)
    moved = TETRA_OBJ.replace("v 0.1 0 0", "v 0.1 0 0.000001")
    real = convert.obj_to_msh
    monkeypatch.setattr(convert, "obj_to_msh", lambda text, source: real(moved, source))
    with pytest.raises(convert.ConversionError, match=r"compiles differently .*'mesh_vert'"):
        convert.convert_robot(source, tmp_path / "out")


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("f 2//2 3//3 4//4", "f 2//2 3//3 4//4 1//1"), "has no lossless MSH form"),
        (("vn 0 0 1", "vn 0 0 1\nvt 0.5 0.5"), "'vt 0.5 0.5' has no lossless MSH form"),
        (("f 1//1 3//3 2//2", "f 1//2 3//3 2//2"), "the normal's equal to the vertex's"),
        (("f 1//1 3//3 2//2", "f 1/1/1 3//3 2//2"), "no texture coordinates"),
        (("f 1//1 3//3 2//2", "f 1 3 2"), "faces must all name their normals"),
        (("vn 0 0 1\n", ""), "3 normals for 4 vertices"),
    ],
)
def test_obj_files_msh_cannot_carry_unchanged_are_refused(change, message):
    with pytest.raises(convert.ConversionError, match=message):
        convert.obj_to_msh(TETRA_OBJ.replace(*change), "tetra.obj")


def test_a_built_wheel_carries_the_robots_and_arm_push_box_runs_from_it(tmp_path, built_wheel):
    """Install the wheel (built offline from a copy of the sources) alone into a folder,
    and make the robot task from there, away from the repository."""
    shipped = {
        str(p.relative_to(REPO)) for p in menagerie.ROOT.rglob("*")
        if p.is_file() and "__pycache__" not in p.parts
    }  # fmt: skip
    with zipfile.ZipFile(built_wheel) as archive:
        assert {n for n in archive.namelist() if n.startswith("entities/menagerie/")} == shipped
    pip = [sys.executable, "-m", "pip", "--disable-pip-version-check", "-q"]
    install = ["install", "--no-deps", "--no-index", "--target", "site", str(built_wheel)]
    subprocess.run([*pip, *install], check=True, cwd=tmp_path)
    code = (
        "import gymnasium, tasks, entities\n"
        "env = gymnasium.make('composer/ArmPushBox-v0')\n"
        "print(env.reset(seed=0)[0]['box_position'].shape, entities.__file__)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True,
        env={"PYTHONPATH": str(tmp_path / "site"), "PATH": "", "MUJOCO_GL": "egl"},
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == f"(3,) {tmp_path / 'site' / 'entities' / '__init__.py'}"


def test_the_readme_here_lists_the_sums_of_the_converted_originals():
    readme = (menagerie.ROOT / "README.md").read_text()
    listed = [line.split()[1] for line in readme.splitlines() if len(line.split()) == 2
              and len(line.split()[0]) == 64]  # fmt: skip
    meshes = sorted(p.name for p in (menagerie.ROOT / "universal_robots_ur5e/assets").iterdir())
    assert listed[0] == "universal_robots_ur5e/ur5e.xml"
    assert [Path(p).with_suffix(".msh").name for p in listed[1:]] == meshes
