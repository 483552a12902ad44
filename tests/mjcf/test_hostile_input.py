"""Untrusted MJCF: no entity expansion, no file or network access through XML, bounded
work on hostile documents, and only mjcf errors out of the public API."""

from __future__ import annotations

import contextlib
import copy
import functools
import io
import os
import subprocess
import sys
import tempfile
import time
import zipfile
from pathlib import Path

import mujoco
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mjcf
from mjcf.io import parser
from tests.conftest import GYM_ASSETS, MUJOCO_TESTDATA

XXE = """<?xml version="1.0"?>
<!DOCTYPE mujoco [<!ENTITY secret SYSTEM "file:///etc/passwd">]>
<mujoco model="&secret;"><worldbody/></mujoco>"""

LAUGHS = (
    '<?xml version="1.0"?><!DOCTYPE lolz [<!ENTITY lol "lol">'
    + "".join(
        f'<!ENTITY lol{i} "{("&lol" + (str(i - 1) if i > 1 else "") + ";") * 10}">'
        for i in range(1, 10)
    )
    + ']><mujoco model="&lol9;"/>'
)


def test_external_entities_are_refused_without_reading() -> None:
    with pytest.raises(mjcf.ParseError, match=r"DTD|entity") as caught:
        mjcf.from_xml_string(XXE)
    assert "root:" not in str(caught.value)


def test_entity_expansion_bomb_is_refused_quickly() -> None:
    start = time.perf_counter()
    with pytest.raises(mjcf.ParseError):
        mjcf.from_xml_string(LAUGHS)
    assert time.perf_counter() - start < 5  # a guard against hanging, not a benchmark


def test_deep_nesting_is_refused() -> None:
    depth = 100_000
    text = "<mujoco><worldbody>" + "<body>" * depth + "</body>" * depth + "</worldbody></mujoco>"
    with pytest.raises(mjcf.ParseError, match="malformed XML"):
        mjcf.from_xml_string(text)


def _nested(depth: int) -> str:
    """A model nested `depth` elements deep: bodies in bodies, a geom in the innermost."""
    bodies = depth - 3  # <mujoco>, <worldbody> and the geom
    return (
        "<mujoco><worldbody>" + "<body>" * bodies + "<geom size='.1'/>" + "</body>" * bodies
        + "</worldbody></mujoco>"
    )  # fmt: skip


def test_models_are_read_and_written_as_deep_as_mujoco_reads_them(tmp_path: Path) -> None:
    """MuJoCo's own reader is the oracle: what it compiles is read, written and compiled;
    one level deeper it refuses, and so do the reader and the writer (with mjcf errors,
    not the IndexError a 600-level model raised, nor libxml2's 256-level refusal)."""
    deepest, too_deep = _nested(parser.MAX_DEPTH), _nested(parser.MAX_DEPTH + 1)
    assert mujoco.MjModel.from_xml_string(deepest).nbody == parser.MAX_DEPTH - 2
    with pytest.raises(ValueError, match="XML_ELEMENT_DEPTH_EXCEEDED"):
        mujoco.MjModel.from_xml_string(too_deep)
    for strict_paths in (False, True):  # read lazily, and element by element
        model = mjcf.from_xml_string(deepest, strict_paths=strict_paths)
        assert mjcf.Physics.from_mjcf_model(model).model.nbody == parser.MAX_DEPTH - 2
        assert mjcf.from_xml_string(model.to_xml_string()).to_xml_string() == model.to_xml_string()
        with pytest.raises(mjcf.ParseError, match="<geom> is nested 500 elements deep; MuJoCo"):
            mjcf.from_xml_string(too_deep, strict_paths=strict_paths)
    innermost = model.find_all("body")[-1]
    innermost.add("body").add("geom", size=[0.1])
    for write in (model.to_xml_string, lambda: mjcf.Physics.from_mjcf_model(model)):
        with pytest.raises(mjcf.SchemaError, match=r"nested 500 elements deep when written"):
            write()
    # Two files, each within the depth, included into one that is not.
    (tmp_path / "inner.xml").write_text(_nested(300).replace("<mujoco><worldbody>", "<mujoco>")
                                        .replace("</worldbody></mujoco>", "</mujoco>"))  # fmt: skip
    outer = "<mujoco><worldbody>" + "<body>" * 250 + "<include file='inner.xml'/>" + "</body>" * 250
    (tmp_path / "outer.xml").write_text(outer + "</worldbody></mujoco>")
    with pytest.raises(mjcf.ParseError, match="nested 500 elements deep"):
        mjcf.from_path(tmp_path / "outer.xml")


