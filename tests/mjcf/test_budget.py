"""A tiny model cannot make MuJoCo work for minutes or allocate gigabytes (`mjcf.budget`):
what it asks is measured before MuJoCo compiles it, as MuJoCo counts it, and refused past
the budget with an error naming the model, the element and the limit; MuJoCo's unknown
exceptions become CompileErrors. The limits are tested small, configured here."""

from __future__ import annotations

import struct
import subprocess
import sys
import time
import zlib

import mujoco
import pytest

import mjcf
from mjcf import budget
from tests.conftest import GYM_ASSETS

# Models under 200 bytes that compiled for minutes or allocated gigabytes, and what the
# budget finds in each.
BOMBS = {
    "replicate": ('<mujoco><worldbody><replicate count="10000"><replicate count="10000">'
                  '<geom size=".1"/></replicate></replicate></worldbody></mujoco>',
                  "100,010,003 elements", "<worldbody>/<replicate>/<replicate>/<geom>"),
    "flexcomp": ('<mujoco><worldbody><flexcomp name="f" type="grid" count="3000 3000 1" '
                 'spacing=".1 .1 .1" dim="2"/></worldbody></mujoco>', "9,000,003 elements",
                 '<flexcomp name="f">'),
    "height field": ('<mujoco><asset><hfield name="h" nrow="100000" ncol="20000" '
                     'size="1 1 1 1"/></asset></mujoco>', "8,000,000,000 bytes",
                     '<hfield name="h">'),
    "texture by default": ('<mujoco><default><texture builtin="checker" width="60000" '
                           'height="60000"/></default><asset><texture name="t" type="2d"/>'
                           "</asset></mujoco>", "10,800,000,000 bytes", '<texture name="t">'),
    "arena": ('<mujoco><size memory="1T"/></mujoco>', "1,099,511,627,776 bytes", "<size>"),
    "keyframes": ('<mujoco><size nkey="1000000000"/><worldbody><body><freejoint/>'
                  '<geom size="1"/></body></worldbody></mujoco>', "1,000,000,006 elements",
                  "<size>"),
    "shadow map": ('<mujoco><visual><quality shadowsize="100000"/></visual></mujoco>',
                   "40,000,000,000 bytes", "<visual>/<quality>"),
    "builtin mesh": ('<mujoco><asset><mesh name="m" builtin="supersphere" '
                     'params="100000 1 1"/></asset></mujoco>', "10,000,000,003 elements",
                     '<mesh name="m">'),
}  # fmt: skip


@pytest.mark.parametrize("name", BOMBS)
def test_tiny_models_asking_for_minutes_or_gigabytes_are_refused_at_once(name):
    text, asked, where = BOMBS[name]
    assert len(text) < 200
    started = time.perf_counter()
    with pytest.raises(mjcf.BudgetError) as caught:
        mjcf.Physics.from_mjcf_model(mjcf.from_xml_string(text, model_dir="."))
    message = str(caught.value)
    assert message.startswith(f"model 'unnamed_model' asks MuJoCo for {asked}, over the budget")
    assert where in message and "if you trust the model, raise the budget's" in message
    with pytest.raises(mjcf.BudgetError, match=f"the model asks MuJoCo for {asked}"):
        mjcf.Physics.from_xml_string(text)
    assert isinstance(caught.value, mjcf.CompileError) and isinstance(caught.value, ValueError)
    assert time.perf_counter() - started < 5  # a guard against compiling, not a benchmark


def _grid(rows: int, columns: int) -> str:
    return (
        f'<mujoco><worldbody><replicate count="{rows}" offset="1 0 0"><replicate '
        f'count="{columns}" offset="0 1 0"><body><joint/><geom size=".1"/></body>'
        "</replicate></replicate></worldbody></mujoco>"
    )


def test_elements_are_counted_as_mujoco_builds_them():
    """The count of a model's elements with its replicates expanded is what MuJoCo
    compiles: bodies, joints and geoms, and the elements that hold them."""
    for rows, columns in ((3, 4), (1, 7), (5, 5)):
        measured = budget.measure(_grid(rows, columns), {})
        model = mujoco.MjModel.from_xml_string(_grid(rows, columns))
        holders = 3 + rows  # <mujoco>, <worldbody>, the outer <replicate>, the inner ones
        assert measured.elements == holders + (model.nbody - 1) + model.njnt + model.ngeom
    flex = (
        '<mujoco><worldbody><flexcomp name="f" type="grid" count="4 5 1" dim="2"/>'
        "</worldbody></mujoco>"
    )
    model = mujoco.MjModel.from_xml_string(flex)
    assert budget.measure(flex, {}).elements == 3 + model.nflexvert


