"""Files a model loads (meshes, textures, height fields, skins ...) as `Asset` objects.

    mesh = model.asset.add('mesh', file=mjcf.Asset(stl_bytes, '.stl', prefix='wheel'))
    model.find('mesh', 'base').file          # Asset: .contents, .extension, .prefix, .path
    xml, assets = model.to_xml_string(), model.get_assets()
    mujoco.MjModel.from_xml_string(xml, assets)   # the same file names in both

A file attribute read from a model file becomes an `Asset` that knows its path (the
way MuJoCo finds it: `compiler strippath/meshdir/texturedir/assetdir`, relative to the
model's directory) and reads its contents on first use. Files are read only when they
are regular files of at most `FILE_SIZE_LIMIT` bytes (1 GiB; raise it for larger
assets), model files and included files too: a device such as /dev/zero or a FIFO is
refused, not read until memory runs out. Files given as
`assets={'name.stl': bytes}` are used instead of disk files of that name, as MuJoCo
uses them.

When a model is written, every file gets a plain, readable name: its own base name,
changed only where two different files would share one (MuJoCo's asset dict knows
files by base name, ignoring case), by the attached model's scope and then a number;
a file without a name of its own (`mjcf.Asset(contents, '.png')`) is named by its
contents' hash, as dm_control names it. Every name a user can get for a file is that
one: `asset.get_vfs_filename()` (in the output of the outermost model its element is
attached into), the keys of `get_assets()`, the XML of `to_xml_string()` and the files
of the exports, so that MuJoCo Menagerie's recipe works:

    assets = {m.file.get_vfs_filename(): m.file.contents for m in model.find_all('mesh')}
    mujoco.MjModel.from_xml_string(model.to_xml_string(), assets)

dm_control's content-hash names are there on request (`filename_with_hash=True`).
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import os
from collections.abc import Iterable
from stat import S_ISREG
from typing import IO, TYPE_CHECKING

from mjcf import errors, upcalls

if TYPE_CHECKING:
    from mjcf.element import Element
    from mjcf.root import RootElement

# Which compiler directory a file attribute is read from, by element tag.
_DIRECTORY = {"mesh": "meshdir", "skin": "meshdir", "hfield": "meshdir", "flexcomp": "meshdir",
              "texture": "texturedir"}  # fmt: skip
# Files that load further files relative to themselves: always referred to by path.
_BY_PATH = frozenset({"model"})
# Attributes of a mesh that MuJoCo's mesh cache (keyed by file name) does not compare:
# a mesh compiled again with other values of them would take the cached data in their
# place, and so would a compile after it with none. Compiling gives such a mesh its file
# under a name of its own values (tests/mjcf/test_mesh_cache.py checks the list).
NOT_IN_MESH_CACHE_KEY = frozenset({"vertex", "normal", "texcoord", "face"})
_file_cache: dict[str, tuple[int, int, bytes]] = {}
# The most bytes mjcf reads of one model file or asset, or lets MuJoCo read: a larger
# file is refused (mjcf.AssetError) rather than read until memory runs out. Raise it for
# larger textures or height fields.
FILE_SIZE_LIMIT = 1 << 30
_READ_PIECE = 1 << 24  # bytes read at once from a file that grew while read


class Asset:
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
        """The file name this asset is written under, as `to_xml_string()` and
        `get_assets()` of the outermost model its element is attached into name it
        (see the module docstring): its plain name unless another file of that name is
        written first. With `filename_with_hash`, dm_control's name
        '<prefix>-<sha1 of contents><ext>', as `to_xml_string(filename_with_hash=True)`
        writes it. Raises mjcf.AssetError if its file cannot be read."""
        if filename_with_hash:
            return hashed_file_name(self)
        owner = self._owner
        if owner is not None and not owner.is_removed:
            written = upcalls.ABOVE.file_name_of(owner.root.namescope.root.model, self)
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
    stat = check_file(path)
    cached = _file_cache.get(path)
    if cached is not None and cached[0] == stat.st_mtime_ns and cached[1] == stat.st_size:
        return cached[2]
    data = read_file(path)
    _file_cache[path] = (stat.st_mtime_ns, stat.st_size, data)
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
        "asset (mjcf.assets.FILE_SIZE_LIMIT, which may be raised)"
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


def _cached_apart(element: Element) -> bool:
    """Whether `element` is a mesh from a file that sets values MuJoCo's mesh cache does
    not compare (see `NOT_IN_MESH_CACHE_KEY`)."""
    return element.tag == "mesh" and not NOT_IN_MESH_CACHE_KEY.isdisjoint(element._attrs)


def _asset_key(name: str) -> str:
    """The key under which MuJoCo's asset dict and file lookup know file `name`: its
    base name in lower case ('x/Part.stl' and 'part.stl' are one file to MuJoCo, even
    when one of them is an absolute path on disk)."""
    return name.replace("\\", "/").rsplit("/", 1)[-1].lower()


class FileNamer:
    """Names the files of one output document, and collects the contents of those that
    go to MuJoCo as assets.

    Each file is named by its plain base name ('pad.stl'), unique as MuJoCo's asset dict
    needs it (by base name, ignoring case). Where different contents would share a name,
    the later file gets the attached model's scope ('gripper-pad.stl'), then a number
    ('pad-2.stl'), in the order the document is written; identical contents share one
    name. `hashed` names files as dm_control does (`hashed_file_name`). `by_path`
    (compiling): files on disk are written as absolute paths that MuJoCo reads itself
    (and caches); their base names are reserved all the same, since MuJoCo would take an
    asset of that name in their place."""

    def __init__(self, root: RootElement, by_path: bool = False, hashed: bool = False) -> None:
        self.root = root
        self.by_path = by_path
        self.hashed = hashed
        self._by_key: dict[str, tuple[str, Asset]] = {}  # asset key -> (name, asset)
        self._named: dict[str, Asset] = {}  # names whose contents go to MuJoCo
        self._users: dict[str, tuple[Element, str]] = {}  # who first named each file
        self._by_asset: dict[int, tuple[Asset, str]] = {}  # id(asset) -> (asset, its name)
        # Elements whose `file` is written under another stem: an unnamed mesh, texture
        # ... would get another name from MuJoCo, so the writer names it explicitly.
        self.renamed: set[Element] = set()

    def name_for(self, element: Element, attribute: str, value: object) -> str:
        """The file name written for one file attribute value; raises mjcf.AssetError
        naming the element if its file cannot be read."""
        asset = resolve(element, attribute, value)
        try:
            if self.by_path and _cached_apart(element):
                return self._cache_name(element, asset)
            if asset.path is not None and (self.by_path or element.tag in _BY_PATH):
                if self.by_path:  # MuJoCo reads it: as mjcf would
                    check_file(asset.path)
                    if not os.access(asset.path, os.R_OK):
                        raise errors.AssetError(f"cannot read asset file {asset.path!r}")
                name = self._take(asset.path, asset, collect=False)
                if name is not None:
                    return name
            own = asset.prefix + asset.extension
            # The common case first: the first file of its name keeps it.
            name = None if self.hashed else self._take(default_file_name(asset), asset)
            if name is None:
                name = self._unique_name(element, asset)
        except errors.AssetError as error:
            raise errors.AssetError(f"{element.path}: {attribute!r}: {error}") from None
        self._users.setdefault(name, (element, attribute))
        self._by_asset[id(asset)] = (asset, name)
        renamed = name != own and attribute == "file"
        if renamed and os.path.splitext(os.path.basename(name))[0] != asset.prefix:
            self.renamed.add(element)
        return name

    def _cache_name(self, element: Element, asset: Asset) -> str:
        """A name for the file of mesh `element` (compiled with values that MuJoCo's
        mesh cache does not compare) made of those values, its file's path and
        contents: MuJoCo's cache then holds it apart from the same file compiled with
        other values."""
        digest = hashlib.sha1((asset.path or "").encode())
        digest.update(asset.contents)
        for name in sorted(NOT_IN_MESH_CACHE_KEY.intersection(element._attrs)):
            value = getattr(element, name)
            digest.update(
                name.encode()
                + b"="
                + repr(value.tolist() if hasattr(value, "tolist") else value).encode()
            )
        name = f"{plain_file_name(asset.prefix)}-{digest.hexdigest()[:16]}{asset.extension}"
        taken = self._take(name, asset)
        assert taken is not None, "a digest of the contents names only those contents"
        return taken

    def _take(self, name: str, asset: Asset, collect: bool = True) -> str | None:
        """The name `asset` gets if it asks for `name`: `name` if its key is free (it
        is then taken, and the contents collected if `collect`), the name of identical
        contents that hold the key, else None."""
        # Names passed as assets are plain file names already; paths on disk are not.
        key = name.lower() if collect else _asset_key(name)
        held = self._by_key.get(key)
        if held is None:
            self._by_key[key] = (name, asset)
            if collect:
                self._named[name] = asset
            return name
        holder_name, holder = held
        if holder is asset or holder == asset:
            return holder_name
        return None

    def _unique_name(self, element: Element, asset: Asset) -> str:
        if self.hashed:
            candidates: Iterable[str] = [hashed_file_name(asset)]
        else:
            base = default_file_name(asset)
            stem, extension = os.path.splitext(base)
            scope = element.root.namescope.prefix(self.root.namescope)
            scope = scope.replace("\\", "").replace("/", "-")
            first = [base, f"{scope}{base}"] if scope else [base]
            numbered = (f"{scope}{stem}-{n}{extension}" for n in range(2, 100_000))
            candidates = itertools.chain(first, numbered)
        for candidate in candidates:
            name = self._take(candidate, asset)
            if name is not None:
                return name
        raise errors.AssetError(f"too many different files named {plain_file_name(asset.name)!r}")

    def name_of(self, asset: Asset) -> str | None:
        """The name `asset` was written under in this output: its own, or that of an
        identical file of the same name written in its place (an attached copy's mesh
        that shares the first copy's, see `mjcf.sharing`); None if neither was written."""
        found = self._by_asset.get(id(asset))
        if found is not None and found[0] is asset:
            return found[1]
        for written, name in self._by_asset.values():
            if written.name == asset.name and written == asset:
                return name
        return None

    def contents(self) -> dict[str, bytes]:
        """`{file name: bytes}` of every asset named so far; raises mjcf.AssetError
        naming the element whose file cannot be read."""
        out = {}
        for name, asset in self._named.items():
            try:
                out[name] = asset.contents
            except errors.AssetError as error:
                user = self._users.get(name)
                if user is None:
                    raise
                raise errors.AssetError(f"{user[0].path}: {user[1]!r}: {error}") from None
        return out
