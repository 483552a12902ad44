"""Meshes drawn with fewer triangles in small images (`mjcf.sim.render_meshes`): the UR5e's
121,783 triangles are simplified for a 64x64 frame, the frame looks as the full meshes' frame
does, and nothing but the render context's triangles changes: not the model, not the
simulation's rays, not what is written to the model at run time, not larger images, not
models whose meshes already fit."""

from __future__ import annotations

import copy

import mujoco
import numpy as np
import pytest

import mjcf
from mjcf.sim import render_meshes, rendering
from tests.conftest import UR5E, gym_model

SIZE = 64


@pytest.fixture(scope="module")
def arm() -> mjcf.Physics:
    """The shipped UR5e bent so each link shows, a camera close enough that it fills an
    eighth of a 64x64 frame, and a rangefinder whose ray meets a link."""
    root = mjcf.from_path(str(UR5E))
    root.worldbody.add("light", pos=[0, 0, 3], dir=[0, 0, -1])
    forearm = root.find("body", "forearm_link")
    root.worldbody.add(
        "camera", name="side", pos=[0.7, -0.7, 0.7], mode="targetbody", target=forearm
    )
    eye = root.worldbody.add("site", name="eye", pos=[0.0, 0.0, 1.5], zaxis=[0, 0, -1])
    root.sensor.add("rangefinder", name="down", site=eye)
    physics = mjcf.Physics.from_mjcf_model(root)
    physics.data.qpos[:] = [0.3, -1.2, 1.5, -1.0, -1.4, 0.2]
    physics.forward()
    return physics


def full_frame(physics: mjcf.Physics, height: int, width: int, **kwargs) -> np.ndarray:
    """The frame with every mesh as it is: a plain renderer of a copy of the model with the
    same small-frame settings (the slow, explicit way)."""
    rendering.backend()  # MuJoCo's renderer makes its contexts on the backend chosen
    copied = copy.copy(physics.model.ptr)
    for key, value in rendering.frame_settings(height, width).items():
        section, attribute = key.split(".")
        visual = copied.vis.quality if section == "quality" else copied.vis.global_
        setattr(visual, attribute, value)
    renderer = mujoco.Renderer(copied, height, width)
    if kwargs.get("depth"):
        renderer.enable_depth_rendering()
    renderer.update_scene(physics.data.ptr, camera="side")
    frame = renderer.render()
    renderer.close()
    return frame


def test_a_small_frame_draws_the_budget_of_triangles(arm: mjcf.Physics) -> None:
    model = arm.model.ptr
    budget = render_meshes.face_budget(SIZE, SIZE)
    assert model.mesh_facenum.sum() > 3 * budget
    drawn = render_meshes.simplified(model, budget)
    assert drawn is not None
    assert budget // 2 < drawn.mesh_facenum.sum() <= budget
    # each mesh keeps triangles of its own vertices
    for mesh in range(model.nmesh):
        start, count = drawn.mesh_faceadr[mesh], drawn.mesh_facenum[mesh]
        faces = drawn.mesh_face[start : start + count]
        assert count > 0 and faces.min() >= 0 and faces.max() < model.mesh_vertnum[mesh]


def test_the_simplified_frame_looks_like_the_full_one(arm: mjcf.Physics) -> None:
    ours = arm.render(SIZE, SIZE, camera_id="side")
    full = full_frame(arm, SIZE, SIZE)
    difference = np.abs(ours.astype(int) - full.astype(int)).max(axis=-1)
    arm_pixels = (full != full[0, 0]).any(axis=-1).sum()
    assert arm_pixels > 400
    assert (difference > 0).sum() > 0  # simplified indeed
    # Edges and highlights move by a pixel here and there (8% of the arm's pixels by more
    # than 48 of 255 at 8 triangles a pixel; 24% at 4); a wrong mesh would differ in most.
    assert (difference > 48).sum() < 0.12 * arm_pixels
    depth = arm.render(SIZE, SIZE, camera_id="side", depth=True)
    full_depth = full_frame(arm, SIZE, SIZE, depth=True)
    far = full_depth.max()  # the background
    on_arm, on_full_arm = depth < far, full_depth < far
    assert (on_arm != on_full_arm).sum() < 0.05 * arm_pixels  # the outline, within a pixel
    both = on_arm & on_full_arm
    assert np.abs(depth - full_depth)[both].max() < 0.02  # metres: within a grid cell


def test_the_model_and_its_rays_are_untouched(arm: mjcf.Physics) -> None:
    model = arm.model.ptr
    before = (model.mesh_face.copy(), model.mesh_facenum.copy(), arm.data.sensordata.copy())
    arm.render(SIZE, SIZE, camera_id="side")
    drawn = render_meshes.simplified(model, render_meshes.face_budget(SIZE, SIZE))
    assert drawn is not None and drawn.mesh_facenum.sum() < before[1].sum()
    arm.forward()
    assert np.array_equal(model.mesh_face, before[0])
    assert np.array_equal(model.mesh_facenum, before[1])
    assert before[2][0] > 0 and np.array_equal(arm.data.sensordata, before[2])


def test_what_is_written_at_run_time_shows(arm: mjcf.Physics) -> None:
    model = arm.model.ptr
    first = arm.render(SIZE, SIZE, camera_id="side")
    saved = model.geom_rgba.copy(), model.mat_rgba.copy()
    try:
        model.geom_rgba[:] = [1.0, 0.0, 0.0, 1.0]
        model.mat_rgba[:] = [1.0, 0.0, 0.0, 1.0]
        red = arm.render(SIZE, SIZE, camera_id="side")
    finally:
        model.geom_rgba[:], model.mat_rgba[:] = saved
    changed = (red != first).any(axis=-1)
    assert changed.sum() > 100
    assert (red[changed][:, 0] >= red[changed][:, 1]).all()  # red where the arm is


def test_large_frames_and_small_models_draw_every_triangle(arm: mjcf.Physics) -> None:
    height, width = 240, 320
    large = arm.render(height, width, camera_id="side")
    assert np.array_equal(large, full_frame(arm, height, width))
    ant = mjcf.Physics.from_mjcf_model(mjcf.from_path(str(gym_model("ant"))))
    assert render_meshes.simplified(ant.model.ptr, render_meshes.face_budget(SIZE, SIZE)) is None


def test_it_can_be_turned_off(arm: mjcf.Physics, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(render_meshes, "FACES_PER_PIXEL", None)
    physics = copy.copy(arm)
    assert np.array_equal(physics.render(SIZE, SIZE, camera_id="side"), full_frame(arm, SIZE, SIZE))
