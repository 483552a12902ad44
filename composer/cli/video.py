"""Frames to files: PNG images (standard library only) and videos (imageio).

    video.write_png(env.render(), video.png_target('frame.png'))   # OutputError: not .png
    path = video.target('out.mp4')            # 'out.gif' when no ffmpeg; OutputError: '.avi'
    written = video.write_video(frames, 'out.mp4', fps=30)   # writes that path

MP4 needs ffmpeg, which `imageio-ffmpeg` ships; when it cannot be found the video is
written as a GIF next to the requested path and the returned path says so. Videos need
`imageio` (in the `[train]`, `[ray]` and `[video]` extras); PNG images need nothing beyond
numpy.
"""

from __future__ import annotations

import os
import struct
import zlib
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from composer.cli.errors import MissingExtraError, OutputError

# What `write_video` writes: MP4 (with ffmpeg), GIF.
VIDEO_FORMATS = (".mp4", ".gif")
VIDEO_INSTALL = "pip install -e '.[video]'  (or: pip install imageio imageio-ffmpeg)"


def png_target(path: str | os.PathLike[str]) -> Path:
    """`path`, checked to name a .png file (what `write_png` writes); raises OutputError."""
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise OutputError(
            f"cannot write {path}: a frame is written as .png, "
            f"not {path.suffix or 'a file without an extension'}"
        )
    return path


def write_png(frame: np.ndarray, path: str | os.PathLike[str]) -> Path:
    """Write an (h, w, 3) uint8 RGB frame as a PNG; raises OutputError if it cannot."""
    frame = np.ascontiguousarray(frame, dtype=np.uint8)
    height, width, _ = frame.shape
    rows = np.concatenate([np.zeros((height, 1), np.uint8), frame.reshape(height, -1)], axis=1)

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)  # 8-bit RGB
    data = b"".join([
        b"\x89PNG\r\n\x1a\n",
        chunk(b"IHDR", header),
        chunk(b"IDAT", zlib.compress(rows.tobytes(), 6)),
        chunk(b"IEND", b""),
    ])  # fmt: skip
    path = Path(path)
    try:
        path.write_bytes(data)
    except OSError as e:
        raise OutputError(f"cannot write {path}: {e.strerror or e}") from e
    return path


def ffmpeg_available() -> bool:
    """Whether imageio can find an ffmpeg executable for MP4."""
    try:
        import imageio_ffmpeg
    except ImportError:
        return False
    try:
        exe = imageio_ffmpeg.get_ffmpeg_exe()
    except RuntimeError:
        return False
    return os.path.isfile(exe) and os.access(exe, os.X_OK)


def target(path: str | os.PathLike[str]) -> Path:
    """The file `write_video` writes for `path`: itself, or a .gif beside it (a GIF asked
    for, or no ffmpeg for an MP4). Raises OutputError for a path that names neither."""
    path = Path(path)
    if path.suffix.lower() not in VIDEO_FORMATS:
        raise OutputError(
            f"cannot write {path}: a video is written as {' or '.join(VIDEO_FORMATS)}, "
            f"not {path.suffix or 'a file without an extension'}"
        )
    if path.suffix.lower() != ".gif" and ffmpeg_available():
        return path
    return path.with_suffix(".gif")


def write_video(frames: Sequence[np.ndarray], path: str | os.PathLike[str], fps: float) -> Path:
    """Write `frames` at `fps` frames a second to `path` (.mp4, or .gif); an MP4 becomes a
    GIF beside it when ffmpeg is missing. Returns the path written. Raises MissingExtraError
    without imageio, OutputError when the file cannot be written."""
    try:
        import imageio.v3 as iio
    except ImportError as e:
        raise MissingExtraError(f"writing a video needs imageio: {VIDEO_INSTALL}") from e
    path = target(path)
    stack = np.stack(frames)
    try:
        if path.suffix.lower() != ".gif":
            iio.imwrite(path, stack, plugin="FFMPEG", fps=fps)
        else:
            iio.imwrite(path, stack, plugin="pillow", duration=round(1000 / fps), loop=0)
    except OSError as e:
        raise OutputError(f"cannot write {path}: {e.strerror or e}") from e
    return path


def require() -> None:
    """Raise MissingExtraError now, before long work, if videos cannot be written."""
    try:
        import imageio.v3  # noqa: F401
    except ImportError as e:
        raise MissingExtraError(f"writing a video needs imageio: {VIDEO_INSTALL}") from e
