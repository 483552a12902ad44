"""Unpacking zip archives from strangers within limits: no decompression bomb.

    unpacker = archives.Unpacker()                   # the limits in force: current_limits()
    with zipfile.ZipFile(path) as archive:
        xml = unpacker.read(archive, 'scene/model.xml', where=path)   # bytes
    mjcf.from_zip('scene.zip', limits=archives.Limits(size=4 << 30, ratio=100))

Every entry is unpacked in pieces, counting the bytes as they come, and refused with
mjcf.UnpackLimitError (naming the archive, the entry, its sizes and the limit) as soon as it
passes `size` or `ratio` (see `Limits`), before more memory is spent.
"""

from __future__ import annotations

import os
import re
import struct
import zipfile
import zlib
from typing import IO, NamedTuple

from mjcf import errors
from mjcf.io import _limits

# A zip of a few megabytes can unpack to gigabytes: deflate packs a run of zeros a
# thousandfold, and an archive may hold many such entries. Model files, meshes and network
# weights pack far less (docs/performance_profile.md, section 8), so a ratio of 100 passes
# them and stops bombs.
DEFAULT_SIZE = 1 << 30
DEFAULT_RATIO = 100.0
# Bytes of one entry that may unpack at any ratio: a small file of zeros is no bomb.
RATIO_FREE_BYTES = 1 << 20
SIZE_VARIABLE = "MJCF_UNPACK_LIMIT"
RATIO_VARIABLE = "MJCF_UNPACK_RATIO"
_PIECE = 1 << 20  # bytes unpacked at once
# What Python's zipfile raises for a corrupt or crafted archive, besides its BadZipFile:
# its parser seeks, unpacks and decodes what the headers say (found by fuzzing:
# tests/mjcf/test_hostile_input.py).
CORRUPT = (zipfile.BadZipFile, OSError, EOFError, ValueError, struct.error, OverflowError,
           NotImplementedError, RuntimeError, zlib.error)  # fmt: skip
