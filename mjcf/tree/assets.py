"""Files a model loads (meshes, textures, height fields, skins ...) as `Asset` objects.

    mesh = model.asset.add('mesh', file=mjcf.Asset(stl_bytes, '.stl', prefix='wheel'))
    model.find('mesh', 'base').file          # Asset: .contents, .extension, .prefix, .path
    assets = {m.file.get_vfs_filename(): m.file.contents for m in model.find_all('mesh')}
    mujoco.MjModel.from_xml_string(model.to_xml_string(), assets)   # Menagerie's recipe

Files, included ones too, are found as MuJoCo finds them (`file_path`) and read on first use, if
regular and at most `FILE_SIZE_LIMIT` bytes (else mjcf.AssetError), the latest kept up to
`FILE_CACHE_LIMIT` bytes; `assets={'a.stl': data}` replace disk files. Each has one plain name."""

from __future__ import annotations

import copy
import hashlib
import os
import threading
from stat import S_ISREG
from typing import IO, TYPE_CHECKING

from mjcf import errors
from mjcf.schema.values import AssetBase
from mjcf.tree import above

if TYPE_CHECKING:
    from mjcf.tree.element import Element

# Which compiler directory a file attribute is read from, by element tag.
_DIRECTORY = {"mesh": "meshdir", "skin": "meshdir", "hfield": "meshdir", "flexcomp": "meshdir",
              "texture": "texturedir"}  # fmt: skip
# Files that load further files relative to themselves: always referred to by path.
BY_PATH = frozenset({"model"})
# Attributes of a mesh that MuJoCo's mesh cache (keyed by file name) does not compare:
# a mesh compiled again with other values of them would take the cached data in their
# place, and so would a compile after it with none. Compiling gives such a mesh its file
# under a name of its own values (tests/mjcf/test_mesh_cache.py checks the list).
NOT_IN_MESH_CACHE_KEY = frozenset({"vertex", "normal", "texcoord", "face"})
# Files read, by path: (mtime, size, contents), least recently read first, up to
# FILE_CACHE_LIMIT bytes in all (a process that reads thousands of mesh files, one
# model's after another, keeps the latest, not all); the oldest are read again if needed.
FILE_CACHE_LIMIT = 256 << 20
_file_cache: dict[str, tuple[int, int, bytes]] = {}
_file_cache_bytes = 0
_file_cache_lock = threading.Lock()
# The most bytes mjcf reads of one model file or asset, or lets MuJoCo read: a larger
# file is refused (mjcf.AssetError) rather than read until memory runs out. Raise it for
# larger textures or height fields.
FILE_SIZE_LIMIT = 1 << 30
_READ_PIECE = 1 << 24  # bytes read at once from a file that grew while read


class Asset(AssetBase):
    """A file's contents with its extension ('.stl') and name stem (`prefix`); `path`
    is where it was read from, if it came from disk (contents are then read lazily).
    The element it was first given to (its owner, see `claim`) tells in which output
    `get_vfs_filename` names it."""

    __slots__ = ("_contents", "_owner", "extension", "path", "prefix")

    def __init__(
        self, contents: bytes | None, extension: str, prefix: str = "", path: str | None = None
    ) -> None:
        if contents is None and path is None:
            raise errors.AssetError("an Asset needs contents or a path")
        if contents is not None and not isinstance(contents, bytes | bytearray):
            raise errors.AssetError(f"Asset contents must be bytes, got {type(contents).__name__}")
        if extension and not extension.startswith("."):
            extension = "." + extension
        self._contents = None if contents is None else bytes(contents)
        self.extension = extension
        self.prefix = prefix
        self.path = path
        self._owner: Element | None = None

    @property
    def contents(self) -> bytes:
        """The file's bytes; raises mjcf.AssetError if its file cannot be read."""
        if self._contents is None:
            assert self.path is not None, "an Asset has contents or a path"
            return _read(self.path)
        return self._contents

    @property
    def name(self) -> str:
        """The file name this asset is known by ('prefix.ext')."""
        return self.prefix + self.extension

    def get_vfs_filename(self, filename_with_hash: bool = False) -> str:
        """The file name this asset is written under, as `to_xml_string()`, the keys of
        `get_assets()` and the exports of the outermost model its element is attached into
        name it: its own base name, changed only where two different files would share one
        (MuJoCo's asset dict knows files by base name, ignoring case), by the attached
        model's scope and then a number; a file without a name of its own
        (`mjcf.Asset(contents, '.png')`) is named by its contents' hash, as dm_control names
        it. With `filename_with_hash`, dm_control's name '<prefix>-<sha1 of contents><ext>',
        as `to_xml_string(filename_with_hash=True)` writes it. Raises mjcf.AssetError if its
        file cannot be read."""
        if filename_with_hash:
            return hashed_file_name(self)
        owner = self._owner
        if owner is not None and not owner.is_removed:
            written = above.file_name_of(owner.root.namescope.root.model, self)
            if written is not None:
                return written
        return default_file_name(self)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Asset):
            return NotImplemented
        if self.path is not None and self.path == other.path:
            return True
        return self.extension == other.extension and self.contents == other.contents

    def __hash__(self) -> int:
        return hash(self.extension)

    def __repr__(self) -> str:
        where = f"path={self.path!r}" if self.path else f"{len(self._contents or b'')} bytes"
        return f"Asset({self.name!r}, {where})"


