"""RenderThreads: the frames of many environments drawn at once, each by its own renderer.

    threads = RenderThreads(count=2)
    frames = threads.draw([0, 1, 2, 3], lambda i: envs[i].physics.render(64, 64))  # 4 frames
    threads.close()

Promise: environment i is always drawn on thread i % count, in one OpenGL context per thread
(`RenderThreads`); `draw` raises the error of the first environment whose draw failed. Why
threads rather than processes, and what they gain: docs/performance_profile.md, "Costs behind
choices".
"""

from __future__ import annotations

import queue
import threading
import weakref
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from mjcf.sim import rendering

Draw = Callable[[int], np.ndarray]
# Environments, by index: a sequence or an array of ints.
Ids = Sequence[int] | np.ndarray


class _Job:
    """One call's share of the work: frames to fill, and a count of threads not done."""

    __slots__ = ("done", "draw", "error", "error_at", "frames", "lock", "pending")

    def __init__(self, draw: Draw, count: int, pending: int) -> None:
        self.draw = draw
        self.frames: list[Any] = [None] * count
        self.error: BaseException | None = None
        self.error_at = len(self.frames)  # the position of the environment that raised
        self.pending = pending
        self.lock = threading.Lock()
        self.done = threading.Event()

    def failed(self, position: int, error: BaseException) -> None:
        """The draw at `position` raised `error`: kept if no earlier position raised."""
        with self.lock:
            if position < self.error_at:
                self.error, self.error_at = error, position

    def finish(self) -> None:
        with self.lock:
            self.pending -= 1
            if self.pending == 0:
                self.done.set()


class RenderThreads:
    """Threads drawing environments' frames, environment i on thread i % count; started at
    the first `draw` that uses them.

    Environment i is always drawn on thread i % count, so its renderers (its `mjcf.Physics`'s
    own) are only ever current in that thread and the caller's; every thread releases its
    OpenGL context before another may use them (`mjcf.sim.rendering.release_context`). The
    environments of one thread share one OpenGL context
    (`mjcf.sim.rendering.context_group(threads.group(i))`, which the caller wraps around what
    may make environment i's renderers, such as its reset). With one thread, or a backend
    whose contexts stay in one thread (anything but EGL), frames are drawn in the caller's
    thread, in order.
    """

    def __init__(self, count: int) -> None:
        """Up to `count` threads (at least 1)."""
        self.count = max(1, int(count))
        self._groups = [object() for _ in range(self.count)]
        self._queues: list[queue.SimpleQueue[Any]] = []
        self._threads: list[threading.Thread] = []
        self._stop: weakref.finalize | None = None

    def group(self, i: int) -> object:
        """The context group (`mjcf.sim.rendering.context_group`) of environment i's renderers."""
        return self._groups[int(i) % self.count]

    def draw(self, ids: Ids, draw: Draw) -> list[np.ndarray]:
        """`draw(i)` for each environment of `ids`, in that order, environment i drawn on
        thread i % count. Raises what a draw raises (the first environment's of those that
        raised), after every thread finished its share."""
        draw = self._in_group(draw)
        if self.count == 1 or len(ids) == 1 or not rendering.threaded():
            return self._in_caller(ids, draw)
        shares: dict[int, list[tuple[int, int]]] = {}
        for position, i in enumerate(ids):
            shares.setdefault(int(i) % self.count, []).append((position, int(i)))
        self._start()
        rendering.release_context()  # the caller may hold the context of one of them
        job = _Job(draw, len(ids), len(shares))
        for thread, share in shares.items():
            self._queues[thread].put((job, share))
        job.done.wait()
        if job.error is not None:
            raise job.error
        return job.frames

    def _in_group(self, draw: Draw) -> Draw:
        """`draw`, with renderers it makes for environment i in i's context group."""

        def grouped(i: int) -> np.ndarray:
            with rendering.context_group(self.group(i)):
                return draw(i)

        return grouped

    @staticmethod
    def _in_caller(ids: Ids, draw: Draw) -> list[np.ndarray]:
        try:
            return [draw(int(i)) for i in ids]
        finally:
            rendering.release_context()

    def _start(self) -> None:
        if self._threads:
            return
        for k in range(self.count):
            work: queue.SimpleQueue[Any] = queue.SimpleQueue()
            thread = threading.Thread(
                target=_serve, args=(work,), name=f"composer-render-{k}", daemon=True
            )
            thread.start()
            self._queues.append(work)
            self._threads.append(thread)
        # Threads hold nothing of this object: they stop when it is collected, unclosed.
        self._stop = weakref.finalize(self, _stop, list(self._queues))

    def close(self) -> None:
        """Stop the threads (a later `draw` starts new ones); safe to call more than once."""
        if self._stop is not None:
            self._stop()
        for thread in self._threads:
            thread.join()
        self._queues, self._threads, self._stop = [], [], None


def _stop(queues: list[queue.SimpleQueue[Any]]) -> None:
    for work in queues:
        work.put(None)


def _serve(work: queue.SimpleQueue[Any]) -> None:
    """A render thread: draw each share put on `work` until None comes."""
    while True:
        item = work.get()
        if item is None:
            return
        _draw_share(*item)
        del item  # holds the draw function, and through it its environments, until then


def _draw_share(job: _Job, share: list[tuple[int, int]]) -> None:
    """Draw `share`, (position, environment) pairs, of `job`."""
    try:
        for position, i in share:
            try:
                job.frames[position] = job.draw(i)
            except BaseException as e:  # handed to the caller, who raises it
                job.failed(position, e)
                break
    finally:
        rendering.release_context()
        job.finish()
