"""What a model may make MuJoCo build: a budget, checked before MuJoCo compiles it.

    mjcf.Physics.from_mjcf_model(model)          # mjcf.BudgetError past the budget
    budget.LIMITS = budget.Budget(elements=10**6, bytes=8 << 30)   # or MJCF_ELEMENT_LIMIT ...
    budget.measure(xml, assets)                  # Measure(elements=..., bytes=..., ...)

Every model mjcf compiles, from a tree or from text, is measured first on the text MuJoCo
gets (includes, attached models and default classes in it), and refused past either limit
of `Budget` with mjcf.BudgetError (a CompileError naming the model, element and limit).
`Physics.from_xml_path` and `from_binary_path` hand the file to MuJoCo unmeasured.
"""

from __future__ import annotations

import functools
import math
import os
import re
import struct
from collections.abc import Callable, Mapping
from typing import NamedTuple

from lxml import etree

from mjcf import errors
from mjcf.io import _limits, archives

DEFAULT_ELEMENTS = 100_000
DEFAULT_BYTES = 2 << 30
ELEMENTS_VARIABLE = "MJCF_ELEMENT_LIMIT"
BYTES_VARIABLE = "MJCF_ALLOCATION_LIMIT"
# What a keyframe holds per joint (a free joint's qpos and qvel), body (mocap pose) and
# actuator (act and ctrl), in doubles: an upper bound of a key's state.
_KEY_DOUBLES = {"joint": 13, "freejoint": 13, "body": 7}
_PNG = b"\x89PNG\r\n\x1a\n"
# A height field of this many samples or more overflows MuJoCo 4.0.0's int count: SIGSEGV.
# It is refused whatever the budget.
_OVERFLOW = 1 << 31
_MEMORY = re.compile(r"\s*(\d+)\s*([KMGTPE]?)\s*", re.IGNORECASE)
_SCALE = {"": 1, "K": 1 << 10, "M": 1 << 20, "G": 1 << 30, "T": 1 << 40, "P": 1 << 50,
          "E": 1 << 60}  # fmt: skip
_IMAGE_ATTRIBUTES = ("file", "fileright", "fileleft", "fileup", "filedown", "filefront",
                     "fileback")  # fmt: skip


class Budget(NamedTuple):
    """The most `elements` and `bytes` a model may make MuJoCo build.

    A model of a few hundred bytes can ask MuJoCo for minutes of work or gigabytes of
    memory: a `<replicate>` in a `<replicate>` makes 10^8 geoms, a `<flexcomp count="3000
    3000 1">` nine million bodies, a `<hfield nrow="100000" ncol="100000">` 40 GB of floats,
    and a PNG of a few megabytes decodes to gigabytes. So every model mjcf compiles (from a
    tree: `Physics.from_mjcf_model`, `compile_model`, composer's environments; from text:
    `Physics.from_xml_string`) is measured first against:

    - `elements` (default 100,000): every element after `<replicate>` expansion, the points
      of a `<flexcomp>` (its `count`, and `cellcount`), the vertices of a builtin `<mesh>`
      (its first parameter squared) and the keyframes `<size nkey>` asks for;
    - `bytes` (default 2 GiB): what the model asks MuJoCo to allocate by number: height
      fields (`nrow` x `ncol` floats, or a PNG's size), textures (builtin `width` x
      `height`, six faces for a cube or skybox, or a PNG's size, at 4 bytes a pixel), `<size
      memory>`, `nuserdata`, `nuser_*` per element, `njmax`/`nconmax` (1 KiB each), the
      keyframes' state, and for rendering the shadow map (`quality shadowsize`) and
      offscreen buffer (`global offwidth` x `offheight`, multisampled).

    Files MuJoCo reads by size otherwise (meshes, custom binary images) are bounded by
    `mjcf.tree.assets.FILE_SIZE_LIMIT`. The limits in force are `current_budget()`."""

    elements: int = DEFAULT_ELEMENTS
    bytes: int = DEFAULT_BYTES