def _read(path: str) -> bytes:
    global _file_cache_bytes
    stat = check_file(path)
    with _file_cache_lock:
        cached = _file_cache.pop(path, None)
        if cached is not None:
            if cached[0] == stat.st_mtime_ns and cached[1] == stat.st_size:
                _file_cache[path] = cached  # now the latest read
                return cached[2]
            _file_cache_bytes -= len(cached[2])
    data = read_file(path)
    with _file_cache_lock:
        if path not in _file_cache and len(data) <= FILE_CACHE_LIMIT:
            while _file_cache and _file_cache_bytes + len(data) > FILE_CACHE_LIMIT:
                _file_cache_bytes -= len(_file_cache.pop(next(iter(_file_cache)))[2])
            _file_cache[path] = (stat.st_mtime_ns, stat.st_size, data)
            _file_cache_bytes += len(data)
    return data


def check_file(path: str) -> os.stat_result:
    """The status of file `path`, which MuJoCo may read whole; raises mjcf.AssetError
    for a file that cannot be read, is not a regular file (a device such as /dev/zero, a
    FIFO, which would never end or block) or holds more than `FILE_SIZE_LIMIT` bytes."""
    try:
        stat = os.stat(path)
    except OSError as error:
        raise errors.AssetError(f"cannot read file {path!r}: {error.strerror}") from None
    _check_stat(path, stat)
    return stat


def read_file(path: str) -> bytes:
    """The contents of file `path`, read at most to `FILE_SIZE_LIMIT` bytes; raises
    mjcf.AssetError as `check_file` does (a FIFO is opened without waiting for a writer,
    then refused)."""
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as error:
        raise errors.AssetError(f"cannot read file {path!r}: {error.strerror}") from None
    # Read with the descriptor alone: a file object around it (os.fdopen) costs as
    # much as reading a model file of 10 kB does.
    try:
        stat = os.fstat(descriptor)
        _check_stat(path, stat)
        # Its size and a byte (a read of the limit would allocate that much first);
        # the rest, still bounded, only if it grew meanwhile.
        data = _read_at_most(descriptor, stat.st_size + 1, path)
        if len(data) > stat.st_size:
            data += _read_at_most(descriptor, FILE_SIZE_LIMIT + 1 - len(data), path)
    finally:
        os.close(descriptor)
    if len(data) > FILE_SIZE_LIMIT:
        raise errors.AssetError(_too_large(path))
    return data


def _read_at_most(descriptor: int, count: int, path: str) -> bytes:
    """At most `count` bytes from `descriptor`, to its end; in pieces of at most
    `_READ_PIECE` bytes past the first; raises mjcf.AssetError if reading fails."""
    pieces: list[bytes] = []
    try:
        while count > 0:
            piece = os.read(descriptor, count if not pieces else min(count, _READ_PIECE))
            if not piece:
                break
            pieces.append(piece)
            count -= len(piece)
    except OSError as error:
        raise errors.AssetError(f"cannot read file {path!r}: {error.strerror}") from None
    return pieces[0] if len(pieces) == 1 else b"".join(pieces)


def read_limited(handle: IO, name: object) -> bytes | str:
    """Everything an open file `handle` gives, at most `FILE_SIZE_LIMIT` bytes (or
    characters); raises mjcf.AssetError for more."""
    try:
        data = handle.read(FILE_SIZE_LIMIT + 1)
    except (OSError, ValueError) as error:  # ValueError: a closed file
        raise errors.AssetError(f"cannot read {name!r}: {error}") from None
    if len(data) > FILE_SIZE_LIMIT:
        raise errors.AssetError(_too_large(name))
    return data


