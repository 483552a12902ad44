"""Debug mode: every element remembers where it was created (a file's elements, their file
and line), and MuJoCo's compile errors name the element and that place.

    mjcf.enable_debug_mode()         # or run with MJCF_DEBUG=1
    model = mjcf.RootElement()
    model.worldbody.add('geom', type='box')          # size missing
    mjcf.Physics.from_mjcf_model(model)
    # mjcf.CompileError: ... <worldbody>/<geom> (created at my_script.py:3) ...

Outside debug mode nothing is recorded, and creating elements costs nothing extra.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from types import FrameType
from typing import NamedTuple

_PACKAGE_DIR = str(Path(__file__).resolve().parents[1])  # mjcf/, all of its layers
_enabled = os.environ.get("MJCF_DEBUG", "").lower() in ("1", "true", "yes", "on")


class SourceLocation(NamedTuple):
    """Where an element was created: a Python file and line, or an XML file and line."""

    filename: str
    line: int

    def __str__(self) -> str:
        return f"{self.filename}:{self.line}"


def enable_debug_mode() -> None:
    """Record the creation site of elements created from now on."""
    global _enabled
    _enabled = True


def disable_debug_mode() -> None:
    """Stop recording creation sites."""
    global _enabled
    _enabled = False


def is_debug_mode() -> bool:
    """Whether creation sites are being recorded."""
    return _enabled


# dm_control's name for it (`mjcf.debugging.debug_mode()`).
debug_mode = is_debug_mode


def creation_site() -> SourceLocation | None:
    """The first stack frame outside this package, in debug mode; else None."""
    if not _enabled:
        return None
    frame: FrameType | None = sys._getframe(1)
    while frame is not None and frame.f_code.co_filename.startswith(_PACKAGE_DIR):
        frame = frame.f_back
    if frame is None:
        return None
    return SourceLocation(frame.f_code.co_filename, frame.f_lineno)


def xml_site(filename: str | None, line: int | None) -> SourceLocation | None:
    """The XML location of a parsed element, in debug mode; else None."""
    if not _enabled or line is None:
        return None
    return SourceLocation(filename or "<string>", line)
