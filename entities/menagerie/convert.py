"""Convert a robot's Wavefront OBJ meshes to MuJoCo's binary MSH format, losslessly, and
prove it: the converted robot must compile to the same MjModel as the original.

    $ python -m entities.menagerie.convert ~/mujoco_menagerie/universal_robots_ur5e \\
          entities/menagerie/universal_robots_ur5e

An MSH file holds the float32s MuJoCo reads from the OBJ text, so nothing is rounded;
OBJ files MSH cannot carry unchanged raise ConversionError (see `obj_to_msh`), and so
does a converted folder that compiles to a different MjModel (file paths aside).
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import sys
from pathlib import Path

import mujoco
import numpy as np

import composer

# OBJ statements MuJoCo ignores when it builds a mesh: materials, groups, smoothing.
_IGNORED = frozenset({"mtllib", "usemtl", "o", "g", "s"})
_OBJ_FILE = re.compile(r'(\bfile="[^"]*?)\.obj"', re.IGNORECASE)


class ConversionError(composer.EntityError):
    """An OBJ file MSH cannot carry unchanged, or a conversion that changed the model."""


def obj_to_msh(text: str, source: str = "<obj>") -> bytes:
    """The MSH file for the OBJ `text` (read from `source`, named in errors).

    MuJoCo reads each number of an OBJ file into a float32; an MSH file holds those
    float32s (vertices, per-vertex normals) and the int32 face indices as they are (the
    UR5e's 31 MB of OBJ text become 10 MB). Only what MSH carries unchanged is converted:
    triangles whose normal index equals their vertex index (`f 1//1 2//2 3//3`), or no
    normals at all. Raises ConversionError for texture coordinates, polygons and other
    elements."""
    vertices: list[list[float]] = []
    normals: list[list[float]] = []
    faces: list[list[int]] = []
    with_normals: set[bool] = set()
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split()
        if not words or words[0].startswith("#") or words[0] in _IGNORED:
            continue
        where = f"{source}:{number}"
        if words[0] in ("v", "vn") and len(words) == 4:
            (vertices if words[0] == "v" else normals).append([float(w) for w in words[1:]])
        elif words[0] == "f" and len(words) == 4:
            face, has_normals = _face(words[1:], where)
            faces.append(face)
            with_normals.add(has_normals)
        else:
            raise ConversionError(f"{where}: {line.strip()!r} has no lossless MSH form")
    if normals and len(normals) != len(vertices):
        raise ConversionError(
            f"{source}: {len(normals)} normals for {len(vertices)} vertices; MSH needs one each"
        )
    if with_normals and with_normals != {bool(normals)}:
        raise ConversionError(f"{source}: faces must all name their normals, or none may")
    header = np.array([len(vertices), len(normals), 0, len(faces)], dtype=np.int32)
    parts = [header, np.array(vertices, np.float32), np.array(normals, np.float32)]
    return b"".join(p.tobytes() for p in [*parts, np.array(faces, np.int32)])


def _face(corners: list[str], where: str) -> tuple[list[int], bool]:
    """The 0-based vertex indices of a triangle's corners, and whether it names normals."""
    indices, named = [], set()
    for corner in corners:
        vertex, _, rest = corner.partition("/")
        texcoord, _, normal = rest.partition("/")
        if texcoord or (normal and normal != vertex) or not vertex.isdigit():
            raise ConversionError(
                f"{where}: face corner {corner!r}: MSH needs 'v' or 'v//v' (positive "
                "indices, the normal's equal to the vertex's, no texture coordinates)"
            )
        indices.append(int(vertex) - 1)
        named.add(bool(normal))
    if len(named) != 1:
        raise ConversionError(f"{where}: a face names normals for some corners only")
    return indices, named.pop()


def model_differences(original: mujoco.MjModel, converted: mujoco.MjModel) -> list[str]:
    """The MjModel fields (arrays and numbers) that differ, leaving out file paths."""
    differ = []
    for name in dir(original):
        if name.startswith("_") or name in ("paths", "npaths", "nbuffer"):
            continue
        if name.endswith("_pathadr"):
            continue
        mine, theirs = getattr(original, name), getattr(converted, name)
        if isinstance(mine, np.ndarray):
            same = mine.shape == theirs.shape and np.array_equal(mine, theirs, equal_nan=True)
        elif isinstance(mine, int | float):
            same = mine == theirs
        else:
            continue
        if not same:
            differ.append(name)
    return differ


def convert_robot(source: str | os.PathLike[str], target: str | os.PathLike[str]) -> list[Path]:
    """Copy the robot folder `source` to `target` with every OBJ mesh converted to MSH and
    the XML files' `file="*.obj"` references renamed; returns the XML files checked. Each is
    compiled beside its original, so a converted folder is exact. Raises ConversionError
    naming every MjModel field that differs (file paths aside)."""
    source, target = Path(source), Path(target)
    shutil.copytree(source, target, ignore=shutil.ignore_patterns("*.obj"), dirs_exist_ok=True)
    for obj in sorted(source.rglob("*.obj")):
        msh = target / obj.relative_to(source).with_suffix(".msh")
        msh.write_bytes(obj_to_msh(obj.read_text(), str(obj)))
    checked = []
    for xml in sorted(source.glob("*.xml")):
        converted = target / xml.name
        converted.write_text(_OBJ_FILE.sub(r'\1.msh"', xml.read_text()))
        differ = model_differences(
            mujoco.MjModel.from_xml_path(str(xml)), mujoco.MjModel.from_xml_path(str(converted))
        )
        if differ:
            raise ConversionError(f"{converted} compiles differently from {xml}: {differ}")
        checked.append(converted)
    return checked


def main(argv: list[str] | None = None) -> int:
    """Command line: convert SOURCE into TARGET; prints the checked files."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], allow_abbrev=False)
    parser.add_argument("source", help="a robot folder with OBJ meshes")
    parser.add_argument("target", help="the folder to write (created if needed)")
    args = parser.parse_args(argv)
    try:
        for xml in convert_robot(args.source, args.target):
            print(f"{xml}: compiles to the same MjModel as the original")
    except ConversionError as e:
        print(f"convert: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