_SUFFIXES = {"": 1, "K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40}
_SIZE = re.compile(r"\s*(\d+(?:\.\d*)?)\s*([KMGT]?)(?:I?B)?\s*", re.IGNORECASE)


class Limits(NamedTuple):
    """How much untrusted archives may unpack: `size` bytes in all the entries one
    `Unpacker` reads (default 1 GiB), `ratio` unpacked bytes per compressed byte of one
    entry (default 100), counted only past the entry's first `RATIO_FREE_BYTES` (1 MiB),
    which any ratio may reach. The limits in force are `current_limits()`."""

    size: int = DEFAULT_SIZE
    ratio: float = DEFAULT_RATIO


# The limits a program sets for every archive it reads; None: the environment's.
LIMITS: Limits | None = None


def parse_size(text: str) -> int:
    """A number of bytes written as '1073741824', '1G', '500M', '1.5GiB'; raises
    mjcf.UnpackLimitError (a ValueError) for anything else."""
    match = _SIZE.fullmatch(text)
    if match is None:
        raise errors.UnpackLimitError(
            f"a size is a number of bytes, with K, M, G or T after it if you like ('2G'), "
            f"not {text!r}"
        )
    return int(float(match.group(1)) * _SUFFIXES[match.group(2).upper()])


def parse_ratio(text: str) -> float:
    """A ratio limit written as a number of at least 1; raises mjcf.UnpackLimitError."""
    try:
        ratio = float(text)
    except ValueError:
        ratio = float("nan")
    if not ratio >= 1:
        raise errors.UnpackLimitError(f"a ratio limit is a number of at least 1, not {text!r}")
    return ratio


def current_limits() -> Limits:
    """The limits in force: `LIMITS` if a program set it, else the environment variables'
    (`MJCF_UNPACK_LIMIT` in bytes, or with a suffix: '2G', '500M'; `MJCF_UNPACK_RATIO`) over
    the defaults. Raises mjcf.UnpackLimitError for a variable that is not a size or ratio."""
    try:
        return _limits.in_force(
            LIMITS,
            Limits,
            {
                SIZE_VARIABLE: (parse_size, DEFAULT_SIZE),
                RATIO_VARIABLE: (parse_ratio, DEFAULT_RATIO),
            },
        )
    except errors.UnpackLimitError as error:
        raise errors.UnpackLimitError(
            f"environment variable {SIZE_VARIABLE} or {RATIO_VARIABLE}: {error}"
        ) from None


def open_archive(source: str | os.PathLike | IO[bytes], where: object) -> zipfile.ZipFile:
    """The zip archive `source` (a path or a binary file); raises mjcf.ParseError naming
    `where` for one that cannot be read as a zip."""
    try:
        return zipfile.ZipFile(source)
    except CORRUPT as error:
        raise errors.ParseError(f"cannot read {where}: {error}") from None


class Unpacker:
    """Reads entries of zip archives within `limits` (default: `current_limits()`),
    counting every byte unpacked: one Unpacker for each untrusted input, whose entries,
    and the entries of archives inside them, share its `size`. `raise_with` names how a
    user raises the limits, for the message. `mjcf.from_zip` reads through one, and so does
    composer's policy reader (`--unpack-limit`, `--unpack-ratio`)."""

    def __init__(
        self,
        limits: Limits | None = None,
        raise_with: str = f"limits= or the environment variables {SIZE_VARIABLE}, {RATIO_VARIABLE}",
    ) -> None:
        self.limits = current_limits() if limits is None else limits
        self.raise_with = raise_with
        self.unpacked = 0  # bytes read so far, all entries together

    def read(self, archive: zipfile.ZipFile, entry: str | zipfile.ZipInfo, where: object) -> bytes:
        """The unpacked bytes of `entry` in `archive` (`where`: the archive's name, for
        messages). Raises mjcf.UnpackLimitError past a limit, KeyError for an entry that
        is not there, mjcf.ParseError for one that cannot be unpacked."""
        info = entry if isinstance(entry, zipfile.ZipInfo) else archive.getinfo(entry)
        # The size the header declares is checked first, and not trusted after: the count
        # of bytes actually unpacked decides.
        self._check(info, info.file_size, where, declared=True)
        pieces = []
        unpacked = 0
        try:
            with archive.open(info) as stream:
                while True:
                    piece = stream.read(_PIECE)
                    if not piece:
                        break
                    unpacked += len(piece)
                    self._check(info, unpacked, where)
                    pieces.append(piece)
        except errors.UnpackLimitError:
            raise
        except CORRUPT as error:
            raise errors.ParseError(f"{where}: cannot unpack {info.filename!r}: {error}") from None
        self.unpacked += unpacked
        return b"".join(pieces)

    def _check(
        self, info: zipfile.ZipInfo, unpacked: int, where: object, declared: bool = False
    ) -> None:
        """Raise UnpackLimitError if `unpacked` bytes of `info` (those its header
        declares, if `declared`) pass a limit."""
        size, ratio = self.limits
        packed = max(info.compress_size, 1)
        if self.unpacked + unpacked > size:
            limit = f"{size:,} bytes unpacked in all"
            if self.unpacked:
                limit += f", of which earlier entries took {self.unpacked:,}"
        elif unpacked > RATIO_FREE_BYTES and unpacked > ratio * packed:
            limit = f"{ratio:g} times its compressed size (past {RATIO_FREE_BYTES:,} bytes)"
        else:
            return
        amount = "declares" if declared else "unpacks to at least"
        raise errors.UnpackLimitError(
            f"{where}: entry {info.filename!r} ({info.compress_size:,} bytes compressed) "
            f"{amount} {unpacked:,} bytes, over the limit of {limit}; if you trust the "
            f"archive, raise the limits with {self.raise_with}"
        )