def test_strict_paths_refuse_includes_outside_the_model_folder(tmp_path: Path) -> None:
    outside = tmp_path / "outside.xml"
    outside.write_text("<mujoco><worldbody><geom size='1'/></worldbody></mujoco>")
    folder = tmp_path / "model"
    folder.mkdir()
    (folder / "up.xml").write_text('<mujoco><include file="../outside.xml"/></mujoco>')
    (folder / "absolute.xml").write_text(f'<mujoco><include file="{outside}"/></mujoco>')
    assert mjcf.from_path(folder / "up.xml").worldbody.geom  # trusted: as MuJoCo resolves it
    for name in ("up.xml", "absolute.xml"):
        with pytest.raises(mjcf.ParseError, match="outside the model's folder"):
            mjcf.from_path(folder / name, strict_paths=True)


def test_strict_paths_refuse_asset_files_outside_the_model_folder(tmp_path: Path) -> None:
    mesh = tmp_path / "secret.msh"
    mesh.write_bytes((MUJOCO_TESTDATA / "abdomen_1_body.msh").read_bytes())
    folder = tmp_path / "model"
    folder.mkdir()
    for file in ("../secret.msh", str(mesh)):
        path = folder / "model.xml"
        path.write_text(f'<mujoco><asset><mesh name="m" file="{file}"/></asset></mujoco>')
        with pytest.raises(mjcf.AssetError, match="outside the model's folder"):
            mjcf.from_path(path, strict_paths=True)
        assert mjcf.from_path(path).get_assets()  # trusted: found as MuJoCo finds it
    # A path that escapes only after an edit is refused when the file is used.
    path.write_text('<mujoco><asset><mesh name="m" file="secret.msh"/></asset></mujoco>')
    model = mjcf.from_path(path, strict_paths=True)
    model.compiler.meshdir = ".."
    with pytest.raises(mjcf.AssetError, match="outside the model's folder"):
        mjcf.Physics.from_mjcf_model(model)


def _corpus() -> list[str]:
    files = [GYM_ASSETS / "ant.xml", GYM_ASSETS / "humanoid.xml", MUJOCO_TESTDATA / "model.xml"]
    return [f.read_text() for f in files]