# The budget a program sets for every model it compiles; None: the environment's.
LIMITS: Budget | None = None


class Measure(NamedTuple):
    """What a model asks of MuJoCo: `elements` and `bytes` in all, and for each the line of
    the element that asks most (`element_line`, `bytes_line`) with what it asks; the line
    of a height field MuJoCo 4.0.0 crashes on (`crash_line`, 0 for none)."""

    elements: int
    bytes: int
    element_line: int
    element_count: int
    bytes_line: int
    bytes_count: int
    crash_line: int = 0


def current_budget() -> Budget:
    """The budget in force: `LIMITS` if a program set it, else the environment variables'
    (`MJCF_ELEMENT_LIMIT`; `MJCF_ALLOCATION_LIMIT` in bytes, or '4G' ...) over the
    defaults. Raises mjcf.BudgetError for a variable that is not a number."""
    try:
        return _limits.in_force(
            LIMITS,
            Budget,
            {
                ELEMENTS_VARIABLE: (int, DEFAULT_ELEMENTS),
                BYTES_VARIABLE: (archives.parse_size, DEFAULT_BYTES),
            },
        )
    except (ValueError, errors.UnpackLimitError) as error:
        raise errors.BudgetError(
            f"environment variable {ELEMENTS_VARIABLE} or {BYTES_VARIABLE} is not a number: {error}"
        ) from None


def check(
    xml: str,
    assets: Mapping[str, bytes],
    model: str,
    where: Callable[[int], str] = lambda line: f"line {line}",
) -> None:
    """Raise mjcf.BudgetError if the MJCF text `xml` (with `assets`, file name -> bytes)
    asks more of MuJoCo than `current_budget()` allows; `model` names the model and
    `where(line)` an element by its line in `xml`, for the message."""
    budget = current_budget()
    measured = measure(xml, assets)
    if measured.crash_line:
        raise errors.BudgetError(
            f"{model}: {where(measured.crash_line)} has {_OVERFLOW:,} or more rows x columns, "
            "on which MuJoCo 4.0.0 crashes (whatever the budget)"
        )
    if measured.elements > budget.elements:
        line, asked, what, limit = (measured.element_line, measured.element_count,
                                    f"{measured.elements:,} elements", budget.elements)  # fmt: skip
        setting, variable = "elements", ELEMENTS_VARIABLE
    elif measured.bytes > budget.bytes:
        line, asked, what, limit = (measured.bytes_line, measured.bytes_count,
                                    f"{measured.bytes:,} bytes", budget.bytes)  # fmt: skip
        setting, variable = "bytes", BYTES_VARIABLE
    else:
        return
    raise errors.BudgetError(
        f"{model} asks MuJoCo for {what}, over the budget of {limit:,} (the most, "
        f"{asked:,}, by {where(line)}); if you trust the model, raise the budget's "
        f"{setting} (mjcf.budget.LIMITS, or the environment variable {variable})"
    )


def measure(xml: str, assets: Mapping[str, bytes]) -> Measure:
    """What the MJCF text `xml` asks of MuJoCo (see `Measure`): its elements counted with
    `<replicate>` expanded, and the memory it asks for by number (images by their
    headers, found in `assets` or on disk by absolute path). Raises mjcf.ParseError for
    text that is not XML."""
    counted, image_files = _counted(xml)
    images = [(line, _image_bytes(names, assets)) for line, names in image_files]
    image_bytes = sum(size for _, size in images)
    line, size = max([(counted.bytes_line, counted.bytes_count), *images], key=lambda x: x[1])
    return Measure(counted.elements, counted.bytes + image_bytes, counted.element_line,
                   counted.element_count, line, size, counted.crash_line)  # fmt: skip


