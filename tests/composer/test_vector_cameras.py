"""Camera observables in a VectorEnvironment: every environment's frames are those of its
single Environment, pixel for pixel, through seeded resets, autoresets and recompiles, drawn
on render threads whatever their number; a camera is not per-environment work."""

from __future__ import annotations

import gc
import threading
import weakref

import numpy as np
import pytest
from gymnasium.utils.env_checker import data_equivalence
from gymnasium.vector import AutoresetMode, SyncVectorEnv

import composer
from composer import observation
from composer.vector import VectorEnvironment
from composer.vector.rendering import RenderThreads
from tests.composer.test_camera_observable import SIZE, CameraSwing
from tests.composer.vector_scenes import BatchedSwing

KEY = "pendulum/front_image"
RED, GREEN, BLUE = [0.9, 0.1, 0.1, 1.0], [0.1, 0.9, 0.1, 1.0], [0.1, 0.1, 0.9, 1.0]


class BatchedCameraSwing(BatchedSwing):
    """BatchedSwing (all batched) observed through the pendulum's camera too; with
    `colours`, each episode paints the rod the next colour (a recompile)."""

    def __init__(self, colours: list[list[float]] | None = None, **images) -> None:
        super().__init__(terminate_above=1.0)
        self.pendulum.observables.add_observable(
            "front_image", observation.MJCFCamera(self.pendulum.camera, *SIZE, **images)
        )
        self.pendulum.observables["front_image"].enabled = True
        self.rod = self.pendulum.mjcf_model.find("geom", "rod")
        self._colours = list(colours or [])

    def initialize_episode_mjcf(self, random_state: np.random.RandomState) -> None:
        if self._colours:
            self.rod.rgba = self._colours.pop(0)


def runs_agree(factory, n, mode=AutoresetMode.NEXT_STEP, steps=40, seed=5, **options):
    """A VectorEnvironment of `factory` and SyncVectorEnv of its single Environments, reset
    with `seed` and stepped with the same actions, observe the same frames; returns the
    episodes that ended and the vector environment."""
    vector = VectorEnvironment(factory, n, autoreset_mode=mode, time_limit=0.3, **options)
    reference = SyncVectorEnv(
        [lambda: composer.Environment(factory(), time_limit=0.3) for _ in range(n)],
        autoreset_mode=mode,
    )
    got, expected = vector.reset(seed=seed), reference.reset(seed=seed)
    assert got[0][KEY].shape[:3] == (n, *SIZE)
    assert data_equivalence(got, expected, exact=True)
    rng = np.random.default_rng(seed)
    ended = 0
    for t in range(steps):
        actions = 2 * rng.uniform(-1, 1, vector.action_space.shape).astype(np.float32)
        got, expected = vector.step(actions), reference.step(actions)
        assert data_equivalence(got, expected, exact=True), t
        ended += int(np.sum(got[2] | got[3]))
    reference.close()
    return ended, vector


@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP])
def test_frames_equal_single_environments_through_autoresets(mode):
    ended, vector = runs_agree(BatchedCameraSwing, 4, mode)
    assert ended >= 4  # terminations and time limits, each reset drawn again
    assert vector.rendered == [KEY] and vector.per_environment == []
    frames = vector.step(np.zeros((4, 1), np.float32))[0][KEY]
    assert frames.dtype == np.uint8 and frames.shape == (4, *SIZE, 3)
    assert len({frame.tobytes() for frame in frames}) == 4  # each its own state
    vector.close()


@pytest.mark.parametrize("image", ["depth", "segmentation"])
def test_depth_and_segmentation_images_equal_single_environments(image):
    _, vector = runs_agree(lambda: BatchedCameraSwing(**{image: True}), 3, steps=12)
    frames = vector.reset(seed=0)[0][KEY]
    assert frames.dtype == (np.float32 if image == "depth" else np.int32)
    vector.close()


def test_frames_equal_single_environments_on_the_per_environment_fallback():
    ended, vector = runs_agree(CameraSwing, 3, steps=30)
    assert ended >= 3 and vector.rendered == [KEY]
    assert "observable pendulum/orientation" in vector.per_environment
    vector.close()


def test_a_recompiled_scene_is_what_each_camera_sees():
    def painted():
        return BatchedCameraSwing(colours=[RED, GREEN, BLUE, RED, GREEN, BLUE])

    ended, vector = runs_agree(painted, 3, steps=40)
    assert ended >= 3
    rods = [env.physics.bind(env.task.rod).rgba for env in vector.environments]
    assert any(not np.array_equal(rod, RED) for rod in rods)  # recompiled since the reset
    vector.close()


@pytest.mark.parametrize("threads", [1, 3])
def test_the_number_of_render_threads_changes_no_frame(threads):
    _, vector = runs_agree(BatchedCameraSwing, 5, steps=15, nthread=threads)
    vector.close()


def test_a_seeded_reset_gives_the_same_frames_again():
    vector = VectorEnvironment(BatchedCameraSwing, 3)
    first = vector.reset(seed=11)[0][KEY]
    zero = np.zeros((3, 1), np.float32)
    after = [vector.step(zero)[0][KEY] for _ in range(3)]
    np.testing.assert_array_equal(vector.reset(seed=11)[0][KEY], first)
    for frames in after:
        np.testing.assert_array_equal(vector.step(zero)[0][KEY], frames)
    assert not np.array_equal(vector.reset(seed=12)[0][KEY], first)
    vector.close()


def test_render_threads_draw_each_environment_on_its_own_thread_in_order():
    threads = RenderThreads(3)
    seen: dict[int, str] = {}

    def draw(i: int) -> np.ndarray:
        seen[i] = threading.current_thread().name
        return np.full((2, 2, 3), i, np.uint8)

    frames = threads.draw([5, 0, 4, 1, 3], draw)
    assert [int(f[0, 0, 0]) for f in frames] == [5, 0, 4, 1, 3]
    assert seen[0] == seen[3] and seen[1] == seen[4] and seen[0] != seen[1] != seen[5]

    def broken(i: int) -> np.ndarray:
        raise ValueError(f"environment {i}")

    with pytest.raises(ValueError, match="environment 1"):
        threads.draw([1, 2, 4], broken)  # the first environment's error of those raised
    threads.close()
    threads.close()
    assert len(threads.draw([0, 1], draw)) == 2  # started again
    threads.close()


def test_an_unclosed_vector_environment_is_collected_and_its_render_threads_stop():
    before = set(threading.enumerate())
    vector = VectorEnvironment(BatchedCameraSwing, 3, nthread=2)
    vector.reset(seed=0)
    vector.step(np.zeros((3, 1), np.float32))  # drawn on the render threads
    threads = [t for t in set(threading.enumerate()) - before if t.name.startswith("composer-")]
    assert len(threads) == 2
    collected = weakref.ref(vector)
    del vector
    gc.collect()
    assert collected() is None
    for thread in threads:
        thread.join(timeout=60)  # a bound for a hang, not a timing
        assert not thread.is_alive()