@st.composite
def _mutated(draw) -> str:
    text = draw(st.sampled_from(_corpus()))
    for _ in range(draw(st.integers(1, 4))):
        position = draw(st.integers(0, len(text)))
        kind = draw(st.sampled_from(["delete", "insert", "replace", "swap-quote"]))
        if kind == "delete":
            text = text[:position] + text[position + draw(st.integers(1, 20)) :]
        elif kind == "insert":
            snippet = draw(st.sampled_from(
                ['<geom size="1"/>', "<body>", "</body>", 'name="torso"', ' class="x"',
                 ' pos="1 2"', ' type="nope"', "&amp;", "<include file='x.xml'/>",
                 ' joint="nothing"', "<frame>", "<replicate count='2'>", "\x00", "é",
                 # What asks MuJoCo for minutes or gigabytes (mjcf.budget refuses it):
                 "<replicate count='100000'>", "<replicate count='100000'><geom size='1'/>",
                 "<hfield name='h' nrow='99999' ncol='99999' size='1 1 1 1'/>",
                 "<size memory='1T' nkey='999999999'/>", " nrow='2000000000'",
                 "<flexcomp name='f' type='grid' count='999 999 9' dim='3'/>",
                 "<texture name='t' builtin='flat' width='99999' height='99999'/>",
                 "<body>" * 300]
            ))  # fmt: skip
            text = text[:position] + snippet + text[position:]
        elif kind == "replace":
            text = text[:position] + draw(st.text(max_size=5)) + text[position + 5 :]
        else:
            text = text.replace('"', "'", 1)
    return text


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_mutated())
def test_mutated_models_raise_only_mjcf_errors(text: str) -> None:
    """Whatever a mutated real model does, only mjcf.Error subclasses escape reading,
    writing, copying, attaching, compiling and binding it, and a repr never raises."""
    try:
        model = mjcf.from_xml_string(text, model_dir=str(GYM_ASSETS))
        elements = model.find_all("body") + model.find_all("geom") + model.find_all("actuator")
        for element in elements:
            repr(element)
            element.full_identifier  # noqa: B018
            element.get_attributes()
        xml = model.to_xml_string()
        mjcf.from_xml_string(xml, model_dir=str(GYM_ASSETS), resolve_references=False)
        scene = mjcf.RootElement(model="scene")
        scene.attach(copy.deepcopy(model))
        scene.to_xml_string()
        physics = mjcf.Physics.from_mjcf_model(model)
        bodies = model.find_all("body")
        if bodies:
            physics.bind(bodies).xpos  # noqa: B018
        physics.bind(model.worldbody).xpos  # noqa: B018
    except mjcf.Error:
        pass


@functools.cache
def _archive() -> bytes:
    """A real model and its mesh files, exported as a zip."""
    folder = Path(tempfile.mkdtemp())
    model = mjcf.from_path(MUJOCO_TESTDATA / "model.xml")
    model.asset.add("mesh", name="extra", file=mjcf.Asset(
        (MUJOCO_TESTDATA / "abdomen_1_body.msh").read_bytes(), ".msh", prefix="extra"))  # fmt: skip
    return Path(mjcf.export_with_assets_as_zip(model, folder / "model.zip")).read_bytes()


@st.composite
def _mutated_zip(draw) -> bytes:
    data = bytearray(_archive())
    for _ in range(draw(st.integers(1, 6))):
        position = draw(st.integers(0, len(data) - 1))
        kind = draw(st.sampled_from(["byte", "size", "cut", "insert"]))
        if kind == "byte":
            data[position] = draw(st.integers(0, 255))
        elif kind == "size":  # a 32-bit field (sizes, offsets, counts) made large
            data[position : position + 4] = draw(st.sampled_from(
                [b"\xff\xff\xff\x7f", b"\xff\xff\xff\xff", b"\x00\x00\x00\x40"]))  # fmt: skip
        elif kind == "cut":
            del data[position : position + draw(st.integers(1, 64))]
        else:
            data[position:position] = draw(st.binary(min_size=1, max_size=16))
    return bytes(data)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_mutated_zip())
def test_mutated_zips_raise_only_mjcf_errors(data: bytes) -> None:
    """A corrupted or crafted archive (sizes, offsets and counts made large, bytes cut or
    inserted) is read or refused with an mjcf.Error, unpacking no more than the limits."""
    with contextlib.suppress(mjcf.Error):
        mjcf.from_zip(io.BytesIO(data), limits=mjcf.archives.Limits(size=1 << 24, ratio=100))


def test_export_writes_only_inside_its_target(tmp_path: Path) -> None:
    """Asset names with directories, '..' or absolute paths become plain file names."""
    mesh = (MUJOCO_TESTDATA / "abdomen_1_body.msh").read_bytes()
    model = mjcf.RootElement(model="evil")
    for i, prefix in enumerate(["../../escape", "/etc/passwd", "sub/dir/name", ".hidden"]):
        asset = mjcf.Asset(mesh, ".msh", prefix=prefix)
        model.asset.add("mesh", name=f"m{i}", file=asset)
    out = tmp_path / "out"
    mjcf.export_with_assets(model, out)
    written = sorted(p.relative_to(tmp_path).as_posix() for p in tmp_path.rglob("*") if p.is_file())
    assert all(name.startswith("out/") and name.count("/") == 1 for name in written), written
    zip_path = mjcf.export_with_assets_as_zip(model, tmp_path / "evil.zip")
    with zipfile.ZipFile(zip_path) as archive:
        entries = [name.split("/") for name in archive.namelist()]
    assert all(len(e) == 2 and e[0] == "evil" and not e[1].startswith(".") for e in entries)


