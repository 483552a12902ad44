"""Benchmark sides in processes of their own, driven round by round from one parent.

    worker = Worker('bench.vector_sides', 'envpool')     # module with SIDES, side name
    worker.build(num_envs=32, nthread=2)
    wall, cpu = worker.round(steps=64)                    # seconds of one timed round
    worker.close()

A side measured in its own process has its own CPU time: `time.process_time` there counts
its threads (a thread pool's included) and nothing of the other sides', whose idle thread
pools and caches stay in their processes. Natively linked libraries that bundle their
own copy of a library (envpool's MuJoCo) never share a process with ours. The parent
alternates the rounds of the sides (`bench.rounds`), so the processes form one tree and
one run.
"""

from __future__ import annotations

import importlib
import multiprocessing
import time
import traceback
from multiprocessing.connection import Connection
from typing import Any


class WorkerError(RuntimeError):
    """A side raised in its process (the message holds its traceback), or the process
    died (the message names the side and its exit code or signal)."""


def _serve(module_name: str, side: str, connection: Connection) -> None:
    module = importlib.import_module(module_name)
    built = None
    while True:
        kind, *arguments = connection.recv()
        if kind == "stop":
            return
        try:
            if kind == "build":
                built = None  # the previous size's environments go first
                built = module.SIDES[side](*arguments)
                reply: Any = getattr(built, "default_threads", None)
            elif kind == "drop":
                built = reply = None
            elif kind == "round":
                assert built is not None, "build before round"
                built.reset()
                wall, cpu = time.perf_counter(), time.process_time()
                built.run(*arguments)
                reply = (time.perf_counter() - wall, time.process_time() - cpu)
            else:
                reply = module.describe(side)
        except Exception:
            connection.send(("error", traceback.format_exc()))
        else:
            connection.send(("ok", reply))


class Worker:
    """One side of a benchmark in a process of its own (see the module docstring)."""

    def __init__(self, module: str, side: str) -> None:
        """Start the process serving `side` of `module`'s SIDES (the module is imported
        there: it and its `describe(side)` must be importable by name)."""
        context = multiprocessing.get_context("spawn")  # no inherited threads or state
        self._connection, child = context.Pipe()
        self.side = side
        self._process = context.Process(target=_serve, args=(module, side, child), daemon=True)
        self._process.start()
        child.close()

    def _call(self, *message: Any) -> Any:
        try:
            self._connection.send(message)
            status, reply = self._connection.recv()
        except (BrokenPipeError, ConnectionResetError, EOFError):
            self._process.join(timeout=5)
            code = self._process.exitcode
            how = f"killed by signal {-code}" if code is not None and code < 0 else (
                f"exit code {code}")  # fmt: skip
            raise WorkerError(
                f"side {self.side!r}'s process died ({how}) before answering {message[0]!r}"
            ) from None
        if status == "error":
            raise WorkerError(f"side {self.side!r} raised:\n{reply}")
        return reply

    def build(self, num_envs: int, nthread: int, *options: Any) -> Any:
        """Make the side's environments (dropping those of an earlier build): its module's
        `SIDES[side](num_envs, nthread, *options)`. Returns what the built side says its
        default thread count would be (its `default_threads`), or None."""
        return self._call("build", num_envs, nthread, *options)

    def drop(self) -> None:
        """Let go of the side's environments (until the next `build`)."""
        self._call("drop")

    def round(self, steps: int) -> tuple[float, float]:
        """Reset (not timed), then run `steps` steps: (wall seconds, CPU seconds of the
        process, its threads included)."""
        return self._call("round", steps)

    def describe(self) -> str:
        """What the side runs (versions, model), as its module's `describe` says."""
        return self._call("describe")

    def close(self) -> None:
        """Stop the process."""
        if self._process.is_alive():
            self._connection.send(("stop",))
            self._process.join(timeout=30)
        if self._process.is_alive():
            self._process.terminate()
        self._connection.close()
