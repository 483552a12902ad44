"""`composer show`: the scene of a task and a rendered frame."""

from __future__ import annotations

import re
import sys

import imageio.v3 as iio
import numpy as np
import pytest

from tests.cli.helpers import composer, environment


def test_show_prints_the_scene_and_writes_a_frame(tmp_path):
    result = composer("show", "Reach", "--out", "frames/reach.png", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    out = result.stdout
    assert out.startswith("Reach (composer/Reach-v0): Move a planar 2-link arm")
    assert "control 0.04 s (8 substeps); time limit 3 s (75 steps)" in out
    assert re.search(r"^  floor \(Floor\)$", out, re.M)
    assert re.search(r"^    arm \(PlanarArm\)$", out, re.M)  # attached under the arena
    assert re.search(r"^      joints +arm/\w+ hinge", out, re.M)
    assert re.search(r"^      actuators +arm/\w+ -> arm/\w+", out, re.M)
    assert "observations (10 values)" in out
    assert re.search(r"^  arm/joint_angles +\(4,\) +float64$", out, re.M)
    assert re.search(r"^  to_target +\(2,\)", out, re.M)
    assert "actions (2 values): Box(-1.0, 1.0, (2,), float32)" in out
    assert out.rstrip().endswith("frame: frames/reach.png (320x240)")
    frame = iio.imread(tmp_path / "frames" / "reach.png")
    assert frame.shape == (240, 320, 3)
    assert frame.std() > 10  # a scene, not a blank image


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="EGL fallback is for Linux")
def test_show_renders_headless_without_mujoco_gl(tmp_path):
    env = environment()
    for name in ("MUJOCO_GL", "DISPLAY", "WAYLAND_DISPLAY"):
        env.pop(name, None)
    result = composer("show", "CartpoleSwingup", "--out", "cartpole.png", cwd=tmp_path, env=env)
    assert result.returncode == 0, result.stderr
    frame = iio.imread(tmp_path / "cartpole.png")
    assert frame.shape == (240, 320, 3) and np.ptp(frame) > 50


def test_show_without_out_writes_nothing(tmp_path):
    result = composer("show", "Reach", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.rstrip().endswith("frame: none (--out FILE.png renders one)")
    assert list(tmp_path.iterdir()) == []  # no Reach.png, no MUJOCO_LOG.TXT