def _check_stat(path: str, stat: os.stat_result) -> None:
    if not S_ISREG(stat.st_mode):
        raise errors.AssetError(
            f"{path!r} is not a regular file (a device, FIFO or socket would be read forever "
            "or block): models and their assets are read from regular files"
        )
    if stat.st_size > FILE_SIZE_LIMIT:
        raise errors.AssetError(_too_large(path))


def _too_large(name: object) -> str:
    return (
        f"{name!r} holds more than {FILE_SIZE_LIMIT} bytes, the limit of a model file or "
        "asset (mjcf.tree.assets.FILE_SIZE_LIMIT, which may be raised)"
    )


def resolve(element: Element, attribute: str, value: object) -> Asset:
    """The `Asset` a file attribute value stands for, found as MuJoCo would find it
    (a name in the model's `assets` dict wins over a file on disk), owned by `element`
    unless another element owns it already (see `claim`)."""
    if isinstance(value, Asset):
        return claim(value, element)
    text = str(value)
    model = element.root
    stem, extension = os.path.splitext(os.path.basename(text))
    for key in (text, os.path.basename(text)):
        data = model.assets.get(key)
        if data is not None:
            return claim(Asset(data, extension, stem), element)
    return claim(Asset(None, extension, stem, path=file_path(element, text)), element)


def claim(asset: Asset, element: Element) -> Asset:
    """`asset`, owned by `element` if no element owns it yet: the first element given an
    asset decides in which model's output `get_vfs_filename` names it."""
    if asset._owner is None:
        asset._owner = element
    return asset


def owned_copy(asset: Asset, element: Element) -> Asset:
    """A copy of `asset` (sharing its contents and path) owned by `element`: the asset
    of a copied model's element."""
    duplicate = copy.copy(asset)
    duplicate._owner = element
    return duplicate


def file_path(element: Element, text: str) -> str:
    """Where MuJoCo looks for file `text` of `element` (strippath, meshdir/texturedir/
    assetdir, relative to the model's directory); raises mjcf.AssetError for a model
    without a directory."""
    compiler = element.root.compiler
    if compiler.strippath == "true":
        text = os.path.basename(text)
    directory_setting = _DIRECTORY.get(element.tag)
    directory = ""
    if directory_setting is not None:
        directory = getattr(compiler, directory_setting) or compiler.assetdir or ""
    if os.path.isabs(text):
        path = text
    elif directory and os.path.isabs(directory):
        path = os.path.join(directory, text)
    else:
        base = element.root.model_dir or os.getcwd()
        path = os.path.normpath(os.path.join(base, directory, text))
    confine = element.root._confine_to
    if confine is not None and not is_inside(os.path.realpath(path), confine):
        raise errors.AssetError(
            f"{element.path}: file {text!r} is outside the model's folder {confine!r}, which "
            "strict_paths forbids"
        )
    return path


def plain_file_name(name: str) -> str:
    """`name` reduced to a plain file name: no directories, no leading dots ('..',
    hidden files), so that it can only ever name a file inside the folder it is
    written to."""
    if "/" in name or "\\" in name or name.startswith("."):
        name = name.replace("\\", "/").rsplit("/", 1)[-1].lstrip(".")
    return name or "asset"


def default_file_name(asset: Asset) -> str:
    """The name `asset` is written under where no other file takes it: its plain name
    ('pad.stl'), or for an asset without a name of its own (no prefix) dm_control's
    '<sha1 of contents><ext>'. Raises mjcf.AssetError if a file to hash cannot be read."""
    if not asset.prefix:
        return hashed_file_name(asset)
    return plain_file_name(asset.name)


def hashed_file_name(asset: Asset) -> str:
    """dm_control's name for `asset`: '<prefix>-<sha1 of contents><extension>', or
    '<sha1><extension>' without a prefix. Raises mjcf.AssetError if its file cannot be
    read."""
    digest = hashlib.sha1(asset.contents).hexdigest()
    stem = plain_file_name(asset.prefix) + "-" if asset.prefix else ""
    return plain_file_name(stem + digest + asset.extension)


def is_inside(path: str, folder: str) -> bool:
    """Whether real path `path` is `folder` or inside it."""
    return path == folder or path.startswith(folder.rstrip(os.sep) + os.sep)
