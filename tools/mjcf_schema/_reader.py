"""MuJoCo's XML reader in a child process, for the probes of the schema generator.

MuJoCo 4.0.0's Python bindings do not recover from some documents: when
``MjSpec.from_string`` fails with ``RuntimeError('Caught an unknown exception!')``
(``<model>`` without ``file``, ``<connect body1="b" anchor=""/>``), the next
document that makes MuJoCo warn (``<attach prefix="" .../>``) spins forever in
the bindings' warning handler. A reader that has failed that way is not trusted
again: it is replaced by a fresh interpreter (not a fork, which would inherit
whatever state its parent is in; the child runs only ``_CHILD``, so it needs
nothing but mujoco). A document the reader takes more than ``READ_SECONDS``
over, or dies on, raises ReaderError instead of ending or stalling the generator.
"""

from __future__ import annotations

import pickle
import select
import subprocess
import sys
import weakref

# Far more than any probe takes (milliseconds; seconds for the largest grids).
READ_SECONDS = 60.0

# Answers (error, written, trusted) to each (document, write_back) on stdin.
_CHILD = """
import os, pickle, sys
import mujoco
answers = os.fdopen(os.dup(1), "wb")
os.dup2(2, 1)  # whatever MuJoCo prints goes to stderr, not into the answers
mujoco.set_mju_user_warning(lambda message: None)  # no MUJOCO_LOG.TXT, no noise
files = pickle.load(sys.stdin.buffer)
pickle.dump("ready", answers)  # reading time is counted from here, not from the start
answers.flush()
while True:
    try:
        document, write_back = pickle.load(sys.stdin.buffer)
    except EOFError:
        break
    try:
        spec = mujoco.MjSpec.from_string(document, include=files)
        answer = (None, spec.to_xml() if write_back else None, True)
    except ValueError as error:  # the reader's own errors
        answer = (str(error), None, True)
    except Exception as error:  # the bindings lost track: see _reader's docstring
        answer = (str(error), None, False)
    pickle.dump(answer, answers)
    answers.flush()
    if not answer[2]:
        break
"""


class ReaderError(RuntimeError):
    """MuJoCo's reader died or ran out of time on a document."""


class Reader:
    """Reads documents with ``MjSpec.from_string`` in a child process, one at a time.

    ``files`` are the files documents may name (``include=`` of ``from_string``).
    """

    def __init__(self, files: dict[str, bytes], seconds: float = READ_SECONDS) -> None:
        self._files = files
        self._seconds = seconds
        self._process: subprocess.Popen[bytes] | None = None
        self._stop: weakref.finalize | None = None

    def read(
        self, document: str, write_back: bool = False, seconds: float | None = None
    ) -> tuple[str | None, str | None]:
        """(error, written): MuJoCo's error for ``document`` (None if it reads it) and,
        when ``write_back``, the MJCF MuJoCo writes back (None if it cannot).

        Raises ReaderError if the reader dies or takes more than ``seconds`` (by
        default the reader's).
        """
        process = self._process or self._start()
        assert process.stdin is not None and process.stdout is not None
        limit = self._seconds if seconds is None else seconds
        try:
            pickle.dump((document, write_back), process.stdin)
            process.stdin.flush()
            if not select.select([process.stdout], [], [], limit)[0]:
                self.close()
                raise ReaderError(f"MuJoCo took over {limit:g} s to read:\n{document}")
            error, written, trusted = pickle.load(process.stdout)
        except (OSError, EOFError, pickle.UnpicklingError):
            self.close()
            raise ReaderError(f"MuJoCo's reader died reading:\n{document}") from None
        if not trusted:
            self.close()
        return error, written

    def close(self) -> None:
        """End the child process; the next read starts a new one."""
        if self._stop is not None:
            self._stop()
        self._process = self._stop = None

    def _start(self) -> subprocess.Popen[bytes]:
        process = subprocess.Popen(
            [sys.executable, "-c", _CHILD], stdin=subprocess.PIPE, stdout=subprocess.PIPE
        )
        assert process.stdin is not None and process.stdout is not None
        self._process = process
        self._stop = weakref.finalize(self, _end, process)
        pickle.dump(self._files, process.stdin)
        process.stdin.flush()
        # Starting (importing mujoco) may take seconds on a loaded machine: not counted
        # against a document, but bounded.
        if not select.select([process.stdout], [], [], READ_SECONDS)[0]:
            self.close()
            raise ReaderError(f"MuJoCo's reader did not start in {READ_SECONDS:g} s")
        try:
            ready = pickle.load(process.stdout)
        except (OSError, EOFError, pickle.UnpicklingError):
            ready = None
        if ready != "ready":
            self.close()
            raise ReaderError("MuJoCo's reader died starting")
        return process


def _end(process: subprocess.Popen[bytes]) -> None:
    assert process.stdin is not None and process.stdout is not None
    try:
        process.stdin.close()  # a child waiting for a document ends on its own
        process.wait(1)
    except (OSError, subprocess.TimeoutExpired):
        process.kill()
        process.wait()
    process.stdout.close()