@pytest.mark.parametrize("entry", ["../evil.xml", "/tmp/evil.xml", "a/../../evil.xml"])
def test_from_zip_refuses_entries_outside_the_archive(tmp_path: Path, entry: str) -> None:
    archive_path = tmp_path / "slip.zip"
    with zipfile.ZipFile(archive_path, "w") as archive:
        archive.writestr("model.xml", "<mujoco><worldbody/></mujoco>")
        archive.writestr(entry, "<mujoco/>")
    with pytest.raises(mjcf.ParseError, match="outside it"):
        mjcf.from_zip(archive_path)
    assert not (tmp_path.parent / "evil.xml").exists()


# -- files that never end ---------------------------------------------------------------

_READ_A_DEVICE = """
import os, sys
import mjcf
fifo = sys.argv[1]
texture = '<mujoco><asset><texture name="t" type="2d" file="{}"/></asset></mujoco>'
for path in ("/dev/zero", fifo):
    for read in (
        lambda: mjcf.from_xml_string(texture.format(path)).get_assets(),
        lambda: mjcf.Physics.from_mjcf_model(mjcf.from_xml_string(texture.format(path))),
        lambda: mjcf.from_path(path),
        lambda: mjcf.from_zip(path),
    ):
        try:
            read()
        except mjcf.Error as error:
            print(type(error).__name__, "not a regular file" in str(error))
"""


def test_a_device_or_fifo_as_a_file_is_refused_not_read(tmp_path: Path) -> None:
    """/dev/zero read whole grew a process to 18.7 GB; a FIFO would block forever. Run in
    a child process, so that a regression fails the test instead of the machine."""
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    result = subprocess.run(
        [sys.executable, "-c", _READ_A_DEVICE, str(fifo)],
        capture_output=True,
        text=True,
        timeout=120,  # a guard against hanging, not a benchmark
        check=True,
    )
    lines = result.stdout.splitlines()
    assert len(lines) == 8 and all(line.endswith(" True") for line in lines), result.stdout
    assert {line.split()[0] for line in lines} == {"AssetError", "ParseError"}


def test_files_above_the_size_limit_are_refused(tmp_path: Path, monkeypatch) -> None:
    model_file = tmp_path / "model.xml"
    model_file.write_text(
        '<mujoco><asset><mesh name="m" file="m.msh"/></asset>'
        '<worldbody><geom type="mesh" mesh="m"/></worldbody></mujoco>'
    )
    (tmp_path / "m.msh").write_bytes((MUJOCO_TESTDATA / "abdomen_1_body.msh").read_bytes())
    model = mjcf.from_path(model_file)
    monkeypatch.setattr(mjcf.tree.assets, "FILE_SIZE_LIMIT", 2_000)
    with pytest.raises(mjcf.AssetError, match=r"more than 2000 bytes.*FILE_SIZE_LIMIT"):
        mjcf.Physics.from_mjcf_model(model)
    with pytest.raises(mjcf.AssetError, match="more than 2000 bytes"):
        model.get_assets()
    monkeypatch.setattr(mjcf.tree.assets, "FILE_SIZE_LIMIT", 100)
    with pytest.raises(mjcf.ParseError, match="more than 100 bytes"):
        mjcf.from_path(model_file)
    monkeypatch.undo()
    assert mjcf.Physics.from_mjcf_model(mjcf.from_path(model_file)).model.nmesh == 1
