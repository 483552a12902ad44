"""Output paths, checked before long work starts so a typo fails in a second, not after
ten minutes of training.

    out = output.directory('runs/Reach')      # created; raises OutputError if not writable
    path = output.file('frame.png')            # that file can be written (its folder created)
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from composer.cli.errors import OutputError


def directory(path: str | os.PathLike[str]) -> Path:
    """Create `path` (and its parents) if needed and check a file can be written in it."""
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=path):
            pass
    except OSError as e:
        raise OutputError(f"cannot write to output directory {path}: {_reason(e)}") from e
    return path


def file(path: str | os.PathLike[str]) -> Path:
    """Check that the file `path` can be written, by opening it for writing (its folder is
    created if needed; a file that was not there is removed again, one that was is left
    unchanged). Raises OutputError naming the file and the reason."""
    path = Path(path)
    if path.is_dir():
        raise OutputError(f"cannot write {path}: it is a directory")
    existed = path.exists()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with path.open("ab"):
            pass
    except OSError as e:
        raise OutputError(f"cannot write {path}: {_reason(e)}") from e
    if not existed:
        path.unlink()
    return path


def _reason(error: OSError) -> str:
    return error.strerror or str(error)
