"""Render settings fitted to the image size (`mjcf.sim.rendering.frame_settings`): a model that
leaves `<visual>` to MuJoCo's defaults renders small frames without shadows and
multisampling and large ones as MuJoCo draws them, on an offscreen buffer of the image's
size; whatever the MJCF sets is kept; the model itself never changes.

Each frame is compared, pixel for pixel, with a plain `mujoco.Renderer` drawing the same
model with the settings written into a copy of it: the slow, explicit way."""

from __future__ import annotations

import copy

import mujoco
import numpy as np
import pytest

import mjcf
from mjcf.sim import rendering
from tests.conftest import gym_model

DEFAULTS = {"shadowsize": 4096, "offsamples": 4, "offwidth": 640, "offheight": 480}


def plain_frame(model, data, height, width, **settings) -> np.ndarray:
    """A frame of a copy of `model` with `settings` written into its <visual>, drawn by a
    plain mujoco.Renderer."""
    copied = copy.copy(model)
    for name, value in settings.items():
        section = copied.vis.quality if name in ("shadowsize", "offsamples") else copied.vis.global_
        setattr(section, name, value)
    renderer = mujoco.Renderer(copied, height, width)
    renderer.update_scene(data)
    frame = renderer.render()
    renderer.close()
    return frame


def visual_of(model: mujoco.MjModel) -> dict[str, int]:
    quality, global_ = model.vis.quality, model.vis.global_
    return {"shadowsize": quality.shadowsize, "offsamples": quality.offsamples,
            "offwidth": global_.offwidth, "offheight": global_.offheight}  # fmt: skip


@pytest.fixture
def ant() -> mjcf.RootElement:
    """Gymnasium's ant, which leaves its render settings to MuJoCo's defaults; its
    directional light casts the ant's shadow on the floor."""
    return mjcf.from_path(str(gym_model("ant")))


def test_small_frames_have_no_shadows_nor_multisampling_and_the_model_is_unchanged(ant):
    physics = mjcf.Physics.from_mjcf_model(ant)
    assert visual_of(physics.model) == DEFAULTS
    frame = physics.render(64, 64)
    fast = plain_frame(physics.model, physics.data, 64, 64, shadowsize=0, offsamples=0,
                       offwidth=64, offheight=64)  # fmt: skip
    np.testing.assert_array_equal(frame, fast)
    # MuJoCo's own settings draw another picture (the ant's shadow, smoothed edges).
    assert np.abs(frame.astype(int) - plain_frame(physics.model, physics.data, 64, 64)).max() > 30
    assert visual_of(physics.model) == DEFAULTS
    assert rendering.frame_settings(84, 84) == {
        "global.offwidth": 84, "global.offheight": 84,
        "quality.shadowsize": 0, "quality.offsamples": 0,
    }  # fmt: skip


def test_large_frames_are_drawn_as_mujoco_draws_them(ant):
    physics = mjcf.Physics.from_mjcf_model(ant)
    frame = physics.render(240, 320)
    np.testing.assert_array_equal(frame, plain_frame(physics.model, physics.data, 240, 320))


def test_what_the_mjcf_sets_is_kept_even_at_mujocos_default_values(ant):
    ant.visual.quality.shadowsize = 4096  # MuJoCo's default, given on purpose
    ant.visual.quality.offsamples = 2
    physics = mjcf.Physics.from_mjcf_model(ant)
    frame = physics.render(64, 64)
    kept = plain_frame(physics.model, physics.data, 64, 64, offwidth=64, offheight=64)
    np.testing.assert_array_equal(frame, kept)
    shadowless = plain_frame(physics.model, physics.data, 64, 64, shadowsize=0)
    assert np.abs(frame.astype(int) - shadowless).max() > 30  # the shadow is drawn
    assert rendering.visual_settings_given(physics._compiled.xml) == {
        "quality.shadowsize",
        "quality.offsamples",
    }


def test_settings_of_an_attached_model_are_kept(ant):
    scene = mjcf.RootElement(model="scene")
    scene.visual.headlight.ambient = [0.3, 0.3, 0.3]
    ant.visual.quality.shadowsize = 1024
    scene.worldbody.attach(ant)
    physics = mjcf.Physics.from_mjcf_model(scene)
    assert physics.model.vis.quality.shadowsize == 1024
    frame = physics.render(64, 64)
    kept = plain_frame(physics.model, physics.data, 64, 64, offsamples=0, offwidth=64,
                       offheight=64)  # fmt: skip
    np.testing.assert_array_equal(frame, kept)


