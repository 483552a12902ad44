"""Files a model loads (meshes, textures, height fields, skins ...) as `Asset` objects.

    mesh = model.asset.add('mesh', file=mjcf.Asset(stl_bytes, '.stl', prefix='wheel'))
    model.find('mesh', 'base').file          # Asset: .contents, .extension, .prefix, .path
    model.get_assets()                       # {file name in to_xml_string(): bytes}

A file attribute read from a model file becomes an `Asset` that knows its path (the
way MuJoCo finds it: `compiler strippath/meshdir/texturedir/assetdir`, relative to the
model's directory) and reads its contents on first use. Files given as
`assets={'name.stl': bytes}` are used instead of disk files of that name.

When a model is written, every asset gets a file name that is unique among the
model's assets and readable (the original base name; the attached model's scope,
then a counter, are added only when two different files share a base name; identical
contents share one name). `to_xml_string()` writes files that exist on disk as paths
relative to the model's directory, so the XML saved there loads as is; compiling and
exporting use flat names with the contents passed along.
"""

from __future__ import annotations

import functools
import itertools
import os
from pathlib import Path
from typing import TYPE_CHECKING

from mjcf import errors

if TYPE_CHECKING:
    from mjcf.element import Element
    from mjcf.root import RootElement

# Which compiler directory a file attribute is read from, by element tag.
_DIRECTORY = {"mesh": "meshdir", "skin": "meshdir", "hfield": "meshdir", "flexcomp": "meshdir",
              "texture": "texturedir"}  # fmt: skip
# Files that load further files relative to themselves: always referred to by path.
_BY_PATH = frozenset({"model"})
_file_cache: dict[str, tuple[int, int, bytes]] = {}


class Asset:
    """A file's contents with its extension ('.stl') and name stem (`prefix`); `path`
    is where it was read from, if it came from disk (contents are then read lazily)."""

    __slots__ = ("_contents", "extension", "path", "prefix")

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

    @property
    def contents(self) -> bytes:
        """The file's bytes; raises mjcf.AssetError if its file cannot be read."""
        if self._contents is None:
            return _read(self.path)
        return self._contents

    @property
    def name(self) -> str:
        """The file name this asset is known by ('prefix.ext')."""
        return self.prefix + self.extension

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
    try:
        stat = os.stat(path)
        cached = _file_cache.get(path)
        if cached is not None and cached[0] == stat.st_mtime_ns and cached[1] == stat.st_size:
            return cached[2]
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError as error:
        raise errors.AssetError(f"cannot read asset file {path!r}: {error.strerror}") from None
    _file_cache[path] = (stat.st_mtime_ns, stat.st_size, data)
    return data


def resolve(element: Element, attribute: str, value: object) -> Asset:
    """The `Asset` a file attribute value stands for, found as MuJoCo would find it
    (a name in the model's `assets` dict wins over a file on disk)."""
    if isinstance(value, Asset):
        return value
    text = str(value)
    model = element.root
    stem, extension = os.path.splitext(os.path.basename(text))
    for key in (text, os.path.basename(text)):
        data = model.assets.get(key)
        if data is not None:
            return Asset(data, extension, stem)
    return Asset(None, extension, stem, path=file_path(element, text))


def file_path(element: Element, text: str) -> str:
    """Where MuJoCo looks for file `text` of `element` (strippath, meshdir/texturedir/
    assetdir, relative to the model's directory); raises mjcf.AssetError for a model
    without a directory."""
    compiler = element.root._section("compiler")
    if compiler._attrs.get("strippath") == "true":
        text = os.path.basename(text)
    directory_setting = _DIRECTORY.get(element._spec.tag)
    directory = ""
    if directory_setting is not None:
        directory = compiler._attrs.get(directory_setting) or compiler._attrs.get("assetdir") or ""
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
    base = name.replace("\\", "/").rsplit("/", 1)[-1].lstrip(".")
    return base or "asset"


def is_inside(path: str, folder: str) -> bool:
    """Whether real path `path` is `folder` or inside it."""
    return path == folder or path.startswith(folder.rstrip(os.sep) + os.sep)


@functools.lru_cache(maxsize=65536)
def _relative_path(path: str, model_dir: str) -> str:
    """`path` relative to `model_dir` if it is inside it, else `path`."""
    if model_dir:
        relative = os.path.relpath(path, model_dir)
        if not relative.startswith(".."):
            return Path(relative).as_posix()
    return path


class FileNamer:
    """Names the assets of one output document, and collects their contents.

    `flat`: every asset gets a flat unique name and its contents are collected (export);
    else files on disk are written as paths relative to the model's directory.
    `by_path`: files on disk are written as absolute paths that MuJoCo reads itself (and
    caches: compiling), and only the other assets are named and collected."""

    def __init__(self, root: RootElement, flat: bool, by_path: bool = False) -> None:
        self.root = root
        self.flat = flat
        self.by_path = by_path
        self._by_base: dict[str, list[Asset]] = {}
        self._named: dict[str, Asset] = {}
        self._users: dict[str, tuple[Element, str]] = {}  # who first named each file

    def name_for(self, element: Element, attribute: str, value: object) -> str:
        """The file name written for one file attribute value; raises mjcf.AssetError
        naming the element if its file cannot be read."""
        asset = resolve(element, attribute, value)
        if asset.path is not None and (self.by_path or element._spec.tag in _BY_PATH):
            if self.by_path and not os.access(asset.path, os.R_OK):
                raise errors.AssetError(
                    f"{element.path}: {attribute!r}: cannot read asset file {asset.path!r}"
                )
            return asset.path
        try:
            name = None
            if not self.flat and asset.path is not None:
                preferred = self._disk_name(asset.path)
                if self._claim(preferred, asset):
                    name = preferred
            if name is None:
                name = self._flat_name(element, asset)
        except errors.AssetError as error:
            raise errors.AssetError(f"{element.path}: {attribute!r}: {error}") from None
        self._users.setdefault(name, (element, attribute))
        return name

    def _disk_name(self, path: str) -> str:
        return _relative_path(path, self.root.model_dir)

    def _claim(self, name: str, asset: Asset) -> bool:
        """Take `name` for `asset` unless its base name is taken by other contents."""
        base = name.rpartition("/")[2]
        holders = self._by_base.get(base)
        if holders is None:  # the common case: a base name seen for the first time
            self._by_base[base] = [asset]
        elif any(holder is not asset and holder != asset for holder in holders):
            return False
        elif asset not in holders:
            holders.append(asset)
        self._named[name] = asset
        return True

    def _flat_name(self, element: Element, asset: Asset) -> str:
        base = plain_file_name(asset.name)
        stem, extension = os.path.splitext(base)
        scope = element.root.namescope.prefix(self.root.namescope).replace("/", "-")
        first = [base, f"{scope}{base}"] if scope else [base]
        numbered = (f"{scope}{stem}-{n}{extension}" for n in range(2, 100_000))
        for candidate in itertools.chain(first, numbered):
            if self._claim(candidate, asset):
                return candidate
        raise errors.AssetError(f"{element.path}: too many assets named {base!r}")

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