class _Counted(NamedTuple):
    measure: Measure  # what the text asks, but the pixels of the images it names
    images: list[tuple[int, list[str]]]  # the image files of each texture and hfield, by line


@functools.lru_cache(maxsize=16)
def _counted(xml: str) -> _Counted:
    """The text's own part of `measure` (kept for the last texts: a model compiled again
    unchanged is written as the same text)."""
    parser = etree.XMLParser(huge_tree=True, resolve_entities=False, no_network=True,
                             load_dtd=False)  # fmt: skip
    try:
        root = etree.fromstring(xml.encode("utf-8"), parser)
    except etree.XMLSyntaxError as error:
        raise errors.ParseError(f"the model is not XML: {error.msg}") from None
    kinds: dict[str, int] = {}
    most_elements = (0, 0)  # (elements, line) of the element that makes the most
    most_bytes = (0, 0)
    elements = 0
    asked = 0
    texture_defaults = _texture_defaults(root)
    crash_line = 0
    images: list[tuple[int, list[str]]] = []
    pending = [(root, 1)]
    while pending:
        element, times = pending.pop()
        tag = element.tag
        if not isinstance(tag, str):
            continue
        elements += times
        kinds[tag] = kinds.get(tag, 0) + times
        inner = times
        if tag in _ASKING:  # the few that ask for more than themselves
            made = times * (1 + _points(element))
            elements += made - times
            most_elements = max(most_elements, (made, element.sourceline or 0))
            size = times * _declared_bytes(element, texture_defaults)
            if size:
                asked += size
                most_bytes = max(most_bytes, (size, element.sourceline or 0))
            parent = element.getparent()
            if tag in ("texture", "hfield") and parent is not None and parent.tag == "asset":
                names = [name for a in _IMAGE_ATTRIBUTES if (name := element.get(a))]
                if names:
                    images.append((element.sourceline or 0, names))
            if tag == "replicate":
                inner = times * _count(element.get("count"))
            elif (
                tag == "hfield"
                and _integer(element.get("nrow")) * _integer(element.get("ncol")) >= _OVERFLOW
            ):
                crash_line = crash_line or element.sourceline or 1
        elif times > most_elements[0]:
            most_elements = (times, element.sourceline or 0)
        pending.extend((child, inner) for child in element)
    size = root.find("size")
    if size is not None:
        keys = _integer(size.get("nkey"))
        per_key = 8 * (1 + sum(n * kinds.get(k, 0) for k, n in _KEY_DOUBLES.items())
                       + 2 * sum(kinds.get(k, 0) for k in _ACTUATORS))  # fmt: skip
        users = sum(_integer(v) for k, v in size.attrib.items() if k.startswith("nuser_"))
        extra = keys * per_key + 8 * users * elements
        elements += keys
        most_elements = max(most_elements, (keys, size.sourceline or 0))
        asked += extra
        most_bytes = max(most_bytes, (_declared_bytes(size, {}) + extra, size.sourceline or 0))
    measured = Measure(elements, asked, most_elements[1], most_elements[0], most_bytes[1],
                       most_bytes[0], crash_line)  # fmt: skip
    return _Counted(measured, images)


# The elements that ask MuJoCo for more than one element's work.
_ASKING = frozenset({"replicate", "flexcomp", "mesh", "hfield", "texture", "size", "quality",
                     "global"})  # fmt: skip
# The actuator elements (each with act and ctrl in a keyframe).
_ACTUATORS = ("general", "motor", "position", "velocity", "intvelocity", "damper",
              "cylinder", "muscle", "adhesion", "plugin")  # fmt: skip


def _points(element: etree._Element) -> int:
    """The elements MuJoCo makes of `element` besides itself: a flexcomp's points, a builtin
    mesh's vertices."""
    tag = element.tag
    if tag == "flexcomp":
        return _product(element.get("count")) + _product(element.get("cellcount"))
    if tag == "mesh" and element.get("builtin"):
        first = _numbers(element.get("params"))[:1]
        return int(first[0]) ** 2 if first and first[0] >= 1 else 0
    return 0


