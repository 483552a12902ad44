"""Rendering without MUJOCO_GL: a backend that works is chosen at the first render, and a
backend that cannot render raises RenderError at every attempt instead of aborting Python.

Each test runs a fresh interpreter, since MuJoCo reads MUJOCO_GL when it is imported (and
tests/conftest.py sets it for this one)."""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
from pathlib import Path

import pytest

from tests.conftest import gym_model

REPO = Path(__file__).resolve().parents[2]
LINUX_ONLY = pytest.mark.skipif(platform.system() != "Linux", reason="Linux's backends")

# Renders twice through mjcf, then once with a plain mujoco.Renderer, and reports each.
SCRIPT = """
import json, os, sys
import mujoco  # first, as a user's notebook may: MuJoCo has then read MUJOCO_GL
from mjcf import errors
from mjcf.sim import rendering
from mjcf.physics import Physics

physics = Physics.from_xml_path(sys.argv[1])
outcomes = []
for _ in range(2):
    try:
        frame = physics.render(240, 320)  # drawn as MuJoCo draws it: larger than 128
        outcomes.append({"backend": rendering.backend(), "std": float(frame.std())})
    except errors.RenderError as e:
        outcomes.append({"error": str(e)})
try:
    renderer = mujoco.Renderer(physics.model, 240, 320)
    renderer.update_scene(physics.data)
    outcomes.append({"mujoco_std": float(renderer.render().std())})
    renderer.close()
except Exception as e:
    outcomes.append({"mujoco_error": type(e).__name__})
print(json.dumps({"outcomes": outcomes, "MUJOCO_GL": os.environ.get("MUJOCO_GL")}))
"""


def run_script(**environment: str | None) -> dict:
    """SCRIPT in a fresh interpreter, without a display, with `environment` (None: unset)."""
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    for key, value in environment.items():
        env.pop(key, None)
        if value is not None:
            env[key] = value
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT, str(gym_model("ant"))],
        env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert done.returncode == 0, (done.returncode, done.stderr[-2000:])  # not aborted (134)
    return json.loads(done.stdout.strip().splitlines()[-1])


@LINUX_ONLY
def test_without_mujoco_gl_a_headless_process_renders_with_egl():
    result = run_script(MUJOCO_GL=None)
    first, second, plain = result["outcomes"]
    if "error" in first:  # a machine without EGL and OSMesa: the error says what to install
        assert "apt-get install libegl1 libegl-mesa0 libgl1" in first["error"]
        assert second == first
        pytest.skip(f"no headless OpenGL here: {first['error']}")
    assert first["backend"] == second["backend"] == "egl"
    assert first["std"] > 5 and second == first  # a real picture, the same twice
    # The choice is MuJoCo's too: a plain mujoco.Renderer made afterwards renders, and
    # child processes inherit it.
    assert plain["mujoco_std"] == pytest.approx(first["std"])
    assert result["MUJOCO_GL"] == "egl"


@LINUX_ONLY
def test_an_explicit_backend_that_cannot_render_fails_every_time_without_aborting():
    # GLFW without a display: MuJoCo alone aborts the process at the second attempt.
    result = run_script(MUJOCO_GL="glfw")
    first, second, plain = result["outcomes"]
    assert "error" in first and second == first
    assert first["error"].startswith("no OpenGL context could be made with MUJOCO_GL='glfw': ")
    assert "GLFW needs a display and $DISPLAY is not set" in first["error"]
    assert "Unset MUJOCO_GL" in first["error"]
    assert "mujoco_error" in plain  # raised, where MuJoCo alone aborted
    assert result["MUJOCO_GL"] == "glfw"  # the user's choice is kept


@LINUX_ONLY
def test_when_egl_fails_the_next_backend_is_tried_and_each_failure_named():
    # An EGL device that does not exist makes EGL fail as a driver without one would.
    result = run_script(MUJOCO_GL=None, MUJOCO_EGL_DEVICE_ID="99")
    first, second, _ = result["outcomes"]
    if "backend" in first:  # OSMesa is installed here
        assert first["backend"] == "osmesa" and first["std"] > 5
        return
    assert second == first
    message = first["error"]
    assert message.startswith("no OpenGL backend can render here (EGL: RuntimeError: ")
    assert "MUJOCO_EGL_DEVICE_ID" in message and "OSMESA: " in message
    assert "GLFW" not in message.partition(")")[0]  # no display: GLFW is not tried
    assert result["MUJOCO_GL"] is None  # nothing chosen, nothing passed on


def test_rendering_turned_off_says_so():
    result = run_script(MUJOCO_GL="off")
    first, second, _ = result["outcomes"]
    assert first == second == {"error": "rendering is turned off: MUJOCO_GL='off'"}