def test_the_budget_is_raised_by_module_setting_or_environment(monkeypatch):
    text = _grid(4, 10)  # 127 elements
    monkeypatch.setattr(budget, "LIMITS", budget.Budget(elements=100, bytes=1 << 20))
    with pytest.raises(mjcf.BudgetError, match="127 elements, over the budget of 100"):
        mjcf.Physics.from_mjcf_model(mjcf.from_xml_string(text))
    monkeypatch.setattr(budget, "LIMITS", budget.Budget(elements=127, bytes=1 << 20))
    assert mjcf.Physics.from_mjcf_model(mjcf.from_xml_string(text)).model.ngeom == 40
    monkeypatch.setattr(budget, "LIMITS", None)
    monkeypatch.setenv("MJCF_ELEMENT_LIMIT", "126")
    with pytest.raises(mjcf.BudgetError, match="MJCF_ELEMENT_LIMIT"):
        mjcf.Physics.from_xml_string(text)
    monkeypatch.setenv("MJCF_ELEMENT_LIMIT", "1000")
    monkeypatch.setenv("MJCF_ALLOCATION_LIMIT", "1K")
    hfield = '<mujoco><asset><hfield name="h" nrow="20" ncol="20" size="1 1 1 1"/></asset></mujoco>'
    with pytest.raises(mjcf.BudgetError, match="1,600 bytes, over the budget of 1,024"):
        mjcf.Physics.from_xml_string(hfield)
    monkeypatch.setenv("MJCF_ALLOCATION_LIMIT", "lots")
    with pytest.raises(mjcf.BudgetError, match="not a number"):
        mjcf.Physics.from_xml_string(hfield)


def _png_header(width: int, height: int) -> bytes:
    """The first bytes of a PNG of `width` x `height` (its header: what a decoder sizes
    its output by), without the image."""
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    chunk = struct.pack(">I", 13) + b"IHDR" + ihdr
    return b"\x89PNG\r\n\x1a\n" + chunk + struct.pack(">I", zlib.crc32(chunk[4:]))


def test_images_are_measured_by_their_headers(tmp_path):
    """A PNG decodes to 4 bytes a pixel whatever its size on disk: given as an asset or
    read by MuJoCo from a file, a texture or height field of 40,000 x 40,000 pixels is
    refused before it is decoded."""
    texture = '<mujoco><asset><texture name="t" type="2d" file="{}"/></asset></mujoco>'
    with pytest.raises(mjcf.BudgetError, match="6,400,000,000 bytes") as caught:
        mjcf.Physics.from_mjcf_model(
            mjcf.from_xml_string(
                texture.format("big.png"), assets={"big.png": _png_header(40_000, 40_000)}
            )
        )
    assert '<texture name="t">' in str(caught.value)
    (tmp_path / "big.png").write_bytes(_png_header(40_000, 40_000))
    hfield = '<mujoco><asset><hfield name="h" file="big.png" size="1 1 1 1"/></asset></mujoco>'
    (tmp_path / "model.xml").write_text(hfield)
    with pytest.raises(mjcf.BudgetError, match="6,400,000,000 bytes"):
        mjcf.Physics.from_mjcf_model(mjcf.from_path(tmp_path / "model.xml"))
    assert (
        budget.measure(texture.format("small.png"), {"small.png": _png_header(64, 32)}).bytes
        == 4 * 64 * 32
    )


def test_real_models_are_well_within_the_budget():
    for name in ("ant", "humanoid", "pusher"):
        text = (GYM_ASSETS / f"{name}.xml").read_text()
        measured = budget.measure(text, {})
        assert measured.elements < budget.DEFAULT_ELEMENTS / 100
        assert measured.bytes < budget.DEFAULT_BYTES / 100


_OUT_OF_MEMORY = """
import resource, mjcf
from mjcf import budget
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))  # malloc fails, nothing is touched
budget.LIMITS = budget.Budget(elements=10**6, bytes=1 << 40)
text = '<mujoco><asset><hfield name="h" nrow="30000" ncol="30000" size="1 1 1 1"/></asset></mujoco>'
for compile in (lambda: mjcf.Physics.from_mjcf_model(mjcf.from_xml_string(text)),
                lambda: mjcf.Physics.from_xml_string(text)):
    try:
        compile()
    except mjcf.CompileError as error:
        print(type(error).__name__, error)
"""


def test_mujocos_unknown_exception_is_a_compile_error_naming_the_model():
    """With the budget raised past what the process may allocate, MuJoCo's compile fails
    with a RuntimeError('Caught an unknown exception!'): a CompileError here (a child
    process whose address space is limited, so the allocation fails at once)."""
    result = subprocess.run(
        [sys.executable, "-c", _OUT_OF_MEMORY], capture_output=True, text=True, timeout=120,
        check=True,
    )  # fmt: skip
    lines = result.stdout.splitlines()
    assert lines == [
        "CompileError MuJoCo failed to compile model 'unnamed_model': Caught an unknown "
        "exception! (most often memory ran out: see mjcf.budget for what a model may ask)",
        "CompileError MuJoCo failed to compile the model: Caught an unknown exception! (most "
        "often memory ran out: see mjcf.budget for what a model may ask)",
    ], result.stdout + result.stderr


_OVERFLOW = """
import resource, sys, mujoco
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
mujoco.MjModel.from_xml_string(sys.argv[1])
"""


def test_a_height_field_mujoco_crashes_on_is_refused_whatever_the_budget(monkeypatch):
    text = (
        '<mujoco><asset><hfield name="h" nrow="1048576" ncol="1048576" size="1 1 1 1"/>'
        "</asset></mujoco>"
    )
    crashed = subprocess.run([sys.executable, "-c", _OVERFLOW, text], capture_output=True,
                             timeout=120, check=False)  # fmt: skip
    assert crashed.returncode == -11  # SIGSEGV: MuJoCo 4.0.0's count overflows
    monkeypatch.setattr(budget, "LIMITS", budget.Budget(elements=10**12, bytes=1 << 62))
    with pytest.raises(mjcf.BudgetError, match=r"MuJoCo 4\.0\.0 crashes"):
        mjcf.Physics.from_mjcf_model(mjcf.from_xml_string(text))
