"""Writing a model with its assets to a folder or a zip, and reading such a zip back.

    mjcf.export_with_assets(model, 'out/')              # out/model.xml + meshes, textures
    mujoco.MjModel.from_xml_path('out/model.xml')       # stock MuJoCo loads it
    mjcf.export_with_assets_as_zip(model, 'scene.zip')  # model.xml + assets, MJZ layout
    model = mjcf.from_zip('scene.zip')

Asset files get flat, readable, unique names next to the XML (see `mjcf.assets`).
Nothing is ever written outside the target: asset names are reduced to plain file
names, and reading a zip never follows a path out of it.
"""

from __future__ import annotations

import io
import os
import posixpath
import zipfile

from mjcf import errors, serializer
from mjcf.assets import plain_file_name
from mjcf.root import RootElement

_MAX_ZIP_ENTRIES = 100_000
_MAX_ZIP_BYTES = 4 << 30


def _contents(model: RootElement, precision: int) -> tuple[str, dict[str, bytes]]:
    xml, assets = serializer.serialize(model, flat_assets=True, precision=precision)
    unsafe = [name for name in assets if plain_file_name(name) != name]
    if unsafe:
        raise errors.AssetError(f"asset names that are not plain file names: {unsafe}")
    return xml, assets


def export_with_assets(
    model: RootElement,
    out_dir: str | os.PathLike,
    model_filename: str = "model.xml",
    precision: int = 17,
) -> str:
    """Write `model` as `out_dir/model_filename` and its assets beside it; returns the
    XML file's path. Raises mjcf.AssetError if an asset cannot be read."""
    if not isinstance(model, RootElement):
        raise errors.AssetError(f"export_with_assets takes a model (RootElement), got {model!r}")
    xml, assets = _contents(model, precision)
    out_dir = os.fspath(out_dir)
    os.makedirs(out_dir, exist_ok=True)
    model_filename = plain_file_name(model_filename)
    if model_filename in assets:
        raise errors.AssetError(f"an asset is named {model_filename!r}, like the model file")
    for name, data in assets.items():
        with open(os.path.join(out_dir, name), "wb") as handle:
            handle.write(data)
    path = os.path.join(out_dir, model_filename)
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(xml)
    return path


def export_with_assets_as_zip(
    model: RootElement,
    zip_path: str | os.PathLike,
    model_filename: str | None = None,
    precision: int = 17,
) -> str:
    """Write `model` and its assets into a zip (model file at the top, 'model.xml' by
    default, which MuJoCo's MJZ loader finds); returns the zip's path. Raises
    mjcf.AssetError if an asset cannot be read (nothing is written then).

    As in dm_control, `zip_path` may be a folder: the zip is then `<folder>/<model
    name>.zip`; and a `model_filename` without '.xml' is dm_control's `model_name`,
    which names both the zip in that folder and the model file ('<model_name>.xml')."""
    zip_path = os.fspath(zip_path)
    stem = model.model
    if model_filename is not None and not model_filename.endswith(".xml"):
        stem = model_filename
        model_filename = model_filename + ".xml"
    if os.path.isdir(zip_path) or zip_path.endswith(("/", os.sep)):
        os.makedirs(zip_path, exist_ok=True)
        zip_path = os.path.join(zip_path, plain_file_name(stem) + ".zip")
    xml, assets = _contents(model, precision)
    model_filename = plain_file_name(model_filename or "model.xml")
    if model_filename in assets:
        raise errors.AssetError(f"an asset is named {model_filename!r}, like the model file")
    with zipfile.ZipFile(zip_path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        archive.writestr(model_filename, xml)
        for name, data in assets.items():
            archive.writestr(name, data)
    return zip_path


def from_zip(
    zip_path: str | os.PathLike | io.IOBase, escape_separators: bool = True
) -> RootElement:
    """Read a model from a zip written by `export_with_assets_as_zip` (or any zip with
    one MJCF file at its top, or in one top folder, and its assets). A composed model
    comes back as one model whose names keep their scopes, escaped ('arm\\/base', see
    `from_xml_string`); it compiles to the same model. Raises mjcf.ParseError for a
    zip that is not such an archive or that is unsafe."""
    from mjcf.parser import from_xml_string

    try:
        archive = zipfile.ZipFile(zip_path)
    except (OSError, zipfile.BadZipFile) as error:
        raise errors.ParseError(f"cannot read zip {zip_path!r}: {error}") from None
    with archive:
        infos = [info for info in archive.infolist() if not info.is_dir()]
        if len(infos) > _MAX_ZIP_ENTRIES or sum(i.file_size for i in infos) > _MAX_ZIP_BYTES:
            raise errors.ParseError(f"zip {zip_path!r} is too large to be a model")
        files: dict[str, bytes] = {}
        for info in infos:
            name = posixpath.normpath(info.filename.replace("\\", "/"))
            if name.startswith(("../", "/")) or name == ".." or ":" in name.split("/", 1)[0]:
                raise errors.ParseError(
                    f"zip {zip_path!r} has an entry outside it: {info.filename!r}"
                )
            files[name] = archive.read(info)
    model_file = _find_model_file(files, zip_path)
    folder = posixpath.dirname(model_file)
    assets = {}
    for name, data in files.items():
        if name != model_file:
            relative = posixpath.relpath(name, folder) if folder else name
            assets[relative] = data
            assets.setdefault(posixpath.basename(name), data)
    return from_xml_string(files[model_file], escape_separators=escape_separators, assets=assets)


def _find_model_file(files: dict[str, bytes], zip_path: object) -> str:
    candidates = [
        name
        for name in files
        if name.endswith(".xml") and name.count("/") <= 1 and b"<mujoco" in files[name][:65536]
    ]
    for preferred in ("model.xml",):
        if preferred in candidates:
            return preferred
    top = [c for c in candidates if "/" not in c]
    if len(top) == 1:
        return top[0]
    if len(candidates) == 1:
        return candidates[0]
    found = sorted(candidates) or "none"
    raise errors.ParseError(f"zip {zip_path!r} must hold one MJCF model at its top; found {found}")
