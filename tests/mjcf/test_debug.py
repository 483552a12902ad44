"""Debug mode: a model MuJoCo rejects raises mjcf.CompileError naming the element and
the Python line that created it."""

from __future__ import annotations

import inspect
from collections.abc import Iterator
from pathlib import Path

import pytest

import mjcf

THIS_FILE = Path(__file__).resolve()


@pytest.fixture
def debug_mode() -> Iterator[None]:
    was_enabled = mjcf.is_debug_mode()
    mjcf.enable_debug_mode()
    try:
        yield
    finally:
        if not was_enabled:
            mjcf.disable_debug_mode()


def _line() -> int:
    """The line of the caller."""
    return inspect.currentframe().f_back.f_lineno


def test_compile_error_names_the_element_and_its_line(debug_mode) -> None:
    model = mjcf.RootElement(model="broken")
    body = model.worldbody.add("body", name="arm")
    line = _line() + 1
    body.add("geom", type="box")  # no size
    with pytest.raises(mjcf.CompileError) as raised:
        mjcf.Physics.from_mjcf_model(model)
    message = str(raised.value)
    assert "size 0 must be positive" in message  # MuJoCo's own words
    assert '<worldbody>/<body name="arm">/<geom>' in message
    assert f"{THIS_FILE}:{line}" in message


def test_compile_error_inside_an_attached_model(debug_mode) -> None:
    child = mjcf.RootElement(model="child")
    leg = child.worldbody.add("body", name="leg")
    leg.add("geom", size=[0.1])
    line = _line() + 1
    inner = leg.add("body", name="foot")  # MuJoCo points at the body of the joint
    inner.add("freejoint")  # not at the top level
    inner.add("geom", size=[0.1])
    scene = mjcf.RootElement(model="scene")
    scene.worldbody.add("body", name="holder").attach(child)
    with pytest.raises(mjcf.CompileError) as raised:
        mjcf.Physics.from_mjcf_model(scene)
    message = str(raised.value)
    assert "free joint can only be used on top level" in message
    assert 'model \'child\': <worldbody>/<body name="leg">/<body name="foot"> (' in message
    assert f"{THIS_FILE}:{line}" in message


def test_parsed_elements_remember_their_file_and_line(debug_mode, tmp_path: Path) -> None:
    path = tmp_path / "bad.xml"
    path.write_text(
        '<mujoco>\n  <worldbody>\n    <geom type="sphere"/>\n  </worldbody>\n</mujoco>\n'
    )
    with pytest.raises(mjcf.CompileError, match=rf"<worldbody>/<geom> \(created at {path}:3\)"):
        mjcf.Physics.from_mjcf_model(mjcf.from_path(path))


def test_outside_debug_mode_the_element_is_still_named() -> None:
    assert not mjcf.is_debug_mode()
    model = mjcf.RootElement(model="broken")
    model.worldbody.add("geom", type="box")
    with pytest.raises(mjcf.CompileError, match=r"in model 'broken': <worldbody>/<geom>$"):
        mjcf.Physics.from_mjcf_model(model)