def test_a_model_compiled_from_text_keeps_values_other_than_mujocos_defaults():
    xml = gym_model("ant").read_text().replace("<option", '<visual><quality shadowsize="1024"/>'
                                               "</visual><option", 1)  # fmt: skip
    physics = mjcf.Physics.from_xml_string(xml)
    frame = physics.render(64, 64)
    kept = plain_frame(physics.model, physics.data, 64, 64, offsamples=0, offwidth=64,
                       offheight=64)  # fmt: skip
    np.testing.assert_array_equal(frame, kept)
    assert physics.model.vis.quality.shadowsize == 1024


def test_any_size_renders_unless_the_mjcf_sets_a_smaller_buffer(ant):
    physics = mjcf.Physics.from_mjcf_model(ant)
    assert physics.render(720, 1280).shape == (720, 1280, 3)  # over MuJoCo's 640x480
    getattr(ant.visual, "global").offwidth = 640
    physics = mjcf.Physics.from_mjcf_model(ant)
    with pytest.raises(mjcf.RenderError, match="offwidth"):
        physics.render(720, 1280)
    assert physics.render(480, 640).shape == (480, 640, 3)


def test_depth_and_segmentation_of_small_frames_match_the_explicit_settings(ant):
    physics = mjcf.Physics.from_mjcf_model(ant)
    depth = physics.render(64, 64, depth=True)
    segmentation = physics.render(64, 64, segmentation=True)
    copied = copy.copy(physics.model)
    copied.vis.quality.shadowsize = copied.vis.quality.offsamples = 0
    copied.vis.global_.offwidth = copied.vis.global_.offheight = 64
    renderer = mujoco.Renderer(copied, 64, 64)
    renderer.update_scene(physics.data)
    renderer.enable_depth_rendering()
    np.testing.assert_array_equal(depth, renderer.render())
    renderer.enable_segmentation_rendering()
    np.testing.assert_array_equal(segmentation, renderer.render())
    renderer.close()


def test_a_renderer_made_after_a_recompile_reuses_an_opengl_context_and_draws_the_same(ant):
    if rendering.backend() != "egl":
        pytest.skip("OpenGL contexts are reused on EGL only")
    physics = mjcf.Physics.from_mjcf_model(ant)
    first = physics.render(64, 64)
    used = physics._renderers[(64, 64)]._gl_context
    ant.find("geom", "floor").rgba = [0.8, 0.3, 0.3, 1]
    physics.reload_from_mjcf_model(ant)  # closes the renderer: its context is kept
    reused = physics.render(64, 64)
    assert physics._renderers[(64, 64)]._gl_context is used
    assert np.abs(reused.astype(int) - first).max() > 30  # the new floor colour is drawn
    rendering._idle_contexts.clear()  # the next renderer makes a context of its own
    fresh = mjcf.Physics.from_mjcf_model(ant)
    np.testing.assert_array_equal(reused, fresh.render(64, 64))
    assert fresh._renderers[(64, 64)]._gl_context is not used


def test_a_context_a_renderer_failed_in_is_freed_not_reused(ant):
    """MuJoCo leaves in the OpenGL context what it made before failing to make its render
    context there (1.5 GB of buffers for a 10,000 x 10,000 frame on Mesa): that context is
    destroyed, which frees them, and never handed to a later renderer."""
    if rendering.backend() != "egl":
        pytest.skip("OpenGL contexts are reused on EGL only")
    physics = mjcf.Physics.from_mjcf_model(ant)
    first = physics.render(64, 64)
    kept = physics._renderers[(64, 64)]._gl_context
    physics.reload_from_mjcf_model(ant)  # closes the renderer: its context is kept for reuse
    with pytest.raises(mjcf.RenderError, match="framebuffer"):
        physics.render(1, 100_000)  # wider than any OpenGL buffer: fails in the kept context
    idle = [context for kept_ones in rendering._idle_contexts.values() for context in kept_ones]
    assert all(context is not kept for context in idle)
    assert kept._context is None  # destroyed (EGL's GLContext.free)
    np.testing.assert_array_equal(physics.render(64, 64), first)
    assert physics._renderers[(64, 64)]._gl_context is not kept