def _declared_bytes(element: etree._Element, texture_defaults: dict[str, dict[str, str]]) -> int:
    """The bytes `element`'s attributes ask MuJoCo to allocate (see `Budget`)."""
    tag = element.tag
    get = element.get
    if tag == "hfield":
        return 4 * _integer(get("nrow")) * _integer(get("ncol"))
    if tag == "texture" and element.getparent() is not None and element.getparent().tag == "asset":
        values = {**texture_defaults.get(get("class") or "main", {}), **element.attrib}
        if not values.get("builtin") or values.get("builtin") == "none":
            return 0
        width, height = _integer(values.get("width")), _integer(values.get("height"))
        channels = _integer(values.get("nchannel")) or 3
        if values.get("type") in ("cube", "skybox"):
            return 6 * width * width * channels
        return width * height * channels
    if tag == "size":
        memory = _memory(get("memory"))
        return memory + 8 * (_integer(get("nuserdata")) + _integer(get("nstack"))) + 1024 * (
            _integer(get("njmax")) + _integer(get("nconmax")))  # fmt: skip
    if tag == "quality":
        return 4 * _integer(get("shadowsize")) ** 2
    if (
        tag == "global"
        and element.getparent() is not None
        and (element.getparent().tag == "visual")
    ):
        return 8 * _integer(get("offwidth")) * _integer(get("offheight"))
    return 0


def _texture_defaults(root: etree._Element) -> dict[str, dict[str, str]]:
    """{default class: the texture attributes it sets, inherited ones included}."""
    found: dict[str, dict[str, str]] = {}
    pending: list[tuple[etree._Element, dict[str, str]]] = [
        (section, {}) for section in root.iterfind("default")
    ]
    while pending:
        default, inherited = pending.pop()
        texture = default.find("texture")
        values = {**inherited, **(texture.attrib if texture is not None else {})}
        found[default.get("class") or "main"] = dict(values)
        pending.extend((child, values) for child in default.iterfind("default"))
    return found


def _image_bytes(names: list[str], assets: Mapping[str, bytes]) -> int:
    """The bytes MuJoCo decodes the PNG files `names` to (4 a pixel; other formats are
    read by their size), found in `assets` by name or base name, or on disk."""
    total = 0
    for name in names:
        header = assets.get(name)
        if header is None:
            header = assets.get(os.path.basename(name))
        if header is None and os.path.isabs(name):
            try:
                with open(name, "rb") as file:
                    header = file.read(24)
            except OSError:
                continue  # MuJoCo will say it cannot read it
        if header is not None and header[:8] == _PNG and len(header) >= 24:
            width, height = struct.unpack(">II", header[16:24])
            total += 4 * width * height
    return total


def _count(text: str | None) -> int:
    value = _integer(text)
    return value if value > 0 else 1


def _integer(text: str | None) -> int:
    """The whole number MuJoCo reads from `text` (0 for none, or for what is not one:
    MuJoCo refuses it when compiling)."""
    numbers = _numbers(text)
    return int(numbers[0]) if numbers and numbers[0] >= 0 else 0


def _numbers(text: str | None) -> list[float]:
    values: list[float] = []
    for word in (text or "").split():
        try:
            value = float(word)
        except ValueError:
            return values
        if not math.isfinite(value):
            return values
        values.append(value)
    return values


def _product(text: str | None) -> int:
    numbers = [n for n in _numbers(text) if n >= 1]
    return math.prod(int(n) for n in numbers) if numbers else 0


def _memory(text: str | None) -> int:
    """A `size memory` value in bytes ('10M'); 0 for none or -1 (MuJoCo's default)."""
    match = _MEMORY.fullmatch(text or "")
    if match is None:
        return 0
    return int(match.group(1)) * _SCALE[match.group(2).upper()]
