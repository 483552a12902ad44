"""Writing a model with its assets to a folder or a zip, and reading such a zip back.

    mjcf.export_with_assets(model, 'out/')              # out/model.xml + meshes, textures
    mujoco.MjModel.from_xml_path('out/model.xml')       # stock MuJoCo loads it
    mjcf.export_with_assets_as_zip(model, 'scene.zip')  # scene/model.xml + assets
    model = mjcf.from_zip('scene.zip')                  # unpacked within mjcf.archives' limits

The XML is `to_xml_string()`, the files beside it `get_assets()`, with the same plain names;
dm_control's keywords (`mjcf_model`, `out_file_name`, `out_dir`, `model_name`) work too.
Nothing is ever written outside the target, and reading a zip never follows a path out.
"""

from __future__ import annotations

import io
import os
import posixpath
import zipfile

from mjcf import errors
from mjcf.io import archives, serializer
from mjcf.io.parser import from_xml_string
from mjcf.tree import assets as _assets
from mjcf.tree.assets import plain_file_name
from mjcf.tree.root import RootElement

_MAX_ZIP_ENTRIES = 100_000
_DEFAULT_FILENAME = "model.xml"
_UNSET: object = object()  # tells a keyword not given from one given as None


def _contents(
    model: RootElement, model_filename: str, precision: int, zero_threshold: float
) -> tuple[str, dict[str, bytes]]:
    """The model's XML and assets, as `to_xml_string` and `get_assets` give them; raises
    mjcf.AssetError for a file that cannot be read or that cannot be exported beside
    the model file."""
    xml, assets = serializer.serialize(model, precision=precision, zero_threshold=zero_threshold)
    unsafe = [name for name in assets if plain_file_name(name) != name]
    if unsafe:
        raise errors.AssetError(f"asset names that are not plain file names: {unsafe}")
    if any(name.lower() == model_filename.lower() for name in assets):
        raise errors.AssetError(f"an asset is named {model_filename!r}, like the model file")
    return xml, assets


def _the_model(model: object, mjcf_model: object) -> RootElement:
    """The model to export, given as `model` or by dm_control's keyword `mjcf_model`;
    raises TypeError for both or neither, mjcf.AssetError for something not a model."""
    if mjcf_model is not None:
        if model is not None:
            raise TypeError("give model or mjcf_model (dm_control's name), not both")
        model = mjcf_model
    if model is None:
        raise TypeError("exporting needs the model to export (model= or mjcf_model=)")
    if not isinstance(model, RootElement):
        raise errors.AssetError(f"exporting takes a model (RootElement), got {model!r}")
    return model


def _checked_filename(name: object, keyword: str) -> str:
    """`name` if it is a plain file name ending in '.xml'; raises mjcf.AssetError (a
    ValueError) otherwise."""
    if not isinstance(name, str) or not name.lower().endswith(".xml"):
        raise errors.AssetError(f"{keyword} must end with '.xml' (a file name), got {name!r}")
    if plain_file_name(name) != name:
        raise errors.AssetError(
            f"{keyword} must be a plain file name (the folder is given separately), got {name!r}"
        )
    return name


def export_with_assets(
    model: RootElement | None = None,
    out_dir: str | os.PathLike | None = None,
    model_filename: str | None = _DEFAULT_FILENAME,
    *,
    precision: int = 17,
    zero_threshold: float = 0.0,
    out_file_name: str | None = _UNSET,  # type: ignore[assignment]
    mjcf_model: RootElement | None = None,
) -> str:
    """Write `model` as `out_dir/model_filename` and its assets beside it (the folder is
    created if needed); returns the XML file's path. `model_filename=None` names it
    '<model name>.xml' (`export_with_assets(model, 'out/', None)`); `mjcf_model` and
    `out_file_name` are dm_control's names for `model` and `model_filename`; `precision`
    and `zero_threshold` are `to_xml_string`'s. Raises mjcf.AssetError (a ValueError)
    for a model file name that is not a plain name ending in '.xml' or an asset that
    cannot be read, and TypeError for a missing model or folder; nothing is written
    then."""
    model = _the_model(model, mjcf_model)
    if out_dir is None:
        raise TypeError("export_with_assets needs out_dir, the folder to write to")
    if out_file_name is not _UNSET:
        if model_filename != _DEFAULT_FILENAME:
            raise TypeError("give model_filename or out_file_name (dm_control's name), not both")
        model_filename = out_file_name
    if model_filename is None:
        model_filename = plain_file_name(model.model) + ".xml"
    keyword = "out_file_name" if out_file_name is not _UNSET else "model_filename"
    model_filename = _checked_filename(model_filename, keyword)
    xml, assets = _contents(model, model_filename, precision, zero_threshold)
    out_dir = os.fspath(out_dir)
    os.makedirs(out_dir, exist_ok=True)
    for name, data in assets.items():
        with open(os.path.join(out_dir, name), "wb") as handle:
            handle.write(data)
    path = os.path.join(out_dir, model_filename)
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(xml)
    return path


