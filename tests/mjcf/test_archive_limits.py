"""Zip archives from strangers unpack within limits (`mjcf.archives`): a decompression bomb
is refused while it unpacks, before its memory is spent, naming the entry, its sizes and
the limit. The bombs are made here, small on disk."""

from __future__ import annotations

import struct
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import mjcf
from mjcf import archives

MODEL = "<mujoco><asset><hfield name='h' file='h.bin' size='1 1 1 1'/></asset></mujoco>"
MIB = 1 << 20


def bomb(path: Path, megabytes: int, *, model: str = MODEL, name: str = "scene/h.bin") -> Path:
    """A zip holding `model` and an entry `name` of `megabytes` MiB of zeros (deflated a
    thousandfold), written piece by piece."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as archive:
        archive.writestr("scene/model.xml", model)
        with archive.open(name, "w", force_zip64=True) as entry:
            zeros = bytes(MIB)
            for _ in range(megabytes):
                entry.write(zeros)
    return path


def test_an_entry_unpacking_past_the_ratio_limit_is_refused_naming_it(tmp_path):
    path = bomb(tmp_path / "bomb.zip", 64)
    assert path.stat().st_size < 100_000  # 64 MiB of zeros
    compressed = zipfile.ZipFile(path).getinfo("scene/h.bin").compress_size
    with pytest.raises(mjcf.UnpackLimitError) as caught:
        mjcf.from_zip(path)
    assert str(caught.value) == (
        f"zip {path!r}: entry 'scene/h.bin' ({compressed:,} bytes compressed) declares "
        "67,108,864 bytes, over the limit of 100 times its compressed size (past 1,048,576 "
        "bytes); if you trust the archive, raise the limits with limits= or the environment "
        "variables MJCF_UNPACK_LIMIT, MJCF_UNPACK_RATIO"
    )
    assert isinstance(caught.value, mjcf.ParseError)  # what from_zip raised for unsafe zips


def _headers_trusted(monkeypatch) -> None:
    """Skip the check of the sizes a zip's headers declare, as if a crafted header had
    passed it: what is left is the count of bytes unpacked."""
    check = archives.Unpacker._check

    def unpacked_only(self, info, unpacked, where, declared=False):
        if not declared:
            check(self, info, unpacked, where)

    monkeypatch.setattr(archives.Unpacker, "_check", unpacked_only)


def test_the_limits_are_checked_while_unpacking_not_only_in_the_headers(tmp_path, monkeypatch):
    path = bomb(tmp_path / "bomb.zip", 64)
    _headers_trusted(monkeypatch)
    with pytest.raises(mjcf.UnpackLimitError) as caught:
        mjcf.from_zip(path)
    # Stopped at the first piece past 100 times its compressed size.
    compressed = zipfile.ZipFile(path).getinfo("scene/h.bin").compress_size
    unpacked = (100 * compressed // MIB + 1) * MIB
    assert f"({compressed:,} bytes compressed) unpacks to at least {unpacked:,} bytes" in str(
        caught.value
    )


def test_no_more_than_the_declared_size_is_unpacked(tmp_path):
    """A header that declares 1,000 bytes for an entry of 8 MiB: the entry is refused
    after 1,000 bytes as corrupt (zipfile reads what the header declares, then checks)."""
    path = tmp_path / "lying.zip"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("scene/model.xml", MODEL)
        archive.writestr("scene/h.bin", bytes(8 * MIB))
    data = bytearray(path.read_bytes())
    central = data.find(b"PK\x01\x02", data.find(b"PK\x01\x02") + 4)  # the second entry's
    assert data[central + 46 : central + 57] == b"scene/h.bin"
    data[central + 24 : central + 28] = struct.pack("<I", 1000)  # its unpacked size
    path.write_bytes(bytes(data))
    with pytest.raises(mjcf.ParseError, match=r"cannot unpack 'scene/h.bin': Bad CRC-32"):
        mjcf.from_zip(path)


def test_an_archive_past_the_size_limit_is_refused_whatever_its_ratio(tmp_path):
    path = tmp_path / "big.zip"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED) as archive:
        archive.writestr("scene/model.xml", MODEL)
        for i in range(3):
            archive.writestr(f"scene/part{i}.bin", bytes(range(256)) * 4096)  # 1 MiB each
    limits = archives.Limits(size=2 * MIB + 100, ratio=100)
    with pytest.raises(mjcf.UnpackLimitError) as caught:
        mjcf.from_zip(path, limits=limits)
    message = str(caught.value)
    assert (
        "entry 'scene/part2.bin' (1,048,576 bytes compressed) declares 1,048,576 bytes" in message
    )
    assert (
        "over the limit of 2,097,252 bytes unpacked in all, of which earlier entries took"
        in message
    )


def test_limits_are_raised_by_keyword_module_setting_or_environment(tmp_path, monkeypatch):
    path = bomb(tmp_path / "zeros.zip", 3, model=MODEL.replace("h.bin", "h.png"), name="x.bin")
    generous = archives.Limits(size=archives.DEFAULT_SIZE, ratio=1e6)
    assert mjcf.from_zip(path, limits=generous).asset.hfield[0].file.name == "h.png"
    with pytest.raises(mjcf.UnpackLimitError, match="100 times its compressed size"):
        mjcf.from_zip(path)
    monkeypatch.setenv("MJCF_UNPACK_RATIO", "1e6")
    assert mjcf.from_zip(path)
    monkeypatch.setenv("MJCF_UNPACK_LIMIT", "2M")
    with pytest.raises(mjcf.UnpackLimitError, match="2,097,152 bytes unpacked in all"):
        mjcf.from_zip(path)
    monkeypatch.setattr(archives, "LIMITS", generous)  # a program's setting wins
    assert mjcf.from_zip(path)
    monkeypatch.setattr(archives, "LIMITS", None)
    monkeypatch.setenv("MJCF_UNPACK_LIMIT", "lots")
    with pytest.raises(mjcf.UnpackLimitError, match=r"MJCF_UNPACK_LIMIT.*not 'lots'"):
        mjcf.from_zip(path)


@pytest.mark.parametrize(
    ("text", "size"), [("1073741824", 1 << 30), ("1G", 1 << 30), ("500m", 500 << 20),
                       ("1.5GiB", 3 << 29), (" 2 K ", 2048)]
)  # fmt: skip
def test_sizes_are_read_with_their_suffixes(text, size):
    assert archives.parse_size(text) == size


_PEAK = """
import resource, sys, mjcf
from mjcf import archives
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
check = archives.Unpacker._check
archives.Unpacker._check = lambda self, info, n, where, declared=False: (
    None if declared else check(self, info, n, where))  # the count of bytes decides
try:
    mjcf.from_zip(sys.argv[1])
except mjcf.UnpackLimitError as error:
    print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before, error)
"""


def test_refusing_a_bomb_spends_no_more_memory_than_the_limit(tmp_path):
    """A 128 MiB entry of 130 kB, refused at 100 times that: the process grew by less than
    a third of the entry (a child process, measured by its peak resident size in KiB)."""
    path = bomb(tmp_path / "bomb.zip", 128)
    result = subprocess.run(
        [sys.executable, "-c", _PEAK, str(path)], capture_output=True, text=True, check=True
    )
    grown, message = result.stdout.split(" ", 1)
    assert "over the limit of 100 times its compressed size" in message
    assert int(grown) < 40 * 1024, result.stdout
