"""Renderers sharing an OpenGL context (`mjcf.sim.rendering.context_group`) and drawing from
other threads (`release_context`): each draws, pixel for pixel, what a renderer with a
context of its own draws, whatever the order, size, model or thread; closing one leaves the
others drawing. The reference is each physics' renderer made outside any group."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import mjcf
from mjcf.sim import rendering
from tests.conftest import gym_model

# (model, height, width): two models, three sizes, one model twice
SCENES = [("ant", 64, 64), ("humanoid", 48, 80), ("ant", 84, 84), ("hopper", 64, 64)]


@pytest.fixture
def egl() -> None:
    if not rendering.threaded():
        pytest.skip("contexts are shared and move between threads on EGL only")


def moved(physics: mjcf.Physics, step: int) -> mjcf.Physics:
    physics.data.qpos[:] = physics.model.qpos0 + 0.05 * step
    physics.forward()
    return physics


def scenes() -> list[tuple[mjcf.Physics, int, int]]:
    return [
        (moved(mjcf.Physics.from_xml_path(str(gym_model(name))), k), height, width)
        for k, (name, height, width) in enumerate(SCENES)
    ]


def test_renderers_of_one_group_draw_what_their_own_contexts_draw(egl):
    grouped, own = scenes(), scenes()
    key = object()
    with rendering.context_group(key):
        for physics, height, width in grouped:
            physics.render(height, width)
    contexts = {id(p._renderers[(h, w)]._gl_context) for p, h, w in grouped}
    assert len(contexts) == 1  # one OpenGL context for all
    expected = [physics.render(height, width) for physics, height, width in own]
    assert len({id(p._renderers[(h, w)]._gl_context) for p, h, w in own}) == len(own)
    for k in [0, 1, 2, 3, 1, 0, 3, 2]:
        physics, height, width = grouped[k]
        np.testing.assert_array_equal(physics.render(height, width), expected[k])
    physics, height, width = grouped[1]
    np.testing.assert_array_equal(
        physics.render(height, width, depth=True), own[1][0].render(height, width, depth=True)
    )
    grouped[0][0].close()  # one renderer fewer: the others draw on
    for k in (3, 1, 2):
        physics, height, width = grouped[k]
        np.testing.assert_array_equal(physics.render(height, width), expected[k])
    for physics, _, _ in grouped + own:
        physics.close()


def test_renderers_draw_from_another_thread_after_release(egl):
    grouped, own = scenes(), scenes()
    expected = [physics.render(height, width) for physics, height, width in own]
    with rendering.context_group(object()):
        first = [physics.render(height, width) for physics, height, width in grouped]
    frames: list[np.ndarray] = []

    def draw() -> None:
        frames.extend(physics.render(height, width) for physics, height, width in grouped)
        rendering.release_context()

    rendering.release_context()  # this thread drew last with the group's context
    worker = threading.Thread(target=draw)
    worker.start()
    worker.join()
    for got, again, want in zip(frames, first, expected, strict=True):
        np.testing.assert_array_equal(got, want)
        np.testing.assert_array_equal(again, want)
    # and back in this thread, which made them
    physics, height, width = grouped[2]
    np.testing.assert_array_equal(physics.render(height, width), expected[2])
    for physics, _, _ in grouped + own:
        physics.close()


def _in_thread(draw):
    """`draw()` in a new thread: what it returned or raised."""
    out: dict = {}

    def run() -> None:
        try:
            out["frame"] = draw()
        except Exception as e:  # reported to the test
            out["error"] = e

    thread = threading.Thread(target=run)
    thread.start()
    thread.join()
    if "error" in out:
        raise out["error"]
    return out["frame"]


def test_a_physics_renders_from_a_thread_while_another_holds_its_renderer(egl):
    """The main thread drew last and holds its renderer's context (no release_context): a
    second thread draws the same frame with a renderer of its own, instead of raising
    EGL_BAD_ACCESS; then the main thread draws on with its own, and closes both."""
    physics = moved(mjcf.Physics.from_xml_path(str(gym_model("ant"))), 1)
    abandoned = len(rendering._abandoned)
    first = physics.render(64, 64)
    for _ in range(2):
        np.testing.assert_array_equal(_in_thread(lambda: physics.render(64, 64)), first)
    np.testing.assert_array_equal(physics.render(64, 64), first)
    assert len(physics._renderers) >= 2  # the main thread's, and the other threads'
    # A renderer whose context another thread holds refuses with a RenderError, not EGL's.
    renderer = physics._renderers[(64, 64)]
    with pytest.raises(rendering.ContextBusyError, match="whose OpenGL context is current"):
        _in_thread(lambda: rendering.render(renderer, physics.data, -1, False, False, None))
    physics.close()
    assert len(rendering._abandoned) == abandoned  # every renderer freed


def test_a_physics_first_drawn_by_a_thread_that_ended_renders_and_closes(egl):
    """The thread that made the renderer ended holding its context, which no other thread
    can free: the main thread draws with its own, and closing keeps that one unfreed
    instead of raising."""
    physics = moved(mjcf.Physics.from_xml_path(str(gym_model("ant"))), 2)
    first = _in_thread(lambda: physics.render(64, 64))
    np.testing.assert_array_equal(physics.render(64, 64), first)
    held = physics._renderers[(64, 64)]._gl_context
    physics.close()
    assert rendering._abandoned[-1][1] is held
