"""The names a model's files are written under, and the files that go with an output.

    files = FileNamer(root)                 # one output document
    files.name_for(mesh, 'file', asset)     # 'pad.stl', unique in the output
    files.contents()                        # {name: bytes}, as MuJoCo takes assets

The writer (`mjcf.io.serializer`) names every file as it writes the document, in the
order the document is written (see `FileNamer` and `mjcf.tree.assets`).
"""

from __future__ import annotations

import hashlib
import itertools
import os
from collections.abc import Iterable
from typing import TYPE_CHECKING

from mjcf import errors
from mjcf.tree.assets import (
    BY_PATH,
    NOT_IN_MESH_CACHE_KEY,
    Asset,
    check_file,
    default_file_name,
    hashed_file_name,
    plain_file_name,
    resolve,
)
from mjcf.tree.element import stored_attributes

if TYPE_CHECKING:
    from mjcf.tree.element import Element
    from mjcf.tree.root import RootElement


def _cached_apart(element: Element) -> bool:
    """Whether `element` is a mesh from a file that sets values MuJoCo's mesh cache does
    not compare (see `NOT_IN_MESH_CACHE_KEY`)."""
    return element.tag == "mesh" and not NOT_IN_MESH_CACHE_KEY.isdisjoint(
        stored_attributes(element)
    )


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
            if asset.path is not None and (self.by_path or element.tag in BY_PATH):
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
        for name in sorted(NOT_IN_MESH_CACHE_KEY.intersection(stored_attributes(element))):
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
        that shares the first copy's, see `mjcf.compose.sharing`); None if neither was written."""
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