def export_with_assets_as_zip(
    model: RootElement | None = None,
    zip_path: str | os.PathLike | None = None,
    model_filename: str | None = None,
    *,
    precision: int = 17,
    zero_threshold: float = 0.0,
    out_dir: str | os.PathLike | None = None,
    model_name: str | None = None,
    mjcf_model: RootElement | None = None,
) -> str:
    """Write `model` and its assets into a zip, inside a folder named like the zip
    (`scene.zip` holds `scene/model.xml` and the assets beside it: dm_control's layout,
    which MuJoCo's `MjSpec.from_zip` and `mjcf.from_zip` load); returns the zip's path.

    Called as the seed documents it, `zip_path` is the zip and `model_filename` the
    model file ('model.xml' by default). Called as dm_control does, with a folder
    (`out_dir`, or a `zip_path` that is a folder or does not end in '.zip') and a
    `model_name` (or a `model_filename` without '.xml'), the zip is
    `<folder>/<model_name>.zip` holding `<model_name>/<model_name>.xml`; `model_name`
    defaults to the model's name; `mjcf_model` is dm_control's name for `model`. Raises
    mjcf.AssetError (a ValueError) for a file that cannot be read or a name that cannot
    be used; nothing is written then."""
    model = _the_model(model, mjcf_model)
    if out_dir is not None:
        if zip_path is not None:
            raise TypeError("give zip_path or out_dir (dm_control's name), not both")
        zip_path = out_dir
    if zip_path is None:
        raise TypeError("export_with_assets_as_zip needs zip_path (or dm_control's out_dir)")
    if model_name is not None:
        if model_filename is not None:
            raise TypeError("give model_filename or model_name (dm_control's name), not both")
        model_filename = model_name
    zip_path = os.fspath(zip_path)
    if model_filename is not None and not model_filename.lower().endswith(".xml"):
        model_name, model_filename = model_filename, model_filename + ".xml"
    into_folder = (
        out_dir is not None
        or os.path.isdir(zip_path)
        or zip_path.endswith(("/", os.sep))
        or not zip_path.lower().endswith(".zip")
    )
    if into_folder:
        stem = model_name if model_name is not None else model.model
        folder = zip_path
        zip_path = os.path.join(folder, plain_file_name(stem) + ".zip")
        model_filename = model_filename or plain_file_name(stem) + ".xml"
    else:
        folder = None
        stem = os.path.splitext(os.path.basename(zip_path))[0]
        model_filename = model_filename or _DEFAULT_FILENAME
    model_filename = _checked_filename(model_filename, "model_filename")
    inside = plain_file_name(stem)
    xml, assets = _contents(model, model_filename, precision, zero_threshold)
    if folder is not None:
        os.makedirs(folder, exist_ok=True)
    with zipfile.ZipFile(zip_path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        archive.writestr(f"{inside}/{model_filename}", xml)
        for name, data in assets.items():
            archive.writestr(f"{inside}/{name}", data)
    return zip_path


def from_zip(
    zip_path: str | os.PathLike | io.IOBase,
    escape_separators: bool = True,
    *,
    limits: archives.Limits | None = None,
) -> RootElement:
    """Read a model from a zip written by `export_with_assets_as_zip` (or any zip with
    one MJCF file at its top, or in one top folder, and its assets). A composed model
    comes back as one model whose names keep their scopes, escaped ('arm\\/base', see
    `from_xml_string`); it compiles to the same model. The archive is unpacked within
    `limits` (default: `mjcf.archives.current_limits()`, 1 GiB in all and 100 times an
    entry's compressed size), checked while unpacking. Raises mjcf.ParseError for a zip
    that is not such an archive or that is unsafe, mjcf.UnpackLimitError (a ParseError)
    for one that unpacks to more than the limits."""
    where = f"zip {zip_path!r}"
    if isinstance(zip_path, str | os.PathLike):
        try:
            _assets.check_file(os.fspath(zip_path))  # not a device or FIFO, not too large
        except errors.AssetError as error:
            raise errors.ParseError(f"cannot read {where}: {error}") from None
    archive = archives.open_archive(zip_path, where)  # type: ignore[arg-type]
    unpacker = archives.Unpacker(limits)
    with archive:
        infos = [info for info in archive.infolist() if not info.is_dir()]
        if len(infos) > _MAX_ZIP_ENTRIES:
            raise errors.ParseError(
                f"{where} has {len(infos):,} entries, more than a model's {_MAX_ZIP_ENTRIES:,}"
            )
        files: dict[str, bytes] = {}
        for info in infos:
            name = posixpath.normpath(info.filename.replace("\\", "/"))
            if name.startswith(("../", "/")) or name == ".." or ":" in name.split("/", 1)[0]:
                raise errors.ParseError(f"{where} has an entry outside it: {info.filename!r}")
            files[name] = unpacker.read(archive, info, where)
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
